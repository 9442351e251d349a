//! STL, ASCII and binary.
//!
//! STL stores every triangle with its own three corners. The reader welds corners at equal
//! positions (bitwise, except that `-0.0` and `0.0` are the same) into shared vertices, in
//! order of first appearance, so the mesh has connectivity; the stored normals are ignored.
//! STL holds only triangles: the writer fans each polygon from its first corner, and writes
//! each triangle's unit normal (zero for a degenerate one).
//!
//! A file is binary when its size is exactly `84 + 50 n`, `n` being the triangle count at
//! bytes 80..84; otherwise it is ASCII if it starts with `solid` and holds no NUL byte, and
//! anything else is an error naming the size the binary header asks for.

use bevy::math::Vec3;
use bevy::platform::collections::HashMap;
use std::fmt::Write as _;

use super::text::{Numbers, check_text, lines};
use crate::io::error::ParseError;
use crate::mesh::soup::PolygonSoup;
use crate::mesh::topology::newell_area_vector;

/// How an STL file is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StlEncoding {
    /// Text (`solid … facet normal … outer loop … vertex …`).
    Ascii,
    /// Binary: an 80-byte header, a triangle count, 50 bytes per triangle (what
    /// [`crate::io::write()`] saves).
    Binary,
}

/// Parses STL, binary or ASCII.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let count = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64);
    if let Some(n) = count
        && 84 + 50 * n == bytes.len() as u64
    {
        return Ok(read_binary(bytes, n as usize));
    }
    let probe = &bytes[..bytes.len().min(512)];
    if bytes.trim_ascii_start().starts_with(b"solid") && !probe.contains(&0) {
        return read_ascii(bytes);
    }
    Err(match count {
        None => ParseError::byte(
            bytes.len(),
            "not ASCII STL, and too short for a binary STL header (84 bytes)",
        ),
        Some(n) => ParseError::byte(
            bytes.len(),
            format!(
                "not ASCII STL; as binary STL of {n} triangles it should be {} bytes, not {}",
                84 + 50 * n,
                bytes.len()
            ),
        ),
    })
}

/// Welds corners into shared vertices.
struct Welder {
    soup: PolygonSoup,
    index: HashMap<[u32; 3], u32>,
}

impl Welder {
    fn new(triangles: usize) -> Self {
        Self {
            soup: PolygonSoup::with_capacity(triangles / 2, triangles, 3 * triangles),
            index: HashMap::default(),
        }
    }

    fn vertex(&mut self, p: Vec3) -> u32 {
        // Adding +0.0 turns -0.0 into +0.0 and leaves every other value as it is.
        let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
        let positions = &mut self.soup.positions;
        *self.index.entry(key).or_insert_with(|| {
            positions.push(p);
            (positions.len() - 1) as u32
        })
    }
}

/// Reads `n` triangles; the caller checked that the size is exactly `84 + 50 n`.
fn read_binary(bytes: &[u8], n: usize) -> PolygonSoup {
    let mut w = Welder::new(n);
    for record in bytes[84..].chunks_exact(50).take(n) {
        let mut floats = record[12..48]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        let mut corner = || {
            let mut c = [0.0f32; 3];
            for x in &mut c {
                *x = floats.next().unwrap_or_default();
            }
            Vec3::from_array(c)
        };
        let (a, b, c) = (corner(), corner(), corner());
        let face = [w.vertex(a), w.vertex(b), w.vertex(c)];
        w.soup.push_face(&face);
    }
    w.soup
}

fn read_ascii(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    check_text(bytes)?;
    let mut w = Welder::new(bytes.len() / 256);
    let mut corners = Vec::with_capacity(3);
    let mut numbers = Numbers::default();
    let mut last = 1;
    for (line, text) in lines(bytes) {
        last = line;
        let mut t = text.split_whitespace();
        match t.next() {
            Some("vertex") => {
                if corners.len() == 3 {
                    return Err(ParseError::line(line, "a facet with more than 3 vertices"));
                }
                let p = numbers.position(&mut t, line)?;
                corners.push(w.vertex(p));
            }
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(ParseError::line(
                        line,
                        format!("a facet with {} vertices (expected 3)", corners.len()),
                    ));
                }
                w.soup.push_face(&corners);
                corners.clear();
            }
            Some("solid" | "facet" | "outer" | "endfacet" | "endsolid") | None => {}
            Some(other) => {
                return Err(ParseError::line(
                    line,
                    format!("unexpected `{other}` in ASCII STL"),
                ));
            }
        }
    }
    if !corners.is_empty() {
        return Err(ParseError::line(last, "file ends inside a facet"));
    }
    w.soup.notes.extend(numbers.note());
    Ok(w.soup)
}

/// The fan triangles of every face, as positions (an out-of-range index reads as the origin),
/// with their unit normals.
fn triangles(soup: &PolygonSoup) -> impl Iterator<Item = (Vec3, [Vec3; 3])> + '_ {
    soup.faces().flat_map(move |f| {
        (1..f.len().saturating_sub(1)).map(move |i| {
            let tri = [f[0], f[i], f[i + 1]]
                .map(|v| soup.positions.get(v as usize).copied().unwrap_or_default());
            (newell_area_vector(&tri).normalize_or_zero(), tri)
        })
    })
}

/// Encodes a soup as STL, polygons fanned into triangles.
pub fn write(soup: &PolygonSoup, encoding: StlEncoding) -> Vec<u8> {
    match encoding {
        StlEncoding::Binary => write_binary(soup),
        StlEncoding::Ascii => write_ascii(soup),
    }
}

fn write_binary(soup: &PolygonSoup) -> Vec<u8> {
    let count: usize = soup.faces().map(|f| f.len().saturating_sub(2)).sum();
    let mut out = Vec::with_capacity(84 + 50 * count);
    // The header must not start with `solid`, or readers may take the file for ASCII.
    let mut header = [b' '; 80];
    header[..17].copy_from_slice(b"written by Pappus");
    out.extend_from_slice(&header);
    out.extend_from_slice(&(count as u32).to_le_bytes());
    for (n, tri) in triangles(soup) {
        for p in std::iter::once(n).chain(tri) {
            for c in p.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

fn write_ascii(soup: &PolygonSoup) -> Vec<u8> {
    let mut out = String::from("solid pappus\n");
    for (n, [a, b, c]) in triangles(soup) {
        let _ = writeln!(
            out,
            "  facet normal {} {} {}\n    outer loop",
            n.x, n.y, n.z
        );
        for p in [a, b, c] {
            let _ = writeln!(out, "      vertex {} {} {}", p.x, p.y, p.z);
        }
        out.push_str("    endloop\n  endfacet\n");
    }
    out.push_str("endsolid pappus\n");
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::tests::mixed;
    use crate::mesh::shapes;

    #[test]
    fn round_trips_weld_shared_corners() {
        let soup = shapes::icosphere(1);
        for e in [StlEncoding::Binary, StlEncoding::Ascii] {
            let back = read(&write(&soup, e)).unwrap();
            assert_eq!(back.positions.len(), soup.positions.len(), "{e:?}");
            assert_eq!(back.face_count(), soup.face_count(), "{e:?}");
            // Same triangles, renumbered in order of first appearance.
            for (f, g) in soup.faces().zip(back.faces()) {
                for (&i, &j) in f.iter().zip(g) {
                    assert_eq!(
                        soup.positions[i as usize].to_array().map(f32::to_bits),
                        back.positions[j as usize].to_array().map(f32::to_bits)
                    );
                }
            }
        }
    }

    #[test]
    fn polygons_are_fanned_on_write() {
        let back = read(&write(&mixed(), StlEncoding::Binary)).unwrap();
        assert_eq!(back.face_count(), 3);
        assert_eq!(back.positions.len(), 5);
        let bytes = write(&mixed(), StlEncoding::Binary);
        assert_eq!(bytes.len(), 84 + 50 * 3);
        assert!(!bytes.starts_with(b"solid"));
    }

    #[test]
    fn reads_ascii_with_several_solids_and_welds_negative_zero() {
        let text = b"solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\nsolid u\nfacet normal 0 0 1\nouter loop\nvertex 1 -0 0\nvertex 1 1 0\nvertex -0.0 1 0\nendloop\nendfacet\nendsolid u\n";
        let soup = read(text).unwrap();
        assert_eq!((soup.positions.len(), soup.face_count()), (4, 2));
        assert_eq!(soup.face(1), &[1, 3, 2]);
    }

    #[test]
    fn binary_files_may_start_with_solid() {
        let mut bytes = write(&shapes::tetrahedron(), StlEncoding::Binary);
        bytes[..6].copy_from_slice(b"solid ");
        let soup = read(&bytes).unwrap();
        assert_eq!((soup.positions.len(), soup.face_count()), (4, 4));
        // Truncated: not mistaken for ASCII, and the error gives the expected size.
        let err = read(&bytes[..bytes.len() - 1]).unwrap_err();
        let expected = format!(
            "not ASCII STL; as binary STL of 4 triangles it should be 284 bytes, not {}",
            bytes.len() - 1
        );
        assert_eq!(
            (err.location, err.message),
            (format!("byte {}", bytes.len() - 1), expected)
        );
    }

    #[test]
    fn odd_values_do_not_panic() {
        let soup = PolygonSoup::from_faces(
            vec![Vec3::NAN, Vec3::INFINITY, Vec3::ZERO, Vec3::X],
            &[vec![0, 1, 2], vec![2, 3, 9], vec![0, 1]],
        );
        let back = read(&write(&soup, StlEncoding::Binary)).unwrap();
        assert_eq!(back.face_count(), 2);
        let back = read(&write(&soup, StlEncoding::Ascii)).unwrap();
        assert_eq!(back.face_count(), 2);
    }

    #[test]
    fn malformed_files_are_errors() {
        let err = read(b"\x00\x01").unwrap_err();
        assert_eq!(err.location, "byte 2");
        assert!(err.message.contains("84 bytes"), "{}", err.message);
        let cases: [(&[u8], &str, &str); 4] = [
            (b"solid t\nfacet\nouter loop\nvertex 0 0\n", "line 4", "expected 3 coordinates, found 2"),
            (b"solid t\nfacet\nouter loop\nvertex 0 0 0\nendloop\n", "line 5", "a facet with 1 vertices (expected 3)"),
            (b"solid t\nfacet\nouter loop\nvertex 0 0 0\nvertex 0 0 0\n", "line 5", "file ends inside a facet"),
            (b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\n", "line 7", "a facet with more than 3 vertices"),
        ];
        for (text, location, message) in cases {
            let err = read(text).unwrap_err();
            assert_eq!(
                (err.location.as_str(), err.message.as_str()),
                (location, message)
            );
        }
        assert_eq!(
            read(b"solid x\nfoo 1 2 3\n").unwrap_err().location,
            "line 2"
        );
    }
}
