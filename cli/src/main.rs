//! `acuity`: the command-line tool. Run `acuity --help`.

use std::process::ExitCode;

use acuity::acuity::threshold_cpd;
use acuity::{Display, EccentricityModel, VelocityModel};
use acuity_lab::thresholds::ThresholdReport;
use clap::{Args, CommandFactory, Parser, Subcommand};

mod exit;

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
    Preprocess(acuity_lab::preprocess::PreprocessArgs),
    /// Fly a scene's camera path under each LOD policy: frame time,
    /// triangles, FLIP against full detail; a table, CSV, plots, images.
    Run(acuity_lab::run::RunArgs),
    /// The reference experiments of Reddy 1998 §5.
    Experiment(acuity_lab::experiment::ExperimentArgs),
    /// A line plot (PNG and SVG) of two columns of a CSV, one line per
    /// group of rows.
    Plot(acuity_lab::plot_csv::PlotArgs),
    /// Remove from an image the detail the acuity model predicts a viewer
    /// cannot see at a gaze point and velocity (Reddy 2001, Fig. 5).
    Blur(acuity_reddy2001::blur::BlurArgs),
    /// View-dependent terrain under each combination of perceptual
    /// criteria over a recorded flight (Reddy 2001, Table 1).
    Terrain(acuity_reddy2001::terrain::TerrainArgs),
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
    let [a, b] = acuity_lab::parse::parse_pair(text, "AxB", |s| {
        s.parse::<T>()
            .map_err(|_| format!("`{s}` in `{text}` is not a number"))
    })?;
    Ok((a, b))
}

/// Adds a suggestion to an unknown subcommand one letter off a known one
/// (`rn`, `rnu`: `run`), which clap's similarity measure misses in short
/// names.
fn suggest_subcommand(e: &mut clap::Error) {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::InvalidSubcommand || e.get(ContextKind::SuggestedSubcommand).is_some()
    {
        return;
    }
    let Some(ContextValue::String(given)) = e.get(ContextKind::InvalidSubcommand) else {
        return;
    };
    let near: Vec<String> = Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_owned())
        .filter(|name| edit_distance(given, name) == 1)
        .collect();
    if !near.is_empty() {
        e.insert(
            ContextKind::SuggestedSubcommand,
            ContextValue::Strings(near),
        );
    }
}

/// Letters inserted, deleted, substituted or swapped (adjacent) to turn
/// `a` into `b`.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            d[i][j] = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
            }
        }
    }
    d[a.len()][b.len()]
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version go to stdout and exit 0.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(mut e) => {
            // Clap's whole message: the error, its suggestions, the usage.
            suggest_subcommand(&mut e);
            let _ = e.print();
            return ExitCode::from(exit::INPUT);
        }
    };
    let result: anyhow::Result<()> = match cli.command {
        Command::Run(args) => acuity_lab::run::run(&args).map(|run| print!("{}", run.table())),
        Command::Experiment(args) => experiment(&args),
        Command::Plot(args) => acuity_lab::plot_csv::plot(&args),
        Command::Blur(args) => acuity_reddy2001::blur::run(&args),
        Command::Terrain(args) => acuity_reddy2001::terrain::run(&args),
        Command::Preprocess(args) => acuity_lab::preprocess::run(&args),
        Command::Thresholds(display) => display
            .display()
            .map(|d| print!("{}", ThresholdReport::new(d)))
            .map_err(Into::into),
        Command::Acuity {
            velocity,
            eccentricity,
            scale,
            eccentricity_model,
            velocity_model,
            display,
        } => display
            .display()
            .and_then(|d| {
                if !(scale > 0.0 && scale <= 1.0) {
                    return Err(acuity::Error::InvalidParameter {
                        name: "scale",
                        reason: format!("{scale} is not in (0, 1]"),
                    });
                }
                let h =
                    velocity_model.acuity_cpd(velocity) * eccentricity_model.factor(eccentricity);
                let xi = d.max_frequency_cpd();
                println!("acuity H: {h:.3} c/deg");
                println!("display limit xi: {xi:.3} c/deg");
                println!("threshold T: {:.3} c/deg", threshold_cpd(h, xi, scale));
                Ok(())
            })
            .map_err(Into::into),
    };
    exit::report(result)
}

/// `acuity experiment`: runs the chosen experiment, which writes its
/// files, and prints its table.
fn experiment(args: &acuity_lab::experiment::ExperimentArgs) -> anyhow::Result<()> {
    use acuity_lab::experiment::{Experiment, error, framerate, speedup};
    match &args.which {
        Experiment::Speedup(a) => speedup(a).map(|o| print!("{}", o.table)),
        Experiment::Error(a) => error(a).map(|sweep| print!("{}", sweep.table())),
        Experiment::Framerate(a) => framerate(a).map(|o| print!("{}", o.table)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_sweeps_defaults_are_the_labs() {
        let cli = Cli::try_parse_from(["acuity", "experiment", "error"]).unwrap();
        let Command::Experiment(args) = cli.command else {
            panic!("not an experiment");
        };
        let acuity_lab::experiment::Experiment::Error(parsed) = args.which else {
            panic!("not the error experiment");
        };
        assert_eq!(
            format!("{parsed:?}"),
            format!("{:?}", acuity_lab::experiment::ErrorArgs::default())
        );
    }

    #[test]
    fn one_letter_off_is_distance_one() {
        assert_eq!(edit_distance("rn", "run"), 1);
        assert_eq!(edit_distance("rnu", "run"), 1);
        assert_eq!(edit_distance("runn", "run"), 1);
        assert_eq!(edit_distance("blurr", "blur"), 1);
        assert_eq!(edit_distance("plto", "plot"), 1);
        assert_eq!(edit_distance("x", "run"), 3);
        assert_eq!(edit_distance("run", "run"), 0);
    }

    #[test]
    fn an_unknown_subcommand_near_a_known_one_gets_it_suggested() {
        let mut e = Cli::try_parse_from(["acuity", "rn"]).err().unwrap();
        suggest_subcommand(&mut e);
        let text = e.to_string();
        assert!(text.contains("'run'"), "{text}");
        let mut e = Cli::try_parse_from(["acuity", "zzz"]).err().unwrap();
        suggest_subcommand(&mut e);
        assert!(!e.to_string().contains("similar"), "{e}");
    }
}
