//! Plain test shapes: a UV sphere and a torus, tessellated to a triangle
//! count, one uniform colour. They give scene files simple objects whose
//! LODs are exact tessellations (smooth silhouettes, no noise), beside the
//! bumpy [`crate::lods::procedural_object`].

use crate::{Error, Mesh, lods};

/// Linear RGB of every vertex: a light grey.
const COLOR: [f32; 3] = [0.6, 0.6, 0.6];

/// Minor (tube) radius of [`Shape::Torus`], model units.
pub const TORUS_MINOR_RADIUS: f64 = 0.35;

/// A plain test shape, centred at the origin, axis +Y, model units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Shape {
    /// A UV sphere of radius 1, poles on the Y axis.
    Sphere,
    /// A torus of major radius 1 and minor radius [`TORUS_MINOR_RADIUS`].
    Torus,
}

impl Shape {
    /// Its name: `sphere` or `torus`.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Sphere => "sphere",
            Shape::Torus => "torus",
        }
    }

    /// The shape on the smallest grid with at least `triangles` triangles
    /// (a sphere has at least 6, a torus at least 18). Smooth normals,
    /// deterministic.
    pub fn mesh(self, triangles: u32) -> Mesh {
        let want = f64::from(triangles.max(1));
        let tau = std::f64::consts::TAU;
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut indices = Vec::new();
        match self {
            Shape::Sphere => {
                // Two poles and `rings` rings of `nu` vertices: a fan at each
                // pole and two triangles per quad between rings, 2 nu rings
                // triangles; nu ≈ 2 rings.
                let rings = ((want / 4.0).sqrt().ceil() as u32).max(1);
                let nu = ((want / (2.0 * f64::from(rings))).ceil() as u32).max(3);
                let mut push = |p: [f64; 3]| {
                    let p = p.map(|c| c as f32);
                    positions.push(p);
                    normals.push(p);
                };
                push([0.0, 1.0, 0.0]);
                for r in 1..=rings {
                    let theta = std::f64::consts::PI * f64::from(r) / f64::from(rings + 1);
                    for i in 0..nu {
                        let phi = tau * f64::from(i) / f64::from(nu);
                        push([
                            theta.sin() * phi.cos(),
                            theta.cos(),
                            theta.sin() * phi.sin(),
                        ]);
                    }
                }
                push([0.0, -1.0, 0.0]);
                let south = 1 + rings * nu;
                let id = |r: u32, i: u32| 1 + (r - 1) * nu + i % nu;
                for i in 0..nu {
                    indices.extend_from_slice(&[0, id(1, i + 1), id(1, i)]);
                    indices.extend_from_slice(&[south, id(rings, i), id(rings, i + 1)]);
                }
                for r in 1..rings {
                    for i in 0..nu {
                        let (a, b, c, d) = (id(r, i), id(r, i + 1), id(r + 1, i + 1), id(r + 1, i));
                        indices.extend_from_slice(&[a, b, c, a, c, d]);
                    }
                }
            }
            Shape::Torus => {
                // nu around the axis, nv around the tube, 2 nu nv triangles;
                // nu : nv as the circumferences, 1 : TORUS_MINOR_RADIUS.
                let ratio = 1.0 / TORUS_MINOR_RADIUS;
                let nv = ((want / (2.0 * ratio)).sqrt().ceil() as u32).max(3);
                let nu = ((want / (2.0 * f64::from(nv))).ceil() as u32).max(3);
                for i in 0..nu {
                    let u = tau * f64::from(i) / f64::from(nu);
                    for j in 0..nv {
                        let v = tau * f64::from(j) / f64::from(nv);
                        let ring = 1.0 + TORUS_MINOR_RADIUS * v.cos();
                        positions.push(
                            [ring * u.cos(), TORUS_MINOR_RADIUS * v.sin(), ring * u.sin()]
                                .map(|c| c as f32),
                        );
                        normals.push(
                            [v.cos() * u.cos(), v.sin(), v.cos() * u.sin()].map(|c| c as f32),
                        );
                    }
                }
                let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
                for i in 0..nu {
                    for j in 0..nv {
                        let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                        indices.extend_from_slice(&[a, c, b, a, d, c]);
                    }
                }
            }
        }
        Mesh {
            colors: vec![COLOR; positions.len()],
            positions,
            normals,
            uvs: Vec::new(),
            texture: None,
            indices,
            normals_computed: true,
        }
    }

    /// An LOD chain: the shape tessellated at each target (finest first,
    /// strictly decreasing), checked ([`lods::check_chain`]).
    pub fn lods(self, object: &str, triangle_targets: &[u32]) -> Result<Vec<Mesh>, Error> {
        lods::check_targets_setting(triangle_targets)?;
        let lods: Vec<Mesh> = triangle_targets.iter().map(|&t| self.mesh(t)).collect();
        lods::check_chain(object, &lods)?;
        Ok(lods)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_meet_their_targets_closely_and_are_valid() {
        for shape in [Shape::Sphere, Shape::Torus] {
            for target in [1u32, 80, 320, 3928] {
                let m = shape.mesh(target);
                m.check().unwrap();
                let n = m.triangle_count() as u32;
                assert!(n >= target, "{shape:?} {target}: {n}");
                assert!(
                    target < 20 || n <= target + target / 10,
                    "{shape:?} {target}: {n}"
                );
                assert_eq!(m, shape.mesh(target));
                // Radius 1 (sphere), 1 ± minor radius (torus), from the Y axis.
                for p in &m.positions {
                    let r = f64::from(p[0].hypot(p[2]));
                    match shape {
                        Shape::Sphere => assert!((f64::from(p[1]).hypot(r) - 1.0).abs() < 1e-6),
                        Shape::Torus => assert!(
                            ((r - 1.0).hypot(f64::from(p[1])) - TORUS_MINOR_RADIUS).abs() < 1e-6
                        ),
                    }
                }
            }
        }
    }

    #[test]
    fn a_chain_is_tessellated_per_target() {
        let lods = Shape::Sphere.lods("ball", &[320, 80]).unwrap();
        let counts: Vec<usize> = lods.iter().map(Mesh::triangle_count).collect();
        assert_eq!(counts, [324, 80]);
        assert!(Shape::Torus.lods("ring", &[80, 80]).is_err());
        // Both targets round up to the same grid: not strictly coarser.
        assert!(Shape::Sphere.lods("ball", &[2, 1]).is_err());
    }
}
