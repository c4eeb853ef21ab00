//! Managing objects: removing them, changing their profile, reading all
//! selections and the change list, biases and LOD ranges. Cross-fades and
//! switches that wait for a saccade are in `transitions.rs`.

mod common;

use acuity::{
    Camera, Components, FrameInput, Gaze, ObjectDesc, ObjectId, ProfileId, Selection, Selector,
    SelectorSettings, Tracker,
};
use common::{Rng, display, four_lod_profile, on_axis, single_lod_profile};
use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;

/// Frame `f` of a camera that drifts forward and turns a little.
fn frame(f: usize) -> FrameInput {
    FrameInput {
        camera: Camera {
            position: DVec3::new(0.0, 0.0, -0.7 * f as f64),
            orientation: Quat::from_rotation_y(0.03 * f as f32),
        },
        gaze: Gaze::at_screen_angles(4.0, -3.0, Tracker::eye_default()),
        dt_s: 1.0 / 60.0,
        scale: 1.0,
    }
}

/// `n` random objects in front of the camera (every fifth one with a
/// single LOD), as descriptions to add to any selector with profiles
/// `[four LODs, one LOD]`.
fn descs(n: usize, seed: u64, profiles: [ProfileId; 2]) -> Vec<ObjectDesc> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|i| {
            let dir = Vec3::new(
                rng.range(-0.9, 0.9) as f32,
                rng.range(-0.6, 0.6) as f32,
                -1.0,
            )
            .normalize();
            ObjectDesc {
                center: dir.as_dvec3() * rng.range(3.0, 150.0),
                radius: rng.range(0.2, 3.0) as f32,
                rotation: rng.rotation(),
                profile: profiles[(i % 5 == 0) as usize],
            }
        })
        .collect()
}

fn selector(settings: SelectorSettings) -> (Selector, [ProfileId; 2]) {
    let mut sel = Selector::new(display(), settings);
    let four = sel.add_profile(&four_lod_profile(3)).unwrap();
    let one = sel.add_profile(&single_lod_profile()).unwrap();
    (sel, [four, one])
}

#[test]
fn removing_objects_leaves_the_others_selecting_as_if_never_there() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let all = descs(300, 1, profiles);
    let ids: Vec<ObjectId> = all.iter().map(|d| sel.add_object(*d).unwrap()).collect();
    let keep: Vec<bool> = (0..all.len()).map(|i| i % 3 != 1 && i % 7 != 0).collect();
    let (mut reference, _) = selector(SelectorSettings::default());
    let kept: Vec<ObjectId> = all
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(d, _)| reference.add_object(*d).unwrap())
        .collect();
    for f in 0..3 {
        sel.select(&frame(f)).unwrap();
        reference.select(&frame(f)).unwrap();
    }
    for (id, _) in ids.iter().zip(&keep).filter(|(_, k)| !**k) {
        sel.remove_object(*id).unwrap();
    }
    assert_eq!(sel.object_count(), kept.len());
    for f in 3..6 {
        sel.select_with_diagnostics(&frame(f)).unwrap();
        reference.select_with_diagnostics(&frame(f)).unwrap();
        let survivors = ids.iter().zip(&keep).filter(|(_, k)| **k).map(|(id, _)| id);
        for (&id, &twin) in survivors.zip(&kept) {
            assert_eq!(sel.selection(id), reference.selection(twin), "frame {f}");
            assert_eq!(sel.diagnostics(id), reference.diagnostics(twin));
        }
    }
}

#[test]
fn a_removed_id_is_refused_even_once_its_entry_is_reused() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let d = descs(3, 2, profiles);
    let a = sel.add_object(d[1]).unwrap();
    let b = sel.add_object(d[2]).unwrap();
    sel.remove_object(a).unwrap();
    assert!(!sel.contains(a) && sel.contains(b));
    assert!(sel.remove_object(a).is_err());
    assert!(sel.set_pose(a, DVec3::ZERO, Quat::IDENTITY).is_err());
    assert!(sel.set_radius(a, 1.0).is_err());
    assert!(sel.set_bias(a, 2.0).is_err());
    assert!(sel.set_profile(a, profiles[0]).is_err());
    let c = sel.add_object(d[1]).unwrap();
    assert_ne!(a, c);
    assert!(sel.contains(c) && !sel.contains(a));
}

#[test]
fn adding_after_removing_most_objects_keeps_the_lists_working() {
    let settings = SelectorSettings {
        fade_time_s: 0.1,
        ..Default::default()
    };
    let (mut sel, profiles) = selector(settings);
    let all = descs(100, 13, profiles);
    let ids: Vec<ObjectId> = all.iter().map(|d| sel.add_object(*d).unwrap()).collect();
    sel.select(&frame(0)).unwrap();
    assert!(sel.changed().len() > 20, "{}", sel.changed().len());
    let visible: Vec<bool> = ids
        .iter()
        .map(|&id| !sel.selection(id).is_culled())
        .collect();
    let sel_was_culled = |d: &ObjectDesc| !visible[all.iter().position(|x| x == d).unwrap()];
    for &id in &ids[..90] {
        sel.remove_object(id).unwrap();
    }
    // The change list of the last frame is longer than the objects left.
    let seen = (0..90).find(|&i| !sel_was_culled(&all[i])).unwrap();
    let again = sel.add_object(all[seen]).unwrap();
    sel.select(&frame(0)).unwrap();
    assert!(sel.changed().contains(&again));
    assert_eq!(sel.object_count(), 11);
}

#[test]
#[should_panic(expected = "not in this selector")]
fn reading_a_removed_objects_selection_panics_with_a_reason() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let a = sel.add_object(descs(1, 3, profiles)[0]).unwrap();
    sel.remove_object(a).unwrap();
    sel.selection(a);
}

#[test]
fn changing_profile_keeps_the_id_and_selects_as_the_new_profile() {
    // Without velocity, so a fresh twin has the same history.
    let settings = SelectorSettings {
        components: Components {
            velocity: false,
            ..Components::ALL
        },
        ..Default::default()
    };
    let (mut sel, profiles) = selector(settings);
    let coarse = sel.add_profile(&four_lod_profile(9)).unwrap();
    let all = descs(40, 4, profiles);
    let ids: Vec<ObjectId> = all.iter().map(|d| sel.add_object(*d).unwrap()).collect();
    sel.select(&frame(0)).unwrap();
    // Every object to another profile: four LODs to one, one to four,
    // four to another four.
    let swapped = |p: ProfileId, i: usize| match (p == profiles[1], i % 2) {
        (true, _) => profiles[0],
        (false, 0) => profiles[1],
        (false, _) => coarse,
    };
    for (i, (&id, d)) in ids.iter().zip(&all).enumerate() {
        sel.set_profile(id, swapped(d.profile, i)).unwrap();
        assert_eq!(sel.profile_of(id).unwrap(), swapped(d.profile, i));
        assert!(sel.selection(id).is_culled(), "not selected since");
    }
    let mut twin = Selector::new(display(), settings);
    for p in [
        four_lod_profile(3),
        single_lod_profile(),
        four_lod_profile(9),
    ] {
        twin.add_profile(&p).unwrap();
    }
    let twins: Vec<ObjectId> = all
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let profile = swapped(d.profile, i);
            twin.add_object(ObjectDesc { profile, ..*d }).unwrap()
        })
        .collect();
    sel.select(&frame(1)).unwrap();
    twin.select(&frame(1)).unwrap();
    for (&id, &t) in ids.iter().zip(&twins) {
        assert_eq!(sel.selection(id), twin.selection(t));
    }
    assert_eq!(sel.triangles(), twin.triangles());
}

#[test]
fn selections_and_object_ids_are_parallel_slices_of_every_object() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let ids: Vec<ObjectId> = descs(200, 5, profiles)
        .into_iter()
        .map(|d| sel.add_object(d).unwrap())
        .collect();
    for id in ids.iter().step_by(4) {
        sel.remove_object(*id).unwrap();
    }
    sel.select(&frame(2)).unwrap();
    assert_eq!(sel.selections().len(), sel.object_count());
    assert_eq!(sel.object_ids().len(), sel.object_count());
    for (&id, &s) in sel.object_ids().iter().zip(sel.selections()) {
        assert_eq!(sel.selection(id), s);
    }
    let mut listed = sel.object_ids().to_vec();
    listed.sort_by_key(|id| format!("{id:?}"));
    listed.dedup();
    assert_eq!(listed.len(), sel.object_count());
}

#[test]
fn the_change_list_holds_exactly_the_objects_whose_selection_changed() {
    let (mut sel, profiles) = selector(SelectorSettings {
        track_changes: true,
        ..Default::default()
    });
    let ids: Vec<ObjectId> = descs(500, 6, profiles)
        .into_iter()
        .map(|d| sel.add_object(d).unwrap())
        .collect();
    // New objects count as culled before their first frame.
    let mut before = vec![Selection::CULLED; ids.len()];
    let mut total = 0;
    for f in 0..12 {
        sel.select(&frame(f)).unwrap();
        let mut expected: Vec<ObjectId> = ids
            .iter()
            .zip(&before)
            .filter(|&(&id, &b)| sel.selection(id) != b)
            .map(|(&id, _)| id)
            .collect();
        let mut got = sel.changed().to_vec();
        let key = |id: &ObjectId| format!("{id:?}");
        expected.sort_by_key(key);
        got.sort_by_key(key);
        assert_eq!(got, expected, "frame {f}");
        total += got.len();
        before = ids.iter().map(|&id| sel.selection(id)).collect();
    }
    assert!(total > 50, "the camera path should switch LODs: {total}");
    // The same frame again (no time passed): nothing changes.
    let still = FrameInput {
        dt_s: 0.0,
        ..frame(11)
    };
    sel.select(&still).unwrap();
    sel.select(&still).unwrap();
    assert!(sel.changed().is_empty(), "{:?}", sel.changed());
}

#[test]
fn without_change_tracking_the_change_list_stays_empty() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    for d in descs(50, 6, profiles) {
        sel.add_object(d).unwrap();
    }
    sel.select(&frame(0)).unwrap();
    assert!(sel.selections().iter().any(|s| !s.is_culled()));
    assert!(sel.changed().is_empty());
}

#[test]
fn a_bias_above_one_keeps_detail_and_below_one_drops_it() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let distances = [4.0, 10.0, 25.0, 60.0, 150.0];
    let plain: Vec<ObjectId> = distances
        .iter()
        .map(|&d| on_axis(&mut sel, profiles[0], -d))
        .collect();
    let fine: Vec<ObjectId> = distances
        .iter()
        .map(|&d| on_axis(&mut sel, profiles[0], -d))
        .collect();
    let coarse: Vec<ObjectId> = distances
        .iter()
        .map(|&d| on_axis(&mut sel, profiles[0], -d))
        .collect();
    for (&f, &c) in fine.iter().zip(&coarse) {
        sel.set_bias(f, 4.0).unwrap();
        sel.set_bias(c, 0.25).unwrap();
    }
    sel.select(&frame(0)).unwrap();
    let lod = |sel: &Selector, id| sel.selection(id).lod().unwrap();
    let (mut finer, mut coarser) = (false, false);
    for i in 0..distances.len() {
        let [f, p, c] = [fine[i], plain[i], coarse[i]].map(|id| lod(&sel, id));
        assert!(f <= p && p <= c, "{f} {p} {c}");
        finer |= f < p;
        coarser |= p < c;
    }
    assert!(finer && coarser, "the biases should change some LOD");
    assert_eq!(sel.bias(fine[0]).unwrap(), 4.0);
    assert_eq!(sel.bias(plain[0]).unwrap(), 1.0);
    // Back to 1: selects like an object that never had a bias.
    for &f in &fine {
        sel.set_bias(f, 1.0).unwrap();
    }
    sel.select(&frame(0)).unwrap();
    for i in 0..distances.len() {
        assert_eq!(lod(&sel, fine[i]), lod(&sel, plain[i]));
    }
}

#[test]
fn bad_biases_and_empty_ranges_are_refused() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let id = on_axis(&mut sel, profiles[0], -10.0);
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(sel.set_bias(id, bad).is_err(), "{bad}");
    }
    #[allow(clippy::reversed_empty_ranges)]
    let empty = 3..=1;
    assert!(sel.set_lod_range(id, empty).is_err());
    assert_eq!(sel.lod_range(id).unwrap(), 0..=usize::MAX);
    sel.set_lod_range(id, 1..=2).unwrap();
    assert_eq!(sel.lod_range(id).unwrap(), 1..=2);
}

#[test]
fn the_budget_counts_biases_and_ranges() {
    let (mut sel, profiles) = selector(SelectorSettings::default());
    let ids: Vec<ObjectId> = descs(400, 8, profiles)
        .into_iter()
        .map(|d| sel.add_object(d).unwrap())
        .collect();
    for (i, &id) in ids.iter().enumerate() {
        match i % 4 {
            0 => sel.set_bias(id, 3.0).unwrap(),
            1 => sel.set_lod_range(id, 1..=2).unwrap(),
            2 => sel.set_bias(id, 0.5).unwrap(),
            _ => {}
        }
    }
    sel.select(&frame(1)).unwrap();
    let full = sel.triangles();
    // The fewest triangles the biases and ranges allow (a budget of 0 is
    // missed at the lowest `s`); every budget between it and `s = 1`'s fits.
    let floor = sel.select_within_budget(&frame(1), 0).unwrap();
    assert!(!floor.within_budget && floor.triangles < full, "{floor:?}");
    let span = full - floor.triangles;
    for budget in [floor.triangles + span / 2, floor.triangles + span / 4, full] {
        let out = sel.select_within_budget(&frame(1), budget).unwrap();
        assert_eq!(out.triangles, sel.triangles(), "budget {budget}");
        assert!(out.within_budget, "{out:?} for {budget}");
        for (i, &id) in ids.iter().enumerate() {
            if let (1, Some(lod)) = (i % 4, sel.selection(id).lod())
                && sel.profile_of(id).unwrap() == profiles[0]
            {
                assert!((1..=2).contains(&lod), "{lod}");
            }
        }
    }
}

fn arbitrary_range() -> impl Strategy<Value = (usize, usize)> {
    (0usize..6, 0usize..6).prop_map(|(a, b)| (a.min(b), a.max(b)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Whatever is removed, added or changed, every live id reads its own
    /// object: its selection matches a selector holding the same objects.
    #[test]
    fn ids_survive_any_sequence_of_removals_and_additions(
        ops in proptest::collection::vec((0u8..4, 0usize..1000), 1..60),
        seed in 0u64..1000,
    ) {
        let settings = SelectorSettings {
            components: Components { velocity: false, ..Components::ALL },
            ..Default::default()
        };
        let (mut sel, profiles) = selector(settings);
        let pool = descs(64, seed, profiles);
        let mut live: Vec<(ObjectId, ObjectDesc)> = Vec::new();
        for (op, k) in ops {
            match op {
                0 | 1 => {
                    let d = pool[k % pool.len()];
                    live.push((sel.add_object(d).unwrap(), d));
                }
                2 if !live.is_empty() => {
                    let (id, _) = live.swap_remove(k % live.len());
                    sel.remove_object(id).unwrap();
                    prop_assert!(!sel.contains(id));
                }
                3 if !live.is_empty() => {
                    let at = k % live.len();
                    let p = profiles[k % 2];
                    sel.set_profile(live[at].0, p).unwrap();
                    live[at].1.profile = p;
                }
                _ => {}
            }
        }
        prop_assert_eq!(sel.object_count(), live.len());
        let (mut twin, _) = selector(settings);
        let twins: Vec<ObjectId> = live.iter().map(|(_, d)| twin.add_object(*d).unwrap()).collect();
        sel.select(&frame(1)).unwrap();
        twin.select(&frame(1)).unwrap();
        for ((id, _), t) in live.iter().zip(&twins) {
            prop_assert_eq!(sel.selection(*id), twin.selection(*t));
        }
    }

    /// A visible object's LOD always lies in its range (as far as its
    /// profile goes), plain or within a budget.
    #[test]
    fn lod_ranges_are_always_respected(
        ranges in proptest::collection::vec(arbitrary_range(), 30),
        bias in 0.05f32..20.0,
        budget_fraction in 0.0f64..1.2,
        f in 0usize..8,
    ) {
        let (mut sel, profiles) = selector(SelectorSettings::default());
        let ids: Vec<ObjectId> = descs(30, 11, profiles)
            .into_iter()
            .map(|d| sel.add_object(d).unwrap())
            .collect();
        for (i, (&id, &(lo, hi))) in ids.iter().zip(&ranges).enumerate() {
            sel.set_lod_range(id, lo..=hi).unwrap();
            if i % 2 == 0 {
                sel.set_bias(id, bias).unwrap();
            }
        }
        let check = |sel: &Selector| -> Result<(), TestCaseError> {
            for (&id, &(lo, hi)) in ids.iter().zip(&ranges) {
                let n = if sel.profile_of(id).unwrap() == profiles[0] { 4 } else { 1 };
                if let Some(lod) = sel.selection(id).lod() {
                    prop_assert!(lod >= lo.min(n - 1) && lod <= hi.min(n - 1), "{lod} {lo} {hi}");
                }
            }
            Ok(())
        };
        sel.select(&frame(f)).unwrap();
        check(&sel)?;
        let full = sel.triangles();
        sel.select_within_budget(&frame(f), (full as f64 * budget_fraction) as u64).unwrap();
        check(&sel)?;
    }

    /// A larger bias never gives a coarser LOD.
    #[test]
    fn lods_never_coarsen_as_the_bias_grows(
        biases in proptest::collection::vec(0.01f32..100.0, 2..6),
        seed in 0u64..1000,
        f in 0usize..8,
    ) {
        let mut biases = biases;
        biases.sort_by(f32::total_cmp);
        let (mut sel, profiles) = selector(SelectorSettings::default());
        let ids: Vec<ObjectId> = descs(40, seed, profiles)
            .into_iter()
            .map(|d| sel.add_object(d).unwrap())
            .collect();
        let mut before: Option<Vec<Selection>> = None;
        for &b in &biases {
            for &id in &ids {
                sel.set_bias(id, b).unwrap();
            }
            // Same frame every time (dt 0: velocities stay).
            sel.select(&FrameInput { dt_s: 0.0, ..frame(f) }).unwrap();
            let now: Vec<Selection> = ids.iter().map(|&id| sel.selection(id)).collect();
            if let Some(before) = &before {
                for (a, b) in before.iter().zip(&now) {
                    prop_assert_eq!(a.is_culled(), b.is_culled());
                    prop_assert!(b.lod() <= a.lod(), "{:?} then {:?}", a, b);
                }
            }
            before = Some(now);
        }
    }
}

/// On rayon, biases and diagnostics together select as on one thread
/// (the loop's parallel split hands out both outputs).
#[cfg(feature = "parallel")]
#[test]
fn biased_diagnostics_on_rayon_match_one_thread() {
    let make = |parallel_min_objects| {
        let (mut sel, profiles) = selector(SelectorSettings {
            parallel_min_objects,
            ..Default::default()
        });
        let ids: Vec<ObjectId> = descs(20_000, 12, profiles)
            .into_iter()
            .map(|d| sel.add_object(d).unwrap())
            .collect();
        for &id in ids.iter().step_by(3) {
            sel.set_bias(id, 3.0).unwrap();
        }
        (sel, ids)
    };
    let (mut serial, ids) = make(usize::MAX);
    let (mut parallel, _) = make(0);
    for f in 0..3 {
        serial.select_with_diagnostics(&frame(f)).unwrap();
        parallel.select_with_diagnostics(&frame(f)).unwrap();
        assert_eq!(serial.selections(), parallel.selections());
        for &id in &ids {
            assert_eq!(serial.diagnostics(id), parallel.diagnostics(id));
        }
    }
}
