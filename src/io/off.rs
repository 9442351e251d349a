//! OFF (Object File Format), ASCII: a header `OFF`, then `V F E`, then V positions, then F
//! faces as `n i0 … i(n−1)`. The counts may share the header's line (`OFF 8 6 0`); `#` starts
//! a comment; blank lines are skipped. Anything after a face's indices (a colour) or after a
//! vertex's three coordinates is ignored, which also makes the `COFF`, `NOFF`, `STOFF`, …
//! headers readable. The 4-D and n-D variants (`4OFF`, `nOFF`) and binary OFF are refused as
//! unsupported. Indices must be non-negative integers; out-of-range ones are kept for the
//! builder to drop.

use std::fmt::Write as _;

use super::text::{Numbers, cap, check_text, index, lines};
use crate::io::error::ParseError;
use crate::mesh::soup::PolygonSoup;

/// Parses OFF text.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    check_text(bytes)?;
    let mut lines = lines(bytes);
    let (first_line, header) = lines
        .next()
        .ok_or_else(|| ParseError::line(1, "empty file (expected `OFF`)"))?;
    let mut tokens = header.split_whitespace();
    let keyword = tokens.next().unwrap_or("");
    let Some(prefix) = keyword.strip_suffix("OFF") else {
        return Err(ParseError::line(
            first_line,
            format!("expected `OFF`, found `{keyword}`"),
        ));
    };
    if prefix.contains(['4', 'n']) {
        return Err(
            ParseError::line(first_line, format!("`{keyword}`: only 3-D OFF is read"))
                .unsupported(),
        );
    }
    if !prefix.chars().all(|c| matches!(c, 'S' | 'T' | 'C' | 'N')) {
        return Err(ParseError::line(
            first_line,
            format!("expected `OFF`, found `{keyword}`"),
        ));
    }
    let rest: Vec<&str> = tokens.collect();
    if rest
        .first()
        .is_some_and(|t| t.eq_ignore_ascii_case("BINARY"))
    {
        return Err(ParseError::line(first_line, "binary OFF").unsupported());
    }
    let counts_on_header = !rest.is_empty();
    let counts_text;
    let (count_line, mut counts): (usize, Vec<&str>) = if counts_on_header {
        (first_line, rest)
    } else {
        let (line, text) = lines
            .next()
            .ok_or_else(|| ParseError::line(first_line + 1, "missing vertex and face counts"))?;
        counts_text = text;
        (line, counts_text.split_whitespace().collect())
    };
    counts.truncate(2);
    let mut counts = counts.into_iter();
    let nv = index(counts.next(), count_line, "vertex count")? as usize;
    let nf = index(counts.next(), count_line, "face count")? as usize;

    // At least 6 bytes per vertex line ("0 0 0\n") and 8 per face line.
    let mut soup =
        PolygonSoup::with_capacity(cap(nv, bytes.len() / 6), cap(nf, bytes.len() / 8), 0);
    let mut numbers = Numbers::default();
    for i in 0..nv {
        let (line, text) = lines.next().ok_or_else(|| {
            ParseError::line(count_line, format!("file ends after {i} of {nv} vertices"))
        })?;
        soup.positions
            .push(numbers.position(&mut text.split_whitespace(), line)?);
    }
    let mut face = Vec::new();
    for i in 0..nf {
        let (line, text) = lines.next().ok_or_else(|| {
            ParseError::line(count_line, format!("file ends after {i} of {nf} faces"))
        })?;
        let mut t = text.split_whitespace();
        let n = index(t.next(), line, "corner count")? as usize;
        face.clear();
        for k in 0..n {
            let Some(token) = t.next() else {
                return Err(ParseError::line(
                    line,
                    format!("expected {n} vertex indices, found {k}"),
                ));
            };
            face.push(index(Some(token), line, "vertex index")?);
        }
        soup.push_face(&face);
    }
    soup.notes.extend(numbers.note());
    Ok(soup)
}

/// Writes OFF text.
pub fn write(soup: &PolygonSoup) -> Vec<u8> {
    let mut out = String::with_capacity(soup.positions.len() * 32 + soup.indices.len() * 8);
    let _ = writeln!(out, "OFF\n{} {} 0", soup.positions.len(), soup.face_count());
    for p in &soup.positions {
        let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
    }
    for face in soup.faces() {
        let _ = write!(out, "{}", face.len());
        for &i in face {
            let _ = write!(out, " {i}");
        }
        out.push('\n');
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::math::Vec3;

    #[test]
    fn reads_counts_on_the_header_line_and_ignores_colours() {
        let soup = read(
            b"OFF 4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n3 0 2 3 0.5 0.5 0.5 1\n",
        )
        .unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.face(0), &[0, 1, 2, 3]);
        assert_eq!(soup.face(1), &[0, 2, 3]);
    }

    #[test]
    fn reads_comments_blank_lines_and_variants() {
        let text = b"# made by hand\nCOFF\n\n# counts\n3 1 3\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255 # red\n0 1 0 0 0 255 255\n3 0 1 2\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(soup.face(0), &[0, 1, 2]);
        // Out of range is the builder's business.
        let soup = read(b"OFF\n1 1 0\n0 0 0\n3 0 5 9\n").unwrap();
        assert_eq!(soup.face(0), &[0, 5, 9]);
    }

    #[test]
    fn errors_name_the_line() {
        let cases: [(&[u8], &str, &str); 9] = [
            (b"", "line 1", "empty file (expected `OFF`)"),
            (b"PLY\n", "line 1", "expected `OFF`, found `PLY`"),
            (
                b"OFF\n# c\n2 1 0\n0 0 0\n1 0 0\n3 0 1\n",
                "line 6",
                "expected 3 vertex indices, found 2",
            ),
            (
                b"OFF\n3 1 0\n0 0 0\n",
                "line 2",
                "file ends after 1 of 3 vertices",
            ),
            (
                b"OFF\n1 0 0\n0 zero 0\n",
                "line 3",
                "`zero` is not a number (y)",
            ),
            (
                b"OFF\n1 0 0\n0 0\n",
                "line 3",
                "expected 3 coordinates, found 2",
            ),
            (
                b"OFF\n1 1 0\n0 0 0\n3 0 -1 0\n",
                "line 4",
                "`-1` is not a non-negative integer (vertex index)",
            ),
            (
                b"OFF\n1 1 0\n0 0 0\n3 0 1.0 0\n",
                "line 4",
                "`1.0` is not a non-negative integer (vertex index)",
            ),
            (
                b"OFF\n-1 0 0\n",
                "line 2",
                "`-1` is not a non-negative integer (vertex count)",
            ),
        ];
        for (text, location, message) in cases {
            let err = read(text).unwrap_err();
            assert_eq!(
                (err.location.as_str(), err.message.as_str()),
                (location, message)
            );
            assert!(!err.unsupported);
        }
        for text in [&b"4OFF\n"[..], b"nOFF\n4\n", b"OFF BINARY\n"] {
            assert!(read(text).unwrap_err().unsupported);
        }
    }

    #[test]
    fn huge_counts_do_not_allocate_or_panic() {
        let err = read(b"OFF\n4000000000 4000000000 0\n").unwrap_err();
        assert!(err.message.contains("file ends"));
    }
}
