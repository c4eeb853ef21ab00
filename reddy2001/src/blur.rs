//! `acuity blur`: the acuity image filter ([`crate::foveate`]) on a PNG
//! (or on a generated photo-like test image), written as a side-by-side
//! PNG like Reddy 2001's Fig. 5: the original, the filter for eccentricity
//! alone, and for eccentricity and velocity.
//!
//! This module is the edge: it decodes and encodes files and converts
//! between sRGB bytes and linear light (the filter averages light, so it
//! runs on linear values).

use std::path::{Path, PathBuf};
use std::time::Instant;

use acuity::{EccentricityModel, VelocityModel};
use anyhow::Context;
use image::{Rgb, RgbImage};

use crate::foveate::{Image, View, foveate};
use crate::fractal::Fbm;

/// Arguments of `acuity blur`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct BlurArgs {
    /// The image (PNG, 8 or 16 bits, grey or colour; alpha is dropped).
    /// Without it, a generated 1920x1080 photo-like test image.
    pub image: Option<PathBuf>,
    /// The angles the image subtends, HORIZxVERT deg (Fig. 5: 150x100).
    #[cfg_attr(feature = "clap", arg(long, value_parser = acuity_lab::parse::parse_angles))]
    pub fov: [f32; 2],
    /// The gaze point, X,Y pixels from the top-left corner.
    #[cfg_attr(feature = "clap", arg(long, value_parser = parse_point))]
    pub gaze: (f32, f32),
    /// Size of the generated test image (without IMAGE), WIDTHxHEIGHT px.
    #[cfg_attr(feature = "clap", arg(long, default_value = "1920x1080", value_parser = acuity_lab::parse::parse_resolution))]
    pub test_size: [u32; 2],
    /// Retinal velocity of the third panel, deg/s (Fig. 5's caption: 50).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 50.0))]
    pub velocity: f32,
    /// Global scale factor s in (0, 1].
    #[cfg_attr(feature = "clap", arg(long, default_value_t = 1.0))]
    pub scale: f32,
    /// How acuity falls with eccentricity: `reddy2001` (the paper's, the
    /// default here) or `cortical_magnification`.
    #[cfg_attr(feature = "clap", arg(long, default_value = "reddy2001"))]
    pub eccentricity_model: EccentricityModel,
    /// How acuity falls with velocity: `reddy2001` (the default here) or
    /// `kelly1979`.
    #[cfg_attr(feature = "clap", arg(long, default_value = "reddy2001"))]
    pub velocity_model: VelocityModel,
    /// The side-by-side PNG to write.
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: PathBuf,
}

/// Parses `X,Y`: two finite numbers (a `--gaze` point, pixels).
pub fn parse_point(text: &str) -> Result<(f32, f32), String> {
    let (a, b) = text
        .split_once(',')
        .ok_or_else(|| format!("`{text}` is not of the form X,Y"))?;
    let parse = |s: &str| match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("`{s}` in `{text}` is not a finite number")),
    };
    Ok((parse(a)?, parse(b)?))
}

/// Runs `acuity blur`: filters the image (or the generated one) at each
/// velocity, prints where the outputs went and writes them.
pub fn run(args: &BlurArgs) -> anyhow::Result<()> {
    let image = match &args.image {
        Some(path) => load_linear(path)?,
        None => test_image(args.test_size[0] as usize, args.test_size[1] as usize),
    };
    let still = View {
        fov_deg: args.fov,
        gaze_px: [args.gaze.0, args.gaze.1],
        velocity_deg_per_s: 0.0,
        scale: args.scale,
        eccentricity_model: args.eccentricity_model,
        velocity_model: args.velocity_model,
    };
    let moving = View {
        velocity_deg_per_s: args.velocity,
        ..still
    };
    // Both views are checked before either is filtered.
    still.validate(image.width, image.height)?;
    moving.validate(image.width, image.height)?;
    let mut panels = vec![(image.clone(), "original".to_owned())];
    for (view, label) in [
        (still, "eccentricity".to_owned()),
        (moving, format!("eccentricity + {} deg/s", args.velocity)),
    ] {
        let start = Instant::now();
        let out = foveate(&image, &view)?;
        println!(
            "{label}: filtered {}x{} px in {:.0} ms",
            image.width,
            image.height,
            start.elapsed().as_secs_f64() * 1e3
        );
        panels.push((out, label));
    }
    side_by_side(&panels)?
        .save(&args.out)
        .with_context(|| format!("writing {}", args.out.display()))?;
    println!("wrote {}", args.out.display());
    Ok(())
}

/// A PNG as linear-light RGB.
fn load_linear(path: &Path) -> anyhow::Result<Image> {
    let decoded = image::open(path)
        .map_err(|e| acuity_lab::error::input_error(format!("reading {}: {e}", path.display())))?;
    let rgb = decoded.to_rgb32f();
    let (width, height) = (rgb.width() as usize, rgb.height() as usize);
    let data = rgb.into_raw().into_iter().map(srgb_to_linear).collect();
    Ok(Image {
        width,
        height,
        channels: 3,
        data,
    })
}

/// sRGB-encoded value in `[0, 1]` to linear light.
fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to an sRGB byte (clamped).
fn linear_to_srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

/// The panels left to right, each labelled in a strip above it.
fn side_by_side(panels: &[(Image, String)]) -> anyhow::Result<RgbImage> {
    const STRIP: u32 = 40;
    const GAP: u32 = 8;
    let (w, h) = (panels[0].0.width as u32, panels[0].0.height as u32);
    let n = panels.len() as u32;
    let mut out = RgbImage::from_pixel(n * w + (n - 1) * GAP, h + STRIP, Rgb([255, 255, 255]));
    for (i, (panel, label)) in panels.iter().enumerate() {
        let x0 = i as u32 * (w + GAP);
        acuity_lab::plot::draw_label(&mut out, x0 as i32 + 4, 8, label, 24)?;
        let c = panel.channels;
        for y in 0..h {
            for x in 0..w {
                let i = (y as usize * panel.width + x as usize) * c;
                let px = if c >= 3 {
                    [0, 1, 2].map(|k| linear_to_srgb8(panel.data[i + k]))
                } else {
                    [linear_to_srgb8(panel.data[i]); 3]
                };
                out.put_pixel(x0 + x, STRIP + y, Rgb(px));
            }
        }
    }
    Ok(out)
}

/// A photo-like test image in linear light: a sky, fractal hills with a
/// foliage-like texture, and patches of fine gratings and checks whose
/// loss the filter shows.
pub fn test_image(width: usize, height: usize) -> Image {
    let ridge = Fbm {
        seed: 11,
        base_period: width as f32 / 3.0,
        octaves: 7,
        persistence: 0.5,
    };
    let texture = Fbm {
        seed: 12,
        base_period: 64.0,
        octaves: 6,
        persistence: 0.6,
    };
    let mut data = Vec::with_capacity(width * height * 3);
    for y in 0..height {
        for x in 0..width {
            let (fx, fy) = (x as f32, y as f32);
            let horizon = height as f32 * (0.45 + 0.15 * ridge.at(fx, 0.0));
            let rgb = if fy < horizon {
                let t = fy / height as f32;
                [0.25 + 0.3 * t, 0.45 + 0.3 * t, 0.9]
            } else {
                let n = 0.5 + 0.5 * texture.at(fx, fy);
                let leaf = (0.5 + 0.5 * texture.at(fx * 4.0, fy * 4.0)).powi(2);
                [0.05 + 0.25 * n * leaf, 0.12 + 0.45 * n, 0.03 + 0.1 * leaf]
            };
            data.extend(rgb.map(|v| v * patch(x, y, width, height)));
        }
    }
    Image {
        width,
        height,
        channels: 3,
        data,
    }
}

/// 1 outside the grating and check patches; inside, a pattern between 0.1
/// and 1 (gratings of 2 to 8 px periods, 4 px checks) along the middle row.
fn patch(x: usize, y: usize, width: usize, height: usize) -> f32 {
    let size = (height / 8).max(4);
    let (cy, row) = (height / 2, y as i64 - (height / 2) as i64);
    if row.unsigned_abs() as usize >= size / 2 {
        return 1.0;
    }
    let slot = width / 6;
    let k = x / slot.max(1);
    let in_slot = x % slot.max(1);
    if in_slot < (slot - size) / 2 || in_slot >= (slot + size) / 2 || k >= 5 {
        return 1.0;
    }
    let on = match k {
        0 => x.is_multiple_of(2),
        1 => (x / 2).is_multiple_of(2),
        2 => (x / 4).is_multiple_of(2),
        3 => ((x / 4) + (y / 4)).is_multiple_of(2),
        _ => ((x / 2) + (y.abs_diff(cy) / 2)).is_multiple_of(2),
    };
    if on { 1.0 } else { 0.1 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_byte() {
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb_to_linear(b as f32 / 255.0)), b);
        }
    }

    #[test]
    fn the_test_image_is_bounded_and_has_fine_detail() {
        let image = test_image(240, 120);
        assert!(image.validate().is_ok());
        assert!(image.data.iter().all(|v| (0.0..=1.0).contains(v)));
        // The 1 px grating in the first slot alternates.
        let i = |x: usize| (60 * 240 + x) * 3;
        let slot_start = (40 - 15) / 2;
        let (a, b) = (image.data[i(slot_start + 2)], image.data[i(slot_start + 3)]);
        assert!((a - b).abs() > 0.05, "{a} {b}");
    }

    #[test]
    fn the_command_writes_three_labelled_panels() {
        let dir = std::env::temp_dir().join(format!("acuity-blur-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let args = BlurArgs {
            image: None,
            fov: [150.0, 100.0],
            gaze: (10.0, 20.0),
            test_size: [96, 48],
            velocity: 50.0,
            scale: 1.0,
            eccentricity_model: EccentricityModel::Reddy2001,
            velocity_model: VelocityModel::Reddy2001,
            out: dir.join("fig5.png"),
        };
        run(&args).unwrap();
        let out = image::open(&args.out).unwrap();
        assert_eq!((out.width(), out.height()), (3 * 96 + 2 * 8, 48 + 40));
        let outside = BlurArgs {
            gaze: (97.0, 20.0),
            ..args
        };
        let e = run(&outside).unwrap_err();
        assert!(e.to_string().contains("outside the 96x48 image"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_missing_file_names_itself() {
        let e = load_linear(Path::new("no/such.png")).unwrap_err();
        assert!(format!("{e:#}").contains("no/such.png"), "{e:#}");
    }
}
