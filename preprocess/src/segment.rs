//! sRGB8 → CIELUV and region growing by ΔE*uv.
//!
//! # Decisions
//! - Colours are converted with `palette` (sRGB8 → linear through its 8-bit
//!   lookup table, then XYZ and CIELUV with the D65 white point, as sRGB
//!   specifies). `L*` is in `0..=100`; ΔE*uv is the Euclidean distance.
//! - **Default threshold: [`DEFAULT_THRESHOLD_DELTA_E`] = 2.3 ΔE*uv**, the
//!   usual just-noticeable difference (Sharma 2003; Mahy et al. 1994 measured
//!   ≈ 2.3 in CIELAB, and CIELUV differences are of the same size near
//!   neutral colours). Below ~1 the threshold would start to pick up the
//!   8-bit quantisation of smooth shading (one sRGB code step is 0.3–1
//!   ΔE*uv), which is not a perceptible feature.
//! - **Region growing**: two 4-neighbours belong to the same region when
//!   their ΔE*uv is *below* the threshold (edge-based growing: a slow
//!   gradient stays one region, a step of at least the threshold separates).
//!   4-connectivity so regions do not leak through diagonal gaps.
//!   Implemented as union-find over pixel indices with path halving, two
//!   linear passes, no recursion (safe for 4096² and beyond), O(pixels).

use palette::{FromColor, Luv, Srgb, white_point::D65};

use crate::Error;

/// The default ΔE*uv threshold; see the module docs.
pub const DEFAULT_THRESHOLD_DELTA_E: f32 = 2.3;

/// A CIELUV image: `L*, u*, v*` per pixel, rows top first.
#[derive(Debug, Clone, PartialEq)]
pub struct LuvImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `[L*, u*, v*]` per pixel, `width * height` entries.
    pub luv: Vec<[f32; 3]>,
}

/// Regions of an image: one label per pixel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Regions {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Region label per pixel, `0..count`, numbered in scan order of each
    /// region's first pixel; [`Regions::NONE`] for excluded pixels.
    pub labels: Vec<u32>,
    /// Number of regions.
    pub count: u32,
}

impl Regions {
    /// Label of pixels that belong to no region (masked out).
    pub const NONE: u32 = u32::MAX;
}

/// Converts one sRGB8 colour to CIELUV `[L*, u*, v*]` (D65).
pub fn srgb8_to_luv(rgb: [u8; 3]) -> [f32; 3] {
    let lin = Srgb::new(rgb[0], rgb[1], rgb[2]).into_linear::<f32>();
    let luv: Luv<D65, f32> = Luv::from_color(lin);
    [luv.l, luv.u, luv.v]
}

/// ΔE*uv: Euclidean distance in CIELUV.
pub fn delta_e_uv(a: [f32; 3], b: [f32; 3]) -> f32 {
    delta_e_uv_sq(a, b).sqrt()
}

#[inline]
fn delta_e_uv_sq(a: [f32; 3], b: [f32; 3]) -> f32 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Converts RGBA8 sRGB pixels (alpha ignored, rows top first, tightly
/// packed) to CIELUV. Errors when the buffer length is not `w * h * 4`.
pub fn rgba_to_luv(width: u32, height: u32, rgba: &[u8]) -> Result<LuvImage, Error> {
    let n = width as usize * height as usize;
    if rgba.len() != n * 4 {
        return Err(Error::Settings {
            field: "rgba",
            message: format!(
                "{} bytes for a {width}x{height} RGBA image (need {})",
                rgba.len(),
                n * 4
            ),
        });
    }
    let mut luv = Vec::with_capacity(n);
    // Rendered images repeat colours (background, flat areas): a one-entry
    // cache skips most conversions.
    let mut last_key = u32::MAX;
    let mut last = [0.0f32; 3];
    for px in rgba.chunks_exact(4) {
        let key = u32::from(px[0]) | (u32::from(px[1]) << 8) | (u32::from(px[2]) << 16);
        if key != last_key {
            last = srgb8_to_luv([px[0], px[1], px[2]]);
            last_key = key;
        }
        luv.push(last);
    }
    Ok(LuvImage { width, height, luv })
}

/// Region growing over 4-neighbours whose ΔE*uv is below
/// `threshold_delta_e`. See the module docs.
pub fn grow_regions(image: &LuvImage, threshold_delta_e: f32) -> Regions {
    let t2 = threshold_delta_e * threshold_delta_e;
    let luv = &image.luv;
    label_components(
        image.width,
        image.height,
        false,
        |_| true,
        |a, b| delta_e_uv_sq(luv[a], luv[b]) < t2,
    )
}

/// Connected components of the pixels where `mask` is true, with 8- or
/// 4-connectivity. Pixels outside the mask get [`Regions::NONE`].
pub fn label_mask(width: u32, height: u32, mask: &[bool], eight_connected: bool) -> Regions {
    assert_eq!(mask.len(), width as usize * height as usize, "mask size");
    label_components(width, height, eight_connected, |i| mask[i], |_, _| true)
}

/// Union-find labelling: pixel `i` takes part when `include(i)`; two
/// neighbouring included pixels join when `joins(i, j)`.
pub(crate) fn label_components(
    width: u32,
    height: u32,
    eight: bool,
    include: impl Fn(usize) -> bool,
    joins: impl Fn(usize, usize) -> bool,
) -> Regions {
    let (w, h) = (width as usize, height as usize);
    let n = w * h;
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut inc = vec![false; n];
    for (i, f) in inc.iter_mut().enumerate() {
        *f = include(i);
    }
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let g = parent[parent[i as usize] as usize];
            parent[i as usize] = g;
            i = g;
        }
        i
    }
    fn union(parent: &mut [u32], a: u32, b: u32) {
        let ra = find(parent, a);
        let rb = find(parent, b);
        if ra != rb {
            // The smaller index becomes the root: roots are first pixels.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            parent[hi as usize] = lo;
        }
    }
    for y in 0..h {
        let row = y * w;
        for x in 0..w {
            let i = row + x;
            if !inc[i] {
                continue;
            }
            if x > 0 && inc[i - 1] && joins(i, i - 1) {
                union(&mut parent, i as u32, (i - 1) as u32);
            }
            if y > 0 {
                let up = i - w;
                if inc[up] && joins(i, up) {
                    union(&mut parent, i as u32, up as u32);
                }
                if eight {
                    if x > 0 && inc[up - 1] && joins(i, up - 1) {
                        union(&mut parent, i as u32, (up - 1) as u32);
                    }
                    if x + 1 < w && inc[up + 1] && joins(i, up + 1) {
                        union(&mut parent, i as u32, (up + 1) as u32);
                    }
                }
            }
        }
    }
    // Second pass: roots are each region's first pixel in scan order, so a
    // root is always met before its members; number roots as they come.
    let mut labels = vec![Regions::NONE; n];
    let mut count = 0u32;
    for i in 0..n {
        if !inc[i] {
            continue;
        }
        let r = find(&mut parent, i as u32) as usize;
        if r == i {
            labels[i] = count;
            count += 1;
        } else {
            labels[i] = labels[r];
        }
    }
    Regions {
        width,
        height,
        labels,
        count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luv_of_white_black_and_red() {
        let w = srgb8_to_luv([255, 255, 255]);
        assert!(
            (w[0] - 100.0).abs() < 0.01 && w[1].abs() < 0.05 && w[2].abs() < 0.05,
            "{w:?}"
        );
        let k = srgb8_to_luv([0, 0, 0]);
        assert!(k[0].abs() < 1e-3);
        // sRGB red: L* 53.24, u* 175.01, v* 37.76 (standard tables).
        let r = srgb8_to_luv([255, 0, 0]);
        assert!(
            (r[0] - 53.24).abs() < 0.05
                && (r[1] - 175.01).abs() < 0.2
                && (r[2] - 37.76).abs() < 0.2,
            "{r:?}"
        );
    }

    #[test]
    fn two_squares_on_a_background_are_three_regions() {
        let (w, h) = (20u32, 10u32);
        let mut rgba = vec![0u8; (w * h * 4) as usize];
        for y in 0..h {
            for x in 0..w {
                let c = if (2..6).contains(&x) && (2..6).contains(&y) {
                    [200, 0, 0]
                } else if (10..15).contains(&x) && (3..8).contains(&y) {
                    [0, 0, 200]
                } else {
                    [30, 30, 30]
                };
                let i = ((y * w + x) * 4) as usize;
                rgba[i..i + 3].copy_from_slice(&c);
            }
        }
        let img = rgba_to_luv(w, h, &rgba).unwrap();
        let r = grow_regions(&img, DEFAULT_THRESHOLD_DELTA_E);
        assert_eq!(r.count, 3);
        assert_eq!(r.labels[0], 0);
    }

    #[test]
    fn a_slow_gradient_is_one_region_a_step_splits_it() {
        let w = 100u32;
        let mut luv: Vec<[f32; 3]> = (0..w).map(|x| [x as f32 * 0.5, 0.0, 0.0]).collect();
        let img = LuvImage {
            width: w,
            height: 1,
            luv: luv.clone(),
        };
        assert_eq!(grow_regions(&img, 2.3).count, 1);
        luv[50][0] += 10.0;
        let img = LuvImage {
            width: w,
            height: 1,
            luv,
        };
        assert_eq!(grow_regions(&img, 2.3).count, 3);
    }

    #[test]
    fn diagonal_pixels_join_only_with_eight_connectivity() {
        let mask = [true, false, false, true];
        assert_eq!(label_mask(2, 2, &mask, true).count, 1);
        assert_eq!(label_mask(2, 2, &mask, false).count, 2);
    }

    #[test]
    fn a_spiral_in_a_large_image_is_labelled_without_recursion() {
        // A long serpentine path: worst case for naive flood fill depth.
        let (w, h) = (1024u32, 1024u32);
        let mut mask = vec![false; (w * h) as usize];
        for y in 0..h as usize {
            for x in 0..w as usize {
                let on_row = y % 2 == 0;
                let link = (y % 4 == 1 && x == w as usize - 1) || (y % 4 == 3 && x == 0);
                mask[y * w as usize + x] = on_row || link;
            }
        }
        let r = label_mask(w, h, &mask, false);
        assert_eq!(r.count, 1);
    }
}
