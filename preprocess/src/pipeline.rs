//! The whole offline analysis of an object: load or generate its LOD chain,
//! render every LOD from every viewpoint at every size of a ladder of
//! on-screen sizes, and measure the unique features of every transition
//! (their frequency and contrast, [`crate::features`]).
//!
//! # Decisions
//! - **A ladder of on-screen sizes**: what a transition changes at 512
//!   pixels is not what survives when the object covers 30, so every LOD is
//!   rendered with its bounding sphere `D` pixels across for each `D` of
//!   [`AnalysisSettings::diameters_px`] (halving from `resolution_px` down
//!   to `min_diameter_px`: 16, 32, ..., 512 by default), the way the scene
//!   renderer draws an object of that size (same shading, same
//!   anti-aliasing). The run time uses the rung nearest the object's pixel
//!   diameter, so what the display cannot show at that size is not in the
//!   images it judges.
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
//! - **Transitions are measured from full detail**: transition `i` holds
//!   the features LOD `i + 1` lacks compared with LOD 0, not with LOD `i`.
//!   Consecutive LODs can each differ by a fraction of a pixel while the
//!   coarsest differs from full detail by several (a silhouette moved a
//!   little at every step), and what the viewer compares, and what the
//!   selection promises, is full detail against the LOD drawn.
//! - **Anti-aliasing**: 4x MSAA by default, as real applications draw and
//!   as the scene renderer draws; without it every LOD swap also moves
//!   aliased edges.
//! - **Frequencies** are `f_cpx × D` cycles per object diameter with `D` the
//!   bounding sphere's diameter in pixels (the rung's image size,
//!   orthographic camera; see [`crate::views`]). The bounding sphere is
//!   LOD 0's and frames every LOD.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use crate::features::{self, FeatureSettings, Grouping, UniqueFeature, Visibility};
pub use crate::input_files::{InputHash, input_hashes};
pub use crate::inputs::{ANALYSIS_VERSION, AnalysisSettings, ObjectSource};
use crate::lods;
use crate::render::{Lighting, MeshId, RenderRequest, Renderer};
use crate::segment::{self, LuvImage, Regions};

use crate::views;
use crate::{Error, Mesh};

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
    /// The size ladder: the bounding sphere's diameter in pixels of each
    /// rung, ascending ([`AnalysisSettings::diameters_px`]).
    pub diameters_px: Vec<u32>,
    /// Index `(view * diameters + rung) * (n_lods - 1) + transition`, where
    /// transition `i` is LOD 0 → LOD `i + 1` (see the module docs).
    pub transitions: Vec<TransitionAnalysis>,
    /// Hashes of every input (see [`input_hashes`]).
    pub input_hashes: Vec<InputHash>,
    /// Non-fatal problems met while loading (missing MTL, ...).
    pub warnings: Vec<String>,
}

impl ObjectAnalysis {
    /// The transitions seen from `view` at rung `rung`, `0 -> 1` first.
    pub fn transitions_at(&self, view: usize, rung: usize) -> &[TransitionAnalysis] {
        let n = self.lod_triangles.len().saturating_sub(1);
        let i = (view * self.diameters_px.len() + rung) * n;
        &self.transitions[i..i + n]
    }
}

/// The unique features of one transition at one viewpoint and size.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TransitionAnalysis {
    /// Number of unique features found; 0 when the two LODs look the same.
    pub feature_count: u32,
    /// The features with contrast, grouped with their like
    /// ([`features::summarise`]), ascending by frequency.
    pub features: Vec<FeatureRecord>,
}

/// A unique feature as the profile stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeatureRecord {
    /// Spatial frequency, cycles per object diameter (> 0).
    pub freq_cdiam: f32,
    /// Area in units of the squared bounding-sphere diameter (its pixel
    /// count over `D²`).
    pub area_diam2: f32,
    /// Relative linear luminance `[lower, higher]` of the feature in the
    /// two renderings (see [`UniqueFeature::luminance`]).
    pub luminance: [f32; 2],
    /// Relative linear luminance range `[lowest, highest]` of what masks
    /// it (see [`UniqueFeature::masker`]).
    pub masker: [f32; 2],
    /// How many measured features the record stands for
    /// ([`features::summarise`]).
    pub count: u32,
}

impl TransitionAnalysis {
    /// The lowest frequency among the stored features, c/diam.
    pub fn lowest_cdiam(&self) -> Option<f32> {
        self.features.first().map(|f| f.freq_cdiam)
    }
}

/// Progress of one object's analysis, reported after each viewpoint at
/// each rung of the size ladder.
#[derive(Debug, Clone, Copy)]
pub struct Progress<'a> {
    /// The object's name.
    pub object: &'a str,
    /// (Viewpoint, rung) pairs analysed so far.
    pub done: usize,
    /// (Viewpoint, rung) pairs in total.
    pub total: usize,
}

/// Options of a run that do not change its results.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// When set, write every rendering
    /// (`<dir>/<object>/d###_view###_lod#.png`, `d` the rung's diameter in
    /// pixels) and every transition's unique features, coloured by feature
    /// (`d###_view###_t#-#_features.png`).
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

/// `mesh` moved and scaled (in f64) so that the sphere `centre`, `radius`
/// becomes the unit sphere at the origin; normals the loader computed are
/// computed again at that size (at a tiny size their cross products
/// underflow).
fn unit_sized(mesh: &Mesh, centre: [f32; 3], radius: f32) -> Mesh {
    let c = glam::Vec3::from(centre).as_dvec3();
    let inv_r = 1.0 / f64::from(radius);
    let mut unit = mesh.clone();
    for p in &mut unit.positions {
        *p = ((glam::Vec3::from(*p).as_dvec3() - c) * inv_r)
            .as_vec3()
            .into();
    }
    if unit.normals_computed {
        unit.compute_smooth_normals();
    }
    unit
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
    let diameters = settings.diameters_px();
    if lods.len() == 1 {
        // Nothing to switch to, so nothing to measure or render.
        return Ok(ObjectAnalysis {
            name: name.into(),
            lod_triangles: vec![lods[0].triangle_count() as u32],
            bounding_sphere: (centre, radius),
            viewpoints,
            diameters_px: diameters,
            transitions: Vec::new(),
            input_hashes: Vec::new(),
            warnings: Vec::new(),
        });
    }
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

    // The analysis is in cycles per object diameter, so it is drawn at unit
    // size: a mesh of 1e-30 or 1e30 model units renders like one of 1.
    let ids: Vec<MeshId> = lods
        .iter()
        .map(|m| renderer.upload_mesh(&unit_sized(m, centre, radius)))
        .collect::<Result<_, _>>()?;
    let result = render_and_measure(
        renderer,
        name,
        &ids,
        &viewpoints,
        &diameters,
        ([0.0; 3], 1.0),
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
        diameters_px: diameters,
        transitions: result?,
        input_hashes: Vec::new(),
        warnings: Vec::new(),
    })
}

/// Renders every LOD for every (rung, viewpoint) pair, rung by rung (one
/// render target size at a time), and measures each pair's transitions on
/// rayon while the next pair renders.
#[allow(clippy::too_many_arguments)]
fn render_and_measure(
    renderer: &Renderer,
    name: &str,
    ids: &[MeshId],
    viewpoints: &[[f32; 3]],
    diameters: &[u32],
    sphere: ([f32; 3], f32),
    settings: &AnalysisSettings,
    run: &RunOptions<'_>,
    inspect: Option<&Path>,
) -> Result<Vec<TransitionAnalysis>, Error> {
    let n_trans = ids.len() - 1;
    let (n_views, n_rungs) = (viewpoints.len(), diameters.len());
    let total = n_views * n_rungs;
    let done = AtomicUsize::new(0);
    type Measured = (usize, Result<Vec<TransitionAnalysis>, Error>);
    let (tx, rx) = std::sync::mpsc::channel::<Measured>();
    let render_result: Result<(), Error> = rayon::scope(|s| {
        for (rung, &res) in diameters.iter().enumerate() {
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
                        dither: &[],
                        albedo: &[],
                        lighting,
                        background_srgb: settings.background_srgb,
                    })?;
                    images.push(out.rgba);
                }
                let tx = tx.clone();
                let done = &done;
                s.spawn(move |_| {
                    let at = ViewAt {
                        view: v,
                        res,
                        diameter_px: cam.sphere_diameter_px,
                    };
                    let r = measure_view(&images, &at, settings, inspect);
                    let _ = tx.send((v * n_rungs + rung, r));
                    let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if let Some(p) = run.progress {
                        p(&Progress {
                            object: name,
                            done: n,
                            total,
                        });
                    }
                });
            }
        }
        Ok(())
    });
    drop(tx);
    render_result?;
    let mut per_pair: Vec<Option<Vec<TransitionAnalysis>>> = vec![None; total];
    for (i, r) in rx {
        per_pair[i] = Some(r?);
    }
    let mut out = Vec::with_capacity(total * n_trans);
    for t in per_pair {
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

/// Which rendering a set of LOD images is.
struct ViewAt {
    view: usize,
    /// Image size, pixels.
    res: u32,
    /// Bounding sphere diameter, pixels.
    diameter_px: f32,
}

/// Converts one view's LOD images to CIELUV, grows each one's regions and
/// measures each transition.
fn measure_view(
    images: &[Vec<u8>],
    at: &ViewAt,
    settings: &AnalysisSettings,
    inspect: Option<&Path>,
) -> Result<Vec<TransitionAnalysis>, Error> {
    let res = at.res;
    let luv: Vec<LuvImage> = images
        .par_iter()
        .map(|im| segment::rgba_to_luv(res, res, im))
        .collect::<Result<_, _>>()?;
    let regions: Vec<Regions> = if settings.grouping == Grouping::Regions {
        luv.par_iter()
            .map(|im| segment::grow_regions(im, settings.threshold_delta_e))
            .collect()
    } else {
        Vec::new()
    };
    let prefix = format!("d{res:03}_view{:03}", at.view);
    if let Some(dir) = inspect {
        for (i, im) in images.iter().enumerate() {
            write_png(&dir.join(format!("{prefix}_lod{i}.png")), res, im)?;
        }
    }
    let feature_settings = FeatureSettings {
        grouping: settings.grouping,
        threshold_delta_e: settings.threshold_delta_e,
        min_change_delta_e: settings.min_change_delta_e,
        feret_directions: settings.feret_directions,
        statistic: settings.statistic,
    };
    (0..images.len() - 1)
        .into_par_iter()
        .map(|t| {
            let pair = regions.get(t + 1).map(|r| (&regions[0], r));
            let (features, labels) =
                features::unique_features(&luv[0], &luv[t + 1], pair, &feature_settings)?;
            if let Some(dir) = inspect {
                write_png(
                    &dir.join(format!("{prefix}_t0-{}_features.png", t + 1)),
                    res,
                    &feature_image(&labels),
                )?;
            }
            Ok(transition_from(&features, at.diameter_px))
        })
        .collect()
}

/// Builds a [`TransitionAnalysis`] from measured features: frequencies in
/// c/diam for a bounding sphere `diameter_px` across, those with contrast
/// grouped with their like ([`features::summarise`]; at most the profile
/// format's limit of records, the most visible kept).
pub fn transition_from(features: &[UniqueFeature], diameter_px: f32) -> TransitionAnalysis {
    let all: Vec<Visibility> = features
        .iter()
        .map(|f| Visibility {
            freq: f.freq_cpx * diameter_px,
            area: f.shape.pixel_count as f32 / (diameter_px * diameter_px),
            luminance: f.luminance,
            masker: f.masker,
        })
        .collect();
    let mut summary = features::summarise(&all);
    let cap = acuity::profile::MAX_FEATURES;
    if summary.len() > cap {
        let records: Vec<Visibility> = summary.iter().map(|s| s.0).collect();
        summary = features::kept_features(&records, cap)
            .into_iter()
            .map(|i| summary[i])
            .collect();
    }
    TransitionAnalysis {
        feature_count: features.len() as u32,
        features: summary
            .into_iter()
            .map(|(f, count)| FeatureRecord {
                freq_cdiam: f.freq,
                area_diam2: f.area,
                luminance: f.luminance,
                masker: f.masker,
                count,
            })
            .collect(),
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

/// `name` with every character but ASCII letters, digits, `-` and `_`
/// replaced by `_`: a file name on every platform (profiles and inspection
/// folders are named by it; two names that give the same one collide).
pub fn file_safe_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn sanitize(name: &str) -> String {
    let s = file_safe_name(name);
    if s.is_empty() { "_".into() } else { s }
}
