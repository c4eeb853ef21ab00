//! Entities with [`AcuityLod`] as the selectors' objects: registered with
//! every camera once their profile has loaded, moved when their
//! `GlobalTransform` changes, removed when the component goes or the
//! entity is despawned.
//!
//! An entity whose LOD chain does not match its profile, or whose profile
//! or transform a selector refuses, is reported once as an
//! [`AcuityError::Object`] and left unregistered until its [`AcuityLod`]
//! changes.

use acuity::ObjectDesc;
use acuity::glam::{DVec3, Quat as AQuat};
use bevy::asset::{AssetId, Assets};
use bevy::ecs::change_detection::DetectChanges;
use bevy::ecs::entity::{Entity, EntityHashMap};
use bevy::ecs::lifecycle::RemovedComponents;
use bevy::ecs::message::MessageWriter;
use bevy::ecs::system::{Commands, Query, Res, ResMut};
use bevy::ecs::world::Ref;
use bevy::transform::components::GlobalTransform;

use crate::cameras::{AcuityCameras, CameraSelector};
use crate::components::{AcuityLod, SelectedLod};
use crate::profile_asset::AcuityProfile;
use crate::settings::AcuityError;

/// Where an entity with [`AcuityLod`] stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Registration {
    /// Waiting for its profile asset.
    Pending,
    /// An object in every camera's selector.
    Ready,
    /// Refused (reported); retried when its `AcuityLod` changes.
    Refused,
}

/// The plugin's record of one entity with [`AcuityLod`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tracked {
    pub(crate) registration: Registration,
    /// The LOD applied (drawn), if any.
    pub(crate) applied: Option<usize>,
    /// The camera whose selection set `applied`.
    pub(crate) decider: Option<Entity>,
}

/// Every entity with [`AcuityLod`] the plugin has seen.
#[derive(bevy::ecs::resource::Resource, Default)]
pub(crate) struct TrackedEntities {
    pub(crate) entities: EntityHashMap<Tracked>,
    /// Registered this frame: drawn at their coarsest LOD until a camera
    /// chooses one (so a child chain never shows all its levels).
    pub(crate) fresh: Vec<Entity>,
}

/// The object a selector is given for an entity: the bounding sphere from
/// the profile's radius and the transform's largest scale.
pub(crate) fn object_pose(
    lod: &AcuityLod,
    transform: &GlobalTransform,
    bounding_radius: f32,
) -> (DVec3, AQuat, f32) {
    let (scale, rotation, translation) = transform.to_scale_rotation_translation();
    let center = translation + rotation * (scale * lod.center);
    let radius = bounding_radius * scale.abs().max_element();
    (
        DVec3::from_array(center.to_array().map(f64::from)),
        AQuat::from_array(rotation.to_array()),
        radius,
    )
}

/// Adds an entity to one camera's selector (its profile first, once).
fn register(
    view: &mut CameraSelector,
    entity: Entity,
    lod: &AcuityLod,
    transform: &GlobalTransform,
    profile_id: AssetId<AcuityProfile>,
    source: &acuity::Profile,
) -> acuity::Result<()> {
    let profile = match view.profiles.get(&profile_id) {
        Some(&p) => p,
        None => {
            let p = view.selector.add_profile(source)?;
            view.profiles.insert(profile_id, p);
            p
        }
    };
    let (center, rotation, radius) = object_pose(lod, transform, source.bounding_radius);
    let id = view.selector.add_object(ObjectDesc {
        center,
        radius,
        rotation,
        profile,
    })?;
    if let Err(e) = view.selector.set_bias(id, lod.bias) {
        view.selector.remove_object(id)?;
        return Err(e);
    }
    view.objects.insert(entity, id);
    view.entities.insert(id, entity);
    Ok(())
}

/// Removes an entity's object from one camera's selector.
fn unregister(view: &mut CameraSelector, entity: Entity) {
    if let Some(id) = view.objects.remove(&entity) {
        view.entities.remove(&id);
        // The id came from this selector, so it is present.
        let _ = view.selector.remove_object(id);
    }
}

/// Reports an entity's error once and marks it refused.
fn refuse(
    tracked: &mut Tracked,
    entity: Entity,
    reason: String,
    errors: &mut MessageWriter<AcuityError>,
) {
    tracing::warn!("acuity: entity {entity}: {reason}");
    errors.write(AcuityError::Object { entity, reason });
    tracked.registration = Registration::Refused;
}

/// Keeps the selectors' objects in step with the entities.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sync_objects(
    mut cameras: ResMut<AcuityCameras>,
    mut tracked: ResMut<TrackedEntities>,
    profiles: Res<Assets<AcuityProfile>>,
    query: Query<(Entity, Ref<AcuityLod>, Ref<GlobalTransform>)>,
    mut removed: RemovedComponents<AcuityLod>,
    mut commands: Commands,
    mut errors: MessageWriter<AcuityError>,
) {
    let (cameras, tracked) = (&mut *cameras, &mut *tracked);
    for entity in removed.read() {
        if query.contains(entity) {
            continue; // removed and inserted again: re-registered below
        }
        if tracked.entities.remove(&entity).is_some() {
            for view in cameras.views.values_mut() {
                unregister(view, entity);
            }
        }
    }
    for (entity, lod, transform) in &query {
        let record = tracked.entities.entry(entity).or_insert(Tracked {
            registration: Registration::Pending,
            applied: None,
            decider: None,
        });
        if lod.is_changed() && !lod.is_added() {
            for view in cameras.views.values_mut() {
                unregister(view, entity);
            }
            record.registration = Registration::Pending;
            record.applied = None;
        }
        if lod.is_added() {
            commands.entity(entity).try_insert(SelectedLod(None));
        }
        let profile_id = lod.profile.id();
        match record.registration {
            Registration::Refused => continue,
            Registration::Pending => {
                let Some(profile) = profiles.get(profile_id) else {
                    continue; // not loaded (yet): a failed load is an asset event
                };
                let profile = &profile.0;
                if lod.levels.len() != profile.lod_count() {
                    let reason = format!(
                        "its LOD chain has {} levels, its profile `{}` {} LODs",
                        lod.levels.len(),
                        profile.name,
                        profile.lod_count()
                    );
                    refuse(record, entity, reason, &mut errors);
                    continue;
                }
                let mut failed = None;
                for view in cameras.views.values_mut() {
                    if let Err(e) = register(view, entity, &lod, &transform, profile_id, profile) {
                        failed = Some(e.to_string());
                        break;
                    }
                }
                if let Some(reason) = failed {
                    for view in cameras.views.values_mut() {
                        unregister(view, entity);
                    }
                    refuse(record, entity, reason, &mut errors);
                    continue;
                }
                record.registration = Registration::Ready;
                tracked.fresh.push(entity);
            }
            Registration::Ready => {
                let Some(profile) = profiles.get(profile_id) else {
                    continue;
                };
                let profile = &profile.0;
                let mut failed = None;
                if transform.is_changed() {
                    let (center, rotation, radius) =
                        object_pose(&lod, &transform, profile.bounding_radius);
                    for view in cameras.views.values_mut() {
                        let Some(id) = view.object(entity) else {
                            continue;
                        };
                        let moved = view
                            .selector
                            .set_pose(id, center, rotation)
                            .and_then(|()| view.selector.set_radius(id, radius));
                        if let Err(e) = moved {
                            failed = Some(e.to_string());
                        }
                    }
                }
                // Cameras new this frame.
                for view in cameras.views.values_mut() {
                    if view.needs_all
                        && failed.is_none()
                        && !view.objects.contains_key(&entity)
                        && let Err(e) =
                            register(view, entity, &lod, &transform, profile_id, profile)
                    {
                        failed = Some(e.to_string());
                    }
                }
                if let Some(reason) = failed {
                    for view in cameras.views.values_mut() {
                        unregister(view, entity);
                    }
                    refuse(record, entity, reason, &mut errors);
                }
            }
        }
    }
    for view in cameras.views.values_mut() {
        view.needs_all = false;
    }
}
