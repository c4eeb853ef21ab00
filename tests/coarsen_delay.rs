//! The coarsening delay ([`SelectorSettings::switch_coarsen_delay_s`]): a
//! coarsening the view asks for waits until it has been asked for that
//! long without a break; one a falling `s` asks for, and every refinement,
//! happen at once.

mod common;

use acuity::{Components, ObjectId, Selection, Selector, SelectorSettings};
use common::{display, four_lod_profile, frame_at, lods, on_axis, random_scene};
use glam::DVec3;

const DT_S: f32 = 1.0 / 15.0;
const DELAY_S: f32 = 0.25;

/// Without the velocity term: the camera jumps between two places, and
/// the jump's speed would coarsen everything for a frame.
fn plain() -> SelectorSettings {
    SelectorSettings {
        components: Components {
            velocity: false,
            ..Components::ALL
        },
        ..SelectorSettings::default()
    }
}

fn delayed() -> SelectorSettings {
    SelectorSettings {
        switch_coarsen_delay_s: DELAY_S,
        ..plain()
    }
}

/// How many of two selections' objects differ (a test failure prints
/// this, not 2000 selections).
fn differ(a: &[Selection], b: &[Selection]) -> usize {
    a.iter().zip(b).filter(|(a, b)| a != b).count()
}

/// The LODs of `sel`'s objects for a frame with the camera at `z` (the
/// objects lie at negative `z`: a larger `z` draws them smaller) and `s`.
fn lods_at(sel: &mut Selector, ids: &[ObjectId], z: f64, scale: f32) -> Vec<Selection> {
    let mut frame = frame_at(DVec3::new(0.0, 0.0, z), DT_S);
    frame.scale = scale;
    sel.select(&frame).unwrap();
    lods(sel, ids)
}

/// What a delayed selector draws while the view asks for `to` after
/// `from`: the coarsenings held, the refinements (and culling) at once.
fn held(from: &[Selection], to: &[Selection]) -> Vec<Selection> {
    from.iter()
        .zip(to)
        .map(|(&f, &t)| match (f.lod(), t.lod()) {
            (Some(f_lod), Some(t_lod)) if t_lod > f_lod => f,
            _ => t,
        })
        .collect()
}

/// The same 2000 objects with the delay and without; the LODs of the
/// plain selector with the camera near (`z = 0`) and backed away (some
/// objects coarsen as they shrink, some refine as they near the centre
/// of the view).
fn delayed_and_plain() -> (Selector, Vec<ObjectId>, Vec<Selection>, Vec<Selection>) {
    let (sel, ids) = random_scene(delayed(), 2000, 11, DVec3::ZERO);
    let (mut plain, _) = random_scene(plain(), 2000, 11, DVec3::ZERO);
    let near = lods_at(&mut plain, &ids, 0.0, 1.0);
    let far = lods_at(&mut plain, &ids, 40.0, 1.0);
    assert!(
        differ(&held(&near, &far), &far) > 0,
        "backing away must coarsen objects"
    );
    (sel, ids, near, far)
}

#[test]
fn a_coarsening_the_view_asks_for_waits_until_asked_for_that_long() {
    let (mut sel, ids, near, far) = delayed_and_plain();
    assert_eq!(differ(&lods_at(&mut sel, &ids, 0.0, 1.0), &near), 0);
    // Asked for at 0, 1/15, 2/15 and 3/15 s after the first far frame.
    for k in 0..4 {
        assert_eq!(
            differ(&lods_at(&mut sel, &ids, 40.0, 1.0), &held(&near, &far)),
            0,
            "coarsened {k}/15 s after the view asked"
        );
    }
    assert_eq!(
        differ(&lods_at(&mut sel, &ids, 40.0, 1.0), &far),
        0,
        "still held 4/15 s > 0.25 s after the view asked"
    );
    // Coming near again refines at once; what refined on the way out
    // (nearer the centre of the view from afar) waits to coarsen.
    assert_eq!(
        differ(&lods_at(&mut sel, &ids, 0.0, 1.0), &held(&far, &near)),
        0,
        "a refinement waited, or a coarsening did not"
    );
}

#[test]
fn a_coarsening_asked_for_again_after_a_break_waits_again() {
    let (mut sel, ids, near, far) = delayed_and_plain();
    let mut shown = lods_at(&mut sel, &ids, 0.0, 1.0);
    // Three frames out and one back, three times: no wait lasts the
    // delay, so no coarsening happens.
    for round in 0..3 {
        for (frames, z, asked) in [(3, 40.0, &far), (1, 0.0, &near)] {
            for _ in 0..frames {
                let expected = held(&shown, asked);
                shown = lods_at(&mut sel, &ids, z, 1.0);
                assert_eq!(differ(&shown, &expected), 0, "round {round}, z = {z}");
            }
        }
    }
    for _ in 0..4 {
        lods_at(&mut sel, &ids, 40.0, 1.0);
    }
    assert_eq!(differ(&lods_at(&mut sel, &ids, 40.0, 1.0), &far), 0);
}

#[test]
fn a_falling_scale_coarsens_at_once_and_the_view_still_waits_below_it() {
    let (mut sel, ids) = random_scene(delayed(), 2000, 12, DVec3::ZERO);
    let (mut plain, _) = random_scene(plain(), 2000, 12, DVec3::ZERO);
    let half_near = lods_at(&mut plain, &ids, 0.0, 0.5);
    let half_far = lods_at(&mut plain, &ids, 40.0, 0.5);
    assert!(differ(&held(&half_near, &half_far), &half_far) > 0);
    lods_at(&mut sel, &ids, 0.0, 1.0);
    assert_eq!(
        differ(&lods_at(&mut sel, &ids, 0.0, 0.5), &half_near),
        0,
        "a scheduler's lower s waited"
    );
    // `s` holds at 1/2: the view's coarsening waits.
    assert_eq!(
        differ(
            &lods_at(&mut sel, &ids, 40.0, 0.5),
            &held(&half_near, &half_far)
        ),
        0
    );
    // `s` falls a little: everything asked for goes at once.
    let lower_far = lods_at(&mut sel, &ids, 40.0, 0.49);
    let plain_lower_far = lods_at(&mut plain, &ids, 40.0, 0.49);
    assert_eq!(differ(&lower_far, &plain_lower_far), 0);
}

#[test]
fn under_a_budget_the_delay_holds_a_coarsening_only_within_the_room() {
    for tight in [false, true] {
        let (mut sel, ids, near, far) = delayed_and_plain();
        let (mut plain, _) = random_scene(plain(), 2000, 11, DVec3::ZERO);
        lods_at(&mut plain, &ids, 40.0, 1.0);
        let far_triangles = plain.triangles();
        let budget = if tight { far_triangles } else { u64::MAX };
        let frame = |z: f64| frame_at(DVec3::new(0.0, 0.0, z), DT_S);
        sel.select_within_budget(&frame(0.0), u64::MAX).unwrap();
        assert_eq!(differ(&lods(&sel, &ids), &near), 0);
        let out = sel.select_within_budget(&frame(40.0), budget).unwrap();
        assert!(out.within_budget, "{out:?}");
        if tight {
            assert_eq!(differ(&lods(&sel, &ids), &far), 0, "held beyond the budget");
        } else {
            assert_eq!(
                differ(&lods(&sel, &ids), &held(&near, &far)),
                0,
                "not held with room"
            );
        }
    }
}

#[test]
fn the_wait_follows_an_object_moved_to_another_slot() {
    // The last object takes the slot of a removed one that never waited:
    // its own wait, begun four frames ago, must carry over.
    let mut sel = Selector::new(display(), delayed());
    let p = sel.add_profile(&four_lod_profile(7)).unwrap();
    let (far, near) = (on_axis(&mut sel, p, -5000.0), on_axis(&mut sel, p, -20.0));
    let lod_at = |sel: &mut Selector, z: f64| {
        sel.select(&frame_at(DVec3::new(0.0, 0.0, z), DT_S))
            .unwrap();
        sel.selection(near).lod()
    };
    let fine = lod_at(&mut sel, 0.0);
    for _ in 0..4 {
        assert_eq!(lod_at(&mut sel, 200.0), fine);
    }
    sel.remove_object(far).unwrap();
    assert_ne!(
        lod_at(&mut sel, 200.0),
        fine,
        "the wait started again in the new slot"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..proptest::prelude::ProptestConfig::default()
    })]

    /// The delay only keeps detail: whatever the camera, `s` and `dt` do
    /// (`dt = 0` included), no object is ever coarser than without it.
    #[test]
    fn the_delay_never_draws_an_object_coarser_than_the_plain_rule(
        frames in proptest::collection::vec((-20.0f64..60.0, 0.05f32..=1.0, 0.0f32..0.2), 1..20),
    ) {
        let settings = SelectorSettings {
            switch_coarsen_delay_s: DELAY_S,
            ..SelectorSettings::default()
        };
        let (mut sel, ids) = random_scene(settings, 200, 13, DVec3::ZERO);
        let (mut plain, _) = random_scene(SelectorSettings::default(), 200, 13, DVec3::ZERO);
        for (z, scale, dt_s) in frames {
            let mut frame = frame_at(DVec3::new(0.0, 0.0, z), dt_s);
            frame.scale = scale;
            sel.select(&frame).unwrap();
            plain.select(&frame).unwrap();
            for (&shown, &asked) in lods(&sel, &ids).iter().zip(&lods(&plain, &ids)) {
                proptest::prop_assert_eq!(shown.is_culled(), asked.is_culled());
                if let (Some(shown), Some(asked)) = (shown.lod(), asked.lod()) {
                    proptest::prop_assert!(shown <= asked, "LOD {} where the plain rule draws {}", shown, asked);
                }
            }
        }
    }
}
