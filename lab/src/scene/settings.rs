//! Validation of the scene's settings tables: `[display]` (resolution,
//! field of view or physical screen, photometry, refresh), `[observer]`,
//! `[profiles]` and `[run]` (rate, policies, frames, screen-size baseline,
//! scale factor).

use std::collections::HashSet;

use super::context::{Ctx, Res};
use super::raw::{RawDisplay, RawObserver, RawProfiles, RawRun};
use super::{
    DisplaySpec, MAX_FRAMES, MAX_RESOLUTION_PX, PhysicalScreen, Policy, ProfileSpec, RunSpec,
};
use crate::limits;

impl Ctx<'_> {
    pub(super) fn observer(&self, o: RawObserver) -> Res<acuity::Observer> {
        let d = acuity::Observer::default();
        let observer = acuity::Observer {
            sensitivity: o.sensitivity.unwrap_or(d.sensitivity),
            masking: o.masking.unwrap_or(d.masking),
            pooling_area_deg2: o.pooling_area_deg2.unwrap_or(d.pooling_area_deg2),
            threshold_jnd: o.threshold_jnd.unwrap_or(d.threshold_jnd),
        };
        match observer.validate() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                Err(self.invalid(format!("observer.{name}"), reason))
            }
            Err(e) => Err(self.invalid("observer", e.to_string())),
            Ok(()) => Ok(observer),
        }
    }

    pub(super) fn profiles(&self, p: RawProfiles) -> Res<ProfileSpec> {
        let statistic = p
            .statistic
            .map(|s| crate::parse::parse_statistic(&s))
            .transpose()
            .map_err(|reason| self.invalid("profiles.statistic", reason))?;
        let spec = ProfileSpec {
            resolution_px: p.resolution,
            min_diameter_px: p.min_diameter,
            msaa_samples: p.msaa_samples,
            viewpoint_level: p.viewpoints,
            statistic,
            threshold_delta_e: p.threshold_delta_e,
            min_change_delta_e: p.min_change_delta_e,
        };
        // The offline pass's own domain check; its defaults are valid, so a
        // failure names one of this table's keys.
        match spec.analysis_settings().validate() {
            Err(acuity_preprocess::Error::Settings { field, message }) => {
                let key = match field {
                    "resolution_px" => "resolution",
                    "min_diameter_px" => "min_diameter",
                    "viewpoint_level" => "viewpoints",
                    other => other,
                };
                Err(self.invalid(format!("profiles.{key}"), message))
            }
            Err(e) => Err(self.invalid("profiles", e.to_string())),
            Ok(()) => Ok(spec),
        }
    }

    pub(super) fn display(&self, d: RawDisplay) -> Res<DisplaySpec> {
        let resolution = d.resolution.0;
        for (k, &px) in resolution.iter().enumerate() {
            if px == 0 || px > MAX_RESOLUTION_PX {
                return Err(self.invalid(
                    format!("display.resolution[{k}]"),
                    format!("{px} pixels is outside 1..={MAX_RESOLUTION_PX}"),
                ));
            }
        }
        let edges = d.fov_edges_deg.map(|e| e.0);
        if edges.is_some() && (d.fov_deg.is_some() || d.screen_cm.is_some()) {
            return Err(self.invalid(
                "display.fov_edges_deg",
                "give one of fov_deg, fov_edges_deg or screen_cm + distance_cm",
            ));
        }
        let given = (
            d.fov_deg
                .map(|f| f.0)
                .or(edges.map(|[l, r, u, dn]| [r - l, u - dn])),
            d.screen_cm.map(|s| s.0),
        );
        let (fov_deg, physical) = match (given.0, given.1, d.distance_cm) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "give either fov_deg or screen_cm + distance_cm, not both",
                ));
            }
            (Some(fov_deg), None, None) => (fov_deg, None),
            (None, Some(size_cm), Some(distance_cm)) => {
                for (k, &s) in size_cm.iter().enumerate() {
                    if !(s > 0.0) {
                        return Err(self.invalid(
                            format!("display.screen_cm[{k}]"),
                            format!("{s} cm must be > 0"),
                        ));
                    }
                }
                if !(distance_cm > 0.0) {
                    return Err(self.invalid(
                        "display.distance_cm",
                        format!("{distance_cm} cm must be > 0"),
                    ));
                }
                let screen = PhysicalScreen {
                    size_cm,
                    distance_cm,
                };
                (screen.fov_deg(), Some(screen))
            }
            (None, Some(_), None) => {
                return Err(self.invalid(
                    "display.distance_cm",
                    "screen_cm needs distance_cm (eye to screen, cm)",
                ));
            }
            (None, None, Some(_)) => {
                return Err(self.invalid(
                    "display.screen_cm",
                    "distance_cm needs screen_cm (width, height in cm)",
                ));
            }
            (None, None, None) => {
                return Err(self.invalid(
                    "display.fov_deg",
                    "missing: give fov_deg = [horizontal, vertical], fov_edges_deg = [left, right, up, down] or screen_cm + distance_cm",
                ));
            }
        };
        for (k, &f) in fov_deg.iter().enumerate() {
            if !(f > 0.0 && f < 180.0) {
                return Err(match edges {
                    Some(e) => self.invalid(
                        "display.fov_edges_deg",
                        format!(
                            "{e:?} is {f} deg {}, not in (0, 180): [left, right, up, down] needs right > left and up > down",
                            ["wide", "high"][k]
                        ),
                    ),
                    None => self.invalid(
                        format!("display.fov_deg[{k}]"),
                        format!("{f} deg must be in (0, 180)"),
                    ),
                });
            }
        }
        let max_edge = f64::from(acuity::display::MAX_EDGE_DEG);
        let fov_edges_deg = match edges {
            Some(e) => {
                for (k, &a) in e.iter().enumerate() {
                    if !(-max_edge..=max_edge).contains(&a) {
                        return Err(self.invalid(
                            format!("display.fov_edges_deg[{k}]"),
                            format!("{a} deg is outside [-{max_edge}, {max_edge}]"),
                        ));
                    }
                }
                e
            }
            None => [
                -0.5 * fov_deg[0],
                0.5 * fov_deg[0],
                0.5 * fov_deg[1],
                -0.5 * fov_deg[1],
            ],
        };
        if let Some(ipd) = d.stereo_ipd_m
            && !(0.0..=1.0).contains(&ipd)
        {
            return Err(self.invalid("display.stereo_ipd_m", format!("{ipd} m is outside [0, 1]")));
        }
        let spec = DisplaySpec {
            resolution_px: resolution,
            fov_deg,
            fov_edges_deg,
            stereo_ipd_m: d.stereo_ipd_m,
            physical,
            peak_luminance_cd_m2: d.peak_luminance_cd_m2.unwrap_or(200.0),
            contrast_ratio: d.contrast_ratio.unwrap_or(1000.0),
            ambient_lux: d.ambient_lux.unwrap_or(250.0),
            refresh_hz: match (d.continuous_motion, d.refresh_hz) {
                (Some(true), Some(_)) => {
                    return Err(self.invalid(
                        "display.continuous_motion",
                        "give refresh_hz or continuous_motion = true, not both",
                    ));
                }
                (Some(true), None) => None,
                (_, hz) => Some(hz.unwrap_or(f64::from(acuity::display::DEFAULT_REFRESH_HZ))),
            },
        };
        if let Some(hz) = spec.refresh_hz
            && !(1.0..=10_000.0).contains(&hz)
        {
            return Err(self.invalid(
                "display.refresh_hz",
                format!("{hz} Hz is outside [1, 10000]"),
            ));
        }
        match spec.photometry() {
            Err(acuity::Error::InvalidParameter { name, reason }) => {
                let key = match name {
                    "peak_cd_m2" => "peak_luminance_cd_m2",
                    other => other,
                };
                Err(self.invalid(format!("display.{key}"), reason))
            }
            Err(e) => Err(self.invalid("display", e.to_string())),
            Ok(_) => Ok(spec),
        }
    }

    pub(super) fn run(&self, r: RawRun, duration_s: f64) -> Res<RunSpec> {
        let target_hz = r.target_hz.unwrap_or(60.0);
        limits::check_target_hz(target_hz).map_err(|e| self.invalid("run.target_hz", e))?;
        let policies = r.policies.unwrap_or_else(|| Policy::ALL.to_vec());
        if policies.is_empty() {
            return Err(self.invalid("run.policies", "needs at least one policy"));
        }
        let mut seen = HashSet::new();
        for (k, p) in policies.iter().enumerate() {
            if !seen.insert(*p) {
                return Err(self.invalid(
                    format!("run.policies[{k}]"),
                    format!("{:?} is listed twice", p.name()),
                ));
            }
        }
        if r.frames == Some(0) {
            return Err(self.invalid("run.frames", "0 frames; need at least 1"));
        }
        let frame_dt_s = match (r.dt_s, r.frames) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("run.dt_s", "give either frames or dt_s, not both"));
            }
            (Some(dt), None) => {
                limits::check_dt_s(dt).map_err(|e| self.invalid("run.dt_s", e))?;
                dt
            }
            (None, Some(n)) => duration_s / f64::from(n),
            (None, None) => 1.0 / target_hz,
        };
        let frames = match r.frames {
            Some(n) if u64::from(n) > MAX_FRAMES => {
                return Err(self.invalid(
                    "run.frames",
                    format!("{n} frames is more than {MAX_FRAMES}"),
                ));
            }
            Some(n) => n,
            None => {
                let n = (duration_s / frame_dt_s).ceil().max(1.0);
                if !(n <= MAX_FRAMES as f64) {
                    let field = if r.dt_s.is_some() {
                        "run.dt_s"
                    } else {
                        "run.target_hz"
                    };
                    return Err(self.invalid(
                        field,
                        format!("{n} frames over {duration_s} s is more than {MAX_FRAMES}"),
                    ));
                }
                n as u32
            }
        };
        let screen_size_bias = r.screen_size_bias.unwrap_or(1.0);
        if !(screen_size_bias > 0.0) {
            return Err(self.invalid(
                "run.screen_size_bias",
                format!("{screen_size_bias} must be > 0"),
            ));
        }
        let screen_size_thresholds = r
            .screen_size_thresholds
            .unwrap_or_else(|| crate::screen_size::DEFAULT_THRESHOLDS_4.to_vec());
        crate::screen_size::check_table(&screen_size_thresholds)
            .map_err(|e| self.invalid("run.screen_size_thresholds", e.to_string()))?;
        let scale_factor = r.scale_factor.unwrap_or(1.0);
        if !(scale_factor > 0.0 && scale_factor <= 1.0) {
            return Err(self.invalid(
                "run.scale_factor",
                format!("{scale_factor} must be in (0, 1]"),
            ));
        }
        let cross_fade_s = r.cross_fade_s.unwrap_or(0.0);
        super::check_cross_fade_s(cross_fade_s).map_err(|e| self.invalid("run.cross_fade_s", e))?;
        let min_scale = r.min_scale.unwrap_or(f64::from(acuity::DEFAULT_MIN_SCALE));
        super::check_min_scale(min_scale).map_err(|e| self.invalid("run.min_scale", e))?;
        Ok(RunSpec {
            target_hz,
            policies,
            frame_dt_s,
            frames,
            flip_every_n_frames: r.flip_every_n_frames.unwrap_or(10),
            screen_size_bias,
            screen_size_thresholds,
            screen_size_foveated: r.screen_size_foveated.unwrap_or(false),
            scale_factor,
            cross_fade_s,
            min_scale: min_scale as f32,
        })
    }
}
