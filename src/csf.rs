//! Contrast sensitivity: when a feature of a given contrast is visible.
//!
//! The foveal, static contrast sensitivity function is Barten's closed form
//! (P. G. J. Barten, "Formula for the contrast sensitivity of the human
//! eye", Proc. SPIE 5294, 2004), which gives absolute sensitivity from the
//! adapting luminance `L` (cd/m²) and the angular size `X0` (deg) of the
//! field the pattern covers:
//!
//! ```text
//! S(u) = 5200 exp(-0.0016 u² (1 + 100/L)^0.08)
//!        / sqrt((1 + 144/X0² + 0.64 u²) (63/L^0.83 + 1/(1 - exp(-0.02 u²))))
//! ```
//!
//! with `u` in c/deg. A feature of Michelson contrast `c` is visible at
//! frequency `u` when `c S(u) >= 1`. The CSF is clamped below its peak
//! (lower frequencies are at least as visible as the peak, as Luebke &
//! Hallen 2001 clamp theirs), so `f_c(c)`, the highest frequency at which
//! contrast `c` is visible, is 0 when `c` is below the peak's threshold and
//! otherwise the root of `c S(u) = 1` above the peak.
//!
//! Masking: a change on top of strong contrast is harder to see. In units
//! of the detection threshold (a contrast times `S(u)`), a change `c` on a
//! masker of contrast `m` is visible when `(c S)^p >= 1 + (k m S)^p`, the
//! masking model of FovVideoVDP 1.2 (Mantiuk et al. 2021; its calibrated
//! `k = 10^-0.974` and `p = 2.4`, with its two exponents taken equal). That
//! is the unmasked rule for the effective contrast
//! `c_eff = (c^p - (k m)^p)^(1/p)` (0 when `c <= k m`): changes under about
//! a tenth of the masker's contrast are invisible at any frequency
//! ([`Csf::masked_contrast`]).
//!
//! Reddy's acuity model stays the core: at retinal velocity `v` and
//! eccentricity `E` the CSF is the foveal one with frequencies scaled by
//! `H(v, E) / H(0, 0)` ([`crate::acuity`]), so a feature of frequency `f`
//! c/deg is invisible when `f > s H(v, E) f_c(c) / H(0, 0)`.
//!
//! Motion on a sampled display. Velocity models (`G(v)`) describe smooth
//! motion, where detail of frequency `u` moving at `v` flickers at `u v`
//! Hz and vanishes above the temporal resolution. A display instead shows
//! each frame still for `t = 1 / refresh` s: to a fixating eye an object
//! moving more than its own detail per frame is a series of still images,
//! each visible like a still image shown for `t`. In Barten's model the eye
//! integrates over `T = 0.1` s and sensitivity grows as `sqrt(T)`, so an
//! image shown for `t < T` keeps `B = sqrt(t / T)` of its sensitivity
//! (0.41 at 60 Hz, 0.33 at 90 Hz). The cut-off frequency that reduced
//! sensitivity leaves is a floor under `G(v)`
//! ([`Csf::sampled_motion_floor`]): 0.84-0.91 of foveal acuity on 60-144
//! Hz displays, so on such displays motion hides little detail that the
//! display can show. The floor holds at every velocity, so `G` stays
//! continuous and non-increasing; it also covers motion slower than a
//! pixel per frame, which is smooth on the retina, but there `G` is above
//! what a display of fewer than about 50 pixels per degree shows anyway.
//! A floor that started only at one pixel per frame (capped there by `G`,
//! to stay monotone) let savings through that FovVideoVDP sees, on a
//! headset of 4 pixels per degree.
//!
//! Field size: a feature is a small patch, not a grating filling the view,
//! and Barten's `X0` models how sensitivity falls as the patch shrinks
//! (spatial summation). Each feature's field is the square root of its
//! area, in degrees at the size the object has on screen
//! ([`Csf::for_field`]).
//!
//! Area pooling (optional). The rule above asks every feature to be
//! invisible. Judgements of a whole image pool differences over it:
//! FovVideoVDP sums its per-pixel differences with a p-norm of exponent
//! `beta = 1.52` normalised by the image's area, so a clearly visible
//! difference a few pixels large costs it little. With
//! [`Observer::pooling_area_deg2`] `= A > 0`, a feature of area `a < A`
//! deg² counts with its contrast scaled by `(a / A)^(1 / beta)`, the
//! contrast at which a feature of area `A` pools to the same amount
//! ([`Csf::pooled_contrast`]). This lets small visible differences go in
//! exchange for triangles; 0, the default, keeps the threshold rule.
//!
//! Calibration. The display's photometry ([`Photometry`], part of
//! [`crate::Display`]) turns a feature's relative luminances into contrast
//! and sets the adapting luminance; the observer ([`Observer`], part of
//! [`crate::SelectorSettings`]) scales sensitivity (Luebke & Hallen
//! calibrate per user and display) and sets the masking constant. With
//! the default photometry (200 cd/m² peak, 40 cd/m² adapting) and a 2 deg
//! field the peak sensitivity is about 290 at 4.9 c/deg, and contrast 1 is
//! visible up to about 49 c/deg, 0.1 up to 35 and 0.02 up to 23; for a
//! patch of 0.1 deg (one or two pixels on a desktop display) the peak is
//! about 19 (a 5% contrast).

use crate::error::{Error, Result};

/// The display's light output, the part of a display that turns relative
/// luminance (0 = black, 1 = peak white) into contrast.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Photometry {
    /// Luminance of peak white, cd/m² (finite, > 0). Default 200 (an office
    /// monitor).
    pub peak_cd_m2: f32,
    /// Luminance of black as the viewer sees it, cd/m²: the panel's black
    /// level plus ambient light reflected by the screen (finite, `0 <=
    /// black < peak`). Default 0.6: a 1000:1 panel (0.2) under 250 lux
    /// reflected with 0.5% (`0.005 * 250 / pi` = 0.4).
    pub black_cd_m2: f32,
    /// The luminance the eye is adapted to, cd/m² (finite, > 0): Barten's
    /// `L`. Default 40 (a fifth of peak: a typical frame's mean).
    pub adapting_cd_m2: f32,
}

impl Default for Photometry {
    /// An office monitor: [`Photometry::from_display`]`(200, 1000, 250)`.
    fn default() -> Self {
        Self {
            peak_cd_m2: 200.0,
            black_cd_m2: 0.2 + SCREEN_REFLECTIVITY * 250.0 / std::f32::consts::PI,
            adapting_cd_m2: 40.0,
        }
    }
}

/// The fraction of ambient light a screen reflects (FovVideoVDP's default
/// display model: 0.5%).
pub const SCREEN_REFLECTIVITY: f32 = 0.005;

impl Photometry {
    /// The photometry of a display of peak luminance `peak_cd_m2` (> 0),
    /// contrast ratio `contrast_ratio` (> 1, black = peak / ratio) under
    /// `ambient_lux` of ambient light (>= 0; reflected with
    /// [`SCREEN_REFLECTIVITY`], `E k / pi`), the eye adapted to a fifth of
    /// peak (a typical frame's mean). Validated; the error names the
    /// argument.
    pub fn from_display(peak_cd_m2: f32, contrast_ratio: f32, ambient_lux: f32) -> Result<Self> {
        if !(contrast_ratio.is_finite() && contrast_ratio > 1.0) {
            return Err(Error::invalid(
                "contrast_ratio",
                format!("{contrast_ratio} is not a finite ratio > 1"),
            ));
        }
        if !(ambient_lux.is_finite() && ambient_lux >= 0.0) {
            return Err(Error::invalid(
                "ambient_lux",
                format!("{ambient_lux} is not a finite illuminance >= 0"),
            ));
        }
        let p = Self {
            peak_cd_m2,
            black_cd_m2: peak_cd_m2 / contrast_ratio
                + SCREEN_REFLECTIVITY * ambient_lux / std::f32::consts::PI,
            adapting_cd_m2: 0.2 * peak_cd_m2,
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks every field's domain; the error names the field.
    pub fn validate(&self) -> Result<()> {
        let positive = |v: f32| v.is_finite() && v > 0.0;
        if !positive(self.peak_cd_m2) {
            return Err(Error::invalid(
                "peak_cd_m2",
                format!("{} is not a finite luminance > 0", self.peak_cd_m2),
            ));
        }
        if !(self.black_cd_m2.is_finite()
            && self.black_cd_m2 >= 0.0
            && self.black_cd_m2 < self.peak_cd_m2)
        {
            return Err(Error::invalid(
                "black_cd_m2",
                format!(
                    "{} is not a finite luminance in [0, peak {})",
                    self.black_cd_m2, self.peak_cd_m2
                ),
            ));
        }
        if !positive(self.adapting_cd_m2) {
            return Err(Error::invalid(
                "adapting_cd_m2",
                format!("{} is not a finite luminance > 0", self.adapting_cd_m2),
            ));
        }
        Ok(())
    }

    /// The luminance in cd/m² of relative luminance `y` (clamped to `[0, 1]`).
    pub fn luminance_cd_m2(&self, y: f32) -> f32 {
        self.black_cd_m2 + (self.peak_cd_m2 - self.black_cd_m2) * y.clamp(0.0, 1.0)
    }

    /// Michelson contrast on this display of a feature whose relative
    /// luminances are `[lower, higher]`: in `[0, 1)`, 0 for equal ones.
    pub fn contrast(&self, luminance: [f32; 2]) -> f32 {
        let (a, b) = (
            self.luminance_cd_m2(luminance[0]),
            self.luminance_cd_m2(luminance[1]),
        );
        (b - a).abs() / (a + b)
    }
}

/// FovVideoVDP 1.2's masking exponent `p` (see the module docs).
pub const MASKING_EXPONENT: f32 = 2.4;
/// FovVideoVDP 1.2's masking constant `k = 10^-0.973838` (see the module
/// docs): the default [`Observer::masking`].
pub const DEFAULT_MASKING: f32 = 0.106_198;

/// The observer's side of the calibration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observer {
    /// Multiplier on the CSF (finite, > 0; default 1: Barten's standard
    /// observer). Above 1 is a more sensitive viewer (more detail kept).
    pub sensitivity: f32,
    /// The masking constant `k` (finite, `>= 0`; default
    /// [`DEFAULT_MASKING`]): a change below about `k` times the contrast it
    /// sits on is invisible. 0 turns masking off.
    pub masking: f32,
    /// The area over which a difference counts in full, deg² (finite,
    /// `>= 0`; 0, the default, turns area pooling off): a feature of
    /// smaller area `a` counts with its contrast scaled by
    /// `(a / pooling_area_deg2)^(1 / beta)` ([`Csf::pooled_contrast`]).
    pub pooling_area_deg2: f32,
    /// The pooled detectability at which an LOD transition stops being
    /// imperceptible, in units of the detection threshold (finite, `>= 1`;
    /// default [`DEFAULT_THRESHOLD_JND`]): a transition whose features pool
    /// to less ([`crate::rows::transition_critical_cdiam`]) is dropped at
    /// `s = 1`. 1 is the threshold of a single grating in a detection
    /// experiment (Barten's CSF).
    pub threshold_jnd: f32,
}

/// The calibration of `s = 1`: the pooled detectability, in units of the
/// detection threshold, below which a transition counts as imperceptible
/// ([`Observer::threshold_jnd`]). Fixed once, for every scene and display,
/// so that `s = 1` lands at the edge of visibility as FovVideoVDP judges
/// whole scenes (foveated JOD 9.75, a quarter JOD below the reference);
/// how it was measured is in the repository's `docs/perception.md`.
pub const DEFAULT_THRESHOLD_JND: f32 = 3.5;

impl Default for Observer {
    fn default() -> Self {
        Self {
            sensitivity: 1.0,
            masking: DEFAULT_MASKING,
            pooling_area_deg2: 0.0,
            threshold_jnd: DEFAULT_THRESHOLD_JND,
        }
    }
}

impl Observer {
    /// Checks every field's domain; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if !(self.sensitivity.is_finite() && self.sensitivity > 0.0) {
            return Err(Error::invalid(
                "sensitivity",
                format!("{} is not a finite multiplier > 0", self.sensitivity),
            ));
        }
        if !(self.masking.is_finite() && self.masking >= 0.0) {
            return Err(Error::invalid(
                "masking",
                format!("{} is not a finite constant >= 0", self.masking),
            ));
        }
        if !(self.pooling_area_deg2.is_finite() && self.pooling_area_deg2 >= 0.0) {
            return Err(Error::invalid(
                "pooling_area_deg2",
                format!("{} is not a finite area >= 0", self.pooling_area_deg2),
            ));
        }
        if !(self.threshold_jnd.is_finite() && self.threshold_jnd >= 1.0) {
            return Err(Error::invalid(
                "threshold_jnd",
                format!(
                    "{} is not a finite detectability >= 1 (the detection threshold)",
                    self.threshold_jnd
                ),
            ));
        }
        Ok(())
    }
}

/// Barten's CSF `S(u)` (see the module docs): absolute contrast
/// sensitivity at `freq_cpd` c/deg (> 0), adapting luminance
/// `luminance_cd_m2` (> 0) and field size `field_deg` (> 0). Finite and
/// non-negative for positive inputs.
pub fn barten_sensitivity(freq_cpd: f64, luminance_cd_m2: f64, field_deg: f64) -> f64 {
    let u2 = freq_cpd * freq_cpd;
    let l = luminance_cd_m2;
    let num = 5200.0 * (-0.0016 * u2 * (1.0 + 100.0 / l).powf(0.08)).exp();
    let den = ((1.0 + 144.0 / (field_deg * field_deg) + 0.64 * u2)
        * (63.0 / l.powf(0.83) + 1.0 / (1.0 - (-0.02 * u2).exp())))
    .sqrt();
    num / den
}

/// Barten's integration time of the eye, s: a still image shown for less
/// is seen with its sensitivity scaled by the square root of the shortfall.
pub const INTEGRATION_TIME_S: f32 = 0.1;

/// Field sizes are clamped into this range, deg: below a twentieth of a
/// degree Barten's spatial integration term is far outside the data it
/// was fitted to; 60 deg is larger than any display.
pub const FIELD_RANGE_DEG: (f32, f32) = (0.05, 60.0);

/// The contrast sensitivity of one display and observer: masking, and the
/// CSF for each field size ([`Csf::for_field`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Csf {
    masking: f32,
    pooling_area_deg2: f32,
    threshold_jnd: f32,
    luminance_cd_m2: f64,
    scale: f64,
}

/// The CSF of one display, observer and field size: the peak, and the
/// highest visible frequency of a contrast.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldCsf {
    luminance_cd_m2: f64,
    field_deg: f64,
    scale: f64,
    peak_freq_cpd: f64,
    peak_sensitivity: f64,
}

/// Frequencies searched, c/deg: the CSF's peak lies far inside, and no
/// contrast is visible at the upper end.
const SEARCH_CPD: (f64, f64) = (0.01, 400.0);

impl Csf {
    /// The contrast sensitivity of a display's photometry and an observer
    /// (both validated).
    pub fn new(photometry: &Photometry, observer: &Observer) -> Result<Self> {
        photometry.validate()?;
        observer.validate()?;
        Ok(Self {
            masking: observer.masking,
            pooling_area_deg2: observer.pooling_area_deg2,
            threshold_jnd: observer.threshold_jnd,
            luminance_cd_m2: f64::from(photometry.adapting_cd_m2),
            scale: f64::from(observer.sensitivity),
        })
    }

    /// The pooled detectability at which a transition becomes visible
    /// ([`Observer::threshold_jnd`]).
    pub fn threshold_jnd(&self) -> f32 {
        self.threshold_jnd
    }

    /// The fraction of foveal acuity that retinal motion cannot take away
    /// on a display that holds each frame for `1 / refresh_hz` s, in
    /// `(0, 1]` (see the module docs, "Motion on a sampled display"):
    /// `f_c(c B) / f_c(c)` with `B = sqrt(t / T)`, `t` the frame time
    /// (at most `T`), `T` Barten's integration time
    /// ([`INTEGRATION_TIME_S`]), `c` the display's largest contrast and the
    /// largest field (the highest floor, the conservative side).
    /// `refresh_hz` must be finite and positive; anything else gives 0
    /// (no floor: continuous motion).
    pub fn sampled_motion_floor(&self, photometry: &Photometry, refresh_hz: f32) -> f32 {
        if !(refresh_hz.is_finite() && refresh_hz > 0.0) {
            return 0.0;
        }
        let frame_s = (1.0 / f64::from(refresh_hz)).min(f64::from(INTEGRATION_TIME_S));
        let flash = (frame_s / f64::from(INTEGRATION_TIME_S)).sqrt() as f32;
        let csf = self.for_field(FIELD_RANGE_DEG.1);
        let contrast = photometry.contrast([0.0, 1.0]);
        let (steady, flashed) = (csf.cutoff_cpd(contrast), csf.cutoff_cpd(contrast * flash));
        if steady > 0.0 {
            (flashed / steady).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The CSF for patterns covering `field_deg` degrees (Barten's `X0`;
    /// clamped into [`FIELD_RANGE_DEG`], `NaN` counts as the smallest).
    pub fn for_field(&self, field_deg: f32) -> FieldCsf {
        let field = if field_deg.is_nan() {
            FIELD_RANGE_DEG.0
        } else {
            field_deg.clamp(FIELD_RANGE_DEG.0, FIELD_RANGE_DEG.1)
        };
        let mut csf = FieldCsf {
            luminance_cd_m2: self.luminance_cd_m2,
            field_deg: f64::from(field),
            scale: self.scale,
            peak_freq_cpd: 0.0,
            peak_sensitivity: 0.0,
        };
        // The peak by golden-section search in log frequency (S is
        // unimodal in u for Barten's form).
        let (mut a, mut b) = (SEARCH_CPD.0.ln(), 60f64.ln());
        let g = (5f64.sqrt() - 1.0) / 2.0;
        for _ in 0..60 {
            let (x1, x2) = (b - g * (b - a), a + g * (b - a));
            if csf.raw(x1.exp()) < csf.raw(x2.exp()) {
                a = x1;
            } else {
                b = x2;
            }
        }
        csf.peak_freq_cpd = (0.5 * (a + b)).exp();
        csf.peak_sensitivity = csf.raw(csf.peak_freq_cpd);
        csf
    }

    /// The effective contrast of a change of Michelson contrast `contrast`
    /// on a masker of contrast `masker_contrast` (both clamped into
    /// `[0, 1]`; see the module docs): at most `contrast`, 0 when it is at
    /// most `k` times the masker's (and for a `NaN` contrast; a `NaN`
    /// masker counts as none), non-decreasing in `contrast`, non-increasing
    /// in the masker's.
    pub fn masked_contrast(&self, contrast: f32, masker_contrast: f32) -> f32 {
        // Michelson contrasts lie in [0, 1]; a `NaN` masker counts as none
        // (the conservative reading).
        let c = contrast.clamp(0.0, 1.0);
        let masker = if masker_contrast.is_nan() {
            0.0
        } else {
            masker_contrast.clamp(0.0, 1.0)
        };
        let m = self.masking * masker;
        // `NaN` in either gives 0 too.
        if c.partial_cmp(&m) != Some(std::cmp::Ordering::Greater) {
            return 0.0;
        }
        if m == 0.0 {
            return c;
        }
        let p = MASKING_EXPONENT;
        (c.powf(p) - m.powf(p)).max(0.0).powf(1.0 / p).min(c)
    }
}

/// FovVideoVDP 1.2's exponent of spatial pooling (`beta`): how its
/// difference maps sum over the image.
pub const POOLING_EXPONENT: f32 = 1.52134;

impl Csf {
    /// The contrast with which a difference of (effective) contrast
    /// `contrast` over `area_deg2` deg² counts: unchanged when area pooling
    /// is off or the area is at least [`Observer::pooling_area_deg2`],
    /// else scaled by `(area / pooling_area)^(1 / beta)` (`beta` =
    /// [`POOLING_EXPONENT`]; a `NaN` or negative area counts as 0).
    /// Non-decreasing in both arguments.
    pub fn pooled_contrast(&self, contrast: f32, area_deg2: f32) -> f32 {
        if self.pooling_area_deg2 <= 0.0 {
            return contrast;
        }
        let share = (area_deg2.max(0.0) / self.pooling_area_deg2).min(1.0);
        if share.is_nan() {
            return 0.0;
        }
        contrast * share.powf(1.0 / POOLING_EXPONENT)
    }
}

impl FieldCsf {
    fn raw(&self, freq_cpd: f64) -> f64 {
        self.scale * barten_sensitivity(freq_cpd, self.luminance_cd_m2, self.field_deg)
    }

    /// The frequency of peak sensitivity, c/deg.
    pub fn peak_cpd(&self) -> f32 {
        self.peak_freq_cpd as f32
    }

    /// Contrast sensitivity at `freq_cpd` (c/deg; negative and `NaN` count
    /// as 0), clamped below the peak: the peak's sensitivity at lower
    /// frequencies. Non-increasing in frequency.
    pub fn sensitivity(&self, freq_cpd: f32) -> f32 {
        let f = f64::from(freq_cpd);
        if f.is_nan() || f <= self.peak_freq_cpd {
            self.peak_sensitivity as f32
        } else {
            self.raw(f.min(SEARCH_CPD.1)) as f32
        }
    }

    /// `f_c(c)`: the highest frequency in c/deg at which Michelson contrast
    /// `contrast` is visible (the clamped CSF's threshold equals it). 0 when
    /// it is invisible at every frequency (below the peak's threshold, or
    /// `NaN`); non-decreasing in contrast.
    pub fn cutoff_cpd(&self, contrast: f32) -> f32 {
        let c = f64::from(contrast);
        if c.is_nan() || c * self.peak_sensitivity < 1.0 {
            return 0.0;
        }
        let visible = |f: f64| c * self.raw(f) >= 1.0;
        let (mut lo, mut hi) = (self.peak_freq_cpd.ln(), SEARCH_CPD.1.ln());
        if visible(SEARCH_CPD.1) {
            return SEARCH_CPD.1 as f32;
        }
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if visible(mid.exp()) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo.exp() as f32
    }

    /// The critical frequency in c/diam of a feature of `freq_cdiam`
    /// (c/diam) and (effective) Michelson contrast `contrast`:
    /// `f H(0, 0) / f_c(c)`, `inf` when the contrast is invisible at every
    /// frequency. The feature is invisible on an object of angular size
    /// `theta` when this exceeds `s H(v, E) theta` (see the module docs).
    pub fn critical_cdiam(&self, freq_cdiam: f32, contrast: f32) -> f32 {
        let cutoff_cpd = self.cutoff_cpd(contrast);
        if cutoff_cpd > 0.0 {
            freq_cdiam * (crate::acuity::MAX_ACUITY_CPD / cutoff_cpd)
        } else {
            f32::INFINITY
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csf() -> Csf {
        Csf::new(&Photometry::default(), &Observer::default()).unwrap()
    }

    fn two_deg() -> FieldCsf {
        csf().for_field(2.0)
    }

    #[test]
    fn barten_matches_published_values() {
        // Values of the formula computed by hand (Barten 2004, eq. 1).
        let s = barten_sensitivity(4.0, 100.0, 40.0);
        assert!((s - 670.4).abs() < 1.0, "{s}");
        let s = barten_sensitivity(40.0, 100.0, 40.0);
        assert!((s - 7.0).abs() < 0.1, "{s}");
    }

    #[test]
    fn sampled_motion_floor_is_high_and_falls_with_the_refresh_rate() {
        let photometry = Photometry::default();
        let floor = |hz| csf().sampled_motion_floor(&photometry, hz);
        let (at60, at90, at144) = (floor(60.0), floor(90.0), floor(144.0));
        assert!((0.85..0.95).contains(&at60), "{at60}");
        assert!(at144 < at90 && at90 < at60, "{at60} {at90} {at144}");
        assert!(at144 > 0.8, "{at144}");
        // A frame held for the whole integration time is a still image.
        assert_eq!(floor(5.0), 1.0);
        for bad in [0.0, -60.0, f32::NAN, f32::INFINITY] {
            assert_eq!(floor(bad), 0.0, "{bad}");
        }
    }

    #[test]
    fn defaults_peak_and_cut_off_where_documented() {
        let c = two_deg();
        assert!((4.5..5.2).contains(&c.peak_cpd()), "{}", c.peak_cpd());
        let peak = c.sensitivity(0.0);
        assert!((270.0..310.0).contains(&peak), "{peak}");
        let f1 = c.cutoff_cpd(1.0);
        assert!((48.0..49.5).contains(&f1), "{f1}");
        // At the cut-off, the threshold equals the contrast.
        let f = c.cutoff_cpd(0.1);
        assert!((0.1 * c.sensitivity(f) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn smaller_fields_are_less_visible() {
        let small = csf().for_field(0.1);
        let peak = small.sensitivity(0.0);
        assert!((17.0..20.0).contains(&peak), "{peak}");
        assert!(small.cutoff_cpd(0.5) < two_deg().cutoff_cpd(0.5));
        assert_eq!(csf().for_field(f32::NAN), csf().for_field(0.0));
    }

    #[test]
    fn below_the_peak_threshold_nothing_is_visible() {
        let c = two_deg();
        let threshold = 1.0 / c.sensitivity(0.0);
        assert_eq!(c.cutoff_cpd(0.99 * threshold), 0.0);
        assert!(c.cutoff_cpd(1.01 * threshold) >= c.peak_cpd());
        assert_eq!(c.cutoff_cpd(f32::NAN), 0.0);
        assert_eq!(c.cutoff_cpd(-1.0), 0.0);
    }

    #[test]
    fn cut_off_grows_with_contrast_and_sensitivity() {
        let c = two_deg();
        let mut prev = 0.0;
        for i in 0..=100 {
            let f = c.cutoff_cpd(i as f32 / 100.0);
            assert!(f >= prev, "{i}");
            prev = f;
        }
        let keen = Csf::new(
            &Photometry::default(),
            &Observer {
                sensitivity: 2.0,
                ..Default::default()
            },
        )
        .unwrap()
        .for_field(2.0);
        assert!(keen.cutoff_cpd(0.05) > c.cutoff_cpd(0.05));
    }

    #[test]
    fn masking_hides_changes_under_a_tenth_of_the_masker() {
        let c = csf();
        assert_eq!(c.masked_contrast(0.3, 0.0), 0.3);
        assert_eq!(c.masked_contrast(0.1, 1.0), 0.0);
        let m = c.masked_contrast(0.3, 1.0);
        assert!(m < 0.3 && m > 0.28, "{m}");
        assert_eq!(c.masked_contrast(f32::NAN, 0.5), 0.0);
        let mut prev = 0.0;
        for i in 0..=100 {
            let e = c.masked_contrast(i as f32 / 100.0, 0.7);
            assert!(e >= prev);
            prev = e;
        }
        let off = Csf::new(
            &Photometry::default(),
            &Observer {
                masking: 0.0,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(off.masked_contrast(0.05, 1.0), 0.05);
    }

    #[test]
    fn area_pooling_scales_small_differences_by_their_share_of_the_pooling_area() {
        let off = csf();
        assert_eq!(off.pooled_contrast(0.3, 0.001), 0.3);
        let on = Csf::new(
            &Photometry::default(),
            &Observer {
                pooling_area_deg2: 2.0,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(on.pooled_contrast(0.3, 2.0), 0.3);
        assert_eq!(on.pooled_contrast(0.3, 50.0), 0.3);
        let quarter = on.pooled_contrast(0.3, 0.5);
        assert!((quarter - 0.3 * 0.25f32.powf(1.0 / POOLING_EXPONENT)).abs() < 1e-6);
        assert_eq!(on.pooled_contrast(0.3, f32::NAN), 0.0);
        assert_eq!(on.pooled_contrast(0.3, -1.0), 0.0);
        let mut prev = 0.0;
        for i in 0..=100 {
            let c = on.pooled_contrast(0.3, i as f32 / 25.0);
            assert!(c >= prev, "{i}");
            prev = c;
        }
        let bad = Observer {
            pooling_area_deg2: f32::INFINITY,
            ..Default::default()
        };
        let e = Csf::new(&Photometry::default(), &bad).unwrap_err();
        assert!(e.to_string().contains("pooling_area_deg2"), "{e}");
    }

    #[test]
    fn the_default_is_an_office_monitor() {
        assert_eq!(
            Photometry::from_display(200.0, 1000.0, 250.0).unwrap(),
            Photometry::default()
        );
        assert!(Photometry::from_display(200.0, 1.0, 0.0).is_err());
        assert!(Photometry::from_display(200.0, 100.0, -1.0).is_err());
        assert!(Photometry::from_display(f32::NAN, 100.0, 0.0).is_err());
    }

    #[test]
    fn contrast_includes_the_black_level() {
        let p = Photometry::default();
        assert!((p.contrast([0.0, 1.0]) - (199.4 / 200.6)).abs() < 1e-4);
        assert_eq!(p.contrast([0.3, 0.3]), 0.0);
        let dark = Photometry {
            black_cd_m2: 0.0,
            ..p
        };
        assert_eq!(dark.contrast([0.0, 0.001]), 1.0);
        assert!(p.contrast([0.0, 0.001]) < 0.2);
    }

    #[test]
    fn bad_calibration_is_refused_with_its_field() {
        let e = |p: Photometry, o: Observer| Csf::new(&p, &o).unwrap_err().to_string();
        let p = Photometry::default();
        let o = Observer::default();
        assert!(
            e(
                Photometry {
                    peak_cd_m2: 0.0,
                    ..p
                },
                o
            )
            .contains("peak_cd_m2")
        );
        assert!(
            e(
                Photometry {
                    black_cd_m2: 300.0,
                    ..p
                },
                o
            )
            .contains("black_cd_m2")
        );
        assert!(
            e(
                p,
                Observer {
                    sensitivity: f32::NAN,
                    ..o
                }
            )
            .contains("sensitivity")
        );
    }
}
