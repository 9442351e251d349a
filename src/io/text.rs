//! Small helpers shared by the text formats (OBJ, OFF, ASCII STL): line splitting with
//! comments removed, number parsing that names the line, and a cap for untrusted counts.

use bevy::math::Vec3;
use std::borrow::Cow;

use super::ParseError;

/// Fails on the first NUL byte: a text format that holds one is a binary file.
pub fn check_text(bytes: &[u8]) -> Result<(), ParseError> {
    match bytes.iter().position(|&b| b == 0) {
        Some(at) => Err(ParseError::byte(at, "NUL byte: this is not a text file")),
        None => Ok(()),
    }
}

/// The non-empty lines of a text with `#` comments removed, trimmed, with 1-based line numbers.
///
/// Lines are decoded one by one and leniently: bytes that are not UTF-8 (a Latin-1 comment, a
/// name) become U+FFFD, so they only matter where a number was expected, and the parse error
/// then names their line. Nothing after them is lost.
pub fn lines(bytes: &[u8]) -> impl Iterator<Item = (usize, Cow<'_, str>)> {
    bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .filter_map(|(i, raw)| {
            let code = raw.split(|&b| b == b'#').next().unwrap_or(raw);
            let code = code.trim_ascii();
            if code.is_empty() {
                return None;
            }
            Some((i + 1, String::from_utf8_lossy(code)))
        })
}

/// Parses a float token, naming the line on failure.
pub fn float(token: Option<&str>, line: usize, what: &str) -> Result<f32, ParseError> {
    let token = token.ok_or_else(|| ParseError::line(line, format!("missing {what}")))?;
    token
        .parse::<f32>()
        .map_err(|_| ParseError::line(line, format!("`{token}` is not a number ({what})")))
}

/// Parses the next three tokens as a position; further tokens (a `w`, a colour, a normal) are
/// left for the caller to ignore.
pub fn position<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    line: usize,
) -> Result<Vec3, ParseError> {
    let mut p = [0.0f32; 3];
    for (k, c) in p.iter_mut().enumerate() {
        let Some(token) = tokens.next() else {
            return Err(ParseError::line(
                line,
                format!("expected 3 coordinates, found {k}"),
            ));
        };
        *c = float(Some(token), line, ["x", "y", "z"][k])?;
    }
    Ok(Vec3::from_array(p))
}

/// Parses a non-negative integer token (a vertex index or a count), naming the line on failure.
/// Negative and fractional values are errors.
pub fn index(token: Option<&str>, line: usize, what: &str) -> Result<u32, ParseError> {
    let token = token.ok_or_else(|| ParseError::line(line, format!("missing {what}")))?;
    token.parse::<u32>().map_err(|_| {
        ParseError::line(
            line,
            format!("`{token}` is not a non-negative integer ({what})"),
        )
    })
}

/// A capacity to reserve for a count read from an untrusted header: never more than the
/// input could hold.
pub fn cap(count: usize, input_len: usize) -> usize {
    count.min(input_len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_drop_comments_and_survive_bad_bytes() {
        let text = b"a 1 # note\n\n  # only a comment\r\nb \xe9t\xe9 2\r\nc 3";
        let got: Vec<(usize, String)> = lines(text).map(|(l, s)| (l, s.into_owned())).collect();
        assert_eq!(
            got,
            vec![
                (1, "a 1".to_string()),
                (4, "b \u{fffd}t\u{fffd} 2".to_string()),
                (5, "c 3".to_string())
            ]
        );
        assert_eq!(check_text(b"ok\n\0x").unwrap_err().location, "byte 3");
    }

    #[test]
    fn positions_count_their_coordinates() {
        let err = position(&mut "1 2".split_whitespace(), 7).unwrap_err();
        assert_eq!(
            (err.location.as_str(), err.message.as_str()),
            ("line 7", "expected 3 coordinates, found 2")
        );
        let p = position(&mut "1 -2 3e1 4".split_whitespace(), 1).unwrap();
        assert_eq!(p, Vec3::new(1.0, -2.0, 30.0));
        assert!(index(Some("-1"), 1, "vertex index").is_err());
        assert!(index(Some("1.5"), 1, "vertex index").is_err());
    }
}
