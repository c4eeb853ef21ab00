//! The fixed-frame-rate controllers against a stepwise synthetic plant:
//! 300 objects with 4 discrete LODs each, whose frame time is the
//! triangles drawn times a cost per triangle times a load factor, with or
//! without noise (a frame's time varying by 5-10%). The plant is in
//! `plant.rs`; the loads that come and go (lasting, jittered and announced)
//! in `loads.rs`; settling, noise, the cost floor and bad input here.

#[path = "../common/mod.rs"]
mod common;
mod loads;
mod plant;

use acuity::{CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings};
use common::Rng;
use plant::*;
use proptest::prelude::*;

/// Frames the controller needs after a single 10x spike to be back at rest
/// (no further change), fitting the frame period and drawing at least 90%
/// of what it drew before (the dead band admits several resting levels of
/// `s`), with at most one reversal on the way.
const SPIKE_RECOVERY_FRAMES: usize = 10;

#[test]
fn recovers_from_a_single_10x_spike_within_10_frames_and_one_reversal() {
    for seed in 0..20 {
        let plant = Plant::new(seed);
        // Settle under a load that needs some reduction.
        let load = 1.5;
        let mut sched = plant.settled_reactive(load);
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
