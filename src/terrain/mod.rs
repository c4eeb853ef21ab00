//! View-dependent terrain (Reddy 2001): a heightfield refined top-down as a
//! quadtree, each node split only while the detail its children add could
//! be perceptible, and triangulated without cracks.
//!
//! Pure computation (no clock, no I/O, no GPU) and allocation-free once a
//! [`Refinement`]'s buffers have grown; it lives in the runtime because an
//! engine drawing terrain needs it per frame, exactly as it needs LOD
//! selection, and it needs nothing beyond glam.
//!
//! - A node's *geometric error* is the largest vertical distance between
//!   the full-resolution heights it covers and the bilinear surface through
//!   its four corners, raised to its children's so that it never grows
//!   down the tree (then a criterion that stops a node stops its subtree).
//! - Criterion ([`refine`](Terrain::refine)): the error, seen from the eye
//!   at the distance of the node's nearest point, subtends `alpha` deg, a
//!   feature of `f = 1 / (2 alpha)` c/deg; the node splits while `f <= T =
//!   s * min(H(v, E), xi)` (Reddy 2001 eq. 4 with the display limit).
//! - Crack-free output: no constraint on neighbouring levels; instead each
//!   leaf is triangulated as a fan around its centre through every vertex
//!   of a finer neighbour that lies on its edges (a leaf without such
//!   vertices is two triangles). Every edge of the output is then shared
//!   by exactly two triangles or lies on the border of what is drawn: no
//!   T-junctions, no skirts, no extra triangles hidden below the surface.

mod refine;

pub use refine::{CULL_NODE_CELLS, RefineStats, Refinement, TerrainSettings, TerrainView};

use crate::error::{Error, Result};

/// A grid of heights: `width` x `height` samples, `spacing` world units
/// apart in `x` (columns) and `y` (rows); sample `(i, j)` lies at world
/// `(i * spacing, j * spacing, heights[j * width + i])`, `z` up.
#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    width: usize,
    height: usize,
    spacing: f32,
    heights: Vec<f32>,
}

/// Most samples along either axis of a heightfield (2^16 + 1).
pub const MAX_HEIGHTFIELD_SIDE: usize = 65_537;

impl Heightfield {
    /// A heightfield of `width` x `height` samples (each in `[2,
    /// MAX_HEIGHTFIELD_SIDE]`), `spacing` world units apart (finite, > 0),
    /// with finite heights in world units, row-major.
    pub fn new(width: usize, height: usize, spacing: f32, heights: Vec<f32>) -> Result<Self> {
        for (axis, n) in [("width", width), ("height", height)] {
            if !(2..=MAX_HEIGHTFIELD_SIDE).contains(&n) {
                return Err(Error::invalid(
                    "heightfield",
                    format!("{axis} {n} samples is outside [2, {MAX_HEIGHTFIELD_SIDE}]"),
                ));
            }
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(Error::invalid(
                "spacing",
                format!("{spacing} is not a finite length > 0"),
            ));
        }
        if heights.len() != width * height {
            return Err(Error::invalid(
                "heights",
                format!(
                    "{} values for {width}x{height} samples ({} expected)",
                    heights.len(),
                    width * height
                ),
            ));
        }
        if let Some(i) = heights.iter().position(|h| !h.is_finite()) {
            return Err(Error::invalid(
                "heights",
                format!("sample ({}, {}) is {}", i % width, i / width, heights[i]),
            ));
        }
        Ok(Self {
            width,
            height,
            spacing,
            heights,
        })
    }

    /// Samples along `x` and along `y`.
    pub fn size(&self) -> [usize; 2] {
        [self.width, self.height]
    }

    /// Distance between neighbouring samples, world units.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// Height of sample `(i, j)`, world units (indices clamped).
    pub fn at(&self, i: usize, j: usize) -> f32 {
        let (i, j) = (i.min(self.width - 1), j.min(self.height - 1));
        self.heights[j * self.width + i]
    }

    /// Triangles of the full-resolution mesh: two per cell.
    pub fn full_triangles(&self) -> usize {
        2 * (self.width - 1) * (self.height - 1)
    }
}

/// A vertex of the refined mesh in half-sample units: `(x2, y2)` lies at
/// sample coordinates `(x2 / 2, y2 / 2)`. Leaf corners are samples (even
/// coordinates); a fan's centre may fall between samples. Exact integers,
/// so shared edges compare exactly.
pub type Vertex = [u32; 2];

/// Per-level node data of the quadtree.
#[derive(Clone, Debug)]
struct Level {
    /// Node side in cells.
    size: u32,
    /// Nodes along `x` and `y`.
    nx: u32,
    ny: u32,
    /// Geometric error, world units (never below the children's).
    error: Vec<f32>,
    /// Lowest and highest height under the node, world units.
    z_range: Vec<[f32; 2]>,
}

/// A heightfield with its quadtree: level 0 is a root of a power-of-two
/// number of cells covering the grid, each level halves the node side, the
/// last has nodes of one cell. Nodes are clipped to the grid, so any size
/// works (the full-resolution mesh is exactly two triangles per cell).
#[derive(Clone, Debug)]
pub struct Terrain {
    field: Heightfield,
    levels: Vec<Level>,
}

impl Terrain {
    /// Builds the quadtree: every node's geometric error and height range,
    /// bottom-up. Cost linear in samples times levels.
    pub fn new(field: Heightfield) -> Self {
        let cells = [field.width as u32 - 1, field.height as u32 - 1];
        let root = cells[0].max(cells[1]).next_power_of_two();
        let depth = root.trailing_zeros() as usize + 1;
        let mut levels: Vec<Level> = Vec::with_capacity(depth);
        for k in (0..depth).rev() {
            let size = root >> k;
            let (nx, ny) = (cells[0].div_ceil(size), cells[1].div_ceil(size));
            let mut level = Level {
                size,
                nx,
                ny,
                error: vec![0.0; (nx * ny) as usize],
                z_range: vec![[0.0; 2]; (nx * ny) as usize],
            };
            let finer = levels.last();
            for j in 0..ny {
                for i in 0..nx {
                    let [x0, y0, x1, y1] = node_rect(size, i, j, cells);
                    let (own, range) = own_error(&field, [x0, y0, x1, y1]);
                    let mut error = own;
                    let mut z = range;
                    if let Some(f) = finer {
                        for (ci, cj) in children(i, j, f.nx, f.ny) {
                            let c = (cj * f.nx + ci) as usize;
                            error = error.max(f.error[c]);
                            z = [z[0].min(f.z_range[c][0]), z[1].max(f.z_range[c][1])];
                        }
                    }
                    level.error[(j * nx + i) as usize] = error;
                    level.z_range[(j * nx + i) as usize] = z;
                }
            }
            levels.push(level);
        }
        levels.reverse();
        Self { field, levels }
    }

    /// The heightfield.
    pub fn heightfield(&self) -> &Heightfield {
        &self.field
    }

    /// Number of quadtree levels (root to single cells).
    pub fn depth(&self) -> usize {
        self.levels.len()
    }

    /// World position of a mesh vertex (`z` up); a vertex between samples
    /// takes the mean of the samples around it.
    pub fn vertex_position(&self, v: Vertex) -> [f32; 3] {
        let (i0, j0) = ((v[0] / 2) as usize, (v[1] / 2) as usize);
        let (i1, j1) = (i0 + (v[0] % 2) as usize, j0 + (v[1] % 2) as usize);
        let h = 0.25
            * (self.field.at(i0, j0)
                + self.field.at(i1, j0)
                + self.field.at(i0, j1)
                + self.field.at(i1, j1));
        let s = 0.5 * self.field.spacing;
        [v[0] as f32 * s, v[1] as f32 * s, h]
    }

    fn cells(&self) -> [u32; 2] {
        [self.field.width as u32 - 1, self.field.height as u32 - 1]
    }
}

/// Cells `[x0, y0, x1, y1]` (sample coordinates of the corners) of node
/// `(i, j)` of side `size`, clipped to the grid.
fn node_rect(size: u32, i: u32, j: u32, cells: [u32; 2]) -> [u32; 4] {
    [
        i * size,
        j * size,
        ((i + 1) * size).min(cells[0]),
        ((j + 1) * size).min(cells[1]),
    ]
}

/// The children of node `(i, j)` that exist on a level of `nx` x `ny`.
fn children(i: u32, j: u32, nx: u32, ny: u32) -> impl Iterator<Item = (u32, u32)> {
    [(0, 0), (1, 0), (0, 1), (1, 1)]
        .into_iter()
        .map(move |(di, dj)| (2 * i + di, 2 * j + dj))
        .filter(move |&(ci, cj)| ci < nx && cj < ny)
}

/// The largest distance between the samples of a rectangle and the
/// bilinear surface through its corners, and the samples' height range.
fn own_error(field: &Heightfield, [x0, y0, x1, y1]: [u32; 4]) -> (f32, [f32; 2]) {
    let h = |x: u32, y: u32| field.at(x as usize, y as usize);
    let (h00, h10, h01, h11) = (h(x0, y0), h(x1, y0), h(x0, y1), h(x1, y1));
    let (w, d) = ((x1 - x0) as f32, (y1 - y0) as f32);
    let mut error = 0.0f32;
    let mut range = [f32::MAX, f32::MIN];
    for y in y0..=y1 {
        let ty = (y - y0) as f32 / d;
        let (left, right) = (h00 + (h01 - h00) * ty, h10 + (h11 - h10) * ty);
        for x in x0..=x1 {
            let tx = (x - x0) as f32 / w;
            let v = h(x, y);
            error = error.max((v - (left + (right - left) * tx)).abs());
            range = [range[0].min(v), range[1].max(v)];
        }
    }
    (error, range)
}

#[cfg(test)]
mod tests;
