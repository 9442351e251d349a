//! Small helpers shared by the text formats.

use super::ParseError;

/// The non-empty, non-comment lines of a text, with 1-based line numbers.
pub fn lines(bytes: &[u8]) -> impl Iterator<Item = (usize, &str)> {
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => t,
        // Keep the valid prefix: the error is reported where the text stops making sense.
        Err(e) => std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or(""),
    };
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty())
}

/// Parses a float token, naming the line on failure.
pub fn float(token: Option<&str>, line: usize, what: &str) -> Result<f32, ParseError> {
    let token = token.ok_or_else(|| ParseError::line(line, format!("missing {what}")))?;
    token
        .parse::<f32>()
        .map_err(|_| ParseError::line(line, format!("`{token}` is not a number ({what})")))
}

/// Parses a non-negative integer token, naming the line on failure.
pub fn index(token: Option<&str>, line: usize, what: &str) -> Result<u32, ParseError> {
    let token = token.ok_or_else(|| ParseError::line(line, format!("missing {what}")))?;
    token.parse::<u32>().map_err(|_| {
        ParseError::line(
            line,
            format!("`{token}` is not a vertex index or count ({what})"),
        )
    })
}

/// A capacity to reserve for a count read from an untrusted header: never more than the
/// input could hold.
pub fn cap(count: usize, input_len: usize) -> usize {
    count.min(input_len)
}
