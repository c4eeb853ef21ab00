//! Property tests over the whole input domain: no panic, no NaN out,
//! monotone where the model is (the CSF included), continuous at its
//! breakpoints.

mod common;

use acuity::acuity::{
    ECCENTRICITY_FLOOR_DEG, VELOCITY_CEILING_DEG_PER_S, VELOCITY_FLOOR_DEG_PER_S, acuity_cpd,
    eccentricity_factor, threshold_cpd, velocity_acuity_cpd,
};
use acuity::csf::Csf;
use acuity::select::lod_for_threshold;
use acuity::{
    Camera, Components, Display, EccentricityModel, FrameInput, Gaze, ObjectDesc, Observer,
    Photometry, Selector, SelectorSettings, Tracker, VelocityModel,
};
use common::four_lod_profile;
use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;
use std::cell::RefCell;
use std::collections::HashMap;

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -1e3f32..1e3,
        1 => proptest::num::f32::ANY,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(0.0f32),
    ]
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 4000,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn model_outputs_are_finite_and_in_range(v in any_f32(), e in any_f32(), xi in any_f32(), s in any_f32()) {
        let g = velocity_acuity_cpd(v);
        let m = eccentricity_factor(e);
        let h = acuity_cpd(v, e);
        prop_assert!((0.1..=60.0).contains(&g));
        prop_assert!((0.0..=1.0).contains(&m) && m > 0.0);
        prop_assert!(h.is_finite() && h > 0.0);
        for model in EccentricityModel::ALL {
            let m = model.factor(e);
            prop_assert!(m > 0.0 && m <= 1.0, "{model:?}: M({e}) = {m}");
        }
        if xi.is_finite() {
            let t = threshold_cpd(h, xi, s);
            prop_assert!(t.is_finite());
        }
    }

    #[test]
    fn faster_or_more_peripheral_never_sees_more(v in 0f32..500.0, dv in 0f32..100.0, e in 0f32..120.0, de in 0f32..50.0) {
        prop_assert!(velocity_acuity_cpd(v + dv) <= velocity_acuity_cpd(v));
        prop_assert!(eccentricity_factor(e + de) <= eccentricity_factor(e));
        prop_assert!(acuity_cpd(v + dv, e + de) <= acuity_cpd(v, e));
        for model in EccentricityModel::ALL {
            prop_assert!(model.factor(e + de) <= model.factor(e), "{model:?} at {e} + {de}");
        }
        for model in VelocityModel::ALL {
            prop_assert!(model.acuity_cpd(v + dv) <= model.acuity_cpd(v), "{model:?} at {v} + {dv}");
        }
    }

    #[test]
    fn velocity_models_are_finite_and_continuous(v in any_f32(), eps in 1e-4f32..1e-2) {
        for model in VelocityModel::ALL {
            let g = model.acuity_cpd(v);
            prop_assert!((0.0..=60.0).contains(&g), "{model:?}: G({v}) = {g}");
        }
        // Kelly's G has no breakpoint; |dG/dv| <= 60 / (v_d + 2) everywhere.
        let kelly = VelocityModel::Kelly1979;
        for v in [0.0f32, 0.15, 1.0, 10.0, 118.3, 500.0] {
            let jump = (kelly.acuity_cpd(v + eps) - kelly.acuity_cpd(v)).abs();
            prop_assert!(jump <= 60.0 / 2.15 * eps * 1.01 + 1e-5, "G_K jumps {} at {}", jump, v);
        }
    }

    #[test]
    fn selection_rule_is_monotone(
        rows in proptest::collection::vec(1f32..1000.0, 1..8),
        t in 0.01f32..60.0, dt in 0f32..60.0,
        theta in 0.01f32..180.0, dtheta in 0f32..90.0,
    ) {
        // Prefix minima are non-increasing.
        let mut prefix = rows.clone();
        for i in 1..prefix.len() { prefix[i] = prefix[i].min(prefix[i - 1]); }
        let base = lod_for_threshold(&prefix, t + dt, theta + dtheta);
        prop_assert!(lod_for_threshold(&prefix, t, theta + dtheta) >= base);
        prop_assert!(lod_for_threshold(&prefix, t + dt, theta) >= base);
        prop_assert!(base <= prefix.len());
    }

    #[test]
    fn contrast_sensitivity_is_finite_and_monotone(
        c in any_f32(), dc in 0f32..1.0, m in any_f32(), field in any_f32(),
        sensitivity in prop_oneof![1e-3f32..1e3, Just(1.0f32)],
        lum in prop_oneof![Just([0.0f32, 1.0]), (0f32..1.0, 0f32..1.0).prop_map(|(a, b)| [a.min(b), a.max(b)])],
    ) {
        let photometry = Photometry::default();
        let csf = Csf::new(&photometry, &Observer { sensitivity, ..Default::default() }).unwrap();
        let contrast = photometry.contrast(lum);
        prop_assert!((0.0..1.0).contains(&contrast), "{contrast}");
        let masked = csf.masked_contrast(c, m);
        prop_assert!(masked.is_finite() && masked >= 0.0);
        prop_assert!(masked <= 1.0 && (c.is_nan() || masked <= c.max(0.0)));
        let for_field = csf.for_field(field);
        let cut = for_field.cutoff_cpd(c);
        prop_assert!(cut.is_finite() && cut >= 0.0, "{cut}");
        // More contrast is visible to at least as high a frequency; less
        // masking leaves at least as much.
        if c.is_finite() {
            prop_assert!(for_field.cutoff_cpd(c + dc) >= cut);
            if m.is_finite() && m >= 0.0 {
                prop_assert!(csf.masked_contrast(c, m + dc) <= masked);
            }
        }
        let q = for_field.critical_cdiam(10.0, masked);
        prop_assert!(q > 0.0 && !q.is_nan(), "{q}");
    }

    #[test]
    fn pooled_critical_frequencies_are_positive_and_monotone(
        raw in proptest::collection::vec(
            (any_f32(), any_f32(), 0f32..1.0, 0f32..1.0, 0f32..1.0, 1u32..5),
            0..12,
        ),
        diameter_deg in prop_oneof![1e-3f32..1e3, Just(0.0f32), Just(f32::NAN)],
        threshold in 1f32..64.0,
        extra in 1f32..4.0,
    ) {
        use acuity::profile::Feature;
        use acuity::rows::{FieldCsfs, transition_critical_cdiam};
        // Features as a profile stores them: finite, positive frequency
        // and area, ordered luminance pairs.
        let features: Vec<Feature> = raw
            .iter()
            .map(|&(f, a, l0, l1, m, count)| Feature {
                freq_cdiam: if f.is_finite() { f.abs().clamp(1e-3, 1e3) } else { 1.0 },
                area_diam2: if a.is_finite() { a.abs().clamp(1e-6, 1.0) } else { 1.0 },
                luminance: [l0.min(l1), l0.max(l1)],
                masker: [m.min(l0), m.max(l0)],
                count,
            })
            .collect();
        let photometry = Photometry::default();
        let q = |threshold_jnd: f32, features: &[Feature]| {
            let observer = Observer { threshold_jnd, ..Default::default() };
            let csf = Csf::new(&photometry, &observer).unwrap();
            transition_critical_cdiam(features, diameter_deg, &photometry, &mut FieldCsfs::new(&csf))
        };
        let base = q(threshold, &features);
        prop_assert!(base > 0.0 && !base.is_nan(), "{base}");
        // A higher threshold: invisible up to at least as high a k.
        prop_assert!(q(threshold * extra, &features) >= base);
        // One more feature (or one counted twice) is never less visible.
        if let Some(first) = features.first() {
            let mut more = features.clone();
            more.push(Feature { count: first.count + 1, ..*first });
            more.sort_by(|a, b| a.freq_cdiam.total_cmp(&b.freq_cdiam));
            // (Within the bisection's precision: the bracket depends on
            // the features.)
            prop_assert!(q(threshold, &more) <= base * (1.0 + 1e-5));
        }
    }

    #[test]
    fn g_and_m_are_continuous_at_their_breakpoints(eps in 1e-6f32..1e-3) {
        for bp in [VELOCITY_FLOOR_DEG_PER_S, VELOCITY_CEILING_DEG_PER_S] {
            let jump = (velocity_acuity_cpd(bp * (1.0 + eps)) - velocity_acuity_cpd(bp * (1.0 - eps))).abs();
            // |dG/dv| <= 27.78 / (v ln 10) around the breakpoint.
            prop_assert!(jump <= 27.78 / std::f32::consts::LN_10 * 2.0 * eps * 1.01 + 1e-5, "G jumps {} at {}", jump, bp);
        }
        let bp = ECCENTRICITY_FLOOR_DEG;
        let jump = (eccentricity_factor(bp + eps) - eccentricity_factor(bp - eps)).abs();
        prop_assert!(jump <= 0.25 * 2.0 * eps + 1e-6, "M jumps {} at {}", jump, bp);
        // Cortical magnification has no breakpoint; its steepest slope,
        // k_cm / e_2 = 0.165 per deg, is at the fovea.
        let cortical = EccentricityModel::CorticalMagnification;
        for e in [0.0f32, 1.0, 3.67, 10.0, 90.0] {
            let jump = (cortical.factor(e + eps) - cortical.factor(e)).abs();
            prop_assert!(jump <= 0.17 * eps + 1e-6, "M_cm jumps {} at {}", jump, e);
        }
    }
}

/// One frame of one object with arbitrary inputs.
#[derive(Debug, Clone)]
struct Case {
    fov_deg: [f32; 2],
    camera: DVec3,
    camera_rot: Quat,
    offset: Vec3,
    radius: f32,
    rot: Quat,
    dt: f32,
    scale: f32,
    gaze: Vec3,
    /// Bits: size, velocity, eccentricity on; Reddy 2001's `M(E)` and `G(v)`
    /// instead of cortical magnification and Kelly 1979; a 90 Hz display.
    components: u8,
    move_by: Vec3,
    cull: bool,
}

fn unit_quat() -> impl Strategy<Value = Quat> {
    (-1f32..1.0, -1f32..1.0, -1f32..1.0, -1f32..1.0)
        .prop_filter("non-zero", |(x, y, z, w)| {
            x * x + y * y + z * z + w * w > 1e-3
        })
        .prop_map(|(x, y, z, w)| Quat::from_xyzw(x, y, z, w).normalize())
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![-1e3f64..1e3, -1e7f64..1e7, Just(0.0)]
}

fn case() -> impl Strategy<Value = Case> {
    (
        (
            prop_oneof![0.001f32..1.0, 1f32..179.0, 179f32..179.9],
            prop_oneof![0.001f32..1.0, 1f32..179.0, 179f32..179.9],
        ),
        (coordinate(), coordinate(), coordinate()),
        unit_quat(),
        (-1e4f32..1e4, -1e4f32..1e4, -1e4f32..1e4),
        prop_oneof![Just(0.0f32), 0f32..1e-3, 0f32..10.0, 0f32..1e6],
        unit_quat(),
        any_f32(),
        prop_oneof![1e-6f32..1.0, Just(1.0f32), 1f32..10.0],
        (-1f32..1.0, -1f32..1.0, -1f32..0.1),
        0u8..32,
        (-100f32..100.0, -100f32..100.0, -100f32..100.0),
        any::<bool>(),
    )
        .prop_filter("gaze must have a direction", |c| {
            Vec3::new(c.8.0, c.8.1, c.8.2).length() > 1e-3
        })
        .prop_map(
            |(fov, cam, camera_rot, off, radius, rot, dt, scale, g, components, mv, cull)| Case {
                fov_deg: [fov.0, fov.1],
                camera: DVec3::new(cam.0, cam.1, cam.2),
                camera_rot,
                offset: Vec3::new(off.0, off.1, off.2),
                radius,
                rot,
                dt,
                scale,
                gaze: Vec3::new(g.0, g.1, g.2),
                components,
                move_by: Vec3::new(mv.0, mv.1, mv.2),
                cull,
            },
        )
}

fn run_case(c: &Case) -> (acuity::Selection, acuity::Diagnostics) {
    let refresh_hz = (c.components & 16 != 0).then_some(90.0);
    let display = Display::new([1920, 1080], c.fov_deg)
        .and_then(|d| d.with_refresh_hz(refresh_hz))
        .unwrap();
    let components = Components {
        size: c.components & 1 != 0,
        velocity: c.components & 2 != 0,
        eccentricity: c.components & 4 != 0,
    };
    let (eccentricity_model, velocity_model) = if c.components & 8 != 0 {
        (EccentricityModel::Reddy2001, VelocityModel::Reddy2001)
    } else {
        (
            EccentricityModel::CorticalMagnification,
            VelocityModel::Kelly1979,
        )
    };
    // Compiling a profile builds its viewpoint lookup: do that once per
    // settings and clone.
    type Template = (Selector, acuity::ProfileId);
    thread_local! {
        static TEMPLATES: RefCell<HashMap<(u8, bool), Template>> = Default::default();
    }
    let (mut sel, p) = TEMPLATES.with(|t| {
        t.borrow_mut()
            .entry((c.components, c.cull))
            .or_insert_with(|| {
                let settings = SelectorSettings {
                    components,
                    cull: c.cull,
                    eccentricity_model,
                    velocity_model,
                    ..Default::default()
                };
                let mut sel = Selector::new(display, settings);
                let p = sel.add_profile(&four_lod_profile(1)).unwrap();
                (sel, p)
            })
            .clone()
    });
    sel.set_display(display);
    let center = c.camera + c.offset.as_dvec3();
    let id = sel
        .add_object(ObjectDesc {
            center,
            radius: c.radius,
            rotation: c.rot,
            profile: p,
        })
        .unwrap();
    let frame = FrameInput {
        camera: Camera {
            position: c.camera,
            orientation: c.camera_rot,
        },
        gaze: Gaze {
            direction_camera: c.gaze,
            tracker: Tracker::eye_default(),
            pursued: None,
        },
        dt_s: c.dt,
        scale: c.scale,
    };
    sel.select_with_diagnostics(&frame).unwrap();
    sel.set_pose(id, center + c.move_by.as_dvec3(), c.rot)
        .unwrap();
    sel.select_with_diagnostics(&frame).unwrap();
    (sel.selection(id), sel.diagnostics(id).unwrap())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn selection_never_panics_or_produces_nan(c in case()) {
        let (s, d) = run_case(&c);
        prop_assert!(s.is_culled() || s.lod().unwrap() < 4);
        if !s.is_culled() {
            prop_assert!(d.angular_size_deg.is_finite() && d.eccentricity_deg.is_finite());
            prop_assert!(d.velocity_deg_per_s.is_finite() && d.threshold_cpd.is_finite(), "{:?}", d);
            prop_assert!(d.threshold_cpd >= 0.0);
        }
    }

    #[test]
    fn farther_smaller_or_lower_scale_is_never_finer(c in case(), farther in 1f32..100.0, shrink in 0f32..1.0, lower in 0f32..1.0) {
        let c = Case { cull: false, ..c };
        let (base, _) = run_case(&c);
        let mut far = c.clone();
        // Scaling the motion too keeps every direction, so the velocity.
        far.offset *= farther;
        far.move_by *= farther;
        let mut small = c.clone();
        small.radius *= shrink;
        let mut low = c.clone();
        low.scale = c.scale.min(1.0) * lower.max(1e-6);
        for (name, other) in [("farther", far), ("smaller", small), ("lower s", low)] {
            let (s, _) = run_case(&other);
            prop_assert!(s.lod() >= base.lod(), "{}: {:?} -> {:?}", name, base, s);
        }
    }

    #[test]
    fn faster_is_never_finer(c in case(), faster in 1f32..50.0) {
        // Three objects end the second frame at the same place (same size,
        // eccentricity and viewpoint), having moved 0, 1 and `faster` times
        // as far along the same line.
        let c = Case { cull: false, ..c };
        let end = c.offset + c.move_by;
        let at_speed = |k: f32| Case { offset: end - k * c.move_by, move_by: k * c.move_by, ..c.clone() };
        let (still, _) = run_case(&at_speed(0.0));
        let (moving, _) = run_case(&at_speed(1.0));
        let (quick, _) = run_case(&at_speed(faster));
        prop_assert!(still.lod() <= moving.lod() && moving.lod() <= quick.lod(), "{:?} {:?} {:?}", still, moving, quick);
    }
}
