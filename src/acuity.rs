//! The visual acuity model: the highest spatial frequency (c/deg) a viewer
//! resolves at a given retinal velocity and eccentricity (Reddy 2001, eq. 4).
//!
//! Eccentricity acts as a scaling of the frequency axis: at eccentricity
//! `E` a pattern of frequency `f` is as visible as one of `f / M(E)` in the
//! fovea. Two models of `M` are offered ([`EccentricityModel`]): Reddy
//! 2001's, and the default, cortical magnification (Dougherty et al.
//! 2003) with the exponent Mantiuk et al. 2021 fitted for FovVideoVDP.
//! Reddy's `M` keeps foveal acuity out to 5.8 deg and then falls as
//! `E^-2` (to 0.044 at 40 deg); cortical magnification falls from the
//! fovea on (0.60 at 5 deg) but only as `E^-0.6` (0.24 at 40 deg), which
//! is what observers' quality judgements support.
//!
//! Breakpoints. The paper rounds the velocity breakpoints to 0.825 and
//! 118.3 deg/s and the eccentricity breakpoint to 5.79 deg; at those rounded
//! values the middle pieces give 60.01, 0.103 and 0.9998, so the published
//! curve jumps by up to 0.01 c/deg. This module clamps the argument to the
//! exact solutions instead ([`VELOCITY_FLOOR_DEG_PER_S`],
//! [`VELOCITY_CEILING_DEG_PER_S`], [`ECCENTRICITY_FLOOR_DEG`]), which makes
//! `G` and `M` continuous and agrees with the published pieces everywhere
//! else.

/// Foveal acuity at rest, c/deg (`G(v)` for slow motion).
pub const MAX_ACUITY_CPD: f32 = 60.0;
/// Acuity at very high retinal velocity, c/deg (`G(v)` for fast motion).
pub const MIN_ACUITY_CPD: f32 = 0.1;
/// `G(v)`'s value at 1 deg/s, c/deg (Reddy 2001, eq. 4).
const G_INTERCEPT_CPD: f32 = 57.69;
/// `G(v)`'s fall per decade of velocity, c/deg (Reddy 2001, eq. 4).
const G_SLOPE_CPD_PER_DECADE: f32 = 27.78;
/// `M(E) = M_NUMERATOR / (M_SLOPE_PER_DEG E + 1)^2` (Reddy 2001, eq. 4).
const M_NUMERATOR: f32 = 7.49;
/// See [`M_NUMERATOR`], 1/deg.
const M_SLOPE_PER_DEG: f32 = 0.3;
/// The velocity offset of Kelly's (1979) CSF peak `45.9 / (v + 2)`, deg/s.
const KELLY_OFFSET_DEG_PER_S: f32 = 2.0;
/// Velocity below which acuity is [`MAX_ACUITY_CPD`], deg/s: the exact
/// solution of `57.69 - 27.78 log10(v) = 60` (the paper: 0.825).
pub const VELOCITY_FLOOR_DEG_PER_S: f32 = 0.825_746_3;
/// Velocity above which acuity is [`MIN_ACUITY_CPD`], deg/s: the exact
/// solution of `57.69 - 27.78 log10(v) = 0.1` (the paper: 118.3).
pub const VELOCITY_CEILING_DEG_PER_S: f32 = 118.324_36;
/// Eccentricity below which acuity is foveal, deg: the exact solution of
/// `7.49 / (0.3 E + 1)^2 = 1` (the paper: 5.79).
pub const ECCENTRICITY_FLOOR_DEG: f32 = 5.789_288;
/// Eccentricity beyond which the model's data end, deg; `M` is held there.
pub const ECCENTRICITY_CEILING_DEG: f32 = 80.0;

/// `G(v)`: acuity in c/deg for a retinal velocity in deg/s (Reddy 2001,
/// eq. 4). Domain: any `f32`. Negative velocities count as their
/// magnitude; `NaN` counts as 0 (full acuity, the conservative answer);
/// `+inf` gives [`MIN_ACUITY_CPD`]. Output in `[0.1, 60]`, non-increasing.
#[inline]
pub fn velocity_acuity_cpd(velocity_deg_per_s: f32) -> f32 {
    let v = sanitize_nonnegative(velocity_deg_per_s)
        .clamp(VELOCITY_FLOOR_DEG_PER_S, VELOCITY_CEILING_DEG_PER_S);
    reddy_velocity_piece_cpd(v.log10()).clamp(MIN_ACUITY_CPD, MAX_ACUITY_CPD)
}

/// The middle piece of Reddy's `G(v)`, `57.69 - 27.78 log10(v)` c/deg,
/// from `log10(v)`; the caller clamps. Shared with the selection loop,
/// which takes its own `log10`.
#[inline(always)]
pub(crate) fn reddy_velocity_piece_cpd(log10_velocity: f32) -> f32 {
    G_INTERCEPT_CPD - G_SLOPE_CPD_PER_DECADE * log10_velocity
}

/// Reddy's `M(E) = min(7.49 / (0.3 E + 1)^2, 1)` for `E` already clamped
/// into `[ECCENTRICITY_FLOOR_DEG, ECCENTRICITY_CEILING_DEG]`; straight-line
/// code, so the selection loop vectorises over it.
#[inline(always)]
pub(crate) fn reddy_eccentricity_factor_unchecked(eccentricity_deg: f32) -> f32 {
    let d = M_SLOPE_PER_DEG * eccentricity_deg + 1.0;
    crate::fastmath::min(M_NUMERATOR / (d * d), 1.0)
}

/// Kelly's `G_K(v)` for `v` already at least the drift; straight-line code
/// shared with the selection loop.
#[inline(always)]
pub(crate) fn kelly_velocity_acuity_unchecked(velocity_deg_per_s: f32) -> f32 {
    MAX_ACUITY_CPD
        * ((DRIFT_VELOCITY_DEG_PER_S + KELLY_OFFSET_DEG_PER_S)
            / (velocity_deg_per_s + KELLY_OFFSET_DEG_PER_S))
}

/// `M(E)`: the fraction of foveal acuity left at an eccentricity in deg
/// (Rovamo–Virsu as simplified by Reddy 2001, eq. 4). Domain: any `f32`;
/// symmetric about the gaze, so a negative eccentricity counts as its
/// magnitude (`M(-10) = M(10)`); `NaN` counts as 0 (the fovea, the
/// conservative answer); beyond 80 deg, `M(80)`. Output in `[0.012, 1]`,
/// non-increasing in `|E|`.
#[inline]
pub fn eccentricity_factor(eccentricity_deg: f32) -> f32 {
    let e = sanitize_nonnegative(eccentricity_deg)
        .clamp(ECCENTRICITY_FLOOR_DEG, ECCENTRICITY_CEILING_DEG);
    reddy_eccentricity_factor_unchecked(e)
}

/// The model in `models` whose `name` is `text`, or an error listing the
/// names.
fn by_name<M: Copy>(
    models: &[M],
    name: fn(M) -> &'static str,
    text: &str,
    what: &str,
) -> Result<M, String> {
    models
        .iter()
        .copied()
        .find(|&m| name(m) == text)
        .ok_or_else(|| {
            let names: Vec<_> = models.iter().map(|&m| name(m)).collect();
            format!("`{text}` is not {what} ({})", names.join(", "))
        })
}

/// Eccentricity at which cortical magnification has halved, deg (Dougherty
/// et al. 2003, `e_2` in `M(e) = A / (e + e_2)`).
pub const CORTICAL_HALF_ECCENTRICITY_DEG: f32 = 3.67;
/// The power of the cortical magnification ratio that scales frequency
/// (Mantiuk et al. 2021, FovVideoVDP 1.2's `k_cm`).
pub const CORTICAL_MAGNIFICATION_EXPONENT: f32 = 0.604_562;
/// Largest eccentricity, deg: the angle between two directions.
pub const MAX_ECCENTRICITY_DEG: f32 = 180.0;

/// `M_cm(E) = (e_2 / (E + e_2))^k_cm`: the fraction of foveal acuity left
/// at an eccentricity in deg under cortical magnification (Dougherty et
/// al. 2003, exponent from Mantiuk et al. 2021). Domain: any `f32`;
/// negative values count as their magnitude (eccentricity is an angle
/// from the gaze; either side is the same), `NaN` as 0, beyond 180 deg as
/// 180. Output in `[0.11, 1]`, within 1e-6 of the formula, continuous
/// and decreasing (to within 3 ulp of rounding); `M_cm(0) = 1`.
#[inline]
pub fn cortical_magnification_factor(eccentricity_deg: f32) -> f32 {
    cortical_factor_unchecked(sanitize_nonnegative(eccentricity_deg).min(MAX_ECCENTRICITY_DEG))
}

/// `(2^-k_cm)^1`, `^2` and `^4`, each the `f32` nearest the exact power.
const CORTICAL_OCTAVE_FACTORS: [f32; 3] = [0.657_671_03, 0.432_531_18, 0.187_083_21];

/// `m^-k_cm = 1 + t Q(t)` for `m = 1 + t` in `[1, 2)`: `Q`'s coefficients,
/// lowest first, a minimax fit of the relative error (within 7e-7) with
/// `1 + Q(1)` set 3e-7 above `2^-k_cm`, so that the product steps down, not
/// up, where the ratio's exponent steps up.
const CORTICAL_MANTISSA_POLY: [f32; 7] = [
    -0.604_516_6,
    0.483_820_6,
    -0.409_893_8,
    0.327_857_05,
    -0.211_449_5,
    0.089_417_22,
    -0.017_563_712,
];

/// [`cortical_magnification_factor`] for `e` in `[0, 180]`; straight-line
/// code, so the selection loop vectorises over it.
#[inline(always)]
pub(crate) fn cortical_factor_unchecked(eccentricity_deg: f32) -> f32 {
    cortical_factor_of_ratio(1.0 + eccentricity_deg * (1.0 / CORTICAL_HALF_ECCENTRICITY_DEG))
}

/// `r^-k_cm` for the ratio `r = 1 + E / e_2` in `[1, 50.05]` (`E` in
/// `[0, 180]`). With `r = 2^k m`, `k` in `0..=5` and `m` in `[1, 2)`,
/// `r^-k_cm = (2^-k_cm)^k m^-k_cm`: the first factor from `k`'s three
/// bits, the second a polynomial. That is within 1e-6 of the formula at
/// about half the cost of a logarithm and an exponential.
#[inline(always)]
fn cortical_factor_of_ratio(ratio: f32) -> f32 {
    let bits = ratio.to_bits();
    let octaves = (bits >> 23).wrapping_sub(127);
    let t = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000) - 1.0;
    let [f1, f2, f4] = CORTICAL_OCTAVE_FACTORS;
    let octave_factor = (if octaves & 1 != 0 { f1 } else { 1.0 })
        * (if octaves & 2 != 0 { f2 } else { 1.0 })
        * (if octaves & 4 != 0 { f4 } else { 1.0 });
    let [c1, c2, c3, c4, c5, c6, c7] = CORTICAL_MANTISSA_POLY;
    let q = (((((c7 * t + c6) * t + c5) * t + c4) * t + c3) * t + c2) * t + c1;
    octave_factor * (1.0 + t * q)
}

/// How acuity falls with eccentricity: the factor `M(E)` of `H(v, E) =
/// G(v) M(E)`. Both scale the contrast sensitivity function along
/// frequency, so the threshold rule is the same for either.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum EccentricityModel {
    /// Cortical magnification ([`cortical_magnification_factor`]): the
    /// model FovVideoVDP's sensitivity follows, fitted to quality
    /// judgements of foveated video.
    #[default]
    CorticalMagnification,
    /// Reddy 2001, eq. 4 ([`eccentricity_factor`]): foveal out to 5.8 deg,
    /// then a steep fall. The papers' reference.
    Reddy2001,
}

impl EccentricityModel {
    /// `M(E)` under this model, in `(0, 1]`. Domain: any `f32`, as the
    /// model's own function.
    #[inline]
    pub fn factor(self, eccentricity_deg: f32) -> f32 {
        match self {
            Self::CorticalMagnification => cortical_magnification_factor(eccentricity_deg),
            Self::Reddy2001 => eccentricity_factor(eccentricity_deg),
        }
    }

    /// The eccentricity in deg at which `M(E)` falls to `factor`: 0 when
    /// `factor >= 1`, `+inf` when the model never falls that far. `NaN`
    /// gives `NaN`.
    pub fn eccentricity_for_factor_deg(self, factor: f32) -> f32 {
        match self {
            Self::Reddy2001 => eccentricity_for_factor_deg(factor),
            Self::CorticalMagnification => {
                if factor >= 1.0 {
                    0.0
                } else if factor < cortical_magnification_factor(MAX_ECCENTRICITY_DEG) {
                    f32::INFINITY
                } else {
                    CORTICAL_HALF_ECCENTRICITY_DEG
                        * (factor.powf(-1.0 / CORTICAL_MAGNIFICATION_EXPONENT) - 1.0)
                }
            }
        }
    }

    /// Every model, the default first.
    pub const ALL: [Self; 2] = [Self::CorticalMagnification, Self::Reddy2001];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::CorticalMagnification => "cortical_magnification",
            Self::Reddy2001 => "reddy2001",
        }
    }
}

impl std::str::FromStr for EccentricityModel {
    type Err = String;

    /// Parses a model's [`name`](EccentricityModel::name).
    fn from_str(text: &str) -> Result<Self, String> {
        by_name(&Self::ALL, Self::name, text, "an eccentricity model")
    }
}

/// The slowest retinal velocity of a fixating eye (its drift), deg/s
/// (Kelly 1979): below it, motion changes nothing.
pub const DRIFT_VELOCITY_DEG_PER_S: f32 = 0.15;

/// `G_K(v) = 60 (v_d + 2) / (v + 2)` c/deg: foveal acuity at a retinal
/// velocity in deg/s under Kelly's (1979) spatio-velocity CSF, whose
/// frequency axis scales with its peak `45.9 / (v + 2)`; relative to the
/// drift `v_d` ([`DRIFT_VELOCITY_DEG_PER_S`]). The cut-off of that CSF at
/// any contrast from 0.03 to 1 follows this ratio within 10% (it is
/// slightly higher, so the ratio is the conservative side) from the drift
/// to 200 deg/s. Domain: any `f32`; negative counts as its magnitude,
/// `NaN` as 0; `+inf` gives 0. Output in `[0, 60]`, decreasing,
/// continuous; no floor of its own (a sampled display's is
/// [`crate::csf::Csf::sampled_motion_floor`]).
#[inline]
pub fn kelly_velocity_acuity_cpd(velocity_deg_per_s: f32) -> f32 {
    let v = sanitize_nonnegative(velocity_deg_per_s).max(DRIFT_VELOCITY_DEG_PER_S);
    kelly_velocity_acuity_unchecked(v)
}

/// How acuity falls with retinal velocity: the factor `G(v)` of
/// `H(v, E) = G(v) M(E)`, a scaling of the frequency axis like `M(E)`.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum VelocityModel {
    /// Kelly 1979 ([`kelly_velocity_acuity_cpd`]): a spatio-velocity CSF
    /// measured on travelling gratings, the base of later video metrics.
    #[default]
    Kelly1979,
    /// Reddy 2001, eq. 4 ([`velocity_acuity_cpd`]): a log-linear fit that
    /// reaches 0.1 c/deg at 118 deg/s. The papers' reference.
    Reddy2001,
}

impl VelocityModel {
    /// Every model, the default first.
    pub const ALL: [Self; 2] = [Self::Kelly1979, Self::Reddy2001];

    /// `G(v)` in c/deg under this model; domain as the model's function.
    #[inline]
    pub fn acuity_cpd(self, velocity_deg_per_s: f32) -> f32 {
        match self {
            Self::Kelly1979 => kelly_velocity_acuity_cpd(velocity_deg_per_s),
            Self::Reddy2001 => velocity_acuity_cpd(velocity_deg_per_s),
        }
    }

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kelly1979 => "kelly1979",
            Self::Reddy2001 => "reddy2001",
        }
    }
}

impl std::str::FromStr for VelocityModel {
    type Err = String;

    /// Parses a model's [`name`](VelocityModel::name).
    fn from_str(text: &str) -> Result<Self, String> {
        by_name(&Self::ALL, Self::name, text, "a velocity model")
    }
}

/// `H(v, E) = G(v) M(E)`: the highest resolvable frequency in c/deg
/// (Reddy 2001, eq. 4), before the display's limit. Domain as
/// [`velocity_acuity_cpd`] and [`eccentricity_factor`].
#[inline]
pub fn acuity_cpd(velocity_deg_per_s: f32, eccentricity_deg: f32) -> f32 {
    velocity_acuity_cpd(velocity_deg_per_s) * eccentricity_factor(eccentricity_deg)
}

/// The selection threshold `T = s * min(H, xi)` in c/deg (Reddy 1998,
/// eq. 5 with the global scale factor of §6). `scale` is clamped into
/// `[0, 1]` (`NaN` counts as 1); `display_limit_cpd` is the display's `xi`.
#[inline]
pub fn threshold_cpd(acuity_cpd: f32, display_limit_cpd: f32, scale: f32) -> f32 {
    let s = if scale.is_nan() {
        1.0
    } else {
        scale.clamp(0.0, 1.0)
    };
    s * acuity_cpd.min(display_limit_cpd)
}

/// The velocity in deg/s at which foveal acuity falls to `acuity_cpd`:
/// the inverse of [`velocity_acuity_cpd`]. Returns 0 when `acuity_cpd`
/// is at least 60 (never needed), `+inf` when it is below 0.1 (never
/// reached). `NaN` gives `NaN`.
pub fn velocity_for_acuity_deg_per_s(acuity_cpd: f32) -> f32 {
    if acuity_cpd >= MAX_ACUITY_CPD {
        0.0
    } else if acuity_cpd < MIN_ACUITY_CPD {
        f32::INFINITY
    } else {
        10f32.powf((G_INTERCEPT_CPD - acuity_cpd) / G_SLOPE_CPD_PER_DECADE)
    }
}

/// The eccentricity in deg at which `M(E)` falls to `factor`: the inverse
/// of [`eccentricity_factor`]. Returns 0 when `factor >= 1`, `+inf` when
/// `factor` is below `M(80)` (never reached within the model's data).
/// `NaN` gives `NaN`.
pub fn eccentricity_for_factor_deg(factor: f32) -> f32 {
    if factor >= 1.0 {
        0.0
    } else if factor < eccentricity_factor(ECCENTRICITY_CEILING_DEG) {
        f32::INFINITY
    } else {
        ((M_NUMERATOR / factor).sqrt() - 1.0) / M_SLOPE_PER_DEG
    }
}

#[inline(always)]
pub(crate) fn sanitize_nonnegative(x: f32) -> f32 {
    // `max` returns the other operand for NaN.
    x.abs().max(0.0)
}

/// Which parts of the model may lower an object's detail. Each switches
/// off on its own (Reddy 1998 §3, orthogonality): velocity off means
/// `v = 0`; eccentricity off means `E = 0`; size off means every object is
/// treated as if it filled the display's field of view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Components {
    /// Angular size of the object.
    pub size: bool,
    /// Retinal velocity.
    pub velocity: bool,
    /// Eccentricity from the gaze.
    pub eccentricity: bool,
}

impl Components {
    /// Every component on.
    pub const ALL: Self = Self {
        size: true,
        velocity: true,
        eccentricity: true,
    };
    /// Every component off: only the display limit and `s` remain.
    pub const NONE: Self = Self {
        size: false,
        velocity: false,
        eccentricity: false,
    };
}

impl Default for Components {
    fn default() -> Self {
        Self::ALL
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breakpoints_solve_the_published_pieces() {
        let g = |v: f32| 57.69 - 27.78 * v.log10();
        assert!((g(VELOCITY_FLOOR_DEG_PER_S) - 60.0).abs() < 1e-4);
        assert!((g(VELOCITY_CEILING_DEG_PER_S) - 0.1).abs() < 1e-4);
        let m = |e: f32| 7.49 / (0.3 * e + 1.0).powi(2);
        assert!((m(ECCENTRICITY_FLOOR_DEG) - 1.0).abs() < 1e-6);
        // The rounded published breakpoints are within 0.1% of ours.
        assert!((VELOCITY_FLOOR_DEG_PER_S / 0.825 - 1.0).abs() < 1e-3);
        assert!((VELOCITY_CEILING_DEG_PER_S / 118.3 - 1.0).abs() < 1e-3);
        assert!((ECCENTRICITY_FLOOR_DEG / 5.79 - 1.0).abs() < 1e-3);
    }

    #[test]
    fn published_pieces_hold_away_from_breakpoints() {
        assert_eq!(velocity_acuity_cpd(0.0), 60.0);
        assert_eq!(velocity_acuity_cpd(0.5), 60.0);
        assert!((velocity_acuity_cpd(10.0) - (57.69 - 27.78)).abs() < 1e-4);
        assert_eq!(velocity_acuity_cpd(500.0), 0.1);
        assert_eq!(eccentricity_factor(3.0), 1.0);
        assert!((eccentricity_factor(20.0) - 7.49 / 49.0).abs() < 1e-6);
        assert_eq!(eccentricity_factor(200.0), eccentricity_factor(80.0));
    }

    #[test]
    fn hostile_inputs_stay_in_range() {
        for x in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1.0,
            0.0,
            f32::MAX,
        ] {
            let g = velocity_acuity_cpd(x);
            let m = eccentricity_factor(x);
            assert!((0.1..=60.0).contains(&g), "G({x}) = {g}");
            assert!((0.0..=1.0).contains(&m), "M({x}) = {m}");
        }
        assert_eq!(velocity_acuity_cpd(f32::NAN), 60.0);
        assert_eq!(threshold_cpd(30.0, 12.5, f32::NAN), 12.5);
    }

    #[test]
    fn negative_arguments_count_as_their_magnitude_and_nan_as_zero() {
        for x in [1.0f32, 5.0, 10.0, 42.0, 200.0] {
            assert_eq!(eccentricity_factor(-x), eccentricity_factor(x), "M({x})");
            assert_eq!(velocity_acuity_cpd(-x), velocity_acuity_cpd(x), "G({x})");
            assert_eq!(acuity_cpd(-x, -x), acuity_cpd(x, x), "H({x})");
        }
        assert!(eccentricity_factor(-10.0) < 1.0);
        assert_eq!(eccentricity_factor(f32::NAN), 1.0);
        assert_eq!(
            eccentricity_factor(f32::NEG_INFINITY),
            eccentricity_factor(80.0)
        );
    }

    #[test]
    fn cortical_magnification_follows_its_formula() {
        for e in [0.0f32, 0.5, 3.67, 10.0, 40.0, 90.0, 180.0] {
            let exact = (3.67f64 / (e as f64 + 3.67)).powf(0.604_562);
            let fast = cortical_magnification_factor(e) as f64;
            assert!(
                (fast / exact - 1.0).abs() < 1e-6,
                "M_cm({e}) = {fast}, want {exact}"
            );
        }
        assert_eq!(cortical_magnification_factor(0.0), 1.0);
        assert_eq!(
            cortical_magnification_factor(-10.0),
            cortical_magnification_factor(10.0)
        );
        assert_eq!(cortical_magnification_factor(f32::NAN), 1.0);
        assert_eq!(
            cortical_magnification_factor(1e9),
            cortical_magnification_factor(180.0)
        );
        let mut before = 1.0;
        for i in 0..=180_000 {
            let m = cortical_magnification_factor(i as f32 * 1e-3);
            assert!(m <= before, "M_cm rises at {} deg", i as f32 * 1e-3);
            before = m;
        }
    }

    /// Every `f32` ratio `1 + E / e_2` that `E` in `[0, 180]` deg reaches
    /// (the ratio is non-decreasing in `E`): the factor is within 1e-6 of
    /// the formula, steps down where the ratio's exponent steps up, and
    /// rises nowhere by more than the polynomial's rounding, 3 ulp (4e-7
    /// relative; a step of 1 ulp in the ratio changes the exact factor by
    /// less than half an ulp).
    #[test]
    fn cortical_magnification_is_monotone_and_accurate_at_every_ratio() {
        let last = 1.0 + MAX_ECCENTRICITY_DEG * (1.0 / CORTICAL_HALF_ECCENTRICITY_DEG);
        let mut before = 1.0f32;
        let mut worst = 0.0f64;
        for bits in 1.0f32.to_bits()..=last.to_bits() {
            let ratio = f32::from_bits(bits);
            let m = cortical_factor_of_ratio(ratio);
            assert!(
                m.to_bits() <= before.to_bits() + 3,
                "M_cm rises by more than 3 ulp at ratio {ratio}"
            );
            if ratio > 1.0 && bits & 0x007f_ffff == 0 {
                assert!(m < before, "M_cm does not step down at ratio {ratio}");
            }
            before = m;
            let exact = (ratio as f64).powf(-(CORTICAL_MAGNIFICATION_EXPONENT as f64));
            worst = worst.max((m as f64 / exact - 1.0).abs());
        }
        assert!(worst < 1e-6, "largest relative error {worst}");
    }

    #[test]
    fn kelly_velocity_acuity_scales_with_the_csf_peak() {
        assert_eq!(kelly_velocity_acuity_cpd(0.0), 60.0);
        assert_eq!(kelly_velocity_acuity_cpd(DRIFT_VELOCITY_DEG_PER_S), 60.0);
        assert!((kelly_velocity_acuity_cpd(10.0) - 60.0 * 2.15 / 12.0).abs() < 1e-4);
        assert_eq!(
            kelly_velocity_acuity_cpd(-10.0),
            kelly_velocity_acuity_cpd(10.0)
        );
        assert_eq!(kelly_velocity_acuity_cpd(f32::NAN), 60.0);
        assert_eq!(kelly_velocity_acuity_cpd(f32::INFINITY), 0.0);
        // No collapse where Reddy's fit reaches its floor.
        assert!(kelly_velocity_acuity_cpd(120.0) > 1.0);
        for model in VelocityModel::ALL {
            assert_eq!(model.name().parse::<VelocityModel>(), Ok(model));
        }
        assert!("kelly".parse::<VelocityModel>().is_err());
    }

    #[test]
    fn inverses_round_trip() {
        for v in [1.0f32, 5.0, 42.0, 100.0] {
            let back = velocity_for_acuity_deg_per_s(velocity_acuity_cpd(v));
            assert!((back / v - 1.0).abs() < 1e-4, "{v} -> {back}");
        }
        for e in [6.0f32, 17.0, 40.0, 79.0] {
            let back = eccentricity_for_factor_deg(eccentricity_factor(e));
            assert!((back / e - 1.0).abs() < 1e-4, "{e} -> {back}");
        }
        for model in EccentricityModel::ALL {
            assert_eq!(model.name().parse::<EccentricityModel>(), Ok(model));
        }
        assert!("reddy".parse::<EccentricityModel>().is_err());
        let model = EccentricityModel::CorticalMagnification;
        for e in [0.5f32, 6.0, 17.0, 40.0, 179.0] {
            let back = model.eccentricity_for_factor_deg(model.factor(e));
            assert!((back / e - 1.0).abs() < 1e-3, "{e} -> {back}");
        }
    }
}
