//! The runtime's one error type.

use std::path::PathBuf;

/// Everything the runtime can refuse, grouped by whose fault it is.
///
/// `InvalidParameter` is the caller's (a value outside its documented
/// domain); the `Profile*` variants are the profile file's; `Io` is the
/// environment's.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter lies outside its documented domain.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The parameter, as named in the API (`fov_deg`, `dt_s`, ...).
        name: &'static str,
        /// What is wrong with it, with the offending value.
        reason: String,
    },
    /// A profile could not be decoded: truncated, garbage or wrong syntax.
    #[error("{}: malformed profile at {location}: {reason}", path_or_input(.path))]
    ProfileFormat {
        /// The file, when the profile came from one.
        path: Option<PathBuf>,
        /// Where in the input: `line L, column C` for JSON, `byte N` for binary.
        location: String,
        /// What was expected or found.
        reason: String,
    },
    /// A profile decoded but breaks a rule of the format.
    #[error("{}: invalid profile field `{field}`: {reason}", path_or_input(.path))]
    ProfileInvalid {
        /// The file, when the profile came from one.
        path: Option<PathBuf>,
        /// The field, as a path (`transitions[3].features[0].freq_cdiam`).
        field: String,
        /// The rule it breaks, with the offending value.
        reason: String,
    },
    /// A profile written by a format version this build cannot read.
    #[error("{}: profile format version {found} is not supported (this build reads {supported}); regenerate it from its object with `acuity preprocess --force` (`acuity run` re-analyses cached profiles by itself)", path_or_input(.path))]
    ProfileVersion {
        /// The file, when the profile came from one.
        path: Option<PathBuf>,
        /// The version the file declares.
        found: u32,
        /// The version this build reads and writes.
        supported: u32,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
}

fn path_or_input(path: &Option<PathBuf>) -> String {
    match path {
        Some(p) => p.display().to_string(),
        None => "<input>".to_owned(),
    }
}

impl Error {
    /// Attaches a file path to a profile error that came from a byte slice
    /// (as [`crate::Profile::from_bytes`] returns it), so that the message
    /// names the file the bytes were read from; other errors are returned
    /// unchanged.
    pub fn with_path(mut self, file: &std::path::Path) -> Self {
        match &mut self {
            Error::ProfileFormat { path, .. }
            | Error::ProfileInvalid { path, .. }
            | Error::ProfileVersion { path, .. } => *path = Some(file.to_path_buf()),
            _ => {}
        }
        self
    }

    pub(crate) fn invalid(name: &'static str, reason: impl Into<String>) -> Self {
        Error::InvalidParameter {
            name,
            reason: reason.into(),
        }
    }
}

/// A number as error messages show it: plainly, or in exponent form when
/// that would take more than a dozen digits (`1e-300`, not 300 zeros).
/// Any `f64`, in whatever unit the message names; NaN and the infinities
/// print as `NaN`, `inf` and `-inf`. Public so that the command-line
/// tool's messages show numbers the same way as the runtime's.
pub fn number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e12).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// The runtime's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
