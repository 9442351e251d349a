//! OFF (Object File Format), ASCII: `OFF`, then `V F E`, then V positions, then F faces as
//! `n i0 … i(n−1)` (anything after the indices, such as a colour, is ignored). The counts may
//! share the header's line; `#` starts a comment.

use bevy::math::Vec3;
use std::fmt::Write as _;

use super::ParseError;
use super::text::{cap, float, index, lines};
use crate::mesh::soup::PolygonSoup;

/// Parses OFF text.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let mut lines = lines(bytes);
    let (first_line, header) = lines
        .next()
        .ok_or_else(|| ParseError::line(1, "empty file (expected `OFF`)"))?;
    let mut tokens: Vec<&str> = header.split_whitespace().collect();
    match tokens.first() {
        Some(&"OFF") => {
            tokens.remove(0);
        }
        Some(t) if t.ends_with("OFF") => {
            return Err(ParseError::line(
                first_line,
                format!("`{t}` files are not supported (plain OFF only)"),
            ));
        }
        _ => return Err(ParseError::line(first_line, "expected `OFF`")),
    }
    let (count_line, counts) = if tokens.is_empty() {
        let (l, t) = lines
            .next()
            .ok_or_else(|| ParseError::line(first_line + 1, "missing vertex and face counts"))?;
        (l, t.split_whitespace().collect::<Vec<_>>())
    } else {
        (first_line, tokens)
    };
    let mut counts = counts.into_iter();
    let nv = index(counts.next(), count_line, "vertex count")? as usize;
    let nf = index(counts.next(), count_line, "face count")? as usize;

    let mut soup =
        PolygonSoup::with_capacity(cap(nv, bytes.len() / 6), cap(nf, bytes.len() / 8), 0);
    for i in 0..nv {
        let (line, text) = lines.next().ok_or_else(|| {
            ParseError::line(count_line, format!("file ends after {i} of {nv} vertices"))
        })?;
        let mut t = text.split_whitespace();
        soup.positions.push(Vec3::new(
            float(t.next(), line, "x")?,
            float(t.next(), line, "y")?,
            float(t.next(), line, "z")?,
        ));
    }
    let mut face = Vec::new();
    for i in 0..nf {
        let (line, text) = lines.next().ok_or_else(|| {
            ParseError::line(count_line, format!("file ends after {i} of {nf} faces"))
        })?;
        let mut t = text.split_whitespace();
        let n = index(t.next(), line, "corner count")? as usize;
        face.clear();
        for _ in 0..n {
            face.push(index(t.next(), line, "vertex index")?);
        }
        soup.push_face(&face);
    }
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

    #[test]
    fn reads_counts_on_the_header_line_and_ignores_colours() {
        let soup = read(b"OFF 4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n").unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.face(0), &[0, 1, 2, 3]);
    }

    #[test]
    fn errors_name_the_line() {
        assert_eq!(read(b"").unwrap_err().location, "line 1");
        assert!(
            read(b"PLY\n")
                .unwrap_err()
                .message
                .contains("expected `OFF`")
        );
        let err = read(b"OFF\n# c\n2 1 0\n0 0 0\n1 0 0\n3 0 1\n").unwrap_err();
        assert_eq!(err.location, "line 6");
        let err = read(b"OFF\n3 1 0\n0 0 0\n").unwrap_err();
        assert!(
            err.message.contains("after 1 of 3 vertices"),
            "{}",
            err.message
        );
        let err = read(b"OFF\n1 0 0\n0 zero 0\n").unwrap_err();
        assert_eq!(err.location, "line 3");
    }

    #[test]
    fn huge_counts_do_not_allocate_or_panic() {
        let err = read(b"OFF\n4000000000 4000000000 0\n").unwrap_err();
        assert!(err.message.contains("file ends"));
    }
}
