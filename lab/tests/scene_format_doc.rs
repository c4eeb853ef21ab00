//! The scene-format reference (`docs/scene-format.md`) names every key the
//! parser reads: each field of the raw scene structs (`lab/src/scene/raw.rs`,
//! the serde side of the format, one field per key) must appear in it as a
//! word, so a new key cannot ship undocumented.

use std::path::Path;

/// The field names declared in `raw.rs` (`pub(super) name: Type`).
fn raw_keys(source: &str) -> Vec<String> {
    let mut keys: Vec<String> = source
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub(super) "))
        .filter_map(|rest| rest.split_once(':'))
        .map(|(name, _)| name.trim().to_owned())
        .filter(|name| {
            name.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        })
        .collect();
    keys.sort();
    keys.dedup();
    keys
}

fn mentions(doc: &str, key: &str) -> bool {
    doc.match_indices(key).any(|(i, _)| {
        let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
        let before = doc[..i].chars().next_back().is_none_or(|c| !word(c));
        let after = doc[i + key.len()..].chars().next().is_none_or(|c| !word(c));
        before && after
    })
}

#[test]
fn every_scene_key_is_in_the_reference() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let raw = std::fs::read_to_string(crate_dir.join("src/scene/raw.rs")).unwrap();
    let doc = std::fs::read_to_string(crate_dir.join("../docs/scene-format.md")).unwrap();
    let keys = raw_keys(&raw);
    assert!(keys.len() > 50, "only {} keys found in raw.rs", keys.len());
    let missing: Vec<&String> = keys.iter().filter(|k| !mentions(&doc, k)).collect();
    assert!(
        missing.is_empty(),
        "docs/scene-format.md does not name these scene keys: {missing:?}"
    );
}

#[test]
fn a_key_is_found_as_a_word_only() {
    assert!(mentions("`point_deg = [x, y]`", "point_deg"));
    assert!(!mentions("eye_point_degrees", "point_deg"));
    assert!(raw_keys("    pub(super) rate_deg_per_s: f64,\n    pub(super) struct X {").len() == 1);
}
