//! Benchmarks: CIELUV conversion + region growing, unique-feature
//! extraction (megapixels/s at 512² and 2048², seeded synthetic images),
//! one 512² render + readback of a ~4000-triangle LOD (and of an empty
//! frame: the part of a frame that is not rasterisation), and the paper's
//! 4-LOD object at 18 viewpoints end to end.

use std::hint::black_box;

use rand::{RngExt, SeedableRng};
use rand_xorshift::XorShiftRng;

use acuity_preprocess::features::{FeatureSettings, unique_features};
use acuity_preprocess::lods::{PAPER_TRIANGLE_TARGETS, ProceduralParams, procedural_object};
use acuity_preprocess::render::Lighting;
use acuity_preprocess::segment::{grow_regions, rgba_to_luv};
use acuity_preprocess::views::camera_for;
use acuity_preprocess::{
    AnalysisSettings, ObjectSource, RenderRequest, Renderer, RendererOptions, RunOptions, analyse,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Mat4;

/// A seeded, render-like RGBA image: a background with smoothly shaded
/// discs of many sizes; `shift` moves the discs a little (a second LOD).
fn image(n: u32, seed: u64, shift: f32) -> Vec<u8> {
    let mut rng = XorShiftRng::seed_from_u64(seed);
    let mut rnd = || rng.random::<f32>();
    let discs: Vec<[f32; 6]> = (0..64)
        .map(|_| {
            [
                rnd() * n as f32,
                rnd() * n as f32,
                (0.01 + 0.1 * rnd()) * n as f32,
                rnd(),
                rnd(),
                rnd(),
            ]
        })
        .collect();
    let mut out = vec![0u8; (n * n * 4) as usize];
    for y in 0..n {
        for x in 0..n {
            let mut c = [10.0f32, 10.0, 10.0];
            for d in &discs {
                let r = (x as f32 - d[0] - shift).hypot(y as f32 - d[1]);
                if r < d[2] {
                    let shade = 0.4 + 0.6 * (1.0 - r / d[2]);
                    c = [
                        d[3] * 255.0 * shade,
                        d[4] * 255.0 * shade,
                        d[5] * 255.0 * shade,
                    ];
                }
            }
            let i = ((y * n + x) * 4) as usize;
            out[i..i + 4].copy_from_slice(&[c[0] as u8, c[1] as u8, c[2] as u8, 255]);
        }
    }
    out
}

fn segmentation(c: &mut Criterion) {
    let mut g = c.benchmark_group("segment");
    for n in [512u32, 2048] {
        let a = image(n, 1, 0.0);
        let b = image(n, 1, 1.5);
        g.throughput(Throughput::Elements(u64::from(n * n)));
        g.bench_function(format!("luv+grow_{n}"), |bench| {
            bench.iter(|| grow_regions(&rgba_to_luv(n, n, black_box(&a)).unwrap(), 2.3).count)
        });
        let (la, lb) = (
            rgba_to_luv(n, n, &a).unwrap(),
            rgba_to_luv(n, n, &b).unwrap(),
        );
        // The two halves of `luv+grow` alone.
        g.bench_function(format!("luv_{n}"), |bench| {
            bench.iter(|| rgba_to_luv(n, n, black_box(&a)).unwrap().luv.len())
        });
        g.bench_function(format!("grow_{n}"), |bench| {
            bench.iter(|| grow_regions(black_box(&la), 2.3).count)
        });
        // The transition's part: features grouped by the sign of the change.
        let settings = FeatureSettings {
            grouping: Default::default(),
            threshold_delta_e: 2.3,
            min_change_delta_e: 1.0,
            feret_directions: 8,
            statistic: Default::default(),
        };
        g.bench_function(format!("unique_features_{n}"), |bench| {
            bench.iter(|| {
                unique_features(black_box(&la), black_box(&lb), None, &settings)
                    .unwrap()
                    .0
                    .len()
            })
        });
    }
    g.finish();
}

fn rendering(c: &mut Criterion) {
    let r = Renderer::new(&RendererOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("adapter: {}", r.adapter_info());
    let m = procedural_object(ProceduralParams {
        triangles: 3928,
        seed: 1,
    });
    let (centre, radius) = m.bounding_sphere();
    let cam = camera_for([0.3, 0.8, 0.5], centre, radius, 512);
    let id = r.upload_mesh(&m).unwrap();
    let mut g = c.benchmark_group("render");
    g.sample_size(20);
    // The fixed part of a frame: clear, submit, wait, readback of 512².
    g.bench_function("clear+readback_512_empty", |bench| {
        bench.iter(|| {
            r.render(&RenderRequest {
                width: 512,
                height: 512,
                view_proj: cam.view_proj,
                instances: &[],
                dither: &[],
                albedo: &[],
                lighting: Lighting::default(),
                background_srgb: [0; 3],
            })
            .unwrap()
            .rgba
            .len()
        })
    });
    g.bench_function("render+readback_512_3944tri", |bench| {
        bench.iter(|| {
            r.render(&RenderRequest {
                width: 512,
                height: 512,
                view_proj: cam.view_proj,
                instances: &[(id, Mat4::IDENTITY)],
                dither: &[],
                albedo: &[],
                lighting: Lighting::default(),
                background_srgb: [0; 3],
            })
            .unwrap()
            .rgba
            .len()
        })
    });
    let object = ObjectSource::Procedural {
        name: "paper".into(),
        params: ProceduralParams {
            triangles: 3928,
            seed: 1,
        },
        triangle_targets: PAPER_TRIANGLE_TARGETS.to_vec(),
    };
    g.sample_size(10);
    g.bench_function("paper_object_4lod_18views_512", |bench| {
        bench.iter(|| {
            analyse(
                &r,
                &object,
                &AnalysisSettings::default(),
                &RunOptions::default(),
            )
            .unwrap()
            .transitions
            .len()
        })
    });
    g.finish();
}

criterion_group!(benches, segmentation, rendering);
criterion_main!(benches);
