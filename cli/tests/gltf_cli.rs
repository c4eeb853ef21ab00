//! `acuity preprocess` on glTF files: a textured asset and a file carrying
//! its own LOD chain are analysed, and a corpus of malformed files
//! (truncated, garbage, bad accessor indices, missing buffers, NaN
//! positions, out-of-range texture references) exits with 1 or 2 and a
//! message naming the file, never a panic (101).

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::Arc;

use acuity_preprocess::lods::generate_lods;
use acuity_preprocess::render::gltf_write::write_glb;
use acuity_preprocess::sample::{checker_texture, textured_globe_glb, uv_sphere};
use serde_json::{Value, json};

const FAST: [&str; 6] = [
    "--resolution",
    "64",
    "--min-diameter",
    "32",
    "--viewpoints",
    "0",
];

fn temp_dir(test: &str) -> PathBuf {
    common::scratch("gltf_cli", test)
}

fn preprocess(path: &Path, extra: &[&str]) -> Output {
    let path = path.to_str().unwrap();
    let args: Vec<&str> = [&["preprocess", path][..], &FAST, extra].concat();
    common::acuity_logged(&args)
}

#[test]
fn a_textured_glb_and_a_glb_chain_are_analysed() {
    let dir = temp_dir("good");
    let globe = dir.join("globe.glb");
    std::fs::write(&globe, textured_globe_glb().unwrap()).unwrap();
    let o = preprocess(&globe, &["--triangles", "2000,500,120"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(dir.join(".acuity-cache/globe.acp").is_file());

    // A file with its own chain: analysed as it is, no --triangles.
    let t = Arc::new(checker_texture(64, 8));
    let chain = generate_lods("c", &uv_sphere(800, Some(t)), &[800, 200]).unwrap();
    let counts: Vec<usize> = chain.iter().map(|m| m.triangle_count()).collect();
    let path = dir.join("chain.glb");
    std::fs::write(&path, write_glb("chain", &chain).unwrap()).unwrap();
    let o = preprocess(&path, &[]);
    assert_eq!(o.status.code(), Some(0));
    let profile = acuity::Profile::load(dir.join(".acuity-cache/chain.acp")).unwrap();
    let got: Vec<usize> = profile.lod_triangles.iter().map(|&n| n as usize).collect();
    assert_eq!(got, counts);

    // A scene names the file's chain with `lods = [file]`, and generates
    // LODs from a glTF with `mesh`.
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        r#"[display]
resolution = [320, 240]
fov_deg = [40.0, 30.0]

[[objects]]
name = "carried"
lods = ["chain.glb"]

[[objects]]
name = "generated"
mesh = "globe.glb"
generate_triangles = [2024, 300]

[camera]
duration_s = 1.0
forward_speed_m_per_s = 1.0
start = { position = [0.0, 0.0, 5.0], yaw_deg = 0.0, pitch_deg = 0.0 }
"#,
    )
    .unwrap();
    let o = preprocess(&scene, &[]);
    assert_eq!(o.status.code(), Some(0));
    let carried = acuity::Profile::load(dir.join(".acuity-cache/carried.acp")).unwrap();
    assert_eq!(carried.lod_triangles, profile.lod_triangles);
}

/// The sample's JSON and binary chunks.
fn split(glb: &[u8]) -> (Value, Vec<u8>) {
    let jlen = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json = serde_json::from_slice(&glb[20..20 + jlen]).unwrap();
    (json, glb[20 + jlen + 8..].to_vec())
}

fn join(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    for w in [0x4654_6c67u32, 2, total as u32, j.len() as u32, 0x4e4f_534a] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out
}

/// A change that breaks the sample.
type Edit = fn(&mut Value, &mut Vec<u8>);

#[test]
fn malformed_gltf_files_exit_with_1_or_2_never_a_panic() {
    let dir = temp_dir("malformed");
    let glb = textured_globe_glb().unwrap();
    let edits: [(&str, Edit); 6] = [
        ("bad_accessor_index", |j, _| {
            j["meshes"][0]["primitives"][0]["indices"] = json!(77)
        }),
        ("missing_buffer", |j, _| {
            j["buffers"][0]["uri"] = json!("nowhere.bin")
        }),
        ("nan_position", |j, bin| {
            let view = j["accessors"][0]["bufferView"].as_u64().unwrap() as usize;
            let at = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        }),
        ("texture_out_of_range", |j, _| {
            j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = json!(9)
        }),
        ("index_past_vertices", |j, bin| {
            let acc = j["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
            let view = j["accessors"][acc]["bufferView"].as_u64().unwrap() as usize;
            let at = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
            bin[at..at + 2].copy_from_slice(&u16::MAX.to_le_bytes());
        }),
        ("view_past_buffer", |j, _| {
            j["bufferViews"][1]["byteOffset"] = json!(1 << 30)
        }),
    ];
    let mut files: Vec<(String, Vec<u8>)> = edits
        .iter()
        .map(|(name, edit)| {
            let (mut j, mut bin) = split(&glb);
            edit(&mut j, &mut bin);
            (format!("{name}.glb"), join(&j, &bin))
        })
        .collect();
    files.push(("truncated.glb".into(), glb[..glb.len() / 2].to_vec()));
    files.push(("header_only.glb".into(), glb[..12].to_vec()));
    files.push(("garbage.glb".into(), b"\x00garbage\xff".to_vec()));
    files.push(("garbage.gltf".into(), b"{ not json".to_vec()));
    files.push(("empty.gltf".into(), Vec::new()));
    for (name, bytes) in files {
        let path = dir.join(&name);
        std::fs::write(&path, &bytes).unwrap();
        let o = preprocess(&path, &[]);
        let code = o.status.code();
        assert!(matches!(code, Some(1) | Some(2)), "{name}: exit {code:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(&name), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
}

#[test]
fn exported_lods_read_back_with_the_profiles_counts_and_hashes() {
    let dir = temp_dir("export");
    let globe = dir.join("globe.glb");
    std::fs::write(&globe, textured_globe_glb().unwrap()).unwrap();
    let args = ["--triangles", "2024,500,120", "--export-lods"];
    let o = preprocess(&globe, &args);
    assert_eq!(o.status.code(), Some(0));
    let cache = dir.join(".acuity-cache");
    let profile = acuity::Profile::load(cache.join("globe.acp")).unwrap();
    let want: Vec<usize> = profile.lod_triangles.iter().map(|&n| n as usize).collect();
    assert_eq!(want.len(), 3);

    // Every exported file is recorded with the hash of its bytes.
    let recorded: Vec<(String, String)> = profile
        .inputs
        .iter()
        .filter_map(|h| {
            Some((
                h.what.strip_prefix("exported:")?.to_owned(),
                h.hash_hex.clone(),
            ))
        })
        .collect();
    let names: Vec<&str> = recorded.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "globe.lods.glb",
            "globe_lod0.obj",
            "globe_lod1.obj",
            "globe_lod2.obj",
            "globe.mtl",
            "globe_basecolor.png"
        ]
    );
    for (name, hash) in &recorded {
        let bytes = std::fs::read(cache.join(name)).unwrap();
        assert_eq!(&blake3_hex(&bytes), hash, "{name}");
    }

    // The .glb reads back as the chain, the OBJ files one LOD each, with
    // the profile's triangle counts; the glb's texture is the asset's.
    let chain =
        acuity_preprocess::render::gltf_mesh::load_gltf(&cache.join("globe.lods.glb")).unwrap();
    let got: Vec<usize> = chain.lods.iter().map(|m| m.triangle_count()).collect();
    assert_eq!(got, want);
    let original = acuity_preprocess::render::gltf_mesh::load_gltf(&globe).unwrap();
    assert_eq!(
        chain.lods[0].texture.as_ref().unwrap().rgba,
        original.lods[0].texture.as_ref().unwrap().rgba
    );
    for (k, n) in want.iter().enumerate() {
        let m =
            acuity_preprocess::mesh::load_obj(&cache.join(format!("globe_lod{k}.obj"))).unwrap();
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        assert_eq!(m.mesh.triangle_count(), *n, "LOD {k}");
        assert!(m.mesh.texture.is_some());
    }

    // A second run is cached (the records are not inputs) and exports the
    // same bytes.
    let o = preprocess(&globe, &args);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("globe: cached"));
    let again = acuity::Profile::load(cache.join("globe.acp")).unwrap();
    assert_eq!(again.inputs, profile.inputs);
}

fn blake3_hex(bytes: &[u8]) -> String {
    acuity_preprocess::input_files::hash_hex(bytes)
}
