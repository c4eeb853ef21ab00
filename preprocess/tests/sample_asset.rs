//! The shipped glTF sample (`models/textured_globe.glb`) is what
//! `acuity_preprocess::sample::textured_globe_glb` makes. Regenerate it with
//! `ACUITY_WRITE_SAMPLE=1 cargo test -p acuity-preprocess --test sample_asset`.

use std::path::Path;

use acuity_preprocess::render::gltf_mesh::{LodRule, load_gltf, parse_gltf};
use acuity_preprocess::sample::{GLOBE_TEXTURE_PX, textured_globe_glb};

#[test]
fn the_shipped_sample_is_what_the_generator_makes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/textured_globe.glb");
    let made = textured_globe_glb().unwrap();
    if std::env::var_os("ACUITY_WRITE_SAMPLE").is_some() {
        std::fs::write(&path, &made).unwrap();
    }
    let shipped = load_gltf(&path).unwrap();
    let fresh = parse_gltf(&made, Path::new("made.glb"), &mut |_| {
        Err(std::io::Error::from(std::io::ErrorKind::NotFound))
    })
    .unwrap();
    assert_eq!(shipped.rule, LodRule::Single);
    let (a, b) = (&shipped.lods[0], &fresh.lods[0]);
    assert_eq!(a.indices, b.indices);
    // Trigonometry may round differently on another platform: compare
    // with a tolerance, not byte for byte.
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!(
            p.iter().zip(q).all(|(x, y)| (x - y).abs() < 1e-5),
            "{p:?} {q:?}"
        );
    }
    let (ta, tb) = (a.texture.as_ref().unwrap(), b.texture.as_ref().unwrap());
    assert_eq!(
        (ta.width, ta.height),
        (GLOBE_TEXTURE_PX, GLOBE_TEXTURE_PX / 2)
    );
    assert!(
        ta.rgba
            .iter()
            .zip(&tb.rgba)
            .all(|(x, y)| x.abs_diff(*y) <= 1)
    );
}
