//! Synthetic validation of feature extraction: shapes of known size give
//! frequencies within 5% of the truth.

use FrequencyStatistic::*;
use acuity_preprocess::features::{FeatureSettings, UniqueFeature, unique_features_of};
use acuity_preprocess::frequency::{Feature, FrequencyStatistic};
use acuity_preprocess::segment::{LuvImage, srgb8_to_luv};

const N: u32 = 256;

/// A pair: background everywhere in `a`; `b` has `shape` pixels in red.
fn pair(shape: impl Fn(f32, f32) -> bool) -> (LuvImage, LuvImage) {
    let bg = srgb8_to_luv([20, 20, 20]);
    let fg = srgb8_to_luv([200, 40, 40]);
    let a = LuvImage {
        width: N,
        height: N,
        luv: vec![bg; (N * N) as usize],
    };
    let luv = (0..N * N)
        .map(|i| {
            if shape((i % N) as f32 + 0.5, (i / N) as f32 + 0.5) {
                fg
            } else {
                bg
            }
        })
        .collect();
    (
        a,
        LuvImage {
            width: N,
            height: N,
            luv,
        },
    )
}

/// The shapes of the unique features between `a` and `b` (ΔE*uv 2.3, K
/// Feret directions).
fn unique_features(a: &LuvImage, b: &LuvImage, k: u32) -> Vec<Feature> {
    let settings = FeatureSettings {
        grouping: Default::default(),
        threshold_delta_e: 2.3,
        min_change_delta_e: 1.0,
        feret_directions: k,
        statistic: FrequencyStatistic::Thickness,
    };
    let (features, _) = unique_features_of(a, b, &settings).unwrap();
    features
        .into_iter()
        .map(|f: UniqueFeature| f.shape)
        .collect()
}

/// Every feature's frequency in cycles per pixel under `stat`, ascending.
fn freqs(shape: impl Fn(f32, f32) -> bool, stat: FrequencyStatistic, k: u32) -> Vec<f32> {
    let (a, b) = pair(shape);
    let mut f: Vec<f32> = unique_features(&a, &b, k)
        .iter()
        .map(|x| x.frequency_cpx(stat))
        .collect();
    f.sort_by(f32::total_cmp);
    f
}

fn assert_within(measured: f32, truth: f32, what: &str) {
    let err = (measured - truth).abs() / truth;
    assert!(
        err <= 0.05,
        "{what}: measured {measured}, truth {truth} ({:.1}% off)",
        err * 100.0
    );
}

/// Bar of width `w`, length `l`, long axis at `deg` degrees, centred.
fn bar(w: f32, l: f32, deg: f32) -> impl Fn(f32, f32) -> bool {
    let (s, c) = deg.to_radians().sin_cos();
    move |x, y| {
        let (dx, dy) = (x - 127.3, y - 128.6);
        let u = dx * c + dy * s;
        let v = -dx * s + dy * c;
        u.abs() <= l / 2.0 && v.abs() <= w / 2.0
    }
}

#[test]
fn identical_images_have_no_features() {
    let (a, _) = pair(|_, _| false);
    let f = unique_features(&a, &a.clone(), 8);
    assert!(f.is_empty());
}

/// Half the image made lighter by `delta_l` (L*), the features found with
/// `min_change_delta_e`.
fn half_lighter(delta_l: f32, min_change_delta_e: f32) -> (LuvImage, Vec<UniqueFeature>) {
    let (a, _) = pair(|_, _| false);
    let mut b = a.clone();
    for p in &mut b.luv[..(N * N / 2) as usize] {
        p[0] += delta_l;
    }
    let settings = FeatureSettings {
        grouping: Default::default(),
        threshold_delta_e: 2.3,
        min_change_delta_e,
        feret_directions: 8,
        statistic: FrequencyStatistic::Thickness,
    };
    (a.clone(), unique_features_of(&a, &b, &settings).unwrap().0)
}

#[test]
fn a_faint_change_is_a_feature_with_its_contrast() {
    // A change above the threshold counts; its contrast decides whether it
    // is seen.
    let (a, f) = half_lighter(1.5, 1.0);
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].shape.pixel_count, N * N / 2);
    let y = |l: f32| acuity_preprocess::features::luminance_of_lightness(l);
    let (ya, yb) = (y(a.luv[0][0]), y(a.luv[0][0] + 1.5));
    let want = (yb - ya) / (yb + ya);
    assert!((f[0].luminance_contrast - want).abs() < 1e-4, "{f:?}");
    assert!(f[0].contrast() >= f[0].luminance_contrast);
}

#[test]
fn a_change_within_the_changed_pixel_threshold_is_no_feature() {
    // 0.5 ΔE*uv: below the default 1, a feature with threshold 0.
    assert!(half_lighter(0.5, 1.0).1.is_empty());
    assert_eq!(half_lighter(0.5, 0.0).1.len(), 1);
}

#[test]
fn a_bad_changed_pixel_threshold_is_an_error_naming_it() {
    let (a, _) = pair(|_, _| false);
    for bad in [f32::NAN, -1.0, f32::INFINITY] {
        let settings = FeatureSettings {
            grouping: Default::default(),
            threshold_delta_e: 2.3,
            min_change_delta_e: bad,
            feret_directions: 8,
            statistic: FrequencyStatistic::Thickness,
        };
        let e = unique_features_of(&a, &a, &settings).unwrap_err();
        assert!(e.to_string().contains("min_change_delta_e"), "{e}");
    }
}

#[test]
fn a_disc_of_diameter_d_is_one_over_2d_by_every_statistic() {
    // Rasterisation is exact to about a pixel, so 5% needs d >= 20.
    for d in [20.0f32, 31.0, 64.0, 101.0, 180.0] {
        for stat in [Longest, Shortest, Mean] {
            let f = freqs(|x, y| (x - 127.3).hypot(y - 128.6) <= d / 2.0, stat, 8);
            assert_eq!(f.len(), 1);
            assert_within(f[0], 1.0 / (2.0 * d), &format!("disc {d} {stat:?}"));
        }
    }
}

#[test]
fn a_feature_of_width_w_reports_one_over_2w() {
    for w in [10.0f32, 20.0, 47.0] {
        // A bar of width w (long axis vertical): its width statistic.
        let f = freqs(bar(w, 200.0, 90.0), Shortest, 8);
        assert_eq!(f.len(), 1);
        assert_within(f[0], 1.0 / (2.0 * w), &format!("bar width {w}"));
        // An axis-aligned w x w square: exact width; longest is its diagonal.
        let sq = |x: f32, y: f32| (100.0..100.0 + w).contains(&x) && (90.0..90.0 + w).contains(&y);
        assert_eq!(freqs(sq, Shortest, 8)[0], 1.0 / (2.0 * w));
        assert_within(
            freqs(sq, Longest, 8)[0],
            1.0 / (2.0 * w * 2f32.sqrt()),
            "square diagonal",
        );
    }
}

#[test]
fn bars_at_several_orientations() {
    // Widths are exact to about a pixel after rasterisation: w >= 20 for 5%.
    let (w, l) = (24.0f32, 180.0f32);
    let diag = w.hypot(l);
    // Longest: any orientation (the K = 8 sampling misses the true maximum
    // by at most 1 - cos(11.25 deg) = 1.9%).
    for deg in [
        0.0f32, 10.0, 22.5, 30.0, 45.0, 60.0, 77.0, 90.0, 135.0, 160.0,
    ] {
        let f = freqs(bar(w, l, deg), Longest, 8);
        assert_eq!(f.len(), 1, "{deg}");
        assert_within(
            f[0],
            1.0 / (2.0 * diag),
            &format!("bar longest at {deg} deg"),
        );
    }
    // Shortest (width): orientations whose normal is a sampled direction.
    for deg in [0.0f32, 22.5, 45.0, 67.5, 90.0, 112.5, 135.0, 157.5] {
        let f = freqs(bar(w, l, deg), Shortest, 8);
        assert_within(f[0], 1.0 / (2.0 * w), &format!("bar width at {deg} deg"));
    }
    // Finer sampling (K = 36, 5 deg steps) measures widths at 30/60/80 deg.
    for deg in [30.0f32, 60.0, 80.0] {
        let f = freqs(bar(w, l, deg), Shortest, 36);
        assert_within(
            f[0],
            1.0 / (2.0 * w),
            &format!("bar width at {deg} deg, K=36"),
        );
    }
}

#[test]
fn gratings_of_known_period_give_one_cycle_per_period() {
    for period in [16.0f32, 24.0, 40.0] {
        for deg in [0.0f32, 45.0, 90.0, 135.0] {
            let (s, c) = deg.to_radians().sin_cos();
            let grating = |x: f32, y: f32| ((x * c + y * s) / period).rem_euclid(1.0) < 0.5;
            let f = freqs(grating, Shortest, 8);
            assert!(f.len() >= 4, "{period} {deg}: {} bars", f.len());
            // Bars cut by the image corners are narrower; the median bar is whole.
            let median = f[f.len() / 2];
            assert_within(
                median,
                1.0 / period,
                &format!("grating period {period} at {deg} deg"),
            );
        }
    }
}

#[test]
fn thickness_of_a_disc_is_its_diameter() {
    for d in [20.0f32, 31.0, 64.0, 101.0, 180.0] {
        let f = freqs(|x, y| (x - 127.3).hypot(y - 128.6) <= d / 2.0, Thickness, 8);
        assert_eq!(f.len(), 1);
        assert_within(f[0], 1.0 / (2.0 * d), &format!("disc {d} thickness"));
    }
}

#[test]
fn thickness_of_a_bar_is_its_width_at_any_orientation() {
    // No sampled directions: every orientation, not only K of them.
    for w in [20.0f32, 24.0, 47.0] {
        for deg in [
            0.0f32, 10.0, 22.5, 30.0, 45.0, 60.0, 77.0, 90.0, 135.0, 160.0,
        ] {
            let f = freqs(bar(w, 180.0, deg), Thickness, 8);
            assert_eq!(f.len(), 1, "{w} {deg}");
            assert_within(
                f[0],
                1.0 / (2.0 * w),
                &format!("bar width {w} at {deg} deg"),
            );
        }
    }
}

#[test]
fn thickness_of_thin_bars_is_within_a_pixel() {
    // Discretisation bound for small widths: rasterised slanted edges move
    // by up to a pixel, so the width is within 1 px (exact when aligned).
    for w in [1.0f32, 2.0, 3.0, 5.0, 8.0] {
        for deg in [0.0f32, 90.0] {
            let (a, b) = pair(bar(w, 150.0, deg));
            let f = unique_features(&a, &b, 8);
            assert_eq!(f.len(), 1);
            assert_eq!(f[0].thickness_px, w, "bar width {w} at {deg} deg");
        }
        for deg in [10.0f32, 30.0, 45.0, 77.0, 135.0] {
            let (a, b) = pair(bar(w.max(2.0), 150.0, deg));
            let f = unique_features(&a, &b, 8);
            // A 1 px slanted bar breaks into 8-connected steps; w >= 2 stays whole.
            let t = f.iter().map(|x| x.thickness_px).fold(0.0, f32::max);
            assert!(
                (t - w.max(2.0)).abs() <= 1.0,
                "bar width {w} at {deg} deg: {t}"
            );
        }
    }
}

#[test]
fn a_ring_is_as_thick_as_its_width_though_its_span_is_its_diameter() {
    // The silhouette-sliver case: a thin ring spans the whole object in every
    // direction, so every Feret statistic reports the outer diameter, but
    // its thickness is the ring's width.
    let outer = 200.0f32;
    for w in [20.0f32, 30.0, 45.0] {
        let ring = |x: f32, y: f32| {
            let r = (x - 127.3).hypot(y - 128.6);
            r <= outer / 2.0 && r > outer / 2.0 - w
        };
        let f = freqs(ring, Thickness, 8);
        assert_eq!(f.len(), 1);
        assert_within(f[0], 1.0 / (2.0 * w), &format!("ring width {w}"));
        for stat in [Longest, Shortest, Mean] {
            let f = freqs(ring, stat, 8);
            assert_within(f[0], 1.0 / (2.0 * outer), &format!("ring span {stat:?}"));
        }
    }
    // Thin rings (the realistic sliver): within a pixel of the width.
    for w in [2.0f32, 3.0, 5.0, 8.0] {
        let ring = |x: f32, y: f32| {
            let r = (x - 127.3).hypot(y - 128.6);
            r <= outer / 2.0 && r > outer / 2.0 - w
        };
        let (a, b) = pair(ring);
        let f = unique_features(&a, &b, 8);
        assert_eq!(f.len(), 1, "ring {w}");
        assert!(
            (f[0].thickness_px - w).abs() <= 1.0,
            "ring width {w}: {}",
            f[0].thickness_px
        );
    }
}

#[test]
fn a_region_touching_the_image_border_is_cut_by_it() {
    // The border counts as outside: a disc half off the image is measured
    // by what is on it (its inscribed disc is the half-disc's).
    let d = 100.0f32;
    let f = freqs(|x, y| x.hypot(y - 128.0) <= d / 2.0, Thickness, 8);
    assert_eq!(f.len(), 1);
    // Largest disc inside a half-disc of radius r has diameter r.
    assert_within(f[0], 1.0 / (2.0 * d / 2.0), "half disc at border");
}
