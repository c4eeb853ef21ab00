//! The viewer's clock over the scene's camera path: real time, looping
//! over the path's duration, paused and stepped frame by frame on request.

/// Most simulated time one frame advances, seconds: after a stall (the
/// window dragged, a slow first frame) the path goes on from where it was
/// rather than skipping ahead.
pub const MAX_ADVANCE_S: f64 = 0.25;

/// Where the viewer is on the camera path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopClock {
    duration_s: f64,
    step_s: f64,
    t_s: f64,
    paused: bool,
}

/// One frame's time on the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// Time on the path, seconds, in `[0, duration)`.
    pub t_s: f64,
    /// Time since the frame before on the path, seconds, for the selector's
    /// velocities; 0 when the path did not move on continuously (paused,
    /// stepped back, looped to the start).
    pub dt_s: f64,
}

impl LoopClock {
    /// A clock at the start of a path `duration_s` seconds long (> 0),
    /// stepping `step_s` seconds (> 0) a frame when paused.
    pub fn new(duration_s: f64, step_s: f64) -> LoopClock {
        let positive = |v: f64, or: f64| if v.is_finite() && v > 0.0 { v } else { or };
        LoopClock {
            duration_s: positive(duration_s, 1.0),
            step_s: positive(step_s, 1.0 / 60.0),
            t_s: 0.0,
            paused: false,
        }
    }

    /// Whether the clock is paused.
    pub fn paused(&self) -> bool {
        self.paused
    }

    /// Pauses or resumes.
    pub fn toggle_pause(&mut self) {
        self.paused = !self.paused;
    }

    /// Moves on by `wall_dt_s` seconds of real time (at most
    /// [`MAX_ADVANCE_S`]; none while paused), wrapping at the end.
    pub fn advance(&mut self, wall_dt_s: f64) -> Tick {
        if self.paused || wall_dt_s.is_nan() || wall_dt_s <= 0.0 {
            return self.hold();
        }
        self.move_by(wall_dt_s.min(MAX_ADVANCE_S))
    }

    /// Steps `frames` frames on (negative: back), wrapping at either end.
    pub fn step(&mut self, frames: i32) -> Tick {
        let tick = self.move_by(f64::from(frames) * self.step_s);
        if frames < 0 {
            Tick { dt_s: 0.0, ..tick }
        } else {
            tick
        }
    }

    /// The current time, not moving.
    pub fn hold(&self) -> Tick {
        Tick {
            t_s: self.t_s,
            dt_s: 0.0,
        }
    }

    fn move_by(&mut self, dt_s: f64) -> Tick {
        let unwrapped = self.t_s + dt_s;
        self.t_s = unwrapped.rem_euclid(self.duration_s);
        // rem_euclid may round up to the duration itself.
        if self.t_s >= self.duration_s {
            self.t_s = 0.0;
        }
        let looped = unwrapped != self.t_s;
        Tick {
            t_s: self.t_s,
            dt_s: if looped { 0.0 } else { dt_s },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_time_advances_and_loops_with_no_velocity_jump() {
        let mut c = LoopClock::new(5.0, 1.0 / 30.0);
        let t = c.advance(0.1);
        assert_eq!(
            t,
            Tick {
                t_s: 0.1,
                dt_s: 0.1
            }
        );
        for _ in 0..48 {
            c.advance(0.1);
        }
        assert!((c.hold().t_s - 4.9).abs() < 1e-9);
        let t = c.advance(0.2);
        assert!((t.t_s - 0.1).abs() < 1e-9, "{t:?}");
        assert_eq!(t.dt_s, 0.0, "the jump back to the start is not motion");
    }

    #[test]
    fn stalls_advance_at_most_the_cap_and_pauses_not_at_all() {
        let mut c = LoopClock::new(5.0, 0.1);
        assert_eq!(c.advance(3.0).t_s, MAX_ADVANCE_S);
        c.toggle_pause();
        assert!(c.paused());
        assert_eq!(
            c.advance(0.1),
            Tick {
                t_s: MAX_ADVANCE_S,
                dt_s: 0.0
            }
        );
        c.toggle_pause();
        assert_eq!(c.advance(f64::NAN).dt_s, 0.0);
        assert_eq!(c.advance(-1.0).t_s, MAX_ADVANCE_S);
    }

    #[test]
    fn steps_move_a_frame_either_way_and_wrap() {
        let mut c = LoopClock::new(1.0, 0.25);
        let t = c.step(1);
        assert_eq!(
            t,
            Tick {
                t_s: 0.25,
                dt_s: 0.25
            }
        );
        assert_eq!(
            c.step(-1),
            Tick {
                t_s: 0.0,
                dt_s: 0.0
            }
        );
        assert_eq!(c.step(-1).t_s, 0.75);
        assert_eq!(c.step(1).t_s, 0.0);
    }

    #[test]
    fn a_bad_duration_or_step_falls_back_to_a_positive_one() {
        let mut c = LoopClock::new(0.0, f64::NAN);
        assert!(c.step(1).t_s > 0.0);
        assert!(c.advance(0.5).t_s < 1.0);
    }
}
