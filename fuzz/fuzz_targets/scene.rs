//! The scene parser: `acuity_lab::scene::Scene::parse` on the input as
//! (lossy) UTF-8. It does not touch the file system.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = acuity_lab::scene::Scene::parse(&text, "fuzz.toml");
});
