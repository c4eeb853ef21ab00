//! What the plugin's tests share: a headless app (no window, no GPU: a
//! `Window` component stands in for the window's size), a stand-in
//! profile, and a camera.

#![allow(dead_code)]

use std::time::Duration;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy::window::{PrimaryWindow, WindowResolution};
use bevy_acuity::{AcuityLod, AcuityPlugin, AcuityProfile, AcuitySettings};

/// The frame time of every test frame, s.
pub const FRAME_S: f64 = 1.0 / 60.0;

/// The examples' stand-in profile: 4 LODs of 4000 to 60 triangles,
/// bounding radius 1.
#[path = "../../../examples/common/mod.rs"]
mod examples_common;
#[allow(unused_imports)]
pub use examples_common::demo_profile;

/// A headless app with the plugin, a 1920x1080 primary window (the
/// component only) and 60 Hz frames; fades off unless `fade_time_s > 0`.
pub fn app(fade_time_s: f32) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        TransformPlugin,
        AssetPlugin::default(),
        AcuityPlugin,
    ));
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        FRAME_S,
    )));
    let mut settings = AcuitySettings::default();
    settings.selector.fade_time_s = fade_time_s;
    app.insert_resource(settings);
    app.world_mut().spawn((
        Window {
            resolution: WindowResolution::new(1920, 1080),
            ..default()
        },
        PrimaryWindow,
    ));
    app
}

/// A perspective camera (60 deg vertical field) at `z` on the +Z axis,
/// looking along -Z at the origin.
pub fn spawn_camera(app: &mut App, z: f32) -> Entity {
    app.world_mut()
        .spawn((
            Camera::default(),
            Projection::Perspective(PerspectiveProjection {
                fov: 60f32.to_radians(),
                ..default()
            }),
            Transform::from_xyz(0.0, 0.0, z),
        ))
        .id()
}

/// Moves a camera to `z` on the +Z axis.
pub fn move_camera(app: &mut App, camera: Entity, z: f32) {
    app.world_mut()
        .get_mut::<Transform>(camera)
        .expect("the camera exists")
        .translation
        .z = z;
}

/// The demo profile as an asset.
pub fn add_profile(app: &mut App) -> Handle<AcuityProfile> {
    app.world_mut()
        .resource_mut::<Assets<AcuityProfile>>()
        .add(AcuityProfile(demo_profile()))
}

/// An entity at `position` whose four LODs are child entities.
pub fn spawn_group(
    app: &mut App,
    profile: Handle<AcuityProfile>,
    position: Vec3,
) -> (Entity, Vec<Entity>) {
    let world = app.world_mut();
    let parent = world
        .spawn((Transform::from_translation(position), Visibility::default()))
        .id();
    let children: Vec<Entity> = (0..4)
        .map(|_| {
            world
                .spawn((Transform::default(), Visibility::default(), ChildOf(parent)))
                .id()
        })
        .collect();
    world
        .entity_mut(parent)
        .insert(AcuityLod::children(profile, children.clone()));
    (parent, children)
}

/// The LOD drawn for an entity.
pub fn lod(app: &App, entity: Entity) -> Option<usize> {
    app.world()
        .get::<bevy_acuity::SelectedLod>(entity)
        .and_then(|s| s.0)
}

/// Which children are not hidden.
pub fn shown(app: &App, children: &[Entity]) -> Vec<usize> {
    children
        .iter()
        .enumerate()
        .filter(|(_, c)| app.world().get::<Visibility>(**c) != Some(&Visibility::Hidden))
        .map(|(i, _)| i)
        .collect()
}

/// Reads a message type across updates (the double buffer of messages is
/// swapped on frames that run the fixed-time loop, so "this update's
/// messages" is not one frame's).
pub struct Reader<M: bevy::ecs::message::Message>(bevy::ecs::message::MessageCursor<M>);

impl<M: bevy::ecs::message::Message + Clone> Reader<M> {
    /// Reads from the first message on.
    pub fn new() -> Self {
        Self(Default::default())
    }

    /// The messages written since the last read.
    pub fn read(&mut self, app: &App) -> Vec<M> {
        let messages = app.world().resource::<bevy::ecs::message::Messages<M>>();
        self.0.read(messages).cloned().collect()
    }
}
