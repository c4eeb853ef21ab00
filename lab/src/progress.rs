//! Progress bars on stderr for the commands' long loops (played frames x
//! policies), hidden when stderr is not a terminal (logs, pipes, tests) or
//! with `--quiet`. Messages printed while a bar runs go through
//! [`ProgressBar::suspend`], so they stay visible and the bar is redrawn
//! below them.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A bar counting `total` steps of `unit` (e.g. `frames`), drawn on stderr
/// unless `quiet` or stderr is not a terminal.
pub fn bar(total: u64, unit: &str, quiet: bool) -> ProgressBar {
    let target = if quiet || !std::io::stderr().is_terminal() {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let bar = ProgressBar::with_draw_target(Some(total), target);
    let template = format!("{{bar:30}} {{pos}}/{{len}} {unit}  {{elapsed_precise}}  {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quiet_bar_is_hidden_and_still_counts() {
        let b = bar(6, "frames", true);
        assert!(b.is_hidden());
        b.inc(4);
        assert_eq!(b.position(), 4);
        assert_eq!(b.length(), Some(6));
    }
}
