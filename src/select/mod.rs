//! Per-object LOD selection: the runtime's hot loop.
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
//! long dependency chains; 32 measured slower, see `docs/selection.md`).
//! Each block's data is prefetched into L2 two blocks ahead (into
//! L1 it evicts the loop's own 13 KB of scratch). With the feature
//! `simd-dispatch` the loop runs compiled for AVX-512 or AVX2 and FMA where
//! the CPU has them (bit-identical results: nothing is fused). The loop is
//! monomorphised over the velocity, eccentricity and nearest-viewpoint
//! switches, so a switched-off component costs nothing, allocates nothing,
//! and runs on rayon (feature `parallel`) above
//! [`SelectorSettings::parallel_min_objects`].
//!
//! After the loop, per-object adjustments (a bias on the threshold, LOD
//! clamps) are applied to the few objects that have them and, when asked
//! for, the selections are compared with the previous frame's 64 at a time
//! to list the objects whose selection changed, and cross-fades advance.
//!
//! Code: `selector` (profiles, the frame's selection), `budgeted`
//! (selection within a triangle budget; its greedy in `best_effort`, its
//! switch rules in `hysteresis`), `objects`
//! (object handles, adding, removing, changing objects), `object_id` (the
//! handle type, a leaf that `camera` names too), `adjust` (bias
//! and clamps), `changes` (the change list and cross-fades), `store` and
//! `tables` (the object blocks and the compiled profiles), `frame` (a
//! frame's constants), `dispatch` (vector width and parallel split),
//! `kernel` (the loop) and `rule` (rungs and LOD counts).

// Index loops over parallel fixed-size arrays are what vectorises here.
#![allow(clippy::needless_range_loop)]

use glam::{DVec3, Quat};

use crate::acuity::{Components, EccentricityModel, VelocityModel};
use crate::camera::{Camera, Gaze};
use crate::csf::Observer;
use crate::display::Display;

mod adjust;
mod best_effort;
mod budgeted;
mod changes;
mod dispatch;
mod frame;
mod hysteresis;
mod kernel;
pub(crate) mod object_id;
mod objects;
mod rule;
mod selector;
mod store;
mod tables;
#[cfg(test)]
mod tests;

pub use object_id::ObjectId;
pub use rule::lod_for_threshold;
pub use selector::Selector;

/// Objects per block of the store.
const BLOCK: usize = 64;
/// [`ProfileRows::lookup`](tables::ProfileRows::lookup) of a profile
/// without viewpoint lookup.
const NO_LOOKUP: u32 = u32::MAX;
/// Retinal velocities are capped here, deg/s: far beyond the model's
/// 118 deg/s ceiling, and keeps the smoothing finite for absurd `dt`.
pub const MAX_VELOCITY_DEG_PER_S: f32 = 1e6;
const RAD_TO_DEG: f32 = 180.0 / std::f32::consts::PI;

/// An object's cross-fade from one LOD to another
/// ([`SelectorSettings::fade_time_s`]), for a renderer to blend or dither:
/// draw `from_lod` with weight `1 - fraction` and `to_lod` with weight
/// `fraction` (with a screen-door dither, `to_lod` covers that fraction of
/// the object's pixels and `from_lod` the complement).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fade {
    /// The object.
    pub object: ObjectId,
    /// The LOD fading out.
    pub from_lod: usize,
    /// The LOD fading in: the object's current selection.
    pub to_lod: usize,
    /// How far the fade has gone, in `[0, 1)`: 0 on the frame of the
    /// switch, then `dt_s / fade_time_s` more each frame; the fade ends
    /// (and leaves [`Selector::fades`]) on the frame it would reach 1.
    pub fraction: f32,
}

/// Handle of a profile added to a [`Selector`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProfileId(u32);

/// An object's selection this frame: an LOD index (0 = finest) or culled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct Selection(u8);

impl Selection {
    /// Outside the view frustum or behind the camera, or not selected
    /// yet (an object added since the last `select*` call).
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
    /// Lowest `s` the budgeted selection may use, in `(0, 1]` (default
    /// [`DEFAULT_MIN_SCALE`], 1e-3; below [`LOWEST_MIN_SCALE`] it is
    /// raised to it, above 1 lowered to 1; not finite, NaN included, it is
    /// the default). A budget it cannot meet with every step down to this
    /// `s` stops there, over budget.
    pub min_scale: f32,
    /// How [`Selector::select_within_budget`] spends a triangle budget
    /// (default: [`BudgetRule::BestEffort`]).
    pub budget_rule: BudgetRule,
    /// How [`Selector::select`] lowers detail at `s < 1` (default:
    /// [`ScaleRule::Uniform`], Reddy 1998's). At `s = 1` both rules choose
    /// the same LODs.
    pub scale_rule: ScaleRule,
    /// Under [`ScaleRule::Budgeted`], the visibility summed over the image
    /// that a selection may add beyond what the triangles from `s` cost,
    /// in best effort's measure ([`Selector::selection_visibility_deg`],
    /// counted from [`VISIBILITY_COUNTED_FROM`], inside the edge of
    /// visibility): best effort starts from the LODs invisible from there
    /// on, takes its cheapest steps per triangle saved until the triangles
    /// of one `s` for all fit (at `s = 1` the rule's without a budget, so
    /// the steps just inside the edge are taken where they save the most
    /// triangles for their visibility), then keeps taking them while the
    /// visibility they add stays within the budget (so a lower `s` always
    /// draws fewer triangles).
    /// Visible differences add up over an image, and an image-level metric
    /// (FovVideoVDP) loses about as much per degree of this measure on
    /// every scene measured, where one `s` costs each scene differently;
    /// so one budget puts `s = 1` near the edge of visibility on each
    /// ([`VisibilityBudget::Imperceptible`]). Off by default: `s = 1` then
    /// draws the LODs each invisible on its own. Costs a budgeted
    /// selection per frame at `s = 1` too.
    pub visibility_budget: VisibilityBudget,
    /// Under [`BudgetRule::BestEffort`], the fraction by which a step an
    /// object had already taken in the previous frame is cheaper than a new
    /// one, in `[0, 0.9]` (values outside are clamped; NaN is 0): objects
    /// whose steps cost about the same then keep their LODs instead of
    /// trading places whenever the budget or the view moves a little
    /// (hysteresis; 0.5 by default, an octave of cost: costs weigh in the
    /// objects' sizes, which change every frame as the view moves).
    pub budget_hysteresis: f32,
    /// Hysteresis of [`Selector::select`]'s switches to coarser LODs, a
    /// fraction in `[0, 1]` (larger values count as 1; NaN and values not
    /// `> 0` are off, the default): an object drawn at a finer LOD last
    /// frame coarsens only where its threshold lies this fraction below
    /// the transition's critical frequency, so a view or `s` that wobbles
    /// by less than that does not switch it back and forth. Switches to
    /// finer LODs happen at once: the rule only keeps detail. Objects with
    /// a bias ([`Selector::set_bias`]) switch without it. It costs the
    /// loop a recorded threshold per object (as a budget does) and a pass
    /// over the objects.
    pub switch_hysteresis: f32,
    /// Least time after a switch to a finer LOD before
    /// [`Selector::select`] switches the object to a coarser one, s (the
    /// frames' `dt_s` summed); NaN and values not `> 0` are off, the
    /// default. Only a switch back the other way waits: an object that
    /// coarsened a frame ago coarsens further at once (a scheduler lowering
    /// `s` frame after frame sees each step in the next frame's time).
    /// Under [`Selector::select_within_budget`], best effort takes a step
    /// that would go back on a refinement before then only after every
    /// other step, where no other meets the budget, such a coarsening
    /// waits only while the budget has room for the finer LOD it keeps,
    /// and an object that coarsened does not switch back to a finer LOD
    /// before then either (under a budget that moves, undoing a coarsening
    /// a few frames later is flicker; holding the coarser LOD only saves
    /// triangles). Under [`ScaleRule::Budgeted`] at `s < 1` no switch back
    /// happens before then, whatever the budget needs. Under
    /// [`Selector::select`] switches to finer LODs happen at once, so there
    /// this only keeps detail: an object the view sweeps back and forth
    /// over a transition does not flicker between two LODs faster than
    /// this.
    pub switch_min_dwell_s: f32,
    /// How long the view must ask for a coarser LOD without a break before
    /// the object coarsens, s (the frames' `dt_s` summed); NaN and values
    /// not `> 0` are off, the default. A coarsening asked for in a frame
    /// whose `s` is lower than the last frame's (a scheduler coming down
    /// from an overload) happens at once, and switches to finer LODs
    /// always do, so the rule only keeps detail: an object that a head
    /// sweep carries out towards the periphery and back within the delay
    /// keeps its LOD, where the plain rule would coarsen it and ask for
    /// the detail back (a visible pop in the fovea). Under
    /// [`Selector::select_within_budget`] the held LOD stays only while
    /// the budget has room for it; under [`ScaleRule::Budgeted`] at
    /// `s < 1` it stays whatever the budget needs, until `s` falls.
    pub switch_coarsen_delay_s: f32,
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
    /// a refresh rate
    /// ([`Display::with_refresh_hz`](crate::display::Display::with_refresh_hz))
    /// never below the floor of sampled motion.
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
    /// so the floor of sampled motion
    /// ([`Display::with_refresh_hz`](crate::display::Display::with_refresh_hz))
    /// does not hold: each object's detail follows `G(v)` at its retinal
    /// velocity (the gaze's own sweep), which drops most of it (saccadic
    /// suppression and motion smear). Detail returns on the first frame the
    /// gaze is slower again, within the tens of milliseconds of suppression
    /// that follow a saccade's landing. `f32::INFINITY` (the default), and
    /// any value not > 0: never; [`SACCADE_THRESHOLD_DEG_PER_S`] is the
    /// usual detection threshold.
    pub saccade_threshold_deg_per_s: f32,
    /// Added to every object's bounding radius when it is selected, world
    /// units: a sphere grown by the distance between the selecting camera
    /// and any eye that sees the frame holds everything that eye sees of
    /// the object, larger and nearer the gaze. [`crate::StereoRig`] sets it
    /// to twice the larger eye offset, so one selection serves both eyes.
    /// Any value not finite and `> 0` counts as 0 (the default).
    pub radius_margin: f32,
    /// Whether each `select*` call lists the objects whose selection
    /// changed ([`Selector::changed`]); off by default. It costs a byte
    /// compared per object and a cache miss or so per change (measured in
    /// `docs/selection.md`). Cross-fades turn it on.
    pub track_changes: bool,
    /// Length of a cross-fade between LODs, s ([`Selector::fades`]).
    /// 0 (the default), and any value not finite and > 0: no cross-fades,
    /// LODs switch at once.
    ///
    /// A switch between two LODs starts a fade from the old LOD to the
    /// new one. A switch during a fade: back to the LOD fading out reverses
    /// the fade (the weights carry on from where they were); to a third
    /// LOD starts a new fade from whichever of the two LODs had the larger
    /// weight (the other, at most half visible, is dropped), so at most two
    /// LODs are ever drawn. Switches to or from culled do not fade (the
    /// object is out of view) and end a running fade, as do removing the
    /// object and changing its profile. Fades do not change the
    /// selections, and the triangle budget does not count the LOD fading
    /// out.
    pub fade_time_s: f32,
    /// With an eye tracker ([`crate::Tracker::Eye`]): the longest a switch
    /// to a coarser LOD waits for a saccade, s. 0 (the default), and any
    /// value not finite and > 0: switches happen on the frame they are
    /// chosen.
    ///
    /// Vision is suppressed during a saccade, so a switch made then is the
    /// least visible one. A switch to a coarser LOD only saves triangles,
    /// so it may wait: the object keeps its finer LOD until a frame in
    /// which the gaze moves faster than the saccade threshold
    /// ([`saccade_threshold_deg_per_s`](Self::saccade_threshold_deg_per_s)
    /// when set, else [`SACCADE_THRESHOLD_DEG_PER_S`]), or until it has
    /// waited this long. Switches to a finer LOD (the detail is visible
    /// now), into or out of view, and out of an object's LOD range happen
    /// at once; a wait ends without a switch when the coarser LOD is no
    /// longer chosen. A waiting object draws more triangles than chosen;
    /// under [`Selector::select_within_budget`] a switch waits only while
    /// the budget has room for the triangles its finer LOD adds. Without
    /// an eye tracker nothing waits (no saccade is seen).
    pub defer_coarsening_s: f32,
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
            min_scale: DEFAULT_MIN_SCALE,
            budget_rule: BudgetRule::default(),
            scale_rule: ScaleRule::default(),
            visibility_budget: VisibilityBudget::Off,
            budget_hysteresis: 0.5,
            switch_hysteresis: 0.0,
            switch_min_dwell_s: 0.0,
            switch_coarsen_delay_s: 0.0,
            simd: SimdLevel::Widest,
            observer: Observer::default(),
            eccentricity_model: EccentricityModel::default(),
            velocity_model: VelocityModel::default(),
            eyes_counter_rotate: true,
            saccade_threshold_deg_per_s: f32::INFINITY,
            radius_margin: 0.0,
            track_changes: false,
            fade_time_s: 0.0,
            defer_coarsening_s: 0.0,
        }
    }
}

/// How a triangle budget is spent when the LODs at the frame's `s` do not
/// fit ([`Selector::select_within_budget`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BudgetRule {
    /// Coarsen first where the predicted visibility per triangle saved is
    /// lowest (Luebke & Hallen 2001 §4; Funkhouser & Séquin 1993's benefit
    /// over cost): objects that save many triangles at a barely visible
    /// cost go before those that save few. A step's visibility is how far
    /// the object's acuity lies above the step's critical acuity (`ln v`)
    /// times the object's angular size in degrees: what a LOD step changes
    /// lies along the object's outline and edges, whose length on screen
    /// grows with its size, and an image is judged by the differences
    /// over all of it.
    #[default]
    BestEffort,
    /// As [`BudgetRule::BestEffort`] with the visibility `ln v` alone,
    /// whatever the object's size (the rule before size weighed in; kept
    /// to measure against).
    BestEffortUnweighted,
    /// Lower one `s` for every object until the triangles fit (Reddy
    /// 1998's global scale): the least visible detail first, whatever it
    /// saves.
    UniformScale,
}

/// How [`Selector::select`] spends a global scale factor `s < 1`
/// ([`SelectorSettings::scale_rule`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ScaleRule {
    /// Every object is judged at `s H(v, E)` (Reddy 1998): the detail
    /// closest to threshold goes first, whatever it saves. The plain loop's
    /// cost per object.
    #[default]
    Uniform,
    /// `s` sets how many triangles are drawn, where
    /// [`SelectorSettings::budget_rule`] decides: the budget is the
    /// triangles [`ScaleRule::Uniform`] would draw at this `s` (its LODs'
    /// triangles, before switch hysteresis and waits for a saccade), spent
    /// from the LODs at `s = 1` as [`Selector::select_within_budget`]
    /// spends a budget (a step is taken whole, so the frame may draw fewer).
    /// It draws more only where
    /// [`SelectorSettings::switch_min_dwell_s`] holds an LOD: this budget
    /// is a scheduler's soft target, so within the dwell time after a
    /// switch an object does not switch back, whichever way the budget
    /// moves (a budget that rises and falls with `s` would otherwise refine
    /// an object and coarsen it again a few frames later: flicker). With [`BudgetRule::BestEffort`] the objects that
    /// save many triangles at a barely visible cost coarsen first, so a
    /// scheduler that turns `s` spends its frame where it is seen. Costs a
    /// budgeted selection per frame while `s < 1` (the plain loop at
    /// `s = 1`).
    Budgeted,
}

/// The visibility summed over the image that `s = 1` may spend
/// ([`SelectorSettings::visibility_budget`]), in best effort's measure
/// (`theta ln(v / v0)^beta` per object, deg, `v0` [`VISIBILITY_COUNTED_FROM`],
/// `beta` [`VISIBILITY_POOLING_EXPONENT`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum VisibilityBudget {
    /// None: `s = 1` draws the LODs each invisible on its own.
    #[default]
    Off,
    /// The calibration that makes `s = 1` just imperceptible over the
    /// whole image: [`IMPERCEPTIBLE_VISIBILITY_DEG`] on a field of view of
    /// [`IMPERCEPTIBLE_VISIBILITY_FIELD_DEG2`], in proportion to the
    /// selector's display's field of view (the budget is a sum over the
    /// image); it follows [`Selector::set_display`].
    Imperceptible,
    /// A budget in deg, whatever the display: finite and `> 0`, else off.
    Deg(f32),
}

/// The visibility budget that puts `s = 1` at the edge of visibility on a
/// display of [`IMPERCEPTIBLE_VISIBILITY_FIELD_DEG2`], deg
/// ([`VisibilityBudget::Imperceptible`]), with the steady switch rules of
/// [`SelectorSettings::just_imperceptible`] and profiles made with the
/// offline pass's defaults. Fixed once, for every scene and display, on
/// the lab's `scenes/library.toml`, on each of its five kinds of object
/// alone (scanned bunnies, bumpy rocks, finely rippled rocks, smooth
/// tessellated spheres and tori) and on ten rocks alone (few objects
/// share one budget, so each takes larger steps): the largest budget
/// measured (in steps of 2 deg) that keeps `s = 1` at or above the edge
/// of visibility (FovVideoVDP, foveated, 9.75 JOD) on each, with
/// visibility counted from [`VISIBILITY_COUNTED_FROM`] and pooled with
/// [`VISIBILITY_POOLING_EXPONENT`] (at 34 deg the ten rocks score 9.747).
/// A scene spends the whole budget on the kinds it has, so a budget
/// fitted to a mixed scene alone leaves a scene of its most cheaply
/// priced kind perceptible.
pub const IMPERCEPTIBLE_VISIBILITY_DEG: f32 = 32.0;

/// `beta`: the exponent with which a visibility budget pools the objects'
/// differences over the image, `theta ln(v / v0)^beta` per object (a
/// Minkowski sum over the pixels that differ; see
/// [`VisibilityBudget`]). FovVideoVDP 1.2's spatial pooling exponent
/// (Mantiuk et al. 2021), the metric the budget is calibrated against:
/// many differences each a little beyond the edge count for less than a
/// few far beyond it, so a scene of many objects spends the budget in
/// smaller steps on more of them.
pub const VISIBILITY_POOLING_EXPONENT: f32 = crate::csf::POOLING_EXPONENT;

/// `v0`: where a visibility budget starts counting a step's visibility,
/// `theta ln(v / v0)^beta` with `v = k / q` (the object's threshold at `s = 1`
/// over the critical acuity of the transitions the step crosses; `v = 1`
/// is the edge at which the step is invisible on its own). Below 1, so
/// that steps just inside the edge are not free: differences each
/// invisible alone still add up over an image (probability summation
/// over its objects), and an object whose step saves many triangles then
/// coarsens before many whose steps each lie just inside the edge and save
/// few. One octave of frequency: a step whose features lie at twice the
/// frequency the eye resolves at their contrast, where the contrast
/// sensitivity function's fall at high frequencies leaves them well below
/// threshold, counts as nothing (two octaves, `v0 = 1/4`, with its budget
/// fixed by the same rule, measured alike). Fixed with
/// [`IMPERCEPTIBLE_VISIBILITY_DEG`] on the same scenes (counted from the
/// edge itself, 1, the library's smooth spheres needed 1.16x a
/// screen-size table's triangles at equal JOD; from 1/2, 0.91x).
pub const VISIBILITY_COUNTED_FROM: f32 = 0.5;

/// The lowest `s` a frame-rate scheduler may use by default:
/// [`SelectorSettings::min_scale`] and
/// [`ReactiveSettings::min_scale`](crate::ReactiveSettings::min_scale).
/// Low enough that nearly every object, even at the centre of the gaze,
/// reaches its coarsest LOD, so that a scheduler can hold a rate its cost
/// floor allows; at 0.01 objects near the gaze keep detail the frame
/// cannot afford, and their LODs then follow the eye model alone as they
/// cross the field.
pub const DEFAULT_MIN_SCALE: f32 = 1e-3;

/// The lowest `min_scale` either setting takes; a lower one is raised to
/// it.
pub const LOWEST_MIN_SCALE: f32 = 1e-6;

/// A `min_scale` as both settings read it: clamped into
/// `[LOWEST_MIN_SCALE, 1]`, and [`DEFAULT_MIN_SCALE`] where it is not
/// finite (NaN and both infinities).
pub(crate) fn effective_min_scale(min_scale: f32) -> f32 {
    if min_scale.is_finite() {
        min_scale.clamp(LOWEST_MIN_SCALE, 1.0)
    } else {
        DEFAULT_MIN_SCALE
    }
}

/// [`SelectorSettings::switch_hysteresis`] of the steady switch rules
/// ([`SelectorSettings::just_imperceptible`], and the lab's schedulers):
/// an object near a transition's critical frequency switches once as the
/// view or `s` crosses it, not back and forth with every small wobble.
pub const STEADY_SWITCH_HYSTERESIS: f32 = 0.15;

/// [`SelectorSettings::switch_min_dwell_s`] of the steady switch rules, s:
/// longer than the quarter second within which a switch back reads as
/// flicker (the lab's reversal counter's window), so that a switch the
/// dwell rule holds back never lands on that window's edge.
pub const STEADY_SWITCH_MIN_DWELL_S: f32 = 0.3;

/// [`SelectorSettings::switch_coarsen_delay_s`] of the steady switch
/// rules, s: a head sweep or a glance carries objects out of the fovea and
/// back within about a second, and each trip out would otherwise cost a
/// coarsening and a refinement.
pub const STEADY_SWITCH_COARSEN_DELAY_S: f32 = 0.5;

/// The field of view [`IMPERCEPTIBLE_VISIBILITY_DEG`] was fixed on, deg²:
/// 43.6 x 33.4 deg, Reddy 1998's display.
pub const IMPERCEPTIBLE_VISIBILITY_FIELD_DEG2: f32 = 43.6 * 33.4;

impl VisibilityBudget {
    /// The budget on `display`, deg: 0 when off (and for a [`Deg`](Self::Deg)
    /// not finite and `> 0`).
    pub fn deg_on(self, display: &Display) -> f32 {
        let deg = match self {
            VisibilityBudget::Off => 0.0,
            VisibilityBudget::Imperceptible => {
                let [x, y] = display.fov_deg();
                IMPERCEPTIBLE_VISIBILITY_DEG * (x * y / IMPERCEPTIBLE_VISIBILITY_FIELD_DEG2)
            }
            VisibilityBudget::Deg(deg) => deg,
        };
        positive_or_zero(deg)
    }
}

impl SelectorSettings {
    /// The default settings with `s = 1` just imperceptible over the whole
    /// image: [`ScaleRule::Budgeted`], [`VisibilityBudget::Imperceptible`]
    /// and the steady switch rules ([`STEADY_SWITCH_HYSTERESIS`],
    /// [`STEADY_SWITCH_MIN_DWELL_S`], [`STEADY_SWITCH_COARSEN_DELAY_S`]),
    /// with which the budget was calibrated: a switch is a change over
    /// time the eye sees beside the detail it removes, and with fewer of
    /// them the same image hides more. Where the default draws at `s = 1`
    /// the LODs each invisible on its own, these also spend the
    /// visibility an image can hide (fewer triangles, still
    /// imperceptible), for a budgeted selection per frame (about ten times
    /// the plain loop's cost per object).
    pub fn just_imperceptible() -> Self {
        Self {
            scale_rule: ScaleRule::Budgeted,
            visibility_budget: VisibilityBudget::Imperceptible,
            switch_hysteresis: STEADY_SWITCH_HYSTERESIS,
            switch_min_dwell_s: STEADY_SWITCH_MIN_DWELL_S,
            switch_coarsen_delay_s: STEADY_SWITCH_COARSEN_DELAY_S,
            ..Self::default()
        }
    }
}

/// An object to select LODs for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectDesc {
    /// Centre of the bounding sphere, world units; each coordinate within
    /// `±MAX_WORLD_COORDINATE`. For an instance of a profiled mesh: the
    /// mesh's bounding-sphere centre (the analysis camera's target) placed
    /// by the instance's transform.
    pub center: DVec3,
    /// Radius of the bounding sphere, world units, finite and `>= 0`. For
    /// an instance of a profiled mesh drawn at uniform scale `k`:
    /// `profile.bounding_radius * k` ([`crate::Profile::bounding_radius`]
    /// is in the mesh's own units). A larger radius makes the object look
    /// bigger to the model and keep more detail; a smaller one, less.
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
    /// Triangles drawn: those of the chosen LODs and of the finer LODs
    /// held by switches waiting for a saccade (culled objects count 0).
    pub triangles: u64,
    /// Whether the budget was met (false when even the lowest `s` is over).
    pub within_budget: bool,
}

/// A duration, rate or setting that is on only when finite and > 0: `v`
/// then, else 0 (off; NaN, infinities and negatives included).
pub(super) fn positive_or_zero(v: f32) -> f32 {
    if v.is_finite() && v > 0.0 { v } else { 0.0 }
}
