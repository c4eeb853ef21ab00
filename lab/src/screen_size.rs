//! The baseline acuity is compared with: LOD by screen-relative height, as
//! game engines do it (Unity's `LODGroup`).
//!
//! # The measure
//! The **relative screen height** of an object is the height its bounding
//! sphere's diameter would take on screen, as a fraction of the viewport's
//! height, for a perspective camera with vertical field of view `fov_v`:
//!
//! ```text
//! h = (2 r) / (2 d tan(fov_v / 2)) = r / (d tan(fov_v / 2))
//! ```
//!
//! with `r` the sphere's radius and `d` the distance from the eye to its
//! centre (both metres). `2 d tan(fov_v/2)` is the height of the view frustum
//! at distance `d`. Like Unity, this uses the distance to the centre and
//! ignores where on screen the object is; `h` can exceed 1.
//!
//! # The table
//! One threshold per LOD, strictly decreasing and > 0 (values above 1 are
//! allowed, since `h` exceeds 1 for a sphere taller than the view). LOD `i` is used while `h * bias >= thresholds[i]`; the finest LOD whose
//! threshold is met wins. Below the last threshold the object is either
//! kept at the coarsest LOD (the default, so every policy draws the same
//! objects) or culled (Unity's behaviour). `bias` is Unity's
//! `QualitySettings.lodBias`: values above 1 keep finer LODs for longer.
//!
//! # Degenerate input
//! [`ScreenSizeLod::select`] never panics. It returns LOD 0 (full detail, the
//! conservative answer) when the camera is inside or on the sphere
//! (`d <= r`), and whenever the input makes `h` meaningless: NaN or infinite
//! radius or distance, negative radius, field of view not in (0, 180) deg.
//! A zero radius outside the camera gives `h = 0` (coarsest or culled).

#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberate: it is also true for NaN"
)]

/// Default thresholds for four LODs, fractions of the viewport height.
pub const DEFAULT_THRESHOLDS_4: [f64; 4] = [0.6, 0.3, 0.1, 0.03];

/// Ratio between consecutive default thresholds past the fourth.
pub const DEFAULT_THRESHOLD_RATIO: f64 = 0.3;

/// The relative screen height `h = r / (d tan(fov_v / 2))` of a bounding
/// sphere (see the module docs); `radius_m` and `distance_m` in metres (only
/// their ratio matters), `fov_v_deg` the vertical field of view in degrees.
///
/// Returns `f64::INFINITY` when the camera is inside or on the sphere
/// (`distance_m <= radius_m`, with `radius_m >= 0`), and NaN when any input
/// is NaN or infinite, the radius is negative, or the field of view is not in
/// (0, 180) deg.
pub fn relative_height(radius_m: f64, distance_m: f64, fov_v_deg: f64) -> f64 {
    if !(radius_m.is_finite() && distance_m.is_finite() && fov_v_deg.is_finite())
        || radius_m < 0.0
        || !(fov_v_deg > 0.0 && fov_v_deg < 180.0)
    {
        return f64::NAN;
    }
    if distance_m <= radius_m {
        return f64::INFINITY;
    }
    radius_m / distance_m * acuity::display::projection_scale(fov_v_deg)
}

/// The sensible default table for `n_lods` LODs: the first `n` of
/// [`DEFAULT_THRESHOLDS_4`], continued past four by multiplying by
/// [`DEFAULT_THRESHOLD_RATIO`]. Empty for zero LODs.
pub fn default_thresholds(n_lods: usize) -> Vec<f64> {
    thresholds_from(&DEFAULT_THRESHOLDS_4, n_lods)
}

/// A table for `n_lods` LODs from `table` (strictly decreasing, > 0, at
/// least one entry): its first `n` entries, continued past its end by
/// multiplying by [`DEFAULT_THRESHOLD_RATIO`]. Empty for zero LODs.
pub fn thresholds_from(table: &[f64], n_lods: usize) -> Vec<f64> {
    let mut t: Vec<f64> = table.iter().copied().take(n_lods).collect();
    while t.len() < n_lods {
        let last = t.last().copied().unwrap_or(DEFAULT_THRESHOLDS_4[0]);
        t.push(last * DEFAULT_THRESHOLD_RATIO);
    }
    t
}

/// Checks a threshold table as [`ScreenSizeLod::new`] does (finite, > 0,
/// strictly decreasing), and that it has between 1 and
/// [`MAX_TABLE_ENTRIES`] entries.
pub fn check_table(table: &[f64]) -> Result<(), ScreenSizeError> {
    if table.is_empty() || table.len() > MAX_TABLE_ENTRIES {
        return Err(ScreenSizeError::TableLength(table.len()));
    }
    ScreenSizeLod::new(table.to_vec(), 1.0, BelowLast::KeepCoarsest).map(|_| ())
}

/// The most entries a threshold table may have.
pub const MAX_TABLE_ENTRIES: usize = 64;

/// What to do with objects below the last threshold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BelowLast {
    /// Draw them at the coarsest LOD (default; every policy then draws the
    /// same set of objects, so costs compare fairly).
    #[default]
    KeepCoarsest,
    /// Do not draw them (Unity's behaviour).
    Cull,
}

/// The LOD chosen for one object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScreenSizeChoice {
    /// Draw this LOD (0 = finest).
    Lod(usize),
    /// Do not draw the object.
    Culled,
}

impl ScreenSizeChoice {
    /// An order from finest to coarsest: the LOD index, or `n_lods` for
    /// culled.
    pub fn rank(self, n_lods: usize) -> usize {
        match self {
            ScreenSizeChoice::Lod(i) => i,
            ScreenSizeChoice::Culled => n_lods,
        }
    }
}

/// Why a threshold table was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScreenSizeError {
    /// A threshold is not finite and positive.
    #[error("thresholds[{index}] = {value} must be finite and > 0")]
    NotPositive {
        /// Which threshold.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Thresholds must fall strictly from LOD 0 to the coarsest.
    #[error("thresholds[{index}] = {value} must be below thresholds[{}] = {previous}", .index - 1)]
    NotDecreasing {
        /// The threshold that is not below its predecessor.
        index: usize,
        /// Its value.
        value: f64,
        /// The predecessor's value.
        previous: f64,
    },
    /// The bias is not finite and positive.
    #[error("bias = {0} must be finite and > 0")]
    Bias(f64),
    /// A threshold table with no entries or more than [`MAX_TABLE_ENTRIES`].
    #[error("{0} thresholds: a table has 1 to {MAX_TABLE_ENTRIES}")]
    TableLength(usize),
}

/// A Unity-LODGroup-style screen-size policy for one LOD chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ScreenSizeLod {
    thresholds: Vec<f64>,
    bias: f64,
    below_last: BelowLast,
}

impl ScreenSizeLod {
    /// A policy with the given thresholds (relative heights, one per LOD,
    /// strictly decreasing, finite and > 0), `bias` (finite, > 0; 1 = none)
    /// and behaviour below the last threshold.
    pub fn new(
        thresholds: Vec<f64>,
        bias: f64,
        below_last: BelowLast,
    ) -> Result<Self, ScreenSizeError> {
        for (index, &value) in thresholds.iter().enumerate() {
            if !(value.is_finite() && value > 0.0) {
                return Err(ScreenSizeError::NotPositive { index, value });
            }
            if index > 0 && !(value < thresholds[index - 1]) {
                return Err(ScreenSizeError::NotDecreasing {
                    index,
                    value,
                    previous: thresholds[index - 1],
                });
            }
        }
        if !(bias.is_finite() && bias > 0.0) {
            return Err(ScreenSizeError::Bias(bias));
        }
        Ok(ScreenSizeLod {
            thresholds,
            bias,
            below_last,
        })
    }

    /// The default table for `n_lods` LODs ([`default_thresholds`]), bias 1,
    /// keep coarsest.
    pub fn with_defaults(n_lods: usize) -> Self {
        ScreenSizeLod {
            thresholds: default_thresholds(n_lods),
            bias: 1.0,
            below_last: BelowLast::KeepCoarsest,
        }
    }

    /// The same table with another bias; `None` unless `bias` is finite and
    /// > 0.
    pub fn with_bias(&self, bias: f64) -> Option<Self> {
        (bias.is_finite() && bias > 0.0).then(|| ScreenSizeLod {
            bias,
            ..self.clone()
        })
    }

    /// The thresholds, one per LOD.
    pub fn thresholds(&self) -> &[f64] {
        &self.thresholds
    }

    /// The bias.
    pub fn bias(&self) -> f64 {
        self.bias
    }

    /// Behaviour below the last threshold.
    pub fn below_last(&self) -> BelowLast {
        self.below_last
    }

    /// Number of LODs.
    pub fn n_lods(&self) -> usize {
        self.thresholds.len()
    }

    /// The LOD for a bounding sphere of `radius_m` at `distance_m` from the
    /// eye with vertical field of view `fov_v_deg` (see the module docs for
    /// degenerate input).
    pub fn select(&self, radius_m: f64, distance_m: f64, fov_v_deg: f64) -> ScreenSizeChoice {
        self.select_relative_height(relative_height(radius_m, distance_m, fov_v_deg))
    }

    /// The LOD for a relative screen height `h` (before the bias is
    /// applied). NaN gives LOD 0; with no LODs the answer is
    /// [`ScreenSizeChoice::Culled`].
    pub fn select_relative_height(&self, h: f64) -> ScreenSizeChoice {
        let n = self.thresholds.len();
        if n == 0 {
            return ScreenSizeChoice::Culled;
        }
        if h.is_nan() {
            return ScreenSizeChoice::Lod(0);
        }
        let biased = h * self.bias;
        // Thresholds fall strictly, so the met ones form a prefix of the
        // complement: the first met threshold is the finest LOD allowed.
        match self.thresholds.iter().position(|&t| biased >= t) {
            Some(i) => ScreenSizeChoice::Lod(i),
            None => match self.below_last {
                BelowLast::KeepCoarsest => ScreenSizeChoice::Lod(n - 1),
                BelowLast::Cull => ScreenSizeChoice::Culled,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn height_matches_the_formula() {
        // r = 1 at d = 10 with a 90 deg vertical field: frustum half height 10.
        assert!((relative_height(1.0, 10.0, 90.0) - 0.1).abs() < 1e-12);
        assert_eq!(relative_height(1.0, 0.5, 60.0), f64::INFINITY);
        assert!(relative_height(f64::NAN, 1.0, 60.0).is_nan());
        assert!(relative_height(1.0, 2.0, 180.0).is_nan());
        assert!(relative_height(-1.0, 2.0, 60.0).is_nan());
        assert_eq!(relative_height(0.0, 2.0, 60.0), 0.0);
    }

    #[test]
    fn default_table_has_the_stated_values() {
        assert_eq!(default_thresholds(4), DEFAULT_THRESHOLDS_4.to_vec());
        assert_eq!(default_thresholds(2), vec![0.6, 0.3]);
        assert!(default_thresholds(0).is_empty());
        let six = default_thresholds(6);
        assert!((six[5] - 0.03 * 0.3 * 0.3).abs() < 1e-15);
        assert!(ScreenSizeLod::new(six, 1.0, BelowLast::Cull).is_ok());
    }

    #[test]
    fn a_custom_table_is_cut_or_continued_and_checked() {
        let table = [0.6, 0.15, 0.04];
        assert_eq!(thresholds_from(&table, 2), vec![0.6, 0.15]);
        let five = thresholds_from(&table, 5);
        assert!((five[4] - 0.04 * 0.3 * 0.3).abs() < 1e-15, "{five:?}");
        assert!(check_table(&table).is_ok());
        assert!(matches!(
            check_table(&[]),
            Err(ScreenSizeError::TableLength(0))
        ));
        assert!(matches!(
            check_table(&[0.5, 0.5]),
            Err(ScreenSizeError::NotDecreasing { index: 1, .. })
        ));
        let long: Vec<f64> = (0..=MAX_TABLE_ENTRIES)
            .map(|i| 1.0 / (i + 1) as f64)
            .collect();
        assert!(matches!(
            check_table(&long),
            Err(ScreenSizeError::TableLength(_))
        ));
    }

    #[test]
    fn bands_follow_the_table() {
        let p = ScreenSizeLod::with_defaults(4);
        assert_eq!(p.select_relative_height(0.7), ScreenSizeChoice::Lod(0));
        assert_eq!(p.select_relative_height(0.6), ScreenSizeChoice::Lod(0));
        assert_eq!(p.select_relative_height(0.5), ScreenSizeChoice::Lod(1));
        assert_eq!(p.select_relative_height(0.05), ScreenSizeChoice::Lod(3));
        assert_eq!(p.select_relative_height(0.001), ScreenSizeChoice::Lod(3));
        let cull = ScreenSizeLod::new(default_thresholds(4), 1.0, BelowLast::Cull).unwrap();
        assert_eq!(cull.select_relative_height(0.001), ScreenSizeChoice::Culled);
    }

    #[test]
    fn bias_keeps_finer_lods_longer() {
        let p = ScreenSizeLod::with_defaults(4).with_bias(2.0).unwrap();
        assert_eq!(p.select_relative_height(0.3), ScreenSizeChoice::Lod(0));
        assert!(ScreenSizeLod::with_defaults(4).with_bias(0.0).is_none());
    }

    #[test]
    fn camera_inside_and_degenerate_input_give_full_detail() {
        let p = ScreenSizeLod::with_defaults(4);
        assert_eq!(p.select(2.0, 1.0, 33.4), ScreenSizeChoice::Lod(0));
        assert_eq!(p.select(f64::NAN, 1.0, 33.4), ScreenSizeChoice::Lod(0));
        assert_eq!(p.select(1.0, f64::INFINITY, 33.4), ScreenSizeChoice::Lod(0));
        assert_eq!(p.select(1.0, 5.0, 0.0), ScreenSizeChoice::Lod(0));
        assert_eq!(
            ScreenSizeLod::with_defaults(0).select(1.0, 5.0, 30.0),
            ScreenSizeChoice::Culled
        );
    }

    #[test]
    fn bad_tables_are_refused() {
        assert!(matches!(
            ScreenSizeLod::new(vec![0.5, 0.5], 1.0, BelowLast::Cull),
            Err(ScreenSizeError::NotDecreasing { index: 1, .. })
        ));
        assert!(matches!(
            ScreenSizeLod::new(vec![0.5, f64::NAN], 1.0, BelowLast::Cull),
            Err(ScreenSizeError::NotPositive { index: 1, .. })
        ));
        assert!(ScreenSizeLod::new(vec![0.5], f64::NAN, BelowLast::Cull).is_err());
    }

    proptest! {
        #[test]
        fn smaller_height_never_gives_a_finer_lod(
            a in prop::num::f64::ANY,
            b in prop::num::f64::ANY,
            bias in 0.01f64..100.0,
            cull in any::<bool>(),
            n in 0usize..8,
        ) {
            let below = if cull { BelowLast::Cull } else { BelowLast::KeepCoarsest };
            let p = ScreenSizeLod::new(default_thresholds(n), bias, below).unwrap();
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prop_assume!(!lo.is_nan() && !hi.is_nan());
            prop_assert!(p.select_relative_height(lo).rank(n) >= p.select_relative_height(hi).rank(n));
        }

        #[test]
        fn farther_never_gives_a_finer_lod(
            r in 0.0f64..10.0,
            d1 in 0.0f64..1000.0,
            d2 in 0.0f64..1000.0,
            fov in 1.0f64..179.0,
        ) {
            let p = ScreenSizeLod::with_defaults(4);
            let (near, far) = if d1 <= d2 { (d1, d2) } else { (d2, d1) };
            prop_assert!(p.select(r, far, fov).rank(4) >= p.select(r, near, fov).rank(4));
        }

        #[test]
        fn never_panics(r in prop::num::f64::ANY, d in prop::num::f64::ANY, fov in prop::num::f64::ANY) {
            let _ = ScreenSizeLod::with_defaults(4).select(r, d, fov);
        }
    }
}
