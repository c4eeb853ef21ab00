//! Frame dumps, and scoring them with FovVideoVDP.
//!
//! FLIP judges single frames at the fovea; a foveated, temporal metric
//! needs whole sequences with the gaze (FovVideoVDP, Mantiuk et al. 2021). A dump folder holds
//! `display.json` and, per played sequence, `<policy>_<knob>/NNNN.png` (RGB,
//! the frame as rendered) and `<policy>_<knob>/gaze.csv` (`frame,x_px,y_px`).
//! [`score_fvvdp`] runs `lab/scripts/fvvdp_score.py` (built into the binary) on
//! one, as an external Python process with `pyfvvdp`.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{Context, bail};
use glam::DVec3;

use crate::scene::{DisplaySpec, Policy};

/// The name of full detail's sequence, the reference every other is
/// scored against.
pub const REFERENCE_SEQUENCE: &str = "full_1";

/// The environment variable naming the Python interpreter (default
/// `python3`).
pub const PYTHON_ENV: &str = "ACUITY_PYTHON";

/// The scoring script, `lab/scripts/fvvdp_score.py`.
pub const FVVDP_SCRIPT: &str = include_str!("../scripts/fvvdp_score.py");

/// Exit code of the script when `pyfvvdp` cannot be imported.
const EXIT_NO_PYFVVDP: i32 = 3;

/// The error metrics `acuity run` and `acuity experiment error` compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Metric {
    /// FLIP (nv-flip) on sampled frames: foveal, per image.
    Flip,
    /// FovVideoVDP (pyfvvdp) on whole dumped sequences: foveated at the
    /// gaze, temporal; in JOD (10 = identical).
    Fvvdp,
}

/// A sequence's folder name: the policy and its knob as the experiments'
/// CSV prints it (`full_1`, `screen_size_0.5`, `acuity_size_0.0625`).
pub fn sequence_name(policy: Policy, knob: f64) -> String {
    format!("{}_{knob}", policy.name())
}

/// A dump being written: PNGs as frames come, `gaze.csv` and
/// `display.json` on [`FrameDump::finish`].
#[derive(Debug)]
pub struct FrameDump {
    root: PathBuf,
    resolution_px: [u32; 2],
    fov_deg: [f64; 2],
    /// Left, right, up, down, deg ([`DisplaySpec::fov_edges_deg`]).
    fov_edges_deg: [f64; 4],
    /// Peak luminance (cd/m²), contrast ratio and ambient light (lux): the
    /// scene's display photometry, as the selection used it.
    photometry: [f64; 3],
    fps: f64,
    /// Per sequence, in order of first frame: its `gaze.csv` text.
    sequences: Vec<(String, String)>,
}

impl FrameDump {
    /// A dump into `root` (created) of frames of `display`, `dt_s` apart.
    pub fn create(root: &Path, display: &DisplaySpec, dt_s: f64) -> anyhow::Result<FrameDump> {
        std::fs::create_dir_all(root).with_context(|| format!("creating {}", root.display()))?;
        Ok(FrameDump {
            root: root.to_owned(),
            resolution_px: display.resolution_px,
            fov_deg: display.fov_deg,
            fov_edges_deg: display.fov_edges_deg,
            photometry: [
                display.peak_luminance_cd_m2,
                display.contrast_ratio,
                display.ambient_lux,
            ],
            fps: 1.0 / dt_s,
            sequences: Vec::new(),
        })
    }

    /// The gaze point of a frame, in pixels
    /// ([`acuity::display::direction_to_pixel_in_edges`]).
    pub fn gaze_pixel(&self, gaze_camera: DVec3) -> [f64; 2] {
        acuity::display::direction_to_pixel_in_edges(
            gaze_camera,
            self.resolution_px,
            self.fov_edges_deg,
        )
    }

    /// Writes frame `frame` of `sequence` (RGBA8 sRGB, alpha dropped) and
    /// records its gaze point in pixels.
    pub fn write_frame(
        &mut self,
        sequence: &str,
        frame: u32,
        rgba: &[u8],
        gaze_px: [f64; 2],
    ) -> anyhow::Result<()> {
        let [w, h] = self.resolution_px;
        if rgba.len() != 4 * w as usize * h as usize {
            bail!("frame {frame} of {sequence} is not {w}x{h} RGBA");
        }
        let dir = self.root.join(sequence);
        let i = match self.sequences.iter().position(|(n, _)| n == sequence) {
            Some(i) => i,
            None => {
                std::fs::create_dir_all(&dir)
                    .with_context(|| format!("creating {}", dir.display()))?;
                self.sequences
                    .push((sequence.to_owned(), "frame,x_px,y_px\n".to_owned()));
                self.sequences.len() - 1
            }
        };
        let rgb: Vec<u8> = rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let path = dir.join(format!("{frame:04}.png"));
        image::save_buffer(&path, &rgb, w, h, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("writing {}", path.display()))?;
        let _ = writeln!(
            self.sequences[i].1,
            "{frame},{:.3},{:.3}",
            gaze_px[0], gaze_px[1]
        );
        Ok(())
    }

    /// Writes every sequence's `gaze.csv` and `display.json`; returns the
    /// dump folder.
    pub fn finish(self) -> anyhow::Result<PathBuf> {
        for (name, csv) in &self.sequences {
            let path = self.root.join(name).join("gaze.csv");
            std::fs::write(&path, csv).with_context(|| format!("writing {}", path.display()))?;
        }
        let display = serde_json::json!({
            "resolution": self.resolution_px,
            "fov_deg": self.fov_deg,
            "fps": self.fps,
            "peak_cd_m2": self.photometry[0],
            "contrast": self.photometry[1],
            "ambient_lux": self.photometry[2],
            "sequences": self.sequences.iter().map(|(n, _)| n).collect::<Vec<_>>(),
        });
        let path = self.root.join("display.json");
        std::fs::write(&path, format!("{display:#}\n"))
            .with_context(|| format!("writing {}", path.display()))?;
        Ok(self.root)
    }
}

/// The Python interpreter: `$ACUITY_PYTHON`, else `python3`.
pub fn python() -> OsString {
    std::env::var_os(PYTHON_ENV)
        .filter(|p| !p.is_empty())
        .unwrap_or_else(|| "python3".into())
}

/// Runs the scoring script (fed on stdin) with `args`; its stdout. Errors
/// say how to get a Python with `pyfvvdp`.
fn run_script(args: &[&std::ffi::OsStr], quiet: bool) -> anyhow::Result<String> {
    let py = python();
    let shown = py.to_string_lossy().into_owned();
    let whence = if std::env::var_os(PYTHON_ENV).is_some_and(|p| !p.is_empty()) {
        format!("from ${PYTHON_ENV}")
    } else {
        format!("the default; set ${PYTHON_ENV} to choose another")
    };
    let mut child = Command::new(&py)
        .arg("-")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(if quiet {
            Stdio::piped()
        } else {
            Stdio::inherit()
        })
        .spawn()
        .with_context(|| {
            format!(
                "FovVideoVDP: cannot run the Python interpreter `{shown}` ({whence}); \
                 it needs Python 3 with pyfvvdp (`pip install pyfvvdp`)"
            )
        })?;
    if let Some(mut stdin) = child.stdin.take() {
        // A script that does not read its stdin (a stand-in) may exit first.
        match stdin.write_all(FVVDP_SCRIPT.as_bytes()) {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                return Err(e).context("FovVideoVDP: feeding the script to Python");
            }
            _ => {}
        }
    }
    let out = child
        .wait_with_output()
        .context("FovVideoVDP: waiting for Python")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let last = stderr.lines().rev().find(|l| !l.trim().is_empty());
    match out.status.code() {
        Some(0) => Ok(String::from_utf8_lossy(&out.stdout).into_owned()),
        Some(EXIT_NO_PYFVVDP) => bail!(
            "FovVideoVDP: pyfvvdp is not installed for `{shown}` ({whence}): \
             install it with `{shown} -m pip install pyfvvdp`"
        ),
        _ => bail!(
            "FovVideoVDP: lab/scripts/fvvdp_score.py failed under `{shown}` ({}){}",
            out.status,
            last.map_or_else(|| " (see above)".to_owned(), |l| format!(": {l}"))
        ),
    }
}

/// Checks that the Python interpreter runs and imports `pyfvvdp`, so a
/// long run does not fail only at the end.
pub fn check_fvvdp() -> anyhow::Result<()> {
    run_script(&["--check".as_ref()], true).map(|_| ())
}

/// Scores every sequence of the dump at `dump` against
/// [`REFERENCE_SEQUENCE`] with FovVideoVDP: JOD per sequence name, also
/// written to `<dump>/fvvdp.json`.
pub fn score_fvvdp(dump: &Path, quiet: bool) -> anyhow::Result<BTreeMap<String, f64>> {
    let started = Instant::now();
    let stdout = run_script(&[dump.as_os_str()], quiet)?;
    let scores = parse_scores(&stdout)?;
    let path = dump.join("fvvdp.json");
    let json = serde_json::to_string_pretty(&scores).context("FovVideoVDP: scores to JSON")?;
    std::fs::write(&path, json + "\n").with_context(|| format!("writing {}", path.display()))?;
    if !quiet {
        eprintln!(
            "FovVideoVDP scored {} sequences in {:.1} s ({})",
            scores.len(),
            started.elapsed().as_secs_f64(),
            path.display()
        );
    }
    Ok(scores)
}

/// The scores in the script's output: its last non-empty line, a JSON
/// object of finite numbers.
pub fn parse_scores(stdout: &str) -> anyhow::Result<BTreeMap<String, f64>> {
    let line = stdout
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .context("FovVideoVDP: the script printed no scores")?;
    let scores: BTreeMap<String, f64> = serde_json::from_str(line).with_context(|| {
        format!("FovVideoVDP: the script's output `{line}` is not a JSON object of scores")
    })?;
    if let Some((name, v)) = scores.iter().find(|(_, v)| !v.is_finite()) {
        bail!("FovVideoVDP: score {v} of `{name}` is not finite");
    }
    Ok(scores)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RES: [u32; 2] = [640, 480];
    const FOV: [f64; 2] = [43.6, 33.4];

    use acuity::display::direction_to_pixel as gaze_pixel;

    #[test]
    fn gaze_pixel_maps_centre_corners_and_sides() {
        let c = gaze_pixel(DVec3::NEG_Z, RES, FOV);
        assert_eq!(c, [320.0, 240.0]);
        // The top-left corner of the image: left (-x) and up (+y).
        let tl = DVec3::new(
            -(0.5 * FOV[0]).to_radians().tan(),
            (0.5 * FOV[1]).to_radians().tan(),
            -1.0,
        )
        .normalize();
        let p = gaze_pixel(tl, RES, FOV);
        assert!(p[0].abs() < 1e-9 && p[1].abs() < 1e-9, "{p:?}");
        let right_down = gaze_pixel(DVec3::new(0.1, -0.1, -1.0), RES, FOV);
        assert!(right_down[0] > 320.0 && right_down[1] > 240.0);
        // Behind the viewer: finite, on the side it points to.
        let behind = gaze_pixel(DVec3::new(1.0, 0.0, 1.0), RES, FOV);
        assert!(behind[0].is_finite() && behind[0] > 640.0, "{behind:?}");
        assert_eq!(gaze_pixel(DVec3::ZERO, RES, FOV), [320.0, 240.0]);
    }

    #[test]
    fn sequence_names_print_knobs_as_the_csv_does() {
        assert_eq!(sequence_name(Policy::Full, 1.0), "full_1");
        assert_eq!(
            sequence_name(Policy::AcuitySize, 0.0625),
            "acuity_size_0.0625"
        );
        assert_eq!(sequence_name(Policy::ScreenSize, 0.5), "screen_size_0.5");
    }

    #[test]
    fn scores_parse_from_the_last_line_only() {
        let s = parse_scores("loading...\n{\"full_1\": 10.0, \"screen_size_1\": 9.5}\n\n").unwrap();
        assert_eq!(s["screen_size_1"], 9.5);
        assert!(parse_scores("").is_err());
        assert!(parse_scores("9.5\n").is_err());
        assert!(parse_scores("{\"a\": \"x\"}").is_err());
    }
}
