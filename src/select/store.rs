//! The object store: objects with more than one LOD in blocks of
//! [`BLOCK`], field by field, with their motion state in matching blocks,
//! so that the loop reads whole blocks in vector-sized passes.

use super::BLOCK;

/// [`BLOCK`] objects with more than one LOD, field by field. Lanes past
/// the last object of the last block are padding, never read.
#[derive(Clone, Debug)]
pub(super) struct Block {
    /// Centre of the bounding sphere, world units.
    pub(super) x: [f64; BLOCK],
    pub(super) y: [f64; BLOCK],
    pub(super) z: [f64; BLOCK],
    /// Radius of the bounding sphere, world units.
    pub(super) radius: [f32; BLOCK],
    /// Start of the object's row: its profile's
    /// [`Selector::profile_row0`](super::Selector::profile_row0).
    pub(super) row0: [u32; BLOCK],
    /// Rotation from the object's frame to the world, normalised
    /// (quaternion x, y, z, w).
    pub(super) rotation: [[f32; BLOCK]; 4],
}

pub(super) const EMPTY_BLOCK: Block = Block {
    x: [0.0; BLOCK],
    y: [0.0; BLOCK],
    z: [0.0; BLOCK],
    radius: [0.0; BLOCK],
    row0: [0; BLOCK],
    rotation: [[0.0; BLOCK], [0.0; BLOCK], [0.0; BLOCK], [1.0; BLOCK]],
};

/// The motion state of a block's objects.
#[derive(Clone, Debug)]
pub(super) struct MotionBlock {
    /// Direction to the object in the eye's frame last frame (x, y, z).
    pub(super) dir_eye: [[f32; BLOCK]; 3],
    /// Smoothed retinal velocity, deg/s; negative: no history yet.
    pub(super) velocity_deg_per_s: [f32; BLOCK],
}

pub(super) const NO_HISTORY: MotionBlock = MotionBlock {
    dir_eye: [[0.0; BLOCK]; 3],
    velocity_deg_per_s: [-1.0; BLOCK],
};

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BudgetEntry {
    /// `H(v, E) u`: the threshold at `s = 1` in c/diam, `u` the size the
    /// object is judged at (`inf` inside the bounding sphere).
    pub(super) k_cdiam: f32,
    /// The object's angular diameter, deg (180 inside its bounding sphere).
    pub(super) angular_size_deg: f32,
    /// Start of the object's prefix-minimum row; `u32::MAX` when culled.
    pub(super) row: u32,
}

/// One object's fields of a [`Block`], for moving an object between lanes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lane {
    pub(super) center: [f64; 3],
    pub(super) radius: f32,
    pub(super) row0: u32,
    pub(super) rotation: [f32; 4],
}

impl Block {
    pub(super) fn lane(&self, lane: usize) -> Lane {
        Lane {
            center: [self.x[lane], self.y[lane], self.z[lane]],
            radius: self.radius[lane],
            row0: self.row0[lane],
            rotation: [0, 1, 2, 3].map(|a| self.rotation[a][lane]),
        }
    }

    pub(super) fn set_lane(&mut self, lane: usize, l: Lane) {
        [self.x[lane], self.y[lane], self.z[lane]] = l.center;
        self.radius[lane] = l.radius;
        self.row0[lane] = l.row0;
        for (a, q) in l.rotation.into_iter().enumerate() {
            self.rotation[a][lane] = q;
        }
    }
}

impl MotionBlock {
    /// One object's motion state: direction and smoothed velocity.
    pub(super) fn lane(&self, lane: usize) -> ([f32; 3], f32) {
        (
            [0, 1, 2].map(|a| self.dir_eye[a][lane]),
            self.velocity_deg_per_s[lane],
        )
    }

    pub(super) fn set_lane(&mut self, lane: usize, (dir, velocity): ([f32; 3], f32)) {
        for (a, d) in dir.into_iter().enumerate() {
            self.dir_eye[a][lane] = d;
        }
        self.velocity_deg_per_s[lane] = velocity;
    }
}

/// The motion state of an object without history.
pub(super) const NO_MOTION: ([f32; 3], f32) = ([0.0; 3], -1.0);
