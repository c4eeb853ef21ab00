//! What the command-line tests share: a fresh scratch folder per test,
//! running the `acuity` binary, and a tiny scene that plays in seconds.

#![allow(dead_code)] // each test binary uses its own part

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty folder for test `test` of the suite `suite`, under
/// cargo's temporary folder for integration tests.
pub fn scratch(suite: &str, test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(suite)
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes [`TINY_SCENE`] into `dir` as `tiny.toml`; its path.
pub fn tiny_scene(dir: &Path) -> PathBuf {
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY_SCENE).unwrap();
    scene
}

/// Runs `acuity ARGS` and waits for it.
pub fn acuity(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_acuity"))
        .args(args)
        .output()
        .expect("cannot start the acuity binary")
}

/// A finished command's stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A tiny scene: 160x120 pixels, 12 copies of a three-LOD rock, 4 frames
/// over a one-second flight, FLIP on every second frame. Tests change it
/// by replacing its lines (e.g. `frames = 4`).
pub const TINY_SCENE: &str = r#"
[display]
resolution = [160, 120]
fov_deg = [43.6, 33.4]

[[objects]]
name = "rocks"
procedural = { kind = "rock", triangles = [800, 200, 60] }
copies = { count = 12, seed = 3, volume_min = [-4.0, -1.0, -20.0], volume_max = [4.0, 1.0, -3.0], random_rotation = true, scale = 0.5 }

[camera]
duration_s = 1.0
forward_speed_m_per_s = 4.0
start = { position = [0.0, 0.0, 0.0], yaw_deg = 0.0, pitch_deg = 0.0 }

[gaze]
mode = "screen_centre"

[run]
target_hz = 60
frames = 4
flip_every_n_frames = 2
"#;

/// As [`acuity`], and prints the command, its exit code and its output
/// (shown when a test fails).
pub fn acuity_logged(args: &[&str]) -> Output {
    let out = acuity(args);
    eprintln!(
        "$ acuity {} -- exit {:?}\n{}{}",
        args.join(" "),
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Flags for coarse, fast profiles (64 px, 6 viewpoints) and no progress.
pub const COARSE: [&str; 5] = [
    "--profile-resolution",
    "64",
    "--profile-viewpoints",
    "0",
    "--quiet",
];

/// `args` followed by [`COARSE`].
pub fn coarse<'a>(args: &[&'a str]) -> Vec<&'a str> {
    [args, &COARSE].concat()
}

/// `acuity run SCENE --out OUT --policies POLICIES`, then `extra` and
/// [`COARSE`].
pub fn run_policies(scene: &Path, out: &Path, policies: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--policies",
        policies,
    ];
    args.extend_from_slice(extra);
    args.extend(COARSE);
    acuity(&args)
}
