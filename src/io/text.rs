//! Small helpers shared by the text formats (OBJ, OFF, ASCII STL): line splitting with
//! comments removed, number parsing that names the line, and a cap for untrusted counts.

use bevy::math::Vec3;
use std::borrow::Cow;

use crate::io::error::ParseError;

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

/// How a number token outside Rust's float syntax was read, when it could be read one way only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mend {
    /// A decimal comma (`1,450607`), as exporters running under a European locale write:
    /// none of the text formats separates numbers by commas, so the comma can only be the
    /// decimal point.
    DecimalComma,
    /// The exponent's sign before its `e` (`3.1+e2` for `3.1e+2`): every character is then
    /// used, where a reader that stops at the `+` (Assimp's) reads 3.1, two orders off.
    SwappedExponentSign,
}

impl Mend {
    /// The token as Rust reads it, when it is one of the two mendable forms (and nothing else).
    fn rewrite(token: &str) -> Option<(String, Mend)> {
        if token.contains(',') {
            let ok = token.matches(',').count() == 1 && !token.contains('.');
            return ok.then(|| (token.replace(',', "."), Mend::DecimalComma));
        }
        let at = token.find(['e', 'E'])?;
        let (mantissa, sign) = (token.get(..at.checked_sub(1)?)?, token.get(at - 1..at)?);
        let exponent = &token[at + 1..];
        let digits = !exponent.is_empty() && exponent.bytes().all(|b| b.is_ascii_digit());
        let plain = mantissa.bytes().any(|b| b.is_ascii_digit())
            && mantissa
                .bytes()
                .enumerate()
                .all(|(i, b)| b.is_ascii_digit() || b == b'.' || (i == 0 && b"+-".contains(&b)));
        (matches!(sign, "+" | "-") && digits && plain).then(|| {
            (
                format!("{mantissa}e{sign}{exponent}"),
                Mend::SwappedExponentSign,
            )
        })
    }
}

/// The first token mended one way, and how many were.
#[derive(Clone, Debug, Default)]
struct Mended {
    count: usize,
    first: Option<(String, usize)>,
}

/// Reads the number tokens of a text format, one grammar for every reader (OBJ, OFF, ASCII
/// STL, ASCII PLY, COLLADA's arrays): Rust's float syntax, and else the two forms that can be
/// read only one way, a decimal comma (`1,450607`) and an exponent's sign before its `e`
/// (`3.1+e2`), each counted for the soup's notes. Anything else that is not a number is an
/// error naming the line.
#[derive(Clone, Debug, Default)]
pub struct Numbers {
    commas: Mended,
    exponents: Mended,
}

impl Numbers {
    /// The token's value; `None` when it is not a number in any form read.
    pub fn parse<T: std::str::FromStr>(&mut self, token: &str, line: usize) -> Option<T> {
        if let Ok(value) = token.parse() {
            return Some(value);
        }
        let (text, mend) = Mend::rewrite(token)?;
        let value = text.parse().ok()?;
        let mended = match mend {
            Mend::DecimalComma => &mut self.commas,
            Mend::SwappedExponentSign => &mut self.exponents,
        };
        mended.count += 1;
        mended.first.get_or_insert_with(|| (token.to_owned(), line));
        Some(value)
    }

    /// Parses a float token, naming the line on failure.
    pub fn float(
        &mut self,
        token: Option<&str>,
        line: usize,
        what: &str,
    ) -> Result<f32, ParseError> {
        let token = token.ok_or_else(|| ParseError::line(line, format!("missing {what}")))?;
        self.parse(token, line)
            .ok_or_else(|| ParseError::line(line, format!("`{token}` is not a number ({what})")))
    }

    /// Parses the next three tokens as a position; further tokens (a `w`, a colour, a normal)
    /// are left for the caller to ignore.
    pub fn position<'a>(
        &mut self,
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
            *c = self.float(Some(token), line, ["x", "y", "z"][k])?;
        }
        Ok(Vec3::from_array(p))
    }

    /// Adds another reader's counts (a document read in parts).
    pub fn add(&mut self, other: &Numbers) {
        for (mine, theirs) in [
            (&mut self.commas, &other.commas),
            (&mut self.exponents, &other.exponents),
        ] {
            mine.count += theirs.count;
            if mine.first.is_none() {
                mine.first.clone_from(&theirs.first);
            }
        }
    }

    /// The note for the soup on what was mended: `"read 2 number(s) with a decimal comma, read
    /// as a decimal point (the first `1,5`, line 3)"`, and the same for exponents after a `;`;
    /// `None` when nothing was.
    pub fn note(&self) -> Option<String> {
        let phrase = |m: &Mended, how: &str| {
            let (token, line) = m.first.as_ref()?;
            Some(format!(
                "{} number(s) {how} (the first `{token}`, line {line})",
                m.count
            ))
        };
        let phrases: Vec<String> = [
            phrase(
                &self.commas,
                "with a decimal comma, read as a decimal point",
            ),
            phrase(
                &self.exponents,
                "with the exponent's sign before its `e`, read as `e` then the sign",
            ),
        ]
        .into_iter()
        .flatten()
        .collect();
        (!phrases.is_empty()).then(|| format!("read {}", phrases.join("; ")))
    }
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
        let mut numbers = Numbers::default();
        let err = numbers
            .position(&mut "1 2".split_whitespace(), 7)
            .unwrap_err();
        assert_eq!(
            (err.location.as_str(), err.message.as_str()),
            ("line 7", "expected 3 coordinates, found 2")
        );
        let p = numbers
            .position(&mut "1 -2 3e1 4".split_whitespace(), 1)
            .unwrap();
        assert_eq!(p, Vec3::new(1.0, -2.0, 30.0));
        assert!(index(Some("-1"), 1, "vertex index").is_err());
        assert!(index(Some("1.5"), 1, "vertex index").is_err());
    }

    #[test]
    fn mends_a_decimal_comma_and_a_swapped_exponent_sign_and_counts_them() {
        let mut numbers = Numbers::default();
        assert_eq!(numbers.parse::<f32>("1,450607", 3), Some(1.450607));
        assert_eq!(numbers.parse::<f32>("-0,5", 4), Some(-0.5));
        assert_eq!(numbers.parse::<f32>("3.1+e2", 9), Some(310.0));
        assert_eq!(numbers.parse::<f64>("2-E3", 9), Some(0.002));
        assert_eq!(numbers.parse::<f32>("1.5e+2", 9), Some(150.0));
        assert_eq!(
            numbers.note().as_deref(),
            Some(
                "read 2 number(s) with a decimal comma, read as a decimal point (the first \
                 `1,450607`, line 3); 2 number(s) with the exponent's sign before its `e`, \
                 read as `e` then the sign (the first `3.1+e2`, line 9)"
            )
        );
        // Forms that could be read more than one way, or not at all, stay errors.
        for bad in [
            "1,2,3", "1.5,2", "3.1+e", "+e2", "3.1*e2", "e+2", "3.1+e2x", "1,5e+2,",
        ] {
            assert_eq!(numbers.parse::<f32>(bad, 1), None, "{bad}");
        }
        let err = numbers.float(Some("3.1+f2"), 12, "x").unwrap_err();
        assert_eq!(err.message, "`3.1+f2` is not a number (x)");
        assert!(Numbers::default().note().is_none());
    }
}
