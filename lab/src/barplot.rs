//! Grouped bar charts as PNG and SVG (one group per category, one coloured
//! bar per series, the value printed above each bar), drawn with
//! `plotters` like [`crate::plot`]'s line plots, with its font and colours.

use std::path::Path;

use anyhow::Context;
use image::RgbImage;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::plot::{PALETTE, PLOT_SIZE_PX, draw_legend, register_font, tick_label};

/// A grouped bar chart.
#[derive(Debug, Clone, Default)]
pub struct BarPlot {
    /// Title above the chart.
    pub title: String,
    /// Label of the value axis (with its unit).
    pub y_label: String,
    /// One label per group, left to right.
    pub categories: Vec<String>,
    /// `(name, one value per category)`; non-finite or negative values
    /// draw no bar.
    pub series: Vec<(String, Vec<f64>)>,
}

/// Renders `plot` into a `width` x `height` image (each at least 300).
pub fn render_bar_plot(plot: &BarPlot, width: u32, height: u32) -> anyhow::Result<RgbImage> {
    let (width, height) = (width.max(300), height.max(300));
    register_font()?;
    let mut buf = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        draw_bar_plot(&root, plot)?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing the chart: {e}"))?;
    }
    RgbImage::from_raw(width, height, buf).context("chart buffer size")
}

/// Writes `plot` at [`PLOT_SIZE_PX`] as a PNG to `path` and as an SVG
/// beside it (`path` with extension `svg`).
pub fn save_bar_plot(plot: &BarPlot, path: &Path) -> anyhow::Result<()> {
    let (w, h) = PLOT_SIZE_PX;
    render_bar_plot(plot, w, h)?
        .save(path)
        .with_context(|| format!("writing {}", path.display()))?;
    let svg = path.with_extension("svg");
    let root = SVGBackend::new(&svg, (w, h)).into_drawing_area();
    draw_bar_plot(&root, plot)?;
    root.present()
        .map_err(|e| anyhow::anyhow!("writing {}: {e}", svg.display()))
}

/// A bar's value as printed above it.
fn value_label(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.1}")
    }
}

/// Draws `plot` on `root`: category `g` spans x in `[g, g + 1)`.
fn draw_bar_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &BarPlot,
) -> anyhow::Result<()> {
    let fail = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("drawing the chart: {e}");
    root.fill(&WHITE).map_err(fail)?;
    let bar = |v: &f64| v.is_finite() && *v >= 0.0;
    let max = plot
        .series
        .iter()
        .flat_map(|(_, v)| v.iter().copied())
        .filter(bar)
        .fold(0.0f64, f64::max);
    let top = if max > 0.0 { max * 1.12 } else { 1.0 };
    let groups = plot.categories.len().max(1);
    let mut chart = ChartBuilder::on(root)
        .caption(&plot.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(30)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..groups as f64, 0.0..top)
        .map_err(fail)?;
    let categories = &plot.categories;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(groups * 2 + 1)
        .x_label_formatter(&|x| {
            // Labels at the groups' centres only.
            let g = x - 0.5;
            if (g - g.round()).abs() < 1e-6 && g >= 0.0 {
                categories
                    .get(g.round() as usize)
                    .cloned()
                    .unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| tick_label(*v))
        .y_desc(plot.y_label.as_str())
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(fail)?;
    let n = plot.series.len().max(1) as f64;
    let width = 0.8 / n;
    for (k, (name, values)) in plot.series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let bars: Vec<(f64, f64)> = values
            .iter()
            .take(plot.categories.len())
            .enumerate()
            .filter(|(_, v)| bar(v))
            .map(|(g, &v)| (g as f64 + 0.1 + k as f64 * width, v))
            .collect();
        chart
            .draw_series(
                bars.iter().map(|&(x, v)| {
                    Rectangle::new([(x, 0.0), (x + width * 0.92, v)], colour.filled())
                }),
            )
            .map_err(fail)?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled()));
        let text = ("sans-serif", 12)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Bottom));
        chart
            .draw_series(
                bars.iter()
                    .map(|&(x, v)| Text::new(value_label(v), (x + width * 0.46, v), text.clone())),
            )
            .map_err(fail)?;
    }
    if !plot.series.is_empty() {
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight).map_err(fail)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_draw_with_empty_and_bad_data() {
        let mut p = BarPlot::default();
        assert_eq!(
            render_bar_plot(&p, 400, 300).unwrap().dimensions(),
            (400, 300)
        );
        p.categories = vec!["a".into(), "b".into()];
        p.series = vec![("x".into(), vec![1.0, f64::NAN]), ("y".into(), vec![-1.0])];
        let img = render_bar_plot(&p, 400, 300).unwrap();
        // The one finite positive bar is drawn in its series' colour.
        let c = PALETTE[0];
        let hits = img.pixels().filter(|px| px.0 == [c.0, c.1, c.2]).count();
        assert!(hits > 500, "{hits} pixels in the bar's colour");
        let dir = std::env::temp_dir().join(format!("acuity-barplot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let png = dir.join("bars.png");
        save_bar_plot(&p, &png).unwrap();
        assert!(png.with_extension("svg").is_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
