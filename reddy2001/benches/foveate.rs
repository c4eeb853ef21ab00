//! The acuity image filter on a 3840x2160 RGB image (the generated test
//! image, linear light), gaze at the centre, 150x100 deg, at rest and at
//! 50 deg/s; on rayon's pool (set `RAYON_NUM_THREADS` to pin the cores).
//!
//! `cargo bench -p acuity-reddy2001 --bench foveate`.

use acuity_reddy2001::blur::test_image;
use acuity_reddy2001::foveate::{View, foveate};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let image = test_image(3840, 2160);
    let still = View::reddy([150.0, 100.0], [1920.0, 1080.0]);
    let moving = View {
        velocity_deg_per_s: 50.0,
        ..still
    };
    let mut group = c.benchmark_group("foveate_3840x2160");
    group.sample_size(10);
    group.bench_function("eccentricity", |b| {
        b.iter(|| foveate(&image, &still).unwrap())
    });
    group.bench_function("eccentricity_velocity_50", |b| {
        b.iter(|| foveate(&image, &moving).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
