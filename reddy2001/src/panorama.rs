//! An equiangular image of a field wider than a planar projection can
//! reach (Reddy 2001's 200 x 135 deg), made of planar tiles: the field is
//! split into a grid of tiles of at most [`MAX_TILE_FOV_DEG`] each way,
//! each drawn by a camera turned to the tile's centre, and the output
//! image is resampled from them.
//!
//! The output is equiangular in the terrain's own coordinates (azimuth
//! about the camera's up axis, elevation above its horizontal plane, as
//! the viewport culling and the eccentricity measure them): column `x` of
//! `w` lies at azimuth `(x + 0.5) / w * H - H / 2`, row `y` of `h` at
//! elevation `V / 2 - (y + 0.5) / h * V`. Tiles cannot be pasted side by
//! side: a planar tile's edges are straight lines in its image plane,
//! which are not lines of constant azimuth once the tile is pitched, so
//! neighbouring tiles would leave gaps and overlaps. Each tile's frustum
//! instead covers its share of the azimuth-elevation box with a margin,
//! at no fewer pixels per degree than the output at its centre, and every
//! output pixel takes the bilinear sample of its direction in its own
//! tile: seams join exactly, whatever the pitch.

use glam::{DVec3, Quat};

use acuity::display::{direction_to_pixel_in_edges, projection_columns};

/// Widest field of one tile along either axis, deg.
pub const MAX_TILE_FOV_DEG: f32 = 90.0;

/// One planar tile of the field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    /// Turn from the camera to the tile's view, camera frame: yaw about
    /// `+y` to the tile's azimuth, then pitch about the turned `+x` to its
    /// elevation.
    pub rotation: Quat,
    /// The tile's frustum edges (left, right, up, down, deg, signed as
    /// [`acuity::display::FovEdges`]).
    pub edges_deg: [f64; 4],
    /// The tile's image size, pixels.
    pub size_px: [u32; 2],
}

impl Tile {
    /// The tile's projection (infinite far plane, wgpu depth) as a matrix.
    pub fn projection(&self, near_m: f32) -> glam::Mat4 {
        let columns = projection_columns(self.edges_deg, f64::from(near_m));
        glam::Mat4::from_cols_array_2d(&columns.map(|c| c.map(|x| x as f32)))
    }
}

/// Where one output pixel samples: its tile and the point in the tile's
/// image, pixels from the top-left corner.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sample {
    tile: u16,
    x: f32,
    y: f32,
}

/// The tiles of a field and the output pixels' samples in them.
#[derive(Clone, Debug)]
pub struct Panorama {
    size_px: [u32; 2],
    fov_deg: [f32; 2],
    grid: [u32; 2],
    tiles: Vec<Tile>,
    samples: Vec<Sample>,
}

/// Extra angle each tile's frustum covers beyond its share, in output
/// pixels, so that bilinear samples at a seam stay inside the tile.
const MARGIN_PX: f64 = 2.0;

impl Panorama {
    /// The tiles for an equiangular image of `size_px` covering `fov_deg`
    /// (horizontal in `(0, 360)`, vertical in `(0, 180)`, deg) about the
    /// camera's forward direction.
    pub fn new(size_px: [u32; 2], fov_deg: [f32; 2]) -> anyhow::Result<Self> {
        let [h_deg, v_deg] = fov_deg;
        if !(h_deg > 0.0 && h_deg < 360.0 && v_deg > 0.0 && v_deg < 180.0) {
            anyhow::bail!("a field of {h_deg} x {v_deg} deg is not in (0, 360) x (0, 180)");
        }
        if size_px.contains(&0) {
            anyhow::bail!("an image of {}x{} px is empty", size_px[0], size_px[1]);
        }
        let grid = fov_deg.map(|a| (a / MAX_TILE_FOV_DEG).ceil() as u32);
        let share = [h_deg / grid[0] as f32, v_deg / grid[1] as f32].map(f64::from);
        let px_per_deg = [
            f64::from(size_px[0]) / f64::from(h_deg),
            f64::from(size_px[1]) / f64::from(v_deg),
        ];
        let margin_deg = [MARGIN_PX / px_per_deg[0], MARGIN_PX / px_per_deg[1]];
        let mut tiles = Vec::with_capacity((grid[0] * grid[1]) as usize);
        for row in 0..grid[1] {
            for column in 0..grid[0] {
                let azimuth = [
                    -0.5 * f64::from(h_deg) + f64::from(column) * share[0] - margin_deg[0],
                    -0.5 * f64::from(h_deg) + f64::from(column + 1) * share[0] + margin_deg[0],
                ];
                let elevation = [
                    0.5 * f64::from(v_deg) - f64::from(row + 1) * share[1] - margin_deg[1],
                    0.5 * f64::from(v_deg) - f64::from(row) * share[1] + margin_deg[1],
                ];
                tiles.push(tile(azimuth, elevation, px_per_deg));
            }
        }
        let mut panorama = Self {
            size_px,
            fov_deg,
            grid,
            tiles,
            samples: Vec::with_capacity(size_px[0] as usize * size_px[1] as usize),
        };
        for y in 0..size_px[1] {
            for x in 0..size_px[0] {
                let sample = panorama.locate(x, y);
                panorama.samples.push(sample);
            }
        }
        Ok(panorama)
    }

    /// The tiles, row by row from the top, left to right.
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }

    /// Tiles across and down.
    pub fn grid(&self) -> [u32; 2] {
        self.grid
    }

    /// Pixels per degree of the output, horizontal then vertical.
    pub fn pixels_per_degree(&self) -> [f32; 2] {
        [
            self.size_px[0] as f32 / self.fov_deg[0],
            self.size_px[1] as f32 / self.fov_deg[1],
        ]
    }

    /// The camera-frame direction (-Z forward, `+y` up) of the centre of
    /// output pixel `(x, y)`.
    pub fn direction(&self, x: u32, y: u32) -> DVec3 {
        let [w, h] = self.size_px.map(f64::from);
        let [fh, fv] = self.fov_deg.map(f64::from);
        let azimuth = ((f64::from(x) + 0.5) / w * fh - 0.5 * fh).to_radians();
        let elevation = (0.5 * fv - (f64::from(y) + 0.5) / h * fv).to_radians();
        DVec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            -elevation.cos() * azimuth.cos(),
        )
    }

    fn locate(&self, x: u32, y: u32) -> Sample {
        let column = (x * self.grid[0] / self.size_px[0]).min(self.grid[0] - 1);
        let row = (y * self.grid[1] / self.size_px[1]).min(self.grid[1] - 1);
        let index = row * self.grid[0] + column;
        let t = &self.tiles[index as usize];
        let d = t.rotation.as_dquat().inverse() * self.direction(x, y);
        let [px, py] = direction_to_pixel_in_edges(d, t.size_px, t.edges_deg);
        Sample {
            tile: index as u16,
            x: px as f32,
            y: py as f32,
        }
    }

    /// The output image (RGBA8, rows top first) from the tiles' images (in
    /// [`tiles`](Self::tiles) order, each RGBA8 of its tile's size), by
    /// bilinear interpolation of the stored values.
    pub fn resample(&self, tiles_rgba: &[Vec<u8>], out: &mut Vec<u8>) -> anyhow::Result<()> {
        if tiles_rgba.len() != self.tiles.len() {
            anyhow::bail!(
                "{} tile images for {} tiles",
                tiles_rgba.len(),
                self.tiles.len()
            );
        }
        for (n, (image, t)) in tiles_rgba.iter().zip(&self.tiles).enumerate() {
            let expected = 4 * t.size_px[0] as usize * t.size_px[1] as usize;
            if image.len() != expected {
                anyhow::bail!("tile {n}: {} bytes, {expected} expected", image.len());
            }
        }
        out.clear();
        out.reserve(self.samples.len() * 4);
        for s in &self.samples {
            let t = &self.tiles[s.tile as usize];
            let image = &tiles_rgba[s.tile as usize];
            let [w, h] = t.size_px;
            // Pixel centres lie at half-integers.
            let fx = (s.x - 0.5).clamp(0.0, (w - 1) as f32);
            let fy = (s.y - 0.5).clamp(0.0, (h - 1) as f32);
            let (x0, y0) = (fx as u32, fy as u32);
            let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
            let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
            let at = |x: u32, y: u32, c: usize| f32::from(image[4 * (y * w + x) as usize + c]);
            for c in 0..4 {
                let top = at(x0, y0, c) * (1.0 - tx) + at(x1, y0, c) * tx;
                let bottom = at(x0, y1, c) * (1.0 - tx) + at(x1, y1, c) * tx;
                out.push((top * (1.0 - ty) + bottom * ty).round() as u8);
            }
        }
        Ok(())
    }
}

/// The tile covering azimuths `azimuth_deg` and elevations
/// `elevation_deg` (each `[low, high]`), at no fewer than `px_per_deg`
/// pixels per degree at its centre.
fn tile(azimuth_deg: [f64; 2], elevation_deg: [f64; 2], px_per_deg: [f64; 2]) -> Tile {
    let centre = [
        0.5 * (azimuth_deg[0] + azimuth_deg[1]),
        0.5 * (elevation_deg[0] + elevation_deg[1]),
    ];
    let rotation = Quat::from_rotation_y(-(centre[0] as f32).to_radians())
        * Quat::from_rotation_x((centre[1] as f32).to_radians());
    let to_tile = rotation.as_dquat().inverse();
    // The box's outline bounds its image in the tile's plane.
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    const STEPS: u32 = 64;
    for k in 0..=STEPS {
        let s = f64::from(k) / f64::from(STEPS);
        let a = azimuth_deg[0] + s * (azimuth_deg[1] - azimuth_deg[0]);
        let e = elevation_deg[0] + s * (elevation_deg[1] - elevation_deg[0]);
        for (az, el) in [
            (a, elevation_deg[0]),
            (a, elevation_deg[1]),
            (azimuth_deg[0], e),
            (azimuth_deg[1], e),
        ] {
            let (az, el) = (az.to_radians(), el.to_radians());
            let d = to_tile * DVec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos());
            let slope = [d.x / -d.z, d.y / -d.z];
            for i in 0..2 {
                lo[i] = lo[i].min(slope[i]);
                hi[i] = hi[i].max(slope[i]);
            }
        }
    }
    // At the centre, one unit of slope spans 180 / pi deg.
    let size_px = [0, 1]
        .map(|i| ((hi[i] - lo[i]) * px_per_deg[i] * 180.0 / std::f64::consts::PI).ceil() as u32);
    Tile {
        rotation,
        edges_deg: [
            lo[0].atan().to_degrees(),
            hi[0].atan().to_degrees(),
            hi[1].atan().to_degrees(),
            lo[1].atan().to_degrees(),
        ],
        size_px,
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn tile_forward(tile: &Tile) -> Vec3 {
        tile.rotation * Vec3::NEG_Z
    }

    #[test]
    fn reddys_field_takes_three_by_two_tiles_under_ninety_degrees() {
        let p = Panorama::new([1280, 1024], [200.0, 135.0]).unwrap();
        assert_eq!(p.grid(), [3, 2]);
        for t in p.tiles() {
            let [l, r, u, d] = t.edges_deg;
            assert!(r - l < 90.0 && u - d < 90.0, "{t:?}");
            assert!(t.size_px[0] < 1280 && t.size_px[1] < 1024, "{t:?}");
        }
        // The middle column's tiles look straight ahead, pitched up and down.
        let up = tile_forward(&p.tiles()[1]);
        assert!(up.x.abs() < 1e-6 && (up.y.asin().to_degrees() - 33.75).abs() < 0.1);
        let left = tile_forward(&p.tiles()[3]);
        assert!(left.x < 0.0 && left.y < 0.0, "{left}");
        let one = Panorama::new([400, 300], [60.0, 45.0]).unwrap();
        assert_eq!(one.grid(), [1, 1]);
    }

    #[test]
    fn every_output_pixel_samples_its_own_direction_inside_its_tile() {
        let p = Panorama::new([320, 216], [200.0, 135.0]).unwrap();
        let [w, h] = p.size_px;
        for y in 0..h {
            for x in 0..w {
                let s = p.samples[(y * w + x) as usize];
                let t = &p.tiles[s.tile as usize];
                let [tw, th] = t.size_px.map(|n| n as f32);
                assert!(
                    s.x >= 0.5 && s.x <= tw - 0.5 && s.y >= 0.5 && s.y <= th - 0.5,
                    "pixel ({x}, {y}) samples ({}, {}) of a {tw}x{th} tile",
                    s.x,
                    s.y
                );
                // Back from the tile's image plane to the camera frame.
                let [l, r, u, d] = t.edges_deg.map(|a| a.to_radians().tan());
                let sx = l + f64::from(s.x) / f64::from(tw) * (r - l);
                let sy = u - f64::from(s.y) / f64::from(th) * (u - d);
                let back = t.rotation.as_dquat() * DVec3::new(sx, sy, -1.0).normalize();
                let angle = back.angle_between(p.direction(x, y)).to_degrees();
                assert!(angle < 0.01, "pixel ({x}, {y}) is {angle} deg off");
            }
        }
    }

    #[test]
    fn tiles_hold_at_least_the_outputs_pixels_per_degree() {
        let p = Panorama::new([1280, 1024], [200.0, 135.0]).unwrap();
        let [ppd_x, ppd_y] = p.pixels_per_degree().map(f64::from);
        for t in p.tiles() {
            // The coarsest spot of a planar tile is its view axis, whether
            // or not that lies inside its edges.
            let [l, r, u, d] = t.edges_deg.map(|a| a.to_radians().tan());
            let per_deg = |n: u32, span: f64| f64::from(n) / span * std::f64::consts::PI / 180.0;
            assert!(per_deg(t.size_px[0], r - l) >= ppd_x, "{t:?}");
            assert!(per_deg(t.size_px[1], u - d) >= ppd_y, "{t:?}");
        }
    }

    #[test]
    fn resampling_a_uniform_tile_set_gives_their_colour_and_checks_sizes() {
        let p = Panorama::new([90, 60], [200.0, 135.0]).unwrap();
        let mut tiles: Vec<Vec<u8>> = p
            .tiles()
            .iter()
            .enumerate()
            .map(|(n, t)| {
                [n as u8 * 40, 7, 200, 255].repeat((t.size_px[0] * t.size_px[1]) as usize)
            })
            .collect();
        let mut out = Vec::new();
        p.resample(&tiles, &mut out).unwrap();
        assert_eq!(out.len(), 90 * 60 * 4);
        // Top-left pixel: tile 0; bottom-right: tile 5.
        assert_eq!(&out[..4], &[0, 7, 200, 255]);
        assert_eq!(&out[out.len() - 4..], &[200, 7, 200, 255]);
        tiles[2].pop();
        assert!(
            p.resample(&tiles, &mut out)
                .unwrap_err()
                .to_string()
                .contains("tile 2")
        );
        assert!(p.resample(&tiles[..5], &mut out).is_err());
        assert!(Panorama::new([10, 10], [360.0, 90.0]).is_err());
        assert!(Panorama::new([0, 10], [100.0, 90.0]).is_err());
    }
}
