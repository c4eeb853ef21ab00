//! Unit tests of the scene format: defaults, located errors, the physical
//! screen's field of view.

use super::locate::line_col;
use super::*;

const MINIMAL: &str = r#"
[display]
resolution = [640, 512]
fov_deg = [43.6, 33.4]

[[objects]]
name = "ball"
procedural = { kind = "sphere", triangles = [320, 80] }

[camera]
duration_s = 2.0
forward_speed_m_per_s = 1.0
"#;

#[test]
fn minimal_scene_parses_with_defaults() {
    let s = Scene::parse(MINIMAL, "dir/min.toml").unwrap();
    assert_eq!(s.display.resolution_px, [640, 512]);
    assert_eq!(s.run.policies, Policy::ALL.to_vec());
    assert_eq!(s.run.frames, 120);
    assert!((s.run.frame_dt_s - 1.0 / 60.0).abs() < 1e-15);
    assert_eq!(s.gaze, GazeSpec::default());
    assert_eq!(s.instance_count(), 1);
    assert_eq!(s.run.cross_fade_s, 0.0);
    assert_eq!(s.run.min_scale, acuity::DEFAULT_MIN_SCALE);
}

#[test]
fn scheduler_floor_is_read_and_checked() {
    let with = |v: &str| format!("{MINIMAL}\n[run]\nmin_scale = {v}\n");
    let s = Scene::parse(&with("0.01"), "min.toml").unwrap();
    assert_eq!(s.run.min_scale, 0.01);
    assert_eq!(super::MIN_FLOOR_SCALE as f32, acuity::LOWEST_MIN_SCALE);
    for bad in ["0", "-0.5", "1e-7", "1.5"] {
        let e = Scene::parse(&with(bad), "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("run.min_scale"), "{bad}: {e}");
        assert!(e.to_string().contains("1e-6..=1"), "{e}");
    }
}

#[test]
fn cross_fade_time_is_read_and_checked() {
    let with = |v: &str| format!("{MINIMAL}\n[run]\ncross_fade_s = {v}\n");
    let s = Scene::parse(&with("0.25"), "min.toml").unwrap();
    assert_eq!(s.run.cross_fade_s, 0.25);
    for bad in ["-0.1", "10.5"] {
        let e = Scene::parse(&with(bad), "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("run.cross_fade_s"), "{bad}: {e}");
        assert!(e.to_string().contains("0..=10"), "{e}");
    }
}

#[test]
fn an_objects_screen_size_bias_is_read_and_checked() {
    let s = Scene::parse(MINIMAL, "min.toml").unwrap();
    assert_eq!(s.objects[0].screen_size_bias, 1.0);
    let with = |v: &str| {
        MINIMAL.replace(
            "triangles = [320, 80] }",
            &format!("triangles = [320, 80] }}\nscreen_size_bias = {v}"),
        )
    };
    let s = Scene::parse(&with("0.35"), "min.toml").unwrap();
    assert_eq!(s.objects[0].screen_size_bias, 0.35);
    for bad in ["0", "-1", "inf", "nan"] {
        let e = Scene::parse(&with(bad), "min.toml").unwrap_err();
        assert_eq!(e.field(), Some("objects[0].screen_size_bias"), "{bad}: {e}");
        let finite = bad.parse::<f64>().is_ok_and(f64::is_finite);
        assert!(!finite || e.to_string().contains("finite and > 0"), "{e}");
    }
}

#[test]
fn physical_screen_gives_the_papers_field_of_view() {
    let text = MINIMAL.replace(
        "fov_deg = [43.6, 33.4]",
        "screen_cm = [40, 30]\ndistance_cm = 50",
    );
    let s = Scene::parse(&text, "x.toml").unwrap();
    assert!((s.display.fov_deg[0] - 43.6).abs() < 0.05);
    assert!((s.display.fov_deg[1] - 33.4).abs() < 0.05);
}

#[test]
fn line_col_counts_characters_and_clamps() {
    assert_eq!(line_col("ab\ncé\nx", 6), (2, 3));
    assert_eq!(line_col("ab\ncé\nx", 5), (2, 2)); // inside 'é': clamped back
    assert_eq!(line_col("ab", 99), (1, 3));
    assert_eq!(line_col("", 0), (1, 1));
}

#[test]
fn validation_error_names_field_and_line() {
    let text = MINIMAL.replace("[320, 80]", "[320, 400]");
    let e = Scene::parse(&text, "min.toml").unwrap_err();
    assert_eq!(e.field(), Some("objects[0].procedural.triangles[1]"));
    assert_eq!(e.line(), Some(8));
    assert!(e.to_string().starts_with("min.toml:8:"), "{e}");
}

#[test]
fn type_error_names_field_and_line() {
    let text = MINIMAL.replace("duration_s = 2.0", "duration_s = \"long\"");
    let e = Scene::parse(&text, "min.toml").unwrap_err();
    assert_eq!(e.field(), Some("camera.duration_s"), "{e}");
    assert_eq!(e.line(), Some(11));
}

#[test]
fn missing_field_is_named() {
    let text = MINIMAL.replace("resolution = [640, 512]\n", "");
    let e = Scene::parse(&text, "min.toml").unwrap_err();
    assert_eq!(e.field(), Some("display.resolution"), "{e}");
    assert_eq!(e.line(), Some(2), "{e}");
}

#[test]
fn nan_is_refused_where_it_stands() {
    let text = MINIMAL.replace("duration_s = 2.0", "duration_s = nan");
    let e = Scene::parse(&text, "min.toml").unwrap_err();
    assert_eq!(e.field(), Some("camera.duration_s"), "{e}");
    assert_eq!(e.line(), Some(11));
}

#[test]
fn a_headset_eye_gives_its_edges_and_both_eyes_select_together() {
    let text = MINIMAL.replace(
        "fov_deg = [43.6, 33.4]",
        "fov_edges_deg = [-54, 50, 52, -52]\nstereo_ipd_m = 0.064",
    );
    let s = Scene::parse(&text, "x.toml").unwrap();
    assert_eq!(s.display.fov_deg, [104.0, 104.0]);
    assert_eq!(s.display.fov_edges_deg, [-54.0, 50.0, 52.0, -52.0]);
    let (both, margin) = s.display.selection_display().unwrap();
    assert_eq!(both.fov_deg(), [108.0, 104.0]);
    assert!((margin - 0.064).abs() < 1e-7);
    assert_eq!(s.display.eye_display().unwrap().fov_edges().left_deg, -54.0);
    assert_eq!(
        s.display.rendered_eye_offset_m(),
        glam::DVec3::new(-0.032, 0.0, 0.0)
    );
    // A symmetric display's edges, and no stereo.
    let m = Scene::parse(MINIMAL, "x.toml").unwrap();
    assert_eq!(m.display.fov_edges_deg, [-21.8, 21.8, 16.7, -16.7]);
    assert_eq!(m.display.selection_display().unwrap().1, 0.0);
}

#[test]
fn bad_edges_and_ipd_are_named() {
    for (replacement, field) in [
        (
            "fov_edges_deg = [-54, 50, 52, -52]\nfov_deg = [1, 1]",
            "display.fov_edges_deg",
        ),
        (
            "fov_edges_deg = [-95, 50, 52, -52]",
            "display.fov_edges_deg[0]",
        ),
        ("fov_edges_deg = [10, 5, 52, -52]", "display.fov_edges_deg"),
        ("fov_edges_deg = [-10, 5, 52]", "display.fov_edges_deg"),
        (
            "fov_deg = [43.6, 33.4]\nstereo_ipd_m = -0.01",
            "display.stereo_ipd_m",
        ),
        (
            "fov_deg = [43.6, 33.4]\nstereo_ipd_m = nan",
            "display.stereo_ipd_m",
        ),
    ] {
        let text = MINIMAL.replace("fov_deg = [43.6, 33.4]", replacement);
        let e = Scene::parse(&text, "x.toml").unwrap_err();
        assert_eq!(e.field(), Some(field), "{replacement}: {e}");
    }
}
