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
//! # lods = ["rock.glb"]              # ... or one glTF carrying its chain (MSFT_lod
//! #                                  #     or nodes named *_LOD0, *_LOD1, ...)
//! # Mesh files are OBJ (+ MTL, map_Kd) or glTF 2.0 (.gltf, .glb).
//! # procedural = { kind = "rock", triangles = [3928, 834, 254, 76] }  # or "sphere", "torus"
//! transform = { position = [0, 0, -5], rotation_deg = [30, 0, 0], scale = 0.1 }
//!
//! [[objects]]
//! name = "rocks"
//! procedural = { kind = "rock", triangles = [3928, 834, 254, 76] }
//! copies = { count = 50, seed = 7, volume_min = [-10, 0, -40], volume_max = [10, 3, -5], random_rotation = true }
//! screen_size_bias = 0.5             # optional: this object's factor on run.screen_size_bias
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
//! defer_coarsening_s = 0.5           # only with tracker = "eye": coarser LODs wait for a saccade
//! viewer_object = "bunny"            # not with tracker = "eye": where the eyes really are, for
//! viewer_copy = 0                    #   the error metrics (the selector still models `mode`)
//!
//! [run]                              # optional; defaults shown in RunSpec
//! target_hz = 60
//! policies = ["full", "screen_size", "acuity_all"]
//! frames = 300                       # or dt_s = 0.0166; default 1 / target_hz
//! flip_every_n_frames = 10
//! screen_size_bias = 1.0
//! screen_size_thresholds = [0.6, 0.3, 0.1, 0.03]  # relative heights, one per LOD
//! screen_size_foveated = false       # weight screen size by M(E) at the gaze
//! cross_fade_s = 0.0                 # dithered cross-fade between LODs, s; 0 = switch at once
//! min_scale = 0.001                  # the schedulers' lowest s
//!
//! [profiles]                         # optional; how the offline pass analyses
//! resolution = 512                   # the size ladder's largest rung, pixels
//! min_diameter = 16                  # its smallest rung (rungs halve from `resolution`)
//! viewpoints = 1                     # view-sphere level: 0 = 6, 1 = 18, 2 = 66
//! statistic = "mean"                 # "mean" | "longest" | "thickness" | "shortest"
//! threshold_delta_e = 2.3            # just-noticeable ΔE*uv of region growing
//! min_change_delta_e = 1.0           # a pixel changed beyond this ΔE*uv belongs to a feature
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

use std::path::{Path, PathBuf};

use acuity_preprocess::{AnalysisSettings, FrequencyStatistic};
use serde::Deserialize;

use crate::gaze::{Gaze, GazeMode, GazeSpec};
use crate::path::CameraPath;
use crate::placement::{Placement, PlacementSpec};

pub use crate::limits::{MAX_COPIES, MAX_FRAMES, MAX_RESOLUTION_PX};

mod context;
mod error;
mod locate;
mod motion;
mod objects;
mod policy;
mod raw;
mod settings;
#[cfg(test)]
mod tests;
mod validate;

pub use error::SceneError;
pub use policy::{Policy, policy_by_name};

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
    /// A pixel counts as changed where two LODs' renderings differ by more
    /// than this, ΔE*uv (finite, >= 0).
    pub min_change_delta_e: Option<f32>,
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
            min_change_delta_e: over.min_change_delta_e.or(self.min_change_delta_e),
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
            min_change_delta_e: self.min_change_delta_e.unwrap_or(d.min_change_delta_e),
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
    /// Computed from `physical` or from `fov_edges_deg` when the file gives
    /// either.
    pub fov_deg: [f64; 2],
    /// The field's edges, deg from the view axis: left, right, up, down
    /// (left and down negative when the axis is inside), each within
    /// `±acuity::display::MAX_EDGE_DEG`. Symmetric (`±fov_deg / 2`) unless
    /// the file gives `fov_edges_deg`.
    pub fov_edges_deg: [f64; 4],
    /// A headset's interpupillary distance, metres (`stereo_ipd_m`, 0 to
    /// 1): the display is then one eye of two, `resolution` and the edges
    /// the left eye's, the right eye its mirror image. One selection serves
    /// both eyes ([`acuity::StereoRig`]); frames are rendered and measured
    /// for the left eye.
    pub stereo_ipd_m: Option<f64>,
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

    /// The display an eye sees (for a headset, the left eye), as the
    /// runtime takes it.
    pub fn eye_display(&self) -> acuity::Result<acuity::Display> {
        let [left_deg, right_deg, up_deg, down_deg] = self.fov_edges_deg.map(|a| a as f32);
        let edges = acuity::FovEdges {
            left_deg,
            right_deg,
            up_deg,
            down_deg,
        };
        acuity::Display::with_fov_edges(self.resolution_px, edges)?
            .with_photometry(self.photometry()?)?
            .with_refresh_hz(self.refresh_hz.map(|hz| hz as f32))
    }

    /// The display selection runs over and the radius margin it needs:
    /// [`DisplaySpec::eye_display`] with no margin, or for a headset the
    /// [`acuity::StereoRig`] of both eyes.
    pub fn selection_display(&self) -> acuity::Result<(acuity::Display, f32)> {
        let eye = self.eye_display()?;
        match self.stereo_ipd_m {
            None => Ok((eye, 0.0)),
            Some(ipd) => {
                let e = eye.fov_edges();
                let mirrored = acuity::FovEdges {
                    left_deg: -e.right_deg,
                    right_deg: -e.left_deg,
                    ..e
                };
                let right = acuity::Display::with_fov_edges(self.resolution_px, mirrored)?
                    .with_photometry(*eye.photometry())?
                    .with_refresh_hz(eye.refresh_hz())?;
                let rig = acuity::StereoRig::from_ipd(eye, right, ipd as f32)?;
                Ok((rig.selection_display()?, rig.radius_margin()))
            }
        }
    }

    /// Where the rendered eye sits relative to the head (the camera),
    /// head frame, metres: half the IPD to the left for a headset, else
    /// nowhere else.
    pub fn rendered_eye_offset_m(&self) -> glam::DVec3 {
        glam::DVec3::new(-0.5 * self.stereo_ipd_m.unwrap_or(0.0), 0.0, 0.0)
    }

    /// The vertical field of view a symmetric display of the same image
    /// height per unit distance would have, deg: what screen-size
    /// thresholds (fractions of the screen's height) measure against.
    pub fn screen_height_fov_deg(&self) -> f64 {
        let [_, _, up, down] = self.fov_edges_deg.map(|a| a.to_radians().tan());
        2.0 * (0.5 * (up - down)).atan().to_degrees()
    }

    /// Pixels per degree along the axis with the most (the display's
    /// resolution limit `xi` is half this, in c/deg): `max(w / fov_h, h / fov_v)`.
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
            .map(|s| acuity::display::physical_fov_deg(s, self.distance_cm))
    }
}

/// One object of a scene: its LOD chain and where it stands.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectSpec {
    /// Unique name (used by gaze tracking and in reports).
    pub name: String,
    /// Where its LODs come from.
    pub source: MeshSource,
    /// A ready-made profile of these LODs (`profile = "file.acp"`, binary
    /// or JSON, resolved against the scene file's folder), used instead of
    /// the cache once its recorded input hashes match the LODs'.
    pub profile: Option<PathBuf>,
    /// Where its instances stand.
    pub placement: PlacementSpec,
    /// This object's factor on the screen-size baseline's bias
    /// (`run.screen_size_bias`), finite and > 0, 1 by default: a per-asset
    /// LOD setting, as an engine's LOD group carries its own thresholds, so
    /// the baseline can be tuned per kind of object. Only the screen-size
    /// policies read it.
    pub screen_size_bias: f64,
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
    /// A unit sphere (radius 1), a UV sphere tessellated at each LOD's
    /// target (`acuity_preprocess::shapes::Shape::Sphere`).
    Sphere,
    /// A torus, major radius 1, minor radius 0.35, tessellated at each
    /// LOD's target (`acuity_preprocess::shapes::Shape::Torus`).
    Torus,
    /// The offline pass's bumpy, colour-banded torus (major radius 1, minor
    /// radius 0.4) with bumps at three scales, simplified to each LOD's
    /// target: features at several spatial frequencies, so LOD transitions
    /// remove visible detail (`acuity_preprocess::lods::procedural_object`).
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
    /// One mesh kept whole as LOD 0, its coarser LODs simplified to a
    /// quarter of the triangles each, down to 32, at most four (`mesh`
    /// without `generate_triangles`).
    Whole {
        /// The mesh, resolved against the scene file's folder.
        mesh: PathBuf,
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
    /// Number of LODs in the chain (>= 1); `None` for a mesh kept whole,
    /// whose count follows from its triangles once it is loaded.
    pub fn n_lods(&self) -> Option<usize> {
        match self {
            MeshSource::Lods(l) => Some(l.len()),
            MeshSource::Generated { triangles, .. } | MeshSource::Procedural { triangles, .. } => {
                Some(triangles.len())
            }
            MeshSource::Whole { .. } => None,
        }
    }
}

/// Whether a path names a mesh file the offline pass reads (`.obj`,
/// `.gltf`, `.glb`, any case) rather than a scene.
pub fn is_mesh_path(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        ["obj", "gltf", "glb"]
            .iter()
            .any(|m| e.eq_ignore_ascii_case(m))
    })
}

/// Checks a cross-fade length, seconds ([`RunSpec::cross_fade_s`]).
pub fn check_cross_fade_s(cross_fade_s: f64) -> Result<(), String> {
    if (0.0..=MAX_CROSS_FADE_S).contains(&cross_fade_s) {
        Ok(())
    } else {
        Err(format!(
            "{cross_fade_s} s is outside 0..={MAX_CROSS_FADE_S} s"
        ))
    }
}

/// Run settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Target frame rate, Hz (from [`limits::MIN_TARGET_HZ`] to
    /// [`limits::MAX_TARGET_HZ`]; default 60). Its period is the frame
    /// budget of the fixed-frame-rate schedulers.
    ///
    /// [`limits::MIN_TARGET_HZ`]: crate::limits::MIN_TARGET_HZ
    /// [`limits::MAX_TARGET_HZ`]: crate::limits::MAX_TARGET_HZ
    pub target_hz: f64,
    /// Policies to run, in file order, no repeats (default: all).
    pub policies: Vec<Policy>,
    /// Simulated time between frames, seconds (> 0). From `dt_s` (from
    /// [`limits::MIN_DT_S`] to [`limits::MAX_DT_S`]), else `duration_s /
    /// frames`, else `1 / target_hz`.
    ///
    /// [`limits::MIN_DT_S`]: crate::limits::MIN_DT_S
    /// [`limits::MAX_DT_S`]: crate::limits::MAX_DT_S
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
    /// Length of a cross-fade between an instance's old and new LOD,
    /// seconds, in `[0, MAX_CROSS_FADE_S]`; 0 (the default): LODs switch
    /// at once. While it fades, both LODs are drawn with complementary
    /// screen-door dither masks.
    pub cross_fade_s: f64,
    /// The lowest `s` the fixed-frame-rate schedulers may use, in
    /// `[MIN_FLOOR_SCALE, 1]`: the reactive scheduler's
    /// [`ReactiveSettings::min_scale`] (screen size's under the same
    /// controller too) and the budgeted selection's
    /// [`SelectorSettings::min_scale`]. Default: [`acuity::DEFAULT_MIN_SCALE`], 1e-3.
    ///
    /// [`ReactiveSettings::min_scale`]: acuity::schedule::ReactiveSettings::min_scale
    /// [`SelectorSettings::min_scale`]: acuity::SelectorSettings::min_scale
    pub min_scale: f32,
}

/// The lowest `run.min_scale` (and `--min-scale`): the runtime's
/// [`acuity::LOWEST_MIN_SCALE`], as written (`f64::from` of the `f32`
/// would print as 9.99999997e-7).
pub const MIN_FLOOR_SCALE: f64 = 1e-6;

/// Checks a scheduler floor ([`RunSpec::min_scale`]).
pub fn check_min_scale(min_scale: f64) -> Result<(), String> {
    if (MIN_FLOOR_SCALE..=1.0).contains(&min_scale) {
        Ok(())
    } else {
        Err(format!("{min_scale} is outside {MIN_FLOOR_SCALE:e}..=1"))
    }
}

/// The longest cross-fade a scene or `--cross-fade-s` may ask for, s.
pub const MAX_CROSS_FADE_S: f64 = 10.0;

/// The longest `[gaze] defer_coarsening_s`, seconds: a switch that waits
/// longer than a few seconds for a saccade is a switch that did not happen.
pub const MAX_DEFER_COARSENING_S: f64 = 10.0;

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
    /// The object named `name`.
    pub fn object(&self, name: &str) -> Option<&ObjectSpec> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// The evaluated gaze (a tracked object resolved to its instance's
    /// position): where the selector models it.
    pub fn gaze(&self) -> Gaze {
        self.evaluate(&self.gaze.mode)
    }

    /// Where the viewer's eyes actually are, evaluated: the scene's
    /// [`GazeSpec::viewer`] if it gives one, else [`Scene::gaze`]. The
    /// error metrics' fixation.
    pub fn viewer_gaze(&self) -> Gaze {
        self.evaluate(self.gaze.viewer.as_ref().unwrap_or(&self.gaze.mode))
    }

    fn evaluate(&self, mode: &GazeMode) -> Gaze {
        let tracked = match mode {
            GazeMode::Track { object, copy } => self
                .object(object)
                .and_then(|o| o.placement.instance(*copy as usize))
                .map(|p| p.position_m),
            _ => None,
        };
        Gaze::new(mode, self.camera.clone(), tracked)
    }

    /// Total number of object instances.
    pub fn instance_count(&self) -> usize {
        self.objects.iter().map(|o| o.placement.count()).sum()
    }
}
