//! Fixed frame rate: choosing the global scale factor `s`, or the
//! triangle budget, that keeps frames inside their period.
//!
//! - [`ReactiveScheduler`] (Reddy 1998 §6) watches measured frame times:
//!   it lowers `s` after a frame over its aim and raises it, never above 1,
//!   when the frames have had spare time for a while.
//! - [`PredictiveScheduler`] (Funkhouser & Séquin 1993) spends a triangle
//!   budget before the frame is drawn, through
//!   [`Selector::select_within_budget`](crate::Selector::select_within_budget)
//!   (least visible detail per triangle first, or one `s` for all); its
//!   [`CostModel`] turns the frame-time aim into that budget from measured
//!   frames.
//!
//! Both aim below the frame period, not at it: at
//! [`ReactiveSettings::headroom`] of it (90% by default), lower still when
//! the frame times they see vary more (the aim leaves
//! [`ReactiveSettings::variation_z`] standard deviations of a frame's
//! relative variation), so that a frame that runs a little long still
//! fits. Between the aim and `1 - dead_band` of it they change nothing (and
//! so switch no LOD): a frame rate that fits is held, not chased.
//!
//! **The cost floor.** No LOD choice removes the frame's fixed time (what
//! does not depend on triangles, including a load spike from elsewhere) nor
//! the triangles of every visible object's coarsest LOD.
//! [`CostModel::floor_s`] predicts that floor, assuming a change of load is
//! additive (other work in the frame) and a triangle costs what it costs
//! where the frames are (the local cost). When the floor lies above the
//! frame period, no `s` reaches the target: both schedulers say so
//! (`target_unreachable`) and stop lowering `s` (or the budget), which
//! would cost detail and buy no frame on time.
//!
//! Both are pure: they are given times, they read no clock.
//!
//! Frame rates: a target rate is accepted from [`MIN_TARGET_HZ`] to
//! [`MAX_TARGET_HZ`] (a frame period of 1 s to 0.1 ms), so its period is a
//! finite, normal `f32` and a triangle budget computed from it is
//! meaningful.
//!
//! Code: this module (the settings, the frame statistics both share, the
//! reactive scheduler), `predictive` (the predictive scheduler), `cost`
//! (the cost model) and `load_step` (telling a step of load, and the
//! memory of the knob before it).

use crate::error::{Error, Result, number};

mod cost;
mod load_step;
mod predictive;

pub use cost::{CostModel, FLOOR_SLOPES};
use load_step::{LoadMemory, LoadSteps, SCALE_COST_EXPONENT};
pub use predictive::PredictiveScheduler;

/// Lowest accepted target frame rate, Hz (a frame period of 1 s).
pub const MIN_TARGET_HZ: f32 = 1.0;
/// Highest accepted target frame rate, Hz (a frame period of 0.1 ms).
pub const MAX_TARGET_HZ: f32 = 10_000.0;
/// Largest triangle budget [`CostModel::triangle_budget`] returns: a target
/// with time for more (an infinite one included) gets this many.
pub const MAX_TRIANGLE_BUDGET: u64 = u64::MAX / 2;

/// Checks a target frame rate in Hz: from [`MIN_TARGET_HZ`] to
/// [`MAX_TARGET_HZ`]; the error names `name` and the limits.
pub fn check_target_hz(name: &'static str, rate_hz: f64) -> Result<()> {
    if (f64::from(MIN_TARGET_HZ)..=f64::from(MAX_TARGET_HZ)).contains(&rate_hz) {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!(
                "{} Hz is outside {MIN_TARGET_HZ}..={MAX_TARGET_HZ} Hz",
                number(rate_hz)
            ),
        ))
    }
}

/// Tuning of the [`ReactiveScheduler`] and the [`PredictiveScheduler`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactiveSettings {
    /// Target frame period, s, e.g. `1.0 / 90.0`: 0.1 ms to 1 s (`1 /
    /// MAX_TARGET_HZ` to `1 / MIN_TARGET_HZ`; the schedulers clamp it
    /// there).
    pub target_frame_s: f32,
    /// Fraction of the period the frames aim at, in `[0.5, 1]`; 0.9 leaves
    /// a tenth of the period for a frame that runs long.
    pub headroom: f32,
    /// Standard deviations of the frames' relative variation (learned from
    /// the measured frames) the aim leaves below the period, `[0, 10]`:
    /// the aim is `period * min(headroom, 1 / (1 + variation_z sigma))`,
    /// at least half the period.
    pub variation_z: f32,
    /// Lowest `s`, in `(0, 1]` (by default
    /// [`DEFAULT_MIN_SCALE`](crate::DEFAULT_MIN_SCALE), 1e-3, as the
    /// budgeted selection's
    /// [`SelectorSettings::min_scale`](crate::SelectorSettings::min_scale);
    /// below [`LOWEST_MIN_SCALE`](crate::LOWEST_MIN_SCALE) it is raised to
    /// it, above 1 lowered to 1; not finite, NaN included, it is the
    /// default).
    pub min_scale: f32,
    /// Exponent of the multiplicative step: `s *= (aim / frame)^gain`.
    /// 0.5 moves half-way (in log terms) towards the estimated fit.
    pub gain: f32,
    /// Frames between `(1 - dead_band) aim` and `aim` change nothing: the
    /// band absorbs the step changes of discrete LODs. `[0, 0.9]`; the
    /// band is widened to 2.5 learned standard deviations of a frame's
    /// relative variation where that is wider (with
    /// [`steer_to_band_middle`](Self::steer_to_band_middle)).
    pub dead_band: f32,
    /// Frames in a row, at least 1, that must lie below the dead band
    /// before `s` (or the budget) rises, or above the aim (but within the
    /// period) before it falls: one lucky or unlucky frame moves nothing.
    /// A frame over the period acts at once.
    pub settle_frames: u32,
    /// Whether a move of the knob steers to the middle of the dead band
    /// (so the frames' jitter leaves it on neither side), or to the aim
    /// itself (as before headroom).
    pub steer_to_band_middle: bool,
    /// Frame time ratios above this count as this much: one huge frame (a
    /// page fault, a shader compile) lowers `s` at most by
    /// `max_ratio^-gain`.
    pub max_ratio: f32,
    /// Largest factor by which `s` rises in one frame.
    pub max_raise: f32,
    /// An overload no larger than this ratio, right after a raise, is
    /// blamed on the raise: that `s` becomes a ceiling not to reach again
    /// until the load drops. Larger overloads are spikes.
    pub spike_ratio: f32,
    /// A frame faster than this fraction of the period means the load has
    /// dropped: the ceiling is lifted.
    pub clear_ratio: f32,
    /// Whether a frame over the period after one over it, under a load
    /// that lasts, moves `s` to where the frame's own cost says it fits
    /// (the reactive scheduler, fed back through
    /// [`ReactiveScheduler::observe`] with a cost model): the triangles
    /// above the coarsest LODs at the cost model's local per-triangle cost,
    /// following `s` with an exponent learned from the frames. Without it
    /// the step is the proportional one, which takes a frame or more per
    /// halving where the triangles follow `s` weakly.
    pub fit_step_to_cost: bool,
}

impl ReactiveSettings {
    /// Defaults for a target frame rate in Hz, from [`MIN_TARGET_HZ`] to
    /// [`MAX_TARGET_HZ`]; another rate (NaN included) is an
    /// [`Error::InvalidParameter`] naming `rate_hz` and the limits.
    pub fn for_rate_hz(rate_hz: f32) -> Result<Self> {
        check_target_hz("rate_hz", f64::from(rate_hz))?;
        Ok(Self {
            target_frame_s: 1.0 / rate_hz,
            headroom: 0.9,
            variation_z: 2.0,
            min_scale: crate::DEFAULT_MIN_SCALE,
            gain: 0.5,
            dead_band: 0.1,
            settle_frames: 3,
            steer_to_band_middle: true,
            max_ratio: 4.0,
            max_raise: 1.25,
            spike_ratio: 2.0,
            clear_ratio: 0.5,
            fit_step_to_cost: true,
        })
    }

    /// The settings of the controllers before headroom, learned variation
    /// and settling: they aim at the period itself and act on every frame.
    /// Kept to measure the controllers against.
    pub fn without_headroom(self) -> Self {
        Self {
            headroom: 1.0,
            variation_z: 0.0,
            settle_frames: 1,
            steer_to_band_middle: false,
            fit_step_to_cost: false,
            ..self
        }
    }

    /// The settings with every field clamped into its domain: the target
    /// period into 0.1 ms to 1 s (`+inf` becomes 1 s; NaN, zero or a
    /// negative period 1/60 s).
    fn clamped(self) -> Self {
        let mut s = self;
        s.target_frame_s = if s.target_frame_s > 0.0 {
            s.target_frame_s
                .clamp(1.0 / MAX_TARGET_HZ, 1.0 / MIN_TARGET_HZ)
        } else {
            1.0 / 60.0
        };
        s.headroom = finite_or(s.headroom, 0.9).clamp(0.5, 1.0);
        s.variation_z = finite_or(s.variation_z, 2.0).clamp(0.0, 10.0);
        s.min_scale = crate::select::effective_min_scale(s.min_scale);
        s.gain = finite_or(s.gain, 0.5).clamp(0.01, 1.0);
        s.dead_band = finite_or(s.dead_band, 0.1).clamp(0.0, 0.9);
        s.settle_frames = s.settle_frames.max(1);
        s.max_ratio = finite_or(s.max_ratio, 4.0).max(1.0);
        s.max_raise = finite_or(s.max_raise, 1.25).max(1.0);
        s.spike_ratio = finite_or(s.spike_ratio, 2.0).max(1.0);
        s.clear_ratio = finite_or(s.clear_ratio, 0.5).clamp(0.0, 1.0);
        s
    }

    /// Whether a cost floor (s; `None`: unknown) lies above the period: no
    /// choice of LODs then brings a frame within it.
    fn beyond_reach(&self, floor_s: Option<f32>) -> bool {
        floor_s.is_some_and(|f| f > self.target_frame_s)
    }

    /// The frame time aimed at, s, for a relative variation `sigma`.
    fn aim_s(&self, sigma: f32) -> f32 {
        let fraction = self
            .headroom
            .min(1.0 / (1.0 + self.variation_z * sigma))
            .max(0.5);
        fraction * self.target_frame_s
    }

    /// The frame time a move of the knob steers to: the middle of the
    /// dead band below `aim_s`, so that the frames' jitter leaves it on
    /// neither side.
    fn steer_s(&self, aim_s: f32, sigma: f32) -> f32 {
        if self.steer_to_band_middle {
            (1.0 - 0.5 * self.band(sigma)) * aim_s
        } else {
            aim_s
        }
    }

    /// The dead band's width, a fraction of the aim: at least
    /// [`dead_band`](Self::dead_band), and wide enough for the frames'
    /// jitter ([`BAND_SIGMAS`] learned standard deviations), at most 0.9.
    fn band(&self, sigma: f32) -> f32 {
        if self.steer_to_band_middle {
            self.dead_band.max(BAND_SIGMAS * sigma).min(0.9)
        } else {
            self.dead_band
        }
    }
}

/// The smallest relative step down.
const MIN_LOWER_FACTOR: f32 = 0.98;
/// The largest exponent of a step down while frames over the period do
/// not respond to `s` (see `ReactiveScheduler::descent_gain`): the step
/// that would fit a frame cost proportional to `s`. With
/// [`ReactiveSettings::max_ratio`] 4, `s` falls at most 4-fold a frame.
/// An exponent of 2 came down a frame sooner on `scenes/vr_sweep.toml`
/// but, after a noisy frame, to a quarter of the `s` that held the rate,
/// and took a second to climb back.
const MAX_DESCENT_GAIN: f32 = 1.0;

/// How a frame's triangles above the coarsest follow `s` (the exponent
/// of a power law) before any move of `s` has shown it: in proportion.
const INITIAL_SCALE_ELASTICITY: f32 = 1.0;
/// The range the learned exponent is kept in: a quarter (a step down
/// then cuts `s` at most by the fourth power of the time it must save)
/// to two (the quadratic cost the gain is sized for).
const SCALE_ELASTICITY_RANGE: (f32, f32) = (0.25, 2.0);
/// Weight of one move of `s` in the learned exponent.
const SCALE_ELASTICITY_RATE: f32 = 0.3;
/// The smallest move of `s` between two frames, in log terms, that
/// teaches the exponent: smaller moves are lost in what the view alone
/// changes from frame to frame.
const SCALE_ELASTICITY_MIN_MOVE: f32 = 0.15;
/// The largest factor by which `s` falls in one frame when the step is
/// fitted to the frame's cost (`ReactiveScheduler::fitted_step`).
const MAX_FITTED_FALL: f32 = 16.0;

/// Weight of a frame in the learned relative variation.
const VARIATION_RATE: f32 = 0.05;
/// Largest relative change between two frames that counts towards the
/// variation: a spike is not jitter.
const VARIATION_CLIP: f32 = 0.25;
/// The relative variation assumed before any frame is seen.
const INITIAL_SIGMA: f32 = 0.03;
/// Width of the dead band, at least, in learned standard deviations of a
/// frame's relative variation.
const BAND_SIGMAS: f32 = 2.5;
/// The cost model's learning rate, at least, on a frame over the period.
const MISS_LEARNING_RATE: f32 = 0.5;
/// Weight of a frame in the smoothed frame time the dead band judges.
const LEVEL_RATE: f32 = 0.3;
/// The first step of the predictive scheduler's return after a load, a
/// fraction of the budget from before it. The view may have grown dearer
/// while the load lasted; the load's frames, of few triangles and mostly
/// fixed time, do not show it, and a budget returned to at once and then
/// cut switches back every object the return refined. Half the budget
/// fits a view whose triangles came to cost up to twice what they did, and
/// its frame, of many triangles, reads what they cost now
/// (`CostModel::budget_by_frame`) for the second step.
const RETURN_FIRST_STEP: f64 = 0.5;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    Hold,
    Raise,
    Lower,
}

/// The learned relative variation of frame times, and the smoothed frame
/// time since the knob last moved (shared by both schedulers).
#[derive(Clone, Copy, Debug, PartialEq)]
struct FrameStats {
    /// Mean square relative variation of one frame.
    variance: f32,
    /// Smoothed frame time since the knob last moved, s.
    level_s: f32,
    last_s: f32,
    /// Frames seen since the knob last moved.
    frames: u32,
    /// Frames in a row whose smoothed time lay below the dead band / above
    /// the aim.
    calm: u32,
    busy: u32,
    /// Frames in a row over the period.
    over: u32,
}

impl FrameStats {
    fn new() -> Self {
        Self {
            variance: INITIAL_SIGMA * INITIAL_SIGMA,
            level_s: 0.0,
            last_s: 0.0,
            frames: 0,
            calm: 0,
            busy: 0,
            over: 0,
        }
    }

    fn sigma(&self) -> f32 {
        self.variance.sqrt()
    }

    /// Learns from a frame of `frame_s` (finite, positive) against the
    /// aim's band.
    fn observe(&mut self, frame_s: f32, aim_s: f32, dead_band: f32, period_s: f32) {
        self.over = if frame_s > period_s { self.over + 1 } else { 0 };
        if self.frames > 0 {
            // Two frames at the same knob differ by sqrt(2) sigma.
            let r = (frame_s / self.last_s)
                .ln()
                .clamp(-VARIATION_CLIP, VARIATION_CLIP);
            self.variance += VARIATION_RATE * (0.5 * r * r - self.variance);
            self.level_s += LEVEL_RATE * (frame_s - self.level_s);
        } else {
            self.level_s = frame_s;
        }
        self.last_s = frame_s;
        self.frames += 1;
        self.calm = if self.level_s < (1.0 - dead_band) * aim_s {
            self.calm + 1
        } else {
            0
        };
        self.busy = if self.level_s > aim_s {
            self.busy + 1
        } else {
            0
        };
    }

    /// Learns from a frame of `frame_s` (finite, positive) against the aim
    /// and band of `settings` before it; returns that aim.
    fn see(&mut self, settings: &ReactiveSettings, frame_s: f32) -> f32 {
        let sigma = self.sigma();
        let aim = settings.aim_s(sigma);
        self.observe(frame_s, aim, settings.band(sigma), settings.target_frame_s);
        aim
    }

    /// Whether the frame just seen missed the period clearly: by more than
    /// the dead band (beyond the jitter), or for the second frame in a row.
    fn missed(&self, frame_s: f32, period_s: f32, band: f32) -> bool {
        frame_s > (1.0 + band) * period_s || self.over >= 2
    }

    /// The knob moved: the level starts again.
    fn moved(&mut self) {
        self.frames = 0;
        self.calm = 0;
        self.busy = 0;
    }
}

/// The reactive fixed-frame-rate controller for `s`.
///
/// It aims at [`ReactiveSettings::headroom`] of the period (less when the
/// frames vary more; the module docs). A frame over the period lowers `s`
/// at once; otherwise `s` moves only after
/// [`ReactiveSettings::settle_frames`] frames in a row above the aim
/// (lower) or below its dead band (raise).
///
/// Stability: the step is proportional in log terms with gain 0.5, which
/// converges without overshoot for frame costs up to quadratic in `s`; the
/// dead band stops it hunting between two discrete LOD levels; and an `s`
/// whose raise overloaded the frame becomes a ceiling (lowered 3% below),
/// so the controller cannot cycle between a level that fits and one that
/// does not. The ceiling is lifted when a frame comes in under
/// [`ReactiveSettings::clear_ratio`] of the period, i.e. the load itself
/// has dropped. Coming down from an overload whose frame time does not
/// follow `s` (the first halvings below full detail switch few objects),
/// the step grows to the one that fits a cost proportional to `s`. A load
/// that steps the frame time up at an unchanged `s` and over the period
/// (another task's work, a spike of many frames) is remembered with the
/// `s` before it: when the frame time steps down again by as much, `s`
/// returns there at once instead of climbing back by the raise rule,
/// whose steps are small where the frame has much fixed time. Under such a
/// load, a frame over the period after one over it moves `s` to where that
/// frame's own cost says it fits
/// ([`ReactiveSettings::fit_step_to_cost`]; fed back through
/// [`observe`](Self::observe) with a cost model): the frame less its
/// triangles above the coarsest LODs (at the cost model's local cost)
/// stays, and those triangles follow `s` by an exponent learned from the
/// frames' moves of `s` (where they follow it weakly, a step sized for a
/// proportional cost leaves several frames of a load late). Limited to
/// loads that last, since a frame late by jitter says nothing of how far
/// `s` must fall.
#[derive(Clone, Debug)]
pub struct ReactiveScheduler {
    settings: ReactiveSettings,
    scale: f32,
    ceiling: Option<f32>,
    last: Step,
    stats: FrameStats,
    /// The last frame's cost floor, s, where known.
    floor_s: Option<f32>,
    /// `s` before the spike that lowered it, until calm frames return it.
    before_spike: Option<f32>,
    /// `s` before the last load that lasts lowered it, until a frame
    /// shows the load gone (see [`load_step::LOAD_STEP`]) or the memory
    /// is too old ([`load_step::LOAD_MEMORY_S`]).
    before_load: Option<LoadMemory<f32>>,
    /// The last two frames' `s` and times, to tell a step of load by.
    load_steps: LoadSteps,
    /// After a frame over the period lowered `s`: the `s` before that
    /// move and the frame's time, to judge the next frame by.
    descent: Option<(f32, f32)>,
    /// The cost model [`Self::observe`] learns the cost floor from.
    cost: Option<CostModel>,
    /// Started below `s = 1` ([`Self::starting_at`]) and every frame so
    /// far below the dead band: `s` rises after each such frame, not after
    /// [`ReactiveSettings::settle_frames`] of them.
    climbing: bool,
    /// The last frame fed back through [`Self::observe`]: its `s` and its
    /// triangles above the coarsest.
    last_drawn: Option<(f32, f32)>,
    /// The learned exponent of `s` that the triangles above the coarsest
    /// follow (`d ln triangles / d ln s`).
    scale_elasticity: f32,
}

impl ReactiveScheduler {
    /// A controller starting at `s = 1`. Settings out of their domains are
    /// clamped into them: the target period into 0.1 ms to 1 s (`+inf`
    /// becomes 1 s; NaN, zero or a negative period 1/60 s).
    pub fn new(settings: ReactiveSettings) -> Self {
        Self {
            settings: settings.clamped(),
            scale: 1.0,
            ceiling: None,
            last: Step::Hold,
            stats: FrameStats::new(),
            floor_s: None,
            before_spike: None,
            before_load: None,
            load_steps: LoadSteps::new(),
            descent: None,
            cost: None,
            climbing: false,
            last_drawn: None,
            scale_elasticity: INITIAL_SCALE_ELASTICITY,
        }
    }

    /// This controller starting at `scale` instead of 1 (clamped into
    /// `[min_scale, 1]`; NaN is 1). A VR runtime that would rather show
    /// its first frames coarse than late starts at
    /// [`ReactiveSettings::min_scale`] and climbs to the target: from
    /// `s = 1` the controller learns only from late frames how far it must
    /// come down (4-5 frames from full detail on a scene that needs a
    /// tenth of its triangles). Until the first frame that is not below
    /// the dead band, `s` rises after every frame (by at most
    /// [`ReactiveSettings::max_raise`]) instead of after
    /// [`ReactiveSettings::settle_frames`] of them.
    pub fn starting_at(mut self, scale: f32) -> Self {
        self.scale = if scale.is_nan() {
            1.0
        } else {
            scale.clamp(self.settings.min_scale, 1.0)
        };
        self.climbing = self.scale < 1.0;
        self
    }

    /// This controller with a cost model (a starting guess or a
    /// calibration, as for [`PredictiveScheduler::new`]) that
    /// [`observe`](Self::observe) fits to the measured frames, to know the
    /// cost floor.
    pub fn with_cost_model(mut self, cost: CostModel) -> Self {
        self.cost = Some(cost);
        self
    }

    /// The cost model given to [`with_cost_model`](Self::with_cost_model),
    /// as learned so far.
    pub fn cost_model(&self) -> Option<&CostModel> {
        self.cost.as_ref()
    }

    /// Feeds back the frame just drawn as [`PredictiveScheduler::observe`]
    /// does: its time (s), the triangles it drew and those it would have
    /// drawn with every visible object at its coarsest LOD. With a cost
    /// model ([`with_cost_model`](Self::with_cost_model)) the model learns
    /// the frame and its cost floor goes to
    /// [`update_with_floor`](Self::update_with_floor); without one, as
    /// [`update`](Self::update). Returns the new `s`.
    pub fn observe(&mut self, frame_time_s: f32, triangles: u64, coarsest_triangles: u64) -> f32 {
        let floor_s = self.cost.as_mut().and_then(|c| {
            c.observe(frame_time_s, triangles);
            c.floor_s(coarsest_triangles)
        });
        let above = triangles.saturating_sub(coarsest_triangles);
        if frame_time_s.is_finite() && frame_time_s > 0.0 {
            self.learn_elasticity(above);
        }
        self.step(frame_time_s, floor_s, Some(above))
    }

    /// The learned exponent of `s` that a frame's triangles above the
    /// coarsest follow (1 until moves of `s` fed back through
    /// [`observe`](Self::observe) show it; kept within 0.25 to 2).
    pub fn scale_elasticity(&self) -> f32 {
        self.scale_elasticity
    }

    /// The current `s`.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The settings in use (after clamping).
    pub fn settings(&self) -> &ReactiveSettings {
        &self.settings
    }

    /// The frame time aimed at now, s (the headroom and the learned
    /// variation applied).
    pub fn aim_s(&self) -> f32 {
        self.settings.aim_s(self.stats.sigma())
    }

    /// The learned relative variation of a frame's time (a standard
    /// deviation; 0.03 before any frame).
    pub fn relative_variation(&self) -> f32 {
        self.stats.sigma()
    }

    /// Whether the last frame's cost floor lay above the period (see
    /// [`update_with_floor`](Self::update_with_floor)).
    pub fn target_unreachable(&self) -> bool {
        self.settings.beyond_reach(self.floor_s)
    }

    /// The last frame's cost floor, s: its time with every visible object
    /// at its coarsest LOD ([`CostModel::floor_s`]); `None` while unknown.
    /// A floor above the period makes the target unreachable; one between
    /// [`aim_s`](Self::aim_s) and the period leaves frames on time only as
    /// far as their jitter allows, whatever the LODs.
    pub fn cost_floor_s(&self) -> Option<f32> {
        self.floor_s
    }

    /// Feeds the measured time of the frame just drawn (s) and returns the
    /// `s` for the next. A time that is zero, negative or not finite
    /// changes nothing.
    pub fn update(&mut self, frame_time_s: f32) -> f32 {
        self.update_with_floor(frame_time_s, None)
    }

    /// As [`update`](Self::update), told the frame's cost floor (s: the
    /// time of the frame at every object's coarsest LOD,
    /// [`CostModel::floor_s`]). While the floor lies above the period, no
    /// `s` reaches the target: `s` is not lowered, and
    /// [`target_unreachable`](Self::target_unreachable) says so. A floor
    /// that is `None` or not finite is unknown.
    pub fn update_with_floor(&mut self, frame_time_s: f32, floor_s: Option<f32>) -> f32 {
        self.step(frame_time_s, floor_s, None)
    }

    /// As [`update_with_floor`](Self::update_with_floor), told the frame's
    /// triangles above its coarsest LODs where it was fed back through
    /// [`observe`](Self::observe) (for [`Self::fitted_step`]).
    fn step(&mut self, frame_time_s: f32, floor_s: Option<f32>, above: Option<u64>) -> f32 {
        if !(frame_time_s.is_finite() && frame_time_s > 0.0) {
            return self.scale;
        }
        let st = self.settings;
        self.floor_s = floor_s.filter(|f| f.is_finite());
        let unreachable = self.target_unreachable();
        let aim = self.stats.see(&st, frame_time_s);
        let old = self.scale;
        let missed =
            self.stats
                .missed(frame_time_s, st.target_frame_s, st.band(self.stats.sigma()));
        self.climbing &= self.stats.calm > 0;
        let settle_frames = if self.climbing { 1 } else { st.settle_frames };
        let settled = self.stats.frames >= settle_frames;
        // A step of the frame time that the change of `s` does not explain
        // is a change of load.
        let step = self
            .load_steps
            .see(SCALE_COST_EXPONENT * old.ln(), frame_time_s);
        let load_gone = LoadMemory::follow(
            &mut self.before_load,
            frame_time_s,
            frame_time_s > st.target_frame_s,
            &step,
            LoadMemory::level_s,
            || Some(old),
        );
        if (missed || self.stats.busy >= st.settle_frames) && !unreachable {
            let measured = if missed {
                frame_time_s
            } else {
                self.stats.level_s.max(aim)
            };
            let ratio = (measured / st.steer_s(aim, self.stats.sigma())).min(st.max_ratio);
            let spike = frame_time_s / st.target_frame_s > st.spike_ratio;
            // The first move down since a raise (not for a spike) blames
            // the raise.
            if self.last == Step::Raise && !spike {
                self.ceiling = Some(old);
            }
            // One frame far over the period, after one within it, may be a
            // spike, not a new load: if calm frames follow, `s` returns to
            // where it was. A second frame over the period is a load.
            self.before_spike =
                (spike && self.stats.over == 1 && self.stats.frames > 1).then_some(old);
            let gain = if missed {
                self.descent_gain(old, frame_time_s)
            } else {
                st.gain
            };
            // A miss after a miss under a load that lasts (not jitter):
            // the step fits the frame's cost.
            let again = missed
                && st.fit_step_to_cost
                && self.before_load.is_some()
                && (self.descent.is_some() || self.stats.over >= 2);
            self.descent = missed.then_some((old, frame_time_s));
            // At least a 2% step: a frame barely over its aim would otherwise
            // creep towards the next LOD step for hundreds of frames.
            let mut next = old * ratio.powf(-gain).min(MIN_LOWER_FACTOR);
            if again
                && let Some(factor) = above.and_then(|above| {
                    self.fitted_step(frame_time_s, st.steer_s(aim, self.stats.sigma()), above)
                })
            {
                next = next.min(old * factor);
            }
            self.scale = next.max(st.min_scale);
        } else if settled && self.stats.calm >= settle_frames {
            let level = self.stats.level_s.max(frame_time_s);
            if level < st.clear_ratio * st.target_frame_s {
                self.ceiling = None;
            }
            let ratio = (level / st.steer_s(aim, self.stats.sigma())).min(st.max_ratio);
            let mut next = old * ratio.powf(-st.gain).min(st.max_raise);
            if let Some(s0) = self.before_spike.take() {
                next = next.max(s0);
            }
            if let Some(c) = self.ceiling {
                next = next.min(0.97 * c);
            }
            self.scale = next.clamp(st.min_scale, 1.0).max(old.min(1.0));
        }
        if load_gone && let Some(m) = self.before_load.take() {
            self.ceiling = None;
            self.scale = self.scale.max(m.before).min(1.0);
        }
        // Climbed back by the raise rule: nothing left to return to.
        if self.scale > old && self.before_load.is_some_and(|m| self.scale >= m.before) {
            self.before_load = None;
        }
        if self.scale >= old {
            self.descent = None;
        }
        // `last` is the last move, holds in between kept.
        if self.scale > old {
            self.last = Step::Raise;
        } else if self.scale < old {
            self.last = Step::Lower;
        }
        // Frames out of reach say nothing of the load after them.
        if self.scale != old || unreachable {
            self.stats.moved();
        }
        self.scale
    }
}

impl ReactiveScheduler {
    /// The factor of `s` that brings a frame of `frame_s` to `steer_s`
    /// (both s) by the frame's own cost: its `above` triangles above the
    /// coarsest LODs cost the cost model's local per-triangle cost, the
    /// rest of the frame stays, and those triangles follow `s` with the
    /// learned exponent. At least `1 / MAX_FITTED_FALL` (a floor above
    /// `steer_s` asks for that). `None` without a cost model whose local
    /// cost is measured, or where the frame drew nothing above its
    /// coarsest LODs.
    fn fitted_step(&self, frame_s: f32, steer_s: f32, above: u64) -> Option<f32> {
        let per_triangle_s = self.cost.as_ref()?.local_per_triangle_s()?;
        let above_s = per_triangle_s * above as f32;
        if !(above_s > 0.0 && above_s.is_finite()) {
            return None;
        }
        let kept_s = frame_s - above_s;
        let fraction = ((steer_s - kept_s) / above_s).clamp(0.0, 1.0);
        let factor = fraction.powf(1.0 / self.scale_elasticity);
        Some(factor.max(1.0 / MAX_FITTED_FALL))
    }

    /// Learns how the triangles above the coarsest (`above`, of the frame
    /// drawn at the current `s`) follow `s`, from a move of `s` since the
    /// last frame fed back of at least [`SCALE_ELASTICITY_MIN_MOVE`].
    fn learn_elasticity(&mut self, above: u64) {
        let (scale, above) = (self.scale, above as f32);
        if let Some((last_scale, last_above)) = self.last_drawn {
            let moved = (scale / last_scale).ln();
            let grew = (above / last_above).ln();
            if moved.abs() >= SCALE_ELASTICITY_MIN_MOVE && grew.is_finite() {
                let (low, high) = SCALE_ELASTICITY_RANGE;
                let seen = (grew / moved).clamp(low, high);
                self.scale_elasticity += SCALE_ELASTICITY_RATE * (seen - self.scale_elasticity);
            }
        }
        self.last_drawn = Some((scale, above));
    }

    /// The exponent of a step down after a frame of `frame_s` over the
    /// period at `scale`. The gain (0.5) is sized for a frame cost up to
    /// quadratic in `s`; where the last step down, also after a frame over
    /// the period, cut the frame time by less than half of what a cost
    /// proportional to `s` would have, the cost is flatter here (the
    /// objects switch further down, the fixed time dominates) and the step
    /// is the one that fits a proportional cost ([`MAX_DESCENT_GAIN`]):
    /// coming down from full detail's frames, each halving of `s` would
    /// otherwise cost a late frame.
    fn descent_gain(&self, scale: f32, frame_s: f32) -> f32 {
        let gain = self.settings.gain;
        match self.descent {
            Some((before, before_frame_s)) if before > scale => {
                let fell = (before / scale).ln();
                let frame_fell = (before_frame_s / frame_s).ln();
                if frame_fell < 0.5 * fell {
                    gain.max(MAX_DESCENT_GAIN)
                } else {
                    gain
                }
            }
            _ => gain,
        }
    }
}

fn finite_or(x: f32, fallback: f32) -> f32 {
    if x.is_finite() { x } else { fallback }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_rates_outside_the_limits_are_refused_by_name() {
        for hz in [0.0, 1e-40, 0.5, 10_001.0, f32::INFINITY, f32::NAN, -60.0] {
            let e = ReactiveSettings::for_rate_hz(hz).unwrap_err().to_string();
            assert!(e.contains("rate_hz") && e.contains("10000"), "{hz}: {e}");
        }
        for hz in [MIN_TARGET_HZ, 90.0, MAX_TARGET_HZ] {
            assert!(ReactiveSettings::for_rate_hz(hz).is_ok(), "{hz}");
        }
    }

    #[test]
    fn an_infinite_target_period_is_the_longest_accepted_not_one_sixtieth() {
        let mut settings = ReactiveSettings::for_rate_hz(60.0).unwrap();
        settings.target_frame_s = f32::INFINITY;
        let sched = ReactiveScheduler::new(settings);
        assert_eq!(sched.settings().target_frame_s, 1.0 / MIN_TARGET_HZ);
        settings.target_frame_s = f32::NAN;
        let sched = ReactiveScheduler::new(settings);
        assert_eq!(sched.settings().target_frame_s, 1.0 / 60.0);
    }
}
