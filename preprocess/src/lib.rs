//! acuity's offline pass: render each LOD of an object from viewpoints
//! spread over its view sphere, find the features each LOD transition
//! removes, and measure their spatial frequencies in cycles per object
//! diameter and their contrast, at a ladder of on-screen sizes.
//!
//! Modules, one concept each: [`mesh`] (OBJ/MTL loading) and [`render`]
//! (the shared headless renderer), both re-exported from crate
//! `acuity-render`; [`lods`] (LOD chains, simplification, a procedural
//! test object), [`shapes`] (a sphere and a torus tessellated to a
//! triangle count), [`views`] (viewpoints and camera), [`segment`] (CIELUV
//! and region growing), [`frequency`] (a feature's size as a frequency),
//! [`features`] (the unique features of a transition and their contrast),
//! [`inputs`] (what an analysis takes: the object's LOD source and the
//! settings), [`pipeline`] (the whole analysis), [`input_files`] (the files an
//! analysis reads, hashed for the cache), [`export`] (an analysed chain
//! written as `.glb` and OBJ), [`sample`] (a textured test asset made by
//! code).
//!
//! The crate returns plain data ([`ObjectAnalysis`]); the `acuity-cli`
//! crate turns it into the runtime's profile format (crate `acuity`). This
//! crate depends on neither (only on the renderer, `acuity-render`).

pub mod export;
pub mod features;
pub mod frequency;
pub mod input_files;
pub mod inputs;
pub mod lods;
pub mod pipeline;
pub mod sample;
pub mod segment;
pub mod shapes;
pub mod views;

pub use acuity_render as render;
pub use acuity_render::{Error, LoadedMesh, Mesh, error, mesh};
pub use frequency::FrequencyStatistic;
pub use pipeline::{
    AnalysisSettings, FeatureRecord, InputHash, ObjectAnalysis, ObjectSource, Progress, RunOptions,
    TransitionAnalysis, analyse, analyse_many, input_hashes,
};
pub use render::{MeshId, RenderOutput, RenderRequest, Renderer, RendererOptions};
