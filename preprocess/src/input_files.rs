//! The files an object's analysis reads, hashed for the profile cache: a
//! mesh file and every file it draws on (MTL files and their textures for
//! OBJ, external buffers and images for glTF), so editing a texture alone
//! makes the cached profile stale; with the generation parameters and the
//! settings, every input of an analysis ([`input_hashes`]).

use std::path::{Path, PathBuf};

use crate::Error;
use crate::inputs::{AnalysisSettings, ObjectSource};
use crate::lods::{self, ProceduralParams};

/// BLAKE3 of `bytes`, 64 lowercase hex digits (the form of every hash
/// in a profile).
pub fn hash_hex(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

/// Hashes a mesh file and every file it draws on: a glTF's external
/// buffers and images, an OBJ's MTL files and their `map_Kd` textures
/// (`missing` for a named file that is absent).
pub fn hash_mesh_file(path: &Path, out: &mut Vec<InputHash>) -> Result<(), Error> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    out.push(InputHash {
        what: path.display().to_string(),
        hash_hex: blake3::hash(&bytes).to_hex().to_string(),
    });
    let hash_named = |p: PathBuf, out: &mut Vec<InputHash>| {
        let read = std::fs::read(&p);
        out.push(InputHash {
            what: p.display().to_string(),
            hash_hex: match &read {
                Ok(b) => blake3::hash(b).to_hex().to_string(),
                Err(_) => "missing".into(),
            },
        });
        read.ok()
    };
    if crate::render::is_gltf(path) {
        for p in crate::render::gltf_mesh::external_files(&bytes, path) {
            hash_named(p, out);
        }
        return Ok(());
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    for name in statements(&bytes, path, "mtllib") {
        let mtl_path = dir.join(&name);
        let Some(mtl) = hash_named(mtl_path.clone(), out) else {
            continue;
        };
        let mtl_dir = mtl_path.parent().unwrap_or(Path::new("")).to_owned();
        for tex in statements(&mtl, &mtl_path, "map_Kd") {
            // The loader's rule: the file is the statement's last token.
            if let Some(last) = tex.split_whitespace().last() {
                hash_named(mtl_dir.join(last), out);
            }
        }
    }
    Ok(())
}

/// The arguments of every `keyword` statement of an OBJ or MTL text:
/// one entry per name for `mtllib`, the whole rest of the line otherwise.
fn statements(bytes: &[u8], path: &Path, keyword: &str) -> Vec<String> {
    let text = crate::mesh::decode_text(bytes, path).unwrap_or_default();
    let mut out = Vec::new();
    for line in crate::mesh::split_lines(&text) {
        let mut toks = line.split('#').next().unwrap_or("").split_whitespace();
        if toks.next() != Some(keyword) {
            continue;
        }
        if keyword == "mtllib" {
            out.extend(toks.map(str::to_owned));
        } else {
            out.push(toks.collect::<Vec<_>>().join(" "));
        }
    }
    out
}

/// A content hash of one input (a file, or a set of parameters).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct InputHash {
    /// The file's path as given (MTL files: as resolved), or a parameter
    /// description such as `settings` or `lod-generation`.
    pub what: String,
    /// BLAKE3 of the content, 64 lowercase hex digits; `missing` for an MTL
    /// file named by an OBJ but absent (the loader then warns and uses the
    /// default colour).
    pub hash_hex: String,
}

/// Content hashes of every input of `object` under `settings`, computed
/// without loading meshes or rendering: each mesh file; for an OBJ each
/// MTL file it names (`mtllib`, resolved next to the OBJ) and each texture
/// those name (`map_Kd`), for a glTF each external buffer and image
/// (`missing` for a named file that is absent); the LOD-generation or
/// procedural parameters, and the settings (with [`crate::inputs::ANALYSIS_VERSION`]).
/// Equal hashes mean the analysis would give the same result. Unreadable
/// mesh files are an [`Error::Io`].
pub fn input_hashes(
    object: &ObjectSource,
    settings: &AnalysisSettings,
) -> Result<Vec<InputHash>, Error> {
    let mut out = Vec::new();
    let hash_str = |s: &str| blake3::hash(s.as_bytes()).to_hex().to_string();
    let generation = |targets: &[u32]| InputHash {
        what: "lod-generation".into(),
        hash_hex: hash_str(&format!("meshopt-simplify targets={}", list(targets))),
    };
    match object {
        ObjectSource::Files { lod_paths, .. } => {
            for p in lod_paths {
                crate::input_files::hash_mesh_file(p, &mut out)?;
            }
        }
        ObjectSource::Generated {
            path,
            triangle_targets,
            ..
        } => {
            crate::input_files::hash_mesh_file(path, &mut out)?;
            out.push(generation(triangle_targets));
        }
        ObjectSource::Whole { path, .. } => {
            crate::input_files::hash_mesh_file(path, &mut out)?;
            out.push(InputHash {
                what: "lod-generation".into(),
                hash_hex: hash_str(&format!(
                    "meshopt-simplify whole mesh, then 1/{} down to {} triangles, at most {} LODs",
                    lods::WHOLE_MESH_STEP,
                    lods::WHOLE_MESH_FLOOR_TRIANGLES,
                    lods::WHOLE_MESH_MAX_LODS
                )),
            });
        }
        ObjectSource::Procedural {
            params,
            triangle_targets,
            ..
        } => {
            let ProceduralParams { triangles, seed } = *params;
            out.push(InputHash {
                what: lods::procedural_description(*params).display().to_string(),
                hash_hex: hash_str(&format!("bumpy-torus triangles={triangles} seed={seed}")),
            });
            out.push(generation(triangle_targets));
        }
        ObjectSource::Shape {
            shape,
            triangle_targets,
            ..
        } => {
            out.push(InputHash {
                what: format!("procedural:{}", shape.name()),
                hash_hex: hash_str(&format!(
                    "tessellate {} targets={}",
                    shape.name(),
                    list(triangle_targets)
                )),
            });
        }
    }
    out.push(InputHash {
        what: "settings".into(),
        hash_hex: hash_str(&settings.cache_key()),
    });
    Ok(out)
}

/// `1,2,3`: a list of counts as cache keys write it.
fn list(values: &[u32]) -> String {
    values
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(",")
}
