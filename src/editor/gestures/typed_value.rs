//! A value typed during a gesture (`G` then `2.5`): the character each key adds to it.

use bevy::prelude::KeyCode;

/// The character `key` types into a gesture's value (a digit, the decimal point, a minus), on
/// the main row or the number pad; `None` for any other key.
pub fn typed_char(key: KeyCode) -> Option<char> {
    Some(match key {
        KeyCode::Digit0 | KeyCode::Numpad0 => '0',
        KeyCode::Digit1 | KeyCode::Numpad1 => '1',
        KeyCode::Digit2 | KeyCode::Numpad2 => '2',
        KeyCode::Digit3 | KeyCode::Numpad3 => '3',
        KeyCode::Digit4 | KeyCode::Numpad4 => '4',
        KeyCode::Digit5 | KeyCode::Numpad5 => '5',
        KeyCode::Digit6 | KeyCode::Numpad6 => '6',
        KeyCode::Digit7 | KeyCode::Numpad7 => '7',
        KeyCode::Digit8 | KeyCode::Numpad8 => '8',
        KeyCode::Digit9 | KeyCode::Numpad9 => '9',
        KeyCode::Period | KeyCode::NumpadDecimal => '.',
        KeyCode::Minus | KeyCode::NumpadSubtract => '-',
        _ => return None,
    })
}
