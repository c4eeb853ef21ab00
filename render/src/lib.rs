//! `acuity-render`: one shared headless renderer (wgpu), used by the
//! offline pass (crate `acuity-preprocess`) and by the real-time scenes
//! (crate `acuity-cli`), and what it draws: [`mesh`] (indexed triangle
//! meshes and the OBJ/MTL loader), [`gltf_mesh`] (the glTF 2.0 loader),
//! [`files`] (either, by extension), [`texture`] (base-colour textures and
//! their mips); and writers for what the offline pass ships: [`gltf_write`]
//! (an LOD chain as one `.glb`) and [`obj_write`]. [`Error`] is the one
//! error type of the renderer, the loaders and the offline pass (which
//! re-exports it).
//!
//! A crate of its own because the scene player uses the renderer and the
//! loader as much as the offline pass does: they need neither the offline
//! pass's analysis nor the runtime.
//!
//! # Decisions
//! - **One device** per [`Renderer`]; meshes are uploaded once
//!   ([`Renderer::upload_mesh`]) and drawn by id. The renderer is `Sync`;
//!   concurrent [`Renderer::render`] calls are serialised by an internal lock
//!   (the GPU queue is serial anyway).
//! - **Adapter**: the backends in `WGPU_BACKEND` when set, else every native
//!   backend, then the GL backend alone as a fallback. On a machine without
//!   a GPU this is Mesa's llvmpipe through EGL (GL backend). No adapter at
//!   all is an error ([`Error::NoAdapter`]), never a silent pass.
//! - **Shading** (same as the run-time renderer): one directional light plus
//!   ambient, Lambert, `colour = vertex colour × texture × (ambient +
//!   diffuse × max(0, n·l))`. The base-colour texture ([`texture`]) is
//!   sampled trilinearly from its mip chain (made on the CPU at upload) in
//!   linear light; a mesh without one samples a white texel, which leaves
//!   its colour exactly as it is. Both sides of a triangle are lit (the normal is flipped on
//!   back faces), no culling, so inconsistent winding in files is harmless.
//! - **Output** is `Rgba8UnormSrgb`: the shader works in linear RGB and the
//!   target encodes to sRGB, so the bytes read back are sRGB8 — exactly what
//!   the offline pass's `segment` module converts to CIELUV. Rows are top
//!   first, tightly packed (the 256-byte row padding of the copy is
//!   stripped).
//! - **4x MSAA** by default ([`DEFAULT_MSAA_SAMPLES`]), as real applications
//!   draw: edges are blended over a pixel, so a silhouette that moves by a
//!   fraction of a pixel between LODs changes its edge pixels by that
//!   fraction (a low-contrast change), not by a whole aliased step. The
//!   offline pass and the scene renderer draw alike. `msaa_samples = 1`
//!   turns it off.
//! - **Cross-fades are dithered**, not blended ([`DitherMask`]): an
//!   instance may carry a screen-door mask that keeps the fragments whose
//!   4x4 ordered-dither (Bayer) threshold at the pixel lies in a range, so
//!   an object fading between two LODs draws both with complementary
//!   masks and every pixel shows exactly one of them, through the usual
//!   depth test and without sorting or blending. The mask is per pixel
//!   (all MSAA samples of a pixel keep or drop together), and fractions
//!   take effect in steps of 1/16.
//! - **Colour overrides**: an instance may carry a surface colour that
//!   replaces its mesh's vertex colours and texture and is lit as usual
//!   ([`RenderRequest::albedo`]), for overlays such as a viewer's colour
//!   per LOD (one flat hue per object, whatever the mesh's own colours);
//!   other instances are drawn as they are.
//!   Instances are grouped per mesh and packed in their own module
//!   (`instances`).
//! - **Deterministic**: the same requests give the same bytes (fixed
//!   pipeline state and sample pattern, no blending; llvmpipe rasterises
//!   deterministically).
//! - **Per frame** only the uniforms and instance data are written; the
//!   targets, their views and the readback buffer are made once per size,
//!   the pipeline and bind group once. The readback buffer is mapped once
//!   per frame and copied out in one piece when rows need no padding.
//! - **sRGB target**: `Rgba8UnormSrgb`, not `Rgba8Unorm`: the latter would
//!   save the encode but quantise linear light to 8 bits. Where the time
//!   goes on llvmpipe is measured in `docs/performance.md`.

mod dither;
pub mod error;
pub mod files;
mod gltf_data;
pub mod gltf_mesh;
mod gltf_nodes;
pub mod gltf_write;
mod instances;
pub mod mesh;
mod mtl;
mod obj_text;
pub mod obj_write;
mod pipeline;
pub mod texture;

use std::collections::HashMap;
use std::sync::{Arc, Mutex, Weak};

use glam::{Mat4, Vec3};

use crate::pipeline::{UNIFORM_SIZE, VERTEX_STRIDE};

pub use crate::dither::DitherMask;
pub use crate::error::Error;
pub use crate::files::{LoadedChain, is_gltf, load_mesh_file};
pub use crate::mesh::{LoadedMesh, Mesh};
pub use crate::texture::Texture;

/// MSAA samples of [`RendererOptions::default`] (and of the offline pass's
/// default settings).
pub const DEFAULT_MSAA_SAMPLES: u32 = 4;

/// The colour target's format. See the module docs.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Handle of a mesh uploaded with [`Renderer::upload_mesh`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MeshId(pub u32);

/// Lighting of a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    /// Direction *towards* the light, world space (need not be unit length).
    pub direction_to_light: [f32; 3],
    /// Diffuse intensity, multiplies the Lambert term (0..1 typical).
    pub diffuse: f32,
    /// Ambient intensity, added to the Lambert term (0..1 typical).
    pub ambient: f32,
}

impl Default for Lighting {
    /// A light over the viewer's right shoulder in view space is not
    /// possible in world space, so: from +X +Y +Z, diffuse 0.75, ambient 0.25.
    fn default() -> Self {
        Self {
            direction_to_light: [0.4, 0.8, 0.45],
            diffuse: 0.75,
            ambient: 0.25,
        }
    }
}

/// One frame to render.
#[derive(Debug, Clone)]
pub struct RenderRequest<'a> {
    /// Image width in pixels (1..=the adapter's texture limit).
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// World to clip space, wgpu conventions (depth 0..1, y up in NDC).
    pub view_proj: Mat4,
    /// What to draw: a mesh and its model-to-world matrix. Instances of the
    /// same mesh are drawn with one instanced draw call.
    pub instances: &'a [(MeshId, Mat4)],
    /// Each instance's dither mask, in the order of `instances`; empty:
    /// none masked (else exactly one per instance).
    pub dither: &'a [DitherMask],
    /// Each instance's surface colour, in the order of `instances`: linear
    /// RGB in `[0, 1]`, replacing its mesh's vertex colours and texture,
    /// lit as usual. Empty: every mesh keeps its own colours (else exactly
    /// one per instance).
    pub albedo: &'a [[f32; 3]],
    /// The light.
    pub lighting: Lighting,
    /// Background colour, sRGB8 (written to the image as is).
    pub background_srgb: [u8; 3],
}

/// A rendered frame.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA8, sRGB-encoded, rows top first, `width * 4` bytes per row.
    pub rgba: Vec<u8>,
    /// Triangles submitted (instances × triangles of their mesh).
    pub triangles: u64,
    /// Draw calls issued (one per distinct mesh).
    pub draw_calls: u32,
}

/// Options for [`Renderer::new`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RendererOptions {
    /// MSAA sample count: 4 (default), 1 (no anti-aliasing) or another
    /// count the adapter supports for `Rgba8UnormSrgb`.
    pub msaa_samples: u32,
}

impl Default for RendererOptions {
    fn default() -> Self {
        Self {
            msaa_samples: DEFAULT_MSAA_SAMPLES,
        }
    }
}

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// The mesh's texture and sampler (shared by meshes with the same
    /// texture; the white texel for untextured meshes).
    material: Arc<wgpu::BindGroup>,
}

struct Target {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    // Views are made once with their textures, not per frame.
    color_view: wgpu::TextureView,
    msaa_view: Option<wgpu::TextureView>,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_bytes_per_row: u32,
}

struct State {
    meshes: Vec<Option<GpuMesh>>,
    /// Uploaded textures by the address of their [`Texture`], which each
    /// entry keeps alive (so the address is not reused); an entry whose
    /// bind group no mesh holds any more is dropped at the next upload.
    textures: HashMap<usize, (Arc<Texture>, Weak<wgpu::BindGroup>)>,
    target: Option<Target>,
    instance_buf: Option<wgpu::Buffer>,
    /// The frame's instances, grouped and packed (kept for its buffers).
    packer: instances::Packer,
}

/// The shared headless renderer. See the module docs.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    material_layout: wgpu::BindGroupLayout,
    white: Arc<wgpu::BindGroup>,
    samples: u32,
    adapter_info: String,
    max_dim: u32,
    state: Mutex<State>,
}

impl Renderer {
    /// Creates the device (once) and the pipeline. Fails with
    /// [`Error::NoAdapter`] when no adapter exists, with [`Error::Settings`]
    /// when the sample count is unsupported.
    pub fn new(options: &RendererOptions) -> Result<Self, Error> {
        pollster::block_on(Self::new_async(options))
    }

    async fn new_async(options: &RendererOptions) -> Result<Self, Error> {
        let env = wgpu::Backends::from_env();
        let first = env.unwrap_or(wgpu::Backends::all());
        let mut tried = vec![format!("{first:?}")];
        let mut found = Self::try_adapter(first).await;
        if found.is_none() && env.is_none() && first != wgpu::Backends::GL {
            tried.push("GL".into());
            found = Self::try_adapter(wgpu::Backends::GL).await;
        }
        let adapter = found.ok_or_else(|| Error::NoAdapter {
            tried: tried.join(", then "),
        })?;
        let info = adapter.get_info();
        let adapter_info = format!("{} ({:?}, {})", info.name, info.backend, info.driver);

        let samples = options.msaa_samples;
        let flags = adapter.get_texture_format_features(COLOR_FORMAT).flags;
        if samples == 0 || (samples > 1 && !flags.sample_count_supported(samples)) {
            return Err(Error::Settings {
                field: "msaa_samples",
                message: format!("{samples} samples not supported by {adapter_info}"),
            });
        }
        let limits = adapter.limits();
        let max_dim = limits.max_texture_dimension_2d;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("acuity"),
                required_features: wgpu::Features::empty(),
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| Error::Gpu {
                message: format!("request_device on {adapter_info}: {e}"),
            })?;

        let pipeline::Pipeline {
            pipeline,
            uniforms,
            bind_group,
            material_layout,
        } = pipeline::Pipeline::new(&device, samples);
        let white_texture = Texture::from_rgba(1, 1, vec![255; 4], "white")
            .map_err(|message| Error::Gpu { message })?;
        let white = Arc::new(texture::bind_group(
            &device,
            &queue,
            &material_layout,
            &white_texture,
            max_dim,
        ));
        Ok(Self {
            device,
            queue,
            pipeline,
            uniforms,
            bind_group,
            material_layout,
            white,
            samples,
            adapter_info,
            max_dim,
            state: Mutex::new(State {
                meshes: Vec::new(),
                textures: HashMap::new(),
                target: None,
                instance_buf: None,
                packer: instances::Packer::default(),
            }),
        })
    }

    async fn try_adapter(backends: wgpu::Backends) -> Option<wgpu::Adapter> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
            .await
            .ok()
    }

    /// The adapter in use: name, backend and driver, for logs and reports.
    pub fn adapter_info(&self) -> &str {
        &self.adapter_info
    }

    /// The MSAA sample count this renderer draws with.
    pub fn msaa_samples(&self) -> u32 {
        self.samples
    }

    /// Uploads a mesh once; draw it by the returned id. The mesh must pass
    /// [`Mesh::check`] (else [`Error::Settings`]).
    pub fn upload_mesh(&self, mesh: &Mesh) -> Result<MeshId, Error> {
        mesh.check().map_err(|message| Error::Settings {
            field: "mesh",
            message,
        })?;
        let mut vbytes = Vec::with_capacity(mesh.positions.len() * VERTEX_STRIDE as usize);
        for i in 0..mesh.positions.len() {
            let uv = mesh.uvs.get(i).copied().unwrap_or([0.0; 2]);
            for a in [mesh.positions[i], mesh.normals[i], mesh.colors[i]] {
                for c in a {
                    vbytes.extend_from_slice(&c.to_le_bytes());
                }
            }
            for c in uv {
                vbytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        let mut ibytes: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        // COPY_BUFFER_ALIGNMENT is 4: u32 indices and f32 vertices always are.
        if ibytes.is_empty() {
            ibytes.extend_from_slice(&[0; 4]);
        }
        let vertices = self.buffer_with(&vbytes, wgpu::BufferUsages::VERTEX);
        let indices = self.buffer_with(&ibytes, wgpu::BufferUsages::INDEX);
        let mut state = self.lock();
        let material = match &mesh.texture {
            None => self.white.clone(),
            Some(t) => {
                state.textures.retain(|_, (_, bg)| bg.strong_count() > 0);
                let key = Arc::as_ptr(t) as usize;
                match state.textures.get(&key).and_then(|(_, bg)| bg.upgrade()) {
                    Some(bg) => bg,
                    None => {
                        let bg = Arc::new(texture::bind_group(
                            &self.device,
                            &self.queue,
                            &self.material_layout,
                            t,
                            self.max_dim,
                        ));
                        state.textures.insert(key, (t.clone(), Arc::downgrade(&bg)));
                        bg
                    }
                }
            }
        };
        state.meshes.push(Some(GpuMesh {
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
            material,
        }));
        Ok(MeshId(state.meshes.len() as u32 - 1))
    }

    /// Frees a mesh's GPU buffers. Its id becomes invalid (rendering it is
    /// an error); ids are not reused. Unknown ids are ignored.
    pub fn free_mesh(&self, id: MeshId) {
        if let Some(slot) = self.lock().meshes.get_mut(id.0 as usize) {
            *slot = None;
        }
    }

    fn buffer_with(&self, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes.len() as u64,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic while holding the lock leaves only GPU handles behind;
        // keep going with them.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Renders one frame offscreen, waits for the GPU and reads the image
    /// back. The call returns only when the frame is complete, so timing it
    /// measures render + readback honestly.
    pub fn render(&self, req: &RenderRequest<'_>) -> Result<RenderOutput, Error> {
        if req.width == 0
            || req.height == 0
            || req.width > self.max_dim
            || req.height > self.max_dim
        {
            return Err(Error::Settings {
                field: "width/height",
                message: format!(
                    "{}x{} outside 1..={} pixels",
                    req.width, req.height, self.max_dim
                ),
            });
        }
        let mut state = self.lock();
        let state = &mut *state;
        instances::check(req, |id| {
            state.meshes.get(id.0 as usize).is_some_and(Option::is_some)
        })?;
        self.ensure_target(state, req.width, req.height);

        // Uniforms.
        let l = Vec3::from(req.lighting.direction_to_light)
            .try_normalize()
            .unwrap_or(Vec3::Z);
        let mut u = [0u8; UNIFORM_SIZE as usize];
        let floats = req.view_proj.to_cols_array().into_iter().chain([
            l.x,
            l.y,
            l.z,
            0.0,
            req.lighting.diffuse,
            req.lighting.ambient,
            0.0,
            0.0,
        ]);
        for (dst, f) in u.chunks_exact_mut(4).zip(floats) {
            dst.copy_from_slice(&f.to_le_bytes());
        }
        self.queue.write_buffer(&self.uniforms, 0, &u);

        let meshes = &state.meshes;
        let triangles = state.packer.pack(req, |id| {
            meshes[id.0 as usize].as_ref().map_or(0, |m| m.index_count)
        });
        let (ibytes, ranges) = (&state.packer.bytes, &state.packer.ranges);
        if !ibytes.is_empty() {
            let need = ibytes.len() as u64;
            if state.instance_buf.as_ref().is_none_or(|b| b.size() < need) {
                state.instance_buf = Some(self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("instances"),
                    size: need.next_power_of_two(),
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
            }
            if let Some(b) = &state.instance_buf {
                self.queue.write_buffer(b, 0, ibytes);
            }
        }

        let target = state.target.as_ref().expect("ensure_target set it");
        let (color_view, msaa_view, depth_view) =
            (&target.color_view, &target.msaa_view, &target.depth_view);
        let bg = req.background_srgb.map(|c| srgb8_to_linear(c) as f64);
        let mut enc = self.device.create_command_encoder(&Default::default());
        {
            let (view, resolve) = match &msaa_view {
                Some(ms) => (ms, Some(color_view)),
                None => (color_view, None),
            };
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("acuity frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: resolve,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: bg[0],
                            g: bg[1],
                            b: bg[2],
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            if let Some(ib) = &state.instance_buf {
                pass.set_vertex_buffer(1, ib.slice(..));
            }
            for (id, inst) in ranges {
                let Some(gm) = state.meshes[id.0 as usize].as_ref() else {
                    continue;
                };
                pass.set_bind_group(1, &*gm.material, &[]);
                pass.set_vertex_buffer(0, gm.vertices.slice(..));
                pass.set_index_buffer(gm.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..gm.index_count, 0, inst.clone());
            }
        }
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target.color,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &target.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(target.padded_bytes_per_row),
                    rows_per_image: Some(req.height),
                },
            },
            wgpu::Extent3d {
                width: req.width,
                height: req.height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([enc.finish()]);

        let (tx, rx) = std::sync::mpsc::channel();
        target
            .readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| {
                let _ = tx.send(r);
            });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu {
                message: format!("waiting for the frame: {e}"),
            })?;
        rx.recv()
            .map_err(|_| Error::Gpu {
                message: "readback callback never ran".into(),
            })?
            .map_err(|e| Error::Gpu {
                message: format!("mapping the readback buffer: {e}"),
            })?;
        let row = req.width as usize * 4;
        let mut rgba = Vec::with_capacity(row * req.height as usize);
        {
            let view = target
                .readback
                .get_mapped_range(..)
                .map_err(|e| Error::Gpu {
                    message: format!("reading the readback buffer: {e}"),
                })?;
            let padded = target.padded_bytes_per_row as usize;
            if padded == row {
                rgba.extend_from_slice(&view[..row * req.height as usize]);
            } else {
                for src in view.chunks(padded).take(req.height as usize) {
                    rgba.extend_from_slice(&src[..row]);
                }
            }
        }
        target.readback.unmap();
        Ok(RenderOutput {
            width: req.width,
            height: req.height,
            rgba,
            triangles,
            draw_calls: ranges.len() as u32,
        })
    }

    fn ensure_target(&self, state: &mut State, width: u32, height: u32) {
        if state
            .target
            .as_ref()
            .is_some_and(|t| t.width == width && t.height == height)
        {
            return;
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let tex = |format, samples, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: None,
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = tex(
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let msaa_color = (self.samples > 1).then(|| {
            tex(
                COLOR_FORMAT,
                self.samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
        });
        let depth = tex(
            DEPTH_FORMAT,
            self.samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let padded_bytes_per_row = (width * 4).div_ceil(align) * align;
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_bytes_per_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        state.target = Some(Target {
            width,
            height,
            color_view: view(&color),
            msaa_view: msaa_color.as_ref().map(view),
            depth_view: view(&depth),
            color,
            readback,
            padded_bytes_per_row,
        });
    }
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("adapter", &self.adapter_info)
            .field("msaa_samples", &self.samples)
            .finish_non_exhaustive()
    }
}

/// sRGB8 code value to linear intensity in `[0, 1]` (IEC 61966-2-1).
pub fn srgb8_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
