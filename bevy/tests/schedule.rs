//! The scale `s` and the fixed-frame-rate schedulers, driven by the frame
//! time Bevy measures (here a manual clock): slow frames lower `s` and
//! coarsen LODs; switched off, `s` is the settings' fixed value.

mod common;

use std::time::Duration;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_acuity::{AcuityScheduler, AcuitySettings, AcuityStats};
use common::*;

/// Frames of `frame_s` each; the stats after the last.
fn run(app: &mut App, frame_s: f64, frames: usize) -> AcuityStats {
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        frame_s,
    )));
    for _ in 0..frames {
        app.update();
    }
    *app.world().resource::<AcuityStats>()
}

#[test]
fn a_fixed_scale_is_used_while_the_scheduler_is_off() {
    let mut app = app(0.0);
    spawn_camera(&mut app, 6.0);
    let profile = add_profile(&mut app);
    let (entity, _) = spawn_group(&mut app, profile, Vec3::ZERO);
    let at_one = run(&mut app, FRAME_S, 3);
    assert_eq!(at_one.scale, 1.0);
    let fine = lod(&app, entity).unwrap();
    app.world_mut().resource_mut::<AcuitySettings>().scale = 0.2;
    let low = run(&mut app, FRAME_S, 3);
    assert_eq!(low.scale, 0.2);
    let coarse = lod(&app, entity).unwrap();
    assert!(
        coarse > fine,
        "s = 0.2 drops detail: {coarse} against {fine}"
    );
    assert!(low.triangles < at_one.triangles);
}

#[test]
fn the_reactive_scheduler_lowers_s_when_frames_run_long_and_can_be_switched_off() {
    let mut app = app(0.0);
    spawn_camera(&mut app, 6.0);
    let profile = add_profile(&mut app);
    let (entity, _) = spawn_group(&mut app, profile, Vec3::ZERO);
    run(&mut app, FRAME_S, 2);
    let fine = lod(&app, entity).unwrap();
    app.insert_resource(AcuityScheduler::reactive(60.0).expect("a valid rate"));
    // Frames of 50 ms against a 60 Hz target.
    let slow = run(&mut app, 0.05, 120);
    assert!(slow.scale < 0.5, "{slow:?}");
    assert!(lod(&app, entity).unwrap() > fine);
    app.insert_resource(AcuityScheduler::Off);
    let off = run(&mut app, 0.05, 2);
    assert_eq!(off.scale, 1.0);
    assert_eq!(lod(&app, entity), Some(fine));
}

#[test]
fn the_predictive_scheduler_budgets_triangles_from_the_frame_time() {
    let mut app = app(0.0);
    spawn_camera(&mut app, 30.0);
    let profile = add_profile(&mut app);
    for i in 0..20 {
        spawn_group(
            &mut app,
            profile.clone(),
            Vec3::new(i as f32 - 10.0, 0.0, 20.0),
        );
    }
    let free = run(&mut app, FRAME_S, 2);
    app.insert_resource(AcuityScheduler::predictive(60.0).expect("a valid rate"));
    let slow = run(&mut app, 0.05, 60);
    let budget = slow.budget.expect("a budget");
    assert!(slow.triangles <= budget.max(20 * 60), "{slow:?}");
    assert!(slow.triangles < free.triangles, "{slow:?} against {free:?}");
}
