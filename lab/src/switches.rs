//! LOD switches between frames (popping) and the reversals among them
//! (flicker).
//!
//! A switch is an instance drawn in two consecutive frames at different
//! LODs. A reversal is a switch that takes an instance back to the LOD it
//! left at its previous switch, at most [`REVERSAL_WINDOW_S`] later: the
//! back-and-forth that reads as flicker, where a monotone crossing (an
//! object receding through its LODs, or a head sweep passing over it once)
//! reads as one pop.
//!
//! Slow reversals, within [`SLOW_REVERSAL_WINDOW_S`], are counted beside:
//! a controller that holds each switch for a dwell time longer than the
//! quarter second (the lab's scheduled policies hold for 0.3 s) can only
//! flicker more slowly, and the quarter-second count alone would not see
//! it. A head sweep that passes an object and comes back within a second
//! counts there too, so they are read against another policy's under the
//! same camera.

/// Longest time between two switches that undo each other for the second
/// to count as a reversal, seconds: a quarter second, shorter than a head
/// sweep's half period, so a sweep that passes an object and comes back is
/// two crossings, not flicker.
pub const REVERSAL_WINDOW_S: f64 = 0.25;

/// Longest time between two switches that undo each other for the second
/// to count as a slow reversal, seconds.
pub const SLOW_REVERSAL_WINDOW_S: f64 = 1.0;

/// One frame's count.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SwitchCount {
    /// Instances drawn this frame and the frame before at different LODs.
    pub switches: u32,
    /// Of which reversals (see the module documentation).
    pub reversals: u32,
    /// Of the switches, those back to the LOD left at the instance's
    /// previous switch within [`SLOW_REVERSAL_WINDOW_S`] (the reversals
    /// included).
    pub slow_reversals: u32,
}

/// Counts switches and reversals over a sequence of frames of one policy.
#[derive(Debug, Clone, Default)]
pub struct SwitchTracker {
    /// The frame before's choices (`None`: culled).
    before: Vec<Option<usize>>,
    /// Per instance: the time of its last switch, s, and the LOD it left.
    last_switch: Vec<Option<(f64, usize)>>,
}

impl SwitchTracker {
    /// Counts the frame at time `t_s` (seconds, non-decreasing over calls)
    /// whose choices are `now` (one per instance; `None`: culled) against
    /// the frame before, and remembers it. The first frame counts nothing.
    pub fn observe(&mut self, t_s: f64, now: &[Option<usize>]) -> SwitchCount {
        self.last_switch.resize(now.len(), None);
        let mut count = SwitchCount::default();
        for ((&before, &now), last) in self.before.iter().zip(now).zip(&mut self.last_switch) {
            let (Some(from), Some(to)) = (before, now) else {
                continue;
            };
            if from == to {
                continue;
            }
            count.switches += 1;
            if let Some((t_last, left)) = *last
                && left == to
            {
                let since_s = t_s - t_last;
                count.reversals += u32::from(since_s <= REVERSAL_WINDOW_S);
                count.slow_reversals += u32::from(since_s <= SLOW_REVERSAL_WINDOW_S);
            }
            *last = Some((t_s, from));
        }
        self.before.clear();
        self.before.extend_from_slice(now);
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(frames: &[&[Option<usize>]], dt_s: f64) -> Vec<SwitchCount> {
        let mut tracker = SwitchTracker::default();
        frames
            .iter()
            .enumerate()
            .map(|(k, f)| tracker.observe(k as f64 * dt_s, f))
            .collect()
    }

    #[test]
    fn a_monotone_crossing_is_switches_without_reversals() {
        let c = counts(&[&[Some(0)], &[Some(1)], &[Some(1)], &[Some(2)]], 0.01);
        let switches: u32 = c.iter().map(|c| c.switches).sum();
        let reversals: u32 = c.iter().map(|c| c.reversals).sum();
        assert_eq!((switches, reversals), (2, 0));
    }

    #[test]
    fn back_and_forth_within_the_window_is_a_reversal_and_later_is_not() {
        let flicker = counts(&[&[Some(0)], &[Some(1)], &[Some(0)], &[Some(1)]], 0.01);
        assert_eq!(flicker.iter().map(|c| c.reversals).sum::<u32>(), 2);
        // The same switches 0.3 s apart: two crossings.
        let slow = counts(&[&[Some(0)], &[Some(1)], &[Some(0)]], 0.3);
        assert_eq!(slow.iter().map(|c| c.switches).sum::<u32>(), 2);
        assert_eq!(slow.iter().map(|c| c.reversals).sum::<u32>(), 0);
        // ... but a slow reversal, as the quick ones are.
        assert_eq!(slow.iter().map(|c| c.slow_reversals).sum::<u32>(), 1);
        assert_eq!(flicker.iter().map(|c| c.slow_reversals).sum::<u32>(), 2);
        // Over a second apart: neither.
        let crossings = counts(&[&[Some(0)], &[Some(1)], &[Some(0)]], 1.1);
        assert_eq!(crossings.iter().map(|c| c.slow_reversals).sum::<u32>(), 0);
    }

    #[test]
    fn culled_frames_and_other_instances_do_not_count() {
        let c = counts(
            &[
                &[Some(0), Some(3)],
                &[None, Some(2)],
                &[Some(1), Some(1)],
                &[Some(1), Some(2)],
            ],
            0.01,
        );
        // Instance 0 reappears at another LOD: no switch. Instance 1 goes
        // 3 -> 2 -> 1 -> 2: the last undoes the one before it.
        assert_eq!(
            c,
            vec![
                SwitchCount::default(),
                SwitchCount {
                    switches: 1,
                    reversals: 0,
                    slow_reversals: 0
                },
                SwitchCount {
                    switches: 1,
                    reversals: 0,
                    slow_reversals: 0
                },
                SwitchCount {
                    switches: 1,
                    reversals: 1,
                    slow_reversals: 1
                },
            ]
        );
    }
}
