//! sRGB8 → CIELUV and region growing by ΔE*uv.
//!
//! # Decisions
//! - Colours are converted as `palette` converts them (sRGB8 → linear
//!   through its 8-bit lookup table, then XYZ and CIELUV with the D65 white
//!   point, as sRGB specifies). `L*` is in `0..=100`; ΔE*uv is the Euclidean
//!   distance. [`srgb8_to_luv`] calls palette; [`rgba_to_luv`] repeats
//!   palette's arithmetic, operation for operation, with its constants
//!   hoisted and a small colour cache, and gives the same bits for all 2²⁴
//!   colours (tested).
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
//!   The label array is the union-find forest itself, turned into labels in
//!   place by the second pass (one allocation per image). Its speed is
//!   measured by `benches/segment.rs` (numbers in `docs/performance.md`).

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
///
/// Gives bit for bit what [`srgb8_to_luv`] gives for every pixel (a test
/// checks all 2²⁴ colours), faster: the same arithmetic without palette's
/// generic layers, and a small direct-mapped cache of converted colours
/// (rendered images repeat colours: background, flat and shaded areas).
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
    let conv = LuvConverter::get();
    let mut cache = ColourCache::new();
    let mut luv = Vec::with_capacity(n);
    // Runs of one colour (background) skip even the cache.
    let mut last_key = u32::MAX;
    let mut last = [0.0f32; 3];
    luv.extend(rgba.chunks_exact(4).map(|px| {
        let key = u32::from(px[0]) | (u32::from(px[1]) << 8) | (u32::from(px[2]) << 16);
        if key != last_key {
            last = cache.get(key, |k| conv.convert(k));
            last_key = key;
        }
        last
    }));
    Ok(LuvImage { width, height, luv })
}

/// A direct-mapped cache from packed sRGB8 (`r | g << 8 | b << 16`) to
/// CIELUV. Keys are 24 bits, so `u32::MAX` marks an empty slot.
struct ColourCache {
    keys: Box<[u32; Self::SLOTS]>,
    values: Box<[[f32; 3]; Self::SLOTS]>,
}

impl ColourCache {
    const BITS: u32 = 12;
    const SLOTS: usize = 1 << Self::BITS;

    fn new() -> Self {
        Self {
            keys: Box::new([u32::MAX; Self::SLOTS]),
            values: Box::new([[0.0; 3]; Self::SLOTS]),
        }
    }

    #[inline]
    fn get(&mut self, key: u32, convert: impl FnOnce(u32) -> [f32; 3]) -> [f32; 3] {
        let slot = (key.wrapping_mul(0x9E37_79B1) >> (32 - Self::BITS)) as usize;
        if self.keys[slot] != key {
            self.keys[slot] = key;
            self.values[slot] = convert(key);
        }
        self.values[slot]
    }
}

/// palette's sRGB8 → CIELUV (D65) conversion with its constants taken out
/// of the per-pixel path; the operations and their order are palette's, so
/// the results are identical (see the exhaustive test).
struct LuvConverter {
    /// sRGB8 code → linear, palette's lookup table.
    linear: [f32; 256],
    /// Linear sRGB → XYZ, row major.
    m: [f32; 9],
    u_ref_prime: f32,
    v_ref_prime: f32,
    kappa: f32,
    epsilon: f32,
}

impl LuvConverter {
    fn get() -> &'static Self {
        static CONVERTER: std::sync::OnceLock<LuvConverter> = std::sync::OnceLock::new();
        CONVERTER.get_or_init(Self::new)
    }

    fn new() -> Self {
        use palette::{LinSrgb, Xyz};
        let linear = std::array::from_fn(|c| Srgb::new(c as u8, 0, 0).into_linear::<f32>().red);
        // Columns of the matrix: the XYZ of the linear primaries (x·1 + 0 + 0
        // is exact).
        let mut m = [0.0f32; 9];
        for (col, rgb) in [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            let xyz: Xyz<D65, f32> = Xyz::from_color(LinSrgb::new(rgb[0], rgb[1], rgb[2]));
            m[col] = xyz.x;
            m[3 + col] = xyz.y;
            m[6 + col] = xyz.z;
        }
        let (wx, wy, wz) = (0.95047f64 as f32, 1.0f32, 1.08883f64 as f32);
        let prime_ref_denom_recip = 1.0 / (wx + 15.0 * wy + 3.0 * wz);
        Self {
            linear,
            m,
            u_ref_prime: 4.0 * wx * prime_ref_denom_recip,
            v_ref_prime: 9.0 * wy * prime_ref_denom_recip,
            kappa: ((29.0f64 / 3.0) as f32).powi(3),
            epsilon: ((6.0f64 / 29.0) as f32).powi(3),
        }
    }

    /// Converts a packed `r | g << 8 | b << 16` colour.
    #[inline]
    fn convert(&self, key: u32) -> [f32; 3] {
        let r = self.linear[(key & 0xff) as usize];
        let g = self.linear[((key >> 8) & 0xff) as usize];
        let b = self.linear[((key >> 16) & 0xff) as usize];
        let m = &self.m;
        let x = m[0] * r + m[1] * g + m[2] * b;
        let y = m[3] * r + m[4] * g + m[5] * b;
        let z = m[6] * r + m[7] * g + m[8] * b;
        let prime_denom = x + 15.0 * y + 3.0 * z;
        if prime_denom == 0.0 {
            return [0.0; 3];
        }
        let recip = 1.0 / prime_denom;
        let u_prime = 4.0 * x * recip;
        let v_prime = 9.0 * y * recip;
        // The white point's Y is 1: y / 1 is y.
        let l = if y > self.epsilon {
            116.0 * y.powf(1.0 / 3.0) - 16.0
        } else {
            self.kappa * y
        };
        [
            l,
            13.0 * l * (u_prime - self.u_ref_prime),
            13.0 * l * (v_prime - self.v_ref_prime),
        ]
    }
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
///
/// One scan in pixel order builds the forest: a pixel that joins a
/// neighbour takes that neighbour's parent (always an earlier pixel), and a
/// second joined neighbour in another tree links the two roots (the smaller
/// index stays the root, so every root is its region's first pixel). A
/// second scan turns parents into labels in place: a parent is always
/// labelled before its children.
pub(crate) fn label_components(
    width: u32,
    height: u32,
    eight: bool,
    include: impl Fn(usize) -> bool,
    joins: impl Fn(usize, usize) -> bool,
) -> Regions {
    let (w, h) = (width as usize, height as usize);
    let n = w * h;
    let mut parent: Vec<u32> = vec![Regions::NONE; n];
    #[inline]
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        loop {
            let p = parent[i as usize];
            if p == i {
                return i;
            }
            let g = parent[p as usize];
            parent[i as usize] = g;
            i = g;
        }
    }
    /// Adds neighbour `q` to pixel `i`'s set, whose current representative
    /// is `p` (`i` itself while it has joined nothing).
    #[inline]
    fn join(parent: &mut [u32], i: u32, p: u32, q: usize) -> u32 {
        let pq = parent[q];
        if p == i {
            return pq;
        }
        if pq == p {
            return p;
        }
        let (ra, rb) = (find(parent, p), find(parent, pq));
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
        lo
    }
    for y in 0..h {
        let row = y * w;
        for x in 0..w {
            let i = row + x;
            if !include(i) {
                continue;
            }
            let iu = i as u32;
            let mut p = iu;
            if x > 0 && include(i - 1) && joins(i, i - 1) {
                p = join(&mut parent, iu, p, i - 1);
            }
            if y > 0 {
                let up = i - w;
                if include(up) && joins(i, up) {
                    p = join(&mut parent, iu, p, up);
                }
                if eight {
                    if x > 0 && include(up - 1) && joins(i, up - 1) {
                        p = join(&mut parent, iu, p, up - 1);
                    }
                    if x + 1 < w && include(up + 1) && joins(i, up + 1) {
                        p = join(&mut parent, iu, p, up + 1);
                    }
                }
            }
            parent[i] = p;
        }
    }
    // Parents into labels, in place: parent[i] <= i, and parent[p] already
    // holds p's label (its root's) when i is reached.
    let mut count = 0u32;
    for i in 0..n {
        let p = parent[i];
        if p == Regions::NONE {
            continue;
        }
        parent[i] = if p as usize == i {
            count += 1;
            count - 1
        } else {
            parent[p as usize]
        };
    }
    Regions {
        width,
        height,
        labels: parent,
        count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_xorshift::XorShiftRng;

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
    fn rgba_to_luv_matches_palette_for_every_colour() {
        // All 2^24 colours in release builds; every 97th in debug builds.
        let step = if cfg!(debug_assertions) { 97 } else { 1 };
        let keys: Vec<u32> = (0u32..1 << 24).step_by(step).collect();
        let rgba: Vec<u8> = keys
            .iter()
            .flat_map(|k| [*k as u8, (k >> 8) as u8, (k >> 16) as u8, 255])
            .collect();
        let img = rgba_to_luv(keys.len() as u32, 1, &rgba).unwrap();
        for (k, got) in keys.iter().zip(&img.luv) {
            let want = srgb8_to_luv([*k as u8, (k >> 8) as u8, (k >> 16) as u8]);
            assert_eq!(
                got.map(f32::to_bits),
                want.map(f32::to_bits),
                "colour {k:06x}: {got:?} vs palette's {want:?}"
            );
        }
    }

    /// Reference labelling: breadth-first flood fill from each unlabelled
    /// pixel in scan order (labels in scan order of first pixels).
    fn flood_fill_reference(
        w: usize,
        h: usize,
        eight: bool,
        include: impl Fn(usize) -> bool,
        joins: impl Fn(usize, usize) -> bool,
    ) -> (Vec<u32>, u32) {
        let mut labels = vec![Regions::NONE; w * h];
        let mut count = 0;
        let mut queue = std::collections::VecDeque::new();
        for s in 0..w * h {
            if !include(s) || labels[s] != Regions::NONE {
                continue;
            }
            labels[s] = count;
            queue.push_back(s);
            while let Some(i) = queue.pop_front() {
                let (x, y) = ((i % w) as isize, (i / w) as isize);
                for (dx, dy) in [
                    (-1, 0),
                    (1, 0),
                    (0, -1),
                    (0, 1),
                    (-1, -1),
                    (1, -1),
                    (-1, 1),
                    (1, 1),
                ]
                .into_iter()
                .take(if eight { 8 } else { 4 })
                {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    // `joins` is asked with the later pixel first, as the
                    // labelling scan does.
                    let (a, b) = if j > i { (j, i) } else { (i, j) };
                    if include(j) && labels[j] == Regions::NONE && joins(a, b) {
                        labels[j] = count;
                        queue.push_back(j);
                    }
                }
            }
            count += 1;
        }
        (labels, count)
    }

    #[test]
    fn labelling_matches_a_flood_fill_on_random_images() {
        let mut rng = XorShiftRng::seed_from_u64(7);
        let mut rnd = move || rng.random::<u32>();
        for case in 0..60 {
            let (w, h) = (1 + rnd() as usize % 40, 1 + rnd() as usize % 40);
            let density = rnd() % 100;
            let mask: Vec<bool> = (0..w * h).map(|_| rnd() % 100 < density).collect();
            for eight in [false, true] {
                let r = label_mask(w as u32, h as u32, &mask, eight);
                let (labels, count) = flood_fill_reference(w, h, eight, |i| mask[i], |_, _| true);
                assert_eq!((r.labels, r.count), (labels, count), "mask case {case}");
            }
            // Few grey levels: many equal neighbours, spirals of joins.
            let levels = 2 + rnd() % 6;
            let luv: Vec<[f32; 3]> = (0..w * h)
                .map(|_| [(rnd() % levels) as f32 * 2.0, 0.0, 0.0])
                .collect();
            let img = LuvImage {
                width: w as u32,
                height: h as u32,
                luv: luv.clone(),
            };
            let r = grow_regions(&img, 2.3);
            let (labels, count) = flood_fill_reference(
                w,
                h,
                false,
                |_| true,
                |a, b| delta_e_uv(luv[a], luv[b]) < 2.3,
            );
            assert_eq!((r.labels, r.count), (labels, count), "image case {case}");
        }
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
