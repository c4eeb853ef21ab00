//! Writes the textured test asset as a `.glb`: a UV sphere with a checker
//! texture drawn by code (`acuity_preprocess::sample`).
//!
//! ```sh
//! cargo run -p acuity-preprocess --example textured_globe -- OUT.glb [TRIANGLES]
//! ```
//!
//! Without TRIANGLES it writes the shipped sample
//! (`models/textured_globe.glb`, checked by `tests/sample_asset.rs`).

use std::sync::Arc;

use acuity_preprocess::render::gltf_write::write_glb_single;
use acuity_preprocess::sample::{GLOBE_TEXTURE_PX, checker_texture, textured_globe_glb, uv_sphere};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args
        .next()
        .ok_or("usage: textured_globe OUT.glb [TRIANGLES]")?;
    let bytes = match args.next() {
        None => textured_globe_glb()?,
        Some(n) => {
            let triangles: u32 = n.parse().map_err(|e| format!("TRIANGLES `{n}`: {e}"))?;
            let t = Arc::new(checker_texture(GLOBE_TEXTURE_PX, 16));
            write_glb_single("textured_globe", &uv_sphere(triangles, Some(t)))?
        }
    };
    std::fs::write(&out, bytes)?;
    println!("wrote {out}");
    Ok(())
}
