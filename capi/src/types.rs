//! The plain-old-data structs of the C interface, laid out as C lays them
//! out (`#[repr(C)]`), with no pointers inside: they can be copied, zeroed
//! and marshalled freely (C# `[StructLayout(LayoutKind.Sequential)]`).
//! Flags are `uint32_t` (0 off, anything else on) rather than `bool`, and
//! enumerations are `uint32_t` constants, so that no value C can store is
//! invalid on the Rust side.

use crate::error::{AcuityStatus, Result, guard, write_out};

/// An object's handle in a selector, from `acuity_selector_add_object`:
/// never 0 (`ACUITY_NO_OBJECT`).
pub type AcuityObject = u64;

/// No object (a frame's `pursued` when the eyes pursue nothing).
pub const ACUITY_NO_OBJECT: AcuityObject = 0;

/// A triangle budget that is off (`acuity_selector_set_budget`,
/// `AcuitySchedulerState::budget`).
pub const ACUITY_NO_BUDGET: u64 = u64::MAX;

/// `AcuitySettings::visibility_budget_deg` for the runtime's calibration
/// of `s = 1`: the visibility budget that makes `s = 1` just imperceptible
/// over the whole image, in proportion to the display's field of view
/// (`ACUITY_IMPERCEPTIBLE_VISIBILITY_DEG` on 43.6 x 33.4 deg;
/// `acuity_settings_just_imperceptible`, which also sets the steady switch
/// rules it was calibrated with).
pub const ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE: f32 = -1.0;

/// The runtime's calibrated visibility budget on a field of view of
/// 43.6 x 33.4 deg, deg (`IMPERCEPTIBLE_VISIBILITY_DEG`).
pub const ACUITY_IMPERCEPTIBLE_VISIBILITY_DEG: f32 = 32.0;

/// The steady switch rules (`acuity_settings_just_imperceptible` and the
/// command line's scheduled policies): `AcuitySettings::switch_hysteresis`
/// (the runtime's `STEADY_SWITCH_HYSTERESIS`).
pub const ACUITY_STEADY_SWITCH_HYSTERESIS: f32 = 0.15;

/// The steady switch rules' `AcuitySettings::switch_min_dwell_s`, s
/// (`STEADY_SWITCH_MIN_DWELL_S`).
pub const ACUITY_STEADY_SWITCH_MIN_DWELL_S: f32 = 0.3;

/// The steady switch rules' `AcuitySettings::switch_coarsen_delay_s`, s
/// (`STEADY_SWITCH_COARSEN_DELAY_S`).
pub const ACUITY_STEADY_SWITCH_COARSEN_DELAY_S: f32 = 0.5;

/// `acuity_scheduler_new`'s kind: Reddy's reactive controller, which
/// turns the selector's `s` from the measured frame times.
pub const ACUITY_SCHEDULER_REACTIVE: u32 = 0;
/// `acuity_scheduler_new`'s kind: the predictive controller, which sets a
/// triangle budget from a cost model of the measured frames (Funkhouser &
/// Séquin 1993), spent by best effort.
pub const ACUITY_SCHEDULER_PREDICTIVE: u32 = 1;

/// The LOD value of an object that is culled (outside the view, behind
/// the camera, or not selected yet).
pub const ACUITY_LOD_CULLED: u8 = 255;

/// No gaze tracking: the gaze is the display's centre, no margin.
pub const ACUITY_TRACKER_NONE: u32 = 0;
/// Head tracking only: the gaze is the head's forward direction; 15 deg
/// are subtracted from every eccentricity for the eyes' freedom.
pub const ACUITY_TRACKER_HEAD: u32 = 1;
/// An eye tracker whose error is `AcuityFrame::tracker_error_deg`.
pub const ACUITY_TRACKER_EYE: u32 = 2;

/// A position in world units, `double` so that scenes far from the origin
/// select exactly as near it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityVec3d {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// A direction.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityVec3f {
    /// x.
    pub x: f32,
    /// y.
    pub y: f32,
    /// z.
    pub z: f32,
}

/// A rotation as a quaternion `(x, y, z, w)`; identity is `(0, 0, 0, 1)`.
/// It need not be exactly normalised; a zero or non-finite one is refused.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcuityQuat {
    /// x.
    pub x: f32,
    /// y.
    pub y: f32,
    /// z.
    pub z: f32,
    /// w.
    pub w: f32,
}

/// A display as the viewer sees it: resolution and the field of view the
/// image subtends at the eye (symmetric about the view axis).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcuityDisplay {
    /// Horizontal resolution, pixels (> 0).
    pub width_px: u32,
    /// Vertical resolution, pixels (> 0).
    pub height_px: u32,
    /// Horizontal field of view, deg, in (0, 179.9].
    pub fov_x_deg: f32,
    /// Vertical field of view, deg, in (0, 179.9].
    pub fov_y_deg: f32,
}

/// How a selector works; fixed at creation. Start from
/// `acuity_settings_default` and change what you need.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcuitySettings {
    /// Time constant of the smoothing of retinal velocity, s (finite,
    /// >= 0; 0: none). Default 0.05.
    pub velocity_time_constant_s: f32,
    /// Length of a cross-fade between LODs, s (finite, >= 0; 0, the
    /// default: LODs switch at once). Turns `track_changes` on.
    pub fade_time_s: f32,
    /// Hysteresis of switches to coarser LODs, a fraction in [0, 1]
    /// (0, the default: off).
    pub switch_hysteresis: f32,
    /// Least time an object keeps an LOD it refined to before it may
    /// coarsen again, s (finite, >= 0; 0, the default: off).
    pub switch_min_dwell_s: f32,
    /// How long the view must ask for a coarser LOD without a break
    /// before the object coarsens, s (finite, >= 0; 0, the default: off).
    /// A coarsening in a frame whose `s` fell happens at once.
    pub switch_coarsen_delay_s: f32,
    /// Non-zero: list the objects whose LOD changed each frame
    /// (`acuity_selector_changes`). Default 0.
    pub track_changes: u32,
    /// Non-zero: cull objects outside the view frustum. Default 1.
    pub cull: u32,
    /// Non-zero: a scale factor `s < 1` sets how many triangles are drawn
    /// (as many as one `s` for every object would draw) and they are
    /// spent where the predicted visibility per triangle saved is lowest
    /// (the runtime's `ScaleRule::Budgeted`; a budgeted selection per
    /// frame while `s < 1`). Default 0: every object judged at `s`.
    pub budgeted_scale: u32,
    /// With `budgeted_scale`: the visibility summed over the image that a
    /// selection may add beyond the triangles from `s`, each step counted
    /// from one octave inside the edge of visibility (the runtime's
    /// `VISIBILITY_COUNTED_FROM`), deg (finite, >= 0; the runtime's
    /// `VisibilityBudget::Deg`; a budgeted
    /// selection per frame at `s = 1` too), or
    /// `ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE`: the calibration that makes
    /// `s = 1` just imperceptible on the selector's display. Default 0:
    /// off.
    pub visibility_budget_deg: f32,
}

/// An object to select LODs for.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcuityObjectDesc {
    /// Centre of the bounding sphere, world units (finite, each coordinate
    /// within +-1e15).
    pub center: AcuityVec3d,
    /// Rotation from the object's frame (its profile's) to the world.
    pub rotation: AcuityQuat,
    /// Radius of the bounding sphere, world units (finite, >= 0): the
    /// profile's `bounding_radius` times the instance's scale.
    pub radius: f32,
    /// The object's profile: an index from `acuity_selector_add_profile`.
    pub profile: u32,
}

/// One frame's input: where the camera is, where the viewer looks, and the
/// time since the previous frame. `acuity_frame_default` fills one in.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcuityFrame {
    /// The camera's position, world units (finite, within +-1e15).
    pub camera_position: AcuityVec3d,
    /// Rotation from camera space to world space: the camera looks along
    /// its local -Z with +Y up.
    pub camera_orientation: AcuityQuat,
    /// The object the eyes pursue (its retinal velocity counts as 0), or
    /// `ACUITY_NO_OBJECT`. A removed object's handle pursues nothing.
    pub pursued: AcuityObject,
    /// Gaze direction in camera space, any finite non-zero vector;
    /// `(0, 0, -1)` is the display's centre.
    pub gaze_direction: AcuityVec3f,
    /// How the gaze is known: `ACUITY_TRACKER_NONE`, `_HEAD` or `_EYE`.
    pub tracker: u32,
    /// With `ACUITY_TRACKER_EYE`: the tracker's error, deg (finite,
    /// >= 0; 1 is typical). Ignored otherwise.
    pub tracker_error_deg: f32,
    /// Time since the previous frame, s (finite, >= 0). 0 keeps the
    /// objects' smoothed velocities as they were (a repeated frame).
    pub dt_s: f32,
}

/// What a profile holds, in brief.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityProfileInfo {
    /// Number of LODs (1 to 64); LOD 0 is the finest.
    pub lod_count: u32,
    /// Triangles of LOD 0.
    pub finest_triangles: u32,
    /// Triangles of the coarsest LOD.
    pub coarsest_triangles: u32,
    /// Number of sampled viewpoints.
    pub viewpoint_count: u32,
    /// Bounding sphere radius of LOD 0 in the mesh's own units.
    pub bounding_radius: f32,
}

/// An object whose selection changed in the last frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityChange {
    /// The object.
    pub object: AcuityObject,
    /// Its LOD now (0 the finest), or `ACUITY_LOD_CULLED`.
    pub lod: u32,
}

/// A cross-fade in progress: draw `from_lod` with weight `1 - fraction`
/// and `to_lod` with weight `fraction`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityFade {
    /// The object.
    pub object: AcuityObject,
    /// The LOD fading out.
    pub from_lod: u32,
    /// The LOD fading in (the object's selection).
    pub to_lod: u32,
    /// How far the fade has gone, in [0, 1).
    pub fraction: f32,
}

/// What a scheduler holds after the frames it saw.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuitySchedulerState {
    /// The `s` it sets, in (0, 1] (1 for the predictive scheduler).
    pub scale: f32,
    /// The triangle budget it sets (`ACUITY_NO_BUDGET` for the reactive
    /// scheduler).
    pub budget: u64,
    /// The frame time it aims at, s: a fraction of the period, lower where
    /// the frames vary more.
    pub aim_s: f32,
    /// 1 when the last frame's cost floor (its time at every object's
    /// coarsest LOD) lay above the period: no LOD choice reaches the rate,
    /// and the scheduler does not lower detail for it. 0 otherwise, and
    /// while the floor is unknown (until three frames whose triangles
    /// differ by more than 10% have measured the cost of a triangle).
    pub target_unreachable: u8,
    /// The last frame's cost floor, s: its time at every visible object's
    /// coarsest LOD. Between `aim_s` and the period, frames are on time
    /// only as far as their jitter allows, whatever the LODs. -1 while the
    /// floor is unknown (as for `target_unreachable`).
    pub cost_floor_s: f32,
}

/// Counts after the last frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityStats {
    /// Objects in the selector.
    pub objects: u64,
    /// Objects not culled.
    pub visible: u64,
    /// Triangles drawn with the current selections.
    pub triangles: u64,
    /// Objects whose selection changed (with `track_changes`; else 0).
    pub changed: u64,
    /// Cross-fades in progress.
    pub fading: u64,
}

impl From<AcuityVec3d> for acuity::glam::DVec3 {
    fn from(v: AcuityVec3d) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

impl From<AcuityVec3f> for acuity::glam::Vec3 {
    fn from(v: AcuityVec3f) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

impl From<AcuityQuat> for acuity::glam::Quat {
    fn from(q: AcuityQuat) -> Self {
        Self::from_xyzw(q.x, q.y, q.z, q.w)
    }
}

impl Default for AcuityQuat {
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

impl Default for AcuitySettings {
    fn default() -> Self {
        Self::from_runtime(acuity::SelectorSettings::default())
    }
}

impl Default for AcuityFrame {
    fn default() -> Self {
        Self {
            camera_position: AcuityVec3d::default(),
            camera_orientation: AcuityQuat::default(),
            pursued: ACUITY_NO_OBJECT,
            gaze_direction: AcuityVec3f {
                x: 0.0,
                y: 0.0,
                z: -1.0,
            },
            tracker: ACUITY_TRACKER_NONE,
            tracker_error_deg: 0.0,
            dt_s: 1.0 / 60.0,
        }
    }
}

impl AcuitySettings {
    /// The fields of the runtime's settings `d` that C sets.
    pub(crate) fn from_runtime(d: acuity::SelectorSettings) -> Self {
        Self {
            velocity_time_constant_s: d.velocity_time_constant_s,
            fade_time_s: d.fade_time_s,
            switch_hysteresis: d.switch_hysteresis,
            switch_min_dwell_s: d.switch_min_dwell_s,
            switch_coarsen_delay_s: d.switch_coarsen_delay_s,
            track_changes: d.track_changes.into(),
            cull: d.cull.into(),
            budgeted_scale: (d.scale_rule == acuity::ScaleRule::Budgeted).into(),
            visibility_budget_deg: match d.visibility_budget {
                acuity::VisibilityBudget::Off => 0.0,
                acuity::VisibilityBudget::Imperceptible => ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE,
                acuity::VisibilityBudget::Deg(deg) => deg,
            },
        }
    }

    /// The runtime's settings; NaN and out-of-range values refused.
    pub(crate) fn to_runtime(self) -> Result<acuity::SelectorSettings> {
        use crate::error::non_negative;
        Ok(acuity::SelectorSettings {
            velocity_time_constant_s: non_negative(
                self.velocity_time_constant_s,
                "settings.velocity_time_constant_s",
            )?,
            fade_time_s: non_negative(self.fade_time_s, "settings.fade_time_s")?,
            switch_hysteresis: non_negative(self.switch_hysteresis, "settings.switch_hysteresis")?,
            switch_min_dwell_s: non_negative(
                self.switch_min_dwell_s,
                "settings.switch_min_dwell_s",
            )?,
            switch_coarsen_delay_s: non_negative(
                self.switch_coarsen_delay_s,
                "settings.switch_coarsen_delay_s",
            )?,
            track_changes: self.track_changes != 0,
            cull: self.cull != 0,
            scale_rule: if self.budgeted_scale != 0 {
                acuity::ScaleRule::Budgeted
            } else {
                acuity::ScaleRule::Uniform
            },
            visibility_budget: if self.visibility_budget_deg
                == ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE
            {
                acuity::VisibilityBudget::Imperceptible
            } else {
                acuity::VisibilityBudget::Deg(non_negative(
                    self.visibility_budget_deg,
                    "settings.visibility_budget_deg",
                )?)
            },
            ..acuity::SelectorSettings::default()
        })
    }
}

/// Writes the default settings into `*out`: velocity smoothing 0.05 s,
/// culling on, no change list, no cross-fades, no hysteresis.
///
/// # Safety
/// `out` must be NULL (refused) or valid for writing an `AcuitySettings`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_settings_default(out: *mut AcuitySettings) -> AcuityStatus {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { write_out(out, "out", AcuitySettings::default()) })
}

/// Writes the default settings with `s = 1` just imperceptible over the
/// whole image into `*out`: `budgeted_scale` 1, `visibility_budget_deg`
/// `ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE` and the steady switch rules the
/// budget was calibrated with (`ACUITY_STEADY_SWITCH_HYSTERESIS`,
/// `ACUITY_STEADY_SWITCH_MIN_DWELL_S`,
/// `ACUITY_STEADY_SWITCH_COARSEN_DELAY_S`): fewer
/// triangles at `s = 1`, still imperceptible, for a budgeted selection per
/// frame (about ten times the plain selection's cost per object).
///
/// # Safety
/// `out` must be NULL (refused) or valid for writing an `AcuitySettings`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_settings_just_imperceptible(
    out: *mut AcuitySettings,
) -> AcuityStatus {
    let settings = AcuitySettings::from_runtime(acuity::SelectorSettings::just_imperceptible());
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { write_out(out, "out", settings) })
}

/// Writes a default frame into `*out`: camera at the origin looking along
/// -Z with +Y up, gaze at the display's centre without tracking, no
/// pursuit, `dt_s` 1/60.
///
/// # Safety
/// `out` must be NULL (refused) or valid for writing an `AcuityFrame`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_frame_default(out: *mut AcuityFrame) -> AcuityStatus {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { write_out(out, "out", AcuityFrame::default()) })
}
