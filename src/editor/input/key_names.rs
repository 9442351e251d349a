//! Keys by name, as the help overlay writes them and scripts and declarations name them:
//! `"C"`, `"F9"`, `"Right"`, and chords of modifiers and a key joined by `+` (`"Alt+C"`,
//! `"Ctrl+Shift+S"`).

use bevy::prelude::KeyCode;

/// A key with exactly these modifiers held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chord {
    /// The key.
    pub key: KeyCode,
    /// Ctrl is held.
    pub ctrl: bool,
    /// Shift is held.
    pub shift: bool,
    /// Alt is held.
    pub alt: bool,
}

/// Reads a chord: any of `Ctrl+`, `Shift+`, `Alt+`, then a key name ([`key_code`]); `None`
/// for a name it does not know or a modifier given twice.
pub fn chord(text: &str) -> Option<Chord> {
    let mut parts: Vec<&str> = text.split('+').collect();
    let key = parts.pop()?;
    let mut chord = Chord {
        key: key_code(key)?,
        ctrl: false,
        shift: false,
        alt: false,
    };
    for modifier in parts {
        let held = match modifier {
            "Ctrl" => &mut chord.ctrl,
            "Shift" => &mut chord.shift,
            "Alt" => &mut chord.alt,
            _ => return None,
        };
        if std::mem::replace(held, true) {
            return None;
        }
    }
    Some(chord)
}

/// The key a name stands for: a letter or digit, `.`, `-`, `=`, or a name such as `F9`,
/// `Escape`, `Right`, `Delete`.
pub fn key_code(name: &str) -> Option<KeyCode> {
    let single = |c: char| -> Option<KeyCode> {
        const LETTERS: [KeyCode; 26] = [
            KeyCode::KeyA,
            KeyCode::KeyB,
            KeyCode::KeyC,
            KeyCode::KeyD,
            KeyCode::KeyE,
            KeyCode::KeyF,
            KeyCode::KeyG,
            KeyCode::KeyH,
            KeyCode::KeyI,
            KeyCode::KeyJ,
            KeyCode::KeyK,
            KeyCode::KeyL,
            KeyCode::KeyM,
            KeyCode::KeyN,
            KeyCode::KeyO,
            KeyCode::KeyP,
            KeyCode::KeyQ,
            KeyCode::KeyR,
            KeyCode::KeyS,
            KeyCode::KeyT,
            KeyCode::KeyU,
            KeyCode::KeyV,
            KeyCode::KeyW,
            KeyCode::KeyX,
            KeyCode::KeyY,
            KeyCode::KeyZ,
        ];
        const DIGITS: [KeyCode; 10] = [
            KeyCode::Digit0,
            KeyCode::Digit1,
            KeyCode::Digit2,
            KeyCode::Digit3,
            KeyCode::Digit4,
            KeyCode::Digit5,
            KeyCode::Digit6,
            KeyCode::Digit7,
            KeyCode::Digit8,
            KeyCode::Digit9,
        ];
        let c = c.to_ascii_uppercase();
        match c {
            'A'..='Z' => Some(LETTERS[(c as u8 - b'A') as usize]),
            '0'..='9' => Some(DIGITS[(c as u8 - b'0') as usize]),
            '.' => Some(KeyCode::Period),
            _ => None,
        }
    };
    match name {
        "Period" => Some(KeyCode::Period),
        "Escape" => Some(KeyCode::Escape),
        "F1" => Some(KeyCode::F1),
        "F9" => Some(KeyCode::F9),
        "Right" => Some(KeyCode::ArrowRight),
        "Left" => Some(KeyCode::ArrowLeft),
        "End" => Some(KeyCode::End),
        "PageUp" => Some(KeyCode::PageUp),
        "PageDown" => Some(KeyCode::PageDown),
        "Delete" => Some(KeyCode::Delete),
        "Enter" => Some(KeyCode::Enter),
        "Backspace" => Some(KeyCode::Backspace),
        "Minus" | "-" => Some(KeyCode::Minus),
        "Equal" | "=" => Some(KeyCode::Equal),
        _ if name.chars().count() == 1 => single(name.chars().next()?),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_letter_and_digit_key_has_a_name() {
        for c in ('A'..='Z').chain('0'..='9') {
            assert!(key_code(&c.to_string()).is_some(), "{c}");
        }
        assert_eq!(key_code("m"), Some(KeyCode::KeyM));
        assert_eq!(key_code("7"), Some(KeyCode::Digit7));
        assert_eq!(key_code("Escape"), Some(KeyCode::Escape));
        assert_eq!(key_code("MM"), None);
    }

    #[test]
    fn chords_read_as_the_help_writes_them() {
        assert_eq!(
            chord("Alt+C"),
            Some(Chord {
                key: KeyCode::KeyC,
                ctrl: false,
                shift: false,
                alt: true
            })
        );
        let save_as = chord("Ctrl+Shift+S").unwrap();
        assert!(save_as.ctrl && save_as.shift && !save_as.alt && save_as.key == KeyCode::KeyS);
        assert_eq!(chord("Ctrl+-").map(|c| c.key), Some(KeyCode::Minus));
        assert_eq!(chord("F9").map(|c| c.key), Some(KeyCode::F9));
        assert_eq!(chord("Hyper+C"), None);
        assert_eq!(chord("Alt+Alt+C"), None);
        assert_eq!(chord("Alt+Nowhere"), None);
    }
}
