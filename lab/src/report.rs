//! The reports of played runs: per-policy summaries ([`Summary`]), the
//! text table, the per-frame and summary CSVs, the line plots over time and
//! the side-by-side FLIP images that `acuity run` writes (the experiments
//! reuse the summaries, table and CSV).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, bail};
use image::RgbImage;

use crate::dump::sequence_name;
use crate::flip::quantile;
use crate::player::{FrameRecord, PolicyRun, WorstFrame};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::scene::Policy;

/// Per-policy summary of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The policy.
    pub policy: Policy,
    /// Its knob ([`PolicyRun::knob`]).
    pub knob: f64,
    /// Mean frame time, milliseconds.
    pub mean_ms: f64,
    /// 95th percentile frame time, milliseconds.
    pub p95_ms: f64,
    /// Mean triangles per frame.
    pub triangles: f64,
    /// Most triangles in one frame (what a frame budget must hold).
    pub triangles_max: f64,
    /// Mean draw calls per frame.
    pub draw_calls: f64,
    /// Mean LOD index over drawn instances and frames (0 = finest).
    pub mean_lod: f64,
    /// Mean frame time of full detail over this policy's, measured in the
    /// same run; `None` without a full-detail run.
    pub speedup: Option<f64>,
    /// Full detail's mean triangles over this policy's.
    pub triangle_ratio: Option<f64>,
    /// Mean over sampled frames of the frame's mean FLIP; NaN if none.
    pub flip_mean: f64,
    /// 95th percentile over sampled frames of the frame's mean FLIP.
    pub flip_p95: f64,
    /// Fraction of frames longer than the target period.
    pub over_budget: f64,
    /// Mean scale factor `s`.
    pub mean_scale: f64,
    /// LOD switches of drawn instances per second of simulated time
    /// (popping); NaN for a single frame.
    pub switches_per_s: f64,
    /// Of which reversals per second (flicker, see [`crate::switches`]);
    /// NaN for a single frame.
    pub reversals_per_s: f64,
    /// Slow reversals per second (within a second, the reversals
    /// included; [`crate::switches::SLOW_REVERSAL_WINDOW_S`]); NaN for a
    /// single frame.
    pub slow_reversals_per_s: f64,
    /// FovVideoVDP of the whole sequence against full detail, JOD (10 =
    /// identical); `None` unless scored ([`attach_jod`]).
    pub jod: Option<f64>,
    /// The most visible local difference: the 99.9th percentile over
    /// pixels and frames of FovVideoVDP's per-pixel distortion map, JOD
    /// lost; `None` unless scored ([`attach_jod`]).
    pub jod_local_p999: Option<f64>,
    /// Mean over frames of the selection's visibility in best effort's
    /// measure, deg (`Selector::selection_visibility_deg`); `None` where
    /// no frame recorded it.
    pub visibility_deg: Option<f64>,
}

/// A per-frame count's total over a run per second of simulated time from
/// its first frame to its last; NaN for fewer than two frames.
fn per_second(r: &PolicyRun, count: impl Fn(&FrameRecord) -> u32) -> f64 {
    let span = match (r.frames.first(), r.frames.last()) {
        (Some(a), Some(b)) => b.t_s - a.t_s,
        _ => 0.0,
    };
    let total: u64 = r.frames.iter().map(|f| u64::from(count(f))).sum();
    if span > 0.0 {
        total as f64 / span
    } else {
        f64::NAN
    }
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

/// Summarises runs; `budget_s` is the target frame period in seconds.
pub fn summarize(runs: &[PolicyRun], budget_s: f64) -> Vec<Summary> {
    let base = |f: &dyn Fn(&PolicyRun) -> f64| {
        runs.iter()
            .find(|r| r.policy == Policy::Full)
            .map(f)
            .filter(|v| v.is_finite() && *v > 0.0)
    };
    let ms = |r: &PolicyRun| mean(r.frames.iter().map(|f| f.frame_ms));
    let tris = |r: &PolicyRun| mean(r.frames.iter().map(|f| f.triangles as f64));
    let (full_ms, full_tris) = (base(&ms), base(&tris));
    runs.iter()
        .map(|r| {
            let times: Vec<f64> = r.frames.iter().map(|f| f.frame_ms).collect();
            let flips: Vec<f64> = r
                .frames
                .iter()
                .filter_map(|f| f.flip_mean.map(f64::from))
                .collect();
            let n = r.frames.len().max(1) as f64;
            Summary {
                policy: r.policy,
                knob: r.knob,
                mean_ms: ms(r),
                p95_ms: quantile(&times, 0.95),
                triangles: tris(r),
                triangles_max: r
                    .frames
                    .iter()
                    .map(|f| f.triangles as f64)
                    .fold(0.0, f64::max),
                draw_calls: mean(r.frames.iter().map(|f| f64::from(f.draw_calls))),
                mean_lod: mean(
                    r.frames
                        .iter()
                        .map(|f| f.mean_lod)
                        .filter(|x| x.is_finite()),
                ),
                speedup: full_ms.map(|b| b / ms(r)),
                triangle_ratio: full_tris.map(|b| b / tris(r)),
                flip_mean: mean(flips.iter().copied()),
                flip_p95: quantile(&flips, 0.95),
                over_budget: r
                    .frames
                    .iter()
                    .filter(|f| f.frame_ms * 1e-3 > budget_s)
                    .count() as f64
                    / n,
                mean_scale: mean(r.frames.iter().map(|f| f64::from(f.scale))),
                switches_per_s: per_second(r, |f| f.lod_switches),
                reversals_per_s: per_second(r, |f| f.lod_reversals),
                slow_reversals_per_s: per_second(r, |f| f.lod_slow_reversals),
                jod: None,
                jod_local_p999: None,
                visibility_deg: Some(mean(r.frames.iter().filter_map(|f| f.visibility_deg)))
                    .filter(|v| v.is_finite()),
            }
        })
        .collect()
}

/// Sets each summary's [`Summary::jod`] from FovVideoVDP scores by
/// sequence name ([`sequence_name`]); every summary must have one.
pub fn attach_jod(summaries: &mut [Summary], scores: &BTreeMap<String, f64>) -> anyhow::Result<()> {
    for s in summaries {
        let name = sequence_name(s.policy, s.knob);
        let jod = scores
            .get(&name)
            .with_context(|| format!("FovVideoVDP gave no score for `{name}`"))?;
        s.jod = Some(*jod);
        s.jod_local_p999 = scores.get(&format!("{name}:local_p999")).copied();
    }
    Ok(())
}

/// What the columns of [`format_table`] mean, a few lines for under the
/// table; the JOD line only when the table has a JOD column.
pub fn table_legend(with_jod: bool) -> String {
    let mut t = String::from(
        "mean/p95 ms: frame time; tris/frm, draws: triangles and draw calls a frame;\n\
         speedup, tri x: full detail's frame time and triangles over the policy's (above 1: faster, fewer);\n\
         LOD: mean LOD drawn (0 = finest); sw/s, rev/s: LOD switches a second, and switches back within 0.25 s;\n\
         FLIP: error against full detail on sampled frames (0 = identical; foveal, so savings away from the gaze count);\n\
         over%: frames over the frame-rate budget; s: mean scale factor of acuity policies (1 = imperceptible).\n",
    );
    if with_jod {
        t.push_str(
            "JOD: FovVideoVDP quality of the sequence, foveated at the gaze (10 = indistinguishable from full detail).\n",
        );
    }
    t.push_str(
        "Policies sit at different errors: compare triangles at equal JOD with \
         `acuity experiment error --metric fvvdp` (docs/perception.md).\n",
    );
    t
}

/// The summary as a text table; a JOD column when any summary has one.
pub fn format_table(summaries: &[Summary]) -> String {
    let with_jod = summaries.iter().any(|s| s.jod.is_some());
    let jod_col = |v: Option<f64>| match (with_jod, v) {
        (false, _) => String::new(),
        (true, Some(v)) => format!(" {v:>6.3}"),
        (true, None) => format!(" {:>6}", "-"),
    };
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<18} {:>9} {:>9} {:>10} {:>6} {:>8} {:>8} {:>6} {:>6} {:>6} {:>8} {:>8} {:>6} {:>5}{}",
        "policy",
        "mean ms",
        "p95 ms",
        "tris/frm",
        "draws",
        "speedup",
        "tri x",
        "LOD",
        "sw/s",
        "rev/s",
        "FLIP",
        "FLIP p95",
        "over%",
        "s",
        if with_jod {
            format!(" {:>6}", "JOD")
        } else {
            String::new()
        }
    );
    let opt = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2}x"));
    let flip = |v: f64| {
        if v.is_finite() {
            format!("{v:.4}")
        } else {
            "-".to_owned()
        }
    };
    for s in summaries {
        let _ = writeln!(
            t,
            "{:<18} {:>9.2} {:>9.2} {:>10.0} {:>6.1} {:>8} {:>8} {:>6.2} {:>6.1} {:>6.1} {:>8} {:>8} {:>6.1} {:>5.2}{}",
            s.policy.label(s.knob),
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.draw_calls,
            opt(s.speedup),
            opt(s.triangle_ratio),
            s.mean_lod,
            s.switches_per_s,
            s.reversals_per_s,
            flip(s.flip_mean),
            flip(s.flip_p95),
            100.0 * s.over_budget,
            s.mean_scale,
            jod_col(s.jod)
        );
    }
    t
}

/// Writes the per-frame CSV ([`frames_csv`]).
pub fn write_frames_csv(runs: &[PolicyRun], path: &Path) -> anyhow::Result<()> {
    std::fs::write(path, frames_csv(runs)).with_context(|| format!("writing {}", path.display()))
}

/// The per-frame CSV: one row per policy and frame.
pub fn frames_csv(runs: &[PolicyRun]) -> String {
    let mut t = String::from(
        "policy,frame,t_s,frame_ms,select_ms,triangles,draw_calls,drawn,mean_lod,lod_switches,scale,triangle_budget,flip_mean,flip_p95,lod_reversals,target_unreachable,in_spike,selection_visibility_deg,cost_floor_ms,aim_ms,lod_slow_reversals,at_limit\n",
    );
    let o = |v: Option<String>| v.unwrap_or_default();
    for r in runs {
        for f in &r.frames {
            let _ = writeln!(
                t,
                "{},{},{:.6},{:.4},{:.4},{},{},{},{:.4},{},{:.5},{},{},{},{},{},{},{},{},{},{},{}",
                r.policy.label(r.knob),
                f.frame,
                f.t_s,
                f.frame_ms,
                f.select_ms,
                f.triangles,
                f.draw_calls,
                f.drawn,
                f.mean_lod,
                f.lod_switches,
                f.scale,
                o(f.triangle_budget.map(|b| b.to_string())),
                o(f.flip_mean.map(|v| format!("{v:.6}"))),
                o(f.flip_p95.map(|v| format!("{v:.6}"))),
                f.lod_reversals,
                o(f.target_unreachable.map(|u| u32::from(u).to_string())),
                u32::from(f.in_spike),
                o(f.visibility_deg.map(|v| format!("{v:.4}"))),
                o(f.cost_floor_ms.map(|v| format!("{v:.3}"))),
                o(f.aim_ms.map(|v| format!("{v:.3}"))),
                f.lod_slow_reversals,
                u32::from(f.at_limit),
            );
        }
    }
    t
}

/// Writes the summary CSV and, beside it, the same rows as JSON
/// ([`write_csv_with_json`]).
pub fn write_summary_csv(summaries: &[Summary], path: &Path) -> anyhow::Result<()> {
    let mut t = String::from(
        "policy,mean_ms,p95_ms,triangles,draw_calls,mean_lod,lod_switches_per_s,speedup,triangle_ratio,flip_mean,flip_p95,over_budget,mean_scale,jod,lod_reversals_per_s,jod_local_p999\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
    for s in summaries {
        let _ = writeln!(
            t,
            "{},{:.4},{:.4},{:.1},{:.2},{:.4},{:.3},{},{},{:.6},{:.6},{:.4},{:.4},{},{:.3},{}",
            s.policy.name(),
            s.mean_ms,
            s.p95_ms,
            s.triangles,
            s.draw_calls,
            s.mean_lod,
            s.switches_per_s,
            o(s.speedup),
            o(s.triangle_ratio),
            s.flip_mean,
            s.flip_p95,
            s.over_budget,
            s.mean_scale,
            s.jod.map(|v| format!("{v:.4}")).unwrap_or_default(),
            s.reversals_per_s,
            o(s.jod_local_p999),
        );
    }
    write_csv_with_json(&t, path)
}

/// Writes CSV `text` (a header row, then rows of unquoted comma-separated
/// fields) to `csv_path`, and the same rows as JSON to `csv_path` with the
/// extension `json`: an array with one object per row, keyed by the
/// header's column names in column order. Fields that parse as integers or
/// finite numbers are numbers; empty and non-finite fields (`NaN`, `inf`) are
/// null; others are strings.
pub fn write_csv_with_json(text: &str, csv_path: &Path) -> anyhow::Result<()> {
    std::fs::write(csv_path, text).with_context(|| format!("writing {}", csv_path.display()))?;
    let json_path = csv_path.with_extension("json");
    let json = serde_json::to_string_pretty(&csv_rows(text)).context("encoding JSON")?;
    std::fs::write(&json_path, json + "\n")
        .with_context(|| format!("writing {}", json_path.display()))
}

/// One CSV row as a JSON object whose keys keep the column order.
struct JsonRow<'a>(Vec<(&'a str, serde_json::Value)>);

impl serde::Serialize for JsonRow<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

fn csv_rows(text: &str) -> Vec<JsonRow<'_>> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines
        .next()
        .map(|h| h.split(',').map(str::trim).collect())
        .unwrap_or_default();
    let value = |field: &str| {
        if field.is_empty() {
            return serde_json::Value::Null;
        }
        if let Ok(n) = field.parse::<i64>() {
            return n.into();
        }
        match field.parse::<f64>() {
            Ok(v) => serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, Into::into),
            Err(_) => field.into(),
        }
    };
    lines
        .map(|line| {
            JsonRow(
                header
                    .iter()
                    .zip(line.split(',').map(str::trim))
                    .map(|(&k, v)| (k, value(v)))
                    .collect(),
            )
        })
        .collect()
}

/// Writes `reference | test | FLIP map` side by side as one PNG.
pub fn write_side_by_side(
    reference_rgba: &[u8],
    worst: &WorstFrame,
    [w, h]: [u32; 2],
    path: &Path,
) -> anyhow::Result<()> {
    let n = w as usize * h as usize;
    if reference_rgba.len() != 4 * n
        || worst.test_rgba.len() != 4 * n
        || worst.map_rgb.len() != 3 * n
    {
        bail!("side-by-side images do not match {w}x{h}");
    }
    let mut img = RgbImage::new(3 * w, h);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let px = |b: &[u8], n: usize| image::Rgb([b[n * i], b[n * i + 1], b[n * i + 2]]);
            img.put_pixel(x, y, px(reference_rgba, 4));
            img.put_pixel(w + x, y, px(&worst.test_rgba, 4));
            img.put_pixel(2 * w + x, y, px(&worst.map_rgb, 3));
        }
    }
    img.save(path)
        .with_context(|| format!("writing {}", path.display()))
}

fn over_time(runs: &[PolicyRun], f: impl Fn(&FrameRecord) -> f64) -> Vec<Series> {
    runs.iter()
        .map(|r| Series {
            name: r.policy.name().to_owned(),
            points: r.frames.iter().map(|x| (x.t_s, f(x))).collect(),
        })
        .collect()
}

/// Writes the plots: frame time, triangles and `s` over time per policy.
pub fn write_plots(runs: &[PolicyRun], scene_name: &str, dir: &Path) -> anyhow::Result<()> {
    let plot = |title: &str, y: &str, series| LinePlot {
        title: format!("{scene_name}: {title}"),
        x_label: "simulated time (s)".into(),
        y_label: y.into(),
        series,
        y_from_zero: true,
        ..Default::default()
    };
    save_line_plot(
        &plot(
            "frame time",
            "frame time (ms)",
            over_time(runs, |f| f.frame_ms),
        ),
        &dir.join("frame_time.png"),
    )?;
    save_line_plot(
        &plot(
            "triangles",
            "triangles per frame",
            over_time(runs, |f| f.triangles as f64),
        ),
        &dir.join("triangles.png"),
    )?;
    save_line_plot(
        &plot(
            "scale factor s",
            "scale factor s",
            over_time(runs, |f| f64::from(f.scale)),
        ),
        &dir.join("scale.png"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_rows_keep_columns_numbers_and_blanks() {
        let rows = csv_rows("policy,mean_ms,jod\nfull,2.5,\nacuity,NaN,9\n\n");
        let json = serde_json::to_string(&rows).unwrap();
        assert_eq!(
            json,
            r#"[{"policy":"full","mean_ms":2.5,"jod":null},{"policy":"acuity","mean_ms":null,"jod":9}]"#
        );
        assert!(csv_rows("").is_empty());
    }
}
