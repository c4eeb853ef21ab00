//! Screen-door masks for dithered cross-fades: which fragments of an
//! instance a draw keeps, by a 4x4 ordered-dither threshold per pixel.

/// A screen-door mask on an instance ([`crate::RenderRequest::dither`]): a
/// fragment is kept when the pixel's ordered-dither threshold `t` (one of
/// `k / 16`, `k = 0..16`, from a 4x4 Bayer matrix over pixel positions) is
/// in `[keep_from, keep_below)`. [`DitherMask::fading_in`] and
/// [`DitherMask::fading_out`] at the same fraction split every pixel
/// between two draws; both keep nothing or everything at 0 and 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DitherMask {
    /// Lowest threshold kept, in `[0, 1]`.
    pub keep_from: f32,
    /// Thresholds from this up are dropped, in `[0, 1]`.
    pub keep_below: f32,
}

impl DitherMask {
    /// Keeps every fragment.
    pub const ALL: DitherMask = DitherMask {
        keep_from: 0.0,
        keep_below: 1.0,
    };

    /// The LOD fading in at `fraction` (in `[0, 1]`) of a cross-fade: keeps
    /// the pixels whose threshold is below `fraction`.
    pub fn fading_in(fraction: f32) -> DitherMask {
        DitherMask {
            keep_from: 0.0,
            keep_below: fraction,
        }
    }

    /// The LOD fading out at `fraction` of a cross-fade: keeps the pixels
    /// whose threshold is at or above `fraction`, the complement of
    /// [`DitherMask::fading_in`].
    pub fn fading_out(fraction: f32) -> DitherMask {
        DitherMask {
            keep_from: fraction,
            keep_below: 1.0,
        }
    }
}

impl Default for DitherMask {
    fn default() -> Self {
        Self::ALL
    }
}
