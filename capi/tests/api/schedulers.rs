//! The frame-rate schedulers through the C interface, on a plant of 40
//! objects: holding a rate, starting low, a load no LOD absorbs, bad
//! input refused by name.

use super::*;
use crate::objects::{scene, triangles};

/// A plant for the schedulers: 40 objects, frames of a period, 2 ms of
/// fixed time and a cost per triangle.
struct Plant {
    selector: *mut AcuitySelector,
    frame: AcuityFrame,
    per_triangle_s: f32,
}

impl Plant {
    /// Frames of `period_s`, full detail taking `full_periods` periods.
    fn new(period_s: f32, full_periods: f32) -> Plant {
        let selector = scene(&AcuitySettings::default(), 40);
        let frame = AcuityFrame {
            dt_s: period_s,
            ..AcuityFrame::default()
        };
        expect(select(selector, &frame), ACUITY_OK);
        let per_triangle_s = (full_periods * period_s - 2e-3) / triangles(selector) as f32;
        Plant {
            selector,
            frame,
            per_triangle_s,
        }
    }

    /// One frame under `sched`: its knob applied, a selection, and the
    /// frame's time (the fixed time, the triangles drawn and `load_s`)
    /// observed. Returns that time, s.
    ///
    /// # Safety
    /// `sched` must be a live scheduler.
    unsafe fn frame(&self, sched: *mut AcuityScheduler, load_s: f32) -> f32 {
        let s = self.selector;
        // SAFETY: a live scheduler by this function's contract, and the
        // plant's live selector.
        unsafe {
            expect(acuity_scheduler_apply(sched, s), ACUITY_OK);
            expect(select(s, &self.frame), ACUITY_OK);
            let t = 2e-3 + triangles(s) as f32 * self.per_triangle_s + load_s;
            expect(acuity_scheduler_observe(sched, t, s), ACUITY_OK);
            t
        }
    }
}

#[test]
fn a_reactive_scheduler_started_low_climbs_without_the_late_start_from_c() {
    // The plant of the next test with full detail at 1.5x the 60 Hz
    // period (its lowest s at about half the period): from s = 1 the
    // reactive scheduler's first frame is late; started at its lowest s
    // it climbs, on time from the first frame.
    let period_s = 1.0 / 60.0;
    let plant = Plant::new(period_s, 1.5);
    let mut sched = null_mut();
    // SAFETY: live scheduler, selector and out-pointers throughout.
    unsafe {
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 60.0, &mut sched),
            ACUITY_OK,
        );
        for scale in [0.0, -0.5, 1.5, f32::NAN, f32::INFINITY] {
            expect(
                acuity_scheduler_start_at(sched, scale),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(
            acuity_scheduler_start_at(null_mut(), 0.5),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_scheduler_start_at(sched, 1e-6), ACUITY_OK);
        let mut state = AcuitySchedulerState::default();
        expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
        assert_eq!(state.scale, 1e-3, "the lowest s");
        let late: Vec<usize> = (0..30)
            .filter(|_| plant.frame(sched, 0.0) > period_s)
            .collect();
        assert!(late.is_empty(), "late frames {late:?}");
        expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
        assert!(state.scale > 0.02, "climbed to {}", state.scale);
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_PREDICTIVE, 60.0, &mut sched),
            ACUITY_OK,
        );
        let m = expect(
            acuity_scheduler_start_at(sched, 0.5),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("predictive"), "{m}");
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        acuity_selector_free(plant.selector);
    }
}

#[test]
fn both_schedulers_hold_a_rate_from_c() {
    // A plant: 2 ms of fixed time and a cost per triangle that makes the
    // selection at `s = 1` take 2x the 60 Hz period; every object's
    // coarsest LOD fits the aim.
    let period_s = 1.0 / 60.0;
    for kind in [ACUITY_SCHEDULER_REACTIVE, ACUITY_SCHEDULER_PREDICTIVE] {
        let plant = Plant::new(period_s, 2.0);
        let mut sched = null_mut();
        let mut late = Vec::new();
        // SAFETY: live scheduler, selector and out-pointers throughout.
        unsafe {
            expect(acuity_scheduler_new(kind, 60.0, &mut sched), ACUITY_OK);
            for k in 0..200 {
                if plant.frame(sched, 0.0) > period_s {
                    late.push(k);
                }
            }
            let mut state = AcuitySchedulerState::default();
            expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
            assert!(state.aim_s > 0.5 * period_s && state.aim_s < period_s);
            match kind {
                ACUITY_SCHEDULER_REACTIVE => {
                    assert!(state.scale < 1.0 && state.budget == ACUITY_NO_BUDGET);
                }
                _ => assert!(state.scale == 1.0 && state.budget < 4000 * 40),
            }
            expect(acuity_scheduler_free(sched), ACUITY_OK);
            acuity_selector_free(plant.selector);
        }
        assert!(
            late.iter().all(|&k| k < 10),
            "kind {kind}: late frames {late:?}"
        );
    }
}

#[test]
fn both_schedulers_report_a_load_no_lod_absorbs_and_hold_their_knob() {
    // A plant whose full detail takes 1.5x the 60 Hz period (a triangle
    // costs about 150x the schedulers' first guess), settled, then 30
    // frames with twice the period of extra work: no LOD choice reaches
    // 60 Hz, and lowering detail would buy nothing. (A scheduler whose
    // cost model has not yet seen frames of different triangle counts
    // knows no floor, and may lower its knob in the spike's first frame.)
    let period_s = 1.0 / 60.0;
    for kind in [ACUITY_SCHEDULER_REACTIVE, ACUITY_SCHEDULER_PREDICTIVE] {
        let plant = Plant::new(period_s, 1.5);
        let mut sched = null_mut();
        let mut state = AcuitySchedulerState::default();
        let (mut reported, mut before) = (0, AcuitySchedulerState::default());
        // SAFETY: live scheduler, selector and out-pointers throughout.
        unsafe {
            expect(acuity_scheduler_new(kind, 60.0, &mut sched), ACUITY_OK);
            for k in 0..230 {
                let load_s = if k >= 200 { 2.0 * period_s } else { 0.0 };
                plant.frame(sched, load_s);
                expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
                if k == 0 {
                    assert_eq!(state.cost_floor_s, -1.0, "kind {kind}: no floor known yet");
                }
                if k == 199 {
                    assert_eq!(state.target_unreachable, 0, "kind {kind}: before the load");
                    // Known (once the frames' triangles have differed) or
                    // not, below the period.
                    assert!(
                        state.cost_floor_s == -1.0
                            || (state.cost_floor_s >= 0.0 && state.cost_floor_s <= period_s),
                        "kind {kind}: floor {} s before the load",
                        state.cost_floor_s
                    );
                }
                if k >= 200 && state.target_unreachable == 1 {
                    assert!(
                        state.cost_floor_s > period_s,
                        "kind {kind}: the floor says it too"
                    );
                    // Held from the first frame that knows the floor.
                    if reported == 0 {
                        before = state;
                    }
                    reported += 1;
                }
            }
            expect(acuity_scheduler_free(sched), ACUITY_OK);
            acuity_selector_free(plant.selector);
        }
        assert!(
            reported >= 28,
            "kind {kind}: {reported} of 30 frames reported"
        );
        assert!(
            state.scale >= 0.9 * before.scale && state.budget as f64 >= 0.9 * before.budget as f64,
            "kind {kind}: s {} -> {}, budget {} -> {}",
            before.scale,
            state.scale,
            before.budget,
            state.budget
        );
    }
}

#[test]
fn schedulers_refuse_bad_input_by_name() {
    let s = scene(&AcuitySettings::default(), 3);
    let mut sched = null_mut();
    // SAFETY: live or NULL pointers as each call documents.
    unsafe {
        let m = expect(
            acuity_scheduler_new(7, 60.0, &mut sched),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("kind"), "{m}");
        for rate_hz in [0.0, -5.0, f32::NAN, f32::INFINITY, 1e6] {
            expect(
                acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, rate_hz, &mut sched),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 60.0, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 90.0, &mut sched),
            ACUITY_OK,
        );
        for t in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let m = expect(
                acuity_scheduler_observe(sched, t, s),
                ACUITY_INVALID_ARGUMENT,
            );
            assert!(m.contains("frame_time_s"), "{m}");
        }
        expect(
            acuity_scheduler_observe(sched, 0.01, null()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_observe(null_mut(), 0.01, s),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_apply(sched, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_scheduler_apply(null_mut(), s), ACUITY_NULL_POINTER);
        expect(
            acuity_scheduler_state(sched, null_mut()),
            ACUITY_NULL_POINTER,
        );
        let m = expect(
            acuity_scheduler_announce_load(sched, 0.005),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("reactive"), "{m}");
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_PREDICTIVE, 90.0, &mut sched),
            ACUITY_OK,
        );
        expect(acuity_scheduler_announce_load(sched, 0.005), ACUITY_OK);
        for extra_s in [-1.0, f32::NAN] {
            expect(
                acuity_scheduler_announce_load(sched, extra_s),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(acuity_scheduler_free(null_mut()), ACUITY_OK);
        acuity_selector_free(s);
    }
}
