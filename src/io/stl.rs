//! STL, ASCII and binary. STL stores every triangle with its own three corners; the reader
//! merges corners at bitwise-equal positions into shared vertices so the mesh has
//! connectivity. STL holds only triangles, so the writer (binary) fans polygons into triangles.

use bevy::math::Vec3;
use bevy::platform::collections::HashMap;

use super::ParseError;
use super::text::{float, lines};
use crate::mesh::soup::PolygonSoup;
use crate::mesh::topology::newell_area_vector;

/// Parses STL, binary or ASCII (binary when the size matches the header's triangle count).
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len()) {
            return Ok(read_binary(bytes, n));
        }
    }
    if bytes.trim_ascii_start().starts_with(b"solid") {
        return read_ascii(bytes);
    }
    if bytes.len() < 84 {
        return Err(ParseError::byte(
            bytes.len(),
            "too short for a binary STL header (84 bytes)",
        ));
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    Err(ParseError::byte(
        bytes.len(),
        format!(
            "binary STL of {n} triangles should be {} bytes",
            84 + 50 * n as u64
        ),
    ))
}

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
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let positions = &mut self.soup.positions;
        *self.index.entry(key).or_insert_with(|| {
            positions.push(p);
            (positions.len() - 1) as u32
        })
    }
}

fn read_binary(bytes: &[u8], n: usize) -> PolygonSoup {
    let mut w = Welder::new(n);
    for t in 0..n {
        let at = 84 + 50 * t + 12;
        let f = |k: usize| {
            let o = at + 4 * k;
            f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]])
        };
        let corners = [0, 1, 2].map(|c| w.vertex(Vec3::new(f(3 * c), f(3 * c + 1), f(3 * c + 2))));
        w.soup.push_face(&corners);
    }
    w.soup
}

fn read_ascii(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let mut w = Welder::new(bytes.len() / 200);
    let mut corners = Vec::with_capacity(3);
    let mut last = 1;
    for (line, text) in lines(bytes) {
        last = line;
        let mut t = text.split_whitespace();
        match t.next() {
            Some("vertex") => {
                let p = Vec3::new(
                    float(t.next(), line, "x")?,
                    float(t.next(), line, "y")?,
                    float(t.next(), line, "z")?,
                );
                corners.push(w.vertex(p));
            }
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(ParseError::line(
                        line,
                        format!("facet with {} vertices (expected 3)", corners.len()),
                    ));
                }
                w.soup.push_face(&corners);
                corners.clear();
            }
            Some("solid" | "facet" | "outer" | "endfacet" | "endsolid") => {}
            Some(other) => return Err(ParseError::line(line, format!("unexpected `{other}`"))),
            None => {}
        }
    }
    if !corners.is_empty() {
        return Err(ParseError::line(last, "file ends inside a facet"));
    }
    Ok(w.soup)
}

/// Writes binary STL; polygons are fanned into triangles.
pub fn write(soup: &PolygonSoup) -> Vec<u8> {
    let triangles: usize = soup.faces().map(|f| f.len().saturating_sub(2)).sum();
    let mut out = Vec::with_capacity(84 + 50 * triangles);
    let mut header = [0u8; 80];
    header[..18].copy_from_slice(b"written by Pappus ");
    out.extend_from_slice(&header);
    out.extend_from_slice(&(triangles as u32).to_le_bytes());
    for f in soup.faces() {
        for i in 1..f.len().saturating_sub(1) {
            let tri = [f[0], f[i], f[i + 1]].map(|v| {
                soup.positions
                    .get(v as usize)
                    .copied()
                    .unwrap_or(Vec3::ZERO)
            });
            let n = newell_area_vector(&tri).normalize_or_zero();
            for p in std::iter::once(n).chain(tri) {
                for c in [p.x, p.y, p.z] {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            out.extend_from_slice(&[0, 0]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_round_trip_welds_shared_corners() {
        let soup = crate::mesh::shapes::icosphere(1);
        let back = read(&write(&soup)).unwrap();
        assert_eq!(back.positions.len(), soup.positions.len());
        assert_eq!(back.face_count(), soup.face_count());
    }

    #[test]
    fn polygons_are_fanned_on_write() {
        let back = read(&write(&crate::io::tests::mixed())).unwrap();
        assert_eq!(back.face_count(), 3);
    }

    #[test]
    fn reads_ascii() {
        let text = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let soup = read(text).unwrap();
        assert_eq!((soup.positions.len(), soup.face_count()), (4, 2));
    }

    #[test]
    fn malformed_files_are_errors() {
        assert!(read(b"\x00\x01").unwrap_err().location.starts_with("byte"));
        let err = read(b"solid t\nfacet\nouter loop\nvertex 0 0\n").unwrap_err();
        assert_eq!(err.location, "line 4");
        let mut truncated = write(&crate::mesh::shapes::tetrahedron());
        truncated.pop();
        assert!(read(&truncated).is_err());
        let err = read(b"solid t\nfacet\nouter loop\nvertex 0 0 0\nendloop\n").unwrap_err();
        assert!(err.message.contains("1 vertices"), "{}", err.message);
    }
}
