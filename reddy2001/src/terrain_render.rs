//! Drawing refined terrain with the project's renderer (`acuity-render`),
//! for `acuity terrain --render-every N`: the triangles become a mesh of
//! solid, lit, flat-shaded polygons (as in Reddy's runs), are uploaded,
//! drawn and read back, and the wall time of that is the frame's draw
//! time (reading back waits for the GPU, so the time is synchronised).
//!
//! A planar image cannot show a field of view of 200 deg, so each frame
//! is drawn as planar tiles under 90 deg each (3 x 2 for 200 x 135 deg),
//! every tile a render of the whole mesh by the camera turned to the
//! tile, and resampled into one equiangular image of the whole field
//! ([`crate::panorama`]): the image shows what the refinement selected
//! for, in the coordinates it selected in. The draw time is the upload,
//! every tile's draw and read-back (each read-back waits for the GPU);
//! the resampling is timed apart (a renderer would do it on the GPU as
//! one texture pass).

use std::time::Instant;

use acuity::Camera;
use acuity::terrain::{Refinement, Terrain};
use acuity_render::{Lighting, Mesh, RenderOutput, RenderRequest, Renderer, RendererOptions};
use anyhow::Context;
use glam::{Mat4, Vec3};

use crate::panorama::{Panorama, Tile};

const NEAR_PLANE_M: f32 = 1.0;

/// The renderer and a reused mesh buffer.
pub struct TerrainRenderer {
    renderer: Renderer,
    mesh: Mesh,
    panorama: Panorama,
    size: [u32; 2],
    z_range: [f32; 2],
    tile_images: Vec<Vec<u8>>,
}

/// One drawn frame.
pub struct Drawn {
    /// Building the mesh from the triangles, ms (CPU).
    pub build_ms: f64,
    /// Uploading, drawing every tile and reading them back, ms
    /// (GPU-synchronised).
    pub draw_ms: f64,
    /// Resampling the tiles into the image, ms (CPU).
    pub resample_ms: f64,
    /// The equiangular image of the whole field; its triangle and draw
    /// call counts are summed over the tiles.
    pub image: RenderOutput,
}

impl TerrainRenderer {
    /// A renderer for `size` pixel equiangular images of a `fov_deg`
    /// field (see the module docs). Fails without a GPU adapter (software
    /// adapters count).
    pub fn new(size: [u32; 2], fov_deg: [f32; 2], terrain: &Terrain) -> anyhow::Result<Self> {
        let panorama = Panorama::new(size, fov_deg).context("tiling the drawn field")?;
        let renderer =
            Renderer::new(&RendererOptions::default()).context("creating the terrain renderer")?;
        let field = terrain.heightfield();
        let [w, d] = field.size();
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for j in 0..d {
            for i in 0..w {
                lo = lo.min(field.at(i, j));
                hi = hi.max(field.at(i, j));
            }
        }
        Ok(Self {
            renderer,
            mesh: Mesh {
                positions: Vec::new(),
                normals: Vec::new(),
                colors: Vec::new(),
                indices: Vec::new(),
                normals_computed: false,
                uvs: Vec::new(),
                texture: None,
            },
            panorama,
            size,
            z_range: [lo, hi.max(lo + 1e-3)],
            tile_images: Vec::new(),
        })
    }

    /// The adapter's description.
    pub fn adapter(&self) -> &str {
        self.renderer.adapter_info()
    }

    /// The tiles each frame is drawn as.
    pub fn panorama(&self) -> &Panorama {
        &self.panorama
    }

    /// Draws one refinement seen by `camera`.
    pub fn draw(
        &mut self,
        terrain: &Terrain,
        refinement: &Refinement,
        camera: &Camera,
    ) -> anyhow::Result<Drawn> {
        let start = Instant::now();
        self.build_mesh(terrain, refinement);
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let id = self.renderer.upload_mesh(&self.mesh)?;
        let (mut triangles, mut draw_calls) = (0, 0);
        self.tile_images.clear();
        for tile in self.panorama.tiles() {
            let request = RenderRequest {
                width: tile.size_px[0],
                height: tile.size_px[1],
                view_proj: view_proj(camera, tile),
                instances: &[(id, Mat4::IDENTITY)],
                dither: &[],
                albedo: &[],
                lighting: Lighting {
                    direction_to_light: [0.3, -0.4, 0.85],
                    ..Lighting::default()
                },
                background_srgb: [150, 190, 235],
            };
            match self.renderer.render(&request) {
                Ok(out) => {
                    triangles += out.triangles;
                    draw_calls += out.draw_calls;
                    self.tile_images.push(out.rgba);
                }
                Err(e) => {
                    self.renderer.free_mesh(id);
                    return Err(e.into());
                }
            }
        }
        self.renderer.free_mesh(id);
        let draw_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let mut rgba = Vec::new();
        self.panorama.resample(&self.tile_images, &mut rgba)?;
        Ok(Drawn {
            build_ms,
            draw_ms,
            resample_ms: start.elapsed().as_secs_f64() * 1e3,
            image: RenderOutput {
                width: self.size[0],
                height: self.size[1],
                rgba,
                triangles,
                draw_calls,
            },
        })
    }

    /// Flat-shaded triangles coloured by height (valley green to rock to
    /// snow). Vertices are not shared, so each triangle has its own normal.
    fn build_mesh(&mut self, terrain: &Terrain, refinement: &Refinement) {
        let m = &mut self.mesh;
        m.positions.clear();
        m.normals.clear();
        m.colors.clear();
        m.indices.clear();
        let [lo, hi] = self.z_range;
        for tri in refinement.triangles() {
            let p = tri.map(|v| Vec3::from(terrain.vertex_position(v)));
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Z);
            let t = ((p[0].z + p[1].z + p[2].z) / 3.0 - lo) / (hi - lo);
            let colour = if t < 0.5 {
                Vec3::new(0.12, 0.35, 0.08).lerp(Vec3::new(0.4, 0.33, 0.25), 2.0 * t)
            } else {
                Vec3::new(0.4, 0.33, 0.25).lerp(Vec3::splat(0.9), 2.0 * t - 1.0)
            };
            for q in p {
                m.indices.push(m.positions.len() as u32);
                m.positions.push(q.to_array());
                m.normals.push(n.to_array());
                m.colors.push(colour.to_array());
            }
        }
    }
}

/// World to clip for one tile: the camera turned to the tile, with the
/// tile's perspective (infinite far plane, depth 0 to 1, wgpu).
fn view_proj(camera: &Camera, tile: &Tile) -> Mat4 {
    let orientation = camera.orientation * tile.rotation;
    let view = Mat4::from_rotation_translation(orientation, camera.position.as_vec3()).inverse();
    tile.projection(NEAR_PLANE_M) * view
}

#[cfg(test)]
mod tests {
    use acuity::terrain::{Heightfield, TerrainSettings, TerrainView};
    use acuity::{Components, EccentricityModel, VelocityModel};
    use glam::DVec3;

    use super::*;

    /// Over a flat plain 6.4 km across, seen level from 100 m above its
    /// middle, every pixel of the 200 x 135 deg field more than 3 deg below
    /// the horizon is ground (the plain's edge is 1.8 deg below it) and
    /// every pixel above it sky: the tiles leave no gap at their seams.
    #[test]
    fn the_whole_field_is_drawn_and_the_tiles_join() {
        let n = 65;
        let field = Heightfield::new(n, n, 100.0, vec![0.0; n * n]).unwrap();
        let terrain = Terrain::new(field);
        let camera = Camera::look_to(DVec3::new(3200.0, 3200.0, 100.0), Vec3::Y, Vec3::Z).unwrap();
        let settings = TerrainSettings {
            components: Components::NONE,
            viewport_cull: false,
            fov_deg: [200.0, 135.0],
            display_limit_cpd: 4.0,
            scale: 1.0,
            eccentricity_model: EccentricityModel::Reddy2001,
            velocity_model: VelocityModel::Reddy2001,
        };
        let view = TerrainView {
            camera,
            previous: None,
            dt_s: 0.1,
        };
        let mut refinement = Refinement::new();
        terrain.refine(&view, &settings, &mut refinement).unwrap();
        let (w, h) = (400, 270);
        let mut renderer = TerrainRenderer::new([w, h], [200.0, 135.0], &terrain).unwrap();
        let drawn = renderer.draw(&terrain, &refinement, &camera).unwrap();
        assert_eq!(drawn.image.rgba.len(), (w * h * 4) as usize);
        assert_eq!(drawn.image.draw_calls, 6);
        let sky = |x: u32, y: u32| {
            let p = &drawn.image.rgba[4 * (y * w + x) as usize..][..3];
            p == [150, 190, 235]
        };
        for y in 0..h {
            let elevation_deg = 67.5 - (y as f32 + 0.5) / h as f32 * 135.0;
            for x in 0..w {
                if elevation_deg < -3.0 {
                    assert!(!sky(x, y), "sky at ({x}, {y}), {elevation_deg} deg");
                } else if elevation_deg > 0.5 {
                    assert!(sky(x, y), "ground at ({x}, {y}), {elevation_deg} deg");
                }
            }
        }
    }
}
