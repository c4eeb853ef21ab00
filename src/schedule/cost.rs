//! The frame-cost model both schedulers read: a line through measured
//! frames, `frame_s = fixed_s + per_triangle_s * triangles`, that turns a
//! frame-time aim into a triangle budget and predicts the cost floor.

use super::{MAX_TRIANGLE_BUDGET, finite_or};

/// Slopes between frames the cost model needs before it predicts a floor.
pub const FLOOR_SLOPES: u32 = 3;
/// Weight of a slope between two frames in the cost model's local
/// per-triangle cost.
const LOCAL_SLOPE_RATE: f32 = 0.2;
/// A frame whose per-triangle cost is below this fraction of the learned
/// one shows a load gone ([`CostModel::observe`]): three standard
/// deviations of a 10% frame-to-frame noise.
const FORGET_BELOW: f32 = 0.7;
/// Weight of such a frame in the learned per-triangle cost.
const FORGET_RATE: f32 = 0.5;

/// A linear frame-cost model, `frame_s = fixed_s + per_triangle_s *
/// triangles`, fitted online from measured frames, that turns a target
/// frame time into the triangle budget for
/// [`Selector::select_within_budget`](crate::Selector::select_within_budget),
/// and predicts the frame's cost floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    /// Time per frame that does not depend on triangles, s.
    pub fixed_s: f32,
    /// Time per triangle, s, as learned: a frame slower than predicted
    /// raises it (so a budget shrinks in proportion, which never
    /// overshoots); a frame far faster (a load gone) lowers it half-way.
    pub per_triangle_s: f32,
    /// Weight of a new observation in the running fit, `(0, 1]`.
    pub learning_rate: f32,
    /// The per-triangle cost given to [`new`](Self::new) (the calibrated
    /// one), s.
    calibrated_per_triangle_s: f32,
    /// The per-triangle cost where the frames are, s ([`Self::floor_s`]).
    local_per_triangle_s: f32,
    /// Time beyond `fixed_s` the last frames took that the local
    /// per-triangle cost does not explain, s: extra load (half of it moves
    /// each frame; a load of half the frame or more at once).
    extra_load_s: f32,
    /// The same, of either sign (below 0 where `fixed_s` is too high), for
    /// the floor: the last frames' time less their triangles at the local
    /// cost, whatever the fixed time given.
    floor_load_s: f32,
    /// The last frame measured: time, s, and triangles.
    last_frame: (f32, u64),
    /// Slopes measured into `local_per_triangle_s`.
    slopes: u32,
    /// Whether `calibrated_per_triangle_s` is a guess ([`Self::from_guess`]).
    guessed: bool,
}

impl CostModel {
    /// A model with an initial guess (or a calibration).
    pub fn new(fixed_s: f32, per_triangle_s: f32) -> Self {
        let per_triangle_s = finite_or(per_triangle_s, 1e-8).max(1e-15);
        Self {
            fixed_s: finite_or(fixed_s, 0.0).max(0.0),
            per_triangle_s,
            learning_rate: 0.1,
            calibrated_per_triangle_s: per_triangle_s,
            local_per_triangle_s: per_triangle_s,
            extra_load_s: 0.0,
            floor_load_s: 0.0,
            last_frame: (0.0, 0),
            slopes: 0,
            guessed: false,
        }
    }

    /// A model from a first guess, not a calibration (an engine that has
    /// measured nothing yet): as [`new`](Self::new), but the slopes the
    /// local cost follows are bounded by the learned per-triangle cost as
    /// well as the guess, so that frames whose triangles cost far less (a
    /// GPU: a nanosecond or less) or far more (a software rasteriser:
    /// hundreds) than the guess still give the floor.
    pub fn from_guess(fixed_s: f32, per_triangle_s: f32) -> Self {
        Self {
            guessed: true,
            ..Self::new(fixed_s, per_triangle_s)
        }
    }

    /// The first guess of an engine that has measured nothing yet (the C
    /// interface's and the Bevy plugin's schedulers): 1 ms of fixed time
    /// and 20 ns per triangle, as [`from_guess`](Self::from_guess), which
    /// the measured frames correct.
    pub fn first_guess() -> Self {
        Self::from_guess(1e-3, 20e-9)
    }

    /// Updates the per-triangle cost and the extra load from a measured
    /// frame (time in s and the triangles it drew). Invalid measurements
    /// change nothing.
    pub fn observe(&mut self, frame_time_s: f32, triangles: u64) {
        self.observe_frame(frame_time_s, triangles, true);
    }

    /// As [`observe`](Self::observe); with `per_triangle` false the frame
    /// leaves the learned per-triangle cost as it is (a frame whose
    /// triangles say little of it) and teaches the rest.
    pub(super) fn observe_frame(&mut self, frame_time_s: f32, triangles: u64, per_triangle: bool) {
        if !(frame_time_s.is_finite() && frame_time_s > 0.0) {
            return;
        }
        let a = self.learning_rate.clamp(1e-3, 1.0);
        let (t0, n0) = self.last_frame;
        let (n0, n1) = (n0 as f32, triangles as f32);
        if n0 > 0.0 && (n1 - n0).abs() > 0.1 * n1.max(n0) {
            let slope = (frame_time_s - t0) / (n1 - n0);
            let cal = self.calibrated_per_triangle_s;
            let (low, high) = if self.guessed {
                let learned = self.per_triangle_s;
                (cal.min(learned), cal.max(learned))
            } else {
                (cal, cal)
            };
            if slope.is_finite() {
                let slope = slope.clamp(0.25 * low, 4.0 * high);
                self.local_per_triangle_s += LOCAL_SLOPE_RATE * (slope - self.local_per_triangle_s);
                self.slopes = self.slopes.saturating_add(1);
            }
        }
        // Finite however large the local cost has grown (a frame of 1e38 s).
        let signed = (frame_time_s - self.fixed_s - self.local_per_triangle_s * n1).max(-f32::MAX);
        // A load of half the frame or more shows at once (a spike's first
        // frame already counts); otherwise the load moves half-way.
        let unexplained = signed.max(0.0);
        let at_once = unexplained > 0.5 * frame_time_s;
        self.extra_load_s = if at_once {
            unexplained
        } else {
            0.5 * self.extra_load_s + 0.5 * unexplained
        };
        self.floor_load_s = if at_once {
            signed
        } else {
            0.5 * self.floor_load_s + 0.5 * signed
        };
        self.last_frame = (frame_time_s, triangles);
        if triangles == 0 || !per_triangle {
            return;
        }
        let measured = ((frame_time_s - self.fixed_s).max(0.0) / triangles as f32).max(1e-15);
        // A frame far cheaper than the learned cost says (beyond any
        // frame-to-frame noise) means a load has gone, a spike's included:
        // half of the gap goes at once, so the budget does not stay
        // starved for the seconds the running fit would take.
        let rate = if measured < FORGET_BELOW * self.per_triangle_s {
            a.max(FORGET_RATE)
        } else {
            a
        };
        self.per_triangle_s += rate * (measured - self.per_triangle_s);
    }

    /// The most triangles that fit `target_frame_s` (s) at the cost per
    /// triangle one frame shows: its time (`frame_time_s`, s) less the
    /// fixed time, over its `triangles`. A direct reading of what the view
    /// costs now, for a budget taken from before the view changed. 0 where
    /// the target leaves no time after the fixed time, at most
    /// [`MAX_TRIANGLE_BUDGET`] (a frame no longer than the fixed time, or
    /// of no triangles, reads as free).
    pub(super) fn budget_by_frame(
        &self,
        target_frame_s: f32,
        frame_time_s: f32,
        triangles: u64,
    ) -> u64 {
        let spare = f64::from(target_frame_s) - f64::from(self.fixed_s);
        let spent = f64::from(frame_time_s) - f64::from(self.fixed_s);
        if spare.is_nan() || spare <= 0.0 {
            return 0;
        }
        if triangles == 0 || spent.is_nan() || spent <= 0.0 {
            return MAX_TRIANGLE_BUDGET;
        }
        capped_budget(spare / spent * triangles as f64)
    }

    /// The per-triangle cost where the frames are, s ([`Self::floor_s`]),
    /// once measured; `None` before [`FLOOR_SLOPES`] slopes.
    pub(super) fn local_per_triangle_s(&self) -> Option<f32> {
        (self.slopes >= FLOOR_SLOPES).then_some(self.local_per_triangle_s)
    }

    /// The time of a frame of `triangles` by the learned per-triangle cost
    /// (the proportional reading), s.
    pub(super) fn frame_s(&self, triangles: u64) -> f32 {
        self.fixed_s + self.per_triangle_s * triangles as f32
    }

    /// The predicted time of a frame at every visible object's coarsest
    /// LOD, s, under the load of the last frames: no choice of LOD makes a
    /// frame faster. It is the last frames' time less what their triangles
    /// beyond `coarsest_triangles` cost at the local per-triangle cost (a
    /// change of load taken as additive: other work in the frame). The
    /// local cost starts at the calibrated one and follows the slope
    /// between consecutive frames whose triangles differ by more than 10%
    /// (within a quarter and four times the calibrated cost; from a guess,
    /// of the lower and the higher of the guess and the learned cost), so
    /// that a frame cost that is not linear in the triangles is read where
    /// the frames are.
    /// `None` until that slope has been measured [`FLOOR_SLOPES`] times:
    /// a calibration is not trusted to call a target out of reach.
    /// Finite, from 0 to `f32::MAX`: frames of finite times give a finite
    /// floor even where their per-triangle cost times the triangles
    /// overflows.
    pub fn floor_s(&self, coarsest_triangles: u64) -> Option<f32> {
        (self.slopes >= FLOOR_SLOPES).then(|| {
            let floor_s = f64::from(self.fixed_s)
                + f64::from(self.floor_load_s)
                + f64::from(self.local_per_triangle_s) * coarsest_triangles as f64;
            floor_s.clamp(0.0, f64::from(f32::MAX)) as f32
        })
    }

    /// The most triangles that fit in `target_frame_s` seconds, by the
    /// lower of two readings of the frames: the learned per-triangle cost
    /// (a change of load proportional to the triangles) and, once its local
    /// cost is measured ([`Self::floor_s`]), the extra load kept and the
    /// local per-triangle cost (a change of load that is additive); so a
    /// load of either kind is met within a frame or two. 0 when the
    /// target leaves no time after `fixed_s` (or is NaN), at most
    /// [`MAX_TRIANGLE_BUDGET`] (a target of `+inf` included). Never
    /// decreases as the target grows.
    pub fn triangle_budget(&self, target_frame_s: f32) -> u64 {
        let spare = f64::from(target_frame_s) - f64::from(self.fixed_s);
        if spare.is_nan() || spare <= 0.0 {
            return 0;
        }
        let per_triangle = f64::from(self.per_triangle_s.max(1e-15));
        let mut budget = spare / per_triangle;
        if self.slopes >= FLOOR_SLOPES {
            // The additive reading: the extra load stays, the rest costs the
            // local per-triangle cost.
            let local = f64::from(self.local_per_triangle_s.max(1e-15));
            budget = budget.min((spare - f64::from(self.extra_load_s)).max(0.0) / local);
        }
        capped_budget(budget)
    }
}

/// A budget of `triangles` (not NaN, `>= 0`), at most
/// [`MAX_TRIANGLE_BUDGET`] (`+inf` included).
fn capped_budget(triangles: f64) -> u64 {
    if triangles >= MAX_TRIANGLE_BUDGET as f64 {
        MAX_TRIANGLE_BUDGET
    } else {
        triangles as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_comes_back_within_a_few_frames_of_a_spike_ending() {
        // 10,000 triangles at 1 us each, then 10 frames with 20 ms more
        // (a spike the running fit reads as per-triangle cost), then the
        // frames of before again. With the fit alone the budget five
        // frames later was 59% of the budget before; it must be 75%.
        let mut m = CostModel::new(0.0, 1e-6);
        let steady = |m: &mut CostModel, k: u64, extra_s: f32| {
            let n = if k.is_multiple_of(2) { 10_000 } else { 12_000 };
            m.observe(1e-6 * n as f32 + extra_s, n);
        };
        for k in 0..60 {
            steady(&mut m, k, 0.0);
        }
        let before = m.triangle_budget(15e-3);
        for k in 0..10 {
            steady(&mut m, k, 20e-3);
        }
        for k in 0..5 {
            steady(&mut m, k, 0.0);
        }
        let after = m.triangle_budget(15e-3);
        assert!(
            after as f64 >= 0.75 * before as f64,
            "{after} triangles five frames after the spike, {before} before"
        );
    }

    #[test]
    fn a_guess_far_from_the_frames_never_puts_the_floor_above_them() {
        // A GPU at 3 ms plus 0.5 ns per triangle, from the guess of 1 ms
        // plus 20 ns (the engine interfaces' first guess): the slopes lie
        // below a quarter of the guess and are read as 5 ns. With the load
        // kept at 0 or more the floor came out at 6 ms, above the 5 ms
        // frames themselves: a 200 Hz target called out of reach.
        let mut m = CostModel::new(1e-3, 20e-9);
        for k in 0..200u64 {
            let n = if k % 2 == 0 { 4_000_000 } else { 6_000_000 };
            m.observe(3e-3 + 0.5e-9 * n as f32, n);
        }
        let floor = m.floor_s(1_000_000).unwrap();
        assert!((0.0..=3.5e-3).contains(&floor), "{floor} s, 3.5 ms true");
        // A calibrated fixed time too high (the lab's line through full
        // detail and its coarsest frames), the local cost right: the floor
        // is the frames' time less their triangles above the coarsest.
        let mut m = CostModel::new(37e-3, 0.28e-6);
        for k in 0..200u64 {
            let n = if k % 2 == 0 { 50_000 } else { 70_000 };
            m.observe(21e-3 + 0.42e-6 * n as f32, n);
        }
        let floor = m.floor_s(20_000).unwrap();
        let true_s = 21e-3 + 0.42e-6 * 20_000.0;
        assert!(
            (floor / true_s - 1.0).abs() < 0.05,
            "{floor} s, {true_s} true"
        );
    }

    #[test]
    fn from_a_guess_the_floor_of_a_gpu_and_of_a_software_rasteriser_is_learnt() {
        // The engine interfaces' guess, 1 ms and 20 ns a triangle: a GPU
        // at 3 ms plus 0.5 ns a triangle, and a software rasteriser at
        // 21 ms plus 0.42 us (`scenes/vr_sweep.toml` on llvmpipe).
        for (fixed_s, per_triangle_s, [n0, n1], coarsest) in [
            (3e-3, 0.5e-9, [4_000_000, 6_000_000], 1_000_000),
            (21e-3, 0.42e-6, [50_000, 70_000], 20_000),
        ] {
            let true_s = fixed_s + per_triangle_s * coarsest as f32;
            let mut guessed = CostModel::first_guess();
            let mut as_calibrated = CostModel::new(1e-3, 20e-9);
            for k in 0..300u64 {
                let n = if k % 2 == 0 { n0 } else { n1 };
                let t = fixed_s + per_triangle_s * n as f32;
                guessed.observe(t, n);
                as_calibrated.observe(t, n);
            }
            let floor = guessed.floor_s(coarsest).unwrap();
            assert!(
                (floor / true_s - 1.0).abs() < 0.1,
                "{floor} s, {true_s} true"
            );
            // The guess taken as a calibration bounds the slopes to 5-80 ns.
            let off = as_calibrated.floor_s(coarsest).unwrap();
            assert!((off / true_s - 1.0).abs() > 0.5, "{off} s, {true_s} true");
        }
    }

    #[test]
    fn a_frame_reads_the_budget_that_fits_at_its_cost_per_triangle() {
        let m = CostModel::new(2e-3, 1e-6);
        // 10,000 triangles in 12 ms: 1 us each beyond the fixed 2 ms.
        assert_eq!(m.budget_by_frame(7e-3, 12e-3, 10_000), 5_000);
        // No time after the fixed time: nothing fits.
        assert_eq!(m.budget_by_frame(1e-3, 12e-3, 10_000), 0);
        assert_eq!(m.budget_by_frame(f32::NAN, 12e-3, 10_000), 0);
        // A frame of no triangles, or no longer than the fixed time, says
        // nothing of their cost: no limit from it.
        for (frame_s, triangles) in [(12e-3, 0), (1e-3, 10_000), (f32::NAN, 10_000)] {
            assert_eq!(
                m.budget_by_frame(7e-3, frame_s, triangles),
                MAX_TRIANGLE_BUDGET
            );
        }
        assert_eq!(
            m.budget_by_frame(f32::INFINITY, 12e-3, 10_000),
            MAX_TRIANGLE_BUDGET
        );
    }

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
}
