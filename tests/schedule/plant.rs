//! The stepwise synthetic plant the controllers are tested on, and what
//! the tests measure of them on it (reversals, the steady state).

use crate::common::Rng;
use acuity::{
    CostModel, PredictiveScheduler, ReactiveScheduler, ReactiveSettings, STEADY_SWITCH_HYSTERESIS,
};

pub const TRIANGLES: [f32; 4] = [3928.0, 834.0, 254.0, 76.0];

pub struct Plant {
    /// Per object, the scale below which it drops to LOD j+1.
    pub breakpoints: Vec<[f32; 3]>,
    pub seconds_per_triangle: f32,
}

impl Plant {
    pub fn new(seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let breakpoints = (0..300)
            .map(|_| {
                let a = rng.range(0.3, 1.6) as f32;
                [
                    a,
                    a * rng.range(0.2, 0.6) as f32,
                    a * rng.range(0.02, 0.15) as f32,
                ]
            })
            .collect();
        // At s = 1 and load 1 the frame takes 80% of a 90 Hz period.
        let mut p = Self {
            breakpoints,
            seconds_per_triangle: 1.0,
        };
        p.seconds_per_triangle = 0.8 / 90.0 / p.triangles(1.0);
        p
    }

    pub fn triangles(&self, scale: f32) -> f32 {
        self.breakpoints
            .iter()
            .map(|b| TRIANGLES[b.iter().filter(|&&s| scale < s).count()])
            .sum()
    }

    pub fn frame_time(&self, scale: f32, load: f32) -> f32 {
        load * self.triangles(scale) * self.seconds_per_triangle
    }

    pub fn lods(&self, scale: f32, out: &mut Vec<u8>) {
        out.clear();
        out.extend(
            self.breakpoints
                .iter()
                .map(|b| b.iter().filter(|&&s| scale < s).count() as u8),
        );
    }

    /// Moves each object's LOD (`lods`, empty at first) to scale `s` with
    /// the selector's switch hysteresis `h`: coarser only where `s (1 + h)`
    /// is below the breakpoint, finer at once. Returns the triangles.
    pub fn step_lods(&self, scale: f32, h: f32, lods: &mut Vec<u8>) -> f32 {
        let count = |s: f32, b: &[f32; 3]| b.iter().filter(|&&x| s < x).count() as u8;
        if lods.len() != self.breakpoints.len() {
            lods.clear();
            lods.extend(self.breakpoints.iter().map(|b| count(scale, b)));
        }
        let mut triangles = 0.0;
        for (lod, b) in lods.iter_mut().zip(&self.breakpoints) {
            let now = count(scale, b);
            *lod = if now > *lod {
                count(scale * (1.0 + h), b).clamp(*lod, now)
            } else {
                now
            };
            triangles += TRIANGLES[*lod as usize];
        }
        triangles
    }

    /// A reactive scheduler at 90 Hz settled on the plant over 300 frames
    /// under `load` (without noise).
    pub fn settled_reactive(&self, load: f32) -> ReactiveScheduler {
        let mut sched = ReactiveScheduler::new(ReactiveSettings::for_rate_hz(90.0).unwrap());
        for _ in 0..300 {
            sched.update(self.frame_time(sched.scale(), load));
        }
        sched
    }

    /// Triangles at the coarsest LOD of every object.
    pub fn coarsest_triangles(&self) -> u64 {
        (TRIANGLES[3] * self.breakpoints.len() as f32) as u64
    }

    /// The largest scale whose triangles fit `budget` (one `s` for all, as
    /// the uniform budget rule), or the lowest scale; and its triangles.
    pub fn fit_budget(&self, budget: u64) -> (f32, f32) {
        let mut breaks: Vec<f32> = self.breakpoints.iter().flatten().copied().collect();
        breaks.sort_by(|a, b| b.total_cmp(a));
        let mut scale = 1.0f32;
        for b in std::iter::once(1.0).chain(breaks.iter().map(|b| b * 0.999)) {
            scale = b.min(1.0);
            if self.triangles(scale) <= budget as f32 {
                break;
            }
        }
        (scale, self.triangles(scale))
    }
}

/// A multiplicative frame-time noise of relative standard deviation
/// `sigma` (about normal in the log).
pub fn noise(rng: &mut Rng, sigma: f32) -> f32 {
    let z: f64 = (0..12).map(|_| rng.unit()).sum::<f64>() - 6.0;
    (sigma * z as f32).exp()
}

/// LOD reversals: an object switching back to the LOD it left at its
/// previous switch within `window` frames.
#[derive(Default)]
pub struct Reversals {
    pub last: Vec<Option<(u8, usize)>>,
    pub before: Vec<u8>,
    pub count: usize,
    pub switches: usize,
}

impl Reversals {
    pub fn observe(&mut self, frame: usize, lods: &[u8], window: usize) {
        if self.before.len() != lods.len() {
            self.before = lods.to_vec();
            self.last = vec![None; lods.len()];
            return;
        }
        for (i, (&now, was)) in lods.iter().zip(self.before.iter_mut()).enumerate() {
            if now != *was {
                self.switches += 1;
                if let Some((from, at)) = self.last[i]
                    && from == now
                    && frame - at <= window
                {
                    self.count += 1;
                }
                self.last[i] = Some((*was, frame));
                *was = now;
            }
        }
    }
}

/// Frames at 90 Hz within which a switch back counts as a reversal (0.25 s).
pub const REVERSAL_WINDOW_FRAMES: usize = 22;

/// What a controller did in steady state on the noisy plant: the share of
/// frames over the period, LOD reversals and switches per second.
pub struct Steady {
    pub over: f64,
    pub reversals_per_s: f64,
    pub switches_per_s: f64,
}

/// The load at `frame`: `base` drifting by 15% over 3 s at 90 Hz (the scene
/// in view changing as the camera moves).
pub fn drifting(base: f32, frame: usize) -> f32 {
    base * (1.0 + 0.15 * (std::f32::consts::TAU * frame as f32 / 270.0).sin())
}

/// The reactive controller on the plant under `load` (drifting) with noise
/// `sigma`: 300 frames to settle, 600 measured.
pub fn reactive_steady(settings: ReactiveSettings, seed: u64, load: f32, sigma: f32) -> Steady {
    let plant = Plant::new(seed);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let mut sched = ReactiveScheduler::new(settings);
    let (mut lods, mut rev, mut over) = (Vec::new(), Reversals::default(), 0);
    for frame in 0..900 {
        let s = sched.scale();
        let triangles = plant.step_lods(s, STEADY_SWITCH_HYSTERESIS, &mut lods);
        if frame >= 300 {
            rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
        }
        let t =
            drifting(load, frame) * triangles * plant.seconds_per_triangle * noise(&mut rng, sigma);
        over += (frame >= 300 && t > settings.target_frame_s) as usize;
        sched.update(t);
    }
    Steady {
        over: over as f64 / 600.0,
        reversals_per_s: rev.count as f64 / (600.0 / 90.0),
        switches_per_s: rev.switches as f64 / (600.0 / 90.0),
    }
}

/// The predictive controller on the plant (one `s` for all within its
/// budget), with 1 ms of fixed time per frame.
pub fn predictive_steady(settings: ReactiveSettings, seed: u64, load: f32, sigma: f32) -> Steady {
    let plant = Plant::new(seed);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let fixed_s = 1e-3;
    let mut sched = PredictiveScheduler::new(
        settings,
        CostModel::new(fixed_s, plant.seconds_per_triangle),
    );
    let (mut lods, mut rev, mut over) = (Vec::new(), Reversals::default(), 0);
    for frame in 0..900 {
        let (s, triangles) = plant.fit_budget(sched.triangle_budget());
        plant.lods(s, &mut lods);
        if frame >= 300 {
            rev.observe(frame, &lods, REVERSAL_WINDOW_FRAMES);
        }
        let t = (fixed_s + drifting(load, frame) * triangles * plant.seconds_per_triangle)
            * noise(&mut rng, sigma);
        over += (frame >= 300 && t > settings.target_frame_s) as usize;
        sched.observe(t, triangles as u64, plant.coarsest_triangles());
    }
    Steady {
        over: over as f64 / 600.0,
        reversals_per_s: rev.count as f64 / (600.0 / 90.0),
        switches_per_s: rev.switches as f64 / (600.0 / 90.0),
    }
}

pub fn reversals(scales: &[f32]) -> usize {
    let mut last = 0.0f32;
    let mut count = 0;
    for w in scales.windows(2) {
        let d = w[1] - w[0];
        if d != 0.0 {
            if last != 0.0 && d.signum() != last.signum() {
                count += 1;
            }
            last = d;
        }
    }
    count
}
