//! Where the viewer is and where they look: the camera and the gaze.
//!
//! Conventions: right-handed world, metres (any unit works as long as
//! positions and radii share it); a camera looks along its local `-Z` with
//! `+Y` up, as in glam's `look_to_rh`.

use glam::{DVec3, Quat, Vec3};

use crate::error::{Error, Result};

/// Largest absolute world coordinate accepted, in world units. Larger
/// values would overflow `f32` squared distances.
pub const MAX_WORLD_COORDINATE: f64 = 1e15;

/// The camera: position (world units, `f64` so that scenes far from the
/// origin select exactly as near it) and orientation (local `-Z` forward,
/// `+Y` up). Its frustum is the display's field of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in world units. Each coordinate within
    /// `±MAX_WORLD_COORDINATE`.
    pub position: DVec3,
    /// Rotation from camera space to world space. Need not be exactly
    /// normalised; it is normalised each frame.
    pub orientation: Quat,
}

impl Camera {
    /// A camera at `position` looking along `forward` with `up` as the
    /// approximate up direction. Fails when either vector is zero or not
    /// finite, or when they are parallel.
    pub fn look_to(position: DVec3, forward: Vec3, up: Vec3) -> Result<Self> {
        let f = forward
            .try_normalize()
            .ok_or_else(|| Error::invalid("forward", format!("{forward} has no direction")))?;
        let right = f
            .cross(up)
            .try_normalize()
            .ok_or_else(|| Error::invalid("up", format!("{up} is zero or parallel to {f}")))?;
        let true_up = right.cross(f);
        let orientation = Quat::from_mat3(&glam::Mat3::from_cols(right, true_up, -f));
        Ok(Self {
            position,
            orientation,
        })
    }

    pub(crate) fn validate(&self) -> Result<Quat> {
        if !self.position.is_finite() || self.position.abs().max_element() > MAX_WORLD_COORDINATE {
            return Err(Error::invalid(
                "camera.position",
                format!(
                    "{} is not finite or beyond ±{MAX_WORLD_COORDINATE:e}",
                    self.position
                ),
            ));
        }
        normalized_rotation(self.orientation, "camera.orientation")
    }
}

pub(crate) fn normalized_rotation(q: Quat, name: &'static str) -> Result<Quat> {
    let len = q.length();
    if !(len.is_finite() && len > 1e-6) {
        return Err(Error::invalid(
            name,
            format!("{q} is not a rotation (length {len})"),
        ));
    }
    Ok(q / len)
}

/// How the gaze is known, and so how far the true gaze may lie from the
/// reported one (the tracker error margin subtracted from eccentricity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tracker {
    /// No tracking: the gaze is assumed to be the centre of the display, as
    /// in Reddy's experiments, and no margin is subtracted. Switch the
    /// eccentricity component off where that assumption is unsafe.
    None,
    /// Head tracking only: the gaze is the head's forward direction, and
    /// eccentricity is reduced by 15 deg for the eyes' freedom in the head
    /// (Luebke et al. 2000).
    Head,
    /// An eye tracker with the given error in deg (1 deg is typical;
    /// [`Tracker::eye_default`]).
    Eye {
        /// Tracker error in deg, at least 0.
        error_deg: f32,
    },
}

impl Tracker {
    /// Eccentricity margin for head tracking, deg.
    pub const HEAD_MARGIN_DEG: f32 = 15.0;
    /// Default eye-tracker error, deg.
    pub const EYE_DEFAULT_ERROR_DEG: f32 = 1.0;

    /// An eye tracker with the default 1 deg error.
    pub fn eye_default() -> Self {
        Tracker::Eye {
            error_deg: Self::EYE_DEFAULT_ERROR_DEG,
        }
    }

    /// The margin in deg subtracted from every eccentricity.
    pub fn margin_deg(&self) -> f32 {
        match *self {
            Tracker::None => 0.0,
            Tracker::Head => Self::HEAD_MARGIN_DEG,
            Tracker::Eye { error_deg } => error_deg,
        }
    }
}

/// Where the viewer looks this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaze {
    /// Gaze direction in camera space (`-Z` is the centre of the display).
    /// Any finite non-zero vector; it is normalised.
    pub direction_camera: Vec3,
    /// How the gaze is known.
    pub tracker: Tracker,
    /// The object the eyes pursue, if any: its retinal velocity is 0
    /// (smooth pursuit keeps it still on the retina; Reddy 2001).
    pub pursued: Option<crate::select::object_id::ObjectId>,
}

impl Gaze {
    /// Looking at the centre of the display, with the given tracker.
    pub fn screen_centre(tracker: Tracker) -> Self {
        Self {
            direction_camera: Vec3::NEG_Z,
            tracker,
            pursued: None,
        }
    }

    /// Looking at a point of the display given as angles from its centre
    /// in deg (`x_deg` to the right, `y_deg` up; each clamped into `[-89,
    /// 89]`, non-finite as 0: [`crate::display::screen_angles_to_direction`]).
    pub fn at_screen_angles(x_deg: f32, y_deg: f32, tracker: Tracker) -> Self {
        let angles_deg = glam::DVec2::new(f64::from(x_deg), f64::from(y_deg));
        let direction_camera = crate::display::screen_angles_to_direction(angles_deg).as_vec3();
        Self {
            direction_camera,
            tracker,
            pursued: None,
        }
    }

    pub(crate) fn validate(&self) -> Result<(Vec3, f32)> {
        let dir = self.direction_camera.try_normalize().ok_or_else(|| {
            Error::invalid(
                "gaze.direction_camera",
                format!("{} has no direction", self.direction_camera),
            )
        })?;
        let margin = self.tracker.margin_deg();
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(Error::invalid(
                "gaze.tracker",
                format!("tracker error {margin} deg is not a finite angle >= 0"),
            ));
        }
        Ok((dir, margin))
    }
}

impl Default for Gaze {
    fn default() -> Self {
        Self::screen_centre(Tracker::None)
    }
}
