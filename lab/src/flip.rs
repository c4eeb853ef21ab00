//! The perceptual error of a frame: NVIDIA's FLIP (Andersson et al. 2020,
//! LDR variant) through the `nv-flip` bindings, evaluated at the display's
//! pixels per degree.
//!
//! FLIP compares a test image with a reference and gives each pixel an
//! error in [0, 1] (0: no visible difference). [`flip_rgba`] wraps the
//! C++ library with size checks (the bindings panic on a size mismatch)
//! and returns the mean, the 95th percentile and the colour-mapped error
//! map (magma, as FLIP's own tool writes it).

use anyhow::{Context, bail};

/// The FLIP comparison of one frame with its reference.
#[derive(Debug, Clone)]
pub struct FlipResult {
    /// Mean per-pixel FLIP error, in [0, 1] (the single number FLIP's
    /// authors recommend).
    pub mean: f32,
    /// 95th percentile of the per-pixel error, in [0, 1].
    pub p95: f32,
    /// The error map, colour-mapped with FLIP's magma table: RGB8, rows
    /// top first, `width * 3` bytes per row.
    pub map_rgb: Vec<u8>,
}

/// Drops the alpha channel of an RGBA8 image (`width * height * 4` bytes).
fn rgba_to_rgb(rgba: &[u8]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// FLIP of `test_rgba` against `reference_rgba`, both sRGB RGBA8 images of
/// `width` x `height` pixels (alpha ignored), for a viewer at
/// `pixels_per_degree` pixels per degree of visual angle (> 0).
///
/// Errors when the buffers do not hold `width * height * 4` bytes, an image
/// is empty, or `pixels_per_degree` is not finite and positive. Identical
/// images give exactly 0.
pub fn flip_rgba(
    reference_rgba: &[u8],
    test_rgba: &[u8],
    width: u32,
    height: u32,
    pixels_per_degree: f32,
) -> anyhow::Result<FlipResult> {
    let expected = (width as usize)
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(4))
        .context("image size overflows")?;
    if width == 0 || height == 0 {
        bail!("FLIP needs a non-empty image, got {width}x{height}");
    }
    if reference_rgba.len() != expected || test_rgba.len() != expected {
        bail!(
            "FLIP images must hold {width}x{height}x4 = {expected} bytes, got {} (reference) and {} (test)",
            reference_rgba.len(),
            test_rgba.len()
        );
    }
    if !(pixels_per_degree.is_finite() && pixels_per_degree > 0.0) {
        bail!("pixels per degree must be finite and > 0, got {pixels_per_degree}");
    }
    let reference = nv_flip::FlipImageRgb8::with_data(width, height, &rgba_to_rgb(reference_rgba));
    let test = nv_flip::FlipImageRgb8::with_data(width, height, &rgba_to_rgb(test_rgba));
    let error_map = nv_flip::flip(reference, test, pixels_per_degree);
    let mut pool = nv_flip::FlipPool::from_image(&error_map);
    let mean = pool.mean();
    let p95 = pool.get_percentile(0.95, false);
    let map_rgb = error_map.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    Ok(FlipResult {
        mean: if mean.is_finite() { mean } else { 0.0 },
        p95: if p95.is_finite() { p95 } else { 0.0 },
        map_rgb,
    })
}

/// The `q`-quantile (`q` in [0, 1]) of `values` by linear interpolation
/// between order statistics; NaN for an empty slice. NaNs are ignored.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let pos = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    v[lo] + (v[hi] - v[lo]) * (pos - lo as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic test pattern: colour ramps plus a checkerboard.
    fn pattern(w: u32, h: u32, phase: u32) -> Vec<u8> {
        let mut v = Vec::with_capacity((w * h * 4) as usize);
        for y in 0..h {
            for x in 0..w {
                let check = if ((x + phase) / 4 + y / 4).is_multiple_of(2) {
                    200
                } else {
                    30
                };
                v.extend_from_slice(&[(x * 255 / w) as u8, check, (y * 255 / h) as u8, 255]);
            }
        }
        v
    }

    #[test]
    fn identical_images_give_zero() {
        let a = pattern(64, 48, 0);
        let r = flip_rgba(&a, &a, 64, 48, 20.0).unwrap();
        assert_eq!(r.mean, 0.0);
        assert_eq!(r.p95, 0.0);
        assert_eq!(r.map_rgb.len(), 64 * 48 * 3);
    }

    #[test]
    fn different_images_give_values_in_unit_interval() {
        let a = pattern(64, 48, 0);
        let b = pattern(64, 48, 2);
        let r = flip_rgba(&a, &b, 64, 48, 20.0).unwrap();
        assert!(r.mean > 0.0 && r.mean <= 1.0, "{}", r.mean);
        assert!(r.p95 >= 0.0 && r.p95 <= 1.0, "{}", r.p95);
        // Black against white is the largest difference FLIP knows.
        let black = vec![0u8; 32 * 32 * 4];
        let white = vec![255u8; 32 * 32 * 4];
        let r = flip_rgba(&black, &white, 32, 32, 20.0).unwrap();
        assert!(r.mean > 0.5 && r.mean <= 1.0, "{}", r.mean);
    }

    #[test]
    fn finer_viewing_hides_fine_detail() {
        // The same checkerboard shift seen from farther away (more pixels
        // per degree) is less visible.
        let a = pattern(64, 48, 0);
        let b = pattern(64, 48, 4);
        let near = flip_rgba(&a, &b, 64, 48, 10.0).unwrap().mean;
        let far = flip_rgba(&a, &b, 64, 48, 120.0).unwrap().mean;
        assert!(far < near, "near {near} far {far}");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let a = pattern(8, 8, 0);
        assert!(flip_rgba(&a, &a[..10], 8, 8, 20.0).is_err());
        assert!(flip_rgba(&a, &a, 8, 9, 20.0).is_err());
        assert!(flip_rgba(&[], &[], 0, 0, 20.0).is_err());
        assert!(flip_rgba(&a, &a, 8, 8, f32::NAN).is_err());
    }

    #[test]
    fn quantile_interpolates() {
        assert_eq!(quantile(&[3.0, 1.0, 2.0], 0.5), 2.0);
        assert_eq!(quantile(&[0.0, 10.0], 0.95), 9.5);
        assert!(quantile(&[], 0.5).is_nan());
    }
}
