//! The glTF 2.0 loader: `acuity_render::gltf_mesh::parse_gltf` on GLB or
//! JSON bytes. External buffers and images are missing (an I/O error: an
//! error for a buffer, a warning for an image).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut resolve =
        |_: &str| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
    if let Ok(loaded) =
        acuity_render::gltf_mesh::parse_gltf(data, Path::new("fuzz.glb"), &mut resolve)
    {
        // What a successful parse returns must be usable.
        for mesh in &loaded.lods {
            assert!(mesh.check().is_ok());
            let _ = mesh.bounding_sphere();
            if let Some(t) = &mesh.texture {
                let _ = t.mip_chain();
            }
        }
    }
    let _ = acuity_render::gltf_mesh::external_files(data, Path::new("fuzz.glb"));
});
