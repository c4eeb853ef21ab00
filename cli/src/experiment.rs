//! `acuity experiment`: the reference experiments of Reddy 1998 §5.
//!
//! `speedup`: N copies of the test object at seeded random positions
//! (`scenes/reddy1998.toml` by default), N in {10, 20, 50, 100, 200, 500,
//! 1000}, several trials each with fresh positions; per trial the camera
//! path is flown with full detail, full acuity and acuity with velocity and
//! eccentricity only. Reported: speedup of full acuity over full detail in
//! mean frame time and in triangles, and the average LOD (1 = finest, as
//! the paper numbers them) of the drawn objects with all criteria versus
//! velocity + eccentricity, from which the size component's share of the
//! reduction is `1 - (lod_ev - 1) / (lod_all - 1)`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, anyhow, bail};

use crate::dump::{Metric, check_fvvdp, score_fvvdp};
use crate::frames::{ProfileArgs, World};
use crate::limits;
use crate::parse::parse_resolution;
use crate::placement::PlacementSpec;
use crate::player::{PlaySettings, Player};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::report::{Summary, attach_jod, format_table, summarize, write_frames_csv};
use crate::scene::{Policy, Scene};

/// The paper's object counts.
pub const PAPER_COUNTS: [u32; 7] = [10, 20, 50, 100, 200, 500, 1000];

/// Arguments of `acuity experiment`.
#[derive(clap::Args, Debug, Clone)]
pub struct ExperimentArgs {
    /// Which experiment.
    #[command(subcommand)]
    pub which: Experiment,
}

/// The experiments.
#[derive(clap::Subcommand, Debug, Clone)]
pub enum Experiment {
    /// Speedup of full acuity over full detail versus object count N, and
    /// the size component's share of the LOD reduction (Reddy 1998 §5.1–5.2).
    Speedup(SpeedupArgs),
    /// Run time against error: mean frame time and triangles versus mean
    /// FLIP (and FovVideoVDP JOD with `--metric fvvdp`), for screen size
    /// across its bias and acuity across `s`.
    Error(ErrorArgs),
    /// A fixed-frame-rate loop (VR-style yaw sweep) under load spikes:
    /// frames over budget and `s` over time, with and without each
    /// scheduler.
    Framerate(FramerateArgs),
}

/// Arguments of `acuity experiment error`.
#[derive(clap::Args, Debug, Clone)]
pub struct ErrorArgs {
    /// The scene.
    #[arg(long, default_value = "scenes/default.toml")]
    pub scene: PathBuf,
    /// Screen-size biases, comma-separated (> 0).
    #[arg(long, value_delimiter = ',', default_values_t = vec![0.25, 0.5, 1.0, 2.0, 4.0])]
    pub biases: Vec<f64>,
    /// Acuity scale factors `s`, comma-separated, in (0, 1].
    #[arg(long, value_delimiter = ',', default_values_t = vec![1.0, 0.5, 0.25, 0.125, 0.0625])]
    pub scales: Vec<f64>,
    /// Acuity policies swept across `s`, comma-separated: `acuity_size`
    /// isolates the size criterion, which FLIP (a foveal, gaze-free metric)
    /// judges fairly; eccentricity and velocity savings count as error in
    /// FLIP even where a viewer fixating the gaze cannot see them.
    #[arg(long, value_delimiter = ',', default_values_t = vec!["acuity_size".to_string(), "acuity_all".to_string()])]
    pub acuity_policies: Vec<String>,
    /// Frames per configuration, spread over the scene's path.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64))]
    pub frames: u32,
    /// FLIP on every n-th frame (>= 1).
    #[arg(long, default_value_t = 3)]
    pub flip_every: u32,
    /// Error metrics, comma-separated: `flip` (FLIP on every n-th frame)
    /// and `fvvdp` (FovVideoVDP on every frame, foveated at the gaze: needs
    /// Python with pyfvvdp, `$ACUITY_PYTHON` or `python3`; dumps the frames,
    /// to `<out>/frames/` without --dump-frames).
    #[arg(long, value_delimiter = ',', default_value = "flip")]
    pub metric: Vec<Metric>,
    /// Screen size's thresholds, relative screen heights, comma-separated,
    /// strictly decreasing (default: the scene's `run.screen_size_thresholds`,
    /// else 0.6,0.3,0.1,0.03).
    #[arg(long, value_delimiter = ',')]
    pub screen_size_thresholds: Option<Vec<f64>>,
    /// Weight screen size's relative heights by the observer's
    /// eccentricity factor at each object's angle from the gaze (a foveated
    /// screen-size baseline; default: the scene's `run.screen_size_foveated`).
    #[arg(long)]
    pub screen_size_foveated: bool,
    /// Options every experiment shares.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Arguments of `acuity experiment framerate`.
#[derive(clap::Args, Debug, Clone)]
pub struct FramerateArgs {
    /// The scene.
    #[arg(long, default_value = "scenes/vr_sweep.toml")]
    pub scene: PathBuf,
    /// Target frame rate, Hz, 1 to 10,000 (default: the scene's). A
    /// software rasteriser cannot reach 90 Hz on this scene; pick a rate it
    /// can nearly hold.
    #[arg(long, value_parser = crate::limits::parse_target_hz)]
    pub target_hz: Option<f64>,
    /// Frames, spread over the scene's path (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64))]
    pub frames: Option<u32>,
    /// Extra load during the spikes, as a fraction of the frame budget,
    /// 0 to 10.
    #[arg(long, default_value_t = 0.5, value_parser = crate::limits::parse_spike_load)]
    pub spike_load: f64,
    /// Options every experiment shares.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Options every experiment shares.
#[derive(clap::Args, Debug, Clone)]
pub struct CommonArgs {
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<[u32; 2]>,
    /// Output folder (default `out/experiment-<name>/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write every played frame to `DIR/<policy>_<knob>/NNNN.png` (RGB, as
    /// rendered; knob as in the CSV, full detail is `full_1`, dumped even
    /// when not played), each folder with gaze.csv (frame,x_px,y_px: the
    /// gaze in pixels, origin top-left, y down), and DIR/display.json
    /// (resolution, fov_deg, fps, photometry, sequences).
    #[arg(long, value_name = "DIR")]
    pub dump_frames: Option<PathBuf>,
    /// Profiles and progress.
    #[command(flatten)]
    pub profiles: ProfileArgs,
}

impl CommonArgs {
    fn load(&self, scene_path: &Path) -> anyhow::Result<World> {
        let mut scene = Scene::load(scene_path)?;
        if let Some(r) = self.resolution {
            scene.display.resolution_px = r;
        }
        let options = self.profiles.load_options(&scene.profiles);
        World::load(scene, &options)
    }

    fn out_dir(&self, name: &str) -> anyhow::Result<PathBuf> {
        let out = self
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join(format!("experiment-{name}")));
        std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
        Ok(out)
    }
}

/// Runs the error experiment; writes `error.csv`, with FLIP
/// `error_time.png` and `error_triangles.png`, with FovVideoVDP
/// `error_jod.png`; returns the summaries (full detail first).
pub fn error(args: &ErrorArgs) -> anyhow::Result<Vec<Summary>> {
    if args.frames == 0 || args.flip_every == 0 {
        bail!("--frames and --flip-every need at least 1");
    }
    if let Some(b) = args.biases.iter().find(|b| !(b.is_finite() && **b > 0.0)) {
        bail!("bias {b} is not > 0");
    }
    if let Some(s) = args.scales.iter().find(|s| !(**s > 0.0 && **s <= 1.0)) {
        bail!("scale factor {s} is not in (0, 1]");
    }
    let mut acuity_policies = Vec::new();
    for name in &args.acuity_policies {
        let p = crate::scene::policy_by_name(name)?;
        if !p.is_fixed_scale_acuity() {
            bail!("`{name}` is not an acuity policy with a fixed scale factor");
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
            .map_err(|e| anyhow::anyhow!("--screen-size-thresholds: {e}"))?;
        world.scene.run.screen_size_thresholds = table.clone();
    }
    world.scene.run.screen_size_foveated |= args.screen_size_foveated;
    let out = args.common.out_dir("error")?;
    let mut settings = PlaySettings::from_scene(&world.scene, Some(args.frames))?;
    settings.flip_every_n_frames = if flip { args.flip_every } else { 0 };
    settings.keep_images = false;
    settings.dump_dir = args
        .common
        .dump_frames
        .clone()
        .or_else(|| fvvdp.then(|| out.join("frames")));
    let mut configs = vec![(Policy::Full, 1.0)];
    configs.extend(args.biases.iter().map(|&b| (Policy::ScreenSize, b)));
    for &p in &acuity_policies {
        configs.extend(args.scales.iter().map(|&s| (p, s)));
    }
    let mut player = Player::new(&world, settings.clone())?;
    let runs = player.play_configs(&configs, 1.0)?;
    let mut sums = summarize(&runs, world.scene.run.budget_s());
    if let (true, Some(dir)) = (fvvdp, &settings.dump_dir) {
        attach_jod(&mut sums, &score_fvvdp(dir, args.common.profiles.quiet)?)?;
    }
    let screen_curve = |y: &dyn Fn(&Summary) -> f64| -> Vec<(f64, f64)> {
        sums.iter()
            .filter(|s| s.policy == Policy::ScreenSize)
            .map(|s| (y(s), s.triangles))
            .collect()
    };
    let (flip_curve, jod_curve) = (
        screen_curve(&|s| s.flip_mean),
        screen_curve(&|s| s.jod.unwrap_or(f64::NAN)),
    );
    let mut csv = String::from(
        "policy,knob,mean_ms,p95_ms,triangles,mean_lod,lod_switches_per_s,flip_mean,flip_p95,triangles_vs_screen_size,jod,triangles_vs_screen_size_jod\n",
    );
    let jod_head = if fvvdp {
        format!(" {:>6} {:>10}", "JOD", "vs scr JOD")
    } else {
        String::new()
    };
    println!(
        "{:<12} {:>8} {:>9} {:>9} {:>10} {:>6} {:>6} {:>8} {:>8} {:>10}{jod_head}",
        "policy",
        "knob",
        "mean ms",
        "p95 ms",
        "tris/frm",
        "LOD",
        "sw/s",
        "FLIP",
        "FLIP p95",
        "vs screen"
    );
    let text = |v: Option<f64>, f: &dyn Fn(f64) -> String, none: &str| v.map_or(none.into(), f);
    for s in &sums {
        let vs = |curve: &[(f64, f64)], v: f64, m: ErrorMeasure| match s.policy {
            Policy::Full | Policy::ScreenSize => None,
            _ => triangles_at_equal(curve, v, m).map(|t| s.triangles / t),
        };
        let ratio = vs(&flip_curve, s.flip_mean, ErrorMeasure::Flip);
        let ratio_jod = s.jod.and_then(|j| vs(&jod_curve, j, ErrorMeasure::Jod));
        let _ = writeln!(
            csv,
            "{},{},{:.4},{:.4},{:.1},{:.4},{:.3},{:.6},{:.6},{},{},{}",
            s.policy.name(),
            s.knob,
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.mean_lod,
            s.switches_per_s,
            s.flip_mean,
            s.flip_p95,
            text(ratio, &|r| format!("{r:.4}"), ""),
            text(s.jod, &|r| format!("{r:.4}"), ""),
            text(ratio_jod, &|r| format!("{r:.4}"), ""),
        );
        let jod_cols = if fvvdp {
            format!(
                " {:>6} {:>10}",
                text(s.jod, &|j| format!("{j:.3}"), "-"),
                text(ratio_jod, &|r| format!("{r:.2}x"), "-")
            )
        } else {
            String::new()
        };
        println!(
            "{:<12} {:>8} {:>9.2} {:>9.2} {:>10.0} {:>6.2} {:>6.1} {:>8.4} {:>8.4} {:>10}{jod_cols}",
            s.policy.name(),
            s.knob,
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.mean_lod,
            s.switches_per_s,
            s.flip_mean,
            s.flip_p95,
            text(ratio, &|r| format!("{r:.2}x"), "-")
        );
    }
    let path = out.join("error.csv");
    std::fs::write(&path, csv).with_context(|| format!("writing {}", path.display()))?;
    let curve = |p: Policy, x: &dyn Fn(&Summary) -> f64, y: &dyn Fn(&Summary) -> f64| {
        let mut pts: Vec<(f64, f64)> = sums
            .iter()
            .filter(|s| s.policy == p || s.policy == Policy::Full)
            .map(|s| (x(s), y(s)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        Series {
            name: match p {
                Policy::ScreenSize => "screen size (bias)".into(),
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
            "mean FLIP",
            "mean frame time (ms)",
            flip_x,
            &|s| s.mean_ms,
        ));
        plots.push((
            "error_triangles.png",
            "triangles vs FLIP",
            "mean FLIP",
            "triangles per frame",
            flip_x,
            &|s| s.triangles,
        ));
    }
    if fvvdp {
        plots.push((
            "error_jod.png",
            "triangles vs FovVideoVDP (10 = identical)",
            "JOD",
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
        let files: Vec<&str> = std::iter::once("error.csv")
            .chain(plots.iter().map(|p| p.0))
            .collect();
        eprintln!("wrote {} ({})", out.display(), files.join(", "));
    }
    Ok(sums)
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
    let mut pts: Vec<(f64, f64)> = curve
        .iter()
        .filter(|&&(_, t)| t > 0.0 && t.is_finite())
        .filter_map(|&(e, t)| Some((axis(e)?, t)))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup_by(|b, a| a.0 == b.0);
    if let Some(&(_, t)) = pts.iter().find(|p| p.0 == x) {
        return Some(t);
    }
    pts.windows(2).find_map(|w| {
        let ((x0, t0), (x1, t1)) = (w[0], w[1]);
        (x0 < x && x < x1).then(|| t0 * (t1 / t0).powf((x - x0) / (x1 - x0)))
    })
}

/// [`triangles_at_equal`] for mean FLIP.
pub fn triangles_at_equal_error(curve: &[(f64, f64)], flip: f64) -> Option<f64> {
    triangles_at_equal(curve, flip, ErrorMeasure::Flip)
}

/// Runs the frame-rate experiment; writes `framerate.csv` (per frame),
/// `framerate_time.png` and `framerate_scale.png`; returns the summaries.
pub fn framerate(args: &FramerateArgs) -> anyhow::Result<Vec<Summary>> {
    limits::check_spike_load(args.spike_load).map_err(|e| anyhow!("--spike-load: {e}"))?;
    if let Some(hz) = args.target_hz {
        limits::check_target_hz(hz).map_err(|e| anyhow!("--target-hz: {e}"))?;
    }
    let mut world = args.common.load(&args.scene)?;
    if let Some(hz) = args.target_hz {
        world.scene.run.target_hz = hz;
    }
    let mut settings = PlaySettings::from_scene(&world.scene, args.frames)?;
    settings.flip_every_n_frames = 0;
    settings.keep_images = false;
    settings.dump_dir = args.common.dump_frames.clone();
    // Two spikes, at 25-37.5% and 62.5-75% of the path.
    let d = f64::from(settings.frames) * settings.dt_s;
    let extra_ms = args.spike_load * world.scene.run.budget_s() * 1e3;
    settings.load_spikes = vec![
        (0.25 * d, 0.375 * d, extra_ms),
        (0.625 * d, 0.75 * d, extra_ms),
    ];
    let policies = [
        Policy::Full,
        Policy::AcuityAll,
        Policy::AcuityReactive,
        Policy::AcuityPredictive,
    ];
    let mut player = Player::new(&world, settings)?;
    let runs = player.play_all(&policies, 1.0)?;
    let sums = summarize(&runs, world.scene.run.budget_s());
    let out = args.common.out_dir("framerate")?;
    println!(
        "target {:.1} Hz ({:.2} ms), spikes of +{extra_ms:.2} ms at {:.2}-{:.2} s and {:.2}-{:.2} s",
        world.scene.run.target_hz,
        world.scene.run.budget_s() * 1e3,
        0.25 * d,
        0.375 * d,
        0.625 * d,
        0.75 * d
    );
    print!("{}", format_table(&sums));
    write_frames_csv(&runs, &out.join("framerate.csv"))?;
    let over_time = |f: &dyn Fn(&crate::player::FrameRecord) -> f64| -> Vec<Series> {
        runs.iter()
            .map(|r| Series {
                name: r.policy.name().into(),
                points: r.frames.iter().map(|x| (x.t_s, f(x))).collect(),
            })
            .collect()
    };
    let budget_ms = world.scene.run.budget_s() * 1e3;
    let mut time_series = over_time(&|f| f.frame_ms);
    time_series.push(Series {
        name: "budget".into(),
        points: vec![(0.0, budget_ms), (d, budget_ms)],
    });
    save_line_plot(
        &LinePlot {
            title: "frame time under load spikes".into(),
            x_label: "simulated time (s)".into(),
            y_label: "ms".into(),
            series: time_series,
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_time.png"),
    )?;
    save_line_plot(
        &LinePlot {
            title: "scale factor s".into(),
            x_label: "simulated time (s)".into(),
            y_label: "s".into(),
            series: over_time(&|f| f64::from(f.scale)),
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_scale.png"),
    )?;
    if !args.common.profiles.quiet {
        eprintln!(
            "wrote {} (framerate.csv, framerate_time.png, framerate_scale.png)",
            out.display()
        );
    }
    Ok(sums)
}

/// Arguments of `acuity experiment speedup`.
#[derive(clap::Args, Debug, Clone)]
pub struct SpeedupArgs {
    /// Scene with one object placed by `copies` (its count and seed are
    /// replaced per N and trial).
    #[arg(long, default_value = "scenes/reddy1998.toml")]
    pub scene: PathBuf,
    /// Object counts, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = PAPER_COUNTS.to_vec())]
    pub counts: Vec<u32>,
    /// Trials per count (seeds `seed + trial`), at least 1.
    #[arg(long, default_value_t = 3)]
    pub trials: u32,
    /// Frames per flight, spread over the scene's path.
    #[arg(long, default_value_t = 25, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64))]
    pub frames: u32,
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept);
    /// the paper's 1280x1024 is slow on a software rasteriser.
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<[u32; 2]>,
    /// Output folder (default `out/experiment-speedup/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write every played frame, per N and trial, to
    /// `DIR/nNNNN_trialT/<policy>_<knob>/NNNN.png` (e.g.
    /// `n0100_trial0/acuity_all_1/0007.png`; RGB, as rendered; knob as in
    /// `acuity run`'s dump, full detail `full_1`), each policy folder with
    /// gaze.csv (frame,x_px,y_px: the gaze in pixels, origin top-left, y
    /// down), each trial folder with display.json (resolution, fov_deg,
    /// fps, photometry, sequences).
    #[arg(long, value_name = "DIR")]
    pub dump_frames: Option<PathBuf>,
    /// Profiles and progress.
    #[command(flatten)]
    pub profiles: ProfileArgs,
}

/// One trial of the speedup experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedupTrial {
    /// Number of objects.
    pub count: u32,
    /// Seed of the placements.
    pub seed: u64,
    /// Mean frame time with full detail, ms.
    pub full_ms: f64,
    /// Mean frame time with full acuity, ms.
    pub acuity_ms: f64,
    /// Mean triangles per frame, full detail.
    pub full_triangles: f64,
    /// Mean triangles per frame, full acuity.
    pub acuity_triangles: f64,
    /// Average LOD (1 = finest) of drawn objects, all criteria.
    pub lod_all: f64,
    /// Average LOD (1 = finest) of drawn objects, velocity + eccentricity.
    pub lod_ecc_vel: f64,
}

impl SpeedupTrial {
    /// Full detail's mean frame time over full acuity's.
    pub fn speedup_time(&self) -> f64 {
        self.full_ms / self.acuity_ms
    }

    /// Full detail's mean triangles over full acuity's.
    pub fn speedup_triangles(&self) -> f64 {
        self.full_triangles / self.acuity_triangles
    }
}

/// The share of the LOD reduction (average LOD above 1) that velocity and
/// eccentricity alone do not achieve, i.e. size's share; NaN when all
/// criteria together lower the average LOD by less than 0.01.
pub fn size_share(lod_all: f64, lod_ecc_vel: f64) -> f64 {
    let all = lod_all - 1.0;
    // Below a hundredth of a level the share is noise.
    if all >= 0.01 {
        1.0 - (lod_ecc_vel - 1.0) / all
    } else {
        f64::NAN
    }
}

/// Runs the speedup experiment and writes `speedup.csv`, `speedup.png` and
/// `average_lod.png`; returns the trials.
pub fn speedup(args: &SpeedupArgs) -> anyhow::Result<Vec<SpeedupTrial>> {
    if args.trials == 0 || args.frames == 0 || args.counts.is_empty() {
        bail!("--trials, --frames and --counts need at least 1");
    }
    if let Some(&c) = args
        .counts
        .iter()
        .find(|&&c| c == 0 || c > crate::scene::MAX_COPIES)
    {
        bail!(
            "object count {c} is outside 1..={}",
            crate::scene::MAX_COPIES
        );
    }
    let mut scene = Scene::load(&args.scene)?;
    if scene.objects.len() != 1 || !matches!(scene.objects[0].placement, PlacementSpec::Copies(_)) {
        bail!(
            "{}: the speedup experiment needs exactly one object placed by `copies`",
            scene.source_path.display()
        );
    }
    if let Some(r) = args.resolution {
        scene.display.resolution_px = r;
    }
    scene.run.flip_every_n_frames = 0;
    let base_seed = match scene.objects[0].placement {
        PlacementSpec::Copies(c) => c.seed,
        PlacementSpec::Transform(_) => 0,
    };
    let mut world = World::load(scene.clone(), &args.profiles.load_options(&scene.profiles))?;
    let mut settings = PlaySettings::from_scene(&scene, Some(args.frames))?;
    settings.flip_every_n_frames = 0;
    settings.keep_images = false;
    settings.policies = vec![Policy::Full, Policy::AcuityAll, Policy::AcuityEccVel];
    let mut trials = Vec::new();
    for &count in &args.counts {
        for trial in 0..args.trials {
            let seed = base_seed.wrapping_add(u64::from(trial));
            let mut s = scene.clone();
            if let PlacementSpec::Copies(c) = &mut s.objects[0].placement {
                c.count = count;
                c.seed = seed;
            }
            world.replace_placements(s)?;
            let mut settings = settings.clone();
            settings.dump_dir = args
                .dump_frames
                .as_ref()
                .map(|d| d.join(format!("n{count:04}_trial{trial}")));
            let mut player = Player::new(&world, settings.clone())?;
            let runs = player.play_all(&settings.policies, world.scene.run.screen_size_bias)?;
            let sums = summarize(&runs, world.scene.run.budget_s());
            let t = SpeedupTrial {
                count,
                seed,
                full_ms: sums[0].mean_ms,
                acuity_ms: sums[1].mean_ms,
                full_triangles: sums[0].triangles,
                acuity_triangles: sums[1].triangles,
                lod_all: sums[1].mean_lod + 1.0,
                lod_ecc_vel: sums[2].mean_lod + 1.0,
            };
            if !args.profiles.quiet {
                eprintln!(
                    "N={count:<5} seed={seed:<6} speedup {:.2}x time, {:.2}x triangles; LOD all {:.2}, ecc+vel {:.2}",
                    t.speedup_time(),
                    t.speedup_triangles(),
                    t.lod_all,
                    t.lod_ecc_vel
                );
            }
            trials.push(t);
        }
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("experiment-speedup"));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut csv = String::from(
        "count,seed,full_ms,acuity_ms,speedup_time,full_triangles,acuity_triangles,speedup_triangles,lod_all,lod_ecc_vel,size_share\n",
    );
    for t in &trials {
        let _ = writeln!(
            csv,
            "{},{},{:.4},{:.4},{:.4},{:.1},{:.1},{:.4},{:.4},{:.4},{:.4}",
            t.count,
            t.seed,
            t.full_ms,
            t.acuity_ms,
            t.speedup_time(),
            t.full_triangles,
            t.acuity_triangles,
            t.speedup_triangles(),
            t.lod_all,
            t.lod_ecc_vel,
            size_share(t.lod_all, t.lod_ecc_vel)
        );
    }
    let csv_path = out.join("speedup.csv");
    std::fs::write(&csv_path, csv).with_context(|| format!("writing {}", csv_path.display()))?;
    // Means per count.
    let per_count = |f: &dyn Fn(&SpeedupTrial) -> f64| -> Vec<(f64, f64)> {
        args.counts
            .iter()
            .map(|&c| {
                let v: Vec<f64> = trials.iter().filter(|t| t.count == c).map(f).collect();
                (f64::from(c), v.iter().sum::<f64>() / v.len().max(1) as f64)
            })
            .collect()
    };
    let table_rows = (
        per_count(&|t| t.speedup_time()),
        per_count(&|t| t.speedup_triangles()),
        per_count(&|t| t.lod_all),
        per_count(&|t| t.lod_ecc_vel),
    );
    println!(
        "{:>6} {:>14} {:>14} {:>9} {:>9} {:>10}",
        "N", "speedup time", "speedup tris", "LOD all", "LOD e+v", "size share"
    );
    for i in 0..args.counts.len() {
        let (a, b, c, d) = (
            table_rows.0[i].1,
            table_rows.1[i].1,
            table_rows.2[i].1,
            table_rows.3[i].1,
        );
        let share = size_share(c, d);
        let share = if share.is_nan() {
            "none".to_string()
        } else {
            format!("{:.0}%", 100.0 * share)
        };
        println!(
            "{:>6} {:>13.2}x {:>13.2}x {:>9.2} {:>9.2} {:>10}",
            args.counts[i], a, b, c, d, share
        );
    }
    save_line_plot(
        &LinePlot {
            title: "speedup of full acuity over full detail".into(),
            x_label: "objects N (log)".into(),
            y_label: "speedup (x)".into(),
            series: vec![
                Series {
                    name: "frame time".into(),
                    points: table_rows.0.clone(),
                },
                Series {
                    name: "triangles".into(),
                    points: table_rows.1.clone(),
                },
            ],
            log_x: true,
            markers: true,
            y_from_zero: true,
        },
        &out.join("speedup.png"),
    )?;
    save_line_plot(
        &LinePlot {
            title: "average LOD (1 = finest)".into(),
            x_label: "objects N (log)".into(),
            y_label: "LOD".into(),
            series: vec![
                Series {
                    name: "all criteria".into(),
                    points: table_rows.2,
                },
                Series {
                    name: "velocity + eccentricity".into(),
                    points: table_rows.3,
                },
            ],
            log_x: true,
            markers: true,
            y_from_zero: true,
        },
        &out.join("average_lod.png"),
    )?;
    if !args.profiles.quiet {
        eprintln!(
            "wrote {} (speedup.csv, speedup.png, average_lod.png)",
            out.display()
        );
    }
    Ok(trials)
}

/// `acuity experiment` as a command: errors print as one line, exit code 2.
pub fn command(args: &ExperimentArgs) -> ExitCode {
    let result = match &args.which {
        Experiment::Speedup(a) => speedup(a).map(|_| ()),
        Experiment::Error(a) => error(a).map(|_| ()),
        Experiment::Framerate(a) => framerate(a).map(|_| ()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", crate::error_line(&e));
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_error_interpolates_in_log_log_and_never_extrapolates() {
        let curve = [(0.04, 10_000.0), (0.01, 40_000.0), (0.0, 90_000.0)];
        let mid = triangles_at_equal_error(&curve, 0.02).unwrap();
        assert!((mid - 20_000.0).abs() < 1e-6, "{mid}");
        assert_eq!(triangles_at_equal_error(&curve, 0.01), Some(40_000.0));
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
        assert_eq!(j(8.0), Some(10_000.0));
        assert_eq!(j(10.0), Some(90_000.0));
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
    fn equal_error_ties_take_the_fewest_triangles_and_skip_bad_points() {
        let jod = [
            (9.0, 50_000.0),
            (9.0, 30_000.0),
            (10.0, 90_000.0),
            (f64::NAN, 1.0),
            (9.5, 0.0),
        ];
        assert_eq!(
            triangles_at_equal(&jod, 9.0, ErrorMeasure::Jod),
            Some(30_000.0)
        );
        let mid = triangles_at_equal(&jod, 9.5, ErrorMeasure::Jod).unwrap();
        assert!((mid - (30_000.0f64 * 90_000.0).sqrt()).abs() < 1e-6);
        // A single point matches only itself.
        assert_eq!(
            triangles_at_equal(&[(9.2, 7.0)], 9.2, ErrorMeasure::Jod),
            Some(7.0)
        );
        assert_eq!(
            triangles_at_equal(&[(9.2, 7.0)], 9.3, ErrorMeasure::Jod),
            None
        );
        // The same for FLIP, lower is better: the direction does not matter.
        let flip = [(0.02, 50_000.0), (0.02, 30_000.0), (0.01, 90_000.0)];
        assert_eq!(triangles_at_equal_error(&flip, 0.02), Some(30_000.0));
    }

    #[test]
    fn size_share_is_the_part_ecc_vel_misses() {
        assert!((size_share(3.0, 1.1) - 0.95).abs() < 1e-12);
        assert_eq!(size_share(2.0, 1.0), 1.0);
        assert!(size_share(1.0, 1.0).is_nan());
    }
}
