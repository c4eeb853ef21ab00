//! An error sweep from Rust: screen size across its bias and acuity across
//! its scale factor `s` on one scene, compared at equal FLIP, as
//! `acuity experiment error` does.
//!
//! ```sh
//! cargo run -p acuity-lab --example error_sweep                  # scenes/default.toml
//! cargo run -p acuity-lab --example error_sweep -- lab/examples/rocks.toml --coarse
//! ```
//!
//! `--coarse` makes missing profiles small and fast (64 px, 6 viewpoints).
//! The same sweep on the command line:
//! `acuity experiment error --scene SCENE --frames 12 --biases 0.5,1,2
//! --scales 1,0.25,0.0625 --acuity-policies acuity_all --flip-every 2
//! --out out/error_sweep` (with `--profile-resolution 64
//! --profile-viewpoints 0` for `--coarse`). Its rows are this example's:
//! the same triangles, LODs and FLIP; frame times are measured anew.

use std::path::PathBuf;

use acuity_lab::experiment::{CommonArgs, ErrorArgs, error};
use acuity_lab::frames::ProfileArgs;

fn main() -> std::process::ExitCode {
    let mut scene = PathBuf::from("scenes/default.toml");
    let mut coarse = false;
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "--coarse" => coarse = true,
            _ if arg.starts_with('-') => {
                eprintln!("error: unknown flag `{arg}` (usage: error_sweep [SCENE] [--coarse])");
                return std::process::ExitCode::from(2);
            }
            _ => scene = PathBuf::from(arg),
        }
    }
    let args = ErrorArgs {
        scene,
        biases: vec![0.5, 1.0, 2.0],
        scales: vec![1.0, 0.25, 0.0625],
        acuity_policies: vec!["acuity_all".into()],
        frames: 12,
        flip_every: 2,
        common: CommonArgs {
            out: Some(PathBuf::from("out/error_sweep")),
            profiles: ProfileArgs {
                profile_resolution: coarse.then_some(64),
                profile_viewpoints: coarse.then_some(0),
                ..ProfileArgs::default()
            },
            ..CommonArgs::default()
        },
        ..ErrorArgs::default()
    };
    let sweep = match error(&args) {
        Ok(sweep) => sweep,
        Err(e) => {
            eprintln!("error: {}", acuity_lab::error::error_line(&e));
            return std::process::ExitCode::FAILURE;
        }
    };
    print!("{}", sweep.table());
    // The rows are data: e.g. the scale factor that draws the fewest
    // triangles while its FLIP stays within screen size's at bias 1.
    let flip_at = |policy: &str, knob: f64| {
        sweep
            .rows
            .iter()
            .find(|r| r.summary.policy.name() == policy && r.summary.knob == knob)
            .map(|r| r.summary.flip_mean)
    };
    if let Some(limit) = flip_at("screen_size", 1.0) {
        let best = sweep
            .rows
            .iter()
            .filter(|r| r.summary.policy.name() == "acuity_all" && r.summary.flip_mean <= limit)
            .min_by(|a, b| a.summary.triangles.total_cmp(&b.summary.triangles));
        match best {
            Some(r) => println!(
                "acuity_all at s = {} draws {:.0} triangles a frame at mean FLIP {:.4} (screen size at bias 1: {:.4})",
                r.summary.knob, r.summary.triangles, r.summary.flip_mean, limit
            ),
            None => {
                println!("no acuity_all row stays within screen size's FLIP at bias 1 ({limit:.4})")
            }
        }
    }
    std::process::ExitCode::SUCCESS
}
