//! `acuity`: the command-line tool. Run `acuity --help`.

use std::process::ExitCode;

use acuity::acuity::threshold_cpd;
use acuity::{Display, EccentricityModel, VelocityModel};
use acuity_cli::thresholds::ThresholdReport;
use clap::{Args, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "acuity",
    version,
    about = "Perceptual level-of-detail selection from a model of visual acuity"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Where a display lets detail drop: xi, eccentricity and velocity
    /// thresholds (Reddy 1998 §4).
    Thresholds(DisplayArgs),
    /// Analyse a scene's objects (or one OBJ) into profiles: render every
    /// LOD from viewpoints on the view sphere, measure the frequencies each
    /// LOD transition removes. Unchanged inputs are not analysed again.
    Preprocess(acuity_cli::preprocess::PreprocessArgs),
    /// Fly a scene's camera path under each LOD policy: frame time,
    /// triangles, FLIP against full detail; a table, CSV, plots, images.
    Run(acuity_cli::run::RunArgs),
    /// The reference experiments of Reddy 1998 §5.
    Experiment(acuity_cli::experiment::ExperimentArgs),
    /// A PNG line plot of two columns of a CSV, one line per group of rows.
    Plot(acuity_cli::plot_csv::PlotArgs),
    /// Remove from an image the detail the acuity model predicts a viewer
    /// cannot see at a gaze point and velocity (Reddy 2001, Fig. 5).
    Blur(acuity_cli::blur::BlurArgs),
    /// View-dependent terrain under each combination of perceptual
    /// criteria over a recorded flight (Reddy 2001, Table 1).
    Terrain(acuity_cli::terrain::TerrainArgs),
    /// The threshold frequency for one velocity and eccentricity.
    Acuity {
        /// Retinal velocity, deg/s (finite, >= 0).
        #[arg(long, default_value_t = 0.0, value_parser = parse_non_negative)]
        velocity: f32,
        /// Eccentricity from the gaze, deg (finite, >= 0).
        #[arg(long, default_value_t = 0.0, value_parser = parse_non_negative)]
        eccentricity: f32,
        /// Global scale factor s in (0, 1].
        #[arg(long, default_value_t = 1.0)]
        scale: f32,
        /// How acuity falls with eccentricity: `cortical_magnification`
        /// (the default) or `reddy2001`.
        #[arg(long, default_value = "cortical_magnification")]
        eccentricity_model: EccentricityModel,
        /// How acuity falls with retinal velocity: `kelly1979` (the
        /// default) or `reddy2001`.
        #[arg(long, default_value = "kelly1979")]
        velocity_model: VelocityModel,
        #[command(flatten)]
        display: DisplayArgs,
    },
}

/// A display, by field of view or by physical size and distance.
#[derive(Args)]
struct DisplayArgs {
    /// Resolution in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x1024", value_parser = parse_pair::<u32>)]
    resolution: (u32, u32),
    /// Field of view in degrees, HORIZxVERT.
    #[arg(long, value_parser = parse_pair::<f32>, conflicts_with_all = ["screen_cm", "distance_cm"])]
    fov: Option<(f32, f32)>,
    /// Physical image size in cm, WIDTHxHEIGHT (with --distance-cm).
    #[arg(long, value_parser = parse_pair::<f32>, requires = "distance_cm")]
    screen_cm: Option<(f32, f32)>,
    /// Viewing distance in cm (with --screen-cm).
    #[arg(long, requires = "screen_cm")]
    distance_cm: Option<f32>,
}

impl DisplayArgs {
    fn display(&self) -> acuity::Result<Display> {
        let res = [self.resolution.0, self.resolution.1];
        match (self.fov, self.screen_cm, self.distance_cm) {
            (_, Some((w, h)), Some(d)) => Display::from_physical(res, [w, h], d),
            (Some((h, v)), _, _) => Display::new(res, [h, v]),
            _ => Display::new(res, [53.1, 41.1]),
        }
    }
}

/// A finite number >= 0 (a speed or an angle from the gaze).
fn parse_non_negative(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!("`{text}` is not a finite number >= 0")),
    }
}

fn parse_pair<T: std::str::FromStr>(text: &str) -> Result<(T, T), String> {
    let (a, b) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}` is not of the form AxB"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<T>()
            .map_err(|_| format!("`{s}` in `{text}` is not a number"))
    };
    Ok((parse(a)?, parse(b)?))
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            // One clear line: clap's first, without its usage footer.
            let text = e.to_string();
            eprintln!("{}", text.lines().next().unwrap_or("invalid arguments"));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Run(args) => return acuity_cli::run::command(&args),
        Command::Experiment(args) => return acuity_cli::experiment::command(&args),
        Command::Plot(args) => return acuity_cli::plot_csv::command(&args),
        Command::Blur(args) => return acuity_cli::blur::command(&args),
        Command::Terrain(args) => return acuity_cli::terrain::command(&args),
        Command::Preprocess(args) => {
            return acuity_cli::preprocess::finish(acuity_cli::preprocess::run(&args));
        }
        Command::Thresholds(display) => display
            .display()
            .map(|d| print!("{}", ThresholdReport::new(d))),
        Command::Acuity {
            velocity,
            eccentricity,
            scale,
            eccentricity_model,
            velocity_model,
            display,
        } => display.display().and_then(|d| {
            if !(scale > 0.0 && scale <= 1.0) {
                return Err(acuity::Error::InvalidParameter {
                    name: "scale",
                    reason: format!("{scale} is not in (0, 1]"),
                });
            }
            let h = velocity_model.acuity_cpd(velocity) * eccentricity_model.factor(eccentricity);
            let xi = d.max_frequency_cpd();
            println!("acuity H: {h:.3} c/deg");
            println!("display limit xi: {xi:.3} c/deg");
            println!("threshold T: {:.3} c/deg", threshold_cpd(h, xi, scale));
            Ok(())
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
