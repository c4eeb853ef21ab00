//! `acuity experiment speedup`.
//!
//! N copies of the test object at seeded random positions
//! (`scenes/reddy1998.toml` by default), N in {10, 20, 50, 100, 200, 500,
//! 1000}, several trials each with fresh positions; per trial the camera
//! path is flown with full detail, full acuity and acuity with velocity and
//! eccentricity only. Reported: speedup of full acuity over full detail in
//! mean frame time and in triangles, and the average LOD (1 = finest, as
//! the paper numbers them) of the drawn objects with all criteria versus
//! velocity + eccentricity, from which the size component's share of the
//! reduction is `1 - (lod_ev - 1) / (lod_all - 1)`. Beside the paper's
//! full acuity (each object's detail invisible on its own), the flight is
//! flown with the runtime's just-imperceptible settings at `s = 1`
//! (`acuity_all_pooled`: visibility summed over the image up to the
//! calibrated budget), the `s = 1` a user of the runtime ships.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::frames::{ProfileArgs, World};
use crate::placement::PlacementSpec;
use crate::player::{PlaySettings, Player};
use crate::plot::{LinePlot, Series, save_line_plot};
use crate::report::summarize;
use crate::scene::{Policy, Scene};

/// The paper's object counts.
pub const PAPER_COUNTS: [u32; 7] = [10, 20, 50, 100, 200, 500, 1000];

/// Arguments of `acuity experiment speedup`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SpeedupArgs {
    /// Scene with one object placed by `copies` (its count and seed are
    /// replaced per N and trial).
    #[cfg_attr(feature = "clap", arg(long, default_value = "scenes/reddy1998.toml"))]
    pub scene: PathBuf,
    /// Object counts, comma-separated.
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ',', default_values_t = PAPER_COUNTS.to_vec()))]
    pub counts: Vec<u32>,
    /// Trials per count (seeds `seed + trial`), at least 1.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 3))]
    pub trials: u32,
    /// Frames per flight, spread over the scene's path.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 25, value_parser = clap::value_parser!(u32).range(1..=crate::scene::MAX_FRAMES as i64)))]
    pub frames: u32,
    /// Override the resolution, WIDTHxHEIGHT pixels (field of view kept);
    /// the paper's 1280x1024 is slow on a software rasteriser.
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_resolution))]
    pub resolution: Option<[u32; 2]>,
    /// Output folder (default `out/experiment-speedup/`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: Option<PathBuf>,
    /// Write every played frame, per N and trial, to
    /// `DIR/nNNNN_trialT/<policy>_<knob>/NNNN.png` (e.g.
    /// `n0100_trial0/acuity_all_1/0007.png`; RGB, as rendered; knob as in
    /// `acuity run`'s dump, full detail `full_1`), each policy folder with
    /// gaze.csv (frame,x_px,y_px: the viewer's fixation in pixels, origin
    /// top-left, y down: the gaze, or `[gaze] viewer_object`'s centre),
    /// each trial folder with display.json (resolution, fov_deg,
    /// fps, photometry, sequences).
    #[cfg_attr(feature = "clap", arg(long, value_name = "DIR"))]
    pub dump_frames: Option<PathBuf>,
    /// Profiles and progress.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub profiles: ProfileArgs,
}

/// One trial of the speedup experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedupTrial {
    /// Number of objects.
    pub count: u32,
    /// Seed of the placements.
    pub seed: u64,
    /// Mean frame time with full detail, ms.
    pub full_ms: f64,
    /// Mean frame time with full acuity, ms.
    pub acuity_ms: f64,
    /// Mean triangles per frame, full detail.
    pub full_triangles: f64,
    /// Mean triangles per frame, full acuity.
    pub acuity_triangles: f64,
    /// Mean frame time with the just-imperceptible settings, ms.
    pub imperceptible_ms: f64,
    /// Mean triangles per frame with the just-imperceptible settings.
    pub imperceptible_triangles: f64,
    /// Average LOD (1 = finest) of drawn objects, all criteria.
    pub lod_all: f64,
    /// Average LOD (1 = finest) of drawn objects, velocity + eccentricity.
    pub lod_ecc_vel: f64,
}

impl SpeedupTrial {
    /// Full detail's mean frame time over full acuity's.
    pub fn speedup_time(&self) -> f64 {
        self.full_ms / self.acuity_ms
    }

    /// Full detail's mean triangles over full acuity's.
    pub fn speedup_triangles(&self) -> f64 {
        self.full_triangles / self.acuity_triangles
    }

    /// Full detail's mean frame time over the just-imperceptible
    /// settings'.
    pub fn speedup_time_imperceptible(&self) -> f64 {
        self.full_ms / self.imperceptible_ms
    }

    /// Full detail's mean triangles over the just-imperceptible settings'.
    pub fn speedup_triangles_imperceptible(&self) -> f64 {
        self.full_triangles / self.imperceptible_triangles
    }
}

/// The share of the LOD reduction (average LOD above 1) that velocity and
/// eccentricity alone do not achieve, i.e. size's share; NaN when all
/// criteria together lower the average LOD by less than 0.01.
pub fn size_share(lod_all: f64, lod_ecc_vel: f64) -> f64 {
    let all = lod_all - 1.0;
    // Below a hundredth of a level the share is noise.
    if all >= 0.01 {
        1.0 - (lod_ecc_vel - 1.0) / all
    } else {
        f64::NAN
    }
}

/// What [`speedup`] measured.
#[derive(Debug, Clone)]
pub struct SpeedupOutcome {
    /// Every trial: one count, one seed.
    pub trials: Vec<SpeedupTrial>,
    /// The table `acuity experiment speedup` prints: means per count.
    pub table: String,
}

/// Runs the speedup experiment and writes `speedup.csv`, `speedup.png` and
/// `average_lod.png`; returns the trials.
pub fn speedup(args: &SpeedupArgs) -> anyhow::Result<SpeedupOutcome> {
    if args.trials == 0 || args.frames == 0 || args.counts.is_empty() {
        crate::bail_input!("--trials, --frames and --counts need at least 1");
    }
    if let Some(&c) = args
        .counts
        .iter()
        .find(|&&c| c == 0 || c > crate::scene::MAX_COPIES)
    {
        crate::bail_input!(
            "object count {c} is outside 1..={}",
            crate::scene::MAX_COPIES
        );
    }
    let mut scene = Scene::load(&args.scene)?;
    if scene.objects.len() != 1 || !matches!(scene.objects[0].placement, PlacementSpec::Copies(_)) {
        crate::bail_input!(
            "{}: the speedup experiment needs exactly one object placed by `copies`",
            scene.source_path.display()
        );
    }
    if let Some(r) = args.resolution {
        scene.display.resolution_px = r;
    }
    scene.run.flip_every_n_frames = 0;
    let base_seed = match scene.objects[0].placement {
        PlacementSpec::Copies(c) => c.seed,
        PlacementSpec::Transform(_) => 0,
    };
    let mut world = World::load(scene.clone(), &args.profiles.load_options(&scene.profiles))?;
    let mut settings = PlaySettings::from_scene(&scene, Some(args.frames))?;
    settings.flip_every_n_frames = 0;
    settings.keep_images = false;
    settings.policies = vec![
        Policy::Full,
        Policy::AcuityAll,
        Policy::AcuityEccVel,
        Policy::AcuityAllPooled,
    ];
    let mut trials = Vec::new();
    let bar = crate::progress::bar(
        (args.counts.len() as u64)
            * u64::from(args.trials)
            * u64::from(args.frames)
            * settings.policies.len() as u64,
        "frames",
        args.profiles.quiet,
    );
    for &count in &args.counts {
        for trial in 0..args.trials {
            let seed = base_seed.wrapping_add(u64::from(trial));
            let mut s = scene.clone();
            if let PlacementSpec::Copies(c) = &mut s.objects[0].placement {
                c.count = count;
                c.seed = seed;
            }
            world.replace_placements(s)?;
            let mut settings = settings.clone();
            settings.dump_dir = args
                .dump_frames
                .as_ref()
                .map(|d| d.join(format!("n{count:04}_trial{trial}")));
            let mut player = Player::new(&world, settings.clone())?;
            player.set_progress(&bar);
            let runs = player.play_all(&settings.policies, world.scene.run.screen_size_bias)?;
            let sums = summarize(&runs, world.scene.run.budget_s());
            let of = |policy: Policy| {
                sums.iter()
                    .find(|s| s.policy == policy)
                    .ok_or_else(|| anyhow::anyhow!("no run of {}", policy.name()))
            };
            let (full, all, ecc_vel, imperceptible) = (
                of(Policy::Full)?,
                of(Policy::AcuityAll)?,
                of(Policy::AcuityEccVel)?,
                of(Policy::AcuityAllPooled)?,
            );
            let t = SpeedupTrial {
                count,
                seed,
                full_ms: full.mean_ms,
                acuity_ms: all.mean_ms,
                full_triangles: full.triangles,
                acuity_triangles: all.triangles,
                lod_all: all.mean_lod + 1.0,
                lod_ecc_vel: ecc_vel.mean_lod + 1.0,
                imperceptible_ms: imperceptible.mean_ms,
                imperceptible_triangles: imperceptible.triangles,
            };
            if !args.profiles.quiet {
                bar.suspend(|| {
                    eprintln!(
                        "N={count:<5} seed={seed:<6} speedup {:.2}x time, {:.2}x triangles; LOD all {:.2}, ecc+vel {:.2}; just imperceptible {:.2}x time, {:.2}x triangles",
                        t.speedup_time(),
                        t.speedup_triangles(),
                        t.lod_all,
                        t.lod_ecc_vel,
                        t.speedup_time_imperceptible(),
                        t.speedup_triangles_imperceptible()
                    )
                });
            }
            trials.push(t);
        }
    }
    bar.finish_and_clear();
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("experiment-speedup"));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut csv = String::from(
        "count,seed,full_ms,acuity_ms,speedup_time,full_triangles,acuity_triangles,speedup_triangles,lod_all,lod_ecc_vel,size_share,imperceptible_ms,speedup_time_imperceptible,imperceptible_triangles,speedup_triangles_imperceptible\n",
    );
    for t in &trials {
        let _ = writeln!(
            csv,
            "{},{},{:.4},{:.4},{:.4},{:.1},{:.1},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.1},{:.4}",
            t.count,
            t.seed,
            t.full_ms,
            t.acuity_ms,
            t.speedup_time(),
            t.full_triangles,
            t.acuity_triangles,
            t.speedup_triangles(),
            t.lod_all,
            t.lod_ecc_vel,
            size_share(t.lod_all, t.lod_ecc_vel),
            t.imperceptible_ms,
            t.speedup_time_imperceptible(),
            t.imperceptible_triangles,
            t.speedup_triangles_imperceptible()
        );
    }
    let csv_path = out.join("speedup.csv");
    crate::report::write_csv_with_json(&csv, &csv_path)?;
    // Means per count.
    let per_count = |f: &dyn Fn(&SpeedupTrial) -> f64| -> Vec<(f64, f64)> {
        args.counts
            .iter()
            .map(|&c| {
                let v: Vec<f64> = trials.iter().filter(|t| t.count == c).map(f).collect();
                (f64::from(c), v.iter().sum::<f64>() / v.len().max(1) as f64)
            })
            .collect()
    };
    let time = per_count(&|t| t.speedup_time());
    let triangles = per_count(&|t| t.speedup_triangles());
    let lod_all = per_count(&|t| t.lod_all);
    let lod_ecc_vel = per_count(&|t| t.lod_ecc_vel);
    let time_imperceptible = per_count(&|t| t.speedup_time_imperceptible());
    let triangles_imperceptible = per_count(&|t| t.speedup_triangles_imperceptible());
    let mut table = String::new();
    let _ = writeln!(
        table,
        "{:>6} {:>14} {:>14} {:>9} {:>9} {:>10} {:>14} {:>14}",
        "N",
        "speedup time",
        "speedup tris",
        "LOD all",
        "LOD e+v",
        "size share",
        "imperc. time",
        "imperc. tris"
    );
    for i in 0..args.counts.len() {
        let share = size_share(lod_all[i].1, lod_ecc_vel[i].1);
        let share = if share.is_nan() {
            "none".to_string()
        } else {
            format!("{:.0}%", 100.0 * share)
        };
        let _ = writeln!(
            table,
            "{:>6} {:>13.2}x {:>13.2}x {:>9.2} {:>9.2} {:>10} {:>13.2}x {:>13.2}x",
            args.counts[i],
            time[i].1,
            triangles[i].1,
            lod_all[i].1,
            lod_ecc_vel[i].1,
            share,
            time_imperceptible[i].1,
            triangles_imperceptible[i].1
        );
    }
    let _ = writeln!(
        table,
        "\nspeedup: full acuity (each object's detail invisible on its own) over full detail;\n\
         imperc.: the runtime's just-imperceptible settings at s = 1 over full detail"
    );
    save_line_plot(
        &LinePlot {
            title: "speedup over full detail at s = 1".into(),
            x_label: "objects N (log)".into(),
            y_label: "speedup (x)".into(),
            series: vec![
                Series {
                    name: "full acuity, frame time".into(),
                    points: time,
                },
                Series {
                    name: "full acuity, triangles".into(),
                    points: triangles,
                },
                Series {
                    name: "just imperceptible, frame time".into(),
                    points: time_imperceptible,
                },
                Series {
                    name: "just imperceptible, triangles".into(),
                    points: triangles_imperceptible,
                },
            ],
            log_x: true,
            markers: true,
            y_from_zero: true,
        },
        &out.join("speedup.png"),
    )?;
    save_line_plot(
        &LinePlot {
            title: "average LOD (1 = finest)".into(),
            x_label: "objects N (log)".into(),
            y_label: "LOD".into(),
            series: vec![
                Series {
                    name: "all criteria".into(),
                    points: lod_all,
                },
                Series {
                    name: "velocity + eccentricity".into(),
                    points: lod_ecc_vel,
                },
            ],
            log_x: true,
            markers: true,
            y_from_zero: true,
        },
        &out.join("average_lod.png"),
    )?;
    if !args.profiles.quiet {
        eprintln!(
            "wrote {} (speedup.csv, speedup.json, speedup and average_lod .png/.svg)",
            out.display()
        );
    }
    Ok(SpeedupOutcome { trials, table })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_share_is_the_part_ecc_vel_misses() {
        assert!((size_share(3.0, 1.1) - 0.95).abs() < 1e-12);
        assert_eq!(size_share(2.0, 1.0), 1.0);
        assert!(size_share(1.0, 1.0).is_nan());
    }
}
