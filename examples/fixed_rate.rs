//! A fixed frame rate, held by each of acuity's two schedulers in turn.
//!
//! - The reactive scheduler with [`SelectorSettings::just_imperceptible`]:
//!   it turns `s` from the measured frame times and the selector spends
//!   `s` as a budget, the visibility an image hides on top (the lab's
//!   best image at equal frame time: `docs/framerate.md`).
//! - The predictive scheduler: each frame, a cost model turns the
//!   frame-time aim into a triangle budget, and the selector spends it,
//!   dropping the least visible detail per triangle first. An engine that
//!   knows of a load before its frame (a shader to compile, a chunk to
//!   stream) can announce it to this one.
//!
//! Both aim at 90% of the period (less when frames vary) and hold their
//! knob while the frames stay in a dead band below the aim; the frame is
//! "drawn", and its measured time feeds the scheduler.
//!
//! The renderer here is simulated: a frame costs 1 ms plus 40 ns per
//! triangle, and from frame 60 to 120 something else slows drawing to
//! 80 ns per triangle (a heavier shader, a busier GPU): the frames right
//! after each change miss or undershoot the 90 Hz target while the
//! scheduler learns, then it holds the rate again.
//!
//! `cargo run --example fixed_rate`

mod common;

use acuity::glam::{DVec3, Quat};
use acuity::{
    Camera, CostModel, Display, FrameInput, Gaze, ObjectDesc, PredictiveScheduler,
    ReactiveScheduler, ReactiveSettings, Selector, SelectorSettings, Tracker,
};
use common::demo_profile;

const TARGET_FRAME_S: f32 = 1.0 / 90.0;

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
    // A first guess at the costs; the measured frames correct it.
    let guess = CostModel::new(1e-3, 20e-9);
    let settings = ReactiveSettings::for_rate_hz(90.0)?;

    println!("reactive scheduler, just-imperceptible settings");
    let mut selector = scene(SelectorSettings::just_imperceptible())?;
    let mut scheduler = ReactiveScheduler::new(settings)
        .with_cost_model(guess)
        .starting_at(settings.min_scale);
    fly(&mut selector, |selector, frame, input| {
        let scale = scheduler.scale();
        selector.select(&FrameInput { scale, ..input })?;
        let triangles = selector.triangles();
        let frame_s = draw(frame, triangles);
        scheduler.observe(frame_s, triangles, selector.coarsest_triangles());
        Ok((triangles, scale, frame_s))
    })?;

    println!("\npredictive scheduler, a triangle budget");
    let mut selector = scene(SelectorSettings::default())?;
    let mut scheduler = PredictiveScheduler::new(settings, guess);
    fly(&mut selector, |selector, frame, input| {
        let outcome = selector.select_within_budget(&input, scheduler.triangle_budget())?;
        let frame_s = draw(frame, outcome.triangles);
        scheduler.observe(frame_s, outcome.triangles, selector.coarsest_triangles());
        Ok((outcome.triangles, outcome.scale, frame_s))
    })
}

/// 2000 objects scattered in front of the viewer, 5 to 80 units away.
fn scene(settings: SelectorSettings) -> Result<Selector, acuity::Error> {
    let display = Display::new([1920, 1080], [90.0, 58.7])?;
    let mut selector = Selector::new(display, settings);
    let profile = selector.add_profile(&demo_profile())?;
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
    Ok(selector)
}

/// 180 frames flying forward; `frame_step` selects, draws and feeds the
/// scheduler, returning the triangles, the `s` and the frame time (s).
fn fly(
    selector: &mut Selector,
    mut frame_step: impl FnMut(&mut Selector, u32, FrameInput) -> Result<(u64, f32, f32), acuity::Error>,
) -> Result<(), acuity::Error> {
    let mut over = 0;
    println!("frame  triangles      s  frame ms");
    for frame in 0..180u32 {
        let input = FrameInput {
            camera: Camera {
                position: DVec3::new(0.0, 0.0, -0.02 * frame as f64),
                orientation: Quat::IDENTITY,
            },
            gaze: Gaze::screen_centre(Tracker::None),
            dt_s: TARGET_FRAME_S,
            scale: 1.0,
        };
        let (triangles, scale, frame_s) = frame_step(selector, frame, input)?;
        over += (frame_s > TARGET_FRAME_S) as u32;
        if frame % 10 == 0 || (60..64).contains(&frame) {
            println!("{frame:5} {triangles:10} {scale:6.3} {:9.2}", frame_s * 1e3);
        }
    }
    println!(
        "{over} of 180 frames over the {:.2} ms target",
        TARGET_FRAME_S * 1e3
    );
    Ok(())
}
