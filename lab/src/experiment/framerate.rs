//! `acuity experiment framerate`: a fixed-frame-rate loop under load
//! spikes, frames over budget and `s` over time per scheduler.
//!
//! Besides the general table it prints one for the schedulers: frames over
//! the period outside the spikes (all of them, and those after the
//! start-up, [`START_UP_S`]) and within them, and within them the
//! frames the scheduler reported out of reach (its cost floor above the
//! period); once settled, the frames whose cost floor lay above the aim
//! (the period can then be held only as far as the frames' jitter allows,
//! whatever the LODs) and the late frames where it did not; LOD switches,
//! reversals and slow reversals (within a second) per second, mean
//! triangles and, with `--metric fvvdp`, the sequence's foveated JOD. Screen size under
//! the same reactive controller (`screen_size_reactive`) and the
//! controllers before headroom (`*_no_headroom`) run beside acuity's.

use std::fmt::Write;
use std::path::PathBuf;

use crate::dump::{Metric, check_fvvdp, score_fvvdp};
use crate::error::input_error;
use crate::limits;
use crate::player::{PlaySettings, Player, PolicyRun};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::report::{
    Summary, attach_jod, format_table, frames_csv, summarize, write_csv_with_json,
};
use crate::scene::Policy;

use super::CommonArgs;
use super::equal_time::{at_equal_frame_time, equal_time_csv, equal_time_plot, equal_time_table};

/// Arguments of `acuity experiment framerate`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct FramerateArgs {
    /// The scene.
    #[cfg_attr(feature = "clap", arg(long, default_value = "scenes/vr_sweep.toml"))]
    pub scene: PathBuf,
    /// Target frame rate, Hz, 1 to 10,000 (default: the scene's). A
    /// software rasteriser cannot reach 90 Hz on this scene; pick a rate it
    /// can nearly hold.
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::limits::parse_target_hz))]
    pub target_hz: Option<f64>,
    /// Frames, spread over the scene's path (default: the scene's).
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64)))]
    pub frames: Option<u32>,
    /// Extra load during the spikes, as a fraction of the frame budget,
    /// 0 to 10.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 0.5, value_parser = crate::limits::parse_spike_load))]
    pub spike_load: f64,
    /// The screen-size table's bias for `screen_size_reactive` at `s = 1`
    /// (the controller multiplies it by its `s`), finite and > 0; 32 draws
    /// about as many triangles as `acuity_all` at `s = 1` on
    /// `scenes/vr_sweep.toml`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 32.0))]
    pub screen_size_bias: f64,
    /// Frame periods, as factors of the real one (comma-separated, each
    /// 0.5 to 2; none by default), each told to a copy of
    /// `screen_size_reactive`'s controller
    /// (`screen_size_reactive_period_F`), whose frames then land longer or
    /// shorter. With `--metric fvvdp` screen size's JOD is interpolated at
    /// each acuity scheduler's mean frame time over these runs and
    /// `screen_size_reactive` (no extrapolation): the comparison at equal
    /// frame time. `0.8,0.9,1.1` spans the schedulers' spread on the
    /// shipped scenes (0.9,1.1 left the predictive scheduler outside on
    /// `scenes/default.toml`).
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub screen_size_periods: Vec<f64>,
    /// The lowest `s` the schedulers may use, screen size's under the same
    /// controller too, 1e-6 to 1 (default: the scene's `run.min_scale`,
    /// else the runtime's 1e-3).
    #[cfg_attr(feature = "clap", arg(long))]
    pub min_scale: Option<f64>,
    /// Error metrics, comma-separated: none by default; `fvvdp` scores
    /// every sequence with FovVideoVDP against full detail (needs Python
    /// with pyfvvdp; dumps the frames, to `<out>/frames/` without
    /// --dump-frames). `flip` is not offered here.
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub metric: Vec<Metric>,
    /// Options every experiment shares.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub common: CommonArgs,
}

/// The policies the experiment plays, in report order.
pub const FRAMERATE_POLICIES: [Policy; 12] = [
    Policy::Full,
    Policy::AcuityAll,
    Policy::AcuityReactive,
    Policy::AcuityReactiveBudgeted,
    Policy::AcuityReactivePooled,
    Policy::AcuityPredictive,
    Policy::AcuityPredictiveAnnounced,
    Policy::AcuityPredictiveUnweighted,
    Policy::AcuityPredictiveUniform,
    Policy::ScreenSizeReactive,
    Policy::AcuityReactiveNoHeadroom,
    Policy::AcuityPredictiveNoHeadroom,
];

/// What [`framerate`] measured.
#[derive(Debug, Clone)]
pub struct FramerateOutcome {
    /// One summary per policy.
    pub summaries: Vec<Summary>,
    /// The tables `acuity experiment framerate` prints: the target and its
    /// load spikes, the policies' summaries, and the rates they held.
    pub table: String,
}

/// Runs the frame-rate experiment; writes `framerate.csv` (per frame),
/// `framerate_summary.csv` (the schedulers' table), `framerate_time.png`
/// and `framerate_scale.png`; returns the summaries.
pub fn framerate(args: &FramerateArgs) -> anyhow::Result<FramerateOutcome> {
    if args.metric.contains(&Metric::Flip) {
        return Err(input_error(
            "--metric: experiment framerate scores with fvvdp only",
        ));
    }
    if !(args.screen_size_bias.is_finite() && args.screen_size_bias > 0.0) {
        return Err(input_error(format!(
            "--screen-size-bias: {} must be finite and > 0",
            args.screen_size_bias
        )));
    }
    if let Some(f) = args
        .screen_size_periods
        .iter()
        .find(|f| !(0.5..=2.0).contains(*f))
    {
        return Err(input_error(format!(
            "--screen-size-periods: {f} is outside 0.5 to 2"
        )));
    }
    let fvvdp = args.metric.contains(&Metric::Fvvdp);
    if fvvdp {
        check_fvvdp()?;
    }
    limits::check_spike_load(args.spike_load)
        .map_err(|e| input_error(format!("--spike-load: {e}")))?;
    if let Some(hz) = args.target_hz {
        limits::check_target_hz(hz).map_err(|e| input_error(format!("--target-hz: {e}")))?;
    }
    if let Some(m) = args.min_scale {
        crate::scene::check_min_scale(m).map_err(|e| input_error(format!("--min-scale: {e}")))?;
    }
    let mut world = args.common.load(&args.scene)?;
    if let Some(hz) = args.target_hz {
        world.scene.run.target_hz = hz;
    }
    if let Some(m) = args.min_scale {
        world.scene.run.min_scale = m as f32;
    }
    // The bias of the screen-size runs whose knob is their period.
    world.scene.run.screen_size_bias = args.screen_size_bias;
    let mut settings = PlaySettings::from_scene(&world.scene, args.frames)?;
    settings.flip_every_n_frames = 0;
    settings.keep_images = false;
    let out = args.common.out_dir("framerate")?;
    settings.dump_dir = args
        .common
        .dump_frames
        .clone()
        .or_else(|| fvvdp.then(|| out.join("frames")));
    // Two spikes, at 25-37.5% and 62.5-75% of the path.
    let d = f64::from(settings.frames) * settings.dt_s;
    let extra_ms = args.spike_load * world.scene.run.budget_s() * 1e3;
    settings.load_spikes = vec![
        (0.25 * d, 0.375 * d, extra_ms),
        (0.625 * d, 0.75 * d, extra_ms),
    ];
    let s = world.scene.run.scale_factor;
    let mut configs: Vec<(Policy, f64)> = FRAMERATE_POLICIES
        .iter()
        .map(|&p| match p {
            Policy::Full => (p, 1.0),
            _ if p.is_screen_size() => (p, args.screen_size_bias),
            _ => (p, s),
        })
        .collect();
    configs.extend(
        args.screen_size_periods
            .iter()
            .map(|&f| (Policy::ScreenSizeReactivePeriod, f)),
    );
    let bar = crate::progress::bar(
        u64::from(settings.frames) * configs.len() as u64,
        "frames",
        args.common.profiles.quiet,
    );
    let dump_dir = settings.dump_dir.clone();
    let mut player = Player::new(&world, settings)?;
    player.set_progress(&bar);
    // The calibration frames at bias 1 (screen size far coarser than full
    // detail) span the triangle counts the schedulers reach.
    let runs = player.play_configs(&configs, 1.0);
    bar.finish_and_clear();
    let runs = runs?;
    let mut sums = summarize(&runs, world.scene.run.budget_s());
    if let (true, Some(dir)) = (fvvdp, &dump_dir) {
        attach_jod(&mut sums, &score_fvvdp(dir, args.common.profiles.quiet)?)?;
    }
    let mut table = String::new();
    let _ = writeln!(
        table,
        "target {:.1} Hz ({:.2} ms), spikes of +{extra_ms:.2} ms at {:.2}-{:.2} s and {:.2}-{:.2} s; the schedulers' floor s = {}",
        world.scene.run.target_hz,
        world.scene.run.budget_s() * 1e3,
        0.25 * d,
        0.375 * d,
        0.625 * d,
        0.75 * d,
        world.scene.run.min_scale
    );
    table.push_str(&format_table(&sums));
    let held = held_rates(&runs, &sums, world.scene.run.budget_s());
    table.push('\n');
    table.push_str(&held_table(&held));
    write_csv_with_json(&frames_csv(&runs), &out.join("framerate.csv"))?;
    write_csv_with_json(&held_csv(&held), &out.join("framerate_summary.csv"))?;
    let equal = at_equal_frame_time(&sums);
    if !equal.is_empty() {
        table.push('\n');
        table.push_str(&equal_time_table(&equal));
        write_csv_with_json(
            &equal_time_csv(&equal),
            &out.join("framerate_equal_time.csv"),
        )?;
        save_line_plot(
            &equal_time_plot(&sums),
            &out.join("framerate_equal_time.png"),
        )?;
    }
    let over_time = |f: &dyn Fn(&crate::player::FrameRecord) -> f64| -> Vec<Series> {
        runs.iter()
            .map(|r| Series {
                name: r.policy.name().into(),
                points: r.frames.iter().map(|x| (x.t_s, f(x))).collect(),
            })
            .collect()
    };
    let budget_ms = world.scene.run.budget_s() * 1e3;
    let mut time_series = over_time(&|f| f.frame_ms);
    time_series.push(Series {
        name: "budget".into(),
        points: vec![(0.0, budget_ms), (d, budget_ms)],
    });
    save_line_plot(
        &LinePlot {
            title: "frame time under load spikes".into(),
            x_label: "simulated time (s)".into(),
            y_label: "frame time (ms)".into(),
            series: time_series,
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_time.png"),
    )?;
    save_line_plot(
        &LinePlot {
            title: "scale factor s".into(),
            x_label: "simulated time (s)".into(),
            y_label: "scale factor s".into(),
            series: over_time(&|f| f64::from(f.scale)),
            y_from_zero: true,
            ..Default::default()
        },
        &out.join("framerate_scale.png"),
    )?;
    if !args.common.profiles.quiet {
        eprintln!(
            "wrote {} (framerate.csv/.json, framerate_summary.csv/.json, framerate_time and framerate_scale .png/.svg{})",
            out.display(),
            if equal.is_empty() {
                ""
            } else {
                ", framerate_equal_time.csv/.json and .png/.svg"
            }
        );
    }
    Ok(FramerateOutcome {
        summaries: sums,
        table,
    })
}

/// How a policy held the frame rate.
#[derive(Debug, Clone, PartialEq)]
pub struct HeldRate {
    /// The policy.
    pub policy: Policy,
    /// Its knob ([`PolicyRun::knob`]).
    pub knob: f64,
    /// Share of the frames outside the load spikes over the period.
    pub over_outside_spikes: f64,
    /// Of those, the share after the start-up ([`START_UP_S`]): the frames
    /// over the period once the scheduler has come down to the target.
    pub over_settled: f64,
    /// Share of the frames within the spikes over the period.
    pub over_in_spikes: f64,
    /// Share of the frames within the spikes the scheduler reported out of
    /// reach (cost floor above the period); `None` without a scheduler
    /// that sees the floor.
    pub unreachable_in_spikes: Option<f64>,
    /// Share of the frames within the spikes over the period although the
    /// scheduler found the target reachable; `None` as above.
    pub over_reachable_in_spikes: Option<f64>,
    /// Share of the frames within the spikes over the period with the
    /// knob at its end ([`crate::policy::Choice::at_limit`]): the floor of
    /// what the policy may draw, the load included, ran over the period,
    /// whatever the scheduler estimated.
    pub over_in_spikes_at_limit: f64,
    /// Share of the frames within the spikes over the period with the
    /// knob short of its end, the target not reported out of reach and
    /// the cost floor not above the aim, less each spike's first frame
    /// where the policy is not told of the load (a load nobody announced
    /// shows first in that frame's time): the late frames within spikes
    /// the scheduler could have avoided. A floor between the aim and the
    /// period leaves no LOD choice the headroom for the frames' jitter, as
    /// [`over_settled_with_room`](Self::over_settled_with_room) counts
    /// outside the spikes.
    pub over_in_spikes_with_room: f64,
    /// Of the frames from each spike's third on, the share late as
    /// [`over_in_spikes_with_room`](Self::over_in_spikes_with_room)
    /// counts them: what is left once a blind controller has seen the load
    /// in the spike's first frame and stepped for it in its second. A
    /// spike's frames are counted from its first, the frame after one
    /// outside the spikes.
    pub over_in_spikes_from_third_with_room: f64,
    /// Share of the frames within the spikes whose cost floor lay above
    /// the scheduler's aim (out of reach included): the frames the target
    /// was held in, if at all, only by their jitter; `None` without a
    /// scheduler that sees the floor.
    pub floor_above_aim_in_spikes: Option<f64>,
    /// Share of the frames outside the spikes reported out of reach.
    pub unreachable_outside_spikes: Option<f64>,
    /// Of the frames outside the spikes after the start-up, the share with
    /// the knob at its end ([`crate::policy::Choice::at_limit`]): a
    /// scheduler there no longer holds the rate by its knob, and the LODs
    /// are those of its lowest `s` (for acuity, by the eye model at that
    /// `s` alone, so they follow the objects across the field).
    pub at_limit_settled: f64,
    /// Of the frames outside the spikes after the start-up, the share
    /// whose cost floor lay above the scheduler's aim: no LOD choice
    /// leaves them the headroom; `None` as above.
    pub floor_above_aim_settled: Option<f64>,
    /// Of the same frames, the share over the period although the cost
    /// floor lay below the aim (or was unknown): the late frames a choice
    /// of LODs could have avoided; `None` as above.
    pub over_settled_with_room: Option<f64>,
    /// LOD switches and reversals per second, mean triangles, mean `s`.
    pub switches_per_s: f64,
    /// LOD reversals per second.
    pub reversals_per_s: f64,
    /// Slow LOD reversals per second (within a second, the reversals
    /// included): the flicker a dwell time longer than the reversals'
    /// quarter second slows down but does not remove.
    pub slow_reversals_per_s: f64,
    /// Mean triangles per frame.
    pub triangles: f64,
    /// Mean scale factor.
    pub mean_scale: f64,
    /// FovVideoVDP JOD of the sequence, when scored.
    pub jod: Option<f64>,
}

/// The run's start-up, s of the scene's time: a scheduler begins at full
/// detail (the reactive one) or at its first guess of the cost (the
/// predictive one) and comes down to the target within it (the reactive
/// one in 4-5 frames at 30 Hz, `docs/framerate.md`), so its frames over
/// the period measure the start, not how the rate is held.
pub const START_UP_S: f64 = 0.5;

fn share(
    frames: &[&crate::player::FrameRecord],
    f: impl Fn(&crate::player::FrameRecord) -> bool,
) -> f64 {
    if frames.is_empty() {
        f64::NAN
    } else {
        frames.iter().filter(|x| f(x)).count() as f64 / frames.len() as f64
    }
}

/// Each run's [`HeldRate`] against a frame period of `budget_s`.
pub fn held_rates(runs: &[PolicyRun], sums: &[Summary], budget_s: f64) -> Vec<HeldRate> {
    runs.iter()
        .zip(sums)
        .map(|(r, s)| {
            let over = |f: &crate::player::FrameRecord| f.frame_ms * 1e-3 > budget_s;
            let (inside, outside): (Vec<_>, Vec<_>) = r.frames.iter().partition(|f| f.in_spike);
            let told = r.policy == Policy::AcuityPredictiveAnnounced;
            // Each frame's place in its spike by frame number: 1 for the
            // first, whose frame before was outside the spikes (or not
            // played), 0 outside the spikes.
            let mut by_frame: Vec<_> = r.frames.iter().collect();
            by_frame.sort_by_key(|f| f.frame);
            let mut place_in_spike = std::collections::HashMap::new();
            let mut run_length = 0u32;
            let mut last_frame = None;
            for f in by_frame {
                let follows_spike_frame = last_frame.is_some_and(|n: u32| n + 1 == f.frame);
                run_length = match (f.in_spike, follows_spike_frame) {
                    (false, _) => 0,
                    (true, true) => run_length + 1,
                    (true, false) => 1,
                };
                last_frame = f.in_spike.then_some(f.frame);
                place_in_spike.insert(f.frame, run_length);
            }
            let place = |f: &crate::player::FrameRecord| place_in_spike.get(&f.frame).copied();
            let first_of_spike = |f: &crate::player::FrameRecord| place(f) == Some(1);
            let from_third: Vec<_> = inside
                .iter()
                .copied()
                .filter(|f| place(f).is_some_and(|k| k >= 3))
                .collect();
            let sees_floor = r.frames.iter().any(|f| f.target_unreachable.is_some());
            let unreachable = |f: &crate::player::FrameRecord| f.target_unreachable == Some(true);
            let floor_above_aim = |f: &crate::player::FrameRecord| {
                matches!((f.cost_floor_ms, f.aim_ms), (Some(floor), Some(aim)) if floor > aim)
            };
            let late_with_room = |f: &crate::player::FrameRecord| {
                over(f) && !f.at_limit && !unreachable(f) && !floor_above_aim(f)
            };
            let settled: Vec<_> = outside
                .iter()
                .copied()
                .filter(|f| f.t_s >= START_UP_S)
                .collect();
            HeldRate {
                policy: r.policy,
                knob: r.knob,
                over_outside_spikes: share(&outside, over),
                over_settled: share(&settled, over),
                over_in_spikes: share(&inside, over),
                unreachable_in_spikes: sees_floor.then(|| share(&inside, unreachable)),
                over_reachable_in_spikes: sees_floor
                    .then(|| share(&inside, |f| over(f) && !unreachable(f))),
                over_in_spikes_at_limit: share(&inside, |f| over(f) && f.at_limit),
                over_in_spikes_with_room: share(&inside, |f| {
                    late_with_room(f) && (told || !first_of_spike(f))
                }),
                over_in_spikes_from_third_with_room: share(&from_third, late_with_room),
                floor_above_aim_in_spikes: sees_floor.then(|| share(&inside, floor_above_aim)),
                unreachable_outside_spikes: sees_floor.then(|| share(&outside, unreachable)),
                at_limit_settled: share(&settled, |f| f.at_limit),
                floor_above_aim_settled: sees_floor.then(|| share(&settled, floor_above_aim)),
                over_settled_with_room: sees_floor
                    .then(|| share(&settled, |f| over(f) && !floor_above_aim(f))),
                switches_per_s: s.switches_per_s,
                reversals_per_s: s.reversals_per_s,
                slow_reversals_per_s: s.slow_reversals_per_s,
                triangles: s.triangles,
                mean_scale: s.mean_scale,
                jod: s.jod,
            }
        })
        .collect()
}

fn pct(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{:.1}", 100.0 * v))
}

/// The schedulers' table: over% outside and within the spikes, within them
/// out of reach and over while reachable, the floor above the aim
/// (`in:flr>aim%`), over with the knob at its end (`in:lim%`) and short of
/// it with the floor below the aim (`in:room%`, each spike's first frame
/// not counted for a policy not told of the load; `in:room3%`: the same
/// among each spike's frames from its third on), once
/// settled the floor above the aim, the late frames with room and the
/// frames with the knob at its end (`lim%set`), switches, reversals,
/// triangles, `s` and JOD.
pub fn held_table(rows: &[HeldRate]) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<32} {:>8} {:>8} {:>8} {:>8} {:>9} {:>11} {:>8} {:>8} {:>9} {:>7} {:>8} {:>9} {:>8} {:>6} {:>6} {:>7} {:>10} {:>5} {:>6}",
        "policy",
        "over% out",
        "over% set",
        "over% in",
        "unreach%",
        "over%reach",
        "in:flr>aim%",
        "in:lim%",
        "in:room%",
        "in:room3%",
        "unr%out",
        "flr>aim%",
        "over%room",
        "lim%set",
        "sw/s",
        "rev/s",
        "rev1s/s",
        "tris/frm",
        "s",
        "JOD"
    );
    for r in rows {
        let _ = writeln!(
            t,
            "{:<32} {:>8} {:>8} {:>8} {:>8} {:>9} {:>11} {:>8} {:>8} {:>9} {:>7} {:>8} {:>9} {:>8} {:>6.1} {:>6.1} {:>7.1} {:>10.0} {:>5.2} {:>6}",
            r.policy.label(r.knob),
            pct(Some(r.over_outside_spikes)),
            pct(Some(r.over_settled)),
            pct(Some(r.over_in_spikes)),
            pct(r.unreachable_in_spikes),
            pct(r.over_reachable_in_spikes),
            pct(r.floor_above_aim_in_spikes),
            pct(Some(r.over_in_spikes_at_limit)),
            pct(Some(r.over_in_spikes_with_room)),
            pct(Some(r.over_in_spikes_from_third_with_room)),
            pct(r.unreachable_outside_spikes),
            pct(r.floor_above_aim_settled),
            pct(r.over_settled_with_room),
            pct(Some(r.at_limit_settled)),
            r.switches_per_s,
            r.reversals_per_s,
            r.slow_reversals_per_s,
            r.triangles,
            r.mean_scale,
            r.jod.map_or("-".into(), |j| format!("{j:.3}")),
        );
    }
    t
}

/// The schedulers' table as CSV (shares as fractions).
pub fn held_csv(rows: &[HeldRate]) -> String {
    let mut t = String::from(
        "policy,over_outside_spikes,over_settled,over_in_spikes,unreachable_in_spikes,over_reachable_in_spikes,unreachable_outside_spikes,floor_above_aim_settled,over_settled_with_room,lod_switches_per_s,lod_reversals_per_s,triangles,mean_scale,jod,lod_slow_reversals_per_s,over_in_spikes_at_limit,over_in_spikes_with_room,at_limit_settled,floor_above_aim_in_spikes,over_in_spikes_from_third_with_room\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
    for r in rows {
        let _ = writeln!(
            t,
            "{},{:.4},{:.4},{:.4},{},{},{},{},{},{:.3},{:.3},{:.1},{:.4},{},{:.3},{:.4},{:.4},{:.4},{},{:.4}",
            r.policy.label(r.knob),
            r.over_outside_spikes,
            r.over_settled,
            r.over_in_spikes,
            o(r.unreachable_in_spikes),
            o(r.over_reachable_in_spikes),
            o(r.unreachable_outside_spikes),
            o(r.floor_above_aim_settled),
            o(r.over_settled_with_room),
            r.switches_per_s,
            r.reversals_per_s,
            r.triangles,
            r.mean_scale,
            o(r.jod),
            r.slow_reversals_per_s,
            r.over_in_spikes_at_limit,
            r.over_in_spikes_with_room,
            r.at_limit_settled,
            o(r.floor_above_aim_in_spikes),
            r.over_in_spikes_from_third_with_room,
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::player::FrameRecord;
    use crate::report::summarize;

    fn frame(t_s: f64, frame_ms: f64, in_spike: bool) -> FrameRecord {
        floored(t_s, frame_ms, in_spike, 50.0)
    }

    /// A frame whose scheduler aimed at 90 ms with a cost floor of
    /// `floor_ms`.
    fn floored(t_s: f64, frame_ms: f64, in_spike: bool, floor_ms: f64) -> FrameRecord {
        FrameRecord {
            policy: Policy::AcuityReactive,
            frame: (t_s * 10.0).round() as u32,
            t_s,
            frame_ms,
            select_ms: 0.0,
            triangles: 1000,
            draw_calls: 1,
            drawn: 1,
            mean_lod: 0.0,
            lod_switches: 0,
            lod_reversals: 0,
            lod_slow_reversals: 0,
            scale: 1.0,
            triangle_budget: None,
            target_unreachable: Some(floor_ms > 100.0),
            cost_floor_ms: Some(floor_ms),
            aim_ms: Some(90.0),
            in_spike,
            at_limit: false,
            visibility_deg: None,
            flip_mean: None,
            flip_p95: None,
        }
    }

    /// The schedulers' table row of one run of `frames` at a 100 ms period.
    fn held_at_100_ms(frames: Vec<FrameRecord>) -> HeldRate {
        let runs = [PolicyRun {
            policy: Policy::AcuityReactive,
            knob: 1.0,
            frames,
            worst: None,
        }];
        held_rates(&runs, &summarize(&runs, 0.1), 0.1).remove(0)
    }

    #[test]
    fn frames_over_the_period_in_the_start_up_count_outside_the_spikes_but_not_once_settled() {
        // A 100 ms period: two late frames in the start-up, one after it
        // of eight outside the spikes, and a late frame in a spike.
        let frames = vec![
            frame(0.0, 300.0, false),
            frame(0.1, 150.0, false),
            frame(0.2, 90.0, false),
            frame(0.6, 90.0, false),
            frame(0.7, 120.0, false),
            frame(0.8, 200.0, true),
            frame(0.9, 90.0, false),
            frame(1.0, 90.0, false),
            frame(1.1, 80.0, false),
        ];
        let held = held_at_100_ms(frames);
        assert_eq!(held.over_outside_spikes, 3.0 / 8.0);
        assert_eq!(held.over_settled, 1.0 / 5.0);
        assert_eq!(held.over_in_spikes, 1.0);
        assert_eq!(held.floor_above_aim_settled, Some(0.0));
        assert_eq!(held.over_settled_with_room, Some(1.0 / 5.0));
    }

    #[test]
    fn late_frames_whose_floor_lay_above_the_aim_are_told_apart_from_those_with_room() {
        // A 100 ms period and a 90 ms aim, all settled and outside the
        // spikes: three frames at a floor of 95 ms (above the aim, below
        // the period), two of them late; one late frame at a floor of 40 ms.
        let mut frames = vec![
            floored(1.0, 104.0, false, 95.0),
            floored(1.1, 99.0, false, 95.0),
            floored(1.2, 101.0, false, 95.0),
            floored(1.3, 120.0, false, 40.0),
            floored(1.4, 85.0, false, 40.0),
        ];
        // Two of them with the knob at its end.
        frames[1].at_limit = true;
        frames[4].at_limit = true;
        let held = held_at_100_ms(frames);
        assert_eq!(held.at_limit_settled, 2.0 / 5.0);
        assert_eq!(held.over_settled, 3.0 / 5.0);
        assert_eq!(held.floor_above_aim_settled, Some(3.0 / 5.0));
        assert_eq!(held.over_settled_with_room, Some(1.0 / 5.0));
        assert_eq!(held.unreachable_outside_spikes, Some(0.0));
    }

    #[test]
    fn late_frames_in_a_spike_are_told_apart_by_the_knob_and_the_spike_start() {
        // A 100 ms period and a 90 ms aim; a spike of six frames: its
        // first late with the knob short of its end (a blind controller
        // could not know), the second the same (the controller's own), the
        // third late with the knob at its end (the policy's floor), the
        // fourth late with the target reported out of reach, the fifth late
        // with the floor between the aim and the period (only the jitter
        // could keep it on time), the sixth on time.
        let mut frames = vec![
            frame(0.9, 90.0, false),
            frame(1.0, 150.0, true),
            frame(1.1, 120.0, true),
            frame(1.2, 110.0, true),
            floored(1.3, 130.0, true, 120.0),
            floored(1.4, 103.0, true, 95.0),
            frame(1.5, 95.0, true),
            frame(1.6, 90.0, false),
        ];
        frames[3].at_limit = true;
        let held = held_at_100_ms(frames.clone());
        assert_eq!(held.over_in_spikes, 5.0 / 6.0);
        assert_eq!(held.over_in_spikes_at_limit, 1.0 / 6.0);
        assert_eq!(held.over_in_spikes_with_room, 1.0 / 6.0);
        assert_eq!(held.floor_above_aim_in_spikes, Some(2.0 / 6.0));
        // From the third frame on: the knob at its end, out of reach, the
        // floor above the aim, on time; none late with room.
        assert_eq!(held.over_in_spikes_from_third_with_room, 0.0);
        // Told of the load, the first frame counts too.
        let runs = [PolicyRun {
            policy: Policy::AcuityPredictiveAnnounced,
            knob: 1.0,
            frames,
            worst: None,
        }];
        let told = held_rates(&runs, &summarize(&runs, 0.1), 0.1).remove(0);
        assert_eq!(told.over_in_spikes_with_room, 2.0 / 6.0);
        assert_eq!(told.over_in_spikes_from_third_with_room, 0.0);
    }

    #[test]
    fn late_frames_with_room_are_counted_from_each_spikes_third_frame() {
        // A 100 ms period and a 90 ms aim; two spikes of four frames, each
        // late with room in its first two frames, the first spike in its
        // fourth too, the second in its third; a spike frame after a
        // frame not played starts a spike of its own.
        let frames = vec![
            frame(0.9, 90.0, false),
            frame(1.0, 150.0, true),
            frame(1.1, 120.0, true),
            frame(1.2, 90.0, true),
            frame(1.3, 110.0, true),
            frame(1.4, 90.0, false),
            frame(2.0, 150.0, true),
            frame(2.1, 120.0, true),
            frame(2.2, 130.0, true),
            frame(2.3, 80.0, true),
            frame(2.5, 120.0, true),
            frame(2.6, 120.0, true),
        ];
        let held = held_at_100_ms(frames);
        assert_eq!(held.over_in_spikes_from_third_with_room, 2.0 / 4.0);
        // Each spike's first frame is left out of the blind policy's share.
        assert_eq!(held.over_in_spikes_with_room, 5.0 / 10.0);
    }
}
