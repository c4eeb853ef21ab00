//! `acuity experiment`: the reference experiments of Reddy 1998 §5.
//!
//! Code: `speedup`, `error_curve` (run time against error) and
//! `framerate`, one experiment each; this module holds their shared
//! options and the command.

mod equal_time;
mod error_curve;
mod framerate;
mod interpolate;
mod speedup;

use std::path::{Path, PathBuf};

use anyhow::Context;

pub use error_curve::{
    ErrorArgs, ErrorMeasure, ErrorRow, ErrorSweep, error, local_p999_at_equal_jod,
    triangles_at_equal, triangles_at_equal_error,
};
pub use framerate::{FramerateArgs, FramerateOutcome, framerate};
pub use speedup::{PAPER_COUNTS, SpeedupArgs, SpeedupOutcome, SpeedupTrial, size_share, speedup};

use crate::frames::{ProfileArgs, World};
use crate::scene::Scene;

/// Arguments of `acuity experiment`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct ExperimentArgs {
    /// Which experiment.
    #[cfg_attr(feature = "clap", command(subcommand))]
    pub which: Experiment,
}

/// The experiments.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Subcommand))]
pub enum Experiment {
    /// Speedup of full acuity over full detail versus object count N, and
    /// the size component's share of the LOD reduction (Reddy 1998 §5.1–5.2).
    Speedup(SpeedupArgs),
    /// Run time against error: mean frame time and triangles versus mean
    /// FLIP (and FovVideoVDP JOD with `--metric fvvdp`), for screen size
    /// across its bias and acuity across `s`.
    Error(ErrorArgs),
    /// A fixed-frame-rate loop (VR-style yaw sweep) under load spikes:
    /// frames over budget and `s` over time, with and without each
    /// scheduler.
    Framerate(FramerateArgs),
}

/// Options every experiment shares.
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct CommonArgs {
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept).
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_resolution))]
    pub resolution: Option<[u32; 2]>,
    /// Output folder (default `out/experiment-<name>/`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: Option<PathBuf>,
    /// Write every played frame to `DIR/<policy>_<knob>/NNNN.png` (RGB, as
    /// rendered; knob as in the CSV, full detail is `full_1`, dumped even
    /// when not played), each folder with gaze.csv (frame,x_px,y_px: the
    /// viewer's fixation in pixels, origin top-left, y down: the gaze, or
    /// `[gaze] viewer_object`'s centre), and DIR/display.json (resolution,
    /// fov_deg, fps, photometry, sequences).
    #[cfg_attr(feature = "clap", arg(long, value_name = "DIR"))]
    pub dump_frames: Option<PathBuf>,
    /// Profiles and progress.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub profiles: ProfileArgs,
}

impl CommonArgs {
    fn load(&self, scene_path: &Path) -> anyhow::Result<World> {
        let mut scene = Scene::load(scene_path)?;
        if let Some(r) = self.resolution {
            scene.display.resolution_px = r;
        }
        let options = self.profiles.load_options(&scene.profiles);
        World::load(scene, &options)
    }

    fn out_dir(&self, name: &str) -> anyhow::Result<PathBuf> {
        let out = self
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join(format!("experiment-{name}")));
        std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
        Ok(out)
    }
}
