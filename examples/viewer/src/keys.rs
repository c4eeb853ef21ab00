//! The viewer's keys, as actions: which key does what is decided here,
//! what an action does in the viewer's window loop.

use winit::keyboard::{Key, NamedKey};

/// What a key press asks the viewer to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Show the next policy (Tab or P).
    NextPolicy,
    /// Turn the LOD colour overlay on or off (O).
    ToggleOverlay,
    /// Halve the scale factor `s` (`[`).
    HalveScale,
    /// Double the scale factor `s` (`]`).
    DoubleScale,
    /// Pause or resume the camera path (Space).
    TogglePause,
    /// One frame back while paused (Left).
    StepBack,
    /// One frame on while paused (Right).
    StepForward,
    /// Quit (Esc).
    Quit,
}

impl Action {
    /// Whether holding the key down repeats the action (stepping does;
    /// toggles and scale changes act once per press).
    pub fn repeats(self) -> bool {
        matches!(self, Action::StepBack | Action::StepForward)
    }
}

/// The action of a key by its logical meaning (the layout's character, so
/// `[` is `[` wherever the layout puts it); `None` for other keys.
pub fn action(key: &Key) -> Option<Action> {
    match key {
        Key::Named(named) => match named {
            NamedKey::Tab => Some(Action::NextPolicy),
            NamedKey::Space => Some(Action::TogglePause),
            NamedKey::ArrowLeft => Some(Action::StepBack),
            NamedKey::ArrowRight => Some(Action::StepForward),
            NamedKey::Escape => Some(Action::Quit),
            _ => None,
        },
        Key::Character(c) => match c.as_str() {
            "p" | "P" => Some(Action::NextPolicy),
            "o" | "O" => Some(Action::ToggleOverlay),
            "[" => Some(Action::HalveScale),
            "]" => Some(Action::DoubleScale),
            " " => Some(Action::TogglePause),
            _ => None,
        },
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ch(c: &str) -> Key {
        Key::Character(c.into())
    }

    #[test]
    fn each_documented_key_has_its_action() {
        let cases = [
            (Key::Named(NamedKey::Tab), Action::NextPolicy),
            (ch("p"), Action::NextPolicy),
            (ch("P"), Action::NextPolicy),
            (ch("o"), Action::ToggleOverlay),
            (ch("O"), Action::ToggleOverlay),
            (ch("["), Action::HalveScale),
            (ch("]"), Action::DoubleScale),
            (Key::Named(NamedKey::Space), Action::TogglePause),
            (ch(" "), Action::TogglePause),
            (Key::Named(NamedKey::ArrowLeft), Action::StepBack),
            (Key::Named(NamedKey::ArrowRight), Action::StepForward),
            (Key::Named(NamedKey::Escape), Action::Quit),
        ];
        for (key, want) in cases {
            assert_eq!(action(&key), Some(want), "{key:?}");
        }
    }

    #[test]
    fn other_keys_do_nothing_and_only_steps_repeat() {
        for key in [ch("q"), ch("{"), Key::Named(NamedKey::Enter)] {
            assert_eq!(action(&key), None, "{key:?}");
        }
        assert!(Action::StepBack.repeats() && Action::StepForward.repeats());
        assert!(!Action::ToggleOverlay.repeats() && !Action::HalveScale.repeats());
    }
}
