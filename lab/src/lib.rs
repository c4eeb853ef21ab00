//! `acuity-lab`: acuity's evaluation lab as a library: everything the
//! `acuity` command line does, callable from Rust.
//!
//! A crate of its own so that the runtime (crate `acuity`) stays lean:
//! nothing here is needed to select LODs, and the lab pulls in the GPU
//! renderer, image and plot output and FLIP (C++). The command line
//! (`acuity-cli`) is a shell over it: argument parsing, exit codes and
//! printing of errors. With the `clap` feature every command's options
//! struct derives `clap::Args`; without it they are plain structs.
//!
//! Scene files and what they describe:
//! - [`scene`]: the TOML scene format, [`scene::Scene::load`] and its one
//!   error type [`scene::SceneError`]; [`limits`]: the largest counts,
//!   sizes and rates the lab accepts; [`parse`]: settings parsed from text
//!   (statistic, resolution, threshold).
//! - [`path`]: the evaluated camera path, [`path::CameraPath::sample`];
//!   [`gaze`]: the evaluated gaze, [`gaze::Gaze::sample`]; [`placement`]:
//!   concrete object placements, including seeded copies.
//!
//! Playing a scene:
//! - [`frames`]: the world (LODs on the GPU, profiles, instances) and frame
//!   rendering; [`policy`]: the LOD policies; [`screen_size`]: the
//!   Unity-LODGroup-style screen-relative-height baseline; [`crossfade`]:
//!   cross-fades of LODs chosen outside the runtime; [`player`]: playing a
//!   world's frames under policies; [`switches`]: LOD switches and flicker
//!   between frames.
//!
//! Measuring and reporting:
//! - [`flip`]: the FLIP error; [`dump`]: frame dumps and FovVideoVDP
//!   scores of them; [`report`]: summaries, tables, CSVs, plots and FLIP
//!   images of played runs; [`plot`] and [`barplot`]: line and bar charts
//!   (PNG and SVG).
//!
//! The commands, one module each, taking the options struct the command
//! line parses: [`run`] (`acuity run`), [`experiment`] (`acuity
//! experiment`: speedup, error, framerate), [`plot_csv`] (`acuity plot`),
//! [`preprocess`] (`acuity preprocess`, with [`library`]: asset folders
//! and shards, and [`profiles`]: the profile cache), [`thresholds`]
//! (`acuity thresholds`). (Reddy 2001's demos, `acuity blur` and `acuity
//! terrain`, are the crate `acuity-reddy2001`.) `run` and the experiments
//! write their files
//! and return what they measured with the table the command line prints;
//! `preprocess` prints a line per object as it goes (stdout). Progress goes to stderr unless `quiet` (a bar only on
//! a terminal).
//!
//! Errors: the commands return [`anyhow::Error`]s whose cause chain holds a
//! typed error; [`error::InputError`], [`scene::SceneError`],
//! [`screen_size::ScreenSizeError`],
//! [`preprocess::PreprocessError::Usage`] and the runtime's, renderer's
//! and image parsers' input kinds blame the input; everything else is a
//! failure while running ([`blame::blames_input`] tells which).
//! [`error::error_line`] prints a chain on one line.

mod arrays;
pub mod barplot;
pub mod blame;
pub mod crossfade;
pub mod dump;
pub mod error;
pub mod experiment;
pub mod flip;
pub mod frames;
pub mod gaze;
pub mod library;
pub mod limits;
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
pub mod thresholds;
