//! Viewpoints on the view sphere and the analysis camera.
//!
//! # Viewpoints
//! The vertices of an octahedron whose faces are each split into `4^L`
//! triangles (edges cut into `n = 2^L` equal parts, flat), projected onto
//! the unit sphere: level 0 → 6, 1 → 18, 2 → 66, 3 → 258 (`4n² + 2`).
//! They are exactly the integer points `(x, y, z)` with `|x|+|y|+|z| = n`,
//! normalised, and are listed in this fixed order: `y` descending (from the
//! +Y pole to the −Y pole), then `x` ascending, then `z` ascending. A
//! viewpoint is the unit direction from the object's centre towards the
//! camera, in the object's own frame.
//!
//! # Camera
//! **Orthographic**, looking at the bounding sphere's centre, with the
//! sphere's diameter exactly filling the square image (`D = resolution`
//! pixels). Orthographic because the runtime converts a c/diam frequency to
//! c/deg by the object's angular size alone (`f / theta`), which is exact
//! for an orthographic view and the small-angle limit of a perspective one;
//! a perspective analysis camera would make the scale depend on an arbitrary
//! analysis distance and vary across the image. Up is +Y unless the view
//! direction is within about 25° of ±Y, then −Z·sign(y) (so the image never
//! flips between neighbouring viewpoints near a pole).

use glam::{Mat4, Vec3};

use crate::Error;

/// The deepest subdivision level accepted (16 386 viewpoints).
pub const MAX_VIEWPOINT_LEVEL: u32 = 6;

/// Number of viewpoints at `level`: `4·4^level + 2`.
pub fn viewpoint_count(level: u32) -> usize {
    4 * 4usize.pow(level) + 2
}

/// The unit viewpoint directions at `level` (0..=[`MAX_VIEWPOINT_LEVEL`]),
/// in the order given in the module docs.
pub fn viewpoints(level: u32) -> Result<Vec<[f32; 3]>, Error> {
    if level > MAX_VIEWPOINT_LEVEL {
        return Err(Error::Settings {
            field: "viewpoint_level",
            message: format!("{level} is above the maximum {MAX_VIEWPOINT_LEVEL}"),
        });
    }
    let n = 1i32 << level;
    let mut out = Vec::with_capacity(viewpoint_count(level));
    for y in (-n..=n).rev() {
        let rem = n - y.abs();
        for x in -rem..=rem {
            let za = rem - x.abs();
            let zs: &[i32] = if za == 0 { &[0] } else { &[-za, za] };
            for &z in zs {
                let v = Vec3::new(x as f32, y as f32, z as f32).normalize();
                out.push(v.into());
            }
        }
    }
    Ok(out)
}

/// The camera for one viewpoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewCamera {
    /// Object (world) to camera space.
    pub view: Mat4,
    /// Camera to clip space (orthographic, wgpu depth 0..1).
    pub proj: Mat4,
    /// `proj * view`.
    pub view_proj: Mat4,
    /// Diameter of the bounding sphere in pixels (= the image size).
    pub sphere_diameter_px: f32,
}

/// The orthographic camera looking along `-direction` at `centre`, fitting a
/// sphere of `radius` (model units, > 0) to a `resolution_px` square image.
pub fn camera_for(
    direction: [f32; 3],
    centre: [f32; 3],
    radius: f32,
    resolution_px: u32,
) -> ViewCamera {
    let d = Vec3::from(direction).try_normalize().unwrap_or(Vec3::Z);
    let c = Vec3::from(centre);
    let r = if radius > 0.0 && radius.is_finite() {
        radius
    } else {
        1.0
    };
    let up = if d.y.abs() < 0.9 {
        Vec3::Y
    } else {
        Vec3::new(0.0, 0.0, -d.y.signum())
    };
    let eye = c + d * (2.0 * r);
    let view = glam::camera::rh::view::look_at_mat4(eye, c, up);
    // The sphere spans view depth r..3r; keep a margin so nothing clips.
    let proj = glam::camera::rh::proj::directx::orthographic(-r, r, -r, r, 0.5 * r, 3.5 * r);
    ViewCamera {
        view,
        proj,
        view_proj: proj * view,
        sphere_diameter_px: resolution_px as f32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_the_octahedron_subdivision() {
        for (level, n) in [(0, 6), (1, 18), (2, 66), (3, 258)] {
            let v = viewpoints(level).unwrap();
            assert_eq!(v.len(), n);
            assert_eq!(viewpoint_count(level), n);
            for p in &v {
                assert!((Vec3::from(*p).length() - 1.0).abs() < 1e-6);
            }
            // All distinct.
            for i in 0..v.len() {
                for j in 0..i {
                    assert!(Vec3::from(v[i]).distance(Vec3::from(v[j])) > 1e-3);
                }
            }
        }
        assert_eq!(viewpoints(0).unwrap()[0], [0.0, 1.0, 0.0]);
        assert!(viewpoints(MAX_VIEWPOINT_LEVEL + 1).is_err());
    }

    #[test]
    fn camera_fits_the_sphere_from_every_level1_viewpoint() {
        let c = [1.0, -2.0, 3.0];
        for d in viewpoints(1).unwrap() {
            let cam = camera_for(d, c, 2.0, 512);
            assert!(cam.view_proj.is_finite());
            let dv = Vec3::from(d);
            // The centre maps to the image centre, mid-depth.
            let p = cam.view_proj.project_point3(Vec3::from(c));
            assert!(p.x.abs() < 1e-5 && p.y.abs() < 1e-5 && p.z > 0.0 && p.z < 1.0);
            // A point on the sphere perpendicular to the view maps to the edge.
            let side = dv.any_orthonormal_vector();
            let q = cam.view_proj.project_point3(Vec3::from(c) + side * 2.0);
            assert!(((q.x * q.x + q.y * q.y).sqrt() - 1.0).abs() < 1e-4);
            // Nearest and farthest points of the sphere are inside the depth range.
            for s in [-2.0, 2.0] {
                let z = cam.view_proj.project_point3(Vec3::from(c) + dv * s).z;
                assert!(z > 0.0 && z < 1.0);
            }
        }
    }
}
