//! Shared test fixtures: a seeded generator, synthetic profiles and
//! scenes, and frames.
#![allow(dead_code)]

use acuity::profile::{Feature, PROFILE_FORMAT_VERSION, Profile, TransitionFeatures};
use acuity::{
    Camera, Display, FrameInput, Gaze, ObjectDesc, ObjectId, ProfileId, Selection, Selector,
    SelectorSettings, Tracker,
};
use glam::{DVec3, Quat, Vec3};
use rand::{RngExt, SeedableRng};
use rand_xorshift::XorShiftRng;

/// The seeded generator of the tests and benches, with the shapes they draw.
pub struct Rng(XorShiftRng);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(XorShiftRng::seed_from_u64(seed))
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0.random()
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0) as f32,
                self.range(-1.0, 1.0) as f32,
                self.range(-1.0, 1.0) as f32,
            );
            if let Some(n) = v.try_normalize()
                && v.length_squared() <= 1.0
            {
                return n;
            }
        }
    }
    pub fn rotation(&mut self) -> Quat {
        Quat::from_axis_angle(
            self.direction(),
            self.range(0.0, std::f64::consts::TAU) as f32,
        )
    }
    pub fn point(&mut self, half_extent: f64) -> DVec3 {
        DVec3::new(
            self.range(-half_extent, half_extent),
            self.range(-half_extent, half_extent),
            self.range(-half_extent, half_extent),
        )
    }
}

/// The 18 viewpoints of a once-subdivided octahedron.
pub fn eighteen_viewpoints() -> Vec<[f32; 3]> {
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut dirs: Vec<Vec3> = axes.to_vec();
    for (i, a) in axes.iter().enumerate() {
        for b in &axes[i + 1..] {
            if a.dot(*b) == 0.0 {
                dirs.push((*a + *b).normalize());
            }
        }
    }
    dirs.iter().map(|d| d.to_array()).collect()
}

/// The size ladder of the synthetic profiles (the offline pass's default).
pub const RUNGS_PX: [f32; 6] = [16.0, 32.0, 64.0, 128.0, 256.0, 512.0];

/// A 4-LOD profile (the paper's 3928/834/254/76 triangles) over 18
/// viewpoints and the default size ladder whose transitions remove coarser
/// features as LODs coarsen (one full-contrast and one faint feature
/// each), with per-viewpoint variation; some transitions have no unique
/// feature.
pub fn four_lod_profile(seed: u64) -> Profile {
    let mut rng = Rng::new(seed);
    let viewpoints = eighteen_viewpoints();
    let mut transitions = Vec::new();
    for _ in &viewpoints {
        for _ in RUNGS_PX {
            for t in 0..3 {
                let features = if rng.unit() < 0.05 {
                    vec![]
                } else {
                    let f = (240.0 / (1 << (2 * t)) as f64 * rng.range(0.6, 1.6)) as f32;
                    vec![
                        Feature {
                            freq_cdiam: f,
                            area_diam2: 0.002,
                            luminance: [0.0, 0.5],
                            masker: [0.0, 0.5],
                            count: 1,
                        },
                        Feature {
                            freq_cdiam: 0.5 * f,
                            area_diam2: 0.02,
                            luminance: [0.4, 0.42],
                            masker: [0.4, 0.42],
                            count: 1,
                        },
                    ]
                    .into_iter()
                    .rev()
                    .collect()
                };
                transitions.push(TransitionFeatures {
                    feature_count: features.len() as u32,
                    features,
                });
            }
        }
    }
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: format!("synthetic-{seed}"),
        lod_triangles: vec![3928, 834, 254, 76],
        bounding_radius: 1.0,
        viewpoints,
        rung_diameters_px: RUNGS_PX.to_vec(),
        transitions,
        settings: Default::default(),
        inputs: vec![],
    }
}

/// A profile with one LOD.
pub fn single_lod_profile() -> Profile {
    Profile {
        format_version: PROFILE_FORMAT_VERSION,
        name: "single".into(),
        lod_triangles: vec![500],
        bounding_radius: 1.0,
        viewpoints: vec![[0.0, 0.0, 1.0]],
        rung_diameters_px: vec![512.0],
        transitions: vec![],
        settings: Default::default(),
        inputs: vec![],
    }
}

/// A 1280x1024 desktop display of 53.1x41.1 degrees.
pub fn display() -> Display {
    Display::new([1280, 1024], [53.1, 41.1]).unwrap()
}

/// A frame at `position` looking along -Z, eyes at the screen's centre, s = 1.
pub fn frame_at(position: DVec3, dt_s: f32) -> FrameInput {
    FrameInput {
        camera: Camera {
            position,
            orientation: Quat::IDENTITY,
        },
        gaze: Gaze::screen_centre(Tracker::None),
        dt_s,
        scale: 1.0,
    }
}

/// A random scene in front of the camera: `n` objects within 5–200 units.
pub fn random_scene(
    settings: SelectorSettings,
    n: usize,
    seed: u64,
    origin: DVec3,
) -> (Selector, Vec<ObjectId>) {
    let mut sel = Selector::new(display(), settings);
    let p = sel.add_profile(&four_lod_profile(7)).unwrap();
    let mut rng = Rng::new(seed);
    let ids = (0..n)
        .map(|_| {
            let dir = Vec3::new(
                rng.range(-0.6, 0.6) as f32,
                rng.range(-0.5, 0.5) as f32,
                -1.0,
            )
            .normalize();
            let center = origin + dir.as_dvec3() * rng.range(5.0, 200.0);
            sel.add_object(ObjectDesc {
                center,
                radius: rng.range(0.2, 3.0) as f32,
                rotation: rng.rotation(),
                profile: p,
            })
            .unwrap()
        })
        .collect();
    (sel, ids)
}

/// Each object's selection.
pub fn lods(sel: &Selector, ids: &[ObjectId]) -> Vec<Selection> {
    ids.iter().map(|&id| sel.selection(id)).collect()
}

/// An object of radius 1 on the view axis of [`frame_at`] at `z`.
pub fn on_axis(sel: &mut Selector, profile: ProfileId, z: f64) -> ObjectId {
    sel.add_object(ObjectDesc {
        center: DVec3::new(0.0, 0.0, z),
        radius: 1.0,
        rotation: Quat::IDENTITY,
        profile,
    })
    .unwrap()
}

/// A two-LOD profile whose one transition is a single feature of
/// `freq_cdiam` seen from every viewpoint and size.
pub fn two_lod_profile(triangles: [u32; 2], freq_cdiam: f32) -> acuity::Profile {
    let mut p = four_lod_profile(1);
    p.lod_triangles = triangles.to_vec();
    let rungs = p.rung_diameters_px.len();
    p.transitions = (0..p.viewpoints.len() * rungs)
        .map(|_| acuity::profile::TransitionFeatures {
            feature_count: 1,
            features: vec![acuity::profile::Feature {
                freq_cdiam,
                area_diam2: 0.01,
                luminance: [0.0, 0.5],
                masker: [0.0, 0.5],
                count: 1,
            }],
        })
        .collect();
    p
}

/// Two objects side by side at the same distance (the same acuity, both
/// visible at `s = 1`): one whose step saves 3000 triangles (4000 to
/// 1000) at a critical frequency of 60 c/diam, one whose step saves 40
/// (100 to 60) at `small_freq_cdiam`.
pub fn big_and_small_saver(
    settings: SelectorSettings,
    small_freq_cdiam: f32,
) -> (Selector, ObjectId, ObjectId) {
    let mut sel = Selector::new(display(), settings);
    let big = sel
        .add_profile(&two_lod_profile([4000, 1000], 60.0))
        .unwrap();
    let small = sel
        .add_profile(&two_lod_profile([100, 60], small_freq_cdiam))
        .unwrap();
    let mut add = |x: f64, profile| {
        sel.add_object(ObjectDesc {
            center: DVec3::new(x, 0.0, -10.0),
            radius: 1.0,
            rotation: Quat::IDENTITY,
            profile,
        })
        .unwrap()
    };
    let (a, b) = (add(-1.5, big), add(1.5, small));
    (sel, a, b)
}

/// `frame` with its global scale factor `s` set to `scale`.
pub fn with_scale(mut frame: FrameInput, scale: f32) -> FrameInput {
    frame.scale = scale;
    frame
}
