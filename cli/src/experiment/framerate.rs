//! `acuity experiment framerate`: a fixed-frame-rate loop under load
//! spikes, frames over budget and `s` over time per scheduler.

use std::path::PathBuf;

use crate::exit::input_error;
use crate::limits;
use crate::player::{PlaySettings, Player};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::report::{Summary, format_table, frames_csv, summarize, write_csv_with_json};
use crate::scene::Policy;

use super::CommonArgs;

/// Arguments of `acuity experiment framerate`.
#[derive(clap::Args, Debug, Clone)]
pub struct FramerateArgs {
    /// The scene.
    #[arg(long, default_value = "scenes/vr_sweep.toml")]
    pub scene: PathBuf,
    /// Target frame rate, Hz, 1 to 10,000 (default: the scene's). A
    /// software rasteriser cannot reach 90 Hz on this scene; pick a rate it
    /// can nearly hold.
    #[arg(long, value_parser = crate::limits::parse_target_hz)]
    pub target_hz: Option<f64>,
    /// Frames, spread over the scene's path (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64))]
    pub frames: Option<u32>,
    /// Extra load during the spikes, as a fraction of the frame budget,
    /// 0 to 10.
    #[arg(long, default_value_t = 0.5, value_parser = crate::limits::parse_spike_load)]
    pub spike_load: f64,
    /// Options every experiment shares.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Runs the frame-rate experiment; writes `framerate.csv` (per frame),
/// `framerate_time.png` and `framerate_scale.png`; returns the summaries.
pub fn framerate(args: &FramerateArgs) -> anyhow::Result<Vec<Summary>> {
    limits::check_spike_load(args.spike_load)
        .map_err(|e| input_error(format!("--spike-load: {e}")))?;
    if let Some(hz) = args.target_hz {
        limits::check_target_hz(hz).map_err(|e| input_error(format!("--target-hz: {e}")))?;
    }
    let mut world = args.common.load(&args.scene)?;
    if let Some(hz) = args.target_hz {
        world.scene.run.target_hz = hz;
    }
    let mut settings = PlaySettings::from_scene(&world.scene, args.frames)?;
    settings.flip_every_n_frames = 0;
    settings.keep_images = false;
    settings.dump_dir = args.common.dump_frames.clone();
    // Two spikes, at 25-37.5% and 62.5-75% of the path.
    let d = f64::from(settings.frames) * settings.dt_s;
    let extra_ms = args.spike_load * world.scene.run.budget_s() * 1e3;
    settings.load_spikes = vec![
        (0.25 * d, 0.375 * d, extra_ms),
        (0.625 * d, 0.75 * d, extra_ms),
    ];
    let policies = [
        Policy::Full,
        Policy::AcuityAll,
        Policy::AcuityReactive,
        Policy::AcuityPredictive,
        Policy::AcuityPredictiveUniform,
    ];
    let bar = crate::progress::bar(
        u64::from(settings.frames) * policies.len() as u64,
        "frames",
        args.common.profiles.quiet,
    );
    let mut player = Player::new(&world, settings)?;
    player.set_progress(&bar);
    let runs = player.play_all(&policies, 1.0);
    bar.finish_and_clear();
    let runs = runs?;
    let sums = summarize(&runs, world.scene.run.budget_s());
    let out = args.common.out_dir("framerate")?;
    println!(
        "target {:.1} Hz ({:.2} ms), spikes of +{extra_ms:.2} ms at {:.2}-{:.2} s and {:.2}-{:.2} s",
        world.scene.run.target_hz,
        world.scene.run.budget_s() * 1e3,
        0.25 * d,
        0.375 * d,
        0.625 * d,
        0.75 * d
    );
    print!("{}", format_table(&sums));
    write_csv_with_json(&frames_csv(&runs), &out.join("framerate.csv"))?;
    let over_time = |f: &dyn Fn(&crate::player::FrameRecord) -> f64| -> Vec<Series> {
        runs.iter()
            .map(|r| Series {
                name: r.policy.name().into(),
                points: r.frames.iter().map(|x| (x.t_s, f(x))).collect(),
            })
            .collect()
    };
    let budget_ms = world.scene.run.budget_s() * 1e3;
    let mut time_series = over_time(&|f| f.frame_ms);
    time_series.push(Series {
        name: "budget".into(),
        points: vec![(0.0, budget_ms), (d, budget_ms)],
    });
    save_line_plot(
        &LinePlot {
            title: "frame time under load spikes".into(),
            x_label: "simulated time (s)".into(),
            y_label: "frame time (ms)".into(),
            series: time_series,
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_time.png"),
    )?;
    save_line_plot(
        &LinePlot {
            title: "scale factor s".into(),
            x_label: "simulated time (s)".into(),
            y_label: "scale factor s".into(),
            series: over_time(&|f| f64::from(f.scale)),
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_scale.png"),
    )?;
    if !args.common.profiles.quiet {
        eprintln!(
            "wrote {} (framerate.csv, framerate.json, framerate_time and framerate_scale .png/.svg)",
            out.display()
        );
    }
    Ok(sums)
}
