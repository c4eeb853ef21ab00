//! The [`Selector`]: adding objects and profiles (compiling their rows),
//! moving objects, and selecting for a frame, plain or with diagnostics;
//! the loop itself is in `kernel`, selection within a triangle budget in
//! `budgeted`.

use std::collections::VecDeque;

use glam::Vec3;

use crate::camera::Tracker;
use crate::csf::Csf;
use crate::display::Display;
use crate::error::Result;
use crate::profile::Profile;
use crate::rows;
use crate::viewpoints::ViewpointLookup;

use super::adjust::Adjust;
use super::best_effort::ChainStep;
use super::dispatch::{dispatch, widest};
use super::frame::{checked_scale, frame_consts, motion_floor_cpd, outside_frustum};
use super::hysteresis::SwitchRecord;
use super::kernel::Outputs;
use super::objects::{Handle, SingleRecord};
use super::store::{Block, BudgetEntry, MotionBlock};
use super::tables::{CompiledProfile, Ladder, ProfileRows, RowLayout, Tables};
use super::{
    Diagnostics, Fade, FrameInput, NO_LOOKUP, ObjectId, ProfileId, SACCADE_THRESHOLD_DEG_PER_S,
    ScaleRule, Selection, SelectorSettings, ViewpointRule, positive_or_zero,
};

/// Selects LODs for a set of objects, frame after frame.
///
/// ```
/// use acuity::{Camera, Display, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings};
/// # fn main() -> Result<(), acuity::Error> {
/// # let profile = acuity::profile_for_docs();
/// let display = Display::new([1920, 1080], [90.0, 58.7])?;
/// let settings = SelectorSettings { track_changes: true, ..Default::default() };
/// let mut selector = Selector::new(display, settings);
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
/// for &changed in selector.changed() {
///     println!("{changed:?} now {:?}", selector.selection(changed));
/// }
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
    pub(super) profile_row0: Vec<u32>,
    /// The profile of each object with more than one LOD (so also their
    /// count: they take slots `0..object_profiles.len()`).
    pub(super) object_profiles: Vec<u32>,
    pub(super) layout: RowLayout,
    pub(super) rows: Vec<f32>,
    /// The lowest `G(v)` on this display and observer, c/deg (0 for
    /// continuous motion).
    motion_floor_cpd: f32,
    /// The gaze direction of the last frame in world axes, with an eye
    /// tracker (for saccade detection).
    gaze_world: Option<Vec3>,
    /// Objects with more than one LOD: the object in slot `i` is lane
    /// `i % BLOCK` of block `i / BLOCK`.
    pub(super) blocks: Vec<Block>,
    pub(super) motion: Vec<MotionBlock>,
    /// Per slot: the selection, last frame's (the two are swapped before
    /// the loop writes every selection anew), and the object's id.
    pub(super) selections: Vec<Selection>,
    pub(super) previous: Vec<Selection>,
    pub(super) slot_ids: Vec<ObjectId>,
    /// Per slot of an object with more than one LOD.
    pub(super) diagnostics: Vec<Diagnostics>,
    pub(super) budget: Vec<BudgetEntry>,
    /// Single-LOD objects, for slots `object_profiles.len()..`.
    pub(super) singles: VecDeque<SingleRecord>,
    /// Ids to slots (and to adjustments and fades); removed objects'
    /// entries are free for reuse.
    pub(super) handles: Vec<Handle>,
    pub(super) free_handles: Vec<u32>,
    /// The objects with a bias or an LOD range, and how many have a bias.
    pub(super) adjusted: Vec<Adjust>,
    pub(super) biased: usize,
    /// The objects whose selection changed in the last call (once
    /// listed), their slots, and what they had before; with capacity for
    /// every object, so that frames never allocate.
    pub(super) changed: Vec<ObjectId>,
    pub(super) changed_slots: Vec<u32>,
    pub(super) switched_from: Vec<Selection>,
    pub(super) fades: Vec<Fade>,
    /// With an eye tracker, whether the gaze moved as fast as a saccade
    /// into this frame; `None` without one.
    pub(super) in_saccade: Option<bool>,
    /// The handles and wait times of the objects whose switch to a
    /// coarser LOD waits for a saccade, this frame's and the frame
    /// before's (swapped each frame; capacity for every object).
    pub(super) deferred: Vec<(u32, f32)>,
    pub(super) deferred_before: Vec<(u32, f32)>,
    /// The best-effort budget's per-slot adjustment index, kept between
    /// frames.
    pub(super) adjusted_of: Vec<u32>,
    /// The best-effort budget's steps of every object, in slot order
    /// (`chains[chain_start[slot]..chain_start[slot + 1]]`), and each
    /// object's visibility at the LOD its chain starts from (deg), kept
    /// between frames for their capacity.
    pub(super) chains: Vec<ChainStep>,
    pub(super) chain_start: Vec<u32>,
    pub(super) chain_start_deg: Vec<f32>,
    /// The switch hysteresis' clock (the sum of the frames' `dt_s`), s,
    /// and per slot what its rules by time remember (the last switch, for
    /// [`SelectorSettings::switch_min_dwell_s`], and since when a coarser
    /// LOD is asked for, for [`SelectorSettings::switch_coarsen_delay_s`]).
    pub(super) clock_s: f64,
    pub(super) switch_records: Vec<SwitchRecord>,
    /// The `s` of the last frame that applied the hysteresis: a lower one
    /// is a scheduler lowering `s`, whose coarsenings do not wait.
    pub(super) hysteresis_scale: f32,
    /// The `s` the last frame's thresholds (`budget`) were recorded at;
    /// `None` when that frame recorded none.
    pub(super) recorded_scale: Option<f32>,
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
            previous: Vec::new(),
            slot_ids: Vec::new(),
            diagnostics: Vec::new(),
            budget: Vec::new(),
            singles: VecDeque::new(),
            handles: Vec::new(),
            free_handles: Vec::new(),
            adjusted: Vec::new(),
            biased: 0,
            changed: Vec::new(),
            changed_slots: Vec::new(),
            switched_from: Vec::new(),
            fades: Vec::new(),
            in_saccade: None,
            deferred: Vec::new(),
            deferred_before: Vec::new(),
            adjusted_of: Vec::new(),
            chains: Vec::new(),
            chain_start: Vec::new(),
            chain_start_deg: Vec::new(),
            clock_s: 0.0,
            switch_records: Vec::new(),
            hysteresis_scale: 1.0,
            recorded_scale: None,
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

    /// Triangles drawn with the current selections (culled objects: 0).
    pub fn triangles(&self) -> u64 {
        let multi: u64 = self
            .object_profiles()
            .zip(&self.selections)
            .filter_map(|(p, s)| s.lod().map(|l| self.profiles[p].triangles[l] as u64))
            .sum();
        multi + self.single_triangles()
    }

    /// Triangles the visible objects would draw at their coarsest LODs
    /// (within their LOD ranges), with the current culling: the part of a
    /// frame no choice of LOD removes ([`crate::CostModel::floor_s`]).
    pub fn coarsest_triangles(&self) -> u64 {
        let coarsest = |p: usize| {
            let t = &self.profiles[p].triangles;
            (t.len() - 1, t)
        };
        let mut multi: u64 = self
            .object_profiles()
            .zip(&self.selections)
            .filter(|(_, s)| !s.is_culled())
            .map(|(p, _)| {
                let (last, t) = coarsest(p);
                u64::from(t[last])
            })
            .sum();
        for a in &self.adjusted {
            let slot = self.handles[a.handle as usize].slot as usize;
            if slot < self.multi() && !self.selections[slot].is_culled() {
                let (last, t) = coarsest(self.object_profiles[slot] as usize);
                let clamped = t[a.clamp(last, t.len())];
                multi = multi - u64::from(t[last]) + u64::from(clamped);
            }
        }
        multi + self.single_triangles()
    }

    pub(super) fn single_triangles(&self) -> u64 {
        self.singles
            .iter()
            .zip(&self.selections[self.multi()..])
            .filter(|(_, s)| !s.is_culled())
            .map(|(o, _)| self.profiles[o.profile as usize].triangles[0] as u64)
            .sum()
    }

    /// The profile index of each object with more than one LOD, in order.
    pub(super) fn object_profiles(&self) -> impl Iterator<Item = usize> + '_ {
        self.object_profiles.iter().map(|&p| p as usize)
    }
}

impl Selector {
    /// Selects every object's LOD for one frame; read the results with
    /// [`selection`](Self::selection), [`selections`](Self::selections),
    /// [`changed`](Self::changed) and [`fades`](Self::fades). Fails only on
    /// an invalid frame (non-finite camera or gaze, `scale` not in
    /// `(0, 1]`), leaving every state unchanged.
    pub fn select(&mut self, frame: &FrameInput) -> Result<()> {
        self.select_recording(frame, false)
    }

    /// As [`select`](Self::select), and records each object's
    /// [`Diagnostics`].
    pub fn select_with_diagnostics(&mut self, frame: &FrameInput) -> Result<()> {
        self.select_recording(frame, true)
    }

    /// [`select`](Self::select), recording the diagnostics when asked.
    fn select_recording(&mut self, frame: &FrameInput, diagnostics: bool) -> Result<()> {
        if self.settings.scale_rule == ScaleRule::Budgeted {
            let scale = checked_scale(frame.scale)?;
            if scale < 1.0 || self.visibility_allowance_deg() > 0.0 {
                self.select_spending_scale(frame, scale, u64::MAX, diagnostics)?;
                if diagnostics {
                    for d in &mut self.diagnostics {
                        d.threshold_cpd *= scale;
                    }
                }
                return Ok(());
            }
        }
        let biased = self.biased > 0;
        let hysteresis = self.hysteresis();
        let thresholds = hysteresis.is_some_and(|h| h.needs_thresholds());
        self.run(frame, frame.scale, diagnostics, biased || thresholds)?;
        if let Some(h) = hysteresis {
            self.advance_clock(frame.dt_s);
            let scale_fell = self.scale_fell(frame.scale);
            self.apply_hysteresis(h, None, scale_fell);
        }
        if !self.adjusted.is_empty() {
            self.apply_adjustments(biased, diagnostics);
        }
        self.finish_frame(frame, None);
        Ok(())
    }

    /// This frame's floor under `G(v)`, c/deg (0 during a saccade with
    /// the saccade rule on), whether the gaze moved as fast as a saccade
    /// (`None`: not known, without an eye tracker or with neither saccade
    /// setting on), and the gaze direction in world axes to remember for
    /// the next frame.
    pub(super) fn frame_motion_floor(
        &self,
        frame: &FrameInput,
    ) -> (f32, Option<bool>, Option<Vec3>) {
        let rule = self.settings.saccade_threshold_deg_per_s;
        let rule_on = rule > 0.0 && rule.is_finite();
        let eye_tracked = matches!(frame.gaze.tracker, Tracker::Eye { .. });
        if !(eye_tracked && (rule_on || self.defers_coarsening())) {
            return (self.motion_floor_cpd, None, None);
        }
        let threshold = if rule_on {
            rule
        } else {
            SACCADE_THRESHOLD_DEG_PER_S
        };
        let gaze_world =
            (frame.camera.orientation.normalize() * frame.gaze.direction_camera).try_normalize();
        let dt = frame.dt_s;
        let in_saccade = match (self.gaze_world, gaze_world) {
            (Some(before), Some(now)) if dt.is_finite() && dt > 0.0 => {
                before.angle_between(now).to_degrees() > threshold * dt
            }
            _ => false,
        };
        let floor = if in_saccade && rule_on {
            0.0
        } else {
            self.motion_floor_cpd
        };
        (floor, Some(in_saccade), gaze_world)
    }

    /// Whether switches to coarser LODs wait for saccades
    /// ([`SelectorSettings::defer_coarsening_s`]).
    pub(super) fn defers_coarsening(&self) -> bool {
        positive_or_zero(self.settings.defer_coarsening_s) > 0.0
    }

    /// The loop over every object, writing the selections and, when asked,
    /// the diagnostics and the budget entries (each visible object's
    /// threshold and row).
    pub(super) fn run(
        &mut self,
        frame: &FrameInput,
        scale_override: f32,
        diagnostics: bool,
        budget: bool,
    ) -> Result<()> {
        let (motion_floor_cpd, in_saccade, gaze_world) = self.frame_motion_floor(frame);
        let mut c = frame_consts(
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
        c.pursued = self.pursued_slot(frame.gaze.pursued);
        self.recorded_scale = budget.then_some(c.scale);
        self.gaze_world = gaze_world;
        self.in_saccade = in_saccade;
        let multi = self.object_profiles.len();
        // Last frame's selections become the previous ones; the loop writes
        // every selection of objects with several LODs, and the one below
        // every single-LOD object's.
        std::mem::swap(&mut self.selections, &mut self.previous);
        if budget {
            self.budget.resize(multi, BudgetEntry::default());
        }
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
        let (multi_selections, single_selections) = self.selections.split_at_mut(multi);
        let outputs = Outputs {
            selections: multi_selections,
            diagnostics: diagnostics.then_some(&mut self.diagnostics[..]),
            budget: budget.then_some(&mut self.budget[..]),
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
            for (o, sel) in self.singles.iter().zip(single_selections) {
                let p = c.world_to_eye * (o.center - c.cam_pos).as_vec3();
                *sel = if outside_frustum(&c, p, o.radius) {
                    Selection::CULLED
                } else {
                    Selection(0)
                };
            }
        } else {
            single_selections.fill(Selection(0));
        }
        Ok(())
    }
}
