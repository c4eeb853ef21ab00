//! Hysteresis on switches to coarser LODs, for [`Selector::select`] (and
//! the dwell rule, within the budget's room, for
//! [`Selector::select_within_budget`]):
//! - by threshold
//!   ([`SelectorSettings::switch_hysteresis`](super::SelectorSettings::switch_hysteresis)):
//!   an object that drew a finer LOD last frame coarsens only as far as its
//!   threshold, raised by the hysteresis, still allows;
//! - by time
//!   ([`SelectorSettings::switch_min_dwell_s`](super::SelectorSettings::switch_min_dwell_s)):
//!   an object that switched to a finer LOD coarsens only once it has held
//!   it that long. A switch the same way as the last one is no reversal
//!   and waits for nothing: an object coarsened a frame ago coarsens
//!   further at once when `s` keeps falling (a controller coming down from
//!   an overload sees each lower `s` in the next frame's time);
//! - by delay
//!   ([`SelectorSettings::switch_coarsen_delay_s`](super::SelectorSettings::switch_coarsen_delay_s)):
//!   a coarsening the view asks for (the object moved out towards the
//!   periphery, got smaller or faster) happens only once the view has
//!   asked for it that long without a break, so an object a head sweep
//!   carries out and back within the delay keeps its LOD throughout. A
//!   coarsening asked for in a frame whose `s` is lower than the last
//!   one's (a scheduler coming down) happens at once.
//!
//! Switches to finer LODs happen at once, so the rules only ever keep
//! more detail than the plain rule: an object near a transition's critical
//! frequency switches once as the view or `s` crosses it, not back and
//! forth with every small wobble.
//!
//! The threshold rule reads the thresholds the loop records for budgets;
//! the rules look at every object once, and change only those whose
//! selection became coarser.

use super::Selection;
use super::Selector;
use super::positive_or_zero;
use super::rule::count_coarser;

/// What the rules by time remember of one object (per slot, for the
/// objects with more than one LOD), by the hysteresis' clock, s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SwitchRecord {
    /// When the object last switched LOD (`-inf`: never) ...
    pub(super) last_at_s: f64,
    /// ... and whether that switch went to a finer LOD.
    pub(super) last_to_finer: bool,
    /// Since when the view has asked for a coarser LOD without a break
    /// (`-inf`: it does not).
    pub(super) coarser_since_s: f64,
}

impl SwitchRecord {
    /// An object that never switched and is asked for no coarser LOD.
    pub(super) const FRESH: Self = Self {
        last_at_s: f64::NEG_INFINITY,
        last_to_finer: false,
        coarser_since_s: f64::NEG_INFINITY,
    };
}

/// What the hysteresis of a frame applies.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hysteresis {
    /// `1 + switch_hysteresis` (1: off).
    factor: f32,
    /// `switch_min_dwell_s` (0: off).
    dwell_s: f32,
    /// `switch_coarsen_delay_s` (0: off).
    coarsen_delay_s: f32,
}

impl Hysteresis {
    /// Whether the loop must record thresholds for it.
    pub(super) fn needs_thresholds(self) -> bool {
        self.factor > 1.0
    }

    /// The rules by time alone (under a budget, whose own order has its
    /// hysteresis), or `None` when both are off.
    pub(super) fn dwell_only(self) -> Option<Self> {
        (self.dwell_s > 0.0 || self.coarsen_delay_s > 0.0).then_some(Self {
            factor: 1.0,
            ..self
        })
    }
}

impl Selector {
    /// The frame's hysteresis, or `None` when both rules are off.
    pub(super) fn hysteresis(&self) -> Option<Hysteresis> {
        let h = self.settings.switch_hysteresis;
        let factor = if h.is_finite() && h > 0.0 {
            1.0 + h.min(1.0)
        } else {
            1.0
        };
        let dwell_s = positive_or_zero(self.settings.switch_min_dwell_s);
        let coarsen_delay_s = positive_or_zero(self.settings.switch_coarsen_delay_s);
        (factor > 1.0 || dwell_s > 0.0 || coarsen_delay_s > 0.0).then_some(Hysteresis {
            factor,
            dwell_s,
            coarsen_delay_s,
        })
    }

    /// Whether `scale` (this frame's `s`) is lower than the last frame's
    /// that applied the hysteresis; records it.
    pub(super) fn scale_fell(&mut self, scale: f32) -> bool {
        let fell = scale < self.hysteresis_scale;
        self.hysteresis_scale = scale;
        fell
    }

    /// Advances the dwell rule's clock by a frame's `dt_s` (not finite or
    /// negative: 0); before the frame's selection.
    pub(super) fn advance_clock(&mut self, dt_s: f32) {
        self.clock_s += f64::from(positive_or_zero(dt_s));
    }

    /// Whether a switch of the object in `slot` to a finer (`to_finer`) or
    /// coarser LOD would go back on a switch the other way made less than
    /// `dwell_s` ago (by the clock as advanced for this frame).
    pub(super) fn reverses_within(&self, slot: usize, dwell_s: f32, to_finer: bool) -> bool {
        dwell_s > 0.0
            && self.switch_records.get(slot).is_some_and(|r| {
                r.last_to_finer != to_finer && self.clock_s - r.last_at_s < f64::from(dwell_s)
            })
    }

    /// The dwell time of the frame's hysteresis (0: off).
    pub(super) fn dwell_s(&self) -> f32 {
        self.hysteresis().map_or(0.0, |h| h.dwell_s)
    }

    /// Holds back switches to coarser LODs (the module docs), from this
    /// frame's recorded thresholds and last frame's selections.
    /// With `room`, a switch is held back only while the triangles it
    /// keeps fit in what is left of it (in slot order). `scale_fell`: this
    /// frame's `s` is lower than the last one's, so coarsenings do not
    /// wait for the delay. Returns the triangles held back.
    pub(super) fn apply_hysteresis(
        &mut self,
        hysteresis: Hysteresis,
        room: Option<u64>,
        scale_fell: bool,
    ) -> u64 {
        let mut room = room.unwrap_or(u64::MAX);
        let mut kept = 0u64;
        let multi = self.multi().min(self.previous.len());
        let delay_s = f64::from(hysteresis.coarsen_delay_s);
        if hysteresis.dwell_s > 0.0 || delay_s > 0.0 {
            self.switch_records.resize(multi, SwitchRecord::FRESH);
        }
        let thresholds = hysteresis.needs_thresholds() && self.budget.len() >= multi;
        for slot in 0..multi {
            let (now, before) = (self.selections[slot], self.previous[slot]);
            // Into or out of view is no switch between LODs.
            let coarser = now.0 > before.0 && !now.is_culled() && !before.is_culled();
            if !coarser && let Some(r) = self.switch_records.get_mut(slot) {
                r.coarser_since_s = f64::NEG_INFINITY;
            }
            if now == before || now.is_culled() || before.is_culled() {
                continue;
            }
            let mut chosen = now;
            if coarser {
                let mut held = usize::from(now.0);
                let entry = self.budget.get(slot).copied().unwrap_or_default();
                if thresholds && entry.row != u32::MAX {
                    let n = self.profiles[self.object_profiles[slot] as usize].lod_count - 1;
                    let row = &self.rows[entry.row as usize..][..n];
                    held = held.min(count_coarser(row, hysteresis.factor * entry.k_cdiam));
                }
                if self.reverses_within(slot, hysteresis.dwell_s, false) {
                    held = usize::from(before.0);
                }
                if delay_s > 0.0 && !scale_fell {
                    let since = &mut self.switch_records[slot].coarser_since_s;
                    if *since == f64::NEG_INFINITY {
                        *since = self.clock_s;
                    }
                    if self.clock_s - *since < delay_s {
                        held = usize::from(before.0);
                    }
                }
                let held = held.max(usize::from(before.0));
                let t = &self.profiles[self.object_profiles[slot] as usize].triangles;
                let extra = u64::from(t[held].saturating_sub(t[usize::from(now.0)]));
                if extra <= room {
                    room -= extra;
                    kept += extra;
                    chosen = Selection(held as u8);
                    self.selections[slot] = chosen;
                }
            }
            if chosen != before
                && let Some(r) = self.switch_records.get_mut(slot)
            {
                if chosen.0 > before.0 {
                    r.coarser_since_s = f64::NEG_INFINITY;
                }
                r.last_at_s = self.clock_s;
                r.last_to_finer = chosen.0 < before.0;
            }
        }
        kept
    }
}
