//! `acuity-reddy2001`: Reddy 2001's two demos of the acuity model beyond
//! LOD selection: the acuity image filter and view-dependent terrain.
//!
//! A crate of its own beside the lab (`acuity-lab`), whose charts, FLIP,
//! input errors and progress bars it uses: the image filter is pure and
//! useful on its own (an engine's foveated post-process), and the terrain
//! demo is not an LOD experiment. With the `clap` feature the commands'
//! options structs derive `clap::Args`.
//!
//! - [`foveate`]: the acuity image filter (Reddy 2001, Fig. 5), pure (an
//!   image in, an image out); [`blur`]: `acuity blur`, the filter on a PNG
//!   or a generated image; [`fractal`]: seeded fractal noise for test
//!   images and terrain.
//! - [`terrain`]: `acuity terrain` (Reddy 2001's Table 1 on
//!   [`acuity::terrain`]); [`flight`]: its procedural valley and flight
//!   path; [`heightfield_file`]: its heightfield files (grey PNG, raw
//!   `f32`); [`terrain_render`]: drawing it; [`panorama`]: an equiangular
//!   image of a wide field from planar tiles.

pub mod blur;
pub mod flight;
pub mod foveate;
pub mod fractal;
pub mod heightfield_file;
pub mod panorama;
pub mod terrain;
pub mod terrain_render;
