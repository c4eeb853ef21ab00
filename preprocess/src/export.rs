//! Writing an analysed LOD chain where its profile is, so what ships is
//! what was measured: one `.glb` holding every LOD (nodes `<name>_LOD<k>`,
//! read back as a chain by the glTF loader and by engines that use the
//! same naming) and one OBJ per LOD sharing an MTL file and, for a textured
//! chain, the texture as PNG.

use std::path::{Path, PathBuf};

use crate::Mesh;
use crate::render::texture::Wrap;
use crate::render::{Error, gltf_write, obj_write};

/// One file written: its path and the BLAKE3 of its bytes (64 lowercase
/// hex digits).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExportedFile {
    /// Where it was written.
    pub path: PathBuf,
    /// BLAKE3 of its content.
    pub hash_hex: String,
}

/// Writes `lods` (finest first) into `dir` as `<stem>.lods.glb` and
/// `<stem>_lod<k>.obj` (with `<stem>.mtl` and, when textured,
/// `<stem>_basecolor.png`), creating `dir`. Returns the files in that
/// order. The OBJ files use the first LOD's texture (a chain shares one).
pub fn export_lods(
    dir: &Path,
    stem: &str,
    name: &str,
    lods: &[Mesh],
) -> Result<Vec<ExportedFile>, Error> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_owned(),
        source,
    })?;
    let mut out = Vec::new();
    let mut write = |file: String, bytes: &[u8]| -> Result<(), Error> {
        let path = dir.join(file);
        std::fs::write(&path, bytes).map_err(|source| Error::Io {
            path: path.clone(),
            source,
        })?;
        out.push(ExportedFile {
            path,
            hash_hex: blake3::hash(bytes).to_hex().to_string(),
        });
        Ok(())
    };
    write(
        format!("{stem}.lods.glb"),
        &gltf_write::write_glb(name, lods)?,
    )?;
    let texture = lods.first().and_then(|m| m.texture.clone());
    let mtl = format!("{stem}.mtl");
    let material = "base";
    for (k, lod) in lods.iter().enumerate() {
        let text = obj_write::obj_text(lod, Some((&mtl, material)));
        write(format!("{stem}_lod{k}.obj"), text.as_bytes())?;
    }
    let png = format!("{stem}_basecolor.png");
    let clamp = texture
        .as_ref()
        .is_some_and(|t| t.wrap == [Wrap::ClampToEdge; 2]);
    let tex_file = texture.as_ref().map(|_| png.as_str());
    write(
        mtl.clone(),
        obj_write::mtl_text(material, tex_file, clamp).as_bytes(),
    )?;
    if let Some(t) = &texture {
        write(png.clone(), &gltf_write::encode_png(t)?)?;
    }
    Ok(out)
}
