//! LOD switches: a camera flying toward an entity makes it switch to finer
//! LODs, and back to coarser ones as it flies away; meshes are swapped and
//! child levels shown one at a time; cross-fades dither two levels.

mod common;

use bevy::camera::visibility::VisibilityRange;
use bevy::prelude::*;
use bevy_acuity::{AcuityLod, AcuityStats, LodFade};
use common::*;

/// Flies the camera from `from` to `to` in `frames` steps; the LOD drawn
/// after each.
fn fly(
    app: &mut App,
    camera: Entity,
    entity: Entity,
    from: f32,
    to: f32,
    frames: u32,
) -> Vec<usize> {
    (0..=frames)
        .map(|i| {
            let z = from + (to - from) * i as f32 / frames as f32;
            move_camera(app, camera, z);
            app.update();
            lod(app, entity).expect("the entity is in view")
        })
        .collect()
}

#[test]
fn a_camera_flying_toward_an_entity_makes_it_finer_and_back() {
    let mut app = app(0.0);
    let camera = spawn_camera(&mut app, 200.0);
    let profile = add_profile(&mut app);
    let (entity, children) = spawn_group(&mut app, profile, Vec3::ZERO);
    let toward = fly(&mut app, camera, entity, 200.0, 1.5, 400);
    // Far away the coarsest LOD, near the finest, every switch finer.
    assert_eq!(toward.first(), Some(&3), "{toward:?}");
    assert_eq!(toward.last(), Some(&0), "{toward:?}");
    assert!(toward.windows(2).all(|w| w[1] <= w[0]), "{toward:?}");
    let mut distinct = toward.clone();
    distinct.dedup();
    assert_eq!(distinct, [3, 2, 1, 0], "every LOD in turn: {toward:?}");
    assert_eq!(shown(&app, &children), [0]);
    let away = fly(&mut app, camera, entity, 1.5, 200.0, 400);
    assert!(away.windows(2).all(|w| w[1] >= w[0]), "{away:?}");
    assert_eq!(away.last(), Some(&3), "{away:?}");
    assert_eq!(shown(&app, &children), [3]);
    assert!(app.world().resource::<AcuityStats>().triangles == 60);
}

#[test]
fn mesh_levels_are_swapped_on_the_entity() {
    let mut app = app(0.0);
    app.init_asset::<Mesh>();
    let camera = spawn_camera(&mut app, 200.0);
    let profile = add_profile(&mut app);
    let meshes: Vec<Handle<Mesh>> = (1..=4)
        .map(|i| {
            let size = i as f32;
            app.world_mut()
                .resource_mut::<Assets<Mesh>>()
                .add(Cuboid::new(size, size, size))
        })
        .collect();
    let entity = app
        .world_mut()
        .spawn((
            Transform::default(),
            AcuityLod::meshes(profile, meshes.clone()),
        ))
        .id();
    let mut seen = Vec::new();
    for z in [200.0, 30.0, 12.0, 6.0, 1.5, 200.0] {
        move_camera(&mut app, camera, z);
        app.update();
        let lod = lod(&app, entity).expect("in view");
        let drawn = &app.world().get::<Mesh3d>(entity).expect("a mesh").0;
        assert_eq!(*drawn, meshes[lod], "LOD {lod} at z = {z}");
        seen.push(lod);
    }
    assert_eq!(seen.first(), Some(&3));
    assert!(seen.contains(&0), "{seen:?}");
    assert_eq!(seen.last(), Some(&3));
}

#[test]
fn a_scaled_entity_keeps_detail_further_away() {
    let mut app = app(0.0);
    // The demo profile's entity switches at 96, 48 and 24 units: at 150
    // it draws LOD 3, and four times larger LOD 1.
    spawn_camera(&mut app, 150.0);
    let profile = add_profile(&mut app);
    let (small, _) = spawn_group(&mut app, profile.clone(), Vec3::new(-1.0, 0.0, 0.0));
    let (large, _) = spawn_group(&mut app, profile, Vec3::new(1.0, 0.0, 0.0));
    app.world_mut()
        .get_mut::<Transform>(large)
        .expect("spawned")
        .scale = Vec3::splat(4.0);
    app.update();
    let (s, l) = (lod(&app, small).unwrap(), lod(&app, large).unwrap());
    assert_eq!((s, l), (3, 1), "the larger entity is finer");
}

#[test]
fn a_switch_cross_fades_two_dithered_children() {
    let fade_s = 0.25;
    let mut app = app(fade_s);
    let camera = spawn_camera(&mut app, 200.0);
    let profile = add_profile(&mut app);
    let (entity, children) = spawn_group(&mut app, profile, Vec3::ZERO);
    app.update();
    assert_eq!(lod(&app, entity), Some(3));
    // Jump close: one switch, 3 -> 0, faded.
    move_camera(&mut app, camera, 1.5);
    app.update();
    let fade = *app.world().get::<LodFade>(entity).expect("a fade starts");
    assert_eq!((fade.from_lod, fade.to_lod), (3, 0));
    app.update();
    let later = *app.world().get::<LodFade>(entity).expect("still fading");
    assert!(later.fraction > fade.fraction, "{later:?} after {fade:?}");
    assert_eq!(shown(&app, &children), [0, 3], "both levels drawn");
    let incoming = app
        .world()
        .get::<VisibilityRange>(children[0])
        .expect("dithered in");
    let outgoing = app
        .world()
        .get::<VisibilityRange>(children[3])
        .expect("dithered out");
    // The camera (1.5 units away) is inside both margins, at the point
    // that shows `fraction` of the incoming level.
    let d = 1.5;
    let m = &incoming.start_margin;
    assert!(m.start <= d && d <= m.end, "{m:?}");
    let shown_in = (d - m.start) / (m.end - m.start);
    assert!(
        (shown_in - later.fraction).abs() < 1e-4,
        "{shown_in} against {later:?}"
    );
    assert_eq!(outgoing.end_margin, incoming.start_margin);
    // After the fade time: one level, no ranges left.
    for _ in 0..(fade_s / FRAME_S as f32).ceil() as usize + 1 {
        app.update();
    }
    assert!(app.world().get::<LodFade>(entity).is_none());
    assert_eq!(shown(&app, &children), [0]);
    assert!(
        children
            .iter()
            .all(|c| app.world().get::<VisibilityRange>(*c).is_none())
    );
}

#[test]
fn an_entity_no_camera_sees_draws_one_level_its_coarsest() {
    let mut app = app(0.0);
    // The camera at z = 20 looks along -Z; the entity is behind it.
    spawn_camera(&mut app, 20.0);
    let profile = add_profile(&mut app);
    let (entity, children) = spawn_group(&mut app, profile, Vec3::new(0.0, 0.0, 40.0));
    app.update();
    assert_eq!(lod(&app, entity), None, "culled: not chosen yet");
    assert_eq!(shown(&app, &children), [3]);
}
