//! The acuity model against the papers' published values (Reddy 1998 §4).

use acuity::Display;
use acuity::acuity::{
    acuity_cpd, eccentricity_factor, eccentricity_for_factor_deg, velocity_acuity_cpd,
    velocity_for_acuity_deg_per_s,
};

fn desktop() -> Display {
    Display::new([1280, 1024], [53.1, 41.1]).unwrap()
}

#[test]
fn desktop_display_limit_is_12_5_cpd() {
    // Reddy 1998 §4: "xi = 12.5 c/deg".
    assert!((desktop().max_frequency_cpd() - 12.5).abs() < 0.05);
}

#[test]
fn detail_can_drop_from_about_17_deg_eccentricity_at_rest() {
    let xi = desktop().max_frequency_cpd();
    let e = eccentricity_for_factor_deg(xi / velocity_acuity_cpd(0.0));
    assert!((e - 17.0).abs() < 0.5, "{e} deg");
    assert!(acuity_cpd(0.0, e - 0.1) > xi && acuity_cpd(0.0, e + 0.1) < xi);
}

#[test]
fn detail_can_drop_from_about_42_deg_per_s_at_the_fovea() {
    let xi = desktop().max_frequency_cpd();
    let v = velocity_for_acuity_deg_per_s(xi);
    assert!((v - 42.0).abs() < 1.0, "{v} deg/s");
    assert!(acuity_cpd(v - 0.5, 0.0) > xi && acuity_cpd(v + 0.5, 0.0) < xi);
}

#[test]
fn at_10_deg_eccentricity_detail_drops_from_about_13_deg_per_s() {
    let xi = desktop().max_frequency_cpd();
    let v = velocity_for_acuity_deg_per_s(xi / eccentricity_factor(10.0));
    assert!((v - 13.0).abs() < 0.5, "{v} deg/s");
}
