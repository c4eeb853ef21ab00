//! What an application puts on entities: [`AcuityLod`] (an entity's LOD
//! chain and profile) and [`AcuityView`] (a camera's display, where its
//! projection and window do not tell it); and what the plugin writes back:
//! [`SelectedLod`] and, during a cross-fade, [`LodFade`].

use bevy::asset::Handle;
use bevy::ecs::component::Component;
use bevy::ecs::entity::Entity;
use bevy::math::Vec3;
use bevy::mesh::Mesh;

use crate::profile_asset::AcuityProfile;

/// The drawables of an LOD chain, finest (LOD 0) first; as many as the
/// profile has LODs.
#[derive(Clone, Debug)]
pub enum LodLevels {
    /// One mesh per LOD: the plugin sets the entity's
    /// [`Mesh3d`](bevy::mesh::Mesh3d) to the chosen one (inserting it when
    /// absent). Materials are untouched.
    Meshes(Vec<Handle<Mesh>>),
    /// One entity per LOD, usually children of this one (an HLOD group: a
    /// level may be a whole subtree): the plugin makes the chosen one
    /// [`Visibility::Inherited`](bevy::camera::visibility::Visibility) and
    /// the others `Hidden`, and cross-fades between two by dithering.
    Children(Vec<Entity>),
}

impl LodLevels {
    /// The number of LODs.
    pub fn len(&self) -> usize {
        match self {
            Self::Meshes(m) => m.len(),
            Self::Children(c) => c.len(),
        }
    }

    /// Whether there are no LODs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// An entity whose LOD acuity chooses: its profile and its LOD chain.
///
/// The object's bounding sphere is the profile's `bounding_radius` (mesh
/// units) times the largest scale of the entity's
/// [`GlobalTransform`](bevy::transform::components::GlobalTransform),
/// centred on the entity's origin plus [`center`](Self::center). The
/// profile's object frame is the entity's (its rotation is the object's).
/// Changing this component re-registers the entity.
#[derive(Component, Clone, Debug)]
pub struct AcuityLod {
    /// The profile; the entity is registered once the asset has loaded.
    pub profile: Handle<AcuityProfile>,
    /// The LOD chain, finest first.
    pub levels: LodLevels,
    /// The bounding sphere's centre in the entity's local frame, mesh
    /// units (the profile's analysis camera aimed there): zero for a mesh
    /// centred on its origin.
    pub center: Vec3,
    /// Multiplies the object's threshold ([`acuity::Selector::set_bias`]):
    /// above 1 keeps more detail, below 1 less; 1 is neutral.
    pub bias: f32,
}

impl AcuityLod {
    /// An LOD chain of meshes swapped on this entity.
    pub fn meshes(profile: Handle<AcuityProfile>, meshes: Vec<Handle<Mesh>>) -> Self {
        Self {
            profile,
            levels: LodLevels::Meshes(meshes),
            center: Vec3::ZERO,
            bias: 1.0,
        }
    }

    /// An LOD chain of entities (usually children) shown one at a time.
    pub fn children(profile: Handle<AcuityProfile>, children: Vec<Entity>) -> Self {
        Self {
            profile,
            levels: LodLevels::Children(children),
            center: Vec3::ZERO,
            bias: 1.0,
        }
    }
}

/// The LOD the plugin applied to an entity with [`AcuityLod`]: the finest
/// any camera chose (0 = finest). `None` until a camera has seen it; an
/// entity that leaves every camera's view keeps its last LOD (Bevy culls
/// it), so `None` never returns once set.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SelectedLod(pub Option<usize>);

/// A cross-fade in progress on an entity, from the runtime's fade state
/// ([`acuity::select::Fade`]) of the camera that chose the entity's LOD:
/// draw `from_lod` with weight `1 - fraction` and `to_lod` with weight
/// `fraction`. Removed when the fade ends. For [`LodLevels::Children`] the
/// plugin dithers the two levels itself ([`crate::AcuitySettings::dither`]);
/// for [`LodLevels::Meshes`] (one entity, one mesh) a custom material can
/// read it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct LodFade {
    /// The LOD fading out.
    pub from_lod: usize,
    /// The LOD fading in (the entity's [`SelectedLod`]).
    pub to_lod: usize,
    /// How far the fade has gone, in `[0, 1)`.
    pub fraction: f32,
}

/// A camera's display where its projection and render target do not give
/// it: an XR eye's asymmetric field (OpenXR's four angles per eye), a
/// render target whose size the plugin cannot read without the renderer
/// (an image), or a refresh rate other than 60 Hz. Optional: a perspective
/// camera rendering to a window needs none.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct AcuityView {
    /// The viewport's size, physical pixels `[width, height]`; `None`:
    /// from the camera's viewport or its window.
    pub resolution_px: Option<[u32; 2]>,
    /// The field's four edges in deg (left, right, up, down; see
    /// [`acuity::FovEdges::from_openxr_radians`]); `None`: from the
    /// perspective projection's vertical field and the viewport's aspect.
    pub fov_edges: Option<acuity::FovEdges>,
    /// The display's refresh rate, Hz; `None`: the runtime's default
    /// (60 Hz).
    pub refresh_hz: Option<f32>,
}
