//! Fixed frame rate: choosing the global scale factor `s`.
//!
//! - [`ReactiveScheduler`] (Reddy 1998 §6) watches measured frame times:
//!   it lowers `s` after a frame over the target period and raises it,
//!   never above 1, when there was spare time.
//! - The predictive mode (Funkhouser & Séquin 1993) lives in
//!   [`Selector::select_within_budget`](crate::Selector::select_within_budget):
//!   it spends a triangle budget before the frame is drawn (least visible
//!   detail per triangle first, or one `s` for all). [`CostModel`] turns a frame-time target into that triangle
//!   budget from measured frames.
//!
//! Both are pure: they are given times, they read no clock.
//!
//! Frame rates: a target rate is accepted from [`MIN_TARGET_HZ`] to
//! [`MAX_TARGET_HZ`] (a frame period of 1 s to 0.1 ms), so its period is a
//! finite, normal `f32` and a triangle budget computed from it is
//! meaningful.

use crate::error::{Error, Result, number};

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

/// Tuning of the [`ReactiveScheduler`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactiveSettings {
    /// Target frame period, s, e.g. `1.0 / 90.0`: 0.1 ms to 1 s (`1 /
    /// MAX_TARGET_HZ` to `1 / MIN_TARGET_HZ`; [`ReactiveScheduler::new`]
    /// clamps it there).
    pub target_frame_s: f32,
    /// Lowest `s`, in `(0, 1]`.
    pub min_scale: f32,
    /// Exponent of the multiplicative step: `s *= (target / frame)^gain`.
    /// 0.5 moves half-way (in log terms) towards the estimated fit.
    pub gain: f32,
    /// Frames between `(1 - dead_band) target` and `target` change nothing:
    /// the band absorbs the step changes of discrete LODs.
    pub dead_band: f32,
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
    /// A frame faster than this fraction of the target means the load has
    /// dropped: the ceiling is lifted.
    pub clear_ratio: f32,
}

impl ReactiveSettings {
    /// Defaults for a target frame rate in Hz, from [`MIN_TARGET_HZ`] to
    /// [`MAX_TARGET_HZ`]; another rate (NaN included) is an
    /// [`Error::InvalidParameter`] naming `rate_hz` and the limits.
    pub fn for_rate_hz(rate_hz: f32) -> Result<Self> {
        check_target_hz("rate_hz", f64::from(rate_hz))?;
        Ok(Self {
            target_frame_s: 1.0 / rate_hz,
            min_scale: 0.05,
            gain: 0.5,
            dead_band: 0.1,
            max_ratio: 4.0,
            max_raise: 1.25,
            spike_ratio: 2.0,
            clear_ratio: 0.5,
        })
    }
}

/// The smallest relative step down.
const MIN_LOWER_FACTOR: f32 = 0.98;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    Hold,
    Raise,
    Lower,
}

/// The reactive fixed-frame-rate controller for `s`.
///
/// Stability: the step is proportional in log terms with gain 0.5, which
/// converges without overshoot for frame costs up to quadratic in `s`; a
/// dead band stops it hunting between two discrete LOD levels; and an `s`
/// whose raise overloaded the frame becomes a ceiling (lowered 3% below),
/// so the controller cannot cycle between a level that fits and one that
/// does not. The ceiling is lifted when a frame comes in under half the
/// target, i.e. the load itself has dropped.
#[derive(Clone, Debug)]
pub struct ReactiveScheduler {
    settings: ReactiveSettings,
    scale: f32,
    ceiling: Option<f32>,
    last: Step,
}

impl ReactiveScheduler {
    /// A controller starting at `s = 1`. Settings out of their domains are
    /// clamped into them: the target period into 0.1 ms to 1 s (`+inf`
    /// becomes 1 s; NaN, zero or a negative period 1/60 s).
    pub fn new(settings: ReactiveSettings) -> Self {
        let mut s = settings;
        s.target_frame_s = if s.target_frame_s > 0.0 {
            s.target_frame_s
                .clamp(1.0 / MAX_TARGET_HZ, 1.0 / MIN_TARGET_HZ)
        } else {
            1.0 / 60.0
        };
        s.min_scale = finite_or(s.min_scale, 0.05).clamp(1e-6, 1.0);
        s.gain = finite_or(s.gain, 0.5).clamp(0.01, 1.0);
        s.dead_band = finite_or(s.dead_band, 0.1).clamp(0.0, 0.9);
        s.max_ratio = finite_or(s.max_ratio, 4.0).max(1.0);
        s.max_raise = finite_or(s.max_raise, 1.25).max(1.0);
        s.spike_ratio = finite_or(s.spike_ratio, 2.0).max(1.0);
        s.clear_ratio = finite_or(s.clear_ratio, 0.5).clamp(0.0, 1.0);
        Self {
            settings: s,
            scale: 1.0,
            ceiling: None,
            last: Step::Hold,
        }
    }

    /// The current `s`.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The settings in use (after clamping).
    pub fn settings(&self) -> &ReactiveSettings {
        &self.settings
    }

    /// Feeds the measured time of the frame just drawn (s) and returns the
    /// `s` for the next. A time that is zero, negative or not finite
    /// changes nothing.
    pub fn update(&mut self, frame_time_s: f32) -> f32 {
        if !(frame_time_s.is_finite() && frame_time_s > 0.0) {
            return self.scale;
        }
        let st = &self.settings;
        let ratio = (frame_time_s / st.target_frame_s).min(st.max_ratio);
        let old = self.scale;
        if ratio > 1.0 {
            if self.last == Step::Raise && ratio <= st.spike_ratio {
                self.ceiling = Some(old);
            }
            // At least a 2% step: a frame barely over budget would otherwise
            // creep towards the next LOD step for hundreds of frames.
            self.scale = (old * ratio.powf(-st.gain).min(MIN_LOWER_FACTOR)).max(st.min_scale);
        } else if ratio < 1.0 - st.dead_band {
            if ratio < st.clear_ratio {
                self.ceiling = None;
            }
            let mut next = old * ratio.powf(-st.gain).min(st.max_raise);
            if let Some(c) = self.ceiling {
                next = next.min(0.97 * c);
            }
            self.scale = next.clamp(st.min_scale, 1.0).max(old.min(1.0));
        }
        self.last = if self.scale > old {
            Step::Raise
        } else if self.scale < old {
            Step::Lower
        } else {
            Step::Hold
        };
        self.scale
    }
}

fn finite_or(x: f32, fallback: f32) -> f32 {
    if x.is_finite() { x } else { fallback }
}

/// A linear frame-cost model, `frame_s = fixed_s + per_triangle_s *
/// triangles`, fitted online from measured frames, that turns a target
/// frame time into the triangle budget for
/// [`Selector::select_within_budget`](crate::Selector::select_within_budget).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    /// Time per frame that does not depend on triangles, s.
    pub fixed_s: f32,
    /// Time per triangle, s.
    pub per_triangle_s: f32,
    /// Weight of a new observation in the running fit, `(0, 1]`.
    pub learning_rate: f32,
}

impl CostModel {
    /// A model with an initial guess.
    pub fn new(fixed_s: f32, per_triangle_s: f32) -> Self {
        Self {
            fixed_s: finite_or(fixed_s, 0.0).max(0.0),
            per_triangle_s: finite_or(per_triangle_s, 1e-8).max(1e-15),
            learning_rate: 0.1,
        }
    }

    /// Updates the per-triangle cost from a measured frame (time in s and
    /// the triangles it drew). Invalid measurements change nothing.
    pub fn observe(&mut self, frame_time_s: f32, triangles: u64) {
        if !(frame_time_s.is_finite() && frame_time_s > 0.0) || triangles == 0 {
            return;
        }
        let measured = ((frame_time_s - self.fixed_s).max(0.0) / triangles as f32).max(1e-15);
        let a = self.learning_rate.clamp(1e-3, 1.0);
        self.per_triangle_s += a * (measured - self.per_triangle_s);
    }

    /// The most triangles that fit in `target_frame_s` seconds: 0 when the
    /// target leaves no time after `fixed_s` (or is NaN), at most
    /// [`MAX_TRIANGLE_BUDGET`] (a target of `+inf` included). Never
    /// decreases as the target grows.
    pub fn triangle_budget(&self, target_frame_s: f32) -> u64 {
        let spare = f64::from(target_frame_s) - f64::from(self.fixed_s);
        if spare.is_nan() || spare <= 0.0 {
            return 0;
        }
        let per_triangle = f64::from(self.per_triangle_s.max(1e-15));
        let budget = spare / per_triangle;
        if budget >= MAX_TRIANGLE_BUDGET as f64 {
            MAX_TRIANGLE_BUDGET
        } else {
            budget as u64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_model_learns_the_per_triangle_cost() {
        let mut m = CostModel::new(0.002, 1e-6);
        for _ in 0..200 {
            // The true cost: 2 ms + 10 ns per triangle.
            m.observe(0.002 + 1e-8 * 500_000.0, 500_000);
        }
        assert!((m.per_triangle_s / 1e-8 - 1.0).abs() < 1e-3, "{m:?}");
        let budget = m.triangle_budget(1.0 / 90.0);
        assert!((budget as f64 / 911_111.0 - 1.0).abs() < 1e-2, "{budget}");
        m.observe(f32::NAN, 10);
        m.observe(0.01, 0);
        assert!((m.per_triangle_s / 1e-8 - 1.0).abs() < 1e-3);
        assert_eq!(m.triangle_budget(0.001), 0);
    }

    #[test]
    fn an_unbounded_target_gets_the_largest_budget_not_zero() {
        let m = CostModel::new(0.002, 1e-8);
        // 1 / 1e-40 Hz overflows f32 to +inf; it used to give a budget of 0.
        let inf = 1.0 / 1e-40_f32;
        assert_eq!(m.triangle_budget(inf), MAX_TRIANGLE_BUDGET);
        assert_eq!(m.triangle_budget(f32::MAX), MAX_TRIANGLE_BUDGET);
        assert_eq!(m.triangle_budget(f32::NAN), 0);
        let mut last = 0;
        for t in [0.0, 0.003, 0.1, 1.0, 1e6, 1e30, f32::MAX, f32::INFINITY] {
            let b = m.triangle_budget(t);
            assert!(b >= last, "{t} s: {b} < {last}");
            last = b;
        }
    }

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
