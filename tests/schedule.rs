//! The reactive fixed-frame-rate controller against a stepwise synthetic
//! plant: 300 objects with 4 discrete LODs each, whose frame time is the
//! triangles drawn times a cost per triangle times a load factor.

mod common;

use acuity::{ReactiveScheduler, ReactiveSettings};
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
}
