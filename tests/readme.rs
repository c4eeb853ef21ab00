//! The README's embedding snippet is the code of `examples/minimal.rs`
//! (its `setup` and `frame` regions), so it uses no undefined names and
//! builds with the example.

use std::path::Path;

/// The lines between `// ANCHOR: name` and `// ANCHOR_END: name`, with
/// their common indentation removed.
fn region(source: &str, name: &str) -> Vec<String> {
    let lines: Vec<&str> = source
        .lines()
        .skip_while(|l| l.trim() != format!("// ANCHOR: {name}"))
        .skip(1)
        .take_while(|l| l.trim() != format!("// ANCHOR_END: {name}"))
        .collect();
    let indent = lines
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    lines
        .iter()
        .map(|l| l.get(indent..).unwrap_or("").to_owned())
        .collect()
}

#[test]
fn the_readme_snippet_is_the_minimal_example() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let example = std::fs::read_to_string(root.join("examples/minimal.rs")).unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let snippet: Vec<String> = readme
        .lines()
        .skip_while(|l| !l.starts_with("## Using the runtime"))
        .skip_while(|l| *l != "```rust")
        .skip(1)
        .take_while(|l| *l != "```")
        .map(str::to_owned)
        .collect();
    let mut expected = region(&example, "setup");
    assert!(expected.len() > 10, "no `setup` region in the example");
    expected.push("// every frame:".to_owned());
    expected.extend(region(&example, "frame"));
    assert_eq!(
        snippet, expected,
        "README.md's snippet under \"Using the runtime\" differs from examples/minimal.rs"
    );
}
