//! Embedding acuity: a profile, objects, a selection per frame, and the
//! list of objects whose LOD changed, which is what a renderer acts on.
//!
//! `cargo run --example minimal` builds a small profile in code;
//! `cargo run --example minimal -- rock.acp` loads one written by
//! `acuity preprocess` instead.

mod common;

use acuity::glam::{DVec3, Quat};
use acuity::{
    Camera, Display, FrameInput, Gaze, ObjectDesc, Profile, Selector, SelectorSettings, Tracker,
};
use common::demo_profile;

fn main() -> std::process::ExitCode {
    common::finish(run())
}

fn run() -> Result<(), acuity::Error> {
    // ANCHOR: setup
    let profile = match std::env::args().nth(1) {
        Some(path) => Profile::load(path)?, // from `acuity preprocess`
        None => demo_profile(),
    };
    // A 1920x1080 screen spanning 90x58.7 degrees of the viewer's field.
    let display = Display::new([1920, 1080], [90.0, 58.7])?;
    let settings = SelectorSettings {
        track_changes: true, // list the objects whose LOD changed each frame
        fade_time_s: 0.25,   // and cross-fade switches over a quarter second
        ..SelectorSettings::default()
    };
    let mut selector = Selector::new(display, settings);
    let rock = selector.add_profile(&profile)?;
    let hero = selector.add_object(ObjectDesc {
        center: DVec3::new(0.0, 0.0, -20.0), // world units, f64
        radius: 0.5,                         // profile.bounding_radius x scale
        rotation: Quat::IDENTITY,            // object frame -> world
        profile: rock,
    })?;
    // ANCHOR_END: setup

    // A field of 400 more rocks along the -Z axis, 2 world units apart.
    let mut rocks = Vec::new();
    for i in 0..400 {
        let (x, z) = ((i % 20) as f64 - 9.5, -2.0 * (i / 20) as f64 - 3.0);
        rocks.push(selector.add_object(ObjectDesc {
            center: DVec3::new(2.0 * x, 0.0, z),
            radius: 0.5,
            rotation: Quat::IDENTITY,
            profile: rock,
        })?);
    }
    // The hero rock keeps more detail; another never goes finer than
    // LOD 1; a third leaves the scene.
    selector.set_bias(hero, 4.0)?;
    selector.set_lod_range(rocks[211], 1..=usize::MAX)?;
    selector.remove_object(rocks[399])?;

    // Fly forward at 3 units/s for two seconds at 60 Hz, eyes on the
    // screen's centre.
    let mut lods = Vec::new(); // what this "renderer" draws
    let mut changes = 0;
    for frame in 0..120 {
        let position = DVec3::new(0.0, 1.0, -0.05 * frame as f64);
        // ANCHOR: frame
        // `position`: the camera's, in world units; it looks along -Z, +Y up.
        selector.select(&FrameInput {
            camera: Camera {
                position,
                orientation: Quat::IDENTITY,
            },
            gaze: Gaze::screen_centre(Tracker::None), // or an eye tracker's gaze
            dt_s: 1.0 / 60.0,
            scale: 1.0, // s in (0, 1]: 1 is imperceptible
        })?;
        // A renderer swaps meshes only for the objects in the change list.
        for &id in selector.changed() {
            let _new_lod = selector.selection(id).lod(); // None: culled
        }
        // ANCHOR_END: frame
        changes += selector.changed().len();
        lods.clear();
        lods.extend(selector.selections().iter().map(|s| s.lod()));
        if frame % 20 == 19 {
            let visible = lods.iter().flatten().count();
            println!(
                "frames {:3}-{frame:3}: {visible:3} rocks visible, {:6} triangles, \
                 {changes:3} changes (LOD or culled), {:2} cross-fading now",
                frame - 19,
                selector.triangles(),
                selector.fades().len(),
            );
            changes = 0;
        }
    }
    // Rock 169 is the hero's neighbour: 1 unit to the left, 1 nearer.
    let (hero_lod, other) = (
        selector.selection(hero).lod(),
        selector.selection(rocks[169]).lod(),
    );
    println!("the hero rock (bias 4) draws LOD {hero_lod:?}, its neighbour LOD {other:?}");
    Ok(())
}
