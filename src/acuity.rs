//! The visual acuity model: the highest spatial frequency (c/deg) a viewer
//! resolves at a given retinal velocity and eccentricity (Reddy 2001, eq. 4).
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
const G_INTERCEPT: f32 = 57.69;
const G_SLOPE: f32 = 27.78;
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
    (G_INTERCEPT - G_SLOPE * v.log10()).clamp(MIN_ACUITY_CPD, MAX_ACUITY_CPD)
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
    let d = 0.3 * e + 1.0;
    (7.49 / (d * d)).min(1.0)
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
        10f32.powf((G_INTERCEPT - acuity_cpd) / G_SLOPE)
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
        ((7.49 / factor).sqrt() - 1.0) / 0.3
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
        let g = |v: f32| G_INTERCEPT - G_SLOPE * v.log10();
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
    fn inverses_round_trip() {
        for v in [1.0f32, 5.0, 42.0, 100.0] {
            let back = velocity_for_acuity_deg_per_s(velocity_acuity_cpd(v));
            assert!((back / v - 1.0).abs() < 1e-4, "{v} -> {back}");
        }
        for e in [6.0f32, 17.0, 40.0, 79.0] {
            let back = eccentricity_for_factor_deg(eccentricity_factor(e));
            assert!((back / e - 1.0).abs() < 1e-4, "{e} -> {back}");
        }
    }
}
