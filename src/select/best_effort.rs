//! Best effort under a triangle budget: when the LODs chosen at the
//! frame's `s` do not fit, coarsen first where the predicted visibility per
//! triangle saved is lowest (Luebke & Hallen 2001 §4 order simplifications
//! by perceptibility for best-effort rendering; Funkhouser & Séquin 1993
//! spend a budget by benefit over cost).
//!
//! The visibility of an object's next step, from LOD `j` to the next LOD
//! that draws fewer triangles, is how far the object's acuity lies above
//! the step's critical acuity: `v = k / q` with `k = H(v, E) u` the
//! object's threshold at `s = 1` and `q` the prefix minimum of the
//! transitions it crosses ([`crate::rows`]): at `s = 1 / v` the step
//! becomes invisible, so `v = 1` is just imperceptible and a larger `v` is
//! further above threshold. Its cost is `ln(v) / saved` (0 at the edge of
//! visibility; in units of log-acuity per triangle), and the greedy takes
//! the cheapest step of all objects, one at a time from a binary heap,
//! until the triangles fit. A uniform `s` takes the steps in order of `v`
//! alone, so an object that would save 3000 triangles at a barely visible
//! cost waits behind one that saves 40 at the same cost; the greedy does
//! not.
//!
//! `s` stays the scheduler's knob: the greedy starts from the LODs at the
//! frame's `s`, takes no step that needs `s` below
//! [`SelectorSettings::min_scale`](super::SelectorSettings::min_scale),
//! and reports as its scale the lowest `s = 1 / v` it reached. The heap's
//! storage is kept between frames, so a frame allocates nothing once it
//! has grown to the number of objects.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::store::BudgetEntry;
use super::{Selection, Selector};

/// One object's next coarsening step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Step {
    /// `ln(v) / saved`: what the step costs per triangle it saves.
    cost: f32,
    /// The scale `s = 1 / v` at which the step becomes invisible.
    scale: f32,
    saved: u32,
    slot: u32,
    to_lod: u8,
}

impl PartialEq for Step {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Step {}

impl PartialOrd for Step {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Step {
    /// Reversed, so that [`BinaryHeap`] (a max-heap) pops the cheapest
    /// step; among equal costs the larger saving, then the lower slot.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .cost
            .total_cmp(&self.cost)
            .then(self.saved.cmp(&other.saved))
            .then(other.slot.cmp(&self.slot))
    }
}

impl Selector {
    /// Chooses the LODs of every visible object with more than one LOD
    /// (writing their selections, before LOD ranges are applied) so that
    /// the triangles fit `triangle_budget` where the steps allowed reach
    /// it, cheapest step first (see the module docs). Returns the scale
    /// reached and the triangles drawn (LOD ranges counted).
    pub(super) fn best_effort_within(&mut self, s_max: f32, triangle_budget: u64) -> (f32, u64) {
        let s_min = self.settings.min_scale.clamp(1e-6, s_max);
        let multi = self.multi();
        // Per slot, its entry in `adjusted` (u32::MAX: none).
        let mut adjusted_of = std::mem::take(&mut self.adjusted_of);
        adjusted_of.clear();
        if !self.adjusted.is_empty() {
            adjusted_of.resize(multi, u32::MAX);
            for (i, a) in self.adjusted.iter().enumerate() {
                let slot = self.handles[a.handle as usize].slot as usize;
                if slot < multi {
                    adjusted_of[slot] = i as u32;
                }
            }
        }
        let mut steps = std::mem::take(&mut self.steps);
        steps.clear();
        let mut triangles = self.single_triangles();
        for slot in 0..multi {
            let entry = self.budget[slot];
            if entry.row == u32::MAX {
                continue;
            }
            let p = self.object_profiles[slot] as usize;
            let lod = self.lod_at(&entry, p, s_max);
            self.selections[slot] = Selection(lod as u8);
            let adjust = adjusted_of.get(slot).copied().unwrap_or(u32::MAX);
            triangles += u64::from(self.drawn_triangles(p, adjust, lod));
            if let Some(step) = self.next_step(slot, &entry, adjust, lod, s_min) {
                steps.push(step);
            }
        }
        // Heapify in one pass, O(n).
        let mut heap = BinaryHeap::from(steps);
        let mut reached = s_max;
        while triangles > triangle_budget {
            let Some(step) = heap.pop() else { break };
            let slot = step.slot as usize;
            triangles -= u64::from(step.saved);
            reached = reached.min(step.scale);
            self.selections[slot] = Selection(step.to_lod);
            let adjust = adjusted_of.get(slot).copied().unwrap_or(u32::MAX);
            let entry = self.budget[slot];
            if let Some(next) = self.next_step(slot, &entry, adjust, step.to_lod as usize, s_min) {
                heap.push(next);
            }
        }
        let mut steps = heap.into_vec();
        steps.clear();
        self.steps = steps;
        self.adjusted_of = adjusted_of;
        (reached.max(s_min), triangles)
    }

    /// Triangles an object of profile `p` draws at `lod`, after the LOD
    /// range of its adjustment (`u32::MAX`: none).
    fn drawn_triangles(&self, p: usize, adjust: u32, lod: usize) -> u32 {
        let t = &self.profiles[p].triangles;
        let lod = match self.adjusted.get(adjust as usize) {
            Some(a) => a.clamp(lod, t.len()),
            None => lod,
        };
        t[lod]
    }

    /// The object's next step from `lod`: to the first coarser LOD that
    /// draws fewer triangles, if `s_min` allows it.
    fn next_step(
        &self,
        slot: usize,
        entry: &BudgetEntry,
        adjust: u32,
        lod: usize,
        s_min: f32,
    ) -> Option<Step> {
        let p = self.object_profiles[slot] as usize;
        let n = self.profiles[p].lod_count;
        let row = &self.rows[entry.row as usize..][..n - 1];
        let now = self.drawn_triangles(p, adjust, lod);
        for (j, &q) in row.iter().enumerate().skip(lod) {
            // Prefix minima only fall, so a step beyond one that needs
            // `s` below `s_min` needs it too.
            let scale = q / entry.k_cdiam;
            if scale.is_nan() || scale < s_min {
                return None;
            }
            let after = self.drawn_triangles(p, adjust, j + 1);
            if after < now {
                let saved = now - after;
                let visibility = (entry.k_cdiam / q).max(1.0);
                return Some(Step {
                    cost: visibility.ln() / saved as f32,
                    scale,
                    saved,
                    slot: slot as u32,
                    to_lod: (j + 1) as u8,
                });
            }
        }
        None
    }
}
