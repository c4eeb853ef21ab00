//! What keeping a profile costs: its size on disk, the time to read it and
//! the time to add it to a selector (where its features are pooled into
//! critical values for one display).
//!
//! `cargo run --release --example profile_cost -- PROFILE.acp...` prints
//! one line per profile; the display is 1280x1024 over 43.6x33.4 deg
//! (Reddy 1998's, 29 pixels per degree).

use std::time::Instant;

use acuity::{Display, Profile, Selector, SelectorSettings};

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: profile_cost PROFILE.acp...");
        std::process::exit(2);
    }
    println!(
        "{:<28} {:>10} {:>9} {:>9} {:>9}",
        "profile", "bytes", "features", "read ms", "add ms"
    );
    let display = Display::new([1280, 1024], [43.6, 33.4])?;
    for path in &paths {
        let bytes = std::fs::metadata(path)?.len();
        let start = Instant::now();
        let profile = Profile::load(path)?;
        let read_ms = start.elapsed().as_secs_f64() * 1e3;
        let features: usize = profile.transitions.iter().map(|t| t.features.len()).sum();
        let mut selector = Selector::new(display, SelectorSettings::default());
        let start = Instant::now();
        selector.add_profile(&profile)?;
        let add_ms = start.elapsed().as_secs_f64() * 1e3;
        println!("{path:<28} {bytes:>10} {features:>9} {read_ms:>9.2} {add_ms:>9.2}");
    }
    Ok(())
}
