//! acuity: perceptual level-of-detail selection.
//!
//! Each object keeps several discrete LODs; every frame acuity picks the
//! coarsest one whose removed detail the viewer cannot see, from the
//! object's angular size, its retinal velocity and its eccentricity from
//! the gaze (Reddy 1998, 2001), judged against a contrast sensitivity
//! function. The offline pass (crate `acuity-preprocess`, driven by the
//! `acuity` tool, crates `acuity-lab` and `acuity-cli`) measures the features each LOD
//! transition removes (their spatial frequency and contrast, at a ladder
//! of on-screen sizes) and stores them in a [`Profile`]; this crate reads
//! profiles and selects.
//!
//! Units: angles in degrees, spatial frequency in cycles per degree
//! (`_cpd`) or cycles per object diameter (`_cdiam`), velocity in deg/s,
//! time in seconds; world lengths in any one unit.
//!
//! Modules: [`acuity`] (the model), [`csf`] (contrast sensitivity and its
//! calibration), [`display`], [`camera`], [`select`] (the per-frame loop),
//! [`schedule`] (fixed frame rate), [`stereo`] (one selection for both
//! eyes of a headset), [`profile`] (the file format), [`terrain`]
//! (view-dependent terrain refined by the same model).
//!
//! Features: `json` (JSON profiles), `parallel` (the selection loop on
//! rayon), `simd-dispatch` (the selection loop in the widest vector
//! instructions the CPU has, detected at run time, through pulp; results
//! are bit-identical without it; on by default). With none of them the
//! runtime needs glam (re-exported as [`glam`]), serde and thiserror
//! alone. The offline pass, the evaluation lab and the command-line tool
//! are the crates `acuity-preprocess`, `acuity-lab` and `acuity-cli`.

#![forbid(unsafe_code)]

pub mod acuity;
pub mod camera;
pub mod csf;
pub mod display;
mod error;
pub mod fastmath;
pub mod profile;
pub mod rows;
pub mod schedule;
pub mod select;
pub mod stereo;
pub mod terrain;
mod viewpoints;

pub use crate::acuity::{Components, EccentricityModel, VelocityModel};
pub use crate::camera::{Camera, Gaze, Tracker};
pub use crate::csf::{Observer, Photometry};
pub use crate::display::{Display, FovEdges};
pub use crate::error::{Error, Result, number as format_number};
pub use crate::profile::Profile;
pub use crate::schedule::{CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings};
pub use crate::select::{
    BudgetOutcome, BudgetRule, DEFAULT_MIN_SCALE, Diagnostics, FrameInput,
    IMPERCEPTIBLE_VISIBILITY_DEG, IMPERCEPTIBLE_VISIBILITY_FIELD_DEG2, LOWEST_MIN_SCALE,
    ObjectDesc, ObjectId, ProfileId, SACCADE_THRESHOLD_DEG_PER_S, STEADY_SWITCH_COARSEN_DELAY_S,
    STEADY_SWITCH_HYSTERESIS, STEADY_SWITCH_MIN_DWELL_S, ScaleRule, Selection, Selector,
    SelectorSettings, SimdLevel, VISIBILITY_COUNTED_FROM, VISIBILITY_POOLING_EXPONENT,
    ViewpointRule, VisibilityBudget,
};
pub use crate::stereo::{Eye, StereoRig};

/// The glam the runtime's API takes (0.34: `DVec3` positions, `Quat`
/// rotations). Use it as `acuity::glam` (or through [`prelude`]) so that a
/// different glam version elsewhere in a program cannot give "expected
/// `DVec3`, found `DVec3`".
pub use glam;

/// What embedding needs, in one import.
///
/// ```
/// use acuity::prelude::*;
///
/// let mut selector = Selector::new(
///     Display::new([1920, 1080], [90.0, 58.7])?,
///     SelectorSettings::default(),
/// );
/// # let profile = acuity::profile_for_docs();
/// let id = selector.add_profile(&profile)?; // Profile::load(path)?
/// let rock = selector.add_object(ObjectDesc {
///     center: DVec3::new(0.0, 0.0, -10.0),
///     radius: 0.5,
///     rotation: Quat::IDENTITY,
///     profile: id,
/// })?;
/// selector.select(&FrameInput {
///     camera: Camera {
///         position: DVec3::ZERO,
///         orientation: Quat::IDENTITY,
///     },
///     gaze: Gaze::screen_centre(Tracker::None),
///     dt_s: 1.0 / 60.0,
///     scale: 1.0,
/// })?;
/// assert!(selector.selection(rock).lod().is_some());
/// # Ok::<(), acuity::Error>(())
/// ```
pub mod prelude {
    pub use crate::glam::{DQuat, DVec3, Quat, Vec3};
    pub use crate::{
        BudgetRule, Camera, Display, Error, FrameInput, Gaze, ObjectDesc, ObjectId, Profile,
        ProfileId, Result, ScaleRule, Selection, Selector, SelectorSettings, Tracker,
        VisibilityBudget,
    };
}

/// A small valid profile for documentation examples.
#[doc(hidden)]
pub fn profile_for_docs() -> Profile {
    let transitions = (0..3)
        .map(|t| profile::TransitionFeatures {
            feature_count: 1,
            features: vec![profile::Feature {
                freq_cdiam: 400.0 / (1 << t) as f32,
                area_diam2: 0.001,
                luminance: [0.0, 0.5],
                masker: [0.0, 0.5],
                count: 1,
            }],
        })
        .collect();
    Profile {
        format_version: profile::PROFILE_FORMAT_VERSION,
        name: "docs".into(),
        lod_triangles: vec![4000, 1000, 250, 60],
        bounding_radius: 1.0,
        viewpoints: vec![[0.0, 0.0, 1.0]],
        rung_diameters_px: vec![512.0],
        transitions,
        settings: Default::default(),
        inputs: vec![],
    }
}
