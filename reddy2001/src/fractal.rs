//! Seeded fractal noise (fBm over value noise): the procedural heightfield
//! of `acuity terrain` and the photo-like test image of `acuity blur`.
//!
//! Natural terrain and natural images both have roughly `1/f` amplitude
//! spectra; summing octaves of smooth noise, each twice the frequency and
//! `persistence` times the amplitude of the one before, gives that shape
//! (persistence 0.5 is `1/f`). Deterministic: the same seed gives the same
//! values on every machine (integer hashing, no global state).

/// Parameters of fractal noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fbm {
    /// Seed; different seeds give unrelated fields.
    pub seed: u64,
    /// Period of the coarsest octave, in samples (> 0).
    pub base_period: f32,
    /// Number of octaves (1 to 24).
    pub octaves: u32,
    /// Amplitude ratio between successive octaves, in `(0, 1)`.
    pub persistence: f32,
}

impl Fbm {
    /// The noise at sample `(x, y)`: roughly in `[-1, 1]` (the octaves'
    /// amplitudes sum to 1).
    pub fn at(&self, x: f32, y: f32) -> f32 {
        let mut freq = 1.0 / self.base_period.max(1e-6);
        let mut amp = 1.0;
        let mut sum = 0.0;
        let mut norm = 0.0;
        for octave in 0..self.octaves.clamp(1, 24) {
            let salt = self
                .seed
                .wrapping_add(u64::from(octave).wrapping_mul(0x9E37_79B9));
            sum += amp * value_noise(x * freq, y * freq, salt);
            norm += amp;
            amp *= self.persistence;
            freq *= 2.0;
        }
        sum / norm
    }

    /// A `width` x `height` grid of [`Fbm::at`], row-major.
    pub fn grid(&self, width: usize, height: usize) -> Vec<f32> {
        let mut out = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                out.push(self.at(x as f32, y as f32));
            }
        }
        out
    }
}

/// Smoothly interpolated lattice noise in `[-1, 1]`.
fn value_noise(x: f32, y: f32, salt: u64) -> f32 {
    let (xf, yf) = (x.floor(), y.floor());
    let (ix, iy) = (xf as i64, yf as i64);
    let (tx, ty) = (smooth(x - xf), smooth(y - yf));
    let v = |dx: i64, dy: i64| lattice(ix + dx, iy + dy, salt);
    let top = v(0, 0) + (v(1, 0) - v(0, 0)) * tx;
    let bottom = v(0, 1) + (v(1, 1) - v(0, 1)) * tx;
    top + (bottom - top) * ty
}

fn smooth(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// A hash of a lattice point to `[-1, 1]` (SplitMix64's finaliser).
fn lattice(x: i64, y: i64, salt: u64) -> f32 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ salt.wrapping_mul(0x1656_67B1_9E37_79F9);
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^= h >> 31;
    (h >> 40) as f32 / (1u64 << 23) as f32 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_deterministic_bounded_and_seeded() {
        let f = Fbm {
            seed: 7,
            base_period: 32.0,
            octaves: 6,
            persistence: 0.5,
        };
        let a = f.grid(40, 30);
        assert_eq!(a, f.grid(40, 30));
        assert!(a.iter().all(|v| v.is_finite() && v.abs() <= 1.0));
        let spread =
            a.iter().cloned().fold(f32::MIN, f32::max) - a.iter().cloned().fold(f32::MAX, f32::min);
        assert!(spread > 0.2, "flat noise: spread {spread}");
        let b = Fbm { seed: 8, ..f }.grid(40, 30);
        assert_ne!(a, b);
    }
}
