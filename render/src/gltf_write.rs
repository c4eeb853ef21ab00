//! Writing an LOD chain as one binary glTF (`.glb`): one node and one mesh
//! per LOD, named `<name>_LOD<k>`, so [`crate::gltf_mesh`] (and engines
//! that follow the same naming) read the chain back.
//!
//! Each LOD keeps its positions, normals, vertex colours (`COLOR_0`,
//! linear; left out when all white), texture coordinates, indices (16-bit
//! where they suffice) and base-colour texture (PNG, embedded in
//! the binary chunk; LODs that share a texture share the image). Material
//! factors are 1: the colour is all in `COLOR_0` and the texture, as the
//! loader multiplies them.

use std::collections::HashMap;
use std::sync::Arc;

use serde_json::{Value, json};

use crate::texture::{Texture, Wrap};
use crate::{Error, Mesh};

/// The GLB bytes of `lods` (finest first), nodes named `<name>_LOD<k>`.
/// Errors only when a texture cannot be encoded as PNG.
pub fn write_glb(name: &str, lods: &[Mesh]) -> Result<Vec<u8>, Error> {
    let names: Vec<String> = (0..lods.len()).map(|k| format!("{name}_LOD{k}")).collect();
    write_named(&names, lods)
}

/// The GLB bytes of one mesh (no LOD chain), node and mesh named `name`.
pub fn write_glb_single(name: &str, mesh: &Mesh) -> Result<Vec<u8>, Error> {
    write_named(&[name.to_owned()], std::slice::from_ref(mesh))
}

/// One node and mesh per entry of `lods`, named by `names`.
fn write_named(names: &[String], lods: &[Mesh]) -> Result<Vec<u8>, Error> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views: Vec<Value> = Vec::new();
    let mut accessors: Vec<Value> = Vec::new();
    let mut images: Vec<Value> = Vec::new();
    let mut samplers: Vec<Value> = Vec::new();
    let mut textures: Vec<Value> = Vec::new();
    let mut materials: Vec<Value> = vec![json!({
        "name": "untextured",
        "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0] }
    })];
    let mut material_of: HashMap<usize, usize> = HashMap::new();
    let mut meshes: Vec<Value> = Vec::new();
    let mut nodes: Vec<Value> = Vec::new();

    // A buffer view over `bytes` (4-byte aligned) and its index.
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8], target: Option<u32>| -> usize {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        bin.extend_from_slice(bytes);
        views.push(v);
        views.len() - 1
    };
    const ARRAY_BUFFER: u32 = 34962;
    const ELEMENT_ARRAY_BUFFER: u32 = 34963;

    for (k, mesh) in lods.iter().enumerate() {
        let mut attribute = |bin: &mut Vec<u8>, data: Vec<f32>, dims: usize, minmax: bool| {
            let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
            let view = push_view(bin, &bytes, Some(ARRAY_BUFFER));
            let ty = ["", "SCALAR", "VEC2", "VEC3", "VEC4"][dims];
            let mut a = json!({
                "bufferView": view, "componentType": 5126,
                "count": data.len() / dims, "type": ty
            });
            if minmax {
                let mut lo = vec![f32::INFINITY; dims];
                let mut hi = vec![f32::NEG_INFINITY; dims];
                for e in data.chunks_exact(dims) {
                    for d in 0..dims {
                        lo[d] = lo[d].min(e[d]);
                        hi[d] = hi[d].max(e[d]);
                    }
                }
                a["min"] = json!(lo);
                a["max"] = json!(hi);
            }
            accessors.push(a);
            accessors.len() - 1
        };
        let pos = attribute(&mut bin, mesh.positions.concat(), 3, true);
        let nrm = attribute(&mut bin, mesh.normals.concat(), 3, false);
        let mut attrs = json!({ "POSITION": pos, "NORMAL": nrm });
        // All-white vertex colours are glTF's default: left out.
        if mesh.colors.iter().any(|c| *c != [1.0; 3]) {
            attrs["COLOR_0"] = json!(attribute(&mut bin, mesh.colors.concat(), 3, false));
        }
        if !mesh.uvs.is_empty() {
            attrs["TEXCOORD_0"] = json!(attribute(&mut bin, mesh.uvs.concat(), 2, false));
        }
        // 16-bit indices where they suffice, else 32-bit.
        let short = mesh.positions.len() <= usize::from(u16::MAX);
        let ibytes: Vec<u8> = if short {
            mesh.indices
                .iter()
                .flat_map(|&i| (i as u16).to_le_bytes())
                .collect()
        } else {
            mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect()
        };
        let iview = push_view(&mut bin, &ibytes, Some(ELEMENT_ARRAY_BUFFER));
        accessors.push(json!({
            "bufferView": iview, "componentType": if short { 5123 } else { 5125 },
            "count": mesh.indices.len(), "type": "SCALAR"
        }));
        let indices = accessors.len() - 1;
        let material = match &mesh.texture {
            None => 0,
            Some(t) => {
                let key = Arc::as_ptr(t) as usize;
                if let Some(&m) = material_of.get(&key) {
                    m
                } else {
                    let png = encode_png(t)?;
                    let view = push_view(&mut bin, &png, None);
                    images.push(json!({ "bufferView": view, "mimeType": "image/png" }));
                    let wrap = |w: Wrap| match w {
                        Wrap::Repeat => 10497,
                        Wrap::ClampToEdge => 33071,
                        Wrap::MirroredRepeat => 33648,
                    };
                    samplers.push(json!({
                        "magFilter": 9729, "minFilter": 9987,
                        "wrapS": wrap(t.wrap[0]), "wrapT": wrap(t.wrap[1])
                    }));
                    textures.push(json!({
                        "source": images.len() - 1, "sampler": samplers.len() - 1
                    }));
                    materials.push(json!({
                        "name": format!("textured{}", textures.len() - 1),
                        "pbrMetallicRoughness": {
                            "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                            "baseColorTexture": { "index": textures.len() - 1 }
                        }
                    }));
                    material_of.insert(key, materials.len() - 1);
                    materials.len() - 1
                }
            }
        };
        let lod_name = &names[k];
        meshes.push(json!({
            "name": lod_name,
            "primitives": [{ "attributes": attrs, "indices": indices, "material": material }]
        }));
        nodes.push(json!({ "name": lod_name, "mesh": k }));
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "acuity" },
        "scene": 0,
        "scenes": [{ "nodes": (0..lods.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{ "byteLength": bin.len() }]
    });
    if !images.is_empty() {
        doc["images"] = json!(images);
        doc["samplers"] = json!(samplers);
        doc["textures"] = json!(textures);
    }
    let mut json_bytes = serde_json::to_vec(&doc).map_err(|e| Error::Gpu {
        message: format!("encoding glTF JSON: {e}"),
    })?;
    while !json_bytes.len().is_multiple_of(4) {
        json_bytes.push(b' ');
    }
    let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_bytes);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}

/// The texture as PNG bytes (sRGB RGBA8).
pub fn encode_png(t: &Texture) -> Result<Vec<u8>, Error> {
    let mut png = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut png),
        &t.rgba,
        t.width,
        t.height,
        image::ExtendedColorType::Rgba8,
    )
    .map_err(|e| Error::WriteImage {
        path: t.source.clone().into(),
        message: e.to_string(),
    })?;
    Ok(png)
}
