//! Where a scene's objects stand: one explicit transform, or `count` copies
//! at seeded random positions inside a box.
//!
//! Copies are drawn from an in-tree SplitMix64 generator (not `rand`), so a
//! seed gives the same placements on every platform and every version of
//! acuity's dependencies. Copy `i` of a seed is always the same, whatever
//! `count` is: raising `count` adds copies without moving the others.

use glam::{DMat4, DQuat, DVec3};

use crate::path::orientation_from_deg;

/// One concrete instance of an object in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Position of the mesh's origin in world space, metres.
    pub position_m: DVec3,
    /// Rotation of the mesh (object-to-world).
    pub rotation: DQuat,
    /// Uniform scale, world metres per mesh unit (> 0).
    pub scale: f64,
}

impl Placement {
    /// The object-to-world matrix: scale, then rotate, then translate.
    pub fn to_matrix(&self) -> DMat4 {
        DMat4::from_scale_rotation_translation(
            DVec3::splat(self.scale),
            self.rotation,
            self.position_m,
        )
    }

    /// A point given in mesh units, in world space (metres).
    pub fn transform_point(&self, mesh_point: DVec3) -> DVec3 {
        self.position_m + self.rotation * (mesh_point * self.scale)
    }
}

/// One explicit placement from a scene file (`transform = { ... }`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Position, metres.
    pub position_m: DVec3,
    /// Yaw, pitch, roll in degrees, composed as in [`crate::path`].
    pub rotation_deg: [f64; 3],
    /// Uniform scale (> 0).
    pub scale: f64,
}

/// Seeded random copies inside an axis-aligned box (`copies = { ... }`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Copies {
    /// Number of copies (>= 1).
    pub count: u32,
    /// Seed of the generator.
    pub seed: u64,
    /// Lower corner of the box the positions are drawn from, metres.
    pub volume_min_m: DVec3,
    /// Upper corner (each component >= the lower corner's), metres.
    pub volume_max_m: DVec3,
    /// Draw a uniformly random rotation for each copy (else identity).
    pub random_rotation: bool,
    /// Uniform scale of every copy (> 0).
    pub scale: f64,
}

/// How an object is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlacementSpec {
    /// One instance.
    Transform(Transform),
    /// Many seeded instances.
    Copies(Copies),
}

impl PlacementSpec {
    /// Number of instances this spec makes.
    pub fn count(&self) -> usize {
        match self {
            PlacementSpec::Transform(_) => 1,
            PlacementSpec::Copies(c) => c.count as usize,
        }
    }

    /// Instance `index` (`0..count()`), or `None` past the end.
    pub fn instance(&self, index: usize) -> Option<Placement> {
        match self {
            PlacementSpec::Transform(t) if index == 0 => Some(Placement {
                position_m: t.position_m,
                rotation: orientation_from_deg(
                    t.rotation_deg[0],
                    t.rotation_deg[1],
                    t.rotation_deg[2],
                ),
                scale: t.scale,
            }),
            PlacementSpec::Transform(_) => None,
            PlacementSpec::Copies(c) if index < c.count as usize => Some(copy_at(c, index as u64)),
            PlacementSpec::Copies(_) => None,
        }
    }

    /// All instances, in index order. Deterministic for a given spec.
    pub fn expand(&self) -> Vec<Placement> {
        (0..self.count()).filter_map(|i| self.instance(i)).collect()
    }
}

/// Copy `index` of `copies`: its own generator stream, seeded from the seed
/// and the index, so copies do not depend on each other.
fn copy_at(copies: &Copies, index: u64) -> Placement {
    let mut rng = SplitMix64::new(
        copies
            .seed
            .wrapping_add(index.wrapping_mul(0xD6E8_FEB8_6659_FD93)),
    );
    let lo = copies.volume_min_m;
    let hi = copies.volume_max_m;
    let position_m = DVec3::new(
        lo.x + (hi.x - lo.x) * rng.next_f64(),
        lo.y + (hi.y - lo.y) * rng.next_f64(),
        lo.z + (hi.z - lo.z) * rng.next_f64(),
    );
    let rotation = if copies.random_rotation {
        uniform_rotation(rng.next_f64(), rng.next_f64(), rng.next_f64())
    } else {
        DQuat::IDENTITY
    };
    Placement {
        position_m,
        rotation,
        scale: copies.scale,
    }
}

/// Uniformly distributed rotation from three uniforms in [0, 1) (Shoemake 1992).
fn uniform_rotation(u1: f64, u2: f64, u3: f64) -> DQuat {
    use std::f64::consts::TAU;
    let a = (1.0 - u1).sqrt();
    let b = u1.sqrt();
    DQuat::from_xyzw(
        a * (TAU * u2).sin(),
        a * (TAU * u2).cos(),
        b * (TAU * u3).sin(),
        b * (TAU * u3).cos(),
    )
    .normalize()
}

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, fast, and fixed forever here.
struct SplitMix64(u64);

impl SplitMix64 {
    fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 bits.
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn copies(count: u32, seed: u64) -> PlacementSpec {
        PlacementSpec::Copies(Copies {
            count,
            seed,
            volume_min_m: DVec3::new(-10.0, 0.0, -50.0),
            volume_max_m: DVec3::new(10.0, 2.0, -5.0),
            random_rotation: true,
            scale: 1.0,
        })
    }

    #[test]
    fn splitmix_matches_the_reference_sequence() {
        // First outputs for seed 0 from the published reference implementation.
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn copies_are_deterministic_and_inside_the_box() {
        let a = copies(100, 7).expand();
        let b = copies(100, 7).expand();
        assert_eq!(a, b);
        assert_eq!(a.len(), 100);
        for p in &a {
            assert!((-10.0..10.0).contains(&p.position_m.x));
            assert!((0.0..2.0).contains(&p.position_m.y));
            assert!((-50.0..-5.0).contains(&p.position_m.z));
            assert!((p.rotation.length() - 1.0).abs() < 1e-12);
        }
        assert_ne!(a, copies(100, 8).expand());
    }

    #[test]
    fn more_copies_keep_the_first_ones() {
        let few = copies(10, 3).expand();
        let many = copies(50, 3).expand();
        assert_eq!(few[..], many[..10]);
    }

    #[test]
    fn transform_is_one_instance() {
        let spec = PlacementSpec::Transform(Transform {
            position_m: DVec3::new(1.0, 2.0, 3.0),
            rotation_deg: [90.0, 0.0, 0.0],
            scale: 2.0,
        });
        let all = spec.expand();
        assert_eq!(all.len(), 1);
        let p = all[0].transform_point(DVec3::NEG_Z);
        assert!((p - DVec3::new(-1.0, 2.0, 3.0)).length() < 1e-12, "{p}");
        assert!(spec.instance(1).is_none());
    }
}
