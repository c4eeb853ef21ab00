//! The validation context [`Ctx`]: the scene text, its parsed TOML
//! document and the file's folder, and the errors it makes: every error
//! of the format is a [`SceneError`] located at the field's line and
//! column. The table checks ([`super::settings`], [`super::objects`],
//! [`super::motion`]) and [`super::validate`] build on it.

use std::ops::Range;
use std::path::{Path, PathBuf};

use toml::Spanned;
use toml::de::DeTable;

use super::SceneError;
use super::locate::{field_at, line_col, locate};

pub(super) struct Ctx<'t> {
    pub(super) text: &'t str,
    pub(super) path: PathBuf,
    pub(super) base_dir: PathBuf,
    pub(super) doc: Spanned<DeTable<'t>>,
    pub(super) syntax_errors: Vec<toml::de::Error>,
}

/// Shorthand for validation results.
pub(super) type Res<T> = Result<T, SceneError>;

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

    pub(super) fn line_col(&self, offset: usize) -> (usize, usize) {
        line_col(self.text, offset)
    }

    pub(super) fn at_span(
        &self,
        field: String,
        span: Option<Range<usize>>,
        reason: String,
    ) -> SceneError {
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
    pub(super) fn invalid(
        &self,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> SceneError {
        let field = field.into();
        let span = locate(self.doc.get_ref(), &field);
        self.at_span(field, span, reason.into())
    }

    pub(super) fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let message = e.message().trim().to_string();
        let span = e.span();
        let (line, column) = span.clone().map_or((1, 1), |s| self.line_col(s.start));
        let mut field = span
            .as_ref()
            .map(|s| field_at(self.doc.get_ref(), s.start))
            .unwrap_or_default();
        // The parser places a missing top-level key at the document: an
        // empty span at its start, or one over all of it.
        let whole_document = span
            .as_ref()
            .is_none_or(|s| s.start == 0 && (s.end == 0 || s.end >= self.text.trim_end().len()));
        if let (Some(missing), true) = (
            backticked_after(&message, "missing field `"),
            whole_document,
        ) {
            // A top-level key is missing: name its table, not the first
            // table of the file.
            let table = if missing == "objects" {
                "[[objects]]".to_string()
            } else {
                format!("[{missing}]")
            };
            return SceneError::Format {
                path: self.path.clone(),
                line: 1,
                column: 1,
                field: Some(missing.to_string()),
                message: format!("the scene has no `{table}` table (docs/scene-format.md)"),
            };
        }
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

    pub(super) fn resolve(&self, relative: &str) -> PathBuf {
        self.base_dir.join(relative)
    }
}

/// The text between `prefix` and the next backtick, if `message` contains
/// `prefix`.
fn backticked_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let start = message.find(prefix)? + prefix.len();
    let rest = &message[start..];
    rest.find('`').map(|end| &rest[..end])
}
