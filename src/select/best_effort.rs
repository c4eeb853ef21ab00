//! Best effort under a triangle budget: when the LODs chosen at the
//! frame's `s` do not fit, coarsen first where the predicted visibility per
//! triangle saved is lowest (Luebke & Hallen 2001 §4 order simplifications
//! by perceptibility for best-effort rendering; Funkhouser & Séquin 1993
//! spend a budget by benefit over cost).
//!
//! The visibility of an object's next step, from LOD `j` to the next LOD
//! that draws fewer triangles, starts from how far the object's acuity
//! lies above the step's critical acuity: `v = k / q` with `k = H(v, E) u`
//! the object's threshold at `s = 1` and `q` the prefix minimum of the
//! transitions it crosses ([`crate::rows`]): at `s = 1 / v` the step
//! becomes invisible, so `v = 1` is just imperceptible and a larger `v` is
//! further above threshold. [`BudgetRule::BestEffort`](super::BudgetRule::BestEffort)
//! weighs `ln v` by the object's angular size `theta` (deg), because an
//! image is judged by its differences over all of it and a LOD step's
//! differences lie along the object's outline and edges, whose length on
//! screen grows with `theta`; its cost is `theta ln(v) / saved` (0 at the
//! edge of visibility). [`BudgetRule::BestEffortUnweighted`](super::BudgetRule::BestEffortUnweighted)
//! leaves the size out: `ln(v) / saved`. The greedy takes the cheapest
//! step of all objects until the triangles fit. A uniform `s` takes the
//! steps in order of `v` alone, so an object that would save 3000
//! triangles at a barely visible cost waits behind one that saves 40 at
//! the same cost; the greedy does not.
//!
//! A step may only be taken after the object's steps before it, so each
//! step counts at the highest cost of its chain so far (a running maximum
//! along the object's LODs); taking steps in order of that cost is what a
//! heap that pops the cheapest available step does, and it needs no heap:
//! the savings are binned over the logarithm of the cost (1024 bins, an
//! 18th of an octave each; twice that with the held steps' tier below),
//! the bin where they reach what the budget needs
//! is found, every step below it is taken and, within it, steps in object
//! order until the triangles fit. Three passes over the objects; the
//! first keeps each object's steps for the others, in buffers whose
//! capacity is kept between frames (no allocation once they have grown).
//!
//! A visibility budget
//! ([`SelectorSettings::visibility_budget`](super::SelectorSettings::visibility_budget),
//! under a budget from `s`) lets the greedy go on once the triangles fit:
//! each step's added visibility (`theta ln(v / v0)^beta` at its LOD less
//! the object's at the LOD before, deg) is binned beside its saving, and
//! the steps left are taken in the same order while the visibility they
//! add stays within the budget. Visible differences add up over an image,
//! so this bounds the image's difference rather than each object's alone.
//! They add up as a Minkowski sum (Quick 1974; Watson 1979): an image's
//! difference is `(sum d^beta)^(1/beta)` over its pixels' differences `d`,
//! with `beta` = [`VISIBILITY_POOLING_EXPONENT`](super::VISIBILITY_POOLING_EXPONENT),
//! FovVideoVDP's spatial pooling exponent (Mantiuk et al. 2021). An
//! object's step changes the pixels along its outline and edges, whose
//! number grows with `theta`, each by a difference that grows with the
//! margin `ln(v / v0)`, so its share of the sum is `theta ln(v / v0)^beta`:
//! many objects each a little beyond the edge count for less than a few
//! far beyond it, which a plain sum (`beta = 1`) would count alike.
//! Because differences add up, a step just inside the edge of visibility
//! is not free either: with a visibility budget, `ln v` is counted from
//! `v0 =` [`VISIBILITY_COUNTED_FROM`](super::VISIBILITY_COUNTED_FROM)
//! below the edge, and the greedy starts from the LODs invisible from
//! there on, so that the triangles from `s` (at `s = 1`, the rule's
//! without a budget) are saved where the steps inside the edge save the
//! most triangles for their visibility. The budget
//! comes on top of what the triangles from `s` needed, so a lower `s`
//! draws fewer triangles than a higher one all the way down from `s = 1`
//! (were it counted from full detail, every `s` whose triangles `s = 1`'s
//! selection already fits would draw that selection again, and a scheduler
//! turning `s` would move nothing). When the triangles needed steps too,
//! the last pass that takes them bins the visibility of the steps left,
//! and two more passes take the allowance's.
//!
//! Hysteresis: a step the object had already taken in the previous frame
//! costs [`SelectorSettings::budget_hysteresis`](super::SelectorSettings::budget_hysteresis)
//! less, so that near ties keep last frame's order; with
//! [`SelectorSettings::switch_min_dwell_s`](super::SelectorSettings::switch_min_dwell_s),
//! a step beyond last frame's LOD of an object that switched to a finer LOD
//! less than that ago comes after every other step (its bins lie above
//! all others', ordered among themselves by cost), so it is taken only
//! where no other step meets the budget, and not at all where even the
//! held steps cannot (they would buy no frame on time, only flicker), and
//! an object that switched to a
//! coarser one does not go back to a finer LOD until the dwell time has
//! passed (the greedy starts from last frame's LOD where that is coarser
//! than the one at the frame's `s`): under a budget that moves, the
//! coarsening it forced and the refinement that would undo it a few frames
//! later are what reads as flicker. A switch the same way as the object's
//! last one is no reversal and waits for nothing. With the budget a scale
//! factor sets ([`ScaleRule::Budgeted`](super::ScaleRule::Budgeted)), a
//! soft target, an object that would go back on its last switch takes no
//! step at all (`strict_dwell`).
//!
//! `s` stays the scheduler's knob: the greedy starts from the LODs at the
//! frame's `s`, takes no step that needs `s` below
//! [`SelectorSettings::min_scale`](super::SelectorSettings::min_scale),
//! and reports as its scale the lowest `s = 1 / v` it reached.

use super::store::BudgetEntry;
use super::{Selection, Selector};

/// One object's next coarsening step.
#[derive(Clone, Copy, Debug)]
struct Step {
    /// `theta ln(v) / saved` (or `ln(v) / saved`): what the step costs
    /// per triangle it saves.
    cost: f32,
    /// The scale `s = 1 / v` at which the step becomes invisible.
    scale: f32,
    /// `theta ln(v)` (under a visibility budget `theta ln(v / v0)^beta`),
    /// deg: the object's visibility at the step's LOD.
    visibility_deg: f32,
    saved: u32,
    to_lod: u8,
}

/// A step of an object's chain as pass 1 found it, for passes 2 and 3.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChainStep {
    /// The chain's running maximum of bins up to this step (the bin of its
    /// highest cost so far, in the held tier once a step was held).
    bin: u16,
    to_lod: u8,
    saved: u32,
    /// As [`Step::scale`] and [`Step::visibility_deg`].
    scale: f32,
    visibility_deg: f32,
}

/// The steps pass 1 kept, as [`Selector::take_steps`] reads them.
#[derive(Clone, Copy, Debug)]
struct Chains<'a> {
    /// Every object's steps, in slot order.
    steps: &'a [ChainStep],
    /// Per slot, where its steps start in `steps` (one more entry: the end).
    start: &'a [u32],
    /// Per slot, its visibility at the LOD its steps start from, deg.
    start_deg: &'a [f32],
}

impl<'a> Chains<'a> {
    /// The steps of the object in `slot`.
    fn of(&self, slot: usize) -> &'a [ChainStep] {
        &self.steps[self.start[slot] as usize..self.start[slot + 1] as usize]
    }
}

/// What [`Selector::take_steps`] takes: every kept step in a bin below
/// `threshold`, and in it those that bring the triangles to
/// `triangle_budget` or whose added visibility fits `allowance_deg`.
#[derive(Clone, Copy, Debug)]
struct Take {
    threshold: usize,
    triangle_budget: u64,
    allowance_deg: f32,
}

/// How [`Selector::next_step`] prices a step.
#[derive(Clone, Copy, Debug)]
struct Pricing {
    /// Whether `ln v` is weighed by the object's angular size.
    weighted: bool,
    /// How the step's visibility is counted.
    counting: Counting,
}

/// Bins of one tier of the cost histogram: bin 0 holds costs of 0 (steps
/// at the edge of visibility), the rest [`BINS_PER_OCTAVE`] a binary octave
/// from `2^LOWEST_OCTAVE`.
const COST_BINS: usize = 1024;
const BINS_PER_OCTAVE: f32 = 18.0;
const LOWEST_OCTAVE: f32 = -40.0;
/// Bins of the histogram: two tiers of [`COST_BINS`], the second for the
/// steps that would switch an object back before its dwell time.
const BINS: usize = 2 * COST_BINS;

impl Step {
    /// The step's bin: its cost, times `keep_factor` when it leads to a LOD
    /// no finer than `kept_lod` (taken last frame); in the second tier when
    /// it goes beyond `kept_lod` and `held_beyond` (the object switched to
    /// a finer LOD within the dwell time).
    fn bin_given(&self, kept_lod: usize, keep_factor: f32, held_beyond: bool) -> usize {
        if usize::from(self.to_lod) <= kept_lod {
            bin_of(self.cost * keep_factor)
        } else if held_beyond {
            COST_BINS + bin_of(self.cost)
        } else {
            bin_of(self.cost)
        }
    }
}

/// How a step's visibility is counted: from where, and how the
/// objects' differences add up over the image.
#[derive(Clone, Copy, Debug)]
pub(super) struct Counting {
    /// `v0`: where the margin starts (1: the edge of visibility; below it,
    /// from within the invisible zone).
    pub from: f32,
    /// `beta`: the exponent of the margin, so that the objects' visibility
    /// `theta m^beta` sums over the image as a Minkowski sum of their
    /// differences (1: a plain sum).
    pub exponent: f32,
}

impl Counting {
    /// Under a visibility budget of `allowance_deg` (`> 0`): from
    /// [`VISIBILITY_COUNTED_FROM`](super::VISIBILITY_COUNTED_FROM), within
    /// the invisible zone, pooled with
    /// [`VISIBILITY_POOLING_EXPONENT`](super::VISIBILITY_POOLING_EXPONENT).
    /// Without one: from the edge of visibility, summed plainly.
    fn under(allowance_deg: f32) -> Self {
        if allowance_deg > 0.0 {
            Self {
                from: super::VISIBILITY_COUNTED_FROM,
                exponent: super::VISIBILITY_POOLING_EXPONENT,
            }
        } else {
            Self {
                from: 1.0,
                exponent: 1.0,
            }
        }
    }

    /// `m^beta` with `m = ln(max(1, v / v0))`, `v = k / q`: how far an
    /// object of threshold `k` at `s = 1` lies above the critical acuity
    /// `q` of the transitions it crossed (c/diam both), counted from `v0`;
    /// 0 at or below `v0`.
    fn margin(self, k_cdiam: f32, q_cdiam: f32) -> f32 {
        let m = (k_cdiam / (q_cdiam * self.from)).max(1.0).ln();
        if self.exponent == 1.0 || m == 0.0 {
            m
        } else {
            m.powf(self.exponent)
        }
    }
}

/// What best effort may add in visibility once the triangles fit, and
/// where it counts each step's visibility from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Allowance {
    /// The summed visibility the steps may add, deg (none when not `> 0`).
    pub deg: f32,
    /// How each step's visibility is counted.
    pub counting: Counting,
}

impl Allowance {
    /// A visibility budget of `deg`, counted from
    /// [`VISIBILITY_COUNTED_FROM`](super::VISIBILITY_COUNTED_FROM) when
    /// it is on, from the edge of visibility when not.
    pub(super) fn of(deg: f32) -> Self {
        Self {
            deg,
            counting: Counting::under(deg),
        }
    }

    /// Nothing to add, the steps priced as under `self`.
    pub(super) fn spent(self) -> Self {
        Self { deg: 0.0, ..self }
    }
}

/// The bin of `cost` within one tier, in `[0, COST_BINS)`.
fn bin_of(cost: f32) -> usize {
    if cost.is_nan() {
        return COST_BINS - 1;
    }
    if cost <= 0.0 {
        return 0;
    }
    let b = (cost.log2() - LOWEST_OCTAVE) * BINS_PER_OCTAVE + 1.0;
    (b.max(1.0) as usize).min(COST_BINS - 1)
}

impl Selector {
    /// Chooses the LODs of every visible object with more than one LOD
    /// (writing their selections, before LOD ranges are applied) so that
    /// the triangles fit `triangle_budget` where the steps allowed reach
    /// it, cheapest step first (see the module docs), taking no step that
    /// needs `s` below `s_min` (in `(0, s_max]`); then, while the
    /// visibility they add (`theta ln(v / v0)^beta`, summed) stays within
    /// `allowance_deg`, the next cheapest steps too (an allowance not
    /// `> 0`, NaN included, is none). Returns the scale
    /// reached and the triangles drawn (LOD ranges counted).
    pub(super) fn best_effort_within(
        &mut self,
        [s_min, s_max]: [f32; 2],
        triangle_budget: u64,
        allowance: Allowance,
        weighted: bool,
        strict_dwell: bool,
    ) -> (f32, u64) {
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
        let adjust_of = |slot: usize| adjusted_of.get(slot).copied().unwrap_or(u32::MAX);
        let h = self.settings.budget_hysteresis;
        let keep_factor = 1.0 - if h.is_nan() { 0.0 } else { h.clamp(0.0, 0.9) };
        let dwell_s = self.dwell_s();
        // With a visibility budget, the greedy starts from the LODs
        // invisible from `v0` on.
        let Allowance {
            deg: allowance_deg,
            counting,
        } = allowance;
        // Pass 1: the LODs at `s_max / v0`, and every later
        // step's saving and added visibility binned by its cost; the steps
        // kept per object for passes 2 and 3.
        let mut saved_by_bin = [0u64; BINS];
        let mut visibility_by_bin = [0f32; BINS];
        let mut triangles = self.single_triangles();
        let mut chains = std::mem::take(&mut self.chains);
        let mut chain_start = std::mem::take(&mut self.chain_start);
        let mut chain_start_deg = std::mem::take(&mut self.chain_start_deg);
        chains.clear();
        chain_start.clear();
        chain_start_deg.clear();
        for slot in 0..multi {
            chain_start.push(chains.len() as u32);
            chain_start_deg.push(0.0);
            let entry = self.budget[slot];
            if entry.row == u32::MAX {
                continue;
            }
            let p = self.object_profiles[slot] as usize;
            let mut lod = self.lod_at(&entry, p, s_max / counting.from);
            // Within the dwell time after a coarsening, no switch back to
            // a finer LOD: a budget's coarsening undone a few frames later
            // is flicker, and keeping the coarser LOD only saves.
            if self.reverses_within(slot, dwell_s, true) {
                let last = self.profiles[p].lod_count - 1;
                lod = lod.max(self.kept_lod(slot).min(last));
            }
            // Whether the object switched to a finer LOD less than the
            // dwell time ago, so that a step beyond last frame's LOD would
            // go back on it. Within that time a given budget starts from
            // the LOD drawn last frame where `s_max` asks for a coarser
            // one: going back is a held step like any other.
            let held = self.reverses_within(slot, dwell_s, false);
            if held && !strict_dwell {
                let drawn = self.previous.get(slot).and_then(|s| s.lod());
                lod = drawn.map_or(lod, |drawn| lod.min(drawn));
            }
            self.selections[slot] = Selection(lod as u8);
            let adjust = adjust_of(slot);
            triangles += u64::from(self.drawn_triangles(p, adjust, lod));
            let mut bin = 0;
            let kept = self.kept_lod(slot);
            // The coarsest LOD the greedy may step to: with `strict_dwell`,
            // last frame's LOD for a held object (a coarser one would go
            // back on its switch; where the start is finer, steps up to it
            // switch nothing); otherwise any.
            let limit = if held && strict_dwell {
                kept
            } else {
                usize::MAX
            };
            let pricing = Pricing { weighted, counting };
            let mut next = self.next_step(slot, &entry, adjust, lod, s_min, pricing);
            if next.is_none() {
                continue;
            }
            let mut shown_deg = self.visibility_at(&entry, p, lod, counting);
            chain_start_deg[slot] = shown_deg;
            while let Some(step) = next.filter(|step| usize::from(step.to_lod) <= limit) {
                bin = bin.max(step.bin_given(kept, keep_factor, held));
                saved_by_bin[bin] += u64::from(step.saved);
                visibility_by_bin[bin] += (step.visibility_deg - shown_deg).max(0.0);
                shown_deg = shown_deg.max(step.visibility_deg);
                chains.push(ChainStep {
                    bin: bin as u16,
                    to_lod: step.to_lod,
                    saved: step.saved,
                    scale: step.scale,
                    visibility_deg: step.visibility_deg,
                });
                next = self.next_step(slot, &entry, adjust, step.to_lod as usize, s_min, pricing);
            }
        }
        chain_start.push(chains.len() as u32);
        let mut reached = s_max;
        let needed = triangles.saturating_sub(triangle_budget);
        // First the steps the triangles need; then, once they fit, the
        // allowance buys the next cheapest steps on top: a budget from
        // `s < 1` spends it beyond the triangles `s` sets, so a lower `s`
        // never draws `s = 1`'s selection again.
        for for_triangles in [true, false] {
            let take = if for_triangles && needed > 0 {
                let mut cumulative = 0u64;
                let threshold = saved_by_bin.iter().position(|&s| {
                    cumulative += s;
                    cumulative >= needed
                });
                // Where even the held steps cannot meet the budget, they
                // would buy no frame on time: every other step is taken,
                // and no held one.
                Take {
                    threshold: threshold.unwrap_or(COST_BINS),
                    triangle_budget: if threshold.is_some() {
                        triangle_budget
                    } else {
                        u64::MAX
                    },
                    allowance_deg: 0.0,
                }
            } else if !for_triangles && allowance_deg > 0.0 {
                let mut shown = 0.0f32;
                Take {
                    threshold: visibility_by_bin
                        .iter()
                        .position(|&v| {
                            shown += v;
                            shown > allowance_deg
                        })
                        .unwrap_or(BINS),
                    triangle_budget: u64::MAX,
                    allowance_deg,
                }
            } else {
                continue;
            };
            // The visibility of the steps left, for the allowance.
            let left = (for_triangles && allowance_deg > 0.0).then_some(&mut visibility_by_bin);
            self.take_steps(
                Chains {
                    steps: &chains,
                    start: &chain_start,
                    start_deg: &chain_start_deg,
                },
                take,
                &mut triangles,
                &mut reached,
                left,
            );
        }
        self.chains = chains;
        self.chain_start = chain_start;
        self.chain_start_deg = chain_start_deg;
        self.adjusted_of = adjusted_of;
        (reached.max(s_min), triangles)
    }

    /// Takes the kept steps `take` allows (every step in a bin below its
    /// threshold; in that bin, steps in object order while the triangles
    /// are over its budget or the step's added visibility fits what is
    /// left of its allowance), from each object's selection on; lowers
    /// `triangles` and `reached` (the lowest `s` a taken step needs).
    /// With `remaining_by_bin`, bins there by cost the added visibility
    /// (deg) of the steps left.
    /// Reads the chains pass 1 kept: a step not yet taken lies in the
    /// threshold's bin or above, so the running maximum it kept is its own
    /// cost or a later step's, as from its LOD; and an object's visibility
    /// at its selection is its chain's start's or that of the last step
    /// taken (a selection is one or the other).
    fn take_steps(
        &mut self,
        chains: Chains,
        take: Take,
        triangles: &mut u64,
        reached: &mut f32,
        mut remaining_by_bin: Option<&mut [f32; BINS]>,
    ) {
        if let Some(bins) = remaining_by_bin.as_deref_mut() {
            bins.fill(0.0);
        }
        let mut added_deg = 0.0f32;
        for below in [true, false] {
            for slot in 0..self.multi() {
                // An object with no steps (culled, or at its coarsest LOD)
                // has nothing to take.
                let chain = chains.of(slot);
                let lod = self.selections[slot].0 as usize;
                let first_left = chain.partition_point(|step| usize::from(step.to_lod) <= lod);
                if first_left == chain.len() {
                    continue;
                }
                let mut shown_deg = match first_left {
                    0 => chains.start_deg[slot],
                    i => chain[i - 1].visibility_deg,
                };
                let mut left = chain[first_left..].iter();
                let mut not_taken = None;
                for step in left.by_ref() {
                    let bin = usize::from(step.bin);
                    let adds_deg = (step.visibility_deg - shown_deg).max(0.0);
                    let taken = if below {
                        bin < take.threshold
                    } else {
                        bin == take.threshold
                            && (*triangles > take.triangle_budget
                                || (take.allowance_deg > 0.0
                                    && added_deg + adds_deg <= take.allowance_deg))
                    };
                    if !taken {
                        not_taken = Some(step);
                        break;
                    }
                    added_deg += adds_deg;
                    shown_deg = shown_deg.max(step.visibility_deg);
                    *triangles -= u64::from(step.saved);
                    *reached = reached.min(step.scale);
                    self.selections[slot] = Selection(step.to_lod);
                }
                if let (false, Some(bins)) = (below, remaining_by_bin.as_deref_mut()) {
                    for step in not_taken.into_iter().chain(left) {
                        bins[usize::from(step.bin)] += (step.visibility_deg - shown_deg).max(0.0);
                        shown_deg = shown_deg.max(step.visibility_deg);
                    }
                }
            }
        }
    }

    /// The last frame's selection in this module's measure of visibility:
    /// the sum over the visible objects with more than one LOD of
    /// `theta ln(max(1, v / v0))^beta` for the LOD each draws (`theta` its
    /// angular size, deg; `v = k / q`, `k` its threshold at `s = 1` and `q`
    /// the prefix minimum of the transitions up to that LOD; with a
    /// visibility budget `v0` is
    /// [`VISIBILITY_COUNTED_FROM`](super::VISIBILITY_COUNTED_FROM) and
    /// `beta` [`VISIBILITY_POOLING_EXPONENT`](super::VISIBILITY_POOLING_EXPONENT),
    /// else both 1), in deg. 0 when every object draws a
    /// LOD invisible from `v0` on; larger
    /// the further, and on the larger objects, the LODs drawn lie beyond.
    /// An estimate of how much of the image differs from full detail, as
    /// best effort ranks steps by it; `None` when the frame recorded no
    /// thresholds (a plain [`Selector::select`] without
    /// [`SelectorSettings::switch_hysteresis`](super::SelectorSettings::switch_hysteresis),
    /// or [`ScaleRule::Budgeted`](super::ScaleRule::Budgeted) at `s = 1`
    /// without a visibility budget).
    /// One pass over the objects.
    pub fn selection_visibility_deg(&self) -> Option<f64> {
        let scale = self.recorded_scale?;
        let counting = Counting::under(self.visibility_allowance_deg());
        let mut sum = 0.0f64;
        for (slot, entry) in self.budget.iter().enumerate().take(self.multi()) {
            let lod = match self.selections[slot].lod() {
                Some(lod) if entry.row != u32::MAX => lod,
                _ => continue,
            };
            // The entry's threshold as at `s = 1`.
            let at_one = BudgetEntry {
                k_cdiam: entry.k_cdiam / scale,
                ..*entry
            };
            let p = self.object_profiles[slot] as usize;
            sum += f64::from(self.visibility_at(&at_one, p, lod, counting));
        }
        Some(sum)
    }

    /// `theta m^beta` ([`Counting::margin`]) of an object of profile `p`
    /// at `lod` (its entry's threshold at `s = 1`), deg.
    fn visibility_at(&self, entry: &BudgetEntry, p: usize, lod: usize, counting: Counting) -> f32 {
        if lod == 0 {
            return 0.0;
        }
        let n = self.profiles[p].lod_count;
        let q = self.rows[entry.row as usize + lod.min(n - 1) - 1];
        let margin = counting.margin(entry.k_cdiam, q);
        if margin.is_finite() {
            margin * entry.angular_size_deg
        } else {
            0.0
        }
    }

    /// The LOD the object in `slot` had last frame (0 when it was culled
    /// or new): steps up to it were taken then.
    fn kept_lod(&self, slot: usize) -> usize {
        self.previous.get(slot).and_then(|s| s.lod()).unwrap_or(0)
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
    /// draws fewer triangles, if `s_min` allows it. Its visibility is
    /// `ln v`, times the object's angular size (deg) when `weighted`.
    fn next_step(
        &self,
        slot: usize,
        entry: &BudgetEntry,
        adjust: u32,
        lod: usize,
        s_min: f32,
        pricing: Pricing,
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
                let margin = pricing.counting.margin(entry.k_cdiam, q);
                let visibility_deg = margin * entry.angular_size_deg;
                let visibility = if pricing.weighted {
                    visibility_deg
                } else {
                    margin
                };
                return Some(Step {
                    cost: visibility / saved as f32,
                    scale,
                    visibility_deg,
                    saved,
                    to_lod: (j + 1) as u8,
                });
            }
        }
        None
    }
}
