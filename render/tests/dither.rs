//! Dithered cross-fades: the two masks of a fade split every pixel between
//! the LOD fading out and the one fading in, and the ends of a fade equal
//! the plain draws. Runs on llvmpipe (no GPU) in CI.

use acuity_render::{DitherMask, Lighting, Mesh, MeshId, RenderRequest, Renderer, RendererOptions};
use glam::Mat4;

const BACKGROUND: [u8; 3] = [0, 0, 0];
const LIGHT: Lighting = Lighting {
    direction_to_light: [0.0, 0.0, 1.0],
    diffuse: 1.0,
    ambient: 0.0,
};

fn renderer(msaa_samples: u32) -> Renderer {
    Renderer::new(&RendererOptions { msaa_samples }).unwrap_or_else(|e| panic!("{e}"))
}

/// A flat polygon in NDC at depth `z` (a fan around its first corner).
fn polygon(corners: &[[f32; 2]], z: f32, color: [f32; 3]) -> Mesh {
    let n = corners.len() as u32;
    Mesh {
        positions: corners.iter().map(|c| [c[0], c[1], z]).collect(),
        normals: vec![[0.0, 0.0, 1.0]; corners.len()],
        colors: vec![color; corners.len()],
        uvs: Vec::new(),
        texture: None,
        indices: (1..n - 1).flat_map(|i| [0, i, i + 1]).collect(),
        normals_computed: false,
    }
}

fn draw(r: &Renderer, size: [u32; 2], instances: &[(MeshId, DitherMask)]) -> Vec<[u8; 4]> {
    let inst: Vec<(MeshId, Mat4)> = instances
        .iter()
        .map(|&(id, _)| (id, Mat4::IDENTITY))
        .collect();
    let dither: Vec<DitherMask> = instances.iter().map(|&(_, m)| m).collect();
    r.render(&RenderRequest {
        width: size[0],
        height: size[1],
        view_proj: Mat4::IDENTITY,
        instances: &inst,
        dither: &dither,
        albedo: &[],
        lighting: LIGHT,
        background_srgb: BACKGROUND,
    })
    .unwrap()
    .rgba
    .chunks_exact(4)
    .map(|p| [p[0], p[1], p[2], p[3]])
    .collect()
}

fn is_background(p: [u8; 4]) -> bool {
    p[..3] == BACKGROUND
}

#[test]
fn a_half_fade_splits_every_pixel_between_the_two_lods() {
    // A pentagon with slanted edges (edge pixels partly covered under
    // MSAA), the same shape for both LODs, so the plain draw's coverage is
    // what the two masks must share.
    let shape = [
        [-0.8, -0.7],
        [0.6, -0.9],
        [0.9, 0.2],
        [0.1, 0.85],
        [-0.7, 0.4],
    ];
    for samples in [1, 4] {
        let r = renderer(samples);
        let lod = r
            .upload_mesh(&polygon(&shape, 0.5, [0.9, 0.6, 0.3]))
            .unwrap();
        let size = [61, 47];
        let plain = draw(&r, size, &[(lod, DitherMask::ALL)]);
        let fade = 0.5;
        let out = draw(&r, size, &[(lod, DitherMask::fading_out(fade))]);
        let into = draw(&r, size, &[(lod, DitherMask::fading_in(fade))]);
        let both = draw(
            &r,
            size,
            &[
                (lod, DitherMask::fading_out(fade)),
                (lod, DitherMask::fading_in(fade)),
            ],
        );
        let covered = plain.iter().filter(|p| !is_background(**p)).count();
        assert!(covered > 500, "{samples}x: the shape covers {covered} px");
        let (mut from_px, mut to_px) = (0, 0);
        for (k, &p) in plain.iter().enumerate() {
            if is_background(p) {
                assert!(
                    is_background(out[k]) && is_background(into[k]),
                    "{samples}x: pixel {k} drawn outside the shape"
                );
                continue;
            }
            // Exactly one of the two draws covers it, as the plain draw does.
            match (out[k] == p, into[k] == p) {
                (true, false) => assert!(is_background(into[k]), "{samples}x: pixel {k}"),
                (false, true) => assert!(is_background(out[k]), "{samples}x: pixel {k}"),
                other => panic!("{samples}x: pixel {k} covered by (from, to) = {other:?}"),
            }
            from_px += usize::from(out[k] == p);
            to_px += usize::from(into[k] == p);
        }
        assert_eq!(from_px + to_px, covered);
        let share = to_px as f64 / covered as f64;
        assert!(
            (share - 0.5).abs() < 0.05,
            "{samples}x: fading-in share {share}"
        );
        // Drawn together, a fade between two identical LODs is the plain draw.
        assert_eq!(both, plain, "{samples}x");
    }
}

#[test]
fn masks_are_complementary_per_pixel_and_spread_over_each_tile() {
    let r = renderer(4);
    let full = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let red = r
        .upload_mesh(&polygon(&full, 0.5, [1.0, 0.0, 0.0]))
        .unwrap();
    let green = r
        .upload_mesh(&polygon(&full, 0.2, [0.0, 1.0, 0.0]))
        .unwrap();
    let size = [32u32, 24u32];
    for (fade, kept_of_16) in [(0.25, 4), (0.5, 8), (0.8, 13), (1.0 / 16.0, 1)] {
        // The LODs at different depths: without the masks the nearer one
        // (green) would hide the other everywhere.
        let img = draw(
            &r,
            size,
            &[
                (red, DitherMask::fading_out(fade)),
                (green, DitherMask::fading_in(fade)),
            ],
        );
        for ty in 0..size[1] / 4 {
            for tx in 0..size[0] / 4 {
                let mut greens = 0;
                for y in ty * 4..ty * 4 + 4 {
                    for x in tx * 4..tx * 4 + 4 {
                        let p = img[(y * size[0] + x) as usize];
                        match p {
                            [255, 0, 0, 255] => {}
                            [0, 255, 0, 255] => greens += 1,
                            other => panic!("fade {fade}: pixel ({x}, {y}) is {other:?}"),
                        }
                    }
                }
                assert_eq!(greens, kept_of_16, "fade {fade}: tile ({tx}, {ty})");
            }
        }
    }
}

#[test]
fn fades_at_0_and_1_equal_the_plain_draws() {
    let r = renderer(4);
    let coarse = [[-0.6, -0.6], [0.7, -0.5], [0.0, 0.8]];
    let fine = [
        [-0.7, -0.6],
        [0.2, -0.7],
        [0.8, 0.1],
        [0.0, 0.7],
        [-0.6, 0.3],
    ];
    let from = r
        .upload_mesh(&polygon(&coarse, 0.4, [0.2, 0.5, 1.0]))
        .unwrap();
    let to = r
        .upload_mesh(&polygon(&fine, 0.6, [1.0, 0.8, 0.1]))
        .unwrap();
    let size = [40, 36];
    let plain_from = draw(&r, size, &[(from, DitherMask::ALL)]);
    let plain_to = draw(&r, size, &[(to, DitherMask::ALL)]);
    assert_ne!(plain_from, plain_to);
    let at = |fade: f32| {
        draw(
            &r,
            size,
            &[
                (from, DitherMask::fading_out(fade)),
                (to, DitherMask::fading_in(fade)),
            ],
        )
    };
    assert_eq!(at(0.0), plain_from);
    assert_eq!(at(1.0), plain_to);
    let half = at(0.5);
    assert!(half != plain_from && half != plain_to);
}

#[test]
fn a_mask_count_other_than_none_or_one_per_instance_is_an_error() {
    let r = renderer(1);
    let id = r
        .upload_mesh(&polygon(
            &[[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]],
            0.5,
            [1.0; 3],
        ))
        .unwrap();
    let err = r
        .render(&RenderRequest {
            width: 8,
            height: 8,
            view_proj: Mat4::IDENTITY,
            instances: &[(id, Mat4::IDENTITY), (id, Mat4::IDENTITY)],
            dither: &[DitherMask::ALL],
            albedo: &[],
            lighting: LIGHT,
            background_srgb: BACKGROUND,
        })
        .unwrap_err();
    assert!(err.to_string().contains("dither"), "{err}");
}
