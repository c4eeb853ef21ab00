//! Textures in the offline pass: a texture is drawn (and its mips), and a
//! texture-only change is seen: the same mesh and LODs with a
//! high-frequency texture and with a flat colour give transitions of
//! different contrasted area. Runs on llvmpipe (no GPU) in CI.

use std::sync::Arc;

use acuity_preprocess::lods::generate_lods;
use acuity_preprocess::pipeline::{ObjectAnalysis, analyse_lods};
use acuity_preprocess::render::Lighting;
use acuity_preprocess::sample::{checker_texture, uv_sphere};
use acuity_preprocess::{
    AnalysisSettings, Mesh, RenderRequest, Renderer, RendererOptions, RunOptions,
};
use glam::Mat4;

fn renderer() -> Renderer {
    Renderer::new(&RendererOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Per viewpoint, the area (diam²) of the features of at least 10%
/// contrast that transition 0 -> 1 has at the one rung analysed.
fn contrasted_area(a: &ObjectAnalysis) -> Vec<f32> {
    (0..a.viewpoints.len())
        .map(|v| {
            a.transitions_at(v, 0)[0]
                .features
                .iter()
                .filter(|f| {
                    (f.luminance[1] - f.luminance[0]) >= 0.1 * (f.luminance[1] + f.luminance[0])
                })
                .map(|f| f.area_diam2)
                .sum()
        })
        .collect()
}

#[test]
fn a_high_frequency_texture_adds_contrasted_features() {
    let r = renderer();
    let settings = AnalysisSettings {
        resolution_px: 128,
        min_diameter_px: 128,
        viewpoint_level: 0,
        ..Default::default()
    };
    let texture = Arc::new(checker_texture(256, 32));
    let textured = uv_sphere(2000, Some(texture));
    // The same mesh with the texture's mean colour and no texture.
    let mut flat = textured.clone();
    flat.texture = None;
    flat.uvs.clear();
    for c in &mut flat.colors {
        *c = [0.3, 0.25, 0.3];
    }
    let targets = [2000, 300];
    let run = RunOptions::default();
    let a_tex = analyse_lods(
        &r,
        "textured",
        &generate_lods("textured", &textured, &targets).unwrap(),
        &settings,
        &run,
    )
    .unwrap();
    let a_flat = analyse_lods(
        &r,
        "flat",
        &generate_lods("flat", &flat, &targets).unwrap(),
        &settings,
        &run,
    )
    .unwrap();
    let (tex, flat) = (contrasted_area(&a_tex), contrasted_area(&a_flat));
    eprintln!("contrasted area (diam²) per view: textured {tex:?}, flat {flat:?}");
    // The flat sphere's coarse LOD only moves its silhouette and shading
    // (its shading change is one contrasted feature); the textured one
    // also moves the checks, contrasted features as wide as a check: more
    // than twice the contrasted area on every viewpoint (measured: 2.5 to
    // 4.8 times).
    for (v, (t, f)) in tex.iter().zip(&flat).enumerate() {
        assert!(*t > 2.0 * f, "view {v}: textured {t} diam², flat {f}");
    }
}

/// A quad filling the view, textured with a 2x1 texture (red | blue) or,
/// for `filter`, a 64x64 one-texel checkerboard.
fn quad(texture: Texture) -> Mesh {
    Mesh {
        positions: vec![
            [-1.0, -1.0, 0.5],
            [1.0, -1.0, 0.5],
            [1.0, 1.0, 0.5],
            [-1.0, 1.0, 0.5],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        colors: vec![[1.0; 3]; 4],
        uvs: vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]],
        texture: Some(Arc::new(texture)),
        indices: vec![0, 1, 2, 0, 2, 3],
        normals_computed: false,
    }
}

use acuity_preprocess::render::Texture;

fn draw(r: &Renderer, m: &Mesh, size: u32) -> Vec<u8> {
    let id = r.upload_mesh(m).unwrap();
    let out = r
        .render(&RenderRequest {
            width: size,
            height: size,
            view_proj: Mat4::IDENTITY,
            instances: &[(id, Mat4::IDENTITY)],
            dither: &[],
            albedo: &[],
            lighting: Lighting {
                direction_to_light: [0.0, 0.0, 1.0],
                diffuse: 1.0,
                ambient: 0.0,
            },
            background_srgb: [0, 0, 0],
        })
        .unwrap();
    r.free_mesh(id);
    out.rgba
}

#[test]
fn the_texture_is_drawn_and_minified_through_its_mips() {
    let r = renderer();
    let t = Texture::from_rgba(2, 1, vec![255, 0, 0, 255, 0, 0, 255, 255], "t").unwrap();
    let mut t = t;
    t.wrap = [acuity_preprocess::render::texture::Wrap::ClampToEdge; 2];
    let img = draw(&r, &quad(t), 64);
    let px = |x: usize, y: usize| &img[(y * 64 + x) * 4..][..3];
    assert_eq!(px(4, 32), [255, 0, 0], "left is red");
    assert_eq!(px(60, 32), [0, 0, 255], "right is blue");
    // A one-texel checkerboard of 256² drawn at 16²: the mips average it
    // to a uniform grey of linear 0.5 (sRGB 188); without mips the samples
    // would alias to black and white.
    let mut rgba = Vec::new();
    for y in 0..256 {
        for x in 0..256 {
            let v = if (x + y) % 2 == 0 { 255 } else { 0 };
            rgba.extend_from_slice(&[v, v, v, 255]);
        }
    }
    let img = draw(
        &r,
        &quad(Texture::from_rgba(256, 256, rgba, "checker").unwrap()),
        16,
    );
    for p in img.chunks_exact(4) {
        assert!((180..=196).contains(&p[0]), "{p:?}");
    }
}

#[test]
fn input_hashes_cover_textures_and_gltf_files() {
    use acuity_preprocess::{ObjectSource, input_hashes};
    let dir = std::env::temp_dir().join(format!("acuity-tex-hash-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let s = AnalysisSettings::default();
    let changed_by = |src: &ObjectSource, file: &str, bytes: &[u8]| -> Vec<String> {
        let before = input_hashes(src, &s).unwrap();
        std::fs::write(dir.join(file), bytes).unwrap();
        let after = input_hashes(src, &s).unwrap();
        before
            .iter()
            .zip(&after)
            .filter(|(a, b)| a != b)
            .map(|(a, _)| a.what.clone())
            .collect()
    };
    // OBJ -> MTL -> map_Kd texture.
    let obj = dir.join("a.obj");
    std::fs::write(&obj, "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("a.mtl"), "newmtl m\nmap_Kd -clamp on tex.png\n").unwrap();
    std::fs::write(dir.join("tex.png"), b"one").unwrap();
    let src = ObjectSource::Generated {
        name: "a".into(),
        path: obj,
        triangle_targets: vec![1, 0],
    };
    let changed = changed_by(&src, "tex.png", b"two");
    assert!(
        changed.len() == 1 && changed[0].ends_with("tex.png"),
        "{changed:?}"
    );
    // A .gltf with an external buffer and image.
    let gltf = dir.join("b.gltf");
    std::fs::write(
        &gltf,
        r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"b%20data.bin","byteLength":4}],
            "images":[{"uri":"b.png"}]}"#,
    )
    .unwrap();
    let src = ObjectSource::Files {
        name: "b".into(),
        lod_paths: vec![gltf],
    };
    let whats: Vec<String> = input_hashes(&src, &s)
        .unwrap()
        .into_iter()
        .map(|h| h.what)
        .collect();
    assert!(
        whats[1].ends_with("b data.bin") && whats[2].ends_with("b.png"),
        "{whats:?}"
    );
    let changed = changed_by(&src, "b.png", b"image");
    assert!(
        changed.len() == 1 && changed[0].ends_with("b.png"),
        "{changed:?}"
    );
    let changed = changed_by(&src, "b data.bin", b"data");
    assert!(
        changed.len() == 1 && changed[0].ends_with("b data.bin"),
        "{changed:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
