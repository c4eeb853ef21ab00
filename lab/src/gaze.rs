//! Where the viewer looks, evaluated at any time, in camera space.
//!
//! # Screen points
//! A screen point `[x_deg, y_deg]` is an angular offset from the centre of
//! the display along its axes: +x right, +y up. It maps to the camera-space
//! direction through the point `(tan x, tan y)` on a screen one unit in front
//! of the eye, `normalize(tan x, tan y, -1)`. So `[x, 0]` lies exactly `x`
//! degrees right of the view axis (and likewise for `[0, y]`), and a point
//! inside the display's field of view lands on the display. Offsets are
//! clamped to ±89 deg.
//!
//! Camera-space conventions are those of [`crate::path`]: -Z forward, +Y up.

#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberate: it is also true for NaN"
)]

use glam::{DVec2, DVec3};

use crate::path::CameraPath;

/// How the viewer's gaze is tracked, which sets the eccentricity margin
/// subtracted for the tracker's error (none, 15 deg for the head, 1 deg
/// for the eyes by default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tracker {
    /// No tracking: the gaze is assumed at the display centre (margin 0 deg
    /// unless the scene says otherwise).
    #[default]
    None,
    /// Head tracking only (default margin 15 deg).
    Head,
    /// Eye tracking (default margin 1 deg).
    Eye,
}

impl Tracker {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Tracker::None => "none",
            Tracker::Head => "head",
            Tracker::Eye => "eye",
        }
    }

    /// The default tracker error margin subtracted from eccentricity, degrees.
    pub fn default_error_deg(self) -> f64 {
        match self {
            Tracker::None => 0.0,
            Tracker::Head => 15.0,
            Tracker::Eye => 1.0,
        }
    }
}

/// A timed point of a gaze path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazePoint {
    /// Time, seconds from the start of the path.
    pub t_s: f64,
    /// Screen point, degrees from the display centre (+x right, +y up).
    pub point_deg: DVec2,
}

/// Where the gaze points, as written in a scene file (object names not yet
/// resolved to positions).
#[derive(Debug, Clone, PartialEq)]
pub enum GazeMode {
    /// The centre of the display.
    ScreenCentre,
    /// A fixed screen point, degrees from the centre.
    Fixed {
        /// The point, degrees (+x right, +y up).
        point_deg: DVec2,
    },
    /// Screen points over time (strictly increasing times), interpolated
    /// linearly in degrees and held before the first and after the last.
    Path(Vec<GazePoint>),
    /// The gaze follows one instance of a named object (its placement's
    /// origin); such an object has zero retinal velocity.
    Track {
        /// The object's `name`.
        object: String,
        /// Which instance (0-based) when the object has copies.
        copy: u32,
    },
}

/// Gaze settings of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct GazeSpec {
    /// Where the gaze points.
    pub mode: GazeMode,
    /// The tracker.
    pub tracker: Tracker,
    /// Tracker error margin subtracted from eccentricity, degrees (>= 0):
    /// [`Tracker::default_error_deg`], or the scene's `eye_error_deg` (which
    /// only the eye tracker takes).
    pub tracker_error_deg: f64,
    /// With the head tracker: the eyes counter-rotate during head turns
    /// (`eyes_counter_rotate`, default true; see
    /// [`acuity::SelectorSettings::eyes_counter_rotate`]).
    pub eyes_counter_rotate: bool,
    /// With the eye tracker: the gaze speed, deg/s, above which a saccade
    /// lifts the floor of sampled motion (`saccade_threshold_deg_per_s`;
    /// default none: never; see
    /// [`acuity::SelectorSettings::saccade_threshold_deg_per_s`]).
    pub saccade_threshold_deg_per_s: Option<f64>,
    /// With the eye tracker: the longest a switch to a coarser LOD waits
    /// for a saccade, s (`defer_coarsening_s`; default 0: switches at once;
    /// see [`acuity::SelectorSettings::defer_coarsening_s`]).
    pub defer_coarsening_s: f64,
    /// Without an eye tracker: where the viewer's eyes actually are, when
    /// the scene says (`viewer_object`, `viewer_copy`: a
    /// [`GazeMode::Track`]). The selector cannot know it and keeps modelling
    /// the gaze from [`mode`](Self::mode); the error metrics take it as the
    /// fixation (FovVideoVDP foveates there, and the dumped `gaze.csv`
    /// holds it). `None`: the viewer looks where the gaze is modelled.
    pub viewer: Option<GazeMode>,
}

impl Default for GazeSpec {
    fn default() -> Self {
        GazeSpec {
            mode: GazeMode::ScreenCentre,
            tracker: Tracker::None,
            tracker_error_deg: 0.0,
            eyes_counter_rotate: true,
            saccade_threshold_deg_per_s: None,
            defer_coarsening_s: 0.0,
            viewer: None,
        }
    }
}

/// The evaluated gaze: a [`GazeSpec`] with any tracked object resolved to a
/// world position and the camera path it is seen from.
#[derive(Debug, Clone, PartialEq)]
pub struct Gaze {
    target: Target,
    camera: CameraPath,
}

#[derive(Debug, Clone, PartialEq)]
enum Target {
    Screen(Vec<GazePoint>),
    World(DVec3),
}

impl Gaze {
    /// The gaze for `mode` seen from `camera`. For [`GazeMode::Track`],
    /// `tracked_position_m` is the tracked instance's world position
    /// (metres); when it is `None` the gaze falls back to the screen centre.
    pub fn new(mode: &GazeMode, camera: CameraPath, tracked_position_m: Option<DVec3>) -> Gaze {
        let target = match mode {
            GazeMode::ScreenCentre => Target::Screen(Vec::new()),
            GazeMode::Fixed { point_deg } => Target::Screen(vec![GazePoint {
                t_s: 0.0,
                point_deg: *point_deg,
            }]),
            GazeMode::Path(points) => Target::Screen(points.clone()),
            GazeMode::Track { .. } => match tracked_position_m {
                Some(p) if p.is_finite() => Target::World(p),
                _ => Target::Screen(Vec::new()),
            },
        };
        Gaze { target, camera }
    }

    /// The gaze direction at `t_s`, a unit vector in camera space (-Z is the
    /// display centre). Never NaN: a non-finite time samples t = 0, and a
    /// tracked point at the eye gives -Z.
    pub fn sample(&self, t_s: f64) -> DVec3 {
        let t_s = if t_s.is_finite() { t_s } else { 0.0 };
        match &self.target {
            Target::Screen(points) => screen_point_to_direction(screen_point_at(points, t_s)),
            Target::World(p) => {
                let (eye, orientation) = self.camera.sample(t_s);
                let local = orientation.inverse() * (*p - eye);
                local.try_normalize().unwrap_or(DVec3::NEG_Z)
            }
        }
    }

    /// The screen point looked at, degrees from the display centre, when the
    /// gaze is given on screen; `None` when it tracks an object.
    pub fn screen_point_deg(&self, t_s: f64) -> Option<DVec2> {
        match &self.target {
            Target::Screen(points) => Some(screen_point_at(points, t_s)),
            Target::World(_) => None,
        }
    }
}

fn screen_point_at(points: &[GazePoint], t_s: f64) -> DVec2 {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return DVec2::ZERO;
    };
    if !(t_s > first.t_s) {
        return first.point_deg;
    }
    if t_s >= last.t_s {
        return last.point_deg;
    }
    let i = points
        .partition_point(|p| p.t_s <= t_s)
        .clamp(1, points.len() - 1);
    let (a, b) = (&points[i - 1], &points[i]);
    let span = b.t_s - a.t_s;
    let u = if span > 0.0 {
        ((t_s - a.t_s) / span).clamp(0.0, 1.0)
    } else {
        1.0
    };
    a.point_deg.lerp(b.point_deg, u)
}

/// The camera-space unit direction through a screen point given in degrees
/// from the display centre (see the module docs):
/// [`acuity::display::screen_angles_to_direction`].
pub fn screen_point_to_direction(point_deg: DVec2) -> DVec3 {
    acuity::display::screen_angles_to_direction(point_deg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::{CameraMotion, Keyframe};

    fn still_camera() -> CameraPath {
        CameraPath {
            duration_s: 1.0,
            motion: CameraMotion::Keyframes(vec![Keyframe {
                t_s: 0.0,
                position_m: DVec3::ZERO,
                yaw_deg: 0.0,
                pitch_deg: 0.0,
                roll_deg: 0.0,
            }]),
        }
    }

    #[test]
    fn centre_is_negative_z() {
        let g = Gaze::new(&GazeMode::ScreenCentre, still_camera(), None);
        assert!((g.sample(0.3) - DVec3::NEG_Z).length() < 1e-12);
    }

    #[test]
    fn screen_point_on_an_axis_has_that_eccentricity() {
        let d = screen_point_to_direction(DVec2::new(20.0, 0.0));
        let ecc = d.angle_between(DVec3::NEG_Z).to_degrees();
        assert!((ecc - 20.0).abs() < 1e-9, "{ecc}");
        assert!(d.x > 0.0);
        let up = screen_point_to_direction(DVec2::new(0.0, 10.0));
        assert!(up.y > 0.0);
        assert!(screen_point_to_direction(DVec2::new(f64::NAN, f64::INFINITY)).is_finite());
    }

    #[test]
    fn path_interpolates_between_points() {
        let mode = GazeMode::Path(vec![
            GazePoint {
                t_s: 0.0,
                point_deg: DVec2::new(-10.0, 0.0),
            },
            GazePoint {
                t_s: 1.0,
                point_deg: DVec2::new(10.0, 0.0),
            },
        ]);
        let g = Gaze::new(&mode, still_camera(), None);
        assert_eq!(g.screen_point_deg(0.5), Some(DVec2::ZERO));
        assert_eq!(g.screen_point_deg(7.0), Some(DVec2::new(10.0, 0.0)));
    }

    #[test]
    fn tracking_points_at_the_object() {
        let mode = GazeMode::Track {
            object: "bunny".into(),
            copy: 0,
        };
        let g = Gaze::new(&mode, still_camera(), Some(DVec3::new(1.0, 0.0, -1.0)));
        let d = g.sample(0.0);
        assert!((d - DVec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-12);
        let at_eye = Gaze::new(&mode, still_camera(), Some(DVec3::ZERO));
        assert_eq!(at_eye.sample(0.0), DVec3::NEG_Z);
    }
}
