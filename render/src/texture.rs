//! Base-colour textures: decoding (PNG, JPEG), the mip chain, wrap modes.
//!
//! A texture multiplies a mesh's vertex colour, as a glTF base-colour
//! texture does; both renderers (the offline pass and scene runs) sample it
//! with the same trilinear filter, so the offline pass sees what a real
//! renderer shows at each on-screen size.
//!
//! # Decisions
//! - **Texels are sRGB8** (glTF's base-colour textures and every `map_Kd`
//!   in practice are sRGB); the GPU format is `Rgba8UnormSrgb`, so sampling
//!   and filtering happen in linear light. Alpha is kept but not drawn
//!   (surfaces are opaque).
//! - **Mipmaps are made on the CPU** ([`Texture::mip_chain`]), once per
//!   texture when it is uploaded: a 2×2 box filter in linear light down to
//!   1×1 (odd sizes take the edge texel twice). No compute or blit pass: the
//!   GL backend on llvmpipe has neither for free, and a few milliseconds per
//!   texture is nothing beside the offline pass.
//! - **Limits**: a decoded texture is at most [`MAX_TEXTURE_SIDE_PX`] on a
//!   side; larger images are refused with an error naming the image, never
//!   allocated. A texture larger than the adapter allows is uploaded from
//!   its first mip level that fits.

use std::path::Path;

use crate::{Error, srgb8_to_linear};

/// Largest accepted texture side, pixels (a 16k texture is 1 GiB of RGBA8
/// with its mips; more is not a base-colour texture but a mistake).
pub const MAX_TEXTURE_SIDE_PX: u32 = 16_384;

/// How texture coordinates outside `[0, 1]` are mapped (glTF's sampler
/// wrap modes; OBJ textures repeat).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// The texture tiles (default).
    #[default]
    Repeat,
    /// The edge texels extend.
    ClampToEdge,
    /// The texture tiles, every other copy mirrored.
    MirroredRepeat,
}

/// A base-colour texture: sRGB8 RGBA texels, rows top first (texture
/// coordinate `v = 0` is the top row, as in glTF).
#[derive(Clone, PartialEq)]
pub struct Texture {
    /// Width, pixels (1..=[`MAX_TEXTURE_SIDE_PX`]).
    pub width: u32,
    /// Height, pixels (1..=[`MAX_TEXTURE_SIDE_PX`]).
    pub height: u32,
    /// `width * height * 4` bytes, sRGB-encoded RGB and linear alpha.
    pub rgba: Vec<u8>,
    /// Wrap mode along `u` and along `v`.
    pub wrap: [Wrap; 2],
    /// Where the texture came from (a file, `image 2 of x.glb`), for
    /// messages.
    pub source: String,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Texture")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("wrap", &self.wrap)
            .field("source", &self.source)
            .finish_non_exhaustive()
    }
}

impl Texture {
    /// Decodes a PNG or JPEG image (the format is read from the bytes).
    /// `source` names it in errors and in [`Texture::source`]; `path` is
    /// the file the error is reported against.
    pub fn decode(bytes: &[u8], path: &Path, source: &str) -> Result<Self, Error> {
        let bad = |message: String| Error::InvalidMesh {
            path: path.to_owned(),
            message: format!("{source}: {message}"),
        };
        let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| bad(format!("cannot read image: {e}")))?;
        if reader.format().is_none() {
            return Err(bad(
                "not a PNG or JPEG image (unrecognised signature)".into()
            ));
        }
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE_PX);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE_PX);
        reader.limits(limits);
        let img = reader
            .decode()
            .map_err(|e| bad(format!("cannot decode image: {e}")))?
            .into_rgba8();
        Self::from_rgba(img.width(), img.height(), img.into_raw(), source).map_err(bad)
    }

    /// A texture from sRGB8 RGBA texels (rows top first), repeating.
    /// Errors when a side is 0 or above [`MAX_TEXTURE_SIDE_PX`] or the byte
    /// count is not `width * height * 4`.
    pub fn from_rgba(width: u32, height: u32, rgba: Vec<u8>, source: &str) -> Result<Self, String> {
        if !(1..=MAX_TEXTURE_SIDE_PX).contains(&width)
            || !(1..=MAX_TEXTURE_SIDE_PX).contains(&height)
        {
            return Err(format!(
                "texture of {width}x{height} pixels; sides must be 1..={MAX_TEXTURE_SIDE_PX}"
            ));
        }
        if rgba.len() != width as usize * height as usize * 4 {
            return Err(format!(
                "texture of {width}x{height} pixels needs {} bytes, got {}",
                width as usize * height as usize * 4,
                rgba.len()
            ));
        }
        Ok(Self {
            width,
            height,
            rgba,
            wrap: [Wrap::Repeat; 2],
            source: source.to_owned(),
        })
    }

    /// The mip chain: level 0 is the texture itself, each next level half
    /// the size (rounded down, at least 1) down to 1×1, each texel the mean
    /// of the 2×2 texels above it in linear light (see the module docs).
    /// Returns `(width, height, rgba)` per level.
    pub fn mip_chain(&self) -> Vec<(u32, u32, Vec<u8>)> {
        let to_linear: Vec<f32> = (0..=255u8).map(srgb8_to_linear).collect();
        let mut levels = vec![(self.width, self.height, self.rgba.clone())];
        while let Some((w, h, px)) = levels.last().filter(|(w, h, _)| *w > 1 || *h > 1) {
            let (w, h) = (*w as usize, *h as usize);
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let mut out = Vec::with_capacity(nw * nh * 4);
            for y in 0..nh {
                let ys = [(2 * y).min(h - 1), (2 * y + 1).min(h - 1)];
                for x in 0..nw {
                    let xs = [(2 * x).min(w - 1), (2 * x + 1).min(w - 1)];
                    let mut sum = [0.0f32; 4];
                    for yy in ys {
                        for xx in xs {
                            let i = (yy * w + xx) * 4;
                            for c in 0..3 {
                                sum[c] += to_linear[px[i + c] as usize];
                            }
                            sum[3] += f32::from(px[i + 3]) / 255.0;
                        }
                    }
                    for (c, s) in sum.iter().enumerate() {
                        let mean = s / 4.0;
                        out.push(if c < 3 {
                            linear_to_srgb8(mean)
                        } else {
                            (mean * 255.0).round() as u8
                        });
                    }
                }
            }
            levels.push((nw as u32, nh as u32, out));
        }
        levels
    }
}

/// Linear intensity in `[0, 1]` to the nearest sRGB8 code value
/// (IEC 61966-2-1; values outside `[0, 1]` are clamped).
pub fn linear_to_srgb8(x: f32) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// Uploads `texture` with its mip chain (from the first level no larger
/// than `max_dim`) and makes its bind group with a trilinear sampler in
/// its wrap modes.
pub(crate) fn bind_group(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layout: &wgpu::BindGroupLayout,
    texture: &Texture,
    max_dim: u32,
) -> wgpu::BindGroup {
    let levels: Vec<(u32, u32, Vec<u8>)> = texture
        .mip_chain()
        .into_iter()
        .skip_while(|(w, h, _)| *w > max_dim || *h > max_dim)
        .collect();
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("base colour"),
        size: wgpu::Extent3d {
            width: levels[0].0,
            height: levels[0].1,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (level, (w, h, rgba)) in levels.iter().enumerate() {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &tex,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 4),
                rows_per_image: Some(*h),
            },
            wgpu::Extent3d {
                width: *w,
                height: *h,
                depth_or_array_layers: 1,
            },
        );
    }
    let address = |w: Wrap| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
    };
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("base colour"),
        address_mode_u: address(texture.wrap[0]),
        address_mode_v: address(texture.wrap[1]),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    let view = tex.create_view(&Default::default());
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("base colour"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_checkerboard_mips_to_its_mean_in_linear_light() {
        // 4x2 black/white checkerboard: every 2x2 box holds two of each.
        let mut rgba = Vec::new();
        for y in 0..2 {
            for x in 0..4 {
                let v = if (x + y) % 2 == 0 { 255 } else { 0 };
                rgba.extend_from_slice(&[v, v, v, 255]);
            }
        }
        let t = Texture::from_rgba(4, 2, rgba, "t").unwrap();
        let mips = t.mip_chain();
        let sizes: Vec<(u32, u32)> = mips.iter().map(|m| (m.0, m.1)).collect();
        assert_eq!(sizes, [(4, 2), (2, 1), (1, 1)]);
        // Linear 0.5 is sRGB 188, not 128 (averaging sRGB codes would give 128).
        assert_eq!(&mips[1].2[..4], &[188, 188, 188, 255]);
        assert_eq!(&mips[2].2[..4], &[188, 188, 188, 255]);
    }

    #[test]
    fn bad_sizes_and_garbage_are_errors() {
        assert!(Texture::from_rgba(0, 1, vec![], "t").is_err());
        assert!(Texture::from_rgba(2, 2, vec![0; 15], "t").is_err());
        let e = Texture::decode(b"not an image", Path::new("x.glb"), "image 0").unwrap_err();
        assert!(e.to_string().contains("image 0"), "{e}");
        // A PNG signature followed by nothing.
        let e = Texture::decode(b"\x89PNG\r\n\x1a\n", Path::new("x.glb"), "image 1").unwrap_err();
        assert!(e.to_string().contains("image 1"), "{e}");
    }

    #[test]
    fn srgb_round_trips() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb8_to_linear(c)), c);
        }
    }
}
