//! The per-object cost of one frame's selection, side by side: the Rust
//! API, the C API called from Rust, and `examples/c/bench.c` compiled with
//! `cc -O2` against the static library, on one scene (that of
//! `benches/select.rs`: 1e5 objects, 8 profiles of 4 LODs, 18 viewpoints
//! and 6 size rungs each, from one splitmix64 generator in both
//! languages). Ignored by default; run it optimised:
//!
//! ```text
//! cargo test --release -p acuity-capi --test bench -- --ignored --nocapture
//! ```
//!
//! `ACUITY_BENCH_OBJECTS` and `ACUITY_BENCH_CYCLES` change the size (1e5)
//! and the number of timed cycles of 8 frames (50). The three runs must
//! draw the same triangles (the same workload), or the test fails.

mod common;

use std::process::Command;
use std::time::Instant;

use acuity::glam::{DVec3, Quat, Vec3};
use acuity::profile::{Feature, PROFILE_FORMAT_VERSION, Profile, TransitionFeatures};
use acuity::{Camera, Display, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings, Tracker};
use acuity_capi::*;
use common::{build_c, c_compiler};

const POSES: usize = 8;

/// splitmix64, as in `bench.c`.
struct SplitMix(u64);

impl SplitMix {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// A 4-LOD profile over the 18 viewpoints of a once-subdivided octahedron
/// and the offline pass's default size ladder, two features a transition
/// (as `tests/common`'s `four_lod_profile` of the root crate).
fn synthetic_profile(seed: u64) -> Profile {
    let mut rng = SplitMix(seed);
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut viewpoints: Vec<Vec3> = axes.to_vec();
    for (i, a) in axes.iter().enumerate() {
        for b in &axes[i + 1..] {
            if a.dot(*b) == 0.0 {
                viewpoints.push((*a + *b).normalize());
            }
        }
    }
    let rungs = vec![16.0, 32.0, 64.0, 128.0, 256.0, 512.0];
    let mut transitions = Vec::new();
    for _ in 0..viewpoints.len() * rungs.len() {
        for t in 0..3 {
            let features = if rng.unit() < 0.05 {
                vec![]
            } else {
                let f = (240.0 / (1 << (2 * t)) as f64 * rng.range(0.6, 1.6)) as f32;
                vec![
                    Feature {
                        freq_cdiam: 0.5 * f,
                        area_diam2: 0.02,
                        luminance: [0.4, 0.42],
                        masker: [0.4, 0.42],
                        count: 1,
                    },
                    Feature {
                        freq_cdiam: f,
                        area_diam2: 0.002,
                        luminance: [0.0, 0.5],
                        masker: [0.0, 0.5],
                        count: 1,
                    },
                ]
            };
            transitions.push(TransitionFeatures {
                feature_count: features.len() as u32,
                features,
            });
        }
    }
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: format!("synthetic-{seed}"),
        lod_triangles: vec![3928, 834, 254, 76],
        bounding_radius: 1.0,
        viewpoints: viewpoints.iter().map(|v| v.to_array()).collect(),
        rung_diameters_px: rungs,
        transitions,
        settings: Default::default(),
        inputs: vec![],
    }
}

/// The objects of `bench.c`, in its order.
fn objects(n: usize, profiles: usize) -> Vec<(DVec3, Quat, f32, usize)> {
    let mut rng = SplitMix(42);
    (0..n)
        .map(|i| {
            let (dx, dy, dz) = (rng.range(-1.2, 1.2), rng.range(-0.8, 0.8), -1.0f64);
            let len = (dx * dx + dy * dy + dz * dz).sqrt();
            let distance = rng.range(2f64.ln(), 500f64.ln()).exp();
            let angle = rng.range(0.0, 2.0 * std::f64::consts::PI);
            let center = DVec3::new(
                dx / len * distance,
                dy / len * distance,
                dz / len * distance,
            );
            let rotation = Quat::from_xyzw(
                0.0,
                (0.5 * angle).sin() as f32,
                0.0,
                (0.5 * angle).cos() as f32,
            );
            let radius = rng.range(0.3, 2.0) as f32;
            (center, rotation, radius, i % profiles)
        })
        .collect()
}

/// The 8 frames of `bench.c`.
fn frames() -> [FrameInput; POSES] {
    let (gx, gy) = (5f64.to_radians().tan(), (-2f64).to_radians().tan());
    let glen = (gx * gx + gy * gy + 1.0).sqrt();
    std::array::from_fn(|k| {
        let step = [0, 1, 2, 3, 4, 3, 2, 1][k] as f64;
        let half = 0.5 * 0.002 * step;
        FrameInput {
            camera: Camera {
                position: DVec3::new(0.0, 0.0, -0.05 * step),
                orientation: Quat::from_xyzw(0.0, half.sin() as f32, 0.0, half.cos() as f32),
            },
            gaze: Gaze {
                direction_camera: Vec3::new(
                    (gx / glen) as f32,
                    (gy / glen) as f32,
                    (-1.0 / glen) as f32,
                ),
                tracker: Tracker::Eye { error_deg: 1.0 },
                pursued: None,
            },
            dt_s: 1.0 / 90.0,
            scale: 1.0,
        }
    })
}

/// Runs `cycles` timed cycles after one warm-up cycle; returns the median
/// and fastest ns per object and frame, and the warm-up's triangles.
/// `cycle(true)` counts triangles (outside the timing, as `bench.c` does),
/// `cycle(false)` only selects.
fn time(objects: usize, cycles: usize, mut cycle: impl FnMut(bool) -> u64) -> (f64, f64, u64) {
    let triangles = cycle(true);
    let mut ns: Vec<f64> = (0..cycles)
        .map(|_| {
            let start = Instant::now();
            cycle(false);
            start.elapsed().as_nanos() as f64 / (POSES * objects) as f64
        })
        .collect();
    ns.sort_by(f64::total_cmp);
    (ns[cycles / 2], ns[0], triangles)
}

fn env_count(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
#[ignore = "a benchmark: cargo test --release -p acuity-capi --test bench -- --ignored --nocapture"]
fn select_cost_rust_and_c() {
    let n = env_count("ACUITY_BENCH_OBJECTS", 100_000);
    let cycles = env_count("ACUITY_BENCH_CYCLES", 50).max(1);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench");
    std::fs::create_dir_all(&dir).unwrap();
    let profiles: Vec<Profile> = (0..8).map(synthetic_profile).collect();
    let paths: Vec<_> = profiles
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let path = dir.join(format!("synthetic-{i}.acp"));
            p.save(&path).unwrap();
            path
        })
        .collect();
    let scene = objects(n, profiles.len());
    let frames = frames();

    // 1. The Rust API.
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    let mut sel = Selector::new(display, SelectorSettings::default());
    let ids: Vec<_> = profiles
        .iter()
        .map(|p| sel.add_profile(p).unwrap())
        .collect();
    for &(center, rotation, radius, p) in &scene {
        sel.add_object(ObjectDesc {
            center,
            radius,
            rotation,
            profile: ids[p],
        })
        .unwrap();
    }
    let rust = time(n, cycles, |count| {
        frames
            .iter()
            .map(|f| {
                sel.select(f).unwrap();
                if count { sel.triangles() } else { 0 }
            })
            .sum()
    });
    drop(sel);

    // 2. The C API, called from Rust.
    let capi = {
        let d = AcuityDisplay {
            width_px: 1920,
            height_px: 1080,
            fov_x_deg: 90.0,
            fov_y_deg: 58.7,
        };
        let c_frames: Vec<AcuityFrame> = frames
            .iter()
            .map(|f| {
                let (p, q, g) = (
                    f.camera.position,
                    f.camera.orientation,
                    f.gaze.direction_camera,
                );
                AcuityFrame {
                    camera_position: AcuityVec3d {
                        x: p.x,
                        y: p.y,
                        z: p.z,
                    },
                    camera_orientation: AcuityQuat {
                        x: q.x,
                        y: q.y,
                        z: q.z,
                        w: q.w,
                    },
                    pursued: ACUITY_NO_OBJECT,
                    gaze_direction: AcuityVec3f {
                        x: g.x,
                        y: g.y,
                        z: g.z,
                    },
                    tracker: ACUITY_TRACKER_EYE,
                    tracker_error_deg: 1.0,
                    dt_s: f.dt_s,
                }
            })
            .collect();
        let mut s = std::ptr::null_mut();
        let ok = AcuityStatus::ACUITY_OK;
        // SAFETY: live structs, selector and out-pointers throughout; the
        // selector is freed once, at the end.
        unsafe {
            assert_eq!(acuity_selector_new(&d, std::ptr::null(), &mut s), ok);
            for path in &paths {
                let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
                let mut p = std::ptr::null_mut();
                assert_eq!(acuity_profile_load(c.as_ptr(), &mut p), ok);
                let mut index = 0;
                assert_eq!(acuity_selector_add_profile(s, p, &mut index), ok);
                acuity_profile_free(p);
            }
            for &(c, q, radius, p) in &scene {
                let desc = AcuityObjectDesc {
                    center: AcuityVec3d {
                        x: c.x,
                        y: c.y,
                        z: c.z,
                    },
                    rotation: AcuityQuat {
                        x: q.x,
                        y: q.y,
                        z: q.z,
                        w: q.w,
                    },
                    radius,
                    profile: p as u32,
                };
                let mut h = 0;
                assert_eq!(acuity_selector_add_object(s, &desc, &mut h), ok);
            }
            let result = time(n, cycles, |count| {
                c_frames
                    .iter()
                    .map(|f| {
                        assert_eq!(acuity_selector_select(s, f), ok);
                        let mut stats = AcuityStats::default();
                        if count {
                            assert_eq!(acuity_selector_stats(s, &mut stats), ok);
                        }
                        stats.triangles
                    })
                    .sum()
            });
            acuity_selector_free(s);
            result
        }
    };

    // 3. bench.c, compiled with cc -O2.
    let c = c_compiler().map(|cc| {
        let exe = build_c(&cc, "bench.c", &dir);
        let run = Command::new(&exe)
            .args(["--bench", &cycles.to_string(), "--objects", &n.to_string()])
            .args(&paths)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
        assert!(
            run.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let number = |key: &str| -> f64 {
            let at = stdout
                .find(key)
                .unwrap_or_else(|| panic!("no `{key}` in {stdout}"))
                + key.len();
            stdout[at..]
                .split_whitespace()
                .next()
                .unwrap()
                .trim_end_matches(',')
                .parse()
                .unwrap()
        };
        (
            number("median "),
            number("min "),
            number("triangles ") as u64,
        )
    });

    let profile = if cfg!(debug_assertions) {
        "debug (use --release)"
    } else {
        "release"
    };
    println!("\nselect, {n} objects x {POSES} frames, {cycles} cycles, {profile} build:");
    println!("| caller | median ns/object | fastest ns/object |");
    println!("|---|---|---|");
    println!(
        "| Rust API (`Selector::select`) | {:.2} | {:.2} |",
        rust.0, rust.1
    );
    println!(
        "| C API from Rust (`acuity_selector_select`) | {:.2} | {:.2} |",
        capi.0, capi.1
    );
    if let Some(c) = c {
        println!(
            "| C (`examples/c/bench.c`, cc -O2) | {:.2} | {:.2} |",
            c.0, c.1
        );
        assert_eq!(
            c.2, rust.2,
            "C and Rust drew different triangles: not the same scene"
        );
    }
    assert_eq!(capi.2, rust.2, "the C API drew different triangles");
}
