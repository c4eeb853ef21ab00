//! The acuity image filter (Reddy 2001, Fig. 5): remove from an image every
//! detail the acuity model predicts a viewer cannot see, for one gaze point
//! and one retinal velocity. Pure computation on `f32` pixel buffers; file
//! formats are the command's business (`crate::blur`).
//!
//! Per pixel: its eccentricity `E` from the gaze, the threshold frequency
//! `T = s * min(H(v, E), xi)` c/deg (Reddy 2001 eq. 4 with the display
//! limit `xi`), and a Gaussian blur whose cut-off is `T` (see
//! [`sigma_px_for_cutoff`]). A per-pixel kernel would cost up to thousands
//! of taps per pixel in the far periphery; instead a Gaussian pyramid is
//! built once and each pixel blends the two levels whose blur brackets the
//! one it needs.
//!
//! Geometry: the image is taken as equiangular (pixels evenly spaced in
//! azimuth and elevation, as a wide field of view such as Reddy's 150 x
//! 100 deg must be), and the eccentricity is the true angle between the
//! gaze's and the pixel's directions. The blur is isotropic in pixels, at
//! the finer axis's pixels per degree.

use acuity::{EccentricityModel, VelocityModel};
use rayon::prelude::*;

/// `sqrt(2 ln 2) / (2 pi)`: a Gaussian of standard deviation `K / f`
/// pixels passes half the amplitude at `f` c/px.
const HALF_GAIN_K: f32 = 0.187_390_6;

/// Everything the filter can refuse: the caller's inputs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FoveateError {
    /// The image has no pixels or no channels.
    #[error("the image is empty ({width}x{height} px, {channels} channels)")]
    EmptyImage {
        /// Width, pixels.
        width: usize,
        /// Height, pixels.
        height: usize,
        /// Channels per pixel.
        channels: usize,
    },
    /// The pixel buffer's length does not match the dimensions.
    #[error(
        "the pixel buffer holds {found} values, {width}x{height}x{channels} = {expected} expected"
    )]
    BufferSize {
        /// Width, pixels.
        width: usize,
        /// Height, pixels.
        height: usize,
        /// Channels per pixel.
        channels: usize,
        /// The length the dimensions need.
        expected: usize,
        /// The buffer's length.
        found: usize,
    },
    /// A field of view outside `(0, 360] x (0, 180]` deg or not finite.
    #[error("field of view {h} x {v} deg is not in (0, 360] x (0, 180]")]
    FieldOfView {
        /// Horizontal, deg.
        h: f32,
        /// Vertical, deg.
        v: f32,
    },
    /// The gaze lies outside the image or is not finite.
    #[error("gaze ({x}, {y}) px lies outside the {width}x{height} image")]
    GazeOutside {
        /// Gaze x, pixels from the left edge.
        x: f32,
        /// Gaze y, pixels from the top edge.
        y: f32,
        /// Width, pixels.
        width: usize,
        /// Height, pixels.
        height: usize,
    },
    /// The velocity is negative or not finite.
    #[error("retinal velocity {0} deg/s is not a finite number >= 0")]
    Velocity(f32),
    /// The global scale factor is outside `(0, 1]`.
    #[error("scale factor {0} is not in (0, 1]")]
    Scale(f32),
}

/// An image of `f32` samples, `channels` per pixel, interleaved, rows top
/// first. The filter is linear, so samples should be linear light.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Samples per pixel.
    pub channels: usize,
    /// `width * height * channels` samples.
    pub data: Vec<f32>,
}

impl Image {
    /// Checks that the image is non-empty and its buffer fits.
    pub fn validate(&self) -> Result<(), FoveateError> {
        let (width, height, channels) = (self.width, self.height, self.channels);
        if width == 0 || height == 0 || channels == 0 {
            return Err(FoveateError::EmptyImage {
                width,
                height,
                channels,
            });
        }
        let expected = width * height * channels;
        if self.data.len() != expected {
            return Err(FoveateError::BufferSize {
                width,
                height,
                channels,
                expected,
                found: self.data.len(),
            });
        }
        Ok(())
    }
}

/// The viewing conditions the filter removes detail for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The angles the image subtends, horizontal then vertical, deg.
    pub fov_deg: [f32; 2],
    /// The gaze point, pixels from the top-left corner (a pixel `(x, y)`
    /// spans `[x, x + 1) x [y, y + 1)`); within the image.
    pub gaze_px: [f32; 2],
    /// Retinal velocity of the whole image, deg/s (0: fixating).
    pub velocity_deg_per_s: f32,
    /// Global scale factor `s` in `(0, 1]` (1: remove only what is
    /// imperceptible).
    pub scale: f32,
    /// How acuity falls with eccentricity.
    pub eccentricity_model: EccentricityModel,
    /// How acuity falls with velocity.
    pub velocity_model: VelocityModel,
}

impl View {
    /// Reddy 2001's models (eq. 4), at rest, `s = 1`.
    pub fn reddy(fov_deg: [f32; 2], gaze_px: [f32; 2]) -> Self {
        Self {
            fov_deg,
            gaze_px,
            velocity_deg_per_s: 0.0,
            scale: 1.0,
            eccentricity_model: EccentricityModel::Reddy2001,
            velocity_model: VelocityModel::Reddy2001,
        }
    }

    /// Checks the view against a `width` x `height` image: the field of
    /// view in `(0, 360] x (0, 180]` deg, the gaze within the image, the
    /// velocity finite and `>= 0`, the scale in `(0, 1]`.
    pub fn validate(&self, width: usize, height: usize) -> Result<(), FoveateError> {
        Geometry::new(width, height, self).map(|_| ())
    }
}

/// Standard deviation in pixels of the Gaussian whose cut-off is
/// `cutoff_cpx` c/px on an image already limited to the display's Nyquist
/// frequency of 0.5 c/px.
///
/// Mapping: a Gaussian of standard deviation `sigma` has the frequency
/// response `exp(-2 pi^2 sigma^2 f^2)`; the cut-off is where it passes half
/// the amplitude, `sigma = sqrt(2 ln 2) / (2 pi f) = 0.187 / f` (half
/// amplitude, because at the acuity limit a grating is at threshold: the
/// model's cut-off is where sensitivity has fallen, not a brick wall). The
/// pixels are already a blur with cut-off 0.5 c/px (the display limit), so
/// only the difference is added, in quadrature: `sigma = 0.187
/// sqrt(1/f^2 - 1/0.5^2)`. So `sigma` is 0 at the display limit and
/// continuous across it. Domain: `cutoff_cpx >= 0` (0 gives `+inf`);
/// `NaN` gives 0.
pub fn sigma_px_for_cutoff(cutoff_cpx: f32) -> f32 {
    // NaN and anything at or above the display limit: no blur.
    if cutoff_cpx.is_nan() || cutoff_cpx >= 0.5 {
        return 0.0;
    }
    HALF_GAIN_K * (1.0 / (cutoff_cpx * cutoff_cpx) - 4.0).sqrt()
}

/// Per-image constants of the eccentricity and threshold computation.
#[derive(Clone, Debug)]
struct Geometry {
    /// Pixels per degree of the finer axis.
    ppd: f32,
    /// `s * min(G(v) M(E), xi)` needs `s`, `G(v)` and `xi` (c/deg).
    scale: f32,
    g_cpd: f32,
    xi_cpd: f32,
    model: EccentricityModel,
    /// Per column, `cos(azimuth - gaze azimuth)`.
    cos_daz: Vec<f32>,
    /// Per row, `(cos, sin)` of the elevation.
    el: Vec<(f32, f32)>,
    gaze_el: (f32, f32),
}

impl Geometry {
    fn new(width: usize, height: usize, view: &View) -> Result<Self, FoveateError> {
        let [fh, fv] = view.fov_deg;
        if !(fh > 0.0 && fh <= 360.0 && fv > 0.0 && fv <= 180.0) {
            return Err(FoveateError::FieldOfView { h: fh, v: fv });
        }
        let [gx, gy] = view.gaze_px;
        if !(gx >= 0.0 && gx <= width as f32 && gy >= 0.0 && gy <= height as f32) {
            return Err(FoveateError::GazeOutside {
                x: gx,
                y: gy,
                width,
                height,
            });
        }
        let v = view.velocity_deg_per_s;
        if !(v.is_finite() && v >= 0.0) {
            return Err(FoveateError::Velocity(v));
        }
        if !(view.scale > 0.0 && view.scale <= 1.0) {
            return Err(FoveateError::Scale(view.scale));
        }
        let (deg_per_px_x, deg_per_px_y) = (fh / width as f32, fv / height as f32);
        let az = |x: f32| ((x - 0.5 * width as f32) * deg_per_px_x).to_radians();
        let el = |y: f32| ((0.5 * height as f32 - y) * deg_per_px_y).to_radians();
        let gaze_az = az(gx);
        let cos_daz = (0..width)
            .map(|x| (az(x as f32 + 0.5) - gaze_az).cos())
            .collect();
        let rows = (0..height)
            .map(|y| {
                let e = el(y as f32 + 0.5);
                (e.cos(), e.sin())
            })
            .collect();
        let ge = el(gy);
        // xi = max over axes of px / (2 fov): the finer axis.
        let ppd = (1.0 / deg_per_px_x).max(1.0 / deg_per_px_y);
        Ok(Self {
            ppd,
            scale: view.scale,
            g_cpd: view.velocity_model.acuity_cpd(v),
            xi_cpd: 0.5 * ppd,
            model: view.eccentricity_model,
            cos_daz,
            el: rows,
            gaze_el: (ge.cos(), ge.sin()),
        })
    }

    /// Eccentricity of pixel `(x, y)`, deg.
    fn eccentricity_deg(&self, x: usize, y: usize) -> f32 {
        let (ce, se) = self.el[y];
        let dot = ce * self.gaze_el.0 * self.cos_daz[x] + se * self.gaze_el.1;
        dot.clamp(-1.0, 1.0).acos().to_degrees()
    }

    /// Blur of pixel `(x, y)`, pixels.
    fn sigma_px(&self, x: usize, y: usize) -> f32 {
        let h = self.g_cpd * self.model.factor(self.eccentricity_deg(x, y));
        let t_cpd = self.scale * h.min(self.xi_cpd);
        sigma_px_for_cutoff(t_cpd / self.ppd)
    }
}

/// The blur in pixels the filter applies at each pixel of a `width` x
/// `height` image, row-major (for inspection and tests).
pub fn sigma_map(width: usize, height: usize, view: &View) -> Result<Vec<f32>, FoveateError> {
    let geo = Geometry::new(width, height, view)?;
    let mut out = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            out.push(geo.sigma_px(x, y));
        }
    }
    Ok(out)
}

/// The filtered image: every pixel blurred as [`sigma_px_for_cutoff`] says
/// for its threshold frequency, through a Gaussian pyramid (see
/// [`Pyramid`]). Pixels that need no blur are copied exactly.
pub fn foveate(image: &Image, view: &View) -> Result<Image, FoveateError> {
    image.validate()?;
    let geo = Geometry::new(image.width, image.height, view)?;
    let pyramid = Pyramid::new(image);
    let (w, c) = (image.width, image.channels);
    let mut data = vec![0.0f32; image.data.len()];
    data.par_chunks_mut(w * c).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let sigma = geo.sigma_px(x, y);
            pyramid.sample(x, y, sigma * sigma, &mut row[x * c..(x + 1) * c]);
        }
    });
    Ok(Image {
        width: image.width,
        height: image.height,
        channels: image.channels,
        data,
    })
}

/// Binomial taps of the 2x reduction, centred between two samples
/// (variance 1.25 samples^2; passes 18% at the new Nyquist frequency).
const REDUCE: [f32; 6] = [
    1.0 / 32.0,
    5.0 / 32.0,
    10.0 / 32.0,
    10.0 / 32.0,
    5.0 / 32.0,
    1.0 / 32.0,
];
const REDUCE_VARIANCE: f32 = 1.25;

/// A Gaussian pyramid at half-octave spacing: octave 0 is the image;
/// octave `l + 1` is octave `l` filtered with `REDUCE` and halved in each
/// dimension (edges clamped), down to a single pixel; beside each octave,
/// the octave filtered with `SMOOTH` at its own resolution. Read back at
/// full resolution by bilinear interpolation, octave `l` has a blur of
/// variance `1.25 (4^l - 1) / 3` (the reductions) `+ 4^l / 6` (the
/// bilinear tent; none at `l = 0`) full-resolution pixels^2, its smoothed
/// copy `0.5 * 4^l` more: successive levels about doubling the variance.
///
/// Blend: a pixel that needs a Gaussian of variance `V` (cut-off `f*`,
/// where it passes half the amplitude) blends the two levels whose
/// variances bracket `V` so that the blend too passes exactly half at
/// `f*`: taking each level as a Gaussian, level `i` passes `2^(-var_i /
/// V)` there. A blend of two Gaussians is not a Gaussian: below `f*` it
/// passes more than half, above it falls less steeply than the target
/// (frequencies the model calls invisible anyway, left at reduced
/// contrast); the half-octave spacing keeps that difference small.
pub struct Pyramid<'a> {
    levels: Vec<Level<'a>>,
}

struct Level<'a> {
    image: std::borrow::Cow<'a, Image>,
    /// log2 of the reduction factor.
    octave: u32,
    /// Blur variance read back at full resolution, px^2.
    variance: f32,
}

/// `[1, 2, 1] / 4` along each axis: variance 0.5 samples^2.
const SMOOTH: [f32; 3] = [0.25, 0.5, 0.25];
const SMOOTH_VARIANCE: f32 = 0.5;

impl<'a> Pyramid<'a> {
    /// Builds the pyramid of a valid image (borrowed as its level 0).
    pub fn new(image: &'a Image) -> Self {
        use std::borrow::Cow;
        let mut levels = Vec::new();
        let mut octave = Cow::Borrowed(image);
        let mut l = 0u32;
        loop {
            let p = 4f32.powi(l as i32);
            let base = REDUCE_VARIANCE * (p - 1.0) / 3.0 + if l > 0 { p / 6.0 } else { 0.0 };
            let smoothed = smooth(&octave);
            let next = (octave.width > 1 || octave.height > 1).then(|| reduce(&octave));
            levels.push(Level {
                image: octave,
                octave: l,
                variance: base,
            });
            levels.push(Level {
                image: Cow::Owned(smoothed),
                octave: l,
                variance: base + SMOOTH_VARIANCE * p,
            });
            match next {
                Some(n) => octave = Cow::Owned(n),
                None => break,
            }
            l += 1;
        }
        Self { levels }
    }

    /// Number of levels (two per octave).
    pub fn len(&self) -> usize {
        self.levels.len()
    }

    /// Never: a pyramid has at least the image itself.
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }

    /// Writes into `out` (one value per channel) pixel `(x, y)` blurred by
    /// a Gaussian of variance `var` px^2 (0: the pixel itself; beyond the
    /// top level: the top level), blended as the type's docs say.
    pub fn sample(&self, x: usize, y: usize, var: f32, out: &mut [f32]) {
        if var.is_nan() || var <= 0.0 {
            let base = &self.levels[0].image;
            let i = (y * base.width + x) * base.channels;
            out.copy_from_slice(&base.data[i..i + base.channels]);
            return;
        }
        let top = self.levels.len() - 1;
        let upper = self.levels.partition_point(|l| l.variance < var).min(top);
        if upper == 0 || self.levels[upper].variance <= var {
            self.bilinear(upper, x, y, 1.0, out, false);
            return;
        }
        let lower = upper - 1;
        let gain_lower = (-self.levels[lower].variance / var).exp2();
        let gain_upper = (-self.levels[upper].variance / var).exp2();
        let w = (gain_lower - 0.5) / (gain_lower - gain_upper);
        self.bilinear(lower, x, y, 1.0 - w, out, false);
        self.bilinear(upper, x, y, w, out, true);
    }

    /// `out (+)= weight *` level `l` read at full-resolution pixel `(x, y)`.
    fn bilinear(&self, l: usize, x: usize, y: usize, weight: f32, out: &mut [f32], add: bool) {
        let Level {
            image: level,
            octave,
            ..
        } = &self.levels[l];
        let c = level.channels;
        let inv = 1.0 / (1u64 << octave) as f32;
        let u = ((x as f32 + 0.5) * inv - 0.5).max(0.0);
        let v = ((y as f32 + 0.5) * inv - 0.5).max(0.0);
        let (x0, y0) = (
            (u as usize).min(level.width - 1),
            (v as usize).min(level.height - 1),
        );
        let (x1, y1) = (
            (x0 + 1).min(level.width - 1),
            (y0 + 1).min(level.height - 1),
        );
        let (fx, fy) = (u - x0 as f32, v - y0 as f32);
        let at = |xx: usize, yy: usize| (yy * level.width + xx) * c;
        let (a, b, d, e) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
        let w00 = (1.0 - fx) * (1.0 - fy) * weight;
        let w10 = fx * (1.0 - fy) * weight;
        let w01 = (1.0 - fx) * fy * weight;
        let w11 = fx * fy * weight;
        let data = &level.data;
        for (k, o) in out.iter_mut().enumerate() {
            let s = w00 * data[a + k] + w10 * data[b + k] + w01 * data[d + k] + w11 * data[e + k];
            *o = if add { *o + s } else { s };
        }
    }
}

/// [`SMOOTH`] along rows and columns at the same resolution (edges
/// clamped).
fn smooth(image: &Image) -> Image {
    let (w, h, c) = (image.width, image.height, image.channels);
    let mut rows = vec![0.0f32; w * h * c];
    rows.par_chunks_mut(w * c).enumerate().for_each(|(y, out)| {
        let src = &image.data[y * w * c..(y + 1) * w * c];
        for x in 0..w {
            let (l, r) = (x.saturating_sub(1), (x + 1).min(w - 1));
            for ch in 0..c {
                out[x * c + ch] = SMOOTH[0] * src[l * c + ch]
                    + SMOOTH[1] * src[x * c + ch]
                    + SMOOTH[2] * src[r * c + ch];
            }
        }
    });
    let mut data = vec![0.0f32; w * h * c];
    data.par_chunks_mut(w * c).enumerate().for_each(|(y, out)| {
        let row = |yy: usize| &rows[yy * w * c..(yy + 1) * w * c];
        let (a, b, d) = (row(y.saturating_sub(1)), row(y), row((y + 1).min(h - 1)));
        for i in 0..w * c {
            out[i] = SMOOTH[0] * a[i] + SMOOTH[1] * b[i] + SMOOTH[2] * d[i];
        }
    });
    Image {
        width: w,
        height: h,
        channels: c,
        data,
    }
}

/// One pyramid step: [`REDUCE`] along rows, then along columns, keeping
/// every other sample (edges clamped).
fn reduce(image: &Image) -> Image {
    let (w, h, c) = (image.width, image.height, image.channels);
    let (w2, h2) = (w.div_ceil(2), h.div_ceil(2));
    let mut rows = vec![0.0f32; w2 * h * c];
    rows.par_chunks_mut(w2 * c)
        .enumerate()
        .for_each(|(y, out)| {
            let src = &image.data[y * w * c..(y + 1) * w * c];
            for j in 0..w2 {
                for (t, &k) in REDUCE.iter().enumerate() {
                    let xs = (2 * j + t).saturating_sub(2).min(w - 1);
                    for ch in 0..c {
                        out[j * c + ch] += k * src[xs * c + ch];
                    }
                }
            }
        });
    let mut data = vec![0.0f32; w2 * h2 * c];
    data.par_chunks_mut(w2 * c)
        .enumerate()
        .for_each(|(j, out)| {
            for (t, &k) in REDUCE.iter().enumerate() {
                let ys = (2 * j + t).saturating_sub(2).min(h - 1);
                let src = &rows[ys * w2 * c..(ys + 1) * w2 * c];
                for (o, &s) in out.iter_mut().zip(src) {
                    *o += k * s;
                }
            }
        });
    Image {
        width: w2,
        height: h2,
        channels: c,
        data,
    }
}

#[cfg(test)]
#[path = "foveate_tests.rs"]
mod tests;
