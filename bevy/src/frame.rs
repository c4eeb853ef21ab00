//! The per-frame selection: the scheduler is fed the frame time Bevy
//! measured (`Time<Real>`), then every camera's selector selects from the
//! camera's `GlobalTransform` (after transform propagation) and the gaze,
//! at the fixed `s`, the reactive scheduler's `s`, or within the
//! predictive scheduler's triangle budget.

use acuity::glam::{DVec3, Quat as AQuat};
use acuity::{Camera as ACamera, FrameInput};
use bevy::camera::Camera;
use bevy::ecs::entity::Entity;
use bevy::ecs::message::MessageWriter;
use bevy::ecs::query::With;
use bevy::ecs::system::{Local, Query, Res, ResMut};
use bevy::time::{Real, Time};
use bevy::transform::components::GlobalTransform;

use crate::cameras::AcuityCameras;
use crate::objects::{Registration, TrackedEntities};
use crate::settings::{AcuityError, AcuityGaze, AcuityScheduler, AcuitySettings, AcuityStats};

/// What the scheduler needs from the frame before.
#[derive(Default)]
pub(crate) struct LastFrame {
    selected: bool,
    triangles: u64,
    coarsest: u64,
}

/// Runs every camera's selector for this frame.
#[allow(clippy::too_many_arguments)]
pub(crate) fn select_lods(
    mut cameras: ResMut<AcuityCameras>,
    settings: Res<AcuitySettings>,
    gaze: Res<AcuityGaze>,
    time: Res<Time<Real>>,
    mut scheduler: ResMut<AcuityScheduler>,
    mut stats: ResMut<AcuityStats>,
    tracked: Res<TrackedEntities>,
    transforms: Query<&GlobalTransform, With<Camera>>,
    mut last: Local<LastFrame>,
    mut errors: MessageWriter<AcuityError>,
) {
    let dt_s = time.delta_secs();
    // The frame just measured is the one selected last time.
    if last.selected {
        match &mut *scheduler {
            AcuityScheduler::Off => {}
            AcuityScheduler::Reactive(r) => {
                r.observe(dt_s, last.triangles, last.coarsest);
            }
            AcuityScheduler::Predictive(p) => p.observe(dt_s, last.triangles, last.coarsest),
        }
    }
    let (scale, budget) = match &mut *scheduler {
        AcuityScheduler::Off => (settings.scale, None),
        AcuityScheduler::Reactive(r) => (r.scale(), None),
        AcuityScheduler::Predictive(p) => (1.0, Some(p.triangle_budget())),
    };
    let share = budget.map(|b| b / cameras.views.len().max(1) as u64);
    let mut frame = LastFrame::default();
    let mut lowest_scale = scale;
    for (&camera, view) in cameras.views.iter_mut() {
        let Ok(transform) = transforms.get(camera) else {
            continue;
        };
        let (_, rotation, translation) = transform.to_scale_rotation_translation();
        let mut frame_gaze = gaze.gaze;
        frame_gaze.pursued = gaze.pursued.and_then(|e| view.object(e));
        let input = FrameInput {
            camera: ACamera {
                position: DVec3::from_array(translation.to_array().map(f64::from)),
                orientation: AQuat::from_array(rotation.to_array()),
            },
            gaze: frame_gaze,
            dt_s,
            scale,
        };
        let result = match share {
            None => view.selector.select(&input).map(|()| {
                frame.triangles += view.selector.triangles();
            }),
            Some(share) => view
                .selector
                .select_within_budget(&input, share)
                .map(|outcome| {
                    frame.triangles += outcome.triangles;
                    lowest_scale = lowest_scale.min(outcome.scale);
                }),
        };
        match result {
            Ok(()) => {
                frame.selected = true;
                frame.coarsest += view.selector.coarsest_triangles();
                view.error = None;
            }
            Err(e) => report(camera, e.to_string(), &mut view.error, &mut errors),
        }
    }
    *stats = AcuityStats {
        scale: lowest_scale,
        triangles: frame.triangles,
        budget,
        cameras: cameras.views.len(),
        objects: tracked
            .entities
            .values()
            .filter(|t| t.registration == Registration::Ready)
            .count(),
    };
    *last = frame;
}

/// Reports a camera's error once (until it selects again).
fn report(
    camera: Entity,
    reason: String,
    known: &mut Option<String>,
    errors: &mut MessageWriter<AcuityError>,
) {
    if known.as_ref() != Some(&reason) {
        tracing::warn!("acuity: camera {camera}: {reason}");
        errors.write(AcuityError::Camera {
            camera,
            reason: reason.clone(),
        });
        *known = Some(reason);
    }
}
