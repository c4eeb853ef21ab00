//! Acuity's schedulers against screen size at equal frame time: under
//! the same reactive controller screen size's frames land at another mean
//! frame time than acuity's, so `experiment framerate` also runs screen
//! size with its controller told other periods
//! ([`Policy::ScreenSizeReactivePeriod`]) and interpolates its JOD at each
//! acuity scheduler's mean frame time.

use std::fmt::Write;

use crate::plot::{LinePlot, Series};
use crate::report::Summary;
use crate::scene::Policy;

/// An acuity scheduler's JOD beside screen size's under the same
/// controller at the same mean frame time.
#[derive(Debug, Clone, PartialEq)]
pub struct EqualFrameTime {
    /// The acuity policy.
    pub policy: Policy,
    /// Its mean frame time, ms (the spikes' frames included).
    pub mean_ms: f64,
    /// Its sequence's foveated JOD.
    pub jod: f64,
    /// Screen size's JOD under the same controller at `mean_ms`,
    /// interpolated over its runs at several periods
    /// ([`jod_at_frame_time`]); `None` outside their range.
    pub screen_size_jod: Option<f64>,
}

/// Screen size's points of (mean frame time, ms; JOD) under the reactive
/// controller: `screen_size_reactive` and its runs told other periods.
fn screen_size_curve(sums: &[Summary]) -> Vec<(f64, f64)> {
    sums.iter()
        .filter(|s| {
            matches!(
                s.policy,
                Policy::ScreenSizeReactive | Policy::ScreenSizeReactivePeriod
            )
        })
        .filter_map(|s| Some((s.mean_ms, s.jod?)))
        .collect()
}

/// The JOD a curve of (mean frame time, ms; JOD) points, in any order,
/// reaches at `mean_ms`: linear between the two neighbouring points by
/// frame time. `None` outside the points' range (no extrapolation: a
/// frame time the controller never ran at is not measured) or for a
/// non-finite `mean_ms`; points with the same frame time are averaged.
pub fn jod_at_frame_time(curve: &[(f64, f64)], mean_ms: f64) -> Option<f64> {
    super::interpolate::linear_at(curve, mean_ms, super::interpolate::Ties::Mean)
}

/// Whether a policy is one of acuity's tuned schedulers, compared with
/// screen size at equal frame time (not the controllers before headroom).
fn compared_at_equal_time(p: Policy) -> bool {
    p.is_scheduled() && !p.is_screen_size() && !p.is_untuned()
}

/// Each scored acuity scheduler
/// against screen size at its mean frame time; empty unless screen size
/// was scored at two frame times or more (`--screen-size-periods` with
/// `--metric fvvdp`).
pub fn at_equal_frame_time(sums: &[Summary]) -> Vec<EqualFrameTime> {
    let curve = screen_size_curve(sums);
    if curve.len() < 2 {
        return Vec::new();
    }
    sums.iter()
        .filter(|s| compared_at_equal_time(s.policy))
        .filter_map(|s| {
            Some(EqualFrameTime {
                policy: s.policy,
                mean_ms: s.mean_ms,
                jod: s.jod?,
                screen_size_jod: jod_at_frame_time(&curve, s.mean_ms),
            })
        })
        .collect()
}

/// The comparison at equal frame time as a table: mean ms, JOD, screen
/// size's JOD there and the difference.
pub fn equal_time_table(rows: &[EqualFrameTime]) -> String {
    let mut t = String::from(
        "at equal mean frame time: screen size under the same controller, its JOD interpolated over its periods\n",
    );
    let _ = writeln!(
        t,
        "{:<30} {:>8} {:>7} {:>10} {:>7}",
        "policy", "mean ms", "JOD", "screen JOD", "diff"
    );
    for r in rows {
        let (screen, diff) = match r.screen_size_jod {
            Some(j) => (format!("{j:.3}"), format!("{:+.3}", r.jod - j)),
            None => ("outside".into(), "-".into()),
        };
        let _ = writeln!(
            t,
            "{:<30} {:>8.2} {:>7.3} {:>10} {:>7}",
            r.policy.name(),
            r.mean_ms,
            r.jod,
            screen,
            diff
        );
    }
    t
}

/// The comparison at equal frame time as CSV (empty where screen size's
/// runs do not span the policy's frame time).
pub fn equal_time_csv(rows: &[EqualFrameTime]) -> String {
    let mut t = String::from("policy,mean_ms,jod,screen_size_jod,jod_minus_screen_size\n");
    for r in rows {
        let o = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
        let _ = writeln!(
            t,
            "{},{:.3},{:.4},{},{}",
            r.policy.name(),
            r.mean_ms,
            r.jod,
            o(r.screen_size_jod),
            o(r.screen_size_jod.map(|j| r.jod - j))
        );
    }
    t
}

/// JOD against mean frame time: screen size's line over its periods and
/// each scored acuity scheduler's point.
pub fn equal_time_plot(sums: &[Summary]) -> LinePlot {
    let mut curve = screen_size_curve(sums);
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut series = vec![Series {
        name: "screen_size_reactive (periods)".into(),
        points: curve,
    }];
    series.extend(
        sums.iter()
            .filter(|s| compared_at_equal_time(s.policy))
            .filter_map(|s| {
                Some(Series {
                    name: s.policy.name().into(),
                    points: vec![(s.mean_ms, s.jod?)],
                })
            }),
    );
    LinePlot {
        title: "JOD at the held rate against mean frame time".into(),
        x_label: "mean frame time (ms)".into(),
        y_label: "FovVideoVDP JOD".into(),
        series,
        markers: true,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A summary of `policy` at `knob` with a mean frame time and a JOD.
    fn scored(policy: Policy, knob: f64, mean_ms: f64, jod: f64) -> Summary {
        Summary {
            policy,
            knob,
            mean_ms,
            p95_ms: mean_ms,
            triangles: 1000.0,
            triangles_max: 1000.0,
            draw_calls: 1.0,
            mean_lod: 0.0,
            speedup: None,
            triangle_ratio: None,
            flip_mean: f64::NAN,
            flip_p95: f64::NAN,
            over_budget: 0.0,
            mean_scale: 1.0,
            switches_per_s: 0.0,
            reversals_per_s: 0.0,
            slow_reversals_per_s: 0.0,
            jod: Some(jod),
            jod_local_p999: None,
            visibility_deg: None,
        }
    }

    #[test]
    fn jod_at_a_frame_time_is_linear_between_neighbours_and_never_extrapolated() {
        let curve = [
            (28.0, 8.3),
            (22.0, 7.7),
            (25.0, 8.0),
            (25.0, 8.2),
            (f64::NAN, 9.0),
        ];
        let at = |ms| jod_at_frame_time(&curve, ms);
        assert!((at(23.5).unwrap() - 7.9).abs() < 1e-12, "{:?}", at(23.5));
        // Two points at 25 ms count as their mean.
        assert!((at(25.0).unwrap() - 8.1).abs() < 1e-12);
        assert!((at(26.5).unwrap() - 8.2).abs() < 1e-12);
        assert_eq!(at(22.0), Some(7.7));
        assert_eq!(at(21.9), None);
        assert_eq!(at(28.1), None);
        assert_eq!(at(f64::NAN), None);
        assert_eq!(jod_at_frame_time(&[(25.0, 8.0)], 24.0), None);
    }

    #[test]
    fn acuity_schedulers_are_compared_with_screen_size_at_their_own_frame_time() {
        let screen = [
            scored(Policy::ScreenSizeReactive, 32.0, 25.0, 8.0),
            scored(Policy::ScreenSizeReactivePeriod, 0.9, 22.0, 7.7),
            scored(Policy::ScreenSizeReactivePeriod, 1.1, 28.0, 8.3),
        ];
        let mut sums = vec![
            scored(Policy::AcuityAll, 1.0, 40.0, 9.5),
            scored(Policy::AcuityPredictive, 1.0, 24.0, 7.95),
            scored(Policy::AcuityReactive, 1.0, 30.0, 8.4),
            scored(Policy::AcuityReactiveNoHeadroom, 1.0, 26.0, 8.0),
        ];
        // One frame time of screen size's is no curve: nothing compared.
        sums.push(screen[0].clone());
        assert!(at_equal_frame_time(&sums).is_empty());
        sums.extend_from_slice(&screen[1..]);
        let rows = at_equal_frame_time(&sums);
        let policies: Vec<Policy> = rows.iter().map(|r| r.policy).collect();
        assert_eq!(
            policies,
            [Policy::AcuityPredictive, Policy::AcuityReactive],
            "only the tuned schedulers"
        );
        let predictive = rows[0].screen_size_jod.unwrap();
        assert!((predictive - 7.9).abs() < 1e-12, "{predictive}");
        assert_eq!(
            rows[1].screen_size_jod, None,
            "30 ms is beyond screen size's 28"
        );
        let table = equal_time_table(&rows);
        assert!(table.contains("+0.050"), "{table}");
        assert!(table.contains("outside"), "{table}");
        assert_eq!(
            Policy::ScreenSizeReactivePeriod.label(0.9),
            "screen_size_reactive_period_0.9"
        );
        assert_eq!(
            Policy::ScreenSizeReactive.label(32.0),
            "screen_size_reactive"
        );
    }
}
