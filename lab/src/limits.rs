//! What scene files and the command line accept: every count, size and rate
//! that sets how much memory or time a command takes is bounded here, and
//! a value beyond its limit is refused with an error that names the field
//! (or flag) and the limit.
//!
//! | what | limit | where it enters |
//! |---|---|---|
//! | frames of a run | 1 to [`MAX_FRAMES`] (10,000,000) | `run.frames`, derived from `run.dt_s` or `run.target_hz`, `--frames` |
//! | display side | 1 to [`MAX_RESOLUTION_PX`] (16,384) pixels | `display.resolution`, `--resolution` |
//! | copies of an object | 1 to [`MAX_COPIES`] (1,000,000) | `copies.count` |
//! | triangles of a procedural LOD | 1 to [`MAX_PROCEDURAL_TRIANGLES`] (10,000,000) | `procedural.triangles` |
//! | triangles at full detail, all instances | [`MAX_SCENE_TRIANGLES`] (1,000,000,000) | LOD 0 x copies, summed over objects |
//! | target frame rate | [`MIN_TARGET_HZ`] (1) to [`MAX_TARGET_HZ`] (10,000) Hz | `run.target_hz`, `--target-hz` |
//! | simulated time step | [`MIN_DT_S`] (0.1 ms) to [`MAX_DT_S`] (1 s) | `run.dt_s` |
//! | load spikes | 0 to [`MAX_SPIKE_LOAD`] (10) frame budgets | `--spike-load` |
//! | scale factor `s` | (0, 1]; below [`MIN_SCALE`] (`f32`'s smallest normal, 1.2e-38) it selects as `MIN_SCALE`: the coarsest LODs | `run.scale_factor`, `--scales` |
//! | the schedulers' lowest `s` | [`MIN_FLOOR_SCALE`](crate::scene::MIN_FLOOR_SCALE) (1e-6) to 1 | `run.min_scale`, `--min-scale` |
//!
//! Before a run or an experiment plays its frames, the memory it will keep
//! (each frame's record per policy, the full-detail images FLIP compares
//! against, the kept worst frames: [`play_memory_bytes`]) is estimated and
//! the work refused when it exceeds the memory available; likewise the
//! procedural LODs, before any is tessellated ([`check_generated_meshes`]).
//!
//! The full-detail triangle count is estimated from the scene file (the
//! first target of `procedural` and `generate_triangles` LODs) when it is
//! read, and checked again with the loaded meshes before anything is
//! analysed or drawn.

use acuity::format_number as number;
use acuity::schedule;

pub use acuity::schedule::{MAX_TARGET_HZ, MIN_TARGET_HZ};

/// Most frames of a run (a frame's records are kept for every policy).
pub const MAX_FRAMES: u64 = 10_000_000;
/// Largest display side, pixels.
pub const MAX_RESOLUTION_PX: u32 = 16_384;
/// Most copies of one object.
pub const MAX_COPIES: u32 = 1_000_000;
/// Most triangles of one LOD of a procedural object (it is tessellated in
/// memory, about 40 bytes a triangle).
pub const MAX_PROCEDURAL_TRIANGLES: u32 = 10_000_000;
/// Most triangles of a scene at full detail: LOD 0's triangles times the
/// object's instances, summed over its objects (each frame may draw them).
pub const MAX_SCENE_TRIANGLES: u64 = 1_000_000_000;
/// Shortest simulated time between frames, seconds (`1 / MAX_TARGET_HZ`).
pub const MIN_DT_S: f64 = 1e-4;
/// Longest simulated time between frames given as `dt_s`, seconds
/// (`1 / MIN_TARGET_HZ`).
pub const MAX_DT_S: f64 = 1.0;
/// Largest extra load of `experiment framerate`'s spikes, in frame budgets.
pub const MAX_SPIKE_LOAD: f64 = 10.0;
/// Smallest scale factor `s` selected with; a smaller positive `s` selects
/// as this one.
pub const MIN_SCALE: f32 = f32::MIN_POSITIVE;

/// Checks a target frame rate, Hz ([`MIN_TARGET_HZ`]..=[`MAX_TARGET_HZ`]);
/// the reason says the limits.
pub fn check_target_hz(hz: f64) -> Result<(), String> {
    match schedule::check_target_hz("target_hz", hz) {
        Ok(()) => Ok(()),
        Err(acuity::Error::InvalidParameter { reason, .. }) => Err(reason),
        Err(e) => Err(e.to_string()),
    }
}

/// Checks a simulated time between frames, seconds
/// ([`MIN_DT_S`]..=[`MAX_DT_S`]).
pub fn check_dt_s(dt_s: f64) -> Result<(), String> {
    if (MIN_DT_S..=MAX_DT_S).contains(&dt_s) {
        Ok(())
    } else {
        Err(format!(
            "{} s is outside {MIN_DT_S}..={MAX_DT_S} s",
            number(dt_s)
        ))
    }
}

/// Checks a load-spike size, in frame budgets (0..=[`MAX_SPIKE_LOAD`]).
pub fn check_spike_load(load: f64) -> Result<(), String> {
    if (0.0..=MAX_SPIKE_LOAD).contains(&load) {
        Ok(())
    } else {
        Err(format!(
            "{} frame budgets is outside 0..={MAX_SPIKE_LOAD}",
            number(load)
        ))
    }
}

/// Checks the triangles of a scene at full detail against
/// [`MAX_SCENE_TRIANGLES`]: `objects` gives each object's name, LOD 0
/// triangles and instance count. The error gives the position of the
/// object that crosses the limit and a reason that names it.
pub fn check_scene_triangles<'a>(
    objects: impl IntoIterator<Item = (&'a str, u64, u64)>,
) -> Result<(), (usize, String)> {
    let mut total = 0u64;
    for (i, (name, triangles, instances)) in objects.into_iter().enumerate() {
        total = total.saturating_add(triangles.saturating_mul(instances));
        if total > MAX_SCENE_TRIANGLES {
            return Err((
                i,
                format!(
                    "with object `{name}` ({triangles} triangles x {instances} instances) the \
                     scene has {total} triangles at full detail, more than {MAX_SCENE_TRIANGLES}"
                ),
            ));
        }
    }
    Ok(())
}

/// What a play of `frames` frames under `configs` policy configurations
/// at `width` x `height` pixels keeps in memory, bytes: every frame's
/// record per configuration (`record_bytes` each), the full-detail
/// reference image of every `flip_every`-th frame (none for 0), and with
/// `keep_images` each configuration's worst frame and its FLIP map.
/// Saturates instead of overflowing.
pub fn play_memory_bytes(
    frames: u64,
    configs: u64,
    record_bytes: u64,
    [width, height]: [u32; 2],
    flip_every: u32,
    keep_images: bool,
) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    let records = frames.saturating_mul(configs).saturating_mul(record_bytes);
    let references = match flip_every {
        0 => 0,
        n => frames.div_ceil(u64::from(n)).saturating_mul(pixels * 4),
    };
    let worst = if keep_images {
        configs.saturating_mul(pixels * 7)
    } else {
        0
    };
    records.saturating_add(references).saturating_add(worst)
}

/// Memory a tessellated triangle takes while LODs are made, bytes: a vertex
/// position, normal and colour per corner and three indices, with the
/// simplifier's working copies.
pub const MESH_BYTES_PER_TRIANGLE: u64 = 120;

/// Refuses objects whose generated LODs (procedural shapes, tessellated in
/// memory at every triangle target) would not fit in the memory available:
/// [`MESH_BYTES_PER_TRIANGLE`] times the targets' sum over every procedural
/// object. LODs read from files or simplified from one are bounded by
/// their files.
pub fn check_generated_meshes<'a>(
    sources: impl IntoIterator<Item = &'a acuity_preprocess::ObjectSource>,
) -> Result<(), String> {
    use acuity_preprocess::ObjectSource;
    let triangles: u64 = sources
        .into_iter()
        .map(|s| match s {
            ObjectSource::Procedural {
                triangle_targets, ..
            }
            | ObjectSource::Shape {
                triangle_targets, ..
            } => triangle_targets.iter().map(|&t| u64::from(t)).sum(),
            _ => 0,
        })
        .sum();
    check_memory(
        triangles.saturating_mul(MESH_BYTES_PER_TRIANGLE),
        &format!("tessellating {triangles} procedural triangles"),
    )
}

/// Refuses work that needs more than the memory the system has available
/// now (`MemAvailable` of `/proc/meminfo`; where that cannot be read,
/// nothing is refused). `what` describes the work in the message.
pub fn check_memory(needed_bytes: u64, what: &str) -> Result<(), String> {
    match available_memory_bytes() {
        Some(available) if needed_bytes > available => Err(format!(
            "{what} needs about {} MiB, more than the {} MiB available",
            needed_bytes >> 20,
            available >> 20
        )),
        _ => Ok(()),
    }
}

fn available_memory_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// Parses a target frame rate flag, Hz (see [`check_target_hz`]).
pub fn parse_target_hz(text: &str) -> Result<f64, String> {
    let hz: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    check_target_hz(hz).map(|()| hz)
}

/// Parses a load-spike flag, frame budgets (see [`check_spike_load`]).
pub fn parse_spike_load(text: &str) -> Result<f64, String> {
    let load: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    check_spike_load(load).map(|()| load)
}

/// Parses `NAME=BIAS`, one object's own screen-size bias (finite, > 0).
pub fn parse_object_bias(text: &str) -> Result<(String, f64), String> {
    let (name, bias) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not NAME=BIAS"))?;
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("`{text}` names no object"));
    }
    let bias: f64 = bias
        .trim()
        .parse()
        .map_err(|_| format!("`{bias}` is not a number"))?;
    check_object_bias(bias).map(|()| (name.to_owned(), bias))
}

/// Checks one object's own screen-size bias (a factor on the run's):
/// finite and > 0.
pub fn check_object_bias(bias: f64) -> Result<(), String> {
    if bias.is_finite() && bias > 0.0 {
        Ok(())
    } else {
        Err(format!("{bias} must be finite and > 0"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_beyond_their_limits_are_refused_with_the_limit() {
        for t in [
            "1e-300", "1e-40", "0", "0.5", "20000", "inf", "nan", "-1", "x",
        ] {
            let e = parse_target_hz(t).unwrap_err();
            assert!(
                e.contains("10000") || e.contains("not a number"),
                "{t}: {e}"
            );
        }
        assert_eq!(parse_target_hz("90"), Ok(90.0));
        let e = parse_target_hz("1e-300").unwrap_err();
        assert!(e.starts_with("1e-300 Hz") && e.len() < 60, "{e}");
        for t in ["1e6", "10.5", "-0.1", "nan", "inf"] {
            let e = parse_spike_load(t).unwrap_err();
            assert!(e.contains("0..=10"), "{t}: {e}");
        }
        assert_eq!(parse_spike_load("0.5"), Ok(0.5));
        assert_eq!(
            parse_object_bias(" fine_rock = 0.35"),
            Ok(("fine_rock".to_owned(), 0.35))
        );
        for t in ["fine_rock", "=0.5", "a=0", "a=-1", "a=inf", "a=x"] {
            assert!(parse_object_bias(t).is_err(), "{t}");
        }
        assert!(check_dt_s(1e-300).is_err() && check_dt_s(1e300).is_err());
        assert!(check_dt_s(f64::NAN).is_err() && check_dt_s(0.05).is_ok());
    }

    #[test]
    fn play_memory_counts_records_references_and_kept_frames() {
        let px = 640 * 480;
        assert_eq!(play_memory_bytes(100, 3, 10, [640, 480], 0, false), 3000);
        assert_eq!(
            play_memory_bytes(100, 3, 10, [640, 480], 10, true),
            3000 + 10 * px * 4 + 3 * px * 7
        );
        let huge = play_memory_bytes(u64::MAX, 9, 128, [16384, 16384], 1, true);
        assert_eq!(huge, u64::MAX);
        if cfg!(target_os = "linux") {
            let e = check_memory(u64::MAX, "this run").unwrap_err();
            assert!(
                e.starts_with("this run needs about") && e.contains("MiB available"),
                "{e}"
            );
        }
        assert!(check_memory(1, "a small run").is_ok());
    }

    #[test]
    fn generated_meshes_beyond_memory_are_refused() {
        use acuity_preprocess::ObjectSource;
        use acuity_preprocess::shapes::Shape;
        let object = |targets: Vec<u32>| ObjectSource::Shape {
            name: "ball".into(),
            shape: Shape::Sphere,
            triangle_targets: targets,
        };
        assert!(check_generated_meshes(&[object(vec![320, 80])]).is_ok());
        // 2,000 objects of 10M + 5M triangles: 3.6 TB.
        let huge: Vec<_> = (0..2000)
            .map(|_| object(vec![10_000_000, 5_000_000]))
            .collect();
        if cfg!(target_os = "linux") {
            let e = check_generated_meshes(&huge).unwrap_err();
            assert!(
                e.starts_with("tessellating 30000000000 procedural triangles needs about"),
                "{e}"
            );
        }
    }

    #[test]
    fn scene_triangles_saturate_and_name_the_object() {
        assert!(check_scene_triangles([("a", 4000, 1000), ("b", 100, 1)]).is_ok());
        let (i, e) =
            check_scene_triangles([("a", 4000, 1), ("rock", u64::MAX, u64::MAX)]).unwrap_err();
        assert_eq!(i, 1);
        assert!(e.contains("`rock`") && e.contains("1000000000"), "{e}");
    }
}
