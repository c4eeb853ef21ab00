//! Selection cost per object: 1e3 to 1e6 objects, 4 LODs, 18 viewpoints,
//! every component on, on the calling thread and on rayon's pool.
//!
//! `cargo bench --bench select`; criterion prints the time per frame and
//! the throughput in objects per second (ns per object = 1000 / Melem/s).

#[path = "../tests/common/mod.rs"]
mod common;

use acuity::{Camera, Display, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings, Tracker};
use common::{Rng, four_lod_profile};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec3, Quat, Vec3};

fn scene(n: usize, parallel: bool) -> Selector {
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    let settings = SelectorSettings {
        parallel_min_objects: if parallel { 0 } else { usize::MAX },
        ..Default::default()
    };
    let mut sel = Selector::new(display, settings);
    let profiles: Vec<_> = (0..8)
        .map(|s| sel.add_profile(&four_lod_profile(s)).unwrap())
        .collect();
    let mut rng = Rng(42);
    for i in 0..n {
        // Objects around the camera, most in front (a fly-through's view).
        let dir = Vec3::new(
            rng.range(-1.2, 1.2) as f32,
            rng.range(-0.8, 0.8) as f32,
            -1.0,
        )
        .normalize();
        let center = dir.as_dvec3() * rng.range(2f64.ln(), 500f64.ln()).exp();
        sel.add_object(ObjectDesc {
            center,
            radius: rng.range(0.3, 2.0) as f32,
            rotation: rng.rotation(),
            profile: profiles[i % profiles.len()],
        })
        .unwrap();
    }
    sel
}

fn bench_select(c: &mut Criterion) {
    let mut group = c.benchmark_group("select");
    for &n in &[1_000usize, 10_000, 100_000, 1_000_000] {
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(20);
        }
        for parallel in [false, true] {
            let mut sel = scene(n, parallel);
            let mut frame = FrameInput {
                camera: Camera {
                    position: DVec3::ZERO,
                    orientation: Quat::IDENTITY,
                },
                gaze: Gaze::at_screen_angles(5.0, -2.0, Tracker::eye_default()),
                dt_s: 1.0 / 90.0,
                scale: 1.0,
            };
            let mut f = 0u32;
            let name = if parallel {
                "parallel"
            } else {
                "single_thread"
            };
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| {
                    f = f.wrapping_add(1);
                    frame.camera.orientation = Quat::from_rotation_y(0.002 * (f % 1000) as f32);
                    frame.camera.position.z = -0.05 * (f % 1000) as f64;
                    sel.select(&frame).unwrap();
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_select);
criterion_main!(benches);
