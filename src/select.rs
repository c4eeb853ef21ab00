//! Per-object LOD selection: the runtime's hot loop (REFERENCE §3–§4).
//!
//! For every object and frame: angular size `theta = 2 asin(r / d)`,
//! eccentricity from the gaze, smoothed retinal velocity, the acuity
//! `T = s H(v, E)` in c/deg, and the coarsest LOD `j` whose removed
//! features (transitions `0..j` at the chosen viewpoint and the rung of the
//! size ladder nearest the object's size on screen) are all invisible: a
//! feature is invisible when its critical frequency in c/diam (its
//! frequency scaled by how much contrast it has, [`crate::rows`]) exceeds
//! `k = T u`, `u` the angular size the object is judged at (its rung's
//! upper end, or its own size `theta` on the bottom and top rungs). Prefix minima of the critical frequencies are compiled
//! per viewpoint and rung when a profile is added (they depend on the
//! display's photometry and the observer), in rows padded with `-inf` to
//! whole groups of 4, which makes the choice a count of 4-wide
//! comparisons.
//!
//! Layout. Objects with more than one LOD live in blocks of 64, field by
//! field within a block (`f64` centre coordinates, radius, profile index,
//! rotation), with their motion state in matching blocks and their outputs
//! in flat arrays; objects with one LOD live apart and are only culled (or
//! not touched at all with culling off). Each block is first culled as a
//! whole, branch-free (the camera-relative centre is taken in `f64` and then
//! rounded to `f32`, so far-off scenes select like scenes at the origin);
//! the visible objects of a sparse block go to a queue of up to 64, which
//! is modelled when the next block's would not fit (a block with most
//! objects visible is modelled whole, which costs less than queueing), in
//! short passes over plain arrays that the compiler vectorises (branch-free
//! polynomial `asin`/`acos`/`log10`, [`crate::fastmath`]), then the viewpoint lookup
//! and the LOD count. Profiles with the same viewpoints share one lookup
//! table; when every profile with more than one LOD has the same row
//! stride and lookup (the profiles of one offline pass), rows are found and
//! LODs counted in straight-line passes too, and a dense block's outputs
//! are written by masks rather than object by object. 64 lanes a pass give
//! each pass 4 independent vectors of 16 to overlap (the polynomials are
//! long dependency chains); 32 measured about 1 ns per object slower with
//! AVX-512. Each block's data is prefetched into L2 two blocks ahead (into
//! L1 it evicts the loop's own 13 KB of scratch). With the feature
//! `simd-dispatch` the loop runs compiled for AVX-512 or AVX2 and FMA where
//! the CPU has them (bit-identical results: nothing is fused). The loop is
//! monomorphised over the velocity, eccentricity and nearest-viewpoint
//! switches, so a switched-off component costs nothing, allocates nothing,
//! and runs on rayon (feature `parallel`) above
//! [`SelectorSettings::parallel_min_objects`].

// Index loops over parallel fixed-size arrays are what vectorises here.
#![allow(clippy::needless_range_loop)]

use glam::{DVec3, Mat3, Quat, Vec3, Vec4};

use crate::acuity::{
    Components, DRIFT_VELOCITY_DEG_PER_S, ECCENTRICITY_CEILING_DEG, ECCENTRICITY_FLOOR_DEG,
    EccentricityModel, MAX_ACUITY_CPD, MAX_ECCENTRICITY_DEG, MIN_ACUITY_CPD,
    VELOCITY_CEILING_DEG_PER_S, VELOCITY_FLOOR_DEG_PER_S, VelocityModel, cortical_factor_unchecked,
};
use crate::camera::{Camera, Gaze, MAX_WORLD_COORDINATE, Tracker, normalized_rotation};
use crate::csf::{Csf, Observer};
use crate::display::Display;
use crate::error::{Error, Result};
use crate::fastmath;
use crate::profile::Profile;
use crate::rows;
use crate::viewpoints::{self, ViewpointLookup};

/// Objects per block of the store.
const BLOCK: usize = 64;
/// Capacity of the queue of visible objects (of sparse blocks): it is
/// modelled when the next block's would not fit, and at the end.
const QUEUE: usize = BLOCK;
/// Objects per parallel work item; a whole number of blocks.
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
const CHUNK: usize = 4096;
/// [`ProfileRows::lookup`] of a profile without viewpoint lookup.
const NO_LOOKUP: u32 = u32::MAX;
/// Retinal velocities are capped here, deg/s: far beyond the model's
/// 118 deg/s ceiling, and keeps the smoothing finite for absurd `dt`.
pub const MAX_VELOCITY_DEG_PER_S: f32 = 1e6;
const RAD_TO_DEG: f32 = 180.0 / std::f32::consts::PI;
const SINGLE_LOD_BIT: u32 = 1 << 31;

/// Handle of an object added to a [`Selector`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ObjectId(u32);

/// Handle of a profile added to a [`Selector`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProfileId(u32);

/// An object's selection this frame: an LOD index (0 = finest) or culled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct Selection(u8);

impl Selection {
    /// Outside the view frustum or behind the camera.
    pub const CULLED: Self = Self(u8::MAX);

    /// The chosen LOD, or `None` when culled.
    pub fn lod(self) -> Option<usize> {
        (self != Self::CULLED).then_some(self.0 as usize)
    }

    /// Whether the object was culled.
    pub fn is_culled(self) -> bool {
        self == Self::CULLED
    }
}

/// What went into one object's choice, for inspection and plots.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Diagnostics {
    /// Angle subtended by the bounding sphere, deg (180 inside it).
    pub angular_size_deg: f32,
    /// Eccentricity after the tracker margin, deg (0 with the component off).
    pub eccentricity_deg: f32,
    /// Smoothed retinal velocity, deg/s (0 with the component off).
    pub velocity_deg_per_s: f32,
    /// The acuity the CSF is scaled to, `T = s H(v, E)` in c/deg: a
    /// feature of contrast `c` is invisible above `T f_c(c) / H(0, 0)`.
    pub threshold_cpd: f32,
}

/// Which viewpoint's frequencies apply to an object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ViewpointRule {
    /// The sampled viewpoint nearest to the actual view direction.
    #[default]
    Nearest,
    /// The lowest frequency over all viewpoints: never coarser than any
    /// viewpoint allows, and no view direction needed.
    WorstCase,
}

/// How a [`Selector`] works; fixed at creation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelectorSettings {
    /// Which model components may lower detail.
    pub components: Components,
    /// Which viewpoint's frequencies apply.
    pub viewpoint_rule: ViewpointRule,
    /// Whether to cull objects outside the frustum (no far plane). With it
    /// off every object gets an LOD and single-LOD objects cost nothing.
    pub cull: bool,
    /// Time constant of the exponential smoothing of retinal velocity, s
    /// (>= 0; 0 means no smoothing). The default, 0.05 s, averages over
    /// about 3 frames at 60 Hz (Reddy 2001 averages "over several frames").
    pub velocity_time_constant_s: f32,
    /// Below this many objects the loop runs on the calling thread.
    pub parallel_min_objects: usize,
    /// Lowest `s` the budgeted selection may use, in `(0, 1]`.
    pub min_scale: f32,
    /// The widest vector instructions the loop may use, detected at run
    /// time (with the feature `simd-dispatch` on x86-64, else ignored). The
    /// results are bit-identical at every level (nothing is fused or
    /// reassociated).
    pub simd: SimdLevel,
    /// The observer's contrast sensitivity calibration (with the
    /// display's photometry, it decides which contrasts are visible).
    pub observer: Observer,
    /// How acuity falls with eccentricity (`M(E)`).
    pub eccentricity_model: EccentricityModel,
    /// How acuity falls with retinal velocity (`G(v)`); on a display with
    /// a refresh rate ([`Display::with_refresh_hz`]) never below the
    /// floor of sampled motion.
    pub velocity_model: VelocityModel,
    /// With head tracking only ([`crate::Tracker::Head`]): whether the eyes
    /// counter-rotate when the head turns (the vestibulo-ocular reflex),
    /// holding their direction in the world, so that a head turn alone
    /// moves no world-fixed object on the retina. On (the default), retinal
    /// velocity is measured in world-aligned axes: only the camera's
    /// translation and objects' own motion count. Off, the eyes are taken
    /// to turn with the head and a head turn sweeps everything across the
    /// retina. Other trackers are unaffected: without tracking the
    /// camera's turns are the display's content moving, and an eye tracker
    /// reports the gaze itself.
    pub eyes_counter_rotate: bool,
    /// With an eye tracker ([`crate::Tracker::Eye`]): the gaze speed, deg/s
    /// in world axes between consecutive frames, above which the eye is
    /// taken to be in a saccade. During a saccade the eye is not fixating,
    /// so the floor of sampled motion ([`Display::with_refresh_hz`]) does
    /// not hold: each object's detail follows `G(v)` at its retinal
    /// velocity (the gaze's own sweep), which drops most of it (saccadic
    /// suppression and motion smear). Detail returns on the first frame the
    /// gaze is slower again, within the tens of milliseconds of suppression
    /// that follow a saccade's landing. `f32::INFINITY` (the default), and
    /// any value not > 0: never; [`SACCADE_THRESHOLD_DEG_PER_S`] is the
    /// usual detection threshold.
    pub saccade_threshold_deg_per_s: f32,
}

/// A gaze speed that only saccades reach, deg/s (smooth pursuit stays
/// below about 100 deg/s; saccades of a few degrees or more peak at
/// 200-700 deg/s): the usual velocity threshold of saccade detection.
pub const SACCADE_THRESHOLD_DEG_PER_S: f32 = 180.0;

/// The vector instructions the selection loop may use
/// ([`SelectorSettings::simd`]); a level the CPU lacks falls back to the
/// next one down.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SimdLevel {
    /// The build's baseline instructions (x86-64: SSE2), for comparison.
    Baseline,
    /// At most AVX2 and FMA (x86-64-v3): for CPUs that lower their clock
    /// for AVX-512, or for comparison.
    Avx2,
    /// The widest the CPU has: AVX-512 (x86-64-v4), else AVX2 and FMA.
    #[default]
    Widest,
}

impl Default for SelectorSettings {
    fn default() -> Self {
        Self {
            components: Components::ALL,
            viewpoint_rule: ViewpointRule::Nearest,
            cull: true,
            velocity_time_constant_s: 0.05,
            parallel_min_objects: 32_768,
            min_scale: 0.01,
            simd: SimdLevel::Widest,
            observer: Observer::default(),
            eccentricity_model: EccentricityModel::default(),
            velocity_model: VelocityModel::default(),
            eyes_counter_rotate: true,
            saccade_threshold_deg_per_s: f32::INFINITY,
        }
    }
}

/// An object to select LODs for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectDesc {
    /// Centre of the bounding sphere, world units; each coordinate within
    /// `±MAX_WORLD_COORDINATE`.
    pub center: DVec3,
    /// Radius of the bounding sphere, world units, finite and `>= 0`.
    pub radius: f32,
    /// Rotation from the object's frame (the profile's) to the world.
    pub rotation: Quat,
    /// The object's profile.
    pub profile: ProfileId,
}

/// One frame's input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameInput {
    /// The camera this frame.
    pub camera: Camera,
    /// The gaze this frame.
    pub gaze: Gaze,
    /// Time since the previous frame, s. Zero, negative, non-finite or
    /// larger than 1e6 s: velocities are not updated this frame (they
    /// keep their smoothed values).
    pub dt_s: f32,
    /// The global scale factor `s` in `(0, 1]` (1: imperceptible; lower
    /// drops detail sooner). Values above 1 count as 1; `NaN`, zero and
    /// negative values are refused.
    pub scale: f32,
}

/// The result of [`Selector::select_within_budget`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetOutcome {
    /// The scale factor `s` chosen.
    pub scale: f32,
    /// Triangles of the chosen LODs (culled objects count 0).
    pub triangles: u64,
    /// Whether the budget was met (false when even the lowest `s` is over).
    pub within_budget: bool,
}
/// [`BLOCK`] objects with more than one LOD, field by field. Lanes past
/// the last object of the last block are padding, never read.
#[derive(Clone, Debug)]
struct Block {
    /// Centre of the bounding sphere, world units.
    x: [f64; BLOCK],
    y: [f64; BLOCK],
    z: [f64; BLOCK],
    /// Radius of the bounding sphere, world units.
    radius: [f32; BLOCK],
    /// Start of the object's row: its profile's [`Selector::profile_row0`].
    row0: [u32; BLOCK],
    /// Rotation from the object's frame to the world, normalised
    /// (quaternion x, y, z, w).
    rotation: [[f32; BLOCK]; 4],
}

const EMPTY_BLOCK: Block = Block {
    x: [0.0; BLOCK],
    y: [0.0; BLOCK],
    z: [0.0; BLOCK],
    radius: [0.0; BLOCK],
    row0: [0; BLOCK],
    rotation: [[0.0; BLOCK], [0.0; BLOCK], [0.0; BLOCK], [1.0; BLOCK]],
};

/// The motion state of a block's objects.
#[derive(Clone, Debug)]
struct MotionBlock {
    /// Direction to the object in the eye's frame last frame (x, y, z).
    dir_eye: [[f32; BLOCK]; 3],
    /// Smoothed retinal velocity, deg/s; negative: no history yet.
    velocity_deg_per_s: [f32; BLOCK],
}

const NO_HISTORY: MotionBlock = MotionBlock {
    dir_eye: [[0.0; BLOCK]; 3],
    velocity_deg_per_s: [-1.0; BLOCK],
};

#[derive(Clone, Copy, Debug, Default)]
struct BudgetEntry {
    /// `H(v, E) u`: the threshold at `s = 1` in c/diam, `u` the size the
    /// object is judged at (`inf` inside the bounding sphere).
    k_cdiam: f32,
    /// Start of the object's prefix-minimum row; `u32::MAX` when culled.
    row: u32,
}

#[derive(Clone, Debug)]
struct CompiledProfile {
    lod_count: usize,
    triangles: Vec<u32>,
}

/// Where a profile's prefix-minimum rows lie in [`Selector::rows`]: row
/// `(block * rungs + rung) * stride` from `start`, block 0 the worst case
/// over viewpoints and block `1 + v` viewpoint `v`; each has
/// `lod_count - 1` entries padded with `-inf` to `stride`, a multiple of 4
/// ([`crate::rows`]).
#[derive(Clone, Copy, Debug)]
struct ProfileRows {
    start: u32,
    stride: u32,
    /// Index into [`Selector::lookups`], or [`NO_LOOKUP`] for one viewpoint
    /// or the worst-case rule.
    lookup: u32,
    /// Index into [`Selector::ladders`].
    ladder: u32,
}

/// A size ladder shared by the profiles analysed with it: the rungs'
/// diameters and, for the current display, the angular sizes at which an
/// object moves up a rung.
#[derive(Clone, Debug, PartialEq)]
struct Ladder {
    diameters_px: Vec<f32>,
    boundaries_deg: Vec<f32>,
}

/// How the profiles' rows are laid out, over the profiles with more than
/// one LOD: with one stride and one viewpoint lookup for all of them (one
/// offline pass's profiles), the loop finds rows and counts LODs in bulk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RowLayout {
    /// No profile with more than one LOD yet.
    Empty,
    /// Every row has `stride` entries; `lookup` is the one viewpoint
    /// lookup ([`NO_LOOKUP`]: none, or the worst-case rule) and `ladder`
    /// the one size ladder.
    Uniform {
        stride: u32,
        lookup: u32,
        ladder: u32,
    },
    /// Strides or lookups differ: rows are found object by object.
    Mixed,
}

impl RowLayout {
    fn admit(self, stride: u32, lookup: u32, ladder: u32) -> Self {
        let uniform = Self::Uniform {
            stride,
            lookup,
            ladder,
        };
        match self {
            Self::Empty => uniform,
            Self::Uniform { .. } if self == uniform => self,
            _ => Self::Mixed,
        }
    }
}

/// The selector's per-profile tables, borrowed for a frame.
struct Tables<'a> {
    rows: &'a [f32],
    profiles: &'a [ProfileRows],
    lookups: &'a [ViewpointLookup],
    ladders: &'a [Ladder],
    object_profiles: &'a [u32],
    layout: RowLayout,
    /// The lowest `G(v)` on this display, c/deg.
    motion_floor_cpd: f32,
}

/// Selects LODs for a set of objects, frame after frame.
///
/// ```
/// use acuity::{Camera, Display, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings};
/// # fn main() -> Result<(), acuity::Error> {
/// # let profile = acuity::profile_for_docs();
/// let display = Display::new([1920, 1080], [90.0, 58.7])?;
/// let mut selector = Selector::new(display, SelectorSettings::default());
/// let profile = selector.add_profile(&profile)?;
/// let id = selector.add_object(ObjectDesc {
///     center: glam::DVec3::new(0.0, 0.0, -20.0),
///     radius: 1.0,
///     rotation: glam::Quat::IDENTITY,
///     profile,
/// })?;
/// let frame = FrameInput {
///     camera: Camera { position: glam::DVec3::ZERO, orientation: glam::Quat::IDENTITY },
///     gaze: Gaze::default(),
///     dt_s: 1.0 / 60.0,
///     scale: 1.0,
/// };
/// selector.select(&frame)?;
/// println!("LOD {:?}", selector.selection(id).lod());
/// # Ok(()) }
/// ```
#[derive(Clone, Debug)]
pub struct Selector {
    display: Display,
    settings: SelectorSettings,
    profiles: Vec<CompiledProfile>,
    profile_rows: Vec<ProfileRows>,
    /// The profiles as added: their rows are compiled again when the
    /// display changes.
    sources: Vec<Profile>,
    /// Viewpoint lookups, one per distinct viewpoint set.
    lookups: Vec<ViewpointLookup>,
    /// Size ladders, one per distinct set of rung diameters.
    ladders: Vec<Ladder>,
    /// Per profile: the start of the rows its objects use (viewpoint 0's
    /// block with the nearest-viewpoint rule and a lookup, else the worst
    /// case's).
    profile_row0: Vec<u32>,
    /// The profile of each object with more than one LOD.
    object_profiles: Vec<u32>,
    layout: RowLayout,
    rows: Vec<f32>,
    /// The lowest `G(v)` on this display and observer, c/deg (0 for
    /// continuous motion).
    motion_floor_cpd: f32,
    /// The gaze direction of the last frame in world axes, with an eye
    /// tracker (for saccade detection).
    gaze_world: Option<Vec3>,
    /// Objects with more than one LOD: object `i` is lane `i % BLOCK` of
    /// block `i / BLOCK`.
    blocks: Vec<Block>,
    motion: Vec<MotionBlock>,
    /// One per object with more than one LOD (so also their count).
    selections: Vec<Selection>,
    diagnostics: Vec<Diagnostics>,
    budget: Vec<BudgetEntry>,
    singles: Vec<SingleRecord>,
    single_selections: Vec<Selection>,
}

#[derive(Clone, Copy, Debug)]
struct SingleRecord {
    center: DVec3,
    radius: f32,
    triangles: u32,
}

#[derive(Clone, Copy)]
struct FrameConsts<'a> {
    cam_pos: DVec3,
    world_to_eye: Mat3,
    planes_eye: [Vec3; 4],
    forward_eye: Vec3,
    cull: bool,
    #[cfg_attr(not(feature = "simd-dispatch"), allow(dead_code))]
    simd: SimdLevel,
    size_on: bool,
    eccentricity_model: EccentricityModel,
    velocity_model: VelocityModel,
    motion_floor_cpd: f32,
    /// Retinal velocity is measured in world-aligned axes: directions are
    /// turned by `eye_to_world` first.
    world_velocity: bool,
    eye_to_world: Mat3,
    margin_deg: f32,
    scale: f32,
    fill_deg: f32,
    dt_valid: bool,
    inv_dt: f32,
    alpha: f32,
    pursued: u32,
    rows: &'a [f32],
    profiles: &'a [ProfileRows],
    lookups: &'a [ViewpointLookup],
    ladders: &'a [Ladder],
    /// The profile of each object with more than one LOD.
    object_profiles: &'a [u32],
    layout: RowLayout,
    /// Viewpoint sets up to this size are searched by comparing every
    /// viewpoint (see [`ViewpointLookup::nearest_batch`]): it depends on
    /// the vector width the loop runs with.
    scan_max_views: usize,
}

impl Selector {
    /// An empty selector for a display.
    pub fn new(display: Display, settings: SelectorSettings) -> Self {
        Self {
            display,
            settings,
            profiles: Vec::new(),
            profile_rows: Vec::new(),
            sources: Vec::new(),
            lookups: Vec::new(),
            ladders: Vec::new(),
            profile_row0: Vec::new(),
            object_profiles: Vec::new(),
            layout: RowLayout::Empty,
            rows: Vec::new(),
            motion_floor_cpd: motion_floor_cpd(&display, &settings),
            gaze_world: None,
            blocks: Vec::new(),
            motion: Vec::new(),
            selections: Vec::new(),
            diagnostics: Vec::new(),
            budget: Vec::new(),
            singles: Vec::new(),
            single_selections: Vec::new(),
        }
    }

    /// The display.
    pub fn display(&self) -> &Display {
        &self.display
    }

    /// Changes the display (a resized window, a new field of view, other
    /// photometry); takes effect from the next frame. Every profile's rows
    /// are compiled again for it.
    pub fn set_display(&mut self, display: Display) {
        self.display = display;
        self.motion_floor_cpd = motion_floor_cpd(&display, &self.settings);
        let ppd = display.pixels_per_degree();
        for ladder in &mut self.ladders {
            ladder.boundaries_deg = rows::rung_boundaries_deg(&ladder.diameters_px, ppd);
        }
        // The observer was validated with the first profile; with none
        // there is nothing to compile.
        let Ok(csf) = Csf::new(display.photometry(), &self.settings.observer) else {
            return;
        };
        for (profile, at) in self.sources.iter().zip(&self.profile_rows) {
            let compiled = rows::compile(profile, display.photometry(), &csf, ppd);
            let start = at.start as usize;
            self.rows[start..start + compiled.rows.len()].copy_from_slice(&compiled.rows);
        }
    }

    /// The settings.
    pub fn settings(&self) -> &SelectorSettings {
        &self.settings
    }

    /// Adds a profile (validated again here) and compiles its rows for
    /// this selector's display and observer ([`crate::rows`]: critical
    /// frequencies per viewpoint and rung, as prefix minima), its
    /// viewpoint lookup and its size ladder (both shared with earlier
    /// profiles that have the same viewpoints or rungs). Fails on an
    /// invalid profile or observer calibration.
    pub fn add_profile(&mut self, profile: &Profile) -> Result<ProfileId> {
        profile.validate()?;
        let csf = Csf::new(self.display.photometry(), &self.settings.observer)?;
        let compiled = rows::compile(
            profile,
            self.display.photometry(),
            &csf,
            self.display.pixels_per_degree(),
        );
        let (n, stride, rungs) = (
            profile.transitions_per_view(),
            compiled.stride,
            compiled.rungs,
        );
        let start = self.rows.len();
        self.rows.extend_from_slice(&compiled.rows);
        let views = profile.viewpoints.len();
        let nearest = self.settings.viewpoint_rule == ViewpointRule::Nearest;
        let lookup = if nearest && views > 1 && n > 0 {
            let directions: Vec<Vec3> = profile
                .viewpoints
                .iter()
                .map(|v| Vec3::from_array(*v).normalize())
                .collect();
            match self
                .lookups
                .iter()
                .position(|l| l.directions() == directions)
            {
                Some(i) => i as u32,
                None => {
                    self.lookups.push(ViewpointLookup::new(directions));
                    self.lookups.len() as u32 - 1
                }
            }
        } else {
            NO_LOOKUP
        };
        let diameters = &profile.rung_diameters_px;
        let ladder = match self
            .ladders
            .iter()
            .position(|l| &l.diameters_px == diameters)
        {
            Some(i) => i as u32,
            None => {
                self.ladders.push(Ladder {
                    diameters_px: diameters.clone(),
                    boundaries_deg: rows::rung_boundaries_deg(
                        diameters,
                        self.display.pixels_per_degree(),
                    ),
                });
                self.ladders.len() as u32 - 1
            }
        };
        let viewed = (lookup != NO_LOOKUP) as usize;
        self.profile_row0
            .push((start + viewed * rungs * stride) as u32);
        if profile.lod_count() > 1 {
            self.layout = self.layout.admit(stride as u32, lookup, ladder);
        }
        self.profile_rows.push(ProfileRows {
            start: start as u32,
            stride: stride as u32,
            lookup,
            ladder,
        });
        self.profiles.push(CompiledProfile {
            lod_count: profile.lod_count(),
            triangles: profile.lod_triangles.clone(),
        });
        self.sources.push(profile.clone());
        Ok(ProfileId(self.profiles.len() as u32 - 1))
    }

    /// Adds an object. Objects whose profile has one LOD are kept apart
    /// and never enter the selection loop.
    pub fn add_object(&mut self, desc: ObjectDesc) -> Result<ObjectId> {
        let profile = self.profiles.get(desc.profile.0 as usize).ok_or_else(|| {
            Error::invalid(
                "profile",
                format!("{:?} is not in this selector", desc.profile),
            )
        })?;
        let (center, radius, rotation) = validate_pose(desc.center, desc.radius, desc.rotation)?;
        if profile.lod_count == 1 {
            self.singles.push(SingleRecord {
                center,
                radius,
                triangles: profile.triangles[0],
            });
            self.single_selections.push(Selection(0));
            return Ok(ObjectId(SINGLE_LOD_BIT | (self.singles.len() as u32 - 1)));
        }
        let i = self.selections.len();
        if i as u32 >= SINGLE_LOD_BIT - 1 {
            return Err(Error::invalid("objects", "more than 2^31 objects"));
        }
        if i.is_multiple_of(BLOCK) {
            self.blocks.push(EMPTY_BLOCK);
            self.motion.push(NO_HISTORY);
        }
        let (block, lane) = (&mut self.blocks[i / BLOCK], i % BLOCK);
        block.x[lane] = center.x;
        block.y[lane] = center.y;
        block.z[lane] = center.z;
        block.radius[lane] = radius;
        block.row0[lane] = self.profile_row0[desc.profile.0 as usize];
        self.object_profiles.push(desc.profile.0);
        for (a, q) in rotation.to_array().into_iter().enumerate() {
            block.rotation[a][lane] = q;
        }
        self.selections.push(Selection(0));
        self.diagnostics.push(Diagnostics::default());
        Ok(ObjectId(i as u32))
    }

    /// Moves an object. Its velocity history is kept: the motion shows up
    /// as retinal velocity in the next frame.
    pub fn set_pose(&mut self, id: ObjectId, center: DVec3, rotation: Quat) -> Result<()> {
        let radius = self.radius(id)?;
        let (center, _, rotation) = validate_pose(center, radius, rotation)?;
        if id.0 & SINGLE_LOD_BIT != 0 {
            self.singles[(id.0 & !SINGLE_LOD_BIT) as usize].center = center;
        } else {
            let i = id.0 as usize;
            let (block, lane) = (&mut self.blocks[i / BLOCK], i % BLOCK);
            block.x[lane] = center.x;
            block.y[lane] = center.y;
            block.z[lane] = center.z;
            for (a, q) in rotation.to_array().into_iter().enumerate() {
                block.rotation[a][lane] = q;
            }
        }
        Ok(())
    }

    /// Changes an object's bounding radius (world units, finite, `>= 0`).
    pub fn set_radius(&mut self, id: ObjectId, radius: f32) -> Result<()> {
        self.radius(id)?;
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(Error::invalid(
                "radius",
                format!("{radius} is not a finite radius >= 0"),
            ));
        }
        if id.0 & SINGLE_LOD_BIT != 0 {
            self.singles[(id.0 & !SINGLE_LOD_BIT) as usize].radius = radius;
        } else {
            let i = id.0 as usize;
            self.blocks[i / BLOCK].radius[i % BLOCK] = radius;
        }
        Ok(())
    }

    fn radius(&self, id: ObjectId) -> Result<f32> {
        let i = (id.0 & !SINGLE_LOD_BIT) as usize;
        let r = if id.0 & SINGLE_LOD_BIT != 0 {
            self.singles.get(i).map(|s| s.radius)
        } else {
            (i < self.selections.len()).then(|| self.blocks[i / BLOCK].radius[i % BLOCK])
        };
        r.ok_or_else(|| Error::invalid("id", format!("{id:?} is not in this selector")))
    }

    /// Number of objects, single-LOD ones included.
    pub fn object_count(&self) -> usize {
        self.selections.len() + self.singles.len()
    }

    /// The selection of an object from the last `select*` call (LOD 0
    /// before the first). Panics if `id` is not from this selector.
    pub fn selection(&self, id: ObjectId) -> Selection {
        if id.0 & SINGLE_LOD_BIT != 0 {
            self.single_selections[(id.0 & !SINGLE_LOD_BIT) as usize]
        } else {
            self.selections[id.0 as usize]
        }
    }

    /// Diagnostics of an object from the last
    /// [`select_with_diagnostics`](Self::select_with_diagnostics) call;
    /// `None` for single-LOD objects, which are never analysed.
    pub fn diagnostics(&self, id: ObjectId) -> Option<Diagnostics> {
        (id.0 & SINGLE_LOD_BIT == 0).then(|| self.diagnostics[id.0 as usize])
    }

    /// Triangles drawn with the current selections (culled objects: 0).
    pub fn triangles(&self) -> u64 {
        let multi: u64 = self
            .object_profiles()
            .zip(&self.selections)
            .filter_map(|(p, s)| s.lod().map(|l| self.profiles[p].triangles[l] as u64))
            .sum();
        multi + self.single_triangles()
    }

    fn single_triangles(&self) -> u64 {
        self.singles
            .iter()
            .zip(&self.single_selections)
            .filter(|(_, s)| !s.is_culled())
            .map(|(o, _)| o.triangles as u64)
            .sum()
    }

    /// The profile index of each object with more than one LOD, in order.
    fn object_profiles(&self) -> impl Iterator<Item = usize> + '_ {
        self.object_profiles.iter().map(|&p| p as usize)
    }
}

fn validate_pose(center: DVec3, radius: f32, rotation: Quat) -> Result<(DVec3, f32, Quat)> {
    if !center.is_finite() || center.abs().max_element() > MAX_WORLD_COORDINATE {
        return Err(Error::invalid(
            "center",
            format!("{center} is not finite or beyond ±{MAX_WORLD_COORDINATE:e}"),
        ));
    }
    if !(radius.is_finite() && radius >= 0.0 && (radius as f64) <= MAX_WORLD_COORDINATE) {
        return Err(Error::invalid(
            "radius",
            format!("{radius} is not a finite radius >= 0"),
        ));
    }
    Ok((center, radius, normalized_rotation(rotation, "rotation")?))
}

/// Which outputs a pass writes besides the selections.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Extra {
    None,
    Diagnostics,
    Budget,
}

impl Selector {
    /// Selects every object's LOD for one frame; read the results with
    /// [`selection`](Self::selection). Fails only on an invalid frame
    /// (non-finite camera or gaze, `scale` not in `(0, 1]`), leaving every
    /// state unchanged.
    pub fn select(&mut self, frame: &FrameInput) -> Result<()> {
        self.run(frame, frame.scale, Extra::None)
    }

    /// As [`select`](Self::select), and records each object's
    /// [`Diagnostics`].
    pub fn select_with_diagnostics(&mut self, frame: &FrameInput) -> Result<()> {
        self.run(frame, frame.scale, Extra::Diagnostics)
    }

    /// Predictive fixed-frame-rate selection (Funkhouser & Séquin 1993 as
    /// REFERENCE §6 adapts it): picks the largest `s` in
    /// `[settings.min_scale, frame.scale]` whose LODs together stay within
    /// `triangle_budget`, before anything is drawn, and selects with it.
    ///
    /// Every object's LOD is a step function of `s` with breakpoints at
    /// `prefix_min / (H u)` (see [`crate::rows`]); the breakpoints' triangle savings
    /// are binned over `log s` (256 bins), and the chosen `s` is checked
    /// against the exact count. Lowering `s` always drops the least
    /// visible detail first.
    pub fn select_within_budget(
        &mut self,
        frame: &FrameInput,
        triangle_budget: u64,
    ) -> Result<BudgetOutcome> {
        self.budget
            .resize(self.selections.len(), BudgetEntry::default());
        let s_max = checked_scale(frame.scale)?;
        self.run(frame, 1.0, Extra::Budget)?;
        let fixed = self.single_triangles();
        let s_min = self.settings.min_scale.clamp(1e-6, s_max);
        let mut scale = s_max;
        let mut triangles = fixed + self.triangles_at(scale);
        if triangles > triangle_budget {
            const BINS: usize = 256;
            let (lo, hi) = (s_min.ln(), s_max.ln());
            let width = ((hi - lo) / BINS as f32).max(f32::MIN_POSITIVE);
            let mut saved = [0u64; BINS];
            for (entry, p) in self.budget.iter().zip(self.object_profiles()) {
                if entry.row == u32::MAX {
                    continue;
                }
                let p = &self.profiles[p];
                let row = &self.rows[entry.row as usize..][..p.lod_count - 1];
                for (j, &f) in row.iter().enumerate() {
                    // LOD > j exactly when s < f / k.
                    let s_break = f / entry.k_cdiam;
                    if s_break <= s_min || s_break > s_max {
                        continue;
                    }
                    let bin = (((s_break.ln() - lo) / width) as usize).min(BINS - 1);
                    saved[bin] += (p.triangles[j] - p.triangles[j + 1]) as u64;
                }
            }
            let needed = triangles - triangle_budget;
            let mut total = 0u64;
            let mut bin = BINS;
            while bin > 0 && total < needed {
                bin -= 1;
                total += saved[bin];
            }
            // Candidate scales: the chosen bin's lower edge, stepping down a
            // bin while the exact count is still over budget.
            loop {
                scale = (lo + width * bin as f32).exp().min(s_max) * (1.0 - 1e-6);
                scale = scale.max(s_min);
                triangles = fixed + self.triangles_at(scale);
                if triangles <= triangle_budget || bin == 0 || scale <= s_min {
                    break;
                }
                bin -= 1;
            }
        }
        self.apply_budget_scale(scale);
        Ok(BudgetOutcome {
            scale,
            triangles,
            within_budget: triangles <= triangle_budget,
        })
    }

    fn triangles_at(&self, scale: f32) -> u64 {
        self.budget
            .iter()
            .zip(self.object_profiles())
            .filter(|(e, _)| e.row != u32::MAX)
            .map(|(e, p)| {
                let p = &self.profiles[p];
                let lod = count_coarser(
                    &self.rows[e.row as usize..][..p.lod_count - 1],
                    scale * e.k_cdiam,
                );
                p.triangles[lod] as u64
            })
            .sum()
    }

    fn apply_budget_scale(&mut self, scale: f32) {
        let profiles = self.object_profiles.iter().map(|&p| p as usize);
        for ((e, p), sel) in self.budget.iter().zip(profiles).zip(&mut self.selections) {
            if e.row == u32::MAX {
                continue;
            }
            let n = self.profiles[p].lod_count - 1;
            *sel = Selection(
                count_coarser(&self.rows[e.row as usize..][..n], scale * e.k_cdiam) as u8,
            );
        }
    }

    /// This frame's floor under `G(v)`, c/deg (0 during a saccade), and the
    /// gaze direction in world axes to remember for the next frame.
    fn frame_motion_floor(&self, frame: &FrameInput) -> (f32, Option<Vec3>) {
        let threshold = self.settings.saccade_threshold_deg_per_s;
        let eye_tracked = matches!(frame.gaze.tracker, Tracker::Eye { .. });
        if !(eye_tracked && threshold > 0.0 && threshold.is_finite()) {
            return (self.motion_floor_cpd, None);
        }
        let gaze_world =
            (frame.camera.orientation.normalize() * frame.gaze.direction_camera).try_normalize();
        let dt = frame.dt_s;
        let in_saccade = match (self.gaze_world, gaze_world) {
            (Some(before), Some(now)) if dt.is_finite() && dt > 0.0 => {
                before.angle_between(now).to_degrees() > threshold * dt
            }
            _ => false,
        };
        let floor = if in_saccade {
            0.0
        } else {
            self.motion_floor_cpd
        };
        (floor, gaze_world)
    }

    fn run(&mut self, frame: &FrameInput, scale_override: f32, extra: Extra) -> Result<()> {
        let (motion_floor_cpd, gaze_world) = self.frame_motion_floor(frame);
        let c = frame_consts(
            &self.display,
            &self.settings,
            Tables {
                rows: &self.rows,
                profiles: &self.profile_rows,
                lookups: &self.lookups,
                ladders: &self.ladders,
                object_profiles: &self.object_profiles,
                layout: self.layout,
                motion_floor_cpd,
            },
            frame,
            scale_override,
        )?;
        self.gaze_world = gaze_world;
        let comps = self.settings.components;
        let nearest = self.settings.viewpoint_rule == ViewpointRule::Nearest;
        let kernel = match (comps.velocity, comps.eccentricity, nearest) {
            (false, false, false) => widest::<false, false, false>,
            (false, false, true) => widest::<false, false, true>,
            (false, true, false) => widest::<false, true, false>,
            (false, true, true) => widest::<false, true, true>,
            (true, false, false) => widest::<true, false, false>,
            (true, false, true) => widest::<true, false, true>,
            (true, true, false) => widest::<true, true, false>,
            (true, true, true) => widest::<true, true, true>,
        };
        let outputs = Outputs {
            selections: &mut self.selections,
            diagnostics: (extra == Extra::Diagnostics).then_some(&mut self.diagnostics[..]),
            budget: (extra == Extra::Budget).then_some(&mut self.budget[..]),
        };
        dispatch(
            &c,
            &self.blocks,
            &mut self.motion,
            outputs,
            kernel,
            self.settings.parallel_min_objects,
        );
        if c.cull {
            for (o, sel) in self.singles.iter().zip(&mut self.single_selections) {
                let p = c.world_to_eye * (o.center - c.cam_pos).as_vec3();
                *sel = if outside_frustum(&c, p, o.radius) {
                    Selection::CULLED
                } else {
                    Selection(0)
                };
            }
        }
        Ok(())
    }
}

/// The per-frame constants of the loop; fails on an invalid frame.
fn frame_consts<'a>(
    display: &Display,
    settings: &SelectorSettings,
    tables: Tables<'a>,
    frame: &FrameInput,
    scale_override: f32,
) -> Result<FrameConsts<'a>> {
    let scale = checked_scale(scale_override)?;
    checked_scale(frame.scale)?;
    let cam_rot = frame.camera.validate()?;
    let (gaze_cam, margin_deg) = frame.gaze.validate()?;
    let gaze_rot = Quat::from_rotation_arc(Vec3::NEG_Z, gaze_cam);
    let world_to_eye = Mat3::from_quat(cam_rot * gaze_rot).transpose();
    let eye_from_cam = Mat3::from_quat(gaze_rot).transpose();
    let [fov_h, fov_v] = display.fov_deg();
    let (sh, ch) = (0.5 * fov_h).to_radians().sin_cos();
    let (sv, cv) = (0.5 * fov_v).to_radians().sin_cos();
    let planes_cam = [
        Vec3::new(ch, 0.0, sh),
        Vec3::new(-ch, 0.0, sh),
        Vec3::new(0.0, cv, sv),
        Vec3::new(0.0, -cv, sv),
    ];
    let dt = frame.dt_s;
    let dt_valid = dt.is_finite() && dt > 0.0 && dt <= 1e6;
    let tau = settings.velocity_time_constant_s;
    let alpha = if dt_valid && tau.is_finite() && tau > 0.0 {
        1.0 - (-dt / tau).exp()
    } else {
        1.0
    };
    let pursued = match frame.gaze.pursued {
        Some(ObjectId(i)) if i & SINGLE_LOD_BIT == 0 => i,
        _ => u32::MAX,
    };
    Ok(FrameConsts {
        cam_pos: frame.camera.position,
        world_to_eye,
        planes_eye: planes_cam.map(|n| eye_from_cam * n),
        forward_eye: eye_from_cam * Vec3::NEG_Z,
        cull: settings.cull,
        simd: settings.simd,
        size_on: settings.components.size,
        eccentricity_model: settings.eccentricity_model,
        velocity_model: settings.velocity_model,
        motion_floor_cpd: tables.motion_floor_cpd,
        world_velocity: settings.eyes_counter_rotate && frame.gaze.tracker == Tracker::Head,
        eye_to_world: world_to_eye.transpose(),
        margin_deg,
        scale,
        fill_deg: display.filling_angular_size_deg(),
        dt_valid,
        inv_dt: if dt_valid { 1.0 / dt } else { 0.0 },
        alpha,
        pursued,
        rows: tables.rows,
        profiles: tables.profiles,
        lookups: tables.lookups,
        ladders: tables.ladders,
        object_profiles: tables.object_profiles,
        layout: tables.layout,
        scan_max_views: viewpoints::SCAN_MAX_VIEWS_128,
    })
}

/// The floor under `G(v)` on `display`, c/deg: what a still frame shows
/// ([`Csf::sampled_motion_floor`]), at every velocity. 0 without a
/// refresh rate or with an invalid calibration (which adding a profile
/// reports).
fn motion_floor_cpd(display: &Display, settings: &SelectorSettings) -> f32 {
    match (
        display.refresh_hz(),
        Csf::new(display.photometry(), &settings.observer),
    ) {
        (Some(hz), Ok(csf)) => MAX_ACUITY_CPD * csf.sampled_motion_floor(display.photometry(), hz),
        _ => 0.0,
    }
}

fn checked_scale(scale: f32) -> Result<f32> {
    if scale > 0.0 {
        Ok(scale.min(1.0))
    } else {
        Err(Error::invalid("scale", format!("{scale} is not in (0, 1]")))
    }
}

struct Outputs<'a> {
    selections: &'a mut [Selection],
    diagnostics: Option<&'a mut [Diagnostics]>,
    budget: Option<&'a mut [BudgetEntry]>,
}

type Kernel = fn(&FrameConsts<'_>, &[Block], &mut [MotionBlock], u32, Outputs<'_>);

/// [`kernel`] compiled for the widest vector instructions the CPU has
/// (pulp detects them once and runs the closure, with `kernel` inlined
/// into it, in a function compiled for them), or for the build's baseline.
fn widest<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    first_index: u32,
    out: Outputs<'_>,
) {
    #[cfg(feature = "simd-dispatch")]
    if c.simd != SimdLevel::Baseline {
        let arch = match (c.simd, pulp::Arch::new()) {
            #[cfg(target_arch = "x86_64")]
            (SimdLevel::Avx2, pulp::Arch::V4(_)) => {
                pulp::x86::V3::try_new().map_or(pulp::Arch::Scalar, pulp::Arch::V3)
            }
            (_, arch) => arch,
        };
        let scan_max_views = match arch {
            #[cfg(target_arch = "x86_64")]
            pulp::Arch::V4(_) => viewpoints::SCAN_MAX_VIEWS_512,
            #[cfg(target_arch = "x86_64")]
            pulp::Arch::V3(_) => viewpoints::SCAN_MAX_VIEWS_256,
            _ => c.scan_max_views,
        };
        let c = &FrameConsts {
            scan_max_views,
            ..*c
        };
        return arch.dispatch(
            #[inline(always)]
            || kernel::<VELOCITY, ECCENTRICITY, NEAREST>(c, blocks, motion, first_index, out),
        );
    }
    kernel::<VELOCITY, ECCENTRICITY, NEAREST>(c, blocks, motion, first_index, out)
}

fn dispatch(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    out: Outputs<'_>,
    kernel: Kernel,
    parallel_min: usize,
) {
    #[cfg(feature = "parallel")]
    if out.selections.len() >= parallel_min.max(2 * CHUNK) {
        use rayon::prelude::*;
        let Outputs {
            selections,
            diagnostics,
            budget,
        } = out;
        let diag_iter = diagnostics.map(|d| d.par_chunks_mut(CHUNK));
        let budget_iter = budget.map(|b| b.par_chunks_mut(CHUNK));
        let base = blocks
            .par_chunks(CHUNK / BLOCK)
            .zip(motion.par_chunks_mut(CHUNK / BLOCK))
            .zip(selections.par_chunks_mut(CHUNK))
            .enumerate();
        match (diag_iter, budget_iter) {
            (Some(d), _) => base.zip(d).for_each(|((i, ((o, m), s)), d)| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: Some(d),
                        budget: None,
                    },
                )
            }),
            (None, Some(b)) => base.zip(b).for_each(|((i, ((o, m), s)), b)| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: None,
                        budget: Some(b),
                    },
                )
            }),
            (None, None) => base.for_each(|(i, ((o, m), s))| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: None,
                        budget: None,
                    },
                )
            }),
        }
        return;
    }
    let _ = parallel_min;
    kernel(c, blocks, motion, 0, out);
}

/// Whether a sphere at `p` (eye frame) of radius `r` lies wholly outside a
/// side plane or behind the eye. Branch-free: which plane culls is random.
#[inline(always)]
fn outside_frustum(c: &FrameConsts<'_>, p: Vec3, r: f32) -> bool {
    let [n0, n1, n2, n3] = c.planes_eye;
    let (a, b, d, e) = (n0.dot(p), n1.dot(p), n2.dot(p), n3.dot(p));
    fastmath::max(
        fastmath::max(a, b),
        fastmath::max(fastmath::max(d, e), -c.forward_eye.dot(p)),
    ) > r
}

/// The selection rule (REFERENCE §4) for one object: the coarsest LOD `j`
/// such that every feature removed on the way from LOD 0 is invisible.
/// `prefix_min_cdiam[t]` is the lowest critical frequency of transitions
/// `0..=t` in c/diam (non-increasing; `inf` where nothing visible changed;
/// [`crate::rows`]), `threshold_cpd` is `T = s H(v, E)` in c/deg and
/// `angular_size_deg` the size the object is judged at; a feature is
/// invisible when its critical frequency exceeds `T` times the size.
/// A `NaN` threshold or size gives 0 (full detail), the conservative answer.
pub fn lod_for_threshold(
    prefix_min_cdiam: &[f32],
    threshold_cpd: f32,
    angular_size_deg: f32,
) -> usize {
    let k = threshold_cpd * angular_size_deg;
    if k.is_nan() {
        return 0;
    }
    count_coarser(prefix_min_cdiam, k)
}

/// Number of LODs past 0 that are invisible: the prefix minima above
/// `k_cdiam` (they are non-increasing, so this is the coarsest safe LOD).
#[inline(always)]
fn count_coarser(prefix_min_cdiam: &[f32], k_cdiam: f32) -> usize {
    prefix_min_cdiam
        .iter()
        .map(|&f| (f > k_cdiam) as usize)
        .sum()
}

/// [`count_coarser`] over a row padded with `-inf` to groups of 4 (at
/// least one): one 4-wide comparison and count per group.
#[inline(always)]
fn count_coarser_padded(row: &[f32], k_cdiam: f32) -> usize {
    let group = |g: &[f32]| count_group(g.try_into().unwrap_or([f32::NEG_INFINITY; 4]), k_cdiam);
    let (first, rest) = row.split_at(4.min(row.len()));
    (group(first) + rest.chunks_exact(4).map(group).sum::<u32>()) as usize
}

/// The entries of `group` above `k_cdiam`, in one 4-wide comparison:
/// glam's `Vec4` is a vector register, so loops over objects that call
/// this are not widened into gathers across objects (which measured
/// slower: about 1 ns per object).
#[inline(always)]
fn count_group(group: [f32; 4], k_cdiam: f32) -> u32 {
    Vec4::from_array(group)
        .cmpgt(Vec4::splat(k_cdiam))
        .bitmask()
        .count_ones()
}

/// Objects to model, field by field: a block's lanes straight from
/// the cull pass, or a queue of visible objects gathered from sparse blocks.
struct Batch {
    /// Object index within the work item.
    index: [u32; QUEUE],
    /// Direction to the camera in the object's frame, not normalised
    /// (x, y, z; with the nearest-viewpoint rule).
    to_camera: [[f32; QUEUE]; 3],
    /// Centre in the eye's frame (x, y, z).
    p: [[f32; QUEUE]; 3],
    /// Squared distance.
    d2: [f32; QUEUE],
    radius: [f32; QUEUE],
    /// Start of the object's row (see [`Block::row0`]).
    row0: [u32; QUEUE],
    /// Last frame's direction and velocity (with the velocity component).
    dir_before: [[f32; QUEUE]; 3],
    velocity_before: [f32; QUEUE],
}

const EMPTY_BATCH: Batch = Batch {
    index: [0; QUEUE],
    to_camera: [[0.0; QUEUE]; 3],
    p: [[0.0; QUEUE]; 3],
    d2: [0.0; QUEUE],
    radius: [0.0; QUEUE],
    row0: [0; QUEUE],
    dir_before: [[0.0; QUEUE]; 3],
    velocity_before: [0.0; QUEUE],
};

/// Blocks with at least this many visible objects are modelled whole (the
/// culled lanes' results are dropped), which costs less than moving the
/// visible ones to the queue.
const DENSE_BLOCK: usize = 40;

/// The model's results for a batch.
struct Modelled {
    theta_deg: [f32; QUEUE],
    inv_d: [f32; QUEUE],
    eccentricity_deg: [f32; QUEUE],
    /// This frame's direction and smoothed velocity (the motion state).
    dir: [[f32; QUEUE]; 3],
    velocity: [f32; QUEUE],
    /// The velocity the model uses (0 for the pursued object).
    seen_velocity: [f32; QUEUE],
    threshold_cpd: [f32; QUEUE],
    k_cdiam: [f32; QUEUE],
    /// The viewpoint whose row applies.
    view: [u32; QUEUE],
    /// Start of the object's prefix-minimum row in the selector's rows.
    row: [u32; QUEUE],
    /// The chosen LOD.
    lod: [u32; QUEUE],
}

const EMPTY_MODELLED: Modelled = Modelled {
    theta_deg: [0.0; QUEUE],
    inv_d: [0.0; QUEUE],
    eccentricity_deg: [0.0; QUEUE],
    dir: [[0.0; QUEUE]; 3],
    velocity: [0.0; QUEUE],
    seen_velocity: [0.0; QUEUE],
    threshold_cpd: [0.0; QUEUE],
    k_cdiam: [0.0; QUEUE],
    view: [0; QUEUE],
    row: [0; QUEUE],
    lod: [0; QUEUE],
};

/// `conjugate(q) * -rel` (the direction to the camera in the object's
/// frame) with the operations of glam's SSE2 `Quat * Vec3`, in its order,
/// so that it rounds the same (`to_object_frame_rounds_like_glam` checks
/// this); `q` is `[x, y, z, w]`.
#[cfg(target_feature = "sse2")]
#[inline(always)]
fn to_object_frame(q: [f32; 4], rel: [f32; 3]) -> [f32; 3] {
    let (bx, by, bz, w) = (-q[0], -q[1], -q[2], q[3]);
    let (vx, vy, vz) = (-rel[0], -rel[1], -rel[2]);
    let b2 = bx * bx + by * by + bz * bz;
    let vb2 = (vx * bx + vy * by + vz * bz) * 2.0;
    let (ww, w2) = (w * w - b2, w * 2.0);
    // glam's cross product is `a * b - c * d`, fused with FMA.
    #[cfg(target_feature = "fma")]
    let mul_sub = |a: f32, b: f32, c: f32, d: f32| (-c).mul_add(d, a * b);
    #[cfg(not(target_feature = "fma"))]
    let mul_sub = |a: f32, b: f32, c: f32, d: f32| a * b - c * d;
    let cx = mul_sub(by, vz, vy, bz);
    let cy = mul_sub(bz, vx, vz, bx);
    let cz = mul_sub(bx, vy, vx, by);
    [
        vx * ww + bx * vb2 + cx * w2,
        vy * ww + by * vb2 + cy * w2,
        vz * ww + bz * vb2 + cz * w2,
    ]
}

/// `conjugate(q) * -rel` by glam itself, where its `Quat` is not SSE2.
#[cfg(not(target_feature = "sse2"))]
#[inline(always)]
fn to_object_frame(q: [f32; 4], rel: [f32; 3]) -> [f32; 3] {
    (Quat::from_array(q).conjugate() * -Vec3::from_array(rel)).to_array()
}

/// Culls a block into lanes `0..BLOCK` of `out`: branch-free over all
/// lanes, so it vectorises. With `NEAREST`, also the direction to the
/// camera in each object's frame. `visible` is 1 for each visible object
/// and 0 for each culled one and each lane past `live`.
#[inline(always)]
fn cull_block<const CULL: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    b: &Block,
    live: usize,
    out: &mut Batch,
    visible: &mut [u32; BLOCK],
) {
    let [cx, cy, cz] = c.cam_pos.to_array();
    let m = c.world_to_eye;
    let [n0, n1, n2, n3] = c.planes_eye;
    let f = c.forward_eye;
    // The `f64` subtraction in a loop of its own: the `f32` work below then
    // runs 4 lanes at a time.
    let mut rel = [[0.0f32; BLOCK]; 3];
    for i in 0..BLOCK {
        rel[0][i] = (b.x[i] - cx) as f32;
        rel[1][i] = (b.y[i] - cy) as f32;
        rel[2][i] = (b.z[i] - cz) as f32;
    }
    for i in 0..BLOCK {
        let (rx, ry, rz) = (rel[0][i], rel[1][i], rel[2][i]);
        // The operations of `Mat3 * Vec3` and `Vec3::dot`, in their order.
        let px = m.x_axis.x * rx + m.y_axis.x * ry + m.z_axis.x * rz;
        let py = m.x_axis.y * rx + m.y_axis.y * ry + m.z_axis.y * rz;
        let pz = m.x_axis.z * rx + m.y_axis.z * ry + m.z_axis.z * rz;
        let d2 = px * px + py * py + pz * pz;
        let r = b.radius[i];
        if NEAREST {
            let q = [0, 1, 2, 3].map(|a| b.rotation[a][i]);
            let d = to_object_frame(q, [rx, ry, rz]);
            for a in 0..3 {
                out.to_camera[a][i] = d[a];
            }
        }
        out.p[0][i] = px;
        out.p[1][i] = py;
        out.p[2][i] = pz;
        out.d2[i] = d2;
        let seen = if CULL {
            let dot = |n: Vec3| n.x * px + n.y * py + n.z * pz;
            let outside = fastmath::max(
                fastmath::max(dot(n0), dot(n1)),
                fastmath::max(fastmath::max(dot(n2), dot(n3)), -dot(f)),
            ) > r;
            d2 <= r * r || !outside
        } else {
            true
        };
        visible[i] = (seen & (i < live)) as u32;
    }
}

#[inline(always)]
fn kernel<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    first_index: u32,
    out: Outputs<'_>,
) {
    let Outputs {
        selections,
        mut diagnostics,
        mut budget,
    } = out;
    let pursued = c.pursued.wrapping_sub(first_index);
    let object_profiles = &c.object_profiles[first_index as usize..];
    let mut block_batch = EMPTY_BATCH;
    let mut visible = [0u32; BLOCK];
    let mut lanes = [0u8; QUEUE];
    let mut queue = EMPTY_BATCH;
    let mut queued = 0;
    let mut m = EMPTY_MODELLED;
    let prefetch = Prefetch::new();
    let total = selections.len();
    let extras = diagnostics.is_some() || budget.is_some();
    for (bi, block) in blocks.iter().enumerate() {
        // A block's data is loaded at once and then worked on for long: the
        // hardware prefetcher does not run that far ahead on its own.
        if let Some(next) = blocks.get(bi + PREFETCH_BLOCKS) {
            prefetch.lines(next);
        }
        if VELOCITY && let Some(next) = motion.get(bi + PREFETCH_BLOCKS) {
            prefetch.lines(next);
        }
        if let Some(next) = selections.get((bi + PREFETCH_BLOCKS) * BLOCK) {
            prefetch.lines(next);
        }
        let base = bi * BLOCK;
        let live = (total - base).min(BLOCK);
        let bb = &mut block_batch;
        if c.cull {
            cull_block::<true, NEAREST>(c, block, live, bb, &mut visible);
        } else {
            cull_block::<false, NEAREST>(c, block, live, bb, &mut visible);
        }
        for i in 0..BLOCK {
            bb.index[i] = (base + i) as u32;
            bb.radius[i] = block.radius[i];
            bb.row0[i] = block.row0[i];
        }
        if let Some(b) = budget.as_deref_mut() {
            for e in &mut b[base..base + live] {
                e.row = u32::MAX;
            }
        }
        let n = visible.iter().sum::<u32>() as usize;
        let dense = n >= DENSE_BLOCK;
        if !dense || extras {
            // The visible lanes, listed branch-free.
            let mut n = 0;
            for (lane, &v) in visible.iter().enumerate() {
                lanes[n] = lane as u8;
                n += v as usize;
            }
        }
        if dense {
            let mb = &motion[bi];
            let before = (
                mb.dir_eye.each_ref().map(|d| &d[..]),
                &mb.velocity_deg_per_s[..],
            );
            model::<VELOCITY, ECCENTRICITY, NEAREST>(
                c,
                bb,
                before,
                BLOCK,
                pursued,
                object_profiles,
                &mut m,
            );
            write_block::<VELOCITY>(
                bb,
                &m,
                &visible,
                &lanes[..n],
                &mut selections[base..base + live],
                &mut motion[bi],
                diagnostics.as_deref_mut(),
                budget.as_deref_mut(),
            );
            continue;
        }
        // Culled: LOD "culled" and no velocity history when next seen; the
        // visible objects' outputs follow when the queue is modelled.
        selections[base..base + live].fill(Selection::CULLED);
        if VELOCITY {
            let mb = &mut motion[bi];
            for i in 0..BLOCK {
                let v = mb.velocity_deg_per_s[i];
                mb.velocity_deg_per_s[i] = if visible[i] != 0 { v } else { -1.0 };
            }
        }
        // Model the queue first where these would not fit.
        if queued + n > QUEUE {
            let outputs = Outputs {
                selections: &mut *selections,
                diagnostics: diagnostics.as_deref_mut(),
                budget: budget.as_deref_mut(),
            };
            flush_queue::<VELOCITY, ECCENTRICITY, NEAREST>(
                c,
                &queue,
                queued,
                pursued,
                object_profiles,
                &mut m,
                motion,
                outputs,
            );
            queued = 0;
        }
        // Append the visible lanes to the queue.
        let mb = &motion[bi];
        for &lane in &lanes[..n] {
            let (lane, at) = (lane as usize % BLOCK, queued % QUEUE);
            queue.index[at] = bb.index[lane];
            queue.row0[at] = bb.row0[lane];
            for a in 0..3 {
                if NEAREST {
                    queue.to_camera[a][at] = bb.to_camera[a][lane];
                }
                queue.p[a][at] = bb.p[a][lane];
                if VELOCITY {
                    queue.dir_before[a][at] = mb.dir_eye[a][lane];
                }
            }
            queue.d2[at] = bb.d2[lane];
            queue.radius[at] = bb.radius[lane];
            if VELOCITY {
                queue.velocity_before[at] = mb.velocity_deg_per_s[lane];
            }
            queued += 1;
        }
    }
    if queued > 0 {
        let outputs = Outputs {
            selections,
            diagnostics,
            budget,
        };
        flush_queue::<VELOCITY, ECCENTRICITY, NEAREST>(
            c,
            &queue,
            queued,
            pursued,
            object_profiles,
            &mut m,
            motion,
            outputs,
        );
    }
}

/// Models the first `queued` objects of the queue (see [`model`]) and
/// writes their outputs.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn flush_queue<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    queue: &Batch,
    queued: usize,
    pursued: u32,
    object_profiles: &[u32],
    m: &mut Modelled,
    motion: &mut [MotionBlock],
    out: Outputs<'_>,
) {
    let before = (
        queue.dir_before.each_ref().map(|d| &d[..]),
        &queue.velocity_before[..],
    );
    model::<VELOCITY, ECCENTRICITY, NEAREST>(c, queue, before, queued, pursued, object_profiles, m);
    let Outputs {
        selections,
        diagnostics,
        budget,
    } = out;
    write_queue::<VELOCITY>(queue, m, queued, selections, motion, diagnostics, budget);
}

/// How many blocks ahead the loop asks for the next block's data.
const PREFETCH_BLOCKS: usize = 2;

/// Software prefetch: a hint, never a load, so any address is sound. On
/// x86-64 with the feature `simd-dispatch`, `prefetcht1` (into L2) through
/// pulp's safe wrapper; elsewhere nothing.
#[derive(Clone, Copy)]
struct Prefetch {
    #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
    sse: Option<pulp::core_arch::x86::Sse>,
}

impl Prefetch {
    fn new() -> Self {
        Self {
            #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
            sse: pulp::core_arch::x86::Sse::try_new(),
        }
    }

    /// Asks for every 64-byte cache line of `item`.
    #[inline(always)]
    fn lines<T>(self, item: &T) {
        #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
        if let Some(sse) = self.sse {
            let start = (item as *const T).cast::<i8>();
            for offset in (0..size_of::<T>()).step_by(64) {
                sse._mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T1 }>(start.wrapping_add(offset));
            }
        }
        #[cfg(not(all(feature = "simd-dispatch", target_arch = "x86_64")))]
        let _ = item;
    }
}

/// Models lanes `0..n` of a batch into `m`, up to each object's LOD: short
/// passes over plain arrays (vectorised), then the viewpoint lookup and
/// the LOD count, in bulk where every profile shares one row layout.
/// `before` is the lanes' motion state (last frame's direction x, y, z and
/// smoothed velocity); `pursued` the pursued object's index within the
/// work item, and `object_profiles` its objects' profiles.
#[inline(always)]
fn model<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    q: &Batch,
    before: ([&[f32]; 3], &[f32]),
    n: usize,
    pursued: u32,
    object_profiles: &[u32],
    m: &mut Modelled,
) {
    let n = n.min(QUEUE);
    // The frame's constants as locals: `m` is written through a reference,
    // and loops that read `c` through one as well do not vectorise.
    let (margin_deg, inv_dt, alpha) = (c.margin_deg, c.inv_dt, c.alpha);
    let (scale, size_on, fill_deg) = (c.scale, c.size_on, c.fill_deg);
    for i in 0..n {
        let (d2, r) = (q.d2[i], q.radius[i]);
        let inv_d = 1.0 / fastmath::max(d2, f32::MIN_POSITIVE).sqrt();
        let sin_half = fastmath::min(r * inv_d, 1.0);
        let theta = 2.0 * fastmath::asin_unchecked(sin_half) * RAD_TO_DEG;
        m.inv_d[i] = inv_d;
        m.theta_deg[i] = if d2 <= r * r { 180.0 } else { theta };
    }
    if ECCENTRICITY {
        for i in 0..n {
            let cos = fastmath::clamp(-q.p[2][i] * m.inv_d[i], -1.0, 1.0);
            let angle_deg = fastmath::acos_unchecked(cos) * RAD_TO_DEG;
            m.eccentricity_deg[i] =
                fastmath::max(angle_deg - 0.5 * m.theta_deg[i] - margin_deg, 0.0);
        }
    }
    if VELOCITY {
        let (dir_before, velocity_before) = (before.0.map(|d| &d[..n]), &before.1[..n]);
        let mut chord = [0.0f32; QUEUE];
        for i in 0..n {
            let inv_d = m.inv_d[i];
            m.dir[0][i] = q.p[0][i] * inv_d;
            m.dir[1][i] = q.p[1][i] * inv_d;
            m.dir[2][i] = q.p[2][i] * inv_d;
        }
        if c.world_velocity {
            let [a, b, d] = c.eye_to_world.to_cols_array_2d();
            for i in 0..n {
                let (x, y, z) = (m.dir[0][i], m.dir[1][i], m.dir[2][i]);
                m.dir[0][i] = a[0] * x + b[0] * y + d[0] * z;
                m.dir[1][i] = a[1] * x + b[1] * y + d[1] * z;
                m.dir[2][i] = a[2] * x + b[2] * y + d[2] * z;
            }
        }
        for i in 0..n {
            let (x, y, z) = (m.dir[0][i], m.dir[1][i], m.dir[2][i]);
            let (ex, ey, ez) = (
                x - dir_before[0][i],
                y - dir_before[1][i],
                z - dir_before[2][i],
            );
            chord[i] = (ex * ex + ey * ey + ez * ez).sqrt();
        }
        if c.dt_valid {
            for i in 0..n {
                let before = velocity_before[i];
                let step_deg =
                    2.0 * fastmath::asin_unchecked(fastmath::min(0.5 * chord[i], 1.0)) * RAD_TO_DEG;
                let now = fastmath::min(step_deg * inv_dt, MAX_VELOCITY_DEG_PER_S);
                let smoothed = before + alpha * (now - before);
                m.velocity[i] = if before < 0.0 { 0.0 } else { smoothed };
            }
        } else {
            for i in 0..n {
                let before = velocity_before[i];
                m.velocity[i] = if before < 0.0 { 0.0 } else { before };
            }
        }
        for i in 0..n {
            m.seen_velocity[i] = if q.index[i] == pursued {
                0.0
            } else {
                m.velocity[i]
            };
        }
    }
    // G(v) in a pass of its own (its polynomial's constants then stay in
    // registers), into `threshold_cpd` until the threshold replaces it.
    if VELOCITY {
        let floor_cpd = c.motion_floor_cpd;
        match c.velocity_model {
            VelocityModel::Kelly1979 => {
                for i in 0..n {
                    let v = fastmath::max(m.seen_velocity[i], DRIFT_VELOCITY_DEG_PER_S);
                    let g = MAX_ACUITY_CPD * ((DRIFT_VELOCITY_DEG_PER_S + 2.0) / (v + 2.0));
                    m.threshold_cpd[i] = fastmath::max(g, floor_cpd);
                }
            }
            VelocityModel::Reddy2001 => {
                for i in 0..n {
                    let v = fastmath::clamp(
                        m.seen_velocity[i],
                        VELOCITY_FLOOR_DEG_PER_S,
                        VELOCITY_CEILING_DEG_PER_S,
                    );
                    let g = fastmath::clamp(
                        57.69 - 27.78 * fastmath::log10(v),
                        MIN_ACUITY_CPD,
                        MAX_ACUITY_CPD,
                    );
                    m.threshold_cpd[i] = fastmath::max(g, floor_cpd);
                }
            }
        }
    }
    // M(E) in a pass per model, so each vectorises on its own.
    let mut m_factor = [1.0f32; QUEUE];
    if ECCENTRICITY {
        match c.eccentricity_model {
            EccentricityModel::CorticalMagnification => {
                for i in 0..n {
                    let e = fastmath::clamp(m.eccentricity_deg[i], 0.0, MAX_ECCENTRICITY_DEG);
                    m_factor[i] = cortical_factor_unchecked(e);
                }
            }
            EccentricityModel::Reddy2001 => {
                for i in 0..n {
                    let e = fastmath::clamp(
                        m.eccentricity_deg[i],
                        ECCENTRICITY_FLOOR_DEG,
                        ECCENTRICITY_CEILING_DEG,
                    );
                    let q = 0.3 * e + 1.0;
                    m_factor[i] = fastmath::min(7.49 / (q * q), 1.0);
                }
            }
        }
    }
    for i in 0..n {
        let g = if VELOCITY {
            m.threshold_cpd[i]
        } else {
            MAX_ACUITY_CPD
        };
        let threshold_cpd = scale * (g * m_factor[i]);
        // Inside the sphere: k = inf keeps every frequency visible (LOD 0).
        // The size it is judged at multiplies in once the rung is known.
        let (d2, r) = (q.d2[i], q.radius[i]);
        m.threshold_cpd[i] = threshold_cpd;
        m.k_cdiam[i] = if d2 <= r * r {
            f32::INFINITY
        } else {
            threshold_cpd
        };
    }
    // Each lane's rung of the size ladder and the size it is judged at.
    let mut rung = [0u32; QUEUE];
    let mut judged_deg = [0.0f32; QUEUE];
    match c.layout {
        RowLayout::Uniform {
            stride,
            lookup,
            ladder,
        } => {
            if NEAREST && lookup != NO_LOOKUP {
                let dirs = [0, 1, 2].map(|a| &q.to_camera[a][..n]);
                let lookup = &c.lookups[lookup as usize];
                lookup.nearest_batch(dirs, &mut m.view[..n], c.scan_max_views);
            } else {
                m.view[..n].fill(0);
            }
            let boundaries = &c.ladders[ladder as usize].boundaries_deg;
            let rungs = boundaries.len() as u32 + 1;
            rung_of(
                boundaries,
                &m.theta_deg[..n],
                size_on,
                fill_deg,
                &mut rung[..n],
                &mut judged_deg[..n],
            );
            for i in 0..n {
                m.row[i] = q.row0[i] + (m.view[i] * rungs + rung[i]) * stride;
                m.k_cdiam[i] *= judged_deg[i];
            }
            if stride == 4 {
                count_rows::<4>(c.rows, &m.row[..n], &m.k_cdiam[..n], &mut m.lod[..n]);
            } else {
                for i in 0..n {
                    let row = &c.rows[m.row[i] as usize..][..stride as usize];
                    m.lod[i] = count_coarser_padded(row, m.k_cdiam[i]) as u32;
                }
            }
        }
        RowLayout::Empty | RowLayout::Mixed => {
            // Each object's profile first, then its cube-map cell (in bulk:
            // it vectorises), its row, then the counts: short, independent
            // iterations overlap better than one long chain of loads.
            let mut strides = [0u32; QUEUE];
            let mut rungs = [0u32; QUEUE];
            let mut lookups = [NO_LOOKUP; QUEUE];
            let mut resolutions = [viewpoints::MIN_RESOLUTION; QUEUE];
            for i in 0..n {
                // Lanes past the last object (modelled, never written) take profile 0.
                let p = object_profiles
                    .get(q.index[i] as usize)
                    .copied()
                    .unwrap_or(0);
                let profile = c.profiles[p as usize];
                let boundaries = &c.ladders[profile.ladder as usize].boundaries_deg;
                let size_deg = if size_on { m.theta_deg[i] } else { fill_deg };
                (rung[i], judged_deg[i]) = rung_and_judged_size(boundaries, size_deg);
                m.k_cdiam[i] *= judged_deg[i];
                rungs[i] = boundaries.len() as u32 + 1;
                m.row[i] = profile.start + rung[i] * profile.stride;
                strides[i] = profile.stride;
                if NEAREST && profile.lookup != NO_LOOKUP {
                    lookups[i] = profile.lookup;
                    resolutions[i] = c.lookups[profile.lookup as usize].resolution();
                }
            }
            if NEAREST {
                let mut cells = [0u32; QUEUE];
                for i in 0..n {
                    let d = Vec3::new(q.to_camera[0][i], q.to_camera[1][i], q.to_camera[2][i]);
                    cells[i] = viewpoints::cell_index(d, resolutions[i]);
                }
                for i in 0..n {
                    if let Some(lookup) = c.lookups.get(lookups[i] as usize) {
                        let d = [0, 1, 2].map(|a| q.to_camera[a][i]);
                        let view = lookup.nearest_in_cell(cells[i], d) as u32;
                        m.row[i] += (1 + view) * rungs[i] * strides[i];
                    }
                }
            }
            for i in 0..n {
                let row = &c.rows[m.row[i] as usize..][..strides[i] as usize];
                m.lod[i] = count_coarser_padded(row, m.k_cdiam[i]) as u32;
            }
        }
    }
}

/// An object's rung of a size ladder, the number of `boundaries_deg`
/// (ascending) below its size on screen `size_deg`, and the size it is
/// judged at: the upper end of its rung's range (the boundary above it), or
/// its own size on the bottom and top rungs (see [`crate::rows`]).
#[inline(always)]
fn rung_and_judged_size(boundaries_deg: &[f32], size_deg: f32) -> (u32, f32) {
    let (mut rung, mut judged) = (0, f32::INFINITY);
    for &b in boundaries_deg {
        let above = size_deg > b;
        rung += above as u32;
        judged = if above {
            judged
        } else {
            fastmath::min(judged, b)
        };
    }
    let own = rung == 0 || judged == f32::INFINITY;
    (rung, if own { size_deg } else { judged })
}

/// [`rung_and_judged_size`] for every lane (`theta_deg`, or `fill_deg` with
/// the size component off), one pass per boundary so that it vectorises.
#[inline(always)]
fn rung_of(
    boundaries_deg: &[f32],
    theta_deg: &[f32],
    size_on: bool,
    fill_deg: f32,
    rungs: &mut [u32],
    judged_deg: &mut [f32],
) {
    let n = theta_deg.len().min(rungs.len()).min(judged_deg.len());
    rungs[..n].fill(0);
    judged_deg[..n].fill(f32::INFINITY);
    let size = |i: usize| if size_on { theta_deg[i] } else { fill_deg };
    for &b in boundaries_deg {
        for i in 0..n {
            let above = size(i) > b;
            rungs[i] += above as u32;
            judged_deg[i] = if above {
                judged_deg[i]
            } else {
                fastmath::min(judged_deg[i], b)
            };
        }
    }
    for i in 0..n {
        let own = rungs[i] == 0 || judged_deg[i] == f32::INFINITY;
        judged_deg[i] = if own { size(i) } else { judged_deg[i] };
    }
}

/// The LOD counts of rows of `STRIDE` entries (a multiple of 4) starting
/// at `starts` (multiples of 4), against `k_cdiam`: whole groups of 4
/// loaded and compared at once ([`count_group`]).
#[inline(always)]
fn count_rows<const STRIDE: usize>(
    rows: &[f32],
    starts: &[u32],
    k_cdiam: &[f32],
    lods: &mut [u32],
) {
    let n = starts.len().min(k_cdiam.len()).min(lods.len());
    let (groups, _) = rows.as_chunks::<4>();
    if groups.len() < STRIDE / 4 {
        return;
    }
    let last = groups.len() - STRIDE / 4;
    for i in 0..n {
        let first = (starts[i] as usize / 4).min(last);
        let k = k_cdiam[i];
        let mut count = 0;
        for &g in &groups[first..][..STRIDE / 4] {
            count += count_group(g, k);
        }
        lods[i] = count;
    }
}

/// Writes a block's outputs after modelling it whole: every lane's
/// selection and motion state, blended with culled (`visible[i] == 0`),
/// branch-free; diagnostics and budget entries of the `lanes` listed.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn write_block<const VELOCITY: bool>(
    q: &Batch,
    m: &Modelled,
    visible: &[u32; BLOCK],
    lanes: &[u8],
    selections: &mut [Selection],
    mb: &mut MotionBlock,
    diagnostics: Option<&mut [Diagnostics]>,
    budget: Option<&mut [BudgetEntry]>,
) {
    // Blends by bit masks: the compiler turns `if` here into branches,
    // which mispredict on every culled lane.
    let mask = |i: usize| 0u32.wrapping_sub(visible[i]);
    let blend = |mask: u32, new: f32, old: f32| {
        f32::from_bits((new.to_bits() & mask) | (old.to_bits() & !mask))
    };
    // Culled is `u8::MAX`: every bit set.
    let lods: [Selection; BLOCK] = std::array::from_fn(|i| Selection((m.lod[i] | !mask(i)) as u8));
    let live = selections.len().min(BLOCK);
    selections[..live].copy_from_slice(&lods[..live]);
    if VELOCITY {
        for i in 0..BLOCK {
            let mask = mask(i);
            for a in 0..3 {
                mb.dir_eye[a][i] = blend(mask, m.dir[a][i], mb.dir_eye[a][i]);
            }
            mb.velocity_deg_per_s[i] = blend(mask, m.velocity[i], -1.0);
        }
    }
    if diagnostics.is_some() || budget.is_some() {
        write_extras(q, m, lanes.iter().map(|&l| l as usize), diagnostics, budget);
    }
}

/// Writes the outputs of lanes `0..n` of the queue, object by object.
#[inline(always)]
fn write_queue<const VELOCITY: bool>(
    q: &Batch,
    m: &Modelled,
    n: usize,
    selections: &mut [Selection],
    motion: &mut [MotionBlock],
    diagnostics: Option<&mut [Diagnostics]>,
    budget: Option<&mut [BudgetEntry]>,
) {
    let n = n.min(QUEUE);
    for i in 0..n {
        let index = q.index[i] as usize;
        selections[index] = Selection(m.lod[i] as u8);
        if VELOCITY {
            let mb = &mut motion[index / BLOCK];
            let lane = index % BLOCK;
            for a in 0..3 {
                mb.dir_eye[a][lane] = m.dir[a][i];
            }
            mb.velocity_deg_per_s[lane] = m.velocity[i];
        }
    }
    if diagnostics.is_some() || budget.is_some() {
        write_extras(q, m, 0..n, diagnostics, budget);
    }
}

/// Diagnostics and budget entries of the given lanes.
fn write_extras(
    q: &Batch,
    m: &Modelled,
    lanes: impl Iterator<Item = usize>,
    mut diagnostics: Option<&mut [Diagnostics]>,
    mut budget: Option<&mut [BudgetEntry]>,
) {
    for i in lanes {
        let i = i % QUEUE;
        let index = q.index[i] as usize;
        if let Some(d) = diagnostics.as_deref_mut() {
            d[index] = Diagnostics {
                angular_size_deg: m.theta_deg[i],
                eccentricity_deg: m.eccentricity_deg[i],
                velocity_deg_per_s: m.seen_velocity[i],
                threshold_cpd: m.threshold_cpd[i],
            };
        }
        if let Some(b) = budget.as_deref_mut() {
            b[index] = BudgetEntry {
                k_cdiam: m.k_cdiam[i],
                row: m.row[i],
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Tracker;
    use crate::profile::{Feature, PROFILE_FORMAT_VERSION, TransitionFeatures};

    /// A seeded xorshift generator, uniform in `[-1, 1)` times `scale`.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self, scale: f32) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            ((self.0 >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * scale
        }

        fn rotation(&mut self) -> Quat {
            let q = Quat::from_xyzw(self.next(1.0), self.next(1.0), self.next(1.0), 0.5);
            q.normalize()
        }
    }

    /// The size ladder of the test profiles: 4 rungs, 16 to 128 pixels.
    const RUNGS: [f32; 4] = [16.0, 32.0, 64.0, 128.0];

    fn profile(rng: &mut Rng, lods: usize, views: usize) -> Profile {
        let viewpoints = (0..views)
            .map(|_| {
                let v = Vec3::new(rng.next(1.0), rng.next(1.0), rng.next(1.0) + 0.01);
                v.normalize().to_array()
            })
            .collect();
        let transitions = (0..views * RUNGS.len() * (lods - 1))
            .map(|t| {
                let mut features: Vec<Feature> = (0..(rng.next(2.0) + 2.0) as usize)
                    .map(|_| {
                        let lo = rng.next(0.25) + 0.25;
                        Feature {
                            area_diam2: 0.001 + rng.next(0.0005),
                            freq_cdiam: 200.0 / (1 << (t % (lods - 1))) as f32
                                * (1.2 + rng.next(0.6)),
                            luminance: [lo, lo + rng.next(0.25) + 0.25],
                            masker: [0.0, rng.next(0.5) + 0.5],
                        }
                    })
                    .collect();
                features.sort_by(|a, b| a.freq_cdiam.total_cmp(&b.freq_cdiam));
                TransitionFeatures {
                    feature_count: features.len() as u32,
                    features,
                }
            })
            .collect();
        Profile {
            format_version: PROFILE_FORMAT_VERSION,
            name: "test".into(),
            lod_triangles: (0..lods).map(|l| 4000 >> l).collect(),
            bounding_radius: 1.0,
            viewpoints,
            rung_diameters_px: RUNGS.to_vec(),
            transitions,
            settings: Default::default(),
            inputs: vec![],
        }
    }

    /// The selection loop one object at a time, as plainly as it can be
    /// written (REFERENCE §3–§4), with its own motion state.
    struct Reference {
        dir_eye: Vec<Vec3>,
        velocity_deg_per_s: Vec<f32>,
    }

    impl Reference {
        fn frame(&mut self, sel: &Selector, frame: &FrameInput) -> Vec<(Selection, Diagnostics)> {
            let s = &sel.settings;
            let c = frame_consts(
                &sel.display,
                s,
                Tables {
                    rows: &sel.rows,
                    profiles: &sel.profile_rows,
                    lookups: &sel.lookups,
                    ladders: &sel.ladders,
                    object_profiles: &sel.object_profiles,
                    layout: sel.layout,
                    motion_floor_cpd: sel.frame_motion_floor(frame).0,
                },
                frame,
                frame.scale,
            )
            .unwrap();
            let mut out = Vec::new();
            for i in 0..sel.selections.len() {
                let (b, l) = (&sel.blocks[i / BLOCK], i % BLOCK);
                let center = DVec3::new(b.x[l], b.y[l], b.z[l]);
                let r = b.radius[l];
                let rotation = Quat::from_array([0, 1, 2, 3].map(|a| b.rotation[a][l]));
                let rel = (center - c.cam_pos).as_vec3();
                let p = c.world_to_eye * rel;
                let d2 = p.length_squared();
                let inside = d2 <= r * r;
                if c.cull && !inside && outside_frustum(&c, p, r) {
                    self.velocity_deg_per_s[i] = -1.0;
                    out.push((Selection::CULLED, Diagnostics::default()));
                    continue;
                }
                let inv_d = 1.0 / d2.max(f32::MIN_POSITIVE).sqrt();
                let theta_deg = if inside {
                    180.0
                } else {
                    2.0 * fastmath::asin((r * inv_d).min(1.0)) * RAD_TO_DEG
                };
                let eccentricity_deg = if s.components.eccentricity {
                    let angle = fastmath::acos((-p.z * inv_d).clamp(-1.0, 1.0)) * RAD_TO_DEG;
                    (angle - 0.5 * theta_deg - c.margin_deg).max(0.0)
                } else {
                    0.0
                };
                let mut velocity = 0.0;
                if s.components.velocity {
                    let dir = p * inv_d;
                    let dir = if c.world_velocity {
                        let [a, b, d] = c.eye_to_world.to_cols_array_2d();
                        Vec3::new(
                            a[0] * dir.x + b[0] * dir.y + d[0] * dir.z,
                            a[1] * dir.x + b[1] * dir.y + d[1] * dir.z,
                            a[2] * dir.x + b[2] * dir.y + d[2] * dir.z,
                        )
                    } else {
                        dir
                    };
                    let before = self.velocity_deg_per_s[i];
                    let v = if before < 0.0 {
                        0.0
                    } else if c.dt_valid {
                        let chord = (dir - self.dir_eye[i]).length();
                        let step = 2.0 * fastmath::asin((0.5 * chord).min(1.0)) * RAD_TO_DEG;
                        let now = (step * c.inv_dt).min(MAX_VELOCITY_DEG_PER_S);
                        before + c.alpha * (now - before)
                    } else {
                        before
                    };
                    self.dir_eye[i] = dir;
                    self.velocity_deg_per_s[i] = v;
                    velocity = if i as u32 == c.pursued { 0.0 } else { v };
                }
                let g = if s.components.velocity {
                    let g = match s.velocity_model {
                        VelocityModel::Kelly1979 => {
                            crate::acuity::kelly_velocity_acuity_cpd(velocity)
                        }
                        VelocityModel::Reddy2001 => {
                            let v = velocity
                                .clamp(VELOCITY_FLOOR_DEG_PER_S, VELOCITY_CEILING_DEG_PER_S);
                            (57.69 - 27.78 * fastmath::log10(v))
                                .clamp(MIN_ACUITY_CPD, MAX_ACUITY_CPD)
                        }
                    };
                    g.max(c.motion_floor_cpd)
                } else {
                    MAX_ACUITY_CPD
                };
                let m = if s.components.eccentricity {
                    s.eccentricity_model.factor(eccentricity_deg)
                } else {
                    1.0
                };
                let threshold_cpd = c.scale * (g * m);
                let size = if s.components.size {
                    theta_deg
                } else {
                    c.fill_deg
                };
                let profile = sel.object_profiles[i] as usize;
                let rows = sel.profile_rows[profile];
                let ladder = &sel.ladders[rows.ladder as usize];
                let rung = ladder.boundaries_deg.iter().filter(|&&b| size > b).count();
                // Judged at the top of its rung's range, or its own size on
                // the bottom and top rungs.
                let judged = match ladder.boundaries_deg.get(rung) {
                    Some(&b) if rung > 0 => b,
                    _ => size,
                };
                let k = if inside {
                    f32::INFINITY
                } else {
                    threshold_cpd * judged
                };
                let rungs = ladder.diameters_px.len();
                let mut block = 0;
                if s.viewpoint_rule == ViewpointRule::Nearest && rows.lookup != NO_LOOKUP {
                    let view =
                        sel.lookups[rows.lookup as usize].nearest(rotation.conjugate() * -rel);
                    block = 1 + view;
                }
                let row = rows.start as usize + (block * rungs + rung) * rows.stride as usize;
                let n = sel.profiles[profile].lod_count - 1;
                let lod = count_coarser(&sel.rows[row..row + n], k);
                let diagnostics = Diagnostics {
                    angular_size_deg: theta_deg,
                    eccentricity_deg,
                    velocity_deg_per_s: velocity,
                    threshold_cpd,
                };
                out.push((Selection(lod as u8), diagnostics));
            }
            out
        }
    }

    /// Profiles of different LOD and viewpoint counts: rows found object
    /// by object.
    const MIXED: [(usize, usize); 6] = [(4, 18), (4, 18), (2, 1), (3, 7), (7, 30), (1, 1)];

    /// Runs the loop and the reference side by side over a few frames and
    /// demands the same selections and diagnostics, bit for bit. `kinds`
    /// lists the profiles as (LODs, viewpoints); with `shared`, profiles
    /// with as many viewpoints share their directions.
    fn matches_reference(
        settings: SelectorSettings,
        objects: usize,
        seed: u64,
        kinds: &[(usize, usize)],
        shared: bool,
    ) {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ seed);
        // Every other seed on a sampled display, whose motion floor binds.
        let refresh_hz = (seed % 2 == 1).then_some(90.0);
        let display = Display::new([1920, 1080], [90.0, 58.7])
            .and_then(|d| d.with_refresh_hz(refresh_hz))
            .unwrap();
        // Saccade detection on every fourth seed (the turning camera carries
        // the eye-tracked gaze past the threshold).
        let settings = SelectorSettings {
            saccade_threshold_deg_per_s: if seed % 4 == 1 {
                SACCADE_THRESHOLD_DEG_PER_S
            } else {
                settings.saccade_threshold_deg_per_s
            },
            ..settings
        };
        let mut sel = Selector::new(display, settings);
        let mut profiles = vec![];
        for &(lods, views) in kinds {
            let mut p = profile(&mut rng, lods, views);
            if shared {
                p.viewpoints = profile(&mut Rng(views as u64 + 1), 2, views).viewpoints;
            }
            profiles.push(sel.add_profile(&p).unwrap());
        }
        let layout = sel.layout;
        let origin = DVec3::new(1e5, -3e6, 1e7) * (seed % 2) as f64;
        let mut ids = vec![];
        for k in 0..objects {
            let offset = if k % 5 == 0 {
                Vec3::new(rng.next(300.0), rng.next(300.0), rng.next(300.0))
            } else {
                let dir = Vec3::new(rng.next(1.3), rng.next(0.9), -1.0).normalize();
                dir * (rng.next(5.0) + 4.0).exp2()
            };
            let radius = if k % 40 == 0 {
                0.0
            } else {
                2.0 + rng.next(1.9)
            };
            let p = profiles[((rng.next(0.5) + 0.5) * kinds.len() as f32) as usize % kinds.len()];
            let desc = ObjectDesc {
                center: origin + offset.as_dvec3(),
                radius,
                rotation: rng.rotation(),
                profile: p,
            };
            ids.push(sel.add_object(desc).unwrap());
        }
        let mut reference = Reference {
            dir_eye: vec![Vec3::ZERO; sel.selections.len()],
            velocity_deg_per_s: vec![-1.0; sel.selections.len()],
        };
        for (f, dt) in [1.0 / 90.0, 1.0 / 90.0, 0.0, -1.0, 0.5, 1.0 / 60.0]
            .into_iter()
            .enumerate()
        {
            let yaw = 0.3 * f as f32 * (seed % 3) as f32;
            let frame = FrameInput {
                camera: Camera {
                    position: origin + DVec3::new(0.1, 0.02, -0.3) * f as f64,
                    orientation: Quat::from_rotation_y(yaw) * Quat::from_rotation_x(0.01),
                },
                gaze: Gaze {
                    pursued: Some(ids[f * 7 % ids.len()]),
                    // Head tracking (its velocity in world axes) on every third seed.
                    ..Gaze::at_screen_angles(
                        5.0,
                        -2.0,
                        if seed % 3 == 2 {
                            Tracker::Head
                        } else {
                            Tracker::eye_default()
                        },
                    )
                },
                dt_s: dt,
                scale: if f == 4 { 0.3 } else { 1.0 },
            };
            let expected = reference.frame(&sel, &frame);
            sel.select_with_diagnostics(&frame).unwrap();
            for (i, &(selection, diagnostics)) in expected.iter().enumerate() {
                assert_eq!(
                    sel.selections[i], selection,
                    "object {i}, frame {f}, {layout:?}"
                );
                if !selection.is_culled() {
                    let bits = |d: Diagnostics| {
                        [
                            d.angular_size_deg,
                            d.eccentricity_deg,
                            d.velocity_deg_per_s,
                            d.threshold_cpd,
                        ]
                        .map(f32::to_bits)
                    };
                    let got = bits(sel.diagnostics[i]);
                    assert_eq!(got, bits(diagnostics), "object {i}, frame {f}");
                }
            }
        }
    }

    #[test]
    fn the_loop_matches_a_scalar_reference_bit_for_bit() {
        for k in 0..64u64 {
            let settings = SelectorSettings {
                components: Components {
                    size: k & 1 != 0,
                    velocity: k & 2 != 0,
                    eccentricity: k & 4 != 0,
                },
                cull: k & 8 != 0,
                viewpoint_rule: if k & 16 != 0 {
                    ViewpointRule::WorstCase
                } else {
                    ViewpointRule::Nearest
                },
                eccentricity_model: if k & 32 != 0 {
                    EccentricityModel::Reddy2001
                } else {
                    EccentricityModel::CorticalMagnification
                },
                velocity_model: if k & 32 != 0 {
                    VelocityModel::Reddy2001
                } else {
                    VelocityModel::Kelly1979
                },
                ..Default::default()
            };
            // The same bits with the CPU's widest instructions and without.
            for simd in [SimdLevel::Widest, SimdLevel::Avx2, SimdLevel::Baseline] {
                let settings = SelectorSettings { simd, ..settings };
                matches_reference(settings, 700 + k as usize, k, &MIXED, false);
                // One offline pass's profiles: rows found in bulk.
                let uniform = [(4, 18), (4, 18), (5, 18), (3, 18), (1, 1)];
                matches_reference(settings, 700 + k as usize, k, &uniform, true);
            }
        }
    }

    #[test]
    fn uniform_layouts_match_the_reference() {
        let nearest = SelectorSettings::default();
        let worst = SelectorSettings {
            viewpoint_rule: ViewpointRule::WorstCase,
            ..nearest
        };
        type Kinds = &'static [(usize, usize)];
        let cases: [(Kinds, bool, RowLayout); 6] = [
            (
                &[(7, 18), (8, 18)],
                true,
                RowLayout::Uniform {
                    stride: 8,
                    lookup: 0,
                    ladder: 0,
                },
            ),
            (
                &[(2, 1), (4, 1), (1, 1)],
                true,
                RowLayout::Uniform {
                    stride: 4,
                    lookup: NO_LOOKUP,
                    ladder: 0,
                },
            ),
            // More viewpoints than any vector width compares one by one.
            (
                &[(4, 66), (3, 66)],
                true,
                RowLayout::Uniform {
                    stride: 4,
                    lookup: 0,
                    ladder: 0,
                },
            ),
            (&[(4, 18), (4, 18)], false, RowLayout::Mixed),
            (&[(4, 18), (9, 18)], true, RowLayout::Mixed),
            (&[(4, 18), (4, 30)], true, RowLayout::Mixed),
        ];
        for (k, (kinds, shared, layout)) in cases.into_iter().enumerate() {
            let mut sel = Selector::new(Display::new([64, 64], [60.0, 60.0]).unwrap(), nearest);
            let mut rng = Rng(k as u64 + 1);
            for &(lods, views) in kinds {
                let mut p = profile(&mut rng, lods, views);
                if shared {
                    p.viewpoints = profile(&mut Rng(views as u64 + 1), 2, views).viewpoints;
                }
                sel.add_profile(&p).unwrap();
            }
            assert_eq!(sel.layout, layout, "case {k}");
            for settings in [nearest, worst] {
                matches_reference(settings, 900, k as u64, kinds, shared);
            }
        }
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn the_parallel_loop_matches_a_scalar_reference_bit_for_bit() {
        let settings = SelectorSettings {
            parallel_min_objects: 0,
            ..Default::default()
        };
        matches_reference(settings, 3 * CHUNK + 77, 5, &MIXED, false);
        matches_reference(settings, 3 * CHUNK + 77, 6, &[(4, 18), (3, 18)], true);
    }

    #[test]
    fn to_object_frame_rounds_like_glam() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |scale: f32| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * scale
        };
        for k in 0..200_000 {
            let q = Quat::from_xyzw(next(1.0), next(1.0), next(1.0), next(1.0));
            let Ok(q) = normalized_rotation(q, "q") else {
                continue;
            };
            let scale = [1e-3, 1.0, 1e3, 1e7][k % 4];
            let rel = Vec3::new(next(scale), next(scale), next(scale));
            let glam = q.conjugate() * (-rel);
            let ours = to_object_frame(q.to_array(), rel.to_array());
            assert_eq!(
                ours.map(f32::to_bits),
                glam.to_array().map(f32::to_bits),
                "{q} {rel}"
            );
        }
    }
}
