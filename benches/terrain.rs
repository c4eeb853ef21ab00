//! Terrain refinement per frame: a 661x847 heightfield (Reddy 2001's
//! size) of seeded rough relief, refined for one view under each of Table
//! 1's criteria with viewport culling, 200x135 deg field of view, display
//! limit 3.8 c/deg. Each iteration refines the same view (walk and
//! crack-free triangulation) into a reused [`Refinement`].
//!
//! `cargo bench --bench terrain`.

use acuity::terrain::{Heightfield, Refinement, Terrain, TerrainSettings, TerrainView};
use acuity::{Camera, Components, EccentricityModel, VelocityModel};
use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DVec3, Vec3};

/// Sums of seeded sines: relief of a few hundred metres at 30 m spacing.
fn heightfield() -> Heightfield {
    let (w, h) = (661usize, 847usize);
    let mut heights = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f32, j as f32);
            let mut z = 0.0;
            let mut amp = 400.0;
            let mut f = 1.0 / 200.0;
            for k in 0..9 {
                let phase = k as f32 * 1.7;
                z += amp * ((x * f + phase).sin() * (y * f * 1.3 - phase).cos());
                amp *= 0.5;
                f *= 2.03;
            }
            heights.push(z);
        }
    }
    Heightfield::new(w, h, 30.0, heights).unwrap()
}

fn bench(c: &mut Criterion) {
    let terrain = Terrain::new(heightfield());
    let at = |yaw: f32| {
        let (s, co) = yaw.to_radians().sin_cos();
        Camera::look_to(
            DVec3::new(9900.0, 3000.0, 900.0),
            Vec3::new(s, co, -0.3),
            Vec3::Z,
        )
        .unwrap()
    };
    let view = TerrainView {
        camera: at(10.0),
        previous: Some(at(5.0)),
        dt_s: 0.1,
    };
    let mut group = c.benchmark_group("terrain_refine_661x847");
    group.sample_size(20);
    let rows = [
        ("cull", Components::NONE),
        (
            "size",
            Components {
                size: true,
                eccentricity: false,
                velocity: false,
            },
        ),
        (
            "size_periph",
            Components {
                size: true,
                eccentricity: true,
                velocity: false,
            },
        ),
        ("all", Components::ALL),
    ];
    for (name, components) in rows {
        let settings = TerrainSettings {
            components,
            viewport_cull: true,
            fov_deg: [200.0, 135.0],
            display_limit_cpd: 3.8,
            scale: 1.0,
            eccentricity_model: EccentricityModel::Reddy2001,
            velocity_model: VelocityModel::Reddy2001,
        };
        let mut out = Refinement::new();
        terrain.refine(&view, &settings, &mut out).unwrap();
        println!("{name}: {} triangles", out.stats().triangles);
        group.bench_function(name, |b| {
            b.iter(|| terrain.refine(&view, &settings, &mut out).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
