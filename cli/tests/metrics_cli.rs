//! `acuity experiment` and the frame dumps and FovVideoVDP scores of `acuity
//! run` and `acuity experiment error` end to end on a tiny scene (160x120,
//! 12 objects, a few frames, coarse profiles), with a fake Python where
//! the metric's script is only observed.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{COARSE, TINY_SCENE as TINY, acuity, run_policies, tiny_scene};

fn scratch(name: &str) -> PathBuf {
    common::scratch("metrics_cli", name)
}

#[test]
fn experiments_run_small_and_write_their_files() {
    let dir = scratch("experiments");
    let scene = tiny_scene(&dir);
    let s = scene.to_str().unwrap();
    let out = |name: &str| dir.join(name).to_str().unwrap().to_owned();
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
            .chain([
                out("speedup"),
                "--dump-frames".into(),
                out("speedup-frames"),
            ])
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
            .chain(
                [
                    "--biases",
                    "0.25,1",
                    "--scales",
                    "1,0.5",
                    "--matched",
                    "--out",
                ]
                .map(String::from),
            )
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
                "--screen-size-periods",
                "0.9,1.1",
                "--min-scale",
                "0.25",
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
        args.extend(COARSE.iter().map(|x| x.to_string()));
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
    // The frame-rate experiment's schedulers' table: one row per policy,
    // screen size under the same controller and the controllers before
    // headroom among them.
    let held =
        std::fs::read_to_string(dir.join("framerate").join("framerate_summary.csv")).unwrap();
    let mut rows = held.lines();
    let header = rows.next().unwrap();
    assert!(
        header.starts_with(
            "policy,over_outside_spikes,over_settled,over_in_spikes,unreachable_in_spikes"
        ),
        "{held}"
    );
    // The floor against the aim once settled, and the slow reversals.
    for column in [
        "floor_above_aim_settled",
        "over_settled_with_room",
        "lod_slow_reversals_per_s",
    ] {
        assert!(header.split(',').any(|c| c == column), "{column}: {held}");
    }
    let frames = std::fs::read_to_string(dir.join("framerate").join("framerate.csv")).unwrap();
    let frame_header = frames.lines().next().unwrap();
    for column in ["cost_floor_ms", "aim_ms", "lod_slow_reversals"] {
        assert!(
            frame_header.split(',').any(|c| c == column),
            "{column}: {frame_header}"
        );
    }
    let names: Vec<&str> = rows.map(|r| r.split(',').next().unwrap()).collect();
    for p in [
        "acuity_reactive",
        "acuity_reactive_pooled",
        "acuity_predictive",
        "screen_size_reactive",
        "acuity_reactive_no_headroom",
        "acuity_predictive_no_headroom",
        "screen_size_reactive_period_0.9",
        "screen_size_reactive_period_1.1",
    ] {
        assert!(names.contains(&p), "{p} missing: {held}");
    }
    // Screen size's controller told 1.1 times the period aims 1.1 times
    // as long in its first frame (before it has seen the frames vary).
    let first_aim_ms = |policy: &str| -> f64 {
        let row = frames
            .lines()
            .find(|r| r.split(',').next() == Some(policy))
            .unwrap_or_else(|| panic!("{policy}: {frames}"));
        let column = frame_header.split(',').position(|c| c == "aim_ms").unwrap();
        row.split(',').nth(column).unwrap().parse().unwrap()
    };
    let ratio =
        first_aim_ms("screen_size_reactive_period_1.1") / first_aim_ms("screen_size_reactive");
    assert!((ratio - 1.1).abs() < 1e-3, "{ratio}");
    // `--min-scale` floors every controller: the reactive ones start at
    // it (0.25 instead of the default 1e-3) and never go below.
    let scales = |policy: &str| -> Vec<f64> {
        let column = frame_header.split(',').position(|c| c == "scale").unwrap();
        frames
            .lines()
            .filter(|r| r.split(',').next() == Some(policy))
            .map(|r| r.split(',').nth(column).unwrap().parse().unwrap())
            .collect()
    };
    for policy in ["acuity_reactive", "screen_size_reactive"] {
        let floored = scales(policy);
        assert!(
            !floored.is_empty() && floored[0] == 0.25 && floored.iter().all(|&s| s >= 0.25),
            "{policy}: {floored:?}"
        );
    }
    // Best effort under screen size's triangles of each frame draws no
    // more than screen size at the same bias (over the just-imperceptible
    // settings too), and fewer than acuity at `s = 1` where that bias
    // draws fewer.
    let error = std::fs::read_to_string(dir.join("error").join("error.csv")).unwrap();
    let header: Vec<&str> = error.lines().next().unwrap().split(',').collect();
    let tris_at = header.iter().position(|&h| h == "triangles").unwrap();
    let triangles = |policy: &str, knob: &str| -> f64 {
        let row = error
            .lines()
            .map(|l| l.split(',').collect::<Vec<_>>())
            .find(|r| r[0] == policy && r[1] == knob)
            .unwrap_or_else(|| panic!("{policy} {knob}: {error}"));
        row[tris_at].parse().unwrap()
    };
    for bias in ["0.25", "1"] {
        let screen = triangles("screen_size", bias);
        for matched in [
            "acuity_best_effort_matched",
            "acuity_best_effort_matched_pooled",
        ] {
            assert!(
                triangles(matched, bias) <= screen + 1e-9,
                "{matched} at bias {bias}: {error}"
            );
        }
    }
    assert!(
        triangles("acuity_best_effort_matched", "0.25") < triangles("acuity_all", "1"),
        "{error}"
    );
    // Speedup dumps per N and trial.
    for n in ["n0003_trial0", "n0006_trial0"] {
        let trial = dir.join("speedup-frames").join(n);
        assert!(trial.join("display.json").is_file(), "{n}");
        for seq in [
            "full_1",
            "acuity_all_1",
            "acuity_ecc_vel_1",
            "acuity_all_pooled_1",
        ] {
            check_sequence(&trial.join(seq), 2);
        }
    }
}

fn acuity_with_python(args: &[&str], python: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_acuity"))
        .args(args)
        .env("ACUITY_PYTHON", python)
        .output()
        .expect("run acuity")
}

/// Width, height and colour type (2 = RGB) from a PNG's IHDR chunk.
fn png_header(path: &Path) -> (u32, u32, u8) {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert_eq!(&b[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20), b[25])
}

/// Checks one dumped sequence: `frames` RGB PNGs of 160x120 and a gaze.csv
/// with a row per frame; returns the gaze rows.
fn check_sequence(dir: &Path, frames: u32) -> Vec<(u32, f64, f64)> {
    let pngs = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension() == Some("png".as_ref()))
        .count();
    assert_eq!(pngs, frames as usize, "{}", dir.display());
    for k in 0..frames {
        let png = dir.join(format!("{k:04}.png"));
        assert_eq!(png_header(&png), (160, 120, 2), "{}", png.display());
    }
    let csv = std::fs::read_to_string(dir.join("gaze.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("frame,x_px,y_px"));
    let rows: Vec<(u32, f64, f64)> = lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            assert_eq!(c.len(), 3, "{l}");
            (
                c[0].parse().unwrap(),
                c[1].parse().unwrap(),
                c[2].parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        (0..frames).collect::<Vec<_>>()
    );
    rows
}

/// `acuity run` of `scene`'s first 3 frames under `policies`, at the
/// coarse profile settings, dumping the frames to `dump`.
fn run_dumping(scene: &Path, out: &Path, dump: &Path, policies: &str) -> std::process::Output {
    run_policies(
        scene,
        out,
        policies,
        &["--frames", "3", "--dump-frames", dump.to_str().unwrap()],
    )
}

#[test]
fn dump_frames_writes_every_sequence_with_gaze_and_display() {
    let dir = scratch("dump");
    let scene = tiny_scene(&dir);
    let dump = dir.join("frames");
    // No `full`: its frames are dumped as the reference anyway.
    let o = run_dumping(&scene, &dir.join("out"), &dump, "screen_size,acuity_size");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut folders: Vec<String> = std::fs::read_dir(&dump)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    folders.sort();
    assert_eq!(folders, ["acuity_size_1", "full_1", "screen_size_1"]);
    for f in &folders {
        // The gaze is at the screen centre.
        for (k, x, y) in check_sequence(&dump.join(f), 3) {
            assert!(
                (x - 80.0).abs() < 1e-3 && (y - 60.0).abs() < 1e-3,
                "{f} {k}: {x},{y}"
            );
        }
    }
    let display: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dump.join("display.json")).unwrap()).unwrap();
    assert_eq!(display["resolution"], serde_json::json!([160, 120]));
    assert_eq!(display["fov_deg"], serde_json::json!([43.6, 33.4]));
    // 4 frames over 1 s in the scene, 3 with --frames: 3 Hz.
    let fps = display["fps"].as_f64().unwrap();
    assert!((fps - 3.0).abs() < 1e-9, "{fps}");
    for key in ["peak_cd_m2", "contrast", "ambient_lux"] {
        assert!(display[key].as_f64().unwrap() > 0.0, "{key}: {display}");
    }
    let mut sequences: Vec<&str> = display["sequences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    sequences.sort();
    assert_eq!(sequences, folders);
}

#[test]
fn the_viewers_object_moves_the_dumped_fixation_and_not_the_selection() {
    let dir = scratch("viewer_object");
    let run = |name: &str, gaze: &str| {
        let scene = dir.join(format!("{name}.toml"));
        // Foveated screen size: a selection that depends on the gaze.
        let text = TINY.replace("mode = \"screen_centre\"", gaze).replace(
            "flip_every_n_frames = 2",
            "flip_every_n_frames = 2\nscreen_size_foveated = true",
        );
        std::fs::write(&scene, text).unwrap();
        let dump = dir.join(name);
        let o = run_dumping(
            &scene,
            &dir.join(format!("{name}-out")),
            &dump,
            "screen_size",
        );
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        dump
    };
    let modelled = run("modelled", "mode = \"screen_centre\"\ntracker = \"head\"");
    let viewer = run(
        "viewer",
        "mode = \"screen_centre\"\ntracker = \"head\"\nviewer_object = \"rocks\"\nviewer_copy = 2",
    );
    let tracked = run(
        "tracked",
        "mode = \"track\"\nobject = \"rocks\"\ncopy = 2\ntracker = \"head\"",
    );
    let gaze = |dump: &Path| check_sequence(&dump.join("screen_size_1"), 3);
    // The fixation is the rock's, as if the selector tracked it...
    assert_eq!(gaze(&viewer), gaze(&tracked));
    assert_ne!(gaze(&viewer), gaze(&modelled));
    // ...while the selection is the modelled gaze's: the same frames,
    // where the tracked gaze's selection differs.
    let frame = |dump: &Path, k: u32| {
        std::fs::read(dump.join(format!("screen_size_1/{k:04}.png"))).unwrap()
    };
    for k in 0..3 {
        assert!(frame(&viewer, k) == frame(&modelled, k), "frame {k}");
    }
    assert!((0..3).any(|k| frame(&tracked, k) != frame(&modelled, k)));
}

#[test]
fn fvvdp_without_a_python_is_a_clear_error() {
    let dir = scratch("fvvdp_no_python");
    std::fs::write(dir.join("s.toml"), TINY).unwrap();
    let s = dir.join("s.toml");
    let nowhere = dir.join("no-such-python");
    let o = acuity_with_python(
        &["run", s.to_str().unwrap(), "--metric", "fvvdp", "--quiet"],
        &nowhere,
    );
    // The metric cannot run here: a failure, not bad input.
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains("no-such-python"), "{stderr}");
    assert!(stderr.contains("pip install pyfvvdp"), "{stderr}");
}

/// A stand-in for Python with pyfvvdp (the script arrives on stdin and is
/// ignored): `--check` passes; scoring prints a log line, then a fixed JOD
/// per sequence folder of the dump (`$2`), and for three of them a local
/// 99.9th percentile; `exit_code` other than 0 fails.
#[cfg(unix)]
fn fake_python(dir: &Path, exit_code: i32) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let path = dir.join(format!("fake-python-{exit_code}"));
    let script = format!(
        r#"#!/bin/sh
[ {exit_code} -ne 0 ] && {{ echo "fake failure" >&2; exit {exit_code}; }}
[ "$2" = "--check" ] && exit 0
echo "scoring $2"
out="{{"; sep=""
for d in "$2"/*/; do
  n=$(basename "$d")
  l=""
  case "$n" in
    full_1) j=10 ;;
    screen_size_0.5) j=8.5; l=1.2 ;;
    screen_size_2) j=9.5; l=0.4 ;;
    acuity_size_1) j=9.25; l=0.5 ;;
    *) j=8 ;;
  esac
  out="$out$sep\"$n\": $j"; sep=", "
  [ -n "$l" ] && out="$out, \"$n:local_p999\": $l"
done
echo "$out}}"
"#
    );
    std::fs::write(&path, script).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

#[cfg(unix)]
#[test]
fn fvvdp_scores_from_the_script_reach_table_csv_and_plots() {
    let dir = scratch("fvvdp_fake");
    let scene = tiny_scene(&dir);
    let s = scene.to_str().unwrap();
    let python = fake_python(&dir, 0);

    // `acuity run`: frames go to <out>/frames without --dump-frames.
    let out = dir.join("run");
    let mut args = vec![
        "run",
        s,
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "2",
        "--policies",
        "full,screen_size,acuity_size",
        "--metric",
        "flip,fvvdp",
    ];
    args.extend(COARSE);
    let o = acuity_with_python(&args, &python);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.lines().next().unwrap().contains("JOD"), "{table}");
    assert!(out.join("frames/full_1/0001.png").is_file());
    assert!(out.join("frames/fvvdp.json").is_file());
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|&h| h == "jod").expect("jod column");
    let jod: Vec<(String, f64)> = summary
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[0].to_owned(), c[col].parse().unwrap())
        })
        .collect();
    assert_eq!(
        jod,
        [
            ("full".to_owned(), 10.0),
            ("screen_size".to_owned(), 8.0),
            ("acuity_size".to_owned(), 9.25)
        ]
    );

    // `acuity experiment error`: JOD columns, the comparison at equal JOD
    // (acuity_size at s = 1 is between the two screen-size points), a plot.
    let out = dir.join("error");
    let mut args = vec![
        "experiment",
        "error",
        "--scene",
        s,
        "--frames",
        "2",
        "--biases",
        "0.5,2",
        "--scales",
        "1,0.5",
        "--acuity-policies",
        "acuity_size",
        "--metric",
        "fvvdp",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(COARSE);
    let o = acuity_with_python(&args, &python);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("error_jod.png").is_file());
    assert!(
        !out.join("error_triangles.png").exists(),
        "no FLIP, no FLIP plot"
    );
    let csv = std::fs::read_to_string(out.join("error.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |h: &str| header.iter().position(|&x| x == h).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let row = |policy: &str, knob: &str| {
        rows.iter()
            .find(|r| r[0] == policy && r[1] == knob)
            .unwrap_or_else(|| panic!("{policy} {knob}: {csv}"))
    };
    let tris = |r: &Vec<&str>| r[at("triangles")].parse::<f64>().unwrap();
    let (lo, hi) = (row("screen_size", "0.5"), row("screen_size", "2"));
    let acuity = row("acuity_size", "1");
    assert_eq!(acuity[at("jod")], "9.2500");
    // JOD 9.25 is 3/4 of the way from 8.5 to 9.5: log-linear in triangles.
    let expect = tris(acuity) / (tris(lo) * (tris(hi) / tris(lo)).powf(0.75));
    let got: f64 = acuity[at("triangles_vs_screen_size_jod")].parse().unwrap();
    assert!(
        (got - expect).abs() < 1e-3 * expect.max(1.0),
        "{got} vs {expect}: {csv}"
    );
    // JOD 8 is below the screen-size curve's range: not compared.
    assert_eq!(
        row("acuity_size", "0.5")[at("triangles_vs_screen_size_jod")],
        ""
    );
    // Screen size's local maximum at the same JOD: linear in JOD, 3/4 of
    // the way from 1.2 to 0.4; none below the curve or for screen size.
    assert_eq!(acuity[at("jod_local_p999")], "0.5000");
    assert_eq!(acuity[at("screen_size_jod_local_p999")], "0.6000");
    assert_eq!(
        row("acuity_size", "0.5")[at("screen_size_jod_local_p999")],
        ""
    );
    assert_eq!(lo[at("screen_size_jod_local_p999")], "");
}

#[cfg(unix)]
#[test]
fn fvvdp_failures_say_why() {
    let dir = scratch("fvvdp_fail");
    let scene = tiny_scene(&dir);
    let out = dir.join("out");
    let run = |python: &Path| {
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--frames",
            "1",
            "--policies",
            "screen_size",
            "--metric",
            "fvvdp",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(COARSE);
        let o = acuity_with_python(&args, python);
        assert_eq!(o.status.code(), Some(1));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    // The script's exit code 3: pyfvvdp does not import.
    let stderr = run(&fake_python(&dir, 3));
    assert!(stderr.contains("pyfvvdp is not installed"), "{stderr}");
    assert!(stderr.contains("pip install pyfvvdp"), "{stderr}");
    // Any other failure: the script's last line.
    let stderr = run(&fake_python(&dir, 1));
    assert!(stderr.contains("fake failure"), "{stderr}");
}

#[test]
fn fixed_budgets_are_one_count_for_every_frame_from_full_details_mean() {
    let dir = scratch("fixed_budgets");
    let scene = tiny_scene(&dir);
    let out = dir.join("error");
    let mut args = vec![
        "experiment",
        "error",
        "--scene",
        scene.to_str().unwrap(),
        "--frames",
        "4",
        "--flip-every",
        "1000",
        "--biases",
        "1",
        "--scales",
        "1",
        "--acuity-policies",
        "acuity_all",
        "--budgets",
        "0.5",
        "--fixed-budgets",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(COARSE);
    let o = acuity(&args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let error = std::fs::read_to_string(out.join("error.csv")).unwrap();
    let header: Vec<&str> = error.lines().next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|&h| h == name).unwrap();
    let value = |policy: &str, name: &str| -> f64 {
        error
            .lines()
            .map(|l| l.split(',').collect::<Vec<_>>())
            .find(|r| r[0] == policy)
            .unwrap_or_else(|| panic!("{policy}: {error}"))[column(name)]
        .parse()
        .unwrap()
    };
    // The count is full detail's mean triangles in view, said on stderr.
    let full_mean = value("full", "triangles");
    let said: f64 = stderr
        .split("budgets fixed at their share of ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no fixed count said: {stderr}"));
    assert!(
        (said - full_mean).abs() <= 0.5,
        "{said} against {full_mean}"
    );
    // No frame of a budgeted policy draws more than half of it.
    for policy in [
        "acuity_best_effort",
        "acuity_best_effort_pooled",
        "acuity_budget_uniform",
    ] {
        let most = value(policy, "triangles_max");
        assert!(
            most <= (0.5 * full_mean).floor(),
            "{policy}: {most} in a frame against a budget of {}",
            0.5 * full_mean
        );
    }
    // Without budgets to fix the flag is refused, naming what is missing.
    let mut bare = args.clone();
    bare.retain(|&a| a != "--budgets" && a != "0.5");
    let o = acuity(&bare);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .contains("--fixed-budgets fixes the budgets of --budgets"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
