//! glTF 2.0 input (`.gltf` with its buffers and images, or `.glb`): triangle
//! meshes with positions, normals, texture coordinates, vertex colours,
//! base-colour factor and texture, node transforms flattened, and the LOD
//! chain the file carries.
//!
//! The `gltf` crate parses and validates the document (every index names
//! an existing object); buffers, images and accessors are read by this
//! module, which checks every range, so a bad file gives an error naming
//! the part that is wrong (`accessor 3 (POSITION of mesh "rock"
//! primitive 0)`), never a panic.
//!
//! # Rules
//! - **What is drawn**: the default scene (else the first; a file with no
//!   scene: every root node), each node's mesh placed by the product of the
//!   transforms from the root (in f64), all in one mesh per LOD. Triangle
//!   lists, strips and fans are drawn; points and lines are skipped with a
//!   warning. Skins and morph targets are ignored (the rest pose is drawn).
//! - **LOD chain** ([`LodRule`]), first that applies:
//!   1. `MSFT_lod` on a node: `extensions.MSFT_lod.ids` lists the nodes of
//!      LOD 1, 2, ...; LOD `k` draws the scene with every such node replaced
//!      by its `k`-th level (its last one when it has fewer).
//!   2. Names: a node whose name (else its mesh's name) ends in `_LOD<n>`
//!      (any case, e.g. `rock_LOD0`, `rock_lod1`) belongs to LOD `n` with
//!      its subtree; LOD `k` draws the nodes of LOD `k` and every node with
//!      no LOD name. The numbers must run 0, 1, ... without a gap.
//!   3. Otherwise one LOD: everything.
//! - **Colour**: `COLOR_0` (linear) × the material's `baseColorFactor`
//!   (alpha ignored: surfaces are opaque) × its `baseColorTexture` (sRGB,
//!   sampled at the `TEXCOORD_n` it names, with the sampler's wrap modes).
//!   A mesh draws one texture: primitives with different textures, or
//!   textured and untextured ones, in one LOD are an error naming both
//!   materials. Vertex colours without a material are white × factor 1, as
//!   glTF's default material.
//! - **Normals**: `NORMAL` when every primitive of the LOD has them, else
//!   smooth normals are computed (as for OBJ).
//! - **Accessors**: float, or integer (normalised or, with
//!   `KHR_mesh_quantization`, not); sparse accessors are refused. Positions
//!   and texture coordinates must be finite.
//! - **Required extensions** other than `KHR_mesh_quantization` are refused
//!   with their name (a file that needs Draco or meshopt compression cannot
//!   be drawn without it).
//! - **Buffers and images**: the GLB binary chunk, `data:` URIs (base64), or
//!   files relative to the glTF file (percent-escapes decoded). A missing
//!   buffer is an error; a missing image a warning (the factor is drawn
//!   alone).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat3, DMat4, DVec3, Vec3};
use gltf::mesh::{Mode, Semantic};

use crate::gltf_data::{percent_decode, read_buffers, read_floats, read_indices, read_uri, short};
use crate::gltf_nodes::{MAX_NODE_DEPTH, check_hierarchy, lod_suffix, msft_lod_ids};
use crate::texture::{Texture, Wrap};
use crate::{Error, Mesh};

pub use crate::gltf_data::FileResolver;

/// How a glTF file's LOD chain was found (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LodRule {
    /// No chain in the file: one LOD.
    Single,
    /// The `MSFT_lod` extension.
    MsftLod,
    /// Node or mesh names ending in `_LOD<n>`.
    Names,
}

/// The LODs of a glTF file, finest first, and the loader's warnings.
#[derive(Debug, Clone)]
pub struct GltfLods {
    /// One mesh per LOD, finest first (at least one).
    pub lods: Vec<Mesh>,
    /// How the chain was found.
    pub rule: LodRule,
    /// Non-fatal problems, each naming the file.
    pub warnings: Vec<String>,
}

/// Reads a `.gltf` or `.glb` file; buffers and images it names are read
/// relative to its folder. See the module docs.
pub fn load_gltf(path: &Path) -> Result<GltfLods, Error> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    let dir = path.parent().map(Path::to_owned).unwrap_or_default();
    let mut resolve = |uri: &str| {
        let p = dir.join(uri);
        std::fs::read(&p).map(|b| (p, b))
    };
    parse_gltf(&bytes, path, &mut resolve)
}

/// The external files (buffers, images) a glTF names, as [`load_gltf`]
/// would resolve them, without reading them; empty for a file that does
/// not parse. For input hashes.
pub fn external_files(bytes: &[u8], path: &Path) -> Vec<PathBuf> {
    let Ok(g) = parse_document(bytes, path) else {
        return Vec::new();
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let buffers = g.document.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(u) => Some(u),
        gltf::buffer::Source::Bin => None,
    });
    let images = g.document.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    buffers
        .chain(images)
        .filter(|u| !u.starts_with("data:"))
        .map(|u| dir.join(percent_decode(u)))
        .collect()
}

/// Parses glTF or GLB bytes. `path` names the file in messages; `resolve`
/// reads the external files it names. Never panics.
pub fn parse_gltf(
    bytes: &[u8],
    path: &Path,
    resolve: &mut FileResolver<'_>,
) -> Result<GltfLods, Error> {
    let bad = |message: String| Error::InvalidMesh {
        path: path.to_owned(),
        message,
    };
    let g = parse_document(bytes, path)?;
    let doc = &g.document;
    if let Some(ext) = doc
        .extensions_required()
        .find(|e| *e != "KHR_mesh_quantization")
    {
        return Err(bad(format!(
            "requires the extension `{ext}`, which acuity cannot read"
        )));
    }
    let mut warnings = Vec::new();
    let buffers = read_buffers(doc, g.blob.as_deref(), resolve).map_err(bad)?;
    let mut ctx = Ctx {
        path,
        buffers,
        textures: HashMap::new(),
        resolve,
        warnings: &mut warnings,
    };

    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    check_hierarchy(doc).map_err(bad)?;
    let msft = msft_lod_ids(doc).map_err(bad)?;
    let names: Vec<Option<usize>> = doc
        .nodes()
        .map(|n| {
            n.name()
                .and_then(lod_suffix)
                .or_else(|| n.mesh().and_then(|m| m.name()).and_then(lod_suffix))
        })
        .collect();
    let (rule, n_lods) = if let Some(n) = msft.values().map(|ids| ids.len() + 1).max() {
        (LodRule::MsftLod, n)
    } else if names.iter().any(Option::is_some) {
        let mut levels: Vec<usize> = names.iter().flatten().copied().collect();
        levels.sort_unstable();
        levels.dedup();
        if let Some(gap) = (0..levels.len()).find(|&k| levels[k] != k) {
            return Err(bad(format!(
                "nodes are named for LODs {levels:?} (names ending in `_LOD<n>`): LOD {gap} is missing"
            )));
        }
        (LodRule::Names, levels.len())
    } else {
        (LodRule::Single, 1)
    };

    let mut lods = Vec::with_capacity(n_lods);
    for level in 0..n_lods {
        let mut acc = Accum::default();
        let mut stack = Vec::new();
        for root in &roots {
            let pick = Pick {
                level,
                rule,
                msft: &msft,
                names: &names,
            };
            visit(
                &mut ctx,
                doc,
                root,
                DMat4::IDENTITY,
                &pick,
                &mut stack,
                &mut acc,
            )?;
        }
        lods.push(acc.finish(path, level, n_lods)?);
    }
    Ok(GltfLods {
        lods,
        rule,
        warnings,
    })
}

/// Parses and validates the document, after checking the GLB header the
/// `gltf` crate would subtract from without a check.
fn parse_document(bytes: &[u8], path: &Path) -> Result<gltf::Gltf, Error> {
    let bad = |message: String| Error::InvalidMesh {
        path: path.to_owned(),
        message,
    };
    if bytes.starts_with(b"glTF") {
        let word = |at: usize| {
            bytes
                .get(at..at + 4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        };
        let (Some(version), Some(length)) = (word(4), word(8)) else {
            return Err(bad(format!(
                "GLB header truncated: {} bytes of 12",
                bytes.len()
            )));
        };
        if version != 2 {
            return Err(bad(format!("GLB version {version}; only glTF 2 is read")));
        }
        if (length as usize) < 20 || length as usize > bytes.len() {
            return Err(bad(format!(
                "GLB header says {length} bytes but the file has {} (truncated or not a GLB file)",
                bytes.len()
            )));
        }
    }
    let invalid = |e: gltf::Error| bad(format!("not a valid glTF 2.0 file: {e}"));
    let g = gltf::Gltf::from_slice_without_validation(bytes).map_err(invalid)?;
    // gltf-json 1.4's validation indexes the accessors by each primitive's
    // POSITION without a bounds check: check that first.
    let root = g.document.as_json();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = gltf::json::validation::Checked::Valid(Semantic::Positions);
            if let Some(i) = prim.attributes.get(&position)
                && i.value() >= root.accessors.len()
            {
                return Err(bad(format!(
                    "meshes[{m}].primitives[{p}].attributes.POSITION = {} is not an accessor (0..{})",
                    i.value(),
                    root.accessors.len()
                )));
            }
        }
    }
    // And `Image::source` unwraps what the validation does not check.
    for (i, image) in root.images.iter().enumerate() {
        match (&image.buffer_view, &image.uri, &image.mime_type) {
            (Some(_), _, None) => {
                return Err(bad(format!("images[{i}] has a bufferView but no mimeType")));
            }
            (None, None, _) => {
                return Err(bad(format!(
                    "images[{i}] has neither a uri nor a bufferView"
                )));
            }
            _ => {}
        }
    }
    let document = gltf::Document::from_json(g.document.into_json()).map_err(invalid)?;
    Ok(gltf::Gltf {
        document,
        blob: g.blob,
    })
}

/// Which nodes LOD `level` draws.
struct Pick<'a> {
    level: usize,
    rule: LodRule,
    msft: &'a HashMap<usize, Vec<usize>>,
    names: &'a [Option<usize>],
}

/// What the traversal needs besides the document.
struct Ctx<'a, 'r> {
    path: &'a Path,
    buffers: Vec<Vec<u8>>,
    /// Texture index -> decoded texture (`None`: image missing).
    textures: HashMap<usize, Option<Arc<Texture>>>,
    resolve: &'a mut FileResolver<'r>,
    warnings: &'a mut Vec<String>,
}

/// Walks `node` and its subtree for one LOD.
fn visit(
    ctx: &mut Ctx<'_, '_>,
    doc: &gltf::Document,
    node: &gltf::Node,
    parent: DMat4,
    pick: &Pick<'_>,
    stack: &mut Vec<usize>,
    acc: &mut Accum,
) -> Result<(), Error> {
    let bad = |message: String| Error::InvalidMesh {
        path: ctx.path.to_owned(),
        message,
    };
    // MSFT_lod: the node stands for its level-`k` replacement.
    let node = match (pick.rule, pick.msft.get(&node.index())) {
        (LodRule::MsftLod, Some(ids)) if pick.level > 0 => {
            let id = ids[(pick.level - 1).min(ids.len() - 1)];
            doc.nodes()
                .nth(id)
                .ok_or_else(|| bad(format!("node {id} missing")))?
        }
        _ => node.clone(),
    };
    if pick.rule == LodRule::Names && pick.names[node.index()].is_some_and(|l| l != pick.level) {
        return Ok(());
    }
    if stack.contains(&node.index()) {
        return Err(bad(format!(
            "node {} is its own ancestor (the node hierarchy has a cycle)",
            node.index()
        )));
    }
    if stack.len() >= MAX_NODE_DEPTH {
        return Err(bad(format!(
            "node hierarchy deeper than {MAX_NODE_DEPTH} levels"
        )));
    }
    let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
    let world = parent * local;
    if !world.is_finite() {
        return Err(bad(format!(
            "node {}: transform is not finite",
            node.index()
        )));
    }
    if let Some(mesh) = node.mesh() {
        for prim in mesh.primitives() {
            read_primitive(ctx, &mesh, &prim, world, acc)?;
        }
    }
    stack.push(node.index());
    for child in node.children() {
        visit(ctx, doc, &child, world, pick, stack, acc)?;
    }
    stack.pop();
    Ok(())
}

/// One LOD's geometry as it is gathered.
#[derive(Default)]
struct Accum {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    colors: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    indices: Vec<u32>,
    all_normals: bool,
    any_primitive: bool,
    /// The LOD's texture and the first material with it / without one.
    texture: Option<Arc<Texture>>,
    textured_material: Option<String>,
    plain_material: Option<String>,
    skipped_modes: usize,
}

impl Accum {
    fn finish(self, path: &Path, level: usize, n_lods: usize) -> Result<Mesh, Error> {
        let what = if n_lods > 1 {
            format!("LOD {level}: ")
        } else {
            String::new()
        };
        let bad = |m: String| Error::InvalidMesh {
            path: path.to_owned(),
            message: format!("{what}{m}"),
        };
        if self.indices.is_empty() {
            return Err(bad(if self.skipped_modes > 0 {
                format!(
                    "no triangles: {} primitive(s) of points or lines only",
                    self.skipped_modes
                )
            } else {
                "no triangles: the scene draws no mesh".into()
            }));
        }
        let textured = self.texture.is_some();
        let mut mesh = Mesh {
            positions: self.positions,
            normals: self.normals,
            colors: self.colors,
            uvs: if textured { self.uvs } else { Vec::new() },
            texture: self.texture,
            indices: self.indices,
            normals_computed: false,
        };
        if !(self.all_normals && self.any_primitive) {
            mesh.compute_smooth_normals();
        }
        mesh.check().map_err(bad)?;
        Ok(mesh)
    }
}

/// Appends one primitive, transformed by `world`.
fn read_primitive(
    ctx: &mut Ctx<'_, '_>,
    mesh: &gltf::Mesh,
    prim: &gltf::Primitive,
    world: DMat4,
    acc: &mut Accum,
) -> Result<(), Error> {
    let mesh_name = match mesh.name() {
        Some(n) => format!("mesh {} ({n:?})", mesh.index()),
        None => format!("mesh {}", mesh.index()),
    };
    let at = format!("{mesh_name} primitive {}", prim.index());
    let bad = |message: String| Error::InvalidMesh {
        path: ctx.path.to_owned(),
        message: format!("{at}: {message}"),
    };
    let mode = prim.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        acc.skipped_modes += 1;
        ctx.warnings.push(format!(
            "{}: {at}: {mode:?} are not triangles; skipped",
            ctx.path.display()
        ));
        return Ok(());
    }
    let path = ctx.path;
    let material = prim.material();
    let pbr = material.pbr_metallic_roughness();
    let factor = pbr.base_color_factor();
    let material_name = match (material.index(), material.name()) {
        (Some(i), Some(nm)) => format!("material {i} ({nm:?})"),
        (Some(i), None) => format!("material {i}"),
        (None, _) => "the default material".into(),
    };
    let info = pbr.base_color_texture();
    let texture = match &info {
        Some(info) => texture_of(ctx, &info.texture())?,
        None => None,
    };
    let buffers = &ctx.buffers;
    let positions_count = prim.get(&Semantic::Positions).map(|a| a.count());
    let read = |sem: Semantic, dims: &[usize]| -> Result<Option<Vec<f32>>, Error> {
        let Some(a) = prim.get(&sem) else {
            return Ok(None);
        };
        // Every attribute has one element per vertex.
        if let Some(n) = positions_count
            && a.count() != n
        {
            return Err(bad(format!(
                "accessor {} ({}) has {} elements but POSITION has {n}",
                a.index(),
                semantic_name(&sem),
                a.count()
            )));
        }
        let what = format!("accessor {} ({} of {at})", a.index(), semantic_name(&sem));
        let (d, v) = read_floats(&a, buffers).map_err(|m| bad_at(path, &what, &m))?;
        if !dims.contains(&d) {
            return Err(bad_at(
                path,
                &what,
                &format!("has {d} components, expected {dims:?}"),
            ));
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(bad_at(
                path,
                &what,
                &format!("element {} is not finite", i / d),
            ));
        }
        Ok(Some(v))
    };
    let positions =
        read(Semantic::Positions, &[3])?.ok_or_else(|| bad("no POSITION attribute".into()))?;
    let n = positions.len() / 3;
    let normals = read(Semantic::Normals, &[3])?;
    let colors = read(Semantic::Colors(0), &[3, 4])?;
    let uvs = match (&texture, &info) {
        (Some(_), Some(info)) => read(Semantic::TexCoords(info.tex_coord()), &[2])?,
        _ => None,
    };
    // One texture per LOD.
    match (&texture, &acc.texture) {
        (Some(t), None) if acc.plain_material.is_none() => {
            acc.texture = Some(t.clone());
            acc.textured_material = Some(material_name.clone());
        }
        (Some(t), Some(have)) if Arc::ptr_eq(t, have) => {}
        (None, None) => {
            acc.plain_material.get_or_insert(material_name.clone());
        }
        _ => {
            let (a, b) = match (&texture, &acc.textured_material, &acc.plain_material) {
                (Some(_), _, Some(plain)) => (material_name.clone(), plain.clone()),
                (_, Some(tex), _) => (tex.clone(), material_name.clone()),
                _ => (material_name.clone(), String::new()),
            };
            return Err(bad(format!(
                "{a} has a base-colour texture and {b} another or none; acuity draws one texture per mesh (bake them into one)"
            )));
        }
    }
    if texture.is_some() && uvs.is_none() {
        return Err(bad(format!(
            "{material_name} has a texture but the primitive has no TEXCOORD_{}",
            info.as_ref().map_or(0, |i| i.tex_coord())
        )));
    }
    let local: Vec<u32> = match prim.indices() {
        Some(a) => {
            let what = format!("accessor {} (indices of {at})", a.index());
            read_indices(&a, buffers, n).map_err(|m| bad_at(path, &what, &m))?
        }
        None => (0..n as u32).collect(),
    };
    let tris = triangulate(mode, &local);
    let base = acc.positions.len();
    if base + n > u32::MAX as usize {
        return Err(bad("more than 4 billion vertices".into()));
    }
    let normal_mat = DMat3::from_mat4(world).inverse().transpose();
    let flip = DMat3::from_mat4(world).determinant() < 0.0;
    for i in 0..n {
        let p = world.transform_point3(DVec3::new(
            f64::from(positions[3 * i]),
            f64::from(positions[3 * i + 1]),
            f64::from(positions[3 * i + 2]),
        ));
        let p = p.as_vec3();
        if !p.is_finite() {
            return Err(bad(format!("vertex {i} is not finite once placed")));
        }
        acc.positions.push(p.into());
        let nrm = normals
            .as_ref()
            .map(|v| {
                let v = DVec3::new(
                    f64::from(v[3 * i]),
                    f64::from(v[3 * i + 1]),
                    f64::from(v[3 * i + 2]),
                );
                (normal_mat * v)
                    .as_vec3()
                    .try_normalize()
                    .unwrap_or(Vec3::Z)
            })
            .unwrap_or(Vec3::Z);
        acc.normals.push(nrm.into());
        let c = match &colors {
            Some(c) => {
                let d = c.len() / n;
                [c[d * i], c[d * i + 1], c[d * i + 2]]
            }
            None => [1.0; 3],
        };
        acc.colors
            .push([0, 1, 2].map(|k| (c[k] * factor[k]).clamp(0.0, 1.0)));
        acc.uvs.push(match &uvs {
            Some(t) => [t[2 * i], t[2 * i + 1]],
            None => [0.0; 2],
        });
    }
    acc.all_normals = (acc.all_normals || !acc.any_primitive) && normals.is_some();
    acc.any_primitive = true;
    for t in tris.chunks_exact(3) {
        let t = if flip {
            [t[0], t[2], t[1]]
        } else {
            [t[0], t[1], t[2]]
        };
        acc.indices.extend(t.map(|i| i + base as u32));
    }
    Ok(())
}

/// A semantic as glTF files spell it (`POSITION`, `TEXCOORD_0`).
fn semantic_name(sem: &Semantic) -> String {
    match sem {
        Semantic::Positions => "POSITION".into(),
        Semantic::Normals => "NORMAL".into(),
        Semantic::Colors(n) => format!("COLOR_{n}"),
        Semantic::TexCoords(n) => format!("TEXCOORD_{n}"),
        other => format!("{other:?}"),
    }
}

fn bad_at(path: &Path, what: &str, message: &str) -> Error {
    Error::InvalidMesh {
        path: path.to_owned(),
        message: format!("{what}: {message}"),
    }
}

/// Triangle strips and fans as lists (degenerate strip triangles dropped).
fn triangulate(mode: Mode, idx: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (2..idx.len())
            .flat_map(|i| {
                if i % 2 == 0 {
                    [idx[i - 2], idx[i - 1], idx[i]]
                } else {
                    [idx[i - 1], idx[i - 2], idx[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..idx.len())
            .flat_map(|i| [idx[0], idx[i - 1], idx[i]])
            .collect(),
        _ => idx[..idx.len() / 3 * 3].to_vec(),
    }
}

/// The decoded base-colour texture of glTF texture `tex` (cached per
/// texture: the sampler's wrap modes belong to it); `None` with a warning
/// when its image file is missing.
fn texture_of(ctx: &mut Ctx<'_, '_>, tex: &gltf::Texture) -> Result<Option<Arc<Texture>>, Error> {
    if let Some(t) = ctx.textures.get(&tex.index()) {
        return Ok(t.clone());
    }
    let image = tex.source();
    let what = format!("image {} (texture {})", image.index(), tex.index());
    let bytes = match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buf = &ctx.buffers[view.buffer().index()];
            let range = view.offset()..view.offset().saturating_add(view.length());
            buf.get(range)
                .ok_or_else(|| {
                    bad_at(
                        ctx.path,
                        &what,
                        &format!("buffer view {} lies outside its buffer", view.index()),
                    )
                })?
                .to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => match read_uri(uri, ctx.resolve) {
            Ok(b) => b,
            Err(e) if !uri.starts_with("data:") => {
                ctx.warnings.push(format!(
                    "{}: {what} `{}` {e}; the base-colour factor is drawn alone",
                    ctx.path.display(),
                    short(uri)
                ));
                ctx.textures.insert(tex.index(), None);
                return Ok(None);
            }
            Err(e) => return Err(bad_at(ctx.path, &what, &e)),
        },
    };
    let mut t = Texture::decode(&bytes, ctx.path, &what)?;
    let sampler = tex.sampler();
    let wrap = |m| match m {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    };
    t.wrap = [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())];
    let t = Some(Arc::new(t));
    ctx.textures.insert(tex.index(), t.clone());
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(
            triangulate(Mode::TriangleStrip, &[0, 1, 2, 3]),
            [0, 1, 2, 2, 1, 3]
        );
        assert_eq!(
            triangulate(Mode::TriangleFan, &[0, 1, 2, 3]),
            [0, 1, 2, 0, 2, 3]
        );
        assert_eq!(triangulate(Mode::Triangles, &[0, 1, 2, 3]), [0, 1, 2]);
    }
}
