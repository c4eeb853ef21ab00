//! A fixed frame rate with the predictive scheduler: each frame, a cost
//! model turns the frame-time aim (90% of the period, less when frames
//! vary) into a triangle budget, held while the frames stay in the dead
//! band; the selector spends it, dropping the least visible detail per
//! triangle first; the frame is "drawn", and its measured time refines the
//! cost model.
//!
//! The renderer here is simulated: a frame costs 1 ms plus 40 ns per
//! triangle, and from frame 60 to 120 something else slows drawing to
//! 80 ns per triangle (a heavier shader, a busier GPU): the frames right
//! after each change miss or undershoot the 90 Hz target while the cost
//! model learns, then the scheduler holds it again.
//!
//! `cargo run --example fixed_rate`

mod common;

use acuity::glam::{DVec3, Quat};
use acuity::{
    Camera, CostModel, Display, FrameInput, Gaze, ObjectDesc, PredictiveScheduler,
    ReactiveSettings, Selector, SelectorSettings, Tracker,
};
use common::demo_profile;

/// The simulated renderer: the time a frame of `triangles` takes, s.
fn draw(frame: u32, triangles: u64) -> f32 {
    let per_triangle_s = if (60..120).contains(&frame) {
        80e-9
    } else {
        40e-9
    };
    1e-3 + per_triangle_s * triangles as f32
}

fn main() -> std::process::ExitCode {
    common::finish(run())
}

fn run() -> Result<(), acuity::Error> {
    let target_frame_s = 1.0 / 90.0;
    let display = Display::new([1920, 1080], [90.0, 58.7])?;
    let mut selector = Selector::new(display, SelectorSettings::default());
    let profile = selector.add_profile(&demo_profile())?;
    // 2000 objects scattered in front of the viewer, 5 to 80 units away.
    let mut state = 1u64;
    let mut random = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..2000 {
        let distance = 5.0 + 75.0 * random();
        let center = DVec3::new(
            (random() - 0.5) * 1.6 * distance,
            (random() - 0.5) * 0.9 * distance,
            -distance,
        );
        selector.add_object(ObjectDesc {
            center,
            radius: 0.6,
            rotation: Quat::IDENTITY,
            profile,
        })?;
    }
    // A first guess at the costs; the measured frames correct it.
    let mut scheduler = PredictiveScheduler::new(
        ReactiveSettings::for_rate_hz(90.0)?,
        CostModel::new(1e-3, 20e-9),
    );
    let mut over = 0;
    println!("frame   budget  triangles      s  frame ms");
    for frame in 0..180u32 {
        let budget = scheduler.triangle_budget();
        let outcome = selector.select_within_budget(
            &FrameInput {
                camera: Camera {
                    position: DVec3::new(0.0, 0.0, -0.02 * frame as f64),
                    orientation: Quat::IDENTITY,
                },
                gaze: Gaze::screen_centre(Tracker::None),
                dt_s: target_frame_s,
                scale: 1.0,
            },
            budget,
        )?;
        let frame_s = draw(frame, outcome.triangles);
        scheduler.observe(frame_s, outcome.triangles, selector.coarsest_triangles());
        over += (frame_s > target_frame_s) as u32;
        if frame % 10 == 0 || (60..64).contains(&frame) {
            println!(
                "{frame:5} {budget:8} {:10} {:6.3} {:9.2}",
                outcome.triangles,
                outcome.scale,
                frame_s * 1e3
            );
        }
    }
    println!(
        "{over} of 180 frames over the {:.2} ms target",
        target_frame_s * 1e3
    );
    Ok(())
}
