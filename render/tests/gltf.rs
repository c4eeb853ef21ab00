//! glTF input: a written chain reads back the same, and a corpus of broken
//! files (truncated, bad indices, missing buffers, NaN, bad texture
//! references, cycles, unsupported extensions) gives errors naming the
//! part that is wrong, never a panic.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use acuity_render::gltf_mesh::{LodRule, parse_gltf};
use acuity_render::gltf_write::write_glb;
use acuity_render::{Error, Mesh, Texture};
use serde_json::{Value, json};

/// An `n`×`n` grid of quads over [0, 1]², textured by `texture`.
fn grid(n: u32, texture: &Arc<Texture>) -> Mesh {
    let mut m = Mesh {
        positions: Vec::new(),
        normals: Vec::new(),
        colors: Vec::new(),
        uvs: Vec::new(),
        texture: Some(texture.clone()),
        indices: Vec::new(),
        normals_computed: false,
    };
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            m.positions.push([u, v, 0.0]);
            m.normals.push([0.0, 0.0, 1.0]);
            m.colors.push([0.5, 0.75, 1.0]);
            m.uvs.push([u, 1.0 - v]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            m.indices.extend([
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j),
                id(i + 1, j + 1),
                id(i, j + 1),
            ]);
        }
    }
    m
}

fn checker_texture() -> Arc<Texture> {
    let mut rgba = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let v = if (x + y) % 2 == 0 { 250 } else { 10 };
            rgba.extend_from_slice(&[v, v / 2, 255 - v, 255]);
        }
    }
    Arc::new(Texture::from_rgba(8, 8, rgba, "checker").unwrap())
}

fn no_files(_: &str) -> std::io::Result<(PathBuf, Vec<u8>)> {
    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
}

fn parse(bytes: &[u8]) -> Result<acuity_render::gltf_mesh::GltfLods, Error> {
    parse_gltf(bytes, Path::new("t.glb"), &mut no_files)
}

/// The JSON and binary chunks of a GLB written by `write_glb`.
fn split(glb: &[u8]) -> (Value, Vec<u8>) {
    let jlen = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json = serde_json::from_slice(&glb[20..20 + jlen]).unwrap();
    (json, glb[20 + jlen + 8..].to_vec())
}

/// A GLB from a JSON document and a binary chunk.
fn join(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out
}

fn sample() -> Vec<u8> {
    let t = checker_texture();
    write_glb("tile", &[grid(4, &t), grid(2, &t)]).unwrap()
}

#[test]
fn a_written_chain_reads_back_the_same() {
    let t = checker_texture();
    let lods = [grid(4, &t), grid(2, &t), grid(1, &t)];
    let glb = write_glb("tile", &lods).unwrap();
    let back = parse(&glb).unwrap();
    assert_eq!(back.rule, LodRule::Names);
    assert_eq!(back.lods.len(), 3);
    for (a, b) in lods.iter().zip(&back.lods) {
        assert_eq!(a.triangle_count(), b.triangle_count());
        assert_eq!(a.positions, b.positions);
        assert_eq!(a.uvs, b.uvs);
        assert_eq!(a.colors, b.colors);
        let bt = b.texture.as_ref().unwrap();
        assert_eq!((bt.width, bt.height, &bt.rgba), (8, 8, &t.rgba));
    }
    // The LODs share one texture, as they did.
    assert!(Arc::ptr_eq(
        back.lods[0].texture.as_ref().unwrap(),
        back.lods[2].texture.as_ref().unwrap()
    ));
}

#[test]
fn node_transforms_are_flattened_and_a_single_mesh_is_one_lod() {
    let t = checker_texture();
    let (mut json, bin) = split(&write_glb("tile", &[grid(1, &t)]).unwrap());
    json["nodes"][0]["name"] = json!("plain");
    json["meshes"][0]["name"] = json!("plain");
    json["nodes"][0]["translation"] = json!([10.0, 0.0, 0.0]);
    json["nodes"][0]["scale"] = json!([2.0, 2.0, 2.0]);
    let back = parse(&join(&json, &bin)).unwrap();
    assert_eq!(back.rule, LodRule::Single);
    let xs: Vec<f32> = back.lods[0].positions.iter().map(|p| p[0]).collect();
    assert_eq!(xs.iter().cloned().fold(f32::MAX, f32::min), 10.0);
    assert_eq!(xs.iter().cloned().fold(f32::MIN, f32::max), 12.0);
}

#[test]
fn msft_lod_gives_the_chain() {
    let t = checker_texture();
    let (mut json, bin) = split(&write_glb("tile", &[grid(4, &t), grid(2, &t)]).unwrap());
    json["nodes"][0]["name"] = json!("a");
    json["nodes"][1]["name"] = json!("b");
    json["nodes"][0]["extensions"] = json!({ "MSFT_lod": { "ids": [1] } });
    json["extensionsUsed"] = json!(["MSFT_lod"]);
    json["scenes"][0]["nodes"] = json!([0]);
    let back = parse(&join(&json, &bin)).unwrap();
    assert_eq!(back.rule, LodRule::MsftLod);
    let counts: Vec<usize> = back.lods.iter().map(Mesh::triangle_count).collect();
    assert_eq!(counts, [32, 8]);
}

#[test]
fn truncated_glb_files_are_errors_at_every_length() {
    let glb = sample();
    for len in 0..glb.len() {
        let r = parse(&glb[..len]);
        // Cutting only padding can leave a readable file; nothing panics.
        if len < glb.len() - 3 {
            assert!(
                r.is_err(),
                "truncated to {len} of {} bytes parsed",
                glb.len()
            );
        }
    }
}

#[test]
fn flipped_bytes_never_panic() {
    let glb = sample();
    // A fixed pseudo-random sequence of single-byte corruptions.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    for _ in 0..3000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let mut bad = glb.clone();
        let at = (x % bad.len() as u64) as usize;
        bad[at] = (x >> 32) as u8;
        let _ = parse(&bad);
    }
}

/// The error message of a file made from the sample by `edit`.
fn error_of(what: &str, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> String {
    let (mut json, mut bin) = split(&sample());
    edit(&mut json, &mut bin);
    match parse(&join(&json, &bin)) {
        Ok(_) => panic!("{what}: the broken file parsed"),
        Err(e) => e.to_string(),
    }
}

/// A change that breaks the sample.
type Edit = Box<dyn FnOnce(&mut Value, &mut Vec<u8>)>;

#[test]
fn broken_files_name_what_is_wrong() {
    let cases: Vec<(&str, Edit, &[&str])> = vec![
        (
            "accessor index out of range",
            Box::new(|j, _| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99)),
            &["POSITION"],
        ),
        (
            "index past the vertices",
            Box::new(|j, bin| {
                let acc = j["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
                let view = j["accessors"][acc]["bufferView"].as_u64().unwrap() as usize;
                let at = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
                bin[at..at + 2].copy_from_slice(&1000u16.to_le_bytes());
            }),
            &["accessor 4", "indices", "1000"],
        ),
        (
            "NaN position",
            Box::new(|j, bin| {
                let view = j["accessors"][0]["bufferView"].as_u64().unwrap() as usize;
                let at = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
                bin[at + 4..at + 8].copy_from_slice(&f32::NAN.to_le_bytes());
            }),
            &["accessor 0", "POSITION", "not finite"],
        ),
        (
            "texture reference out of range",
            Box::new(|j, _| {
                j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = json!(7)
            }),
            &["materials[1].pbrMetallicRoughness.baseColorTexture.index"],
        ),
        (
            "image source out of range",
            Box::new(|j, _| j["textures"][0]["source"] = json!(3)),
            &["textures[0].source"],
        ),
        (
            "buffer view past its buffer",
            Box::new(|j, _| j["bufferViews"][0]["byteLength"] = json!(1_000_000)),
            &["buffer view 0", "outside buffer 0"],
        ),
        (
            "accessor past its view",
            Box::new(|j, _| j["accessors"][0]["count"] = json!(5000)),
            &["accessor 0", "run past the end of buffer view"],
        ),
        (
            "attribute shorter than POSITION",
            Box::new(|j, _| {
                let uv = j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"].clone();
                let uv = uv.as_u64().unwrap() as usize;
                j["accessors"][uv]["count"] = json!(3);
            }),
            &["TEXCOORD_0", "has 3 elements but POSITION has 25"],
        ),
        (
            "missing binary chunk",
            Box::new(|_, bin| bin.clear()),
            &["buffer 0"],
        ),
        (
            "external buffer missing",
            Box::new(|j, _| j["buffers"][0]["uri"] = json!("gone.bin")),
            &["buffer 0", "gone.bin", "cannot be read"],
        ),
        (
            "required extension",
            Box::new(|j, _| {
                j["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
                j["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
            }),
            &["KHR_draco_mesh_compression"],
        ),
        (
            "node cycle",
            Box::new(|j, _| {
                j["nodes"][0]["children"] = json!([1]);
                j["nodes"][1]["children"] = json!([0]);
            }),
            &["cycle"],
        ),
        (
            "LOD gap",
            Box::new(|j, _| j["nodes"][1]["name"] = json!("tile_LOD2")),
            &["LOD 1 is missing"],
        ),
        (
            "bad MSFT_lod id",
            Box::new(|j, _| j["nodes"][0]["extensions"] = json!({ "MSFT_lod": { "ids": [42] } })),
            &["MSFT_lod", "42"],
        ),
        (
            "undecodable image",
            Box::new(|j, bin| {
                let view = j["images"][0]["bufferView"].as_u64().unwrap() as usize;
                let at = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
                bin[at + 20..at + 40].fill(0);
            }),
            &["image 0"],
        ),
    ];
    for (what, edit, words) in cases {
        let e = error_of(what, edit);
        for w in words {
            assert!(e.contains(w), "{what}: `{w}` not in: {e}");
        }
        assert!(e.starts_with("t.glb: "), "{what}: {e}");
    }
}

#[test]
fn garbage_and_empty_files_are_errors() {
    for bytes in [
        &b""[..],
        b"glTF",
        b"glTF\x02\0\0\0\x05\0\0\0",
        b"{",
        b"\x00\x01\x02",
        b"{\"asset\":{}}",
    ] {
        assert!(parse(bytes).is_err(), "{bytes:?}");
    }
    // A document with no meshes draws nothing.
    let e = parse(br#"{"asset":{"version":"2.0"}}"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no triangles"), "{e}");
}
