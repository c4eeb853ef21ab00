//! Entities and cameras coming and going: a despawned entity's object is
//! removed from every camera's selector, a despawned camera's selector is
//! dropped and the entities it kept fine coarsen to what the others chose,
//! and an LOD chain that does not match its profile is an error message,
//! not a panic.

mod common;

use bevy::prelude::*;
use bevy_acuity::{AcuityCameras, AcuityError, AcuityLod, AcuityStats};
use common::*;

fn object_count(app: &App, camera: Entity) -> Option<usize> {
    app.world()
        .resource::<AcuityCameras>()
        .get(camera)
        .map(|c| c.object_count())
}

#[test]
fn despawning_an_entity_removes_its_object() {
    let mut app = app(0.0);
    let camera = spawn_camera(&mut app, 20.0);
    let profile = add_profile(&mut app);
    let groups: Vec<Entity> = (0..3)
        .map(|i| {
            spawn_group(
                &mut app,
                profile.clone(),
                Vec3::new(3.0 * i as f32, 0.0, 0.0),
            )
            .0
        })
        .collect();
    app.update();
    assert_eq!(object_count(&app, camera), Some(3));
    app.world_mut().entity_mut(groups[0]).despawn();
    app.update();
    assert_eq!(object_count(&app, camera), Some(2));
    // Removing the component alone removes the object too.
    app.world_mut().entity_mut(groups[1]).remove::<AcuityLod>();
    app.update();
    assert_eq!(object_count(&app, camera), Some(1));
    assert_eq!(app.world().resource::<AcuityStats>().objects, 1);
    // A camera that appears later gets the remaining entity only.
    let late = spawn_camera(&mut app, 10.0);
    app.update();
    assert_eq!(object_count(&app, late), Some(1));
    assert!(lod(&app, groups[2]).is_some());
}

#[test]
fn a_despawned_camera_is_dropped_and_its_choices_with_it() {
    let mut app = app(0.0);
    let near = spawn_camera(&mut app, 1.5);
    let far = spawn_camera(&mut app, 200.0);
    let profile = add_profile(&mut app);
    let (entity, children) = spawn_group(&mut app, profile, Vec3::ZERO);
    app.update();
    assert_eq!(app.world().resource::<AcuityCameras>().len(), 2);
    // The finest LOD any camera chose.
    assert_eq!(lod(&app, entity), Some(0));
    app.world_mut().entity_mut(near).despawn();
    app.update();
    let cameras = app.world().resource::<AcuityCameras>();
    assert_eq!(cameras.len(), 1);
    assert!(cameras.get(near).is_none());
    assert_eq!(object_count(&app, far), Some(1));
    assert_eq!(lod(&app, entity), Some(3), "the far camera's choice");
    assert_eq!(shown(&app, &children), [3]);
    // No camera at all: nothing selects, nothing breaks, the LOD stays.
    app.world_mut().entity_mut(far).despawn();
    app.update();
    app.update();
    assert!(app.world().resource::<AcuityCameras>().is_empty());
    assert_eq!(lod(&app, entity), Some(3));
}

#[test]
fn an_inactive_camera_does_not_select() {
    let mut app = app(0.0);
    let camera = spawn_camera(&mut app, 1.5);
    let profile = add_profile(&mut app);
    let (entity, _) = spawn_group(&mut app, profile, Vec3::ZERO);
    app.world_mut().get_mut::<Camera>(camera).unwrap().is_active = false;
    app.update();
    assert!(app.world().resource::<AcuityCameras>().is_empty());
    assert_eq!(lod(&app, entity), None);
}

#[test]
fn an_lod_chain_that_does_not_match_its_profile_is_an_error_message() {
    let mut app = app(0.0);
    let mut errors = Reader::<AcuityError>::new();
    let camera = spawn_camera(&mut app, 20.0);
    let profile = add_profile(&mut app);
    let child = app.world_mut().spawn(Transform::default()).id();
    // Two levels for a profile of four.
    let entity = app
        .world_mut()
        .spawn((
            Transform::default(),
            AcuityLod::children(profile, vec![child, child]),
        ))
        .id();
    app.update();
    let errors_now = errors.read(&app);
    assert_eq!(errors_now.len(), 1, "{errors_now:?}");
    assert!(
        matches!(&errors_now[0], AcuityError::Object { entity: e, reason } if *e == entity && reason.contains("4 LODs")),
        "{errors_now:?}"
    );
    assert_eq!(object_count(&app, camera), Some(0));
    // Reported once, not every frame.
    app.update();
    app.update();
    assert!(errors.read(&app).is_empty());
}

#[test]
fn a_camera_with_a_non_finite_transform_is_an_error_message() {
    let mut app = app(0.0);
    let mut errors = Reader::<AcuityError>::new();
    let camera = spawn_camera(&mut app, 20.0);
    let profile = add_profile(&mut app);
    spawn_group(&mut app, profile, Vec3::ZERO);
    app.update();
    move_camera(&mut app, camera, f32::NAN);
    app.update();
    app.update();
    let errors_now = errors.read(&app);
    assert!(
        matches!(errors_now.as_slice(), [AcuityError::Camera { camera: c, .. }] if *c == camera),
        "{errors_now:?}"
    );
}
