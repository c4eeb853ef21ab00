//! Scene files: every shipped scene parses, every bad fixture is refused
//! with an error naming its field and line, and no text makes the parser
//! panic.
//!
//! Each fixture in `tests/fixtures/scenes/` states what it expects:
//! `# expect-field: <path>` on its first line, and the offending line marked
//! with `# <- error` (or `# expect-line: N` where the error has no line of
//! its own, e.g. a missing table).

use std::path::{Path, PathBuf};

use acuity_lab::scene::{MeshSource, Policy, Scene, SceneError};
use proptest::prelude::*;

/// The smallest valid scene: one procedural object on a straight path.
const MINIMAL_SCENE: &str = r#"
[display]
resolution = [640, 480]
fov_deg = [43.6, 33.4]

[[objects]]
name = "ball"
procedural = { kind = "sphere", triangles = [320, 80] }

[camera]
duration_s = 2.0
forward_speed_m_per_s = 1.0
"#;

/// The repository root, which holds the shipped `scenes/`.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the lab crate sits in the repository")
        .to_path_buf()
}

fn fixtures() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/scenes"))
            .expect("fixture folder")
            .map(|e| e.expect("dir entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
    files.sort();
    files
}

struct Expect {
    field: String,
    line: usize,
}

fn expectation(path: &Path, text: &str) -> Expect {
    let field = text
        .lines()
        .find_map(|l| l.strip_prefix("# expect-field: "))
        .unwrap_or_else(|| panic!("{}: no `# expect-field:` line", path.display()))
        .trim()
        .to_string();
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("# expect-line: "))
        .map(|n| n.trim().parse().expect("line number"))
        .or_else(|| {
            text.lines()
                .position(|l| l.contains("# <- error"))
                .map(|i| i + 1)
        })
        .unwrap_or_else(|| panic!("{}: no `# <- error` marker", path.display()));
    Expect { field, line }
}

#[test]
fn shipped_scenes_load() {
    for name in ["default.toml", "reddy1998.toml", "vr_sweep.toml"] {
        let path = root().join("scenes").join(name);
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!scene.objects.is_empty(), "{name}");
        assert!(scene.run.frames > 0, "{name}");
        for o in &scene.objects {
            assert_eq!(o.placements().len(), o.placement.count(), "{name}");
            assert!(o.source.n_lods().is_none_or(|n| n >= 1));
        }
    }
}

#[test]
fn reddy1998_matches_the_papers_setup() {
    let scene = Scene::load(root().join("scenes/reddy1998.toml")).unwrap();
    assert_eq!(scene.display.fov_deg, [43.6, 33.4]);
    assert_eq!(scene.camera.duration_s, 5.0);
    let (p, _) = scene.camera.sample(5.0);
    assert!((p.length() - 4.36 * 5.0).abs() < 1e-9, "{p}");
    assert_eq!(scene.objects.len(), 1);
    match &scene.objects[0].source {
        MeshSource::Procedural { triangles, .. } => assert_eq!(triangles, &[3928, 834, 254, 76]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn default_scene_runs_every_policy() {
    let scene = Scene::load(root().join("scenes/default.toml")).unwrap();
    for p in Policy::ALL {
        assert!(scene.run.policies.contains(&p), "{}", p.name());
    }
    // The tracked bunny is in front of the camera at the start.
    let g = scene.gaze().sample(0.0);
    assert!(g.z < 0.0, "{g}");
}

#[test]
fn vr_sweep_reaches_200_deg_per_s() {
    let scene = Scene::load(root().join("scenes/vr_sweep.toml")).unwrap();
    assert_eq!(scene.run.target_hz, 90.0);
    let end = scene.camera.duration_s;
    let dt = 1e-4;
    let a = scene.camera.forward(end - dt);
    let b = scene.camera.forward(end);
    let rate = a.angle_between(b).to_degrees() / dt;
    assert!((rate - 200.0).abs() < 1.0, "{rate}");
}

#[test]
fn profiles_table_is_read_and_flags_override_it() {
    use acuity_lab::scene::ProfileSpec;
    use acuity_preprocess::{AnalysisSettings, FrequencyStatistic};
    let text = &format!(
        "{MINIMAL_SCENE}{}",
        r#"
[profiles]
statistic = "thickness"
threshold_delta_e = 8.0
min_change_delta_e = 0.5
"#
    );
    let scene = Scene::parse(text, "inline.toml").unwrap_or_else(|e| panic!("{e}"));
    let spec = scene.profiles;
    assert_eq!(spec.statistic, Some(FrequencyStatistic::Thickness));
    assert_eq!(spec.threshold_delta_e, Some(8.0));
    assert_eq!(spec.min_change_delta_e, Some(0.5));
    assert_eq!(spec.resolution_px, None);
    let defaults = AnalysisSettings::default();
    let settings = spec.analysis_settings();
    assert_eq!(settings.resolution_px, defaults.resolution_px);
    assert_eq!(settings.statistic, FrequencyStatistic::Thickness);
    let flags = ProfileSpec {
        threshold_delta_e: Some(2.0),
        resolution_px: Some(256),
        ..ProfileSpec::default()
    };
    let merged = spec.overridden_by(flags).analysis_settings();
    assert_eq!(merged.threshold_delta_e, 2.0);
    assert_eq!(merged.min_change_delta_e, 0.5);
    assert_eq!(merged.resolution_px, 256);
    assert_eq!(merged.statistic, FrequencyStatistic::Thickness);
    // Without the table, everything is the offline pass's default.
    let plain = Scene::parse(
        &text.replace("[profiles]", "[run]").replace(
            "statistic = \"thickness\"\nthreshold_delta_e = 8.0\nmin_change_delta_e = 0.5",
            "",
        ),
        "plain.toml",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.profiles, ProfileSpec::default());
    assert_eq!(plain.profiles.analysis_settings(), defaults);
    // 0 counts any difference; below 0 or not finite is an error naming the key.
    let zero = text.replace("min_change_delta_e = 0.5", "min_change_delta_e = 0.0");
    assert!(Scene::parse(&zero, "zero.toml").is_ok());
    for bad in ["-1.0", "nan", "inf"] {
        let bad_text = text.replace(
            "min_change_delta_e = 0.5",
            &format!("min_change_delta_e = {bad}"),
        );
        let err = Scene::parse(&bad_text, "bad.toml")
            .expect_err(bad)
            .to_string();
        assert!(err.contains("profiles.min_change_delta_e"), "{bad}: {err}");
    }
}

#[test]
fn screen_size_table_and_foveation_are_read_from_the_run_table() {
    let plain = Scene::parse(MINIMAL_SCENE, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        plain.run.screen_size_thresholds,
        acuity_lab::screen_size::DEFAULT_THRESHOLDS_4.to_vec()
    );
    assert!(!plain.run.screen_size_foveated);
    let text = format!(
        "{MINIMAL_SCENE}\n[run]\nscreen_size_thresholds = [0.6, 0.15, 0.04]\nscreen_size_foveated = true\n"
    );
    let scene = Scene::parse(&text, "table.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.run.screen_size_thresholds, vec![0.6, 0.15, 0.04]);
    assert!(scene.run.screen_size_foveated);
    for bad in ["[]", "[0.5, -0.1]", "[0.5, nan]"] {
        let text = format!("{MINIMAL_SCENE}\n[run]\nscreen_size_thresholds = {bad}\n");
        let err = Scene::parse(&text, "bad.toml").expect_err(bad).to_string();
        assert!(err.contains("run.screen_size_thresholds"), "{bad}: {err}");
    }
}

#[test]
fn the_saccade_threshold_is_read_for_an_eye_tracker() {
    let plain = Scene::parse(MINIMAL_SCENE, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.gaze.saccade_threshold_deg_per_s, None);
    let text =
        format!("{MINIMAL_SCENE}\n[gaze]\ntracker = \"eye\"\nsaccade_threshold_deg_per_s = 180\n");
    let scene = Scene::parse(&text, "eye.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.gaze.saccade_threshold_deg_per_s, Some(180.0));
    for bad in ["0", "-5", "nan", "inf"] {
        let text = text.replace("= 180", &format!("= {bad}"));
        let err = Scene::parse(&text, "bad.toml").expect_err(bad).to_string();
        assert!(
            err.contains("gaze.saccade_threshold_deg_per_s"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn the_wait_for_a_saccade_is_read_for_an_eye_tracker_only() {
    let plain = Scene::parse(MINIMAL_SCENE, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.gaze.defer_coarsening_s, 0.0);
    let text = format!("{MINIMAL_SCENE}\n[gaze]\ntracker = \"eye\"\ndefer_coarsening_s = 0.5\n");
    let scene = Scene::parse(&text, "eye.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.gaze.defer_coarsening_s, 0.5);
    let head = text.replace("\"eye\"", "\"head\"");
    for (bad, text) in [
        ("-0.1", text.replace("= 0.5", "= -0.1")),
        ("nan", text.replace("= 0.5", "= nan")),
        ("11", text.replace("= 0.5", "= 11")),
        ("head tracker", head),
    ] {
        let err = Scene::parse(&text, "bad.toml").expect_err(bad).to_string();
        assert!(err.contains("gaze.defer_coarsening_s"), "{bad}: {err}");
    }
}

#[test]
fn observer_table_chooses_the_eye_models_and_display_its_refresh_rate() {
    let text = MINIMAL_SCENE;
    let plain = Scene::parse(text, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        plain.eccentricity_model,
        acuity::EccentricityModel::CorticalMagnification
    );
    assert_eq!(plain.velocity_model, acuity::VelocityModel::Kelly1979);
    assert_eq!(plain.display.refresh_hz, Some(60.0));
    let reddy = format!(
        "{text}\n[observer]\neccentricity_model = \"reddy2001\"\nvelocity_model = \"reddy2001\"\n"
    );
    let reddy = Scene::parse(&reddy, "reddy.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        reddy.eccentricity_model,
        acuity::EccentricityModel::Reddy2001
    );
    assert_eq!(reddy.velocity_model, acuity::VelocityModel::Reddy2001);
    let sampled = text.replace(
        "fov_deg = [43.6, 33.4]",
        "fov_deg = [43.6, 33.4]\nrefresh_hz = 90",
    );
    let sampled = Scene::parse(&sampled, "sampled.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sampled.display.refresh_hz, Some(90.0));
    let continuous = text.replace(
        "fov_deg = [43.6, 33.4]",
        "fov_deg = [43.6, 33.4]\ncontinuous_motion = true",
    );
    let continuous = Scene::parse(&continuous, "continuous.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(continuous.display.refresh_hz, None);
    let both = text.replace(
        "fov_deg = [43.6, 33.4]",
        "fov_deg = [43.6, 33.4]\ncontinuous_motion = true\nrefresh_hz = 90",
    );
    let err = Scene::parse(&both, "both.toml").unwrap_err().to_string();
    assert!(err.contains("display.continuous_motion"), "{err}");
}

#[test]
fn bad_fixtures_name_field_and_line() {
    let files = fixtures();
    assert!(files.len() >= 20, "{} fixtures", files.len());
    let mut failures = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let want = expectation(&path, &text);
        let err = match Scene::load(&path) {
            Ok(_) => {
                failures.push(format!("{}: parsed, expected an error", path.display()));
                continue;
            }
            Err(e) => e,
        };
        let shown = err.to_string();
        eprintln!("{shown}");
        if err.field() != Some(want.field.as_str()) || err.line() != Some(want.line) {
            failures.push(format!(
                "{}: expected `{}` at line {}, got {:?} at {:?}: {shown}",
                path.display(),
                want.field,
                want.line,
                err.field(),
                err.line()
            ));
        }
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !shown.contains(&name) || !shown.contains(&format!(":{}:", want.line)) {
            failures.push(format!("{name}: message lacks file or line: {shown}"));
        }
        if !shown.contains(&want.field) && !matches!(err, SceneError::Format { .. }) {
            failures.push(format!("{name}: message lacks the field: {shown}"));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn missing_file_is_an_io_error_naming_the_file() {
    let err = Scene::load("no/such/scene.toml").unwrap_err();
    assert!(matches!(err, SceneError::Io { .. }));
    assert!(err.to_string().contains("no/such/scene.toml"));
}

#[test]
fn every_truncation_of_every_scene_is_handled() {
    let mut texts: Vec<String> = ["default.toml", "reddy1998.toml", "vr_sweep.toml"]
        .iter()
        .map(|n| std::fs::read_to_string(root().join("scenes").join(n)).unwrap())
        .collect();
    texts.extend(
        fixtures()
            .iter()
            .map(|p| std::fs::read_to_string(p).unwrap()),
    );
    for text in &texts {
        for (cut, _) in text.char_indices() {
            let _ = Scene::parse(&text[..cut], "truncated.toml");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,400}") {
        if let Err(e) = Scene::parse(&text, "garbage.toml") {
            prop_assert!(e.line().is_some_and(|l| l >= 1));
        }
    }

    #[test]
    fn toml_like_text_never_panics(
        text in r#"(\[{1,2}[a-z_]{1,12}\]{1,2}\n|[a-z_]{1,12} = (-?[0-9]{1,4}(\.[0-9]+)?|"[a-z.]{0,8}"|\[[0-9, .]{0,12}\]|\{ ?[a-z]{1,5} = [0-9]{1,3} ?\}|nan|inf|true)\n){0,20}"#
    ) {
        let _ = Scene::parse(&text, "fuzz.toml");
    }

    #[test]
    fn mutated_default_scene_never_panics(cut in 0usize..4000, byte in any::<u8>()) {
        let text = std::fs::read_to_string(root().join("scenes/default.toml")).unwrap();
        let mut bytes = text.into_bytes();
        let at = cut % bytes.len();
        bytes[at] = byte;
        let text = String::from_utf8_lossy(&bytes);
        let _ = Scene::parse(&text, "mutated.toml");
    }
}

#[test]
fn deeply_nested_values_do_not_overflow_the_stack() {
    for depth in [100, 10_000, 200_000] {
        let arrays = format!("x = {}{}\n", "[".repeat(depth), "]".repeat(depth));
        let tables = format!("x = {}1{}\n", "{a=".repeat(depth), "}".repeat(depth));
        let headers = format!("[{}]\n", vec!["a"; depth].join("."));
        for text in [arrays, tables, headers] {
            let e = Scene::parse(&text, "deep.toml").unwrap_err();
            assert!(e.line().is_some());
        }
    }
}

#[test]
fn values_beyond_a_limit_are_refused_with_the_limit() {
    let base = r#"
[display]
resolution = [640, 480]
fov_deg = [43.6, 33.4]

[[objects]]
name = "rocks"
procedural = { kind = "rock", triangles = [320, 80] }

[camera]
duration_s = 2.0
forward_speed_m_per_s = 1.0

[run]
frames = 10
"#;
    let cases = [
        (
            "frames = 10",
            "frames = 10\ntarget_hz = 1e-40",
            "run.target_hz",
            "10000",
        ),
        (
            "frames = 10",
            "frames = 10\ntarget_hz = 1e300",
            "run.target_hz",
            "10000",
        ),
        ("frames = 10", "dt_s = 1e-300", "run.dt_s", "0.0001"),
        (
            "[320, 80]",
            "[4000000000, 200, 50]",
            "objects[0].procedural.triangles[0]",
            "10000000",
        ),
        (
            "[320, 80] }",
            "[5000000, 80] }\ncopies = { count = 1000, volume_min = [0, 0, -9], volume_max = [1, 1, -8] }",
            "objects[0].copies.count",
            "1000000000",
        ),
        (
            "frames = 10",
            "frames = 10\n[gaze]\ntracker = \"head\"\neye_error_deg = 5",
            "gaze.eye_error_deg",
            "tracker = \"eye\"",
        ),
    ];
    for (from, to, field, limit) in cases {
        let text = base.replace(from, to);
        let e = Scene::parse(&text, "limits.toml").expect_err(to);
        let shown = e.to_string();
        assert_eq!(e.field(), Some(field), "{shown}");
        assert!(shown.contains(limit), "{to}: {shown}");
    }
    // At the limits, and the eye tracker with its error, parse.
    for (from, to) in [
        ("frames = 10", "frames = 10\ntarget_hz = 1"),
        ("frames = 10", "frames = 10\ntarget_hz = 10000"),
        ("frames = 10", "dt_s = 1"),
        ("[320, 80]", "[10000000, 80]"),
        (
            "frames = 10",
            "frames = 10\n[gaze]\ntracker = \"eye\"\neye_error_deg = 2",
        ),
    ] {
        let text = base.replace(from, to);
        Scene::parse(&text, "limits.toml").unwrap_or_else(|e| panic!("{to}: {e}"));
    }
}

#[test]
fn arrays_of_the_wrong_length_name_their_field() {
    let base = r#"
[display]
resolution = [640, 480]
fov_deg = [43.6, 33.4]

[[objects]]
name = "rocks"
procedural = { kind = "rock", triangles = [320, 80] }
transform = { position = [0, 0, -5], rotation_deg = [30, 0, 0] }

[camera]
duration_s = 2.0
forward_speed_m_per_s = 1.0
start = { position = [0, 1, 0] }

[gaze]
mode = "fixed"
point_deg = [1, 2]
"#;
    Scene::parse(base, "arrays.toml").unwrap_or_else(|e| panic!("{e}"));
    let cases = [
        ("[640, 480]", "[64, 48, \"junk\"]", "display.resolution"),
        ("[43.6, 33.4]", "[43.6, 33.4, 20]", "display.fov_deg"),
        (
            "[0, 0, -5]",
            "[0, 0, -5, 99]",
            "objects[0].transform.position",
        ),
        (
            "[30, 0, 0]",
            "[30, 0, 0, 45]",
            "objects[0].transform.rotation_deg",
        ),
        ("[0, 1, 0]", "[0, 1, 0, 0]", "camera.start.position"),
        ("[1, 2]", "[1, 2, 3]", "gaze.point_deg"),
        ("[1, 2]", "[1]", "gaze.point_deg"),
    ];
    for (from, to, field) in cases {
        let e = Scene::parse(&base.replace(from, to), "arrays.toml").expect_err(to);
        let shown = e.to_string();
        assert_eq!(e.field(), Some(field), "{to}: {shown}");
        assert!(shown.contains("exactly"), "{to}: {shown}");
    }
}

#[test]
fn the_viewers_object_is_read_without_an_eye_tracker_only() {
    use acuity_lab::gaze::GazeMode;
    let plain = Scene::parse(MINIMAL_SCENE, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.gaze.viewer, None);
    let text = format!("{MINIMAL_SCENE}\n[gaze]\ntracker = \"head\"\nviewer_object = \"ball\"\n");
    let scene = Scene::parse(&text, "head.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.gaze.viewer,
        Some(GazeMode::Track {
            object: "ball".into(),
            copy: 0
        })
    );
    // The selector's gaze stays where the scene models it.
    assert_eq!(scene.gaze.mode, GazeMode::ScreenCentre);
    for (field, text) in [
        ("gaze.viewer_object", text.replace("\"head\"", "\"eye\"")),
        (
            "gaze.viewer_object",
            text.replace("viewer_object = \"ball\"", "viewer_object = \"cube\""),
        ),
        ("gaze.viewer_copy", format!("{text}viewer_copy = 1\n")),
        (
            "gaze.viewer_copy",
            text.replace("viewer_object = \"ball\"", "viewer_copy = 0"),
        ),
    ] {
        let err = Scene::parse(&text, "bad.toml")
            .expect_err(field)
            .to_string();
        assert!(err.contains(field), "{field}: {err}");
    }
}

#[test]
fn a_missing_top_level_table_is_named_as_a_table() {
    for (missing, text) in [
        (
            "camera",
            MINIMAL_SCENE.split("[camera]").next().unwrap().to_string(),
        ),
        (
            "display",
            MINIMAL_SCENE.replace(
                "[display]\nresolution = [640, 480]\nfov_deg = [43.6, 33.4]\n",
                "",
            ),
        ),
    ] {
        let e = Scene::parse(&text, "s.toml").unwrap_err();
        let message = e.to_string();
        assert!(
            message.contains(&format!("the scene has no `[{missing}]` table")),
            "{message}"
        );
        assert_eq!(e.field(), Some(missing), "{message}");
    }
}

#[test]
fn a_mesh_given_as_a_scene_says_how_to_analyse_it() {
    for name in ["mesh.obj", "chain.GLB", "a.gltf"] {
        let e = Scene::load(name).unwrap_err();
        assert!(matches!(e, SceneError::NotAScene { .. }), "{e}");
        let message = e.to_string();
        assert!(
            message.contains(&format!("acuity preprocess {name}")),
            "{message}"
        );
    }
}

#[test]
fn a_mesh_without_generate_triangles_is_kept_whole() {
    let text = MINIMAL_SCENE.replace(
        "procedural = { kind = \"sphere\", triangles = [320, 80] }",
        "mesh = \"ball.obj\"",
    );
    let scene = Scene::parse(&text, "dir/s.toml").unwrap();
    assert_eq!(
        scene.objects[0].source,
        MeshSource::Whole {
            mesh: PathBuf::from("dir/ball.obj")
        }
    );
    assert_eq!(scene.objects[0].source.n_lods(), None);
}
