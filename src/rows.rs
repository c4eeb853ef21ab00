//! A profile compiled for one display and observer: what the selection
//! loop compares against.
//!
//! A feature of frequency `f` c/diam and contrast `c` (after masking,
//! [`Csf::masked_contrast`], judged by the CSF of its own field size,
//! [`Csf::for_field`]) on an object of angular size `theta` is invisible
//! when `f / theta > s H(v, E) f_c(c) / H(0, 0)` ([`crate::csf`]), that is
//! when its *critical frequency* `q = f H(0, 0) / f_c(c)` (c/diam) exceeds
//! `k = s H(v, E) theta` (with `theta` the size the object is judged at,
//! below). A
//! transition is invisible when every one of its features is, so its
//! critical frequency is the lowest of its features' (`inf` when it has
//! none, or none that any contrast threshold lets through). Going from
//! LOD 0 to LOD `j` is invisible when the prefix minimum over transitions
//! `0..j` exceeds `k`.
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
/// field. Fields are rounded up to a sixteenth of an octave (a larger field
/// is at least as visible), so a profile needs a few dozen.
pub struct FieldCsfs<'a> {
    csf: &'a Csf,
    by_step: HashMap<i32, FieldCsf>,
}

impl<'a> FieldCsfs<'a> {
    /// An empty cache for `csf`.
    pub fn new(csf: &'a Csf) -> Self {
        Self {
            csf,
            by_step: HashMap::new(),
        }
    }

    /// The CSF for a field of `field_deg` degrees, rounded up.
    pub fn get(&mut self, field_deg: f32) -> &FieldCsf {
        let step = (16.0 * field_deg.max(1e-6).log2()).ceil().clamp(-1e4, 1e4) as i32;
        let csf = self.csf;
        self.by_step
            .entry(step)
            .or_insert_with(|| csf.for_field((step as f32 / 16.0).exp2()))
    }
}

/// The critical frequency of one feature on a display, c/diam: its
/// contrast there, masked by the contrast it sits on, judged by the CSF of
/// its field (`sqrt(area)` times the object's diameter, `diameter_deg`).
pub fn feature_critical_cdiam(
    feature: &Feature,
    diameter_deg: f32,
    photometry: &Photometry,
    csfs: &mut FieldCsfs<'_>,
) -> f32 {
    let masked = csfs.csf.masked_contrast(
        photometry.contrast(feature.luminance),
        photometry.contrast(feature.masker),
    );
    let field_deg = feature.area_diam2.sqrt() * diameter_deg;
    let contrast = csfs.csf.pooled_contrast(masked, field_deg * field_deg);
    csfs.get(field_deg)
        .critical_cdiam(feature.freq_cdiam, contrast)
}

/// The critical frequency of a transition: its features' lowest.
pub fn transition_critical_cdiam(
    features: &[Feature],
    diameter_deg: f32,
    photometry: &Photometry,
    csfs: &mut FieldCsfs<'_>,
) -> f32 {
    features
        .iter()
        .map(|f| feature_critical_cdiam(f, diameter_deg, photometry, csfs))
        .fold(f32::INFINITY, f32::min)
}

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
                let critical =
                    transition_critical_cdiam(&tr.features, diameter_deg, photometry, &mut csfs);
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

    /// An object 10 deg across.
    const DIAMETER_DEG: f32 = 10.0;

    #[test]
    fn a_full_contrast_feature_is_critical_at_its_frequency_times_h0_over_the_cut_off() {
        let (p, c) = csf();
        let f = Feature {
            freq_cdiam: 10.0,
            area_diam2: 0.01,
            luminance: [0.0, 1.0],
            masker: [0.0, 1.0],
        };
        let mut csfs = FieldCsfs::new(&c);
        let full = p.contrast([0.0, 1.0]);
        // A field of sqrt(0.01) * 10 = 1 deg.
        let cutoff = c.for_field(1.0).cutoff_cpd(c.masked_contrast(full, full));
        let q = feature_critical_cdiam(&f, DIAMETER_DEG, &p, &mut csfs);
        assert!((q - 10.0 * 60.0 / cutoff).abs() < 1e-3, "{q}");
        // Less contrast: visible only at lower frequencies, so critical
        // sooner in c/diam.
        let faint = Feature {
            luminance: [0.4, 0.5],
            masker: [0.4, 0.5],
            ..f
        };
        assert!(feature_critical_cdiam(&faint, DIAMETER_DEG, &p, &mut csfs) > q);
        let invisible = Feature {
            luminance: [0.5, 0.5001],
            ..f
        };
        assert_eq!(
            feature_critical_cdiam(&invisible, DIAMETER_DEG, &p, &mut csfs),
            f32::INFINITY
        );
        // A change under a tenth of the contrast it sits on is masked.
        let masked = Feature {
            luminance: [0.45, 0.5],
            ..f
        };
        assert_eq!(
            feature_critical_cdiam(&masked, DIAMETER_DEG, &p, &mut csfs),
            f32::INFINITY
        );
        let unmasked = Feature {
            masker: [0.45, 0.5],
            ..masked
        };
        assert!(feature_critical_cdiam(&unmasked, DIAMETER_DEG, &p, &mut csfs).is_finite());
        // A smaller patch is less visible: critical sooner.
        let small = Feature {
            area_diam2: 0.0001,
            ..f
        };
        assert!(feature_critical_cdiam(&small, DIAMETER_DEG, &p, &mut csfs) > q);
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
            };
            feature_critical_cdiam(&f, DIAMETER_DEG, &p, &mut FieldCsfs::new(csf))
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
