//! Line plots as PNG and SVG, drawn with `plotters`: axes with ticks and
//! labels (with units), one coloured line per series, a legend. Text uses
//! DejaVu Sans embedded in the binary (`assets/`, licence beside it), so no
//! system fonts are needed; SVGs leave text to the viewer's `sans-serif`.
//!
//! Also [`draw_label`] for text on images, and what [`crate::barplot`]
//! shares: [`PALETTE`], [`PLOT_SIZE_PX`], [`register_font`].

use std::path::Path;
use std::sync::OnceLock;

use anyhow::{Context, bail};
use image::RgbImage;
use plotters::coord::Shift;
use plotters::prelude::*;

/// One line of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points `(x, y)` in data units, drawn in order; points that are not
    /// finite or beyond [`PLOTTABLE`] break the line.
    pub points: Vec<(f64, f64)>,
}

/// A line plot.
#[derive(Debug, Clone, Default)]
pub struct LinePlot {
    /// Title above the plot.
    pub title: String,
    /// Label of the x axis (with its unit).
    pub x_label: String,
    /// Label of the y axis (with its unit).
    pub y_label: String,
    /// The lines.
    pub series: Vec<Series>,
    /// Logarithmic x axis (non-positive x are skipped).
    pub log_x: bool,
    /// Draw a marker at every point (for sparse data).
    pub markers: bool,
    /// Start the y axis at 0 (else at the data's minimum).
    pub y_from_zero: bool,
}

/// Distinct line colours (matplotlib's `tab10`), cycled.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The size of the plots [`save_line_plot`] and
/// [`crate::barplot::save_bar_plot`] write, pixels.
pub const PLOT_SIZE_PX: (u32, u32) = (900, 500);

/// DejaVu Sans (Bitstream Vera licence, `assets/DejaVuSans-LICENSE.txt`).
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font as plotters' `sans-serif` (once); an error
/// if it cannot be read, so that no plot is drawn without text.
pub fn register_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
    });
    if !ok {
        bail!("the embedded plot font could not be read");
    }
    Ok(())
}

/// Renders `plot` into a `width` x `height` image (each at least 200).
pub fn render_line_plot(plot: &LinePlot, width: u32, height: u32) -> anyhow::Result<RgbImage> {
    let (width, height) = (width.max(200), height.max(200));
    register_font()?;
    let mut buf = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        draw_line_plot(&root, plot)?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing the plot: {e}"))?;
    }
    RgbImage::from_raw(width, height, buf).context("plot buffer size")
}

/// Writes `plot` as an SVG to `path`, `width` x `height` pixels.
pub fn write_line_plot_svg(
    plot: &LinePlot,
    width: u32,
    height: u32,
    path: &Path,
) -> anyhow::Result<()> {
    register_font()?;
    let root = SVGBackend::new(path, (width.max(200), height.max(200))).into_drawing_area();
    draw_line_plot(&root, plot)?;
    root.present()
        .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))
}

/// Writes `plot` at [`PLOT_SIZE_PX`] as a PNG to `path` and as an SVG
/// beside it (`path` with extension `svg`).
pub fn save_line_plot(plot: &LinePlot, path: &Path) -> anyhow::Result<()> {
    let (w, h) = PLOT_SIZE_PX;
    render_line_plot(plot, w, h)?
        .save(path)
        .with_context(|| format!("writing {}", path.display()))?;
    write_line_plot_svg(plot, w, h, &path.with_extension("svg"))
}

/// The largest magnitude drawn (and on a log x axis, the reciprocal of the
/// smallest x). Beyond it `plotters`' tick search on a log axis can take
/// practically forever, and no data acuity writes gets near it.
pub const PLOTTABLE: f64 = 1e100;

/// The drawable stretches of a series: split where a point is not finite,
/// beyond [`PLOTTABLE`], or, on a log x axis, has x below its reciprocal.
fn segments(points: &[(f64, f64)], log_x: bool) -> Vec<Vec<(f64, f64)>> {
    let mut out = vec![Vec::new()];
    for &(x, y) in points {
        let drawable = x.abs() <= PLOTTABLE && y.abs() <= PLOTTABLE;
        if drawable && (!log_x || x >= 1.0 / PLOTTABLE) {
            out.last_mut().expect("never empty").push((x, y));
        } else if !out.last().expect("never empty").is_empty() {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// `[lo, hi]` widened to a drawable span: finite, `lo < hi`.
fn span(lo: f64, hi: f64, fallback: (f64, f64)) -> (f64, f64) {
    if !(hi - lo).is_finite() {
        return fallback;
    }
    if hi > lo {
        return (lo, hi);
    }
    let pad = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
    (lo - pad, hi + pad)
}

/// The axes' ranges: x over the data with 2% margins (a decade when there is
/// none, on a log axis), y with 5% head room and from 0 when asked.
fn ranges(plot: &LinePlot) -> ((f64, f64), (f64, f64)) {
    let pts: Vec<(f64, f64)> = plot
        .series
        .iter()
        .flat_map(|s| segments(&s.points, plot.log_x).into_iter().flatten())
        .collect();
    let fold = |f: fn(&(f64, f64)) -> f64| {
        pts.iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let (x0, x1) = fold(|p| p.0);
    let (mut y0, y1) = fold(|p| p.1);
    if plot.y_from_zero && y0.is_finite() {
        y0 = y0.min(0.0);
    }
    // 2% margins, so that markers at the ends are whole.
    let x = if plot.log_x {
        let (a, b) = span(x0.log10(), x1.log10(), (0.0, 1.0));
        let m = 0.02 * (b - a);
        (10f64.powf(a - m), 10f64.powf(b + m))
    } else {
        let (a, b) = span(x0, x1, (0.0, 1.0));
        let m = 0.02 * (b - a);
        (a - m, b + m)
    };
    let (y0, y1) = span(y0, y1, (0.0, 1.0));
    let head = 0.05 * (y1 - y0);
    (
        x,
        (
            y0,
            if (y1 + head).is_finite() {
                y1 + head
            } else {
                y1
            },
        ),
    )
}

/// Draws `plot` on `root`.
fn draw_line_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &LinePlot,
) -> anyhow::Result<()> {
    let fail = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("drawing the plot: {e}");
    root.fill(&WHITE).map_err(fail)?;
    let ((x0, x1), (y0, y1)) = ranges(plot);
    let mut builder = ChartBuilder::on(root);
    builder
        .caption(&plot.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(64);
    // The same drawing on a linear or a logarithmic x axis.
    macro_rules! draw {
        ($x_range:expr) => {{
            let mut chart = builder.build_cartesian_2d($x_range, y0..y1).map_err(fail)?;
            chart
                .configure_mesh()
                .x_desc(plot.x_label.as_str())
                .y_desc(plot.y_label.as_str())
                .x_label_formatter(&|v| {
                    if plot.log_x {
                        log_tick_label(*v)
                    } else {
                        tick_label(*v)
                    }
                })
                .y_label_formatter(&|v| tick_label(*v))
                .label_style(("sans-serif", 13))
                .axis_desc_style(("sans-serif", 15))
                .light_line_style(TRANSPARENT)
                .bold_line_style(RGBColor(225, 225, 225))
                .draw()
                .map_err(fail)?;
            for (k, s) in plot.series.iter().enumerate() {
                let colour = PALETTE[k % PALETTE.len()];
                let style = colour.stroke_width(2);
                let mut parts = segments(&s.points, plot.log_x);
                if parts.is_empty() {
                    // Still named in the legend.
                    parts.push(Vec::new());
                }
                for (i, part) in parts.iter().enumerate() {
                    let drawn = chart
                        .draw_series(LineSeries::new(part.iter().copied(), style))
                        .map_err(fail)?;
                    if i == 0 {
                        drawn.label(s.name.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                        });
                    }
                    if plot.markers {
                        chart
                            .draw_series(part.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                            .map_err(fail)?;
                    }
                }
            }
            if !plot.series.is_empty() {
                let corner = emptiest_corner(plot, (x0, x1), (y0, y1));
                draw_legend(&mut chart, corner).map_err(fail)?;
            }
        }};
    }
    if plot.log_x {
        draw!((x0..x1).log_scale());
    } else {
        draw!(x0..x1);
    }
    Ok(())
}

/// A tick label: few digits, no trailing zeros.
pub(crate) fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e6).contains(&a) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

/// A tick label on a logarithmic axis: [`tick_label`] at 1, 2 and 5
/// times a power of ten, none between, so that the ticks of a decade's
/// upper half (60, 70, 80, 90, 100) do not run into each other.
fn log_tick_label(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let mantissa = v / 10f64.powf(v.log10().floor());
    if [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|m| (mantissa - m).abs() < 1e-6 * m)
    {
        tick_label(v)
    } else {
        String::new()
    }
}

/// Draws `text` in black on `img` with its top-left corner at `(x, y)`,
/// `size_px` pixels high. Text outside the image is clipped.
pub fn draw_label(
    img: &mut RgbImage,
    x: i32,
    y: i32,
    text: &str,
    size_px: u32,
) -> anyhow::Result<()> {
    register_font()?;
    let (w, h) = img.dimensions();
    let root = BitMapBackend::with_buffer(img.as_mut(), (w, h)).into_drawing_area();
    root.draw(&Text::new(
        text,
        (x, y),
        ("sans-serif", size_px).into_font(),
    ))
    .and_then(|()| root.present())
    .map_err(|e| anyhow::anyhow!("drawing a label: {e}"))
}

/// The share of a corner's width and height the legend is taken to
/// cover when [`emptiest_corner`] looks for the lines under it.
const LEGEND_SHARE: (f64, f64) = (0.5, 0.45);

/// The corner of the plotting area where the lines pass least, for the
/// legend: the lines are sampled (20 points per segment between data
/// points, in the axes' own scale) and counted in each corner's
/// [`LEGEND_SHARE`] of the area. Ties keep the upper right, then the
/// upper left, lower right and lower left, so a plot without data keeps
/// the usual place.
fn emptiest_corner(plot: &LinePlot, x: (f64, f64), y: (f64, f64)) -> SeriesLabelPosition {
    let to_unit = |px: f64, py: f64| {
        let (u, (a, b)) = if plot.log_x {
            (px.log10(), (x.0.log10(), x.1.log10()))
        } else {
            (px, x)
        };
        ((u - a) / (b - a), (py - y.0) / (y.1 - y.0))
    };
    // (right, upper), in the order ties are broken.
    let corners = [(true, true), (false, true), (true, false), (false, false)];
    let mut counts = [0usize; 4];
    for s in &plot.series {
        for part in segments(&s.points, plot.log_x) {
            let unit: Vec<(f64, f64)> = part.iter().map(|&(px, py)| to_unit(px, py)).collect();
            let samples = unit.windows(2).flat_map(|w| {
                (0..20).map(move |i| {
                    let t = f64::from(i) / 20.0;
                    (
                        w[0].0 + t * (w[1].0 - w[0].0),
                        w[0].1 + t * (w[1].1 - w[0].1),
                    )
                })
            });
            for (u, v) in samples.chain(unit.last().copied()) {
                for (k, &(right, upper)) in corners.iter().enumerate() {
                    let in_x = if right {
                        u >= 1.0 - LEGEND_SHARE.0
                    } else {
                        u <= LEGEND_SHARE.0
                    };
                    let in_y = if upper {
                        v >= 1.0 - LEGEND_SHARE.1
                    } else {
                        v <= LEGEND_SHARE.1
                    };
                    counts[k] += usize::from(in_x && in_y);
                }
            }
        }
    }
    match (0..4).min_by_key(|&k| (counts[k], k)) {
        Some(1) => SeriesLabelPosition::UpperLeft,
        Some(2) => SeriesLabelPosition::LowerRight,
        Some(3) => SeriesLabelPosition::LowerLeft,
        _ => SeriesLabelPosition::UpperRight,
    }
}

/// The legend of a chart's labelled series at `corner` (the style every
/// plot of the tool shares).
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    corner: SeriesLabelPosition,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(corner)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .label_font(("sans-serif", 13))
        .draw()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(points: &[(f64, f64)], log_x: bool) -> LinePlot {
        LinePlot {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            series: vec![Series {
                name: "a".into(),
                points: points.to_vec(),
            }],
            log_x,
            markers: false,
            y_from_zero: false,
        }
    }

    #[test]
    fn the_legend_goes_where_the_lines_are_not() {
        // JOD rising with triangles: the lower right is empty.
        let rising = line(&[(0.1, 8.6), (0.3, 9.5), (0.6, 9.8), (1.0, 10.0)], false);
        let (x, y) = ranges(&rising);
        assert_eq!(
            emptiest_corner(&rising, x, y),
            SeriesLabelPosition::LowerRight
        );
        // Frame time falling as the bias drops, on a log axis: the upper
        // right is empty.
        let falling = line(&[(0.25, 50.0), (1.0, 30.0), (4.0, 10.0)], true);
        let (x, y) = ranges(&falling);
        assert_eq!(
            emptiest_corner(&falling, x, y),
            SeriesLabelPosition::UpperRight
        );
        // Along the top, then down at the right: the lower left is empty.
        let flat_top = line(&[(0.0, 1.0), (1.0, 1.0), (2.0, 0.0)], false);
        let (x, y) = ranges(&flat_top);
        assert_eq!(
            emptiest_corner(&flat_top, x, y),
            SeriesLabelPosition::LowerLeft
        );
        let empty = line(&[], false);
        let (x, y) = ranges(&empty);
        assert_eq!(
            emptiest_corner(&empty, x, y),
            SeriesLabelPosition::UpperRight
        );
    }

    #[test]
    fn ticks_read_well() {
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(100.0), "100");
        assert_eq!(tick_label(-0.0001), "-1e-4");
        assert_eq!(tick_label(-0.0), "0");
        for (v, label) in [(10.0, "10"), (20.0, "20"), (50.0, "50"), (100.0, "100")] {
            assert_eq!(log_tick_label(v), label);
        }
        for v in [30.0, 60.0, 90.0, 0.0, -10.0, f64::NAN] {
            assert_eq!(log_tick_label(v), "", "{v}");
        }
        assert_eq!(log_tick_label(0.002), "0.002");
    }

    #[test]
    fn non_finite_points_break_lines() {
        let s = segments(
            &[
                (0.0, 1.0),
                (1.0, f64::NAN),
                (2.0, 3.0),
                (3.0, 4.0),
                (-1.0, 1.0),
                (4.0, 1e200),
            ],
            true,
        );
        assert_eq!(s, vec![vec![(2.0, 3.0), (3.0, 4.0)]]);
        assert_eq!(
            segments(&[(0.0, 1.0), (f64::INFINITY, 0.0)], false).len(),
            1
        );
    }

    #[test]
    fn plots_draw_without_data_and_with_bad_data() {
        let dir = std::env::temp_dir().join(format!("acuity-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut p = LinePlot {
            title: "empty".into(),
            x_label: "time (s)".into(),
            y_label: "frame time (ms)".into(),
            ..Default::default()
        };
        let img = render_line_plot(&p, 300, 200).unwrap();
        assert_eq!(img.dimensions(), (300, 200));
        p.series.push(Series {
            name: "nan".into(),
            points: vec![(f64::NAN, 1.0), (1.0, f64::INFINITY)],
        });
        p.series.push(Series {
            name: "huge".into(),
            points: vec![(2.0, 3.0), (1e300, -1e300), (0.0, 1.0)],
        });
        p.series.push(Series {
            name: "wide".into(),
            points: vec![(1e-90, 1e90), (1e90, -1e90)],
        });
        p.log_x = true;
        p.markers = true;
        let png = dir.join("bad.png");
        save_line_plot(&p, &png).unwrap();
        let svg = std::fs::read_to_string(png.with_extension("svg")).unwrap();
        assert!(svg.contains("<svg") && svg.contains("huge"), "{svg}");
        let img = image::open(&png).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), PLOT_SIZE_PX);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_line_is_drawn_in_its_colour() {
        let p = LinePlot {
            series: vec![Series {
                name: "a".into(),
                points: vec![(0.0, 0.0), (1.0, 1.0), (2.0, 0.5)],
            }],
            ..Default::default()
        };
        let img = render_line_plot(&p, 400, 300).unwrap();
        let c = PALETTE[0];
        let hits = img.pixels().filter(|px| px.0 == [c.0, c.1, c.2]).count();
        assert!(hits > 100, "{hits} pixels in the line's colour");
    }

    #[test]
    fn labels_draw_dark_pixels() {
        let mut img = RgbImage::from_pixel(200, 40, image::Rgb([255, 255, 255]));
        draw_label(&mut img, 4, 4, "reference", 20).unwrap();
        let dark = img.pixels().filter(|px| px.0[0] < 100).count();
        assert!(dark > 50, "{dark} dark pixels");
    }
}
