//! The command line's shared conventions, end to end: clap's full argument
//! errors with suggestions, exit code 2 for bad input and 1 for failures
//! while running, the JSON twin of the summary CSV, and plots as PNG and
//! SVG.

mod common;

use common::{acuity, run_policies, stderr};

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("conventions_cli", name)
}

#[test]
fn a_mistyped_command_gets_a_suggestion_and_the_usage() {
    let o = acuity(&["rn"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.starts_with("error: "), "{e}");
    assert!(e.contains("similar") && e.contains("'run'"), "{e}");
    assert!(e.contains("Usage:"), "{e}");
    let o = acuity(&["run", "s.toml", "--polices", "full"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("--policies"), "{e}");
}

#[test]
fn a_missing_argument_is_named() {
    let o = acuity(&["run"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("required") && e.contains("<SCENE>"), "{e}");
    assert!(e.contains("Usage: acuity run"), "{e}");
}

#[test]
fn help_goes_to_stdout_and_succeeds() {
    let o = acuity(&["run", "--help"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("Usage: acuity run"));
}

const CSV: &str = "policy,frames,ms\nfull,1,2.0\nfull,2,NaN\nfull,3,2.5\nacuity,1,1.0\nacuity,2,\n";

#[test]
fn bad_input_exits_2_and_a_failure_while_running_exits_1_each_printed_once() {
    let dir = scratch("codes");
    let csv = dir.join("t.csv");
    std::fs::write(&csv, CSV).unwrap();
    let csv = csv.to_str().unwrap();
    let png = dir.join("t.png");
    let png = png.to_str().unwrap();
    // Input: a column the CSV does not have, a CSV that is not there, a
    // scene or image that does not exist, bad values the commands check.
    let missing_scene = dir.join("none.toml");
    let missing_image = dir.join("none.png");
    for args in [
        vec!["plot", csv, "--x", "frames", "--y", "nope", "--out", png],
        vec!["plot", "no/such.csv", "--x", "a", "--y", "b", "--out", png],
        vec!["run", missing_scene.to_str().unwrap(), "--quiet"],
        vec!["acuity", "--scale", "2"],
        vec![
            "blur",
            missing_image.to_str().unwrap(),
            "--fov",
            "150x100",
            "--gaze",
            "1,1",
            "--out",
            png,
        ],
        vec!["terrain", "--duration", "0", "--out", png],
    ] {
        let o = acuity(&args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
        assert!(e.starts_with("error: "), "{args:?}: {e}");
    }
    // Running: the output folder cannot be written (a file is in the way).
    std::fs::write(dir.join("file"), "").unwrap();
    let blocked = dir.join("file").join("t.png");
    let o = acuity(&[
        "plot",
        csv,
        "--x",
        "frames",
        "--y",
        "ms",
        "--out",
        blocked.to_str().unwrap(),
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert_eq!(e.matches("os error").count(), 1, "{e}");
}

#[test]
fn plot_writes_png_and_svg_and_skips_rows_without_numbers() {
    let dir = scratch("plot");
    let csv = dir.join("t.csv");
    std::fs::write(&csv, CSV).unwrap();
    let png = dir.join("t.png");
    let o = acuity(&[
        "plot",
        csv.to_str().unwrap(),
        "--x",
        "frames",
        "--y",
        "ms",
        "--group",
        "policy",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (900, 500));
    let svg = std::fs::read_to_string(dir.join("t.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{svg}");
    for text in ["full", "acuity", "frames", "ms against frames"] {
        assert!(svg.contains(text), "{text} missing from the SVG");
    }
    assert!(
        stderr(&o).contains("2 rows without numbers"),
        "{}",
        stderr(&o)
    );
}

/// The shared tiny scene, smaller still: 96x72 pixels, 4 rocks of two
/// LODs, 3 frames, no FLIP.
fn tiny() -> String {
    common::TINY_SCENE
        .replace("[160, 120]", "[96, 72]")
        .replace("[800, 200, 60]", "[400, 100]")
        .replace("count = 12", "count = 4")
        .replace("frames = 4", "frames = 3")
        .replace("flip_every_n_frames = 2", "flip_every_n_frames = 0")
}

#[test]
fn a_run_writes_its_summary_as_json_beside_the_csv_and_plots_as_svg() {
    let dir = scratch("summary");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, tiny()).unwrap();
    let out = dir.join("out");
    let o = run_policies(&scene, &out, "full,screen_size,acuity_all", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), csv.lines().count() - 1);
    assert_eq!(rows.len(), 3);
    for (row, line) in rows.iter().zip(csv.lines().skip(1)) {
        let row = row.as_object().unwrap();
        let mut keys: Vec<&str> = row.keys().map(String::as_str).collect();
        let mut columns = header.clone();
        keys.sort_unstable();
        columns.sort_unstable();
        assert_eq!(keys, columns);
        assert_eq!(row["policy"], line.split(',').next().unwrap());
        assert!(row["mean_ms"].as_f64().unwrap() > 0.0);
        assert!(row["jod"].is_null());
    }
    for plot in ["frame_time", "triangles", "scale"] {
        assert!(out.join(format!("{plot}.png")).is_file(), "{plot}.png");
        assert!(out.join(format!("{plot}.svg")).is_file(), "{plot}.svg");
    }
    // --quiet: no progress bar and no chatter on stderr.
    assert_eq!(stderr(&o), "");
}
