//! Once warm, the frame loop allocates nothing: with biases, LOD ranges,
//! cross-fades and the change list too, and after objects were removed.
#![allow(unsafe_code)] // A counting global allocator needs it; the library forbids unsafe code.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use acuity::{Camera, Display, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings, Tracker};
use common::{Rng, four_lod_profile, single_lod_profile};
use glam::{DVec3, Quat};

struct Counting;

thread_local! {
    // Per thread: the test harness's own threads allocate too (more so on
    // a loaded machine), and only the selecting thread's count matters.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn warm_frames_allocate_nothing() {
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    let settings = SelectorSettings {
        fade_time_s: 0.1,
        defer_coarsening_s: 0.05,
        ..Default::default()
    };
    let mut sel = Selector::new(display, settings);
    let p = sel.add_profile(&four_lod_profile(1)).unwrap();
    let single = sel.add_profile(&single_lod_profile()).unwrap();
    let mut rng = Rng::new(1);
    let mut ids = Vec::new();
    for i in 0..5000 {
        let id = sel
            .add_object(ObjectDesc {
                center: rng.point(100.0),
                radius: 1.0,
                rotation: Quat::IDENTITY,
                profile: if i % 10 == 0 { single } else { p },
            })
            .unwrap();
        match i % 7 {
            0 => sel.set_bias(id, 2.5).unwrap(),
            1 => sel.set_lod_range(id, 1..=2).unwrap(),
            2 => sel.remove_object(id).unwrap(),
            _ => ids.push(id),
        }
    }
    let mut frame = FrameInput {
        camera: Camera {
            position: DVec3::ZERO,
            orientation: Quat::IDENTITY,
        },
        gaze: Gaze::default(),
        dt_s: 1.0 / 90.0,
        scale: 1.0,
    };
    // Warm up every path once.
    sel.select(&frame).unwrap();
    sel.select_with_diagnostics(&frame).unwrap();
    sel.select_within_budget(&frame, 100_000).unwrap();
    let before = allocations();
    let (mut changes, mut fading) = (0, 0);
    for f in 0..20 {
        frame.camera.orientation = Quat::from_rotation_y(0.02 * f as f32);
        // An eye tracker's gaze that jumps (a saccade) every fifth frame.
        let gaze_x_deg = if f % 10 < 5 { 0.0 } else { 10.0 };
        frame.gaze = Gaze::at_screen_angles(gaze_x_deg, 0.0, Tracker::eye_default());
        sel.select(&frame).unwrap();
        changes += sel.changed().len();
        sel.select_with_diagnostics(&frame).unwrap();
        changes += sel.changed().len();
        sel.select_within_budget(&frame, 100_000).unwrap();
        changes += sel.changed().len();
        fading += sel.fades().len();
    }
    let during = allocations() - before;
    assert_eq!(during, 0, "{during} allocations in 60 warm frames");
    assert!(
        changes > 300 && fading > 100,
        "{changes} changes, {fading} fades"
    );
    assert!(ids.iter().all(|&id| sel.contains(id)));
}

#[test]
fn warm_terrain_refinement_allocates_nothing() {
    use acuity::terrain::{Heightfield, Refinement, Terrain, TerrainSettings, TerrainView};
    use acuity::{Components, EccentricityModel, VelocityModel};
    use glam::Vec3;

    let (w, h) = (65, 49);
    let heights = (0..w * h)
        .map(|n| {
            let (x, y) = ((n % w) as f32, (n / w) as f32);
            20.0 * (0.3 * x).sin() * (0.2 * y).cos() + 5.0 * (1.7 * x + 0.9 * y).sin()
        })
        .collect();
    let terrain = Terrain::new(Heightfield::new(w, h, 10.0, heights).unwrap());
    let settings = TerrainSettings {
        components: Components::ALL,
        viewport_cull: true,
        fov_deg: [200.0, 135.0],
        display_limit_cpd: 3.8,
        scale: 1.0,
        eccentricity_model: EccentricityModel::Reddy2001,
        velocity_model: VelocityModel::Reddy2001,
    };
    let view = |yaw: f32| {
        let at = |yaw: f32| {
            let (s, c) = yaw.to_radians().sin_cos();
            Camera::look_to(
                DVec3::new(300.0, 100.0, 60.0),
                Vec3::new(s, c, -0.3),
                Vec3::Z,
            )
            .unwrap()
        };
        TerrainView {
            camera: at(yaw),
            previous: Some(at(yaw - 3.0)),
            dt_s: 0.1,
        }
    };
    let mut out = Refinement::new();
    let yaws = [0.0, 40.0, -70.0, 150.0];
    for &yaw in &yaws {
        terrain.refine(&view(yaw), &settings, &mut out).unwrap();
    }
    let before = allocations();
    for &yaw in &yaws {
        terrain.refine(&view(yaw), &settings, &mut out).unwrap();
        assert!(out.stats().triangles > 0);
    }
    assert_eq!(allocations() - before, 0);
}
