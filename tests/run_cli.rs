//! `acuity run` end to end on a tiny scene (160x120, 12 objects, a few
//! frames, coarse profiles), and its error on a broken object.
#![cfg(feature = "tools")]

use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("run_cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const TINY: &str = r#"
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

fn acuity(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_acuity"))
        .args(args)
        .output()
        .expect("run acuity")
}

#[test]
fn tiny_run_never_draws_more_than_full_detail_and_full_has_zero_flip() {
    let dir = scratch("tiny");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
    let out = dir.join("out");
    let o = acuity(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--profile-resolution",
        "64",
        "--profile-viewpoints",
        "0",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "stderr: {stderr}");
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("acuity_all"), "{table}");
    for f in [
        "frames.csv",
        "summary.csv",
        "frame_time.png",
        "triangles.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let mut rows: Vec<(String, u32, u64, Option<f64>)> = Vec::new();
    for line in csv.lines().skip(1) {
        let c: Vec<&str> = line.split(',').collect();
        rows.push((
            c[0].to_owned(),
            c[1].parse().unwrap(),
            c[5].parse().unwrap(),
            c[11].parse().ok(),
        ));
    }
    let full: Vec<_> = rows.iter().filter(|r| r.0 == "full").collect();
    assert_eq!(full.len(), 4);
    assert!(full.iter().any(|r| r.2 > 0), "nothing drawn: {csv}");
    for r in rows.iter().filter(|r| r.0.starts_with("acuity")) {
        let f = full.iter().find(|f| f.1 == r.1).unwrap();
        assert!(
            r.2 <= f.2,
            "{} frame {}: {} > {} triangles",
            r.0,
            r.1,
            r.2,
            f.2
        );
    }
    let flips: Vec<f64> = full.iter().filter_map(|r| r.3).collect();
    assert_eq!(flips.len(), 2, "{csv}");
    assert!(flips.iter().all(|&f| f == 0.0), "full vs itself: {flips:?}");
}

#[test]
fn broken_object_gives_a_clear_error() {
    let dir = scratch("broken");
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let scene = TINY.replace(
        "procedural = { kind = \"rock\", triangles = [800, 200, 60] }",
        "mesh = \"broken.obj\"\ngenerate_triangles = [100, 50]",
    );
    std::fs::write(dir.join("s.toml"), scene).unwrap();
    let o = acuity(&["run", dir.join("s.toml").to_str().unwrap(), "--quiet"]);
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains("object `rocks`"), "{stderr}");
    assert!(stderr.contains("broken.obj"), "{stderr}");
}

#[test]
fn unknown_policy_and_zero_frames_are_refused() {
    let dir = scratch("bad_args");
    std::fs::write(dir.join("s.toml"), TINY).unwrap();
    let s = dir.join("s.toml");
    let o = acuity(&["run", s.to_str().unwrap(), "--policies", "fastest"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown policy `fastest`"));
    let o = acuity(&["run", s.to_str().unwrap(), "--frames", "0", "--quiet"]);
    assert!(!o.status.success());
}

#[test]
fn experiments_run_small_and_write_their_files() {
    let dir = scratch("experiments");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
    let s = scene.to_str().unwrap();
    let out = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let profile = [
        "--profile-resolution",
        "64",
        "--profile-viewpoints",
        "0",
        "--quiet",
    ];
    let runs: [(Vec<String>, &str, &str); 3] = [
        (
            [
                "experiment",
                "speedup",
                "--scene",
                s,
                "--counts",
                "3,6",
                "--trials",
                "1",
            ]
            .iter()
            .map(|x| x.to_string())
            .chain(["--frames", "2", "--out"].map(String::from))
            .chain([out("speedup")])
            .collect(),
            "speedup",
            "speedup.csv",
        ),
        (
            [
                "experiment",
                "error",
                "--scene",
                s,
                "--frames",
                "2",
                "--flip-every",
                "1",
            ]
            .iter()
            .map(|x| x.to_string())
            .chain(["--biases", "1", "--scales", "1,0.5", "--out"].map(String::from))
            .chain([out("error")])
            .collect(),
            "error",
            "error.csv",
        ),
        (
            [
                "experiment",
                "framerate",
                "--scene",
                s,
                "--frames",
                "4",
                "--target-hz",
                "60",
            ]
            .iter()
            .map(|x| x.to_string())
            .chain(["--out".to_owned(), out("framerate")])
            .collect(),
            "framerate",
            "framerate.csv",
        ),
    ];
    for (mut args, folder, csv) in runs {
        args.extend(profile.iter().map(|x| x.to_string()));
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = acuity(&refs);
        assert!(
            o.status.success(),
            "{folder}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let text = std::fs::read_to_string(dir.join(folder).join(csv)).unwrap();
        assert!(text.lines().count() > 1, "{folder}: {text}");
    }
}
