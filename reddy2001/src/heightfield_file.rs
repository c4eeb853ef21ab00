//! Heightfield files for `acuity terrain --heightfield`: a grey PNG (8 or
//! 16 bits, scaled to a height range) or a raw grid of little-endian `f32`
//! heights in metres (`.f32` or `.raw`, its size given by `--grid`, since
//! the file has no header). Both are read with the first row north (the
//! top of an image, as GIS tools write DEMs) and one sample per pixel or
//! value; the terrain's `y` grows northward, so rows are flipped.

use std::path::Path;

use acuity::terrain::{Heightfield, MAX_HEIGHTFIELD_SIDE};
use anyhow::Context;

/// How a heightfield file's samples become heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightfieldFormat {
    /// Metres between samples (finite, > 0).
    pub spacing_m: f32,
    /// Height of white in a PNG, m (finite, > 0); unused for raw grids.
    pub height_range_m: f32,
    /// Columns and rows of a raw grid (required for raw files, refused for
    /// PNGs, whose size is their own).
    pub grid: Option<[u32; 2]>,
}

/// Parses `--grid COLUMNSxROWS` (two whole numbers; [`load`] checks their
/// range against the heightfield's limits).
pub fn parse_grid(text: &str) -> Result<[u32; 2], String> {
    acuity_lab::parse::parse_pair(text, "COLUMNSxROWS", |s| {
        s.parse::<u32>()
            .map_err(|_| format!("`{s}` in `{text}` is not a whole number of samples"))
    })
}

/// Whether `path` names a raw `f32` grid (by its extension: `f32` or
/// `raw`, any case) rather than an image.
pub fn is_raw(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("f32") || e.eq_ignore_ascii_case("raw"))
}

/// Reads a heightfield file (see the module docs). Errors name the file
/// and what is wrong with it.
pub fn load(path: &Path, format: &HeightfieldFormat) -> anyhow::Result<Heightfield> {
    if is_raw(path) {
        let Some(grid) = format.grid else {
            acuity_lab::bail_input!(
                "{}: a raw f32 heightfield needs its size: --grid COLUMNSxROWS",
                path.display()
            );
        };
        load_raw(path, grid, format.spacing_m)
    } else {
        if let Some([w, h]) = format.grid {
            acuity_lab::bail_input!(
                "--grid {w}x{h} is for raw f32 heightfields (.f32, .raw); {} is read as an image of its own size",
                path.display()
            );
        }
        load_png(path, format.spacing_m, format.height_range_m)
    }
}

/// A grey PNG: black is 0 m, white `range_m`.
fn load_png(path: &Path, spacing_m: f32, range_m: f32) -> anyhow::Result<Heightfield> {
    if !(range_m.is_finite() && range_m > 0.0) {
        acuity_lab::bail_input!("--height-range-m {range_m} is not a finite height > 0");
    }
    let grey = image::open(path)
        .with_context(|| format!("reading {}", path.display()))?
        .to_luma16();
    let (w, h) = (grey.width() as usize, grey.height() as usize);
    let mut heights = vec![0.0f32; w * h];
    for (x, y, p) in grey.enumerate_pixels() {
        let j = h - 1 - y as usize;
        heights[j * w + x as usize] = p.0[0] as f32 / 65535.0 * range_m;
    }
    Heightfield::new(w, h, spacing_m, heights).with_context(|| format!("{}", path.display()))
}

/// A raw grid of `columns x rows` little-endian `f32` heights in metres,
/// row-major, first row north.
fn load_raw(path: &Path, [columns, rows]: [u32; 2], spacing_m: f32) -> anyhow::Result<Heightfield> {
    let side = 2..=MAX_HEIGHTFIELD_SIDE as u64;
    if !(side.contains(&u64::from(columns)) && side.contains(&u64::from(rows))) {
        acuity_lab::bail_input!(
            "--grid {columns}x{rows}: each side must be 2 to {MAX_HEIGHTFIELD_SIDE} samples"
        );
    }
    let expected = u64::from(columns) * u64::from(rows) * 4;
    let actual = std::fs::metadata(path)
        .with_context(|| format!("reading {}", path.display()))?
        .len();
    if actual != expected {
        acuity_lab::bail_input!(
            "{}: {actual} bytes, but --grid {columns}x{rows} needs {columns} x {rows} x 4 = {expected} bytes of f32",
            path.display()
        );
    }
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    if bytes.len() as u64 != expected {
        anyhow::bail!(
            "{}: changed size while read ({} bytes, {expected} expected)",
            path.display(),
            bytes.len()
        );
    }
    let (w, h) = (columns as usize, rows as usize);
    let mut heights = vec![0.0f32; w * h];
    for (n, value) in bytes.chunks_exact(4).enumerate() {
        let height_m = f32::from_le_bytes([value[0], value[1], value[2], value[3]]);
        let (row, column) = (n / w, n % w);
        if !height_m.is_finite() {
            acuity_lab::bail_input!(
                "{}: the sample at row {row} (from the first, north), column {column} is {height_m}; heights must be finite metres",
                path.display()
            );
        }
        heights[(h - 1 - row) * w + column] = height_m;
    }
    Heightfield::new(w, h, spacing_m, heights).with_context(|| format!("{}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder for one test's files.
    fn folder(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("acuity-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn raw_bytes(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn format(grid: Option<[u32; 2]>) -> HeightfieldFormat {
        HeightfieldFormat {
            spacing_m: 10.0,
            height_range_m: 1000.0,
            grid,
        }
    }

    fn error(path: &Path, grid: Option<[u32; 2]>) -> String {
        format!("{:#}", load(path, &format(grid)).unwrap_err())
    }

    #[test]
    fn a_grey_png_loads_with_its_top_row_north() {
        let dir = folder("heightfield-png");
        let path = dir.join("h.png");
        let mut img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::new(3, 2);
        img.put_pixel(0, 0, image::Luma([65535]));
        img.put_pixel(2, 1, image::Luma([32768]));
        img.save(&path).unwrap();
        let field = load(&path, &format(None)).unwrap();
        assert_eq!(field.size(), [3, 2]);
        assert_eq!(field.at(0, 1), 1000.0); // top-left: north-west
        assert!((field.at(2, 0) - 500.0).abs() < 0.1);
        assert_eq!(field.at(1, 0), 0.0);
        let flat = HeightfieldFormat {
            height_range_m: 0.0,
            ..format(None)
        };
        assert!(load(&path, &flat).is_err());
        assert!(error(&dir.join("none.png"), None).contains("none.png"));
        let e = error(&path, Some([3, 2]));
        assert!(e.contains("--grid 3x2 is for raw f32"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_raw_grid_loads_in_metres_with_its_first_row_north() {
        let dir = folder("heightfield-raw");
        // 3 columns x 2 rows; the first row is the northern one.
        let north = [100.0, -2.5, 7.25];
        let south = [0.0, 1e4, 3.0];
        for name in ["h.f32", "h.RAW"] {
            let path = dir.join(name);
            std::fs::write(&path, raw_bytes(&[north, south].concat())).unwrap();
            assert!(is_raw(&path));
            let field = load(&path, &format(Some([3, 2]))).unwrap();
            assert_eq!(field.size(), [3, 2]);
            assert_eq!(field.spacing(), 10.0);
            for i in 0..3 {
                assert_eq!(field.at(i, 1), north[i], "north, column {i}");
                assert_eq!(field.at(i, 0), south[i], "south, column {i}");
            }
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_raw_grid_of_the_wrong_size_is_refused_with_both_sizes() {
        let dir = folder("heightfield-raw-size");
        let path = dir.join("h.f32");
        std::fs::write(&path, raw_bytes(&[0.0; 5])).unwrap();
        let e = error(&path, Some([3, 2]));
        assert!(e.contains("h.f32"), "{e}");
        assert!(e.contains("20 bytes"), "{e}");
        assert!(e.contains("3 x 2 x 4 = 24 bytes"), "{e}");
        std::fs::write(&path, &raw_bytes(&[0.0; 6])[..23]).unwrap();
        assert!(error(&path, Some([3, 2])).contains("23 bytes"));
        // Sizes whose byte count overflows 32 bits are compared exactly.
        let e = error(&path, Some([65_537, 65_537]));
        assert!(e.contains("17180393476 bytes"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_non_finite_raw_sample_is_refused_with_its_row_and_column() {
        let dir = folder("heightfield-raw-nan");
        let path = dir.join("h.raw");
        for (bad, shown) in [(f32::NAN, "NaN"), (f32::INFINITY, "inf")] {
            let mut values = [1.0f32; 6];
            values[5] = bad; // row 1, column 2
            std::fs::write(&path, raw_bytes(&values)).unwrap();
            let e = error(&path, Some([3, 2]));
            assert!(e.contains("row 1"), "{e}");
            assert!(e.contains("column 2"), "{e}");
            assert!(e.contains(shown), "{e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn grid_sizes_parse_as_columns_by_rows() {
        assert_eq!(parse_grid("661x847"), Ok([661, 847]));
        assert_eq!(parse_grid("3X2"), Ok([3, 2]));
        assert!(parse_grid("661").unwrap_err().contains("COLUMNSxROWS"));
        assert!(parse_grid("661x-1").unwrap_err().contains("`-1`"));
    }

    #[test]
    fn a_raw_grid_needs_a_size_of_at_least_two_by_two() {
        let dir = folder("heightfield-raw-grid");
        let path = dir.join("h.f32");
        std::fs::write(&path, raw_bytes(&[0.0; 4])).unwrap();
        let e = error(&path, None);
        assert!(e.contains("--grid COLUMNSxROWS"), "{e}");
        for grid in [[1, 4], [4, 1], [0, 0], [65_538, 2]] {
            let e = error(&path, Some(grid));
            assert!(e.contains("each side must be 2 to 65537"), "{grid:?}: {e}");
        }
        let e = error(&dir.join("none.f32"), Some([2, 2]));
        assert!(e.contains("none.f32"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
