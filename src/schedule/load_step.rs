//! Telling a step of load from jitter: a change of the frame time that
//! the frame's own change of cost does not explain, against each of the
//! last two frames.
//!
//! A load that lasts (a spike of many frames, another task's work) shows
//! as a step of the frame time. Both schedulers keep the knob they had
//! when it came and return to it when the frame time steps down again,
//! instead of climbing back by their raise rules. Judged against the last
//! frame alone, one jittered frame within the load followed by an ordinary
//! one looked like the load's end: the knob went back up in the middle of
//! the load, and the late frames that followed drove it far lower than the
//! load needed. A step is a step from a level, so a fall must hold
//! against both of the last two frames. A rise must be a step from one of
//! them and half a step from the other: a load whose first frame follows
//! a frame heavier by jitter rises by less than a step from that frame.

use super::VARIATION_CLIP;

/// A frame whose time rose by more than this, in log terms, from one of
/// the last two frames and by half as much from the other, beyond what its
/// change of cost explains, shows a new load; a fall by as much below each
/// shows it gone. The largest change of frame time the learned variation
/// takes for jitter ([`VARIATION_CLIP`]).
pub(super) const LOAD_STEP: f32 = VARIATION_CLIP;

/// The largest exponent of `s` a frame's cost is taken to follow when a
/// step of the frame time is told apart from a change of load
/// ([`LOAD_STEP`]): quadratic, as for the reactive gain.
pub(super) const SCALE_COST_EXPONENT: f32 = 2.0;

/// How long a scheduler keeps what it had before a load, s of frames: a
/// stall of a second or two (a shader compiled, a chunk streamed in) is
/// remembered through; after a longer load the raise rules climb back,
/// since a knob from longer ago says little about what the view now costs.
pub(super) const LOAD_MEMORY_S: f32 = 4.0;

/// What a scheduler had before a load that lasts (its knob, `K`) and the
/// time the load added (s), while the frames show the load.
#[derive(Clone, Copy, Debug)]
pub(super) struct LoadMemory<K> {
    pub before: K,
    pub added_s: f32,
    /// The frame time before the load, s.
    level_s: f32,
    /// Frame time since the load came, s.
    age_s: f32,
}

impl<K> LoadMemory<K> {
    /// A load that added `added_s` (s) came with a frame of
    /// `frame_time_s` (s); the scheduler had `before`.
    fn new(before: K, frame_time_s: f32, added_s: f32) -> Self {
        Self {
            before,
            added_s,
            level_s: frame_time_s - added_s,
            age_s: 0.0,
        }
    }

    /// One more frame of `frame_time_s` (s): whether the memory stays. It
    /// goes once older than [`LOAD_MEMORY_S`], and on the frame after the
    /// load's first if that frame does not show the load: a step of load
    /// lasts, so the next frame, though drawn with the knob the first one
    /// lowered, still lies above what the frames before it took by half
    /// a step ([`LOAD_STEP`]); one frame of jitter does not.
    /// `expected_s` is that frame's time as the frames before the load
    /// would have had it (s): the level before the load, or less where the
    /// scheduler knows what its knob's change saves.
    /// That frame also gives the load's size, if smaller than its first
    /// frame's: the first may have been heavier by jitter, and a load
    /// taken for larger than it is would not be seen to end.
    fn kept(&mut self, frame_time_s: f32, expected_s: impl FnOnce(&Self) -> f32) -> bool {
        let first = self.age_s == 0.0;
        self.age_s += frame_time_s;
        if first {
            let expected_s = expected_s(self);
            if frame_time_s <= expected_s * (0.5 * LOAD_STEP).exp() {
                return false;
            }
            self.added_s = self.added_s.min(frame_time_s - expected_s);
        }
        self.age_s <= LOAD_MEMORY_S
    }

    /// The frame time before the load, s.
    pub fn level_s(&self) -> f32 {
        self.level_s
    }

    /// The memory a scheduler keeps (`slot`) through one more frame of
    /// `frame_time_s` (s) and its `step`: a memory from before is kept or
    /// dropped ([`Self::kept`], with `expected_s`); where none is left and
    /// the frame, over the period (`over`), rose by a step of load, the
    /// scheduler's knob (`knob`; none, nothing to remember) is remembered.
    /// Returns whether the frame ends the load remembered
    /// ([`LoadStep::ends_load`]).
    pub fn follow(
        slot: &mut Option<Self>,
        frame_time_s: f32,
        over: bool,
        step: &LoadStep,
        expected_s: impl FnOnce(&Self) -> f32,
        knob: impl FnOnce() -> Option<K>,
    ) -> bool {
        if slot
            .as_mut()
            .is_some_and(|m| !m.kept(frame_time_s, expected_s))
        {
            *slot = None;
        }
        if slot.is_none()
            && over
            && let Some((before, added_s)) = step.rose_s.and_then(|r| knob().map(|k| (k, r)))
        {
            *slot = Some(Self::new(before, frame_time_s, added_s));
        }
        slot.as_ref().is_some_and(|m| step.ends_load(m.added_s))
    }
}

/// The last two frames, to judge the next one's step of frame time by.
#[derive(Clone, Copy, Debug)]
pub(super) struct LoadSteps {
    /// Each frame's log cost (the log of what its cost is at most
    /// proportional to) and its time, s; most recent first, NaN before a
    /// frame.
    last: [(f32, f32); 2],
}

/// A frame's step of load against the last two frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct LoadStep {
    /// The frame rose by a step of load (a step from one of the two
    /// frames, half a step from the other): its rise from the lower of
    /// them, the level before the load, s.
    pub rose_s: Option<f32>,
    /// The frame rose by a step from each of the two frames: clear news of
    /// more load, which may be learned at once.
    pub rose_from_both: bool,
    /// The frame fell by a step of load: the smaller of its falls below
    /// the two frames, s.
    pub fell_s: Option<f32>,
}

impl LoadStep {
    /// Whether this frame ends a load that added `added_s` (s): a fall by
    /// a step of load, and by at least half the time the load added.
    pub fn ends_load(&self, added_s: f32) -> bool {
        self.fell_s.is_some_and(|fell_s| fell_s >= 0.5 * added_s)
    }
}

impl LoadSteps {
    /// No frame seen yet: no step until two frames have been.
    pub const fn new() -> Self {
        Self {
            last: [(f32::NAN, f32::NAN); 2],
        }
    }

    /// Judges a frame of `frame_time_s` (s, finite and > 0) whose cost is
    /// at most proportional to `exp(log_cost)` (for the reactive
    /// scheduler `s^2`, [`SCALE_COST_EXPONENT`]; for the predictive one
    /// the triangles drawn), and remembers it. A log cost that is not
    /// finite (no triangles) judges no step.
    pub fn see(&mut self, log_cost: f32, frame_time_s: f32) -> LoadStep {
        let mut step = LoadStep {
            rose_s: Some(f32::NEG_INFINITY),
            rose_from_both: true,
            fell_s: Some(f32::INFINITY),
        };
        // The rise beyond what the cost explains, the larger over the two
        // frames, in log terms.
        let mut most_rise = f32::NEG_INFINITY;
        for (last_log_cost, last_s) in self.last {
            let by_cost = log_cost - last_log_cost;
            let log_step = (frame_time_s / last_s).ln();
            if !(by_cost.is_finite() && log_step.is_finite()) {
                return self.remember(log_cost, frame_time_s, LoadStep::default());
            }
            let rise = log_step - by_cost.max(0.0);
            most_rise = most_rise.max(rise);
            step.rose_from_both &= rise > LOAD_STEP;
            step.rose_s = step
                .rose_s
                .filter(|_| rise > 0.5 * LOAD_STEP)
                .map(|r| r.max(frame_time_s - last_s));
            step.fell_s = step
                .fell_s
                .filter(|_| log_step < -LOAD_STEP + by_cost.min(0.0))
                .map(|f| f.min(last_s - frame_time_s));
        }
        // A load whose first frame follows one heavier by jitter rises by a
        // step from the other frame and by half a step from that one.
        if most_rise <= LOAD_STEP {
            step.rose_s = None;
        }
        step.rose_from_both &= step.rose_s.is_some();
        self.remember(log_cost, frame_time_s, step)
    }

    fn remember(&mut self, log_cost: f32, frame_time_s: f32, step: LoadStep) -> LoadStep {
        self.last = [(log_cost, frame_time_s), self.last[0]];
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(times_s: &[f32]) -> Vec<LoadStep> {
        let mut steps = LoadSteps::new();
        times_s.iter().map(|&t| steps.see(0.0, t)).collect()
    }

    #[test]
    fn a_step_against_both_of_the_last_two_frames_is_a_load() {
        let steps = frames(&[0.05, 0.05, 0.09, 0.09, 0.05]);
        assert_eq!(steps[2].rose_s.map(|r| (r * 1e3).round()), Some(40.0));
        assert_eq!(steps[4].fell_s.map(|f| (f * 1e3).round()), Some(40.0));
        assert!(steps[3].rose_s.is_none() && steps[3].fell_s.is_none());
    }

    #[test]
    fn a_load_after_a_frame_heavier_by_jitter_is_a_load() {
        // 50 ms, 56 ms (jitter), then 70 ms: a step from 50 ms, half a
        // step from 56 ms.
        let steps = frames(&[0.05, 0.056, 0.07]);
        assert_eq!(steps[2].rose_s.map(|r| (r * 1e3).round()), Some(20.0));
        // Half a step from each is no load.
        assert!(frames(&[0.05, 0.05, 0.058])[2].rose_s.is_none());
        // Nor a step from a frame lighter by jitter alone.
        assert!(frames(&[0.05, 0.04, 0.052])[2].rose_s.is_none());
    }

    #[test]
    fn one_jittered_frame_within_a_load_does_not_end_it() {
        // Loaded frames of 57 ms, one of 79 ms, then 58 ms again: the fall
        // from 79 ms is no fall from the level before it.
        let steps = frames(&[0.057, 0.057, 0.079, 0.058]);
        assert!(steps[3].fell_s.is_none());
    }

    #[test]
    fn a_step_the_cost_explains_is_no_load() {
        let mut steps = LoadSteps::new();
        steps.see(0.0, 0.05);
        steps.see(0.0, 0.05);
        // Twice the cost, 1.8 times the time.
        assert_eq!(steps.see(2f32.ln(), 0.09), LoadStep::default());
    }

    #[test]
    fn a_memory_of_a_load_is_kept_for_its_time_only() {
        // A load of 20 ms on frames of 30 ms, lasting.
        let mut memory = LoadMemory::new(0.5f32, 0.05, 0.02);
        let kept = (0..1000)
            .take_while(|_| memory.kept(0.05, LoadMemory::level_s))
            .count();
        assert!((79..=80).contains(&kept), "{kept} frames");
    }

    #[test]
    fn a_memory_goes_when_the_next_frame_does_not_show_the_load() {
        // One frame 40% over frames of 30 ms, then 31 ms: jitter.
        let mut memory = LoadMemory::new(0.5f32, 0.042, 0.012);
        assert!(!memory.kept(0.031, LoadMemory::level_s));
        // The load stays, the knob lowered: 36 ms, above 30 ms by more
        // than half a step.
        let mut memory = LoadMemory::new(0.5f32, 0.042, 0.012);
        assert!(memory.kept(0.036, LoadMemory::level_s));
        // The load's size, from that frame: 6 ms, not the first's 12 ms.
        assert!((memory.added_s - 0.006).abs() < 1e-6, "{}", memory.added_s);
        // Where the knob's change is known to save a third, 30 ms shows
        // the load.
        let mut memory = LoadMemory::new(0.5f32, 0.042, 0.012);
        assert!(memory.kept(0.030, |m| m.level_s() / 1.5));
    }

    #[test]
    fn before_two_frames_and_without_a_cost_there_is_no_step() {
        let steps = frames(&[0.01, 0.05]);
        assert_eq!(steps[1], LoadStep::default());
        let mut steps = LoadSteps::new();
        steps.see(f32::NEG_INFINITY, 0.01);
        steps.see(f32::NEG_INFINITY, 0.01);
        assert_eq!(steps.see(f32::NEG_INFINITY, 0.05), LoadStep::default());
    }
}
