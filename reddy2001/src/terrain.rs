//! `acuity terrain`: Reddy 2001's Table 1 on acuity's view-dependent
//! terrain ([`acuity::terrain`]): the recorded flight over the procedural
//! valley ([`crate::flight`]) refined under six combinations of criteria,
//! with the average triangles and refinement time per frame beside the
//! paper's numbers, as a printed table, CSV and bar plots.
//!
//! Measured: the refinement (the quadtree walk and the crack-free
//! triangulation, on one core) every frame; with `--render-every N`, also
//! every N-th frame drawn with the project's renderer
//! ([`crate::terrain_render`]): the GPU-synchronised draw time, and FLIP
//! against the full-resolution row's image of the same frame. The
//! paper's frame times (SGI O2, 1999) are given for reference only.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use acuity::terrain::{Refinement, Terrain, TerrainSettings, TerrainView};
use acuity::{Components, EccentricityModel, VelocityModel};
use anyhow::Context;

use crate::flight::{Flight, Pose, ValleySettings, poses_csv};
use crate::heightfield_file::HeightfieldFormat;
use crate::terrain_render::TerrainRenderer;
use acuity_lab::barplot::{BarPlot, save_bar_plot};

/// Arguments of `acuity terrain`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct TerrainArgs {
    /// Output folder.
    #[cfg_attr(feature = "clap", arg(long, default_value = "out/terrain"))]
    pub out: PathBuf,
    /// Field of view, HORIZxVERT deg (Reddy: 200x135), as azimuth and
    /// elevation about the view direction.
    #[cfg_attr(feature = "clap", arg(long, default_value = "200x135", value_parser = acuity_lab::parse::parse_angles))]
    pub fov: [f32; 2],
    /// Display resolution, WIDTHxHEIGHT px: with the field of view it sets
    /// the display limit xi = max(w / (2 h_fov), h / (2 v_fov)).
    #[cfg_attr(feature = "clap", arg(long, default_value = "1280x1024", value_parser = acuity_lab::parse::parse_resolution))]
    pub resolution: [u32; 2],
    /// Heightfield samples, WIDTHxHEIGHT (Reddy's Yosemite model: 661x847).
    #[cfg_attr(feature = "clap", arg(long, default_value = "661x847", value_parser = acuity_lab::parse::parse_resolution))]
    pub size: [u32; 2],
    /// A heightfield file instead of the procedural valley, the first row
    /// north, one sample per pixel or value: a PNG (grey, 8 or 16 bits;
    /// colour is taken as its luminance; black is 0 m, white
    /// --height-range-m) or, named `.f32` or `.raw`, a raw grid of
    /// little-endian f32 heights in metres, row-major, with its size in
    /// --grid. The flight takes the same line as over the valley (up the
    /// middle).
    #[cfg_attr(feature = "clap", arg(long))]
    pub heightfield: Option<PathBuf>,
    /// Size of a raw f32 --heightfield, COLUMNSxROWS (each 2 to 65537;
    /// the file must hold COLUMNS x ROWS x 4 bytes).
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::heightfield_file::parse_grid))]
    pub grid: Option<[u32; 2]>,
    /// Metres between the samples of --heightfield.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 30.0))]
    pub spacing_m: f32,
    /// Height of white in --heightfield, m.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 2000.0))]
    pub height_range_m: f32,
    /// Seed of the procedural terrain.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 2001))]
    pub seed: u64,
    /// Frames per second of the flight (the path is the same at any rate).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=240)))]
    pub fps: u32,
    /// Duration of the flight, s (0.1 to 600).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 20.0))]
    pub duration: f32,
    /// Window over which retinal velocity is measured, s: the angle a
    /// node's direction turned since the camera that long ago (averaging
    /// over several frames, as Reddy smoothed it).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 0.1))]
    pub velocity_window: f32,
    /// Global scale factor s in (0, 1].
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 1.0))]
    pub scale: f32,
    /// Draw every N-th frame of each row with the renderer at the display
    /// resolution (0: draw nothing; drawing needs a GPU or a software
    /// adapter such as llvmpipe).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 30))]
    pub render_every: u32,
    /// How acuity falls with eccentricity (the paper's `reddy2001` by
    /// default here, or `cortical_magnification`).
    #[cfg_attr(feature = "clap", arg(long, default_value = "reddy2001"))]
    pub eccentricity_model: EccentricityModel,
    /// How acuity falls with velocity (`reddy2001` by default here, or
    /// `kelly1979`).
    #[cfg_attr(feature = "clap", arg(long, default_value = "reddy2001"))]
    pub velocity_model: VelocityModel,
    /// Print no progress bar on stderr (the table and warnings still print).
    #[cfg_attr(feature = "clap", arg(long))]
    pub quiet: bool,
}

/// One row of Table 1: its criteria and the paper's results.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    /// Short name (CSV, plots).
    pub name: &'static str,
    /// Size, peripheral (eccentricity) and velocity.
    pub components: Components,
    /// Viewport culling.
    pub viewport_cull: bool,
    /// The paper's average triangles per frame.
    pub paper_triangles: u32,
    /// The paper's average frame time, ms.
    pub paper_frame_ms: f32,
}

const fn row(name: &'static str, c: [bool; 4], tris: u32, ms: f32) -> Row {
    Row {
        name,
        components: Components {
            size: c[0],
            eccentricity: c[1],
            velocity: c[2],
        },
        viewport_cull: c[3],
        paper_triangles: tris,
        paper_frame_ms: ms,
    }
}

/// Table 1's six rows (size, peripheral, velocity, viewport cull).
pub const ROWS: [Row; 6] = [
    row("none", [false, false, false, false], 1_116_720, 7127.0),
    row("cull", [false, false, false, true], 449_828, 2517.0),
    row("size", [true, false, false, true], 59_980, 920.0),
    row("size+periph", [true, true, false, true], 40_684, 650.0),
    row("size+velocity", [true, false, true, true], 60_850, 953.0),
    row("all", [true, true, true, true], 8_964, 161.0),
];

/// The result of one row over the flight.
#[derive(Clone, Debug)]
pub struct RowResult {
    /// The row.
    pub row: Row,
    /// Triangles per frame.
    pub triangles: Vec<usize>,
    /// Refinement time per frame, ms.
    pub refine_ms: Vec<f64>,
    /// Draw time of each drawn frame, ms (GPU-synchronised).
    pub draw_ms: Vec<f64>,
    /// Mean FLIP error of each drawn frame against the first row's.
    pub flip: Vec<f64>,
}

impl RowResult {
    /// Mean triangles per frame.
    pub fn mean_triangles(&self) -> f64 {
        mean(self.triangles.iter().map(|&t| t as f64))
    }

    /// Mean refinement time per frame, ms.
    pub fn mean_refine_ms(&self) -> f64 {
        mean(self.refine_ms.iter().copied())
    }
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// Runs `acuity terrain`: flies the recorded flight under each
/// combination of perceptual criteria, prints the table and writes the
/// outputs.
pub fn run(args: &TerrainArgs) -> anyhow::Result<()> {
    if !(0.1..=600.0).contains(&args.duration) {
        acuity_lab::bail_input!("--duration {} s is outside [0.1, 600]", args.duration);
    }
    if !(args.velocity_window > 0.0 && args.velocity_window <= 10.0) {
        acuity_lab::bail_input!(
            "--velocity-window {} s is outside (0, 10]",
            args.velocity_window
        );
    }
    let start = Instant::now();
    let (valley, field) = match &args.heightfield {
        Some(path) => {
            let format = HeightfieldFormat {
                spacing_m: args.spacing_m,
                height_range_m: args.height_range_m,
                grid: args.grid,
            };
            let field = crate::heightfield_file::load(path, &format)?;
            let valley = ValleySettings {
                size: field.size(),
                spacing_m: args.spacing_m,
                ..Default::default()
            };
            (valley, field)
        }
        None => {
            if let Some([w, h]) = args.grid {
                anyhow::bail!(
                    "--grid {w}x{h} is the size of a raw --heightfield, and none is given"
                );
            }
            let valley = ValleySettings {
                size: args.size.map(|n| n as usize),
                seed: args.seed,
                ..Default::default()
            };
            let field = valley.heightfield().context("the procedural terrain")?;
            (valley, field)
        }
    };
    let full = field.full_triangles();
    let terrain = Terrain::new(field);
    println!(
        "terrain: {}x{} samples, {full} triangles at full resolution, quadtree of {} levels built in {:.0} ms",
        valley.size[0],
        valley.size[1],
        terrain.depth(),
        start.elapsed().as_secs_f64() * 1e3
    );
    let flight = Flight {
        duration_s: args.duration,
        ..Default::default()
    };
    let frames = (flight.duration_s * args.fps as f32).round().max(1.0) as usize;
    let pose = |t: f32| flight.pose(t, &valley, terrain.heightfield());
    let poses: Vec<Pose> = (0..frames)
        .map(|i| pose(i as f32 / args.fps as f32))
        .collect();
    let mut views = Vec::with_capacity(frames);
    for p in &poses {
        views.push(TerrainView {
            camera: p.camera()?,
            previous: Some(pose(p.t_s - args.velocity_window).camera()?),
            dt_s: args.velocity_window,
        });
    }
    println!(
        "flight: {frames} frames over {:.1} s, view turning at {:.1} deg/s on average",
        flight.duration_s,
        Flight::mean_angular_speed_deg_per_s(&poses)
    );
    let [w, h] = args.resolution;
    let xi = (w as f32 / (2.0 * args.fov[0])).max(h as f32 / (2.0 * args.fov[1]));
    println!(
        "display: {w}x{h} px over {}x{} deg, limit xi = {xi:.2} c/deg",
        args.fov[0], args.fov[1]
    );
    let bar = acuity_lab::progress::bar((frames * ROWS.len()) as u64, "frames", args.quiet);
    let mut renderer = if args.render_every > 0 {
        let r = TerrainRenderer::new(args.resolution, args.fov, &terrain)
            .context("drawing the terrain (--render-every 0 measures refinement alone)")?;
        let [columns, rows] = r.panorama().grid();
        println!(
            "drawing every {} frames on {} (the whole {}x{} deg, equiangular, from {columns}x{rows} planar tiles)",
            args.render_every,
            r.adapter(),
            args.fov[0],
            args.fov[1]
        );
        Some(r)
    } else {
        None
    };
    let ppd = args.resolution[0] as f32 / args.fov[0];
    let mut references: Vec<Vec<u8>> = Vec::new();
    let mut results = Vec::with_capacity(ROWS.len());
    let mut mesh = Refinement::new();
    for row in ROWS {
        bar.set_message(row.name);
        let settings = TerrainSettings {
            components: row.components,
            viewport_cull: row.viewport_cull,
            fov_deg: args.fov,
            display_limit_cpd: xi,
            scale: args.scale,
            eccentricity_model: args.eccentricity_model,
            velocity_model: args.velocity_model,
        };
        let mut result = RowResult {
            row,
            triangles: Vec::with_capacity(frames),
            refine_ms: Vec::with_capacity(frames),
            draw_ms: Vec::new(),
            flip: Vec::new(),
        };
        for (i, view) in views.iter().enumerate() {
            let start = Instant::now();
            terrain.refine(view, &settings, &mut mesh)?;
            result.refine_ms.push(start.elapsed().as_secs_f64() * 1e3);
            result.triangles.push(mesh.stats().triangles);
            bar.inc(1);
            let Some(r) = renderer.as_mut() else { continue };
            if i % args.render_every as usize != 0 {
                continue;
            }
            let drawn = r.draw(&terrain, &mesh, &view.camera)?;
            result.draw_ms.push(drawn.draw_ms);
            let k = i / args.render_every as usize;
            if references.len() <= k {
                references.push(drawn.image.rgba.clone());
            }
            let [w, h] = args.resolution;
            let flip = acuity_lab::flip::flip_rgba(&references[k], &drawn.image.rgba, w, h, ppd)?;
            result.flip.push(flip.mean as f64);
            if k == frames / args.render_every as usize / 2 {
                std::fs::create_dir_all(&args.out)?;
                let path = args.out.join(format!("frame_{}.png", row.name));
                image::RgbaImage::from_raw(w, h, drawn.image.rgba)
                    .context("a rendered frame of the wrong size")?
                    .save(&path)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
        }
        results.push(result);
    }
    bar.finish_and_clear();
    print!("{}", format_table(&results, full));
    write_outputs(&args.out, &results, full, &poses)
}

/// The table as printed: ours beside the paper's.
pub fn format_table(results: &[RowResult], full_triangles: usize) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<14} {:>12} {:>8} {:>9} {:>11} {:>9} {:>7} {:>15}",
        "criteria", "triangles", "%", "paper %", "refine ms", "draw ms", "FLIP", "paper frame ms"
    );
    let or_dash = |v: &[f64], digits: usize| {
        if v.is_empty() {
            "-".to_owned()
        } else {
            format!("{:.*}", digits, mean(v.iter().copied()))
        }
    };
    for r in results {
        let tris = r.mean_triangles();
        let _ = writeln!(
            t,
            "{:<14} {:>12.0} {:>7.2}% {:>8.1}% {:>11.3} {:>9} {:>7} {:>15.0}",
            r.row.name,
            tris,
            100.0 * tris / full_triangles as f64,
            100.0 * r.row.paper_triangles as f64 / 1_116_720.0,
            r.mean_refine_ms(),
            or_dash(&r.draw_ms, 1),
            or_dash(&r.flip, 4),
            r.row.paper_frame_ms
        );
    }
    t
}

fn write_outputs(
    dir: &Path,
    results: &[RowResult],
    full: usize,
    poses: &[Pose],
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let write = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
    };
    let mut table = String::from(
        "criteria,size,peripheral,velocity,viewport_cull,mean_triangles,triangle_percent,mean_refine_ms,p95_refine_ms,drawn_frames,mean_draw_ms,mean_flip,paper_triangles,paper_percent,paper_frame_ms\n",
    );
    let opt = |v: &[f64]| {
        if v.is_empty() {
            String::new()
        } else {
            format!("{:.5}", mean(v.iter().copied()))
        }
    };
    let mut frames = String::from("criteria,frame,triangles,refine_ms\n");
    for r in results {
        let c = r.row.components;
        let tris = r.mean_triangles();
        let mut sorted = r.refine_ms.clone();
        sorted.sort_by(f64::total_cmp);
        let p95 = sorted
            .get(((sorted.len() as f64 * 0.95) as usize).min(sorted.len().saturating_sub(1)))
            .copied()
            .unwrap_or(0.0);
        let _ = writeln!(
            table,
            "{},{},{},{},{},{:.1},{:.4},{:.4},{:.4},{},{},{},{},{:.2},{}",
            r.row.name,
            c.size,
            c.eccentricity,
            c.velocity,
            r.row.viewport_cull,
            tris,
            100.0 * tris / full as f64,
            r.mean_refine_ms(),
            p95,
            r.draw_ms.len(),
            opt(&r.draw_ms),
            opt(&r.flip),
            r.row.paper_triangles,
            100.0 * r.row.paper_triangles as f64 / 1_116_720.0,
            r.row.paper_frame_ms
        );
        for (i, (t, ms)) in r.triangles.iter().zip(&r.refine_ms).enumerate() {
            let _ = writeln!(frames, "{},{i},{t},{ms:.4}", r.row.name);
        }
    }
    write("table1.csv", table)?;
    write("frames.csv", frames)?;
    write("flight.csv", poses_csv(poses))?;
    let categories: Vec<String> = results.iter().map(|r| r.row.name.to_owned()).collect();
    save_bar_plot(
        &BarPlot {
            title: "Triangles per frame".into(),
            y_label: "triangles (% of full resolution)".into(),
            categories: categories.clone(),
            series: vec![
                (
                    "acuity".into(),
                    results
                        .iter()
                        .map(|r| 100.0 * r.mean_triangles() / full as f64)
                        .collect(),
                ),
                (
                    "Reddy 2001".into(),
                    results
                        .iter()
                        .map(|r| 100.0 * r.row.paper_triangles as f64 / 1_116_720.0)
                        .collect(),
                ),
            ],
        },
        &dir.join("table1.png"),
    )?;
    save_bar_plot(
        &BarPlot {
            title: "Refinement time per frame (one core)".into(),
            y_label: "refinement time (ms)".into(),
            categories,
            series: vec![(
                "acuity refinement".into(),
                results.iter().map(RowResult::mean_refine_ms).collect(),
            )],
        },
        &dir.join("refine_ms.png"),
    )?;
    println!(
        "wrote {}: table1.csv, frames.csv, flight.csv, table1 and refine_ms .png/.svg",
        dir.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_flight_writes_the_table_csvs_and_plots() {
        let dir = std::env::temp_dir().join(format!("acuity-table1-{}", std::process::id()));
        let args = TerrainArgs {
            out: dir.clone(),
            fov: [200.0, 135.0],
            resolution: [1280, 1024],
            heightfield: None,
            grid: None,
            spacing_m: 30.0,
            height_range_m: 2000.0,
            size: [65, 129],
            seed: 1,
            fps: 10,
            duration: 1.0,
            velocity_window: 0.1,
            scale: 1.0,
            render_every: 0,
            eccentricity_model: EccentricityModel::Reddy2001,
            velocity_model: VelocityModel::Reddy2001,
            quiet: true,
        };
        run(&args).unwrap();
        let table = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
        assert_eq!(table.lines().count(), 7, "{table}");
        assert!(
            table
                .lines()
                .nth(1)
                .unwrap()
                .starts_with("none,false,false,false,false,16384.0,100.0000,")
        );
        let frames = std::fs::read_to_string(dir.join("frames.csv")).unwrap();
        assert_eq!(frames.lines().count(), 1 + 6 * 10);
        for png in ["table1.png", "refine_ms.png"] {
            assert!(image::open(dir.join(png)).is_ok(), "{png}");
        }
        let bad = TerrainArgs {
            fov: [0.0, 135.0],
            ..args.clone()
        };
        let e = run(&bad).unwrap_err();
        assert!(
            acuity_lab::error::error_line(&e).contains("fov_deg"),
            "{e:#}"
        );
        let stray_grid = TerrainArgs {
            grid: Some([65, 129]),
            ..args.clone()
        };
        let e = run(&stray_grid).unwrap_err();
        assert!(
            acuity_lab::error::error_line(&e).contains("none is given"),
            "{e:#}"
        );
        // The same flight over a raw f32 grid of the same size.
        let raw = dir.join("valley.f32");
        let bytes: Vec<u8> = (0..65 * 129)
            .flat_map(|n| (50.0 * ((n % 65) as f32 * 0.3).sin() + (n / 65) as f32).to_le_bytes())
            .collect();
        std::fs::write(&raw, bytes).unwrap();
        let from_raw = TerrainArgs {
            heightfield: Some(raw),
            grid: Some([65, 129]),
            ..args
        };
        run(&from_raw).unwrap();
        let table = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
        assert!(
            table
                .lines()
                .nth(1)
                .unwrap()
                .starts_with("none,false,false,false,false,16384.0,100.0000,"),
            "{table}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn the_rows_are_table_1s() {
        assert_eq!(ROWS.len(), 6);
        assert!(!ROWS[0].viewport_cull && ROWS[1..].iter().all(|r| r.viewport_cull));
        assert_eq!(ROWS[5].components, Components::ALL);
        let paper: Vec<u32> = ROWS.iter().map(|r| r.paper_triangles).collect();
        assert_eq!(paper[0], 1_116_720);
        assert!(paper[5] < paper[3] && paper[3] < paper[2]);
    }
}
