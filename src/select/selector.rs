//! The [`Selector`]: adding objects and profiles (compiling their rows),
//! moving objects, and selecting for a frame, plain, with diagnostics or
//! within a triangle budget; the loop itself is in `kernel`.

use glam::{DVec3, Quat, Vec3};

use crate::camera::{MAX_WORLD_COORDINATE, Tracker, normalized_rotation};
use crate::csf::Csf;
use crate::display::Display;
use crate::error::{Error, Result};
use crate::profile::Profile;
use crate::rows;
use crate::viewpoints::ViewpointLookup;

use super::dispatch::{Outputs, dispatch, widest};
use super::frame::{checked_scale, frame_consts, motion_floor_cpd, outside_frustum};
use super::rule::count_coarser;
use super::store::{Block, BudgetEntry, EMPTY_BLOCK, MotionBlock, NO_HISTORY};
use super::tables::{CompiledProfile, Ladder, ProfileRows, RowLayout, Tables};
use super::{
    BLOCK, BudgetOutcome, Diagnostics, FrameInput, NO_LOOKUP, ObjectDesc, ObjectId, ProfileId,
    SINGLE_LOD_BIT, Selection, SelectorSettings, ViewpointRule,
};

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
    pub(super) display: Display,
    pub(super) settings: SelectorSettings,
    pub(super) profiles: Vec<CompiledProfile>,
    pub(super) profile_rows: Vec<ProfileRows>,
    /// The profiles as added: their rows are compiled again when the
    /// display changes.
    sources: Vec<Profile>,
    /// Viewpoint lookups, one per distinct viewpoint set.
    pub(super) lookups: Vec<ViewpointLookup>,
    /// Size ladders, one per distinct set of rung diameters.
    pub(super) ladders: Vec<Ladder>,
    /// Per profile: the start of the rows its objects use (viewpoint 0's
    /// block with the nearest-viewpoint rule and a lookup, else the worst
    /// case's).
    profile_row0: Vec<u32>,
    /// The profile of each object with more than one LOD.
    pub(super) object_profiles: Vec<u32>,
    pub(super) layout: RowLayout,
    pub(super) rows: Vec<f32>,
    /// The lowest `G(v)` on this display and observer, c/deg (0 for
    /// continuous motion).
    motion_floor_cpd: f32,
    /// The gaze direction of the last frame in world axes, with an eye
    /// tracker (for saccade detection).
    gaze_world: Option<Vec3>,
    /// Objects with more than one LOD: object `i` is lane `i % BLOCK` of
    /// block `i / BLOCK`.
    pub(super) blocks: Vec<Block>,
    motion: Vec<MotionBlock>,
    /// One per object with more than one LOD (so also their count).
    pub(super) selections: Vec<Selection>,
    pub(super) diagnostics: Vec<Diagnostics>,
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

    /// Predictive fixed-frame-rate selection (after Funkhouser & Séquin
    /// 1993, with `s` as the one knob): picks the largest `s` in
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
    pub(super) fn frame_motion_floor(&self, frame: &FrameInput) -> (f32, Option<Vec3>) {
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
