//! `acuity run <scene>`: fly a scene's camera path under each LOD policy,
//! measure every frame, compare sampled frames with full detail by FLIP,
//! and write a table, a per-frame CSV, plots and side-by-side images;
//! optionally dump every frame and score the dump with FovVideoVDP
//! ([`crate::dump`]).
//!
//! This module is the command: its arguments, loading the scene with the
//! overrides, and writing the outputs. The frames are played by
//! [`crate::player`] and summarised and written by [`crate::report`].

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;

use crate::dump::Metric;
use crate::frames::{ProfileArgs, World};
use crate::player::{PlaySettings, Player, PolicyRun};
use crate::report::{
    Summary, attach_jod, format_table, summarize, write_frames_csv, write_plots,
    write_side_by_side, write_summary_csv,
};
use crate::scene::{Scene, policy_by_name};

/// Arguments of `acuity run`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Output folder (default `out/<scene file name>/`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: Option<PathBuf>,
    /// Number of frames, spread over the same path, 1 to 10,000,000
    /// (default: the scene's).
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64)))]
    pub frames: Option<u32>,
    /// Policies to run, comma-separated (default: the scene's).
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub policies: Option<Vec<String>>,
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept).
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_resolution))]
    pub resolution: Option<[u32; 2]>,
    /// Error metrics, comma-separated: `flip` (FLIP on sampled frames) and
    /// `fvvdp` (FovVideoVDP on every frame, foveated at the gaze: needs
    /// Python with pyfvvdp, `$ACUITY_PYTHON` or `python3`; dumps the frames,
    /// to `<out>/frames/` without --dump-frames).
    #[cfg_attr(
        feature = "clap",
        arg(long, value_delimiter = ',', default_value = "flip")
    )]
    pub metric: Vec<Metric>,
    /// Write every played frame to `DIR/<policy>_<knob>/NNNN.png` (RGB, as
    /// rendered; knob as in the experiments' CSV, full detail is `full_1`,
    /// dumped even when `full` is not played), each folder with gaze.csv
    /// (frame,x_px,y_px: the viewer's fixation in pixels, origin top-left, y
    /// down: the gaze, or `[gaze] viewer_object`'s centre), and
    /// DIR/display.json (resolution, fov_deg, fps, photometry, sequences).
    #[cfg_attr(feature = "clap", arg(long, value_name = "DIR"))]
    pub dump_frames: Option<PathBuf>,
    /// Cross-fade between LODs over this many seconds, drawn dithered
    /// (default: the scene's `run.cross_fade_s`; 0 = switch at once).
    #[cfg_attr(feature = "clap", arg(long, value_name = "SECONDS"))]
    pub cross_fade_s: Option<f64>,
    /// Profiles and progress.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub profiles: ProfileArgs,
}

/// What [`run`] produced.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// Per-policy runs.
    pub runs: Vec<PolicyRun>,
    /// Their summaries.
    pub summaries: Vec<Summary>,
    /// Where the files went.
    pub out_dir: PathBuf,
}

impl RunOutcome {
    /// The table `acuity run` prints: one line per policy, then what its
    /// columns mean ([`crate::report::table_legend`]).
    pub fn table(&self) -> String {
        let with_jod = self.summaries.iter().any(|s| s.jod.is_some());
        format!(
            "{}\n{}",
            format_table(&self.summaries),
            crate::report::table_legend(with_jod)
        )
    }
}

/// Loads `args.scene`, applies the overrides and loads its world.
pub fn load_world(args: &RunArgs) -> anyhow::Result<World> {
    let mut scene = Scene::load(&args.scene)?;
    if let Some(r) = args.resolution {
        scene.display.resolution_px = r;
    }
    if let Some(s) = args.cross_fade_s {
        crate::scene::check_cross_fade_s(s)
            .map_err(|e| crate::error::input_error(format!("--cross-fade-s: {e}")))?;
        scene.run.cross_fade_s = s;
    }
    if let Some(p) = &args.policies {
        let mut ps = Vec::new();
        for name in p {
            let policy = policy_by_name(name)?;
            if !ps.contains(&policy) {
                ps.push(policy);
            }
        }
        scene.run.policies = ps;
    }
    let options = args.profiles.load_options(&scene.profiles);
    World::load(scene, &options)
}

/// Runs `acuity run`: plays, prints the table and writes every output.
pub fn run(args: &RunArgs) -> anyhow::Result<RunOutcome> {
    if args.frames == Some(0) {
        return Err(crate::error::input_error("--frames must be at least 1"));
    }
    let fvvdp = args.metric.contains(&Metric::Fvvdp);
    if fvvdp {
        crate::dump::check_fvvdp()?;
    }
    let world = load_world(args)?;
    let scene = &world.scene;
    let name = scene
        .source_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&name));
    std::fs::create_dir_all(&out_dir).with_context(|| format!("creating {}", out_dir.display()))?;
    let mut settings = PlaySettings::from_scene(scene, args.frames)?;
    if !args.metric.contains(&Metric::Flip) {
        settings.flip_every_n_frames = 0;
    }
    settings.dump_dir = args
        .dump_frames
        .clone()
        .or_else(|| fvvdp.then(|| out_dir.join("frames")));
    if !args.profiles.quiet {
        let fade = if scene.run.cross_fade_s > 0.0 {
            format!(", {} s dithered cross-fades", scene.run.cross_fade_s)
        } else {
            String::new()
        };
        eprintln!(
            "{name}: {} instances, {} frames x {} policies at {}x{}{fade}, renderer: {}",
            world.instances.len(),
            settings.frames,
            settings.policies.len(),
            scene.display.resolution_px[0],
            scene.display.resolution_px[1],
            world.renderer.adapter_info()
        );
    }
    let mut player = Player::new(&world, settings.clone())?;
    let bar = crate::progress::bar(
        u64::from(settings.frames) * settings.policies.len() as u64,
        "frames",
        args.profiles.quiet,
    );
    player.set_progress(&bar);
    let started = Instant::now();
    let runs = player.play_all(&settings.policies, scene.run.screen_size_bias);
    bar.finish_and_clear();
    let runs = runs?;
    if !args.profiles.quiet {
        eprintln!("played in {:.1} s", started.elapsed().as_secs_f64());
    }
    let mut summaries = summarize(&runs, scene.run.budget_s());
    if let (true, Some(dir)) = (fvvdp, &settings.dump_dir) {
        attach_jod(
            &mut summaries,
            &crate::dump::score_fvvdp(dir, args.profiles.quiet)?,
        )?;
    }
    write_frames_csv(&runs, &out_dir.join("frames.csv"))?;
    write_summary_csv(&summaries, &out_dir.join("summary.csv"))?;
    write_plots(&runs, &name, &out_dir)?;
    for r in &runs {
        if let Some(wf) = &r.worst {
            let reference = player.reference(wf.frame)?.to_vec();
            let path = out_dir.join(format!("flip_{}_frame{:04}.png", r.policy.name(), wf.frame));
            write_side_by_side(&reference, wf, scene.display.resolution_px, &path)?;
        }
    }
    if !args.profiles.quiet {
        let flip_images = if runs.iter().any(|r| r.worst.is_some()) {
            ", flip_*.png: reference | policy | FLIP"
        } else {
            ""
        };
        eprintln!(
            "wrote {} (frames.csv, summary.csv, summary.json, frame_time, triangles and scale .png/.svg{flip_images})",
            out_dir.display()
        );
        if let Some(dir) = &settings.dump_dir {
            eprintln!("dumped every frame to {}", dir.display());
        }
    }
    Ok(RunOutcome {
        runs,
        summaries,
        out_dir,
    })
}
