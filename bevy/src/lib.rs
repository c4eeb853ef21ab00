//! `bevy_acuity`: acuity's perceptual level-of-detail selection in Bevy.
//!
//! Add [`AcuityPlugin`], give each entity with an LOD chain an
//! [`AcuityLod`] (its profile, loaded as a Bevy asset, and its levels:
//! meshes swapped on the entity, or child entities shown one at a time),
//! and every active perspective camera selects, each frame after transform
//! propagation, the coarsest LOD whose missing detail its viewer cannot
//! see; the entity draws the finest LOD any camera chose. Only the entities
//! in a camera's change list are touched.
//!
//! Why a plugin rather than Bevy's distance-based
//! [`VisibilityRange`](bevy::camera::visibility::VisibilityRange): a
//! distance table ignores the display (pixels per degree), the gaze and
//! motion, and what each LOD actually lacks; acuity's profiles measure the
//! last and its runtime judges them for the first three. The plugin keeps
//! Bevy's dithered cross-fade for the switch itself.
//!
//! The library needs no renderer: it depends on Bevy's ECS, assets,
//! transforms, cameras, meshes, windows and time only (`bevy` without
//! default features), so its tests run headless. The window example
//! (feature `window`) adds the renderer. Usage, system order and limits:
//! `docs/bevy.md` in the repository.

mod apply;
mod cameras;
mod components;
mod frame;
mod objects;
mod profile_asset;
mod settings;

use bevy::app::{App, Plugin, PostUpdate};
use bevy::asset::{AssetApp, AssetEventSystems};
use bevy::camera::visibility::VisibilitySystems;
use bevy::ecs::schedule::{IntoScheduleConfigs, SystemSet};
use bevy::transform::TransformSystems;

pub use crate::cameras::{AcuityCameras, CameraSelector};
pub use crate::components::{AcuityLod, AcuityView, LodFade, LodLevels, SelectedLod};
pub use crate::profile_asset::{AcuityProfile, AcuityProfileLoader, ProfileLoadError};
pub use crate::settings::{AcuityError, AcuityGaze, AcuityScheduler, AcuitySettings, AcuityStats};
/// The runtime, for its settings and types (`acuity::SelectorSettings`,
/// `acuity::Tracker`, `acuity::FovEdges`, `acuity::Profile`).
pub use acuity;

/// The plugin's systems, in `PostUpdate`: after transform propagation and
/// asset events, before Bevy computes bounds and visibility (so a swapped
/// mesh is culled with its own bounds the same frame).
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AcuitySystems;

/// Perceptual LOD selection: the [`AcuityProfile`] asset and its loader,
/// the resources ([`AcuitySettings`], [`AcuityGaze`], [`AcuityScheduler`],
/// [`AcuityStats`], [`AcuityCameras`]), the [`AcuityError`] message, and
/// the systems in [`AcuitySystems`].
///
/// Needs Bevy's `AssetPlugin` (added before it) and a time and transform
/// plugin (`DefaultPlugins` or `MinimalPlugins` with `TransformPlugin`).
#[derive(Default)]
pub struct AcuityPlugin;

impl Plugin for AcuityPlugin {
    fn build(&self, app: &mut App) {
        app.init_asset::<AcuityProfile>()
            .init_asset_loader::<AcuityProfileLoader>()
            .add_message::<AcuityError>()
            .init_resource::<AcuitySettings>()
            .init_resource::<AcuityGaze>()
            .init_resource::<AcuityScheduler>()
            .init_resource::<AcuityStats>()
            .init_resource::<AcuityCameras>()
            .init_resource::<objects::TrackedEntities>()
            .configure_sets(
                PostUpdate,
                AcuitySystems
                    .after(TransformSystems::Propagate)
                    .after(AssetEventSystems)
                    .before(VisibilitySystems::CalculateBounds)
                    .before(VisibilitySystems::VisibilityPropagate)
                    .before(VisibilitySystems::CheckVisibility),
            )
            .add_systems(
                PostUpdate,
                (
                    cameras::sync_cameras,
                    objects::sync_objects,
                    frame::select_lods,
                    apply::apply_lods,
                )
                    .chain()
                    .in_set(AcuitySystems),
            );
    }
}
