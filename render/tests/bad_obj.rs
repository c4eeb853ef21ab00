//! Malformed and unusual OBJ/MTL files: each gives a correct mesh or a
//! clear error naming the file (and line), never a panic, never a silently
//! wrong mesh. Also: every fixture cut short at many lengths, and garbage.

use std::path::{Path, PathBuf};

use acuity_render::Error;
use acuity_render::mesh::{load_obj, parse_obj};
use proptest::prelude::*;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/bad_obj")
        .join(name)
}

enum Expect {
    /// A mesh with this many triangles and at least this many warnings.
    Mesh { triangles: usize, warnings: usize },
    /// A parse error in this file (name ends with) at this line.
    Line { file: &'static str, line: usize },
    /// An invalid-mesh error whose message contains this text.
    Invalid(&'static str),
}
use Expect::*;

const CASES: &[(&str, Expect)] = &[
    ("empty.obj", Invalid("empty mesh")),
    ("comments_only.obj", Invalid("empty mesh")),
    (
        "utf16le.obj",
        Mesh {
            triangles: 1,
            warnings: 0,
        },
    ),
    (
        "utf16be.obj",
        Mesh {
            triangles: 1,
            warnings: 0,
        },
    ),
    (
        "latin1.obj",
        Mesh {
            triangles: 1,
            warnings: 0,
        },
    ),
    (
        "index_out_of_range.obj",
        Line {
            file: "index_out_of_range.obj",
            line: 4,
        },
    ),
    (
        "index_zero.obj",
        Line {
            file: "index_zero.obj",
            line: 4,
        },
    ),
    (
        "index_negative_out_of_range.obj",
        Line {
            file: "index_negative_out_of_range.obj",
            line: 4,
        },
    ),
    (
        "normal_index_out_of_range.obj",
        Line {
            file: "normal_index_out_of_range.obj",
            line: 5,
        },
    ),
    (
        "nan_coordinate.obj",
        Line {
            file: "nan_coordinate.obj",
            line: 2,
        },
    ),
    (
        "inf_coordinate.obj",
        Line {
            file: "inf_coordinate.obj",
            line: 3,
        },
    ),
    (
        "overflow_1e39.obj",
        Line {
            file: "overflow_1e39.obj",
            line: 3,
        },
    ),
    // w is accepted and ignored, with a warning because it is not 1.
    (
        "w_component.obj",
        Mesh {
            triangles: 1,
            warnings: 1,
        },
    ),
    (
        "five_numbers.obj",
        Line {
            file: "five_numbers.obj",
            line: 1,
        },
    ),
    ("points_only.obj", Invalid("only points/lines")),
    ("lines_only.obj", Invalid("only points/lines")),
    (
        "face_two_corners.obj",
        Line {
            file: "face_two_corners.obj",
            line: 4,
        },
    ),
    (
        "polygon_300.obj",
        Mesh {
            triangles: 298,
            warnings: 0,
        },
    ),
    // A missing MTL is a warning (plus one for the then-unknown material).
    (
        "missing_mtl.obj",
        Mesh {
            triangles: 1,
            warnings: 2,
        },
    ),
    // A present but malformed MTL is an error naming the MTL file and line.
    (
        "malformed_mtl.obj",
        Line {
            file: "malformed.mtl",
            line: 2,
        },
    ),
    (
        "good_mtl.obj",
        Mesh {
            triangles: 2,
            warnings: 1,
        },
    ),
    (
        "vertex_colors.obj",
        Mesh {
            triangles: 1,
            warnings: 0,
        },
    ),
    (
        "garbage_token.obj",
        Line {
            file: "garbage_token.obj",
            line: 2,
        },
    ),
];

#[test]
fn every_fixture_gives_its_expected_outcome() {
    let listed: Vec<&str> = CASES.iter().map(|c| c.0).collect();
    for entry in std::fs::read_dir(fixture("")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        assert!(
            name.ends_with(".mtl") || listed.contains(&name.as_str()),
            "fixture {name} has no expectation"
        );
    }
    for (name, expect) in CASES {
        let r = load_obj(&fixture(name));
        match (expect, &r) {
            (
                Mesh {
                    triangles,
                    warnings,
                },
                Ok(m),
            ) => {
                assert_eq!(m.mesh.triangle_count(), *triangles, "{name}");
                assert!(m.warnings.len() >= *warnings, "{name}: {:?}", m.warnings);
                m.mesh.check().unwrap();
            }
            (
                Line { file, line },
                Err(Error::Parse {
                    path,
                    line: l,
                    message,
                }),
            ) => {
                assert!(
                    path.ends_with(file),
                    "{name}: error names {}",
                    path.display()
                );
                assert_eq!(l, line, "{name}: {message}");
            }
            (Invalid(text), Err(Error::InvalidMesh { path, message })) => {
                assert!(path.ends_with(name), "{name}");
                assert!(message.contains(text), "{name}: {message}");
            }
            _ => panic!("{name}: unexpected outcome {r:?}"),
        }
        if let Err(e) = &r {
            eprintln!("{name}: {e}");
        }
    }
}

#[test]
fn colours_come_from_vertex_colours_and_materials() {
    let m = load_obj(&fixture("good_mtl.obj")).unwrap().mesh;
    // First face uses `red` (Kd 0.8 0.1 0.1), the second an unknown material.
    assert!(m.colors.contains(&[0.8, 0.1, 0.1]));
    assert!(
        m.colors
            .contains(&acuity_render::mesh::DEFAULT_COLOR_LINEAR)
    );
    let m = load_obj(&fixture("vertex_colors.obj")).unwrap().mesh;
    assert_eq!(
        m.colors,
        vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    );
    // UTF-16 and Latin-1 give the same geometry as plain text.
    let a = load_obj(&fixture("utf16le.obj")).unwrap().mesh;
    let b = load_obj(&fixture("utf16be.obj")).unwrap().mesh;
    let c = load_obj(&fixture("latin1.obj")).unwrap().mesh;
    assert!(a == b && b == c);
    assert_eq!(
        a.positions,
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
}

fn parse_bytes(bytes: &[u8]) -> Result<acuity_render::LoadedMesh, Error> {
    let mtl = std::fs::read(fixture("good.mtl")).unwrap();
    parse_obj(bytes, Path::new("fuzz.obj"), &mut |_| {
        Ok((PathBuf::from("good.mtl"), mtl.clone()))
    })
}

#[test]
fn every_fixture_cut_short_at_every_length_loads_or_errs_cleanly() {
    for entry in std::fs::read_dir(fixture("")).unwrap() {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        for len in 0..=bytes.len() {
            // Never a panic; any mesh that comes back is valid.
            if let Ok(m) = parse_bytes(&bytes[..len]) {
                m.mesh
                    .check()
                    .unwrap_or_else(|e| panic!("{} cut at {len}: {e}", path.display()));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn garbage_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        if let Ok(m) = parse_bytes(&bytes) {
            prop_assert!(m.mesh.check().is_ok());
        }
    }

    #[test]
    fn obj_like_garbage_never_panics(lines in proptest::collection::vec(
        prop_oneof![
            Just("v 0 0 0".to_string()), Just("v 1 0 0".to_string()), Just("v 0 1 0 1 1 1".to_string()),
            Just("vn 0 0 1".to_string()), Just("vt 0 0".to_string()), Just("usemtl red".to_string()),
            Just("mtllib good.mtl".to_string()), Just("l 1 2".to_string()),
            "f( -?[0-9]{1,2}(/-?[0-9]?(/-?[0-9])?)?){0,6}",
            "v( -?[0-9.e+]{1,6}){0,7}",
            "[a-z/ 0-9.#-]{0,20}",
        ], 0..30)) {
        let text = lines.join("\n");
        if let Ok(m) = parse_bytes(text.as_bytes()) {
            prop_assert!(m.mesh.check().is_ok());
        }
    }
}
