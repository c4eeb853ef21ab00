//! The plugin's resources: [`AcuitySettings`] (the selector's settings,
//! the fixed `s`, dithering), [`AcuityGaze`] (where the viewer looks),
//! [`AcuityScheduler`] (the fixed-frame-rate controller, or off),
//! [`AcuityStats`] (what the last frame chose), and the [`AcuityError`]
//! message by which bad input is reported instead of a panic.

use acuity::{
    CostModel, Gaze, PredictiveScheduler, ReactiveScheduler, ReactiveSettings, SelectorSettings,
    Tracker,
};
use bevy::ecs::entity::Entity;
use bevy::ecs::message::Message;
use bevy::ecs::resource::Resource;
use bevy::math::Vec3;

/// How every camera's selector works, and the fixed scale `s`.
///
/// Changing [`selector`](Self::selector) rebuilds the selectors (every
/// object re-registered, velocities and fades reset); changing
/// [`scale`](Self::scale) or [`dither`](Self::dither) takes effect on the
/// next frame.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct AcuitySettings {
    /// The global scale factor `s` in `(0, 1]` (1: imperceptible; lower
    /// drops detail sooner), used while [`AcuityScheduler::Off`]; values
    /// above 1 count as 1, others are refused per frame with an
    /// [`AcuityError`].
    pub scale: f32,
    /// The runtime's selector settings for every camera.
    /// `track_changes` is always on (the plugin acts on the change list);
    /// `fade_time_s` (s, 0.25 by default here) sets the cross-fades.
    pub selector: SelectorSettings,
    /// Cross-fade [`LodLevels::Children`](crate::LodLevels::Children)
    /// levels by Bevy's dithered visibility ranges (on by default). The
    /// dither follows the distance from the camera that chose the LOD, so
    /// with several cameras it is exact for that one only.
    pub dither: bool,
}

impl Default for AcuitySettings {
    fn default() -> Self {
        Self::from_runtime(SelectorSettings::default())
    }
}

impl AcuitySettings {
    /// The defaults with `s = 1` just imperceptible over each camera's
    /// whole image ([`SelectorSettings::just_imperceptible`]: the
    /// runtime's calibrated visibility budget, scaled to each camera's
    /// field of view): fewer triangles at `s = 1`, for a budgeted
    /// selection per frame.
    pub fn just_imperceptible() -> Self {
        Self::from_runtime(SelectorSettings::just_imperceptible())
    }

    /// The plugin's settings over the runtime's `selector`: `s = 1`,
    /// dithered fades of 0.25 s, the change list on.
    fn from_runtime(selector: SelectorSettings) -> Self {
        Self {
            scale: 1.0,
            selector: SelectorSettings {
                track_changes: true,
                fade_time_s: 0.25,
                ..selector
            },
            dither: true,
        }
    }
}

/// Where the viewer looks, for every camera: the screen's centre (no
/// tracking), the head's forward direction, or an eye tracker's gaze.
/// Default: the screen's centre without tracking.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct AcuityGaze {
    /// The runtime's gaze (direction in camera space, tracker). Its
    /// `pursued` field is ignored: use [`pursued`](Self::pursued).
    pub gaze: Gaze,
    /// The entity (with [`AcuityLod`](crate::AcuityLod)) the eyes pursue:
    /// its retinal velocity is 0.
    pub pursued: Option<Entity>,
}

impl Default for AcuityGaze {
    fn default() -> Self {
        Self::screen_centre()
    }
}

impl AcuityGaze {
    /// No tracking: the gaze is the screen's centre, no margin.
    pub fn screen_centre() -> Self {
        Self {
            gaze: Gaze::screen_centre(Tracker::None),
            pursued: None,
        }
    }

    /// Head tracking (a headset without eye tracking): the gaze is the
    /// view's forward direction, eccentricity reduced by 15 deg.
    pub fn head() -> Self {
        Self {
            gaze: Gaze::screen_centre(Tracker::Head),
            pursued: None,
        }
    }

    /// An eye tracker's gaze: a direction in the camera's frame (`-Z` is
    /// the screen's centre, `+Y` up) and the tracker's error, deg.
    pub fn eye(direction_camera: Vec3, error_deg: f32) -> Self {
        Self {
            gaze: Gaze {
                direction_camera: acuity::glam::Vec3::from_array(direction_camera.to_array()),
                tracker: Tracker::Eye { error_deg },
                pursued: None,
            },
            pursued: None,
        }
    }

    /// A point of the screen as angles from its centre, deg (`x_deg` to
    /// the right, `y_deg` up), with the given tracker.
    pub fn at_screen_angles(x_deg: f32, y_deg: f32, tracker: Tracker) -> Self {
        Self {
            gaze: Gaze::at_screen_angles(x_deg, y_deg, tracker),
            pursued: None,
        }
    }
}

/// The fixed-frame-rate controller, fed the measured frame time (Bevy's
/// real-time clock, `Time<Real>`: the wall time between frames), or off.
#[derive(Resource, Clone, Debug, Default)]
pub enum AcuityScheduler {
    /// `s` is [`AcuitySettings::scale`]: nothing adapts to the frame time.
    #[default]
    Off,
    /// Reddy's reactive `s`: lowered when frames run long, raised when
    /// they run short; every camera selects at that `s`.
    Reactive(ReactiveScheduler),
    /// A triangle budget from a cost model of measured frames, spent by
    /// best effort (`Selector::select_within_budget`); with several
    /// cameras each gets an equal share and the model sees their sum.
    Predictive(PredictiveScheduler),
}

impl AcuityScheduler {
    /// The reactive controller aiming at `rate_hz` frames per second, with
    /// a cost model (from the same guess as [`Self::predictive`]) for the
    /// cost floor: while no LOD choice reaches the rate it does not lower
    /// `s`.
    pub fn reactive(rate_hz: f32) -> acuity::Result<Self> {
        Ok(Self::Reactive(
            ReactiveScheduler::new(ReactiveSettings::for_rate_hz(rate_hz)?)
                .with_cost_model(CostModel::first_guess()),
        ))
    }

    /// The predictive controller aiming at `rate_hz` frames per second,
    /// starting from a guess of 1 ms per frame plus 20 ns per triangle
    /// (`CostModel::first_guess`) that the measured frames correct.
    pub fn predictive(rate_hz: f32) -> acuity::Result<Self> {
        Ok(Self::Predictive(PredictiveScheduler::new(
            ReactiveSettings::for_rate_hz(rate_hz)?,
            CostModel::first_guess(),
        )))
    }
}

/// What the last frame chose, summed over the cameras.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityStats {
    /// The scale `s` the cameras selected at (the budgeted selection's
    /// lowest, under [`AcuityScheduler::Predictive`]).
    pub scale: f32,
    /// Triangles of the chosen LODs, summed over the cameras.
    pub triangles: u64,
    /// The predictive scheduler's triangle budget, if it is on.
    pub budget: Option<u64>,
    /// Cameras selecting.
    pub cameras: usize,
    /// Entities registered (with a loaded profile).
    pub objects: usize,
}

/// Bad input met by the plugin, also logged as a warning. Each is
/// reported once per cause (an entity's, until its [`AcuityLod`](crate::AcuityLod)
/// changes; a camera's, until it selects again).
#[derive(Message, Clone, Debug, PartialEq)]
pub enum AcuityError {
    /// An entity could not be registered or updated: an LOD chain whose
    /// length differs from its profile's LOD count, a profile the
    /// selector refuses, a transform that is not finite.
    Object {
        /// The entity with [`AcuityLod`](crate::AcuityLod).
        entity: Entity,
        /// What is wrong.
        reason: String,
    },
    /// A camera could not select: a display the runtime refuses (a field
    /// of view out of range, a zero-sized window), a bad `s` or gaze.
    Camera {
        /// The camera entity.
        camera: Entity,
        /// What is wrong.
        reason: String,
    },
}

impl std::fmt::Display for AcuityError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Object { entity, reason } => write!(f, "acuity: entity {entity}: {reason}"),
            Self::Camera { camera, reason } => write!(f, "acuity: camera {camera}: {reason}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use acuity::{ScaleRule, VisibilityBudget};

    #[test]
    fn just_imperceptible_keeps_the_plugins_defaults_and_adds_the_calibration() {
        let (calibrated, default) = (
            AcuitySettings::just_imperceptible(),
            AcuitySettings::default(),
        );
        assert_eq!(
            calibrated.selector.visibility_budget,
            VisibilityBudget::Imperceptible
        );
        assert_eq!(calibrated.selector.scale_rule, ScaleRule::Budgeted);
        assert!(calibrated.selector.track_changes);
        assert_eq!(
            calibrated.selector.fade_time_s,
            default.selector.fade_time_s
        );
        assert_eq!(
            (calibrated.scale, calibrated.dither),
            (default.scale, default.dither)
        );
    }
}
