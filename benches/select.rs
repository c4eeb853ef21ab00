//! Selection cost per object: 1e3 to 1e6 objects, 4 LODs, 18 viewpoints,
//! every component on, on the calling thread (with the CPU's widest vector
//! instructions, with at most AVX2: `_avx2`, and with the build's baseline
//! ones: `_baseline`) and on rayon's pool.
//!
//! Every iteration selects the same fixed cycle of [`POSES`] frames (the
//! camera turns and moves a little between consecutive poses, so retinal
//! velocities are non-zero), so every measurement sees the same workload
//! whatever its speed; the throughput counts `POSES * n` objects. The
//! fraction of objects left after culling over the cycle is printed per
//! scene (about 0.75 with this scene), to read the time per object against.
//!
//! `single_thread_tracked` (1e5 and 1e6 objects) is the widest
//! single-thread case with the change list on, and
//! `single_thread_adjusted` (1e5) with every 100th object biased, every
//! 100th other one with an LOD range and cross-fades on: what those cost.
//!
//! `single_thread_best_effort` and `single_thread_budget_uniform` (1e5 and
//! 1e6) select within a triangle budget of half the triangles the poses
//! draw at `s = 1` ([`Selector::select_within_budget`]), by each
//! [`BudgetRule`]: the loop plus the budget's own work.
//! `single_thread_budgeted_scale` (1e5 and 1e6) selects at `s = 0.5` with
//! [`ScaleRule::Budgeted`]: the triangles that `s` draws, spent best
//! effort (at `s = 1` it is the plain loop). `single_thread_pooled` (1e5
//! and 1e6) selects at `s = 1` with that rule and a visibility budget
//! ([`SelectorSettings::visibility_budget`], the calibrated deg): a budgeted
//! selection every frame. `single_thread_just_imperceptible` (1e5 and
//! 1e6) is [`SelectorSettings::just_imperceptible`] at `s = 1`: the
//! calibrated budget (on this display's field of view) and the steady
//! switch rules, as shipped; `single_thread_just_imperceptible_halved`
//! the same at `s = 0.5` (the triangles that `s` draws spent best effort,
//! then the budget on top: a scheduler's frame).
//!
//! `cargo bench --bench select`; criterion prints the time per cycle and
//! the throughput in objects per second (ns per object = 1000 / Melem/s).

#[path = "../tests/common/mod.rs"]
mod common;

use acuity::{
    BudgetRule, Camera, Display, FrameInput, Gaze, IMPERCEPTIBLE_VISIBILITY_DEG, ObjectDesc,
    ObjectId, ScaleRule, Selector, SelectorSettings, SimdLevel, Tracker, VisibilityBudget,
};
use common::{Rng, four_lod_profile};
use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use glam::{DVec3, Quat, Vec3};

/// Frames per iteration: the camera swings out over 4 steps and back.
const POSES: usize = 8;

/// What a scene turns on besides the default settings.
#[derive(Clone, Copy, PartialEq)]
enum Extras {
    None,
    /// The change list.
    Tracked,
    /// Biases, LOD ranges and cross-fades.
    Adjusted,
    /// Selection within half the triangles drawn at `s = 1`, by a rule.
    Budget(BudgetRule),
    /// Selection at `s = 0.5` spent as a budget.
    BudgetedScale,
    /// Selection at `s = 1` with a visibility budget.
    Pooled,
    /// [`SelectorSettings::just_imperceptible`] at `s = 1`: the calibrated
    /// visibility budget and the steady switch rules.
    JustImperceptible,
    /// [`SelectorSettings::just_imperceptible`] at `s = 0.5`.
    JustImperceptibleHalved,
}

fn scene(n: usize, parallel: bool, simd: SimdLevel, extras: Extras) -> (Selector, Vec<ObjectId>) {
    let adjusted = extras == Extras::Adjusted;
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    let base = if matches!(
        extras,
        Extras::JustImperceptible | Extras::JustImperceptibleHalved
    ) {
        SelectorSettings::just_imperceptible()
    } else {
        SelectorSettings::default()
    };
    let settings = SelectorSettings {
        parallel_min_objects: if parallel { 0 } else { usize::MAX },
        simd,
        track_changes: extras == Extras::Tracked,
        fade_time_s: if adjusted { 0.2 } else { 0.0 },
        budget_rule: match extras {
            Extras::Budget(rule) => rule,
            _ => base.budget_rule,
        },
        scale_rule: if matches!(extras, Extras::BudgetedScale | Extras::Pooled) {
            ScaleRule::Budgeted
        } else {
            base.scale_rule
        },
        visibility_budget: if extras == Extras::Pooled {
            VisibilityBudget::Deg(IMPERCEPTIBLE_VISIBILITY_DEG)
        } else {
            base.visibility_budget
        },
        ..base
    };
    let mut sel = Selector::new(display, settings);
    let profiles: Vec<_> = (0..8)
        .map(|s| sel.add_profile(&four_lod_profile(s)).unwrap())
        .collect();
    let mut rng = Rng::new(42);
    let ids = (0..n)
        .map(|i| {
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
            .unwrap()
        })
        .collect::<Vec<_>>();
    if adjusted {
        for (i, &id) in ids.iter().enumerate() {
            match i % 100 {
                0 => sel.set_bias(id, 2.0).unwrap(),
                50 => sel.set_lod_range(id, 1..=2).unwrap(),
                _ => {}
            }
        }
    }
    (sel, ids)
}

/// The frames of one cycle: 0.002 rad of yaw and 0.05 units of travel per
/// step, out to 4 steps and back.
fn poses() -> [FrameInput; POSES] {
    std::array::from_fn(|k| {
        let step = [0, 1, 2, 3, 4, 3, 2, 1][k] as f32;
        FrameInput {
            camera: Camera {
                position: DVec3::new(0.0, 0.0, -0.05 * step as f64),
                orientation: Quat::from_rotation_y(0.002 * step),
            },
            gaze: Gaze::at_screen_angles(5.0, -2.0, Tracker::eye_default()),
            dt_s: 1.0 / 90.0,
            scale: 1.0,
        }
    })
}

fn bench_select(c: &mut Criterion) {
    let mut group = c.benchmark_group("select");
    let frames = poses();
    for &n in &[1_000usize, 10_000, 100_000, 1_000_000] {
        group.throughput(Throughput::Elements((POSES * n) as u64));
        if n >= 100_000 {
            group.sample_size(10);
            group.sampling_mode(SamplingMode::Flat);
        }
        for (name, parallel, simd, extras) in [
            ("single_thread", false, SimdLevel::Widest, Extras::None),
            (
                "single_thread_tracked",
                false,
                SimdLevel::Widest,
                Extras::Tracked,
            ),
            (
                "single_thread_adjusted",
                false,
                SimdLevel::Widest,
                Extras::Adjusted,
            ),
            ("single_thread_avx2", false, SimdLevel::Avx2, Extras::None),
            (
                "single_thread_baseline",
                false,
                SimdLevel::Baseline,
                Extras::None,
            ),
            ("parallel", true, SimdLevel::Widest, Extras::None),
            (
                "single_thread_best_effort",
                false,
                SimdLevel::Widest,
                Extras::Budget(BudgetRule::BestEffort),
            ),
            (
                "single_thread_best_effort_unweighted",
                false,
                SimdLevel::Widest,
                Extras::Budget(BudgetRule::BestEffortUnweighted),
            ),
            (
                "single_thread_budget_uniform",
                false,
                SimdLevel::Widest,
                Extras::Budget(BudgetRule::UniformScale),
            ),
            (
                "single_thread_budgeted_scale",
                false,
                SimdLevel::Widest,
                Extras::BudgetedScale,
            ),
            (
                "single_thread_pooled",
                false,
                SimdLevel::Widest,
                Extras::Pooled,
            ),
            (
                "single_thread_just_imperceptible",
                false,
                SimdLevel::Widest,
                Extras::JustImperceptible,
            ),
            (
                "single_thread_just_imperceptible_halved",
                false,
                SimdLevel::Widest,
                Extras::JustImperceptibleHalved,
            ),
        ] {
            let wanted = match extras {
                Extras::None => true,
                Extras::Tracked
                | Extras::Budget(_)
                | Extras::BudgetedScale
                | Extras::Pooled
                | Extras::JustImperceptible
                | Extras::JustImperceptibleHalved => n >= 100_000,
                Extras::Adjusted => n == 100_000,
            };
            if !wanted {
                continue;
            }
            let (mut sel, ids) = scene(n, parallel, simd, extras);
            let mut visible = 0;
            let mut triangles = 0;
            for frame in &frames {
                sel.select(frame).unwrap();
                triangles += sel.triangles();
                visible += ids
                    .iter()
                    .filter(|&&id| !sel.selection(id).is_culled())
                    .count();
            }
            eprintln!(
                "{name}/{n}: visible fraction {:.3}",
                visible as f64 / (POSES * n) as f64
            );
            let budget = triangles / (2 * POSES as u64);
            let halved = frames.map(|f| FrameInput { scale: 0.5, ..f });
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| match extras {
                    Extras::Budget(_) => {
                        for frame in &frames {
                            sel.select_within_budget(frame, budget).unwrap();
                        }
                    }
                    Extras::BudgetedScale | Extras::JustImperceptibleHalved => {
                        for frame in &halved {
                            sel.select(frame).unwrap();
                        }
                    }
                    _ => {
                        for frame in &frames {
                            sel.select(frame).unwrap();
                        }
                    }
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_select);
criterion_main!(benches);
