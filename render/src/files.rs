//! Mesh files by their extension: OBJ (`.obj`, one mesh) or glTF 2.0
//! (`.gltf`, `.glb`: the LOD chain the file carries, often one level).

use std::path::Path;

use crate::{Error, Mesh, gltf_mesh, mesh};

/// The meshes of a file, finest first (one for OBJ), and the loaders'
/// warnings.
#[derive(Debug, Clone)]
pub struct LoadedChain {
    /// At least one mesh, finest first.
    pub lods: Vec<Mesh>,
    /// Non-fatal problems, each naming the file.
    pub warnings: Vec<String>,
}

/// Whether `path` names a glTF file (`.gltf` or `.glb`, any case).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Loads a mesh file: glTF by [`gltf_mesh::load_gltf`] (its LOD chain),
/// anything else as OBJ by [`mesh::load_obj`] (one mesh).
pub fn load_mesh_file(path: &Path) -> Result<LoadedChain, Error> {
    if is_gltf(path) {
        let g = gltf_mesh::load_gltf(path)?;
        Ok(LoadedChain {
            lods: g.lods,
            warnings: g.warnings,
        })
    } else {
        let m = mesh::load_obj(path)?;
        Ok(LoadedChain {
            lods: vec![m.mesh],
            warnings: m.warnings,
        })
    }
}
