use proptest::prelude::*;

use super::*;

/// A vertical grating of `period_px` (values 0..1), one channel.
fn grating(width: usize, height: usize, period_px: f32) -> Image {
    let data = (0..height)
        .flat_map(|_| {
            (0..width)
                .map(move |x| 0.5 + 0.5 * (2.0 * std::f32::consts::PI * x as f32 / period_px).sin())
        })
        .collect();
    Image {
        width,
        height,
        channels: 1,
        data,
    }
}

/// Peak-to-peak amplitude over a window of `half` pixels around `(x, y)`.
fn amplitude(image: &Image, x: usize, y: usize, half: usize) -> f32 {
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for yy in y.saturating_sub(half)..(y + half).min(image.height) {
        for xx in x.saturating_sub(half)..(x + half).min(image.width) {
            let v = image.data[yy * image.width + xx];
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    hi - lo
}

// 1200 px over 150 deg: 8 px/deg, display limit 4 c/deg. The grating's
// 3 px period is 2.7 c/deg: visible at the gaze (T = xi = 4 c/deg), not
// at 70 deg (Reddy's M(70) H = 0.93 c/deg) nor at 110 deg/s (G = 0.98).
const W: usize = 1200;
const H: usize = 100;
const FOV: [f32; 2] = [150.0, 12.5];

#[test]
fn the_gaze_keeps_a_fine_grating_that_the_periphery_loses() {
    let image = grating(W, H, 3.0);
    let view = View::reddy(FOV, [10.0, 50.0]);
    let out = foveate(&image, &view).unwrap();
    // Sampled every 120 deg of phase, the grating spans 0.87.
    let original = amplitude(&image, 10, 50, 4);
    assert!(original > 0.85);
    // At the gaze the pixels are copied exactly.
    for x in 0..20 {
        assert_eq!(out.data[50 * W + x], image.data[50 * W + x], "x = {x}");
    }
    // 70 deg to the right: 560 px.
    let far = amplitude(&out, 570, 50, 4);
    assert!(far < 0.25 * original, "peripheral amplitude {far}");
    // Moving at 110 deg/s even the gaze loses it.
    let moving = View {
        velocity_deg_per_s: 110.0,
        ..view
    };
    let out = foveate(&image, &moving).unwrap();
    let fovea = amplitude(&out, 10, 50, 4);
    assert!(fovea < 0.25 * original, "moving foveal amplitude {fovea}");
}

#[test]
fn a_constant_image_stays_constant() {
    let image = Image {
        width: 333,
        height: 77,
        channels: 3,
        data: [0.2f32, 0.5, 0.9].repeat(333 * 77),
    };
    let view = View {
        velocity_deg_per_s: 40.0,
        ..View::reddy([150.0, 100.0], [100.0, 30.0])
    };
    let out = foveate(&image, &view).unwrap();
    for (i, (&a, &b)) in out.data.iter().zip(&image.data).enumerate() {
        assert!((a - b).abs() < 1e-5, "sample {i}: {a} != {b}");
    }
}

#[test]
fn the_blur_grows_with_eccentricity_and_velocity() {
    let view = View::reddy(FOV, [0.0, 50.0]);
    let still = sigma_map(W, H, &view).unwrap();
    let fast = sigma_map(
        W,
        H,
        &View {
            velocity_deg_per_s: 110.0,
            ..view
        },
    )
    .unwrap();
    let row = 50 * W;
    assert_eq!(still[row], 0.0);
    for x in 1..W {
        assert!(still[row + x] >= still[row + x - 1], "x = {x}");
        assert!(fast[row + x] >= fast[row + x - 1], "x = {x}");
        assert!(fast[row + x] >= still[row + x], "x = {x}");
    }
    assert!(still[row + W - 1] > 1.0);
    assert!(fast[row] > 1.0);
}

#[test]
fn the_pyramid_blur_matches_its_target_variance() {
    // An impulse's second moment after filtering is the blur's variance.
    let (w, h) = (257, 257);
    let mut data = vec![0.0f32; w * h];
    data[128 * w + 128] = 1.0;
    let image = Image {
        width: w,
        height: h,
        channels: 1,
        data,
    };
    let pyramid = Pyramid::new(&image);
    for sigma in [1.0f32, 2.0, 4.0, 8.0, 16.0] {
        let mut out = [0.0];
        let (mut mass, mut second) = (0.0f64, 0.0f64);
        for y in 0..h {
            for x in 0..w {
                pyramid.sample(x, y, sigma * sigma, &mut out);
                let d2 = ((x as f64 - 128.0).powi(2) + (y as f64 - 128.0).powi(2)) / 2.0;
                mass += out[0] as f64;
                second += out[0] as f64 * d2;
            }
        }
        let measured = (second / mass).sqrt();
        assert!((mass - 1.0).abs() < 0.02, "sigma {sigma}: mass {mass}");
        assert!(
            (measured / sigma as f64 - 1.0).abs() < 0.25,
            "sigma {sigma}: measured {measured}"
        );
    }
}

#[test]
fn bad_input_is_refused_with_a_clear_error() {
    let image = grating(16, 8, 4.0);
    let ok = View::reddy([60.0, 30.0], [8.0, 4.0]);
    assert!(foveate(&image, &ok).is_ok());
    let zero_fov = View {
        fov_deg: [0.0, 30.0],
        ..ok
    };
    assert!(matches!(
        foveate(&image, &zero_fov),
        Err(FoveateError::FieldOfView { .. })
    ));
    let outside = View {
        gaze_px: [17.0, 4.0],
        ..ok
    };
    let e = foveate(&image, &outside).unwrap_err();
    assert!(e.to_string().contains("outside the 16x8 image"), "{e}");
    let nan = View {
        velocity_deg_per_s: f32::NAN,
        ..ok
    };
    assert_eq!(
        foveate(&image, &nan).unwrap_err().to_string(),
        "retinal velocity NaN deg/s is not a finite number >= 0"
    );
    let empty = Image {
        width: 0,
        height: 8,
        channels: 3,
        data: vec![],
    };
    assert!(matches!(
        foveate(&empty, &ok),
        Err(FoveateError::EmptyImage { .. })
    ));
    let short = Image {
        data: vec![0.0; 5],
        ..image.clone()
    };
    assert!(matches!(
        foveate(&short, &ok),
        Err(FoveateError::BufferSize { .. })
    ));
    assert!(matches!(
        foveate(&image, &View { scale: 0.0, ..ok }),
        Err(FoveateError::Scale(_))
    ));
}

#[test]
fn a_one_pixel_image_passes_through() {
    let image = Image {
        width: 1,
        height: 1,
        channels: 2,
        data: vec![0.25, 0.75],
    };
    let view = View {
        velocity_deg_per_s: 100.0,
        ..View::reddy([10.0, 10.0], [0.5, 0.5])
    };
    assert_eq!(foveate(&image, &view).unwrap(), image);
}

proptest! {
    #[test]
    fn sigma_is_finite_non_negative_and_falls_with_the_cutoff(
        a in 0.0f32..0.6, b in 0.0f32..0.6,
    ) {
        let (lo, hi) = (a.min(b), a.max(b));
        let (s_lo, s_hi) = (sigma_px_for_cutoff(lo), sigma_px_for_cutoff(hi));
        prop_assert!(s_hi >= 0.0 && s_hi.is_finite());
        prop_assert!(s_lo >= s_hi);
    }

    #[test]
    fn output_stays_within_the_input_range(
        seed in 0u64..1000, v in 0.0f32..200.0, gx in 0.0f32..1.0, gy in 0.0f32..1.0,
    ) {
        let noise = crate::fractal::Fbm { seed, base_period: 4.0, octaves: 3, persistence: 0.5 };
        let (w, h) = (37, 23);
        let image = Image { width: w, height: h, channels: 1, data: noise.grid(w, h) };
        let view = View {
            velocity_deg_per_s: v,
            ..View::reddy([120.0, 80.0], [gx * w as f32, gy * h as f32])
        };
        let out = foveate(&image, &view).unwrap();
        let lo = image.data.iter().cloned().fold(f32::MAX, f32::min);
        let hi = image.data.iter().cloned().fold(f32::MIN, f32::max);
        for &o in &out.data {
            prop_assert!(o.is_finite() && o >= lo - 1e-5 && o <= hi + 1e-5);
        }
    }
}
