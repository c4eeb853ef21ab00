//! A textured test asset made by code: a UV sphere with texture
//! coordinates and a base-colour texture drawn procedurally. It is the
//! shipped glTF sample (`models/textured_globe.glb`, written by
//! [`textured_globe_glb`]) and the texture tests' object.

use std::sync::Arc;

use crate::render::{Texture, gltf_write};
use crate::{Error, Mesh};

/// Triangles of the shipped sample's mesh (LOD 0).
pub const GLOBE_TRIANGLES: u32 = 2_000;
/// Texture size of the shipped sample, pixels (width; height is half).
pub const GLOBE_TEXTURE_PX: u32 = 256;

/// A UV sphere of radius 1 (model units, centred at the origin, poles on
/// the Y axis) with at least `triangles` triangles, texture coordinates
/// `u` = longitude / 360°, `v` = colatitude / 180° (the seam's vertices are
/// doubled), white vertex colours, smooth normals, and `texture`.
pub fn uv_sphere(triangles: u32, texture: Option<Arc<Texture>>) -> Mesh {
    // Triangles = 2 · nu · (nv - 1) = 4 nv (nv - 1) with nu = 2 nv: the
    // smallest nv with 4 nv (nv - 1) >= triangles.
    let t = f64::from(triangles.max(8));
    let nv = (((1.0 + (1.0 + t).sqrt()) / 2.0).ceil() as u32).max(2);
    let nu = 2 * nv;
    let mut m = Mesh {
        positions: Vec::new(),
        normals: Vec::new(),
        colors: Vec::new(),
        uvs: Vec::new(),
        texture,
        indices: Vec::new(),
        normals_computed: false,
    };
    for j in 0..=nv {
        let theta = std::f64::consts::PI * f64::from(j) / f64::from(nv);
        for i in 0..=nu {
            let phi = std::f64::consts::TAU * f64::from(i) / f64::from(nu);
            let p = [
                (theta.sin() * phi.cos()) as f32,
                theta.cos() as f32,
                (-theta.sin() * phi.sin()) as f32,
            ];
            m.positions.push(p);
            m.normals.push(p);
            m.colors.push([1.0; 3]);
            m.uvs.push([
                (f64::from(i) / f64::from(nu)) as f32,
                (f64::from(j) / f64::from(nv)) as f32,
            ]);
        }
    }
    let id = |i: u32, j: u32| j * (nu + 1) + i;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
            if j > 0 {
                m.indices.extend([a, b, d]);
            }
            if j + 1 < nv {
                m.indices.extend([d, b, c]);
            }
        }
    }
    m
}

/// A texture of `width_px` × `width_px / 2` sRGB texels drawn by code: a
/// checkerboard of `checks` squares around (light and dark, high contrast),
/// tinted by broad colour bands, so it has detail at one fine scale and
/// colour at a coarse one.
pub fn checker_texture(width_px: u32, checks: u32) -> Texture {
    let (w, h) = (width_px.max(2), (width_px / 2).max(1));
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let (u, v) = (f64::from(x) / f64::from(w), f64::from(y) / f64::from(h));
            let check = ((u * f64::from(checks)).floor() + (v * f64::from(checks) / 2.0).floor())
                as i64
                % 2
                == 0;
            let band = 0.5 + 0.5 * (std::f64::consts::TAU * 2.0 * u).sin();
            let base: [f64; 3] = [0.35 + 0.6 * band, 0.55, 0.95 - 0.6 * band];
            let k = if check { 1.0 } else { 0.25 };
            rgba.extend(base.map(|c| (255.0 * c * k).round() as u8));
            rgba.push(255);
        }
    }
    // Sizes and length are right by construction.
    Texture::from_rgba(w, h, rgba, "procedural checker").unwrap_or_else(|_| unreachable!())
}

/// The shipped sample: [`uv_sphere`] of [`GLOBE_TRIANGLES`] with
/// [`checker_texture`] ([`GLOBE_TEXTURE_PX`], 16 checks around) as a GLB
/// with one LOD, node `textured_globe`. Deterministic bytes.
pub fn textured_globe_glb() -> Result<Vec<u8>, Error> {
    let t = Arc::new(checker_texture(GLOBE_TEXTURE_PX, 16));
    gltf_write::write_glb_single("textured_globe", &uv_sphere(GLOBE_TRIANGLES, Some(t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_is_valid_and_near_its_target() {
        let m = uv_sphere(2000, None);
        m.check().unwrap();
        assert!(
            (2000..2400).contains(&m.triangle_count()),
            "{}",
            m.triangle_count()
        );
        let t = Arc::new(checker_texture(64, 8));
        uv_sphere(100, Some(t)).check().unwrap();
    }
}
