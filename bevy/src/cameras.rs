//! One `acuity::Selector` per camera ([`AcuityCameras`]), kept in step
//! with the cameras: made when a perspective camera appears, its display
//! rebuilt when the window's size or the field of view changes, dropped
//! when the camera is despawned or turned off.
//!
//! A camera's display is its viewport in physical pixels (from the
//! camera's computed viewport when the renderer has set it, else from its
//! window) and its field of view: the perspective projection's vertical
//! field, the horizontal one from the viewport's aspect, or an
//! [`AcuityView`]'s edges (an XR eye).

use std::collections::HashMap;

use acuity::{Display, FovEdges, ObjectId, ProfileId, Selection, Selector, SelectorSettings};
use bevy::asset::AssetId;
use bevy::camera::{Camera, Projection, RenderTarget};
use bevy::ecs::entity::{Entity, EntityHashMap};
use bevy::ecs::message::MessageWriter;
use bevy::ecs::query::With;
use bevy::ecs::resource::Resource;
use bevy::ecs::system::{Query, Res, ResMut};
use bevy::window::{PrimaryWindow, Window, WindowRef};

use crate::components::AcuityView;
use crate::profile_asset::AcuityProfile;
use crate::settings::{AcuityError, AcuitySettings};

/// One camera's selector and the mapping between its objects and entities.
pub struct CameraSelector {
    pub(crate) selector: Selector,
    pub(crate) profiles: HashMap<AssetId<AcuityProfile>, ProfileId>,
    pub(crate) objects: EntityHashMap<ObjectId>,
    pub(crate) entities: HashMap<ObjectId, Entity>,
    /// New this frame: every registered entity is still to be added.
    pub(crate) needs_all: bool,
    /// The last selection error reported for this camera (reported once).
    pub(crate) error: Option<String>,
}

impl CameraSelector {
    fn new(display: Display, settings: &SelectorSettings) -> Self {
        Self {
            selector: Selector::new(display, *settings),
            profiles: HashMap::new(),
            objects: EntityHashMap::default(),
            entities: HashMap::new(),
            needs_all: true,
            error: None,
        }
    }

    /// The runtime's selector (selections, fades, triangles, diagnostics).
    pub fn selector(&self) -> &Selector {
        &self.selector
    }

    /// The display this camera selects for.
    pub fn display(&self) -> &Display {
        self.selector.display()
    }

    /// The object of an entity with [`AcuityLod`](crate::AcuityLod), if
    /// registered with this camera.
    pub fn object(&self, entity: Entity) -> Option<ObjectId> {
        self.objects.get(&entity).copied()
    }

    /// What this camera chose for an entity this frame (`None`: not
    /// registered).
    pub fn selection(&self, entity: Entity) -> Option<Selection> {
        self.object(entity).map(|id| self.selector.selection(id))
    }

    /// The number of objects this camera's selector holds.
    pub fn object_count(&self) -> usize {
        self.selector.object_count()
    }
}

/// Every selecting camera's [`CameraSelector`], by camera entity.
#[derive(Resource, Default)]
pub struct AcuityCameras {
    pub(crate) views: EntityHashMap<CameraSelector>,
    /// A camera went away this frame: every entity's LOD is reconsidered.
    pub(crate) removed_any: bool,
    /// The display error last reported per camera (reported once).
    pub(crate) display_errors: EntityHashMap<String>,
}

impl AcuityCameras {
    /// A camera's selector, if that camera selects.
    pub fn get(&self, camera: Entity) -> Option<&CameraSelector> {
        self.views.get(&camera)
    }

    /// The number of selecting cameras.
    pub fn len(&self) -> usize {
        self.views.len()
    }

    /// Whether no camera selects.
    pub fn is_empty(&self) -> bool {
        self.views.is_empty()
    }

    /// The selecting cameras and their selectors, in no fixed order.
    pub fn iter(&self) -> impl Iterator<Item = (Entity, &CameraSelector)> {
        self.views.iter().map(|(e, v)| (*e, v))
    }
}

/// The viewport's size in physical pixels, where it can be known.
fn viewport_px(
    camera: &Camera,
    target: Option<&RenderTarget>,
    view: Option<&AcuityView>,
    windows: &Query<&Window>,
    primary: &Query<&Window, With<PrimaryWindow>>,
) -> Option<[u32; 2]> {
    if let Some(px) = view.and_then(|v| v.resolution_px) {
        return Some(px);
    }
    if let Some(size) = camera.physical_viewport_size() {
        return Some(size.to_array());
    }
    let window = match target? {
        RenderTarget::Window(WindowRef::Primary) => primary.single().ok()?,
        RenderTarget::Window(WindowRef::Entity(e)) => windows.get(*e).ok()?,
        RenderTarget::None { size } => return Some(size.to_array()),
        _ => return None,
    };
    Some(window.physical_size().to_array())
}

/// The display a camera selects for: `Ok(None)` where it is not a
/// perspective camera or its size is not known yet.
pub(crate) fn camera_display(
    camera: &Camera,
    projection: &Projection,
    target: Option<&RenderTarget>,
    view: Option<&AcuityView>,
    windows: &Query<&Window>,
    primary: &Query<&Window, With<PrimaryWindow>>,
) -> acuity::Result<Option<Display>> {
    let Some(resolution) = viewport_px(camera, target, view, windows, primary) else {
        return Ok(None);
    };
    let edges = match (view.and_then(|v| v.fov_edges), projection) {
        (Some(edges), _) => edges,
        (None, Projection::Perspective(p)) => {
            let [w, h] = resolution.map(|x| x.max(1) as f32);
            let half_y = 0.5 * p.fov;
            let half_x = (half_y.tan() * w / h).atan();
            FovEdges::symmetric([2.0 * half_x.to_degrees(), 2.0 * half_y.to_degrees()])
        }
        (None, _) => return Ok(None),
    };
    let mut display = Display::with_fov_edges(resolution, edges)?;
    if let Some(hz) = view.and_then(|v| v.refresh_hz) {
        display = display.with_refresh_hz(Some(hz))?;
    }
    Ok(Some(display))
}

type CameraItem<'a> = (
    Entity,
    &'a Camera,
    &'a Projection,
    Option<&'a RenderTarget>,
    Option<&'a AcuityView>,
);

/// Makes, updates and drops the cameras' selectors.
pub(crate) fn sync_cameras(
    mut cameras: ResMut<AcuityCameras>,
    settings: Res<AcuitySettings>,
    query: Query<CameraItem>,
    windows: Query<&Window>,
    primary: Query<&Window, With<PrimaryWindow>>,
    mut errors: MessageWriter<AcuityError>,
) {
    let mut selector_settings = settings.selector;
    selector_settings.track_changes = true;
    let cameras = &mut *cameras;
    cameras.removed_any = false;
    // Despawned, switched off or no longer perspective: dropped below.
    let before = cameras.views.len();
    cameras.views.retain(|e, view| {
        query.get(*e).is_ok_and(|(_, c, ..)| c.is_active)
            && *view.selector.settings() == selector_settings
    });
    cameras.removed_any = cameras.views.len() != before;
    cameras.display_errors.retain(|e, _| query.contains(*e));
    for (entity, camera, projection, target, view) in &query {
        if !camera.is_active {
            continue;
        }
        let display = match camera_display(camera, projection, target, view, &windows, &primary) {
            Ok(Some(d)) => d,
            Ok(None) => {
                // Not (or no longer) a perspective camera of known size.
                cameras.removed_any |= cameras.views.remove(&entity).is_some();
                continue;
            }
            Err(e) => {
                let reason = e.to_string();
                if cameras.display_errors.get(&entity) != Some(&reason) {
                    tracing::warn!("acuity: camera {entity}: {reason}");
                    errors.write(AcuityError::Camera {
                        camera: entity,
                        reason: reason.clone(),
                    });
                    cameras.display_errors.insert(entity, reason);
                }
                continue;
            }
        };
        cameras.display_errors.remove(&entity);
        match cameras.views.get_mut(&entity) {
            Some(v) if *v.selector.display() != display => {
                v.selector.set_display(display);
            }
            Some(_) => {}
            None => {
                cameras
                    .views
                    .insert(entity, CameraSelector::new(display, &selector_settings));
            }
        }
    }
}
