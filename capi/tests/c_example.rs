//! `examples/c/minimal.c`, compiled with the system C compiler against the
//! static library and the committed header, prints what the same scene
//! selected through the Rust API gives (the scene of `examples/minimal.rs`).
//! Without a C compiler this fails, unless `ACUITY_SKIP_C=1`.

mod common;

use std::process::Command;

use acuity::glam::{DVec3, Quat};
use acuity::{
    Camera, Display, FrameInput, Gaze, ObjectDesc, Selection, Selector, SelectorSettings, Tracker,
};
use common::{build_c, c_compiler, demo_profile};

/// `examples/minimal.rs`'s scene and frames, printed as `minimal.c` prints.
fn expected_output() -> String {
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    let settings = SelectorSettings {
        track_changes: true,
        fade_time_s: 0.25,
        ..SelectorSettings::default()
    };
    let mut selector = Selector::new(display, settings);
    let rock = selector.add_profile(&demo_profile()).unwrap();
    let desc = |center| ObjectDesc {
        center,
        radius: 0.5,
        rotation: Quat::IDENTITY,
        profile: rock,
    };
    let hero = selector
        .add_object(desc(DVec3::new(0.0, 0.0, -20.0)))
        .unwrap();
    let rocks: Vec<_> = (0..400)
        .map(|i| {
            let (x, z) = ((i % 20) as f64 - 9.5, -2.0 * (i / 20) as f64 - 3.0);
            selector
                .add_object(desc(DVec3::new(2.0 * x, 0.0, z)))
                .unwrap()
        })
        .collect();
    selector.set_bias(hero, 4.0).unwrap();
    selector.set_lod_range(rocks[211], 1..=usize::MAX).unwrap();
    selector.remove_object(rocks[399]).unwrap();
    let mut out = String::new();
    let mut changes = 0;
    for frame in 0..120 {
        selector
            .select(&FrameInput {
                camera: Camera {
                    position: DVec3::new(0.0, 1.0, -0.05 * frame as f64),
                    orientation: Quat::IDENTITY,
                },
                gaze: Gaze::screen_centre(Tracker::None),
                dt_s: 1.0 / 60.0,
                scale: 1.0,
            })
            .unwrap();
        changes += selector.changed().len();
        if frame % 20 == 19 {
            let visible = selector
                .selections()
                .iter()
                .filter(|s| !s.is_culled())
                .count();
            out += &format!(
                "frames {:3}-{frame:3}: {visible:3} rocks visible, {:6} triangles, \
                 {changes:3} changes (LOD or culled), {:2} cross-fading now\n",
                frame - 19,
                selector.triangles(),
                selector.fades().len(),
            );
            changes = 0;
        }
    }
    let lod = |s: Selection| s.lod().map_or("culled".to_owned(), |l| format!("LOD {l}"));
    out += &format!(
        "the hero rock (bias 4) draws {}, its neighbour {}\n",
        lod(selector.selection(hero)),
        lod(selector.selection(rocks[169])),
    );
    out
}

#[test]
fn minimal_c_prints_what_rust_selects() {
    let Some(cc) = c_compiler() else { return };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("c_example");
    std::fs::create_dir_all(&dir).unwrap();
    let exe = build_c(&cc, "minimal.c", &dir);
    let expected = expected_output();

    // The profile embedded as JSON (acuity_profile_from_bytes).
    let run = Command::new(&exe).output().expect("running minimal");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "minimal exited {:?}: {}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(stdout, expected);
    assert!(stdout.contains("the hero rock (bias 4) draws LOD 0"));

    // The same profile as a binary file (acuity_profile_load).
    let path = dir.join("rock.acp");
    demo_profile().save(&path).unwrap();
    let run = Command::new(&exe).arg(&path).output().unwrap();
    assert!(run.status.success());
    assert_eq!(String::from_utf8_lossy(&run.stdout), expected);

    // A missing file: exit 1 and the runtime's message, naming the file.
    let missing = dir.join("missing.acp");
    let run = Command::new(&exe).arg(&missing).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.starts_with("error: ") && stderr.contains("missing.acp"),
        "{stderr}"
    );
    assert!(stderr.contains("(status 8)"), "ACUITY_IO: {stderr}");
}
