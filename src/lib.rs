//! acuity: perceptual level-of-detail selection.
//!
//! Each object keeps several discrete LODs; every frame acuity picks the
//! coarsest one whose removed detail the viewer cannot see, from the
//! object's angular size, its retinal velocity and its eccentricity from
//! the gaze (Reddy 1998, 2001), judged against a contrast sensitivity
//! function. The offline pass (crate `acuity-preprocess`, driven by the
//! `acuity` tool of crate `acuity-cli`) measures the features each LOD
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
//! runtime needs glam, serde and thiserror alone. The command-line tool
//! and the offline pass are the crates `acuity-cli` and
//! `acuity-preprocess`.

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
    BudgetOutcome, BudgetRule, Diagnostics, FrameInput, ObjectDesc, ObjectId, ProfileId,
    SACCADE_THRESHOLD_DEG_PER_S, Selection, Selector, SelectorSettings, SimdLevel, ViewpointRule,
};
pub use crate::stereo::{Eye, StereoRig};

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
