//! Parsing and validation of scene text: the TOML is parsed (recovering
//! from syntax errors to locate them), checked for NaN and infinities,
//! deserialised into the [`super::raw`] form and then checked rule by rule
//! into the public types; every failure is a located [`SceneError`].
//! Objects and the camera and gaze have their own submodules.

use std::collections::HashSet;
use std::ops::Range;
use std::path::{Path, PathBuf};

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::locate::{field_at, line_col, locate};
use super::raw::{RawDisplay, RawObserver, RawProfiles, RawRun, RawScene};
use super::{
    DisplaySpec, MAX_FRAMES, MAX_RESOLUTION_PX, MeshSource, PhysicalScreen, Policy, ProfileSpec,
    RunSpec, Scene, SceneError,
};
use crate::limits;

mod motion;
mod objects;

pub(super) struct Ctx<'t> {
    text: &'t str,
    path: PathBuf,
    base_dir: PathBuf,
    doc: Spanned<DeTable<'t>>,
    syntax_errors: Vec<toml::de::Error>,
}

/// Shorthand for validation results.
type Res<T> = Result<T, SceneError>;

impl<'t> Ctx<'t> {
    pub(super) fn new(text: &'t str, path: &Path) -> Ctx<'t> {
        let (doc, syntax_errors) = DeTable::parse_recoverable(text);
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ctx {
            text,
            path: path.to_path_buf(),
            base_dir,
            doc,
            syntax_errors,
        }
    }

    pub(super) fn scene(&self) -> Res<Scene> {
        if let Some(e) = self.syntax_errors.first() {
            return Err(self.toml_error(e));
        }
        check_finite(self.doc.get_ref(), &mut String::new()).map_err(|(field, span, text)| {
            self.at_span(
                field,
                Some(span),
                format!("`{text}` is not a finite number"),
            )
        })?;
        let raw: RawScene = toml::from_str(self.text).map_err(|e| self.toml_error(&e))?;
        self.validate(raw)
    }

    // -- locating ----------------------------------------------------------

    fn line_col(&self, offset: usize) -> (usize, usize) {
        line_col(self.text, offset)
    }

    fn at_span(&self, field: String, span: Option<Range<usize>>, reason: String) -> SceneError {
        let (line, column) = span.map_or((1, 1), |s| self.line_col(s.start));
        SceneError::Invalid {
            path: self.path.clone(),
            line,
            column,
            field,
            reason,
        }
    }

    /// An `Invalid` error at `field`, located at the deepest part of the
    /// field path that exists in the document.
    fn invalid(&self, field: impl Into<String>, reason: impl Into<String>) -> SceneError {
        let field = field.into();
        let span = locate(self.doc.get_ref(), &field);
        self.at_span(field, span, reason.into())
    }

    fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let message = e.message().trim().to_string();
        let span = e.span();
        let (line, column) = span.clone().map_or((1, 1), |s| self.line_col(s.start));
        let mut field = span
            .as_ref()
            .map(|s| field_at(self.doc.get_ref(), s.start))
            .unwrap_or_default();
        if let Some(missing) = backticked_after(&message, "missing field `") {
            if field.is_empty() {
                field = missing.to_string();
            } else if !field.ends_with(missing) {
                field = format!("{field}.{missing}");
            }
        }
        SceneError::Format {
            path: self.path.clone(),
            line,
            column,
            field: (!field.is_empty()).then_some(field),
            message,
        }
    }

    fn resolve(&self, relative: &str) -> PathBuf {
        self.base_dir.join(relative)
    }

    // -- validation --------------------------------------------------------

    fn validate(&self, raw: RawScene) -> Res<Scene> {
        let display = self.display(raw.display)?;
        if raw.objects.is_empty() {
            return Err(self.invalid("objects", "the scene needs at least one object"));
        }
        let mut names = HashSet::new();
        let mut objects = Vec::with_capacity(raw.objects.len());
        for (i, o) in raw.objects.into_iter().enumerate() {
            let obj = self.object(i, o)?;
            if !names.insert(obj.name.clone()) {
                return Err(self.invalid(
                    format!("objects[{i}].name"),
                    format!("the name {:?} is used by an earlier object", obj.name),
                ));
            }
            objects.push(obj);
        }
        self.scene_triangles(&objects)?;
        let camera = self.camera(raw.camera)?;
        let gaze = self.gaze(raw.gaze.unwrap_or_default(), &objects)?;
        let run = self.run(raw.run.unwrap_or_default(), camera.duration_s)?;
        let profiles = self.profiles(raw.profiles.unwrap_or_default())?;
        let raw_observer = raw.observer.unwrap_or_default();
        let eccentricity_model = raw_observer.eccentricity_model.unwrap_or_default();
        let velocity_model = raw_observer.velocity_model.unwrap_or_default();
        let observer = self.observer(raw_observer)?;
        Ok(Scene {
            source_path: self.path.clone(),
            display,
            objects,
            camera,
            gaze,
            run,
            profiles,
            observer,
            eccentricity_model,
            velocity_model,
        })
    }

    fn observer(&self, o: RawObserver) -> Res<acuity::Observer> {
        let d = acuity::Observer::default();
        let observer = acuity::Observer {
            sensitivity: o.sensitivity.unwrap_or(d.sensitivity),
            masking: o.masking.unwrap_or(d.masking),
        };
        match observer.validate() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                Err(self.invalid(format!("observer.{name}"), reason))
            }
            Err(e) => Err(self.invalid("observer", e.to_string())),
            Ok(()) => Ok(observer),
        }
    }

    fn profiles(&self, p: RawProfiles) -> Res<ProfileSpec> {
        let statistic = p
            .statistic
            .map(|s| crate::run::parse_statistic(&s))
            .transpose()
            .map_err(|reason| self.invalid("profiles.statistic", reason))?;
        let spec = ProfileSpec {
            resolution_px: p.resolution,
            min_diameter_px: p.min_diameter,
            msaa_samples: p.msaa_samples,
            viewpoint_level: p.viewpoints,
            statistic,
            threshold_delta_e: p.threshold_delta_e,
        };
        // The offline pass's own domain check; its defaults are valid, so a
        // failure names one of this table's keys.
        match spec.analysis_settings().validate() {
            Err(acuity_preprocess::Error::Settings { field, message }) => {
                let key = match field {
                    "resolution_px" => "resolution",
                    "min_diameter_px" => "min_diameter",
                    "viewpoint_level" => "viewpoints",
                    other => other,
                };
                Err(self.invalid(format!("profiles.{key}"), message))
            }
            Err(e) => Err(self.invalid("profiles", e.to_string())),
            Ok(()) => Ok(spec),
        }
    }

    fn display(&self, d: RawDisplay) -> Res<DisplaySpec> {
        let resolution = d.resolution.0;
        for (k, &px) in resolution.iter().enumerate() {
            if px == 0 || px > MAX_RESOLUTION_PX {
                return Err(self.invalid(
                    format!("display.resolution[{k}]"),
                    format!("{px} pixels is outside 1..={MAX_RESOLUTION_PX}"),
                ));
            }
        }
        let given = (d.fov_deg.map(|f| f.0), d.screen_cm.map(|s| s.0));
        let (fov_deg, physical) = match (given.0, given.1, d.distance_cm) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "give either fov_deg or screen_cm + distance_cm, not both",
                ));
            }
            (Some(fov_deg), None, None) => (fov_deg, None),
            (None, Some(size_cm), Some(distance_cm)) => {
                for (k, &s) in size_cm.iter().enumerate() {
                    if !(s > 0.0) {
                        return Err(self.invalid(
                            format!("display.screen_cm[{k}]"),
                            format!("{s} cm must be > 0"),
                        ));
                    }
                }
                if !(distance_cm > 0.0) {
                    return Err(self.invalid(
                        "display.distance_cm",
                        format!("{distance_cm} cm must be > 0"),
                    ));
                }
                let screen = PhysicalScreen {
                    size_cm,
                    distance_cm,
                };
                (screen.fov_deg(), Some(screen))
            }
            (None, Some(_), None) => {
                return Err(self.invalid(
                    "display.distance_cm",
                    "screen_cm needs distance_cm (eye to screen, cm)",
                ));
            }
            (None, None, Some(_)) => {
                return Err(self.invalid(
                    "display.screen_cm",
                    "distance_cm needs screen_cm (width, height in cm)",
                ));
            }
            (None, None, None) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "missing: give fov_deg = [horizontal, vertical] or screen_cm + distance_cm",
                ));
            }
        };
        for (k, &f) in fov_deg.iter().enumerate() {
            if !(f > 0.0 && f < 180.0) {
                return Err(self.invalid(
                    format!("display.fov_deg[{k}]"),
                    format!("{f} deg must be in (0, 180)"),
                ));
            }
        }
        let spec = DisplaySpec {
            resolution_px: resolution,
            fov_deg,
            physical,
            peak_luminance_cd_m2: d.peak_luminance_cd_m2.unwrap_or(200.0),
            contrast_ratio: d.contrast_ratio.unwrap_or(1000.0),
            ambient_lux: d.ambient_lux.unwrap_or(250.0),
            refresh_hz: match (d.continuous_motion, d.refresh_hz) {
                (Some(true), Some(_)) => {
                    return Err(self.invalid(
                        "display.continuous_motion",
                        "give refresh_hz or continuous_motion = true, not both",
                    ));
                }
                (Some(true), None) => None,
                (_, hz) => Some(hz.unwrap_or(f64::from(acuity::display::DEFAULT_REFRESH_HZ))),
            },
        };
        if let Some(hz) = spec.refresh_hz
            && !(1.0..=10_000.0).contains(&hz)
        {
            return Err(self.invalid(
                "display.refresh_hz",
                format!("{hz} Hz is outside [1, 10000]"),
            ));
        }
        match spec.photometry() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                let key = match name {
                    "peak_cd_m2" => "peak_luminance_cd_m2",
                    other => other,
                };
                Err(self.invalid(format!("display.{key}"), reason))
            }
            Err(e) => Err(self.invalid("display", e.to_string())),
            Ok(_) => Ok(spec),
        }
    }

    fn run(&self, r: RawRun, duration_s: f64) -> Res<RunSpec> {
        let target_hz = r.target_hz.unwrap_or(60.0);
        limits::check_target_hz(target_hz).map_err(|e| self.invalid("run.target_hz", e))?;
        let policies = r.policies.unwrap_or_else(|| Policy::ALL.to_vec());
        if policies.is_empty() {
            return Err(self.invalid("run.policies", "needs at least one policy"));
        }
        let mut seen = HashSet::new();
        for (k, p) in policies.iter().enumerate() {
            if !seen.insert(*p) {
                return Err(self.invalid(
                    format!("run.policies[{k}]"),
                    format!("{:?} is listed twice", p.name()),
                ));
            }
        }
        if r.frames == Some(0) {
            return Err(self.invalid("run.frames", "0 frames; need at least 1"));
        }
        let frame_dt_s = match (r.dt_s, r.frames) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("run.dt_s", "give either frames or dt_s, not both"));
            }
            (Some(dt), None) => {
                limits::check_dt_s(dt).map_err(|e| self.invalid("run.dt_s", e))?;
                dt
            }
            (None, Some(n)) => duration_s / f64::from(n),
            (None, None) => 1.0 / target_hz,
        };
        let frames = match r.frames {
            Some(n) if u64::from(n) > MAX_FRAMES => {
                return Err(self.invalid(
                    "run.frames",
                    format!("{n} frames is more than {MAX_FRAMES}"),
                ));
            }
            Some(n) => n,
            None => {
                let n = (duration_s / frame_dt_s).ceil().max(1.0);
                if !(n <= MAX_FRAMES as f64) {
                    let field = if r.dt_s.is_some() {
                        "run.dt_s"
                    } else {
                        "run.target_hz"
                    };
                    return Err(self.invalid(
                        field,
                        format!("{n} frames over {duration_s} s is more than {MAX_FRAMES}"),
                    ));
                }
                n as u32
            }
        };
        let screen_size_bias = r.screen_size_bias.unwrap_or(1.0);
        if !(screen_size_bias > 0.0) {
            return Err(self.invalid(
                "run.screen_size_bias",
                format!("{screen_size_bias} must be > 0"),
            ));
        }
        let screen_size_thresholds = r
            .screen_size_thresholds
            .unwrap_or_else(|| crate::screen_size::DEFAULT_THRESHOLDS_4.to_vec());
        crate::screen_size::check_table(&screen_size_thresholds)
            .map_err(|e| self.invalid("run.screen_size_thresholds", e.to_string()))?;
        let scale_factor = r.scale_factor.unwrap_or(1.0);
        if !(scale_factor > 0.0 && scale_factor <= 1.0) {
            return Err(self.invalid(
                "run.scale_factor",
                format!("{scale_factor} must be in (0, 1]"),
            ));
        }
        Ok(RunSpec {
            target_hz,
            policies,
            frame_dt_s,
            frames,
            flip_every_n_frames: r.flip_every_n_frames.unwrap_or(10),
            screen_size_bias,
            screen_size_thresholds,
            screen_size_foveated: r.screen_size_foveated.unwrap_or(false),
            scale_factor,
        })
    }

    /// Every mesh file named by the scene must exist.
    pub(super) fn check_files(&self, scene: &Scene) -> Res<()> {
        for (i, o) in scene.objects.iter().enumerate() {
            match &o.source {
                MeshSource::Lods(lods) => {
                    for (k, l) in lods.iter().enumerate() {
                        if !l.is_file() {
                            return Err(self.invalid(
                                format!("objects[{i}].lods[{k}]"),
                                format!("no such file: {}", l.display()),
                            ));
                        }
                    }
                }
                MeshSource::Generated { mesh, .. } => {
                    if !mesh.is_file() {
                        return Err(self.invalid(
                            format!("objects[{i}].mesh"),
                            format!("no such file: {}", mesh.display()),
                        ));
                    }
                }
                MeshSource::Procedural { .. } => {}
            }
        }
        Ok(())
    }
}

/// The text between `prefix` and the next backtick, if `message` contains
/// `prefix`.
fn backticked_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let start = message.find(prefix)? + prefix.len();
    let rest = &message[start..];
    rest.find('`').map(|end| &rest[..end])
}

/// Finds the first NaN or infinite float: its field path, span and text.
fn check_finite(
    table: &DeTable<'_>,
    prefix: &mut String,
) -> Result<(), (String, Range<usize>, String)> {
    for (k, v) in table.iter() {
        let len = prefix.len();
        if !prefix.is_empty() {
            prefix.push('.');
        }
        prefix.push_str(k.get_ref());
        check_finite_value(v, prefix)?;
        prefix.truncate(len);
    }
    Ok(())
}

fn check_finite_value(
    v: &Spanned<DeValue<'_>>,
    prefix: &mut String,
) -> Result<(), (String, Range<usize>, String)> {
    match v.get_ref() {
        DeValue::Float(f) => {
            let text = f.as_str();
            let finite = text
                .replace('_', "")
                .parse::<f64>()
                .is_ok_and(f64::is_finite);
            if !finite {
                return Err((prefix.clone(), v.span(), text.to_string()));
            }
        }
        DeValue::Table(t) => check_finite(t, prefix)?,
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                let len = prefix.len();
                prefix.push_str(&format!("[{i}]"));
                check_finite_value(item, prefix)?;
                prefix.truncate(len);
            }
        }
        _ => {}
    }
    Ok(())
}
