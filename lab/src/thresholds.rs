//! The theoretical evaluation of Reddy 1998 §4 for one display: where the
//! display limit `xi` stops being the binding constraint, in eccentricity
//! and in velocity.

use std::fmt;

use acuity::Display;
use acuity::acuity::{
    MAX_ACUITY_CPD, acuity_cpd, eccentricity_factor, eccentricity_for_factor_deg,
    velocity_for_acuity_deg_per_s,
};

/// Eccentricities (deg) of the table in [`ThresholdReport`].
pub const TABLE_ECCENTRICITIES_DEG: [f32; 8] = [0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0];

/// What a display lets the acuity model do.
#[derive(Clone, Debug, PartialEq)]
pub struct ThresholdReport {
    /// The display.
    pub display: Display,
    /// The display limit `xi`, c/deg.
    pub display_limit_cpd: f32,
    /// Eccentricity beyond which detail can drop for a still object, deg
    /// (0 when acuity never exceeds `xi`).
    pub eccentricity_at_rest_deg: f32,
    /// Velocity beyond which detail can drop at the fovea, deg/s.
    pub velocity_at_fovea_deg_per_s: f32,
    /// `(eccentricity deg, velocity deg/s)`: the velocity beyond which detail
    /// can drop at each eccentricity (0 where it can drop at rest).
    pub velocity_by_eccentricity: Vec<(f32, f32)>,
}

impl ThresholdReport {
    /// Evaluates the model against a display.
    pub fn new(display: Display) -> Self {
        let xi = display.max_frequency_cpd();
        let velocity_by_eccentricity = TABLE_ECCENTRICITIES_DEG
            .iter()
            .map(|&e| {
                (
                    e,
                    velocity_for_acuity_deg_per_s(xi / eccentricity_factor(e)),
                )
            })
            .collect();
        Self {
            display,
            display_limit_cpd: xi,
            eccentricity_at_rest_deg: eccentricity_for_factor_deg(xi / MAX_ACUITY_CPD),
            velocity_at_fovea_deg_per_s: velocity_for_acuity_deg_per_s(xi),
            velocity_by_eccentricity,
        }
    }
}

impl fmt::Display for ThresholdReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [w, h] = self.display.resolution_px();
        let [fh, fv] = self.display.fov_deg();
        writeln!(f, "display: {w}x{h} px over {fh:.1}x{fv:.1} deg")?;
        writeln!(f, "display limit xi: {:.2} c/deg", self.display_limit_cpd)?;
        writeln!(
            f,
            "at rest, detail can drop beyond {:.1} deg eccentricity",
            self.eccentricity_at_rest_deg
        )?;
        writeln!(
            f,
            "at the fovea, detail can drop beyond {:.1} deg/s",
            self.velocity_at_fovea_deg_per_s
        )?;
        writeln!(f)?;
        writeln!(
            f,
            "eccentricity_deg  velocity_deg_per_s  acuity_at_rest_cpd"
        )?;
        for &(e, v) in &self.velocity_by_eccentricity {
            writeln!(f, "{e:>16.1}  {v:>18.1}  {:>18.2}", acuity_cpd(0.0, e))?;
        }
        Ok(())
    }
}
