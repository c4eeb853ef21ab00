//! Finding the sampled viewpoint nearest to a view direction, in constant
//! time and without unpredictable branches.
//!
//! A cube map over the sphere of directions stores, per cell, the (at most
//! two) viewpoints that can be nearest anywhere in the cell, as a pair with
//! the normal of the plane that splits the sphere between them; the lookup
//! takes one dot product with that normal to keep the closer. Cells with more
//! candidates (near a Voronoi vertex; about 1% of them) fall back to a
//! scan. The candidate sets are conservative, so the answer is exact: if
//! `c` is the cell's centre, `rho` its angular radius and `w*` the viewpoint
//! nearest `c`, every point of the cell is within `angle(w*, c) + rho` of
//! `w*`, so only viewpoints within `angle(w*, c) + 2 rho` of `c` can be
//! nearest anywhere in it.

use glam::Vec3;

/// Cells per cube-face edge.
const RESOLUTION: usize = 32;
/// Cells of the cube map.
pub(crate) const CELLS: usize = 6 * RESOLUTION * RESOLUTION;
/// Most directions one [`ViewpointLookup::nearest_batch`] call takes.
pub(crate) const QUEUE_MAX: usize = 256;
/// Marks a cell with more than two candidates.
const SCAN: u16 = u16::MAX;
/// Dot products closer than this count as a tie (tests only skip those).
const TIE_MARGIN: f32 = 1e-5;

/// Nearest-viewpoint lookup for one viewpoint set.
#[derive(Clone, Debug)]
pub(crate) struct ViewpointLookup {
    directions: Vec<Vec3>,
    /// The candidate pairs, padded to a power of two.
    pairs: Vec<Pair>,
    /// Per cell, its pair in `pairs` (`SCAN` for more than two candidates).
    cells: Box<[u16; CELLS]>,
}

/// Two viewpoints that can be nearest in a cell (equal when one suffices).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    /// `directions[b] - directions[a]`: `b` is nearer exactly where the
    /// dot product of this with the direction is positive.
    normal: [f32; 3],
    /// `[a, b]`.
    views: [u16; 2],
}

impl Pair {
    /// The nearer viewpoint of the pair to `d`.
    #[inline(always)]
    fn nearer(&self, d: [f32; 3]) -> u16 {
        let [x, y, z] = self.normal;
        let dot = (x * d[0]) + (y * d[1]) + (z * d[2]);
        self.views[(dot > 0.0) as usize]
    }
}

impl ViewpointLookup {
    /// Builds the lookup. `directions` are unit vectors, fewer than 65535.
    pub(crate) fn new(directions: Vec<Vec3>) -> Self {
        debug_assert!(!directions.is_empty() && directions.len() < SCAN as usize);
        let mut cells = Box::new([SCAN; CELLS]);
        let mut pairs = Vec::new();
        let mut pair_ids = std::collections::HashMap::new();
        let step = 2.0 / RESOLUTION as f64;
        let mut candidates = Vec::new();
        for face in 0..6 {
            for j in 0..RESOLUTION {
                for i in 0..RESOLUTION {
                    let (u0, v0) = (i as f64 * step - 1.0, j as f64 * step - 1.0);
                    let centre = face_point(face, u0 + 0.5 * step, v0 + 0.5 * step).normalize();
                    let rho = [(0.0, 0.0), (step, 0.0), (0.0, step), (step, step)]
                        .iter()
                        .map(|&(du, dv)| {
                            let corner = face_point(face, u0 + du, v0 + dv).normalize();
                            centre.dot(corner).clamp(-1.0, 1.0).acos()
                        })
                        .fold(0.0, f64::max);
                    let dots = directions.iter().map(|d| centre.dot(d.as_dvec3()));
                    let nearest = dots.clone().fold(-1.0, f64::max).clamp(-1.0, 1.0).acos();
                    // The margin absorbs f32 rounding of the cell index.
                    let reach = (nearest + 2.0 * rho + 1e-4).min(std::f64::consts::PI).cos();
                    candidates.clear();
                    candidates.extend(
                        dots.enumerate()
                            .filter(|&(_, d)| d >= reach)
                            .map(|(k, _)| k),
                    );
                    let views = match candidates[..] {
                        [a] => [a as u16; 2],
                        [a, b] => [a as u16, b as u16],
                        _ => continue,
                    };
                    let id = *pair_ids.entry(views).or_insert_with(|| {
                        let [a, b] = views.map(|v| directions[v as usize]);
                        pairs.push(Pair {
                            normal: (b - a).to_array(),
                            views,
                        });
                        pairs.len() as u16 - 1
                    });
                    cells[(face * RESOLUTION + j) * RESOLUTION + i] = id;
                }
            }
        }
        // Padding makes masked indices valid without a bounds check.
        let padding = Pair {
            normal: [0.0; 3],
            views: [0; 2],
        };
        pairs.resize(pairs.len().max(1).next_power_of_two(), padding);
        Self {
            directions,
            pairs,
            cells,
        }
    }

    /// The viewpoint directions, unit vectors.
    pub(crate) fn directions(&self) -> &[Vec3] {
        &self.directions
    }

    /// The index of the viewpoint nearest to `dir` (any non-zero vector;
    /// zero or non-finite vectors give some valid index).
    #[cfg(test)]
    pub(crate) fn nearest(&self, dir: Vec3) -> usize {
        self.nearest_in_cell(cell_index(dir), dir)
    }

    /// [`nearest`](Self::nearest) with `cell = cell_index(dir)` computed
    /// beforehand (in bulk: [`cell_index`] vectorises).
    #[inline(always)]
    pub(crate) fn nearest_in_cell(&self, cell: u32, dir: Vec3) -> usize {
        let id = self.cells[(cell as usize).min(CELLS - 1)];
        if id == SCAN {
            return nearest_with_margin(&self.directions, dir).0;
        }
        self.pairs[id as usize % self.pairs.len()].nearer(dir.to_array()) as usize
    }

    /// [`nearest_in_cell`](Self::nearest_in_cell) for `cells.len()`
    /// directions (at most [`QUEUE_MAX`]; any more are left alone) given
    /// component by component (`dirs[a][i]`), into `views`: one
    /// straight-line pass (a dot product with the cell's split normal per
    /// direction, rounded as there), then a scan for the few whose cell has
    /// more than two candidates.
    #[inline(always)]
    pub(crate) fn nearest_batch(&self, cells: &[u32], dirs: [&[f32]; 3], views: &mut [u32]) {
        let n = cells.len().min(views.len()).min(QUEUE_MAX);
        let (cells, views) = (&cells[..n], &mut views[..n]);
        let [dx, dy, dz] = dirs.map(|d| &d[..n]);
        let mask = self.pairs.len() - 1;
        let pairs = &self.pairs[..=mask];
        let mut scans = [0u8; QUEUE_MAX];
        let mut scanned = 0;
        for i in 0..n {
            let id = self.cells[(cells[i] as usize).min(CELLS - 1)];
            scans[scanned] = i as u8;
            scanned += (id == SCAN) as usize;
            views[i] = pairs[id as usize & mask].nearer([dx[i], dy[i], dz[i]]) as u32;
        }
        for &i in &scans[..scanned] {
            let i = i as usize % n;
            let d = Vec3::new(dx[i], dy[i], dz[i]);
            views[i] = nearest_with_margin(&self.directions, d).0 as u32;
        }
    }

    /// Fraction of cells that need a scan.
    #[cfg(test)]
    fn scan_fraction(&self) -> f64 {
        self.cells.iter().filter(|&&c| c == SCAN).count() as f64 / self.cells.len() as f64
    }
}

/// The nearest direction by largest dot product, and whether it beats the
/// runner-up by more than the tie margin.
fn nearest_with_margin(directions: &[Vec3], d: Vec3) -> (usize, bool) {
    let mut best = (0, f32::NEG_INFINITY);
    let mut second = f32::NEG_INFINITY;
    for (k, dir) in directions.iter().enumerate() {
        let dot = dir.dot(d);
        if dot > best.1 {
            second = best.1;
            best = (k, dot);
        } else if dot > second {
            second = dot;
        }
    }
    (best.0, best.1 - second > TIE_MARGIN)
}

/// The cube-map cell of a direction (any vector; zero or non-finite ones
/// give some cell), below `6 * RESOLUTION^2`. Straight-line code on `f32`
/// and `u32`, so loops over it vectorise.
#[inline(always)]
pub(crate) fn cell_index(dir: Vec3) -> u32 {
    let (face, u, v) = cube_coords(dir);
    (face * RESOLUTION as u32 + cell(v)) * RESOLUTION as u32 + cell(u)
}

/// The cell along one face axis of face coordinate `u` in `[-1, 1]`:
/// `floor((u + 1) R / 2)` clamped into `0..R` (`NaN`: 0), as a float to
/// integer cast would give, but from the bits of `x + 2^23` (which is `x`
/// rounded to an integer) less one where that rounded up.
#[inline(always)]
fn cell(u: f32) -> u32 {
    const TWO_POW_23: f32 = 8_388_608.0;
    let x = crate::fastmath::clamp(
        (u + 1.0) * (0.5 * RESOLUTION as f32),
        0.0,
        (RESOLUTION - 1) as f32,
    );
    let t = x + TWO_POW_23;
    let rounded_up = (t - TWO_POW_23 > x) as u32;
    (t.to_bits() & 0xff) - rounded_up
}

/// The point on the cube's face `face` at face coordinates `(u, v)` in
/// `[-1, 1]`. Faces: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
fn face_point(face: usize, u: f64, v: f64) -> glam::DVec3 {
    use glam::DVec3;
    match face {
        0 => DVec3::new(1.0, u, v),
        1 => DVec3::new(-1.0, u, v),
        2 => DVec3::new(u, 1.0, v),
        3 => DVec3::new(u, -1.0, v),
        4 => DVec3::new(u, v, 1.0),
        _ => DVec3::new(u, v, -1.0),
    }
}

/// The inverse of [`face_point`] for a direction: its face by major axis
/// and the face coordinates of its central projection. Written with
/// selects rather than branches: the face is random from object to object.
#[inline(always)]
fn cube_coords(d: Vec3) -> (u32, f32, f32) {
    let a = d.abs();
    let x_major = (a.x >= a.y) & (a.x >= a.z);
    let y_major = !x_major & (a.y >= a.z);
    let (xm, ym) = (x_major as u32 as f32, y_major as u32 as f32);
    let zm = 1.0 - xm - ym;
    let major = a.x * xm + a.y * ym + a.z * zm;
    let signed = d.x * xm + d.y * ym + d.z * zm;
    let u = d.y * xm + d.x * (1.0 - xm);
    let v = d.z * (1.0 - zm) + d.y * zm;
    let z_major = !x_major & !y_major;
    let face = 2 * (y_major as u32) + 4 * (z_major as u32) + (signed < 0.0) as u32;
    let inv = 1.0 / major;
    (face, u * inv, v * inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The octahedron's vertices and its 12 edge midpoints: 18 directions.
    fn eighteen() -> Vec<Vec3> {
        let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        let mut dirs = axes.to_vec();
        for (i, a) in axes.iter().enumerate() {
            for b in &axes[i + 1..] {
                if a.dot(*b) == 0.0 {
                    dirs.push((*a + *b).normalize());
                }
            }
        }
        dirs
    }

    /// A seeded xorshift generator, uniform in `[-1, 1)`.
    fn uniform(mut state: u64) -> impl FnMut() -> f32 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        }
    }

    #[test]
    fn lookup_matches_a_full_scan() {
        let lookup = ViewpointLookup::new(eighteen());
        assert_eq!(lookup.directions.len(), 18);
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        for _ in 0..200_000 {
            let d = Vec3::new(next(), next(), next());
            if d.length_squared() < 1e-6 {
                continue;
            }
            let (exact, clear) = nearest_with_margin(&lookup.directions, d.normalize());
            if clear {
                assert_eq!(lookup.nearest(d), exact, "direction {d}");
            }
        }
        let scan = lookup.scan_fraction();
        assert!(scan < 0.05, "{scan} of cells need a scan");
    }

    #[test]
    fn the_batch_lookup_matches_the_single_one() {
        let lookup = ViewpointLookup::new(eighteen());
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let mut dirs: Vec<Vec3> = (0..50_000)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        dirs.extend([Vec3::ZERO, Vec3::NAN, Vec3::INFINITY, Vec3::splat(1e30)]);
        let cells: Vec<u32> = dirs.iter().map(|&d| cell_index(d)).collect();
        let components = [0, 1, 2].map(|a| dirs.iter().map(|d| d[a]).collect::<Vec<_>>());
        let mut views = vec![0; dirs.len()];
        for start in (0..dirs.len()).step_by(QUEUE_MAX) {
            let end = (start + QUEUE_MAX).min(dirs.len());
            let [x, y, z] = components.each_ref().map(|c| &c[start..end]);
            lookup.nearest_batch(&cells[start..end], [x, y, z], &mut views[start..end]);
        }
        assert!(cells.iter().any(|&c| lookup.cells[c as usize] == SCAN));
        for (i, &d) in dirs.iter().enumerate() {
            assert_eq!(views[i] as usize, lookup.nearest(d), "direction {d}");
        }
    }

    #[test]
    fn cell_floors_like_a_cast() {
        let cast = |u: f32| (((u + 1.0) * (0.5 * RESOLUTION as f32)) as usize).min(RESOLUTION - 1);
        let mut us = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.5, 1.5, 2.0];
        for k in 0..=2 * RESOLUTION {
            let u = k as f32 / RESOLUTION as f32 - 1.0;
            us.extend([u, u.next_up(), u.next_down()]);
        }
        us.extend((0..100_001).map(|i| i as f32 / 50_000.0 - 1.0));
        for u in us {
            assert_eq!(cell(u) as usize, cast(u), "u = {u}");
        }
    }

    #[test]
    fn degenerate_directions_give_a_valid_index() {
        let lookup = ViewpointLookup::new(eighteen());
        for d in [Vec3::ZERO, Vec3::NAN, Vec3::INFINITY, Vec3::splat(1e30)] {
            assert!(lookup.nearest(d) < 18);
        }
    }
}
