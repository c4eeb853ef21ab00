//! Parsing and validation of scene text, [`Scene::load`] and
//! [`Scene::parse`]: the TOML is parsed (recovering from syntax errors to
//! locate them), checked for NaN and infinities, deserialised into the
//! [`super::raw`] form and then checked table by table into the public
//! types; every failure is a located [`SceneError`].

use std::collections::HashSet;
use std::ops::Range;
use std::path::Path;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::context::{Ctx, Res};
use super::raw::RawScene;
use super::{MeshSource, Scene, SceneError};

impl Scene {
    /// Reads, parses and validates a scene file, and checks that every mesh
    /// file it names exists. A mesh file (`.obj`, `.gltf`, `.glb`) is
    /// refused as [`SceneError::NotAScene`] before it is read.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        if super::is_mesh_path(path) {
            return Err(SceneError::NotAScene {
                path: path.to_path_buf(),
            });
        }
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let ctx = Ctx::new(&text, path);
        let scene = ctx.scene()?;
        ctx.check_files(&scene)?;
        Ok(scene)
    }

    /// Parses and validates scene text. `path_for_messages` names the file
    /// in errors, and its folder is the base of relative mesh paths. Does not
    /// touch the file system. Never panics, whatever the text.
    pub fn parse(text: &str, path_for_messages: impl AsRef<Path>) -> Result<Scene, SceneError> {
        Ctx::new(text, path_for_messages.as_ref()).scene()
    }
}

impl Ctx<'_> {
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
                MeshSource::Generated { mesh, .. } | MeshSource::Whole { mesh } => {
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
