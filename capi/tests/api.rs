//! The C interface called from Rust: status codes and messages for bad
//! input (NULL pointers, NaN, corrupt profiles), never a panic; objects
//! added and removed under stable handles; a frame's LODs.

mod common;

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

#[test]
fn objects_are_added_and_removed_under_stable_handles() {
    let s = selector();
    let a = add(s, -5.0);
    let b = add(s, -6.0);
    let c = add(s, -7.0);
    let mut stats = AcuityStats::default();
    // SAFETY: live selector, handles and out-pointers throughout.
    unsafe {
        expect(acuity_selector_remove_object(s, b), ACUITY_OK);
        let m = expect(acuity_selector_remove_object(s, b), ACUITY_UNKNOWN_OBJECT);
        assert!(m.contains("removed"), "{m}");
        let mut l = 0;
        expect(acuity_selector_lod(s, b, &mut l), ACUITY_UNKNOWN_OBJECT);
        expect(acuity_selector_set_bias(s, b, 2.0), ACUITY_UNKNOWN_OBJECT);
        expect(acuity_selector_remove_object(s, 0), ACUITY_UNKNOWN_OBJECT);
        expect(
            acuity_selector_remove_object(s, u64::MAX),
            ACUITY_UNKNOWN_OBJECT,
        );
        // The freed slot is reused under a new handle; the old one stays dead.
        let d = add(s, -8.0);
        assert_ne!(d, b);
        expect(acuity_selector_lod(s, b, &mut l), ACUITY_UNKNOWN_OBJECT);
        expect(select(s, &AcuityFrame::default()), ACUITY_OK);
        expect(acuity_selector_stats(s, &mut stats), ACUITY_OK);
        assert_eq!(stats.objects, 3);
        assert_eq!(stats.visible, 3);
        assert_eq!(stats.changed, 3, "every object appears on its first frame");
        // The change list names the live handles.
        let mut changes = [AcuityChange::default(); 3];
        let mut count = 0;
        expect(
            acuity_selector_changes(s, null_mut(), 0, &mut count),
            ACUITY_OK,
        );
        assert_eq!(count, 3);
        expect(
            acuity_selector_changes(s, changes.as_mut_ptr(), 2, &mut count),
            ACUITY_BUFFER_TOO_SMALL,
        );
        assert_eq!(count, 3);
        expect(
            acuity_selector_changes(s, changes.as_mut_ptr(), 3, &mut count),
            ACUITY_OK,
        );
        let mut named: Vec<_> = changes.iter().map(|c| c.object).collect();
        named.sort();
        let mut live = vec![a, c, d];
        live.sort();
        assert_eq!(named, live);
        for ch in changes {
            assert_eq!(ch.lod, u32::from(lod(s, ch.object)));
        }
        // Bulk LODs: a stale handle reads culled and fails the call.
        let handles = [a, b, c];
        let mut lods = [0u8; 3];
        expect(
            acuity_selector_lods(s, handles.as_ptr(), 3, lods.as_mut_ptr()),
            ACUITY_UNKNOWN_OBJECT,
        );
        assert_eq!(lods, [lod(s, a), ACUITY_LOD_CULLED, lod(s, c)]);
        // Moving an object behind the camera culls it.
        let behind = AcuityVec3d {
            x: 0.0,
            y: 0.0,
            z: 5.0,
        };
        expect(
            acuity_selector_set_pose(s, a, &behind, &AcuityQuat::default()),
            ACUITY_OK,
        );
        expect(select(s, &AcuityFrame::default()), ACUITY_OK);
        assert_eq!(lod(s, a), ACUITY_LOD_CULLED);
        expect(
            acuity_selector_changes(s, changes.as_mut_ptr(), 3, &mut count),
            ACUITY_OK,
        );
        assert_eq!(
            &changes[..count],
            &[AcuityChange {
                object: a,
                lod: 255
            }]
        );
        acuity_selector_free(s);
    }
}

#[test]
fn near_objects_get_finer_lods_than_far_ones() {
    let s = selector();
    let near = add(s, -3.0);
    let mid = add(s, -30.0);
    let far = add(s, -300.0);
    let off_axis = {
        let mut d = desc(-3.0);
        d.center.x = -2.5; // about 40 deg left: eccentric
        let mut h = 0;
        // SAFETY: live selector and out-pointer.
        expect(
            unsafe { acuity_selector_add_object(s, &d, &mut h) },
            ACUITY_OK,
        );
        h
    };
    let f = AcuityFrame {
        dt_s: 0.0,
        ..AcuityFrame::default()
    };
    expect(select(s, &f), ACUITY_OK);
    let (n, m, fa, o) = (lod(s, near), lod(s, mid), lod(s, far), lod(s, off_axis));
    assert!(n < m && m <= fa, "near {n}, mid {m}, far {fa}");
    assert_eq!(n, 0);
    assert_eq!(fa, 3, "the coarsest at 300 units");
    assert!(o > n, "eccentric {o} coarser than foveal {n}");
    // A lower s never adds detail; a bias above 1 never removes any.
    // SAFETY: live selector.
    unsafe {
        expect(acuity_selector_set_scale(s, 0.1), ACUITY_OK);
        expect(select(s, &f), ACUITY_OK);
        assert!(lod(s, mid) >= m);
        expect(acuity_selector_set_bias(s, mid, 100.0), ACUITY_OK);
        expect(select(s, &f), ACUITY_OK);
        assert_eq!(lod(s, mid), 0);
        expect(
            acuity_selector_set_lod_range(s, near, 2, u32::MAX),
            ACUITY_OK,
        );
        expect(select(s, &f), ACUITY_OK);
        assert_eq!(lod(s, near), 2);
        acuity_selector_free(s);
    }
}

#[test]
fn a_budgeted_scale_never_draws_more_than_one_s_for_all() {
    let triangles_at = |budgeted_scale: u32, scale: f32| {
        let settings = AcuitySettings {
            budgeted_scale,
            ..AcuitySettings::default()
        };
        let mut s = null_mut();
        let mut stats = AcuityStats::default();
        // SAFETY: live structs, selector and out-pointers throughout.
        unsafe {
            expect(acuity_selector_new(&DISPLAY, &settings, &mut s), ACUITY_OK);
            let p = demo();
            expect(acuity_selector_add_profile(s, p, &mut 0), ACUITY_OK);
            expect(acuity_profile_free(p), ACUITY_OK);
            for i in 0..40 {
                let mut d = desc(-3.0 - 4.0 * f64::from(i));
                d.center.x = f64::from(i % 7) - 3.0;
                expect(acuity_selector_add_object(s, &d, &mut 0), ACUITY_OK);
            }
            expect(acuity_selector_set_scale(s, scale), ACUITY_OK);
            expect(select(s, &AcuityFrame::default()), ACUITY_OK);
            expect(acuity_selector_stats(s, &mut stats), ACUITY_OK);
            acuity_selector_free(s);
        }
        stats.triangles
    };
    assert_eq!(triangles_at(1, 1.0), triangles_at(0, 1.0));
    let pooled = AcuitySettings {
        budgeted_scale: 1,
        visibility_budget_deg: 200.0,
        ..AcuitySettings::default()
    };
    let s = scene(&pooled, 40);
    expect(select(s, &AcuityFrame::default()), ACUITY_OK);
    let with_budget = triangles(s);
    // SAFETY: from acuity_selector_new, freed once.
    unsafe { acuity_selector_free(s) };
    assert!(
        with_budget < triangles_at(1, 1.0),
        "a visibility budget of 200 deg saved nothing at s = 1"
    );
    // The calibration: s = 1 just imperceptible on the selector's display.
    let mut calibrated = AcuitySettings::default();
    // SAFETY: a valid place to write settings.
    expect(
        unsafe { acuity_settings_just_imperceptible(&mut calibrated) },
        ACUITY_OK,
    );
    assert_eq!(
        (calibrated.budgeted_scale, calibrated.visibility_budget_deg),
        (1, ACUITY_VISIBILITY_BUDGET_IMPERCEPTIBLE)
    );
    // The header's constants are the runtime's, and what the settings set.
    assert_eq!(
        ACUITY_IMPERCEPTIBLE_VISIBILITY_DEG,
        acuity::IMPERCEPTIBLE_VISIBILITY_DEG
    );
    assert_eq!(
        (
            calibrated.switch_hysteresis,
            calibrated.switch_min_dwell_s,
            calibrated.switch_coarsen_delay_s
        ),
        (
            ACUITY_STEADY_SWITCH_HYSTERESIS,
            ACUITY_STEADY_SWITCH_MIN_DWELL_S,
            ACUITY_STEADY_SWITCH_COARSEN_DELAY_S
        )
    );
    assert_eq!(
        (
            ACUITY_STEADY_SWITCH_HYSTERESIS,
            ACUITY_STEADY_SWITCH_MIN_DWELL_S,
            ACUITY_STEADY_SWITCH_COARSEN_DELAY_S
        ),
        (
            acuity::STEADY_SWITCH_HYSTERESIS,
            acuity::STEADY_SWITCH_MIN_DWELL_S,
            acuity::STEADY_SWITCH_COARSEN_DELAY_S
        )
    );
    let s = scene(&calibrated, 40);
    expect(select(s, &AcuityFrame::default()), ACUITY_OK);
    let at_edge = triangles(s);
    // SAFETY: from acuity_selector_new, freed once.
    unsafe { acuity_selector_free(s) };
    // The calibrated budget on this field (3.6 times Reddy's) is below 200 deg.
    assert!(at_edge <= triangles_at(1, 1.0) && at_edge >= with_budget);
    for scale in [0.5, 0.2, 0.05] {
        let (budgeted, uniform) = (triangles_at(1, scale), triangles_at(0, scale));
        assert!(budgeted <= uniform, "s = {scale}: {budgeted} > {uniform}");
    }
    assert!(triangles_at(1, 0.05) < triangles_at(1, 1.0));
}

#[test]
fn fades_are_listed_with_handles() {
    let settings = AcuitySettings {
        fade_time_s: 0.5,
        ..AcuitySettings::default()
    };
    let mut s = null_mut();
    let mut count = 0;
    let mut fades = [AcuityFade::default(); 4];
    // SAFETY: live structs, selector and out-pointers.
    unsafe {
        expect(acuity_selector_new(&DISPLAY, &settings, &mut s), ACUITY_OK);
        let p = demo();
        let mut index = 0;
        expect(acuity_selector_add_profile(s, p, &mut index), ACUITY_OK);
        acuity_profile_free(p);
        let h = add(s, -3.0);
        let mut f = AcuityFrame::default();
        expect(select(s, &f), ACUITY_OK);
        assert_eq!(lod(s, h), 0);
        // Far away now: it switches coarser and fades.
        f.camera_position.z = 200.0;
        f.dt_s = 0.0;
        expect(select(s, &f), ACUITY_OK);
        expect(
            acuity_selector_fades(s, fades.as_mut_ptr(), 4, &mut count),
            ACUITY_OK,
        );
        assert_eq!(count, 1);
        assert_eq!(fades[0].object, h);
        assert_eq!(fades[0].from_lod, 0);
        assert_eq!(fades[0].to_lod, u32::from(lod(s, h)));
        acuity_selector_free(s);
    }
}

/// A selector with `n` demo objects spread over 3 to 3 + 4n m in front of
/// the camera, created with `settings`.
fn scene(settings: &AcuitySettings, n: u32) -> *mut AcuitySelector {
    let mut s = null_mut();
    // SAFETY: live structs, selector and out-pointers throughout.
    unsafe {
        expect(acuity_selector_new(&DISPLAY, settings, &mut s), ACUITY_OK);
        let p = demo();
        expect(acuity_selector_add_profile(s, p, &mut 0), ACUITY_OK);
        expect(acuity_profile_free(p), ACUITY_OK);
        for i in 0..n {
            let mut d = desc(-3.0 - 4.0 * f64::from(i));
            d.center.x = f64::from(i % 7) - 3.0;
            expect(acuity_selector_add_object(s, &d, &mut 0), ACUITY_OK);
        }
    }
    s
}

fn triangles(s: *mut AcuitySelector) -> u64 {
    let mut stats = AcuityStats::default();
    // SAFETY: live selector and out-pointer.
    expect(unsafe { acuity_selector_stats(s, &mut stats) }, ACUITY_OK);
    stats.triangles
}

#[test]
fn a_triangle_budget_is_met_and_can_be_turned_off() {
    let s = scene(&AcuitySettings::default(), 40);
    let frame = AcuityFrame::default();
    expect(select(s, &frame), ACUITY_OK);
    let free = triangles(s);
    // SAFETY: live selector throughout.
    unsafe {
        expect(acuity_selector_set_budget(s, free / 3), ACUITY_OK);
        expect(select(s, &frame), ACUITY_OK);
        let within = triangles(s);
        assert!(
            within <= free / 3,
            "{within} triangles for a budget of {}",
            free / 3
        );
        assert!(within > 0);
        expect(acuity_selector_set_budget(s, ACUITY_NO_BUDGET), ACUITY_OK);
        expect(select(s, &frame), ACUITY_OK);
        assert_eq!(triangles(s), free);
        expect(
            acuity_selector_set_budget(null_mut(), 10),
            ACUITY_NULL_POINTER,
        );
        acuity_selector_free(s);
    }
}

/// A plant for the schedulers: 40 objects, frames of a period, 2 ms of
/// fixed time and a cost per triangle.
struct Plant {
    selector: *mut AcuitySelector,
    frame: AcuityFrame,
    per_triangle_s: f32,
}

impl Plant {
    /// Frames of `period_s`, full detail taking `full_periods` periods.
    fn new(period_s: f32, full_periods: f32) -> Plant {
        let selector = scene(&AcuitySettings::default(), 40);
        let frame = AcuityFrame {
            dt_s: period_s,
            ..AcuityFrame::default()
        };
        expect(select(selector, &frame), ACUITY_OK);
        let per_triangle_s = (full_periods * period_s - 2e-3) / triangles(selector) as f32;
        Plant {
            selector,
            frame,
            per_triangle_s,
        }
    }

    /// One frame under `sched`: its knob applied, a selection, and the
    /// frame's time (the fixed time, the triangles drawn and `load_s`)
    /// observed. Returns that time, s.
    ///
    /// # Safety
    /// `sched` must be a live scheduler.
    unsafe fn frame(&self, sched: *mut AcuityScheduler, load_s: f32) -> f32 {
        let s = self.selector;
        // SAFETY: a live scheduler by this function's contract, and the
        // plant's live selector.
        unsafe {
            expect(acuity_scheduler_apply(sched, s), ACUITY_OK);
            expect(select(s, &self.frame), ACUITY_OK);
            let t = 2e-3 + triangles(s) as f32 * self.per_triangle_s + load_s;
            expect(acuity_scheduler_observe(sched, t, s), ACUITY_OK);
            t
        }
    }
}

#[test]
fn a_reactive_scheduler_started_low_climbs_without_the_late_start_from_c() {
    // The plant of the next test with full detail at 1.5x the 60 Hz
    // period (its lowest s at about half the period): from s = 1 the
    // reactive scheduler's first frame is late; started at its lowest s
    // it climbs, on time from the first frame.
    let period_s = 1.0 / 60.0;
    let plant = Plant::new(period_s, 1.5);
    let mut sched = null_mut();
    // SAFETY: live scheduler, selector and out-pointers throughout.
    unsafe {
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 60.0, &mut sched),
            ACUITY_OK,
        );
        for scale in [0.0, -0.5, 1.5, f32::NAN, f32::INFINITY] {
            expect(
                acuity_scheduler_start_at(sched, scale),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(
            acuity_scheduler_start_at(null_mut(), 0.5),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_scheduler_start_at(sched, 1e-6), ACUITY_OK);
        let mut state = AcuitySchedulerState::default();
        expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
        assert_eq!(state.scale, 1e-3, "the lowest s");
        let late: Vec<usize> = (0..30)
            .filter(|_| plant.frame(sched, 0.0) > period_s)
            .collect();
        assert!(late.is_empty(), "late frames {late:?}");
        expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
        assert!(state.scale > 0.02, "climbed to {}", state.scale);
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_PREDICTIVE, 60.0, &mut sched),
            ACUITY_OK,
        );
        let m = expect(
            acuity_scheduler_start_at(sched, 0.5),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("predictive"), "{m}");
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        acuity_selector_free(plant.selector);
    }
}

#[test]
fn both_schedulers_hold_a_rate_from_c() {
    // A plant: 2 ms of fixed time and a cost per triangle that makes full
    // detail take 3x the 60 Hz period; every object's coarsest LOD fits.
    let period_s = 1.0 / 60.0;
    for kind in [ACUITY_SCHEDULER_REACTIVE, ACUITY_SCHEDULER_PREDICTIVE] {
        let plant = Plant::new(period_s, 3.0);
        let mut sched = null_mut();
        let mut late = Vec::new();
        // SAFETY: live scheduler, selector and out-pointers throughout.
        unsafe {
            expect(acuity_scheduler_new(kind, 60.0, &mut sched), ACUITY_OK);
            for k in 0..200 {
                if plant.frame(sched, 0.0) > period_s {
                    late.push(k);
                }
            }
            let mut state = AcuitySchedulerState::default();
            expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
            assert!(state.aim_s > 0.5 * period_s && state.aim_s < period_s);
            match kind {
                ACUITY_SCHEDULER_REACTIVE => {
                    assert!(state.scale < 1.0 && state.budget == ACUITY_NO_BUDGET);
                }
                _ => assert!(state.scale == 1.0 && state.budget < 4000 * 40),
            }
            expect(acuity_scheduler_free(sched), ACUITY_OK);
            acuity_selector_free(plant.selector);
        }
        assert!(
            late.iter().all(|&k| k < 10),
            "kind {kind}: late frames {late:?}"
        );
    }
}

#[test]
fn both_schedulers_report_a_load_no_lod_absorbs_and_hold_their_knob() {
    // A plant whose full detail takes 1.5x the 60 Hz period (a triangle
    // costs about 150x the schedulers' first guess), settled, then 30
    // frames with twice the period of extra work: no LOD choice reaches
    // 60 Hz, and lowering detail would buy nothing. (A scheduler whose
    // cost model has not yet seen frames of different triangle counts
    // knows no floor, and may lower its knob in the spike's first frame.)
    let period_s = 1.0 / 60.0;
    for kind in [ACUITY_SCHEDULER_REACTIVE, ACUITY_SCHEDULER_PREDICTIVE] {
        let plant = Plant::new(period_s, 1.5);
        let mut sched = null_mut();
        let mut state = AcuitySchedulerState::default();
        let (mut reported, mut before) = (0, AcuitySchedulerState::default());
        // SAFETY: live scheduler, selector and out-pointers throughout.
        unsafe {
            expect(acuity_scheduler_new(kind, 60.0, &mut sched), ACUITY_OK);
            for k in 0..230 {
                let load_s = if k >= 200 { 2.0 * period_s } else { 0.0 };
                plant.frame(sched, load_s);
                expect(acuity_scheduler_state(sched, &mut state), ACUITY_OK);
                if k == 0 {
                    assert_eq!(state.cost_floor_s, -1.0, "kind {kind}: no floor known yet");
                }
                if k == 199 {
                    assert_eq!(state.target_unreachable, 0, "kind {kind}: before the load");
                    // Known (once the frames' triangles have differed) or
                    // not, below the period.
                    assert!(
                        state.cost_floor_s == -1.0
                            || (state.cost_floor_s >= 0.0 && state.cost_floor_s <= period_s),
                        "kind {kind}: floor {} s before the load",
                        state.cost_floor_s
                    );
                }
                if k >= 200 && state.target_unreachable == 1 {
                    assert!(
                        state.cost_floor_s > period_s,
                        "kind {kind}: the floor says it too"
                    );
                    // Held from the first frame that knows the floor.
                    if reported == 0 {
                        before = state;
                    }
                    reported += 1;
                }
            }
            expect(acuity_scheduler_free(sched), ACUITY_OK);
            acuity_selector_free(plant.selector);
        }
        assert!(
            reported >= 28,
            "kind {kind}: {reported} of 30 frames reported"
        );
        assert!(
            state.scale >= 0.9 * before.scale && state.budget as f64 >= 0.9 * before.budget as f64,
            "kind {kind}: s {} -> {}, budget {} -> {}",
            before.scale,
            state.scale,
            before.budget,
            state.budget
        );
    }
}

#[test]
fn schedulers_refuse_bad_input_by_name() {
    let s = scene(&AcuitySettings::default(), 3);
    let mut sched = null_mut();
    // SAFETY: live or NULL pointers as each call documents.
    unsafe {
        let m = expect(
            acuity_scheduler_new(7, 60.0, &mut sched),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("kind"), "{m}");
        for rate_hz in [0.0, -5.0, f32::NAN, f32::INFINITY, 1e6] {
            expect(
                acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, rate_hz, &mut sched),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 60.0, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_REACTIVE, 90.0, &mut sched),
            ACUITY_OK,
        );
        for t in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let m = expect(
                acuity_scheduler_observe(sched, t, s),
                ACUITY_INVALID_ARGUMENT,
            );
            assert!(m.contains("frame_time_s"), "{m}");
        }
        expect(
            acuity_scheduler_observe(sched, 0.01, null()),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_observe(null_mut(), 0.01, s),
            ACUITY_NULL_POINTER,
        );
        expect(
            acuity_scheduler_apply(sched, null_mut()),
            ACUITY_NULL_POINTER,
        );
        expect(acuity_scheduler_apply(null_mut(), s), ACUITY_NULL_POINTER);
        expect(
            acuity_scheduler_state(sched, null_mut()),
            ACUITY_NULL_POINTER,
        );
        let m = expect(
            acuity_scheduler_announce_load(sched, 0.005),
            ACUITY_INVALID_ARGUMENT,
        );
        assert!(m.contains("reactive"), "{m}");
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(
            acuity_scheduler_new(ACUITY_SCHEDULER_PREDICTIVE, 90.0, &mut sched),
            ACUITY_OK,
        );
        expect(acuity_scheduler_announce_load(sched, 0.005), ACUITY_OK);
        for extra_s in [-1.0, f32::NAN] {
            expect(
                acuity_scheduler_announce_load(sched, extra_s),
                ACUITY_INVALID_ARGUMENT,
            );
        }
        expect(acuity_scheduler_free(sched), ACUITY_OK);
        expect(acuity_scheduler_free(null_mut()), ACUITY_OK);
        acuity_selector_free(s);
    }
}
