//! The serde form of a scene file: one `Raw*` struct per table, as the
//! TOML gives it (unknown keys refused, optional keys `Option`), before the
//! rules of the format are checked in [`super::validate`].

use serde::Deserialize;

use super::{Policy, ProceduralKind};
use crate::arrays::Exact;
use crate::gaze::Tracker;
use crate::path::SweepShape;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub(super) display: RawDisplay,
    pub(super) objects: Vec<RawObject>,
    pub(super) camera: RawCamera,
    #[serde(default)]
    pub(super) gaze: Option<RawGaze>,
    #[serde(default)]
    pub(super) run: Option<RawRun>,
    #[serde(default)]
    pub(super) profiles: Option<RawProfiles>,
    #[serde(default)]
    pub(super) observer: Option<RawObserver>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDisplay {
    pub(super) resolution: Exact<u32, 2>,
    pub(super) fov_deg: Option<Exact<f64, 2>>,
    pub(super) fov_edges_deg: Option<Exact<f64, 4>>,
    pub(super) stereo_ipd_m: Option<f64>,
    pub(super) screen_cm: Option<Exact<f64, 2>>,
    pub(super) distance_cm: Option<f64>,
    pub(super) peak_luminance_cd_m2: Option<f64>,
    pub(super) contrast_ratio: Option<f64>,
    pub(super) ambient_lux: Option<f64>,
    pub(super) refresh_hz: Option<f64>,
    pub(super) continuous_motion: Option<bool>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObserver {
    pub(super) sensitivity: Option<f32>,
    pub(super) masking: Option<f32>,
    pub(super) pooling_area_deg2: Option<f32>,
    pub(super) threshold_jnd: Option<f32>,
    pub(super) eccentricity_model: Option<acuity::EccentricityModel>,
    pub(super) velocity_model: Option<acuity::VelocityModel>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObject {
    pub(super) name: String,
    pub(super) lods: Option<Vec<String>>,
    pub(super) mesh: Option<String>,
    pub(super) generate_triangles: Option<Vec<u32>>,
    pub(super) procedural: Option<RawProcedural>,
    pub(super) profile: Option<String>,
    pub(super) transform: Option<RawTransform>,
    pub(super) copies: Option<RawCopies>,
    pub(super) screen_size_bias: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProcedural {
    pub(super) kind: ProceduralKind,
    pub(super) triangles: Vec<u32>,
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTransform {
    #[serde(default)]
    pub(super) position: Exact<f64, 3>,
    #[serde(default)]
    pub(super) rotation_deg: Exact<f64, 3>,
    #[serde(default = "one")]
    pub(super) scale: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCopies {
    pub(super) count: u32,
    #[serde(default)]
    pub(super) seed: u64,
    pub(super) volume_min: Exact<f64, 3>,
    pub(super) volume_max: Exact<f64, 3>,
    #[serde(default)]
    pub(super) random_rotation: bool,
    #[serde(default = "one")]
    pub(super) scale: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub(super) duration_s: Option<f64>,
    pub(super) keyframes: Option<Vec<RawKeyframe>>,
    pub(super) forward_speed_m_per_s: Option<f64>,
    pub(super) start: Option<RawStart>,
    pub(super) yaw_sweep: Option<RawYawSweep>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawKeyframe {
    pub(super) t: f64,
    pub(super) position: Exact<f64, 3>,
    #[serde(default)]
    pub(super) yaw_deg: f64,
    #[serde(default)]
    pub(super) pitch_deg: f64,
    #[serde(default)]
    pub(super) roll_deg: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStart {
    #[serde(default)]
    pub(super) position: Exact<f64, 3>,
    #[serde(default)]
    pub(super) yaw_deg: f64,
    #[serde(default)]
    pub(super) pitch_deg: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawYawSweep {
    pub(super) amplitude_deg: f64,
    pub(super) rate_deg_per_s: f64,
    pub(super) rate_end_deg_per_s: Option<f64>,
    #[serde(default)]
    pub(super) shape: SweepShape,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub(super) enum RawGazeMode {
    #[default]
    ScreenCentre,
    Fixed,
    Path,
    Track,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGaze {
    #[serde(default)]
    pub(super) mode: RawGazeMode,
    pub(super) point_deg: Option<Exact<f64, 2>>,
    pub(super) path: Option<Vec<RawGazePoint>>,
    pub(super) object: Option<String>,
    pub(super) copy: Option<u32>,
    #[serde(default)]
    pub(super) tracker: Tracker,
    pub(super) eye_error_deg: Option<f64>,
    pub(super) eyes_counter_rotate: Option<bool>,
    pub(super) saccade_threshold_deg_per_s: Option<f64>,
    pub(super) defer_coarsening_s: Option<f64>,
    pub(super) viewer_object: Option<String>,
    pub(super) viewer_copy: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGazePoint {
    pub(super) t: f64,
    pub(super) point_deg: Exact<f64, 2>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRun {
    pub(super) target_hz: Option<f64>,
    pub(super) policies: Option<Vec<Policy>>,
    pub(super) frames: Option<u32>,
    pub(super) dt_s: Option<f64>,
    pub(super) flip_every_n_frames: Option<u32>,
    pub(super) screen_size_bias: Option<f64>,
    pub(super) screen_size_thresholds: Option<Vec<f64>>,
    pub(super) screen_size_foveated: Option<bool>,
    pub(super) scale_factor: Option<f64>,
    pub(super) cross_fade_s: Option<f64>,
    pub(super) min_scale: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProfiles {
    pub(super) resolution: Option<u32>,
    pub(super) min_diameter: Option<u32>,
    pub(super) msaa_samples: Option<u32>,
    pub(super) viewpoints: Option<u32>,
    pub(super) statistic: Option<String>,
    pub(super) threshold_delta_e: Option<f32>,
    pub(super) min_change_delta_e: Option<f32>,
}
