//! The camera's path through a scene, evaluated at any time.
//!
//! # Conventions
//! World space is right-handed with **+Y up**, positions in metres. A camera
//! with identity orientation sits at its position looking along **-Z**, with
//! +X to its right and +Y up (the OpenGL / glam `look_to_rh` convention).
//! Camera space is the same frame attached to the camera.
//!
//! Orientations are given as yaw, pitch and roll in degrees and composed as
//! `R = Ry(yaw) * Rx(pitch) * Rz(roll)` (glam's `EulerRot::YXZ`):
//! - **yaw** turns about +Y; positive yaw turns the view to the **left**
//!   (from -Z towards -X), as seen from above.
//! - **pitch** turns about the camera's +X; positive pitch looks **up**.
//! - **roll** turns about the camera's +Z (its backward axis); positive roll
//!   leans the camera's +Y towards -X (the camera rolls counter-clockwise as
//!   its viewer sees it, so the world appears to turn clockwise).
//!
//! # Interpolation
//! Between keyframes the position is interpolated **linearly** and the
//! orientation by **slerp** (shortest arc), so consecutive keyframes should
//! turn by less than 180 deg. Before the first keyframe the path holds the
//! first; after the last it holds the last.
//!
//! A forward path moves at constant speed along the start heading (body
//! motion) while the head turns in a yaw sweep about that heading (see
//! [`YawSweep`]), as a VR user walking forward and looking around.

#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberate: it is also true for NaN"
)]

use glam::{DQuat, DVec3, EulerRot};

/// The orientation for yaw, pitch and roll in degrees (see the module docs
/// for the axes and order).
pub fn orientation_from_deg(yaw_deg: f64, pitch_deg: f64, roll_deg: f64) -> DQuat {
    DQuat::from_euler(
        EulerRot::YXZ,
        yaw_deg.to_radians(),
        pitch_deg.to_radians(),
        roll_deg.to_radians(),
    )
}

/// A camera keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Keyframe {
    /// Time of the keyframe, seconds from the start of the path.
    pub t_s: f64,
    /// Camera position in world space, metres.
    pub position_m: DVec3,
    /// Yaw, degrees (positive turns left).
    pub yaw_deg: f64,
    /// Pitch, degrees (positive looks up).
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
}

impl Keyframe {
    /// The keyframe's orientation.
    pub fn orientation(&self) -> DQuat {
        orientation_from_deg(self.yaw_deg, self.pitch_deg, self.roll_deg)
    }
}

/// The waveform of a yaw sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepShape {
    /// Triangle wave: the head turns at exactly the sweep rate and reverses
    /// instantly at ± amplitude (constant angular speed; the default).
    #[default]
    Triangle,
    /// Sine wave with the same period as the triangle wave; its peak angular
    /// speed is `pi / 2` times the sweep rate, its mean speed equals it.
    Sine,
}

/// A periodic head turn about the vertical axis, left and right of the start
/// heading: yaw goes 0 → +amplitude → 0 → -amplitude → 0.
///
/// The sweep rate may ramp linearly from `rate_deg_per_s` at t = 0 to
/// `rate_end_deg_per_s` at the end of the path, for experiments over a range
/// of head speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YawSweep {
    /// Largest yaw either side of the start heading, degrees (> 0).
    pub amplitude_deg: f64,
    /// Angular speed of the head at t = 0, deg/s (>= 0).
    pub rate_deg_per_s: f64,
    /// Angular speed at the end of the path, deg/s; equal to
    /// `rate_deg_per_s` for a constant rate.
    pub rate_end_deg_per_s: f64,
    /// Waveform.
    pub shape: SweepShape,
}

impl YawSweep {
    /// Yaw offset from the start heading at `t_s`, degrees, for a path of
    /// `duration_s`. The angle swept so far is the integral of the (linearly
    /// ramped) rate; the offset is that angle folded into the waveform.
    pub fn yaw_offset_deg(&self, t_s: f64, duration_s: f64) -> f64 {
        let a = self.amplitude_deg;
        if !(a > 0.0) || !t_s.is_finite() {
            return 0.0;
        }
        let slope = if duration_s > 0.0 {
            (self.rate_end_deg_per_s - self.rate_deg_per_s) / duration_s
        } else {
            0.0
        };
        let swept = self.rate_deg_per_s * t_s + 0.5 * slope * t_s * t_s;
        if !swept.is_finite() {
            return 0.0;
        }
        let phase = (swept / (4.0 * a)).rem_euclid(1.0); // 0..1 over one period
        match self.shape {
            SweepShape::Triangle => {
                // 0 → a over [0, 0.25], a → -a over [0.25, 0.75], -a → 0 after.
                if phase < 0.25 {
                    4.0 * a * phase
                } else if phase < 0.75 {
                    a * (2.0 - 4.0 * phase)
                } else {
                    4.0 * a * (phase - 1.0)
                }
            }
            SweepShape::Sine => a * (std::f64::consts::TAU * phase).sin(),
        }
    }
}

/// How the camera moves.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraMotion {
    /// Keyframes with strictly increasing times (at least one).
    Keyframes(Vec<Keyframe>),
    /// Constant-speed motion along the start heading, with an optional head
    /// yaw sweep.
    Forward {
        /// Speed along the start heading, m/s (>= 0).
        speed_m_per_s: f64,
        /// Position at t = 0, metres.
        start_m: DVec3,
        /// Heading yaw at t = 0, degrees.
        start_yaw_deg: f64,
        /// Heading pitch at t = 0, degrees.
        start_pitch_deg: f64,
        /// Head rotation about the heading, if any.
        yaw_sweep: Option<YawSweep>,
    },
}

/// A camera path: where the camera is and which way it looks at each time.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraPath {
    /// Length of the run, seconds (> 0). Sampling outside `[0, duration_s]`
    /// still works (keyframes clamp, forward motion extrapolates).
    pub duration_s: f64,
    /// The motion.
    pub motion: CameraMotion,
}

impl CameraPath {
    /// Camera position (world, metres) and orientation (camera-to-world) at
    /// `t_s` seconds. A non-finite `t_s` samples t = 0.
    pub fn sample(&self, t_s: f64) -> (DVec3, DQuat) {
        let t_s = if t_s.is_finite() { t_s } else { 0.0 };
        match &self.motion {
            CameraMotion::Keyframes(keys) => sample_keyframes(keys, t_s),
            CameraMotion::Forward {
                speed_m_per_s,
                start_m,
                start_yaw_deg,
                start_pitch_deg,
                yaw_sweep,
            } => {
                let heading = orientation_from_deg(*start_yaw_deg, *start_pitch_deg, 0.0);
                let position = *start_m + heading * DVec3::NEG_Z * (speed_m_per_s * t_s);
                let yaw = yaw_sweep.map_or(0.0, |s| s.yaw_offset_deg(t_s, self.duration_s));
                let orientation = orientation_from_deg(start_yaw_deg + yaw, *start_pitch_deg, 0.0);
                (position, orientation)
            }
        }
    }

    /// The camera's viewing direction (world space, unit) at `t_s`.
    pub fn forward(&self, t_s: f64) -> DVec3 {
        self.sample(t_s).1 * DVec3::NEG_Z
    }
}

fn sample_keyframes(keys: &[Keyframe], t_s: f64) -> (DVec3, DQuat) {
    let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
        return (DVec3::ZERO, DQuat::IDENTITY);
    };
    if t_s <= first.t_s {
        return (first.position_m, first.orientation());
    }
    if t_s >= last.t_s {
        return (last.position_m, last.orientation());
    }
    // First keyframe strictly after t: keys[i - 1].t_s <= t_s < keys[i].t_s.
    let i = keys
        .partition_point(|k| k.t_s <= t_s)
        .clamp(1, keys.len() - 1);
    let (a, b) = (&keys[i - 1], &keys[i]);
    let span = b.t_s - a.t_s;
    let u = if span > 0.0 {
        ((t_s - a.t_s) / span).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let position = a.position_m.lerp(b.position_m, u);
    let orientation = a.orientation().slerp(b.orientation(), u).normalize();
    (position, orientation)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn identity_looks_down_negative_z() {
        assert!(close(
            orientation_from_deg(0.0, 0.0, 0.0) * DVec3::NEG_Z,
            DVec3::NEG_Z
        ));
    }

    #[test]
    fn positive_yaw_turns_left_positive_pitch_looks_up() {
        let left = orientation_from_deg(90.0, 0.0, 0.0) * DVec3::NEG_Z;
        assert!(close(left, DVec3::NEG_X), "{left}");
        let up = orientation_from_deg(0.0, 90.0, 0.0) * DVec3::NEG_Z;
        assert!(close(up, DVec3::Y), "{up}");
    }

    #[test]
    fn keyframes_interpolate_linearly_and_clamp() {
        let k = |t_s, x, yaw_deg| Keyframe {
            t_s,
            position_m: DVec3::new(x, 0.0, 0.0),
            yaw_deg,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        };
        let path = CameraPath {
            duration_s: 2.0,
            motion: CameraMotion::Keyframes(vec![k(0.0, 0.0, 0.0), k(2.0, 4.0, 90.0)]),
        };
        let (p, q) = path.sample(1.0);
        assert!(close(p, DVec3::new(2.0, 0.0, 0.0)));
        let half = orientation_from_deg(45.0, 0.0, 0.0);
        assert!(q.angle_between(half) < 1e-9);
        assert!(close(path.sample(-5.0).0, DVec3::ZERO));
        assert!(close(path.sample(9.0).0, DVec3::new(4.0, 0.0, 0.0)));
        assert!(close(path.sample(f64::NAN).0, DVec3::ZERO));
    }

    #[test]
    fn forward_motion_covers_speed_times_time() {
        let path = CameraPath {
            duration_s: 5.0,
            motion: CameraMotion::Forward {
                speed_m_per_s: 4.36,
                start_m: DVec3::new(0.0, 1.0, 0.0),
                start_yaw_deg: 0.0,
                start_pitch_deg: 0.0,
                yaw_sweep: None,
            },
        };
        let (p, _) = path.sample(5.0);
        assert!(close(p, DVec3::new(0.0, 1.0, -21.8)), "{p}");
    }

    #[test]
    fn triangle_sweep_turns_at_the_stated_rate() {
        let s = YawSweep {
            amplitude_deg: 60.0,
            rate_deg_per_s: 120.0,
            rate_end_deg_per_s: 120.0,
            shape: SweepShape::Triangle,
        };
        assert!((s.yaw_offset_deg(0.25, 10.0) - 30.0).abs() < 1e-9);
        assert!((s.yaw_offset_deg(0.5, 10.0) - 60.0).abs() < 1e-9);
        assert!((s.yaw_offset_deg(1.0, 10.0) - 0.0).abs() < 1e-9);
        assert!((s.yaw_offset_deg(1.5, 10.0) + 60.0).abs() < 1e-9);
        // Speed between samples equals the rate away from the turning points.
        let dt = 1e-4;
        let v = (s.yaw_offset_deg(0.7 + dt, 10.0) - s.yaw_offset_deg(0.7, 10.0)) / dt;
        assert!((v.abs() - 120.0).abs() < 1e-6, "{v}");
    }

    #[test]
    fn ramped_sweep_reaches_the_end_rate() {
        let s = YawSweep {
            amplitude_deg: 1000.0,
            rate_deg_per_s: 0.0,
            rate_end_deg_per_s: 200.0,
            shape: SweepShape::Triangle,
        };
        let dt = 1e-4;
        let v = (s.yaw_offset_deg(5.0, 5.0) - s.yaw_offset_deg(5.0 - dt, 5.0)) / dt;
        assert!((v.abs() - 200.0).abs() < 0.01, "{v}");
    }
}
