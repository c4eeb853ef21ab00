//! From a rendered frame to the window's pixels: the LOD overlay's
//! colours, RGBA8 to softbuffer's `0RGB` words, and the frame scaled
//! nearest-neighbour into the window, centred with black bars where the
//! aspect ratios differ.

/// The LOD overlay's colours, finest LOD first (LOD 4 and coarser take the
/// last): linear RGB replacing each object's own colours, lit as usual
/// ([`acuity_render::RenderRequest::albedo`]).
pub const OVERLAY_PALETTE: [[f32; 3]; 5] = [
    [0.10, 1.00, 0.10], // LOD 0: green
    [1.00, 0.85, 0.05], // LOD 1: yellow
    [1.00, 0.25, 0.02], // LOD 2: orange
    [1.00, 0.03, 0.03], // LOD 3: red
    [0.90, 0.05, 1.00], // LOD 4 and coarser: magenta
];

/// The overlay's legend, one line, in the order of [`OVERLAY_PALETTE`].
pub const OVERLAY_LEGEND: &str =
    "LOD overlay (O): LOD 0 green, 1 yellow, 2 orange, 3 red, 4 and coarser magenta";

/// Largest window asked for at start, physical pixels: a larger frame
/// starts scaled down to fit (the window may be resized at will).
pub const MAX_START_WINDOW_PX: [u32; 2] = [1600, 1000];

/// The window size to ask for at start for a `frame` of `[width, height]`
/// pixels: the frame's size, scaled down (aspect kept, each side >= 1) to
/// fit [`MAX_START_WINDOW_PX`].
pub fn start_window_size(frame: [u32; 2]) -> [u32; 2] {
    let [w, h] = frame.map(|v| v.max(1));
    let fit = (f64::from(MAX_START_WINDOW_PX[0]) / f64::from(w))
        .min(f64::from(MAX_START_WINDOW_PX[1]) / f64::from(h))
        .min(1.0);
    [w, h].map(|v| ((f64::from(v) * fit).round() as u32).max(1))
}

/// RGBA8 pixels (alpha ignored) as softbuffer's words: `0x00RRGGBB`.
pub fn pack_rgba(rgba: &[u8]) -> Vec<u32> {
    rgba.chunks_exact(4)
        .map(|p| u32::from(p[0]) << 16 | u32::from(p[1]) << 8 | u32::from(p[2]))
        .collect()
}

/// Where a `src` image lands in a `dst` window: `(x, y, width, height)` in
/// window pixels, the largest scaling that fits with the aspect ratio kept
/// (each side at least 1 pixel), centred.
pub fn letterbox_rect(src: [u32; 2], dst: [u32; 2]) -> [u32; 4] {
    let [sw, sh] = src.map(|v| u64::from(v.max(1)));
    let [dw, dh] = dst.map(u64::from);
    // Fit by width unless that is too tall: dw / sw <= dh / sh.
    let (w, h) = if dw * sh <= dh * sw {
        (dw, dw * sh / sw)
    } else {
        (dh * sw / sh, dh)
    };
    let (w, h) = (w.clamp(1, dw.max(1)), h.clamp(1, dh.max(1)));
    [(dw - w.min(dw)) / 2, (dh - h.min(dh)) / 2, w, h].map(|v| v as u32)
}

/// Scales `src` (`src_size` pixels, rows top first) into `dst`
/// (`dst_size`, likewise) nearest-neighbour, letterboxed
/// ([`letterbox_rect`]) on black. `dst` must hold `dst_size` pixels and
/// `src` `src_size` pixels.
pub fn letterbox(src: &[u32], src_size: [u32; 2], dst: &mut [u32], dst_size: [u32; 2]) {
    let [sw, sh] = src_size.map(|v| v as usize);
    let [dw, dh] = dst_size.map(|v| v as usize);
    debug_assert_eq!(src.len(), sw * sh);
    debug_assert_eq!(dst.len(), dw * dh);
    dst.fill(0);
    if sw == 0 || sh == 0 || dw == 0 || dh == 0 {
        return;
    }
    let [x0, y0, w, h] = letterbox_rect(src_size, dst_size).map(|v| v as usize);
    // The source column of each window column (the pixel whose centre is
    // nearest), computed once per frame.
    let columns: Vec<usize> = (0..w)
        .map(|x| ((2 * x + 1) * sw / (2 * w)).min(sw - 1))
        .collect();
    for y in 0..h {
        let sy = ((2 * y + 1) * sh / (2 * h)).min(sh - 1);
        let row = &src[sy * sw..(sy + 1) * sw];
        let out = &mut dst[(y0 + y) * dw + x0..][..w];
        for (o, &sx) in out.iter_mut().zip(&columns) {
            *o = row[sx];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgba_packs_to_0rgb() {
        let words = pack_rgba(&[0x12, 0x34, 0x56, 0xff, 255, 0, 128, 0]);
        assert_eq!(words, vec![0x0012_3456, 0x00ff_0080]);
    }

    #[test]
    fn the_palette_has_a_distinct_dominant_hue_per_lod() {
        for (k, a) in OVERLAY_PALETTE.iter().enumerate() {
            assert!(a.iter().all(|c| (0.0..=1.0).contains(c)));
            for b in &OVERLAY_PALETTE[k + 1..] {
                let d: f32 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
                assert!(d > 0.2, "{a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn letterbox_rects_fit_centre_and_keep_aspect() {
        // Same aspect: the whole window.
        assert_eq!(letterbox_rect([640, 480], [1280, 960]), [0, 0, 1280, 960]);
        // Wider window: bars left and right.
        assert_eq!(letterbox_rect([640, 480], [1000, 480]), [180, 0, 640, 480]);
        // Taller window: bars above and below.
        assert_eq!(letterbox_rect([640, 480], [320, 1000]), [0, 380, 320, 240]);
        // A side that would round to nothing keeps one pixel.
        assert_eq!(letterbox_rect([1000, 10], [5, 5]), [0, 2, 5, 1]);
    }

    #[test]
    fn nearest_neighbour_scaling_repeats_pixels_and_blacks_the_bars() {
        // 2 x 1 source into a 6 x 2 window: 4 x 2 image, 1 px bars.
        let src = [0x00aa_0000, 0x0000_00bb];
        let mut dst = vec![0xdead_beef; 12];
        letterbox(&src, [2, 1], &mut dst, [6, 2]);
        let row = [0, 0xaa_0000, 0xaa_0000, 0xbb, 0xbb, 0];
        assert_eq!(dst[..6], row);
        assert_eq!(dst[6..], row);
        // Downscaling picks the pixel nearest each window pixel's centre.
        let src: Vec<u32> = (0..16).collect();
        let mut dst = vec![0; 4];
        letterbox(&src, [4, 4], &mut dst, [2, 2]);
        assert_eq!(dst, vec![5, 7, 13, 15]);
    }

    #[test]
    fn start_windows_fit_the_limit_with_the_frame_aspect() {
        assert_eq!(start_window_size([640, 480]), [640, 480]);
        assert_eq!(start_window_size([3200, 1000]), [1600, 500]);
        assert_eq!(start_window_size([2000, 2000]), [1000, 1000]);
        assert_eq!(start_window_size([0, 0]), [1, 1]);
    }
}
