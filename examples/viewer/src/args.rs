//! The viewer's command line: a scene file and a few options for
//! automated runs. Parsed by hand (five options do not need `clap`); a bad
//! argument is an input error (exit code 2).

use std::ffi::OsString;
use std::path::PathBuf;

use acuity_lab::error::input_error;
use acuity_lab::scene::{Policy, policy_by_name};

/// The scene played when none is given, relative to the current folder.
pub const DEFAULT_SCENE: &str = "scenes/default.toml";

/// The policy shown first when `--policy` is not given.
pub const DEFAULT_POLICY: Policy = Policy::AcuityAll;

/// The usage text of `--help`.
pub const USAGE: &str = "\
usage: acuity-viewer [SCENE.toml] [--policy NAME] [--overlay] [--frames N] [--screenshot FILE.png]

Flies through SCENE's camera path in real time, looping (default scenes/default.toml).
  --policy NAME          the LOD policy shown first (default acuity_all)
  --overlay              start with the LOD colour overlay on
  --frames N             quit after N frames (N >= 1)
  --screenshot FILE.png  on quitting, write the last frame shown to FILE.png
                         (at the scene's resolution, overlay included)
keys: Tab/P policy, O overlay, [ ] halve/double s, Space pause,
      Left/Right step a frame while paused, Esc quit";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Print [`USAGE`] and exit.
    Help,
    /// Open the viewer.
    View(Options),
}

/// The viewer's options.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// The policy shown first.
    pub policy: Policy,
    /// Whether the LOD overlay starts on.
    pub overlay: bool,
    /// Quit after this many frames (>= 1); `None`: run until closed.
    pub frames: Option<u32>,
    /// Where to write the last frame shown (at the scene's resolution,
    /// as rendered, overlay included), a `.png` file.
    pub screenshot: Option<PathBuf>,
}

/// Parses the arguments after the program name. Errors are input errors
/// ([`acuity_lab::error::InputError`]) naming the argument at fault.
pub fn parse(args: impl IntoIterator<Item = OsString>) -> anyhow::Result<Command> {
    let mut scene: Option<PathBuf> = None;
    let mut options = Options {
        scene: PathBuf::from(DEFAULT_SCENE),
        policy: DEFAULT_POLICY,
        overlay: false,
        frames: None,
        screenshot: None,
    };
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let text = arg
            .to_str()
            .map(str::to_owned)
            .filter(|t| t.starts_with('-') && t.len() > 1);
        let Some(text) = text else {
            if scene.replace(PathBuf::from(&arg)).is_some() {
                return Err(input_error(format!(
                    "unexpected argument `{}`: give one scene file",
                    arg.to_string_lossy()
                )));
            }
            continue;
        };
        let (flag, inline) = match text.split_once('=') {
            Some((f, v)) => (f.to_owned(), Some(OsString::from(v))),
            None => (text, None),
        };
        let mut value = |what: &str| {
            inline
                .clone()
                .or_else(|| args.next())
                .ok_or_else(|| input_error(format!("{flag} needs {what}")))
        };
        match flag.as_str() {
            "--help" | "-h" => return Ok(Command::Help),
            "--overlay" => options.overlay = true,
            "--policy" => {
                let name = value("a policy name")?;
                options.policy = policy_by_name(&name.to_string_lossy())
                    .map_err(|e| input_error(format!("--policy: {e}")))?;
            }
            "--frames" => {
                let n = value("a frame count")?;
                let n = n.to_string_lossy();
                options.frames = match n.trim().parse::<u32>() {
                    Ok(k) if k >= 1 => Some(k),
                    _ => {
                        return Err(input_error(format!(
                            "--frames `{n}`: give a whole number from 1 to {}",
                            u32::MAX
                        )));
                    }
                };
            }
            "--screenshot" => {
                let path = PathBuf::from(value("a file name")?);
                let png = path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("png"));
                if !png {
                    return Err(input_error(format!(
                        "--screenshot `{}`: the file name must end in .png",
                        path.display()
                    )));
                }
                options.screenshot = Some(path);
            }
            _ => {
                return Err(input_error(format!("unknown option `{flag}` (see --help)")));
            }
        }
        if inline.is_some() && matches!(flag.as_str(), "--help" | "--overlay") {
            return Err(input_error(format!("{flag} takes no value")));
        }
    }
    if let Some(s) = scene {
        options.scene = s;
    }
    Ok(Command::View(options))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(args: &[&str]) -> anyhow::Result<Command> {
        parse(args.iter().map(OsString::from))
    }

    fn options(args: &[&str]) -> Options {
        match parse_str(args).unwrap() {
            Command::View(o) => o,
            Command::Help => panic!("{args:?} asked for help"),
        }
    }

    fn error(args: &[&str]) -> String {
        let e = parse_str(args).unwrap_err();
        assert!(acuity_lab::blame::blames_input(&e), "{e}");
        e.to_string()
    }

    #[test]
    fn no_arguments_play_the_default_scene_under_acuity_all() {
        let o = options(&[]);
        assert_eq!(o.scene, PathBuf::from("scenes/default.toml"));
        assert_eq!(o.policy, Policy::AcuityAll);
        assert!(!o.overlay && o.frames.is_none() && o.screenshot.is_none());
    }

    #[test]
    fn every_option_in_either_form() {
        let o = options(&[
            "--overlay",
            "scenes/library.toml",
            "--frames",
            "90",
            "--policy=screen_size",
            "--screenshot=/tmp/a.PNG",
        ]);
        assert_eq!(o.scene, PathBuf::from("scenes/library.toml"));
        assert_eq!(o.policy, Policy::ScreenSize);
        assert!(o.overlay);
        assert_eq!(o.frames, Some(90));
        assert_eq!(o.screenshot, Some(PathBuf::from("/tmp/a.PNG")));
        assert_eq!(parse_str(&["x.toml", "--help"]).unwrap(), Command::Help);
        assert_eq!(parse_str(&["-h"]).unwrap(), Command::Help);
    }

    #[test]
    fn bad_arguments_are_input_errors_that_name_them() {
        assert!(error(&["--frames", "0"]).contains("--frames `0`"));
        assert!(error(&["--frames", "ten"]).contains("--frames `ten`"));
        assert!(error(&["--frames"]).contains("--frames needs a frame count"));
        assert!(error(&["--policy", "fastest"]).contains("unknown policy `fastest`"));
        assert!(error(&["--screenshot", "a.jpg"]).contains("must end in .png"));
        assert!(error(&["a.toml", "b.toml"]).contains("unexpected argument `b.toml`"));
        assert!(error(&["--fps"]).contains("unknown option `--fps`"));
        assert!(error(&["-x"]).contains("unknown option `-x`"));
        assert!(error(&["--overlay=yes"]).contains("--overlay takes no value"));
    }
}
