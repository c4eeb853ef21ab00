//! The whole offline analysis of an object: load or generate its LOD chain,
//! render every LOD from every viewpoint, and measure the unique features of
//! every transition.
//!
//! # Decisions
//! - **One renderer** (one device) is passed in and shared by every object
//!   and view. Views are rendered one after the other (the GPU queue is
//!   serial; llvmpipe rasterises with its own threads) and each view's CPU
//!   analysis (CIELUV, changed masks, Feret extents) runs on rayon while the
//!   next view renders. Objects in [`analyse_many`] are analysed in turn,
//!   and one failing object does not stop the others.
//! - **Lighting** is fixed relative to the *camera* (from above, to the
//!   right and in front of the viewer), so every viewpoint sees the object
//!   lit the same way; a light fixed to the object would leave the views
//!   from its dark side with hardly any measurable detail.
//! - **Background**: a fixed colour, black by default, the largest contrast
//!   against lit surfaces (silhouettes are the most visible features, as
//!   Luebke & Hallen argue).
//! - **Frequencies** are `f_cpx × D` cycles per object diameter with `D` the
//!   bounding sphere's diameter in pixels (= `resolution_px`, orthographic
//!   camera; see [`crate::views`]). The bounding sphere is LOD 0's and
//!   frames every LOD.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use crate::frequency::{self, Feature, FrequencyStatistic};
use crate::lods::{self, ProceduralParams};
use crate::render::{Lighting, MeshId, RenderRequest, Renderer};
use crate::segment::{self, LuvImage, Regions};
use crate::views;
use crate::{Error, Mesh};

/// Version of the analysis algorithm, part of the settings hash so that
/// profiles made by an older algorithm are not reused.
pub const ANALYSIS_VERSION: u32 = 1;

/// Settings of the analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisSettings {
    /// Square image size in pixels, 16..=8192 (default 512). The bounding
    /// sphere's diameter spans the whole image.
    pub resolution_px: u32,
    /// View-sphere subdivision level, 0..=6: 6, 18 (default, level 1), 66,
    /// 258, ... viewpoints.
    pub viewpoint_level: u32,
    /// ΔE*uv just-noticeable difference, > 0 (default 2.3); used for region
    /// growing and for deciding which pixels changed.
    pub threshold_delta_e: f32,
    /// Number of Feret directions K, 4..=360 (default 8).
    pub feret_directions: u32,
    /// MSAA samples, 1 (default) or what the adapter supports; must match
    /// the [`Renderer`]'s.
    pub msaa_samples: u32,
    /// How a feature's extents become one length (default longest).
    pub statistic: FrequencyStatistic,
    /// Background colour, sRGB8 (default black).
    pub background_srgb: [u8; 3],
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        Self {
            resolution_px: 512,
            viewpoint_level: 1,
            threshold_delta_e: segment::DEFAULT_THRESHOLD_DELTA_E,
            feret_directions: frequency::DEFAULT_FERET_DIRECTIONS,
            msaa_samples: 1,
            statistic: FrequencyStatistic::Longest,
            background_srgb: [0, 0, 0],
        }
    }
}

impl AnalysisSettings {
    /// Checks every field's domain; the error names the field.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |field, message: String| Err(Error::Settings { field, message });
        if !(16..=8192).contains(&self.resolution_px) {
            return bad(
                "resolution_px",
                format!("{} outside 16..=8192", self.resolution_px),
            );
        }
        if self.viewpoint_level > views::MAX_VIEWPOINT_LEVEL {
            return bad(
                "viewpoint_level",
                format!(
                    "{} above {}",
                    self.viewpoint_level,
                    views::MAX_VIEWPOINT_LEVEL
                ),
            );
        }
        if !(self.threshold_delta_e.is_finite() && self.threshold_delta_e > 0.0) {
            return bad(
                "threshold_delta_e",
                format!("{} is not a positive number", self.threshold_delta_e),
            );
        }
        if !(4..=360).contains(&self.feret_directions) {
            return bad(
                "feret_directions",
                format!("{} outside 4..=360", self.feret_directions),
            );
        }
        if self.msaa_samples == 0 {
            return bad("msaa_samples", "0 samples".into());
        }
        Ok(())
    }
}

/// Where an object's LODs come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ObjectSource {
    /// One OBJ file per LOD, finest first.
    Files {
        /// Object name (used in messages and reports).
        name: String,
        /// OBJ files, finest first.
        lod_paths: Vec<PathBuf>,
    },
    /// One OBJ file simplified to each triangle target (see
    /// [`lods::generate_lods`]).
    Generated {
        /// Object name.
        name: String,
        /// The source OBJ file.
        path: PathBuf,
        /// Triangle targets, finest first, strictly decreasing.
        triangle_targets: Vec<u32>,
    },
    /// The procedural test object ([`lods::procedural_object`]) simplified to
    /// each triangle target.
    Procedural {
        /// Object name.
        name: String,
        /// Shape parameters.
        params: ProceduralParams,
        /// Triangle targets, finest first, strictly decreasing.
        triangle_targets: Vec<u32>,
    },
}

impl ObjectSource {
    /// The object's name.
    pub fn name(&self) -> &str {
        match self {
            Self::Files { name, .. }
            | Self::Generated { name, .. }
            | Self::Procedural { name, .. } => name,
        }
    }

    /// Loads or generates the LOD chain (checked), with loader warnings.
    pub fn load_lods(&self) -> Result<(Vec<Mesh>, Vec<String>), Error> {
        match self {
            Self::Files { name, lod_paths } => lods::load_lod_files(name, lod_paths),
            Self::Generated {
                name,
                path,
                triangle_targets,
            } => {
                let loaded = crate::mesh::load_obj(path)?;
                Ok((
                    lods::generate_lods(name, &loaded.mesh, triangle_targets)?,
                    loaded.warnings,
                ))
            }
            Self::Procedural {
                name,
                params,
                triangle_targets,
            } => {
                let m = lods::procedural_object(*params);
                Ok((lods::generate_lods(name, &m, triangle_targets)?, Vec::new()))
            }
        }
    }
}

/// A content hash of one input (a file, or a set of parameters).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct InputHash {
    /// The file's path as given (MTL files: as resolved), or a parameter
    /// description such as `settings` or `lod-generation`.
    pub what: String,
    /// BLAKE3 of the content, 64 lowercase hex digits; `missing` for an MTL
    /// file named by an OBJ but absent (the loader then warns and uses the
    /// default colour).
    pub hash_hex: String,
}

/// The analysis of one object.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectAnalysis {
    /// The object's name.
    pub name: String,
    /// Triangles per LOD, finest first.
    pub lod_triangles: Vec<u32>,
    /// Bounding sphere of LOD 0: centre and radius, model units.
    pub bounding_sphere: ([f32; 3], f32),
    /// Viewpoints: unit vectors in the object's frame, centre → camera, in
    /// [`views::viewpoints`] order.
    pub viewpoints: Vec<[f32; 3]>,
    /// Viewpoint-major: index `view * (n_lods - 1) + transition`, where
    /// transition `i` is LOD `i` → LOD `i + 1`.
    pub transitions: Vec<TransitionAnalysis>,
    /// Hashes of every input (see [`input_hashes`]).
    pub input_hashes: Vec<InputHash>,
    /// Non-fatal problems met while loading (missing MTL, ...).
    pub warnings: Vec<String>,
}

/// The unique features of one transition at one viewpoint.
#[derive(Debug, Clone, PartialEq)]
pub struct TransitionAnalysis {
    /// The lowest unique frequency, cycles per object diameter; `None` when
    /// the two LODs look the same (no perceptible difference).
    pub lowest_cdiam: Option<f32>,
    /// Every unique feature's frequency, cycles per object diameter,
    /// ascending (one entry per feature; many may be at the pixel limit
    /// `D / 2`).
    pub frequencies_cdiam: Vec<f32>,
}

impl TransitionAnalysis {
    /// A histogram of `frequencies_cdiam` over `edges` (ascending bin
    /// edges, c/diam): `counts[i]` counts `edges[i] <= f < edges[i + 1]`;
    /// frequencies outside are not counted.
    pub fn histogram(&self, edges: &[f32]) -> Vec<u32> {
        let mut counts = vec![0u32; edges.len().saturating_sub(1)];
        for &f in &self.frequencies_cdiam {
            if let Some(i) = edges.windows(2).position(|w| w[0] <= f && f < w[1]) {
                counts[i] += 1;
            }
        }
        counts
    }
}

/// Progress of one object's analysis, reported after each viewpoint.
#[derive(Debug, Clone, Copy)]
pub struct Progress<'a> {
    /// The object's name.
    pub object: &'a str,
    /// Viewpoints finished so far.
    pub views_done: usize,
    /// Viewpoints in total.
    pub views_total: usize,
}

/// Options of a run that do not change its results.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// When set, write every rendering (`<dir>/<object>/view###_lod#.png`)
    /// and every transition's unique features, coloured by feature
    /// (`view###_t#-#_features.png`).
    pub inspect_dir: Option<&'a Path>,
    /// Called from worker threads after each viewpoint.
    pub progress: Option<&'a (dyn Fn(&Progress<'_>) + Sync)>,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("inspect_dir", &self.inspect_dir)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Analyses one object. See the module docs.
pub fn analyse(
    renderer: &Renderer,
    object: &ObjectSource,
    settings: &AnalysisSettings,
    run: &RunOptions<'_>,
) -> Result<ObjectAnalysis, Error> {
    settings.validate()?;
    let hashes = input_hashes(object, settings)?;
    let (lods, warnings) = object.load_lods()?;
    let mut a = analyse_lods(renderer, object.name(), &lods, settings, run)?;
    a.input_hashes = hashes;
    a.warnings = warnings;
    Ok(a)
}

/// Analyses several objects with one renderer; one object's failure does
/// not stop the others. Results are in input order.
pub fn analyse_many(
    renderer: &Renderer,
    objects: &[ObjectSource],
    settings: &AnalysisSettings,
    run: &RunOptions<'_>,
) -> Vec<Result<ObjectAnalysis, Error>> {
    objects
        .iter()
        .map(|o| analyse(renderer, o, settings, run))
        .collect()
}

/// Analyses an LOD chain that is already in memory (no input hashes).
pub fn analyse_lods(
    renderer: &Renderer,
    name: &str,
    lods: &[Mesh],
    settings: &AnalysisSettings,
    run: &RunOptions<'_>,
) -> Result<ObjectAnalysis, Error> {
    settings.validate()?;
    if renderer.msaa_samples() != settings.msaa_samples {
        return Err(Error::Settings {
            field: "msaa_samples",
            message: format!(
                "settings ask for {} but the renderer was made with {}",
                settings.msaa_samples,
                renderer.msaa_samples()
            ),
        });
    }
    lods::check_chain(name, lods)?;
    let (centre, radius) = lods[0].bounding_sphere();
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(Error::LodChain {
            object: name.into(),
            lod: 0,
            message: format!("degenerate bounding sphere (radius {radius})"),
        });
    }
    let viewpoints = views::viewpoints(settings.viewpoint_level)?;
    let inspect = match run.inspect_dir {
        Some(d) => {
            let dir = d.join(sanitize(name));
            std::fs::create_dir_all(&dir).map_err(|source| Error::Io {
                path: dir.clone(),
                source,
            })?;
            Some(dir)
        }
        None => None,
    };

    let ids: Vec<MeshId> = lods
        .iter()
        .map(|m| renderer.upload_mesh(m))
        .collect::<Result<_, _>>()?;
    let result = render_and_measure(
        renderer,
        name,
        &ids,
        &viewpoints,
        (centre, radius),
        settings,
        run,
        inspect.as_deref(),
    );
    for id in &ids {
        renderer.free_mesh(*id);
    }
    Ok(ObjectAnalysis {
        name: name.into(),
        lod_triangles: lods.iter().map(|m| m.triangle_count() as u32).collect(),
        bounding_sphere: (centre, radius),
        viewpoints,
        transitions: result?,
        input_hashes: Vec::new(),
        warnings: Vec::new(),
    })
}

#[allow(clippy::too_many_arguments)]
fn render_and_measure(
    renderer: &Renderer,
    name: &str,
    ids: &[MeshId],
    viewpoints: &[[f32; 3]],
    sphere: ([f32; 3], f32),
    settings: &AnalysisSettings,
    run: &RunOptions<'_>,
    inspect: Option<&Path>,
) -> Result<Vec<TransitionAnalysis>, Error> {
    let res = settings.resolution_px;
    let n_trans = ids.len() - 1;
    let done = AtomicUsize::new(0);
    let (tx, rx) = std::sync::mpsc::channel::<(usize, Result<Vec<TransitionAnalysis>, Error>)>();
    let render_result: Result<(), Error> = rayon::scope(|s| {
        for (v, &dir) in viewpoints.iter().enumerate() {
            let cam = views::camera_for(dir, sphere.0, sphere.1, res);
            let lighting = camera_light(&cam.view);
            let mut images = Vec::with_capacity(ids.len());
            for id in ids {
                let out = renderer.render(&RenderRequest {
                    width: res,
                    height: res,
                    view_proj: cam.view_proj,
                    instances: &[(*id, Mat4::IDENTITY)],
                    lighting,
                    background_srgb: settings.background_srgb,
                })?;
                images.push(out.rgba);
            }
            let tx = tx.clone();
            let done = &done;
            s.spawn(move |_| {
                let r = measure_view(&images, res, cam.sphere_diameter_px, settings, inspect, v);
                let _ = tx.send((v, r));
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(p) = run.progress {
                    p(&Progress {
                        object: name,
                        views_done: n,
                        views_total: viewpoints.len(),
                    });
                }
            });
        }
        Ok(())
    });
    drop(tx);
    render_result?;
    let mut per_view: Vec<Option<Vec<TransitionAnalysis>>> = vec![None; viewpoints.len()];
    for (v, r) in rx {
        per_view[v] = Some(r?);
    }
    let mut out = Vec::with_capacity(viewpoints.len() * n_trans);
    for t in per_view {
        out.extend(t.ok_or_else(|| Error::Gpu {
            message: "a viewpoint's analysis did not finish".into(),
        })?);
    }
    Ok(out)
}

/// The analysis light, fixed relative to the camera (see the module docs).
fn camera_light(view: &Mat4) -> Lighting {
    let inv = view.inverse();
    let right = inv.transform_vector3(Vec3::X);
    let up = inv.transform_vector3(Vec3::Y);
    let back = inv.transform_vector3(Vec3::Z); // towards the camera
    Lighting {
        direction_to_light: (back + 0.6 * up + 0.4 * right).normalize().into(),
        ..Lighting::default()
    }
}

/// Converts one view's LOD images to CIELUV and measures each transition.
fn measure_view(
    images: &[Vec<u8>],
    res: u32,
    diameter_px: f32,
    settings: &AnalysisSettings,
    inspect: Option<&Path>,
    view: usize,
) -> Result<Vec<TransitionAnalysis>, Error> {
    let luv: Vec<LuvImage> = images
        .par_iter()
        .map(|im| segment::rgba_to_luv(res, res, im))
        .collect::<Result<_, _>>()?;
    if let Some(dir) = inspect {
        for (i, im) in images.iter().enumerate() {
            write_png(&dir.join(format!("view{view:03}_lod{i}.png")), res, im)?;
        }
    }
    (0..images.len() - 1)
        .into_par_iter()
        .map(|t| {
            let (features, regions) = frequency::unique_features(
                &luv[t],
                &luv[t + 1],
                settings.threshold_delta_e,
                settings.feret_directions,
            )?;
            if let Some(dir) = inspect {
                write_png(
                    &dir.join(format!("view{view:03}_t{}-{}_features.png", t, t + 1)),
                    res,
                    &feature_image(&regions),
                )?;
            }
            Ok(transition_from(&features, settings.statistic, diameter_px))
        })
        .collect()
}

/// Builds a [`TransitionAnalysis`] from measured features.
pub fn transition_from(
    features: &[Feature],
    statistic: FrequencyStatistic,
    diameter_px: f32,
) -> TransitionAnalysis {
    let f: Vec<f32> = frequency::frequencies_cpx(features, statistic)
        .into_iter()
        .map(|f| f * diameter_px)
        .collect();
    TransitionAnalysis {
        lowest_cdiam: f.first().copied(),
        frequencies_cdiam: f,
    }
}

fn feature_image(regions: &Regions) -> Vec<u8> {
    let mut out = Vec::with_capacity(regions.labels.len() * 4);
    for &l in &regions.labels {
        if l == Regions::NONE {
            out.extend_from_slice(&[0, 0, 0, 255]);
        } else {
            // A bright colour per feature, stable across runs.
            let h = l.wrapping_mul(2_654_435_761);
            out.extend_from_slice(&[
                128 | (h >> 24) as u8,
                128 | (h >> 16) as u8,
                128 | (h >> 8) as u8,
                255,
            ]);
        }
    }
    out
}

fn write_png(path: &Path, res: u32, rgba: &[u8]) -> Result<(), Error> {
    image::save_buffer(path, rgba, res, res, image::ExtendedColorType::Rgba8).map_err(|e| {
        Error::WriteImage {
            path: path.to_owned(),
            message: e.to_string(),
        }
    })
}

fn sanitize(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "_".into() } else { s }
}

/// Content hashes of every input of `object` under `settings`, computed
/// without loading meshes or rendering: each OBJ file, each MTL file it
/// names (`mtllib`, resolved next to the OBJ; `missing` when absent), the
/// LOD-generation or procedural parameters, and the settings (with
/// [`ANALYSIS_VERSION`]). Equal hashes mean the analysis would give the
/// same result. Unreadable OBJ files are an [`Error::Io`].
pub fn input_hashes(
    object: &ObjectSource,
    settings: &AnalysisSettings,
) -> Result<Vec<InputHash>, Error> {
    let mut out = Vec::new();
    let hash_str = |s: &str| blake3::hash(s.as_bytes()).to_hex().to_string();
    match object {
        ObjectSource::Files { lod_paths, .. } => {
            for p in lod_paths {
                hash_obj_and_mtls(p, &mut out)?;
            }
        }
        ObjectSource::Generated {
            path,
            triangle_targets,
            ..
        } => {
            hash_obj_and_mtls(path, &mut out)?;
            out.push(InputHash {
                what: "lod-generation".into(),
                hash_hex: hash_str(&format!("meshopt-simplify targets={triangle_targets:?}")),
            });
        }
        ObjectSource::Procedural {
            params,
            triangle_targets,
            ..
        } => {
            out.push(InputHash {
                what: lods::procedural_description(*params).display().to_string(),
                hash_hex: hash_str(&format!("{params:?}")),
            });
            out.push(InputHash {
                what: "lod-generation".into(),
                hash_hex: hash_str(&format!("meshopt-simplify targets={triangle_targets:?}")),
            });
        }
    }
    out.push(InputHash {
        what: "settings".into(),
        hash_hex: hash_str(&format!("v{ANALYSIS_VERSION} {settings:?}")),
    });
    Ok(out)
}

fn hash_obj_and_mtls(path: &Path, out: &mut Vec<InputHash>) -> Result<(), Error> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    out.push(InputHash {
        what: path.display().to_string(),
        hash_hex: blake3::hash(&bytes).to_hex().to_string(),
    });
    let dir = path.parent().unwrap_or(Path::new(""));
    let text = crate::mesh::decode_text(&bytes, path).unwrap_or_default();
    for line in crate::mesh::split_lines(&text) {
        let mut toks = line.split('#').next().unwrap_or("").split_whitespace();
        if toks.next() != Some("mtllib") {
            continue;
        }
        for name in toks {
            let p = dir.join(name);
            let hash_hex = match std::fs::read(&p) {
                Ok(b) => blake3::hash(&b).to_hex().to_string(),
                Err(_) => "missing".into(),
            };
            out.push(InputHash {
                what: p.display().to_string(),
                hash_hex,
            });
        }
    }
    Ok(())
}
