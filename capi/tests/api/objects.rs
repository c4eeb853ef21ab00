//! Objects through the C interface: added and removed under stable
//! handles, a frame's LODs, budgets (of triangles, and `s` spent as one)
//! and fades.

use super::*;

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
pub(crate) fn scene(settings: &AcuitySettings, n: u32) -> *mut AcuitySelector {
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

pub(crate) fn triangles(s: *mut AcuitySelector) -> u64 {
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
        // A budget of 1 is missed at the lowest `s`: the fewest triangles.
        expect(acuity_selector_set_budget(s, 1), ACUITY_OK);
        expect(select(s, &frame), ACUITY_OK);
        let floor = triangles(s);
        assert!(floor < free, "{floor} of {free}");
        let budget = floor + (free - floor) / 3;
        expect(acuity_selector_set_budget(s, budget), ACUITY_OK);
        expect(select(s, &frame), ACUITY_OK);
        let within = triangles(s);
        assert!(
            within <= budget,
            "{within} triangles for a budget of {budget}"
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
