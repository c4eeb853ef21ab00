//! `acuity preprocess` over an asset library (a folder, a manifest): the
//! union of `--shard k/4`, k = 1..4, is the unsharded run's profiles byte
//! for byte, a broken asset fails alone, `--check` is the merge step, and
//! `--csv` writes the summary.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::Arc;

use acuity_preprocess::render::gltf_write::write_glb_single;
use acuity_preprocess::render::obj_write::obj_text;
use acuity_preprocess::sample::{checker_texture, uv_sphere};

const FAST: [&str; 8] = [
    "--resolution",
    "32",
    "--min-diameter",
    "32",
    "--viewpoints",
    "0",
    "--triangles",
    "300,100",
];

fn temp_dir(test: &str) -> PathBuf {
    common::scratch("library_cli", test)
}

fn preprocess(args: &[&str]) -> Output {
    let args: Vec<&str> = [&["preprocess"][..], args, &FAST].concat();
    common::acuity_logged(&args)
}

/// A library of six assets (OBJ and glTF, one in a subfolder, one broken).
fn library(dir: &Path) -> PathBuf {
    let lib = dir.join("lib");
    std::fs::create_dir_all(lib.join("rocks")).unwrap();
    let t = Arc::new(checker_texture(32, 4));
    for (i, n) in [320u32, 400, 500].iter().enumerate() {
        let glb = write_glb_single("g", &uv_sphere(*n, Some(t.clone()))).unwrap();
        std::fs::write(lib.join(format!("globe{i}.glb")), glb).unwrap();
    }
    std::fs::write(lib.join("ball.obj"), obj_text(&uv_sphere(360, None), None)).unwrap();
    std::fs::write(
        lib.join("rocks/pebble.obj"),
        obj_text(&uv_sphere(420, None), None),
    )
    .unwrap();
    std::fs::write(lib.join("broken.glb"), b"glTF\x02\0\0\0").unwrap();
    lib
}

/// Every `.acp` file in `dir`, by name.
fn profiles(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "acp"))
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

#[test]
fn the_union_of_shards_is_the_unsharded_run_byte_for_byte() {
    let dir = temp_dir("shards");
    let lib = library(&dir);
    let (whole, sharded) = (dir.join("whole"), dir.join("sharded"));
    let csv = dir.join("summary.csv");
    let o = preprocess(&[
        lib.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    // The broken asset fails alone.
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("broken.glb"));
    let want = profiles(&whole);
    let names: Vec<&str> = want.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "ball.acp",
            "globe0.acp",
            "globe1.acp",
            "globe2.acp",
            "rocks_pebble.acp"
        ]
    );
    let table = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(table.lines().count(), 7, "{table}");
    assert!(table.contains("\"broken\",failed"), "{table}");

    let mut counts = Vec::new();
    for k in 1..=4 {
        let shard = format!("{k}/4");
        let o = preprocess(&[
            lib.to_str().unwrap(),
            "--out",
            sharded.to_str().unwrap(),
            "--shard",
            &shard,
        ]);
        assert!(matches!(o.status.code(), Some(0) | Some(1)));
        counts.push(profiles(&sharded).len());
    }
    assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
    assert_eq!(profiles(&sharded), want);

    // The merge step: all present but the broken asset's.
    let check = |out: &Path| {
        preprocess(&[
            lib.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--check",
        ])
    };
    let o = check(&sharded);
    assert_eq!(o.status.code(), Some(1));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("broken: no profile"), "{text}");
    assert!(text.contains("5 of 6 objects"), "{text}");
    // Without the broken asset, a manifest of the rest checks clean...
    let manifest = lib.join("good.txt");
    std::fs::write(
        &manifest,
        "# the good ones\nball.obj\nglobe0.glb\nglobe1.glb\nglobe2.glb\nrocks/pebble.obj\n",
    )
    .unwrap();
    let m = manifest.to_str().unwrap();
    let o = preprocess(&[m, "--out", sharded.to_str().unwrap(), "--check"]);
    assert_eq!(o.status.code(), Some(0));
    // ...until an asset changes: its profile is stale.
    std::fs::write(lib.join("ball.obj"), obj_text(&uv_sphere(380, None), None)).unwrap();
    let o = preprocess(&[m, "--out", sharded.to_str().unwrap(), "--check"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stdout).contains("ball: stale profile"));
    // A truncated profile is named corrupt, with what to run, and the
    // check writes nothing and promises no analysis.
    let pebble = sharded.join("rocks_pebble.acp");
    let bytes = std::fs::read(&pebble).unwrap();
    std::fs::write(&pebble, &bytes[..40]).unwrap();
    let o = preprocess(&[m, "--out", sharded.to_str().unwrap(), "--check"]);
    assert_eq!(o.status.code(), Some(1));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("rocks/pebble: profile"), "{text}");
    assert!(text.contains("is corrupt"), "{text}");
    assert!(
        text.contains("`acuity preprocess` without --check"),
        "{text}"
    );
    assert!(!String::from_utf8_lossy(&o.stderr).contains("analysing"));
    assert_eq!(std::fs::read(&pebble).unwrap().len(), 40);
}
