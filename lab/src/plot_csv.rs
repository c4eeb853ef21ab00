//! `acuity plot`: a line plot (PNG and SVG) of two columns of a CSV file that acuity
//! (or a script around it) wrote, one line per group of rows, so that a
//! sweep's table comes with its picture.
//!
//! The CSV is the plain kind acuity writes: a header row of column names,
//! then rows of comma-separated fields with no quoting. Rows whose x or y
//! field is not a finite number are left out (and counted in the message).
//! Each line joins its points in order of x, so a file whose rows are not
//! sorted (sweeps appended run by run) still draws each curve once; points
//! with the same x keep the file's order.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Context, bail};

use crate::error::input_error;
use crate::plot::{LinePlot, Series, save_line_plot};

/// Arguments of `acuity plot`.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct PlotArgs {
    /// The CSV file.
    pub csv: PathBuf,
    /// The column on the x axis.
    #[cfg_attr(feature = "clap", arg(long))]
    pub x: String,
    /// The column on the y axis.
    #[cfg_attr(feature = "clap", arg(long))]
    pub y: String,
    /// Columns whose values name a line (one line per distinct
    /// combination), comma-separated; none: one line.
    #[cfg_attr(feature = "clap", arg(long, value_delimiter = ','))]
    pub group: Vec<String>,
    /// Keep only rows whose COLUMN has VALUE (repeatable; all must hold).
    #[cfg_attr(feature = "clap", arg(long = "filter", value_name = "COLUMN=VALUE", value_parser = parse_filter))]
    pub filters: Vec<(String, String)>,
    /// Logarithmic x axis.
    #[cfg_attr(feature = "clap", arg(long))]
    pub log_x: bool,
    /// The plot's title (default: `Y against X`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub title: Option<String>,
    /// The PNG to write; the SVG goes beside it (extension `svg`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: PathBuf,
}

/// Parses a `--filter` value, `COLUMN=VALUE`: the column and the value.
pub fn parse_filter(text: &str) -> Result<(String, String), String> {
    text.split_once('=')
        .map(|(c, v)| (c.trim().to_owned(), v.trim().to_owned()))
        .ok_or_else(|| format!("`{text}` is not COLUMN=VALUE"))
}

/// The lines of a plot from CSV `text`: `(name, points)` per group, in
/// order of the group's name, points in order of x (file order among equal
/// x); and how many kept rows had no number where x or y should be.
pub fn series_from_csv(text: &str, args: &PlotArgs) -> anyhow::Result<(Vec<Series>, usize)> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines
        .next()
        .context("the file is empty: no header row")?
        .split(',')
        .map(str::trim)
        .collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .with_context(|| format!("no column `{name}` (columns: {})", header.join(", ")))
    };
    let (xi, yi) = (column(&args.x)?, column(&args.y)?);
    let groups: Vec<usize> = args
        .group
        .iter()
        .map(|g| column(g))
        .collect::<Result<_, _>>()?;
    let filters: Vec<(usize, &str)> = args
        .filters
        .iter()
        .map(|(c, v)| Ok((column(c)?, v.as_str())))
        .collect::<anyhow::Result<_>>()?;
    let mut by_group: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut skipped = 0;
    for (n, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != header.len() {
            bail!(
                "row {} has {} fields, the header {}",
                n + 2,
                fields.len(),
                header.len()
            );
        }
        if filters.iter().any(|&(c, v)| fields[c] != v) {
            continue;
        }
        let number = |i: usize| fields[i].parse::<f64>().ok().filter(|v| v.is_finite());
        let (Some(x), Some(y)) = (number(xi), number(yi)) else {
            skipped += 1;
            continue;
        };
        let name = groups
            .iter()
            .map(|&g| fields[g])
            .collect::<Vec<_>>()
            .join(" ");
        by_group.entry(name).or_default().push((x, y));
    }
    let series = by_group
        .into_iter()
        .map(|(name, mut points)| {
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                name: if name.is_empty() {
                    args.y.clone()
                } else {
                    name
                },
                points,
            }
        })
        .collect();
    Ok((series, skipped))
}

/// Runs `acuity plot`: reads the CSV, writes the PNG and the SVG.
pub fn plot(args: &PlotArgs) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(&args.csv)
        .map_err(|e| input_error(format!("reading {}: {e}", args.csv.display())))?;
    let (series, skipped) = series_from_csv(&text, args).map_err(|e| {
        input_error(format!(
            "{}: {}",
            args.csv.display(),
            crate::error::error_line(&e)
        ))
    })?;
    if series.iter().all(|s| s.points.is_empty()) {
        crate::bail_input!("{}: no row has numbers in both columns", args.csv.display());
    }
    let plot = LinePlot {
        title: args
            .title
            .clone()
            .unwrap_or_else(|| format!("{} against {}", args.y, args.x)),
        x_label: args.x.clone(),
        y_label: args.y.clone(),
        series,
        log_x: args.log_x,
        markers: true,
        y_from_zero: false,
    };
    save_line_plot(&plot, &args.out)?;
    let note = if skipped > 0 {
        format!(" ({skipped} rows without numbers left out)")
    } else {
        String::new()
    };
    eprintln!(
        "wrote {} and {}{note}",
        args.out.display(),
        args.out.with_extension("svg").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(group: &[&str], filters: &[(&str, &str)]) -> PlotArgs {
        PlotArgs {
            csv: PathBuf::new(),
            x: "rate".into(),
            y: "jod".into(),
            group: group.iter().map(|s| s.to_string()).collect(),
            filters: filters
                .iter()
                .map(|(c, v)| (c.to_string(), v.to_string()))
                .collect(),
            log_x: false,
            title: None,
            out: PathBuf::new(),
        }
    }

    const CSV: &str = "rate,eyes,policy,jod\n0,fixed,full,10\n0,fixed,all,9.5\n30,fixed,all,9.1\n30,free,all,8\n60,fixed,all,NaN\n";

    #[test]
    fn rows_group_filter_and_skip_non_numbers() {
        let (s, skipped) = series_from_csv(CSV, &args(&["policy"], &[("eyes", "fixed")])).unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].name, "all");
        assert_eq!(s[0].points, vec![(0.0, 9.5), (30.0, 9.1)]);
        assert_eq!(s[1].points, vec![(0.0, 10.0)]);
        assert_eq!(skipped, 1);
        let (one, _) = series_from_csv(CSV, &args(&[], &[])).unwrap();
        assert_eq!(one.len(), 1);
        assert_eq!(one[0].name, "jod");
    }

    #[test]
    fn each_line_joins_its_points_in_order_of_x() {
        let csv = "rate,eyes,policy,jod\n30,fixed,all,9.1\n0,fixed,all,9.5\n15,fixed,all,9.3\n15,fixed,all,9.2\n";
        let (s, _) = series_from_csv(csv, &args(&["policy"], &[])).unwrap();
        assert_eq!(
            s[0].points,
            vec![(0.0, 9.5), (15.0, 9.3), (15.0, 9.2), (30.0, 9.1)]
        );
    }

    #[test]
    fn bad_input_names_the_problem() {
        let e = series_from_csv(CSV, &args(&["nope"], &[])).unwrap_err();
        assert!(e.to_string().contains("no column `nope`"), "{e}");
        let e = series_from_csv("", &args(&[], &[])).unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
        let e = series_from_csv("rate,jod\n1,2,3\n", &args(&[], &[])).unwrap_err();
        assert!(e.to_string().contains("row 2 has 3 fields"), "{e}");
        assert!(parse_filter("eyes").is_err());
    }
}
