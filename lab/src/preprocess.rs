//! `acuity preprocess`: the offline pass on a scene file or one mesh file
//! (OBJ or glTF), writing one runtime profile per object.
//!
//! - **Inputs.** A scene file (`.toml`): every object in it. `lods = [...]`
//!   objects are analysed from their files, `mesh` + `generate_triangles`
//!   objects from LODs simplified from the mesh, and `procedural` objects
//!   from the offline pass's generators (see [`crate::profiles::object_source`]). Or one
//!   mesh file (`.obj`, `.gltf`, `.glb`): a glTF that carries an LOD chain
//!   (`MSFT_lod`, or nodes named `*_LOD<n>`) is analysed as it is; otherwise
//!   its LODs are generated at `--triangles`, or without them the mesh is
//!   kept whole: LOD 0 is the mesh as given, each coarser LOD a quarter of
//!   the one before, down to 32 triangles, at most four LODs (a
//!   5,120-triangle mesh: 5120/1280/320/80). The object is named after the
//!   file stem.
//! - **Cache.** Profiles go to `--out` (default `<dir of PATH>/.acuity-cache/`)
//!   as `<object>.acp` ([`profiles::cache_path`]). An object whose input
//!   files, generation parameters and settings hash as recorded in its
//!   profile is not rendered again ([`profiles::cached_profile`]); the
//!   command says `cached` for it. `--force` and `--inspect` analyse every
//!   object regardless.
//! - **Rendering.** One [`Renderer`] (one device) for all objects, created
//!   only when some object needs analysing, so a fully cached run never
//!   opens a device. Objects are analysed one after the other, each in
//!   parallel over its viewpoints (`--jobs` sets the rayon pool size).
//! - **Errors.** A failing object is reported on stderr with the file and
//!   line its error carries, and the others are still analysed. Exit code:
//!   0 when every object has a profile, 1 when any object failed or no
//!   renderer could be made,
//!   2 for bad arguments (including a PATH that is not a readable scene or
//!   mesh file, or a scene file that does not parse).
//! - **Export.** `--export-lods` writes each object's analysed LOD chain
//!   beside its profile ([`profiles::export_lods`]) and records the files'
//!   hashes in it, so what ships is exactly what was measured.
//! - **Report.** A table on stdout: object, LOD triangles, viewpoints, the
//!   median over viewpoints of each transition's critical frequency at the
//!   largest rung ([`median_critical_cdiam`]; c/diam, `none` where nothing
//!   visible changes), cached/analysed, seconds.

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use acuity_preprocess::lods;
use acuity_preprocess::pipeline::{AnalysisSettings, ObjectSource, Progress, RunOptions};
use acuity_preprocess::views;
use acuity_render::{Renderer, RendererOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::library::Job;
use crate::profiles::{self, object_source};
use crate::scene::{ProfileSpec, Scene};
use acuity::rows::{FieldCsfs, transition_critical_cdiam};
use acuity::{Observer, Photometry, Profile, csf::Csf};

/// Arguments of `acuity preprocess`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct PreprocessArgs {
    /// A scene file (.toml: every object in it), one mesh (.obj, .gltf,
    /// .glb: its LODs are generated with --triangles, or a glTF's own chain
    /// is used), a folder of meshes or a manifest (.txt) listing them, one
    /// object each (an asset library).
    pub path: PathBuf,
    /// LOD triangle targets for mesh files, finest first, strictly
    /// decreasing (Reddy 1998's chain: 3928,834,254,76) [default: the mesh
    /// kept whole as LOD 0, then quarters of it down to 32 triangles, at
    /// most 4 LODs; a glTF with its own chain: that chain].
    #[cfg_attr(
        feature = "clap",
        arg(long, value_delimiter = ',', value_name = "N,N,...")
    )]
    pub triangles: Option<Vec<u32>>,
    /// Worker threads for the analysis (rayon pool size) [default: one per
    /// CPU core].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(1..=1024)))]
    pub jobs: Option<u32>,
    /// Square rendering size in pixels (16..=8192) [default: a scene's
    /// `[profiles]`, else 512].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(AnalysisSettings::MIN_RESOLUTION_PX as i64..=AnalysisSettings::MAX_RESOLUTION_PX as i64)))]
    pub resolution: Option<u32>,
    /// Smallest rung of the size ladder, pixels: rungs halve from
    /// `--resolution` down to it [default: the scene's `[profiles]`, else
    /// 16].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(AnalysisSettings::MIN_DIAMETER_PX as i64..=AnalysisSettings::MAX_RESOLUTION_PX as i64)))]
    pub min_diameter: Option<u32>,
    /// MSAA samples (1: none) [default: the scene's `[profiles]`, else 4].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(1..=16)))]
    pub msaa: Option<u32>,
    /// View-sphere subdivision level: 0 -> 6 viewpoints, 1 -> 18, 2 -> 66,
    /// 3 -> 258, ... (0..=6) [default: a scene's `[profiles]`, else 1].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(0..=AnalysisSettings::MAX_VIEWPOINT_LEVEL as i64)))]
    pub viewpoints: Option<u32>,
    /// Just-noticeable colour difference, ΔE*uv (> 0), for region growing
    /// [default: a scene's `[profiles]`, else 2.3].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_threshold))]
    pub threshold: Option<f32>,
    /// A pixel counts as changed where two LODs' renderings differ by more
    /// than this, ΔE*uv (>= 0); 0 counts any difference [default: a
    /// scene's `[profiles]`, else 1].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_min_change))]
    pub min_change: Option<f32>,
    /// Feature-size statistic: `mean` (a feature's extent averaged over
    /// orientations), `longest` (the lowest frequency it could be seen
    /// at), `thickness` (diameter of the largest inscribed disc: a thin
    /// sliver is as fine as its width, however long) or `shortest`
    /// [default: a scene's `[profiles]`, else mean].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_statistic))]
    pub statistic: Option<acuity_preprocess::FrequencyStatistic>,
    /// Folder for the profiles (NAME.acp, one per object) [default:
    /// .acuity-cache in the folder of PATH].
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: Option<PathBuf>,
    /// Write every rendered view and every transition's unique features as
    /// PNGs under this folder (analyses cached objects again).
    #[cfg_attr(feature = "clap", arg(long))]
    pub inspect: Option<PathBuf>,
    /// Also write each profile as JSON (NAME.json beside NAME.acp).
    #[cfg_attr(feature = "clap", arg(long))]
    pub json: bool,
    /// Analyse every object even when its cached profile is up to date.
    #[cfg_attr(feature = "clap", arg(long))]
    pub force: bool,
    /// Also write each object's analysed LOD chain beside its profile:
    /// NAME.lods.glb (every LOD) and `NAME_lod<k>.obj` (+ NAME.mtl, and
    /// NAME_basecolor.png when textured); the profile records each file's
    /// hash.
    #[cfg_attr(feature = "clap", arg(long))]
    pub export_lods: bool,
    /// Process only shard K of N (1 <= K <= N): a deterministic subset of
    /// the objects by the hash of their names, for batch systems that run
    /// the shards of a library (see `crate::library`).
    #[cfg_attr(feature = "clap", arg(long, value_name = "K/N", value_parser = crate::library::parse_shard))]
    pub shard: Option<crate::library::Shard>,
    /// Render nothing: check that every object (of the shard, if given) has
    /// an up-to-date profile in the profile folder; exit 1 naming those
    /// that have none or a stale one (the merge step of sharded runs).
    #[cfg_attr(feature = "clap", arg(long))]
    pub check: bool,
    /// Also write the summary table as CSV to this file.
    #[cfg_attr(feature = "clap", arg(long, value_name = "FILE"))]
    pub csv: Option<PathBuf>,
}

/// Why `acuity preprocess` failed: unusable arguments (the input's fault)
/// or objects that failed while running.
#[derive(Debug, thiserror::Error)]
pub enum PreprocessError {
    /// The arguments are unusable (the input's fault).
    #[error("{0}")]
    Usage(String),
    /// Some objects failed; each was reported as it failed.
    #[error("{failed} of {total} objects failed")]
    ObjectsFailed {
        /// Objects that failed.
        failed: usize,
        /// Objects in the input.
        total: usize,
    },
}

/// The objects named by `args.path`, the default profile folder, and a
/// scene's `[profiles]` (none for a mesh file).
fn jobs_for(args: &PreprocessArgs) -> Result<(Vec<Job>, PathBuf, ProfileSpec), PreprocessError> {
    let path = &args.path;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let default_out = path.parent().unwrap_or(Path::new("")).join(".acuity-cache");
    if path.is_dir() {
        let assets = crate::library::folder_assets(path).map_err(PreprocessError::Usage)?;
        let jobs = assets
            .into_iter()
            .map(|(name, p)| mesh_job(name, &p, args.triangles.as_deref()))
            .collect::<Result<_, _>>()?;
        return Ok((jobs, path.join(".acuity-cache"), ProfileSpec::default()));
    }
    match ext.as_deref() {
        Some("toml") => {
            if args.triangles.is_some() {
                return Err(PreprocessError::Usage(
                    "--triangles applies to a single mesh file; a scene gives each object's LODs"
                        .into(),
                ));
            }
            let text = std::fs::read_to_string(path).map_err(|e| {
                PreprocessError::Usage(format!("{}: cannot read scene file: {e}", path.display()))
            })?;
            // `parse`, not `load`: a missing mesh file is that object's
            // error, not the whole scene's.
            let scene =
                Scene::parse(&text, path).map_err(|e| PreprocessError::Usage(e.to_string()))?;
            for o in scene.objects.iter().filter(|o| o.profile.is_some()) {
                if let Some(p) = &o.profile {
                    println!(
                        "{}: profile given by the scene ({}), not analysed",
                        o.name,
                        p.display()
                    );
                }
            }
            let jobs = scene
                .objects
                .iter()
                .filter(|o| o.profile.is_none())
                .map(|o| Job {
                    name: o.name.clone(),
                    source: object_source(&o.name, &o.source),
                })
                .collect();
            Ok((jobs, default_out, scene.profiles))
        }
        Some("obj" | "gltf" | "glb") => {
            if !path.is_file() {
                return Err(PreprocessError::Usage(format!(
                    "{}: no such file",
                    path.display()
                )));
            }
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "object".into());
            let job = mesh_job(name, path, args.triangles.as_deref())?;
            Ok((vec![job], default_out, ProfileSpec::default()))
        }
        Some("txt") => {
            let assets = crate::library::manifest_assets(path).map_err(PreprocessError::Usage)?;
            let jobs = assets
                .into_iter()
                .map(|(name, p)| mesh_job(name, &p, args.triangles.as_deref()))
                .collect::<Result<_, _>>()?;
            Ok((jobs, default_out, ProfileSpec::default()))
        }
        _ => Err(PreprocessError::Usage(format!(
            "{}: expected a scene file (.toml), a mesh (.obj, .gltf, .glb), a folder of meshes or a manifest (.txt)",
            path.display()
        ))),
    }
}

/// The job of one mesh file: a glTF that carries an LOD chain is analysed
/// as it is unless `triangles` asks for generated LODs; otherwise LODs are
/// generated at `triangles`, or, without them, the mesh is kept whole as
/// LOD 0 with coarser LODs of a quarter of the triangles each
/// ([`lods::whole_mesh_targets`]).
fn mesh_job(name: String, path: &Path, triangles: Option<&[u32]>) -> Result<Job, PreprocessError> {
    let source = match triangles {
        None if acuity_render::is_gltf(path) && gltf_carries_chain(path) => ObjectSource::Files {
            name: name.clone(),
            lod_paths: vec![path.to_owned()],
        },
        None => ObjectSource::Whole {
            name: name.clone(),
            path: path.to_owned(),
        },
        Some(targets) => {
            if let Err(e) = lods::check_targets(targets) {
                return Err(PreprocessError::Usage(format!("--triangles: {e}")));
            }
            ObjectSource::Generated {
                name: name.clone(),
                path: path.to_owned(),
                triangle_targets: targets.to_vec(),
            }
        }
    };
    Ok(Job { name, source })
}

/// Whether a glTF file carries an LOD chain of two or more levels. A file
/// that does not load counts as not (its error comes when it is analysed).
fn gltf_carries_chain(path: &Path) -> bool {
    acuity_render::gltf_mesh::load_gltf(path).is_ok_and(|g| g.lods.len() >= 2)
}

/// What happened to one object.
#[derive(Debug)]
enum Outcome {
    Cached(Profile),
    Analysed(Profile),
    /// Another object of the run has the same inputs and settings: its
    /// profile, saved under this object's name; nothing rendered.
    Shared(Profile),
    Failed(String),
}

impl Outcome {
    /// The object's profile, unless it failed.
    fn profile(&self) -> Option<&Profile> {
        match self {
            Outcome::Cached(p) | Outcome::Analysed(p) | Outcome::Shared(p) => Some(p),
            Outcome::Failed(_) => None,
        }
    }

    fn profile_mut(&mut self) -> Option<&mut Profile> {
        match self {
            Outcome::Cached(p) | Outcome::Analysed(p) | Outcome::Shared(p) => Some(p),
            Outcome::Failed(_) => None,
        }
    }
}

/// `profile`, made for another object of the same inputs and settings,
/// named and saved as `job`'s cached profile: [`Outcome::Shared`], or the
/// failure to save it.
fn share_profile(profile: &Profile, job: &Job, out_dir: &Path) -> Outcome {
    let save = || -> anyhow::Result<Profile> {
        let mut shared = profile.clone();
        shared.name = job.name.clone();
        std::fs::create_dir_all(out_dir)?;
        shared.save(profiles::cache_path(out_dir, &job.source))?;
        Ok(shared)
    };
    match save() {
        Ok(p) => Outcome::Shared(p),
        Err(e) => Outcome::Failed(crate::error::error_line(&e)),
    }
}

/// One row of the final table.
#[derive(Debug)]
struct Row {
    name: String,
    outcome: Outcome,
    seconds: f64,
}

/// Runs `acuity preprocess`; see the module docs. Per-object results and
/// the table go to stdout, errors and the progress bar to stderr.
pub fn run(args: &PreprocessArgs) -> anyhow::Result<()> {
    let (mut jobs, default_out, scene_spec) = jobs_for(args)?;
    if let Some(shard) = args.shard {
        jobs.retain(|j| shard.contains(&j.name));
        println!(
            "shard {}/{}: {} object(s) of this run",
            shard.k,
            shard.n,
            jobs.len()
        );
    }
    let flags = ProfileSpec {
        resolution_px: args.resolution,
        min_diameter_px: args.min_diameter,
        msaa_samples: args.msaa,
        viewpoint_level: args.viewpoints,
        threshold_delta_e: args.threshold,
        min_change_delta_e: args.min_change,
        statistic: args.statistic,
    };
    let settings = scene_spec.overridden_by(flags).analysis_settings();
    settings
        .validate()
        .map_err(|e| PreprocessError::Usage(e.to_string()))?;
    let out_dir = args.out.clone().unwrap_or(default_out);
    profiles::check_distinct_cache_paths(&out_dir, jobs.iter().map(|j| &j.source))
        .map_err(PreprocessError::Usage)?;
    crate::limits::check_generated_meshes(jobs.iter().map(|j| &j.source))
        .map_err(PreprocessError::Usage)?;
    if args.check {
        return crate::library::check_profiles(&jobs, &settings, &out_dir, args.shard.is_none());
    }
    let rows = match args.jobs {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build()?
            .install(|| process(args, &settings, &jobs, &out_dir)),
        None => process(args, &settings, &jobs, &out_dir),
    };
    print!("{}", table(&rows));
    if let Some(csv) = &args.csv {
        std::fs::write(csv, summary_csv(&rows))
            .map_err(|e| anyhow::anyhow!("{}: cannot write CSV: {e}", csv.display()))?;
    }
    let failed = rows
        .iter()
        .filter(|r| matches!(r.outcome, Outcome::Failed(_)))
        .count();
    if failed > 0 {
        return Err(PreprocessError::ObjectsFailed {
            failed,
            total: rows.len(),
        }
        .into());
    }
    Ok(())
}

fn process(
    args: &PreprocessArgs,
    settings: &AnalysisSettings,
    jobs: &[Job],
    out_dir: &Path,
) -> Vec<Row> {
    let analyse_all = args.force || args.inspect.is_some();
    // Each object's inputs hashed once: for the cache and to find objects
    // with the same inputs and settings (one mesh under two names), which
    // share one analysis. `made`: the objects whose profile is made.
    let keys: Vec<anyhow::Result<Vec<String>>> = jobs
        .iter()
        .map(|j| profiles::input_key(&j.source, settings))
        .collect();
    let mut made: Vec<usize> = Vec::new();
    let made_alike = |made: &[usize], i: usize| {
        let key = keys[i].as_ref().ok()?;
        made.iter()
            .copied()
            .find(|&k| keys[k].as_ref().is_ok_and(|other| other == key))
    };
    // First pass, hashing only: which objects are cached, or share a
    // cached object's profile.
    let mut rows: Vec<Option<Row>> = Vec::with_capacity(jobs.len());
    let mut to_analyse = Vec::new();
    for (i, j) in jobs.iter().enumerate() {
        let t0 = Instant::now();
        let row = |outcome| {
            Some(Row {
                name: j.name.clone(),
                outcome,
                seconds: t0.elapsed().as_secs_f64(),
            })
        };
        if analyse_all {
            rows.push(None);
            to_analyse.push(i);
            continue;
        }
        let cached = keys[i]
            .as_ref()
            .map(|key| profiles::cached_profile(&j.source, key, settings, out_dir));
        match cached {
            Ok(Some(p)) => {
                made.push(i);
                rows.push(row(Outcome::Cached(p)));
            }
            Ok(None) => {
                rows.push(None);
                to_analyse.push(i);
            }
            Err(e) => rows.push(row(Outcome::Failed(crate::error::error_line(e)))),
        }
    }
    // Objects left to analyse that a cached object's profile serves.
    to_analyse.retain(|&i| {
        let Some(k) = made_alike(&made, i) else {
            return true;
        };
        let t0 = Instant::now();
        let Some(profile) = rows[k].as_ref().and_then(|r| r.outcome.profile()) else {
            return true;
        };
        let outcome = share_profile(profile, &jobs[i], out_dir);
        rows[i] = Some(Row {
            name: jobs[i].name.clone(),
            outcome,
            seconds: t0.elapsed().as_secs_f64(),
        });
        false
    });

    let views_per_object =
        views::viewpoint_count(settings.viewpoint_level) * settings.diameters_px().len();
    let bar = progress_bar((to_analyse.len() * views_per_object) as u64);
    let shown = AtomicBool::new(false);
    let tty = std::io::stderr().is_terminal();
    let started = Instant::now();
    let on_progress = |_: &Progress<'_>| {
        // Appear only for work that takes more than a second.
        if tty
            && started.elapsed() > Duration::from_secs(1)
            && shown
                .compare_exchange(false, true, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
        {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.inc(1);
    };
    let run = RunOptions {
        inspect_dir: args.inspect.as_deref(),
        progress: Some(&on_progress),
    };

    // Report the first pass, in input order.
    for (i, (j, r)) in jobs.iter().zip(&rows).enumerate() {
        match r.as_ref().map(|r| &r.outcome) {
            Some(Outcome::Cached(_)) => {
                println!("{}: cached (inputs unchanged, nothing rendered)", j.name)
            }
            Some(Outcome::Shared(_)) => println!(
                "{}: shared with `{}` (the same inputs and settings, nothing rendered)",
                j.name,
                made_alike(&made, i).map_or("?", |k| jobs[k].name.as_str())
            ),
            Some(Outcome::Failed(e)) => eprintln!("error: object `{}`: {e}", j.name),
            _ => {}
        }
    }

    let mut renderer: Option<Result<Renderer, String>> = None;
    for &i in &to_analyse {
        let j = &jobs[i];
        let src = &j.source;
        let t0 = Instant::now();
        // An object analysed earlier in this loop serves this one.
        if let Some(k) = made_alike(&made, i)
            && let Some(p) = rows[k].as_ref().and_then(|r| r.outcome.profile())
        {
            let outcome = share_profile(p, j, out_dir);
            bar.suspend(|| match &outcome {
                Outcome::Failed(e) => eprintln!("error: object `{}`: {e}", j.name),
                _ => println!(
                    "{}: shared with `{}` (the same inputs and settings, nothing rendered)",
                    j.name, jobs[k].name
                ),
            });
            bar.inc(views_per_object as u64);
            rows[i] = Some(Row {
                name: j.name.clone(),
                outcome,
                seconds: t0.elapsed().as_secs_f64(),
            });
            continue;
        }
        bar.set_message(j.name.clone());
        let r = renderer.get_or_insert_with(|| {
            let r = Renderer::new(&RendererOptions {
                msaa_samples: settings.msaa_samples,
            })
            .map_err(|e| e.to_string());
            if let Ok(r) = &r {
                bar.suspend(|| eprintln!("renderer: {}", r.adapter_info()));
            }
            r
        });
        let outcome = match r {
            Err(e) => Outcome::Failed(format!("no renderer: {e}")),
            Ok(r) => match profiles::analyse_to_cache(r, src, settings, out_dir, &run) {
                Ok((p, warnings)) => {
                    bar.suspend(|| {
                        for w in warnings {
                            eprintln!("warning: object `{}`: {w}", j.name);
                        }
                    });
                    made.push(i);
                    Outcome::Analysed(p)
                }
                Err(e) => Outcome::Failed(crate::error::error_line(&e)),
            },
        };
        let seconds = t0.elapsed().as_secs_f64();
        bar.suspend(|| match &outcome {
            Outcome::Analysed(p) => println!(
                "{}: analysed ({} viewpoints, {} LODs, {seconds:.2} s)",
                j.name,
                p.viewpoints.len(),
                p.lod_count()
            ),
            Outcome::Failed(e) => eprintln!("error: object `{}`: {e}", j.name),
            _ => {}
        });
        rows[i] = Some(Row {
            name: j.name.clone(),
            outcome,
            seconds,
        });
    }
    bar.finish_and_clear();

    let mut rows: Vec<Row> = rows.into_iter().flatten().collect();
    if args.export_lods {
        for (row, j) in rows.iter_mut().zip(jobs) {
            let Some(p) = row.outcome.profile_mut() else {
                continue;
            };
            match profiles::export_lods(&j.source, p, out_dir) {
                Ok(files) => println!("{}: exported {} LOD files", j.name, files.len()),
                Err(e) => {
                    let line = crate::error::error_line(&e);
                    eprintln!("error: object `{}`: {line}", j.name);
                    row.outcome = Outcome::Failed(line);
                }
            }
        }
    }
    if args.json {
        for (row, j) in rows.iter_mut().zip(jobs) {
            let Some(p) = row.outcome.profile() else {
                continue;
            };
            let src = &j.source;
            let path = profiles::cache_path(out_dir, src).with_extension("json");
            if let Err(e) = write_json_if_changed(p, &path) {
                let line = crate::error::error_line(&e);
                eprintln!("error: object `{}`: {line}", j.name);
                row.outcome = Outcome::Failed(line);
            }
        }
    }
    rows
}

/// Writes `profile` as JSON to `path` unless the file already holds exactly
/// those bytes (so a cached run leaves it untouched).
fn write_json_if_changed(profile: &Profile, path: &Path) -> anyhow::Result<()> {
    let bytes = acuity::profile::json::encode(profile)?;
    if std::fs::read(path).is_ok_and(|old| old == bytes) {
        return Ok(());
    }
    profile.save(path)?;
    Ok(())
}

fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
    if let Ok(style) =
        ProgressStyle::with_template("{bar:30} {pos}/{len} views  {elapsed_precise}  {msg}")
    {
        bar.set_style(style);
    }
    bar
}

/// Median over viewpoints of each transition's critical frequency at the
/// largest rung of the size ladder, c/diam ([`transition_critical_cdiam`]
/// under the default display photometry and observer, on a display of 30
/// pixels per degree): the transition is
/// invisible on an object of `theta` deg at rest in the fovea while this
/// exceeds `60 theta` (a viewpoint without visible features counts as
/// infinite).
pub fn median_critical_cdiam(profile: &Profile) -> Vec<f32> {
    let photometry = Photometry::default();
    let Ok(csf) = Csf::new(&photometry, &Observer::default()) else {
        return Vec::new();
    };
    let mut csfs = FieldCsfs::new(&csf);
    let top = profile.rung_diameters_px.len().saturating_sub(1);
    // The largest rung on a desktop display of 30 pixels per degree.
    let diameter_deg = profile.rung_diameters_px.get(top).map_or(1.0, |d| d / 30.0);
    (0..profile.transitions_per_view())
        .map(|t| {
            let mut v: Vec<f32> = (0..profile.viewpoints.len())
                .map(|view| {
                    let features = &profile.transitions_at(view, top)[t].features;
                    transition_critical_cdiam(features, diameter_deg, &photometry, &mut csfs)
                })
                .collect();
            v.sort_by(f32::total_cmp);
            match v.len() {
                0 => f32::INFINITY,
                n if n % 2 == 1 => v[n / 2],
                n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
            }
        })
        .collect()
}

/// The summary as CSV: one line per object (critical frequencies joined
/// by `/`, `inf` where nothing visible changes).
fn summary_csv(rows: &[Row]) -> String {
    let mut out =
        String::from("object,result,lod_triangles,viewpoints,critical_cdiam,seconds,error\n");
    for r in rows {
        let (p, result, error) = match &r.outcome {
            Outcome::Cached(p) => (Some(p), "cached", ""),
            Outcome::Analysed(p) => (Some(p), "analysed", ""),
            Outcome::Shared(p) => (Some(p), "shared", ""),
            Outcome::Failed(e) => (None, "failed", e.as_str()),
        };
        let join = |v: Vec<String>| v.join("/");
        let lods = p.map_or_else(String::new, |p| {
            join(p.lod_triangles.iter().map(u32::to_string).collect())
        });
        let views = p.map_or_else(String::new, |p| p.viewpoints.len().to_string());
        let freqs = p.map_or_else(String::new, |p| {
            join(
                median_critical_cdiam(p)
                    .iter()
                    .map(|f| {
                        if f.is_finite() {
                            format!("{f:.3}")
                        } else {
                            "inf".into()
                        }
                    })
                    .collect(),
            )
        });
        let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
        out.push_str(&format!(
            "{},{result},{lods},{views},{freqs},{:.3},{}\n",
            quote(&r.name),
            r.seconds,
            quote(error)
        ));
    }
    out
}

fn table(rows: &[Row]) -> String {
    let header = [
        "object",
        "LODs (triangles)",
        "viewpoints",
        "critical c/diam per transition (median)",
        "result",
        "s",
    ];
    let cells: Vec<[String; 6]> = rows
        .iter()
        .map(|r| {
            let (profile, result) = match &r.outcome {
                Outcome::Cached(p) => (Some(p), "cached".to_string()),
                Outcome::Analysed(p) => (Some(p), "analysed".to_string()),
                Outcome::Shared(p) => (Some(p), "shared".to_string()),
                Outcome::Failed(_) => (None, "FAILED".to_string()),
            };
            let dash = || "-".to_string();
            let lods = profile.map_or_else(dash, |p| {
                p.lod_triangles
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join("/")
            });
            let views = profile.map_or_else(dash, |p| p.viewpoints.len().to_string());
            let freqs = profile.map_or_else(dash, |p| {
                median_critical_cdiam(p)
                    .iter()
                    .map(|f| {
                        if f.is_finite() {
                            format!("{f:.1}")
                        } else {
                            "none".into()
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(" / ")
            });
            [
                r.name.clone(),
                lods,
                views,
                freqs,
                result,
                format!("{:.2}", r.seconds),
            ]
        })
        .collect();
    let mut width = header.map(|h| h.chars().count());
    for c in &cells {
        for (w, s) in width.iter_mut().zip(c) {
            *w = (*w).max(s.chars().count());
        }
    }
    let mut out = String::new();
    let mut line = |cols: &[&str]| {
        let mut l = String::new();
        for (i, (c, w)) in cols.iter().zip(width).enumerate() {
            if i > 0 {
                l.push_str("  ");
            }
            let _ = write!(l, "{c:<w$}");
        }
        let _ = writeln!(out, "{}", l.trim_end());
    };
    line(&header);
    let rule: Vec<String> = width.iter().map(|&w| "-".repeat(w)).collect();
    line(&rule.iter().map(String::as_str).collect::<Vec<_>>());
    for c in &cells {
        line(&c.iter().map(String::as_str).collect::<Vec<_>>());
    }
    out
}
