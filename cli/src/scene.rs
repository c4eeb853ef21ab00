//! Scene files: what a run renders, how the camera and gaze move, and which
//! LOD policies to compare.
//!
//! A scene is a TOML file with six tables. Units are in the key names
//! (`_deg`, `_cm`, `_s`, `_m_per_s`, `_hz`); positions are metres in the
//! world frame of [`crate::path`] (right-handed, +Y up, the camera looks
//! along -Z). Paths to meshes are relative to the scene file.
//!
//! ```toml
//! [display]
//! resolution = [1280, 1024]          # pixels, width x height
//! fov_deg = [43.6, 33.4]             # horizontal, vertical; or instead:
//! # screen_cm = [40, 30]             # physical width, height
//! # distance_cm = 50                 # eye to screen
//!
//! [[objects]]
//! name = "bunny"
//! mesh = "../models/bunny.obj"       # generate LODs from one mesh ...
//! generate_triangles = [3674, 834, 254, 76]
//! # lods = ["a.obj", "b.obj"]        # ... or give the chain finest first
//! # procedural = { kind = "rock", triangles = [3928, 834, 254, 76] }
//! transform = { position = [0, 0, -5], rotation_deg = [30, 0, 0], scale = 0.1 }
//!
//! [[objects]]
//! name = "rocks"
//! procedural = { kind = "rock", triangles = [3928, 834, 254, 76] }
//! copies = { count = 50, seed = 7, volume_min = [-10, 0, -40], volume_max = [10, 3, -5], random_rotation = true }
//!
//! [camera]
//! duration_s = 5.0
//! forward_speed_m_per_s = 4.36       # or keyframes = [{ t = 0, position = [..], yaw_deg = 0 }, ..]
//! start = { position = [0, 1.5, 0], yaw_deg = 0, pitch_deg = 0 }
//! yaw_sweep = { amplitude_deg = 60, rate_deg_per_s = 120 }
//!
//! [gaze]                             # optional; default: screen centre, no tracker
//! mode = "track"                     # "screen_centre" | "fixed" | "path" | "track"
//! object = "bunny"
//! copy = 0
//! tracker = "eye"                    # "none" | "head" | "eye"
//! eye_error_deg = 1.0                # only with tracker = "eye"
//! saccade_threshold_deg_per_s = 180  # only with tracker = "eye"; default: no saccade rule
//!
//! [run]                              # optional; defaults shown in RunSpec
//! target_hz = 60
//! policies = ["full", "screen_size", "acuity_all"]
//! frames = 300                       # or dt_s = 0.0166; default 1 / target_hz
//! flip_every_n_frames = 10
//! screen_size_bias = 1.0
//! screen_size_thresholds = [0.6, 0.3, 0.1, 0.03]  # relative heights, one per LOD
//! screen_size_foveated = false       # weight screen size by M(E) at the gaze
//!
//! [profiles]                         # optional; how the offline pass analyses
//! resolution = 512                   # the size ladder's largest rung, pixels
//! min_diameter = 16                  # its smallest rung (rungs halve from `resolution`)
//! viewpoints = 1                     # view-sphere level: 0 = 6, 1 = 18, 2 = 66
//! statistic = "thickness"            # "thickness" | "longest" | "mean" | "shortest"
//! threshold_delta_e = 2.3            # just-noticeable ΔE*uv of region growing
//! msaa_samples = 4                   # anti-aliasing of the analysis and of `run`'s frames
//! ```
//!
//! `[profiles]` records how an asset library's profiles are made, so every
//! command that analyses the scene (`acuity preprocess`, `run`,
//! `experiment`) makes the same ones; a command-line flag overrides a key,
//! and a key left out takes the offline pass's default
//! ([`acuity_preprocess::AnalysisSettings::default`]).
//!
//! Unknown keys are errors (so a misspelt key is not silently ignored), and
//! so are NaN and infinite numbers anywhere in the file and arrays longer
//! or shorter than their field's. Every error is a [`SceneError`] naming
//! the file, line, column and field path (`objects[2].copies.count`).
//!
//! Limits ([`crate::limits`] has them all): at most 10,000,000 frames
//! (`run.frames`, or as `dt_s` or `target_hz` imply), 16,384 pixels a
//! display side, 1,000,000 copies of an object, 10,000,000 triangles a
//! procedural LOD and 1,000,000,000 triangles at full detail over all
//! instances; `target_hz` in 1..=10,000 Hz, `dt_s` in 0.0001..=1 s, and
//! `scale_factor` in (0, 1] (below 1.2e-38 it selects as 1.2e-38). A value
//! beyond a limit is an error naming the field and the limit.

#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberate: it is also true for NaN"
)]

use std::collections::HashSet;
use std::ops::Range;
use std::path::{Path, PathBuf};

use acuity_preprocess::{AnalysisSettings, FrequencyStatistic};
use glam::{DVec2, DVec3};
use serde::Deserialize;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::gaze::{Gaze, GazeMode, GazePoint, GazeSpec, Tracker};
use crate::path::{CameraMotion, CameraPath, Keyframe, SweepShape, YawSweep};
use crate::placement::{Copies, Placement, PlacementSpec, Transform};

use crate::arrays::Exact;
use crate::limits;
pub use crate::limits::{MAX_COPIES, MAX_FRAMES, MAX_RESOLUTION_PX};

/// Everything that can be wrong with a scene file. Each variant names the
/// file; all but `Io` also name the line and column (1-based) and the field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read scene file: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML, or does not fit the scene format (missing
    /// or unknown key, wrong type, unknown name).
    #[error("{}:{line}:{column}: {}{message}", path.display(), field_prefix(field.as_deref()))]
    Format {
        /// The scene file.
        path: PathBuf,
        /// Line, 1-based (1 when the error has no better place, e.g. a
        /// missing top-level table).
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// The field path, when one can be named.
        field: Option<String>,
        /// What the parser expected or found.
        message: String,
    },
    /// The file parses but a value breaks a rule of the format.
    #[error("{}:{line}:{column}: invalid `{field}`: {reason}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// Line, 1-based, of the field (or of its nearest enclosing table
        /// when the field is missing).
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// The field path, e.g. `objects[2].copies.count`.
        field: String,
        /// The rule it breaks, with the offending value.
        reason: String,
    },
}

fn field_prefix(field: Option<&str>) -> String {
    field.map(|f| format!("`{f}`: ")).unwrap_or_default()
}

impl SceneError {
    /// The scene file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            SceneError::Io { path, .. }
            | SceneError::Format { path, .. }
            | SceneError::Invalid { path, .. } => path,
        }
    }

    /// The line (1-based), when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Format { line, .. } | SceneError::Invalid { line, .. } => Some(*line),
        }
    }

    /// The column (1-based, in characters), when known.
    pub fn column(&self) -> Option<usize> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Format { column, .. } | SceneError::Invalid { column, .. } => Some(*column),
        }
    }

    /// The field path, when known.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Format { field, .. } => field.as_deref(),
            SceneError::Invalid { field, .. } => Some(field),
        }
    }
}

// ---------------------------------------------------------------------------
// Public, validated types

/// A parsed and validated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The file the scene came from (or the name given to [`Scene::parse`]);
    /// mesh paths were resolved against its folder.
    pub source_path: PathBuf,
    /// The display.
    pub display: DisplaySpec,
    /// The objects, in file order (at least one; names are unique).
    pub objects: Vec<ObjectSpec>,
    /// The camera path.
    pub camera: CameraPath,
    /// The gaze.
    pub gaze: GazeSpec,
    /// Run settings.
    pub run: RunSpec,
    /// How the scene's profiles are made.
    pub profiles: ProfileSpec,
    /// The viewer's contrast sensitivity calibration (`[observer]`).
    pub observer: acuity::Observer,
    /// How acuity falls with eccentricity (`[observer] eccentricity_model`).
    pub eccentricity_model: acuity::EccentricityModel,
    /// How acuity falls with retinal velocity (`[observer] velocity_model`).
    pub velocity_model: acuity::VelocityModel,
}

/// How profiles are made (`[profiles]`, or the matching command-line flags);
/// `None` leaves a setting at the offline pass's default.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProfileSpec {
    /// Side of each rendered view at the size ladder's largest rung,
    /// pixels (16..=8192).
    pub resolution_px: Option<u32>,
    /// The size ladder's smallest rung, pixels (4..=`resolution_px`).
    pub min_diameter_px: Option<u32>,
    /// MSAA samples of the analysis and of the scene's frames (1 or what
    /// the adapter supports, usually 4).
    pub msaa_samples: Option<u32>,
    /// View-sphere level (0..=6; 0 = 6 viewpoints, 1 = 18, 2 = 66).
    pub viewpoint_level: Option<u32>,
    /// Feature-size statistic.
    pub statistic: Option<FrequencyStatistic>,
    /// Just-noticeable colour difference, ΔE*uv (finite, > 0).
    pub threshold_delta_e: Option<f32>,
}

impl ProfileSpec {
    /// Each setting from `over` where it has one, else from `self`.
    pub fn overridden_by(self, over: ProfileSpec) -> ProfileSpec {
        ProfileSpec {
            resolution_px: over.resolution_px.or(self.resolution_px),
            min_diameter_px: over.min_diameter_px.or(self.min_diameter_px),
            msaa_samples: over.msaa_samples.or(self.msaa_samples),
            viewpoint_level: over.viewpoint_level.or(self.viewpoint_level),
            statistic: over.statistic.or(self.statistic),
            threshold_delta_e: over.threshold_delta_e.or(self.threshold_delta_e),
        }
    }

    /// The offline pass's settings: these values over its defaults.
    pub fn analysis_settings(&self) -> AnalysisSettings {
        let d = AnalysisSettings::default();
        AnalysisSettings {
            resolution_px: self.resolution_px.unwrap_or(d.resolution_px),
            // The default smallest rung, not an explicit one, shrinks to fit
            // a small largest rung.
            min_diameter_px: self.min_diameter_px.unwrap_or(
                d.min_diameter_px
                    .min(self.resolution_px.unwrap_or(d.resolution_px)),
            ),
            msaa_samples: self.msaa_samples.unwrap_or(d.msaa_samples),
            viewpoint_level: self.viewpoint_level.unwrap_or(d.viewpoint_level),
            statistic: self.statistic.unwrap_or(d.statistic),
            threshold_delta_e: self.threshold_delta_e.unwrap_or(d.threshold_delta_e),
            ..d
        }
    }
}

/// The display: resolution and field of view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplaySpec {
    /// Width and height, pixels (each in `1..=MAX_RESOLUTION_PX`).
    pub resolution_px: [u32; 2],
    /// Horizontal and vertical field of view, degrees (each in (0, 180)).
    /// Computed from `physical` when the file gives a screen size.
    pub fov_deg: [f64; 2],
    /// The physical screen, when the file gave one.
    pub physical: Option<PhysicalScreen>,
    /// Luminance of peak white, cd/m² (default 200: an office monitor).
    pub peak_luminance_cd_m2: f64,
    /// Contrast ratio of the panel, peak over black (default 1000).
    pub contrast_ratio: f64,
    /// Ambient light on the screen, lux (default 250: an office).
    pub ambient_lux: f64,
    /// Refresh rate of the sample-and-hold panel, Hz (`refresh_hz`, in
    /// `[1, 10000]`, default 60); `None` with `continuous_motion = true`
    /// (motion as the velocity models measured it, for the papers'
    /// experiments).
    pub refresh_hz: Option<f64>,
}

impl DisplaySpec {
    /// The display's photometry ([`acuity::Photometry::from_display`] of
    /// its peak luminance, contrast ratio and ambient light).
    pub fn photometry(&self) -> acuity::Result<acuity::Photometry> {
        acuity::Photometry::from_display(
            self.peak_luminance_cd_m2 as f32,
            self.contrast_ratio as f32,
            self.ambient_lux as f32,
        )
    }

    /// Pixels per degree along the axis with the most (the display limit of
    /// REFERENCE §2 is half this, in c/deg): `max(w / fov_h, h / fov_v)`.
    pub fn pixels_per_deg(&self) -> f64 {
        let [w, h] = self.resolution_px;
        let [fh, fv] = self.fov_deg;
        (f64::from(w) / fh).max(f64::from(h) / fv)
    }

    /// Width over height.
    pub fn aspect(&self) -> f64 {
        f64::from(self.resolution_px[0]) / f64::from(self.resolution_px[1])
    }
}

/// A physical screen seen from a distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalScreen {
    /// Width and height of the screen, centimetres.
    pub size_cm: [f64; 2],
    /// Distance from the eye to the screen (on its centre line), centimetres.
    pub distance_cm: f64,
}

impl PhysicalScreen {
    /// Horizontal and vertical field of view, degrees: `2 atan(size / (2 distance))`.
    pub fn fov_deg(&self) -> [f64; 2] {
        self.size_cm
            .map(|s| 2.0 * (0.5 * s / self.distance_cm).atan().to_degrees())
    }
}

/// One object of a scene: its LOD chain and where it stands.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectSpec {
    /// Unique name (used by gaze tracking and in reports).
    pub name: String,
    /// Where its LODs come from.
    pub source: MeshSource,
    /// Where its instances stand.
    pub placement: PlacementSpec,
}

impl ObjectSpec {
    /// All instances of the object, deterministic for a given seed.
    pub fn placements(&self) -> Vec<Placement> {
        self.placement.expand()
    }
}

/// Procedural test objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProceduralKind {
    /// A unit sphere (radius 1).
    Sphere,
    /// A torus, major radius 1, minor radius 0.35.
    Torus,
    /// A unit sphere displaced by seeded multi-octave noise: features at
    /// several spatial frequencies, so LOD transitions remove visible detail.
    Rock,
}

/// Where an object's LOD chain comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSource {
    /// Ready-made LODs, finest first (`lods = [...]`), paths resolved
    /// against the scene file's folder.
    Lods(Vec<PathBuf>),
    /// LODs simplified from one mesh to target triangle counts
    /// (`mesh` + `generate_triangles`, strictly decreasing). A first target
    /// at or above the mesh's own count means "the mesh itself".
    Generated {
        /// The source mesh, resolved against the scene file's folder.
        mesh: PathBuf,
        /// Target triangles per LOD, finest first.
        triangles: Vec<u32>,
    },
    /// A procedural object tessellated to target triangle counts (finest
    /// first, strictly decreasing; met as closely as the tessellation allows).
    Procedural {
        /// The kind of object.
        kind: ProceduralKind,
        /// Target triangles per LOD, finest first.
        triangles: Vec<u32>,
    },
}

impl MeshSource {
    /// Number of LODs in the chain (>= 1).
    pub fn n_lods(&self) -> usize {
        match self {
            MeshSource::Lods(l) => l.len(),
            MeshSource::Generated { triangles, .. } | MeshSource::Procedural { triangles, .. } => {
                triangles.len()
            }
        }
    }
}

/// The LOD policies a run can compare (REFERENCE §6–§7; issue 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Policy {
    /// LOD 0 everywhere.
    Full,
    /// Screen-relative height thresholds ([`crate::screen_size`]).
    ScreenSize,
    /// Acuity, size only.
    AcuitySize,
    /// Acuity, size and eccentricity.
    AcuitySizeEcc,
    /// Acuity, size and velocity.
    AcuitySizeVel,
    /// Acuity, eccentricity and velocity, size off (the comparison of
    /// Reddy 1998 §5.2 that shows size's share of the reduction).
    AcuityEccVel,
    /// Acuity, all components.
    AcuityAll,
    /// Acuity, all components, reactive fixed-frame-rate scheduler.
    AcuityReactive,
    /// Acuity, all components, predictive fixed-frame-rate scheduler.
    AcuityPredictive,
}

impl Policy {
    /// Every policy, in report order.
    pub const ALL: [Policy; 9] = [
        Policy::Full,
        Policy::ScreenSize,
        Policy::AcuitySize,
        Policy::AcuitySizeEcc,
        Policy::AcuitySizeVel,
        Policy::AcuityEccVel,
        Policy::AcuityAll,
        Policy::AcuityReactive,
        Policy::AcuityPredictive,
    ];

    /// Whether this is an acuity policy whose scale factor `s` is fixed
    /// (not set by a scheduler), so it can be swept across `s`.
    pub fn is_fixed_scale_acuity(self) -> bool {
        matches!(
            self,
            Policy::AcuitySize
                | Policy::AcuitySizeEcc
                | Policy::AcuitySizeVel
                | Policy::AcuityEccVel
                | Policy::AcuityAll
        )
    }

    /// The name used in scene files and reports.
    pub fn name(self) -> &'static str {
        match self {
            Policy::Full => "full",
            Policy::ScreenSize => "screen_size",
            Policy::AcuitySize => "acuity_size",
            Policy::AcuitySizeEcc => "acuity_size_ecc",
            Policy::AcuitySizeVel => "acuity_size_vel",
            Policy::AcuityEccVel => "acuity_ecc_vel",
            Policy::AcuityAll => "acuity_all",
            Policy::AcuityReactive => "acuity_reactive",
            Policy::AcuityPredictive => "acuity_predictive",
        }
    }
}

/// Run settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Target frame rate, Hz (from [`limits::MIN_TARGET_HZ`] to
    /// [`limits::MAX_TARGET_HZ`]; default 60). Its period is the frame
    /// budget of the fixed-frame-rate schedulers.
    pub target_hz: f64,
    /// Policies to run, in file order, no repeats (default: all).
    pub policies: Vec<Policy>,
    /// Simulated time between frames, seconds (> 0). From `dt_s` (from
    /// [`limits::MIN_DT_S`] to [`limits::MAX_DT_S`]), else `duration_s /
    /// frames`, else `1 / target_hz`.
    pub frame_dt_s: f64,
    /// Number of frames (>= 1). From `frames`, else
    /// `ceil(duration_s / frame_dt_s)`.
    pub frames: u32,
    /// Compute FLIP against full detail on every n-th frame; 0 = never
    /// (default 10).
    pub flip_every_n_frames: u32,
    /// Bias of the screen-size policy (> 0; default 1).
    pub screen_size_bias: f64,
    /// The screen-size policy's thresholds, relative screen heights
    /// (strictly decreasing, > 0; an object with more LODs continues the
    /// table by [`crate::screen_size::DEFAULT_THRESHOLD_RATIO`]); default
    /// [`crate::screen_size::DEFAULT_THRESHOLDS_4`].
    pub screen_size_thresholds: Vec<f64>,
    /// Whether the screen-size policy weights each object's relative height
    /// by the observer's eccentricity factor `M(E)` at the object's angle
    /// from the gaze (a foveated screen-size baseline; default false).
    pub screen_size_foveated: bool,
    /// Acuity's global scale factor `s` in (0, 1] (default 1); the schedulers
    /// start from it.
    pub scale_factor: f64,
}

impl RunSpec {
    /// Simulated time of frame `k`, seconds: `k * frame_dt_s`.
    pub fn frame_time_s(&self, k: u32) -> f64 {
        f64::from(k) * self.frame_dt_s
    }

    /// Frame period of the target rate, seconds.
    pub fn budget_s(&self) -> f64 {
        1.0 / self.target_hz
    }
}

impl Scene {
    /// Reads, parses and validates a scene file, and checks that every mesh
    /// file it names exists.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let ctx = Ctx::new(&text, path);
        let scene = ctx.scene()?;
        ctx.check_files(&scene)?;
        Ok(scene)
    }

    /// Parses and validates scene text. `path_for_messages` names the file
    /// in errors, and its folder is the base of relative mesh paths. Does not
    /// touch the file system. Never panics, whatever the text.
    pub fn parse(text: &str, path_for_messages: impl AsRef<Path>) -> Result<Scene, SceneError> {
        Ctx::new(text, path_for_messages.as_ref()).scene()
    }

    /// The object named `name`.
    pub fn object(&self, name: &str) -> Option<&ObjectSpec> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// The evaluated gaze (a tracked object resolved to its instance's
    /// position).
    pub fn gaze(&self) -> Gaze {
        let tracked = match &self.gaze.mode {
            GazeMode::Track { object, copy } => self
                .object(object)
                .and_then(|o| o.placement.instance(*copy as usize))
                .map(|p| p.position_m),
            _ => None,
        };
        Gaze::new(&self.gaze.mode, self.camera.clone(), tracked)
    }

    /// Total number of object instances.
    pub fn instance_count(&self) -> usize {
        self.objects.iter().map(|o| o.placement.count()).sum()
    }
}

// ---------------------------------------------------------------------------
// Raw serde form

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    display: RawDisplay,
    objects: Vec<RawObject>,
    camera: RawCamera,
    #[serde(default)]
    gaze: Option<RawGaze>,
    #[serde(default)]
    run: Option<RawRun>,
    #[serde(default)]
    profiles: Option<RawProfiles>,
    #[serde(default)]
    observer: Option<RawObserver>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDisplay {
    resolution: Exact<u32, 2>,
    fov_deg: Option<Exact<f64, 2>>,
    screen_cm: Option<Exact<f64, 2>>,
    distance_cm: Option<f64>,
    peak_luminance_cd_m2: Option<f64>,
    contrast_ratio: Option<f64>,
    ambient_lux: Option<f64>,
    refresh_hz: Option<f64>,
    continuous_motion: Option<bool>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawObserver {
    sensitivity: Option<f32>,
    masking: Option<f32>,
    eccentricity_model: Option<acuity::EccentricityModel>,
    velocity_model: Option<acuity::VelocityModel>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    name: String,
    lods: Option<Vec<String>>,
    mesh: Option<String>,
    generate_triangles: Option<Vec<u32>>,
    procedural: Option<RawProcedural>,
    transform: Option<RawTransform>,
    copies: Option<RawCopies>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProcedural {
    kind: ProceduralKind,
    triangles: Vec<u32>,
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTransform {
    #[serde(default)]
    position: Exact<f64, 3>,
    #[serde(default)]
    rotation_deg: Exact<f64, 3>,
    #[serde(default = "one")]
    scale: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCopies {
    count: u32,
    #[serde(default)]
    seed: u64,
    volume_min: Exact<f64, 3>,
    volume_max: Exact<f64, 3>,
    #[serde(default)]
    random_rotation: bool,
    #[serde(default = "one")]
    scale: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    duration_s: Option<f64>,
    keyframes: Option<Vec<RawKeyframe>>,
    forward_speed_m_per_s: Option<f64>,
    start: Option<RawStart>,
    yaw_sweep: Option<RawYawSweep>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawKeyframe {
    t: f64,
    position: Exact<f64, 3>,
    #[serde(default)]
    yaw_deg: f64,
    #[serde(default)]
    pitch_deg: f64,
    #[serde(default)]
    roll_deg: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawStart {
    #[serde(default)]
    position: Exact<f64, 3>,
    #[serde(default)]
    yaw_deg: f64,
    #[serde(default)]
    pitch_deg: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawYawSweep {
    amplitude_deg: f64,
    rate_deg_per_s: f64,
    rate_end_deg_per_s: Option<f64>,
    #[serde(default)]
    shape: SweepShape,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
enum RawGazeMode {
    #[default]
    ScreenCentre,
    Fixed,
    Path,
    Track,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawGaze {
    #[serde(default)]
    mode: RawGazeMode,
    point_deg: Option<Exact<f64, 2>>,
    path: Option<Vec<RawGazePoint>>,
    object: Option<String>,
    copy: Option<u32>,
    #[serde(default)]
    tracker: Tracker,
    eye_error_deg: Option<f64>,
    eyes_counter_rotate: Option<bool>,
    saccade_threshold_deg_per_s: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGazePoint {
    t: f64,
    point_deg: Exact<f64, 2>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRun {
    target_hz: Option<f64>,
    policies: Option<Vec<Policy>>,
    frames: Option<u32>,
    dt_s: Option<f64>,
    flip_every_n_frames: Option<u32>,
    screen_size_bias: Option<f64>,
    screen_size_thresholds: Option<Vec<f64>>,
    screen_size_foveated: Option<bool>,
    scale_factor: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawProfiles {
    resolution: Option<u32>,
    min_diameter: Option<u32>,
    msaa_samples: Option<u32>,
    viewpoints: Option<u32>,
    statistic: Option<String>,
    threshold_delta_e: Option<f32>,
}

// ---------------------------------------------------------------------------
// Parsing and validation

struct Ctx<'t> {
    text: &'t str,
    path: PathBuf,
    base_dir: PathBuf,
    doc: Spanned<DeTable<'t>>,
    syntax_errors: Vec<toml::de::Error>,
}

/// Shorthand for validation results.
type Res<T> = Result<T, SceneError>;

impl<'t> Ctx<'t> {
    fn new(text: &'t str, path: &Path) -> Ctx<'t> {
        let (doc, syntax_errors) = DeTable::parse_recoverable(text);
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ctx {
            text,
            path: path.to_path_buf(),
            base_dir,
            doc,
            syntax_errors,
        }
    }

    fn scene(&self) -> Res<Scene> {
        if let Some(e) = self.syntax_errors.first() {
            return Err(self.toml_error(e));
        }
        check_finite(self.doc.get_ref(), &mut String::new()).map_err(|(field, span, text)| {
            self.at_span(
                field,
                Some(span),
                format!("`{text}` is not a finite number"),
            )
        })?;
        let raw: RawScene = toml::from_str(self.text).map_err(|e| self.toml_error(&e))?;
        self.validate(raw)
    }

    // -- locating ----------------------------------------------------------

    fn line_col(&self, offset: usize) -> (usize, usize) {
        line_col(self.text, offset)
    }

    fn at_span(&self, field: String, span: Option<Range<usize>>, reason: String) -> SceneError {
        let (line, column) = span.map_or((1, 1), |s| self.line_col(s.start));
        SceneError::Invalid {
            path: self.path.clone(),
            line,
            column,
            field,
            reason,
        }
    }

    /// An `Invalid` error at `field`, located at the deepest part of the
    /// field path that exists in the document.
    fn invalid(&self, field: impl Into<String>, reason: impl Into<String>) -> SceneError {
        let field = field.into();
        let span = locate(self.doc.get_ref(), &field);
        self.at_span(field, span, reason.into())
    }

    fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let message = e.message().trim().to_string();
        let span = e.span();
        let (line, column) = span.clone().map_or((1, 1), |s| self.line_col(s.start));
        let mut field = span
            .as_ref()
            .map(|s| field_at(self.doc.get_ref(), s.start))
            .unwrap_or_default();
        if let Some(missing) = backticked_after(&message, "missing field `") {
            if field.is_empty() {
                field = missing.to_string();
            } else if !field.ends_with(missing) {
                field = format!("{field}.{missing}");
            }
        }
        SceneError::Format {
            path: self.path.clone(),
            line,
            column,
            field: (!field.is_empty()).then_some(field),
            message,
        }
    }

    fn resolve(&self, relative: &str) -> PathBuf {
        self.base_dir.join(relative)
    }

    // -- validation --------------------------------------------------------

    fn validate(&self, raw: RawScene) -> Res<Scene> {
        let display = self.display(raw.display)?;
        if raw.objects.is_empty() {
            return Err(self.invalid("objects", "the scene needs at least one object"));
        }
        let mut names = HashSet::new();
        let mut objects = Vec::with_capacity(raw.objects.len());
        for (i, o) in raw.objects.into_iter().enumerate() {
            let obj = self.object(i, o)?;
            if !names.insert(obj.name.clone()) {
                return Err(self.invalid(
                    format!("objects[{i}].name"),
                    format!("the name {:?} is used by an earlier object", obj.name),
                ));
            }
            objects.push(obj);
        }
        self.scene_triangles(&objects)?;
        let camera = self.camera(raw.camera)?;
        let gaze = self.gaze(raw.gaze.unwrap_or_default(), &objects)?;
        let run = self.run(raw.run.unwrap_or_default(), camera.duration_s)?;
        let profiles = self.profiles(raw.profiles.unwrap_or_default())?;
        let raw_observer = raw.observer.unwrap_or_default();
        let eccentricity_model = raw_observer.eccentricity_model.unwrap_or_default();
        let velocity_model = raw_observer.velocity_model.unwrap_or_default();
        let observer = self.observer(raw_observer)?;
        Ok(Scene {
            source_path: self.path.clone(),
            display,
            objects,
            camera,
            gaze,
            run,
            profiles,
            observer,
            eccentricity_model,
            velocity_model,
        })
    }

    fn observer(&self, o: RawObserver) -> Res<acuity::Observer> {
        let d = acuity::Observer::default();
        let observer = acuity::Observer {
            sensitivity: o.sensitivity.unwrap_or(d.sensitivity),
            masking: o.masking.unwrap_or(d.masking),
        };
        match observer.validate() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                Err(self.invalid(format!("observer.{name}"), reason))
            }
            Err(e) => Err(self.invalid("observer", e.to_string())),
            Ok(()) => Ok(observer),
        }
    }

    fn profiles(&self, p: RawProfiles) -> Res<ProfileSpec> {
        let statistic = p
            .statistic
            .map(|s| crate::run::parse_statistic(&s))
            .transpose()
            .map_err(|reason| self.invalid("profiles.statistic", reason))?;
        let spec = ProfileSpec {
            resolution_px: p.resolution,
            min_diameter_px: p.min_diameter,
            msaa_samples: p.msaa_samples,
            viewpoint_level: p.viewpoints,
            statistic,
            threshold_delta_e: p.threshold_delta_e,
        };
        // The offline pass's own domain check; its defaults are valid, so a
        // failure names one of this table's keys.
        match spec.analysis_settings().validate() {
            Err(acuity_preprocess::Error::Settings { field, message }) => {
                let key = match field {
                    "resolution_px" => "resolution",
                    "min_diameter_px" => "min_diameter",
                    "viewpoint_level" => "viewpoints",
                    other => other,
                };
                Err(self.invalid(format!("profiles.{key}"), message))
            }
            Err(e) => Err(self.invalid("profiles", e.to_string())),
            Ok(()) => Ok(spec),
        }
    }

    fn display(&self, d: RawDisplay) -> Res<DisplaySpec> {
        let resolution = d.resolution.0;
        for (k, &px) in resolution.iter().enumerate() {
            if px == 0 || px > MAX_RESOLUTION_PX {
                return Err(self.invalid(
                    format!("display.resolution[{k}]"),
                    format!("{px} pixels is outside 1..={MAX_RESOLUTION_PX}"),
                ));
            }
        }
        let given = (d.fov_deg.map(|f| f.0), d.screen_cm.map(|s| s.0));
        let (fov_deg, physical) = match (given.0, given.1, d.distance_cm) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "give either fov_deg or screen_cm + distance_cm, not both",
                ));
            }
            (Some(fov_deg), None, None) => (fov_deg, None),
            (None, Some(size_cm), Some(distance_cm)) => {
                for (k, &s) in size_cm.iter().enumerate() {
                    if !(s > 0.0) {
                        return Err(self.invalid(
                            format!("display.screen_cm[{k}]"),
                            format!("{s} cm must be > 0"),
                        ));
                    }
                }
                if !(distance_cm > 0.0) {
                    return Err(self.invalid(
                        "display.distance_cm",
                        format!("{distance_cm} cm must be > 0"),
                    ));
                }
                let screen = PhysicalScreen {
                    size_cm,
                    distance_cm,
                };
                (screen.fov_deg(), Some(screen))
            }
            (None, Some(_), None) => {
                return Err(self.invalid(
                    "display.distance_cm",
                    "screen_cm needs distance_cm (eye to screen, cm)",
                ));
            }
            (None, None, Some(_)) => {
                return Err(self.invalid(
                    "display.screen_cm",
                    "distance_cm needs screen_cm (width, height in cm)",
                ));
            }
            (None, None, None) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "missing: give fov_deg = [horizontal, vertical] or screen_cm + distance_cm",
                ));
            }
        };
        for (k, &f) in fov_deg.iter().enumerate() {
            if !(f > 0.0 && f < 180.0) {
                return Err(self.invalid(
                    format!("display.fov_deg[{k}]"),
                    format!("{f} deg must be in (0, 180)"),
                ));
            }
        }
        let spec = DisplaySpec {
            resolution_px: resolution,
            fov_deg,
            physical,
            peak_luminance_cd_m2: d.peak_luminance_cd_m2.unwrap_or(200.0),
            contrast_ratio: d.contrast_ratio.unwrap_or(1000.0),
            ambient_lux: d.ambient_lux.unwrap_or(250.0),
            refresh_hz: match (d.continuous_motion, d.refresh_hz) {
                (Some(true), Some(_)) => {
                    return Err(self.invalid(
                        "display.continuous_motion",
                        "give refresh_hz or continuous_motion = true, not both",
                    ));
                }
                (Some(true), None) => None,
                (_, hz) => Some(hz.unwrap_or(f64::from(acuity::display::DEFAULT_REFRESH_HZ))),
            },
        };
        if let Some(hz) = spec.refresh_hz
            && !(1.0..=10_000.0).contains(&hz)
        {
            return Err(self.invalid(
                "display.refresh_hz",
                format!("{hz} Hz is outside [1, 10000]"),
            ));
        }
        match spec.photometry() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                let key = match name {
                    "peak_cd_m2" => "peak_luminance_cd_m2",
                    other => other,
                };
                Err(self.invalid(format!("display.{key}"), reason))
            }
            Err(e) => Err(self.invalid("display", e.to_string())),
            Ok(_) => Ok(spec),
        }
    }

    fn object(&self, i: usize, o: RawObject) -> Res<ObjectSpec> {
        let at = |f: &str| format!("objects[{i}].{f}");
        if o.name.trim().is_empty() {
            return Err(self.invalid(at("name"), "must not be empty"));
        }
        let given = [o.lods.is_some(), o.mesh.is_some(), o.procedural.is_some()];
        let source = match (o.lods, o.mesh, o.procedural) {
            _ if given.iter().filter(|&&g| g).count() > 1 => {
                return Err(self.invalid(
                    at("name"),
                    "give exactly one mesh source: lods, mesh + generate_triangles, or procedural",
                ));
            }
            (Some(lods), None, None) => {
                if o.generate_triangles.is_some() {
                    return Err(self.invalid(at("generate_triangles"), "only valid with `mesh`"));
                }
                if lods.is_empty() {
                    return Err(self.invalid(at("lods"), "needs at least one mesh file"));
                }
                for (k, l) in lods.iter().enumerate() {
                    if l.trim().is_empty() {
                        return Err(self.invalid(at(&format!("lods[{k}]")), "empty path"));
                    }
                }
                MeshSource::Lods(lods.iter().map(|l| self.resolve(l)).collect())
            }
            (None, Some(mesh), None) => {
                if mesh.trim().is_empty() {
                    return Err(self.invalid(at("mesh"), "empty path"));
                }
                let Some(triangles) = o.generate_triangles else {
                    return Err(self.invalid(
                        at("generate_triangles"),
                        "missing: `mesh` needs generate_triangles = [finest, ..., coarsest]",
                    ));
                };
                self.triangles(&at("generate_triangles"), &triangles)?;
                MeshSource::Generated {
                    mesh: self.resolve(&mesh),
                    triangles,
                }
            }
            (None, None, Some(p)) => {
                if o.generate_triangles.is_some() {
                    return Err(self.invalid(at("generate_triangles"), "only valid with `mesh`"));
                }
                self.triangles(&at("procedural.triangles"), &p.triangles)?;
                if p.triangles[0] > limits::MAX_PROCEDURAL_TRIANGLES {
                    return Err(self.invalid(
                        at("procedural.triangles[0]"),
                        format!(
                            "{} triangles is more than {} (a procedural LOD's limit)",
                            p.triangles[0],
                            limits::MAX_PROCEDURAL_TRIANGLES
                        ),
                    ));
                }
                MeshSource::Procedural {
                    kind: p.kind,
                    triangles: p.triangles,
                }
            }
            _ => {
                return Err(self.invalid(
                    at("name"),
                    "missing mesh source: give lods, mesh + generate_triangles, or procedural",
                ));
            }
        };
        let placement = match (o.transform, o.copies) {
            (Some(_), Some(_)) => {
                return Err(self.invalid(at("copies"), "give either transform or copies, not both"));
            }
            (Some(t), None) => {
                if !(t.scale > 0.0) {
                    return Err(
                        self.invalid(at("transform.scale"), format!("{} must be > 0", t.scale))
                    );
                }
                PlacementSpec::Transform(Transform {
                    position_m: DVec3::from_array(t.position.0),
                    rotation_deg: t.rotation_deg.0,
                    scale: t.scale,
                })
            }
            (None, Some(c)) => {
                if c.count == 0 || c.count > MAX_COPIES {
                    return Err(self.invalid(
                        at("copies.count"),
                        format!("{} is outside 1..={MAX_COPIES}", c.count),
                    ));
                }
                let (volume_min, volume_max) = (c.volume_min.0, c.volume_max.0);
                for k in 0..3 {
                    if volume_min[k] > volume_max[k] {
                        return Err(self.invalid(
                            at(&format!("copies.volume_max[{k}]")),
                            format!(
                                "{} is below volume_min[{k}] = {}",
                                volume_max[k], volume_min[k]
                            ),
                        ));
                    }
                }
                if !(c.scale > 0.0) {
                    return Err(
                        self.invalid(at("copies.scale"), format!("{} must be > 0", c.scale))
                    );
                }
                PlacementSpec::Copies(Copies {
                    count: c.count,
                    seed: c.seed,
                    volume_min_m: DVec3::from_array(volume_min),
                    volume_max_m: DVec3::from_array(volume_max),
                    random_rotation: c.random_rotation,
                    scale: c.scale,
                })
            }
            (None, None) => PlacementSpec::Transform(Transform {
                position_m: DVec3::ZERO,
                rotation_deg: [0.0; 3],
                scale: 1.0,
            }),
        };
        Ok(ObjectSpec {
            name: o.name,
            source,
            placement,
        })
    }

    /// The full-detail triangles of the procedural objects (the others'
    /// are known once their meshes are loaded) against
    /// [`limits::MAX_SCENE_TRIANGLES`].
    fn scene_triangles(&self, objects: &[ObjectSpec]) -> Res<()> {
        let counts = objects.iter().map(|o| {
            let triangles = match &o.source {
                MeshSource::Procedural { triangles, .. } => u64::from(triangles[0]),
                _ => 0,
            };
            (o.name.as_str(), triangles, o.placement.count() as u64)
        });
        limits::check_scene_triangles(counts).map_err(|(i, reason)| {
            let field = match objects[i].placement {
                PlacementSpec::Copies(_) => format!("objects[{i}].copies.count"),
                PlacementSpec::Transform(_) => format!("objects[{i}].procedural.triangles[0]"),
            };
            self.invalid(field, reason)
        })
    }

    fn triangles(&self, field: &str, triangles: &[u32]) -> Res<()> {
        if triangles.is_empty() {
            return Err(self.invalid(field, "needs at least one LOD"));
        }
        for (k, &n) in triangles.iter().enumerate() {
            if n == 0 {
                return Err(self.invalid(format!("{field}[{k}]"), "0 triangles"));
            }
            if k > 0 && n >= triangles[k - 1] {
                return Err(self.invalid(
                    format!("{field}[{k}]"),
                    format!(
                        "{n} must be below the previous LOD's {} (finest first)",
                        triangles[k - 1]
                    ),
                ));
            }
        }
        Ok(())
    }

    fn camera(&self, c: RawCamera) -> Res<CameraPath> {
        let positive = |field: &str, v: f64, unit: &str| -> Res<f64> {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(self.invalid(field, format!("{v} {unit} must be > 0")))
            }
        };
        match (c.keyframes, c.forward_speed_m_per_s) {
            (Some(_), Some(_)) => Err(self.invalid(
                "camera.forward_speed_m_per_s",
                "give either keyframes or forward_speed_m_per_s, not both",
            )),
            (None, None) => Err(self.invalid(
                "camera",
                "missing motion: give keyframes or forward_speed_m_per_s",
            )),
            (Some(keys), None) => {
                if c.start.is_some() || c.yaw_sweep.is_some() {
                    let f = if c.start.is_some() {
                        "start"
                    } else {
                        "yaw_sweep"
                    };
                    return Err(self.invalid(
                        format!("camera.{f}"),
                        "only valid with forward_speed_m_per_s",
                    ));
                }
                if keys.is_empty() {
                    return Err(self.invalid("camera.keyframes", "needs at least one keyframe"));
                }
                for k in 1..keys.len() {
                    if !(keys[k].t > keys[k - 1].t) {
                        return Err(self.invalid(
                            format!("camera.keyframes[{k}].t"),
                            format!(
                                "times must increase: {} s is not after {} s",
                                keys[k].t,
                                keys[k - 1].t
                            ),
                        ));
                    }
                }
                if keys[0].t < 0.0 {
                    return Err(self.invalid(
                        "camera.keyframes[0].t",
                        format!("{} s must be >= 0", keys[0].t),
                    ));
                }
                let last_t = keys.last().map_or(0.0, |k| k.t);
                let duration_s = match c.duration_s {
                    Some(d) => positive("camera.duration_s", d, "s")?,
                    None if last_t > 0.0 => last_t,
                    None => {
                        return Err(self.invalid(
                            "camera.duration_s",
                            "missing: needed when the keyframes span no time",
                        ));
                    }
                };
                let keyframes = keys
                    .into_iter()
                    .map(|k| Keyframe {
                        t_s: k.t,
                        position_m: DVec3::from_array(k.position.0),
                        yaw_deg: k.yaw_deg,
                        pitch_deg: k.pitch_deg,
                        roll_deg: k.roll_deg,
                    })
                    .collect();
                Ok(CameraPath {
                    duration_s,
                    motion: CameraMotion::Keyframes(keyframes),
                })
            }
            (None, Some(speed)) => {
                if !(speed >= 0.0) {
                    return Err(self.invalid(
                        "camera.forward_speed_m_per_s",
                        format!("{speed} m/s must be >= 0"),
                    ));
                }
                let Some(d) = c.duration_s else {
                    return Err(self.invalid(
                        "camera.duration_s",
                        "missing: a forward path needs duration_s",
                    ));
                };
                let duration_s = positive("camera.duration_s", d, "s")?;
                let start = c.start.unwrap_or_default();
                let yaw_sweep = match c.yaw_sweep {
                    None => None,
                    Some(s) => {
                        positive("camera.yaw_sweep.amplitude_deg", s.amplitude_deg, "deg")?;
                        if !(s.rate_deg_per_s >= 0.0) {
                            return Err(self.invalid(
                                "camera.yaw_sweep.rate_deg_per_s",
                                format!("{} deg/s must be >= 0", s.rate_deg_per_s),
                            ));
                        }
                        let end = s.rate_end_deg_per_s.unwrap_or(s.rate_deg_per_s);
                        if !(end >= 0.0) {
                            return Err(self.invalid(
                                "camera.yaw_sweep.rate_end_deg_per_s",
                                format!("{end} deg/s must be >= 0"),
                            ));
                        }
                        Some(YawSweep {
                            amplitude_deg: s.amplitude_deg,
                            rate_deg_per_s: s.rate_deg_per_s,
                            rate_end_deg_per_s: end,
                            shape: s.shape,
                        })
                    }
                };
                Ok(CameraPath {
                    duration_s,
                    motion: CameraMotion::Forward {
                        speed_m_per_s: speed,
                        start_m: DVec3::from_array(start.position.0),
                        start_yaw_deg: start.yaw_deg,
                        start_pitch_deg: start.pitch_deg,
                        yaw_sweep,
                    },
                })
            }
        }
    }

    fn gaze(&self, g: RawGaze, objects: &[ObjectSpec]) -> Res<GazeSpec> {
        let unexpected = |field: &str, mode: &str| {
            self.invalid(
                format!("gaze.{field}"),
                format!("not used with mode = \"{mode}\""),
            )
        };
        if g.mode != RawGazeMode::Fixed && g.point_deg.is_some() {
            return Err(unexpected("point_deg", mode_name(g.mode)));
        }
        if g.mode != RawGazeMode::Path && g.path.is_some() {
            return Err(unexpected("path", mode_name(g.mode)));
        }
        if g.mode != RawGazeMode::Track && (g.object.is_some() || g.copy.is_some()) {
            let f = if g.object.is_some() { "object" } else { "copy" };
            return Err(unexpected(f, mode_name(g.mode)));
        }
        let mode = match g.mode {
            RawGazeMode::ScreenCentre => GazeMode::ScreenCentre,
            RawGazeMode::Fixed => {
                let Some(Exact(p)) = g.point_deg else {
                    return Err(self.invalid(
                        "gaze.point_deg",
                        "missing: mode = \"fixed\" needs point_deg = [x, y]",
                    ));
                };
                self.screen_point("gaze.point_deg", p)?;
                GazeMode::Fixed {
                    point_deg: DVec2::from_array(p),
                }
            }
            RawGazeMode::Path => {
                let Some(points) = g.path else {
                    return Err(self.invalid(
                        "gaze.path",
                        "missing: mode = \"path\" needs path = [{ t = .., point_deg = [x, y] }, ..]",
                    ));
                };
                if points.is_empty() {
                    return Err(self.invalid("gaze.path", "needs at least one point"));
                }
                for (k, p) in points.iter().enumerate() {
                    self.screen_point(&format!("gaze.path[{k}].point_deg"), p.point_deg.0)?;
                    if k > 0 && !(p.t > points[k - 1].t) {
                        return Err(self.invalid(
                            format!("gaze.path[{k}].t"),
                            format!(
                                "times must increase: {} s is not after {} s",
                                p.t,
                                points[k - 1].t
                            ),
                        ));
                    }
                }
                GazeMode::Path(
                    points
                        .into_iter()
                        .map(|p| GazePoint {
                            t_s: p.t,
                            point_deg: DVec2::from_array(p.point_deg.0),
                        })
                        .collect(),
                )
            }
            RawGazeMode::Track => {
                let Some(object) = g.object else {
                    return Err(self.invalid(
                        "gaze.object",
                        "missing: mode = \"track\" needs object = \"<name>\"",
                    ));
                };
                let Some(obj) = objects.iter().find(|o| o.name == object) else {
                    let known: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
                    return Err(self.invalid(
                        "gaze.object",
                        format!("no object named {object:?} (objects: {known:?})"),
                    ));
                };
                let copy = g.copy.unwrap_or(0);
                if copy as usize >= obj.placement.count() {
                    return Err(self.invalid(
                        "gaze.copy",
                        format!(
                            "object {object:?} has {} instance(s); copy {copy} does not exist",
                            obj.placement.count()
                        ),
                    ));
                }
                GazeMode::Track { object, copy }
            }
        };
        if g.eye_error_deg.is_some() && g.tracker != Tracker::Eye {
            return Err(self.invalid(
                "gaze.eye_error_deg",
                format!(
                    "needs tracker = \"eye\" (tracker is \"{}\", whose margin is fixed at {} deg)",
                    g.tracker.name(),
                    g.tracker.default_error_deg()
                ),
            ));
        }
        let tracker_error_deg = g
            .eye_error_deg
            .unwrap_or_else(|| g.tracker.default_error_deg());
        if !(0.0..90.0).contains(&tracker_error_deg) {
            return Err(self.invalid(
                "gaze.eye_error_deg",
                format!("{tracker_error_deg} deg must be in [0, 90)"),
            ));
        }
        if g.eyes_counter_rotate.is_some() && g.tracker != Tracker::Head {
            return Err(self.invalid(
                "gaze.eyes_counter_rotate",
                "applies to tracker = \"head\" only (eye trackers report the gaze; without tracking, camera turns move the display's content)",
            ));
        }
        if let Some(v) = g.saccade_threshold_deg_per_s {
            if g.tracker != Tracker::Eye {
                return Err(self.invalid(
                    "gaze.saccade_threshold_deg_per_s",
                    "needs tracker = \"eye\" (only an eye tracker sees saccades)",
                ));
            }
            if !(v > 0.0 && v.is_finite()) {
                return Err(self.invalid(
                    "gaze.saccade_threshold_deg_per_s",
                    format!("{v} deg/s must be finite and > 0"),
                ));
            }
        }
        Ok(GazeSpec {
            mode,
            tracker: g.tracker,
            tracker_error_deg,
            eyes_counter_rotate: g.eyes_counter_rotate.unwrap_or(true),
            saccade_threshold_deg_per_s: g.saccade_threshold_deg_per_s,
        })
    }

    fn screen_point(&self, field: &str, p: [f64; 2]) -> Res<()> {
        for (k, &a) in p.iter().enumerate() {
            if !(a.abs() < 90.0) {
                return Err(self.invalid(
                    format!("{field}[{k}]"),
                    format!("{a} deg must be in (-90, 90)"),
                ));
            }
        }
        Ok(())
    }

    fn run(&self, r: RawRun, duration_s: f64) -> Res<RunSpec> {
        let target_hz = r.target_hz.unwrap_or(60.0);
        limits::check_target_hz(target_hz).map_err(|e| self.invalid("run.target_hz", e))?;
        let policies = r.policies.unwrap_or_else(|| Policy::ALL.to_vec());
        if policies.is_empty() {
            return Err(self.invalid("run.policies", "needs at least one policy"));
        }
        let mut seen = HashSet::new();
        for (k, p) in policies.iter().enumerate() {
            if !seen.insert(*p) {
                return Err(self.invalid(
                    format!("run.policies[{k}]"),
                    format!("{:?} is listed twice", p.name()),
                ));
            }
        }
        if r.frames == Some(0) {
            return Err(self.invalid("run.frames", "0 frames; need at least 1"));
        }
        let frame_dt_s = match (r.dt_s, r.frames) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("run.dt_s", "give either frames or dt_s, not both"));
            }
            (Some(dt), None) => {
                limits::check_dt_s(dt).map_err(|e| self.invalid("run.dt_s", e))?;
                dt
            }
            (None, Some(n)) => duration_s / f64::from(n),
            (None, None) => 1.0 / target_hz,
        };
        let frames = match r.frames {
            Some(n) if u64::from(n) > MAX_FRAMES => {
                return Err(self.invalid(
                    "run.frames",
                    format!("{n} frames is more than {MAX_FRAMES}"),
                ));
            }
            Some(n) => n,
            None => {
                let n = (duration_s / frame_dt_s).ceil().max(1.0);
                if !(n <= MAX_FRAMES as f64) {
                    let field = if r.dt_s.is_some() {
                        "run.dt_s"
                    } else {
                        "run.target_hz"
                    };
                    return Err(self.invalid(
                        field,
                        format!("{n} frames over {duration_s} s is more than {MAX_FRAMES}"),
                    ));
                }
                n as u32
            }
        };
        let screen_size_bias = r.screen_size_bias.unwrap_or(1.0);
        if !(screen_size_bias > 0.0) {
            return Err(self.invalid(
                "run.screen_size_bias",
                format!("{screen_size_bias} must be > 0"),
            ));
        }
        let screen_size_thresholds = r
            .screen_size_thresholds
            .unwrap_or_else(|| crate::screen_size::DEFAULT_THRESHOLDS_4.to_vec());
        crate::screen_size::check_table(&screen_size_thresholds)
            .map_err(|e| self.invalid("run.screen_size_thresholds", e.to_string()))?;
        let scale_factor = r.scale_factor.unwrap_or(1.0);
        if !(scale_factor > 0.0 && scale_factor <= 1.0) {
            return Err(self.invalid(
                "run.scale_factor",
                format!("{scale_factor} must be in (0, 1]"),
            ));
        }
        Ok(RunSpec {
            target_hz,
            policies,
            frame_dt_s,
            frames,
            flip_every_n_frames: r.flip_every_n_frames.unwrap_or(10),
            screen_size_bias,
            screen_size_thresholds,
            screen_size_foveated: r.screen_size_foveated.unwrap_or(false),
            scale_factor,
        })
    }

    /// Every mesh file named by the scene must exist.
    fn check_files(&self, scene: &Scene) -> Res<()> {
        for (i, o) in scene.objects.iter().enumerate() {
            match &o.source {
                MeshSource::Lods(lods) => {
                    for (k, l) in lods.iter().enumerate() {
                        if !l.is_file() {
                            return Err(self.invalid(
                                format!("objects[{i}].lods[{k}]"),
                                format!("no such file: {}", l.display()),
                            ));
                        }
                    }
                }
                MeshSource::Generated { mesh, .. } => {
                    if !mesh.is_file() {
                        return Err(self.invalid(
                            format!("objects[{i}].mesh"),
                            format!("no such file: {}", mesh.display()),
                        ));
                    }
                }
                MeshSource::Procedural { .. } => {}
            }
        }
        Ok(())
    }
}

fn mode_name(m: RawGazeMode) -> &'static str {
    match m {
        RawGazeMode::ScreenCentre => "screen_centre",
        RawGazeMode::Fixed => "fixed",
        RawGazeMode::Path => "path",
        RawGazeMode::Track => "track",
    }
}

/// The text between `prefix` and the next backtick, if `message` contains
/// `prefix`.
fn backticked_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let start = message.find(prefix)? + prefix.len();
    let rest = &message[start..];
    rest.find('`').map(|end| &rest[..end])
}

/// 1-based line and column (in characters) of a byte offset; offsets past
/// the end or inside a character are clamped.
pub(crate) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(field: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in field.split('.') {
        let mut pieces = part.split('[');
        if let Some(key) = pieces.next()
            && !key.is_empty()
        {
            out.push(Seg::Key(key));
        }
        for idx in pieces {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(Seg::Index(i));
            }
        }
    }
    out
}

/// The span of the deepest part of `field` present in the document: the key
/// for a table entry, the element for an array index.
fn locate(root: &DeTable<'_>, field: &str) -> Option<Range<usize>> {
    let mut best = None;
    let mut current: Option<&DeValue<'_>> = None;
    for seg in segments(field) {
        match seg {
            Seg::Key(k) => {
                let table = match current {
                    None => root,
                    Some(v) => match v.as_table() {
                        Some(t) => t,
                        None => break,
                    },
                };
                let Some((key, value)) = table.iter().find(|(key, _)| key.get_ref() == k) else {
                    break;
                };
                best = Some(key.span());
                current = Some(value.get_ref());
            }
            Seg::Index(i) => {
                let Some(item) = current.and_then(|v| v.as_array()).and_then(|a| a.get(i)) else {
                    break;
                };
                best = Some(item.span());
                current = Some(item.get_ref());
            }
        }
    }
    best
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.contains(&offset) || (span.start == offset && span.end == offset)
}

/// The field path of the deepest key or element whose span holds `offset`
/// ("" when none does). The whole tree is searched: a `[table]` header's span
/// covers only the header, not the keys under it.
fn field_at(root: &DeTable<'_>, offset: usize) -> String {
    find_in_table(root, offset, "").unwrap_or_default()
}

fn find_in_table(table: &DeTable<'_>, offset: usize, prefix: &str) -> Option<String> {
    for (k, v) in table.iter() {
        let path = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        let deeper = find_in_value(v.get_ref(), offset, &path);
        if deeper.is_some() {
            return deeper;
        }
        if contains(&k.span(), offset) || contains(&v.span(), offset) {
            return Some(path);
        }
    }
    None
}

fn find_in_value(value: &DeValue<'_>, offset: usize, path: &str) -> Option<String> {
    match value {
        DeValue::Table(t) => find_in_table(t, offset, path),
        DeValue::Array(a) => a.iter().enumerate().find_map(|(i, item)| {
            let item_path = format!("{path}[{i}]");
            find_in_value(item.get_ref(), offset, &item_path)
                .or_else(|| contains(&item.span(), offset).then_some(item_path))
        }),
        _ => None,
    }
}

/// Finds the first NaN or infinite float: its field path, span and text.
fn check_finite(
    table: &DeTable<'_>,
    prefix: &mut String,
) -> Result<(), (String, Range<usize>, String)> {
    for (k, v) in table.iter() {
        let len = prefix.len();
        if !prefix.is_empty() {
            prefix.push('.');
        }
        prefix.push_str(k.get_ref());
        check_finite_value(v, prefix)?;
        prefix.truncate(len);
    }
    Ok(())
}

fn check_finite_value(
    v: &Spanned<DeValue<'_>>,
    prefix: &mut String,
) -> Result<(), (String, Range<usize>, String)> {
    match v.get_ref() {
        DeValue::Float(f) => {
            let text = f.as_str();
            let finite = text
                .replace('_', "")
                .parse::<f64>()
                .is_ok_and(f64::is_finite);
            if !finite {
                return Err((prefix.clone(), v.span(), text.to_string()));
            }
        }
        DeValue::Table(t) => check_finite(t, prefix)?,
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                let len = prefix.len();
                prefix.push_str(&format!("[{i}]"));
                check_finite_value(item, prefix)?;
                prefix.truncate(len);
            }
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
[display]
resolution = [640, 512]
fov_deg = [43.6, 33.4]

[[objects]]
name = "ball"
procedural = { kind = "sphere", triangles = [320, 80] }

[camera]
duration_s = 2.0
forward_speed_m_per_s = 1.0
"#;

    #[test]
    fn minimal_scene_parses_with_defaults() {
        let s = Scene::parse(MINIMAL, "dir/min.toml").unwrap();
        assert_eq!(s.display.resolution_px, [640, 512]);
        assert_eq!(s.run.policies, Policy::ALL.to_vec());
        assert_eq!(s.run.frames, 120);
        assert!((s.run.frame_dt_s - 1.0 / 60.0).abs() < 1e-15);
        assert_eq!(s.gaze, GazeSpec::default());
        assert_eq!(s.instance_count(), 1);
    }

    #[test]
    fn physical_screen_gives_the_papers_field_of_view() {
        let text = MINIMAL.replace(
            "fov_deg = [43.6, 33.4]",
            "screen_cm = [40, 30]\ndistance_cm = 50",
        );
        let s = Scene::parse(&text, "x.toml").unwrap();
        assert!((s.display.fov_deg[0] - 43.6).abs() < 0.05);
        assert!((s.display.fov_deg[1] - 33.4).abs() < 0.05);
    }

    #[test]
    fn line_col_counts_characters_and_clamps() {
        assert_eq!(line_col("ab\ncé\nx", 6), (2, 3));
        assert_eq!(line_col("ab\ncé\nx", 5), (2, 2)); // inside 'é': clamped back
        assert_eq!(line_col("ab", 99), (1, 3));
        assert_eq!(line_col("", 0), (1, 1));
    }

    #[test]
    fn validation_error_names_field_and_line() {
        let text = MINIMAL.replace("[320, 80]", "[320, 400]");
        let e = Scene::parse(&text, "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("objects[0].procedural.triangles[1]"));
        assert_eq!(e.line(), Some(8));
        assert!(e.to_string().starts_with("min.toml:8:"), "{e}");
    }

    #[test]
    fn type_error_names_field_and_line() {
        let text = MINIMAL.replace("duration_s = 2.0", "duration_s = \"long\"");
        let e = Scene::parse(&text, "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("camera.duration_s"), "{e}");
        assert_eq!(e.line(), Some(11));
    }

    #[test]
    fn missing_field_is_named() {
        let text = MINIMAL.replace("resolution = [640, 512]\n", "");
        let e = Scene::parse(&text, "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("display.resolution"), "{e}");
        assert_eq!(e.line(), Some(2), "{e}");
    }

    #[test]
    fn nan_is_refused_where_it_stands() {
        let text = MINIMAL.replace("duration_s = 2.0", "duration_s = nan");
        let e = Scene::parse(&text, "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("camera.duration_s"), "{e}");
        assert_eq!(e.line(), Some(11));
    }
}
