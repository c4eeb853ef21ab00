//! The C interface called from Rust: status codes and messages for bad
//! input (NULL pointers, NaN, corrupt profiles), never a panic; objects
//! added and removed under stable handles; a frame's LODs. Objects and
//! budgets are in `objects.rs`, the schedulers in `schedulers.rs`.

#[path = "../common/mod.rs"]
mod common;
mod objects;
mod schedulers;

use std::ffi::CStr;
use std::ptr::{null, null_mut};

use acuity_capi::*;
use common::demo_profile;

use AcuityStatus::*;

fn last_error() -> String {
    // SAFETY: never NULL, NUL-terminated, valid until this thread's next call.
    unsafe { CStr::from_ptr(acuity_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// Asserts a status and, for failures, that a message was left.
#[track_caller]
fn expect(status: AcuityStatus, want: AcuityStatus) -> String {
    let message = last_error();
    assert_eq!(status, want, "message: {message}");
    if want == ACUITY_OK {
        assert_eq!(message, "", "a success leaves no message");
    } else {
        assert!(!message.is_empty(), "{want:?} without a message");
    }
    message
}

fn profile_from(bytes: &[u8]) -> (AcuityStatus, *mut AcuityProfile) {
    let mut p = null_mut();
    // SAFETY: a live slice and a writable out-pointer.
    let status = unsafe { acuity_profile_from_bytes(bytes.as_ptr(), bytes.len(), &mut p) };
    (status, p)
}

fn demo() -> *mut AcuityProfile {
    let bytes = acuity::profile::binary::encode(&demo_profile()).unwrap();
    let (status, p) = profile_from(&bytes);
    expect(status, ACUITY_OK);
    p
}

const DISPLAY: AcuityDisplay = AcuityDisplay {
    width_px: 1920,
    height_px: 1080,
    fov_x_deg: 90.0,
    fov_y_deg: 58.7,
};

/// A selector with the demo profile (index 0) and change tracking.
fn selector() -> *mut AcuitySelector {
    let settings = AcuitySettings {
        track_changes: 1,
        ..AcuitySettings::default()
    };
    let mut s = null_mut();
    // SAFETY: live structs and out-pointers throughout.
    unsafe {
        expect(acuity_selector_new(&DISPLAY, &settings, &mut s), ACUITY_OK);
        let p = demo();
        let mut index = u32::MAX;
        expect(acuity_selector_add_profile(s, p, &mut index), ACUITY_OK);
        assert_eq!(index, 0);
        expect(acuity_profile_free(p), ACUITY_OK);
    }
    s
}

fn desc(z: f64) -> AcuityObjectDesc {
    AcuityObjectDesc {
        center: AcuityVec3d { x: 0.0, y: 0.0, z },
        rotation: AcuityQuat::default(),
        radius: 0.5,
        profile: 0,
    }
}

fn add(s: *mut AcuitySelector, z: f64) -> AcuityObject {
    let mut h = 0;
    // SAFETY: live selector and out-pointer.
    expect(
        unsafe { acuity_selector_add_object(s, &desc(z), &mut h) },
        ACUITY_OK,
    );
    assert_ne!(h, ACUITY_NO_OBJECT);
    h
}

fn lod(s: *mut AcuitySelector, h: AcuityObject) -> u8 {
    let mut l = 0;
    // SAFETY: live selector and out-pointer.
    expect(unsafe { acuity_selector_lod(s, h, &mut l) }, ACUITY_OK);
    l
}

fn select(s: *mut AcuitySelector, frame: &AcuityFrame) -> AcuityStatus {
    // SAFETY: live selector and frame.
    unsafe { acuity_selector_select(s, frame) }
}

#[test]
fn null_pointers_give_a_status_and_a_message() {
    let s = selector();
    let mut p = null_mut();
    let mut out_sel = null_mut();
    let mut h = 0;
    let mut index = 0;
    let mut count = 0;
    let mut l = 0;
    let frame = AcuityFrame::default();
    // SAFETY: every pointer is NULL or live.
    unsafe {
        let m = expect(
            acuity_profile_from_bytes(null(), 10, &mut p),
            ACUITY_NULL_POINTER,
        );
        assert!(m.contains("bytes"), "{m}");
        expect(
            acuity_profile_from_bytes(b"{}".as_ptr(), 2, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_profile_load(null(), &mut p), ACUITY_NULL_POINTER);
        expect(
            acuity_profile_load(c"x.acp".as_ptr(), null_mut()),
            ACUITY_NULL_POINTER,
        );
        assert!(p.is_null(), "no profile on failure");
        expect(acuity_profile_info(null(), null_mut()), ACUITY_NULL_POINTER);
        expect(acuity_settings_default(null_mut()), ACUITY_NULL_POINTER);
        expect(acuity_frame_default(null_mut()), ACUITY_NULL_POINTER);
        expect(
            acuity_selector_new(null(), null(), &mut out_sel),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_new(&DISPLAY, null(), null_mut()),
            ACUITY_NULL_POINTER,
        );
        assert!(out_sel.is_null());
        expect(
            acuity_selector_add_profile(s, null(), &mut index),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_add_profile(null_mut(), null(), &mut index),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_add_object(s, null(), &mut h),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_add_object(s, &desc(-5.0), null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_remove_object(null_mut(), 1),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_set_scale(null_mut(), 1.0),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_select(null_mut(), &frame),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_selector_select(s, null()), ACUITY_NULL_POINTER);
        expect(
            acuity_selector_changes(s, null_mut(), 0, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_changes(s, null_mut(), 5, &mut count),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_fades(s, null_mut(), 0, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_lods(s, null(), 3, &mut l),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_selector_lod(null_mut(), 1, &mut l),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_selector_stats(s, null_mut()), ACUITY_NULL_POINTER);
        expect(
            acuity_selector_set_pose(s, 1, null(), &AcuityQuat::default()),
            ACUITY_NULL_POINTER,
        );
        // Freeing NULL is a no-op; an empty array may be NULL.
        expect(acuity_profile_free(null_mut()), ACUITY_OK);
        expect(acuity_selector_free(null_mut()), ACUITY_OK);
        expect(acuity_selector_lods(s, null(), 0, null_mut()), ACUITY_OK);
        // The selector is unharmed.
        expect(acuity_selector_select(s, &frame), ACUITY_OK);
        expect(acuity_selector_free(s), ACUITY_OK);
    }
}

#[test]
fn nan_and_out_of_domain_numbers_are_refused() {
    let s = selector();
    let h = add(s, -10.0);
    let nan = f32::NAN;
    let mut out = null_mut();
    let mut h2 = 0;
    // SAFETY: every pointer is live.
    unsafe {
        let mut d = DISPLAY;
        d.fov_x_deg = nan;
        let m = expect(
            acuity_selector_new(&d, null(), &mut out),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("fov_x_deg"), "{m}");
        d = DISPLAY;
        d.width_px = 0;
        expect(
            acuity_selector_new(&d, null(), &mut out),
            ACUITY_INVALID_ARGUMENT,
        );
        let settings = AcuitySettings {
            fade_time_s: nan,
            ..AcuitySettings::default()
        };
        expect(
            acuity_selector_new(&DISPLAY, &settings, &mut out),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(out.is_null());
        // Negative values but the calibration's are refused.
        for v in [nan, -2.0, -0.5, f32::INFINITY] {
            let settings = AcuitySettings {
                visibility_budget_deg: v,
                ..AcuitySettings::default()
            };
            let m = expect(
                acuity_selector_new(&DISPLAY, &settings, &mut out),
                ACUITY_INVALID_ARGUMENT,
            );
            assert!(m.contains("visibility_budget_deg"), "{m}");
        }

        let mut bad = desc(-5.0);
        bad.center.x = f64::NAN;
        expect(
            acuity_selector_add_object(s, &bad, &mut h2),
            ACUITY_INVALID_ARGUMENT,
        );
        bad = desc(-5.0);
        bad.radius = nan;
        expect(
            acuity_selector_add_object(s, &bad, &mut h2),
            ACUITY_INVALID_ARGUMENT,
        );
        bad = desc(-5.0);
        bad.rotation.w = nan;
        expect(
            acuity_selector_add_object(s, &bad, &mut h2),
            ACUITY_INVALID_ARGUMENT,
        );
        bad = desc(-5.0);
        bad.profile = 7;
        expect(
            acuity_selector_add_object(s, &bad, &mut h2),
            ACUITY_UNKNOWN_PROFILE,
        );
        assert_eq!(h2, 0, "no handle on failure");

        for v in [nan, 0.0, -1.0, f32::INFINITY] {
            expect(acuity_selector_set_scale(s, v), ACUITY_INVALID_ARGUMENT);
        }
        expect(acuity_selector_set_scale(s, 2.0), ACUITY_OK); // counts as 1
        expect(acuity_selector_set_bias(s, h, nan), ACUITY_INVALID_ARGUMENT);
        expect(acuity_selector_set_bias(s, h, 0.0), ACUITY_INVALID_ARGUMENT);
        expect(
            acuity_selector_set_radius(s, h, nan),
            ACUITY_INVALID_ARGUMENT,
        );
        expect(
            acuity_selector_set_lod_range(s, h, 2, 1),
            ACUITY_INVALID_ARGUMENT,
        );
        let centre = AcuityVec3d {
            x: f64::NAN,
            y: 0.0,
            z: 0.0,
        };
        expect(
            acuity_selector_set_pose(s, h, &centre, &AcuityQuat::default()),
            ACUITY_INVALID_ARGUMENT,
        );
    }
    let ok = AcuityFrame::default();
    let frames: [fn(&mut AcuityFrame); 9] = [
        |f| f.dt_s = f32::NAN,
        |f| f.dt_s = f32::INFINITY,
        |f| f.dt_s = -0.01,
        |f| f.camera_position.y = f64::NAN,
        |f| f.camera_orientation.x = f32::NAN,
        |f| f.camera_orientation.w = 0.0,
        |f| f.gaze_direction = AcuityVec3f::default(),
        |f| f.tracker = 7,
        |f| {
            f.tracker = ACUITY_TRACKER_EYE;
            f.tracker_error_deg = f32::NAN
        },
    ];
    for change in frames {
        let mut f = ok;
        change(&mut f);
        let m = expect(select(s, &f), ACUITY_INVALID_ARGUMENT);
        assert!(m.contains('`') || m.contains("invalid"), "{m}");
    }
    // A refused frame leaves the selector as it was: not selected yet.
    assert_eq!(lod(s, h), ACUITY_LOD_CULLED);
    expect(select(s, &ok), ACUITY_OK);
    assert_ne!(lod(s, h), ACUITY_LOD_CULLED);
    // SAFETY: from acuity_selector_new, freed once.
    unsafe { acuity_selector_free(s) };
}

#[test]
fn dt_zero_is_a_repeated_frame() {
    let s = selector();
    let h = add(s, -10.0);
    let mut f = AcuityFrame {
        dt_s: 0.0,
        ..AcuityFrame::default()
    };
    expect(select(s, &f), ACUITY_OK);
    let first = lod(s, h);
    assert_ne!(first, ACUITY_LOD_CULLED);
    // The camera jumps with no time passing: no velocity from it.
    f.camera_position.x = 0.5;
    expect(select(s, &f), ACUITY_OK);
    assert_eq!(lod(s, h), first);
    // SAFETY: from acuity_selector_new, freed once.
    unsafe { acuity_selector_free(s) };
}

#[test]
fn corrupt_profiles_give_status_codes() {
    let good = acuity::profile::binary::encode(&demo_profile()).unwrap();
    let mut corrupt = good.clone();
    let at = corrupt.len() / 2;
    corrupt[at] ^= 0x5a;
    let cases: Vec<(Vec<u8>, AcuityStatus)> = vec![
        (corrupt, ACUITY_PROFILE_FORMAT),
        (good[..good.len() - 3].to_vec(), ACUITY_PROFILE_FORMAT),
        (Vec::new(), ACUITY_PROFILE_FORMAT),
        (b"\xff\xfe garbage".to_vec(), ACUITY_PROFILE_FORMAT),
        (b"{\"format_version\": 3".to_vec(), ACUITY_PROFILE_FORMAT),
    ];
    for (bytes, want) in cases {
        let (status, p) = profile_from(&bytes);
        expect(status, want);
        assert!(p.is_null());
    }
    // Well-formed JSON that breaks the format's rules, or is too old.
    let mut profile = demo_profile();
    profile.lod_triangles[2] = 5000;
    let json = json_of(&profile);
    let (status, _) = profile_from(json.as_bytes());
    let m = expect(status, ACUITY_PROFILE_INVALID);
    assert!(m.contains("lod_triangles[2]"), "{m}");
    let old =
        json_of(&demo_profile()).replacen("\"format_version\": 3", "\"format_version\": 2", 1);
    let (status, _) = profile_from(old.as_bytes());
    expect(status, ACUITY_PROFILE_VERSION);

    // Files: missing, and a corrupt one; the message names the file.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let mut p = null_mut();
    let missing = std::ffi::CString::new(dir.join("no-such.acp").to_str().unwrap()).unwrap();
    // SAFETY: NUL-terminated path, writable out-pointer.
    let m = expect(
        unsafe { acuity_profile_load(missing.as_ptr(), &mut p) },
        ACUITY_IO,
    );
    assert!(m.contains("no-such.acp"), "{m}");
    let bad = dir.join("corrupt.acp");
    std::fs::write(&bad, &good[..40]).unwrap();
    let bad = std::ffi::CString::new(bad.to_str().unwrap()).unwrap();
    // SAFETY: as above.
    let m = expect(
        unsafe { acuity_profile_load(bad.as_ptr(), &mut p) },
        ACUITY_PROFILE_FORMAT,
    );
    assert!(m.contains("corrupt.acp"), "{m}");
    assert!(p.is_null());
}

/// The demo profile as the runtime's JSON encoding writes it.
fn json_of(profile: &acuity::Profile) -> String {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join(format!(
        "{}-{}.json",
        profile.name, profile.lod_triangles[2]
    ));
    // The JSON encoder validates; write the valid form and edit it.
    let mut valid = profile.clone();
    valid.lod_triangles = demo_profile().lod_triangles;
    valid.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    if profile.lod_triangles[2] == valid.lod_triangles[2] {
        return text;
    }
    text.replacen("250", &profile.lod_triangles[2].to_string(), 1)
}

#[test]
fn json_and_binary_profiles_load_and_describe_themselves() {
    let json = json_of(&demo_profile());
    for bytes in [
        json.into_bytes(),
        acuity::profile::binary::encode(&demo_profile()).unwrap(),
    ] {
        let (status, p) = profile_from(&bytes);
        expect(status, ACUITY_OK);
        let mut info = AcuityProfileInfo::default();
        // SAFETY: live profile and out-pointer; freed once.
        unsafe {
            expect(acuity_profile_info(p, &mut info), ACUITY_OK);
            acuity_profile_free(p);
        }
        assert_eq!(info.lod_count, 4);
        assert_eq!((info.finest_triangles, info.coarsest_triangles), (4000, 60));
        assert_eq!(info.viewpoint_count, 1);
    }
}

#[test]
fn last_error_is_per_thread() {
    let (status, _) = profile_from(b"nonsense");
    let m = expect(status, ACUITY_PROFILE_FORMAT);
    std::thread::spawn(|| assert_eq!(last_error(), ""))
        .join()
        .unwrap();
    assert_eq!(
        last_error(),
        m,
        "reading the message is not a call that clears it"
    );
    let mut settings = AcuitySettings::default();
    // SAFETY: writable out-pointer.
    expect(unsafe { acuity_settings_default(&mut settings) }, ACUITY_OK);
}
