//! Finding the sampled viewpoint nearest to a view direction, in constant
//! time and without unpredictable branches.
//!
//! The nearest viewpoint is defined by `nearest_scan`: the first one with
//! the largest dot product, rounded one fixed way. Small sets (up to 48
//! viewpoints with AVX-512, 32 with AVX2, 8 with SSE2) are searched that
//! way in bulk, many directions at once in vector registers. Larger ones
//! use a cube map over the sphere of directions, finer for larger sets,
//! that stores per cell
//! the viewpoints that can be nearest anywhere in the cell: mostly one or
//! two (a pair, whose dot products the lookup compares), a short list near
//! a Voronoi vertex. The candidate sets are conservative, so the answer is
//! the scan's, bit for bit: if `c` is the cell's centre, `rho` its angular
//! radius and `w*` the viewpoint nearest `c`, every point of the cell is
//! within `angle(w*, c) + rho` of `w*`, so only viewpoints within
//! `angle(w*, c) + 2 rho` of `c` can be nearest anywhere in it. A margin of
//! [`MARGIN_RAD`] on that reach keeps every other viewpoint's dot product
//! below `w*`'s by at least `MARGIN_RAD * sin(rho)` (about 5e-6 at the
//! finest cells), far more than the `f32` rounding of two dot products.

// Index loops over parallel fixed-size arrays are what vectorises here.
#![allow(clippy::needless_range_loop)]

use glam::{DVec3, Vec3};

/// Cells per cube-face edge for the smallest sets; larger sets get more,
/// in proportion to the square root of their size, up to [`MAX_RESOLUTION`].
pub(crate) const MIN_RESOLUTION: u32 = 32;
/// Finest cube map: 6 * 256^2 cells of 4 bytes (1.5 MiB), from about 1,200
/// viewpoints up.
const MAX_RESOLUTION: u32 = 256;
/// Most directions one [`ViewpointLookup::nearest_batch`] call takes.
pub(crate) const QUEUE_MAX: usize = 256;
/// Viewpoint sets up to this size are searched by comparing every
/// viewpoint in bulk ([`ViewpointLookup::nearest_batch`]) with 128-bit
/// vectors (the x86-64 baseline's SSE2): a few vector instructions per
/// viewpoint and 4 directions, against a chain of dependent loads per
/// direction through the cube map.
pub(crate) const SCAN_MAX_VIEWS_128: usize = 8;
/// [`SCAN_MAX_VIEWS_128`] with 256-bit vectors (AVX2).
#[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
pub(crate) const SCAN_MAX_VIEWS_256: usize = 32;
/// [`SCAN_MAX_VIEWS_128`] with 512-bit vectors (AVX-512).
#[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
pub(crate) const SCAN_MAX_VIEWS_512: usize = 48;
/// Extra reach of a cell's candidate set, radians: see the module docs.
const MARGIN_RAD: f64 = 1e-3;
/// Marks a cell entry as a candidate list's start in
/// [`ViewpointLookup::lists`] rather than a pair.
const LIST: u32 = 1 << 31;

/// Nearest-viewpoint lookup for one viewpoint set.
#[derive(Clone, Debug)]
pub(crate) struct ViewpointLookup {
    directions: Vec<Vec3>,
    /// Cells per cube-face edge.
    resolution: u32,
    /// Per cell, its pair in `pairs`, or `LIST` plus the start of its
    /// candidate list in `lists`.
    cells: Vec<u32>,
    /// The candidate pairs, padded to a power of two.
    pairs: Vec<Pair>,
    /// Candidate lists, each its length and then its viewpoints, ascending.
    lists: Vec<u16>,
}

/// Two viewpoints that can be nearest in a cell (equal when one suffices).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    /// The two directions, `a` first.
    a: [f32; 3],
    b: [f32; 3],
    /// `[a, b]`, `a <= b`.
    views: [u16; 2],
}

impl Pair {
    /// The nearer viewpoint of the pair to `d` by [`dot`], `a` on a tie:
    /// what `nearest_scan` gives when both are the candidates.
    #[inline(always)]
    fn nearer(&self, d: [f32; 3]) -> u16 {
        self.views[(dot(self.b, d) > dot(self.a, d)) as usize]
    }
}

/// Directions [`ViewpointLookup::nearest_batch`] compares at once.
const LANES: usize = 16;

/// The nearest viewpoint so far of `LANES` directions, by `nearest_scan`'s
/// rule, lane by lane. Bit masks rather than `if`: that compiles to branches.
#[derive(Clone, Copy)]
struct Closest {
    dot: [f32; LANES],
    view: [u32; LANES],
}

impl Closest {
    const NONE: Self = Self {
        dot: [f32::NEG_INFINITY; LANES],
        view: [0; LANES],
    };

    /// Takes viewpoint `view` (direction `dir`) where it is closer to the
    /// direction `d[..][l]` than the closest so far.
    #[inline(always)]
    fn offer(&mut self, d: &[[f32; LANES]; 3], dir: [f32; 3], view: u32) {
        for l in 0..LANES {
            let dot = dot(dir, [d[0][l], d[1][l], d[2][l]]);
            let closer = 0u32.wrapping_sub((dot > self.dot[l]) as u32);
            self.dot[l] = crate::fastmath::max(dot, self.dot[l]);
            self.view[l] = (view & closer) | (self.view[l] & !closer);
        }
    }

    /// The views, each taken from `later` (which was offered only higher
    /// viewpoint indices) where that is closer: a tie keeps the lower index.
    #[inline(always)]
    fn or_closer(&self, later: &Self) -> [u32; LANES] {
        std::array::from_fn(|l| {
            let closer = 0u32.wrapping_sub((later.dot[l] > self.dot[l]) as u32);
            (later.view[l] & closer) | (self.view[l] & !closer)
        })
    }
}

/// The dot product that decides which viewpoint is nearest, in this
/// order (`(x + y) + z`, nothing fused) everywhere, so that every way of
/// finding the nearest viewpoint rounds alike.
#[inline(always)]
fn dot(v: [f32; 3], d: [f32; 3]) -> f32 {
    v[0] * d[0] + v[1] * d[1] + v[2] * d[2]
}

/// The definition of the nearest viewpoint: the first of `directions`
/// with the largest [`dot`] with `d` (0 when no dot product is a number).
#[cfg(test)]
fn nearest_scan(directions: &[Vec3], d: [f32; 3]) -> usize {
    let mut best = (0, f32::NEG_INFINITY);
    for (k, v) in directions.iter().enumerate() {
        let dot = dot(v.to_array(), d);
        if dot > best.1 {
            best = (k, dot);
        }
    }
    best.0
}

impl ViewpointLookup {
    /// Builds the lookup. `directions` are unit vectors, fewer than 65535.
    /// Cost: a few ball queries per cell, each over the viewpoints in a
    /// handful of grid buckets (about 0.1 s for 16,386 viewpoints).
    pub(crate) fn new(directions: Vec<Vec3>) -> Self {
        debug_assert!(!directions.is_empty() && directions.len() < u16::MAX as usize);
        let resolution = ((MIN_RESOLUTION as f64 * (directions.len() as f64 / 18.0).sqrt()).ceil()
            as u32)
            .clamp(MIN_RESOLUTION, MAX_RESOLUTION);
        let r = resolution as usize;
        let exact: Vec<DVec3> = directions.iter().map(|d| d.as_dvec3()).collect();
        let grid = Grid::new(&exact);
        let mut cells = vec![0; 6 * r * r];
        let mut pairs = Vec::new();
        let mut pair_ids = std::collections::HashMap::new();
        let mut lists = Vec::new();
        let step = 2.0 / r as f64;
        let mut candidates = Vec::new();
        for face in 0..6 {
            for j in 0..r {
                for i in 0..r {
                    let (u0, v0) = (i as f64 * step - 1.0, j as f64 * step - 1.0);
                    let centre = face_point(face, u0 + 0.5 * step, v0 + 0.5 * step).normalize();
                    let rho = [(0.0, 0.0), (step, 0.0), (0.0, step), (step, step)]
                        .iter()
                        .map(|&(du, dv)| {
                            let corner = face_point(face, u0 + du, v0 + dv).normalize();
                            centre.dot(corner).clamp(-1.0, 1.0).acos()
                        })
                        .fold(0.0, f64::max);
                    let nearest = grid.nearest_dot(&exact, centre).clamp(-1.0, 1.0).acos();
                    let reach = (nearest + 2.0 * rho + MARGIN_RAD).min(std::f64::consts::PI);
                    candidates.clear();
                    grid.within(&exact, centre, reach, &mut candidates);
                    candidates.sort_unstable();
                    let cell = &mut cells[(face * r + j) * r + i];
                    *cell = match candidates[..] {
                        [a] => pair_id(&mut pairs, &mut pair_ids, &directions, [a, a]),
                        [a, b] => pair_id(&mut pairs, &mut pair_ids, &directions, [a, b]),
                        _ => {
                            let start = lists.len() as u32;
                            lists.push(candidates.len() as u16);
                            lists.extend(candidates.iter().map(|&k| k as u16));
                            LIST | start
                        }
                    };
                }
            }
        }
        // Padding makes masked indices valid without a bounds check.
        let padding = Pair {
            a: [0.0; 3],
            b: [0.0; 3],
            views: [0; 2],
        };
        pairs.resize(pairs.len().max(1).next_power_of_two(), padding);
        Self {
            directions,
            resolution,
            cells,
            pairs,
            lists,
        }
    }

    /// The viewpoint directions, unit vectors.
    pub(crate) fn directions(&self) -> &[Vec3] {
        &self.directions
    }

    /// The index of the viewpoint nearest to `dir` (any non-zero vector;
    /// zero or non-finite vectors give some valid index), through the
    /// cube map: what `nearest_scan` gives.
    #[cfg(test)]
    pub(crate) fn nearest(&self, dir: Vec3) -> usize {
        self.nearest_in_cell(self.cell_index(dir), dir.to_array())
    }

    /// Cells per cube-face edge, for [`cell_index`].
    pub(crate) fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The cube-map cell of a direction: [`cell_index`].
    #[inline(always)]
    fn cell_index(&self, dir: Vec3) -> u32 {
        cell_index(dir, self.resolution)
    }

    /// `nearest` with `cell = cell_index(dir, resolution)`
    /// computed beforehand (in bulk: [`cell_index`] vectorises).
    #[inline(always)]
    pub(crate) fn nearest_in_cell(&self, cell: u32, dir: [f32; 3]) -> usize {
        let id = self.cells[(cell as usize).min(self.cells.len() - 1)];
        if id & LIST != 0 {
            return self.nearest_in_list(id, dir);
        }
        self.pairs[id as usize & (self.pairs.len() - 1)].nearer(dir) as usize
    }

    /// The nearest of the candidate list that cell entry `id` points to:
    /// `nearest_scan` over it (ascending, so ties keep the lower index).
    #[inline(never)]
    fn nearest_in_list(&self, id: u32, dir: [f32; 3]) -> usize {
        let start = (id & !LIST) as usize;
        let len = self.lists.get(start).map_or(0, |&len| len as usize);
        let list = self.lists.get(start + 1..start + 1 + len).unwrap_or(&[]);
        let mut best = (list.first().map_or(0, |&k| k as usize), f32::NEG_INFINITY);
        for &k in list {
            let dot = dot(self.directions[k as usize].to_array(), dir);
            if dot > best.1 {
                best = (k as usize, dot);
            }
        }
        best.0
    }

    /// `nearest` for the directions `dirs` (given
    /// component by component: `dirs[a][i]`; at most [`QUEUE_MAX`], any
    /// more are left alone), into `views`. Small sets compare every
    /// viewpoint with 16 directions at a time; larger ones find each
    /// direction's cell and compare its pair in a straight-line pass, then
    /// scan for the few whose cell has more than two candidates.
    #[inline(always)]
    pub(crate) fn nearest_batch(
        &self,
        dirs: [&[f32]; 3],
        views: &mut [u32],
        scan_max_views: usize,
    ) {
        let n = dirs
            .iter()
            .fold(views.len(), |n, d| n.min(d.len()))
            .min(QUEUE_MAX);
        let [dx, dy, dz] = dirs.map(|d| &d[..n]);
        let views = &mut views[..n];
        if self.directions.len() <= scan_max_views {
            for (k, out) in views.chunks_mut(LANES).enumerate() {
                let mut d = [[0.0f32; LANES]; 3];
                for (a, src) in [dx, dy, dz].into_iter().enumerate() {
                    d[a][..out.len()].copy_from_slice(&src[k * LANES..][..out.len()]);
                }
                // Two independent halves: each step waits on the last
                // comparison of its own half only.
                let (first, second) = self.directions.split_at(self.directions.len().div_ceil(2));
                let (mut early, mut late) = (Closest::NONE, Closest::NONE);
                for (v, dir) in first.iter().enumerate() {
                    early.offer(&d, dir.to_array(), v as u32);
                    if let Some(dir) = second.get(v) {
                        late.offer(&d, dir.to_array(), (first.len() + v) as u32);
                    }
                }
                let nearest = early.or_closer(&late);
                let len = out.len();
                out.copy_from_slice(&nearest[..len]);
            }
            return;
        }
        let mask = self.pairs.len() - 1;
        let pairs = &self.pairs[..=mask];
        let mut cells = [0u32; QUEUE_MAX];
        for i in 0..n {
            cells[i] = self.cell_index(Vec3::new(dx[i], dy[i], dz[i]));
        }
        let mut listed = [0u8; QUEUE_MAX];
        let mut count = 0;
        for i in 0..n {
            let id = self.cells[(cells[i] as usize).min(self.cells.len() - 1)];
            listed[count] = i as u8;
            count += (id & LIST != 0) as usize;
            // A list's entry gives some pair here; it is overwritten below.
            views[i] = pairs[id as usize & mask].nearer([dx[i], dy[i], dz[i]]) as u32;
        }
        for &i in &listed[..count] {
            let i = i as usize % n;
            let id = self.cells[(cells[i] as usize).min(self.cells.len() - 1)];
            views[i] = self.nearest_in_list(id, [dx[i], dy[i], dz[i]]) as u32;
        }
    }

    /// Fraction of cells with a candidate list.
    #[cfg(test)]
    fn list_fraction(&self) -> f64 {
        let lists = self.cells.iter().filter(|&&c| c & LIST != 0).count();
        lists as f64 / self.cells.len() as f64
    }
}

/// The id of the pair `views` in `pairs`, added if new.
fn pair_id(
    pairs: &mut Vec<Pair>,
    ids: &mut std::collections::HashMap<[usize; 2], u32>,
    directions: &[Vec3],
    views: [usize; 2],
) -> u32 {
    *ids.entry(views).or_insert_with(|| {
        let [a, b] = views.map(|v| directions[v].to_array());
        pairs.push(Pair {
            a,
            b,
            views: views.map(|v| v as u16),
        });
        pairs.len() as u32 - 1
    })
}

/// Unit directions bucketed in a uniform grid over `[-1, 1]^3`, for the
/// ball queries that build the cube map.
struct Grid {
    size: usize,
    /// Bucket `b` holds `items[starts[b]..starts[b + 1]]`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    fn new(directions: &[DVec3]) -> Self {
        // About one direction per occupied bucket (they lie on a sphere).
        let size = ((directions.len() as f64).sqrt().ceil() as usize).clamp(1, 128);
        let mut grid = Self {
            size,
            starts: vec![0; size * size * size + 1],
            items: vec![0; directions.len()],
        };
        for d in directions {
            let b = grid.bucket(*d);
            grid.starts[b + 1] += 1;
        }
        for b in 0..size * size * size {
            grid.starts[b + 1] += grid.starts[b];
        }
        let mut next = grid.starts.clone();
        for (k, d) in directions.iter().enumerate() {
            let b = grid.bucket(*d);
            grid.items[next[b] as usize] = k as u32;
            next[b] += 1;
        }
        grid
    }

    fn axis(&self, x: f64) -> usize {
        (((x + 1.0) * 0.5 * self.size as f64).max(0.0) as usize).min(self.size - 1)
    }

    fn bucket(&self, d: DVec3) -> usize {
        (self.axis(d.z) * self.size + self.axis(d.y)) * self.size + self.axis(d.x)
    }

    /// Calls `f` with each direction in the buckets that overlap the ball
    /// of radius `chord` around `p` (every direction within it, and some
    /// more).
    fn each_near(&self, p: DVec3, chord: f64, mut f: impl FnMut(usize)) {
        let lo = (p - chord).to_array().map(|x| self.axis(x));
        let hi = (p + chord).to_array().map(|x| self.axis(x));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                let row = (z * self.size + y) * self.size;
                let items =
                    self.starts[row + lo[0]] as usize..self.starts[row + hi[0] + 1] as usize;
                for &k in &self.items[items] {
                    f(k as usize);
                }
            }
        }
    }

    /// The largest dot product of a direction with the unit vector `p`:
    /// balls of doubling radius until one holds the answer for certain.
    fn nearest_dot(&self, directions: &[DVec3], p: DVec3) -> f64 {
        let mut chord = 2.0 / self.size as f64;
        loop {
            let mut best = f64::NEG_INFINITY;
            self.each_near(p, chord, |k| best = best.max(directions[k].dot(p)));
            // Chord c is dot 1 - c^2 / 2: the best lies within the ball.
            if best >= 1.0 - 0.5 * chord * chord || chord >= 2.0 {
                return best;
            }
            chord = (2.0 * chord).min(2.0);
        }
    }

    /// Pushes every direction within `angle` (radians, at most pi) of the
    /// unit vector `p` to `out`.
    fn within(&self, directions: &[DVec3], p: DVec3, angle: f64, out: &mut Vec<usize>) {
        let (chord, cos) = (2.0 * (0.5 * angle).sin(), angle.cos());
        self.each_near(p, chord, |k| {
            if directions[k].dot(p) >= cos {
                out.push(k);
            }
        });
    }
}

/// The cube-map cell of a direction (any vector; zero or non-finite ones
/// give some cell), below `6 r^2` for `r` cells per face edge (at most
/// [`MAX_RESOLUTION`]). Straight-line code on `f32` and `u32`, so loops
/// over it vectorise.
#[inline(always)]
pub(crate) fn cell_index(dir: Vec3, r: u32) -> u32 {
    let (face, u, v) = cube_coords(dir);
    (face * r + cell(v, r)) * r + cell(u, r)
}

/// The cell along one face axis of face coordinate `u` in `[-1, 1]` with
/// `r` cells (at most [`MAX_RESOLUTION`]): `floor((u + 1) r / 2)` clamped
/// into `0..r` (`NaN`: 0), as a float to integer cast would give, but from
/// the bits of `x + 2^23` (which is `x` rounded to an integer) less one
/// where that rounded up.
#[inline(always)]
fn cell(u: f32, r: u32) -> u32 {
    const TWO_POW_23: f32 = 8_388_608.0;
    let x = crate::fastmath::clamp((u + 1.0) * (0.5 * r as f32), 0.0, (r - 1) as f32);
    let t = x + TWO_POW_23;
    let rounded_up = (t - TWO_POW_23 > x) as u32;
    (t.to_bits() & 0x007f_ffff) - rounded_up
}

/// The point on the cube's face `face` at face coordinates `(u, v)` in
/// `[-1, 1]`. Faces: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
fn face_point(face: usize, u: f64, v: f64) -> DVec3 {
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
    use rand::{RngExt, SeedableRng};
    use rand_xorshift::XorShiftRng;

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

    /// The seeded generator of the tests, uniform in `[-1, 1)`.
    fn uniform(seed: u64) -> impl FnMut() -> f32 {
        let mut rng = XorShiftRng::seed_from_u64(seed);
        move || rng.random_range(-1.0f32..1.0)
    }

    /// `count` random unit directions.
    fn random_set(count: usize, seed: u64) -> Vec<Vec3> {
        let mut next = uniform(seed);
        let mut dirs = vec![];
        while dirs.len() < count {
            let d = Vec3::new(next(), next(), next());
            if (1e-2..=1.0).contains(&d.length_squared()) {
                dirs.push(d.normalize());
            }
        }
        dirs
    }

    /// Random directions of magnitudes from 1e-20 to 1e15.
    fn directions(count: usize, seed: u64) -> Vec<Vec3> {
        let mut next = uniform(seed);
        (0..count)
            .map(|_| Vec3::new(next(), next(), next()) * 10f32.powf(17.5 * next() - 2.5))
            .collect()
    }

    /// The sets the tests run on: the 18 of a once-subdivided octahedron
    /// and random ones, small and large.
    fn sets() -> Vec<Vec<Vec3>> {
        vec![
            eighteen(),
            random_set(7, 3),
            random_set(32, 5),
            random_set(100, 7),
            random_set(400, 11),
        ]
    }

    #[test]
    fn the_cube_map_gives_the_full_scan_bit_for_bit() {
        for (k, set) in sets().into_iter().enumerate() {
            let lookup = ViewpointLookup::new(set.clone());
            for d in directions(40_000, 0x9e37_79b9_7f4a_7c15 + k as u64) {
                if d.length_squared() < f32::MIN_POSITIVE {
                    continue;
                }
                let scan = nearest_scan(&set, d.to_array());
                assert_eq!(lookup.nearest(d), scan, "set {k}, direction {d}");
            }
        }
        let listed = ViewpointLookup::new(eighteen()).list_fraction();
        assert!(listed < 0.05, "{listed} of cells have a list");
    }

    #[test]
    fn the_batch_lookup_matches_the_single_one() {
        for (k, set) in sets().into_iter().enumerate() {
            let lookup = ViewpointLookup::new(set);
            let dirs = directions(20_000, 0x2545_f491_4f6c_dd1d + k as u64);
            let components = [0, 1, 2].map(|a| dirs.iter().map(|d| d[a]).collect::<Vec<_>>());
            let mut cells = dirs
                .iter()
                .map(|&d| lookup.cells[lookup.cell_index(d) as usize]);
            assert!(k < 3 || cells.any(|c| c & LIST != 0), "set {k}");
            // Through the cube map, and comparing every viewpoint.
            for scan_max_views in [0, usize::MAX] {
                let mut views = vec![0; dirs.len()];
                // Uneven batches: partial groups of 16 lanes too.
                let mut start = 0;
                for len in (1..=QUEUE_MAX).cycle().step_by(37) {
                    if start == dirs.len() {
                        break;
                    }
                    let end = (start + len).min(dirs.len());
                    let [x, y, z] = components.each_ref().map(|c| &c[start..end]);
                    lookup.nearest_batch([x, y, z], &mut views[start..end], scan_max_views);
                    start = end;
                }
                for (i, &d) in dirs.iter().enumerate() {
                    let single = lookup.nearest(d);
                    assert_eq!(views[i] as usize, single, "set {k}, direction {d}");
                }
            }
        }
    }

    #[test]
    fn cell_floors_like_a_cast() {
        for r in [MIN_RESOLUTION, 77, MAX_RESOLUTION] {
            let cast = |u: f32| (((u + 1.0) * (0.5 * r as f32)) as u32).min(r - 1);
            let mut us = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.5, 1.5, 2.0];
            for k in 0..=2 * r {
                let u = k as f32 / r as f32 - 1.0;
                us.extend([u, u.next_up(), u.next_down()]);
            }
            us.extend((0..100_001).map(|i| i as f32 / 50_000.0 - 1.0));
            for u in us {
                assert_eq!(cell(u, r), cast(u), "u = {u}, {r} cells");
            }
        }
    }

    /// The viewpoints of the offline pass at subdivision `level`
    /// (preprocess/src/views.rs): 18 at level 1, 258 at 3, 16,386 at 6.
    fn octahedral(level: u32) -> Vec<Vec3> {
        let n = 1i32 << level;
        let mut out = vec![];
        for y in (-n..=n).rev() {
            let rem = n - y.abs();
            for x in -rem..=rem {
                let za = rem - x.abs();
                let zs: &[i32] = if za == 0 { &[0] } else { &[-za, za] };
                for &z in zs {
                    out.push(Vec3::new(x as f32, y as f32, z as f32).normalize());
                }
            }
        }
        out
    }

    #[test]
    fn fine_viewpoint_sets_keep_short_candidate_lists() {
        for level in [1, 3, 6] {
            let set = octahedral(level);
            let lookup = ViewpointLookup::new(set.clone());
            let listed = lookup.list_fraction();
            let longest = (0..lookup.cells.len())
                .filter(|&c| lookup.cells[c] & LIST != 0)
                .map(|c| lookup.lists[(lookup.cells[c] & !LIST) as usize])
                .max()
                .unwrap_or(0);
            // Level 6 is past the finest cube map's ratio of cells to views.
            let bound = if level < 6 { 0.05 } else { 0.3 };
            assert!(
                listed < bound,
                "level {level}: {listed} of cells have a list"
            );
            assert!(longest <= 8, "level {level}: a list of {longest}");
            for d in directions(2_000, level as u64) {
                if d.length_squared() >= f32::MIN_POSITIVE {
                    assert_eq!(lookup.nearest(d), nearest_scan(&set, d.to_array()));
                }
            }
        }
    }

    #[test]
    fn degenerate_directions_give_a_valid_index() {
        let odd = [Vec3::ZERO, Vec3::NAN, Vec3::INFINITY, Vec3::splat(1e30)];
        for set in sets() {
            let (count, lookup) = (set.len(), ViewpointLookup::new(set));
            let components = [0, 1, 2].map(|a| odd.each_ref().map(|d| d[a]));
            for scan_max_views in [0, usize::MAX] {
                let mut views = [u32::MAX; 4];
                let dirs = components.each_ref().map(|c| &c[..]);
                lookup.nearest_batch(dirs, &mut views, scan_max_views);
                assert!(views.iter().all(|&v| (v as usize) < count));
            }
            for d in odd {
                assert!(lookup.nearest(d) < count);
            }
        }
    }
}
