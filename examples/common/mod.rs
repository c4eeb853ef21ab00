//! What the examples share: a stand-in profile, and errors printed as a
//! user reads them.

use acuity::Profile;
use acuity::profile::{Feature, PROFILE_FORMAT_VERSION, TransitionFeatures};

/// A stand-in for a profile from `acuity preprocess`: 4 LODs of 4000 to
/// 60 triangles, bounding radius 1 (see [`stand_in_profile`]).
pub fn demo_profile() -> Profile {
    stand_in_profile("rock", 1.0, vec![4000, 1000, 250, 60])
}

/// A stand-in profile of the given LOD chain (triangles, finest first) and
/// bounding radius (mesh units): one viewpoint, one size rung, each
/// transition removing one feature of half the frequency of the one before
/// (200 c/diam first). The Bevy plugin's and the C interface's tests and
/// examples include this file too.
pub fn stand_in_profile(name: &str, bounding_radius: f32, lod_triangles: Vec<u32>) -> Profile {
    let transitions = (0..lod_triangles.len().saturating_sub(1))
        .map(|t| TransitionFeatures {
            feature_count: 1,
            features: vec![Feature {
                freq_cdiam: 200.0 / (1u64 << t.min(63)) as f32,
                area_diam2: 0.01,
                luminance: [0.2, 0.5],
                masker: [0.2, 0.5],
                count: 1,
            }],
        })
        .collect();
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: name.into(),
        lod_triangles,
        bounding_radius,
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
