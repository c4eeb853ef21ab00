//! The size of a feature (a labelled set of pixels) as a spatial frequency.
//!
//! # Decisions
//! - **Feret extent** along `K` directions `θ_k = k·180°/K` (`k = 0..K`):
//!   the spread of the pixel centres projected on the direction, plus one
//!   pixel (a pixel counts as one unit of length in every direction). A
//!   feature of extent `L` pixels is half a cycle: `f = 1/(2L)` c/pixel.
//! - **Statistic** ([`FrequencyStatistic`]): `Longest` (the conservative
//!   bound: the lowest frequency a feature could be seen at), `Shortest` (the feature's width: what a grating's
//!   bars give; accurate only for features aligned within about 90°/K of a
//!   sampled direction, since long features measured slightly off their
//!   normal read much wider), or `Mean` (mean caliper diameter over the K
//!   directions, `≈ perimeter / π` for convex features), or `Thickness`
//!   (the diameter of the largest disc inscribed in the feature, below).
//! - **Thickness** (the inscribed-disc diameter): an exact Euclidean
//!   distance transform (Felzenszwalb–Huttenlocher: a 1D pass down each
//!   column, then the lower envelope of parabolas along each row) gives each
//!   pixel of the feature its distance `d` to the centre of the nearest pixel
//!   *outside* the feature (pixels of other features and the image border
//!   count as outside). It runs over the feature's bounding box plus a one
//!   pixel margin, so a frame costs O(sum of the features' box areas),
//!   O(pixels) unless boxes overlap heavily. A pixel centre at distance `d`
//!   from the nearest outside centre is `d - ½` from the feature's edge, so
//!   `2·max d - 1` is the largest inscribed disc centred on a pixel centre:
//!   exact for odd axis-aligned widths, one pixel short for even ones (the
//!   best centre lies between pixels). Half a pixel of sub-pixel refinement
//!   recovers it: along x and along y, the distance is a tent `R - |t - c|`
//!   around the medial axis `c`, so a pixel and its larger neighbour on that
//!   axis give `2R - 1 = d(p) + d(neighbour)`; the thin axis is the one
//!   with the smaller sum, and the feature's thickness is the largest such
//!   value over its pixels (a lone pixel: 1; a bar `w` pixels wide: `w`;
//!   a disc of diameter `D`: `D`; a ring of width `w`: `w`). The rest is
//!   rasterisation: edges that are not axis-aligned put outside centres up
//!   to `√2/2` px beyond the edge and the tent's slope along x or y is
//!   `|cos|` of the angle to the normal, so thin slanted features read up to
//!   about one pixel off (under 5% from a width of 20 px; see
//!   `tests/synthetic.rs`).
//! - **Which statistic**: `Mean` is the default. A feature's extent
//!   averaged over the K directions is its size as orientation-tuned
//!   channels see it, at every orientation: a disc's diameter, about
//!   `0.64 L` for a thin sliver of length `L`, between its width and its
//!   span. What decides is how it prices the kinds of object against each
//!   other, since the runtime's visibility budget of `s = 1` is spent on
//!   whichever kind looks cheapest: a coarser LOD's faceted shading
//!   changes large areas of a smooth surface by a little, which the
//!   grouping breaks into thousands of specks and thin pieces; by their
//!   width (`Thickness`) the pieces all read at the resolution limit
//!   whatever the object's size, so a smooth object's transitions looked
//!   nearly free and the budget went where FovVideoVDP saw it. Judged by
//!   FovVideoVDP, `Mean` and `Longest` keep every kind measured at the
//!   edge of visibility and `Mean` keeps equal or more quality at equal
//!   triangles (`docs/perception/visibility-budget.md`, "The size statistic"). The cost: a
//!   thin sliver that wraps round the object (a silhouette moved by a
//!   pixel or two all round) spans the object's diameter in every
//!   direction, so `Mean`, `Longest` and even `Shortest` report ~1 c/diam
//!   and such a transition is allowed later; `Thickness` measures its
//!   width instead. All four agree on compact features (a disc gives `D`
//!   by all four). A thin feature's low contrast is what makes it hard to
//!   see, and the contrast is measured separately ([`crate::features`]).
//! - Converting to cycles per object diameter multiplies by the bounding
//!   sphere's diameter in pixels (the image size for the analysis camera).

use crate::segment::Regions;

/// The default number of Feret directions.
pub const DEFAULT_FERET_DIRECTIONS: u32 = 8;

/// How a feature's K extents become one length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FrequencyStatistic {
    /// The longest extent (lowest frequency): the lowest frequency a
    /// compact feature could be seen at; a thin feature that wraps round
    /// the object reads as coarse as the object.
    Longest,
    /// The shortest extent (the feature's width, highest frequency).
    Shortest,
    /// The mean extent over the K directions (the mean caliper diameter):
    /// a feature's size averaged over orientations. The default (see the
    /// module docs).
    #[default]
    Mean,
    /// The diameter of the largest inscribed disc (the feature's width,
    /// whatever its shape or orientation; see the module docs): a thin
    /// sliver is as fine as its width, however long.
    Thickness,
}

impl FrequencyStatistic {
    /// A stable name, as the command line and scene files spell it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Longest => "longest",
            Self::Shortest => "shortest",
            Self::Mean => "mean",
            Self::Thickness => "thickness",
        }
    }
}

/// One feature: a connected set of pixels, measured along K directions.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    /// Number of pixels in the feature.
    pub pixel_count: u32,
    /// Extent in pixels along direction `k·180°/K`, for `k = 0..K`.
    pub extents_px: Vec<f32>,
    /// Diameter in pixels of the largest disc inscribed in the feature
    /// (from its Euclidean distance transform; see the module docs).
    pub thickness_px: f32,
}

impl Feature {
    /// The feature's length in pixels under `statistic`.
    pub fn length_px(&self, statistic: FrequencyStatistic) -> f32 {
        let e = &self.extents_px;
        match statistic {
            FrequencyStatistic::Longest => e.iter().copied().fold(0.0, f32::max),
            FrequencyStatistic::Shortest => e.iter().copied().fold(f32::INFINITY, f32::min),
            FrequencyStatistic::Mean => e.iter().sum::<f32>() / e.len().max(1) as f32,
            FrequencyStatistic::Thickness => self.thickness_px,
        }
    }

    /// The feature's frequency `1 / (2 L)` in cycles per pixel (at most 0.5).
    pub fn frequency_cpx(&self, statistic: FrequencyStatistic) -> f32 {
        1.0 / (2.0 * self.length_px(statistic).max(1.0))
    }
}

/// Unit direction vectors `(cos θ_k, sin θ_k)`, `θ_k = k·180°/K`, in image
/// coordinates (x right, y down).
pub fn feret_directions(k: u32) -> Vec<[f32; 2]> {
    (0..k)
        .map(|i| {
            let t = std::f64::consts::PI * f64::from(i) / f64::from(k);
            [t.cos() as f32, t.sin() as f32]
        })
        .collect()
}

/// Measures every region of `regions` (pixels labelled [`Regions::NONE`]
/// are skipped) along `directions` Feret directions (≥ 1), and its
/// thickness. Features are in label order.
pub fn measure_regions(regions: &Regions, directions: u32) -> Vec<Feature> {
    let dirs = feret_directions(directions.max(1));
    let k = dirs.len();
    let n = regions.count as usize;
    let mut lo = vec![f32::INFINITY; n * k];
    let mut hi = vec![f32::NEG_INFINITY; n * k];
    let mut counts = vec![0u32; n];
    // Bounding boxes: [min x, min y, max x, max y].
    let mut boxes = vec![[usize::MAX, usize::MAX, 0, 0]; n];
    let w = regions.width as usize;
    for (i, &l) in regions.labels.iter().enumerate() {
        if l == Regions::NONE {
            continue;
        }
        let (xi, yi) = (i % w, i / w);
        let (x, y) = (xi as f32, yi as f32);
        let l = l as usize;
        counts[l] += 1;
        let b = &mut boxes[l];
        *b = [b[0].min(xi), b[1].min(yi), b[2].max(xi), b[3].max(yi)];
        let (lo, hi) = (&mut lo[l * k..(l + 1) * k], &mut hi[l * k..(l + 1) * k]);
        for (j, d) in dirs.iter().enumerate() {
            let p = x * d[0] + y * d[1];
            lo[j] = lo[j].min(p);
            hi[j] = hi[j].max(p);
        }
    }
    let mut scratch = DistanceScratch::default();
    (0..n)
        .map(|l| Feature {
            pixel_count: counts[l],
            extents_px: (0..k)
                .map(|j| hi[l * k + j] - lo[l * k + j] + 1.0)
                .collect(),
            thickness_px: if counts[l] == 0 {
                0.0
            } else {
                region_thickness(regions, l as u32, boxes[l], &mut scratch)
            },
        })
        .collect()
}

/// Reusable buffers of [`region_thickness`].
#[derive(Default)]
struct DistanceScratch {
    /// Squared distances over the padded box, row-major.
    grid: Vec<f64>,
    row: Vec<f64>,
    v: Vec<usize>,
    z: Vec<f64>,
}

/// Thickness in pixels of region `label` with bounding box `bbox`
/// (`[min x, min y, max x, max y]`, inclusive): see the module docs.
fn region_thickness(
    regions: &Regions,
    label: u32,
    bbox: [usize; 4],
    s: &mut DistanceScratch,
) -> f32 {
    let w = regions.width as usize;
    // The box plus a margin of one outside pixel on every side.
    let (bw, bh) = (bbox[2] - bbox[0] + 3, bbox[3] - bbox[1] + 3);
    let inside = |px: usize, py: usize| {
        (1..bw - 1).contains(&px)
            && (1..bh - 1).contains(&py)
            && regions.labels[(bbox[1] + py - 1) * w + bbox[0] + px - 1] == label
    };
    s.grid.clear();
    s.grid.resize(bw * bh, 0.0);
    // Columns: distance to the nearest outside pixel in the same column
    // (the margin guarantees one above and below).
    for px in 1..bw - 1 {
        let mut d = 0.0f64;
        for py in 0..bh {
            d = if inside(px, py) { d + 1.0 } else { 0.0 };
            s.grid[py * bw + px] = d;
        }
        let mut d = 0.0f64;
        for py in (0..bh).rev() {
            let g = &mut s.grid[py * bw + px];
            d = if *g > 0.0 { d + 1.0 } else { 0.0 };
            *g = g.min(d) * g.min(d);
        }
    }
    // Rows: exact squared Euclidean distance (all inputs are finite).
    s.row.resize(bw, 0.0);
    s.v.resize(bw, 0);
    s.z.resize(bw + 1, 0.0);
    for py in 1..bh - 1 {
        let line = &mut s.grid[py * bw..(py + 1) * bw];
        s.row.copy_from_slice(line);
        lower_envelope(&s.row, line, &mut s.v, &mut s.z);
    }
    // Sub-pixel estimate per pixel: the thinner of the x and y tents.
    let d = |px: usize, py: usize| s.grid[py * bw + px].sqrt();
    let mut best = 0.0f64;
    for py in 1..bh - 1 {
        for px in 1..bw - 1 {
            if !inside(px, py) {
                continue;
            }
            let c = d(px, py);
            let along_x = c + d(px - 1, py).max(d(px + 1, py));
            let along_y = c + d(px, py - 1).max(d(px, py + 1));
            best = best.max(along_x.min(along_y));
        }
    }
    best as f32
}

/// The 1D squared distance transform of sampled function `f` (finite
/// values) into `out`: `out[q] = min_p (q - p)² + f[p]`, by the lower
/// envelope of parabolas (Felzenszwalb & Huttenlocher 2012). `v` holds at
/// least `f.len()` and `z` at least `f.len() + 1` entries.
fn lower_envelope(f: &[f64], out: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let sq = |q: usize| (q * q) as f64;
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let cross = |q: usize, p: usize| ((f[q] + sq(q)) - (f[p] + sq(p))) / (2.0 * (q - p) as f64);
    for q in 1..n {
        // z[0] = -inf and s is finite, so k never goes below 0.
        let mut s = cross(q, v[k]);
        while s <= z[k] {
            k -= 1;
            s = cross(q, v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let dq = q.abs_diff(p) as f64;
        *o = dq * dq + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::label_mask;

    fn feature_of(w: u32, h: u32, on: impl Fn(u32, u32) -> bool, k: u32) -> Vec<Feature> {
        let mask: Vec<bool> = (0..w * h).map(|i| on(i % w, i / w)).collect();
        measure_regions(&label_mask(w, h, &mask, true), k)
    }

    #[test]
    fn a_single_pixel_is_half_a_cycle_per_pixel() {
        let f = feature_of(3, 3, |x, y| x == 1 && y == 1, 8);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].frequency_cpx(FrequencyStatistic::Longest), 0.5);
    }

    #[test]
    fn an_axis_aligned_rectangle_has_exact_side_extents() {
        let f = feature_of(
            40,
            40,
            |x, y| (5..25).contains(&x) && (10..14).contains(&y),
            4,
        );
        assert_eq!(f[0].extents_px[0], 20.0); // along x
        assert_eq!(f[0].extents_px[2], 4.0); // along y
        assert_eq!(f[0].length_px(FrequencyStatistic::Shortest), 4.0);
        assert_eq!(f[0].pixel_count, 80);
        assert_eq!(f[0].length_px(FrequencyStatistic::Thickness), 4.0);
    }

    #[test]
    fn thickness_of_small_axis_aligned_shapes_is_exact() {
        // Lone pixel, dominoes, bars of odd and even width, touching the
        // image border (which counts as outside).
        assert_eq!(
            feature_of(3, 3, |x, y| x == 1 && y == 1, 4)[0].thickness_px,
            1.0
        );
        assert_eq!(feature_of(1, 1, |_, _| true, 4)[0].thickness_px, 1.0);
        assert_eq!(
            feature_of(5, 5, |x, y| y == 2 && x < 2, 4)[0].thickness_px,
            1.0
        );
        for w in 1..=9u32 {
            let f = feature_of(60, 30, |x, y| (3..3 + w).contains(&y) && x < 50, 4);
            assert_eq!(f[0].thickness_px, w as f32, "horizontal bar {w}");
            let f = feature_of(30, 60, |x, y| x < w && (5..55).contains(&y), 4);
            assert_eq!(f[0].thickness_px, w as f32, "vertical bar {w} at border");
        }
    }

    #[test]
    fn the_lower_envelope_is_the_brute_force_minimum() {
        let f = [0.0, 9.0, 4.0, 100.0, 1.0, 1.0, 25.0, 0.0, 49.0, 16.0];
        let (mut out, mut v, mut z) = ([0.0; 10], [0; 10], [0.0; 11]);
        lower_envelope(&f, &mut out, &mut v, &mut z);
        for (q, o) in out.iter().enumerate() {
            let want = (0..10)
                .map(|p| (q as f64 - p as f64).powi(2) + f[p])
                .fold(f64::INFINITY, f64::min);
            assert_eq!(*o, want, "{q}");
        }
    }
}
