//! Loads that come and go: after a lasting load both controllers return to
//! where they were, a jittered frame leaves no memory of a load, a blind
//! load is met from its third frame where the triangles follow `s`
//! weakly, and an announced load is budgeted for before its first frame.

use crate::common::Rng;
use crate::plant::*;
use acuity::{CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings};

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
        let load = 1.5;
        let mut sched = plant.settled_reactive(load);
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
fn an_announced_load_is_budgeted_for_before_its_first_frame() {
    // The predictive controller on the plant at 90 Hz with 5% noise, then
    // spikes of +40% of the period (reachable: the budget can make room)
    // of 20 frames each, told in advance or not.
    let run = |announce: bool, seed: u64| {
        let plant = Plant::new(seed);
        let mut rng = Rng::new(seed ^ 0xa11);
        let fixed_s = 1e-3;
        let mut sched = predictive_at_90_hz(&plant, fixed_s);
        let period_s = sched.settings().target_frame_s;
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
            let extra_s = if spike { 0.4 * period_s } else { 0.0 };
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
            if spike && t > period_s {
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

/// Frames of a blind load's third to tenth that were late with room (the
/// floor at or below the aim), and those counted, on a plant whose frames
/// take `fixed` of the 90 Hz period plus their triangles (at `s = 1`,
/// `full` periods), varying by 5%: the reactive scheduler with a
/// calibrated cost model settled, then `extra` periods added for 30
/// frames. Over 20 seeds.
fn late_in_load(settings: ReactiveSettings, fixed: f32, full: f32, extra: f32) -> (usize, usize) {
    let period = settings.target_frame_s;
    let (mut late, mut counted) = (0, 0);
    for seed in 0..20 {
        let plant = Plant::new(seed);
        let (fixed_s, extra_s) = (fixed * period, extra * period);
        let per_triangle_s = full * period / plant.triangles(1.0);
        let mut sched = ReactiveScheduler::new(settings)
            .with_cost_model(CostModel::new(fixed_s, per_triangle_s));
        let mut rng = Rng::new(seed ^ 0x10ad);
        let coarsest = plant.coarsest_triangles();
        for k in 0..330 {
            let load_s = if k >= 300 { extra_s } else { 0.0 };
            let triangles = plant.triangles(sched.scale());
            let t = (fixed_s + load_s + per_triangle_s * triangles) * noise(&mut rng, 0.05);
            let floor_s = fixed_s + load_s + per_triangle_s * coarsest as f32;
            if (302..310).contains(&k) && floor_s <= sched.aim_s() {
                counted += 1;
                late += usize::from(t > period);
            }
            sched.observe(t, triangles as u64, coarsest);
        }
    }
    (late, counted)
}

#[test]
fn a_blind_load_where_the_triangles_follow_s_weakly_is_met_by_its_third_frame() {
    // Four plants (fixed time, full detail's frame and the load, in
    // periods): the load's first frame is late and its second may be (a
    // blind controller learns the load from them); from the third on, with
    // the cost floor at or below the aim, at most 5% of the frames may be
    // late. Stepping in proportion (the step before it fitted the frame's
    // cost) left 18, 72, 29 and 26 of the 160 frames late.
    let fitted = ReactiveSettings::for_rate_hz(90.0).unwrap();
    let proportional = ReactiveSettings {
        fit_step_to_cost: false,
        ..fitted
    };
    let mut worst_proportional = 0;
    for (fixed, full, extra) in [
        (0.25, 1.5, 0.35),
        (0.3, 3.0, 0.4),
        (0.2, 1.2, 0.5),
        (0.1, 4.0, 0.3),
    ] {
        let (late, counted) = late_in_load(fitted, fixed, full, extra);
        assert!(counted >= 100, "{counted} frames with room");
        assert!(
            late * 20 <= counted,
            "fixed {fixed}, full {full}, load {extra}: {late} of {counted} late"
        );
        worst_proportional =
            worst_proportional.max(late_in_load(proportional, fixed, full, extra).0);
    }
    assert!(
        worst_proportional >= 50,
        "{worst_proportional}: the plants must need the fitted step"
    );
}
