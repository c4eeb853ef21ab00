//! Asymmetric fields of view and one selection for both eyes of a headset.

mod common;

use acuity::{
    Camera, Components, Display, FovEdges, FrameInput, Gaze, ObjectDesc, ObjectId, Selector,
    SelectorSettings, StereoRig, Tracker, ViewpointRule,
};
use common::{Rng, four_lod_profile};
use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;

fn frame(position: DVec3, orientation: Quat) -> FrameInput {
    FrameInput {
        camera: Camera {
            position,
            orientation,
        },
        gaze: Gaze::screen_centre(Tracker::None),
        dt_s: 1.0 / 90.0,
        scale: 1.0,
    }
}

/// A headset eye: 104 deg across, the inner edge nearer the nose, 1832 x
/// 1920 pixels. `mirror` gives the right eye.
fn headset_eye(mirror: bool) -> Display {
    let (outer, inner) = (-54.0, 50.0);
    let edges = FovEdges {
        left_deg: if mirror { -inner } else { outer },
        right_deg: if mirror { -outer } else { inner },
        up_deg: 52.0,
        down_deg: -52.0,
    };
    Display::with_fov_edges([1832, 1920], edges).unwrap()
}

#[test]
fn symmetric_edges_are_the_symmetric_display() {
    let d = Display::new([640, 480], [60.0, 45.0]).unwrap();
    let e = Display::with_fov_edges([640, 480], FovEdges::symmetric([60.0, 45.0])).unwrap();
    assert_eq!(d, e);
    assert_eq!(e.fov_edges(), FovEdges::symmetric([60.0, 45.0]));
    let a = headset_eye(false);
    assert_eq!(a.fov_deg(), [104.0, 104.0]);
    assert_eq!(a.fov_edges().left_deg, -54.0);
    assert_eq!(a.fov_edges().right_deg, 50.0);
}

#[test]
fn bad_edges_are_refused_naming_the_edge() {
    let ok = FovEdges::symmetric([90.0, 90.0]);
    for (edges, needle) in [
        (
            FovEdges {
                left_deg: f32::NAN,
                ..ok
            },
            "left_deg",
        ),
        (
            FovEdges {
                right_deg: 90.0,
                ..ok
            },
            "right_deg",
        ),
        (
            FovEdges {
                left_deg: 10.0,
                right_deg: 5.0,
                ..ok
            },
            "field of view",
        ),
        (
            FovEdges {
                up_deg: -50.0,
                ..ok
            },
            "field of view",
        ),
    ] {
        let e = Display::with_fov_edges([100, 100], edges)
            .unwrap_err()
            .to_string();
        assert!(e.contains("fov_edges") && e.contains(needle), "{e}");
    }
}

#[test]
fn culling_follows_the_asymmetric_edges() {
    // Looking along -Z; the field spans 10 deg left to 50 deg right.
    let edges = FovEdges {
        left_deg: -10.0,
        right_deg: 50.0,
        up_deg: 20.0,
        down_deg: -20.0,
    };
    let display = Display::with_fov_edges([600, 400], edges).unwrap();
    let mut sel = Selector::new(display, SelectorSettings::default());
    let p = sel.add_profile(&four_lod_profile(3)).unwrap();
    let at = |deg: f64| {
        let a = deg.to_radians();
        DVec3::new(a.sin(), 0.0, -a.cos()) * 50.0
    };
    let add = |sel: &mut Selector, deg: f64| {
        sel.add_object(ObjectDesc {
            center: at(deg),
            radius: 0.5,
            rotation: Quat::IDENTITY,
            profile: p,
        })
        .unwrap()
    };
    let right_40 = add(&mut sel, 40.0);
    let left_30 = add(&mut sel, -30.0);
    let left_5 = add(&mut sel, -5.0);
    let right_55 = add(&mut sel, 55.0);
    sel.select(&frame(DVec3::ZERO, Quat::IDENTITY)).unwrap();
    assert!(!sel.selection(right_40).is_culled());
    assert!(!sel.selection(left_5).is_culled());
    assert!(sel.selection(left_30).is_culled());
    assert!(sel.selection(right_55).is_culled());
}

#[test]
fn a_rig_selects_over_both_fields_at_the_finer_density() {
    let rig = StereoRig::from_ipd(headset_eye(false), headset_eye(true), 0.064).unwrap();
    let d = rig.selection_display().unwrap();
    assert_eq!(d.fov_edges(), FovEdges::symmetric([108.0, 104.0]));
    // 1832 px over 104 deg, over 108 deg.
    assert_eq!(d.resolution_px(), [1903, 1920]);
    assert!((rig.radius_margin() - 0.064).abs() < 1e-7);
    assert!(StereoRig::from_ipd(headset_eye(false), headset_eye(true), f32::NAN).is_err());
    let other = headset_eye(true).with_refresh_hz(Some(72.0)).unwrap();
    assert!(StereoRig::from_ipd(headset_eye(false), other, 0.064).is_err());
}

/// Selects `centres` (with `radius`) from one camera and display.
fn select(
    display: Display,
    settings: SelectorSettings,
    camera: (DVec3, Quat),
    objects: &[(DVec3, f32, Quat)],
) -> Vec<acuity::Selection> {
    let mut sel = Selector::new(display, settings);
    let p = sel.add_profile(&four_lod_profile(11)).unwrap();
    let ids: Vec<ObjectId> = objects
        .iter()
        .map(|&(center, radius, rotation)| {
            sel.add_object(ObjectDesc {
                center,
                radius,
                rotation,
                profile: p,
            })
            .unwrap()
        })
        .collect();
    sel.select(&frame(camera.0, camera.1)).unwrap();
    ids.iter().map(|&id| sel.selection(id)).collect()
}

/// Whether the sphere `object` (centre, radius) lies outside the cone
/// around the view direction of an eye at `position` with orientation
/// `orientation` that holds the display's whole field of view (out to its
/// farthest corner): no part of it is in view.
fn outside_every_view_direction(
    display: Display,
    orientation: Quat,
    position: DVec3,
    object: (DVec3, f32, Quat),
) -> bool {
    let e = display.fov_edges();
    let tan = |deg: f32| f64::from(deg.to_radians().tan().abs());
    let corner_deg = (tan(e.left_deg)
        .max(tan(e.right_deg))
        .hypot(tan(e.up_deg).max(tan(e.down_deg))))
    .atan()
    .to_degrees();
    let local = orientation.inverse().as_dquat() * (object.0 - position);
    let distance = local.length();
    let radius = f64::from(object.1);
    if distance <= radius {
        return false;
    }
    let from_forward_deg = (-local.z / distance).clamp(-1.0, 1.0).acos().to_degrees();
    from_forward_deg - (radius / distance).asin().to_degrees() > corner_deg
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whatever either eye would select on its own, the rig's one selection
    /// is as fine or finer, and culls only what neither eye sees (with the
    /// worst-case viewpoint rule; see `acuity::stereo` for the nearest).
    #[test]
    fn one_selection_is_right_for_both_eyes(
        seed in any::<u64>(),
        ipd in 0.0f32..0.2,
        size in any::<bool>(),
        eccentricity in any::<bool>(),
    ) {
        let rig = StereoRig::from_ipd(headset_eye(false), headset_eye(true), ipd).unwrap();
        let settings = SelectorSettings {
            components: Components { size, velocity: false, eccentricity },
            viewpoint_rule: ViewpointRule::WorstCase,
            ..Default::default()
        };
        let mut rng = Rng::new(seed);
        let head = (rng.point(1000.0), rng.rotation());
        let objects: Vec<(DVec3, f32, Quat)> = (0..64)
            .map(|_| {
                let distance = rng.range(0.1f64.ln(), 300f64.ln()).exp();
                let centre = head.0 + rng.direction().as_dvec3() * distance;
                (centre, rng.range(0.01, 2.0) as f32, rng.rotation())
            })
            .collect();
        let both = select(
            rig.selection_display().unwrap(),
            rig.selector_settings(settings),
            head,
            &objects,
        );
        for eye in [rig.left(), rig.right()] {
            let position = head.0 + (head.1 * eye.offset).as_dvec3();
            let alone = select(eye.display, settings, (position, head.1), &objects);
            for (k, (b, a)) in both.iter().zip(&alone).enumerate() {
                match (b.lod(), a.lod()) {
                    // The planes' test is conservative for a sphere that
                    // straddles the eye's plane (its half-spaces are not
                    // nested behind the apex), so the eye alone may keep
                    // one it cannot see; the rig may cull only those.
                    (None, Some(_)) => prop_assert!(
                        outside_every_view_direction(eye.display, head.1, position, objects[k]),
                        "object {k}: culled, the eye sees it"
                    ),
                    (Some(b), Some(a)) => prop_assert!(b <= a, "object {k}: LOD {b} for both, {a} for one eye"),
                    _ => {}
                }
            }
        }
    }
}

#[test]
fn a_zero_margin_changes_nothing() {
    let mut rng = Rng::new(5);
    let objects: Vec<(DVec3, f32, Quat)> = (0..256)
        .map(|_| {
            let d = Vec3::new(
                rng.range(-0.5, 0.5) as f32,
                rng.range(-0.4, 0.4) as f32,
                -1.0,
            );
            (d.as_dvec3() * rng.range(2.0, 200.0), 1.0, rng.rotation())
        })
        .collect();
    let display = Display::new([1280, 1024], [53.1, 41.1]).unwrap();
    let camera = (DVec3::ZERO, Quat::IDENTITY);
    let plain = select(display, SelectorSettings::default(), camera, &objects);
    for margin in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let settings = SelectorSettings {
            radius_margin: margin,
            ..Default::default()
        };
        assert_eq!(
            select(display, settings, camera, &objects),
            plain,
            "{margin}"
        );
    }
    let grown = SelectorSettings {
        radius_margin: 0.5,
        ..Default::default()
    };
    let coarser = select(display, grown, camera, &objects);
    assert!(
        coarser
            .iter()
            .zip(&plain)
            .all(|(g, p)| match (g.lod(), p.lod()) {
                (Some(g), Some(p)) => g <= p,
                (None, Some(_)) => false,
                _ => true,
            })
    );
}
