//! `acuity run <scene>`: fly a scene's camera path under each LOD policy,
//! measure every frame, compare sampled frames with full detail by FLIP,
//! and write a table, a per-frame CSV, plots and side-by-side images;
//! optionally dump every frame and score the dump with FovVideoVDP
//! ([`crate::dump`]).
//!
//! Frame time is wall-clock time from the start of LOD selection to the
//! moment the rendered image is back in memory (the renderer waits for the
//! GPU), so it counts selection, submission, rasterisation and readback.
//! The full-detail reference frames, FLIP and frame dumps are computed
//! outside it.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use image::RgbImage;

use crate::dump::{FrameDump, Metric, REFERENCE_SEQUENCE, sequence_name};
use crate::flip::{flip_rgba, quantile};
use crate::frames::{FrameView, ProfileArgs, World, parse_resolution};
use crate::gaze::Gaze as GazePath;
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::policy::{PolicyRunner, fit_cost_model};
use crate::scene::{MAX_FRAMES, Policy, Scene};
use acuity::CostModel;

/// Arguments of `acuity run`.
#[derive(clap::Args, Debug, Clone)]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Output folder (default `out/<scene file name>/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Number of frames, spread over the same path, 1 to 10,000,000
    /// (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64))]
    pub frames: Option<u32>,
    /// Policies to run, comma-separated (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    pub policies: Option<Vec<String>>,
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<[u32; 2]>,
    /// Error metrics, comma-separated: `flip` (FLIP on sampled frames) and
    /// `fvvdp` (FovVideoVDP on every frame, foveated at the gaze: needs
    /// Python with pyfvvdp, `$ACUITY_PYTHON` or `python3`; dumps the frames,
    /// to `<out>/frames/` without --dump-frames).
    #[arg(long, value_delimiter = ',', default_value = "flip")]
    pub metric: Vec<Metric>,
    /// Write every played frame to `DIR/<policy>_<knob>/NNNN.png` (RGB, as
    /// rendered; knob as in the experiments' CSV, full detail is `full_1`,
    /// dumped even when `full` is not played), each folder with gaze.csv
    /// (frame,x_px,y_px: the gaze in pixels, origin top-left, y down), and
    /// DIR/display.json (resolution, fov_deg, fps, photometry, sequences).
    #[arg(long, value_name = "DIR")]
    pub dump_frames: Option<PathBuf>,
    /// Profiles and progress.
    #[command(flatten)]
    pub profiles: ProfileArgs,
}

/// Parses a feature-size statistic name: `longest`, `mean`, `shortest` or
/// `thickness`.
pub fn parse_statistic(text: &str) -> Result<acuity_preprocess::FrequencyStatistic, String> {
    use acuity_preprocess::FrequencyStatistic as F;
    match text {
        "longest" => Ok(F::Longest),
        "mean" => Ok(F::Mean),
        "shortest" => Ok(F::Shortest),
        "thickness" => Ok(F::Thickness),
        _ => Err(format!(
            "`{text}` is not one of longest, mean, shortest, thickness"
        )),
    }
}

/// A policy by its scene-file name.
pub fn policy_by_name(name: &str) -> anyhow::Result<Policy> {
    Policy::ALL
        .into_iter()
        .find(|p| p.name() == name.trim())
        .with_context(|| {
            let names: Vec<&str> = Policy::ALL.iter().map(|p| p.name()).collect();
            format!("unknown policy `{name}` (known: {})", names.join(", "))
        })
}

/// How a scene is played.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaySettings {
    /// Frames per policy (>= 1).
    pub frames: u32,
    /// Simulated time between frames, seconds (> 0).
    pub dt_s: f64,
    /// FLIP against full detail on every n-th frame (0: never).
    pub flip_every_n_frames: u32,
    /// The policies, in run order.
    pub policies: Vec<Policy>,
    /// Keep each policy's worst-FLIP frame in memory for images.
    pub keep_images: bool,
    /// Extra load inside the timed frame: `(start_s, end_s, extra_ms)`
    /// windows of simulated time during which each frame also spins the
    /// CPU for `extra_ms` milliseconds (a stand-in for a game's logic or
    /// streaming spikes). Empty by default.
    pub load_spikes: Vec<(f64, f64, f64)>,
    /// Dump every played frame, and full detail's, into this folder
    /// ([`FrameDump`]); `None` by default.
    pub dump_dir: Option<PathBuf>,
}

impl PlaySettings {
    /// The scene's run settings; `frames` (if given, >= 1) replaces the
    /// frame count and spreads the frames over the same simulated time.
    pub fn from_scene(scene: &Scene, frames: Option<u32>) -> anyhow::Result<PlaySettings> {
        let run = &scene.run;
        let (frames, dt_s) = match frames {
            Some(0) => bail!("--frames must be at least 1"),
            Some(n) if u64::from(n) > MAX_FRAMES => {
                bail!("--frames {n} is more than {MAX_FRAMES}")
            }
            Some(n) => (n, run.frame_dt_s * f64::from(run.frames) / f64::from(n)),
            None => (run.frames, run.frame_dt_s),
        };
        Ok(PlaySettings {
            frames,
            dt_s,
            flip_every_n_frames: run.flip_every_n_frames,
            policies: run.policies.clone(),
            keep_images: true,
            load_spikes: Vec::new(),
            dump_dir: None,
        })
    }
}

/// One played frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameRecord {
    /// The policy.
    pub policy: Policy,
    /// Frame index.
    pub frame: u32,
    /// Simulated time, seconds.
    pub t_s: f64,
    /// Measured frame time (selection + render + readback), milliseconds.
    pub frame_ms: f64,
    /// Of which LOD selection, milliseconds.
    pub select_ms: f64,
    /// Triangles drawn.
    pub triangles: u64,
    /// Draw calls issued (one per distinct mesh and LOD).
    pub draw_calls: u32,
    /// Instances drawn (not culled).
    pub drawn: u32,
    /// Mean LOD index of the drawn instances (0 = finest); NaN if none.
    pub mean_lod: f64,
    /// Instances drawn this frame and the frame before at different LODs.
    pub lod_switches: u32,
    /// The scale factor `s` used.
    pub scale: f32,
    /// The predictive scheduler's triangle budget, if any.
    pub triangle_budget: Option<u64>,
    /// Mean per-pixel FLIP against full detail, on sampled frames.
    pub flip_mean: Option<f32>,
    /// 95th percentile of per-pixel FLIP, on sampled frames.
    pub flip_p95: Option<f32>,
}

/// The frame of a policy with the largest FLIP, for images.
#[derive(Debug, Clone)]
pub struct WorstFrame {
    /// Frame index.
    pub frame: u32,
    /// Its mean FLIP.
    pub flip_mean: f32,
    /// The policy's image, RGBA8 sRGB.
    pub test_rgba: Vec<u8>,
    /// The colour-mapped FLIP map, RGB8.
    pub map_rgb: Vec<u8>,
}

/// Everything measured for one policy.
#[derive(Debug, Clone)]
pub struct PolicyRun {
    /// The policy.
    pub policy: Policy,
    /// Its knob: the bias for screen size, the scale factor `s` (a cap
    /// for the schedulers) for acuity, 1 for full detail.
    pub knob: f64,
    /// One record per frame.
    pub frames: Vec<FrameRecord>,
    /// The worst-FLIP frame (if images were kept and FLIP was sampled).
    pub worst: Option<WorstFrame>,
}

/// Plays a loaded world under policies, sharing full-detail references.
pub struct Player<'w> {
    world: &'w World,
    gaze: GazePath,
    settings: PlaySettings,
    full: PolicyRunner,
    references: HashMap<u32, Vec<u8>>,
    cost_samples: Vec<(f64, u64)>,
    lods: Vec<Option<usize>>,
}

impl<'w> Player<'w> {
    /// A player for `world`; renders one untimed warm-up frame.
    pub fn new(world: &'w World, settings: PlaySettings) -> anyhow::Result<Player<'w>> {
        let full = PolicyRunner::new(
            world,
            Policy::Full,
            world.scene.run.screen_size_bias,
            fit_cost_model(&[]),
        )?;
        let mut p = Player {
            world,
            gaze: world.scene.gaze(),
            settings,
            full,
            references: HashMap::new(),
            cost_samples: Vec::new(),
            lods: Vec::new(),
        };
        let view = p.view(0);
        p.full.choose(world, &view, 0.0, &mut p.lods)?;
        world.render(&view, &p.lods)?;
        Ok(p)
    }

    /// The settings.
    pub fn settings(&self) -> &PlaySettings {
        &self.settings
    }

    fn view(&self, k: u32) -> FrameView {
        self.world
            .view_at(k, f64::from(k) * self.settings.dt_s, &self.gaze)
    }

    /// The full-detail image of frame `k` (rendered once, then cached).
    pub fn reference(&mut self, k: u32) -> anyhow::Result<&[u8]> {
        if !self.references.contains_key(&k) {
            let view = self.view(k);
            let mut lods = Vec::new();
            self.full.choose(self.world, &view, 0.0, &mut lods)?;
            let out = self.world.render(&view, &lods)?;
            self.references.insert(k, out.rgba);
        }
        Ok(&self.references[&k])
    }

    /// Measures a few untimed-for-results frames spread over the path, at
    /// full detail and with screen-size LODs (different triangle counts),
    /// and fits the predictive scheduler's starting cost model to them.
    /// Also warms the renderer's caches for every mesh.
    pub fn calibrate(&mut self, screen_size_bias: f64) -> anyhow::Result<CostModel> {
        let world = self.world;
        let mut screen = PolicyRunner::new(
            world,
            Policy::ScreenSize,
            screen_size_bias,
            fit_cost_model(&[]),
        )?;
        let n = self.settings.frames.min(CALIBRATION_FRAMES);
        let mut lods = Vec::new();
        for i in 0..n {
            let k = i * self.settings.frames / n;
            let view = self.view(k);
            for runner in [&mut self.full, &mut screen] {
                let start = Instant::now();
                runner.choose(world, &view, 0.0, &mut lods)?;
                let out = world.render(&view, &lods)?;
                self.cost_samples
                    .push((start.elapsed().as_secs_f64(), out.triangles));
            }
        }
        Ok(fit_cost_model(&self.cost_samples))
    }

    /// Plays every frame under each policy, each with a fresh selector.
    /// Policies are interleaved frame by frame (in an order rotated every
    /// frame), so background load and caches affect them alike.
    pub fn play_all(
        &mut self,
        policies: &[Policy],
        screen_size_bias: f64,
    ) -> anyhow::Result<Vec<PolicyRun>> {
        let s = self.world.scene.run.scale_factor;
        let configs: Vec<(Policy, f64)> = policies
            .iter()
            .map(|&p| match p {
                Policy::Full => (p, 1.0),
                Policy::ScreenSize => (p, screen_size_bias),
                _ => (p, s),
            })
            .collect();
        self.play_configs(&configs, screen_size_bias)
    }

    /// As [`Player::play_all`], each policy with its own knob (see
    /// [`PolicyRun::knob`]); a policy may appear with several knobs.
    /// `calibration_bias` is the screen-size bias of the calibration frames.
    pub fn play_configs(
        &mut self,
        configs: &[(Policy, f64)],
        calibration_bias: f64,
    ) -> anyhow::Result<Vec<PolicyRun>> {
        let world = self.world;
        let needed = crate::limits::play_memory_bytes(
            u64::from(self.settings.frames),
            configs.len() as u64,
            std::mem::size_of::<FrameRecord>() as u64,
            world.scene.display.resolution_px,
            self.settings.flip_every_n_frames,
            self.settings.keep_images,
        );
        crate::limits::check_memory(
            needed,
            &format!(
                "{} frames x {} policies at {}x{} pixels",
                self.settings.frames,
                configs.len(),
                world.scene.display.resolution_px[0],
                world.scene.display.resolution_px[1]
            ),
        )
        .map_err(|e| anyhow::anyhow!("{e}: use fewer frames, policies or pixels"))?;
        let cost = self.calibrate(calibration_bias)?;
        let mut runners = configs
            .iter()
            .map(|&(p, knob)| {
                let bias = if p == Policy::ScreenSize { knob } else { 1.0 };
                let mut r = PolicyRunner::new(world, p, bias, cost)?;
                if p != Policy::Full && p != Policy::ScreenSize {
                    r.set_scale(knob);
                }
                Ok(r)
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let mut runs: Vec<PolicyRun> = configs
            .iter()
            .map(|&(policy, knob)| PolicyRun {
                policy,
                knob,
                frames: Vec::with_capacity(self.settings.frames as usize),
                worst: None,
            })
            .collect();
        let policies = configs;
        let [w, h] = world.scene.display.resolution_px;
        let ppd = world.pixels_per_degree();
        let mut lods = std::mem::take(&mut self.lods);
        // Each policy's choices of the frame before, to count LOD switches.
        let mut before: Vec<Vec<Option<usize>>> = vec![Vec::new(); policies.len()];
        let n_pol = policies.len().max(1);
        // A sequence per distinct name (a repeated configuration is dumped
        // once), and full detail's even when it is not played.
        let names: Vec<String> = configs.iter().map(|&(p, k)| sequence_name(p, k)).collect();
        let dumped: Vec<bool> = (0..names.len())
            .map(|i| !names[..i].contains(&names[i]))
            .collect();
        let dump_reference = !names.iter().any(|n| n == REFERENCE_SEQUENCE);
        let mut dump = match &self.settings.dump_dir {
            Some(dir) => Some(FrameDump::create(
                dir,
                &world.scene.display,
                self.settings.dt_s,
            )?),
            None => None,
        };
        for k in 0..self.settings.frames {
            let view = self.view(k);
            let gaze_px = dump.as_ref().map(|d| d.gaze_pixel(view.gaze_camera));
            for j in 0..policies.len() {
                let p = (j + k as usize) % n_pol;
                let (runner, run) = (&mut runners[p], &mut runs[p]);
                let start = Instant::now();
                let choice = runner.choose(world, &view, self.settings.dt_s as f32, &mut lods)?;
                let selected = start.elapsed();
                let out = world.render(&view, &lods)?;
                if let Some(&(_, _, ms)) = self
                    .settings
                    .load_spikes
                    .iter()
                    .find(|(a, b, _)| (*a..*b).contains(&view.t_s))
                {
                    spin(start.elapsed().as_secs_f64() + ms * 1e-3, start);
                }
                let frame_s = start.elapsed().as_secs_f64();
                runner.observe(frame_s, out.triangles);
                let lod_switches = lod_switches(&before[p], &lods);
                before[p].clone_from(&lods);
                if let (Some(d), Some(g)) = (dump.as_mut(), gaze_px)
                    && dumped[p]
                {
                    d.write_frame(&names[p], k, &out.rgba, g)?;
                }
                let drawn: Vec<usize> = lods.iter().flatten().copied().collect();
                let mean_lod = if drawn.is_empty() {
                    f64::NAN
                } else {
                    drawn.iter().sum::<usize>() as f64 / drawn.len() as f64
                };
                let mut rec = FrameRecord {
                    policy: run.policy,
                    frame: k,
                    t_s: view.t_s,
                    frame_ms: frame_s * 1e3,
                    select_ms: selected.as_secs_f64() * 1e3,
                    triangles: out.triangles,
                    draw_calls: out.draw_calls,
                    drawn: drawn.len() as u32,
                    mean_lod,
                    lod_switches,
                    scale: choice.scale,
                    triangle_budget: choice.triangle_budget,
                    flip_mean: None,
                    flip_p95: None,
                };
                let every = self.settings.flip_every_n_frames;
                if every > 0 && k % every == 0 {
                    let keep = self.settings.keep_images;
                    let reference = self.reference(k)?;
                    let f = flip_rgba(reference, &out.rgba, w, h, ppd)?;
                    rec.flip_mean = Some(f.mean);
                    rec.flip_p95 = Some(f.p95);
                    if keep && run.worst.as_ref().is_none_or(|x| f.mean > x.flip_mean) {
                        run.worst = Some(WorstFrame {
                            frame: k,
                            flip_mean: f.mean,
                            test_rgba: out.rgba,
                            map_rgb: f.map_rgb,
                        });
                    }
                }
                run.frames.push(rec);
            }
            if let (Some(d), Some(g)) = (dump.as_mut(), gaze_px)
                && dump_reference
            {
                let rendered;
                let rgba: &[u8] = match self.references.get(&k) {
                    Some(r) => r,
                    None => {
                        self.full.choose(world, &view, 0.0, &mut lods)?;
                        rendered = world.render(&view, &lods)?;
                        &rendered.rgba
                    }
                };
                d.write_frame(REFERENCE_SEQUENCE, k, rgba, g)?;
            }
        }
        self.lods = lods;
        if let Some(d) = dump {
            d.finish()?;
        }
        Ok(runs)
    }
}

/// Instances drawn in both frames whose LOD differs (`None`: culled).
fn lod_switches(before: &[Option<usize>], now: &[Option<usize>]) -> u32 {
    before
        .iter()
        .zip(now)
        .filter(|(b, n)| b.is_some() && n.is_some() && b != n)
        .count() as u32
}

/// Busy-waits until `until_s` seconds after `start`.
fn spin(until_s: f64, start: Instant) {
    while start.elapsed().as_secs_f64() < until_s {
        std::hint::spin_loop();
    }
}

/// Frames measured by [`Player::calibrate`] (at most; fewer in short runs).
pub const CALIBRATION_FRAMES: u32 = 8;

/// Per-policy summary of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The policy.
    pub policy: Policy,
    /// Its knob ([`PolicyRun::knob`]).
    pub knob: f64,
    /// Mean frame time, milliseconds.
    pub mean_ms: f64,
    /// 95th percentile frame time, milliseconds.
    pub p95_ms: f64,
    /// Mean triangles per frame.
    pub triangles: f64,
    /// Mean draw calls per frame.
    pub draw_calls: f64,
    /// Mean LOD index over drawn instances and frames (0 = finest).
    pub mean_lod: f64,
    /// Mean frame time of full detail over this policy's, measured in the
    /// same run; `None` without a full-detail run.
    pub speedup: Option<f64>,
    /// Full detail's mean triangles over this policy's.
    pub triangle_ratio: Option<f64>,
    /// Mean over sampled frames of the frame's mean FLIP; NaN if none.
    pub flip_mean: f64,
    /// 95th percentile over sampled frames of the frame's mean FLIP.
    pub flip_p95: f64,
    /// Fraction of frames longer than the target period.
    pub over_budget: f64,
    /// Mean scale factor `s`.
    pub mean_scale: f64,
    /// LOD switches of drawn instances per second of simulated time
    /// (popping); NaN for a single frame.
    pub switches_per_s: f64,
    /// FovVideoVDP of the whole sequence against full detail, JOD (10 =
    /// identical); `None` unless scored ([`attach_jod`]).
    pub jod: Option<f64>,
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

/// Summarises runs; `budget_s` is the target frame period in seconds.
pub fn summarize(runs: &[PolicyRun], budget_s: f64) -> Vec<Summary> {
    let base = |f: &dyn Fn(&PolicyRun) -> f64| {
        runs.iter()
            .find(|r| r.policy == Policy::Full)
            .map(f)
            .filter(|v| v.is_finite() && *v > 0.0)
    };
    let ms = |r: &PolicyRun| mean(r.frames.iter().map(|f| f.frame_ms));
    let tris = |r: &PolicyRun| mean(r.frames.iter().map(|f| f.triangles as f64));
    let (full_ms, full_tris) = (base(&ms), base(&tris));
    runs.iter()
        .map(|r| {
            let times: Vec<f64> = r.frames.iter().map(|f| f.frame_ms).collect();
            let flips: Vec<f64> = r
                .frames
                .iter()
                .filter_map(|f| f.flip_mean.map(f64::from))
                .collect();
            let n = r.frames.len().max(1) as f64;
            Summary {
                policy: r.policy,
                knob: r.knob,
                mean_ms: ms(r),
                p95_ms: quantile(&times, 0.95),
                triangles: tris(r),
                draw_calls: mean(r.frames.iter().map(|f| f64::from(f.draw_calls))),
                mean_lod: mean(
                    r.frames
                        .iter()
                        .map(|f| f.mean_lod)
                        .filter(|x| x.is_finite()),
                ),
                speedup: full_ms.map(|b| b / ms(r)),
                triangle_ratio: full_tris.map(|b| b / tris(r)),
                flip_mean: mean(flips.iter().copied()),
                flip_p95: quantile(&flips, 0.95),
                over_budget: r
                    .frames
                    .iter()
                    .filter(|f| f.frame_ms * 1e-3 > budget_s)
                    .count() as f64
                    / n,
                mean_scale: mean(r.frames.iter().map(|f| f64::from(f.scale))),
                switches_per_s: {
                    let span = match (r.frames.first(), r.frames.last()) {
                        (Some(a), Some(b)) => b.t_s - a.t_s,
                        _ => 0.0,
                    };
                    let total: u64 = r.frames.iter().map(|f| u64::from(f.lod_switches)).sum();
                    if span > 0.0 {
                        total as f64 / span
                    } else {
                        f64::NAN
                    }
                },
                jod: None,
            }
        })
        .collect()
}

/// Sets each summary's [`Summary::jod`] from FovVideoVDP scores by
/// sequence name ([`sequence_name`]); every summary must have one.
pub fn attach_jod(summaries: &mut [Summary], scores: &BTreeMap<String, f64>) -> anyhow::Result<()> {
    for s in summaries {
        let name = sequence_name(s.policy, s.knob);
        let jod = scores
            .get(&name)
            .with_context(|| format!("FovVideoVDP gave no score for `{name}`"))?;
        s.jod = Some(*jod);
    }
    Ok(())
}

/// The summary as a text table; a JOD column when any summary has one.
pub fn format_table(summaries: &[Summary]) -> String {
    let with_jod = summaries.iter().any(|s| s.jod.is_some());
    let jod_col = |v: Option<f64>| match (with_jod, v) {
        (false, _) => String::new(),
        (true, Some(v)) => format!(" {v:>6.3}"),
        (true, None) => format!(" {:>6}", "-"),
    };
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<18} {:>9} {:>9} {:>10} {:>6} {:>8} {:>8} {:>6} {:>6} {:>8} {:>8} {:>6} {:>5}{}",
        "policy",
        "mean ms",
        "p95 ms",
        "tris/frm",
        "draws",
        "speedup",
        "tri x",
        "LOD",
        "sw/s",
        "FLIP",
        "FLIP p95",
        "over%",
        "s",
        if with_jod {
            format!(" {:>6}", "JOD")
        } else {
            String::new()
        }
    );
    let opt = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2}x"));
    let flip = |v: f64| {
        if v.is_finite() {
            format!("{v:.4}")
        } else {
            "-".to_owned()
        }
    };
    for s in summaries {
        let _ = writeln!(
            t,
            "{:<18} {:>9.2} {:>9.2} {:>10.0} {:>6.1} {:>8} {:>8} {:>6.2} {:>6.1} {:>8} {:>8} {:>6.1} {:>5.2}{}",
            s.policy.name(),
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.draw_calls,
            opt(s.speedup),
            opt(s.triangle_ratio),
            s.mean_lod,
            s.switches_per_s,
            flip(s.flip_mean),
            flip(s.flip_p95),
            100.0 * s.over_budget,
            s.mean_scale,
            jod_col(s.jod)
        );
    }
    t
}

/// Writes the per-frame CSV.
pub fn write_frames_csv(runs: &[PolicyRun], path: &Path) -> anyhow::Result<()> {
    let mut t = String::from(
        "policy,frame,t_s,frame_ms,select_ms,triangles,draw_calls,drawn,mean_lod,lod_switches,scale,triangle_budget,flip_mean,flip_p95\n",
    );
    let o = |v: Option<String>| v.unwrap_or_default();
    for r in runs {
        for f in &r.frames {
            let _ = writeln!(
                t,
                "{},{},{:.6},{:.4},{:.4},{},{},{},{:.4},{},{:.5},{},{},{}",
                f.policy.name(),
                f.frame,
                f.t_s,
                f.frame_ms,
                f.select_ms,
                f.triangles,
                f.draw_calls,
                f.drawn,
                f.mean_lod,
                f.lod_switches,
                f.scale,
                o(f.triangle_budget.map(|b| b.to_string())),
                o(f.flip_mean.map(|v| format!("{v:.6}"))),
                o(f.flip_p95.map(|v| format!("{v:.6}"))),
            );
        }
    }
    std::fs::write(path, t).with_context(|| format!("writing {}", path.display()))
}

/// Writes the summary CSV.
pub fn write_summary_csv(summaries: &[Summary], path: &Path) -> anyhow::Result<()> {
    let mut t = String::from(
        "policy,mean_ms,p95_ms,triangles,draw_calls,mean_lod,lod_switches_per_s,speedup,triangle_ratio,flip_mean,flip_p95,over_budget,mean_scale,jod\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
    for s in summaries {
        let _ = writeln!(
            t,
            "{},{:.4},{:.4},{:.1},{:.2},{:.4},{:.3},{},{},{:.6},{:.6},{:.4},{:.4},{}",
            s.policy.name(),
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.draw_calls,
            s.mean_lod,
            s.switches_per_s,
            o(s.speedup),
            o(s.triangle_ratio),
            s.flip_mean,
            s.flip_p95,
            s.over_budget,
            s.mean_scale,
            s.jod.map(|v| format!("{v:.4}")).unwrap_or_default()
        );
    }
    std::fs::write(path, t).with_context(|| format!("writing {}", path.display()))
}

/// Writes `reference | test | FLIP map` side by side as one PNG.
pub fn write_side_by_side(
    reference_rgba: &[u8],
    worst: &WorstFrame,
    [w, h]: [u32; 2],
    path: &Path,
) -> anyhow::Result<()> {
    let n = w as usize * h as usize;
    if reference_rgba.len() != 4 * n
        || worst.test_rgba.len() != 4 * n
        || worst.map_rgb.len() != 3 * n
    {
        bail!("side-by-side images do not match {w}x{h}");
    }
    let mut img = RgbImage::new(3 * w, h);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let px = |b: &[u8], n: usize| image::Rgb([b[n * i], b[n * i + 1], b[n * i + 2]]);
            img.put_pixel(x, y, px(reference_rgba, 4));
            img.put_pixel(w + x, y, px(&worst.test_rgba, 4));
            img.put_pixel(2 * w + x, y, px(&worst.map_rgb, 3));
        }
    }
    img.save(path)
        .with_context(|| format!("writing {}", path.display()))
}

fn over_time(runs: &[PolicyRun], f: impl Fn(&FrameRecord) -> f64) -> Vec<Series> {
    runs.iter()
        .map(|r| Series {
            name: r.policy.name().to_owned(),
            points: r.frames.iter().map(|x| (x.t_s, f(x))).collect(),
        })
        .collect()
}

/// Writes the plots: frame time, triangles and `s` over time per policy.
pub fn write_plots(runs: &[PolicyRun], scene_name: &str, dir: &Path) -> anyhow::Result<()> {
    let plot = |title: &str, y: &str, series| LinePlot {
        title: format!("{scene_name}: {title}"),
        x_label: "simulated time (s)".into(),
        y_label: y.into(),
        series,
        y_from_zero: true,
        ..Default::default()
    };
    save_line_plot(
        &plot("frame time", "ms", over_time(runs, |f| f.frame_ms)),
        &dir.join("frame_time.png"),
    )?;
    save_line_plot(
        &plot(
            "triangles",
            "triangles",
            over_time(runs, |f| f.triangles as f64),
        ),
        &dir.join("triangles.png"),
    )?;
    save_line_plot(
        &plot(
            "scale factor s",
            "s",
            over_time(runs, |f| f64::from(f.scale)),
        ),
        &dir.join("scale.png"),
    )
}

/// What [`run`] produced.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// Per-policy runs.
    pub runs: Vec<PolicyRun>,
    /// Their summaries.
    pub summaries: Vec<Summary>,
    /// Where the files went.
    pub out_dir: PathBuf,
}

/// Loads `args.scene`, applies the overrides and loads its world.
pub fn load_world(args: &RunArgs) -> anyhow::Result<World> {
    let mut scene = Scene::load(&args.scene)?;
    if let Some(r) = args.resolution {
        scene.display.resolution_px = r;
    }
    if let Some(p) = &args.policies {
        let mut ps = Vec::new();
        for name in p {
            let policy = policy_by_name(name)?;
            if !ps.contains(&policy) {
                ps.push(policy);
            }
        }
        scene.run.policies = ps;
    }
    let options = args.profiles.load_options(&scene.profiles);
    World::load(scene, &options)
}

/// Runs `acuity run`: plays, prints the table and writes every output.
pub fn run(args: &RunArgs) -> anyhow::Result<RunOutcome> {
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    let fvvdp = args.metric.contains(&Metric::Fvvdp);
    if fvvdp {
        crate::dump::check_fvvdp()?;
    }
    let world = load_world(args)?;
    let scene = &world.scene;
    let name = scene
        .source_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&name));
    std::fs::create_dir_all(&out_dir).with_context(|| format!("creating {}", out_dir.display()))?;
    let mut settings = PlaySettings::from_scene(scene, args.frames)?;
    if !args.metric.contains(&Metric::Flip) {
        settings.flip_every_n_frames = 0;
    }
    settings.dump_dir = args
        .dump_frames
        .clone()
        .or_else(|| fvvdp.then(|| out_dir.join("frames")));
    if !args.profiles.quiet {
        eprintln!(
            "{name}: {} instances, {} frames x {} policies at {}x{}, renderer: {}",
            world.instances.len(),
            settings.frames,
            settings.policies.len(),
            scene.display.resolution_px[0],
            scene.display.resolution_px[1],
            world.renderer.adapter_info()
        );
    }
    let mut player = Player::new(&world, settings.clone())?;
    let started = Instant::now();
    let runs = player.play_all(&settings.policies, scene.run.screen_size_bias)?;
    if !args.profiles.quiet {
        eprintln!("played in {:.1} s", started.elapsed().as_secs_f64());
    }
    let mut summaries = summarize(&runs, scene.run.budget_s());
    if let (true, Some(dir)) = (fvvdp, &settings.dump_dir) {
        attach_jod(
            &mut summaries,
            &crate::dump::score_fvvdp(dir, args.profiles.quiet)?,
        )?;
    }
    print!("{}", format_table(&summaries));
    write_frames_csv(&runs, &out_dir.join("frames.csv"))?;
    write_summary_csv(&summaries, &out_dir.join("summary.csv"))?;
    write_plots(&runs, &name, &out_dir)?;
    for r in &runs {
        if let Some(wf) = &r.worst {
            let reference = player.reference(wf.frame)?.to_vec();
            let path = out_dir.join(format!("flip_{}_frame{:04}.png", r.policy.name(), wf.frame));
            write_side_by_side(&reference, wf, scene.display.resolution_px, &path)?;
        }
    }
    if !args.profiles.quiet {
        let flip_images = if runs.iter().any(|r| r.worst.is_some()) {
            ", flip_*.png: reference | policy | FLIP"
        } else {
            ""
        };
        eprintln!(
            "wrote {} (frames.csv, summary.csv, frame_time.png, triangles.png, scale.png{flip_images})",
            out_dir.display()
        );
        if let Some(dir) = &settings.dump_dir {
            eprintln!("dumped every frame to {}", dir.display());
        }
    }
    Ok(RunOutcome {
        runs,
        summaries,
        out_dir,
    })
}

/// `acuity run` as a command: errors print as one line; exit code 2 for
/// bad input or failures.
pub fn command(args: &RunArgs) -> ExitCode {
    match run(args) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", crate::error_line(&e));
            ExitCode::from(2)
        }
    }
}
