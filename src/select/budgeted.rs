//! Selection within a triangle budget: a given one
//! ([`Selector::select_within_budget`]) or the one a uniform `s` sets
//! ([`ScaleRule::Budgeted`]), spent by [`SelectorSettings::budget_rule`]:
//! best effort (`best_effort`), or one `s` for every object found from
//! the LODs' breakpoints binned over `log s`.

use crate::error::Result;

#[cfg(doc)]
use super::SelectorSettings;
use super::best_effort::Allowance;
use super::frame::checked_scale;
use super::rule::count_coarser;
use super::store::BudgetEntry;
use super::{BudgetOutcome, BudgetRule, FrameInput, ScaleRule, Selection, Selector};

/// What a budgeted selection must fit.
#[derive(Clone, Copy)]
enum Budget {
    /// A number of triangles.
    Triangles(u64),
    /// As many triangles as [`ScaleRule::Uniform`] draws at this `s`, and
    /// at most the second (`u64::MAX`: no more; a smaller one from
    /// [`Selector::select_within_budget`] under [`ScaleRule::Budgeted`]).
    UniformAt(f32, u64),
}

impl Selector {
    /// Selection within a triangle budget, decided before anything is
    /// drawn (the predictive fixed-frame-rate scheduler's step, after
    /// Funkhouser & Séquin 1993): starting from the LODs at `frame.scale`,
    /// coarsens until the triangles fit `triangle_budget` or no step
    /// allowed by [`SelectorSettings::min_scale`] is left, by the rule of
    /// [`SelectorSettings::budget_rule`]:
    /// - [`BudgetRule::BestEffort`]: the cheapest step in predicted
    ///   visibility, weighted by the object's angular size, per triangle
    ///   saved first (`best_effort`);
    /// - [`BudgetRule::BestEffortUnweighted`]: the same without the size;
    /// - [`BudgetRule::UniformScale`]: the largest `s` in
    ///   `[min_scale, frame.scale]` whose LODs fit, one `s` for every
    ///   object. Every object's LOD is a step function of `s` with
    ///   breakpoints at `prefix_min / (H u)` (see [`crate::rows`]); the
    ///   breakpoints' triangle savings are binned over `log s` (256 bins),
    ///   and the chosen `s` is checked against the exact count.
    ///
    /// Under [`ScaleRule::Budgeted`] the LODs at `frame.scale` are those
    /// [`select`](Self::select) draws there (`s` spent as a budget, with
    /// the visibility budget), and a budget caps that selection: where it
    /// fits, it is drawn; where it does not, best effort fills the given
    /// budget from the LODs at `s = 1` (the visibility budget spends
    /// nothing more then, and a held object may be coarsened). So a budget
    /// never draws more than `select` at the same `s`, one that does not
    /// bind draws the same, and the triangles drawn do not fall as the
    /// budget rises.
    ///
    /// Objects' biases and LOD ranges apply as in [`select`](Self::select).
    /// The outcome's `scale` is the `s` chosen (uniform) or the lowest `s`
    /// at which a step taken is invisible (best effort).
    pub fn select_within_budget(
        &mut self,
        frame: &FrameInput,
        triangle_budget: u64,
    ) -> Result<BudgetOutcome> {
        if self.settings.scale_rule == ScaleRule::Budgeted {
            let scale = checked_scale(frame.scale)?;
            return self.select_spending_scale(frame, scale, triangle_budget, false);
        }
        self.select_budgeted(frame, Budget::Triangles(triangle_budget), false)
    }

    /// Under [`ScaleRule::Budgeted`]: `scale` (checked, in `(0, 1]`)
    /// spent as a budget from the LODs at `s = 1` of `frame`, capped by
    /// `cap` triangles (`u64::MAX`: none).
    pub(super) fn select_spending_scale(
        &mut self,
        frame: &FrameInput,
        scale: f32,
        cap: u64,
        diagnostics: bool,
    ) -> Result<BudgetOutcome> {
        let at_one = FrameInput {
            scale: 1.0,
            ..*frame
        };
        self.select_budgeted(&at_one, Budget::UniformAt(scale, cap), diagnostics)
    }

    /// [`select_within_budget`](Self::select_within_budget) with the
    /// budget given or taken from a uniform `s`
    /// ([`ScaleRule::Budgeted`]), recording the diagnostics when asked.
    fn select_budgeted(
        &mut self,
        frame: &FrameInput,
        budget: Budget,
        diagnostics: bool,
    ) -> Result<BudgetOutcome> {
        let s_max = checked_scale(frame.scale)?;
        self.run(frame, 1.0, diagnostics, true)?;
        self.bias_budget_entries();
        // The lowest `s` a step may need: `min_scale` (not finite: the
        // default), or a lower `s` whose triangles are the budget (every
        // step the uniform rule takes there).
        let min_scale = super::effective_min_scale(self.settings.min_scale).min(s_max);
        let from_scale = !matches!(budget, Budget::Triangles(_));
        // The budget the greedy meets first, and the one the caller gave
        // (none for a budget from `s` alone).
        let (s_min, mut triangle_budget, given) = match budget {
            Budget::Triangles(t) => (min_scale, t, t),
            Budget::UniformAt(scale, cap) => (
                min_scale.min(scale),
                self.single_triangles() + self.triangles_at(scale),
                cap,
            ),
        };
        // A budget from `s` is the scheduler's soft target: within the
        // dwell time after a switch an object does not switch back however
        // the budget moves. A given budget may force a coarsening.
        let strict_dwell = from_scale;
        let dwell = self.hysteresis().and_then(|h| h.dwell_only());
        if dwell.is_some() {
            self.advance_clock(frame.dt_s);
        }
        // The summed visibility a budget from `s` may add once its
        // triangles fit (`visibility_budget`).
        let allowance = Allowance::of(if from_scale {
            self.visibility_allowance_deg()
        } else {
            0.0
        });
        let (mut scale, mut triangles) =
            self.spend_budget([s_min, s_max], triangle_budget, allowance, strict_dwell);
        // A given budget below what `s` draws: best effort fills the given
        // one instead, held objects included.
        if triangles > given && triangle_budget != given {
            triangle_budget = given;
            (scale, triangles) = self.spend_budget([s_min, s_max], given, allowance.spent(), false);
        }
        if !self.adjusted.is_empty() {
            self.apply_adjustments(false, false);
        }
        // Coarsenings before the dwell time or the coarsening delay, and
        // switches waiting for a saccade, hold finer LODs only within the
        // given budget's room (a budget from `s` alone holds them whatever
        // it needs, unless `s` fell).
        if let Some(h) = dwell {
            let room = given.saturating_sub(triangles);
            let scale_fell = match budget {
                Budget::UniformAt(scale, _) => self.scale_fell(scale),
                Budget::Triangles(_) => false,
            };
            triangles += self.apply_hysteresis(h, Some(room), scale_fell);
        }
        triangles += self.finish_frame(frame, Some(triangle_budget.saturating_sub(triangles)));
        let met = if given == u64::MAX {
            triangle_budget
        } else {
            given
        };
        Ok(BudgetOutcome {
            scale,
            triangles,
            within_budget: triangles <= met,
        })
    }

    /// One pass of [`SelectorSettings::budget_rule`] within
    /// `triangle_budget`: the scale reached and the triangles drawn.
    fn spend_budget(
        &mut self,
        [s_min, s_max]: [f32; 2],
        triangle_budget: u64,
        allowance: Allowance,
        strict_dwell: bool,
    ) -> (f32, u64) {
        match self.settings.budget_rule {
            rule @ (BudgetRule::BestEffort | BudgetRule::BestEffortUnweighted) => self
                .best_effort_within(
                    [s_min, s_max],
                    triangle_budget,
                    allowance,
                    rule == BudgetRule::BestEffort,
                    strict_dwell,
                ),
            BudgetRule::UniformScale => {
                let (scale, triangles) = self.uniform_scale_within([s_min, s_max], triangle_budget);
                self.apply_budget_scale(scale);
                (scale, triangles)
            }
        }
    }

    /// The largest `s` in `[s_min, s_max]` whose LODs fit
    /// `triangle_budget` (or `s_min`), and the triangles at it.
    fn uniform_scale_within(&self, [s_min, s_max]: [f32; 2], triangle_budget: u64) -> (f32, u64) {
        let fixed = self.single_triangles();
        let mut scale = s_max;
        let mut triangles = fixed + self.triangles_at(scale);
        if triangles > triangle_budget {
            const BINS: usize = 256;
            let (lo, hi) = (s_min.ln(), s_max.ln());
            let width = ((hi - lo) / BINS as f32).max(f32::MIN_POSITIVE);
            let mut saved = [0i64; BINS];
            // Each breakpoint's saving goes to its bin; `keep` says which
            // transitions count (an LOD range stops some).
            let mut add =
                |entry: &BudgetEntry, p: usize, sign: i64, keep: &dyn Fn(usize) -> bool| {
                    let p = &self.profiles[p];
                    let row = &self.rows[entry.row as usize..][..p.lod_count - 1];
                    for (j, &f) in row.iter().enumerate() {
                        // LOD > j exactly when s < f / k.
                        let s_break = f / entry.k_cdiam;
                        if s_break <= s_min || s_break > s_max || !keep(j) {
                            continue;
                        }
                        let bin = (((s_break.ln() - lo) / width) as usize).min(BINS - 1);
                        saved[bin] += sign * (p.triangles[j] - p.triangles[j + 1]) as i64;
                    }
                };
            for (entry, p) in self.budget.iter().zip(self.object_profiles()) {
                if entry.row != u32::MAX {
                    add(entry, p, 1, &|_| true);
                }
            }
            // A transition outside an object's LOD range changes nothing.
            for a in &self.adjusted {
                let slot = self.handles[a.handle as usize].slot as usize;
                if let Some(entry) = self.budget.get(slot).filter(|e| e.row != u32::MAX) {
                    let p = self.object_profiles[slot] as usize;
                    let n = self.profiles[p].lod_count;
                    let (lo_lod, hi_lod) = (a.clamp(0, n), a.clamp(usize::MAX, n));
                    add(entry, p, -1, &|j| !(lo_lod <= j && j < hi_lod));
                }
            }
            let needed = (triangles - triangle_budget) as i64;
            let mut total = 0i64;
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
        (scale, triangles)
    }

    /// The LOD an object with budget entry `entry` takes at scale `s`,
    /// before its LOD range.
    pub(super) fn lod_at(&self, entry: &BudgetEntry, profile: usize, scale: f32) -> usize {
        let p = &self.profiles[profile];
        count_coarser(
            &self.rows[entry.row as usize..][..p.lod_count - 1],
            scale * entry.k_cdiam,
        )
    }

    /// [`SelectorSettings::visibility_budget`] on this display, deg (0:
    /// off).
    pub(super) fn visibility_allowance_deg(&self) -> f32 {
        self.settings.visibility_budget.deg_on(&self.display)
    }

    fn triangles_at(&self, scale: f32) -> u64 {
        let all: u64 = self
            .budget
            .iter()
            .zip(self.object_profiles())
            .filter(|(e, _)| e.row != u32::MAX)
            .map(|(e, p)| self.profiles[p].triangles[self.lod_at(e, p, scale)] as u64)
            .sum();
        // The objects with an LOD range: the clamped LOD's triangles.
        let mut adjusted = 0i64;
        for a in &self.adjusted {
            let slot = self.handles[a.handle as usize].slot as usize;
            if let Some(e) = self.budget.get(slot).filter(|e| e.row != u32::MAX) {
                let p = self.object_profiles[slot] as usize;
                let (t, lod) = (&self.profiles[p].triangles, self.lod_at(e, p, scale));
                adjusted += t[a.clamp(lod, t.len())] as i64 - t[lod] as i64;
            }
        }
        all.saturating_add_signed(adjusted)
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
}
