//! The JSON profile decoder: `acuity::profile::json::decode` (feature
//! `json`).
#![no_main]

use acuity::profile::json;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(profile) = json::decode(data) {
        // A decoded profile is valid and encodes again.
        profile.validate().expect("decoded profile validates");
        let _ = json::encode(&profile).expect("decoded profile encodes");
    }
});
