//! What the examples share: a stand-in profile, and errors printed as a
//! user reads them.

use acuity::Profile;
use acuity::profile::{Feature, PROFILE_FORMAT_VERSION, TransitionFeatures};

/// A stand-in for a profile from `acuity preprocess`: 4 LODs of 4000 to
/// 60 triangles, one viewpoint, one size rung, each transition removing
/// one feature of half the frequency of the one before.
pub fn demo_profile() -> Profile {
    let transitions = (0..3)
        .map(|t| TransitionFeatures {
            feature_count: 1,
            features: vec![Feature {
                freq_cdiam: 200.0 / (1 << t) as f32,
                area_diam2: 0.01,
                luminance: [0.2, 0.5],
                masker: [0.2, 0.5],
                count: 1,
            }],
        })
        .collect();
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: "rock".into(),
        lod_triangles: vec![4000, 1000, 250, 60],
        bounding_radius: 1.0,
        viewpoints: vec![[0.0, 0.0, 1.0]],
        rung_diameters_px: vec![256.0],
        transitions,
        settings: Default::default(),
        inputs: vec![],
    }
}

/// Ends an example: its error (if any) printed on one line in its
/// `Display` form, and the exit code.
pub fn finish<E: std::fmt::Display>(result: Result<(), E>) -> std::process::ExitCode {
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
