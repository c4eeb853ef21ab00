//! The fixed-frame-rate controllers against a stepwise synthetic plant:
//! 300 objects with 4 discrete LODs each, whose frame time is the
//! triangles drawn times a cost per triangle times a load factor, with or
//! without noise (a frame's time varying by 5-10%).

mod common;

use acuity::{
    CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings, STEADY_SWITCH_HYSTERESIS,
};
use common::Rng;
use proptest::prelude::*;

const TRIANGLES: [f32; 4] = [3928.0, 834.0, 254.0, 76.0];

struct Plant {
    /// Per object, the scale below which it drops to LOD j+1.
    breakpoints: Vec<[f32; 3]>,
    seconds_per_triangle: f32,
}

impl Plant {
    fn new(seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let breakpoints = (0..300)
            .map(|_| {
                let a = rng.range(0.3, 1.6) as f32;
                [
                    a,
                    a * rng.range(0.2, 0.6) as f32,
                    a * rng.range(0.02, 0.15) as f32,
                ]
            })
            .collect();
        // At s = 1 and load 1 the frame takes 80% of a 90 Hz period.
        let mut p = Self {
            breakpoints,
            seconds_per_triangle: 1.0,
        };
        p.seconds_per_triangle = 0.8 / 90.0 / p.triangles(1.0);
        p
    }

    fn triangles(&self, scale: f32) -> f32 {
        self.breakpoints
            .iter()
            .map(|b| TRIANGLES[b.iter().filter(|&&s| scale < s).count()])
            .sum()
    }

    fn frame_time(&self, scale: f32, load: f32) -> f32 {
        load * self.triangles(scale) * self.seconds_per_triangle
    }

    fn lods(&self, scale: f32, out: &mut Vec<u8>) {
        out.clear();
        out.extend(
            self.breakpoints
                .iter()
                .map(|b| b.iter().filter(|&&s| scale < s).count() as u8),
        );
    }

    /// Moves each object's LOD (`lods`, empty at first) to scale `s` with
    /// the selector's switch hysteresis `h`: coarser only where `s (1 + h)`
    /// is below the breakpoint, finer at once. Returns the triangles.
    fn step_lods(&self, scale: f32, h: f32, lods: &mut Vec<u8>) -> f32 {
        let count = |s: f32, b: &[f32; 3]| b.iter().filter(|&&x| s < x).count() as u8;
        if lods.len() != self.breakpoints.len() {
            lods.clear();
            lods.extend(self.breakpoints.iter().map(|b| count(scale, b)));
        }
        let mut triangles = 0.0;
        for (lod, b) in lods.iter_mut().zip(&self.breakpoints) {
            let now = count(scale, b);
            *lod = if now > *lod {
                count(scale * (1.0 + h), b).clamp(*lod, now)
            } else {
                now
            };
            triangles += TRIANGLES[*lod as usize];
        }
        triangles
    }

    /// Triangles at the coarsest LOD of every object.
    fn coarsest_triangles(&self) -> u64 {
        (TRIANGLES[3] * self.breakpoints.len() as f32) as u64
    }

    /// The largest scale whose triangles fit `budget` (one `s` for all, as
    /// the uniform budget rule), or the lowest scale; and its triangles.
    fn fit_budget(&self, budget: u64) -> (f32, f32) {
        let mut breaks: Vec<f32> = self.breakpoints.iter().flatten().copied().collect();
        breaks.sort_by(|a, b| b.total_cmp(a));
        let mut scale = 1.0f32;
        for b in std::iter::once(1.0).chain(breaks.iter().map(|b| b * 0.999)) {
            scale = b.min(1.0);
            if self.triangles(scale) <= budget as f32 {
                break;
            }
        }
        (scale, self.triangles(scale))
    }
}

/// A multiplicative frame-time noise of relative standard deviation
/// `sigma` (about normal in the log).
fn noise(rng: &mut Rng, sigma: f32) -> f32 {
    let z: f64 = (0..12).map(|_| rng.unit()).sum::<f64>() - 6.0;
    (sigma * z as f32).exp()
}

/// LOD reversals: an object switching back to the LOD it left at its
/// previous switch within `window` frames.
#[derive(Default)]
struct Reversals {
    last: Vec<Option<(u8, usize)>>,
    before: Vec<u8>,
    count: usize,
    switches: usize,
}

impl Reversals {
    fn observe(&mut self, frame: usize, lods: &[u8], window: usize) {
        if self.before.len() != lods.len() {
            self.before = lods.to_vec();
            self.last = vec![None; lods.len()];
            return;
        }
        for (i, (&now, was)) in lods.iter().zip(self.before.iter_mut()).enumerate() {
            if now != *was {
                self.switches += 1;
                if let Some((from, at)) = self.last[i]
                    && from == now
                    && frame - at <= window
                {
                    self.count += 1;
                }
                self.last[i] = Some((*was, frame));
                *was = now;
            }
        }
    }
}

/// Frames at 90 Hz within which a switch back counts as a reversal (0.25 s).
const REVERSAL_WINDOW_FRAMES: usize = 22;

/// What a controller did in steady state on the noisy plant: the share of
/// frames over the period, LOD reversals and switches per second.
struct Steady {
    over: f64,
    reversals_per_s: f64,
    switches_per_s: f64,
}

/// The load at `frame`: `base` drifting by 15% over 3 s at 90 Hz (the scene
/// in view changing as the camera moves).
fn drifting(base: f32, frame: usize) -> f32 {
    base * (1.0 + 0.15 * (std::f32::consts::TAU * frame as f32 / 270.0).sin())
}

/// The reactive controller on the plant under `load` (drifting) with noise
/// `sigma`: 300 frames to settle, 600 measured.
fn reactive_steady(settings: ReactiveSettings, seed: u64, load: f32, sigma: f32) -> Steady {
    let plant = Plant::new(seed);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let mut sched = ReactiveScheduler::new(settings);
    let (mut lods, mut rev, mut over) = (Vec::new(), Reversals::default(), 0);
    for frame in 0..900 {
        let s = sched.scale();
        let triangles = plant.step_lods(s, STEADY_SWITCH_HYSTERESIS, &mut lods);
        if frame >= 300 {
            rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
        }
        let t =
            drifting(load, frame) * triangles * plant.seconds_per_triangle * noise(&mut rng, sigma);
        over += (frame >= 300 && t > settings.target_frame_s) as usize;
        sched.update(t);
    }
    Steady {
        over: over as f64 / 600.0,
        reversals_per_s: rev.count as f64 / (600.0 / 90.0),
        switches_per_s: rev.switches as f64 / (600.0 / 90.0),
    }
}

/// The predictive controller on the plant (one `s` for all within its
/// budget), with 1 ms of fixed time per frame.
fn predictive_steady(settings: ReactiveSettings, seed: u64, load: f32, sigma: f32) -> Steady {
    let plant = Plant::new(seed);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let fixed_s = 1e-3;
    let mut sched = PredictiveScheduler::new(
        settings,
        CostModel::new(fixed_s, plant.seconds_per_triangle),
    );
    let (mut lods, mut rev, mut over) = (Vec::new(), Reversals::default(), 0);
    for frame in 0..900 {
        let (s, triangles) = plant.fit_budget(sched.triangle_budget());
        plant.lods(s, &mut lods);
        if frame >= 300 {
            rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
        }
        let t = (fixed_s + drifting(load, frame) * triangles * plant.seconds_per_triangle)
            * noise(&mut rng, sigma);
        over += (frame >= 300 && t > settings.target_frame_s) as usize;
        sched.observe(t, triangles as u64, plant.coarsest_triangles());
    }
    Steady {
        over: over as f64 / 600.0,
        reversals_per_s: rev.count as f64 / (600.0 / 90.0),
        switches_per_s: rev.switches as f64 / (600.0 / 90.0),
    }
}

fn reversals(scales: &[f32]) -> usize {
    let mut last = 0.0f32;
    let mut count = 0;
    for w in scales.windows(2) {
        let d = w[1] - w[0];
        if d != 0.0 {
            if last != 0.0 && d.signum() != last.signum() {
                count += 1;
            }
            last = d;
        }
    }
    count
}

/// Frames the controller needs after a single 10x spike to be back at rest
/// (no further change), fitting the frame period and drawing at least 90%
/// of what it drew before (the dead band admits several resting levels of
/// `s`), with at most one reversal on the way.
const SPIKE_RECOVERY_FRAMES: usize = 10;

#[test]
fn recovers_from_a_single_10x_spike_within_10_frames_and_one_reversal() {
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        // Settle under a load that needs some reduction.
        let load = 1.5;
        for _ in 0..300 {
            let t = plant.frame_time(sched.scale(), load);
            sched.update(t);
        }
        let settled = sched.scale();
        let spike = 10.0 * plant.frame_time(settled, load);
        let mut trace = vec![settled, sched.update(spike)];
        for _ in 0..60 {
            let t = plant.frame_time(sched.scale(), load);
            trace.push(sched.update(t));
        }
        let last = *trace.last().unwrap();
        let (before, after) = (
            plant.frame_time(settled, load),
            plant.frame_time(last, load),
        );
        assert!(
            after <= 1.0 / 90.0 && after >= 0.9 * before,
            "seed {seed}: {before} s before, {after} s after: {trace:?}"
        );
        let back = trace.iter().rposition(|&s| s != last);
        assert!(
            back.is_some_and(|f| f <= SPIKE_RECOVERY_FRAMES),
            "seed {seed}: back after {back:?} frames; trace {trace:?}"
        );
        assert!(
            reversals(&trace) <= 1,
            "seed {seed}: {} reversals in {trace:?}",
            reversals(&trace)
        );
    }
}

#[test]
fn after_a_lasting_load_spike_the_reactive_controller_is_back_within_a_few_frames() {
    // 20 frames with half the period added (the lab's blind load spikes).
    // Once the load ends, the frames must draw 90% of the triangles they
    // drew before it within 6 frames, with at most one frame late. When
    // only a spike of one frame was remembered, `s` climbed back by the
    // raise rule alone, in 12 frames (seed 0). With odd seeds the load's
    // first 3 frames are out of reach (a floor above the period), so `s`
    // holds through them: that `s` is still the one to return to. With
    // every third seed the load's last frame is heavier, so `s` falls
    // once more and the first frame without the load is drawn at a lower
    // `s` than the frame before it. With every fourth seed one frame in
    // the load's middle is half the period heavier and out of reach, so
    // `s` holds through it: the frame after it falls from it by a step,
    // but not from the load's level. Judged against the last frame alone,
    // that fall was the load's end: `s` went back up within the load, its
    // late frames drove `s` lower than the load needed, and nothing was
    // left to return to (seed 3: back after 9 frames).
    let period = 1.0 / 90.0;
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        let load = 1.5;
        for _ in 0..300 {
            let t = plant.frame_time(sched.scale(), load);
            sched.update(t);
        }
        let before = plant.triangles(sched.scale());
        for k in 0..20 {
            let jolt = seed % 4 == 3 && k == 10;
            let extra = if (seed % 3 == 2 && k == 19) || jolt {
                1.0
            } else {
                0.5
            };
            let t = plant.frame_time(sched.scale(), load) + extra * period;
            let floor = ((seed % 2 == 1 && k < 3) || jolt).then_some(2.0 * period);
            sched.update_with_floor(t, floor);
        }
        let (mut back, mut late, mut trace) = (None, 0, Vec::new());
        for k in 0..60 {
            let s = sched.scale();
            trace.push(s);
            let t = plant.frame_time(s, load);
            late += usize::from(t > period);
            if back.is_none() && plant.triangles(s) >= 0.9 * before {
                back = Some(k);
            }
            sched.update(t);
        }
        assert!(
            back.is_some_and(|k| k <= 6),
            "seed {seed}: back after {back:?} frames: {trace:?}"
        );
        assert!(late <= 1, "seed {seed}: {late} frames late: {trace:?}");
    }
}

/// The predictive scheduler at 90 Hz on `plant`, calibrated on its
/// frames of `fixed_s` (s) plus the triangles.
fn predictive_at_90_hz(plant: &Plant, fixed_s: f32) -> PredictiveScheduler {
    PredictiveScheduler::new(
        ReactiveSettings::for_rate_hz(90.0).unwrap(),
        CostModel::new(fixed_s, plant.seconds_per_triangle),
    )
}

/// One frame of `plant` under the predictive scheduler's budget: `fixed_s`
/// plus the triangles at `load` times their cost, plus `extra_s` (s).
/// Returns the triangles and the frame time.
fn predictive_frame(
    plant: &Plant,
    sched: &mut PredictiveScheduler,
    fixed_s: f32,
    load: f32,
    extra_s: f32,
) -> (f32, f32) {
    let (_, triangles) = plant.fit_budget(sched.triangle_budget());
    let t = fixed_s + load * triangles * plant.seconds_per_triangle + extra_s;
    sched.observe(t, triangles as u64, plant.coarsest_triangles());
    (triangles, t)
}

#[test]
fn after_a_lasting_load_spike_the_predictive_budget_is_back_within_a_few_frames() {
    // As for the reactive controller: 20 frames with half the period
    // added to frames of 1 ms plus the triangles; within 6 frames of the
    // load's end the budget must draw 90% of the triangles it drew before,
    // with at most one frame late. By the cost model and the raise rule
    // alone it took 32 frames (seed 0).
    let period = 1.0 / 90.0;
    let fixed_s = 1e-3;
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut sched = predictive_at_90_hz(&plant, fixed_s);
        let load = 1.5;
        let frame = |sched: &mut PredictiveScheduler, extra_s: f32| {
            predictive_frame(&plant, sched, fixed_s, load, extra_s)
        };
        for _ in 0..300 {
            frame(&mut sched, 0.0);
        }
        let (before, _) = frame(&mut sched, 0.0);
        for _ in 0..20 {
            frame(&mut sched, 0.5 * period);
        }
        let (mut back, mut late, mut trace) = (None, 0, Vec::new());
        for k in 0..60 {
            let (_, triangles) = plant.fit_budget(sched.triangle_budget());
            trace.push(triangles);
            let t = fixed_s + load * triangles * plant.seconds_per_triangle;
            late += usize::from(t > period);
            if back.is_none() && triangles >= 0.9 * before {
                back = Some(k);
            }
            sched.observe(t, triangles as u64, plant.coarsest_triangles());
        }
        assert!(
            back.is_some_and(|k| k <= 6),
            "seed {seed}: back after {back:?} frames ({before} triangles before): {trace:?}"
        );
        assert!(late <= 1, "seed {seed}: {late} frames late: {trace:?}");
    }
}

#[test]
fn after_a_lasting_load_the_budget_is_not_cut_for_what_the_load_taught() {
    // As above, but the view grows 10% dearer while the load lasts, so the
    // budget from before it puts the frames a little over the aim and the
    // scheduler must come down. The cost model had learnt the load's
    // frames; judged by it, the budget fell to 70% of what fits (seed 0)
    // and every object refined on the return switched back. With the
    // model from before the load, it must stay above 80%.
    let period = 1.0 / 90.0;
    let fixed_s = 1e-3;
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut sched = predictive_at_90_hz(&plant, fixed_s);
        let frame = |sched: &mut PredictiveScheduler, load: f32, extra_s: f32| {
            predictive_frame(&plant, sched, fixed_s, load, extra_s).0
        };
        for _ in 0..300 {
            frame(&mut sched, 1.5, 0.0);
        }
        for _ in 0..20 {
            frame(&mut sched, 1.65, 0.5 * period);
        }
        // What fits the aim at the dearer view, by the settings' aim.
        let aim_s = sched.aim_s();
        let fits = (aim_s - fixed_s) / (1.65 * plant.seconds_per_triangle);
        // The first frame without the load is drawn with the budget the
        // load left (the frame time tells the load gone), the next half-way
        // back (the return's first step).
        frame(&mut sched, 1.65, 0.0);
        frame(&mut sched, 1.65, 0.0);
        let least = (0..30)
            .map(|_| frame(&mut sched, 1.65, 0.0))
            .fold(f32::INFINITY, f32::min);
        assert!(
            least >= 0.8 * fits,
            "seed {seed}: {least} triangles at the least, {fits} fit the aim"
        );
    }
}

#[test]
fn after_a_load_through_which_the_view_grew_dearer_the_return_takes_nothing_back() {
    // The view's triangles come to cost 40% more while a load of half the
    // period lasts, told in advance or not. Nothing the load's frames
    // show (few triangles, mostly fixed time) says so. Returned at once to
    // the budget from before the load, the frames after it were 20% over
    // the period and the budget was cut again: every object the return
    // refined switched back within a few frames. The return must draw no
    // frame over the period, and never draw fewer triangles than a frame
    // after the load already drew (give or take the plant's LOD steps).
    let period = 1.0 / 90.0;
    let fixed_s = 1e-3;
    for told in [false, true] {
        for seed in 0..20 {
            let plant = Plant::new(seed);
            let mut sched = predictive_at_90_hz(&plant, fixed_s);
            let frame = |sched: &mut PredictiveScheduler, load: f32, extra_s: f32| {
                if told {
                    sched.announce_load(extra_s);
                }
                predictive_frame(&plant, sched, fixed_s, load, extra_s)
            };
            for _ in 0..300 {
                frame(&mut sched, 1.5, 0.0);
            }
            for _ in 0..20 {
                frame(&mut sched, 2.1, 0.5 * period);
            }
            let (mut most, mut least_after_most, mut late, mut trace) =
                (0f32, f32::INFINITY, 0, Vec::new());
            for _ in 0..30 {
                let (triangles, t) = frame(&mut sched, 2.1, 0.0);
                trace.push(triangles);
                late += usize::from(t > period);
                if triangles > most {
                    (most, least_after_most) = (triangles, triangles);
                }
                least_after_most = least_after_most.min(triangles);
            }
            assert!(
                late == 0 && least_after_most >= 0.9 * most,
                "told {told}, seed {seed}: {late} frames late, {most} triangles then \
                 {least_after_most}: {trace:?}"
            );
        }
    }
}

/// The plant's load factor and the time added to frame `k` of
/// [`a_jittered_frame_leaves_no_memory_of_a_load`]: 300 frames at 1.5, one
/// frame 35% heavier (a step from both frames before it, over the
/// period), the view growing a third dearer over 60 frames, 20 more, 20
/// frames with half the period added, then the view alone. `None` past the
/// end.
fn jitter_then_load(k: usize, period: f32) -> Option<(f32, f32, f32)> {
    let dearer = |k: usize| 1.5 + 0.5 * ((k as f32 - 300.0) / 60.0).clamp(0.0, 1.0);
    match k {
        0..300 => Some((1.5, 1.0, 0.0)),
        300 => Some((1.5, 1.35, 0.0)),
        301..400 => Some((dearer(k), 1.0, 0.0)),
        400..420 => Some((2.0, 1.0, 0.5 * period)),
        420..460 => Some((2.0, 1.0, 0.0)),
        _ => None,
    }
}

#[test]
fn a_jittered_frame_leaves_no_memory_of_a_load() {
    // One frame of jitter looks like a load's first. Remembered until the
    // next load's end, its knob (from before the view grew dearer) was
    // where both schedulers went back to: frames late until they came
    // down again, every object refined in between switching back (the
    // predictive scheduler on `scenes/vr_sweep.toml` at 30 Hz). After the
    // real load the frames must draw at most 10% more triangles than
    // before it, with at most one frame late. Before, seed 0 drew 45% more
    // with 2 frames late (reactive), 36% more with 1 late (predictive).
    let period = 1.0 / 90.0;
    let fixed_s = 1e-3;
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut reactive = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        let mut predictive = predictive_at_90_hz(&plant, fixed_s);
        let (mut before, mut most, mut late) = ([0.0f32; 2], [0.0f32; 2], [0usize; 2]);
        for k in 0.. {
            let Some((load, jitter, extra_s)) = jitter_then_load(k, period) else {
                break;
            };
            let drawn = [
                plant.triangles(reactive.scale()),
                plant.fit_budget(predictive.triangle_budget()).1,
            ];
            let times =
                drawn.map(|n| (fixed_s + load * n * plant.seconds_per_triangle) * jitter + extra_s);
            for i in 0..2 {
                if k == 399 {
                    before[i] = drawn[i];
                }
                if k >= 420 {
                    most[i] = most[i].max(drawn[i]);
                    late[i] += usize::from(times[i] > period);
                }
            }
            reactive.update(times[0]);
            predictive.observe(times[1], drawn[1] as u64, plant.coarsest_triangles());
        }
        for (i, name) in ["reactive", "predictive"].iter().enumerate() {
            assert!(
                most[i] <= 1.1 * before[i] && late[i] <= 1,
                "seed {seed}, {name}: {} triangles after the load, {} before, {} frames late",
                most[i],
                before[i],
                late[i]
            );
        }
    }
}

#[test]
fn a_step_of_load_just_over_the_period_is_learned_at_once_without_a_measured_slope() {
    // A scene of 100,000 triangles at 1 ms plus 0.1 us each, at 60 Hz: the
    // budget holds every triangle, so no two frames differ in triangles
    // and the cost model never measures a slope (no floor, no additive
    // reading). A load of 6 ms puts the frames 2% over the period, not
    // by the dead band: learning it at the running rate took 10 late
    // frames; the step's frame is news of more load, learned at once.
    let period = 1.0 / 60.0;
    let (fixed_s, per_triangle_s, scene) = (1e-3, 1e-7, 100_000u64);
    let mut sched = PredictiveScheduler::new(
        ReactiveSettings::for_rate_hz(60.0).unwrap(),
        CostModel::new(fixed_s, per_triangle_s),
    );
    let mut frame = |extra_s: f32| -> f32 {
        let triangles = sched.triangle_budget().min(scene);
        let t = fixed_s + per_triangle_s * triangles as f32 + extra_s;
        sched.observe(t, triangles, 10_000);
        t
    };
    for _ in 0..100 {
        frame(0.0);
    }
    let late = (0..40).filter(|_| frame(6e-3) > period).count();
    assert!(late <= 4, "{late} frames late");
}

#[test]
fn sustained_double_load_settles_without_a_repeating_swing() {
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        let mut trace = Vec::new();
        for _ in 0..600 {
            let t = plant.frame_time(sched.scale(), 2.0);
            trace.push(sched.update(t));
        }
        let tail = &trace[300..];
        assert!(
            tail.iter().all(|&s| s == tail[0]),
            "seed {seed}: still moving: {:?}",
            &tail[..20]
        );
        let settle = trace
            .iter()
            .rposition(|&s| s != tail[0])
            .map_or(0, |i| i + 1);
        assert!(
            settle < 100,
            "seed {seed}: took {settle} frames to settle: {:?}",
            &trace[..settle.min(200)]
        );
        let target = 1.0 / 90.0;
        let t = plant.frame_time(tail[0], 2.0);
        assert!(
            t <= target && t >= 0.5 * target,
            "seed {seed}: settled at {t} s for a {target} s target"
        );
    }
}

#[test]
fn invalid_frame_times_change_nothing() {
    let plant = Plant::new(1);
    let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
    for _ in 0..50 {
        let t = plant.frame_time(sched.scale(), 2.0);
        sched.update(t);
    }
    let before = format!("{sched:?}");
    for t in [0.0, -1.0, f32::NAN, f32::NEG_INFINITY, f32::INFINITY] {
        sched.update(t);
        assert_eq!(format!("{sched:?}"), before, "frame time {t}");
    }
}

#[test]
fn huge_frame_times_are_capped() {
    let settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
    let mut sched = ReactiveScheduler::new(settings);
    let s = sched.update(1e30);
    let floor = settings.max_ratio.powf(-settings.gain);
    assert!(
        (s - floor).abs() < 1e-6,
        "one huge frame took s to {s}, not {floor}"
    );
}

/// Loads that need LODs dropped (1.5 and 2, drifting by 15%) and frame
/// times varying by 5% and 10%: in steady state at most 5% of the frames
/// over the period in every run, and at most 2 LOD reversals per second in
/// every run with 5% noise and on average over the seeds with 10% (where
/// one move of the knob that the noise undoes within 0.25 s flips some 30
/// of the plant's 300 objects twice), for both controllers.
#[test]
fn with_noisy_frames_steady_state_is_within_budget_and_does_not_flicker() {
    let settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
    let mut failures = Vec::new();
    for (load, sigma) in [(1.5, 0.05), (2.0, 0.1)] {
        for name in ["reactive", "predictive"] {
            let mut mean_reversals = 0.0;
            for seed in 0..8 {
                let st = match name {
                    "reactive" => reactive_steady(settings, seed, load, sigma),
                    _ => predictive_steady(settings, seed, load, sigma),
                };
                mean_reversals += st.reversals_per_s / 8.0;
                if st.over > 0.05 || (sigma <= 0.05 && st.reversals_per_s > 2.0) {
                    failures.push(format!(
                        "{name}, seed {seed}, load {load}, noise {sigma}: {:.1}% over, {:.1} reversals/s ({:.1} switches/s)",
                        100.0 * st.over,
                        st.reversals_per_s,
                        st.switches_per_s
                    ));
                }
            }
            if mean_reversals > 2.0 {
                failures.push(format!(
                    "{name}, load {load}, noise {sigma}: {mean_reversals:.1} reversals/s on average"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The controllers as they were before headroom fail those bounds on the
/// same plant (so the test above can fail): the reactive one aiming at the
/// period itself and acting on every frame (`without_headroom`, no switch
/// hysteresis), the predictive one spending the period's budget from its
/// cost model every frame.
#[test]
fn the_controllers_before_headroom_miss_or_flicker_on_the_noisy_plant() {
    let old = ReactiveSettings::for_rate_hz(90.0)
        .unwrap()
        .without_headroom();
    let (mut reactive, mut predictive) = (Vec::new(), Vec::new());
    for seed in 0..8 {
        let plant = Plant::new(seed);
        let mut rng = Rng::new(seed ^ 0x5eed);
        let mut sched = ReactiveScheduler::new(old);
        let (mut lods, mut rev, mut over) = (Vec::new(), Reversals::default(), 0);
        for frame in 0..900 {
            let triangles = plant.step_lods(sched.scale(), 0.0, &mut lods);
            if frame >= 300 {
                rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
            }
            let t = drifting(1.5, frame)
                * triangles
                * plant.seconds_per_triangle
                * noise(&mut rng, 0.05);
            over += (frame >= 300 && t > old.target_frame_s) as usize;
            sched.update(t);
        }
        reactive.push((over as f64 / 600.0, rev.count as f64 / (600.0 / 90.0)));
        let mut cost = CostModel::new(1e-3, plant.seconds_per_triangle);
        let (mut rev, mut over) = (Reversals::default(), 0);
        for frame in 0..900 {
            let (s, triangles) = plant.fit_budget(cost.triangle_budget(old.target_frame_s));
            plant.lods(s, &mut lods);
            if frame >= 300 {
                rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
            }
            let t = (1e-3 + drifting(1.5, frame) * triangles * plant.seconds_per_triangle)
                * noise(&mut rng, 0.05);
            over += (frame >= 300 && t > old.target_frame_s) as usize;
            cost.observe(t, triangles as u64);
        }
        predictive.push((over as f64 / 600.0, rev.count as f64 / (600.0 / 90.0)));
    }
    for (name, runs) in [("reactive", &reactive), ("predictive", &predictive)] {
        let failing = runs.iter().filter(|(o, r)| *o > 0.05 || *r > 2.0).count();
        assert!(
            failing >= 1,
            "{name} before headroom met the bounds on every seed: {runs:?}"
        );
    }
}

/// A spike of extra load no LOD can absorb (the cost floor far above the
/// period) for 30 frames: the reactive controller told the floor keeps its
/// `s` (it reports the target out of reach), and after the spike it is
/// back to its level within 10 frames. A spike that the coarsest LODs
/// absorb is not reported.
#[test]
fn an_unreachable_spike_does_not_lower_s_and_is_reported() {
    for seed in 0..8 {
        let plant = Plant::new(seed);
        let settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
        let mut sched = ReactiveScheduler::new(settings);
        let mut cost = CostModel::new(0.0, plant.seconds_per_triangle * 1.5);
        let mut rng = Rng::new(seed);
        // The model measures its local cost from frames at other triangle
        // counts before it predicts a floor.
        assert_eq!(cost.floor_s(1000), None);
        for s in [1.0, 0.5, 0.25, 0.125] {
            cost.observe(plant.frame_time(s, 1.5), plant.triangles(s) as u64);
        }
        let mut frame = |sched: &mut ReactiveScheduler, extra_s: f32| {
            let s = sched.scale();
            let triangles = plant.triangles(s);
            let t = (plant.frame_time(s, 1.5) + extra_s) * noise(&mut rng, 0.05);
            cost.observe(t, triangles as u64);
            sched.update_with_floor(t, cost.floor_s(plant.coarsest_triangles()));
        };
        for _ in 0..300 {
            frame(&mut sched, 0.0);
        }
        let settled = sched.scale();
        assert!(!sched.target_unreachable(), "seed {seed}");
        let mut lowest = settled;
        let mut reported = 0;
        for _ in 0..30 {
            frame(&mut sched, 2.0 * settings.target_frame_s);
            lowest = lowest.min(sched.scale());
            reported += sched.target_unreachable() as u32;
            // The floor itself is reported, and says the same.
            let floor = sched
                .cost_floor_s()
                .expect("a floor once the slope is measured");
            assert_eq!(floor > settings.target_frame_s, sched.target_unreachable());
        }
        assert!(
            reported >= 28,
            "seed {seed}: out of reach reported in {reported} of 30 frames"
        );
        assert!(
            lowest >= 0.9 * settled,
            "seed {seed}: s fell from {settled} to {lowest} for nothing"
        );
        let mut back = None;
        for k in 0..60 {
            frame(&mut sched, 0.0);
            if back.is_none() && sched.scale() >= 0.9 * settled {
                back = Some(k);
            }
        }
        assert!(
            back.is_some_and(|k| k <= 10),
            "seed {seed}: back after {back:?} frames"
        );
        let mut reported = 0;
        for _ in 0..30 {
            frame(&mut sched, 0.3 * settings.target_frame_s);
            reported += sched.target_unreachable() as u32;
        }
        assert_eq!(reported, 0, "seed {seed}: a reachable spike reported");
    }
}

/// A case the property below found: a frame of 3.4e38 s (finite) makes
/// the per-triangle cost so large that the floor's product overflowed to
/// infinity.
#[test]
fn a_frame_near_the_largest_finite_time_leaves_the_floor_finite() {
    let mut cost = CostModel::first_guess();
    for (frame_s, triangles) in [
        (0.059_487_67, 1_620_102),
        (0.094_381_854, 1),
        (3.357_561_6e38, 154_645),
        (0.065_019_56, 0),
    ] {
        cost.observe(frame_s, triangles);
    }
    let floor = cost.floor_s(1_959_122).expect("three slopes measured");
    assert!(floor.is_finite() && floor > 1.0, "floor {floor} s");
}

/// Another: a frame of 7.4e37 s drives the local per-triangle cost to
/// 1e33 s; the next frame's load less its triangles at that cost was
/// -inf, and the floor (-inf plus the coarsest triangles' +inf) NaN.
#[test]
fn a_local_cost_grown_past_the_frames_leaves_the_floor_a_number() {
    let mut cost = CostModel::first_guess();
    for (frame_s, triangles) in [
        (0.046_971_317, 1),
        (7.377_171e37, 4_247),
        (0.017_089_326, 1),
        (0.085_408_38, 306_092),
    ] {
        cost.observe(frame_s, triangles);
    }
    let floor = cost.floor_s(306_092).expect("three slopes measured");
    assert!(
        (0.0..=f32::MAX).contains(&floor),
        "floor {floor} s: {cost:?}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn scale_stays_within_floor_and_one(times in proptest::collection::vec(prop_oneof![0f32..1.0, proptest::num::f32::ANY], 1..200), floor in 0.001f32..1.0) {
        let mut settings = ReactiveSettings::for_rate_hz(60.0).unwrap();
        settings.min_scale = floor;
        let mut sched = ReactiveScheduler::new(settings);
        for t in times {
            let s = sched.update(t);
            prop_assert!(s.is_finite() && s <= 1.0 && s >= floor.min(1.0) - 1e-7, "s = {}", s);
        }
    }

    #[test]
    fn with_a_guessed_cost_model_s_and_the_floor_stay_finite(
        frames in proptest::collection::vec(
            (prop_oneof![0f32..0.1, proptest::num::f32::ANY], 0u64..5_000_000, 0u64..5_000_000),
            1..200,
        ),
    ) {
        let settings = ReactiveSettings::for_rate_hz(60.0).unwrap();
        let mut sched = ReactiveScheduler::new(settings)
            .with_cost_model(CostModel::first_guess());
        for (frame_s, triangles, coarsest) in frames {
            let coarsest = coarsest.min(triangles);
            let s = sched.observe(frame_s, triangles, coarsest);
            prop_assert!(s.is_finite() && s > 0.0 && s <= 1.0, "s = {}", s);
            let m = sched.cost_model().unwrap();
            prop_assert!(m.per_triangle_s.is_finite() && m.per_triangle_s > 0.0, "{:?}", m);
            if let Some(f) = m.floor_s(coarsest) {
                prop_assert!(f.is_finite() && f >= 0.0, "floor {} s: {:?}", f, m);
            }
        }
    }

    #[test]
    fn an_announced_load_never_raises_the_budget(
        frames in proptest::collection::vec(
            (prop_oneof![0f32..0.1, proptest::num::f32::ANY], 0u64..2_000_000, prop_oneof![0f32..0.05, proptest::num::f32::ANY]),
            1..100,
        ),
    ) {
        let settings = ReactiveSettings::for_rate_hz(60.0).unwrap();
        let cost = CostModel::new(2e-3, 1e-8);
        let mut told = PredictiveScheduler::new(settings, cost);
        for (frame_s, triangles, load_s) in frames {
            let before = told.triangle_budget();
            told.announce_load(load_s);
            let with_load = told.triangle_budget();
            prop_assert!(with_load <= before, "{} > {} with {} s announced", with_load, before, load_s);
            told.observe(frame_s, triangles, triangles / 10);
            let m = told.cost_model();
            prop_assert!(m.per_triangle_s.is_finite() && m.per_triangle_s > 0.0, "{:?}", m);
        }
    }
}

#[test]
fn an_announced_load_is_budgeted_for_before_its_first_frame() {
    // The predictive controller on the plant at 90 Hz with 5% noise, then
    // spikes of +40% of the period (reachable: the budget can make room)
    // of 20 frames each, told in advance or not.
    let run = |announce: bool, seed: u64| {
        let settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
        let plant = Plant::new(seed);
        let mut rng = Rng::new(seed ^ 0xa11);
        let fixed_s = 1e-3;
        let mut sched = PredictiveScheduler::new(
            settings,
            CostModel::new(fixed_s, plant.seconds_per_triangle),
        );
        let (mut first_over, mut over) = (0, 0);
        // The highest ratio of the learnt per-triangle cost at a spike's
        // end to the one just before it.
        let (mut before, mut learnt) = (0f32, 0f32);
        // The reported floor's rise over a told spike's first frame, at
        // least, relative to the load told.
        let (mut floor_before, mut floor_rise) = (0f32, f32::INFINITY);
        for frame in 0..900 {
            let phase = frame % 150;
            let spike = frame >= 300 && (100..120).contains(&phase);
            let extra_s = if spike {
                0.4 * settings.target_frame_s
            } else {
                0.0
            };
            if announce && spike {
                sched.announce_load(extra_s);
            }
            let budget = sched.triangle_budget();
            let per_triangle_s = sched.cost_model().per_triangle_s;
            if frame >= 300 && phase == 100 {
                before = per_triangle_s;
            }
            if frame >= 300 && phase == 120 {
                learnt = learnt.max(per_triangle_s / before);
            }
            let (_, triangles) = plant.fit_budget(budget);
            let t = (fixed_s + triangles * plant.seconds_per_triangle + extra_s)
                * noise(&mut rng, 0.05);
            if spike && t > settings.target_frame_s {
                over += 1;
                first_over += usize::from(phase == 100);
            }
            sched.observe(t, triangles as u64, plant.coarsest_triangles());
            let floor_s = sched.cost_floor_s().unwrap_or(f32::NAN);
            if frame >= 300 && phase == 99 {
                floor_before = floor_s;
            }
            if announce && frame >= 300 && phase == 100 {
                floor_rise = floor_rise.min((floor_s - floor_before) / extra_s);
            }
        }
        if announce {
            // The floor reported includes the load told for its frame.
            assert!(
                floor_rise > 0.5,
                "seed {seed}: floor rose {floor_rise} of the load"
            );
        }
        (first_over, over, learnt)
    };
    for seed in 0..8 {
        let (first_told, over_told, learnt) = run(true, seed);
        let (first_blind, over_blind, _) = run(false, seed);
        // Four spikes: blind, a spike's first frame is late (but where the
        // noise, or a budget still low from the spike before, left room).
        assert!(first_blind >= 3, "seed {seed}: {first_blind}");
        assert!(
            first_told <= 1,
            "seed {seed}: {first_told} first frames late"
        );
        assert!(
            over_told < over_blind && over_told <= 4,
            "seed {seed}: {over_told} of 80 spike frames late when told, {over_blind} blind"
        );
        // A told load is not learnt as the scene's cost.
        assert!(
            learnt < 1.1,
            "seed {seed}: the per-triangle cost rose {learnt}x in a spike"
        );
    }
}

#[test]
fn a_told_load_leaves_the_budget_as_it_found_it() {
    // A load of 60% of the period told for 20 frames leaves no room for
    // triangles: every object at its coarsest LOD, and the frames less
    // the told load far below the aim. The budget those frames do not
    // draw must not rise meanwhile. The cost model's fixed time is
    // calibrated too high (4 ms against 1 ms, as the lab's line through
    // full detail and the coarsest LODs), so it read those frames as
    // nearly free (the per-triangle cost halving every frame) and the
    // raise rule took its budget: after the load, seed 0 drew full detail
    // (1.6 times the triangles of before), 2 of the next 10 frames late.
    let period = 1.0 / 90.0;
    let fixed_s = 1e-3;
    for seed in 0..20 {
        let plant = Plant::new(seed);
        // Calibrated at 4 ms of fixed time.
        let mut sched = predictive_at_90_hz(&plant, 4e-3);
        let frame = |sched: &mut PredictiveScheduler, extra_s: f32| {
            sched.announce_load(extra_s);
            predictive_frame(&plant, sched, fixed_s, 1.5, extra_s)
        };
        let mut before = 0.0;
        for _ in 0..300 {
            before = frame(&mut sched, 0.0).0;
        }
        for _ in 0..20 {
            frame(&mut sched, 0.6 * period);
        }
        let (mut most, mut late) = (0f32, 0);
        for _ in 0..10 {
            let (triangles, t) = frame(&mut sched, 0.0);
            most = most.max(triangles);
            late += usize::from(t > period);
        }
        assert!(
            most <= 1.1 * before && late == 0,
            "seed {seed}: {most} triangles after the told load, {before} before, {late} late"
        );
    }
}

/// A plant whose objects all switch below `s = 0.24`, so the first
/// halvings of `s` change no triangles, under a load that makes the frame
/// at `s = 1` take 2.4x to 3.7x the 90 Hz period (by seed).
fn overloaded_plant(seed: u64) -> (Plant, f32) {
    let mut plant = Plant::new(seed);
    for b in &mut plant.breakpoints {
        *b = b.map(|x| 0.15 * x);
    }
    plant.seconds_per_triangle = 0.8 / 90.0 / plant.triangles(1.0);
    (plant, 3.0 + (seed % 3) as f32 * 0.8)
}

#[test]
fn coming_down_from_an_overload_where_the_cost_is_flat_in_s_takes_few_late_frames() {
    // At the start the frame takes 2.4x to 3.7x the period, and the
    // triangles do not change over the first halvings of `s` (every
    // object switches below `s = 0.24`). A step sized for a cost
    // proportional to `s` spends a late frame on each halving (6 late
    // frames on every seed); one that grows while the frame time does not
    // fall comes down in 3.
    let target = 1.0 / 90.0;
    let mut worst = 0;
    for seed in 0..20 {
        let (plant, load) = overloaded_plant(seed);
        let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        let mut late = 0;
        let mut trace = Vec::new();
        for _ in 0..300 {
            let t = plant.frame_time(sched.scale(), load);
            if t <= target {
                break;
            }
            late += 1;
            trace.push((sched.scale(), t / target));
            sched.update(t);
        }
        worst = worst.max(late);
        assert!(late <= 3, "seed {seed}: {late} late frames: {trace:?}");
        for _ in 0..300 {
            let t = plant.frame_time(sched.scale(), load);
            sched.update(t);
        }
        let t = plant.frame_time(sched.scale(), load);
        assert!(
            t <= target && t >= 0.5 * target,
            "seed {seed}: settled at {t} s for a {target} s target"
        );
    }
    assert!(worst >= 2, "{worst}: the plant starts within the period");
}

#[test]
fn started_at_its_lowest_s_the_reactive_controller_climbs_to_the_target_without_a_late_frame() {
    // The overloaded plant of the test above (2.4x to 3.7x the period at
    // s = 1), frames varying by 5%: started at its lowest `s`, the
    // controller draws no frame over the period on its way up and raises
    // `s` after every frame below its dead band: within a quarter of its
    // aim by frame 20 on every seed from the default floor of 1e-3 (by
    // frame 15 from 0.01; raising after three frames each, by frame 30).
    let target = 1.0 / 90.0;
    let mut slowest = 0;
    for seed in 0..20 {
        let (plant, load) = overloaded_plant(seed);
        let settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
        let mut sched = ReactiveScheduler::new(settings).starting_at(settings.min_scale);
        assert_eq!(sched.scale(), settings.min_scale);
        let mut rng = Rng::new(seed ^ 0xc11b);
        let mut frame = 0;
        loop {
            let t = plant.frame_time(sched.scale(), load) * noise(&mut rng, 0.05);
            assert!(t <= target, "seed {seed}: frame {frame} took {t} s");
            if t >= 0.75 * sched.aim_s() {
                break;
            }
            sched.update(t);
            frame += 1;
            assert!(frame < 300, "seed {seed}: never climbed");
        }
        slowest = slowest.max(frame);
    }
    assert!(
        slowest <= 20,
        "within a quarter of the aim at frame {slowest}"
    );
}

#[test]
fn a_floor_that_is_not_finite_is_the_default_floor() {
    let mut settings = ReactiveSettings::for_rate_hz(90.0).unwrap();
    let floor_of = |settings: ReactiveSettings| {
        let mut sched = ReactiveScheduler::new(settings);
        for _ in 0..200 {
            sched.update(1.0);
        }
        sched.scale()
    };
    let default_floor = floor_of(settings);
    assert_eq!(default_floor, acuity::DEFAULT_MIN_SCALE);
    // Not finite: the default, as the budgeted selection reads it.
    for floor in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        settings.min_scale = floor;
        assert_eq!(floor_of(settings), default_floor, "{floor}");
    }
    // Finite: clamped into [LOWEST_MIN_SCALE, 1].
    settings.min_scale = 2.0;
    assert_eq!(floor_of(settings), 1.0);
    settings.min_scale = -1.0;
    assert_eq!(floor_of(settings), acuity::LOWEST_MIN_SCALE);
}
