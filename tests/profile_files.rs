//! Profile files on disk: round trips, refusals, and hostile bytes.

mod common;

use acuity::{Error, Profile};
use common::four_lod_profile;
use proptest::prelude::*;

/// A fresh folder under cargo's per-target scratch space (not the system's
/// temporary folder, which would collect one folder per run).
fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("profile_files")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn both_encodings_round_trip_bit_identical_through_files() {
    let dir = temp_dir("roundtrip");
    let p = four_lod_profile(5);
    for name in ["a.json", "a.acp"] {
        let path = dir.join(name);
        p.save(&path).unwrap();
        let first = std::fs::read(&path).unwrap();
        let back = Profile::load(&path).unwrap();
        assert_eq!(back, p);
        back.save(&path).unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            first,
            "{name} changed on rewrite"
        );
    }
    let json = std::fs::metadata(dir.join("a.json")).unwrap().len();
    let bin = std::fs::metadata(dir.join("a.acp")).unwrap().len();
    assert!(bin * 4 < json, "binary {bin} bytes, JSON {json} bytes");
}

#[test]
fn invalid_profiles_are_not_written() {
    let dir = temp_dir("refuse");
    let mut p = four_lod_profile(5);
    p.transitions[7].features[0].freq_cdiam = f32::INFINITY;
    for name in ["bad.json", "bad.acp"] {
        let path = dir.join(name);
        let e = p.save(&path).unwrap_err();
        assert!(
            e.to_string()
                .contains("transitions[7].features[0].freq_cdiam"),
            "{e}"
        );
        assert!(!path.exists());
    }
}

#[test]
fn non_finite_values_in_a_file_are_refused_on_read() {
    // A binary file with a NaN and a correct checksum: only validation can
    // catch it.
    let p = four_lod_profile(5);
    let mut bytes = acuity::profile::binary::encode(&p).unwrap();
    let radius_at = bytes
        .windows(4)
        .position(|w| w == 1.0f32.to_le_bytes())
        .unwrap();
    bytes[radius_at..radius_at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let body = bytes.len() - 8;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in &bytes[..body] {
        h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
    }
    bytes[body..].copy_from_slice(&h.to_le_bytes());
    let e = Profile::from_bytes(&bytes).unwrap_err();
    assert!(
        matches!(&e, Error::ProfileInvalid { field, .. } if field == "bounding_radius"),
        "{e}"
    );
}

#[test]
fn errors_name_the_file() {
    let dir = temp_dir("names");
    let path = dir.join("broken.json");
    std::fs::write(&path, b"{\"format_version\": 1, \"name\": 3}").unwrap();
    let e = Profile::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("broken.json") && e.contains("name") && e.contains("line 1"),
        "{e}"
    );
    let e = Profile::load(dir.join("missing.json"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.json"), "{e}");
}

#[test]
fn a_newer_version_is_refused_by_number() {
    let json =
        String::from_utf8(acuity::profile::json::encode(&four_lod_profile(1)).unwrap()).unwrap();
    let json = json.replacen("\"format_version\": 3", "\"format_version\": 4", 1);
    assert!(matches!(
        Profile::from_bytes(json.as_bytes()),
        Err(Error::ProfileVersion { found: 4, .. })
    ));
}

#[test]
fn a_format_2_profile_is_refused_with_how_to_regenerate_it() {
    // Format 2 stored only each transition's most visible features, which
    // cannot be pooled; its files are refused, binary and JSON alike.
    let mut bytes = acuity::profile::binary::encode(&four_lod_profile(1)).unwrap();
    bytes[8..12].copy_from_slice(&2u32.to_le_bytes());
    let json =
        String::from_utf8(acuity::profile::json::encode(&four_lod_profile(1)).unwrap()).unwrap();
    let json = json.replacen("\"format_version\": 3", "\"format_version\": 2", 1);
    for bytes in [bytes, json.into_bytes()] {
        let e = Profile::from_bytes(&bytes).unwrap_err();
        assert!(
            matches!(
                e,
                Error::ProfileVersion {
                    found: 2,
                    supported: 3,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("regenerate"), "{e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn garbage_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        let _ = Profile::from_bytes(&bytes);
        let mut with_magic = acuity::profile::binary::MAGIC.to_vec();
        with_magic.extend_from_slice(&bytes);
        prop_assert!(Profile::from_bytes(&with_magic).is_err());
    }

    #[test]
    fn corrupted_files_are_errors_never_panics(pos in any::<prop::sample::Index>(), byte in any::<u8>(), cut in any::<prop::sample::Index>()) {
        // A JSON file without its final newline is still whole.
        for (bytes, whole_without) in [
            (acuity::profile::binary::encode(&four_lod_profile(2)).unwrap(), 0),
            (acuity::profile::json::encode(&four_lod_profile(2)).unwrap(), 1),
        ] {
            let mut b = bytes.clone();
            let i = pos.index(b.len());
            b[i] = byte;
            let _ = Profile::from_bytes(&b);
            let n = cut.index(bytes.len() - whole_without);
            prop_assert!(Profile::from_bytes(&bytes[..n]).is_err());
        }
    }
}

#[cfg(unix)]
#[test]
fn saving_over_a_link_replaces_the_link_and_leaves_its_target_alone() {
    let dir = temp_dir("link");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    let path = dir.join("rock.acp");
    let _ = std::fs::remove_file(&path);
    std::os::unix::fs::symlink(&victim, &path).unwrap();
    four_lod_profile(2).save(&path).unwrap();
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    assert!(!std::fs::symlink_metadata(&path).unwrap().is_symlink());
    assert_eq!(Profile::load(&path).unwrap(), four_lod_profile(2));
    // No temporary file is left behind.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[cfg(unix)]
#[test]
fn a_device_fifo_or_folder_is_refused_without_reading_or_waiting() {
    let dir = temp_dir("special");
    let fifo = dir.join("fifo.acp");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let zero = dir.join("zero.acp");
    let _ = std::fs::remove_file(&zero);
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let folder = dir.join("folder.acp");
    std::fs::create_dir_all(&folder).unwrap();
    for path in [fifo, zero, folder, "/dev/zero".into()] {
        // On a thread, so a load that blocks fails the test instead of
        // hanging it.
        let (tx, rx) = std::sync::mpsc::channel();
        let p = path.clone();
        std::thread::spawn(move || {
            tx.send(Profile::load(&p).map(|_| ()).map_err(|e| e.to_string()))
        });
        let got = rx
            .recv_timeout(std::time::Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("{}: still reading after 10 s", path.display()));
        let e = got.unwrap_err();
        assert!(e.contains("not a regular file"), "{}: {e}", path.display());
        assert_eq!(e.matches("regular").count(), 1, "{e}");
    }
}
