//! Drawing refined terrain with the project's renderer (`acuity-render`),
//! for `acuity terrain --render-every N`: the triangles become a mesh of
//! solid, lit, flat-shaded polygons (as in Reddy's runs), are uploaded,
//! drawn and read back, and the wall time of that is the frame's draw
//! time (reading back waits for the GPU, so the time is synchronised).
//!
//! A planar image cannot show a field of view of 200 deg: the renderer
//! draws the central part, at most 120 deg across (the rest of the
//! triangles are still submitted and clipped by the GPU, so the draw time
//! covers every triangle the refinement produced).

use std::time::Instant;

use acuity::Camera;
use acuity::display::projection_columns;
use acuity::terrain::{Refinement, Terrain};
use acuity_render::{Lighting, Mesh, RenderOutput, RenderRequest, Renderer, RendererOptions};
use anyhow::Context;
use glam::{Mat4, Vec3};

/// Widest horizontal field of view drawn, deg.
pub const MAX_DRAWN_FOV_DEG: f32 = 120.0;
const NEAR_PLANE_M: f32 = 1.0;

/// The renderer and a reused mesh buffer.
pub struct TerrainRenderer {
    renderer: Renderer,
    mesh: Mesh,
    size: [u32; 2],
    fov_deg: [f32; 2],
    z_range: [f32; 2],
}

/// One drawn frame.
pub struct Drawn {
    /// Building the mesh from the triangles, ms (CPU).
    pub build_ms: f64,
    /// Uploading, drawing and reading back, ms (GPU-synchronised).
    pub draw_ms: f64,
    /// The image.
    pub image: RenderOutput,
}

impl TerrainRenderer {
    /// A renderer for `size` pixel images of the central part of a
    /// `fov_deg` field (see the module docs). Fails without a GPU adapter
    /// (software adapters count).
    pub fn new(size: [u32; 2], fov_deg: [f32; 2], terrain: &Terrain) -> anyhow::Result<Self> {
        let renderer =
            Renderer::new(&RendererOptions::default()).context("creating the terrain renderer")?;
        let h = fov_deg[0].min(MAX_DRAWN_FOV_DEG);
        let v = 2.0
            * ((0.5 * h).to_radians().tan() * size[1] as f32 / size[0] as f32)
                .atan()
                .to_degrees();
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
            size,
            fov_deg: [h, v],
            z_range: [lo, hi.max(lo + 1e-3)],
        })
    }

    /// The adapter's description.
    pub fn adapter(&self) -> &str {
        self.renderer.adapter_info()
    }

    /// The drawn field of view, horizontal then vertical, deg.
    pub fn drawn_fov_deg(&self) -> [f32; 2] {
        self.fov_deg
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
        let request = RenderRequest {
            width: self.size[0],
            height: self.size[1],
            view_proj: self.view_proj(camera),
            instances: &[(id, Mat4::IDENTITY)],
            dither: &[],
            lighting: Lighting {
                direction_to_light: [0.3, -0.4, 0.85],
                ..Lighting::default()
            },
            background_srgb: [150, 190, 235],
        };
        let image = self.renderer.render(&request);
        self.renderer.free_mesh(id);
        let image = image?;
        Ok(Drawn {
            build_ms,
            draw_ms: start.elapsed().as_secs_f64() * 1e3,
            image,
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

    /// World to clip: the camera's view with a perspective of the drawn
    /// field of view, infinite far plane, depth 0 to 1 (wgpu).
    fn view_proj(&self, camera: &Camera) -> Mat4 {
        let [h, v] = self.fov_deg.map(|a| 0.5 * f64::from(a));
        let columns = projection_columns([-h, h, v, -v], f64::from(NEAR_PLANE_M));
        let proj = Mat4::from_cols_array_2d(&columns.map(|c| c.map(|x| x as f32)));
        let view = Mat4::from_rotation_translation(camera.orientation, camera.position.as_vec3())
            .inverse();
        proj * view
    }
}
