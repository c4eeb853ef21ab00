//! `acuity-cli`: the `acuity` command-line tool and its building blocks:
//! scene files, camera and gaze paths, the offline pass's driver, and the
//! baseline LOD policies acuity is compared with.
//!
//! A crate of its own so that the runtime (crate `acuity`) stays lean:
//! nothing here is needed to select LODs, and the tool pulls in the GPU
//! renderer, image and plot output, FLIP (C++) and argument parsing.
//!
//! - [`scene`]: the TOML scene format, [`scene::Scene::load`] and its one
//!   error type [`scene::SceneError`]; [`limits`]: the largest counts,
//!   sizes and rates it and the command line accept; [`parse`]: settings
//!   parsed from text (statistic, resolution, threshold).
//! - [`path`]: the evaluated camera path, [`path::CameraPath::sample`].
//! - [`gaze`]: the evaluated gaze, [`gaze::Gaze::sample`].
//! - [`placement`]: concrete object placements, including seeded copies.
//! - [`screen_size`]: the Unity-LODGroup-style screen-relative-height policy.
//! - [`frames`]: the scene player's world (LODs on the GPU, profiles,
//!   instances) and frame rendering; [`policy`]: the LOD policies;
//!   [`crossfade`]: cross-fades of LODs chosen outside the runtime;
//!   [`player`]: playing a world's frames under policies; [`switches`]:
//!   counting LOD switches and flicker between frames; [`report`]:
//!   summaries, tables, CSVs, plots and FLIP images of played runs;
//!   [`flip`]: the FLIP error; [`dump`]: frame dumps and FovVideoVDP
//!   scores of them; [`plot`]: line plots (PNG and SVG); [`run`]: `acuity
//!   run`; [`experiment`]: `acuity experiment`; [`plot_csv`]: `acuity
//!   plot` (a plot of any two columns of a CSV).
//! - [`foveate`]: the acuity image filter (Reddy 2001, Fig. 5), pure;
//!   [`blur`]: `acuity blur`; [`fractal`]: seeded fractal noise.
//! - [`terrain`]: `acuity terrain` (Reddy 2001's Table 1 on
//!   [`acuity::terrain`]); [`flight`]: its procedural valley and flight
//!   path; [`heightfield_file`]: its heightfield files (grey PNG, raw
//!   `f32`); [`terrain_render`]: drawing it; [`panorama`]: an
//!   equiangular image of a wide field from planar tiles; [`barplot`]: bar charts (PNG and
//!   SVG).
//! - [`preprocess`]: `acuity preprocess`; [`profiles`]: the profile cache;
//!   [`thresholds`]: `acuity thresholds`.
//! - [`exit`]: the commands' exit codes (2: bad input, 1: failed while
//!   running) and their one-line error printing; [`progress`]: their
//!   progress bars.

mod arrays;
pub mod barplot;
pub mod blur;
pub mod crossfade;
pub mod dump;
pub mod exit;
pub mod experiment;
pub mod flight;
pub mod flip;
pub mod foveate;
pub mod fractal;
pub mod frames;
pub mod gaze;
pub mod heightfield_file;
pub mod library;
pub mod limits;
pub mod panorama;
pub mod parse;
pub mod path;
pub mod placement;
pub mod player;
pub mod plot;
pub mod plot_csv;
pub mod policy;
pub mod preprocess;
pub mod profiles;
pub mod progress;
pub mod report;
pub mod run;
pub mod scene;
pub mod screen_size;
pub mod switches;
pub mod terrain;
pub mod terrain_render;
pub mod thresholds;

/// An error and its causes on one line, `error: cause: ...`, as the
/// commands print them. A cause whose text ends its parent's is left out:
/// some errors (I/O errors with their file) print their cause and also
/// return it as their source.
pub fn error_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.ends_with(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_io_error_prints_once() {
        let io = std::io::Error::from(std::io::ErrorKind::IsADirectory);
        let text = io.to_string();
        let e = anyhow::Error::new(acuity::Error::Io {
            path: "cache/rock.acp".into(),
            source: io,
        })
        .context("object `rock`");
        let line = error_line(&e);
        assert_eq!(line, format!("object `rock`: cache/rock.acp: {text}"));
        assert_eq!(format!("{e:#}").matches(&text).count(), 2, "{e:#}");
    }
}
