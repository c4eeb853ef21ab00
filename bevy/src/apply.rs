//! Applying the selections: only the entities in some camera's change
//! list (or every entity, the frame a camera goes away) are looked at; each
//! draws the finest LOD any camera chose (a mesh swapped, or one child
//! shown), and an entity culled by every camera keeps its LOD (Bevy culls
//! it).
//!
//! Cross-fades come from the runtime's fade state of the camera that chose
//! the entity's LOD: a [`LodFade`] component while it lasts, and for child
//! levels both levels shown with complementary dithers through Bevy's
//! [`VisibilityRange`] (its margins placed around the camera's distance so
//! that the incoming level covers `fraction` of the pixels and the outgoing
//! one the rest; Bevy's renderer dithers any mesh with a visibility range).

use std::ops::Range;

use bevy::camera::visibility::{Visibility, VisibilityRange};
use bevy::ecs::change_detection::DetectChangesMut;
use bevy::ecs::entity::{Entity, EntityHashMap};
use bevy::ecs::system::{Commands, Local, Query, Res, ResMut};
use bevy::mesh::Mesh3d;
use bevy::transform::components::GlobalTransform;

use crate::cameras::AcuityCameras;
use crate::components::{AcuityLod, LodFade, LodLevels, SelectedLod};
use crate::objects::{Registration, TrackedEntities};
use crate::settings::AcuitySettings;

/// Buffers kept between frames.
#[derive(Default)]
pub(crate) struct ApplyState {
    dirty: Vec<Entity>,
    fading: EntityHashMap<LodFade>,
    fading_next: EntityHashMap<LodFade>,
}

/// Shows level `lod` of a child chain: that child `Inherited` (and the
/// fading-out one, if any), the others `Hidden`.
fn show_children(
    children: &[Entity],
    lod: usize,
    also: Option<usize>,
    visibility: &mut Query<&mut Visibility>,
    commands: &mut Commands,
) {
    for (i, &child) in children.iter().enumerate() {
        let want = if i == lod || Some(i) == also {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        };
        match visibility.get_mut(child) {
            Ok(mut v) => {
                v.set_if_neq(want);
            }
            Err(_) => {
                commands.entity(child).try_insert(want);
            }
        }
    }
}

/// Draws LOD `lod` of an entity.
fn apply_lod(
    entity: Entity,
    levels: &LodLevels,
    lod: usize,
    meshes: &mut Query<&mut Mesh3d>,
    visibility: &mut Query<&mut Visibility>,
    commands: &mut Commands,
) {
    match levels {
        LodLevels::Meshes(m) => {
            let Some(mesh) = m.get(lod) else { return };
            match meshes.get_mut(entity) {
                Ok(mut current) => {
                    if current.0 != *mesh {
                        current.0 = mesh.clone();
                    }
                }
                Err(_) => {
                    commands.entity(entity).try_insert(Mesh3d(mesh.clone()));
                }
            }
        }
        LodLevels::Children(c) => show_children(c, lod, None, visibility, commands),
    }
}

/// The margin, world units, around a camera `distance` away in which a
/// visibility range shows `fraction` of the incoming level: Bevy fades a
/// level in over its start margin and out over its end margin, linearly
/// in distance, with complementary dither patterns.
fn fade_margin(distance: f32, fraction: f32) -> Range<f32> {
    let width = 0.5 * distance;
    let start = distance - fraction.clamp(0.0, 1.0) * width;
    start..start + width
}

/// Applies this frame's selections and fades.
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply_lods(
    cameras: Res<AcuityCameras>,
    settings: Res<AcuitySettings>,
    mut tracked: ResMut<TrackedEntities>,
    lods: Query<&AcuityLod>,
    mut selected: Query<&mut SelectedLod>,
    mut meshes: Query<&mut Mesh3d>,
    mut visibility: Query<&mut Visibility>,
    transforms: Query<&GlobalTransform>,
    mut state: Local<ApplyState>,
    mut commands: Commands,
) {
    let state = &mut *state;
    state.dirty.clear();
    if cameras.removed_any {
        state.dirty.extend(tracked.entities.keys().copied());
    } else {
        for (_, view) in cameras.iter() {
            let ids = view.selector.changed().iter();
            state
                .dirty
                .extend(ids.filter_map(|id| view.entities.get(id).copied()));
        }
        state.dirty.sort_unstable();
        state.dirty.dedup();
    }
    for &entity in &state.dirty {
        let Some(record) = tracked.entities.get_mut(&entity) else {
            continue;
        };
        let Ok(lod) = lods.get(entity) else { continue };
        if record.registration != Registration::Ready {
            continue;
        }
        let mut best: Option<(usize, Entity)> = None;
        for (camera, view) in cameras.iter() {
            if let Some(l) = view.selection(entity).and_then(|s| s.lod())
                && best.is_none_or(|(b, _)| l < b)
            {
                best = Some((l, camera));
            }
        }
        let Some((chosen, camera)) = best else {
            continue; // culled by every camera: keep what is drawn
        };
        record.decider = Some(camera);
        if record.applied == Some(chosen) {
            continue;
        }
        record.applied = Some(chosen);
        apply_lod(
            entity,
            &lod.levels,
            chosen,
            &mut meshes,
            &mut visibility,
            &mut commands,
        );
        match selected.get_mut(entity) {
            Ok(mut s) => s.0 = Some(chosen),
            Err(_) => {
                commands
                    .entity(entity)
                    .try_insert(SelectedLod(Some(chosen)));
            }
        }
    }

    // Registered this frame but culled by every camera: the coarsest LOD.
    for entity in std::mem::take(&mut tracked.fresh) {
        let applied = tracked.entities.get(&entity).and_then(|r| r.applied);
        if let (None, Ok(lod)) = (applied, lods.get(entity))
            && let Some(coarsest) = lod.levels.len().checked_sub(1)
        {
            apply_lod(
                entity,
                &lod.levels,
                coarsest,
                &mut meshes,
                &mut visibility,
                &mut commands,
            );
        }
    }

    // Fades: those of the camera that chose each entity's LOD.
    state.fading_next.clear();
    for (camera, view) in cameras.iter() {
        for fade in view.selector.fades() {
            let Some(&entity) = view.entities.get(&fade.object) else {
                continue;
            };
            let Some(record) = tracked.entities.get(&entity) else {
                continue;
            };
            if record.decider == Some(camera) && record.applied == Some(fade.to_lod) {
                state.fading_next.insert(
                    entity,
                    LodFade {
                        from_lod: fade.from_lod,
                        to_lod: fade.to_lod,
                        fraction: fade.fraction,
                    },
                );
            }
        }
    }
    for (&entity, fade) in &state.fading_next {
        if state.fading.get(&entity) != Some(fade) {
            commands.entity(entity).try_insert(*fade);
        }
        let Ok(AcuityLod {
            levels: LodLevels::Children(children),
            ..
        }) = lods.get(entity)
        else {
            continue;
        };
        if !settings.dither {
            continue;
        }
        let camera = tracked.entities.get(&entity).and_then(|r| r.decider);
        let eye = camera.and_then(|c| transforms.get(c).ok());
        let (Some(eye), Some(&from), Some(&to)) =
            (eye, children.get(fade.from_lod), children.get(fade.to_lod))
        else {
            continue;
        };
        show_children(
            children,
            fade.to_lod,
            Some(fade.from_lod),
            &mut visibility,
            &mut commands,
        );
        for (child, incoming) in [(from, false), (to, true)] {
            let Ok(at) = transforms.get(child) else {
                continue;
            };
            let distance = at.translation().distance(eye.translation());
            if !(distance.is_finite() && distance > 0.0) {
                continue;
            }
            let margin = fade_margin(distance, fade.fraction);
            let range = if incoming {
                VisibilityRange {
                    start_margin: margin,
                    end_margin: 1e30..f32::MAX,
                    use_aabb: false,
                }
            } else {
                VisibilityRange {
                    start_margin: 0.0..0.0,
                    end_margin: margin,
                    use_aabb: false,
                }
            };
            commands.entity(child).try_insert(range);
        }
    }
    // Fades that ended: one level shown, no ranges left behind.
    for (&entity, fade) in &state.fading {
        if state.fading_next.contains_key(&entity) {
            continue;
        }
        commands.entity(entity).try_remove::<LodFade>();
        let Ok(AcuityLod {
            levels: LodLevels::Children(children),
            ..
        }) = lods.get(entity)
        else {
            continue;
        };
        for i in [fade.from_lod, fade.to_lod] {
            if let Some(&child) = children.get(i) {
                commands.entity(child).try_remove::<VisibilityRange>();
            }
        }
        if let Some(lod) = tracked.entities.get(&entity).and_then(|r| r.applied) {
            show_children(children, lod, None, &mut visibility, &mut commands);
        }
    }
    std::mem::swap(&mut state.fading, &mut state.fading_next);
}
