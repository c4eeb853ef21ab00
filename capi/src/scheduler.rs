//! The fixed-frame-rate controllers: a scheduler is told each frame's
//! measured time and sets the selector's knob for the next frame, `s`
//! (reactive) or a triangle budget (predictive).

use acuity::{CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings};

use crate::error::{
    AcuityStatus, Failure, Result, borrow, borrow_mut, check_out, guard, write_out,
};
use crate::selector::{AcuitySelector, with_selector};
use crate::types::{
    ACUITY_NO_BUDGET, ACUITY_SCHEDULER_PREDICTIVE, ACUITY_SCHEDULER_REACTIVE, AcuitySchedulerState,
};

/// `AcuitySchedulerState::cost_floor_s` while the floor is unknown.
const UNKNOWN_FLOOR_S: f32 = -1.0;

/// A fixed-frame-rate controller. Opaque; from `acuity_scheduler_new`,
/// freed with `acuity_scheduler_free`. Not thread-safe: one thread at a
/// time.
pub struct AcuityScheduler {
    inner: Inner,
}

enum Inner {
    Reactive(ReactiveScheduler),
    Predictive(PredictiveScheduler),
}

/// Creates a scheduler of `kind` (`ACUITY_SCHEDULER_REACTIVE` or
/// `ACUITY_SCHEDULER_PREDICTIVE`) holding `rate_hz` frames a second (1 to
/// 10,000), with the runtime's defaults: it aims at 90% of the period
/// (less where the frames vary more), changes nothing while the frames lie
/// in a dead band below that, and keeps switches from flickering. On
/// success `*out` is a new scheduler the caller frees with
/// `acuity_scheduler_free`.
///
/// Each frame: `acuity_scheduler_apply` before `acuity_selector_select`,
/// `acuity_scheduler_observe` with the frame's measured time after it was
/// drawn. For the budgeted spending of `s` (no reversals under the
/// reactive scheduler) create the selector with `budgeted_scale`; for
/// flicker-free switching, set `switch_min_dwell_s`,
/// `switch_coarsen_delay_s` and `switch_hysteresis` to the steady switch
/// rules (`ACUITY_STEADY_SWITCH_MIN_DWELL_S`,
/// `ACUITY_STEADY_SWITCH_COARSEN_DELAY_S`,
/// `ACUITY_STEADY_SWITCH_HYSTERESIS`), as the command line's scheduled
/// policies do.
///
/// # Safety
/// `out` must be NULL (refused) or valid for writing a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_new(
    kind: u32,
    rate_hz: f32,
    out: *mut *mut AcuityScheduler,
) -> AcuityStatus {
    guard(|| {
        check_out(out, "out")?;
        let settings = ReactiveSettings::for_rate_hz(rate_hz)?;
        let inner = match kind {
            ACUITY_SCHEDULER_REACTIVE => Inner::Reactive(
                ReactiveScheduler::new(settings).with_cost_model(CostModel::first_guess()),
            ),
            ACUITY_SCHEDULER_PREDICTIVE => {
                Inner::Predictive(PredictiveScheduler::new(settings, CostModel::first_guess()))
            }
            other => {
                return Err(Failure::invalid(format!(
                    "`kind` is {other}; it must be ACUITY_SCHEDULER_REACTIVE (0) or \
                     ACUITY_SCHEDULER_PREDICTIVE (1)"
                )));
            }
        };
        let raw = Box::into_raw(Box::new(AcuityScheduler { inner }));
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out, "out", raw) }
    })
}

/// Frees a scheduler. NULL does nothing.
///
/// # Safety
/// `scheduler` must be NULL or a scheduler from this library not freed
/// yet, and no other call may be using it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_free(scheduler: *mut AcuityScheduler) -> AcuityStatus {
    guard(|| {
        if !scheduler.is_null() {
            // SAFETY: from `Box::into_raw` in `acuity_scheduler_new` and
            // not freed yet, by the caller's contract.
            drop(unsafe { Box::from_raw(scheduler) });
        }
        Ok(())
    })
}

/// Sets the selector's knob for the next `acuity_selector_select`: the
/// reactive scheduler's `s` (replacing `acuity_selector_set_scale`'s), or
/// the predictive scheduler's triangle budget (replacing
/// `acuity_selector_set_budget`'s; `s` back to 1).
///
/// # Safety
/// `scheduler` must be NULL (refused) or a live scheduler, `selector`
/// NULL (refused) or a live selector, each used by no other thread.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_apply(
    scheduler: *mut AcuityScheduler,
    selector: *mut AcuitySelector,
) -> AcuityStatus {
    with_selector(selector, |sel| {
        // SAFETY: forwarded from this function's contract.
        let sched = unsafe { borrow_mut(scheduler, "scheduler") }?;
        match &mut sched.inner {
            Inner::Reactive(r) => sel.set_knobs(r.scale(), None),
            Inner::Predictive(p) => sel.set_knobs(1.0, Some(p.triangle_budget())),
        }
        Ok(())
    })
}

/// Tells the scheduler the measured time of the frame just drawn, s
/// (finite, > 0: the wall time from one frame's start to the next's, or
/// the CPU and GPU time your engine measures), and reads the triangles
/// the selector chose for it and its coarsest triangles (the cost floor).
///
/// # Safety
/// `scheduler` must be NULL (refused) or a live scheduler, `selector`
/// NULL (refused) or a live selector, each used by no other thread.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_observe(
    scheduler: *mut AcuityScheduler,
    frame_time_s: f32,
    selector: *const AcuitySelector,
) -> AcuityStatus {
    guard(|| {
        // SAFETY: forwarded from this function's contract.
        let sched = unsafe { borrow_mut(scheduler, "scheduler") }?;
        // SAFETY: forwarded from this function's contract.
        let sel = unsafe { borrow(selector, "selector") }?;
        sel.check_usable()?;
        let t = frame_time(frame_time_s, "frame_time_s")?;
        let (triangles, coarsest) = sel.triangles();
        match &mut sched.inner {
            Inner::Reactive(r) => {
                r.observe(t, triangles, coarsest);
            }
            Inner::Predictive(p) => p.observe(t, triangles, coarsest),
        }
        Ok(())
    })
}

/// Tells the predictive scheduler of extra work the next frame will do
/// (a shader to compile, a chunk to stream in), s (finite, >= 0): that
/// frame's budget leaves room for it, and the load is not learnt as the
/// scene's cost. Call it before `acuity_scheduler_apply`. The reactive
/// scheduler has no cost model to budget a load with: it refuses the
/// call (`ACUITY_INVALID_ARGUMENT`).
///
/// # Safety
/// `scheduler` must be NULL (refused) or a live scheduler no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_announce_load(
    scheduler: *mut AcuityScheduler,
    extra_s: f32,
) -> AcuityStatus {
    guard(|| {
        // SAFETY: forwarded from this function's contract.
        let sched = unsafe { borrow_mut(scheduler, "scheduler") }?;
        let extra_s = crate::error::non_negative(extra_s, "extra_s")?;
        match &mut sched.inner {
            Inner::Reactive(_) => Err(Failure::invalid(
                "the reactive scheduler cannot budget an announced load; \
                 use ACUITY_SCHEDULER_PREDICTIVE",
            )),
            Inner::Predictive(p) => {
                p.announce_load(extra_s);
                Ok(())
            }
        }
    })
}

/// Sets the reactive scheduler's `s` to `scale` (finite, in (0, 1]; below
/// the scheduler's lowest `s`, 1e-3, it starts there) and climbs from it:
/// until the first frame that is not below the dead band, `s` rises after
/// every frame instead of after three. Call it before the first frame (or
/// after a cut to a new scene) to show the first frames coarse rather than
/// late: from `s = 1` the scheduler learns only from late frames how far
/// it must come down. The predictive scheduler starts from its cost model:
/// it refuses the call (`ACUITY_INVALID_ARGUMENT`).
///
/// # Safety
/// `scheduler` must be NULL (refused) or a live scheduler no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_start_at(
    scheduler: *mut AcuityScheduler,
    scale: f32,
) -> AcuityStatus {
    guard(|| {
        // SAFETY: forwarded from this function's contract.
        let sched = unsafe { borrow_mut(scheduler, "scheduler") }?;
        if !(scale.is_finite() && scale > 0.0 && scale <= 1.0) {
            return Err(Failure::invalid(format!(
                "`scale` is {scale}; it must be finite and in (0, 1]"
            )));
        }
        match &mut sched.inner {
            Inner::Reactive(r) => {
                *r = r.clone().starting_at(scale);
                Ok(())
            }
            Inner::Predictive(_) => Err(Failure::invalid(
                "the predictive scheduler starts from its cost model; \
                 acuity_scheduler_start_at is for ACUITY_SCHEDULER_REACTIVE",
            )),
        }
    })
}

/// Writes what the scheduler holds into `*out` (see
/// `AcuitySchedulerState`).
///
/// # Safety
/// `scheduler` must be NULL (refused) or a live scheduler no other thread
/// uses; `out` NULL (refused) or valid for writing an
/// `AcuitySchedulerState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_scheduler_state(
    scheduler: *mut AcuityScheduler,
    out: *mut AcuitySchedulerState,
) -> AcuityStatus {
    guard(|| {
        check_out(out, "out")?;
        // SAFETY: forwarded from this function's contract.
        let sched = unsafe { borrow_mut(scheduler, "scheduler") }?;
        let state = match &mut sched.inner {
            Inner::Reactive(r) => AcuitySchedulerState {
                scale: r.scale(),
                budget: ACUITY_NO_BUDGET,
                aim_s: r.aim_s(),
                target_unreachable: u8::from(r.target_unreachable()),
                cost_floor_s: r.cost_floor_s().unwrap_or(UNKNOWN_FLOOR_S),
            },
            Inner::Predictive(p) => AcuitySchedulerState {
                scale: 1.0,
                budget: p.triangle_budget(),
                aim_s: p.aim_s(),
                target_unreachable: u8::from(p.target_unreachable()),
                cost_floor_s: p.cost_floor_s().unwrap_or(UNKNOWN_FLOOR_S),
            },
        };
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out, "out", state) }
    })
}

/// A measured frame time: finite and > 0.
fn frame_time(value: f32, name: &str) -> Result<f32> {
    let t = crate::error::finite(value, name)?;
    if t <= 0.0 {
        return Err(Failure::invalid(format!(
            "`{name}` is {t}; it must be > 0 (a measured frame time, s)"
        )));
    }
    Ok(t)
}

impl std::fmt::Debug for AcuityScheduler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self.inner {
            Inner::Reactive(_) => "AcuityScheduler::Reactive",
            Inner::Predictive(_) => "AcuityScheduler::Predictive",
        })
    }
}
