//! Validation of `[camera]` and `[gaze]`: keyframes or a forward path
//! with its yaw sweep, and the gaze mode with its tracker.

use glam::{DVec2, DVec3};

use super::context::{Ctx, Res};
use super::raw::{RawCamera, RawGaze, RawGazeMode};
use super::{MAX_DEFER_COARSENING_S, ObjectSpec};
use crate::arrays::Exact;
use crate::gaze::{GazeMode, GazePoint, GazeSpec, Tracker};
use crate::path::{CameraMotion, CameraPath, Keyframe, YawSweep};

impl Ctx<'_> {
    pub(super) fn camera(&self, c: RawCamera) -> Res<CameraPath> {
        let positive = |field: &str, v: f64, unit: &str| -> Res<f64> {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(self.invalid(field, format!("{v} {unit} must be > 0")))
            }
        };
        match (c.keyframes, c.forward_speed_m_per_s) {
            (Some(_), Some(_)) => Err(self.invalid(
                "camera.forward_speed_m_per_s",
                "give either keyframes or forward_speed_m_per_s, not both",
            )),
            (None, None) => Err(self.invalid(
                "camera",
                "missing motion: give keyframes or forward_speed_m_per_s",
            )),
            (Some(keys), None) => {
                if c.start.is_some() || c.yaw_sweep.is_some() {
                    let f = if c.start.is_some() {
                        "start"
                    } else {
                        "yaw_sweep"
                    };
                    return Err(self.invalid(
                        format!("camera.{f}"),
                        "only valid with forward_speed_m_per_s",
                    ));
                }
                if keys.is_empty() {
                    return Err(self.invalid("camera.keyframes", "needs at least one keyframe"));
                }
                for k in 1..keys.len() {
                    if !(keys[k].t > keys[k - 1].t) {
                        return Err(self.invalid(
                            format!("camera.keyframes[{k}].t"),
                            format!(
                                "times must increase: {} s is not after {} s",
                                keys[k].t,
                                keys[k - 1].t
                            ),
                        ));
                    }
                }
                if keys[0].t < 0.0 {
                    return Err(self.invalid(
                        "camera.keyframes[0].t",
                        format!("{} s must be >= 0", keys[0].t),
                    ));
                }
                let last_t = keys.last().map_or(0.0, |k| k.t);
                let duration_s = match c.duration_s {
                    Some(d) => positive("camera.duration_s", d, "s")?,
                    None if last_t > 0.0 => last_t,
                    None => {
                        return Err(self.invalid(
                            "camera.duration_s",
                            "missing: needed when the keyframes span no time",
                        ));
                    }
                };
                let keyframes = keys
                    .into_iter()
                    .map(|k| Keyframe {
                        t_s: k.t,
                        position_m: DVec3::from_array(k.position.0),
                        yaw_deg: k.yaw_deg,
                        pitch_deg: k.pitch_deg,
                        roll_deg: k.roll_deg,
                    })
                    .collect();
                Ok(CameraPath {
                    duration_s,
                    motion: CameraMotion::Keyframes(keyframes),
                })
            }
            (None, Some(speed)) => {
                if !(speed >= 0.0) {
                    return Err(self.invalid(
                        "camera.forward_speed_m_per_s",
                        format!("{speed} m/s must be >= 0"),
                    ));
                }
                let Some(d) = c.duration_s else {
                    return Err(self.invalid(
                        "camera.duration_s",
                        "missing: a forward path needs duration_s",
                    ));
                };
                let duration_s = positive("camera.duration_s", d, "s")?;
                let start = c.start.unwrap_or_default();
                let yaw_sweep = match c.yaw_sweep {
                    None => None,
                    Some(s) => {
                        positive("camera.yaw_sweep.amplitude_deg", s.amplitude_deg, "deg")?;
                        if !(s.rate_deg_per_s >= 0.0) {
                            return Err(self.invalid(
                                "camera.yaw_sweep.rate_deg_per_s",
                                format!("{} deg/s must be >= 0", s.rate_deg_per_s),
                            ));
                        }
                        let end = s.rate_end_deg_per_s.unwrap_or(s.rate_deg_per_s);
                        if !(end >= 0.0) {
                            return Err(self.invalid(
                                "camera.yaw_sweep.rate_end_deg_per_s",
                                format!("{end} deg/s must be >= 0"),
                            ));
                        }
                        Some(YawSweep {
                            amplitude_deg: s.amplitude_deg,
                            rate_deg_per_s: s.rate_deg_per_s,
                            rate_end_deg_per_s: end,
                            shape: s.shape,
                        })
                    }
                };
                Ok(CameraPath {
                    duration_s,
                    motion: CameraMotion::Forward {
                        speed_m_per_s: speed,
                        start_m: DVec3::from_array(start.position.0),
                        start_yaw_deg: start.yaw_deg,
                        start_pitch_deg: start.pitch_deg,
                        yaw_sweep,
                    },
                })
            }
        }
    }

    pub(super) fn gaze(&self, g: RawGaze, objects: &[ObjectSpec]) -> Res<GazeSpec> {
        let unexpected = |field: &str, mode: &str| {
            self.invalid(
                format!("gaze.{field}"),
                format!("not used with mode = \"{mode}\""),
            )
        };
        if g.mode != RawGazeMode::Fixed && g.point_deg.is_some() {
            return Err(unexpected("point_deg", mode_name(g.mode)));
        }
        if g.mode != RawGazeMode::Path && g.path.is_some() {
            return Err(unexpected("path", mode_name(g.mode)));
        }
        if g.mode != RawGazeMode::Track && (g.object.is_some() || g.copy.is_some()) {
            let f = if g.object.is_some() { "object" } else { "copy" };
            return Err(unexpected(f, mode_name(g.mode)));
        }
        let mode = match g.mode {
            RawGazeMode::ScreenCentre => GazeMode::ScreenCentre,
            RawGazeMode::Fixed => {
                let Some(Exact(p)) = g.point_deg else {
                    return Err(self.invalid(
                        "gaze.point_deg",
                        "missing: mode = \"fixed\" needs point_deg = [x, y]",
                    ));
                };
                self.screen_point("gaze.point_deg", p)?;
                GazeMode::Fixed {
                    point_deg: DVec2::from_array(p),
                }
            }
            RawGazeMode::Path => {
                let Some(points) = g.path else {
                    return Err(self.invalid(
                        "gaze.path",
                        "missing: mode = \"path\" needs path = [{ t = .., point_deg = [x, y] }, ..]",
                    ));
                };
                if points.is_empty() {
                    return Err(self.invalid("gaze.path", "needs at least one point"));
                }
                for (k, p) in points.iter().enumerate() {
                    self.screen_point(&format!("gaze.path[{k}].point_deg"), p.point_deg.0)?;
                    if k > 0 && !(p.t > points[k - 1].t) {
                        return Err(self.invalid(
                            format!("gaze.path[{k}].t"),
                            format!(
                                "times must increase: {} s is not after {} s",
                                p.t,
                                points[k - 1].t
                            ),
                        ));
                    }
                }
                GazeMode::Path(
                    points
                        .into_iter()
                        .map(|p| GazePoint {
                            t_s: p.t,
                            point_deg: DVec2::from_array(p.point_deg.0),
                        })
                        .collect(),
                )
            }
            RawGazeMode::Track => {
                let Some(object) = g.object else {
                    return Err(self.invalid(
                        "gaze.object",
                        "missing: mode = \"track\" needs object = \"<name>\"",
                    ));
                };
                let copy = self.instance(objects, "gaze.object", "gaze.copy", &object, g.copy)?;
                GazeMode::Track { object, copy }
            }
        };
        if g.eye_error_deg.is_some() && g.tracker != Tracker::Eye {
            return Err(self.invalid(
                "gaze.eye_error_deg",
                format!(
                    "needs tracker = \"eye\" (tracker is \"{}\", whose margin is fixed at {} deg)",
                    g.tracker.name(),
                    g.tracker.default_error_deg()
                ),
            ));
        }
        let tracker_error_deg = g
            .eye_error_deg
            .unwrap_or_else(|| g.tracker.default_error_deg());
        if !(0.0..90.0).contains(&tracker_error_deg) {
            return Err(self.invalid(
                "gaze.eye_error_deg",
                format!("{tracker_error_deg} deg must be in [0, 90)"),
            ));
        }
        if g.eyes_counter_rotate.is_some() && g.tracker != Tracker::Head {
            return Err(self.invalid(
                "gaze.eyes_counter_rotate",
                "applies to tracker = \"head\" only (eye trackers report the gaze; without tracking, camera turns move the display's content)",
            ));
        }
        if let Some(v) = g.saccade_threshold_deg_per_s {
            if g.tracker != Tracker::Eye {
                return Err(self.invalid(
                    "gaze.saccade_threshold_deg_per_s",
                    "needs tracker = \"eye\" (only an eye tracker sees saccades)",
                ));
            }
            if !(v > 0.0 && v.is_finite()) {
                return Err(self.invalid(
                    "gaze.saccade_threshold_deg_per_s",
                    format!("{v} deg/s must be finite and > 0"),
                ));
            }
        }
        if let Some(wait_s) = g.defer_coarsening_s {
            if g.tracker != Tracker::Eye {
                return Err(self.invalid(
                    "gaze.defer_coarsening_s",
                    "needs tracker = \"eye\" (only an eye tracker sees saccades)",
                ));
            }
            if !(0.0..=MAX_DEFER_COARSENING_S).contains(&wait_s) {
                return Err(self.invalid(
                    "gaze.defer_coarsening_s",
                    format!("{wait_s} s must be in [0, {MAX_DEFER_COARSENING_S}]"),
                ));
            }
        }
        if g.viewer_copy.is_some() && g.viewer_object.is_none() {
            return Err(self.invalid("gaze.viewer_copy", "needs viewer_object = \"<name>\""));
        }
        let viewer = match g.viewer_object {
            Some(_) if g.tracker == Tracker::Eye => {
                return Err(self.invalid(
                    "gaze.viewer_object",
                    "not used with tracker = \"eye\" (an eye tracker reports where the viewer looks)",
                ));
            }
            Some(object) => {
                let copy = self.instance(
                    objects,
                    "gaze.viewer_object",
                    "gaze.viewer_copy",
                    &object,
                    g.viewer_copy,
                )?;
                Some(GazeMode::Track { object, copy })
            }
            None => None,
        };
        Ok(GazeSpec {
            mode,
            tracker: g.tracker,
            tracker_error_deg,
            eyes_counter_rotate: g.eyes_counter_rotate.unwrap_or(true),
            saccade_threshold_deg_per_s: g.saccade_threshold_deg_per_s,
            defer_coarsening_s: g.defer_coarsening_s.unwrap_or(0.0),
            viewer,
        })
    }

    /// The copy (default 0) of the object named `object` that a gaze
    /// tracks, checked to exist; errors name `object_field` or
    /// `copy_field`.
    fn instance(
        &self,
        objects: &[ObjectSpec],
        object_field: &str,
        copy_field: &str,
        object: &str,
        copy: Option<u32>,
    ) -> Res<u32> {
        let Some(obj) = objects.iter().find(|o| o.name == object) else {
            let known: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
            return Err(self.invalid(
                object_field,
                format!("no object named {object:?} (objects: {known:?})"),
            ));
        };
        let copy = copy.unwrap_or(0);
        if copy as usize >= obj.placement.count() {
            return Err(self.invalid(
                copy_field,
                format!(
                    "object {object:?} has {} instance(s); copy {copy} does not exist",
                    obj.placement.count()
                ),
            ));
        }
        Ok(copy)
    }

    fn screen_point(&self, field: &str, p: [f64; 2]) -> Res<()> {
        for (k, &a) in p.iter().enumerate() {
            if !(a.abs() < 90.0) {
                return Err(self.invalid(
                    format!("{field}[{k}]"),
                    format!("{a} deg must be in (-90, 90)"),
                ));
            }
        }
        Ok(())
    }
}

fn mode_name(m: RawGazeMode) -> &'static str {
    match m {
        RawGazeMode::ScreenCentre => "screen_centre",
        RawGazeMode::Fixed => "fixed",
        RawGazeMode::Path => "path",
        RawGazeMode::Track => "track",
    }
}
