//! The command-line tools' building blocks: scene files, camera and gaze
//! paths, and the baseline LOD policies acuity is compared with.
//!
//! Nothing here is needed by the runtime; it is compiled only with the
//! `tools` feature (on by default).
//!
//! - [`scene`]: the TOML scene format, [`scene::Scene::load`] and its one
//!   error type [`scene::SceneError`].
//! - [`path`]: the evaluated camera path, [`path::CameraPath::sample`].
//! - [`gaze`]: the evaluated gaze, [`gaze::Gaze::sample`].
//! - [`placement`]: concrete object placements, including seeded copies.
//! - [`screen_size`]: the Unity-LODGroup-style screen-relative-height policy.
//! - [`frames`]: the scene player's world (LODs on the GPU, profiles,
//!   instances) and frame rendering; [`policy`]: the LOD policies;
//!   [`flip`]: the FLIP error; [`dump`]: frame dumps and FovVideoVDP
//!   scores of them; [`plot`]: PNG line plots; [`run`]: `acuity
//!   run`; [`experiment`]: `acuity experiment`.

pub mod dump;
pub mod experiment;
pub mod flip;
pub mod frames;
pub mod gaze;
pub mod path;
pub mod placement;
pub mod plot;
pub mod policy;
pub mod preprocess;
pub mod profiles;
pub mod run;
pub mod scene;
pub mod screen_size;
pub mod thresholds;
