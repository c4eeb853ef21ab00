//! [`SceneError`]: what can be wrong with a scene file, and where (file,
//! line, column, field path), so that every error points at the text to fix.

use std::path::{Path, PathBuf};

/// Everything that can be wrong with a scene file. Each variant names the
/// file; all but `Io` also name the line and column (1-based) and the field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read scene file: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML, or does not fit the scene format (missing
    /// or unknown key, wrong type, unknown name).
    #[error("{}:{line}:{column}: {}{message}", path.display(), field_prefix(field.as_deref()))]
    Format {
        /// The scene file.
        path: PathBuf,
        /// Line, 1-based (1 when the error has no better place, e.g. a
        /// missing top-level table).
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// The field path, when one can be named.
        field: Option<String>,
        /// What the parser expected or found.
        message: String,
    },
    /// The file is a mesh (OBJ or glTF), not a scene: the commands that play
    /// scenes say so and how to analyse or play the mesh.
    #[error(
        "{}: a mesh, not a scene file: analyse it with `acuity preprocess {}`, \
         or play it by naming it in a scene's `[[objects]]` (`mesh = \"{}\"`; \
         the scene format: docs/scene-format.md)",
        path.display(), path.display(), path.display()
    )]
    NotAScene {
        /// The mesh file given as a scene.
        path: PathBuf,
    },
    /// The file parses but a value breaks a rule of the format.
    #[error("{}:{line}:{column}: invalid `{field}`: {reason}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// Line, 1-based, of the field (or of its nearest enclosing table
        /// when the field is missing).
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// The field path, e.g. `objects[2].copies.count`.
        field: String,
        /// The rule it breaks, with the offending value.
        reason: String,
    },
}

fn field_prefix(field: Option<&str>) -> String {
    field.map(|f| format!("`{f}`: ")).unwrap_or_default()
}

impl SceneError {
    /// The scene file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            SceneError::Io { path, .. }
            | SceneError::NotAScene { path }
            | SceneError::Format { path, .. }
            | SceneError::Invalid { path, .. } => path,
        }
    }

    /// The line (1-based), when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            SceneError::Io { .. } | SceneError::NotAScene { .. } => None,
            SceneError::Format { line, .. } | SceneError::Invalid { line, .. } => Some(*line),
        }
    }

    /// The column (1-based, in characters), when known.
    pub fn column(&self) -> Option<usize> {
        match self {
            SceneError::Io { .. } | SceneError::NotAScene { .. } => None,
            SceneError::Format { column, .. } | SceneError::Invalid { column, .. } => Some(*column),
        }
    }

    /// The field path, when known.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. } | SceneError::NotAScene { .. } => None,
            SceneError::Format { field, .. } => field.as_deref(),
            SceneError::Invalid { field, .. } => Some(field),
        }
    }
}
