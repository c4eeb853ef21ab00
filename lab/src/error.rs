//! The lab's input error and its one-line printing, a leaf module: the
//! scene format, the world, the experiments and the commands raise
//! [`InputError`] for values the user gave that cannot be used, and a
//! caller (the command line's exit codes among them) tells input's fault
//! from a failure while running by finding it, or another typed input
//! error, along an error's cause chain.

/// A value the user gave that the lab cannot use (an argument, an
/// override, a file's contents): the input's fault, not a failure while
/// running.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// An [`InputError`] as an [`anyhow::Error`]:
/// `return Err(input_error(format!(...)))`.
pub fn input_error(message: impl Into<String>) -> anyhow::Error {
    InputError(message.into()).into()
}

/// `anyhow::bail!` for input errors: returns an [`InputError`] with the
/// formatted message from the enclosing function.
#[macro_export]
macro_rules! bail_input {
    ($($arg:tt)*) => {
        return Err($crate::error::input_error(format!($($arg)*)))
    };
}

/// An error and its causes on one line, `error: cause: ...`, as the
/// commands print them. A cause whose text ends its parent's is left out:
/// some errors (I/O errors with their file) print their cause and also
/// return it as their source.
pub fn error_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.ends_with(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_io_error_prints_once() {
        let io = std::io::Error::from(std::io::ErrorKind::IsADirectory);
        let text = io.to_string();
        let e = anyhow::Error::new(acuity::Error::Io {
            path: "cache/rock.acp".into(),
            source: io,
        })
        .context("object `rock`");
        let line = error_line(&e);
        assert_eq!(line, format!("object `rock`: cache/rock.acp: {text}"));
        assert_eq!(format!("{e:#}").matches(&text).count(), 2, "{e:#}");
    }
}
