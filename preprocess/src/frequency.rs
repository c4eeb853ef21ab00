//! Unique features of an LOD transition and their spatial frequencies.
//!
//! # Decisions
//! - **Changed pixels**: those whose ΔE*uv between the two renderings is
//!   *above* the threshold (the same just-noticeable difference as region
//!   growing, [`crate::segment::DEFAULT_THRESHOLD_DELTA_E`] by default).
//! - **One feature = one 8-connected component of the changed mask.** A
//!   changed feature is a set of touching changed pixels; 8-connectivity
//!   keeps thin diagonal features (a silhouette edge that moved by a pixel)
//!   in one piece. The changed pixels are thereby "grown" into regions.
//! - **Feret extent** along `K` directions `θ_k = k·180°/K` (`k = 0..K`):
//!   the spread of the pixel centres projected on the direction, plus one
//!   pixel (a pixel counts as one unit of length in every direction). A
//!   feature of extent `L` pixels is half a cycle: `f = 1/(2L)` c/pixel.
//! - **Statistic** ([`FrequencyStatistic`]): `Longest` (default, the
//!   conservative choice of REFERENCE §5: the lowest frequency a feature
//!   could be seen at), `Shortest` (the feature's width: what a grating's
//!   bars give; accurate only for features aligned within about 90°/K of a
//!   sampled direction, since long features measured slightly off their
//!   normal read much wider), or `Mean` (mean caliper diameter over the K
//!   directions, `≈ perimeter / π` for convex features).
//! - Converting to cycles per object diameter multiplies by the bounding
//!   sphere's diameter in pixels (the image size for the analysis camera).

use crate::Error;
use crate::segment::{LuvImage, Regions, label_mask};

/// The default number of Feret directions.
pub const DEFAULT_FERET_DIRECTIONS: u32 = 8;

/// How a feature's K extents become one length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FrequencyStatistic {
    /// The longest extent (lowest frequency). Conservative; the default.
    #[default]
    Longest,
    /// The shortest extent (the feature's width, highest frequency).
    Shortest,
    /// The mean extent over the K directions.
    Mean,
}

/// One feature: a connected set of pixels, measured along K directions.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    /// Number of pixels in the feature.
    pub pixel_count: u32,
    /// Extent in pixels along direction `k·180°/K`, for `k = 0..K`.
    pub extents_px: Vec<f32>,
}

impl Feature {
    /// The feature's length in pixels under `statistic`.
    pub fn length_px(&self, statistic: FrequencyStatistic) -> f32 {
        let e = &self.extents_px;
        match statistic {
            FrequencyStatistic::Longest => e.iter().copied().fold(0.0, f32::max),
            FrequencyStatistic::Shortest => e.iter().copied().fold(f32::INFINITY, f32::min),
            FrequencyStatistic::Mean => e.iter().sum::<f32>() / e.len().max(1) as f32,
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
/// are skipped) along `directions` Feret directions (≥ 1). Features are in
/// label order.
pub fn measure_regions(regions: &Regions, directions: u32) -> Vec<Feature> {
    let dirs = feret_directions(directions.max(1));
    let k = dirs.len();
    let n = regions.count as usize;
    let mut lo = vec![f32::INFINITY; n * k];
    let mut hi = vec![f32::NEG_INFINITY; n * k];
    let mut counts = vec![0u32; n];
    let w = regions.width as usize;
    for (i, &l) in regions.labels.iter().enumerate() {
        if l == Regions::NONE {
            continue;
        }
        let (x, y) = ((i % w) as f32, (i / w) as f32);
        let l = l as usize;
        counts[l] += 1;
        let (lo, hi) = (&mut lo[l * k..(l + 1) * k], &mut hi[l * k..(l + 1) * k]);
        for (j, d) in dirs.iter().enumerate() {
            let p = x * d[0] + y * d[1];
            lo[j] = lo[j].min(p);
            hi[j] = hi[j].max(p);
        }
    }
    (0..n)
        .map(|l| Feature {
            pixel_count: counts[l],
            extents_px: (0..k)
                .map(|j| hi[l * k + j] - lo[l * k + j] + 1.0)
                .collect(),
        })
        .collect()
}

/// The mask of pixels whose ΔE*uv between `a` and `b` exceeds
/// `threshold_delta_e`. Errors when the images differ in size.
pub fn changed_mask(
    a: &LuvImage,
    b: &LuvImage,
    threshold_delta_e: f32,
) -> Result<Vec<bool>, Error> {
    if (a.width, a.height) != (b.width, b.height) || a.luv.len() != b.luv.len() {
        return Err(Error::Settings {
            field: "images",
            message: format!(
                "sizes differ: {}x{} and {}x{}",
                a.width, a.height, b.width, b.height
            ),
        });
    }
    let t2 = threshold_delta_e * threshold_delta_e;
    Ok(a.luv
        .iter()
        .zip(&b.luv)
        .map(|(p, q)| {
            let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
            d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > t2
        })
        .collect())
}

/// The unique features of a pair of renderings: the 8-connected components
/// of their changed mask, measured along `directions` Feret directions.
/// Identical images give no features. Also returns the component labels
/// (for inspection images).
pub fn unique_features(
    a: &LuvImage,
    b: &LuvImage,
    threshold_delta_e: f32,
    directions: u32,
) -> Result<(Vec<Feature>, Regions), Error> {
    let mask = changed_mask(a, b, threshold_delta_e)?;
    let regions = label_mask(a.width, a.height, &mask, true);
    Ok((measure_regions(&regions, directions), regions))
}

/// How changed pixels are grouped into features.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Grouping {
    /// 8-connected components of the changed mask (what the pipeline uses).
    #[default]
    ChangedMask,
    /// As `ChangedMask`, but two changed neighbours join only when they lie
    /// in the same CIELUV region of *both* renderings (region growing at the
    /// same threshold): a changed area that straddles a perceptible edge of
    /// either image is one feature per side.
    SplitByImageRegions,
    /// As `ChangedMask`, but two changed neighbours join only when their
    /// changes (signed CIELUV differences) differ by less than the threshold.
    SplitByChange,
}

/// Like [`unique_features`], with a choice of [`Grouping`].
pub fn unique_features_grouped(
    a: &LuvImage,
    b: &LuvImage,
    threshold_delta_e: f32,
    directions: u32,
    grouping: Grouping,
) -> Result<(Vec<Feature>, Regions), Error> {
    let mask = changed_mask(a, b, threshold_delta_e)?;
    let (w, h) = (a.width, a.height);
    let regions = match grouping {
        Grouping::ChangedMask => label_mask(w, h, &mask, true),
        Grouping::SplitByImageRegions => {
            let ra = crate::segment::grow_regions(a, threshold_delta_e);
            let rb = crate::segment::grow_regions(b, threshold_delta_e);
            crate::segment::label_components(
                w,
                h,
                true,
                |i| mask[i],
                |i, j| ra.labels[i] == ra.labels[j] && rb.labels[i] == rb.labels[j],
            )
        }
        Grouping::SplitByChange => {
            let t2 = threshold_delta_e * threshold_delta_e;
            let d = |i: usize| {
                let (p, q) = (a.luv[i], b.luv[i]);
                [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
            };
            crate::segment::label_components(
                w,
                h,
                true,
                |i| mask[i],
                |i, j| {
                    let (x, y) = (d(i), d(j));
                    let e = [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
                    e[0] * e[0] + e[1] * e[1] + e[2] * e[2] < t2
                },
            )
        }
    };
    Ok((measure_regions(&regions, directions), regions))
}

/// Every feature's frequency in cycles per pixel under `statistic`,
/// ascending.
pub fn frequencies_cpx(features: &[Feature], statistic: FrequencyStatistic) -> Vec<f32> {
    let mut f: Vec<f32> = features
        .iter()
        .map(|x| x.frequency_cpx(statistic))
        .collect();
    f.sort_by(f32::total_cmp);
    f
}

#[cfg(test)]
mod tests {
    use super::*;

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
    }
}
