//! The loop against a scalar reference implementation, bit for bit, over
//! every switch, vector width, row layout and (with `parallel`) work split.

use glam::{DVec3, Quat, Vec3};
use rand::{RngExt, SeedableRng};
use rand_xorshift::XorShiftRng;

#[cfg(feature = "parallel")]
use super::dispatch::CHUNK;
use super::frame::{frame_consts, outside_frustum};
use super::kernel::to_object_frame;
use super::rule::count_coarser;
use super::tables::{RowLayout, Tables};
use super::*;
use crate::Tracker;
use crate::acuity::{
    MAX_ACUITY_CPD, MIN_ACUITY_CPD, VELOCITY_CEILING_DEG_PER_S, VELOCITY_FLOOR_DEG_PER_S,
};
use crate::camera::normalized_rotation;
use crate::display::Display;
use crate::fastmath;
use crate::profile::Profile;
use crate::profile::{Feature, PROFILE_FORMAT_VERSION, TransitionFeatures};

/// The seeded generator of the tests, uniform in `[-1, 1)` times `scale`.
struct Rng(XorShiftRng);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(XorShiftRng::seed_from_u64(seed))
    }

    fn next(&mut self, scale: f32) -> f32 {
        self.0.random_range(-1.0f32..1.0) * scale
    }

    fn rotation(&mut self) -> Quat {
        let q = Quat::from_xyzw(self.next(1.0), self.next(1.0), self.next(1.0), 0.5);
        q.normalize()
    }
}

/// The size ladder of the test profiles: 4 rungs, 16 to 128 pixels.
const RUNGS: [f32; 4] = [16.0, 32.0, 64.0, 128.0];

fn profile(rng: &mut Rng, lods: usize, views: usize) -> Profile {
    let viewpoints = (0..views)
        .map(|_| {
            let v = Vec3::new(rng.next(1.0), rng.next(1.0), rng.next(1.0) + 0.01);
            v.normalize().to_array()
        })
        .collect();
    let transitions = (0..views * RUNGS.len() * (lods - 1))
        .map(|t| {
            let mut features: Vec<Feature> = (0..(rng.next(2.0) + 2.0) as usize)
                .map(|_| {
                    let lo = rng.next(0.25) + 0.25;
                    Feature {
                        area_diam2: 0.001 + rng.next(0.0005),
                        freq_cdiam: 200.0 / (1 << (t % (lods - 1))) as f32 * (1.2 + rng.next(0.6)),
                        luminance: [lo, lo + rng.next(0.25) + 0.25],
                        masker: [0.0, rng.next(0.5) + 0.5],
                        count: 1,
                    }
                })
                .collect();
            features.sort_by(|a, b| a.freq_cdiam.total_cmp(&b.freq_cdiam));
            TransitionFeatures {
                feature_count: features.len() as u32,
                features,
            }
        })
        .collect();
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: "test".into(),
        lod_triangles: (0..lods).map(|l| 4000 >> l).collect(),
        bounding_radius: 1.0,
        viewpoints,
        rung_diameters_px: RUNGS.to_vec(),
        transitions,
        settings: Default::default(),
        inputs: vec![],
    }
}

/// The selection loop one object at a time, as plainly as it can be
/// written (the model of [`crate::acuity`], the rule of [`super::rule`]),
/// with its own motion state.
struct Reference {
    dir_eye: Vec<Vec3>,
    velocity_deg_per_s: Vec<f32>,
}

impl Reference {
    fn frame(&mut self, sel: &Selector, frame: &FrameInput) -> Vec<(Selection, Diagnostics)> {
        let s = &sel.settings;
        let mut c = frame_consts(
            &sel.display,
            s,
            Tables {
                rows: &sel.rows,
                profiles: &sel.profile_rows,
                lookups: &sel.lookups,
                ladders: &sel.ladders,
                object_profiles: &sel.object_profiles,
                layout: sel.layout,
                motion_floor_cpd: sel.frame_motion_floor(frame).0,
            },
            frame,
            frame.scale,
        )
        .unwrap();
        c.pursued = sel.pursued_slot(frame.gaze.pursued);
        let mut out = Vec::new();
        for i in 0..sel.multi() {
            let (b, l) = (&sel.blocks[i / BLOCK], i % BLOCK);
            let center = DVec3::new(b.x[l], b.y[l], b.z[l]);
            let r = b.radius[l];
            let rotation = Quat::from_array([0, 1, 2, 3].map(|a| b.rotation[a][l]));
            let rel = (center - c.cam_pos).as_vec3();
            let p = c.world_to_eye * rel;
            let d2 = p.length_squared();
            let inside = d2 <= r * r;
            if c.cull && !inside && outside_frustum(&c, p, r) {
                self.velocity_deg_per_s[i] = -1.0;
                out.push((Selection::CULLED, Diagnostics::default()));
                continue;
            }
            let inv_d = 1.0 / d2.max(f32::MIN_POSITIVE).sqrt();
            let theta_deg = if inside {
                180.0
            } else {
                2.0 * fastmath::asin((r * inv_d).min(1.0)) * RAD_TO_DEG
            };
            let eccentricity_deg = if s.components.eccentricity {
                let angle = fastmath::acos((-p.z * inv_d).clamp(-1.0, 1.0)) * RAD_TO_DEG;
                (angle - 0.5 * theta_deg - c.margin_deg).max(0.0)
            } else {
                0.0
            };
            let mut velocity = 0.0;
            if s.components.velocity {
                let dir = p * inv_d;
                let dir = if c.world_velocity {
                    let [a, b, d] = c.eye_to_world.to_cols_array_2d();
                    Vec3::new(
                        a[0] * dir.x + b[0] * dir.y + d[0] * dir.z,
                        a[1] * dir.x + b[1] * dir.y + d[1] * dir.z,
                        a[2] * dir.x + b[2] * dir.y + d[2] * dir.z,
                    )
                } else {
                    dir
                };
                let before = self.velocity_deg_per_s[i];
                let v = if before < 0.0 {
                    0.0
                } else if c.dt_valid {
                    let chord = (dir - self.dir_eye[i]).length();
                    let step = 2.0 * fastmath::asin((0.5 * chord).min(1.0)) * RAD_TO_DEG;
                    let now = (step * c.inv_dt).min(MAX_VELOCITY_DEG_PER_S);
                    before + c.alpha * (now - before)
                } else {
                    before
                };
                self.dir_eye[i] = dir;
                self.velocity_deg_per_s[i] = v;
                velocity = if i as u32 == c.pursued { 0.0 } else { v };
            }
            let g = if s.components.velocity {
                let g = match s.velocity_model {
                    VelocityModel::Kelly1979 => crate::acuity::kelly_velocity_acuity_cpd(velocity),
                    VelocityModel::Reddy2001 => {
                        let v =
                            velocity.clamp(VELOCITY_FLOOR_DEG_PER_S, VELOCITY_CEILING_DEG_PER_S);
                        (57.69 - 27.78 * fastmath::log10(v)).clamp(MIN_ACUITY_CPD, MAX_ACUITY_CPD)
                    }
                };
                g.max(c.motion_floor_cpd)
            } else {
                MAX_ACUITY_CPD
            };
            let m = if s.components.eccentricity {
                s.eccentricity_model.factor(eccentricity_deg)
            } else {
                1.0
            };
            let threshold_cpd = c.scale * (g * m);
            let size = if s.components.size {
                theta_deg
            } else {
                c.fill_deg
            };
            let profile = sel.object_profiles[i] as usize;
            let rows = sel.profile_rows[profile];
            let ladder = &sel.ladders[rows.ladder as usize];
            let rung = ladder.boundaries_deg.iter().filter(|&&b| size > b).count();
            // Judged at the top of its rung's range, or its own size on
            // the bottom and top rungs.
            let judged = match ladder.boundaries_deg.get(rung) {
                Some(&b) if rung > 0 => b,
                _ => size,
            };
            let k = if inside {
                f32::INFINITY
            } else {
                threshold_cpd * judged
            };
            let rungs = ladder.diameters_px.len();
            let mut block = 0;
            if s.viewpoint_rule == ViewpointRule::Nearest && rows.lookup != NO_LOOKUP {
                let view = sel.lookups[rows.lookup as usize].nearest(rotation.conjugate() * -rel);
                block = 1 + view;
            }
            let row = rows.start as usize + (block * rungs + rung) * rows.stride as usize;
            let n = sel.profiles[profile].lod_count - 1;
            let lod = count_coarser(&sel.rows[row..row + n], k);
            let diagnostics = Diagnostics {
                angular_size_deg: theta_deg,
                eccentricity_deg,
                velocity_deg_per_s: velocity,
                threshold_cpd,
            };
            out.push((Selection(lod as u8), diagnostics));
        }
        out
    }
}

/// Profiles of different LOD and viewpoint counts: rows found object
/// by object.
const MIXED: [(usize, usize); 6] = [(4, 18), (4, 18), (2, 1), (3, 7), (7, 30), (1, 1)];

/// Runs the loop and the reference side by side over a few frames and
/// demands the same selections and diagnostics, bit for bit. `kinds`
/// lists the profiles as (LODs, viewpoints); with `shared`, profiles
/// with as many viewpoints share their directions.
fn matches_reference(
    settings: SelectorSettings,
    objects: usize,
    seed: u64,
    kinds: &[(usize, usize)],
    shared: bool,
) {
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15 ^ seed);
    // Every other seed on a sampled display, whose motion floor binds.
    let refresh_hz = (seed % 2 == 1).then_some(90.0);
    let display = Display::new([1920, 1080], [90.0, 58.7])
        .and_then(|d| d.with_refresh_hz(refresh_hz))
        .unwrap();
    // Saccade detection on every fourth seed (the turning camera carries
    // the eye-tracked gaze past the threshold).
    let settings = SelectorSettings {
        saccade_threshold_deg_per_s: if seed % 4 == 1 {
            SACCADE_THRESHOLD_DEG_PER_S
        } else {
            settings.saccade_threshold_deg_per_s
        },
        ..settings
    };
    let mut sel = Selector::new(display, settings);
    let mut profiles = vec![];
    for &(lods, views) in kinds {
        let mut p = profile(&mut rng, lods, views);
        if shared {
            p.viewpoints = profile(&mut Rng::new(views as u64 + 1), 2, views).viewpoints;
        }
        profiles.push(sel.add_profile(&p).unwrap());
    }
    let layout = sel.layout;
    let origin = DVec3::new(1e5, -3e6, 1e7) * (seed % 2) as f64;
    let mut ids = vec![];
    for k in 0..objects {
        let offset = if k % 5 == 0 {
            Vec3::new(rng.next(300.0), rng.next(300.0), rng.next(300.0))
        } else {
            let dir = Vec3::new(rng.next(1.3), rng.next(0.9), -1.0).normalize();
            dir * (rng.next(5.0) + 4.0).exp2()
        };
        let radius = if k % 40 == 0 {
            0.0
        } else {
            2.0 + rng.next(1.9)
        };
        let p = profiles[((rng.next(0.5) + 0.5) * kinds.len() as f32) as usize % kinds.len()];
        let desc = ObjectDesc {
            center: origin + offset.as_dvec3(),
            radius,
            rotation: rng.rotation(),
            profile: p,
        };
        ids.push(sel.add_object(desc).unwrap());
    }
    let mut reference = Reference {
        dir_eye: vec![Vec3::ZERO; sel.multi()],
        velocity_deg_per_s: vec![-1.0; sel.multi()],
    };
    for (f, dt) in [1.0 / 90.0, 1.0 / 90.0, 0.0, -1.0, 0.5, 1.0 / 60.0]
        .into_iter()
        .enumerate()
    {
        let yaw = 0.3 * f as f32 * (seed % 3) as f32;
        let frame = FrameInput {
            camera: Camera {
                position: origin + DVec3::new(0.1, 0.02, -0.3) * f as f64,
                orientation: Quat::from_rotation_y(yaw) * Quat::from_rotation_x(0.01),
            },
            gaze: Gaze {
                pursued: Some(ids[f * 7 % ids.len()]),
                // Head tracking (its velocity in world axes) on every third seed.
                ..Gaze::at_screen_angles(
                    5.0,
                    -2.0,
                    if seed % 3 == 2 {
                        Tracker::Head
                    } else {
                        Tracker::eye_default()
                    },
                )
            },
            dt_s: dt,
            scale: if f == 4 { 0.3 } else { 1.0 },
        };
        let expected = reference.frame(&sel, &frame);
        sel.select_with_diagnostics(&frame).unwrap();
        for (i, &(selection, diagnostics)) in expected.iter().enumerate() {
            assert_eq!(
                sel.selections[i], selection,
                "object {i}, frame {f}, {layout:?}"
            );
            if !selection.is_culled() {
                let bits = |d: Diagnostics| {
                    [
                        d.angular_size_deg,
                        d.eccentricity_deg,
                        d.velocity_deg_per_s,
                        d.threshold_cpd,
                    ]
                    .map(f32::to_bits)
                };
                let got = bits(sel.diagnostics[i]);
                assert_eq!(got, bits(diagnostics), "object {i}, frame {f}");
            }
        }
    }
}

#[test]
fn the_loop_matches_a_scalar_reference_bit_for_bit() {
    for k in 0..64u64 {
        let settings = SelectorSettings {
            components: Components {
                size: k & 1 != 0,
                velocity: k & 2 != 0,
                eccentricity: k & 4 != 0,
            },
            cull: k & 8 != 0,
            viewpoint_rule: if k & 16 != 0 {
                ViewpointRule::WorstCase
            } else {
                ViewpointRule::Nearest
            },
            eccentricity_model: if k & 32 != 0 {
                EccentricityModel::Reddy2001
            } else {
                EccentricityModel::CorticalMagnification
            },
            velocity_model: if k & 32 != 0 {
                VelocityModel::Reddy2001
            } else {
                VelocityModel::Kelly1979
            },
            ..Default::default()
        };
        // The same bits with the CPU's widest instructions and without.
        for simd in [SimdLevel::Widest, SimdLevel::Avx2, SimdLevel::Baseline] {
            let settings = SelectorSettings { simd, ..settings };
            matches_reference(settings, 700 + k as usize, k, &MIXED, false);
            // One offline pass's profiles: rows found in bulk.
            let uniform = [(4, 18), (4, 18), (5, 18), (3, 18), (1, 1)];
            matches_reference(settings, 700 + k as usize, k, &uniform, true);
        }
    }
}

#[test]
fn uniform_layouts_match_the_reference() {
    let nearest = SelectorSettings::default();
    let worst = SelectorSettings {
        viewpoint_rule: ViewpointRule::WorstCase,
        ..nearest
    };
    type Kinds = &'static [(usize, usize)];
    let cases: [(Kinds, bool, RowLayout); 6] = [
        (
            &[(7, 18), (8, 18)],
            true,
            RowLayout::Uniform {
                stride: 8,
                lookup: 0,
                ladder: 0,
            },
        ),
        (
            &[(2, 1), (4, 1), (1, 1)],
            true,
            RowLayout::Uniform {
                stride: 4,
                lookup: NO_LOOKUP,
                ladder: 0,
            },
        ),
        // More viewpoints than any vector width compares one by one.
        (
            &[(4, 66), (3, 66)],
            true,
            RowLayout::Uniform {
                stride: 4,
                lookup: 0,
                ladder: 0,
            },
        ),
        (&[(4, 18), (4, 18)], false, RowLayout::Mixed),
        (&[(4, 18), (9, 18)], true, RowLayout::Mixed),
        (&[(4, 18), (4, 30)], true, RowLayout::Mixed),
    ];
    for (k, (kinds, shared, layout)) in cases.into_iter().enumerate() {
        let mut sel = Selector::new(Display::new([64, 64], [60.0, 60.0]).unwrap(), nearest);
        let mut rng = Rng::new(k as u64 + 1);
        for &(lods, views) in kinds {
            let mut p = profile(&mut rng, lods, views);
            if shared {
                p.viewpoints = profile(&mut Rng::new(views as u64 + 1), 2, views).viewpoints;
            }
            sel.add_profile(&p).unwrap();
        }
        assert_eq!(sel.layout, layout, "case {k}");
        for settings in [nearest, worst] {
            matches_reference(settings, 900, k as u64, kinds, shared);
        }
    }
}

#[cfg(feature = "parallel")]
#[test]
fn the_parallel_loop_matches_a_scalar_reference_bit_for_bit() {
    let settings = SelectorSettings {
        parallel_min_objects: 0,
        ..Default::default()
    };
    matches_reference(settings, 3 * CHUNK + 77, 5, &MIXED, false);
    matches_reference(settings, 3 * CHUNK + 77, 6, &[(4, 18), (3, 18)], true);
}

#[test]
fn to_object_frame_rounds_like_glam() {
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let mut next = |scale: f32| rng.next(scale);
    for k in 0..200_000 {
        let q = Quat::from_xyzw(next(1.0), next(1.0), next(1.0), next(1.0));
        let Ok(q) = normalized_rotation(q, "q") else {
            continue;
        };
        let scale = [1e-3, 1.0, 1e3, 1e7][k % 4];
        let rel = Vec3::new(next(scale), next(scale), next(scale));
        let glam = q.conjugate() * (-rel);
        let ours = to_object_frame(q.to_array(), rel.to_array());
        assert_eq!(
            ours.map(f32::to_bits),
            glam.to_array().map(f32::to_bits),
            "{q} {rel}"
        );
    }
}
