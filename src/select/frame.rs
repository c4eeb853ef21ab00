//! A frame's constants for the loop: the camera and gaze as matrices and
//! frustum planes, the smoothing and scale factors and the selector's
//! tables, checked once per frame so that the loop cannot fail.

use glam::{DVec3, Mat3, Quat, Vec3};

use crate::acuity::{EccentricityModel, MAX_ACUITY_CPD, VelocityModel};
use crate::camera::Tracker;
use crate::csf::Csf;
use crate::display::{Display, FovEdges};
use crate::error::{Error, Result};
use crate::fastmath;
use crate::viewpoints::{self, ViewpointLookup};

use super::tables::{Ladder, ProfileRows, RowLayout, Tables};
use super::{FrameInput, SelectorSettings, SimdLevel, positive_or_zero};

#[derive(Clone, Copy)]
pub(super) struct FrameConsts<'a> {
    pub(super) cam_pos: DVec3,
    pub(super) world_to_eye: Mat3,
    pub(super) planes_eye: [Vec3; 4],
    pub(super) forward_eye: Vec3,
    pub(super) cull: bool,
    #[cfg_attr(not(feature = "simd-dispatch"), allow(dead_code))]
    pub(super) simd: SimdLevel,
    pub(super) size_on: bool,
    pub(super) eccentricity_model: EccentricityModel,
    pub(super) velocity_model: VelocityModel,
    pub(super) motion_floor_cpd: f32,
    /// Retinal velocity is measured in world-aligned axes: directions are
    /// turned by `eye_to_world` first.
    pub(super) world_velocity: bool,
    pub(super) eye_to_world: Mat3,
    pub(super) margin_deg: f32,
    /// [`SelectorSettings::radius_margin`], sanitised: finite and `>= 0`.
    pub(super) radius_margin: f32,
    pub(super) scale: f32,
    pub(super) fill_deg: f32,
    pub(super) dt_valid: bool,
    pub(super) inv_dt: f32,
    pub(super) alpha: f32,
    pub(super) pursued: u32,
    pub(super) rows: &'a [f32],
    pub(super) profiles: &'a [ProfileRows],
    pub(super) lookups: &'a [ViewpointLookup],
    pub(super) ladders: &'a [Ladder],
    /// The profile of each object with more than one LOD.
    pub(super) object_profiles: &'a [u32],
    pub(super) layout: RowLayout,
    /// Viewpoint sets up to this size are searched by comparing every
    /// viewpoint (see [`ViewpointLookup::nearest_batch`]): it depends on
    /// the vector width the loop runs with.
    pub(super) scan_max_views: usize,
}

/// The per-frame constants of the loop; fails on an invalid frame.
pub(super) fn frame_consts<'a>(
    display: &Display,
    settings: &SelectorSettings,
    tables: Tables<'a>,
    frame: &FrameInput,
    scale_override: f32,
) -> Result<FrameConsts<'a>> {
    let scale = checked_scale(scale_override)?;
    checked_scale(frame.scale)?;
    let cam_rot = frame.camera.validate()?;
    let (gaze_cam, margin_deg) = frame.gaze.validate()?;
    let gaze_rot = Quat::from_rotation_arc(Vec3::NEG_Z, gaze_cam);
    let world_to_eye = Mat3::from_quat(cam_rot * gaze_rot).transpose();
    let eye_from_cam = Mat3::from_quat(gaze_rot).transpose();
    let planes_cam = side_planes(display.fov_edges());
    let dt = frame.dt_s;
    let dt_valid = dt.is_finite() && dt > 0.0 && dt <= 1e6;
    let tau = settings.velocity_time_constant_s;
    let alpha = if dt_valid && tau.is_finite() && tau > 0.0 {
        1.0 - (-dt / tau).exp()
    } else {
        1.0
    };
    Ok(FrameConsts {
        cam_pos: frame.camera.position,
        world_to_eye,
        planes_eye: planes_cam.map(|n| eye_from_cam * n),
        forward_eye: eye_from_cam * Vec3::NEG_Z,
        cull: settings.cull,
        simd: settings.simd,
        size_on: settings.components.size,
        eccentricity_model: settings.eccentricity_model,
        velocity_model: settings.velocity_model,
        motion_floor_cpd: tables.motion_floor_cpd,
        world_velocity: settings.eyes_counter_rotate && frame.gaze.tracker == Tracker::Head,
        eye_to_world: world_to_eye.transpose(),
        margin_deg,
        radius_margin: positive_or_zero(settings.radius_margin),
        scale,
        fill_deg: display.filling_angular_size_deg(),
        dt_valid,
        inv_dt: if dt_valid { 1.0 / dt } else { 0.0 },
        alpha,
        // The selector sets it: ids reach objects through its handles.
        pursued: u32::MAX,
        rows: tables.rows,
        profiles: tables.profiles,
        lookups: tables.lookups,
        ladders: tables.ladders,
        object_profiles: tables.object_profiles,
        layout: tables.layout,
        scan_max_views: viewpoints::SCAN_MAX_VIEWS_128,
    })
}

/// The floor under `G(v)` on `display`, c/deg: what a still frame shows
/// ([`Csf::sampled_motion_floor`]), at every velocity. 0 without a
/// refresh rate or with an invalid calibration (which adding a profile
/// reports).
pub(super) fn motion_floor_cpd(display: &Display, settings: &SelectorSettings) -> f32 {
    match (
        display.refresh_hz(),
        Csf::new(display.photometry(), &settings.observer),
    ) {
        (Some(hz), Ok(csf)) => MAX_ACUITY_CPD * csf.sampled_motion_floor(display.photometry(), hz),
        _ => 0.0,
    }
}

/// The outward normals of the four side planes of a field of view, camera
/// frame (-Z forward): a direction `d` lies beyond an edge when `n . d >
/// 0`. The right edge at angle `a` has `n = (cos a, 0, sin a)`, so `n . d
/// = sin(theta - a)` for `d` at `theta` to the right; the others likewise.
fn side_planes(edges: FovEdges) -> [Vec3; 4] {
    let (sr, cr) = edges.right_deg.to_radians().sin_cos();
    let (sl, cl) = edges.left_deg.to_radians().sin_cos();
    let (su, cu) = edges.up_deg.to_radians().sin_cos();
    let (sd, cd) = edges.down_deg.to_radians().sin_cos();
    [
        Vec3::new(cr, 0.0, sr),
        Vec3::new(-cl, 0.0, -sl),
        Vec3::new(0.0, cu, su),
        Vec3::new(0.0, -cd, -sd),
    ]
}

pub(super) fn checked_scale(scale: f32) -> Result<f32> {
    if scale > 0.0 {
        Ok(scale.min(1.0))
    } else {
        Err(Error::invalid("scale", format!("{scale} is not in (0, 1]")))
    }
}

/// Whether a sphere at `p` (eye frame) of radius `r` lies wholly outside a
/// side plane or behind the eye. Branch-free: which plane culls is random.
#[inline(always)]
pub(super) fn outside_frustum(c: &FrameConsts<'_>, p: Vec3, r: f32) -> bool {
    let [n0, n1, n2, n3] = c.planes_eye;
    let (a, b, d, e) = (n0.dot(p), n1.dot(p), n2.dot(p), n3.dot(p));
    fastmath::max(
        fastmath::max(a, b),
        fastmath::max(fastmath::max(d, e), -c.forward_eye.dot(p)),
    ) > r
}
