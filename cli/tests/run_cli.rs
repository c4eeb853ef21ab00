//! `acuity run` end to end on a tiny scene (160x120, 12 objects, a few
//! frames, coarse profiles), and its error on a broken object.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{COARSE, TINY_SCENE as TINY, acuity, coarse};

fn scratch(name: &str) -> PathBuf {
    common::scratch("run_cli", name)
}

#[test]
fn tiny_run_never_draws_more_than_full_detail_and_full_has_zero_flip() {
    let dir = scratch("tiny");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
    let out = dir.join("out");
    let o = acuity(&coarse(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]));
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
            c[12].parse().ok(),
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

/// Triangles per (policy, frame) of a run's frames.csv.
fn triangles_by_frame(out: &Path) -> Vec<(String, u32, u64)> {
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    csv.lines()
        .skip(1)
        .map(|line| {
            let c: Vec<&str> = line.split(',').collect();
            (
                c[0].to_owned(),
                c[1].parse().unwrap(),
                c[5].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn cross_fades_draw_the_lod_going_as_well_and_leave_the_choices_alone() {
    let dir = scratch("cross_fade");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--frames",
            "16",
            "--policies",
            "screen_size,acuity_all",
            "--cache-dir",
            dir.to_str().unwrap(),
        ];
        args.extend(COARSE);
        args.extend_from_slice(extra);
        let o = acuity(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        triangles_by_frame(&out)
    };
    let plain = run("off", &[]);
    let faded = run("on", &["--cross-fade-s", "0.5"]);
    assert_eq!(plain.len(), faded.len());
    let mut more = 0;
    for (p, f) in plain.iter().zip(&faded) {
        assert_eq!((&p.0, p.1), (&f.0, f.1));
        assert!(f.2 >= p.2, "{f:?} draws less than {p:?}");
        more += usize::from(f.2 > p.2);
    }
    assert!(more > 0, "no frame drew a fading LOD: {faded:?}");
    let o = acuity(&["run", scene.to_str().unwrap(), "--cross-fade-s", "11"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--cross-fade-s") && stderr.contains("0..=10"),
        "{stderr}"
    );
}

#[test]
fn a_single_lod_object_parses_loads_and_is_always_drawn_whole() {
    let dir = scratch("single_lod");
    let scene = dir.join("single.toml");
    let text = TINY.replace(
        "[camera]",
        "[[objects]]\nname = \"single\"\nprocedural = { kind = \"rock\", triangles = [500] }\n\
         transform = { position = [0.0, 0.0, -5.0] }\n\n[camera]",
    );
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let o = acuity(&coarse(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--policies",
        "full,screen_size,acuity_all",
    ]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    for line in csv.lines().skip(1) {
        let triangles: u64 = line.split(',').nth(5).unwrap().parse().unwrap();
        assert!(triangles >= 500, "the single LOD went missing: {line}");
    }
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
    // A frame count that would need gigabytes is refused up front (it
    // used to abort allocating), on the command line and in the scene.
    for args in [
        vec!["run", s.to_str().unwrap(), "--frames", "4294967295"],
        vec![
            "experiment",
            "error",
            "--scene",
            s.to_str().unwrap(),
            "--frames",
            "4294967295",
        ],
    ] {
        let o = acuity(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("10000000"),
            "{args:?}"
        );
    }
    let huge = TINY.replace("frames = 4", "frames = 4294967295");
    std::fs::write(dir.join("huge.toml"), huge).unwrap();
    let o = acuity(&["run", dir.join("huge.toml").to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("run.frames"));
}

#[test]
fn out_of_range_arguments_exit_2_naming_the_limit() {
    // Clap's errors come whole (error, usage); the commands' in one line.
    let cases: [(&[&str], &str); 10] = [
        (&["acuity", "--velocity", "nan"], "--velocity"),
        (&["acuity", "--velocity=-1"], "--velocity"),
        (&["acuity", "--eccentricity=-10"], "--eccentricity"),
        (&["acuity", "--eccentricity", "inf"], "--eccentricity"),
        (&["acuity", "--scale", "nan"], "scale"),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--spike-load",
                "1e6",
            ],
            "0..=10",
        ),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--target-hz",
                "1e-300",
            ],
            "10000",
        ),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--target-hz",
                "1e-40",
            ],
            "10000",
        ),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--screen-size-bias",
                "0",
            ],
            "--screen-size-bias",
        ),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--metric",
                "flip",
            ],
            "--metric",
        ),
    ];
    for (args, says) in cases {
        let o = acuity(args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        let first = stderr.lines().next().unwrap_or_default();
        assert!(first.starts_with("error: "), "{args:?}: {stderr}");
        assert!(first.contains(says), "{args:?}: {stderr}");
    }
    let o = acuity(&["acuity", "--velocity", "10", "--eccentricity", "10"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn names_sharing_a_profile_file_are_refused_as_by_preprocess() {
    let dir = scratch("same_file");
    let scene = TINY.replace(
        "[camera]",
        "[[objects]]\nname = \"a b\"\nprocedural = { kind = \"rock\", triangles = [80, 20] }\n\n\
         [[objects]]\nname = \"a_b\"\nprocedural = { kind = \"rock\", triangles = [80, 20] }\n\n[camera]",
    );
    let s = dir.join("s.toml");
    std::fs::write(&s, scene).unwrap();
    let cache = dir.join("cache");
    for command in ["run", "preprocess"] {
        let mut args = vec![command, s.to_str().unwrap()];
        args.extend(match command {
            "run" => ["--cache-dir", cache.to_str().unwrap(), "--quiet"],
            _ => ["--out", cache.to_str().unwrap(), "--force"],
        });
        let o = acuity(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command}: {stderr}");
        assert!(
            stderr.contains("objects `a b` and `a_b` would share the profile file"),
            "{command}: {stderr}"
        );
    }
    assert!(!cache.join("a_b.acp").exists());
}

#[test]
fn work_that_cannot_fit_in_memory_is_refused_before_it_starts() {
    let dir = scratch("memory");
    // 10M frames with a 1024x1024 reference image every frame: 40 TiB.
    let scene = TINY
        .replace("resolution = [160, 120]", "resolution = [1024, 1024]")
        .replace(
            "frames = 4\nflip_every_n_frames = 2",
            "frames = 10000000\nflip_every_n_frames = 1",
        );
    let s = dir.join("s.toml");
    std::fs::write(&s, scene).unwrap();
    let cache = dir.join("cache");
    let o = acuity_within(
        &coarse(&[
            "run",
            s.to_str().unwrap(),
            "--cache-dir",
            cache.to_str().unwrap(),
            "--policies",
            "full,screen_size",
        ]),
        300,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    assert!(
        stderr.contains("10000000 frames x 2 policies at 1024x1024 pixels needs about"),
        "{stderr}"
    );
}

/// Runs `acuity` and fails the test if it has not finished in `limit_s`.
fn acuity_within(args: &[&str], limit_s: u64) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_acuity"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run acuity");
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() > limit_s {
            let _ = child.kill();
            panic!("{args:?} still running after {limit_s} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
#[test]
fn unusable_cached_profiles_are_replaced_with_a_warning_and_io_errors_print_once() {
    let dir = scratch("bad_cache");
    let objects = ["corrupt", "fifo", "device", "folder"]
        .map(|name| {
            format!(
                "[[objects]]\nname = \"{name}\"\nprocedural = {{ kind = \"rock\", triangles = [80, 20] }}\n"
            )
        })
        .concat();
    let scene = TINY.replace(
        "[[objects]]\nname = \"rocks\"\nprocedural = { kind = \"rock\", triangles = [800, 200, 60] }\n\
         copies = { count = 12, seed = 3, volume_min = [-4.0, -1.0, -20.0], volume_max = [4.0, 1.0, -3.0], random_rotation = true, scale = 0.5 }\n",
        &objects,
    );
    assert_ne!(scene, TINY);
    let s = dir.join("s.toml");
    std::fs::write(&s, scene).unwrap();
    let cache = dir.join("cache");
    std::fs::create_dir_all(cache.join("folder.acp")).unwrap();
    std::fs::write(cache.join("corrupt.acp"), b"GARBAGE").unwrap();
    std::os::unix::fs::symlink("/dev/zero", cache.join("device.acp")).unwrap();
    let made = Command::new("mkfifo")
        .arg(cache.join("fifo.acp"))
        .status()
        .unwrap();
    assert!(made.success());
    let o = acuity_within(
        &coarse(&[
            "run",
            s.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
            "--cache-dir",
            cache.to_str().unwrap(),
        ]),
        300,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    // Replacing the folder fails while running: exit 1, not bad input.
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    for name in ["corrupt", "fifo", "device", "folder"] {
        let warning = stderr
            .lines()
            .find(|l| l.starts_with("warning: ") && l.contains(&format!("{name}.acp")));
        assert!(warning.is_some(), "no warning for {name}: {stderr}");
    }
    assert!(stderr.contains("is corrupt"), "{stderr}");
    // The three files replaced were regular files before the folder's
    // rename failed.
    for name in ["corrupt", "fifo", "device"] {
        let p = cache.join(format!("{name}.acp"));
        assert!(std::fs::symlink_metadata(&p).unwrap().is_file(), "{name}");
        acuity::Profile::load(&p).unwrap();
    }
    let error = stderr.lines().find(|l| l.starts_with("error: ")).unwrap();
    assert!(error.contains("folder.acp"), "{stderr}");
    let cause = std::io::Error::from(std::io::ErrorKind::IsADirectory).to_string();
    assert_eq!(error.matches("os error").count(), 1, "{error} ({cause})");
}

#[test]
fn a_positive_scale_too_small_for_f32_is_the_coarsest_not_full_detail() {
    let dir = scratch("tiny_scale");
    let s = dir.join("s.toml");
    std::fs::write(
        &s,
        TINY.replace("frames = 4", "frames = 2\nscale_factor = 1e-46"),
    )
    .unwrap();
    let out = dir.join("out");
    let o = acuity(&coarse(&[
        "run",
        s.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--policies",
        "full,acuity_size",
        "--cache-dir",
        dir.join("cache").to_str().unwrap(),
    ]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let tris = |policy: &str| -> f64 {
        let line = csv.lines().find(|l| l.starts_with(policy)).unwrap();
        line.split(',').nth(3).unwrap().parse().unwrap()
    };
    assert!(tris("acuity_size") < tris("full"), "{csv}");
}

#[test]
fn experiments_run_small_and_write_their_files() {
    let dir = scratch("experiments");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
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
    assert!(
        rows.next()
            .unwrap()
            .starts_with("policy,over_outside_spikes,over_in_spikes,unreachable_in_spikes"),
        "{held}"
    );
    let names: Vec<&str> = rows.map(|r| r.split(',').next().unwrap()).collect();
    for p in [
        "acuity_reactive",
        "acuity_predictive",
        "screen_size_reactive",
        "acuity_reactive_no_headroom",
        "acuity_predictive_no_headroom",
    ] {
        assert!(names.contains(&p), "{p} missing: {held}");
    }
    // Speedup dumps per N and trial.
    for n in ["n0003_trial0", "n0006_trial0"] {
        let trial = dir.join("speedup-frames").join(n);
        assert!(trial.join("display.json").is_file(), "{n}");
        for seq in ["full_1", "acuity_all_1", "acuity_ecc_vel_1"] {
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
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "3",
        "--policies",
        policies,
        "--dump-frames",
        dump.to_str().unwrap(),
    ];
    args.extend(COARSE);
    acuity(&args)
}

#[test]
fn dump_frames_writes_every_sequence_with_gaze_and_display() {
    let dir = scratch("dump");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
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
/// per sequence folder of the dump (`$2`); `exit_code` other than 0 fails.
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
  case "$n" in
    full_1) j=10 ;;
    screen_size_0.5) j=8.5 ;;
    screen_size_2) j=9.5 ;;
    acuity_size_1) j=9.25 ;;
    *) j=8 ;;
  esac
  out="$out$sep\"$n\": $j"; sep=", "
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
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
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
}

#[cfg(unix)]
#[test]
fn fvvdp_failures_say_why() {
    let dir = scratch("fvvdp_fail");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
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
