//! The unique features of an LOD transition, with their size and their
//! contrast (Reddy 1998 §3.3).
//!
//! # Decisions
//! - **Unique features** are where the two renderings differ by more than
//!   [`FeatureSettings::min_change_delta_e`] (default
//!   [`DEFAULT_MIN_CHANGE_DELTA_E`], 1 ΔE*uv), grouped into coherent
//!   changes. A change of one sRGB code step in one channel is at most
//!   0.94 ΔE*uv: such pixels flip with the rasteriser's last bit (a tenth
//!   of a pixel's shift in the view changes which), and counted as changed
//!   they bridge real features into large faint ones, so the profile would
//!   depend on where the outline fell. The threshold stays below half the
//!   just-noticeable difference (2.3). Two 8-connected
//!   changed pixels (a silhouette that moved diagonally by one pixel stays
//!   one feature) belong to one feature when the change brightens both or
//!   darkens both ([`Grouping::ChangeSign`], the default). A silhouette or
//!   a hole whose edge moved is one feature, even where the surface's
//!   colour varies quickly along it; a network of small shading changes
//!   that alternate between lighter and darker is many small features,
//!   not one as large as the object; and a feature's mean contrast never
//!   averages a brightening against a darkening.
//! - **Reddy's regions** ([`Grouping::Regions`]): each LOD's rendering is
//!   segmented by CIELUV region growing ([`crate::segment::grow_regions`]:
//!   neighbours closer than the just-noticeable ΔE*uv form one region, an
//!   area seen as one patch), and changed pixels join only when they also
//!   lie in one region of either rendering: a feature is the part of a
//!   region of one LOD with no counterpart in the other. Measured against
//!   FovVideoVDP on `scenes/reddy1998.toml` it ranks LOD choices worse: on
//!   an object 16 to 64 pixels across with vertex colours, neighbouring
//!   pixels differ by more than the just-noticeable difference almost
//!   everywhere, so regions are single pixels and every change breaks
//!   into one-pixel features that read as finer than they are.
//! - **Size**: the feature's length under a [`FrequencyStatistic`]
//!   ([`crate::frequency`]; by default its mean extent over orientations),
//!   giving `1 / (2 L)` c/pixel.
//! - **Luminance contrast** is Michelson contrast between the feature's
//!   mean *linear* relative luminance `Y` (CIE Y of the sRGB pixels, 0 to 1)
//!   in the two renderings: what the feature shows against what replaces it
//!   (its surround once it is gone; for a silhouette, the background it was
//!   rendered on). It is kept as the pair `[lower, higher]` of the two
//!   luminances, not as a ratio, so that the display's black level can be
//!   folded in at run time (profiles are display-independent).
//! - **Chromatic term**: the difference of the mean `u*, v*` is converted to
//!   the Michelson contrast of a lightness change of the same size in
//!   CIELUV (`ΔL* ≈ (2/3)(L* + 16) c` for a small contrast `c`, so
//!   `c_chroma = 3 Δuv / (2 (L̄* + 16))`). When it is the larger, the
//!   feature's luminance pair is replaced by the pair with the same mean
//!   and that contrast. CIELUV counts a chromatic step as visible as an
//!   equal lightness step for large fields, and chromatic sensitivity falls
//!   off at lower frequencies than luminance sensitivity, so judging it
//!   with the luminance CSF is conservative.
//! - **Masker**: a change is harder to see on top of strong contrast (a
//!   sliver along a silhouette is masked by the silhouette itself). The
//!   masker of a feature is the luminance range (lowest and highest `Y`)
//!   over its pixels and their 8 neighbours, in whichever rendering has
//!   the smaller range (mutual masking: the masker is what both images
//!   share). The run time turns it into a threshold elevation
//!   (`acuity::csf`).
//! - **Area**: the feature's pixel count. Larger features are more visible
//!   (spatial summation; the run time uses it as the CSF's field size).
//! - **What is kept**: every feature with contrast ([`kept_features`]).
//!   The run time pools a transition's features (visible differences add
//!   up, `acuity::rows`), so a feature cannot be dropped because another
//!   is more visible; only features whose two luminances are equal
//!   (invisible on any display) are left out.

use crate::Error;
use crate::frequency::{self, FrequencyStatistic};
use crate::segment::{LuvImage, Regions, grow_regions, label_components};

/// How changed pixels are grouped into features (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Grouping {
    /// Neighbours whose change has the same sign (both lighter or both
    /// darker). The default.
    #[default]
    ChangeSign,
    /// As `ChangeSign`, and only within one CIELUV region of either
    /// rendering (Reddy's feature extraction).
    Regions,
}

impl Grouping {
    /// A stable name (settings files, cache keys).
    pub fn name(self) -> &'static str {
        match self {
            Self::ChangeSign => "change_sign",
            Self::Regions => "regions",
        }
    }
}

/// How unique features are found and measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeatureSettings {
    /// How changed pixels are grouped.
    pub grouping: Grouping,
    /// ΔE*uv just-noticeable difference of region growing (> 0; used by
    /// [`Grouping::Regions`]).
    pub threshold_delta_e: f32,
    /// A pixel counts as changed where the renderings differ by more than
    /// this, ΔE*uv (finite, >= 0; 0: any difference).
    pub min_change_delta_e: f32,
    /// Number of Feret directions K (>= 1).
    pub feret_directions: u32,
    /// How a feature's size becomes one length.
    pub statistic: FrequencyStatistic,
}

/// Default [`FeatureSettings::min_change_delta_e`], ΔE*uv: just above one
/// sRGB code step in one channel (at most 0.94 ΔE*uv).
pub const DEFAULT_MIN_CHANGE_DELTA_E: f32 = 1.0;

/// Checks a [`FeatureSettings::min_change_delta_e`] (finite, >= 0); the
/// error names the field. [`unique_features`] and
/// [`crate::AnalysisSettings::validate`] both check it.
pub fn check_min_change_delta_e(min_change_delta_e: f32) -> Result<(), Error> {
    if min_change_delta_e.is_finite() && min_change_delta_e >= 0.0 {
        Ok(())
    } else {
        Err(Error::Settings {
            field: "min_change_delta_e",
            message: format!("{min_change_delta_e} is not a finite ΔE*uv >= 0"),
        })
    }
}

/// One unique feature of a transition.
#[derive(Debug, Clone, PartialEq)]
pub struct UniqueFeature {
    /// Its shape: pixel count, Feret extents, thickness.
    pub shape: frequency::Feature,
    /// Its frequency `1 / (2 L)` in cycles per pixel (at most 0.5).
    pub freq_cpx: f32,
    /// Mean relative linear luminance in the finer and the coarser LOD's
    /// rendering.
    pub luminance_finer: f32,
    /// See [`UniqueFeature::luminance_finer`].
    pub luminance_coarser: f32,
    /// Michelson contrast of the two mean luminances (0 to 1).
    pub luminance_contrast: f32,
    /// Michelson contrast equivalent of the chromatic difference (see the
    /// module docs).
    pub chromatic_contrast: f32,
    /// The luminance pair `[lower, higher]` the feature is judged by: the
    /// two mean luminances, or, when the chromatic term is larger, the
    /// pair with their mean and the chromatic contrast.
    pub luminance: [f32; 2],
    /// The masker's luminance range `[lowest, highest]` (see the module
    /// docs).
    pub masker: [f32; 2],
}

impl UniqueFeature {
    /// The contrast the feature is judged by: Michelson contrast of
    /// [`UniqueFeature::luminance`] on a display with a zero black level.
    pub fn contrast(&self) -> f32 {
        michelson(self.luminance[0], self.luminance[1])
    }
}

/// Michelson contrast `(hi - lo) / (hi + lo)` of two luminances (0 when
/// both are 0).
pub fn michelson(lo: f32, hi: f32) -> f32 {
    let sum = lo + hi;
    if sum > 0.0 {
        (hi - lo).abs() / sum
    } else {
        0.0
    }
}

/// Relative linear luminance `Y` (0 to 1) of a CIELUV lightness `L*`: the
/// exact inverse of the CIE formula [`crate::segment`] converts with.
pub fn luminance_of_lightness(l_star: f32) -> f32 {
    const KAPPA: f32 = 24_389.0 / 27.0;
    if l_star > 8.0 {
        let t = (l_star + 16.0) / 116.0;
        (t * t * t).min(1.0)
    } else {
        (l_star / KAPPA).max(0.0)
    }
}

/// The unique features of the transition between renderings `finer` and
/// `coarser` (same size). With [`Grouping::Regions`], `regions` are each
/// one's regions (from [`grow_regions`] at `settings.threshold_delta_e`);
/// else they are not read and may be `None`. Returns the features in label
/// order and the feature labels (for inspection images). Identical images
/// give no features.
pub fn unique_features(
    finer: &LuvImage,
    coarser: &LuvImage,
    regions: Option<(&Regions, &Regions)>,
    settings: &FeatureSettings,
) -> Result<(Vec<UniqueFeature>, Regions), Error> {
    let (w, h) = (finer.width, finer.height);
    let n = w as usize * h as usize;
    check_min_change_delta_e(settings.min_change_delta_e)?;
    let regions = match (settings.grouping, regions) {
        (Grouping::Regions, Some((ra, rb))) => Some((&ra.labels, &rb.labels)),
        (Grouping::Regions, None) => {
            return Err(Error::Settings {
                field: "regions",
                message: "grouping by regions needs both renderings' regions".into(),
            });
        }
        (Grouping::ChangeSign, _) => None,
    };
    let sizes_match = (coarser.width, coarser.height) == (w, h)
        && finer.luv.len() == n
        && coarser.luv.len() == n
        && regions.is_none_or(|(ra, rb)| ra.len() == n && rb.len() == n);
    if !sizes_match {
        return Err(Error::Settings {
            field: "images",
            message: format!(
                "sizes differ: {w}x{h} and {}x{} (or their regions)",
                coarser.width, coarser.height
            ),
        });
    }
    let (a, b) = (&finer.luv, &coarser.luv);
    // Lightness is monotonic in luminance: its change has the same sign.
    let brighter = |i: usize| b[i][0] > a[i][0];
    let min_change_sq = settings.min_change_delta_e * settings.min_change_delta_e;
    // A squared distance above a threshold >= 0 implies the pixels differ.
    let changed = |i: usize| {
        let d = [a[i][0] - b[i][0], a[i][1] - b[i][1], a[i][2] - b[i][2]];
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > min_change_sq
    };
    let labels = label_components(w, h, true, changed, |i, j| {
        brighter(i) == brighter(j)
            && regions.is_none_or(|(ra, rb)| ra[i] == ra[j] || rb[i] == rb[j])
    });
    let shapes = frequency::measure_regions(&labels, settings.feret_directions);
    // Per feature: sums of Y and of L*, u*, v* in each image.
    let ya: Vec<f32> = a.iter().map(|p| luminance_of_lightness(p[0])).collect();
    let yb: Vec<f32> = b.iter().map(|p| luminance_of_lightness(p[0])).collect();
    let mut sums = vec![[0.0f64; 8]; labels.count as usize];
    // Per feature: [min, max] of Y around it in each rendering.
    let mut ranges = vec![[[f32::INFINITY, f32::NEG_INFINITY]; 2]; labels.count as usize];
    let (wu, hu) = (w as usize, h as usize);
    for (i, &l) in labels.labels.iter().enumerate() {
        if l == Regions::NONE {
            continue;
        }
        let (p, q) = (a[i], b[i]);
        let s = &mut sums[l as usize];
        s[0] += f64::from(ya[i]);
        s[1] += f64::from(yb[i]);
        for c in 0..3 {
            s[2 + c] += f64::from(p[c]);
            s[5 + c] += f64::from(q[c]);
        }
        let (x, y) = (i % wu, i / wu);
        let r = &mut ranges[l as usize];
        for ny in y.saturating_sub(1)..(y + 2).min(hu) {
            for nx in x.saturating_sub(1)..(x + 2).min(wu) {
                let j = ny * wu + nx;
                for (range, v) in r.iter_mut().zip([ya[j], yb[j]]) {
                    range[0] = range[0].min(v);
                    range[1] = range[1].max(v);
                }
            }
        }
    }
    let features = shapes
        .into_iter()
        .zip(sums)
        .zip(ranges)
        .map(|((shape, s), [ra, rb])| {
            let k = 1.0 / f64::from(shape.pixel_count.max(1));
            let mean = |x: f64| (x * k) as f32;
            let (ya, yb) = (mean(s[0]), mean(s[1]));
            let (du, dv) = (mean(s[3]) - mean(s[6]), mean(s[4]) - mean(s[7]));
            let l_mean = 0.5 * (mean(s[2]) + mean(s[5]));
            let chromatic_contrast =
                (1.5 * (du * du + dv * dv).sqrt() / (l_mean + 16.0).max(16.0)).min(1.0);
            let luminance_contrast = michelson(ya.min(yb), ya.max(yb));
            let luminance = if chromatic_contrast > luminance_contrast {
                // The pair around the mean, moved down where it would pass
                // peak white (the same contrast).
                let c = chromatic_contrast;
                let hi = (0.5 * (ya + yb) * (1.0 + c)).min(1.0);
                [hi * (1.0 - c) / (1.0 + c), hi]
            } else {
                [ya.min(yb), ya.max(yb)]
            };
            UniqueFeature {
                freq_cpx: shape.frequency_cpx(settings.statistic),
                shape,
                luminance_finer: ya,
                luminance_coarser: yb,
                luminance_contrast,
                chromatic_contrast,
                luminance,
                masker: if michelson(ra[0], ra[1]) <= michelson(rb[0], rb[1]) {
                    ra
                } else {
                    rb
                },
            }
        })
        .collect();
    Ok((features, labels))
}

/// [`unique_features`] with the regions grown here when the grouping needs
/// them (for tests and benchmarks; the pipeline grows each LOD's regions
/// once and shares them between its transitions).
pub fn unique_features_of(
    finer: &LuvImage,
    coarser: &LuvImage,
    settings: &FeatureSettings,
) -> Result<(Vec<UniqueFeature>, Regions), Error> {
    if settings.grouping == Grouping::Regions {
        let ra = grow_regions(finer, settings.threshold_delta_e);
        let rb = grow_regions(coarser, settings.threshold_delta_e);
        unique_features(finer, coarser, Some((&ra, &rb)), settings)
    } else {
        unique_features(finer, coarser, None, settings)
    }
}

/// A feature as the profile stores it: frequency, the luminance pair
/// `[lower, higher]`, the masker's range `[lowest, highest]` and area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Visibility {
    /// Frequency (any unit, the same for all).
    pub freq: f32,
    /// Area (any unit, the same for all).
    pub area: f32,
    /// Luminance pair `[lower, higher]`.
    pub luminance: [f32; 2],
    /// Masker range `[lowest, highest]`.
    pub masker: [f32; 2],
}

impl Visibility {
    /// Michelson contrast of the luminance pair on a display whose black
    /// is 0: the highest it has on any display, 0 when the two are equal.
    pub fn largest_contrast(&self) -> f32 {
        let [lo, hi] = self.luminance;
        if hi > lo { (hi - lo) / (hi + lo) } else { 0.0 }
    }
}

/// The indices of the features a profile keeps, ascending by frequency:
/// every feature that has contrast (unequal luminances) and finite values,
/// since the run time pools them all. Above `max` such features (a noisy
/// texture at the largest rung), the `max` with the largest
/// `largest_contrast() * sqrt(area)` are kept (the most visible at the CSF's
/// peak under linear spatial summation), and the rest are dropped.
pub fn kept_features(features: &[Visibility], max: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..features.len())
        .filter(|&i| {
            let f = &features[i];
            f.freq.is_finite()
                && f.area.is_finite()
                && f.luminance.iter().all(|l| l.is_finite())
                && f.masker.iter().all(|m| m.is_finite())
                && f.largest_contrast() > 0.0
        })
        .collect();
    if order.len() > max {
        let weight = |i: usize| features[i].largest_contrast() * features[i].area.max(0.0).sqrt();
        order.sort_by(|&i, &j| weight(j).total_cmp(&weight(i)).then(i.cmp(&j)));
        order.truncate(max);
    }
    order.sort_by(|&i, &j| {
        features[i]
            .freq
            .total_cmp(&features[j].freq)
            .then(i.cmp(&j))
    });
    order
}

/// Widths of the bins [`summarise`] groups features by, in octaves:
/// frequency, area, contrast (at black 0), mean luminance, masker contrast
/// and masker mean.
pub const SUMMARY_BIN_OCTAVES: [f32; 6] = [0.25, 0.5, 0.25, 0.25, 0.5, 0.5];

/// Groups features that are alike into one record each, with a count: the
/// summary a profile stores. Features fall in one group when they share a
/// bin of [`SUMMARY_BIN_OCTAVES`] in frequency, area, contrast, mean
/// luminance, masker contrast and masker mean; the group's record is their
/// envelope, at least as visible as each of them on any display: the
/// lowest frequency, the largest area, the lowest of their lower and the
/// highest of their higher luminances, and the least masker (the highest
/// masker floor, with the smallest masker range above it: a lower
/// Michelson contrast than each member's for any black level). Pooling
/// `count` copies of the record therefore never understates the group.
/// Records come out ascending by frequency; features without contrast or
/// with non-finite values are left out.
pub fn summarise(features: &[Visibility]) -> Vec<(Visibility, u32)> {
    use std::collections::BTreeMap;
    let bin = |v: f32, octaves: f32| (v.max(1e-9).log2() / octaves).floor() as i32;
    let mut groups: BTreeMap<[i32; 6], (Visibility, u32, f32)> = BTreeMap::new();
    for i in kept_features(features, usize::MAX) {
        let f = features[i];
        let [lo, hi] = f.luminance;
        let [mlo, mhi] = f.masker;
        let masker_contrast = if mhi > mlo {
            (mhi - mlo) / (mhi + mlo)
        } else {
            0.0
        };
        let o = SUMMARY_BIN_OCTAVES;
        let key = [
            bin(f.freq, o[0]),
            bin(f.area, o[1]),
            bin(f.largest_contrast(), o[2]),
            bin(0.5 * (lo + hi) + 1e-3, o[3]),
            bin(masker_contrast + 1e-3, o[4]),
            bin(0.5 * (mlo + mhi) + 1e-3, o[5]),
        ];
        groups
            .entry(key)
            .and_modify(|(g, n, width)| {
                g.freq = g.freq.min(f.freq);
                g.area = g.area.max(f.area);
                g.luminance = [g.luminance[0].min(lo), g.luminance[1].max(hi)];
                g.masker[0] = g.masker[0].max(mlo);
                *width = width.min(mhi - mlo);
                *n += 1;
            })
            .or_insert((f, 1, mhi - mlo));
    }
    let mut out: Vec<(Visibility, u32)> = groups
        .into_values()
        .map(|(mut g, n, width)| {
            g.masker[1] = (g.masker[0] + width.max(0.0)).min(1.0);
            (g, n)
        })
        .collect();
    out.sort_by(|a, b| a.0.freq.total_cmp(&b.0.freq));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_xorshift::XorShiftRng;

    #[test]
    fn lightness_inverts_the_cie_formula() {
        for y in [0.0f32, 0.001, 0.008, 0.0089, 0.05, 0.18, 0.5, 1.0] {
            let l = if y > 216.0 / 24389.0 {
                116.0 * y.powf(1.0 / 3.0) - 16.0
            } else {
                24389.0 / 27.0 * y
            };
            assert!((luminance_of_lightness(l) - y).abs() < 1e-5, "{y}");
        }
    }

    fn v(freq: f32, luminance: [f32; 2]) -> Visibility {
        Visibility {
            freq,
            area: 1.0,
            luminance,
            masker: [0.0, 1.0],
        }
    }

    #[test]
    fn every_feature_with_contrast_is_kept_coarsest_first() {
        let f = [
            v(3.0, [0.2, 0.9]),
            v(1.0, [0.1, 0.5]),
            v(2.0, [0.1, 0.4]), // less visible than the one before: kept too
            v(4.0, [0.3, 0.3]), // no contrast
            v(f32::NAN, [0.0, 0.9]),
            v(2.0, [0.0, 0.4]),
        ];
        assert_eq!(kept_features(&f, 100), vec![1, 2, 5, 0]);
    }

    #[test]
    fn above_the_cap_the_faint_and_small_go_first() {
        let f = [
            v(1.0, [0.45, 0.5]),
            Visibility {
                area: 0.01,
                ..v(2.0, [0.0, 1.0])
            },
            v(3.0, [0.0, 1.0]),
            v(4.0, [0.2, 0.8]),
        ];
        // Weights: 0.053, 0.1, 1, 0.6.
        assert_eq!(kept_features(&f, 2), vec![2, 3]);
        assert_eq!(kept_features(&f, 3), vec![1, 2, 3]);
    }

    /// Michelson contrast of `[lo, hi]` with black `black` added.
    fn on_display(pair: [f32; 2], black: f32) -> f32 {
        (pair[1] - pair[0]) / (pair[1] + pair[0] + 2.0 * black)
    }

    #[test]
    fn a_summary_record_is_at_least_as_visible_as_each_feature_it_counts_on_any_display() {
        let mut rng = XorShiftRng::seed_from_u64(0x5eed);
        let mut next = || rng.random::<f32>();
        let features: Vec<Visibility> = (0..2000)
            .map(|_| {
                let (a, b) = (next(), next());
                let (c, d) = (next(), next());
                Visibility {
                    freq: 1.0 + 30.0 * next(),
                    area: 1e-4 + 0.01 * next(),
                    luminance: [a.min(b), a.max(b)],
                    masker: [c.min(d), c.max(d)],
                }
            })
            .collect();
        let summary = summarise(&features);
        assert!(summary.len() < features.len());
        assert_eq!(summary.iter().map(|s| s.1).sum::<u32>(), 2000);
        assert!(summary.windows(2).all(|w| w[0].0.freq <= w[1].0.freq));
        // Every feature is covered by a record of its bins: check each
        // against the record whose envelope holds it.
        for f in &features {
            let covering = summary.iter().any(|(g, _)| {
                g.freq <= f.freq
                    && g.area >= f.area
                    && [0.0, 0.01, 0.3].iter().all(|&black| {
                        on_display(g.luminance, black) >= on_display(f.luminance, black) - 1e-6
                            && on_display(g.masker, black) <= on_display(f.masker, black) + 1e-6
                    })
            });
            assert!(covering, "{f:?}");
        }
        for (g, _) in &summary {
            assert!(g.masker[0] <= g.masker[1] && g.masker[1] <= 1.0, "{g:?}");
        }
    }
}
