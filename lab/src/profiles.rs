//! From the offline pass's plain data to runtime profiles, with a cache:
//! an object whose inputs and settings hash as before is not analysed again.

use std::path::{Path, PathBuf};

use acuity_preprocess::lods::ProceduralParams;
use acuity_preprocess::pipeline::{
    self, AnalysisSettings, ObjectAnalysis, ObjectSource, RunOptions,
};
use acuity_preprocess::shapes::Shape;
use acuity_render::Renderer;

use acuity::profile::{Feature, InputHash, PROFILE_FORMAT_VERSION, Profile, TransitionFeatures};

use crate::scene::{MeshSource, ProceduralKind};

/// Where a profile came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CacheOutcome {
    /// The cached profile matched every input hash: nothing was rendered.
    Cached,
    /// The object was analysed (no cache, or an input or setting changed).
    Analysed,
    /// The scene named a ready-made profile, made from the same inputs.
    Given,
    /// Another object of the scene with the same inputs and settings had
    /// it: one analysis for both.
    Shared,
}

/// The analysis settings as the profile records them.
pub fn settings_record(settings: &AnalysisSettings) -> std::collections::BTreeMap<String, String> {
    [
        ("resolution_px", settings.resolution_px.to_string()),
        ("min_diameter_px", settings.min_diameter_px.to_string()),
        ("viewpoint_level", settings.viewpoint_level.to_string()),
        ("grouping", format!("{:?}", settings.grouping)),
        ("threshold_delta_e", settings.threshold_delta_e.to_string()),
        (
            "min_change_delta_e",
            settings.min_change_delta_e.to_string(),
        ),
        ("feret_directions", settings.feret_directions.to_string()),
        ("msaa_samples", settings.msaa_samples.to_string()),
        ("statistic", format!("{:?}", settings.statistic)),
        ("background_srgb", format!("{:?}", settings.background_srgb)),
        ("analysis_version", pipeline::ANALYSIS_VERSION.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v))
    .collect()
}

/// Converts an analysis into a runtime profile (the same features, the
/// ladder's diameters as `f32`).
pub fn profile_from_analysis(analysis: &ObjectAnalysis, settings: &AnalysisSettings) -> Profile {
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: analysis.name.clone(),
        lod_triangles: analysis.lod_triangles.clone(),
        bounding_radius: analysis.bounding_sphere.1,
        viewpoints: analysis.viewpoints.clone(),
        rung_diameters_px: analysis.diameters_px.iter().map(|&d| d as f32).collect(),
        transitions: analysis
            .transitions
            .iter()
            .map(|t| TransitionFeatures {
                feature_count: t.feature_count,
                features: t
                    .features
                    .iter()
                    .map(|f| Feature {
                        freq_cdiam: f.freq_cdiam,
                        area_diam2: f.area_diam2,
                        luminance: f.luminance,
                        masker: f.masker,
                        count: f.count,
                    })
                    .collect(),
            })
            .collect(),
        settings: settings_record(settings),
        inputs: analysis
            .input_hashes
            .iter()
            .map(|h| InputHash {
                what: h.what.clone(),
                hash_hex: h.hash_hex.clone(),
            })
            .collect(),
    }
}

/// The cache file of an object: `<cache_dir>/<name>.acp` (binary profile).
pub fn cache_path(cache_dir: &Path, object: &ObjectSource) -> PathBuf {
    let safe = pipeline::file_safe_name(object.name());
    cache_dir.join(format!("{safe}.acp"))
}

/// Refuses objects whose profiles would share a file in `cache_dir`:
/// distinct names can map to one file name once sanitised (`a b` and `a_b`
/// both to `a_b.acp`, see [`cache_path`]). The reason names both objects
/// and the file.
pub fn check_distinct_cache_paths<'a>(
    cache_dir: &Path,
    objects: impl IntoIterator<Item = &'a ObjectSource>,
) -> Result<(), String> {
    let mut seen = std::collections::HashMap::new();
    for o in objects {
        let path = cache_path(cache_dir, o);
        if let Some(other) = seen.insert(path.clone(), o.name()) {
            return Err(format!(
                "objects `{other}` and `{}` would share the profile file {}; rename one",
                o.name(),
                path.display()
            ));
        }
    }
    Ok(())
}

/// What the profile cache holds for an object.
#[derive(Debug, Clone, PartialEq)]
pub enum CacheState {
    /// A profile whose recorded input hashes and settings equal the
    /// current ones.
    Fresh(Profile),
    /// No profile file.
    Missing,
    /// A readable profile of other inputs or settings.
    Stale,
    /// A file that is no usable profile (corrupt, of an older or newer
    /// format, not a regular file); why.
    Unusable(String),
}

/// What makes two objects' profiles the same, and a cached one fresh: the
/// content hashes (hex) of the object's inputs (files, generation
/// parameters) under `settings`, in order, whatever the paths they were
/// read from. Hashing reads the inputs (an unreadable input file is an
/// error) but renders nothing.
pub fn input_key(
    object: &ObjectSource,
    settings: &AnalysisSettings,
) -> anyhow::Result<Vec<String>> {
    let hashes = pipeline::input_hashes(object, settings)?;
    Ok(hashes.into_iter().map(|h| h.hash_hex).collect())
}

/// What `cache_dir` holds for `object` under `settings`: a profile is
/// fresh when the content hashes of its inputs ([`input_key`]) and its
/// settings equal the current ones.
pub fn cache_state(
    object: &ObjectSource,
    settings: &AnalysisSettings,
    cache_dir: &Path,
) -> anyhow::Result<CacheState> {
    let key = input_key(object, settings)?;
    Ok(cache_state_of(object, &key, settings, cache_dir))
}

/// [`cache_state`] for an object whose [`input_key`] is `key`.
fn cache_state_of(
    object: &ObjectSource,
    key: &[String],
    settings: &AnalysisSettings,
    cache_dir: &Path,
) -> CacheState {
    let path = cache_path(cache_dir, object);
    let cached = match Profile::load(&path) {
        Ok(p) => p,
        Err(e) => {
            return match unusable(&e, &path) {
                Some(why) => CacheState::Unusable(why),
                None => CacheState::Missing,
            };
        }
    };
    let inputs: Vec<&InputHash> = cached
        .inputs
        .iter()
        .filter(|h| !h.what.starts_with(EXPORTED_PREFIX))
        .collect();
    // Contents, not names: the recorded `what` (a path as it was spelled,
    // relative to wherever the command ran) is for humans, so the same
    // bytes hit the same profile from any folder, spelling or checkout.
    let same = inputs.len() == key.len() && inputs.iter().zip(key).all(|(a, b)| a.hash_hex == *b);
    if same && cached.settings == settings_record(settings) {
        CacheState::Fresh(cached)
    } else {
        CacheState::Stale
    }
}

/// The cached profile of an object whose [`input_key`] is `key`, when
/// `cache_dir` holds one whose recorded input hashes and settings equal
/// the current ones ([`cache_state`]); `None` when there is none, it is
/// unusable, or anything changed. An unusable one is reported on stderr as
/// a warning line, since the caller analyses the object again and replaces
/// it.
pub fn cached_profile(
    object: &ObjectSource,
    key: &[String],
    settings: &AnalysisSettings,
    cache_dir: &Path,
) -> Option<Profile> {
    match cache_state_of(object, key, settings, cache_dir) {
        CacheState::Fresh(p) => Some(p),
        CacheState::Unusable(why) => {
            eprintln!(
                "warning: {}: cached profile {why}; analysing `{}` again to replace it",
                cache_path(cache_dir, object).display(),
                object.name()
            );
            None
        }
        CacheState::Missing | CacheState::Stale => None,
    }
}

/// Why the cached profile at `path`, which failed to load with `e`, is
/// unusable; `None` when there is no file to replace.
fn unusable(e: &acuity::Error, path: &Path) -> Option<String> {
    use std::cmp::Ordering;
    match e {
        acuity::Error::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => None,
        acuity::Error::Io { source, .. } => Some(format!("cannot be read: {source}")),
        acuity::Error::ProfileVersion {
            found, supported, ..
        } => {
            let age = match found.cmp(supported) {
                Ordering::Less => "an older",
                _ => "a newer",
            };
            Some(format!(
                "has {age} format version ({found}; this build reads {supported})"
            ))
        }
        _ => {
            let text = e.to_string();
            let prefix = format!("{}: ", path.display());
            Some(format!(
                "is corrupt ({})",
                text.strip_prefix(&prefix).unwrap_or(&text)
            ))
        }
    }
}

/// Analyses an object with `renderer` and writes its profile to
/// [`cache_path`] (creating `cache_dir`), whatever the cache holds.
/// Returns the profile and the loader's non-fatal warnings.
pub fn analyse_to_cache(
    renderer: &Renderer,
    object: &ObjectSource,
    settings: &AnalysisSettings,
    cache_dir: &Path,
    run: &RunOptions<'_>,
) -> anyhow::Result<(Profile, Vec<String>)> {
    let analysis = pipeline::analyse(renderer, object, settings, run)?;
    let profile = profile_from_analysis(&analysis, settings);
    std::fs::create_dir_all(cache_dir)?;
    profile.save(cache_path(cache_dir, object))?;
    Ok((profile, analysis.warnings))
}

/// The profile of an object whose [`input_key`] is `key`: from
/// `cache_dir` when its recorded input hashes (which cover the files, the
/// generation parameters and the settings) equal the current ones
/// ([`cached_profile`]), else analysed with `renderer` and written there
/// ([`analyse_to_cache`]).
pub fn ensure_profile(
    renderer: &Renderer,
    object: &ObjectSource,
    key: &[String],
    settings: &AnalysisSettings,
    cache_dir: &Path,
    run: &RunOptions<'_>,
) -> anyhow::Result<(Profile, CacheOutcome)> {
    if let Some(cached) = cached_profile(object, key, settings, cache_dir) {
        return Ok((cached, CacheOutcome::Cached));
    }
    let (profile, _warnings) = analyse_to_cache(renderer, object, settings, cache_dir, run)?;
    Ok((profile, CacheOutcome::Analysed))
}

/// A ready-made profile of `object`'s LODs, read from `path`: its
/// recorded input hashes (files, generation parameters; not the analysis
/// settings, which it keeps as made) must equal the LODs' contents, or the
/// LODs must be files its analysis exported (their contents recorded as
/// `exported:` entries); otherwise the error (an input error) names the
/// first input that differs.
pub fn given_profile(object: &ObjectSource, path: &Path) -> anyhow::Result<Profile> {
    let profile = Profile::load(path)?;
    let current = pipeline::input_hashes(object, &AnalysisSettings::default())?;
    // (what, content hash) of each input but the settings.
    let lods: Vec<(&str, &str)> = current
        .iter()
        .filter(|h| h.what != "settings")
        .map(|h| (h.what.as_str(), h.hash_hex.as_str()))
        .collect();
    let recorded: Vec<(&str, &str)> = profile
        .inputs
        .iter()
        .filter(|h| h.what != "settings" && !h.what.starts_with(EXPORTED_PREFIX))
        .map(|h| (h.what.as_str(), h.hash_hex.as_str()))
        .collect();
    // Or the LODs are files the profile's analysis exported
    // (`--export-lods`): each of their contents is one it recorded.
    let exported: Vec<&str> = profile
        .inputs
        .iter()
        .filter(|h| h.what.starts_with(EXPORTED_PREFIX))
        .map(|h| h.hash_hex.as_str())
        .collect();
    let is_export = !lods.is_empty() && lods.iter().all(|h| exported.contains(&h.1));
    if let (false, Some(k)) = (
        is_export,
        (0..lods.len().max(recorded.len()))
            .find(|&k| lods.get(k).map(|h| h.1) != recorded.get(k).map(|h| h.1)),
    ) {
        let name =
            |h: Option<&(&str, &str)>| h.map_or("nothing".to_owned(), |h| format!("`{}`", h.0));
        return Err(crate::error::input_error(format!(
            "{}: a profile of other inputs than object `{}`'s LODs: it records {} where the LODs have {} (analyse them with `acuity preprocess`, or name the profile made from them)",
            path.display(),
            object.name(),
            name(recorded.get(k)),
            name(lods.get(k)),
        )));
    }
    Ok(profile)
}

/// How a profile records a file `--export-lods` wrote: an entry of its
/// `inputs` named `exported:<file name>` with the file's BLAKE3. The
/// profile format has no field for outputs; these entries are not inputs
/// and the cache check skips them.
pub const EXPORTED_PREFIX: &str = "exported:";

/// Writes the LOD chain of `object` (loaded or generated again, exactly as
/// the analysis made it) beside its profile in `cache_dir`
/// ([`acuity_preprocess::export::export_lods`]), replaces the profile's
/// `exported:` records with the new files' hashes and saves the profile.
/// Checks that the chain has the profile's triangle counts. Returns the
/// files written.
pub fn export_lods(
    object: &ObjectSource,
    profile: &mut Profile,
    cache_dir: &Path,
) -> anyhow::Result<Vec<acuity_preprocess::export::ExportedFile>> {
    let (lods, _warnings) = object.load_lods()?;
    let counts: Vec<u32> = lods.iter().map(|m| m.triangle_count() as u32).collect();
    anyhow::ensure!(
        counts == profile.lod_triangles,
        "the LOD chain has {counts:?} triangles but its profile {:?}; analyse it again (--force)",
        profile.lod_triangles
    );
    let stem = pipeline::file_safe_name(object.name());
    let files = acuity_preprocess::export::export_lods(cache_dir, &stem, object.name(), &lods)?;
    profile
        .inputs
        .retain(|h| !h.what.starts_with(EXPORTED_PREFIX));
    profile.inputs.extend(files.iter().map(|f| InputHash {
        what: format!(
            "{EXPORTED_PREFIX}{}",
            f.path.file_name().unwrap_or_default().to_string_lossy()
        ),
        hash_hex: f.hash_hex.clone(),
    }));
    profile.save(cache_path(cache_dir, object))?;
    Ok(files)
}

/// Seed of the procedural generator for scene objects of kind `rock` (the
/// scene format has no seed for the shape; this one is fixed so profiles
/// are reproducible).
pub const PROCEDURAL_SEED: u32 = 1;

/// The offline pass's source for a scene object: files and generated LODs
/// map one to one; `rock` is the offline pass's bumpy, colour-banded torus
/// with bumps at three scales ([`acuity_preprocess::lods::procedural_object`], seed
/// [`PROCEDURAL_SEED`]) simplified to each target, `sphere` and `torus`
/// are [`Shape`]s tessellated at each target.
pub fn object_source(name: &str, source: &MeshSource) -> ObjectSource {
    match source {
        MeshSource::Lods(paths) => ObjectSource::Files {
            name: name.into(),
            lod_paths: paths.clone(),
        },
        MeshSource::Generated { mesh, triangles } => ObjectSource::Generated {
            name: name.into(),
            path: mesh.clone(),
            triangle_targets: triangles.clone(),
        },
        MeshSource::Whole { mesh } => ObjectSource::Whole {
            name: name.into(),
            path: mesh.clone(),
        },
        MeshSource::Procedural { kind, triangles } => match kind {
            ProceduralKind::Rock => ObjectSource::Procedural {
                name: name.into(),
                params: ProceduralParams {
                    triangles: triangles.first().copied().unwrap_or(0),
                    seed: PROCEDURAL_SEED,
                },
                triangle_targets: triangles.clone(),
            },
            ProceduralKind::Sphere | ProceduralKind::Torus => ObjectSource::Shape {
                name: name.into(),
                shape: match kind {
                    ProceduralKind::Sphere => Shape::Sphere,
                    _ => Shape::Torus,
                },
                triangle_targets: triangles.clone(),
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use acuity_preprocess::pipeline::{FeatureRecord, TransitionAnalysis};

    use super::*;

    #[test]
    fn analysis_becomes_a_valid_profile_with_every_feature() {
        let t = |f: &[(f32, [f32; 2])]| TransitionAnalysis {
            feature_count: 2 * f.len() as u32,
            features: f
                .iter()
                .map(|&(freq_cdiam, luminance)| FeatureRecord {
                    freq_cdiam,
                    area_diam2: 0.01,
                    luminance,
                    masker: luminance,
                    count: 1,
                })
                .collect(),
        };
        let analysis = ObjectAnalysis {
            name: "x".into(),
            lod_triangles: vec![100, 40, 10],
            bounding_sphere: ([0.0; 3], 1.5),
            viewpoints: vec![[0.0, 0.0, 1.0]],
            diameters_px: vec![16, 32],
            transitions: vec![
                t(&[(0.5, [0.0, 0.5]), (3.0, [0.1, 0.9])]),
                t(&[]),
                t(&[(8.0, [0.2, 0.3])]),
                t(&[]),
            ],
            input_hashes: vec![],
            warnings: vec![],
        };
        let p = profile_from_analysis(&analysis, &AnalysisSettings::default());
        p.validate().unwrap();
        assert_eq!(p.rung_diameters_px, [16.0, 32.0]);
        assert_eq!(p.transitions[0].feature_count, 4);
        assert_eq!(p.transitions[0].features[1].luminance, [0.1, 0.9]);
        assert_eq!(p.transitions_at(0, 1)[0].features[0].freq_cdiam, 8.0);
        assert!(p.transitions[1].features.is_empty());
    }

    #[test]
    fn names_that_sanitise_alike_are_refused() {
        let rock = |name: &str| ObjectSource::Procedural {
            name: name.into(),
            params: acuity_preprocess::lods::ProceduralParams {
                triangles: 100,
                seed: 1,
            },
            triangle_targets: vec![100, 10],
        };
        let (a, b, c) = (rock("a b"), rock("a_b"), rock("c"));
        let e = check_distinct_cache_paths(Path::new("cache"), [&a, &c, &b]).unwrap_err();
        assert!(
            e.contains("`a b` and `a_b`") && e.contains("a_b.acp"),
            "{e}"
        );
        assert!(check_distinct_cache_paths(Path::new("cache"), [&a, &c]).is_ok());
    }

    #[test]
    fn a_missing_cache_file_is_quiet_and_a_bad_one_says_why() {
        let io = |kind| acuity::Error::Io {
            path: "x.acp".into(),
            source: std::io::Error::from(kind),
        };
        let at = Path::new("x.acp");
        assert_eq!(unusable(&io(std::io::ErrorKind::NotFound), at), None);
        assert!(unusable(&io(std::io::ErrorKind::InvalidInput), at).is_some());
        let version = |found| acuity::Error::ProfileVersion {
            path: None,
            found,
            supported: 2,
        };
        assert!(unusable(&version(1), at).unwrap().contains("older"));
        assert!(unusable(&version(3), at).unwrap().contains("newer"));
        let garbage = Profile::from_bytes(b"GARBAGE").unwrap_err().with_path(at);
        let why = unusable(&garbage, at).unwrap();
        assert!(why.starts_with("is corrupt (malformed"), "{why}");
    }
}
