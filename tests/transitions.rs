//! Switching over time: cross-fades between LODs
//! ([`SelectorSettings::fade_time_s`]) and switches to a coarser LOD that
//! wait for a saccade ([`SelectorSettings::defer_coarsening_s`]).

mod common;

use acuity::{Camera, Components, FrameInput, Gaze, ObjectId, Selector, SelectorSettings, Tracker};
use common::{display, four_lod_profile, on_axis};
use glam::{DVec3, Quat};

/// The camera at the origin looking along -Z, the eye tracker's gaze 4 deg
/// right of and 3 deg below the centre, 60 Hz.
fn frame0() -> FrameInput {
    FrameInput {
        camera: Camera {
            position: DVec3::ZERO,
            orientation: Quat::IDENTITY,
        },
        gaze: Gaze::at_screen_angles(4.0, -3.0, Tracker::eye_default()),
        dt_s: 1.0 / 60.0,
        scale: 1.0,
    }
}

/// A selector with `settings`, velocity off, and one object 3 m ahead.
fn one_ahead(settings: SelectorSettings) -> (Selector, ObjectId) {
    let settings = SelectorSettings {
        components: Components {
            velocity: false,
            ..Components::ALL
        },
        ..settings
    };
    let mut sel = Selector::new(display(), settings);
    let profile = sel.add_profile(&four_lod_profile(3)).unwrap();
    let id = on_axis(&mut sel, profile, -3.0);
    (sel, id)
}

fn fading(fade_time_s: f32) -> (Selector, ObjectId) {
    one_ahead(SelectorSettings {
        fade_time_s,
        ..Default::default()
    })
}

/// The fade time of the fade tests, s: with steps of a power of two times
/// it, fractions add up exactly.
const FADE_S: f32 = 0.125;

/// Moves the object to `distance` and lets any fade end.
fn settle(sel: &mut Selector, id: ObjectId, distance: f64) -> usize {
    step(sel, id, distance, 1.0);
    step(sel, id, distance, 1.0).unwrap()
}

/// Moves the object to `distance` and selects with `dt_s`.
fn step(sel: &mut Selector, id: ObjectId, distance: f64, dt_s: f32) -> Option<usize> {
    sel.set_pose(id, DVec3::new(0.0, 0.0, -distance), Quat::IDENTITY)
        .unwrap();
    sel.select(&FrameInput { dt_s, ..frame0() }).unwrap();
    sel.selection(id).lod()
}

#[test]
fn without_a_fade_time_lods_switch_at_once() {
    let (mut sel, id) = fading(0.0);
    let near = step(&mut sel, id, 3.0, 0.01);
    let far = step(&mut sel, id, 200.0, 0.01);
    assert_ne!(near, far);
    assert!(sel.fades().is_empty() && sel.fade(id).is_none());
}

#[test]
fn a_switch_fades_over_the_fade_time() {
    let (mut sel, id) = fading(FADE_S);
    let near = settle(&mut sel, id, 3.0);
    let far = step(&mut sel, id, 200.0, 0.5 * FADE_S).unwrap();
    assert_ne!(near, far);
    let f = sel.fade(id).unwrap();
    assert_eq!(
        (f.object, f.from_lod, f.to_lod, f.fraction),
        (id, near, far, 0.0)
    );
    assert_eq!(sel.fades(), &[f]);
    // A quarter of the fade time a frame: 0.25, 0.5, 0.75, then done.
    for k in 1..=3 {
        step(&mut sel, id, 200.0, 0.25 * FADE_S);
        assert_eq!(sel.fade(id).unwrap().fraction, 0.25 * k as f32);
    }
    step(&mut sel, id, 200.0, 0.25 * FADE_S);
    assert_eq!(sel.fade(id), None);
    assert!(sel.fades().is_empty());
    // A frame without a valid dt does not advance a fade.
    step(&mut sel, id, 3.0, 0.25 * FADE_S);
    step(&mut sel, id, 3.0, 0.0);
    assert_eq!(sel.fade(id).unwrap().fraction, 0.0);
}

#[test]
fn switching_back_mid_fade_reverses_it() {
    let (mut sel, id) = fading(FADE_S);
    let near = settle(&mut sel, id, 3.0);
    let far = step(&mut sel, id, 200.0, 0.0).unwrap();
    step(&mut sel, id, 200.0, 0.75 * FADE_S);
    let back = step(&mut sel, id, 3.0, 0.0).unwrap();
    assert_eq!(back, near);
    let f = sel.fade(id).unwrap();
    assert_eq!((f.from_lod, f.to_lod, f.fraction), (far, near, 0.25));
}

#[test]
fn a_third_lod_mid_fade_starts_from_the_stronger_one() {
    let (mut sel, id) = fading(FADE_S);
    // Three distances with three different LODs.
    let mut at = Vec::new();
    for d in [3.0, 6.0, 12.0, 25.0, 50.0, 100.0, 200.0, 400.0] {
        let lod = settle(&mut sel, id, d);
        if at.last().is_none_or(|&(_, l)| l != lod) {
            at.push((d, lod));
        }
    }
    assert!(at.len() >= 3, "{at:?}");
    let [(d0, l0), (d1, l1), (d2, l2)] = [at[0], at[1], at[2]];
    for (fraction, stronger) in [(0.75, l1), (0.25, l0)] {
        settle(&mut sel, id, d0);
        step(&mut sel, id, d1, 0.0);
        step(&mut sel, id, d1, fraction * FADE_S);
        step(&mut sel, id, d2, 0.0);
        let f = sel.fade(id).unwrap();
        assert_eq!((f.from_lod, f.to_lod, f.fraction), (stronger, l2, 0.0));
    }
}

#[test]
fn culling_and_removal_end_a_fade() {
    let (mut sel, id) = fading(0.1);
    step(&mut sel, id, 3.0, 0.02);
    step(&mut sel, id, 200.0, 0.02);
    assert!(sel.fade(id).is_some());
    // Behind the camera: culled, no fade into or out of it.
    step(&mut sel, id, -50.0, 0.02);
    assert!(sel.selection(id).is_culled() && sel.fade(id).is_none());
    step(&mut sel, id, 200.0, 0.02);
    assert!(sel.fade(id).is_none());
    step(&mut sel, id, 3.0, 0.02);
    assert!(sel.fade(id).is_some());
    sel.remove_object(id).unwrap();
    assert!(sel.fades().is_empty());
}

/// A selector whose switches to coarser LODs wait up to `wait_s` for a
/// saccade, with one object 3 m ahead, settled.
fn deferring(wait_s: f32) -> (Selector, ObjectId) {
    let (mut sel, id) = one_ahead(SelectorSettings {
        defer_coarsening_s: wait_s,
        track_changes: true,
        ..Default::default()
    });
    settle(&mut sel, id, 3.0);
    (sel, id)
}

/// As [`step`], with the gaze at `gaze_x_deg` right of the centre (eye
/// tracker) or with `tracker`.
fn look(sel: &mut Selector, id: ObjectId, distance: f64, gaze_x_deg: f32, tracker: Tracker) {
    sel.set_pose(id, DVec3::new(0.0, 0.0, -distance), Quat::IDENTITY)
        .unwrap();
    let frame = FrameInput {
        gaze: Gaze::at_screen_angles(gaze_x_deg, 0.0, tracker),
        dt_s: 0.125,
        ..frame0()
    };
    sel.select(&frame).unwrap();
}

#[test]
fn a_switch_to_a_coarser_lod_waits_for_a_saccade_or_the_longest_wait() {
    let eye = Tracker::eye_default();
    let (mut sel, id) = deferring(0.5);
    let near = sel.selection(id).lod().unwrap();
    let (mut at_once, other) = deferring(0.0);
    look(&mut at_once, other, 200.0, 0.0, eye);
    let far = at_once.selection(other).lod().unwrap();
    assert!(far > near);
    // Fixating: held for 0.125, 0.25 and 0.375 s, switched at 0.5 s.
    for k in 1..=4 {
        look(&mut sel, id, 200.0, 0.0, eye);
        let (lod, listed) = (
            sel.selection(id).lod().unwrap(),
            sel.changed().contains(&id),
        );
        if k < 4 {
            assert_eq!((lod, listed), (near, false), "frame {k}");
        } else {
            assert_eq!((lod, listed), (far, true), "frame {k}");
        }
    }
    // Back near: a finer LOD comes at once.
    look(&mut sel, id, 3.0, 0.0, eye);
    assert_eq!(sel.selection(id).lod(), Some(near));
    // Far again: held, then switched in the frame the gaze jumps 20 deg
    // in 1/90 s (1800 deg/s: a saccade).
    look(&mut sel, id, 200.0, 0.0, eye);
    assert_eq!(sel.selection(id).lod(), Some(near));
    sel.set_pose(id, DVec3::new(0.0, 0.0, -200.0), Quat::IDENTITY)
        .unwrap();
    sel.select(&FrameInput {
        gaze: Gaze::at_screen_angles(20.0, 0.0, eye),
        dt_s: 1.0 / 90.0,
        ..frame0()
    })
    .unwrap();
    assert!(
        sel.selection(id).lod() > Some(near),
        "switched in the saccade"
    );
    assert!(sel.changed().contains(&id));
}

#[test]
fn under_a_budget_a_switch_waits_only_while_the_budget_has_room() {
    let eye = Tracker::eye_default();
    let far_frame = |sel: &mut Selector, id: ObjectId| {
        sel.set_pose(id, DVec3::new(0.0, 0.0, -200.0), Quat::IDENTITY)
            .unwrap();
        FrameInput {
            gaze: Gaze::at_screen_angles(0.0, 0.0, eye),
            dt_s: 0.125,
            ..frame0()
        }
    };
    let (mut at_once, other) = deferring(0.0);
    let f = far_frame(&mut at_once, other);
    let far = at_once.select_within_budget(&f, u64::MAX).unwrap();
    // A generous budget: the switch waits, and the outcome counts the
    // finer LOD it holds.
    let (mut sel, id) = deferring(0.5);
    let near = sel.selection(id).lod().unwrap();
    let f = far_frame(&mut sel, id);
    let held = sel.select_within_budget(&f, u64::MAX).unwrap();
    assert_eq!(sel.selection(id).lod(), Some(near));
    assert!(held.triangles > far.triangles, "{held:?} {far:?}");
    assert_eq!(held.triangles, sel.triangles());
    // A budget with no room for the finer LOD: the switch happens now.
    let (mut sel, id) = deferring(0.5);
    let f = far_frame(&mut sel, id);
    let tight = sel.select_within_budget(&f, far.triangles).unwrap();
    assert_eq!(sel.selection(id), at_once.selection(other));
    assert!(sel.selection(id).lod() > Some(near));
    assert!(sel.changed().contains(&id));
    assert_eq!(
        (tight.triangles, tight.within_budget),
        (far.triangles, true)
    );
    assert_eq!(tight.triangles, sel.triangles());
}

#[test]
fn a_wait_ends_without_a_switch_when_the_coarser_lod_is_no_longer_chosen() {
    let eye = Tracker::eye_default();
    let (mut sel, id) = deferring(0.5);
    let near = sel.selection(id).lod().unwrap();
    for _ in 0..3 {
        look(&mut sel, id, 200.0, 0.0, eye);
    }
    look(&mut sel, id, 3.0, 0.0, eye);
    assert!(!sel.changed().contains(&id), "nothing switched");
    // The wait starts over: three more frames far are held again.
    for _ in 0..3 {
        look(&mut sel, id, 200.0, 0.0, eye);
        assert_eq!(sel.selection(id).lod(), Some(near));
    }
}

#[test]
fn without_an_eye_tracker_or_a_wait_time_switches_happen_at_once() {
    for (wait_s, tracker) in [
        (0.5, Tracker::None),
        (0.5, Tracker::Head),
        (0.0, Tracker::eye_default()),
        (f32::NAN, Tracker::eye_default()),
    ] {
        let (mut sel, id) = deferring(wait_s);
        let near = sel.selection(id).lod().unwrap();
        look(&mut sel, id, 200.0, 0.0, tracker);
        assert!(
            sel.selection(id).lod().unwrap() > near,
            "{wait_s} {tracker:?}"
        );
    }
}

#[test]
fn a_waiting_switch_never_leaves_the_lod_range() {
    let eye = Tracker::eye_default();
    let (mut sel, id) = deferring(0.5);
    let near = sel.selection(id).lod().unwrap();
    sel.set_lod_range(id, near + 1..=usize::MAX).unwrap();
    look(&mut sel, id, 3.0, 0.0, eye);
    assert_eq!(
        sel.selection(id).lod(),
        Some(near + 1),
        "out of range at once"
    );
}
