//! The files an object's analysis reads, hashed for the profile cache: a
//! mesh file and every file it draws on (MTL files and their textures for
//! OBJ, external buffers and images for glTF), so editing a texture alone
//! makes the cached profile stale.

use std::path::{Path, PathBuf};

use crate::Error;
use crate::pipeline::InputHash;

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
