//! The viewer's window loop: each frame moves the clock, lets the shown
//! policy choose every instance's LOD, renders with the scene player's
//! [`World`] (coloured per LOD when the overlay is on) and presents the
//! frame read back from the renderer through softbuffer.
//!
//! A frame is rendered when the path moves or a key changes what is shown;
//! while paused, redraws (exposure, resizing) present the last frame again.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::Instant;

use acuity_lab::frames::World;
use acuity_lab::gaze::Gaze as GazePath;
use acuity_lab::limits::MIN_SCALE;
use acuity_lab::policy::{PolicyRunner, fit_cost_model};
use acuity_lab::scene::Policy;
use anyhow::Context;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use crate::clock::{LoopClock, Tick};
use crate::keys::{Action, action};
use crate::present::{OVERLAY_PALETTE, letterbox, pack_rgba, start_window_size};

/// How often the window title's numbers are refreshed, seconds.
const TITLE_EVERY_S: f64 = 0.25;

/// What the viewer shows and how it stops.
#[derive(Debug, Clone)]
pub struct ViewSettings {
    /// The policy shown first (its index in `policies`).
    pub first_policy: usize,
    /// The policies Tab and P cycle through.
    pub policies: Vec<Policy>,
    /// Whether the LOD overlay starts on.
    pub overlay: bool,
    /// Quit after this many frames; `None`: run until closed.
    pub frames: Option<u32>,
    /// Where to write the last frame shown on quitting.
    pub screenshot: Option<PathBuf>,
}

/// The window and the surface its pixels are written to.
struct Screen {
    window: Rc<Window>,
    surface: softbuffer::Surface<Rc<Window>, Rc<Window>>,
}

/// The last frame rendered.
struct Shown {
    rgba: Vec<u8>,
    pixels: Vec<u32>,
    triangles: u64,
    full_triangles: u64,
}

/// The viewer's state; run by winit's event loop.
pub struct Viewer {
    world: World,
    gaze: GazePath,
    runners: Vec<PolicyRunner>,
    active: usize,
    overlay: bool,
    scale: f64,
    clock: LoopClock,
    settings: ViewSettings,
    window: Option<Screen>,
    lods: Vec<Option<usize>>,
    shown: Option<Shown>,
    /// Time on the path and selector dt of the next frame, if one is due
    /// beyond the clock's own motion (a key was pressed).
    pending: Option<Tick>,
    /// The runner that chose the last frame: another one's velocity
    /// history is stale, so its first frame uses dt 0.
    chose_last: Option<usize>,
    frames_shown: u32,
    last_frame: Option<Instant>,
    fps: f64,
    title_at: Option<Instant>,
    /// The first error met; the loop stops at it.
    pub error: Option<anyhow::Error>,
}

impl Viewer {
    /// A viewer over a loaded world: one runner per policy.
    pub fn new(world: World, settings: ViewSettings) -> anyhow::Result<Viewer> {
        let run = &world.scene.run;
        let scale = f64::from((run.scale_factor as f32).clamp(MIN_SCALE, 1.0));
        let runners = settings
            .policies
            .iter()
            .map(|&p| {
                let mut r = PolicyRunner::new(&world, p, run.screen_size_bias, fit_cost_model(&[]))
                    .with_context(|| format!("policy {}", p.name()))?;
                r.set_scale(scale);
                Ok(r)
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let clock = LoopClock::new(world.scene.camera.duration_s, run.frame_dt_s);
        Ok(Viewer {
            gaze: world.scene.gaze(),
            chose_last: None,
            runners,
            active: settings.first_policy,
            overlay: settings.overlay,
            scale,
            clock,
            world,
            settings,
            window: None,
            lods: Vec::new(),
            shown: None,
            pending: None,
            frames_shown: 0,
            last_frame: None,
            fps: 0.0,
            title_at: None,
            error: None,
        })
    }

    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let [w, h] = start_window_size(self.world.scene.display.resolution_px);
        let attributes = Window::default_attributes()
            .with_title("acuity viewer")
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Rc::new(
            event_loop
                .create_window(attributes)
                .context("cannot open a window")?,
        );
        let context = softbuffer::Context::new(window.clone())
            .map_err(|e| anyhow::anyhow!("cannot draw into the window: {e}"))?;
        let surface = softbuffer::Surface::new(&context, window.clone())
            .map_err(|e| anyhow::anyhow!("cannot draw into the window: {e}"))?;
        self.window = Some(Screen { window, surface });
        Ok(())
    }

    fn act(&mut self, a: Action, event_loop: &ActiveEventLoop) {
        match a {
            Action::NextPolicy => {
                self.active = (self.active + 1) % self.runners.len();
                self.pending = Some(self.clock.hold());
            }
            Action::ToggleOverlay => {
                self.overlay = !self.overlay;
                self.pending = Some(self.clock.hold());
            }
            Action::HalveScale | Action::DoubleScale => {
                let factor = if a == Action::HalveScale { 0.5 } else { 2.0 };
                self.scale = next_scale(self.scale, factor);
                for r in &mut self.runners {
                    r.set_scale(self.scale);
                }
                self.pending = Some(self.clock.hold());
            }
            Action::TogglePause => {
                self.clock.toggle_pause();
                // Resuming starts timing afresh, not from before the pause.
                self.last_frame = None;
            }
            Action::StepBack | Action::StepForward if self.clock.paused() => {
                let frames = if a == Action::StepBack { -1 } else { 1 };
                self.pending = Some(self.clock.step(frames));
            }
            Action::StepBack | Action::StepForward => {}
            Action::Quit => event_loop.exit(),
        }
        // The title changes with the next frame shown.
        self.title_at = None;
        if let Some(w) = &self.window {
            w.window.request_redraw();
        }
    }

    /// Renders the frame due now, if any.
    fn render(&mut self) -> anyhow::Result<()> {
        let now = Instant::now();
        let since_last_s = self.last_frame.map(|t| now.duration_since(t).as_secs_f64());
        let tick = match self.pending.take() {
            Some(t) => t,
            None if self.clock.paused() && self.shown.is_some() => return Ok(()),
            None => {
                // Frames played one after another: their rate.
                if let Some(dt) = since_last_s.filter(|&dt| dt > 0.0) {
                    self.fps = if self.fps > 0.0 {
                        0.8 * self.fps + 0.2 / dt
                    } else {
                        1.0 / dt
                    };
                }
                self.clock.advance(since_last_s.unwrap_or(0.0))
            }
        };
        self.last_frame = Some(now);
        let world = &self.world;
        // No error metric runs here, so the fixation is the modelled gaze.
        let view = world.view_at(self.frames_shown, tick.t_s, &self.gaze, &self.gaze);
        let dt_s = if self.chose_last == Some(self.active) {
            tick.dt_s
        } else {
            0.0
        };
        self.chose_last = Some(self.active);
        let runner = &mut self.runners[self.active];
        let started = Instant::now();
        runner.choose(world, &view, dt_s as f32, &mut self.lods)?;
        let palette: &[[f32; 3]] = if self.overlay { &OVERLAY_PALETTE } else { &[] };
        let out = world.render_coloured(&view, &self.lods, runner.fades(), palette)?;
        runner.observe(started.elapsed().as_secs_f64(), out.triangles);
        let full_triangles = self
            .world
            .instances
            .iter()
            .zip(&self.lods)
            .filter(|(_, lod)| lod.is_some())
            .map(|(i, _)| u64::from(self.world.objects[i.object].lod_triangles[0]))
            .sum();
        self.shown = Some(Shown {
            pixels: pack_rgba(&out.rgba),
            rgba: out.rgba,
            triangles: out.triangles,
            full_triangles,
        });
        self.frames_shown = self.frames_shown.saturating_add(1);
        Ok(())
    }

    fn present(&mut self) -> anyhow::Result<()> {
        let (Some(w), Some(shown)) = (self.window.as_mut(), self.shown.as_ref()) else {
            return Ok(());
        };
        let size = w.window.inner_size();
        let (Some(width), Some(height)) =
            (NonZeroU32::new(size.width), NonZeroU32::new(size.height))
        else {
            return Ok(());
        };
        let fail = |e: softbuffer::SoftBufferError| anyhow::anyhow!("presenting a frame: {e}");
        w.surface.resize(width, height).map_err(fail)?;
        let mut buffer = w.surface.buffer_mut().map_err(fail)?;
        letterbox(
            &shown.pixels,
            self.world.scene.display.resolution_px,
            &mut buffer,
            [size.width, size.height],
        );
        buffer.present().map_err(fail)?;
        Ok(())
    }

    fn refresh_title(&mut self) {
        let Some(w) = &self.window else { return };
        let share =
            self.shown
                .as_ref()
                .filter(|s| s.full_triangles > 0)
                .map_or(String::from("-"), |s| {
                    format!(
                        "{:.0}%",
                        100.0 * s.triangles as f64 / s.full_triangles as f64
                    )
                });
        let policy = self.runners[self.active].policy();
        let title = format!(
            "acuity viewer: {}, s = {}, {share} of full-detail triangles, {:.1} fps{}{}",
            policy.name(),
            format_scale(self.scale),
            self.fps,
            if self.overlay { ", LOD overlay" } else { "" },
            if self.clock.paused() { ", paused" } else { "" },
        );
        w.window.set_title(&title);
        self.title_at = Some(Instant::now());
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        self.render()?;
        self.present()?;
        let due = self
            .title_at
            .is_none_or(|t| t.elapsed().as_secs_f64() >= TITLE_EVERY_S);
        if due {
            self.refresh_title();
        }
        if self.settings.frames.is_some_and(|n| self.frames_shown >= n) {
            event_loop.exit();
        }
        Ok(())
    }

    /// Writes the last frame shown to the `--screenshot` file, if asked.
    pub fn write_screenshot(&self) -> anyhow::Result<()> {
        let Some(path) = &self.settings.screenshot else {
            return Ok(());
        };
        let shown = self
            .shown
            .as_ref()
            .context("no frame was shown, so there is no screenshot to write")?;
        let [w, h] = self.world.scene.display.resolution_px;
        image::save_buffer(path, &shown.rgba, w, h, image::ExtendedColorType::Rgba8)
            .with_context(|| format!("writing the screenshot {}", path.display()))?;
        eprintln!("screenshot: {}", path.display());
        Ok(())
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        event_loop.set_control_flow(ControlFlow::Poll);
        if let Err(e) = self.open_window(event_loop) {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if let Some(a) = action(&event.logical_key)
                    && (!event.repeat || a.repeats())
                {
                    self.act(a, event_loop);
                }
            }
            WindowEvent::Resized(_) => {
                if let Some(w) = &self.window {
                    w.window.request_redraw();
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        // Playing: a frame after every batch of events. Paused: wait for
        // the next key or exposure.
        let playing = !self.clock.paused() || self.pending.is_some();
        event_loop.set_control_flow(if playing {
            ControlFlow::Poll
        } else {
            ControlFlow::Wait
        });
        if playing && let Some(w) = &self.window {
            w.window.request_redraw();
        }
    }
}

/// The scale factor `s` after multiplying it by `factor`, kept in
/// `[MIN_SCALE, 1]` (the range the runtime selects with).
pub fn next_scale(scale: f64, factor: f64) -> f64 {
    (scale * factor).clamp(f64::from(MIN_SCALE), 1.0)
}

/// `s` for the title: plain for powers of two down to 1/1024, else in
/// scientific notation.
pub fn format_scale(scale: f64) -> String {
    if scale >= 1.0 / 1024.0 {
        format!("{}", (scale * 1e6).round() / 1e6)
    } else {
        format!("{scale:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_halves_and_doubles_within_the_runtime_range() {
        assert_eq!(next_scale(1.0, 2.0), 1.0);
        assert_eq!(next_scale(1.0, 0.5), 0.5);
        assert_eq!(next_scale(0.25, 2.0), 0.5);
        let mut s = 1.0;
        for _ in 0..200 {
            s = next_scale(s, 0.5);
        }
        assert_eq!(s, f64::from(MIN_SCALE));
        assert!(next_scale(s, 2.0) > s);
    }

    #[test]
    fn scales_print_short() {
        assert_eq!(format_scale(1.0), "1");
        assert_eq!(format_scale(0.125), "0.125");
        assert_eq!(format_scale(1.0 / 4096.0), "2.44e-4");
    }
}
