//! Per-object adjustments: a bias on the object's threshold and a range
//! of LODs it may take. Kept in a short list of the objects that have one,
//! applied after the loop, so objects without one cost nothing.

use std::ops::RangeInclusive;

use crate::error::{Error, Result};

use super::objects::NONE;
use super::rule::count_coarser;
use super::{ObjectId, Selection, Selector};

/// An object's bias and LOD range.
#[derive(Clone, Copy, Debug)]
pub(super) struct Adjust {
    /// The object's handle.
    pub(super) handle: u32,
    pub(super) bias: f32,
    pub(super) min_lod: usize,
    pub(super) max_lod: usize,
}

impl Adjust {
    pub(super) fn range(&self) -> RangeInclusive<usize> {
        self.min_lod..=self.max_lod
    }

    fn is_default(&self) -> bool {
        self.bias == 1.0 && self.min_lod == 0 && self.max_lod == usize::MAX
    }

    /// `lod` clamped into the range, as far as a profile of `lod_count`
    /// LODs allows.
    pub(super) fn clamp(&self, lod: usize, lod_count: usize) -> usize {
        let coarsest = lod_count - 1;
        lod.clamp(self.min_lod.min(coarsest), self.max_lod.min(coarsest))
    }
}

impl Selector {
    /// Sets an object's bias: a multiplier on its threshold `T = s H(v, E)`
    /// (what [`Diagnostics::threshold_cpd`](super::Diagnostics) reports),
    /// finite and `> 0`; 1 is the default. Above 1 the object keeps more
    /// detail (a feature must be finer to be dropped), below 1 less: its
    /// LOD never coarsens as the bias grows. It acts like a scale factor
    /// `s` of its own (for a hero object, or background clutter), and the
    /// budgeted selection scales it with `s` too.
    ///
    /// While any object has a bias other than 1, `select` also records
    /// every visible object's threshold and row (as the budgeted
    /// selection does), which costs a few percent.
    pub fn set_bias(&mut self, id: ObjectId, bias: f32) -> Result<()> {
        self.slot(id)?;
        if !(bias.is_finite() && bias > 0.0) {
            return Err(Error::invalid(
                "bias",
                format!("{bias} is not a finite bias > 0"),
            ));
        }
        self.adjust(id, |a| a.bias = bias);
        Ok(())
    }

    /// Sets the LODs an object may take: its selection is clamped into
    /// `lods` (0 the finest; an end past the profile's coarsest LOD means
    /// the coarsest), after its bias. Culling is unaffected. `0..=usize::MAX`
    /// is the default; an empty range is refused.
    pub fn set_lod_range(&mut self, id: ObjectId, lods: RangeInclusive<usize>) -> Result<()> {
        self.slot(id)?;
        let (min_lod, max_lod) = (*lods.start(), *lods.end());
        if min_lod > max_lod {
            return Err(Error::invalid(
                "lods",
                format!("{min_lod}..={max_lod} is empty"),
            ));
        }
        self.adjust(id, |a| {
            a.min_lod = min_lod;
            a.max_lod = max_lod;
        });
        Ok(())
    }

    /// Changes an object's adjustment, adding it to or dropping it from
    /// the list as it leaves or returns to the default.
    fn adjust(&mut self, id: ObjectId, change: impl FnOnce(&mut Adjust)) {
        let h = id.index as usize;
        let at = match self.handles[h].adjust {
            NONE => {
                self.adjusted.push(Adjust {
                    handle: id.index,
                    bias: 1.0,
                    min_lod: 0,
                    max_lod: usize::MAX,
                });
                self.handles[h].adjust = self.adjusted.len() as u32 - 1;
                self.adjusted.len() - 1
            }
            i => i as usize,
        };
        let was_biased = self.adjusted[at].bias != 1.0;
        change(&mut self.adjusted[at]);
        let biased = self.adjusted[at].bias != 1.0;
        self.biased = self.biased + biased as usize - was_biased as usize;
        if self.adjusted[at].is_default() {
            self.remove_adjust(at);
        }
    }

    /// Drops entry `at` of the adjustment list.
    pub(super) fn remove_adjust(&mut self, at: usize) {
        let gone = self.adjusted.swap_remove(at);
        self.biased -= (gone.bias != 1.0) as usize;
        self.handles[gone.handle as usize].adjust = NONE;
        if let Some(moved) = self.adjusted.get(at) {
            self.handles[moved.handle as usize].adjust = at as u32;
        }
    }

    /// After the loop: the biased objects' LODs counted again at their
    /// biased threshold (from the rows and thresholds the loop recorded,
    /// when `recount`; their diagnostics' thresholds scaled when
    /// `diagnostics`), and every adjusted object's LOD clamped.
    pub(super) fn apply_adjustments(&mut self, recount: bool, diagnostics: bool) {
        let multi = self.multi();
        for a in &self.adjusted {
            let slot = self.handles[a.handle as usize].slot as usize;
            if slot >= multi || self.selections[slot].is_culled() {
                continue;
            }
            let lod_count = self.profiles[self.object_profiles[slot] as usize].lod_count;
            let mut lod = self.selections[slot].0 as usize;
            if recount && a.bias != 1.0 {
                let e = self.budget[slot];
                let row = &self.rows[e.row as usize..][..lod_count - 1];
                lod = count_coarser(row, a.bias * e.k_cdiam);
                if diagnostics {
                    self.diagnostics[slot].threshold_cpd *= a.bias;
                }
            }
            self.selections[slot] = Selection(a.clamp(lod, lod_count) as u8);
        }
    }

    /// Before a budgeted choice: the biased objects' recorded thresholds
    /// times their bias.
    pub(super) fn bias_budget_entries(&mut self) {
        let multi = self.multi();
        for a in &self.adjusted {
            let slot = self.handles[a.handle as usize].slot as usize;
            if slot < multi && a.bias != 1.0 && self.budget[slot].row != u32::MAX {
                self.budget[slot].k_cdiam *= a.bias;
            }
        }
    }
}
