//! Behaviour of the per-object selection.

mod common;

use acuity::{
    Camera, Components, FrameInput, Gaze, ObjectDesc, Selector, SelectorSettings, Tracker,
    ViewpointRule,
};
use common::{display, four_lod_profile, frame_at, lods, random_scene, single_lod_profile};
use glam::{DVec3, Quat, Vec3};

#[test]
fn camera_inside_a_bounding_sphere_gets_lod_0_whatever_the_components() {
    for bits in 0..8u8 {
        let components = Components {
            size: bits & 1 != 0,
            velocity: bits & 2 != 0,
            eccentricity: bits & 4 != 0,
        };
        let mut sel = Selector::new(
            display(),
            SelectorSettings {
                components,
                ..Default::default()
            },
        );
        let p = sel.add_profile(&four_lod_profile(1)).unwrap();
        // A big sphere around the camera, and one that is merely close.
        let around = sel
            .add_object(ObjectDesc {
                center: DVec3::new(0.5, 0.0, 0.0),
                radius: 2.0,
                rotation: Quat::IDENTITY,
                profile: p,
            })
            .unwrap();
        let mut frame = frame_at(DVec3::ZERO, 1.0 / 60.0);
        frame.scale = 0.01;
        for _ in 0..3 {
            frame.camera.position.x += 0.3; // moving fast inside it
            sel.select(&frame).unwrap();
            assert_eq!(
                sel.selection(around).lod(),
                Some(0),
                "components {components:?}"
            );
        }
    }
}

#[test]
fn objects_behind_or_beside_the_frustum_are_culled_unless_culling_is_off() {
    for cull in [true, false] {
        let mut sel = Selector::new(
            display(),
            SelectorSettings {
                cull,
                ..Default::default()
            },
        );
        let p = sel.add_profile(&four_lod_profile(1)).unwrap();
        let single = sel.add_profile(&single_lod_profile()).unwrap();
        let add = |sel: &mut Selector, center: DVec3, profile| {
            sel.add_object(ObjectDesc {
                center,
                radius: 1.0,
                rotation: Quat::IDENTITY,
                profile,
            })
            .unwrap()
        };
        let ahead = add(&mut sel, DVec3::new(0.0, 0.0, -10.0), p);
        let behind = add(&mut sel, DVec3::new(0.0, 0.0, 10.0), p);
        let beside = add(&mut sel, DVec3::new(50.0, 0.0, -10.0), p);
        let above = add(&mut sel, DVec3::new(0.0, 30.0, -10.0), p);
        let grazing = add(&mut sel, DVec3::new(0.0, 0.0, 0.9), p); // reaches past the eye plane
        let single_behind = add(&mut sel, DVec3::new(0.0, 0.0, 10.0), single);
        let single_ahead = add(&mut sel, DVec3::new(0.0, 0.0, -10.0), single);
        sel.select(&frame_at(DVec3::ZERO, 0.016)).unwrap();
        assert!(!sel.selection(ahead).is_culled());
        assert!(!sel.selection(grazing).is_culled());
        assert_eq!(sel.selection(single_ahead).lod(), Some(0));
        for id in [behind, beside, above, single_behind] {
            assert_eq!(
                sel.selection(id).is_culled(),
                cull,
                "{id:?} with cull = {cull}"
            );
        }
    }
}

#[test]
fn translating_the_whole_scene_by_1e5_changes_no_lod() {
    let settings = SelectorSettings::default();
    let offset = DVec3::new(1e5, -1e5, 1e5);
    let (mut a, ids_a) = random_scene(settings, 3000, 11, DVec3::ZERO);
    let (mut b, ids_b) = random_scene(settings, 3000, 11, offset);
    let mut changed = 0;
    for f in 0..10 {
        // The camera flies forward and turns: velocities are non-zero.
        let pos = DVec3::new(0.1 * f as f64, 0.0, -0.5 * f as f64);
        let mut fa = frame_at(pos, 1.0 / 60.0);
        fa.camera.orientation = Quat::from_rotation_y(0.01 * f as f32);
        let mut fb = fa;
        fb.camera.position += offset;
        a.select(&fa).unwrap();
        b.select(&fb).unwrap();
        let (la, lb) = (lods(&a, &ids_a), lods(&b, &ids_b));
        changed += la.iter().zip(&lb).filter(|(x, y)| x != y).count();
        assert!(
            la.iter().any(|l| l.lod() > Some(0)),
            "the scene must exercise coarse LODs"
        );
    }
    assert_eq!(changed, 0);
}

#[test]
fn world_coordinates_of_1e7_select_like_the_origin() {
    let (mut a, ids_a) = random_scene(SelectorSettings::default(), 500, 5, DVec3::ZERO);
    let far = DVec3::splat(1e7);
    let (mut b, ids_b) = random_scene(SelectorSettings::default(), 500, 5, far);
    a.select(&frame_at(DVec3::ZERO, 0.01)).unwrap();
    b.select(&frame_at(far, 0.01)).unwrap();
    assert_eq!(lods(&a, &ids_a), lods(&b, &ids_b));
}

#[test]
fn velocity_resolves_a_tenth_of_a_degree_per_second_at_90_hz() {
    for origin in [DVec3::ZERO, DVec3::splat(1e5)] {
        let mut sel = Selector::new(display(), SelectorSettings::default());
        let p = sel.add_profile(&four_lod_profile(2)).unwrap();
        let distance = 10.0;
        let id = sel
            .add_object(ObjectDesc {
                center: origin + DVec3::new(0.0, 0.0, -distance),
                radius: 0.5,
                rotation: Quat::IDENTITY,
                profile: p,
            })
            .unwrap();
        let dt = 1.0 / 90.0;
        let rate_rad = 0.1f64.to_radians();
        for f in 0..90 {
            let angle = rate_rad * dt as f64 * f as f64;
            let center = origin + DVec3::new(distance * angle.sin(), 0.0, -distance * angle.cos());
            sel.set_pose(id, center, Quat::IDENTITY).unwrap();
            sel.select_with_diagnostics(&frame_at(origin, dt)).unwrap();
        }
        let v = sel.diagnostics(id).unwrap().velocity_deg_per_s;
        assert!(
            (v - 0.1).abs() < 0.005,
            "measured {v} deg/s at origin {origin}"
        );
    }
}

#[test]
fn a_pursued_object_has_no_retinal_velocity() {
    // Continuous motion: on a sampled display the floor would bind.
    let continuous = display().with_refresh_hz(None).unwrap();
    let mut sel = Selector::new(continuous, SelectorSettings::default());
    let p = sel.add_profile(&four_lod_profile(3)).unwrap();
    let desc = |x| ObjectDesc {
        center: DVec3::new(x, 0.0, -10.0),
        radius: 3.0,
        rotation: Quat::IDENTITY,
        profile: p,
    };
    let pursued = sel.add_object(desc(0.0)).unwrap();
    let other = sel.add_object(desc(0.0)).unwrap();
    let mut frame = frame_at(DVec3::ZERO, 1.0 / 60.0);
    frame.gaze.pursued = Some(pursued);
    for f in 1..30 {
        let c = DVec3::new(0.25 * f as f64, 0.0, -10.0); // ~85 deg/s
        sel.set_pose(pursued, c, Quat::IDENTITY).unwrap();
        sel.set_pose(other, c, Quat::IDENTITY).unwrap();
        sel.select_with_diagnostics(&frame).unwrap();
    }
    assert_eq!(sel.diagnostics(pursued).unwrap().velocity_deg_per_s, 0.0);
    assert!(sel.diagnostics(other).unwrap().velocity_deg_per_s > 50.0);
    // The pursued object is judged at rest: a finer threshold, never a
    // coarser LOD.
    let (dp, d_other) = (
        sel.diagnostics(pursued).unwrap(),
        sel.diagnostics(other).unwrap(),
    );
    assert!(
        dp.threshold_cpd > 5.0 * d_other.threshold_cpd,
        "{dp:?} {d_other:?}"
    );
    assert!(sel.selection(pursued).lod() <= sel.selection(other).lod());
    // On a 60 Hz panel the moving object is seen as still frames: its
    // threshold stays at the floor, far above continuous motion's.
    let sampled = display();
    assert_eq!(sampled.refresh_hz(), Some(60.0));
    sel.set_display(sampled);
    sel.select_with_diagnostics(&frame).unwrap();
    let floored = sel.diagnostics(other).unwrap().threshold_cpd;
    assert!(
        floored > 5.0 * d_other.threshold_cpd,
        "{floored} {d_other:?}"
    );
    assert!(floored <= sel.diagnostics(pursued).unwrap().threshold_cpd);
}

#[test]
fn with_head_tracking_a_pure_head_turn_leaves_world_fixed_detail_unchanged() {
    // Size and velocity only: eccentricity changes as objects move in view.
    let components = Components {
        eccentricity: false,
        ..Components::ALL
    };
    for eyes_counter_rotate in [true, false] {
        let settings = SelectorSettings {
            components,
            eyes_counter_rotate,
            cull: false,
            ..SelectorSettings::default()
        };
        let (mut sel, ids) = random_scene(settings, 200, 11, DVec3::ZERO);
        let turned = |yaw_deg: f32| FrameInput {
            camera: Camera {
                position: DVec3::ZERO,
                orientation: Quat::from_rotation_y(yaw_deg.to_radians()),
            },
            gaze: Gaze::screen_centre(Tracker::Head),
            dt_s: 1.0 / 90.0,
            scale: 1.0,
        };
        sel.select(&turned(0.0)).unwrap();
        let still = lods(&sel, &ids);
        let mut fastest = 0.0f32;
        // A 120 deg/s head turn over half a second.
        for f in 1..=45 {
            sel.select_with_diagnostics(&turned(f as f32 * 120.0 / 90.0))
                .unwrap();
            for &id in &ids {
                fastest = fastest.max(sel.diagnostics(id).unwrap().velocity_deg_per_s);
            }
        }
        if eyes_counter_rotate {
            assert!(fastest < 1e-2, "{fastest} deg/s");
            assert_eq!(lods(&sel, &ids), still);
        } else {
            assert!(fastest > 100.0, "{fastest} deg/s");
            assert_ne!(lods(&sel, &ids), still);
        }
    }
}

#[test]
fn during_a_saccade_detail_drops_and_returns_the_frame_the_gaze_lands() {
    let settings = |threshold: f32| SelectorSettings {
        cull: false,
        saccade_threshold_deg_per_s: threshold,
        ..SelectorSettings::default()
    };
    // The gaze fixates 10 deg left for 20 frames at 90 Hz, jumps 20 deg in
    // three frames (600 deg/s), then fixates 10 deg right.
    let gaze_x_deg = |f: usize| match f {
        0..20 => -10.0,
        20..23 => -10.0 + 20.0 * (f - 19) as f32 / 3.0,
        _ => 10.0,
    };
    for tracker in [Tracker::eye_default(), Tracker::None, Tracker::Head] {
        let (mut off, ids) = random_scene(settings(f32::INFINITY), 300, 5, DVec3::ZERO);
        let (mut on, _) = random_scene(
            settings(acuity::SACCADE_THRESHOLD_DEG_PER_S),
            300,
            5,
            DVec3::ZERO,
        );
        let mut coarser_in_saccade = false;
        for f in 0..30 {
            let frame = FrameInput {
                camera: Camera {
                    position: DVec3::ZERO,
                    orientation: Quat::IDENTITY,
                },
                gaze: Gaze::at_screen_angles(gaze_x_deg(f), 0.0, tracker),
                dt_s: 1.0 / 90.0,
                scale: 1.0,
            };
            off.select(&frame).unwrap();
            on.select(&frame).unwrap();
            let (a, b) = (lods(&off, &ids), lods(&on, &ids));
            let in_saccade = (20..23).contains(&f) && matches!(tracker, Tracker::Eye { .. });
            if in_saccade {
                for (x, y) in a.iter().zip(&b) {
                    assert!(y.lod() >= x.lod(), "frame {f}: {y:?} finer than {x:?}");
                }
                coarser_in_saccade |= a != b;
            } else {
                assert_eq!(a, b, "frame {f}, {tracker:?}");
            }
        }
        assert_eq!(
            coarser_in_saccade,
            matches!(tracker, Tracker::Eye { .. }),
            "{tracker:?}"
        );
    }
}

#[test]
fn every_component_combination_works_and_switching_off_never_coarsens() {
    let mut reference = None;
    for bits in 0..8u8 {
        let components = Components {
            size: bits & 1 != 0,
            velocity: bits & 2 != 0,
            eccentricity: bits & 4 != 0,
        };
        let (mut sel, ids) = random_scene(
            SelectorSettings {
                components,
                ..Default::default()
            },
            400,
            3,
            DVec3::ZERO,
        );
        let mut frame = frame_at(DVec3::ZERO, 1.0 / 60.0);
        for f in 0..5 {
            frame.camera.orientation = Quat::from_rotation_y(0.05 * f as f32);
            sel.select(&frame).unwrap();
        }
        let l = lods(&sel, &ids);
        if bits == 7 {
            reference = Some((l, ids));
        } else if bits == 0 {
            // Only the display limit is left: an object filling the field of
            // view drops only features finer than xi.
            assert!(l.iter().all(|s| s.lod() <= Some(3)));
        }
    }
    // Switching components off can only keep or refine the LOD.
    let (all, ids) = reference.unwrap();
    for bits in 0..7u8 {
        let components = Components {
            size: bits & 1 != 0,
            velocity: bits & 2 != 0,
            eccentricity: bits & 4 != 0,
        };
        let (mut sel, _) = random_scene(
            SelectorSettings {
                components,
                ..Default::default()
            },
            400,
            3,
            DVec3::ZERO,
        );
        let mut frame = frame_at(DVec3::ZERO, 1.0 / 60.0);
        for f in 0..5 {
            frame.camera.orientation = Quat::from_rotation_y(0.05 * f as f32);
            sel.select(&frame).unwrap();
        }
        for (k, id) in ids.iter().enumerate() {
            let (a, b) = (sel.selection(*id), all[k]);
            if !a.is_culled() && components.size {
                assert!(
                    a.lod() <= b.lod(),
                    "{components:?}: object {k} got {a:?}, all components {b:?}"
                );
            }
        }
    }
}

#[test]
fn worst_case_viewpoints_are_never_coarser_than_nearest() {
    let (mut nearest, ids) = random_scene(SelectorSettings::default(), 2000, 9, DVec3::ZERO);
    let (mut worst, _) = random_scene(
        SelectorSettings {
            viewpoint_rule: ViewpointRule::WorstCase,
            ..Default::default()
        },
        2000,
        9,
        DVec3::ZERO,
    );
    let frame = frame_at(DVec3::ZERO, 0.016);
    nearest.select(&frame).unwrap();
    worst.select(&frame).unwrap();
    let (n, w) = (lods(&nearest, &ids), lods(&worst, &ids));
    assert!(n.iter().zip(&w).all(|(a, b)| b.lod() <= a.lod()));
    assert!(
        n.iter().zip(&w).any(|(a, b)| b.lod() < a.lod()),
        "the rules should differ somewhere"
    );
}

#[test]
fn diagnostics_follow_the_geometry() {
    let mut sel = Selector::new(display(), SelectorSettings::default());
    let p = sel.add_profile(&four_lod_profile(4)).unwrap();
    // 30 deg off-axis, radius 1 at distance 10.
    let a = 30f64.to_radians();
    let id = sel
        .add_object(ObjectDesc {
            center: DVec3::new(10.0 * a.sin(), 0.0, -10.0 * a.cos()),
            radius: 1.0,
            rotation: Quat::IDENTITY,
            profile: p,
        })
        .unwrap();
    let mut frame = frame_at(DVec3::ZERO, 0.016);
    frame.gaze = Gaze::screen_centre(Tracker::eye_default());
    sel.select_with_diagnostics(&frame).unwrap();
    let d = sel.diagnostics(id).unwrap();
    let theta = 2.0 * (0.1f32).asin().to_degrees();
    assert!((d.angular_size_deg - theta).abs() < 1e-3, "{d:?}");
    assert!(
        (d.eccentricity_deg - (30.0 - theta / 2.0 - 1.0)).abs() < 1e-3,
        "{d:?}"
    );
    assert_eq!(d.velocity_deg_per_s, 0.0);
    let h = 60.0 * acuity::EccentricityModel::CorticalMagnification.factor(d.eccentricity_deg);
    // T = s H: the display's limit is in the profile's renderings.
    assert!((d.threshold_cpd - h).abs() < 1e-4, "{d:?} {h}");
    // Head tracking subtracts 15 deg instead.
    frame.gaze = Gaze::screen_centre(Tracker::Head);
    sel.select_with_diagnostics(&frame).unwrap();
    let d = sel.diagnostics(id).unwrap();
    assert!(
        (d.eccentricity_deg - (30.0 - theta / 2.0 - 15.0)).abs() < 1e-3,
        "{d:?}"
    );
}

#[test]
fn an_invalid_frame_is_refused_and_changes_nothing() {
    let (mut sel, ids) = random_scene(SelectorSettings::default(), 100, 1, DVec3::ZERO);
    sel.select(&frame_at(DVec3::ZERO, 0.016)).unwrap();
    let before = lods(&sel, &ids);
    let bad_frames = [
        FrameInput {
            scale: f32::NAN,
            ..frame_at(DVec3::ZERO, 0.016)
        },
        FrameInput {
            scale: 0.0,
            ..frame_at(DVec3::ZERO, 0.016)
        },
        frame_at(DVec3::new(f64::NAN, 0.0, 0.0), 0.016),
        frame_at(DVec3::new(1e300, 0.0, 0.0), 0.016),
        FrameInput {
            gaze: Gaze {
                direction_camera: Vec3::ZERO,
                ..Gaze::default()
            },
            ..frame_at(DVec3::ZERO, 0.016)
        },
        FrameInput {
            camera: Camera {
                position: DVec3::ZERO,
                orientation: Quat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            },
            ..frame_at(DVec3::ZERO, 0.016)
        },
    ];
    for f in bad_frames {
        assert!(sel.select(&f).is_err(), "{f:?} accepted");
        assert_eq!(lods(&sel, &ids), before);
    }
}

#[test]
fn bad_objects_are_refused() {
    let mut sel = Selector::new(display(), SelectorSettings::default());
    let p = sel.add_profile(&four_lod_profile(1)).unwrap();
    let ok = ObjectDesc {
        center: DVec3::ZERO,
        radius: 1.0,
        rotation: Quat::IDENTITY,
        profile: p,
    };
    assert!(
        sel.add_object(ObjectDesc {
            radius: f32::NAN,
            ..ok
        })
        .is_err()
    );
    assert!(sel.add_object(ObjectDesc { radius: -1.0, ..ok }).is_err());
    assert!(
        sel.add_object(ObjectDesc {
            center: DVec3::new(0.0, f64::INFINITY, 0.0),
            ..ok
        })
        .is_err()
    );
    assert!(
        sel.add_object(ObjectDesc {
            rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            ..ok
        })
        .is_err()
    );
    let id = sel.add_object(ok).unwrap();
    assert!(sel.set_pose(id, DVec3::NAN, Quat::IDENTITY).is_err());
    assert!(sel.set_radius(id, f32::INFINITY).is_err());
    assert_eq!(sel.object_count(), 1);
}

#[test]
fn zero_and_negative_dt_keep_velocities() {
    let mut sel = Selector::new(display(), SelectorSettings::default());
    let p = sel.add_profile(&four_lod_profile(3)).unwrap();
    let id = sel
        .add_object(ObjectDesc {
            center: DVec3::new(0.0, 0.0, -30.0),
            radius: 1.0,
            rotation: Quat::IDENTITY,
            profile: p,
        })
        .unwrap();
    for f in 1..20 {
        sel.set_pose(id, DVec3::new(0.2 * f as f64, 0.0, -30.0), Quat::IDENTITY)
            .unwrap();
        sel.select_with_diagnostics(&frame_at(DVec3::ZERO, 1.0 / 60.0))
            .unwrap();
    }
    let v = sel.diagnostics(id).unwrap().velocity_deg_per_s;
    for dt in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e30, f32::MIN_POSITIVE] {
        sel.select_with_diagnostics(&frame_at(DVec3::ZERO, dt))
            .unwrap();
        let d = sel.diagnostics(id).unwrap();
        assert!(
            d.velocity_deg_per_s.is_finite() && d.threshold_cpd.is_finite(),
            "dt {dt}: {d:?}"
        );
        if !(dt > 0.0 && dt <= 1e6) {
            assert_eq!(d.velocity_deg_per_s, v, "dt {dt}");
        }
    }
}
