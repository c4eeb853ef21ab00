//! The one error type of the renderer, the OBJ/MTL loader and the offline
//! pass (`acuity-preprocess` re-exports it), grouped by whose fault it is.

use std::path::PathBuf;

/// Everything that can go wrong in the offline pass, its renderer or its
/// loader.
///
/// Variants name the file and line (input files), the object and LOD
/// (LOD chains), the field (settings) or the graphics layer (rendering).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A line of an OBJ or MTL file is malformed or refers to something that
    /// does not exist (the file's fault).
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        /// The OBJ or MTL file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with the line.
        message: String,
    },
    /// A file parsed, but the mesh it describes cannot be analysed (no
    /// triangles, only points or lines, ...).
    #[error("{}: {message}", path.display())]
    InvalidMesh {
        /// The OBJ file (or a description such as `procedural:...`).
        path: PathBuf,
        /// What is wrong with the mesh.
        message: String,
    },
    /// An LOD chain is not a chain: a level does not have fewer triangles
    /// than the one before it, or the chain has fewer than two levels.
    #[error("object {object}, LOD {lod}: {message}")]
    LodChain {
        /// The object's name.
        object: String,
        /// Index of the offending LOD (0 = finest).
        lod: usize,
        /// What is wrong.
        message: String,
    },
    /// A setting or argument is outside its domain (the caller's fault).
    #[error("invalid {field}: {message}")]
    Settings {
        /// The field or argument name.
        field: &'static str,
        /// Why it is invalid.
        message: String,
    },
    /// No graphics adapter could be found for headless rendering.
    #[error(
        "no graphics adapter found (tried backends: {tried}); install Mesa (llvmpipe via EGL) or a GPU driver, or set WGPU_BACKEND"
    )]
    NoAdapter {
        /// The backends that were tried.
        tried: String,
    },
    /// The graphics device failed (device request, validation, readback).
    #[error("GPU error: {message}")]
    Gpu {
        /// The graphics layer's message.
        message: String,
    },
    /// An inspection image could not be written.
    #[error("{}: cannot write image: {message}", path.display())]
    WriteImage {
        /// The PNG file.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
}
