//! Minimal PNG line plots: axes with numbered ticks, one coloured line per
//! series, a legend. Drawn with the `image` crate and a built-in 5x7 pixel
//! font, so no font files or system libraries are needed.

use std::path::Path;

use anyhow::Context;
use image::{Rgb, RgbImage};

/// One line of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points `(x, y)` in data units, drawn in order; non-finite points
    /// break the line.
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

/// Distinct line colours, cycled.
const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

const GLYPH_W: u32 = 5;
const GLYPH_H: u32 = 7;

/// 5x7 glyphs, rows top first, `#` set. Lower case is drawn as upper case;
/// unknown characters as a box.
fn glyph(c: char) -> [&'static str; GLYPH_H as usize] {
    match c.to_ascii_uppercase() {
        '0' => [
            ".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###.",
        ],
        '1' => [
            "..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###.",
        ],
        '2' => [
            ".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####",
        ],
        '3' => [
            "####.", "....#", "....#", ".###.", "....#", "....#", "####.",
        ],
        '4' => [
            "...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#.",
        ],
        '5' => [
            "#####", "#....", "####.", "....#", "....#", "#...#", ".###.",
        ],
        '6' => [
            ".###.", "#....", "#....", "####.", "#...#", "#...#", ".###.",
        ],
        '7' => [
            "#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#...",
        ],
        '8' => [
            ".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###.",
        ],
        '9' => [
            ".###.", "#...#", "#...#", ".####", "....#", "....#", ".###.",
        ],
        'A' => [
            ".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#",
        ],
        'B' => [
            "####.", "#...#", "#...#", "####.", "#...#", "#...#", "####.",
        ],
        'C' => [
            ".###.", "#...#", "#....", "#....", "#....", "#...#", ".###.",
        ],
        'D' => [
            "####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####.",
        ],
        'E' => [
            "#####", "#....", "#....", "####.", "#....", "#....", "#####",
        ],
        'F' => [
            "#####", "#....", "#....", "####.", "#....", "#....", "#....",
        ],
        'G' => [
            ".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####",
        ],
        'H' => [
            "#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#",
        ],
        'I' => [
            ".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###.",
        ],
        'J' => [
            "..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##..",
        ],
        'K' => [
            "#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#",
        ],
        'L' => [
            "#....", "#....", "#....", "#....", "#....", "#....", "#####",
        ],
        'M' => [
            "#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#",
        ],
        'N' => [
            "#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#",
        ],
        'O' => [
            ".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###.",
        ],
        'P' => [
            "####.", "#...#", "#...#", "####.", "#....", "#....", "#....",
        ],
        'Q' => [
            ".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#",
        ],
        'R' => [
            "####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#",
        ],
        'S' => [
            ".####", "#....", "#....", ".###.", "....#", "....#", "####.",
        ],
        'T' => [
            "#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#..",
        ],
        'U' => [
            "#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###.",
        ],
        'V' => [
            "#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#..",
        ],
        'W' => [
            "#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#.",
        ],
        'X' => [
            "#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#",
        ],
        'Y' => [
            "#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#..",
        ],
        'Z' => [
            "#####", "....#", "...#.", "..#..", ".#...", "#....", "#####",
        ],
        ' ' => [
            ".....", ".....", ".....", ".....", ".....", ".....", ".....",
        ],
        '.' => [
            ".....", ".....", ".....", ".....", ".....", ".##..", ".##..",
        ],
        ',' => [
            ".....", ".....", ".....", ".....", ".##..", "..#..", ".#...",
        ],
        ':' => [
            ".....", ".##..", ".##..", ".....", ".##..", ".##..", ".....",
        ],
        '-' => [
            ".....", ".....", ".....", "#####", ".....", ".....", ".....",
        ],
        '+' => [
            ".....", "..#..", "..#..", "#####", "..#..", "..#..", ".....",
        ],
        '=' => [
            ".....", ".....", "#####", ".....", "#####", ".....", ".....",
        ],
        '_' => [
            ".....", ".....", ".....", ".....", ".....", ".....", "#####",
        ],
        '/' => [
            "....#", "....#", "...#.", "..#..", ".#...", "#....", "#....",
        ],
        '(' => [
            "...#.", "..#..", ".#...", ".#...", ".#...", "..#..", "...#.",
        ],
        ')' => [
            ".#...", "..#..", "...#.", "...#.", "...#.", "..#..", ".#...",
        ],
        '%' => [
            "##...", "##..#", "...#.", "..#..", ".#...", "#..##", "...##",
        ],
        _ => [
            "#####", "#...#", "#...#", "#...#", "#...#", "#...#", "#####",
        ],
    }
}

/// Draws `text` with its top-left corner at `(x, y)`, each font pixel a
/// `scale` x `scale` block. Pixels outside the image are skipped.
pub fn draw_text(img: &mut RgbImage, x: i64, y: i64, text: &str, scale: u32, color: [u8; 3]) {
    let mut cx = x;
    for c in text.chars() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for (col, b) in bits.bytes().enumerate() {
                if b != b'#' {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        put(
                            img,
                            cx + (col as u32 * scale + dx) as i64,
                            y + (row as u32 * scale + dy) as i64,
                            color,
                        );
                    }
                }
            }
        }
        cx += ((GLYPH_W + 1) * scale) as i64;
    }
}

/// Width of `text` drawn at `scale`, pixels.
pub fn text_width(text: &str, scale: u32) -> i64 {
    (text.chars().count() as u32 * (GLYPH_W + 1) * scale) as i64
}

fn put(img: &mut RgbImage, x: i64, y: i64, color: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, Rgb(color));
    }
}

fn line(
    img: &mut RgbImage,
    (x0, y0): (i64, i64),
    (x1, y1): (i64, i64),
    color: [u8; 3],
    thick: i64,
) {
    let (dx, dy) = ((x1 - x0).abs(), -(y1 - y0).abs());
    let (sx, sy) = (if x0 < x1 { 1 } else { -1 }, if y0 < y1 { 1 } else { -1 });
    let (mut x, mut y, mut err) = (x0, y0, dx + dy);
    // Bounded: a line longer than this is off any sane image anyway.
    for _ in 0..100_000 {
        for ox in 0..thick {
            for oy in 0..thick {
                put(img, x + ox - thick / 2, y + oy - thick / 2, color);
            }
        }
        if x == x1 && y == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// Round tick values covering `[lo, hi]`, about `n` of them.
fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return vec![lo];
    }
    let raw = span / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t <= hi + step * 1e-9 && out.len() < 50 {
        out.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        t += step;
    }
    out
}

/// A tick label: few digits, no trailing zeros.
fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e6).contains(&a) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_owned()
}

/// Renders `plot` into a `width` x `height` image (each at least 200).
pub fn render_line_plot(plot: &LinePlot, width: u32, height: u32) -> RgbImage {
    let (width, height) = (width.max(200), height.max(200));
    let mut img = RgbImage::from_pixel(width, height, Rgb([255, 255, 255]));
    let fx = |x: f64| if plot.log_x { x.log10() } else { x };
    let pts = || {
        plot.series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|(x, y)| x.is_finite() && y.is_finite() && (!plot.log_x || *x > 0.0))
    };
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts() {
        x0 = x0.min(fx(x));
        x1 = x1.max(fx(x));
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if plot.y_from_zero {
        y0 = y0.min(0.0);
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    if y1 <= y0 {
        y1 = y0 + 1.0;
    }
    y1 += 0.05 * (y1 - y0);
    let (left, right, top, bottom) = (70i64, width as i64 - 20, 42i64, height as i64 - 45);
    let px = |x: f64| left + ((fx(x) - x0) / (x1 - x0) * (right - left) as f64).round() as i64;
    let py = |y: f64| bottom - ((y - y0) / (y1 - y0) * (bottom - top) as f64).round() as i64;
    let dark = [40, 40, 40];
    let grid = [225, 225, 225];
    // Grid and ticks.
    let xt: Vec<f64> = if plot.log_x {
        ticks(x0.floor(), x1.ceil(), 6)
            .into_iter()
            .filter(|e| *e >= x0 - 1e-9 && *e <= x1 + 1e-9 && e.fract() == 0.0)
            .map(|e| 10f64.powf(e))
            .collect()
    } else {
        ticks(x0, x1, 6)
    };
    for &t in &xt {
        let x = px(t);
        line(&mut img, (x, top), (x, bottom), grid, 1);
        let l = tick_label(t);
        draw_text(&mut img, x - text_width(&l, 1) / 2, bottom + 6, &l, 1, dark);
    }
    for t in ticks(y0, y1, 6) {
        let y = py(t);
        line(&mut img, (left, y), (right, y), grid, 1);
        let l = tick_label(t);
        draw_text(&mut img, left - 6 - text_width(&l, 1), y - 3, &l, 1, dark);
    }
    line(&mut img, (left, bottom), (right, bottom), dark, 1);
    line(&mut img, (left, top), (left, bottom), dark, 1);
    // Labels.
    draw_text(&mut img, left, 8, &plot.title, 2, dark);
    let xl = &plot.x_label;
    draw_text(
        &mut img,
        (left + right) / 2 - text_width(xl, 1) / 2,
        bottom + 22,
        xl,
        1,
        dark,
    );
    draw_text(&mut img, 4, top - 12, &plot.y_label, 1, dark);
    // Lines.
    for (k, s) in plot.series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let mut prev: Option<(i64, i64)> = None;
        for &(x, y) in &s.points {
            if !(x.is_finite() && y.is_finite()) || (plot.log_x && x <= 0.0) {
                prev = None;
                continue;
            }
            let p = (px(x), py(y));
            if let Some(q) = prev {
                line(&mut img, q, p, color, 2);
            }
            if plot.markers {
                for dx in -2..=2 {
                    for dy in -2..=2 {
                        put(&mut img, p.0 + dx, p.1 + dy, color);
                    }
                }
            }
            prev = Some(p);
        }
    }
    // Legend, top right.
    let lw = plot
        .series
        .iter()
        .map(|s| text_width(&s.name, 1))
        .max()
        .unwrap_or(0)
        + 26;
    for (k, s) in plot.series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let y = top + 6 + 12 * k as i64;
        let x = right - lw - 4;
        line(&mut img, (x, y + 3), (x + 16, y + 3), color, 3);
        draw_text(&mut img, x + 22, y, &s.name, 1, dark);
    }
    img
}

/// Renders `plot` at 900 x 500 pixels and writes it as PNG.
pub fn save_line_plot(plot: &LinePlot, path: &Path) -> anyhow::Result<()> {
    render_line_plot(plot, 900, 500)
        .save(path)
        .with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_glyph_is_five_by_seven() {
        for c in (' '..='~').chain(['é']) {
            for row in glyph(c) {
                assert_eq!(row.len(), GLYPH_W as usize, "{c:?}");
            }
            assert_eq!(glyph(c).len(), GLYPH_H as usize);
        }
    }

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(3.0, 3.0, 5), vec![3.0]);
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(100.0), "100");
    }

    #[test]
    fn plots_draw_without_data_and_with_bad_data() {
        let mut p = LinePlot {
            title: "empty".into(),
            ..Default::default()
        };
        let img = render_line_plot(&p, 300, 200);
        assert_eq!(img.dimensions(), (300, 200));
        p.series.push(Series {
            name: "nan".into(),
            points: vec![
                (f64::NAN, 1.0),
                (1.0, f64::INFINITY),
                (2.0, 3.0),
                (1e300, -1e300),
            ],
        });
        p.log_x = true;
        render_line_plot(&p, 300, 200);
    }
}
