//! The scene player: plays a loaded [`World`] under LOD policies frame by
//! frame, measures every frame ([`FrameRecord`]) and compares sampled
//! frames with full detail by FLIP, sharing the full-detail references
//! between policies. `acuity run` and the experiments play through it.
//!
//! Frame time is wall-clock time from the start of LOD selection to the
//! moment the rendered image is back in memory (the renderer waits for the
//! GPU), so it counts selection, submission, rasterisation and readback.
//! The full-detail reference frames, FLIP and frame dumps are computed
//! outside it.

use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

use crate::dump::{FrameDump, REFERENCE_SEQUENCE, sequence_name};
use crate::flip::flip_rgba;
use crate::frames::{FrameView, World};
use crate::gaze::Gaze as GazePath;
use crate::policy::{PolicyRunner, fit_cost_model};
use crate::scene::{MAX_FRAMES, Policy, Scene};
use crate::switches::SwitchTracker;
use acuity::CostModel;
use indicatif::ProgressBar;

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
    /// The triangles a budgeted policy's share is of: `None` (default)
    /// full detail's triangles in view in the frame before, so the budget
    /// follows the objects in view; `Some(n)` (finite, > 0) a fixed count,
    /// so each share is one budget for every frame, as an engine's frame
    /// budget is.
    pub fixed_budget_base_triangles: Option<f64>,
}

impl PlaySettings {
    /// The scene's run settings; `frames` (if given, >= 1) replaces the
    /// frame count and spreads the frames over the same simulated time.
    pub fn from_scene(scene: &Scene, frames: Option<u32>) -> anyhow::Result<PlaySettings> {
        let run = &scene.run;
        let (frames, dt_s) = match frames {
            Some(0) => crate::bail_input!("--frames must be at least 1"),
            Some(n) if u64::from(n) > MAX_FRAMES => {
                crate::bail_input!("--frames {n} is more than {MAX_FRAMES}")
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
            fixed_budget_base_triangles: None,
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
    /// Of which reversals: switches back to the LOD left at the instance's
    /// previous switch, within [`crate::switches::REVERSAL_WINDOW_S`].
    pub lod_reversals: u32,
    /// Of the switches, slow reversals: back to the LOD left at the
    /// instance's previous switch within
    /// [`crate::switches::SLOW_REVERSAL_WINDOW_S`], the reversals included.
    pub lod_slow_reversals: u32,
    /// The scale factor `s` used.
    pub scale: f32,
    /// The predictive scheduler's triangle budget, if any.
    pub triangle_budget: Option<u64>,
    /// Whether the scheduler found this frame's cost floor above the frame
    /// period (no LOD choice could reach the target); `None` for policies
    /// without a scheduler that sees the floor.
    pub target_unreachable: Option<bool>,
    /// The scheduler's cost floor after this frame, ms (the frame at every
    /// visible object's coarsest LOD); `None` where unknown or blind.
    pub cost_floor_ms: Option<f64>,
    /// The frame time the scheduler aimed at after this frame, ms (its
    /// headroom below the period); `None` without a scheduler.
    pub aim_ms: Option<f64>,
    /// Whether the frame fell in a load spike ([`PlaySettings::load_spikes`]).
    pub in_spike: bool,
    /// Whether the policy's knob was at its end ([`crate::policy::Choice::at_limit`]):
    /// a late frame there ran over on the floor of what the policy may
    /// draw.
    pub at_limit: bool,
    /// The selection's visibility in best effort's measure, deg
    /// ([`crate::policy::Choice::visibility_deg`]).
    pub visibility_deg: Option<f64>,
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
    /// The gaze the selector models.
    gaze: GazePath,
    /// Where the viewer's eyes actually are (the metrics' fixation).
    viewer: GazePath,
    settings: PlaySettings,
    full: PolicyRunner,
    references: HashMap<u32, Vec<u8>>,
    cost_samples: Vec<(f64, u64)>,
    lods: Vec<Option<usize>>,
    progress: ProgressBar,
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
            viewer: world.scene.viewer_gaze(),
            settings,
            full,
            references: HashMap::new(),
            cost_samples: Vec::new(),
            lods: Vec::new(),
            progress: ProgressBar::hidden(),
        };
        let view = p.view(0);
        p.full.choose(world, &view, 0.0, &mut p.lods)?;
        world.render(&view, &p.lods)?;
        Ok(p)
    }

    /// Advances `bar` by one for every frame played under one policy (its
    /// length is the caller's: frames x policies, summed over players).
    pub fn set_progress(&mut self, bar: &ProgressBar) {
        self.progress = bar.clone();
    }

    /// The settings.
    pub fn settings(&self) -> &PlaySettings {
        &self.settings
    }

    fn view(&self, k: u32) -> FrameView {
        self.world.view_at(
            k,
            f64::from(k) * self.settings.dt_s,
            &self.gaze,
            &self.viewer,
        )
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
                Policy::ScreenSize | Policy::ScreenSizeReactive => (p, screen_size_bias),
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
        .map_err(|e| {
            crate::error::input_error(format!("{e}: use fewer frames, policies or pixels"))
        })?;
        let cost = self.calibrate(calibration_bias)?;
        let mut runners = configs
            .iter()
            .map(|&(p, knob)| {
                let bias = if p.knob_is_bias() {
                    knob
                } else if p.is_screen_size() {
                    world.scene.run.screen_size_bias
                } else {
                    1.0
                };
                let mut r = PolicyRunner::new(world, p, bias, cost)?;
                if p != Policy::Full && !p.knob_is_bias() {
                    r.set_knob(knob);
                }
                if let Some(base) = self.settings.fixed_budget_base_triangles {
                    r.fix_budget_base(base);
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
        let mut switches = vec![SwitchTracker::default(); policies.len()];
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
            let gaze_px = dump.as_ref().map(|d| d.gaze_pixel(view.fixation_camera));
            for j in 0..policies.len() {
                let p = (j + k as usize) % n_pol;
                let (runner, run) = (&mut runners[p], &mut runs[p]);
                let spike = self
                    .settings
                    .load_spikes
                    .iter()
                    .find(|(a, b, _)| (*a..*b).contains(&view.t_s));
                if let Some(&(_, _, ms)) = spike {
                    runner.announce_load(ms * 1e-3);
                }
                let start = Instant::now();
                let choice = runner.choose(world, &view, self.settings.dt_s as f32, &mut lods)?;
                let selected = start.elapsed();
                let out = world.render_faded(&view, &lods, runner.fades())?;
                if let Some(&(_, _, ms)) = spike {
                    spin(start.elapsed().as_secs_f64() + ms * 1e-3, start);
                }
                let frame_s = start.elapsed().as_secs_f64();
                runner.observe(frame_s, out.triangles);
                let switched = switches[p].observe(view.t_s, &lods);
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
                    lod_switches: switched.switches,
                    lod_reversals: switched.reversals,
                    lod_slow_reversals: switched.slow_reversals,
                    scale: choice.scale,
                    triangle_budget: choice.triangle_budget,
                    target_unreachable: runner.target_unreachable(),
                    cost_floor_ms: runner.cost_floor_s().map(|f| f * 1e3),
                    aim_ms: runner.aim_s().map(|a| a * 1e3),
                    in_spike: spike.is_some(),
                    at_limit: choice.at_limit,
                    visibility_deg: choice.visibility_deg,
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
                self.progress.inc(1);
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

/// Busy-waits until `until_s` seconds after `start`.
fn spin(until_s: f64, start: Instant) {
    while start.elapsed().as_secs_f64() < until_s {
        std::hint::spin_loop();
    }
}

/// Frames measured by [`Player::calibrate`] (at most; fewer in short runs).
pub const CALIBRATION_FRAMES: u32 = 8;
