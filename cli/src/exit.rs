//! The commands' exit codes and error printing, one rule for all: 2 when
//! the input is at fault (an argument, or a scene, profile, mesh, CSV or
//! image that does not parse or breaks a rule), 1 when running failed (I/O
//! mid-run, the renderer, a metric script). Clap's own argument errors exit
//! 2 as well (see `main.rs`).
//!
//! An error is input's fault when any error along its cause chain is of an
//! input kind ([`is_input_error`]): the typed errors of the scene, profile
//! and mesh parsers and of the checks of images and threshold tables, and
//! the lab's `InputError`, which the commands raise for values clap cannot
//! check by itself. Everything else is a run-time failure.

use std::process::ExitCode;

use acuity_lab::blame::is_input_kind;
use acuity_lab::error::error_line;
use acuity_reddy2001::foveate::FoveateError;

/// Exit code for bad arguments or bad input.
pub const INPUT: u8 = 2;
/// Exit code for a failure while running.
pub const RUNTIME: u8 = 1;

/// Whether any error along `e`'s cause chain blames the input: the lab's
/// input kinds ([`is_input_kind`]) and the image filter's settings.
pub fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain()
        .any(|cause| is_input_kind(cause) || cause.is::<FoveateError>())
}

/// The exit code for `e`: [`INPUT`] or [`RUNTIME`].
pub fn exit_code(e: &anyhow::Error) -> ExitCode {
    ExitCode::from(if is_input_error(e) { INPUT } else { RUNTIME })
}

/// Ends a command: prints its error (if any) once, on one line
/// ([`error_line`]), and gives the exit code.
pub fn report<T>(result: anyhow::Result<T>) -> ExitCode {
    match result {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_line(&e));
            exit_code(&e)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use acuity_lab::error::input_error;
    use anyhow::Context;

    #[test]
    fn input_kinds_anywhere_in_the_chain_blame_the_input() {
        let e = Err::<(), _>(input_error("--frames must be at least 1"))
            .context("run")
            .unwrap_err();
        assert!(is_input_error(&e));
        let profile = anyhow::Error::new(acuity::Error::ProfileInvalid {
            path: None,
            field: "transitions".into(),
            reason: "empty".into(),
        })
        .context("object `rock`");
        assert!(is_input_error(&profile));
        let mesh = anyhow::Error::new(acuity_render::Error::Parse {
            path: "a.obj".into(),
            line: 3,
            message: "bad face".into(),
        });
        assert!(is_input_error(&mesh));
    }

    #[test]
    fn io_gpu_and_untyped_failures_are_runtime_failures() {
        let io = anyhow::Error::new(acuity::Error::Io {
            path: "out/summary.csv".into(),
            source: std::io::Error::from(std::io::ErrorKind::PermissionDenied),
        });
        assert!(!is_input_error(&io));
        let gpu = anyhow::Error::new(acuity_render::Error::Gpu {
            message: "lost".into(),
        });
        assert!(!is_input_error(&gpu));
        assert!(!is_input_error(&anyhow::anyhow!("FovVideoVDP failed")));
        assert_eq!(exit_code(&gpu), ExitCode::from(RUNTIME));
        assert_eq!(report::<()>(Err(input_error("bad"))), ExitCode::from(INPUT));
        assert_eq!(report(Ok(())), ExitCode::SUCCESS);
    }
}
