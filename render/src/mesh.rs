//! Indexed triangle meshes and the OBJ/MTL loader.
//!
//! The loader is our own rather than `tobj`: tobj 4.0.5 panics on a short
//! colour such as `Kd 0.5 0.5` and reports no line numbers, and a bad asset
//! must give a clear error naming its file and line, never a panic.
//!
//! # Loading rules (decided here; see the tests in `tests/bad_obj.rs`)
//! - **Text**: UTF-8 (a BOM is skipped), UTF-16 LE/BE with a BOM (decoded),
//!   anything else is read byte-wise with invalid UTF-8 replaced (so Latin-1
//!   comments and names are harmless: keywords and numbers are ASCII).
//!   Lines end with `\n`, `\r\n` or a lone `\r`. `#` starts a comment.
//! - **`v x y z [w]`** or **`v x y z r g b`** (vertex colour, linear RGB,
//!   clamped to `[0, 1]`). Any other count is an error. `w` is the weight of
//!   rational curves and has no meaning for polygons: it must be a finite
//!   number and is otherwise ignored. A coordinate that is not a finite `f32`
//!   (`nan`, `inf`, or `1e39`, which overflows `f32`) is an error naming the
//!   line, even when no face uses that vertex.
//! - **`vn x y z`**: finite numbers. Normals from the file are used only when
//!   every face corner names one; otherwise all normals are computed (below).
//! - **`vt u [v [w]]`**: texture coordinates, finite numbers (`v` defaults
//!   to 0, `w` is ignored). OBJ's `v` points up, so the mesh stores
//!   `1 - v` (texture rows run top first, as in glTF).
//! - **`f`**: at least 3 corners `v`, `v/vt`, `v//vn` or `v/vt/vn`; negative
//!   indices are relative. An index of 0, or one that refers to an element
//!   not defined *before* the face line, is an error. Polygons are
//!   triangulated as a fan from their first corner (like tinyobjloader;
//!   correct for convex polygons, which is what exporters write).
//! - **`p`, `l`**: points and lines are never turned into triangles. A file
//!   with points or lines but no faces is an error; in a file with faces
//!   they are ignored.
//! - **`mtllib`, `usemtl`**: the diffuse colour `Kd` (linear RGB) of the
//!   material is used. A missing MTL file or an unknown material name gives a
//!   *warning* and the default colour (the geometry is still right and
//!   exporters often omit the MTL). A present but malformed MTL file is an
//!   *error* naming the MTL file and line. `map_Kd [options] file` is the
//!   material's base-colour texture (sRGB PNG or JPEG, relative to the MTL
//!   file's folder; `-clamp on` clamps, otherwise it repeats; other options
//!   are skipped). A missing texture file is a warning (the material's
//!   colour is used alone); an undecodable one an error. A mesh draws one
//!   texture: faces of materials with different textures, or textured and
//!   untextured faces mixed, are an error naming both materials. Other MTL
//!   keywords are ignored.
//! - **Colour** of a corner: vertex colour × `Kd` when both exist, either
//!   one alone, else [`DEFAULT_COLOR_LINEAR`]; times the texture, if any.
//! - **Computed normals** are smooth: area-weighted face normals summed over
//!   every corner at the same position (so material seams do not crease the
//!   shading). For flat shading, put normals in the file.
//! - Other keywords (`o`, `g`, `s`, `vp`, curves, ...) are ignored.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use crate::Error;
use crate::mtl::{MtlEntry, parse_mtl};
use crate::obj_text::parse_numbers;
use crate::texture::Texture;

pub use crate::mtl::MtlResolver;
pub use crate::obj_text::{decode_text, split_lines};

/// Colour used when a face has neither a vertex colour nor a material:
/// linear RGB 0.5 (sRGB about 188), a mid grey.
pub const DEFAULT_COLOR_LINEAR: [f32; 3] = [0.5, 0.5, 0.5];

/// An indexed triangle mesh, ready to render.
///
/// All per-vertex arrays have the same length; `indices.len()` is a multiple
/// of 3 and every index is below the vertex count. Units of `positions` are
/// the model's own (whatever the file uses).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions, model units.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Vertex colours, linear RGB in `[0, 1]` (vertex colour × material
    /// diffuse colour, already multiplied).
    pub colors: Vec<[f32; 3]>,
    /// Texture coordinates `(u, v)`, `v = 0` at the texture's top row:
    /// empty when the mesh has none, else one per vertex.
    pub uvs: Vec<[f32; 2]>,
    /// Base-colour texture multiplying `colors` (sampled at `uvs`, which
    /// it needs); shared between the LODs of a chain.
    pub texture: Option<Arc<Texture>>,
    /// Triangle list, counter-clockwise front faces (the renderer lights
    /// both sides, so winding errors in files do not matter).
    pub indices: Vec<u32>,
    /// Whether `normals` were computed (smooth) rather than read from the
    /// file; simplification recomputes computed normals.
    pub normals_computed: bool,
}

/// A loaded mesh and the non-fatal problems met while loading it.
#[derive(Debug, Clone)]
pub struct LoadedMesh {
    /// The mesh.
    pub mesh: Mesh,
    /// Human-readable warnings, each naming the file (and line where known).
    pub warnings: Vec<String>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Checks the invariants listed on [`Mesh`] plus at least one triangle
    /// and finite positions; the message says what is wrong.
    pub fn check(&self) -> Result<(), String> {
        let n = self.positions.len();
        if self.normals.len() != n || self.colors.len() != n {
            return Err(format!(
                "attribute lengths differ: {} positions, {} normals, {} colours",
                n,
                self.normals.len(),
                self.colors.len()
            ));
        }
        if !self.uvs.is_empty() && self.uvs.len() != n {
            return Err(format!(
                "{} texture coordinates for {n} vertices",
                self.uvs.len()
            ));
        }
        if self.texture.is_some() && self.uvs.is_empty() {
            return Err("a texture but no texture coordinates".into());
        }
        if let Some(uv) = self.uvs.iter().find(|t| !t.iter().all(|c| c.is_finite())) {
            return Err(format!("non-finite texture coordinate {uv:?}"));
        }
        if self.indices.is_empty() {
            return Err("mesh has no triangles".into());
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(format!(
                "index count {} is not a multiple of 3",
                self.indices.len()
            ));
        }
        if let Some(i) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!("index {i} out of range ({n} vertices)"));
        }
        if let Some(p) = self
            .positions
            .iter()
            .find(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(format!("non-finite position {p:?}"));
        }
        Ok(())
    }

    /// Bounding sphere: centre of the axis-aligned bounding box and the
    /// largest distance from it to a vertex used by a triangle. Model units.
    /// Not the minimal sphere, but deterministic and at most about 15% larger.
    pub fn bounding_sphere(&self) -> ([f32; 3], f32) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for &i in &self.indices {
            let p = Vec3::from(self.positions[i as usize]);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if !lo.is_finite() {
            return ([0.0; 3], 0.0);
        }
        let c = (lo + hi) * 0.5;
        // In f64: a squared f32 distance underflows below about 1e-19.
        let r = self
            .indices
            .iter()
            .map(|&i| {
                Vec3::from(self.positions[i as usize])
                    .as_dvec3()
                    .distance(c.as_dvec3())
            })
            .fold(0.0f64, f64::max);
        (c.into(), r as f32)
    }

    /// Replaces `normals` by smooth area-weighted normals, summed over all
    /// vertices with bit-identical positions. Degenerate spots get +Z.
    pub fn compute_smooth_normals(&mut self) {
        let mut by_pos: HashMap<[u32; 3], Vec3> = HashMap::new();
        let key = |p: [f32; 3]| [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        for t in self.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(self.positions[i as usize]));
            // Cross product length = 2 * area: area weighting for free.
            let n = (b - a).cross(c - a);
            if !n.is_finite() {
                continue;
            }
            for &i in t {
                *by_pos
                    .entry(key(self.positions[i as usize]))
                    .or_insert(Vec3::ZERO) += n;
            }
        }
        self.normals = self
            .positions
            .iter()
            .map(|&p| {
                by_pos
                    .get(&key(p))
                    .and_then(|n| n.try_normalize())
                    .unwrap_or(Vec3::Z)
                    .into()
            })
            .collect();
        self.normals_computed = true;
    }
}

/// Reads and parses an OBJ file; MTL files named by `mtllib` are looked up
/// relative to the OBJ's folder. See the module docs for the rules.
pub fn load_obj(path: &Path) -> Result<LoadedMesh, Error> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    let dir = path.parent().map(Path::to_owned).unwrap_or_default();
    let mut resolve = |name: &str| {
        let p = dir.join(name);
        std::fs::read(&p).map(|b| (p, b))
    };
    parse_obj(&bytes, path, &mut resolve)
}

/// Parses OBJ bytes. `path` is only used in messages. Never panics.
pub fn parse_obj(
    bytes: &[u8],
    path: &Path,
    resolve_mtl: &mut MtlResolver<'_>,
) -> Result<LoadedMesh, Error> {
    let text = decode_text(bytes, path)?;
    let perr = |line: usize, message: String| Error::Parse {
        path: path.to_owned(),
        line,
        message,
    };

    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut vcolors: Vec<Option<[f32; 3]>> = Vec::new();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut texcoords: Vec<[f32; 2]> = Vec::new();
    let mut points_lines = 0usize;
    let mut warnings = Vec::new();
    let mut warned_w = false;
    // Materials by name. Names are looked up when `usemtl` is seen.
    let mut materials: HashMap<String, MtlEntry> = HashMap::new();
    let mut current = MtlEntry::default();
    let mut current_name = String::new();
    // The mesh's one texture, and the first material with / without one.
    let mut texture: Option<Arc<Texture>> = None;
    let mut textured_material: Option<String> = None;
    let mut plain_material: Option<(String, usize)> = None;
    let mut warned_no_vt = false;
    // Unified vertices: (position, normal or MAX, texcoord or MAX, colour)
    // -> index.
    let mut corners: Vec<(u32, u32, u32, Option<[f32; 3]>)> = Vec::new();
    let mut corner_map: HashMap<(u32, u32, u32, [u32; 3], bool), u32> = HashMap::new();
    let mut indices: Vec<u32> = Vec::new();
    let mut all_have_normals = true;

    for (line_idx, raw) in split_lines(&text).enumerate() {
        let line_no = line_idx + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        match kw {
            "v" => {
                let nums = parse_numbers(toks, line_no, "v", path)?;
                let (p, c) = match nums.len() {
                    3 => ([nums[0], nums[1], nums[2]], None),
                    4 => {
                        if nums[3] != 1.0 && !warned_w {
                            warned_w = true;
                            warnings.push(format!(
                                "{}:{line_no}: vertex weight w = {} ignored (w only applies to rational curves)",
                                path.display(),
                                nums[3]
                            ));
                        }
                        ([nums[0], nums[1], nums[2]], None)
                    }
                    6 => (
                        [nums[0], nums[1], nums[2]],
                        Some([nums[3], nums[4], nums[5]].map(|x| x.clamp(0.0, 1.0))),
                    ),
                    n => {
                        return Err(perr(
                            line_no,
                            format!(
                                "`v` needs 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b), found {n}"
                            ),
                        ));
                    }
                };
                positions.push(p);
                vcolors.push(c);
            }
            "vn" => {
                let nums = parse_numbers(toks, line_no, "vn", path)?;
                if nums.len() != 3 {
                    return Err(perr(
                        line_no,
                        format!("`vn` needs 3 numbers, found {}", nums.len()),
                    ));
                }
                normals.push([nums[0], nums[1], nums[2]]);
            }
            "vt" => {
                let nums = parse_numbers(toks, line_no, "vt", path)?;
                if !(1..=3).contains(&nums.len()) {
                    return Err(perr(
                        line_no,
                        format!(
                            "`vt` needs 1 to 3 numbers (u [v [w]]), found {}",
                            nums.len()
                        ),
                    ));
                }
                texcoords.push([nums[0], 1.0 - nums.get(1).copied().unwrap_or(0.0)]);
            }
            "p" | "l" => points_lines += 1,
            "f" => {
                match (&current.texture, &texture) {
                    (Some(t), None) if plain_material.is_none() => {
                        texture = Some(t.clone());
                        textured_material = Some(current_name.clone());
                    }
                    (Some(t), Some(have)) if Arc::ptr_eq(t, have) => {}
                    (None, None) => {
                        plain_material.get_or_insert((current_name.clone(), line_no));
                    }
                    (None, Some(_)) => {
                        return Err(perr(
                            line_no,
                            one_texture_message(textured_material.as_deref(), &current_name),
                        ));
                    }
                    (Some(_), _) => {
                        let other = match &plain_material {
                            Some((m, _)) => m.clone(),
                            None => textured_material.clone().unwrap_or_default(),
                        };
                        return Err(perr(
                            line_no,
                            one_texture_message(Some(&current_name), &other),
                        ));
                    }
                }
                let mut face: Vec<u32> = Vec::new();
                for tok in toks {
                    let (vi, ti, ni) =
                        parse_corner(tok, positions.len(), texcoords.len(), normals.len())
                            .map_err(|m| perr(line_no, m))?;
                    let ni_key = match ni {
                        Some(n) => n as u32,
                        None => {
                            all_have_normals = false;
                            u32::MAX
                        }
                    };
                    if ti.is_none() && current.texture.is_some() && !warned_no_vt {
                        warned_no_vt = true;
                        warnings.push(format!(
                            "{}:{line_no}: face of textured material `{current_name}` without texture coordinates; it samples the texture at (0, 0)",
                            path.display()
                        ));
                    }
                    let ti_key = ti.map_or(u32::MAX, |t| t as u32);
                    let color = match (vcolors[vi], current.kd) {
                        (Some(v), Some(k)) => Some([v[0] * k[0], v[1] * k[1], v[2] * k[2]]),
                        (Some(v), None) => Some(v),
                        (None, Some(k)) => Some(k),
                        (None, None) => None,
                    };
                    let cb = color.unwrap_or([0.0; 3]).map(f32::to_bits);
                    let key = (vi as u32, ni_key, ti_key, cb, color.is_some());
                    let idx = *corner_map.entry(key).or_insert_with(|| {
                        corners.push((vi as u32, ni_key, ti_key, color));
                        (corners.len() - 1) as u32
                    });
                    face.push(idx);
                }
                if face.len() < 3 {
                    return Err(perr(
                        line_no,
                        format!(
                            "face with {} corner(s); a face needs at least 3",
                            face.len()
                        ),
                    ));
                }
                for k in 1..face.len() - 1 {
                    indices.extend_from_slice(&[face[0], face[k], face[k + 1]]);
                }
            }
            "mtllib" => {
                let names: Vec<&str> = toks.collect();
                if names.is_empty() {
                    warnings.push(format!(
                        "{}:{line_no}: `mtllib` without a file name",
                        path.display()
                    ));
                }
                for name in names {
                    match resolve_mtl(name) {
                        Ok((mtl_path, mtl_bytes)) => {
                            let mtl_dir = Path::new(name).parent().unwrap_or(Path::new(""));
                            let mut resolve_in_mtl_dir = |tex: &str| {
                                let rel = mtl_dir.join(tex);
                                resolve_mtl(&rel.to_string_lossy())
                            };
                            for (k, v) in parse_mtl(
                                &mtl_bytes,
                                &mtl_path,
                                &mut resolve_in_mtl_dir,
                                &mut warnings,
                            )? {
                                materials.insert(k, v);
                            }
                        }
                        Err(e) => warnings.push(format!(
                            "{}:{line_no}: material library `{name}` not read ({e}); default colour used",
                            path.display()
                        )),
                    }
                }
            }
            "usemtl" => {
                let name = content
                    .trim_start()
                    .strip_prefix("usemtl")
                    .unwrap_or("")
                    .trim();
                name.clone_into(&mut current_name);
                current = match materials.get(name) {
                    Some(m) => m.clone(),
                    None => {
                        warnings.push(format!(
                            "{}:{line_no}: unknown material `{name}`; default colour used",
                            path.display()
                        ));
                        MtlEntry::default()
                    }
                };
            }
            _ => {}
        }
    }

    let invalid = |message: String| Error::InvalidMesh {
        path: path.to_owned(),
        message,
    };
    if indices.is_empty() {
        return Err(invalid(if points_lines > 0 {
            format!(
                "no faces: the file has only points/lines ({points_lines} `p`/`l` statements), which are never turned into triangles"
            )
        } else if positions.is_empty() {
            "empty mesh: no vertices and no faces".to_string()
        } else {
            format!(
                "no faces ({} vertices but no `f` statements)",
                positions.len()
            )
        }));
    }

    let use_file_normals = all_have_normals && !normals.is_empty();
    let has_uvs = corners.iter().any(|c| c.2 != u32::MAX);
    let mut mesh = Mesh {
        positions: corners.iter().map(|c| positions[c.0 as usize]).collect(),
        normals: corners
            .iter()
            .map(|c| {
                if use_file_normals {
                    Vec3::from(normals[c.1 as usize])
                        .try_normalize()
                        .unwrap_or(Vec3::Z)
                        .into()
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect(),
        colors: corners
            .iter()
            .map(|c| c.3.unwrap_or(DEFAULT_COLOR_LINEAR))
            .collect(),
        uvs: if has_uvs || texture.is_some() {
            corners
                .iter()
                .map(|c| texcoords.get(c.2 as usize).copied().unwrap_or([0.0; 2]))
                .collect()
        } else {
            Vec::new()
        },
        texture,
        indices,
        normals_computed: false,
    };
    if !use_file_normals {
        mesh.compute_smooth_normals();
    }
    mesh.check().map_err(invalid)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// The error for a mesh whose faces need two textures (or a texture and
/// none).
fn one_texture_message(textured: Option<&str>, other: &str) -> String {
    format!(
        "material `{}` has a texture and material `{other}` another or none; acuity draws one base-colour texture per mesh (split the mesh or bake the materials into one texture)",
        textured.unwrap_or("")
    )
}

/// Parses one face corner `v[/vt[/vn]]` into 0-based (position, texture
/// coordinate, normal).
fn parse_corner(
    tok: &str,
    n_pos: usize,
    n_tex: usize,
    n_norm: usize,
) -> Result<(usize, Option<usize>, Option<usize>), String> {
    let parts: Vec<&str> = tok.split('/').collect();
    if parts.len() > 3 {
        return Err(format!("face corner `{tok}` has more than 3 parts"));
    }
    let resolve = |s: &str, count: usize, what: &str| -> Result<Option<usize>, String> {
        if s.is_empty() {
            return Ok(None);
        }
        let x: i64 = s
            .parse()
            .map_err(|_| format!("face corner `{tok}`: `{s}` is not an integer index"))?;
        let idx = if x > 0 {
            x - 1
        } else if x < 0 {
            count as i64 + x
        } else {
            return Err(format!(
                "face corner `{tok}`: {what} index 0 (OBJ indices start at 1)"
            ));
        };
        if idx < 0 || idx >= count as i64 {
            return Err(format!(
                "face corner `{tok}`: {what} index {x} out of range ({count} {what}s defined before this line)"
            ));
        }
        Ok(Some(idx as usize))
    };
    let v = resolve(parts[0], n_pos, "position")?
        .ok_or_else(|| format!("face corner `{tok}` has no position index"))?;
    let t = match parts.get(1) {
        Some(s) => resolve(s, n_tex, "texture coordinate")?,
        None => None,
    };
    let n = match parts.get(2) {
        Some(s) => resolve(s, n_norm, "normal")?,
        None => None,
    };
    Ok((v, t, n))
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::texture::Wrap;

    fn parse(s: &str) -> Result<LoadedMesh, Error> {
        parse_obj(s.as_bytes(), Path::new("t.obj"), &mut |_| {
            Err(std::io::Error::from(std::io::ErrorKind::NotFound))
        })
    }

    #[test]
    fn quad_becomes_two_triangles_with_smooth_normals() {
        let m = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
            .unwrap()
            .mesh;
        assert_eq!(m.triangle_count(), 2);
        assert!(m.normals_computed);
        for n in &m.normals {
            assert!((n[2] - 1.0).abs() < 1e-6);
        }
        assert_eq!(m.colors[0], DEFAULT_COLOR_LINEAR);
    }

    #[test]
    fn line_numbers_count_cr_lf_and_lone_cr() {
        let e = parse("v 0 0 0\r\nv 1 0 0\rv 1 nan 0\n").unwrap_err();
        assert!(matches!(e, Error::Parse { line: 3, .. }), "{e}");
    }

    #[test]
    fn relative_indices_and_vertex_colours() {
        let m = parse("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf -3 -2 -1\n")
            .unwrap()
            .mesh;
        assert_eq!(m.indices, vec![0, 1, 2]);
        assert_eq!(m.colors[1], [0.0, 1.0, 0.0]);
    }

    #[test]
    fn a_tiny_mesh_keeps_its_radius() {
        let m = parse("v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\nf 1 2 3\n")
            .unwrap()
            .mesh;
        let (_, r) = m.bounding_sphere();
        let want = 0.5e-30 * std::f32::consts::SQRT_2;
        assert!((r / want - 1.0).abs() < 1e-5, "{r}");
    }

    /// A 2x1 PNG: one red texel, one blue.
    fn two_texel_png() -> Vec<u8> {
        let t = crate::Texture::from_rgba(2, 1, vec![255, 0, 0, 255, 0, 0, 255, 255], "t").unwrap();
        crate::gltf_write::encode_png(&t).unwrap()
    }

    fn parse_with_files(obj: &str, mtl: &str) -> Result<LoadedMesh, Error> {
        let (mtl, png) = (mtl.as_bytes().to_vec(), two_texel_png());
        parse_obj(obj.as_bytes(), Path::new("t.obj"), &mut |name| match name {
            "t.mtl" => Ok((PathBuf::from(name), mtl.clone())),
            "tex.png" => Ok((PathBuf::from(name), png.clone())),
            _ => Err(std::io::Error::from(std::io::ErrorKind::NotFound)),
        })
    }

    const TEXTURED_QUAD: &str = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3 4/4\n";

    #[test]
    fn vt_and_map_kd_give_a_textured_mesh() {
        let m = parse_with_files(
            TEXTURED_QUAD,
            "newmtl a\nKd 1 1 1\nmap_Kd -clamp on tex.png\n",
        )
        .unwrap()
        .mesh;
        let t = m.texture.as_ref().expect("textured");
        assert_eq!((t.width, t.height, t.wrap[0]), (2, 1, Wrap::ClampToEdge));
        // OBJ's v points up; the mesh's rows run top first.
        assert_eq!(m.uvs, [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    }

    #[test]
    fn a_missing_texture_warns_and_two_textures_are_an_error() {
        let l = parse_with_files(TEXTURED_QUAD, "newmtl a\nmap_Kd gone.png\n").unwrap();
        assert!(l.mesh.texture.is_none());
        assert!(
            l.warnings.iter().any(|w| w.contains("gone.png")),
            "{:?}",
            l.warnings
        );
        let two = format!("{TEXTURED_QUAD}usemtl b\nf 1/1 3/3 4/4\n");
        let e = parse_with_files(&two, "newmtl a\nmap_Kd tex.png\nnewmtl b\n").unwrap_err();
        assert!(matches!(e, Error::Parse { line: 13, .. }), "{e}");
        assert!(e.to_string().contains("one base-colour texture"), "{e}");
        let e = parse_with_files(TEXTURED_QUAD, "newmtl a\nmap_Kd t.mtl\n").unwrap_err();
        assert!(e.to_string().contains("t.mtl"), "{e}");
    }
}
