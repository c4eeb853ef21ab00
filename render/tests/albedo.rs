//! Per-instance colour overrides: an instance with an albedo is drawn
//! exactly as its mesh would be with that vertex colour (lit the same),
//! other instances are untouched, and an albedo count other than none or
//! one per instance is an error. Runs on llvmpipe (no GPU) in CI.

use acuity_render::{Lighting, Mesh, MeshId, RenderRequest, Renderer, RendererOptions};
use glam::Mat4;

const LIGHT: Lighting = Lighting {
    direction_to_light: [0.3, 0.2, 1.0],
    diffuse: 0.6,
    ambient: 0.3,
};

/// An axis-aligned rectangle in NDC at depth 0.5, its normals tilted
/// across it (so its shading varies), coloured per corner.
fn rect(x: [f32; 2], y: [f32; 2], colors: [[f32; 3]; 4]) -> Mesh {
    let corners = [[x[0], y[0]], [x[1], y[0]], [x[1], y[1]], [x[0], y[1]]];
    Mesh {
        positions: corners.iter().map(|c| [c[0], c[1], 0.5]).collect(),
        normals: vec![
            [-0.5, 0.0, 1.0],
            [0.5, 0.0, 1.0],
            [0.5, 0.3, 1.0],
            [-0.5, 0.3, 1.0],
        ],
        colors: colors.to_vec(),
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
    albedo: &[[f32; 3]],
) -> Result<Vec<u8>, acuity_render::Error> {
    let inst: Vec<(MeshId, Mat4)> = ids.iter().map(|&id| (id, Mat4::IDENTITY)).collect();
    let out = r.render(&RenderRequest {
        width: size[0],
        height: size[1],
        view_proj: Mat4::IDENTITY,
        instances: &inst,
        dither: &[],
        albedo,
        lighting: LIGHT,
        background_srgb: [0, 0, 0],
    })?;
    Ok(out.rgba)
}

#[test]
fn an_albedo_replaces_the_mesh_colours_and_is_lit_as_usual() {
    let rainbow = [
        [0.9, 0.2, 0.1],
        [0.1, 0.8, 0.3],
        [0.2, 0.3, 0.9],
        [0.9, 0.9, 0.2],
    ];
    let green = [0.1, 0.8, 0.2];
    for samples in [1, 4] {
        let r = Renderer::new(&RendererOptions {
            msaa_samples: samples,
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let (left_x, right_x) = ([-1.0, 0.0], [0.0, 1.0]);
        let left = r.upload_mesh(&rect(left_x, [-1.0, 1.0], rainbow)).unwrap();
        let right = r.upload_mesh(&rect(right_x, [-1.0, 1.0], rainbow)).unwrap();
        let left_green = r
            .upload_mesh(&rect(left_x, [-1.0, 1.0], [green; 4]))
            .unwrap();
        let size = [32, 16];
        let plain = draw(&r, size, &[left, right], &[]).unwrap();
        let want = draw(&r, size, &[left_green, right], &[]).unwrap();
        assert_ne!(plain, want, "{samples}x: the colours differ");
        let got = draw(&r, size, &[left, right], &[green, [0.5; 3]]).unwrap();
        let got_left: Vec<u8> = got
            .chunks(size[0] as usize * 4)
            .flat_map(|row| row[..64].to_vec())
            .collect();
        let want_left: Vec<u8> = want
            .chunks(size[0] as usize * 4)
            .flat_map(|row| row[..64].to_vec())
            .collect();
        assert_eq!(got_left, want_left, "{samples}x: as if coloured green");
        let only_left = draw(&r, size, &[left, right], &[green, green]).unwrap();
        assert_ne!(only_left, got, "{samples}x: the right one's albedo counts");
        let untouched = draw(&r, size, &[left, right], &[]).unwrap();
        assert_eq!(untouched, plain, "{samples}x: without albedo, as before");
    }
}

#[test]
fn an_albedo_count_other_than_none_or_one_per_instance_is_an_error() {
    let r = Renderer::new(&RendererOptions { msaa_samples: 1 }).unwrap_or_else(|e| panic!("{e}"));
    let id = r
        .upload_mesh(&rect([-1.0, 1.0], [-1.0, 1.0], [[1.0; 3]; 4]))
        .unwrap();
    for colours in [vec![[1.0; 3]], vec![[1.0; 3]; 3]] {
        let err = draw(&r, [8, 8], &[id, id], &colours).unwrap_err();
        assert!(
            matches!(
                err,
                acuity_render::Error::Settings {
                    field: "albedo",
                    ..
                }
            ),
            "{err}"
        );
    }
}
