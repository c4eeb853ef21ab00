//! The OBJ/MTL parser: `acuity_render::mesh::parse_obj`.
//!
//! The input is split at its first NUL byte: the bytes before it are the
//! OBJ text, the bytes after it are served as the contents of every MTL file
//! that a `mtllib` line names. Without a NUL byte, every MTL file is missing
//! (an I/O error, which the parser turns into a warning).
#![no_main]

use std::path::{Path, PathBuf};

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    };
    let mut resolve = |name: &str| match mtl {
        Some(bytes) => Ok((PathBuf::from(name), bytes.to_vec())),
        None => Err(std::io::Error::from(std::io::ErrorKind::NotFound)),
    };
    if let Ok(loaded) = acuity_render::mesh::parse_obj(obj, Path::new("fuzz.obj"), &mut resolve)
    {
        // What a successful parse returns must be usable.
        let mesh = &loaded.mesh;
        let _ = mesh.check();
        let _ = mesh.triangle_count();
        let _ = mesh.bounding_sphere();
    }
});
