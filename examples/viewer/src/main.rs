//! `acuity-viewer`: an interactive viewer that flies through a scene's
//! camera path in real time, looping, under any LOD policy of the scene
//! player, and shows each object's chosen LOD as a colour overlay.
//!
//! ```text
//! cargo run --release -p acuity-viewer -- scenes/default.toml
//! ```
//!
//! Keys: Tab or P next policy, O LOD overlay, `[` / `]` halve / double the
//! scale factor `s`, Space pause, Left / Right one frame while paused, Esc
//! quit. The title shows the policy, `s`, the triangles drawn as a share
//! of full detail and frames per second.
//!
//! Frames are drawn by the scene player's [`acuity_lab::frames::World`]:
//! the same headless wgpu renderer, MSAA and pixels that `acuity run`
//! measures, read back to RGBA and put in the window through softbuffer
//! (scaled nearest-neighbour, letterboxed). So the viewer shows exactly
//! the frames acuity measures, and there is no second GPU path (swap
//! chain, shaders) to keep in sync with it; the cost is a readback and a
//! CPU copy per frame.
//!
//! The pure parts are modules of their own with unit tests: [`args`] (the
//! command line), [`keys`] (key to action), [`present`] (the overlay's
//! colours, pixel packing, letterboxing) and [`clock`] (the looping
//! clock); [`app`] is the window loop. Exit codes follow the `acuity`
//! tool's: 2 for a bad argument or scene ([`acuity_lab::blame`]), 1 for a
//! failure while running (no display included).

mod app;
mod args;
mod clock;
mod keys;
mod present;

use std::process::ExitCode;

use acuity_lab::frames::{LoadOptions, World};
use acuity_lab::scene::{Policy, Scene};
use anyhow::Context;
use winit::event_loop::EventLoop;

use crate::app::{ViewSettings, Viewer};
use crate::args::{Command, Options, USAGE};

fn main() -> ExitCode {
    let result = args::parse(std::env::args_os().skip(1)).and_then(|command| match command {
        Command::Help => {
            println!("{USAGE}");
            Ok(())
        }
        Command::View(options) => view(options),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", acuity_lab::error::error_line(&e));
            ExitCode::from(if acuity_lab::blame::blames_input(&e) {
                2
            } else {
                1
            })
        }
    }
}

/// Loads the scene and its world, opens the window and plays until quit.
fn view(options: Options) -> anyhow::Result<()> {
    let scene = Scene::load(&options.scene)?;
    // Before the profiles, which may take minutes to make: a display to
    // open the window on.
    let event_loop = EventLoop::new().context(
        "cannot open a window: no display could be reached (the viewer needs X11: \
         is DISPLAY set? Wayland sessions need XWayland)",
    )?;
    eprintln!(
        "{}: {} objects; loading their LODs and profiles",
        options.scene.display(),
        scene.objects.len()
    );
    let load = LoadOptions {
        verbose: true,
        settings: scene.profiles.analysis_settings(),
        ..LoadOptions::default()
    };
    let world = World::load(scene, &load)?;
    eprintln!("renderer: {}", world.renderer.adapter_info());
    eprintln!("{}", present::OVERLAY_LEGEND);
    eprintln!(
        "keys: Tab/P policy, O overlay, [ ] halve/double s, Space pause, \
         Left/Right step while paused, Esc quit"
    );
    // Tab and P cycle through every policy, in `Policy::ALL`'s order.
    let first_policy = Policy::ALL
        .iter()
        .position(|&p| p == options.policy)
        .unwrap_or(0);
    let mut viewer = Viewer::new(
        world,
        ViewSettings {
            first_policy,
            policies: Policy::ALL.to_vec(),
            overlay: options.overlay,
            frames: options.frames,
            screenshot: options.screenshot,
        },
    )?;
    let ran = event_loop
        .run_app(&mut viewer)
        .context("the window's event loop failed");
    if let Some(e) = viewer.error.take() {
        return Err(e);
    }
    ran?;
    viewer.write_screenshot()
}
