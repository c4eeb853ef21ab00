//! `acuity run` end to end on a tiny scene (160x120, 12 objects, a few
//! frames, coarse profiles), and its error on a broken object.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{COARSE, TINY_SCENE as TINY, acuity, coarse, run_policies, tiny_scene};

fn scratch(name: &str) -> PathBuf {
    common::scratch("run_cli", name)
}

#[test]
fn tiny_run_never_draws_more_than_full_detail_and_full_has_zero_flip() {
    let dir = scratch("tiny");
    let scene = tiny_scene(&dir);
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
    // Under the table, what its columns mean and where the fair
    // comparison lives.
    assert!(table.contains("tri x: full detail's"), "{table}");
    assert!(table.contains("experiment error --metric fvvdp"), "{table}");
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

/// `acuity run` of `scene` (coarse profiles cached in `dir`) for `frames`
/// frames under `policies`, with `extra` flags, into `dir/name`: the
/// triangles per (policy, frame).
fn run_triangles(
    dir: &Path,
    scene: &Path,
    name: &str,
    frames: &str,
    policies: &str,
    extra: &[&str],
) -> Vec<(String, u32, u64)> {
    let out = dir.join(name);
    let flags = [
        &["--frames", frames, "--cache-dir", dir.to_str().unwrap()],
        extra,
    ]
    .concat();
    let o = run_policies(scene, &out, policies, &flags);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    triangles_by_frame(&out)
}

#[test]
fn cross_fades_draw_the_lod_going_as_well_and_leave_the_choices_alone() {
    let dir = scratch("cross_fade");
    let scene = tiny_scene(&dir);
    let run = |name: &str, extra: &[&str]| {
        run_triangles(&dir, &scene, name, "16", "screen_size,acuity_all", extra)
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
fn an_objects_screen_size_bias_multiplies_the_runs() {
    let dir = scratch("object_bias");
    let run = |name: &str, text: String| {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text).unwrap();
        run_triangles(&dir, &scene, name, "8", "screen_size", &[])
    };
    let on_object = TINY.replace(
        "scale = 0.5 }\n",
        "scale = 0.5 }\nscreen_size_bias = 0.25\n",
    );
    assert_ne!(on_object, TINY);
    let plain = run("plain", TINY.to_owned());
    let object = run("object", on_object);
    let whole_run = run(
        "run",
        TINY.replace("[run]\n", "[run]\nscreen_size_bias = 0.25\n"),
    );
    assert_eq!(object, whole_run, "one object's bias is the run's for it");
    assert!(
        object.iter().zip(&plain).all(|(o, p)| o.2 <= p.2),
        "{object:?} against {plain:?}"
    );
    assert!(object.iter().zip(&plain).any(|(o, p)| o.2 < p.2));
}

#[test]
fn the_object_bias_flag_overrides_the_scene_and_names_what_is_wrong() {
    let dir = scratch("object_bias_flag");
    let error_csv = |name: &str, scene_text: &str, extra: &[&str]| {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, scene_text).unwrap();
        let out = dir.join(name);
        let mut args = vec![
            "experiment",
            "error",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--frames",
            "4",
            "--biases",
            "1",
            "--scales",
            "1",
            "--acuity-policies",
            "acuity_all",
            "--flip-every",
            "1000",
            "--cache-dir",
            dir.to_str().unwrap(),
        ];
        args.extend(COARSE);
        args.extend_from_slice(extra);
        let o = acuity(&args);
        (o.status.code(), common::stderr(&o), out.join("error.csv"))
    };
    let keyed = TINY.replace(
        "scale = 0.5 }\n",
        "scale = 0.5 }\nscreen_size_bias = 0.25\n",
    );
    let (code, e, by_key) = error_csv("key", &keyed, &[]);
    assert_eq!(code, Some(0), "{e}");
    let (code, e, by_flag) = error_csv("flag", TINY, &["--screen-size-object-bias", "rocks=0.25"]);
    assert_eq!(code, Some(0), "{e}");
    // Policy, knob and triangles: the frame times differ run to run.
    let triangles = |p: &Path| -> Vec<String> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                format!("{},{},{}", c[0], c[1], c[4])
            })
            .collect()
    };
    let key_rows = triangles(&by_key);
    assert_eq!(key_rows.len(), 4, "{key_rows:?}");
    assert_eq!(key_rows, triangles(&by_flag));
    let (code, e, plain) = error_csv("plain", TINY, &[]);
    assert_eq!(code, Some(0), "{e}");
    assert_ne!(key_rows[2], triangles(&plain)[2], "screen size at bias 1");
    let (code, e, _) = error_csv(
        "unknown",
        TINY,
        &["--screen-size-object-bias", "boulder=0.5"],
    );
    assert_eq!(code, Some(2), "{e}");
    assert!(
        e.contains("no object `boulder`") && e.contains("rocks"),
        "{e}"
    );
    let (code, e, _) = error_csv("zero", TINY, &["--screen-size-object-bias", "rocks=0"]);
    assert_eq!(code, Some(2), "{e}");
    assert!(
        e.contains("--screen-size-object-bias") && e.contains("> 0"),
        "{e}"
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
    let o = run_policies(&scene, &out, "full,screen_size,acuity_all", &[]);
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
    let cases: [(&[&str], &str); 12] = [
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
                "--screen-size-periods",
                "0.9,3",
            ],
            "--screen-size-periods",
        ),
        (
            &[
                "experiment",
                "framerate",
                "--scene",
                "no/such.toml",
                "--min-scale",
                "0",
            ],
            "--min-scale",
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
    // Four rocks of different inputs (alike ones would share one analysis).
    let objects = ["corrupt", "fifo", "device", "folder"]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            format!(
                "[[objects]]\nname = \"{name}\"\nprocedural = {{ kind = \"rock\", triangles = [{}, 20] }}\n",
                80 + k
            )
        })
        .collect::<String>();
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
    let cache = dir.join("cache");
    let o = run_policies(
        &s,
        &out,
        "full,acuity_size",
        &["--cache-dir", cache.to_str().unwrap()],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let tris = |policy: &str| -> f64 {
        let line = csv.lines().find(|l| l.starts_with(policy)).unwrap();
        line.split(',').nth(3).unwrap().parse().unwrap()
    };
    assert!(tris("acuity_size") < tris("full"), "{csv}");
}
