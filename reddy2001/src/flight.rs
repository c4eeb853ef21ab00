//! The inputs of `acuity terrain`: a procedural fractal valley standing in
//! for Reddy 2001's Yosemite Valley model (661 x 847 elevations, 1.1 M
//! triangles at full resolution), and a recorded flight path through it
//! (20 s at about 50 deg/s average angular velocity, as in the paper).
//!
//! The flight is a function of time, so that any frame rate samples the
//! same path ("the same apparent velocity"), and the camera some time
//! earlier is at hand for retinal velocity.

use std::f32::consts::TAU;
use std::fmt::Write as _;

use acuity::Camera;
use acuity::terrain::Heightfield;
use glam::Vec3;

use crate::fractal::Fbm;

/// The procedural terrain's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValleySettings {
    /// Samples along `x` and `y` (Reddy's model: 661 x 847).
    pub size: [usize; 2],
    /// Distance between samples, m (a 30 m DEM, like USGS's of the time).
    pub spacing_m: f32,
    /// Height of the fractal relief, m.
    pub relief_m: f32,
    /// Depth of the valley carved along `y`, m.
    pub valley_depth_m: f32,
    /// Noise seed.
    pub seed: u64,
}

impl Default for ValleySettings {
    fn default() -> Self {
        Self {
            size: [661, 847],
            spacing_m: 30.0,
            relief_m: 900.0,
            valley_depth_m: 1000.0,
            seed: 2001,
        }
    }
}

impl ValleySettings {
    /// `x` of the valley floor's centre line at `y`, in samples.
    fn valley_centre(&self, y: f32) -> f32 {
        0.5 * self.size[0] as f32 + 0.08 * self.size[0] as f32 * (y / 140.0).sin()
    }

    /// The heightfield: fractal relief (`1/f`, 10 octaves) with a
    /// meandering valley of Gaussian cross-section along `y`.
    pub fn heightfield(&self) -> acuity::Result<Heightfield> {
        let [w, h] = self.size;
        let noise = Fbm {
            seed: self.seed,
            base_period: 256.0,
            octaves: 10,
            persistence: 0.5,
        };
        let half_width = 0.12 * w as f32;
        let mut heights = Vec::with_capacity(w * h);
        for y in 0..h {
            let centre = self.valley_centre(y as f32);
            for x in 0..w {
                let across = (x as f32 - centre) / half_width;
                let valley = self.valley_depth_m * (-across * across).exp();
                let n = noise.at(x as f32, y as f32);
                heights.push(self.relief_m * (0.6 + n) + self.valley_depth_m - valley);
            }
        }
        Heightfield::new(w, h, self.spacing_m, heights)
    }
}

/// The flight: up the valley, banking its view left and right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Duration, s (Reddy: about 20).
    pub duration_s: f32,
    /// Ground speed along the valley, m/s.
    pub speed_m_per_s: f32,
    /// Height above the valley floor, m.
    pub clearance_m: f32,
    /// Amplitude of the view's yaw swing, deg.
    pub yaw_swing_deg: f32,
    /// Period of the yaw swing, s. A sine swing of amplitude `A` and period
    /// `P` turns at `4 A / P` deg/s on average: 60 deg over 4.8 s is 50.
    pub yaw_period_s: f32,
    /// Mean pitch, deg (negative: looking down).
    pub pitch_deg: f32,
    /// Amplitude of the pitch swing, deg (period 3.1 times the yaw's, so
    /// the two do not lock).
    pub pitch_swing_deg: f32,
}

impl Default for Flight {
    fn default() -> Self {
        Self {
            duration_s: 20.0,
            speed_m_per_s: 250.0,
            clearance_m: 300.0,
            yaw_swing_deg: 60.0,
            yaw_period_s: 4.8,
            pitch_deg: -15.0,
            pitch_swing_deg: 10.0,
        }
    }
}

/// One sample of the flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Time, s.
    pub t_s: f32,
    /// Eye position, m.
    pub position: Vec3,
    /// Heading of the view, deg clockwise from `+y`.
    pub yaw_deg: f32,
    /// Pitch of the view, deg (negative: down).
    pub pitch_deg: f32,
}

impl Pose {
    /// The camera: looking along yaw and pitch, `+z` up. Fails for a
    /// vertical or non-finite view.
    pub fn camera(&self) -> acuity::Result<Camera> {
        Camera::look_to(self.position.as_dvec3(), self.forward(), Vec3::Z)
    }

    /// The view's forward direction.
    fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw_deg.to_radians().sin_cos();
        let (sp, cp) = self.pitch_deg.to_radians().sin_cos();
        Vec3::new(sy * cp, cy * cp, sp)
    }
}

impl Flight {
    /// The pose at `t_s` seconds (any time; the path continues beyond its
    /// ends), over `field` made by `valley`.
    pub fn pose(&self, t_s: f32, valley: &ValleySettings, field: &Heightfield) -> Pose {
        let s = field.spacing();
        let start_y = 0.1 * valley.size[1] as f32;
        let y = start_y + t_s * self.speed_m_per_s / s;
        let x = valley.valley_centre(y);
        let [w, h] = field.size();
        // Above the highest ground within 3 samples, so the eye never dips
        // into a wall as the valley bends.
        let mut ground = f32::MIN;
        for dy in -3i32..=3 {
            for dx in -3i32..=3 {
                let i = (x as i32 + dx).clamp(0, w as i32 - 1) as usize;
                let j = (y as i32 + dy).clamp(0, h as i32 - 1) as usize;
                ground = ground.max(field.at(i, j));
            }
        }
        let heading = (valley.valley_centre(y + 1.0) - x).atan().to_degrees();
        let phase = TAU * t_s / self.yaw_period_s;
        Pose {
            t_s,
            position: Vec3::new(x * s, y * s, ground + self.clearance_m),
            yaw_deg: heading + self.yaw_swing_deg * phase.sin(),
            pitch_deg: self.pitch_deg + self.pitch_swing_deg * (phase / 3.1).sin(),
        }
    }

    /// Mean angular speed of the view direction over `poses`, deg/s.
    pub fn mean_angular_speed_deg_per_s(poses: &[Pose]) -> f32 {
        let mut total = 0.0;
        for pair in poses.windows(2) {
            let (a, b) = (pair[0].forward(), pair[1].forward());
            total += a.cross(b).length().atan2(a.dot(b)).to_degrees();
        }
        let span = poses.last().map_or(0.0, |p| p.t_s) - poses.first().map_or(0.0, |p| p.t_s);
        if span > 0.0 { total / span } else { 0.0 }
    }
}

/// The poses as CSV: `t_s,x_m,y_m,z_m,yaw_deg,pitch_deg`.
pub fn poses_csv(poses: &[Pose]) -> String {
    let mut out = String::from("t_s,x_m,y_m,z_m,yaw_deg,pitch_deg\n");
    for p in poses {
        let _ = writeln!(
            out,
            "{:.4},{:.2},{:.2},{:.2},{:.3},{:.3}",
            p.t_s, p.position.x, p.position.y, p.position.z, p.yaw_deg, p.pitch_deg
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_flight_turns_at_about_fifty_degrees_per_second() {
        let valley = ValleySettings {
            size: [129, 257],
            ..Default::default()
        };
        let field = valley.heightfield().unwrap();
        let flight = Flight::default();
        let poses: Vec<Pose> = (0..=600)
            .map(|i| flight.pose(i as f32 / 30.0, &valley, &field))
            .collect();
        let speed = Flight::mean_angular_speed_deg_per_s(&poses);
        assert!((45.0..=60.0).contains(&speed), "{speed} deg/s");
        for p in &poses {
            let (i, j) = (p.position.x / 30.0, p.position.y / 30.0);
            let ground = field.at(i as usize, j as usize);
            assert!(p.position.z >= ground + 299.0, "{p:?} over {ground}");
        }
    }

    #[test]
    fn the_default_valley_has_the_papers_size() {
        let valley = ValleySettings::default();
        let field = valley.heightfield().unwrap();
        assert_eq!(field.full_triangles(), 1_116_720);
    }
}
