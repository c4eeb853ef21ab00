//! Minimal PNG grouped bar charts (one group per category, one coloured
//! bar per series, value printed above each bar), drawn like
//! [`crate::plot`]'s line plots with its built-in font.

use std::path::Path;

use anyhow::Context;
use image::{Rgb, RgbImage};

use crate::plot::{draw_text, text_width};

/// A grouped bar chart.
#[derive(Debug, Clone, Default)]
pub struct BarPlot {
    /// Title above the chart.
    pub title: String,
    /// Label of the value axis (with its unit).
    pub y_label: String,
    /// One label per group, left to right.
    pub categories: Vec<String>,
    /// `(name, one value per category)`; non-finite values draw no bar.
    pub series: Vec<(String, Vec<f64>)>,
}

const COLOURS: [[u8; 3]; 4] = [[31, 119, 180], [255, 127, 14], [44, 160, 44], [214, 39, 40]];

/// Renders `plot` into a `width` x `height` image (each at least 300).
pub fn render_bar_plot(plot: &BarPlot, width: u32, height: u32) -> RgbImage {
    let (width, height) = (width.max(300), height.max(300));
    let mut img = RgbImage::from_pixel(width, height, Rgb([255, 255, 255]));
    let dark = [40, 40, 40];
    let (left, right, top, bottom) = (60i64, width as i64 - 20, 50i64, height as i64 - 60);
    draw_text(&mut img, left, 12, &plot.title, 2, dark);
    draw_text(&mut img, 4, top - 16, &plot.y_label, 1, dark);
    let max = plot
        .series
        .iter()
        .flat_map(|(_, v)| v.iter().copied())
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max)
        .max(1e-12);
    let y_of = |v: f64| bottom - ((v / max) * (bottom - top) as f64).round() as i64;
    for x in left..=right {
        put(&mut img, x, bottom, dark);
    }
    for y in top..=bottom {
        put(&mut img, left, y, dark);
    }
    let groups = plot.categories.len().max(1) as i64;
    let group_w = (right - left) / groups;
    let n = plot.series.len().max(1) as i64;
    let bar_w = ((group_w - 16) / n).max(2);
    for (g, label) in plot.categories.iter().enumerate() {
        let gx = left + g as i64 * group_w + 8;
        for (k, (_, values)) in plot.series.iter().enumerate() {
            let Some(&v) = values.get(g) else { continue };
            if !v.is_finite() || v < 0.0 {
                continue;
            }
            let x0 = gx + k as i64 * bar_w;
            let y0 = y_of(v);
            let colour = COLOURS[k % COLOURS.len()];
            for x in x0..x0 + bar_w - 2 {
                for y in y0..bottom {
                    put(&mut img, x, y, colour);
                }
            }
            let text = if v >= 10.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.1}")
            };
            let tx = x0 + (bar_w - 2 - text_width(&text, 1)) / 2;
            draw_text(&mut img, tx, y0 - 10, &text, 1, dark);
        }
        let tx = gx + (group_w - 16 - text_width(label, 1)) / 2;
        draw_text(&mut img, tx.max(gx), bottom + 8, label, 1, dark);
    }
    for (k, (name, _)) in plot.series.iter().enumerate() {
        let y = height as i64 - 24;
        let x = left + k as i64 * 220;
        let colour = COLOURS[k % COLOURS.len()];
        for dx in 0..12 {
            for dy in 0..8 {
                put(&mut img, x + dx, y + dy, colour);
            }
        }
        draw_text(&mut img, x + 18, y, name, 1, dark);
    }
    img
}

/// Renders `plot` at 900 x 500 pixels and writes it as PNG.
pub fn save_bar_plot(plot: &BarPlot, path: &Path) -> anyhow::Result<()> {
    render_bar_plot(plot, 900, 500)
        .save(path)
        .with_context(|| format!("writing {}", path.display()))
}

fn put(img: &mut RgbImage, x: i64, y: i64, colour: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, Rgb(colour));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_draw_with_empty_and_bad_data() {
        let mut p = BarPlot::default();
        assert_eq!(render_bar_plot(&p, 400, 300).dimensions(), (400, 300));
        p.categories = vec!["a".into(), "b".into()];
        p.series = vec![("x".into(), vec![1.0, f64::NAN]), ("y".into(), vec![-1.0])];
        let img = render_bar_plot(&p, 400, 300);
        // The one finite positive bar reaches the top of the plot area.
        assert_eq!(img.get_pixel(70, 60).0, COLOURS[0]);
    }
}
