//! Per-instance tints: a tinted instance's pixels are its untinted pixels
//! times the tint in linear light, other instances are untouched, and a
//! tint count other than none or one per instance is an error. Runs on
//! llvmpipe (no GPU) in CI.

use acuity_render::{
    Lighting, Mesh, MeshId, RenderRequest, Renderer, RendererOptions, srgb8_to_linear,
};
use glam::Mat4;

const LIGHT: Lighting = Lighting {
    direction_to_light: [0.0, 0.0, 1.0],
    diffuse: 0.6,
    ambient: 0.3,
};

/// An axis-aligned rectangle in NDC at depth 0.5, facing the light.
fn rect(x: [f32; 2], y: [f32; 2], color: [f32; 3]) -> Mesh {
    let corners = [[x[0], y[0]], [x[1], y[0]], [x[1], y[1]], [x[0], y[1]]];
    Mesh {
        positions: corners.iter().map(|c| [c[0], c[1], 0.5]).collect(),
        normals: vec![[0.0, 0.0, 1.0]; 4],
        colors: vec![color; 4],
        uvs: Vec::new(),
        texture: None,
        indices: vec![0, 1, 2, 0, 2, 3],
        normals_computed: false,
    }
}

fn draw(
    r: &Renderer,
    size: [u32; 2],
    ids: &[MeshId],
    tint: &[[f32; 3]],
) -> Result<Vec<[u8; 4]>, acuity_render::Error> {
    let inst: Vec<(MeshId, Mat4)> = ids.iter().map(|&id| (id, Mat4::IDENTITY)).collect();
    let out = r.render(&RenderRequest {
        width: size[0],
        height: size[1],
        view_proj: Mat4::IDENTITY,
        instances: &inst,
        dither: &[],
        tint,
        lighting: LIGHT,
        background_srgb: [0, 0, 0],
    })?;
    Ok(out
        .rgba
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect())
}

#[test]
fn a_tint_multiplies_the_shaded_colour_in_linear_light() {
    for samples in [1, 4] {
        let r = Renderer::new(&RendererOptions {
            msaa_samples: samples,
        })
        .unwrap_or_else(|e| panic!("{e}"));
        // Two instances of different meshes, side by side, edges slanted
        // by nothing (whole pixels) so MSAA resolves no partial coverage
        // differently.
        let left = r
            .upload_mesh(&rect([-1.0, 0.0], [-1.0, 1.0], [0.9, 0.7, 0.5]))
            .unwrap();
        let right = r
            .upload_mesh(&rect([0.0, 1.0], [-1.0, 1.0], [0.4, 0.8, 0.6]))
            .unwrap();
        let size = [32, 16];
        let ids = [left, right];
        let plain = draw(&r, size, &ids, &[]).unwrap();
        let white = draw(&r, size, &ids, &[[1.0; 3]; 2]).unwrap();
        assert_eq!(white, plain, "{samples}x: a white tint changes nothing");
        let tint = [0.25, 0.5, 1.0];
        let tinted = draw(&r, size, &ids, &[tint, [1.0; 3]]).unwrap();
        for (k, (&p, &t)) in plain.iter().zip(&tinted).enumerate() {
            let x = k as u32 % size[0];
            assert!(
                p[..3].iter().all(|&c| c > 0),
                "{samples}x: pixel {k} is {p:?}"
            );
            if x >= size[0] / 2 {
                assert_eq!(t, p, "{samples}x: untinted pixel {k} changed");
                continue;
            }
            for c in 0..3 {
                let want = srgb8_to_linear(p[c]) * tint[c];
                let got = srgb8_to_linear(t[c]);
                // Both are rounded to sRGB8: allow one code step of each.
                let step = |v: u8| srgb8_to_linear(v.saturating_add(1)) - srgb8_to_linear(v);
                assert!(
                    (got - want).abs() <= step(t[c]) + step(p[c]) * tint[c],
                    "{samples}x: pixel {k} channel {c}: {got} vs {want} ({p:?} -> {t:?})"
                );
            }
            assert_eq!(t[2], p[2], "{samples}x: a tint of 1 keeps blue");
            assert!(t[0] < p[0] && t[1] < p[1], "{samples}x: pixel {k}");
        }
    }
}

#[test]
fn a_tint_count_other_than_none_or_one_per_instance_is_an_error() {
    let r = Renderer::new(&RendererOptions { msaa_samples: 1 }).unwrap_or_else(|e| panic!("{e}"));
    let id = r
        .upload_mesh(&rect([-1.0, 1.0], [-1.0, 1.0], [1.0; 3]))
        .unwrap();
    for tints in [vec![[1.0; 3]], vec![[1.0; 3]; 3]] {
        let err = draw(&r, [8, 8], &[id, id], &tints).unwrap_err();
        assert!(
            matches!(err, acuity_render::Error::Settings { field: "tint", .. }),
            "{err}"
        );
    }
}
