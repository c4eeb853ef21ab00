//! `acuity experiment error`: run time against error. Mean frame time and
//! triangles against mean FLIP (and FovVideoVDP JOD), for screen size
//! across its bias and acuity across `s`, compared at equal error.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::dump::{Metric, check_fvvdp, score_fvvdp};
use crate::frames::World;
use crate::player::{PlaySettings, Player};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::report::{Summary, attach_jod, summarize};
use crate::scene::Policy;

use super::CommonArgs;

/// The policies `--matched` adds, each at every screen-size bias.
const MATCHED: [Policy; 2] = [
    Policy::AcuityBestEffortMatched,
    Policy::AcuityBestEffortMatchedPooled,
];

/// Arguments of `acuity experiment error`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct ErrorArgs {
    /// The scene.
    #[cfg_attr(feature = "clap", arg(long, default_value = "scenes/default.toml"))]
    pub scene: PathBuf,
    /// Screen-size biases, comma-separated (> 0).
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ',', default_values_t = vec![0.25, 0.5, 1.0, 2.0, 4.0]))]
    pub biases: Vec<f64>,
    /// Acuity scale factors `s`, comma-separated, in (0, 1].
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ',', default_values_t = vec![1.0, 0.5, 0.25, 0.125, 0.0625]))]
    pub scales: Vec<f64>,
    /// Acuity policies swept across `s`, comma-separated: `acuity_size`
    /// isolates the size criterion, which FLIP (a foveal, gaze-free metric)
    /// judges fairly; eccentricity and velocity savings count as error in
    /// FLIP even where a viewer fixating the gaze cannot see them.
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ',', default_values_t = vec!["acuity_size".to_string(), "acuity_all".to_string()]))]
    pub acuity_policies: Vec<String>,
    /// Triangle budgets as shares of full detail's triangles in view,
    /// comma-separated, in (0, 1]: each runs `acuity_best_effort` (the
    /// least visible detail per triangle first, weighed by object size),
    /// `acuity_best_effort_pooled` (capping the just-imperceptible
    /// selection), `acuity_best_effort_unweighted` (without the size) and
    /// `acuity_budget_uniform` (one `s` lowered for all) under that budget
    /// (default: none).
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub budgets: Vec<f64>,
    /// Make each budget one fixed triangle count for every frame, as an
    /// engine's frame budget is: its share of full detail's mean triangles
    /// in view over the path (measured first, by playing full detail
    /// alone), instead of a share of full detail's triangles in view frame
    /// by frame.
    #[cfg_attr(feature = "clap", arg(long))]
    pub fixed_budgets: bool,
    /// Also run `acuity_best_effort_matched` at each screen-size bias:
    /// best effort under, in each frame, the triangles screen size draws
    /// in that frame, so the two rankings meet at equal triangles frame by
    /// frame; and `acuity_best_effort_matched_pooled`, the same budget over
    /// the runtime's just-imperceptible settings.
    #[cfg_attr(feature = "clap", arg(long))]
    pub matched: bool,
    /// Frames per configuration, spread over the scene's path.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64)))]
    pub frames: u32,
    /// FLIP on every n-th frame (>= 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 3))]
    pub flip_every: u32,
    /// Error metrics, comma-separated: `flip` (FLIP on every n-th frame)
    /// and `fvvdp` (FovVideoVDP on every frame, foveated at the gaze: needs
    /// Python with pyfvvdp, `$ACUITY_PYTHON` or `python3`; dumps the frames,
    /// to `<out>/frames/` without --dump-frames).
    #[cfg_attr(
        feature = "clap",
        arg(long, value_delimiter = ',', default_value = "flip")
    )]
    pub metric: Vec<Metric>,
    /// Screen size's thresholds, relative screen heights, comma-separated,
    /// strictly decreasing (default: the scene's `run.screen_size_thresholds`,
    /// else 0.6,0.3,0.1,0.03).
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub screen_size_thresholds: Option<Vec<f64>>,
    /// Weight screen size's relative heights by the observer's
    /// eccentricity factor at each object's angle from the gaze (a foveated
    /// screen-size baseline; default: the scene's `run.screen_size_foveated`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub screen_size_foveated: bool,
    /// One object's own screen-size bias, `NAME=BIAS` (finite, > 0;
    /// repeatable): a factor on screen size's bias for that object of the
    /// scene (default: the object's `screen_size_bias`), a table tuned per
    /// kind of object.
    #[cfg_attr(feature = "clap", arg(long = "screen-size-object-bias", value_name = "NAME=BIAS", value_parser = crate::limits::parse_object_bias))]
    pub screen_size_object_biases: Vec<(String, f64)>,
    /// Options every experiment shares.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub common: CommonArgs,
}

impl Default for ErrorArgs {
    /// The command line's defaults: `acuity experiment error` with no flags.
    fn default() -> Self {
        Self {
            scene: PathBuf::from("scenes/default.toml"),
            biases: vec![0.25, 0.5, 1.0, 2.0, 4.0],
            scales: vec![1.0, 0.5, 0.25, 0.125, 0.0625],
            acuity_policies: vec!["acuity_size".into(), "acuity_all".into()],
            budgets: Vec::new(),
            fixed_budgets: false,
            matched: false,
            frames: 30,
            flip_every: 3,
            metric: vec![Metric::Flip],
            screen_size_thresholds: None,
            screen_size_foveated: false,
            screen_size_object_biases: Vec::new(),
            common: CommonArgs::default(),
        }
    }
}

/// Runs the error experiment; writes `error.csv`, with FLIP
/// `error_time.png` and `error_triangles.png`, with FovVideoVDP
/// `error_jod.png`; returns the summaries (full detail first).
pub fn error(args: &ErrorArgs) -> anyhow::Result<ErrorSweep> {
    if args.frames == 0 || args.flip_every == 0 {
        crate::bail_input!("--frames and --flip-every need at least 1");
    }
    if let Some(b) = args.biases.iter().find(|b| !(b.is_finite() && **b > 0.0)) {
        crate::bail_input!("bias {b} is not > 0");
    }
    if let Some(s) = args.scales.iter().find(|s| !(**s > 0.0 && **s <= 1.0)) {
        crate::bail_input!("scale factor {s} is not in (0, 1]");
    }
    if let Some(b) = args.budgets.iter().find(|b| !(**b > 0.0 && **b <= 1.0)) {
        crate::bail_input!("budget share {b} is not in (0, 1]");
    }
    if args.fixed_budgets && args.budgets.is_empty() {
        crate::bail_input!("--fixed-budgets fixes the budgets of --budgets, and none is given");
    }
    let mut acuity_policies = Vec::new();
    for name in &args.acuity_policies {
        let p = crate::scene::policy_by_name(name)?;
        if !p.is_fixed_scale_acuity() {
            crate::bail_input!("`{name}` is not an acuity policy with a fixed scale factor");
        }
        if !acuity_policies.contains(&p) {
            acuity_policies.push(p);
        }
    }
    let (flip, fvvdp) = (
        args.metric.contains(&Metric::Flip),
        args.metric.contains(&Metric::Fvvdp),
    );
    if fvvdp {
        check_fvvdp()?;
    }
    let mut world = args.common.load(&args.scene)?;
    if let Some(table) = &args.screen_size_thresholds {
        crate::screen_size::check_table(table)
            .map_err(|e| crate::error::input_error(format!("--screen-size-thresholds: {e}")))?;
        world.scene.run.screen_size_thresholds = table.clone();
    }
    world.scene.run.screen_size_foveated |= args.screen_size_foveated;
    for (name, bias) in &args.screen_size_object_biases {
        crate::limits::check_object_bias(*bias).map_err(|e| {
            crate::error::input_error(format!("--screen-size-object-bias {name}: {e}"))
        })?;
        let objects = &mut world.scene.objects;
        let Some(object) = objects.iter_mut().find(|o| o.name == *name) else {
            let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
            crate::bail_input!(
                "--screen-size-object-bias: the scene has no object `{name}` (it has {})",
                names.join(", ")
            );
        };
        object.screen_size_bias = *bias;
    }
    let out = args.common.out_dir("error")?;
    let mut settings = PlaySettings::from_scene(&world.scene, Some(args.frames))?;
    settings.flip_every_n_frames = if flip { args.flip_every } else { 0 };
    settings.keep_images = false;
    settings.dump_dir = args
        .common
        .dump_frames
        .clone()
        .or_else(|| fvvdp.then(|| out.join("frames")));
    if args.fixed_budgets && !args.budgets.is_empty() {
        let base = full_detail_mean_triangles(&world, &settings)?;
        settings.fixed_budget_base_triangles = Some(base);
        // Said even with --quiet: the budgets' counts are part of the result.
        eprintln!(
            "budgets fixed at their share of {base:.0} triangles a frame (full detail's mean in view)"
        );
    }
    let mut configs = vec![(Policy::Full, 1.0)];
    configs.extend(args.biases.iter().map(|&b| (Policy::ScreenSize, b)));
    for &p in &acuity_policies {
        configs.extend(args.scales.iter().map(|&s| (p, s)));
    }
    for p in Policy::BUDGETED {
        configs.extend(args.budgets.iter().map(|&b| (p, b)));
    }
    if args.matched {
        for matched in MATCHED {
            configs.extend(args.biases.iter().map(|&b| (matched, b)));
        }
    }
    let mut player = Player::new(&world, settings.clone())?;
    let bar = crate::progress::bar(
        u64::from(settings.frames) * configs.len() as u64,
        "frames",
        args.common.profiles.quiet,
    );
    player.set_progress(&bar);
    let runs = player.play_configs(&configs, 1.0);
    bar.finish_and_clear();
    let runs = runs?;
    let mut sums = summarize(&runs, world.scene.run.budget_s());
    if let (true, Some(dir)) = (fvvdp, &settings.dump_dir) {
        attach_jod(&mut sums, &score_fvvdp(dir, args.common.profiles.quiet)?)?;
    }
    let sweep = ErrorSweep::new(sums, fvvdp);
    let path = out.join("error.csv");
    crate::report::write_csv_with_json(&sweep.csv(), &path)?;
    let sums: Vec<&Summary> = sweep.rows.iter().map(|r| &r.summary).collect();
    let curve = |p: Policy, x: &dyn Fn(&Summary) -> f64, y: &dyn Fn(&Summary) -> f64| {
        let mut pts: Vec<(f64, f64)> = sums
            .iter()
            .copied()
            .filter(|s| s.policy == p || s.policy == Policy::Full)
            .map(|s| (x(s), y(s)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        Series {
            name: match p {
                Policy::ScreenSize => "screen size (bias)".into(),
                _ if p.is_matched() => format!("{} (bias)", p.name()),
                _ if p.is_budgeted() => format!("{} (budget)", p.name()),
                _ => format!("{} (s)", p.name()),
            },
            points: pts,
        }
    };
    type Field<'a> = &'a dyn Fn(&Summary) -> f64;
    let flip_x: Field = &|s| s.flip_mean;
    let jod_x: Field = &|s| s.jod.unwrap_or(f64::NAN);
    let mut plots: Vec<(&str, &str, &str, &str, Field, Field)> = Vec::new();
    if flip {
        plots.push((
            "error_time.png",
            "frame time vs FLIP",
            "mean FLIP (0 = identical, 1 = maximal)",
            "mean frame time (ms)",
            flip_x,
            &|s| s.mean_ms,
        ));
        plots.push((
            "error_triangles.png",
            "triangles vs FLIP",
            "mean FLIP (0 = identical, 1 = maximal)",
            "triangles per frame",
            flip_x,
            &|s| s.triangles,
        ));
    }
    if fvvdp {
        plots.push((
            "error_jod.png",
            "triangles vs FovVideoVDP (10 = identical)",
            "FovVideoVDP quality (JOD)",
            "triangles per frame",
            jod_x,
            &|s| s.triangles,
        ));
    }
    for (file, title, xlabel, ylabel, x, y) in &plots {
        save_line_plot(
            &LinePlot {
                title: (*title).into(),
                x_label: (*xlabel).into(),
                y_label: (*ylabel).into(),
                series: std::iter::once(Policy::ScreenSize)
                    .chain(acuity_policies.iter().copied())
                    .chain(
                        Policy::BUDGETED
                            .into_iter()
                            .filter(|_| !args.budgets.is_empty()),
                    )
                    .chain(MATCHED.into_iter().filter(|_| args.matched))
                    .map(|p| curve(p, *x, *y))
                    .collect(),
                log_x: false,
                markers: true,
                y_from_zero: true,
            },
            &out.join(file),
        )?;
    }
    if !args.common.profiles.quiet {
        let plots: Vec<&str> = plots.iter().map(|p| p.0.trim_end_matches(".png")).collect();
        eprintln!(
            "wrote {} (error.csv, error.json, {} .png/.svg)",
            out.display(),
            plots.join(", ")
        );
    }
    Ok(sweep)
}

/// Full detail's mean triangles a frame in view over the path: full detail
/// played alone, with no metric and nothing dumped.
fn full_detail_mean_triangles(world: &World, settings: &PlaySettings) -> anyhow::Result<f64> {
    let mut alone = settings.clone();
    alone.flip_every_n_frames = 0;
    alone.keep_images = false;
    alone.dump_dir = None;
    let runs = Player::new(world, alone)?.play_configs(&[(Policy::Full, 1.0)], 1.0)?;
    let frames = &runs[0].frames;
    if frames.is_empty() {
        crate::bail_input!("full detail played no frame to fix the budgets by");
    }
    Ok(frames.iter().map(|f| f.triangles as f64).sum::<f64>() / frames.len() as f64)
}

/// One configuration of an error sweep: its summary and its triangles
/// against screen size's at equal error.
#[derive(Debug, Clone)]
pub struct ErrorRow {
    /// The played configuration (policy, knob, time, triangles, errors).
    pub summary: Summary,
    /// Its triangles over screen size's at the same mean FLIP, read off
    /// screen size's curve across its bias (`None` for full detail, screen
    /// size itself, or a FLIP outside screen size's range).
    pub vs_screen_size_flip: Option<f64>,
    /// The same at equal FovVideoVDP JOD (`None` also without JOD).
    pub vs_screen_size_jod: Option<f64>,
    /// Screen size's local 99.9th percentile (JOD units) at this row's
    /// JOD, read off screen size's sweep ([`local_p999_at_equal_jod`]):
    /// the most visible local difference screen size shows at the same
    /// overall quality (`None` as for `vs_screen_size_jod`).
    pub screen_size_local_p999: Option<f64>,
}

/// What [`error`] measured: one row per configuration, in play order
/// (full detail, screen size across its bias, each acuity policy across
/// `s`, the budgeted policies across their budgets).
#[derive(Debug, Clone)]
pub struct ErrorSweep {
    /// The rows.
    pub rows: Vec<ErrorRow>,
    /// Whether FovVideoVDP scored the sweep (the JOD columns).
    pub fvvdp: bool,
}

impl ErrorSweep {
    /// Rows from played summaries: each compared with the screen-size
    /// configurations among them at equal FLIP and at equal JOD.
    pub fn new(summaries: Vec<Summary>, fvvdp: bool) -> Self {
        let screen_curve = |y: &dyn Fn(&Summary) -> f64| -> Vec<(f64, f64)> {
            summaries
                .iter()
                .filter(|s| s.policy == Policy::ScreenSize)
                .map(|s| (y(s), s.triangles))
                .collect()
        };
        let (flip_curve, jod_curve) = (
            screen_curve(&|s| s.flip_mean),
            screen_curve(&|s| s.jod.unwrap_or(f64::NAN)),
        );
        let local_curve: Vec<(f64, f64)> = summaries
            .iter()
            .filter(|s| s.policy == Policy::ScreenSize)
            .filter_map(|s| Some((s.jod?, s.jod_local_p999?)))
            .collect();
        let rows = summaries
            .iter()
            .map(|s| {
                // Full detail and screen size are the references, not compared.
                let compared = !matches!(s.policy, Policy::Full | Policy::ScreenSize);
                let vs = |curve: &[(f64, f64)], v: f64, m: ErrorMeasure| {
                    triangles_at_equal(curve, v, m).map(|t| s.triangles / t)
                };
                let flip = Some(s.flip_mean).filter(|_| compared);
                let jod = s.jod.filter(|_| compared);
                ErrorRow {
                    vs_screen_size_flip: flip.and_then(|f| vs(&flip_curve, f, ErrorMeasure::Flip)),
                    vs_screen_size_jod: jod.and_then(|j| vs(&jod_curve, j, ErrorMeasure::Jod)),
                    screen_size_local_p999: jod
                        .and_then(|j| local_p999_at_equal_jod(&local_curve, j)),
                    summary: s.clone(),
                }
            })
            .collect();
        Self { rows, fvvdp }
    }

    /// The table `acuity experiment error` prints: a header, one line per
    /// row and what the columns mean; the JOD columns only when FovVideoVDP
    /// scored the sweep.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let jod_head = if self.fvvdp {
            format!(
                " {:>6} {:>10} {:>9} {:>9}",
                "JOD", "vs scr JOD", "JOD p99.9", "scr p99.9"
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "{:<17} {:>8} {:>9} {:>9} {:>10} {:>6} {:>6} {:>6} {:>8} {:>8} {:>10}{jod_head}",
            "policy",
            "knob",
            "mean ms",
            "p95 ms",
            "tris/frm",
            "LOD",
            "sw/s",
            "rev/s",
            "FLIP",
            "FLIP p95",
            "vs screen"
        );
        for r in &self.rows {
            let s = &r.summary;
            let jod_cols = if self.fvvdp {
                format!(
                    " {:>6} {:>10} {:>9} {:>9}",
                    text(s.jod, &|j| format!("{j:.3}"), "-"),
                    text(r.vs_screen_size_jod, &|r| format!("{r:.2}x"), "-"),
                    text(s.jod_local_p999, &|r| format!("{r:.3}"), "-"),
                    text(r.screen_size_local_p999, &|r| format!("{r:.3}"), "-")
                )
            } else {
                String::new()
            };
            // FLIP is not measured with `--metric fvvdp` alone: "-", not NaN.
            let flip = |v: f64| text(v.is_finite().then_some(v), &|v| format!("{v:.4}"), "-");
            let _ = writeln!(
                out,
                "{:<17} {:>8} {:>9.2} {:>9.2} {:>10.0} {:>6.2} {:>6.1} {:>6.1} {:>8} {:>8} {:>10}{jod_cols}",
                s.policy.name(),
                s.knob,
                s.mean_ms,
                s.p95_ms,
                s.triangles,
                s.mean_lod,
                s.switches_per_s,
                s.reversals_per_s,
                flip(s.flip_mean),
                flip(s.flip_p95),
                text(r.vs_screen_size_flip, &|r| format!("{r:.2}x"), "-")
            );
        }
        out.push_str(
            "\nknob: screen size's bias (acuity_best_effort_matched: the bias whose triangles it gets each frame), acuity's scale factor s,\n\
             or the budget's share of full detail's triangles;\n\
             tris/frm: triangles a frame; LOD: mean LOD drawn (0 = finest); sw/s, rev/s: LOD switches a second, and back within 0.25 s;\n\
             FLIP: mean error against full detail (0 = identical); vs screen: triangles over screen size's at the same FLIP (below 1: fewer).\n",
        );
        if self.fvvdp {
            out.push_str(
                "JOD: FovVideoVDP quality, foveated (10 = indistinguishable); vs scr JOD: triangles over screen size's at the same JOD;\n\
                 JOD p99.9: the local 99.9th percentile (the worst small region); scr p99.9: screen size's at the same JOD.\n",
            );
        }
        out
    }

    /// The rows as `error.csv` holds them, with its header.
    pub fn csv(&self) -> String {
        let mut csv = String::from(
            "policy,knob,mean_ms,p95_ms,triangles,mean_lod,lod_switches_per_s,flip_mean,flip_p95,triangles_vs_screen_size,jod,triangles_vs_screen_size_jod,lod_reversals_per_s,jod_local_p999,selection_visibility_deg,screen_size_jod_local_p999,triangles_max\n",
        );
        for r in &self.rows {
            let s = &r.summary;
            let _ = writeln!(
                csv,
                "{},{},{:.4},{:.4},{:.1},{:.4},{:.3},{:.6},{:.6},{},{},{},{:.3},{},{},{},{:.0}",
                s.policy.name(),
                s.knob,
                s.mean_ms,
                s.p95_ms,
                s.triangles,
                s.mean_lod,
                s.switches_per_s,
                s.flip_mean,
                s.flip_p95,
                text(r.vs_screen_size_flip, &|r| format!("{r:.4}"), ""),
                text(s.jod, &|r| format!("{r:.4}"), ""),
                text(r.vs_screen_size_jod, &|r| format!("{r:.4}"), ""),
                s.reversals_per_s,
                text(s.jod_local_p999, &|r| format!("{r:.4}"), ""),
                text(s.visibility_deg, &|r| format!("{r:.4}"), ""),
                text(r.screen_size_local_p999, &|r| format!("{r:.4}"), ""),
                s.triangles_max,
            );
        }
        csv
    }
}

/// `v` formatted by `f`, or `none`.
fn text(v: Option<f64>, f: &dyn Fn(f64) -> String, none: &str) -> String {
    v.map_or(none.into(), f)
}

/// An error measure, for comparisons at equal error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorMeasure {
    /// Mean FLIP: lower is better, 0 = identical. Compared on a log scale,
    /// so points of zero FLIP are left out.
    Flip,
    /// FovVideoVDP JOD: higher is better, 10 = identical. Already a
    /// perceptual scale (one JOD, 75% of observers), compared linearly;
    /// every finite value counts, 10 included.
    Jod,
}

/// The triangles per frame a policy curve (points of error and triangles,
/// any order) reaches at error `value`, interpolating log(triangles)
/// linearly between the two neighbouring points along the measure's axis
/// (log FLIP, or JOD). `None` outside the curve's range of error or where
/// there is none (no extrapolation: a comparison at an error the curve
/// never reached is not measured). Points with equal error count as the
/// one with the fewest triangles (the curve reaches that error with
/// those). The direction of the measure does not matter here: only where
/// `value` falls between points does.
pub fn triangles_at_equal(curve: &[(f64, f64)], value: f64, measure: ErrorMeasure) -> Option<f64> {
    let axis = |e: f64| match measure {
        ErrorMeasure::Flip => (e > 0.0 && e.is_finite()).then(|| e.ln()),
        ErrorMeasure::Jod => e.is_finite().then_some(e),
    };
    let x = axis(value)?;
    let pts: Vec<(f64, f64)> = curve
        .iter()
        .filter(|&&(_, t)| t > 0.0 && t.is_finite())
        .filter_map(|&(e, t)| Some((axis(e)?, t.ln())))
        .collect();
    super::interpolate::linear_at(&pts, x, super::interpolate::Ties::Lowest).map(f64::exp)
}

/// The local 99.9th percentile a curve of points `(JOD, local 99.9th
/// percentile)` (any order) shows at JOD `jod`, interpolated linearly in
/// JOD between the two neighbouring points. `None` outside the curve's
/// range of JOD or where there is none (no extrapolation); non-finite
/// points are left out, and points of equal JOD count as the lowest local
/// value among them (the comparison a policy must pass is against the
/// best the curve shows at that JOD).
pub fn local_p999_at_equal_jod(curve: &[(f64, f64)], jod: f64) -> Option<f64> {
    super::interpolate::linear_at(curve, jod, super::interpolate::Ties::Lowest)
}

/// [`triangles_at_equal`] for mean FLIP.
pub fn triangles_at_equal_error(curve: &[(f64, f64)], flip: f64) -> Option<f64> {
    triangles_at_equal(curve, flip, ErrorMeasure::Flip)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `got` is `want` up to rounding (log triangles are interpolated).
    fn near(got: Option<f64>, want: f64) -> bool {
        got.is_some_and(|g| (g - want).abs() <= 1e-9 * want.abs())
    }

    #[test]
    fn equal_error_interpolates_in_log_log_and_never_extrapolates() {
        let curve = [(0.04, 10_000.0), (0.01, 40_000.0), (0.0, 90_000.0)];
        let mid = triangles_at_equal_error(&curve, 0.02).unwrap();
        assert!((mid - 20_000.0).abs() < 1e-6, "{mid}");
        assert!(near(triangles_at_equal_error(&curve, 0.01), 40_000.0));
        assert_eq!(triangles_at_equal_error(&curve, 0.05), None);
        assert_eq!(triangles_at_equal_error(&curve, 0.005), None);
        assert_eq!(triangles_at_equal_error(&curve, 0.0), None);
        assert_eq!(triangles_at_equal_error(&curve, f64::NAN), None);
    }

    #[test]
    fn equal_jod_interpolates_log_triangles_linearly_in_jod() {
        // Higher is better: more triangles, higher JOD; any order.
        let curve = [(9.0, 40_000.0), (8.0, 10_000.0), (10.0, 90_000.0)];
        let j = |v| triangles_at_equal(&curve, v, ErrorMeasure::Jod);
        let mid = j(8.5).unwrap();
        assert!((mid - 20_000.0).abs() < 1e-6, "{mid}");
        let upper = j(9.5).unwrap();
        assert!((upper - 60_000.0).abs() < 1e-6, "{upper}");
        // The ends are in; JOD 10 (identical) is a point like any other.
        assert!(near(j(8.0), 10_000.0));
        assert!(near(j(10.0), 90_000.0));
        // No extrapolation, no NaN.
        assert_eq!(j(7.99), None);
        assert_eq!(j(10.01), None);
        assert_eq!(j(f64::NAN), None);
        // FLIP's log axis would refuse these; JOD takes them.
        let low = [(-1.0, 100.0), (0.0, 400.0)];
        let t = triangles_at_equal(&low, -0.5, ErrorMeasure::Jod).unwrap();
        assert!((t - 200.0).abs() < 1e-9, "{t}");
        assert_eq!(triangles_at_equal(&low, -0.5, ErrorMeasure::Flip), None);
    }

    #[test]
    fn local_maximum_at_equal_jod_interpolates_linearly_and_never_extrapolates() {
        // Screen size's sweep: a higher JOD, a lower local maximum.
        let curve = [(9.9, 0.2), (9.6, 1.1), (9.7, 0.8), (9.7, 0.9)];
        let at = |j| local_p999_at_equal_jod(&curve, j);
        let mid = at(9.8).unwrap();
        assert!((mid - 0.5).abs() < 1e-9, "{mid}");
        let low = at(9.65).unwrap();
        assert!((low - 0.95).abs() < 1e-9, "{low}");
        // Ties take the lowest local value; the ends are in.
        assert_eq!(at(9.7), Some(0.8));
        assert_eq!(at(9.9), Some(0.2));
        assert_eq!(at(9.59), None);
        assert_eq!(at(9.91), None);
        assert_eq!(at(f64::NAN), None);
        assert_eq!(local_p999_at_equal_jod(&[(f64::NAN, 1.0)], 9.0), None);
    }

    #[test]
    fn equal_error_ties_take_the_fewest_triangles_and_skip_bad_points() {
        let jod = [
            (9.0, 50_000.0),
            (9.0, 30_000.0),
            (10.0, 90_000.0),
            (f64::NAN, 1.0),
            (9.5, 0.0),
        ];
        assert!(near(
            triangles_at_equal(&jod, 9.0, ErrorMeasure::Jod),
            30_000.0
        ));
        let mid = triangles_at_equal(&jod, 9.5, ErrorMeasure::Jod).unwrap();
        assert!((mid - (30_000.0f64 * 90_000.0).sqrt()).abs() < 1e-6);
        // A single point matches only itself.
        assert!(near(
            triangles_at_equal(&[(9.2, 7.0)], 9.2, ErrorMeasure::Jod),
            7.0
        ));
        assert_eq!(
            triangles_at_equal(&[(9.2, 7.0)], 9.3, ErrorMeasure::Jod),
            None
        );
        // The same for FLIP, lower is better: the direction does not matter.
        let flip = [(0.02, 50_000.0), (0.02, 30_000.0), (0.01, 90_000.0)];
        assert!(near(triangles_at_equal_error(&flip, 0.02), 30_000.0));
    }
}
