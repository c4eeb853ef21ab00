//! The selection rule over compiled rows: an object's rung of the size
//! ladder and the size it is judged at, and the count of prefix minima
//! above its threshold (its LOD), one object at a time or in bulk.

use glam::Vec4;

use crate::fastmath;

/// The selection rule for one object: the coarsest LOD `j`
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
pub(super) fn count_coarser(prefix_min_cdiam: &[f32], k_cdiam: f32) -> usize {
    prefix_min_cdiam
        .iter()
        .map(|&f| (f > k_cdiam) as usize)
        .sum()
}

/// [`count_coarser`] over a row padded with `-inf` to groups of 4 (at
/// least one): one 4-wide comparison and count per group.
#[inline(always)]
pub(super) fn count_coarser_padded(row: &[f32], k_cdiam: f32) -> usize {
    let group = |g: &[f32]| count_group(g.try_into().unwrap_or([f32::NEG_INFINITY; 4]), k_cdiam);
    let (first, rest) = row.split_at(4.min(row.len()));
    (group(first) + rest.chunks_exact(4).map(group).sum::<u32>()) as usize
}

/// The entries of `group` above `k_cdiam`, in one 4-wide comparison:
/// glam's `Vec4` is a vector register, so loops over objects that call
/// this are not widened into gathers across objects (which measured
/// slower).
#[inline(always)]
fn count_group(group: [f32; 4], k_cdiam: f32) -> u32 {
    Vec4::from_array(group)
        .cmpgt(Vec4::splat(k_cdiam))
        .bitmask()
        .count_ones()
}

/// An object's rung of a size ladder, the number of `boundaries_deg`
/// (ascending) below its size on screen `size_deg`, and the size it is
/// judged at: the upper end of its rung's range (the boundary above it), or
/// its own size on the bottom and top rungs (see [`crate::rows`]).
#[inline(always)]
pub(super) fn rung_and_judged_size(boundaries_deg: &[f32], size_deg: f32) -> (u32, f32) {
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
pub(super) fn rung_of(
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
pub(super) fn count_rows<const STRIDE: usize>(
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
