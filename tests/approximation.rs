//! The fast selection loop (polynomial asin/acos/log10/exp2, cube-map viewpoint
//! lookup, f32) against an exact oracle written from the model's equations
//! (the docs of `acuity::acuity`) in f64 with the standard library's functions
//! (the critical frequencies of the transitions are the library's own).

mod common;

use acuity::csf::Csf;
use acuity::rows::{FieldCsfs, transition_critical_cdiam};
use acuity::{
    Camera, Display, EccentricityModel, FrameInput, Gaze, ObjectDesc, Observer, Profile, Selector,
    SelectorSettings, Tracker, VelocityModel,
};
use common::{Rng, four_lod_profile};
use glam::{DQuat, DVec3, Vec3};

struct Oracle {
    /// The eye model and the floor under `G` of sampled motion, c/deg.
    models: (VelocityModel, EccentricityModel),
    motion_floor_cpd: f64,
    /// Per viewpoint, per rung: prefix minima of the critical frequencies.
    rows: Vec<Vec<Vec<f64>>>,
    views: Vec<DVec3>,
    /// Angular sizes at which the rung goes up, deg.
    boundaries_deg: Vec<f64>,
}

impl Oracle {
    fn new(p: &Profile, display: &Display, models: (VelocityModel, EccentricityModel)) -> Self {
        let photometry = display.photometry();
        let csf = Csf::new(photometry, &Observer::default()).unwrap();
        let motion_floor_cpd = display.refresh_hz().map_or(0.0, |hz| {
            60.0 * f64::from(csf.sampled_motion_floor(photometry, hz))
        });
        let mut csfs = FieldCsfs::new(&csf);
        let ppd = display.pixels_per_degree();
        let rows = (0..p.viewpoints.len())
            .map(|v| {
                (0..p.rung_diameters_px.len())
                    .map(|r| {
                        let diameter_deg = p.rung_diameters_px[r] / ppd;
                        let mut m = f64::INFINITY;
                        p.transitions_at(v, r)
                            .iter()
                            .map(|t| {
                                let q = transition_critical_cdiam(
                                    &t.features,
                                    diameter_deg,
                                    photometry,
                                    &mut csfs,
                                );
                                m = m.min(q as f64);
                                m
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect();
        let views = p
            .viewpoints
            .iter()
            .map(|v| Vec3::from_array(*v).as_dvec3())
            .collect();
        let ppd = f64::from(ppd);
        let boundaries_deg: Vec<f64> = p
            .rung_diameters_px
            .windows(2)
            .map(|w| (w[0] as f64 * w[1] as f64).sqrt() / ppd)
            .collect();
        // Size never buys less detail: the critical acuity q / u over rungs
        // (u the boundary above the rung) only falls, and the top rung's
        // objects, judged at their own size, are held to the last one.
        let mut rows: Vec<Vec<Vec<f64>>> = rows;
        let n = p.transitions_per_view();
        for view in &mut rows {
            let mut acuity = vec![f64::INFINITY; n];
            for (rung, row) in view.iter_mut().enumerate() {
                // The boundary above the rung; the top rung is held to the
                // last one.
                let (upper, top) = match boundaries_deg.get(rung) {
                    Some(&b) => (b, false),
                    None => (*boundaries_deg.last().unwrap_or(&f64::INFINITY), true),
                };
                for (q, a) in row.iter_mut().zip(&mut acuity) {
                    if !top {
                        *a = a.min(*q / upper);
                    }
                    *q = q.min(*a * upper);
                }
            }
        }
        Self {
            models,
            motion_floor_cpd,
            rows,
            views,
            boundaries_deg,
        }
    }

    /// Returns the LOD and the smallest relative distance of `k` to any of
    /// the row's frequencies (how close the choice is to a tie).
    #[allow(clippy::too_many_arguments)]
    fn select(
        &self,
        cam: DVec3,
        cam_rot: DQuat,
        center: DVec3,
        prev_center: DVec3,
        radius: f64,
        rot: DQuat,
        dt: f64,
        alpha: f64,
    ) -> (usize, f64) {
        let to_eye = cam_rot.inverse();
        let rel = to_eye * (center - cam);
        let d = rel.length();
        let theta = 2.0 * (radius / d).asin().to_degrees();
        let ecc_angle = rel
            .normalize()
            .dot(DVec3::NEG_Z)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        let ecc = (ecc_angle - theta / 2.0 - 1.0).max(0.0);
        let prev = (to_eye * (prev_center - cam)).normalize();
        let step = 2.0
            * ((rel.normalize() - prev).length() / 2.0)
                .asin()
                .to_degrees();
        let v = alpha * step / dt;
        let g = match self.models.0 {
            VelocityModel::Reddy2001 if v <= 0.8257463 => 60.0,
            VelocityModel::Reddy2001 if v > 118.32436 => 0.1,
            VelocityModel::Reddy2001 => 57.69 - 27.78 * v.log10(),
            VelocityModel::Kelly1979 => 60.0 * 2.15 / (v.max(0.15) + 2.0),
        }
        .max(self.motion_floor_cpd);
        let m = match self.models.1 {
            EccentricityModel::Reddy2001 if ecc <= 5.789288 => 1.0,
            EccentricityModel::Reddy2001 => 7.49 / (0.3 * ecc.min(80.0) + 1.0).powi(2),
            EccentricityModel::CorticalMagnification => (3.67 / (ecc + 3.67)).powf(0.604562),
        };
        let rung = self.boundaries_deg.iter().filter(|&&b| theta > b).count();
        // Judged at the top of the rung's range; at its own size on the
        // bottom and top rungs.
        let judged = match self.boundaries_deg.get(rung) {
            Some(&b) if rung > 0 => b,
            _ => theta,
        };
        let k = g * m * judged;
        let to_camera = rot.inverse() * (cam - center).normalize();
        let view = (0..self.views.len())
            .max_by(|&a, &b| {
                self.views[a]
                    .dot(to_camera)
                    .total_cmp(&self.views[b].dot(to_camera))
            })
            .unwrap();
        let row = &self.rows[view][rung];
        let lod = row.iter().filter(|&&f| f > k).count();
        let margin = row
            .iter()
            .filter(|f| f.is_finite())
            .map(|f| ((f - k) / k).abs())
            .fold(f64::INFINITY, f64::min);
        (lod, margin)
    }
}

#[test]
fn fast_loop_picks_the_exact_models_lod() {
    // The defaults: Kelly's G with a 60 Hz panel's floor, cortical M.
    let display = Display::new([1920, 1080], [90.0, 58.7]).unwrap();
    fast_loop_matches_the_oracle(display, SelectorSettings::default());
    // The papers' models with continuous motion.
    let settings = SelectorSettings {
        velocity_model: VelocityModel::Reddy2001,
        eccentricity_model: EccentricityModel::Reddy2001,
        ..SelectorSettings::default()
    };
    fast_loop_matches_the_oracle(display.with_refresh_hz(None).unwrap(), settings);
}

fn fast_loop_matches_the_oracle(display: Display, settings: SelectorSettings) {
    let profile = four_lod_profile(3);
    let models = (settings.velocity_model, settings.eccentricity_model);
    let oracle = Oracle::new(&profile, &display, models);
    let mut rng = Rng::new(2024);
    let mut selector = Selector::new(
        display,
        SelectorSettings {
            cull: false,
            ..settings
        },
    );
    let p = selector.add_profile(&profile).unwrap();
    let n = 100_000;
    let cam = DVec3::new(3.0, -2.0, 1.0);
    let cam_rot = rng.rotation();
    let mut objects = Vec::with_capacity(n);
    for _ in 0..n {
        let distance = rng.range(2f64.ln(), 300f64.ln()).exp();
        let center = cam + rng.direction().as_dvec3() * distance;
        let prev = center + rng.direction().as_dvec3() * rng.range(0.0, 0.02) * distance;
        let radius = rng.range(0.2, 1.9);
        let rot = rng.rotation();
        let id = selector
            .add_object(ObjectDesc {
                center: prev,
                radius: radius as f32,
                rotation: rot,
                profile: p,
            })
            .unwrap();
        objects.push((id, center, prev, radius, rot));
    }
    let dt = 1.0 / 60.0;
    let frame = FrameInput {
        camera: Camera {
            position: cam,
            orientation: cam_rot,
        },
        gaze: Gaze::screen_centre(Tracker::eye_default()),
        dt_s: dt,
        scale: 1.0,
    };
    selector.select(&frame).unwrap();
    for (id, center, _, _, rot) in &objects {
        selector.set_pose(*id, *center, *rot).unwrap();
    }
    selector.select(&frame).unwrap();
    let alpha = 1.0 - (-(dt as f64) / 0.05).exp();
    let (mut agree, mut near_tie, mut clear_disagree) = (0, 0, 0);
    let mut lod_counts = [0usize; 4];
    for (id, center, prev, radius, rot) in &objects {
        let (exact, margin) = oracle.select(
            cam,
            cam_rot.as_dquat(),
            *center,
            *prev,
            *radius,
            rot.as_dquat(),
            dt as f64,
            alpha,
        );
        let fast = selector.selection(*id).lod().unwrap();
        lod_counts[exact] += 1;
        if fast == exact {
            agree += 1;
        } else if margin < 1e-4 {
            near_tie += 1;
        } else {
            clear_disagree += 1;
        }
    }
    println!(
        "{models:?}: {agree} agree, {near_tie} differ within 1e-4 of a threshold, {clear_disagree} differ clearly; exact LODs {lod_counts:?}"
    );
    assert_eq!(clear_disagree, 0);
    assert!(near_tie <= n / 10_000, "{near_tie} near-tie differences");
    assert!(
        lod_counts.iter().all(|&c| c > n / 50),
        "the scene must exercise every LOD: {lod_counts:?}"
    );
}
