//! A profile compiled for one display and observer: what the selection
//! loop compares against.
//!
//! The CSF scaled along frequency by `k / (H(0, 0) theta)` (with `k = s
//! H(v, E) theta`, `theta` the size the object is judged at, below) shows
//! a feature of frequency `f` c/diam and contrast `c` (after masking,
//! [`Csf::masked_contrast`], judged by the CSF of its own field size,
//! [`Csf::for_field`]) with detectability `d(k) = c S(f H(0, 0) / k)`: its
//! contrast in units of its threshold ([`crate::csf`]). Visible
//! differences add up: a transition's features pool by probability
//! summation, `D(k) = (sum_i d_i(k)^beta)^(1/beta)` with `beta` =
//! [`DETECTABILITY_EXPONENT`], and the transition is invisible while `D`
//! stays below the observer's threshold [`Csf::threshold_jnd`] (the
//! calibration of `s = 1`). `D` only grows with `k`, so each transition has
//! one *critical frequency* `q` (c/diam, [`transition_critical_cdiam`]):
//! it is invisible exactly when `q > k` (`inf` when it has no features, or
//! none that reach the threshold at any frequency). With a single feature
//! and a threshold of 1, `q = f H(0, 0) / f_c(c)`, `f_c(c)` the highest
//! frequency at which contrast `c` is visible. Going from LOD 0 to LOD `j`
//! is invisible when the prefix minimum over transitions `0..j` exceeds
//! `k`. All of this is done when a profile is added to a selector, so the
//! per-object loop still compares one number per transition.
//!
//! Rows: per viewpoint and rung of the size ladder, the prefix minima of
//! the transitions' critical frequencies, padded with `-inf` to `stride`
//! (a multiple of 4, at least 4). Before the viewpoints' rows come one row
//! per rung with the worst case over viewpoints. Row `(block * rungs +
//! rung) * stride`, block 0 the worst case and `1 + v` viewpoint `v`.
//!
//! The rung an object uses is the one nearest (in log size) to its
//! diameter on screen, `theta` times pixels per degree: rung `r` serves
//! angular sizes between the geometric means of its diameter and its
//! neighbours', converted to degrees with the display's pixels per degree.
//! The display's resolution limit is thereby in the images: a rung is
//! rendered at the size the display shows the object, so what the display
//! cannot show is not among its features.
//!
//! Size never buys less detail. Within a rung, an object is judged at the
//! upper end of the rung's range (`k = s H u_r` with `u_r` the boundary
//! above it): the largest object the rung serves shows its features at the
//! lowest frequencies in c/deg, so this is conservative for every size in
//! the range. The bottom and top rungs judge an object at its own size
//! (the top rung's range has no end; below the bottom rung there is no
//! boundary to keep monotonic, and a far-off speck must be able to drop
//! detail); at the bottom rung's upper end that is `u_0` as well. Across rungs, a feature measured on a larger rendering is finer
//! in c/diam (a one-pixel sliver is `D / 2` c/diam), so left alone an object
//! could become *coarser* as it grows past a boundary. The compiled rows
//! therefore hold, per transition, the running minimum over rungs of the
//! critical acuity `q_r / u_r` (c/deg: the `s H` below which the
//! transition is invisible), times `u_r`: a larger object is never judged
//! invisible where a smaller one was visible.

use std::collections::HashMap;

use crate::csf::{Csf, FieldCsf, Photometry};
use crate::profile::{Feature, Profile};

/// A profile's rows and ladder for one display and observer.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CompiledRows {
    /// `(1 + viewpoints) * rungs` rows of `stride` entries (see the module
    /// docs).
    pub rows: Vec<f32>,
    /// Entries per row: `lod_count - 1` rounded up to a multiple of 4
    /// (at least 4).
    pub stride: usize,
    /// Rungs of the size ladder.
    pub rungs: usize,
}

/// The CSFs of one display and observer by field size, computed once per
/// field and tabulated for pooling. Fields are rounded up to a sixteenth of
/// an octave (a larger field is at least as visible), so a profile needs a
/// few dozen.
pub struct FieldCsfs<'a> {
    csf: &'a Csf,
    by_step: HashMap<i32, usize>,
    tables: Vec<SensitivityTable>,
}

/// `ln S(u)` of one field's CSF on a grid of `ln u` from its peak to
/// [`TABLE_END_CPD`], interpolated linearly in log-log: the clamped CSF
/// (the peak's sensitivity below the peak, 0 beyond the end), so
/// non-increasing in frequency.
struct SensitivityTable {
    ln_peak_cpd: f32,
    ln_sensitivity: Vec<f32>,
}

/// Grid step of the sensitivity tables, in `ln u`: a 32nd of an octave.
const TABLE_STEP: f32 = std::f32::consts::LN_2 / 32.0;
/// Highest tabulated frequency, c/deg: no contrast is visible beyond.
const TABLE_END_CPD: f32 = 400.0;

impl SensitivityTable {
    fn new(csf: &FieldCsf) -> Self {
        let peak = csf.peak_cpd().max(1e-3);
        let ln_peak_cpd = peak.ln();
        let n = ((TABLE_END_CPD.ln() - ln_peak_cpd) / TABLE_STEP)
            .ceil()
            .max(1.0) as usize
            + 1;
        let ln_sensitivity = (0..n)
            .map(|j| {
                let s = csf.sensitivity((ln_peak_cpd + j as f32 * TABLE_STEP).exp());
                if s > 0.0 { s.ln() } else { f32::NEG_INFINITY }
            })
            .collect();
        Self {
            ln_peak_cpd,
            ln_sensitivity,
        }
    }

    /// `ln S` at `ln u` (c/deg); `-inf` beyond the table, never `NaN`.
    fn ln_at(&self, ln_freq_cpd: f32) -> f32 {
        let t = (ln_freq_cpd - self.ln_peak_cpd) / TABLE_STEP;
        if t.is_nan() || t <= 0.0 {
            return self.ln_sensitivity[0];
        }
        let i = t as usize;
        let frac = t - i as f32;
        match (self.ln_sensitivity.get(i), self.ln_sensitivity.get(i + 1)) {
            (Some(&a), Some(&b)) if b.is_finite() => a + (b - a) * frac,
            // Past the last finite entry (sensitivity underflows to 0):
            // nothing is visible, and no `inf - inf` is taken.
            (Some(&a), _) if frac == 0.0 => a,
            _ => f32::NEG_INFINITY,
        }
    }

    fn ln_peak_sensitivity(&self) -> f32 {
        self.ln_sensitivity[0]
    }
}

impl<'a> FieldCsfs<'a> {
    /// An empty cache for `csf`.
    pub fn new(csf: &'a Csf) -> Self {
        Self {
            csf,
            by_step: HashMap::new(),
            tables: Vec::new(),
        }
    }

    /// The table index of the CSF for a field of `field_deg` degrees,
    /// rounded up.
    fn table(&mut self, field_deg: f32) -> usize {
        let step = (16.0 * field_deg.max(1e-6).log2()).ceil().clamp(-1e4, 1e4) as i32;
        let (csf, tables) = (self.csf, &mut self.tables);
        *self.by_step.entry(step).or_insert_with(|| {
            tables.push(SensitivityTable::new(
                &csf.for_field((step as f32 / 16.0).exp2()),
            ));
            tables.len() - 1
        })
    }
}

/// One feature as pooling sees it: `ln` of its effective contrast, `ln` of
/// its frequency times `H(0, 0)` (c/diam times c/deg), its field's table.
#[derive(Clone, Copy)]
struct PoolTerm {
    count: f64,
    ln_contrast: f32,
    ln_freq_h0: f32,
    table: usize,
}

/// The critical frequency of a transition, c/diam: the `k = s H(v, E)
/// theta` (see the module docs) at which its features' pooled
/// detectability reaches the observer's threshold
/// ([`Csf::threshold_jnd`]); below it the transition is invisible. `inf`
/// when it stays below the threshold at any `k` (no features, or none
/// that any frequency makes visible enough).
///
/// Each feature's detectability is `d_i(k) = c_i S_i(f_i H(0, 0) / k)`:
/// its effective contrast (masked by what it sits on,
/// [`Csf::masked_contrast`]) over the threshold of the CSF of its own field
/// (`sqrt(area)` times the object's diameter `diameter_deg`: spatial
/// summation within the feature, [`Csf::for_field`]), at the frequency it
/// shows when the CSF is scaled along frequency by `k / (H(0, 0) theta)`.
/// The transition's detectability is their Minkowski sum (probability
/// summation), `D(k) = (sum_i d_i^beta)^(1/beta)` with `beta` =
/// [`DETECTABILITY_EXPONENT`]. `D` is non-decreasing in `k`, so the root is
/// found by bisection in `ln k`; the result is its lower end (the
/// conservative side).
pub fn transition_critical_cdiam(
    features: &[Feature],
    diameter_deg: f32,
    photometry: &Photometry,
    csfs: &mut FieldCsfs<'_>,
) -> f32 {
    let mut terms: Vec<PoolTerm> = Vec::with_capacity(features.len());
    critical_with(features, diameter_deg, photometry, csfs, &mut terms)
}

fn critical_with(
    features: &[Feature],
    diameter_deg: f32,
    photometry: &Photometry,
    csfs: &mut FieldCsfs<'_>,
    terms: &mut Vec<PoolTerm>,
) -> f32 {
    let csf = csfs.csf;
    let ln_h0 = crate::acuity::MAX_ACUITY_CPD.ln();
    let beta = DETECTABILITY_EXPONENT;
    let threshold = csf.threshold_jnd();
    terms.clear();
    // `(sum_i (c_i S_peak,i)^beta)`: the detectability when every feature
    // sits at or below its CSF's peak.
    let mut most_pow = 0.0f64;
    let (mut lowest_ln_f, mut highest_ln_f, mut lowest_ln_peak) =
        (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY);
    for f in features {
        let masked = csf.masked_contrast(
            photometry.contrast(f.luminance),
            photometry.contrast(f.masker),
        );
        let field_deg = f.area_diam2.sqrt() * diameter_deg;
        let contrast = csf.pooled_contrast(masked, field_deg * field_deg);
        if contrast.is_nan() || contrast <= 0.0 {
            continue;
        }
        let table = csfs.table(field_deg);
        let t = &csfs.tables[table];
        let term = PoolTerm {
            count: f64::from(f.count),
            ln_contrast: contrast.ln(),
            ln_freq_h0: f.freq_cdiam.ln() + ln_h0,
            table,
        };
        most_pow +=
            term.count * f64::from(beta * (term.ln_contrast + t.ln_peak_sensitivity())).exp();
        lowest_ln_f = lowest_ln_f.min(term.ln_freq_h0);
        highest_ln_f = highest_ln_f.max(term.ln_freq_h0);
        lowest_ln_peak = lowest_ln_peak.min(t.ln_peak_cpd);
        terms.push(term);
    }
    let threshold_pow = f64::from(threshold).powf(f64::from(beta));
    if terms.is_empty() || most_pow.is_nan() || most_pow < threshold_pow {
        return f32::INFINITY;
    }
    let tables = &csfs.tables;
    let detectability_pow = |ln_k: f32| -> f64 {
        terms
            .iter()
            .map(|t| {
                let ln_s = tables[t.table].ln_at(t.ln_freq_h0 - ln_k);
                t.count * f64::from(beta * (t.ln_contrast + ln_s)).exp()
            })
            .sum()
    };
    // At `lo` every feature lies beyond the tables (nothing visible); at
    // `hi` every feature lies at or below its peak (`most_pow`).
    let mut lo = lowest_ln_f - TABLE_END_CPD.ln();
    let mut hi = highest_ln_f - lowest_ln_peak;
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        if detectability_pow(mid) >= threshold_pow {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo.exp()
}

/// Bisection steps in `ln k`: the bracket spans at most about 25 in `ln k`,
/// so 32 halvings leave it under 1e-8 relative.
const BISECTION_STEPS: u32 = 32;

/// The exponent `beta` of the Minkowski sum that pools a transition's
/// features (probability summation): the Weibull slope of the
/// psychometric function, 3 to 4 in detection experiments (Tyler & Chen,
/// Vision Research 40, 2000; Laming, JOSA A 30(3), 2013), and the fourth
/// root with which contrast sums over area (Baldwin & Meese, Journal of
/// Vision 15(15):4, 2015).
pub const DETECTABILITY_EXPONENT: f32 = 4.0;

/// Compiles a validated profile's rows (see the module docs) for a display
/// of `pixels_per_degree`: an object at rung `r` is
/// `rung_diameters_px[r] / pixels_per_degree` degrees across.
pub(crate) fn compile(
    profile: &Profile,
    photometry: &Photometry,
    csf: &Csf,
    pixels_per_degree: f32,
) -> CompiledRows {
    let mut csfs = FieldCsfs::new(csf);
    let mut terms = Vec::new();
    let n = profile.transitions_per_view();
    let stride = n.next_multiple_of(4).max(4);
    let rungs = profile.rung_diameters_px.len();
    let views = profile.viewpoints.len();
    let mut rows = vec![f32::NEG_INFINITY; (1 + views) * rungs * stride];
    for rung in 0..rungs {
        rows[rung * stride..rung * stride + n].fill(f32::INFINITY);
    }
    let boundaries = rung_boundaries_deg(&profile.rung_diameters_px, pixels_per_degree);
    for v in 0..views {
        for rung in 0..rungs {
            let mut running = f32::INFINITY;
            let at = ((1 + v) * rungs + rung) * stride;
            let diameter_deg = profile.rung_diameters_px[rung] / pixels_per_degree;
            for (t, tr) in profile.transitions_at(v, rung).iter().enumerate() {
                let critical = critical_with(
                    &tr.features,
                    diameter_deg,
                    photometry,
                    &mut csfs,
                    &mut terms,
                );
                running = running.min(critical);
                rows[at + t] = running;
                let worst = &mut rows[rung * stride + t];
                *worst = worst.min(running);
            }
        }
    }
    for block in 0..=views {
        for t in 0..n {
            let at = |rung: usize| (block * rungs + rung) * stride + t;
            // The critical acuity `q / u` may only fall as the rung rises.
            let mut acuity_cpd = f32::INFINITY;
            for (rung, &upper_deg) in boundaries.iter().enumerate() {
                let q = &mut rows[at(rung)];
                if *q / upper_deg <= acuity_cpd {
                    acuity_cpd = *q / upper_deg;
                } else {
                    *q = acuity_cpd * upper_deg;
                }
            }
            // The top rung's objects are judged at their own size, at least
            // the last boundary.
            if let Some(&last_deg) = boundaries.last() {
                let q = &mut rows[at(rungs - 1)];
                *q = q.min(acuity_cpd * last_deg);
            }
        }
    }
    CompiledRows {
        rows,
        stride,
        rungs,
    }
}

/// The angular sizes, deg, at which an object moves to the next rung: the
/// geometric means of neighbouring rungs' diameters over `pixels_per_degree`
/// (`rungs - 1` values, ascending). An object of angular size `theta` uses
/// rung `#{b : theta > b}`.
pub(crate) fn rung_boundaries_deg(diameters_px: &[f32], pixels_per_degree: f32) -> Vec<f32> {
    diameters_px
        .windows(2)
        .map(|w| (w[0] * w[1]).sqrt() / pixels_per_degree)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::csf::Observer;
    use crate::profile::tests::sample_profile;

    fn csf() -> (Photometry, Csf) {
        let p = Photometry::default();
        (p, Csf::new(&p, &Observer::default()).unwrap())
    }

    /// The CSF of the default display and an observer whose threshold is
    /// `threshold_jnd`.
    fn csf_at(threshold_jnd: f32) -> (Photometry, Csf) {
        let p = Photometry::default();
        let observer = Observer {
            threshold_jnd,
            ..Default::default()
        };
        (p, Csf::new(&p, &observer).unwrap())
    }

    /// An object 10 deg across.
    const DIAMETER_DEG: f32 = 10.0;

    fn critical(features: &[Feature], p: &Photometry, c: &Csf) -> f32 {
        transition_critical_cdiam(features, DIAMETER_DEG, p, &mut FieldCsfs::new(c))
    }

    const FULL: Feature = Feature {
        freq_cdiam: 10.0,
        area_diam2: 0.01,
        luminance: [0.0, 1.0],
        masker: [0.0, 1.0],
        count: 1,
    };

    #[test]
    fn one_feature_is_critical_at_its_frequency_times_h0_over_the_cut_off_of_its_contrast_over_the_threshold()
     {
        for threshold in [1.0, 2.0, 8.0] {
            let (p, c) = csf_at(threshold);
            let full = p.contrast([0.0, 1.0]);
            // A field of sqrt(0.01) * 10 = 1 deg.
            let cutoff = c
                .for_field(1.0)
                .cutoff_cpd(c.masked_contrast(full, full) / threshold);
            let q = critical(&[FULL], &p, &c);
            let want = 10.0 * 60.0 / cutoff;
            assert!((q / want - 1.0).abs() < 2e-3, "{threshold}: {q} {want}");
        }
    }

    #[test]
    fn fainter_masked_or_smaller_features_are_critical_sooner() {
        let (p, c) = csf();
        let q = critical(&[FULL], &p, &c);
        let faint = Feature {
            luminance: [0.4, 0.5],
            masker: [0.4, 0.5],
            ..FULL
        };
        assert!(critical(&[faint], &p, &c) > q);
        let invisible = Feature {
            luminance: [0.5, 0.5001],
            ..FULL
        };
        assert_eq!(critical(&[invisible], &p, &c), f32::INFINITY);
        // A change under a tenth of the contrast it sits on is masked.
        let masked = Feature {
            luminance: [0.45, 0.5],
            ..FULL
        };
        assert_eq!(critical(&[masked], &p, &c), f32::INFINITY);
        let unmasked = Feature {
            masker: [0.45, 0.5],
            ..masked
        };
        assert!(critical(&[unmasked], &p, &c).is_finite());
        let small = Feature {
            area_diam2: 0.0001,
            ..FULL
        };
        assert!(critical(&[small], &p, &c) > q);
        assert_eq!(critical(&[], &p, &c), f32::INFINITY);
    }

    #[test]
    fn n_equal_features_pool_to_one_seen_at_the_threshold_over_the_fourth_root_of_n() {
        let (p, c) = csf_at(4.0);
        for n in [2usize, 5, 40] {
            let many = vec![FULL; n];
            let (_, lower) = csf_at(4.0 / (n as f32).powf(1.0 / DETECTABILITY_EXPONENT));
            let (got, want) = (critical(&many, &p, &c), critical(&[FULL], &p, &lower));
            assert!((got / want - 1.0).abs() < 1e-4, "{n}: {got} {want}");
            assert!(got < critical(&[FULL], &p, &c));
        }
    }

    #[test]
    fn adding_a_feature_or_lowering_the_threshold_never_makes_a_transition_less_visible() {
        let faint = Feature {
            freq_cdiam: 4.0,
            area_diam2: 0.2,
            luminance: [0.45, 0.5],
            masker: [0.45, 0.5],
            count: 1,
        };
        let mut previous = f32::INFINITY;
        for threshold in [64.0, 16.0, 4.0, 1.0] {
            let (p, c) = csf_at(threshold);
            let one = critical(&[FULL], &p, &c);
            let two = critical(&[FULL, faint], &p, &c);
            assert!(two <= one, "{threshold}: {two} {one}");
            assert!(one <= previous, "{threshold}: {one} {previous}");
            previous = one;
        }
    }

    #[test]
    fn sensitivity_tables_follow_the_csf_fall_monotonically_and_never_give_nan() {
        let (_, c) = csf();
        for field_deg in [0.05, 0.3, 2.0, 60.0] {
            let exact = c.for_field(field_deg);
            let table = SensitivityTable::new(&exact);
            let mut previous = f32::INFINITY;
            for i in 0..=4000 {
                let freq_cpd = 0.01 * 1.0025f32.powi(i);
                let ln_s = table.ln_at(freq_cpd.ln());
                assert!(!ln_s.is_nan() && ln_s <= previous, "{field_deg} {freq_cpd}");
                previous = ln_s;
                let s = exact.sensitivity(freq_cpd);
                if s > 1e-3 {
                    assert!(
                        (ln_s.exp() / s - 1.0).abs() < 5e-3,
                        "{field_deg} {freq_cpd}"
                    );
                }
            }
            assert_eq!(table.ln_at(f32::NAN), table.ln_peak_sensitivity());
            assert_eq!(table.ln_at(1e3f32.ln()), f32::NEG_INFINITY);
        }
    }

    #[test]
    fn area_pooling_lets_only_features_smaller_than_its_area_go_sooner() {
        let p = Photometry::default();
        let plain = Csf::new(&p, &Observer::default()).unwrap();
        let pooled = Csf::new(
            &p,
            &Observer {
                pooling_area_deg2: 1.0,
                ..Default::default()
            },
        )
        .unwrap();
        let q = |csf: &Csf, area_diam2: f32| {
            let f = Feature {
                freq_cdiam: 20.0,
                area_diam2,
                luminance: [0.1, 0.6],
                masker: [0.1, 0.6],
                count: 1,
            };
            critical(&[f], &p, csf)
        };
        // 0.0001 diam² of a 10 deg object: 0.01 deg², a hundredth of the
        // pooling area.
        assert!(q(&pooled, 0.0001) > q(&plain, 0.0001));
        // 0.02 diam²: 2 deg², more than the pooling area.
        assert_eq!(q(&pooled, 0.02), q(&plain, 0.02));
    }

    #[test]
    fn rows_are_prefix_minima_with_a_worst_case_per_rung() {
        let (p, c) = csf();
        let profile = sample_profile();
        let ppd = 20.0;
        let r = compile(&profile, &p, &c, ppd);
        let mut csfs = FieldCsfs::new(&c);
        assert_eq!((r.stride, r.rungs), (4, 2));
        assert_eq!(r.rows.len(), 7 * 2 * 4);
        for v in 0..6 {
            for rung in 0..2 {
                let row = &r.rows[((1 + v) * 2 + rung) * 4..][..4];
                assert!(row[..3].windows(2).all(|w| w[0] >= w[1]), "{row:?}");
                assert_eq!(row[3], f32::NEG_INFINITY);
                let diameter_deg = profile.rung_diameters_px[rung] / ppd;
                let features = &profile.transitions_at(v, rung)[0].features;
                let want = transition_critical_cdiam(features, diameter_deg, &p, &mut csfs);
                assert_eq!(row[0], want);
                for (t, &entry) in row.iter().enumerate().take(3) {
                    assert!(r.rows[rung * 4 + t] <= entry);
                }
            }
        }
    }

    #[test]
    fn a_larger_object_is_never_judged_invisible_where_a_smaller_was_visible() {
        let (p, c) = csf();
        let profile = sample_profile();
        let ppd = 20.0;
        let r = compile(&profile, &p, &c, ppd);
        let b = rung_boundaries_deg(&profile.rung_diameters_px, ppd);
        for block in 0..7 {
            for t in 0..3 {
                let q0 = r.rows[(block * 2) * 4 + t];
                let q1 = r.rows[(block * 2 + 1) * 4 + t];
                // At the boundary, rung 0 is judged at b and rung 1 at its
                // own size b: the threshold on s H may only fall.
                assert!(q1 / b[0] <= q0 / b[0], "block {block} t {t}: {q0} {q1}");
            }
        }
    }

    #[test]
    fn rung_boundaries_are_geometric_means_in_degrees() {
        let b = rung_boundaries_deg(&[16.0, 32.0, 64.0], 10.0);
        assert_eq!(b.len(), 2);
        assert!((b[0] - 512f32.sqrt() / 10.0).abs() < 1e-6);
        assert!((b[1] - 2048f32.sqrt() / 10.0).abs() < 1e-6);
        assert!(rung_boundaries_deg(&[512.0], 10.0).is_empty());
    }
}
