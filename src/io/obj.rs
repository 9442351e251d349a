//! Wavefront OBJ, read with `tobj` and written here.
//!
//! `tobj` renumbers vertices in order of first use, drops unreferenced ones, splits the file
//! into models at `o`/`g`/`usemtl` (duplicating vertices shared across them) and rejects the
//! whole file for one out-of-range face. Pappus wants the file's own numbering (scripts name
//! vertices by it), every vertex (unreferenced ones are counted as repairs by the builder) and
//! one connected mesh. So a first pass here lists the `v` lines and each `f` line's vertex
//! numbers (the part before the first `/`; negative numbers count back from the last vertex
//! defined so far, positive ones may name a vertex defined later). Faces that name a missing
//! vertex, or have fewer than 3 corners, stay in the soup in file order (a missing vertex
//! becomes its 0-based number, or `u32::MAX` when that does not fit) for the builder to drop
//! and count. The well-formed faces are handed to `tobj` as one model (grouping statements
//! left out), and its first-use numbering is mapped back to the file's and checked against
//! the first pass.
//!
//! Ignored: texture coordinates, normals, materials (no `.mtl` is opened), groups and objects
//! (all merged into one mesh), points and lines, a vertex's `w` or colour. A malformed `v` or
//! `f` line is an error naming its line.

use bevy::math::Vec3;
use std::fmt::Write as _;

use super::ParseError;
use super::text::{cap, check_text, lines, position};
use crate::mesh::soup::PolygonSoup;

/// One `f` line: where it was, and its corners as 0-based numbers, not yet range-checked
/// (`None`: a number that can name no vertex, such as `0`).
struct RawFace {
    line: usize,
    corners: Vec<Option<u64>>,
}

/// Parses OBJ text.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    check_text(bytes)?;
    let mut positions = Vec::new();
    let mut faces: Vec<RawFace> = Vec::new();
    for (line, text) in lines(bytes) {
        let mut tokens = text.split_whitespace();
        match tokens.next() {
            Some("v") => positions.push(position(&mut tokens, line)?),
            Some("f") => {
                let defined = positions.len() as i64;
                let corners = tokens
                    .map(|token| {
                        let number = token.split('/').next().unwrap_or("");
                        let n: i64 = number.parse().map_err(|_| {
                            ParseError::line(line, format!("`{token}` is not a vertex reference"))
                        })?;
                        // 1-based, or negative: relative to the vertices defined so far.
                        let i = if n < 0 { defined + n } else { n - 1 };
                        Ok(u64::try_from(i).ok())
                    })
                    .collect::<Result<Vec<_>, ParseError>>()?;
                faces.push(RawFace { line, corners });
            }
            _ => {}
        }
    }

    let count = positions.len() as u64;
    let good = |f: &RawFace| {
        f.corners.len() >= 3 && f.corners.iter().all(|c| c.is_some_and(|i| i < count))
    };
    let mut soup = PolygonSoup::with_capacity(positions.len(), faces.len(), 0);
    soup.positions = positions;
    let parsed = parse_with_tobj(&soup.positions, &faces, &good)?;
    let mut parsed = parsed.iter();
    let mut corners = Vec::new();
    for face in &faces {
        if good(face) {
            let Some(next) = parsed.next() else {
                return Err(ParseError::line(face.line, "tobj lost this face"));
            };
            soup.push_face(next);
        } else {
            corners.clear();
            corners.extend(
                face.corners
                    .iter()
                    .map(|c| c.and_then(|i| u32::try_from(i).ok()).unwrap_or(u32::MAX)),
            );
            soup.push_face(&corners);
        }
    }
    Ok(soup)
}

/// Runs `tobj` on the vertices and the well-formed faces, and returns those faces in the
/// file's numbering. Fails if `tobj` disagrees with the first pass (a bug, not a bad file).
fn parse_with_tobj(
    positions: &[Vec3],
    faces: &[RawFace],
    good: &dyn Fn(&RawFace) -> bool,
) -> Result<Vec<Vec<u32>>, ParseError> {
    let Some(first) = faces.iter().find(|f| good(f)) else {
        return Ok(Vec::new());
    };
    let disagree =
        |what: &str| ParseError::line(first.line, format!("tobj and Pappus disagree: {what}"));
    let mut text = String::with_capacity(cap(positions.len() * 24 + faces.len() * 16, 1 << 30));
    for p in positions {
        let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
    }
    let mut first_use = Vec::new();
    let mut seen = vec![false; positions.len()];
    for face in faces.iter().filter(|f| good(f)) {
        text.push('f');
        for &i in face.corners.iter().flatten() {
            let _ = write!(text, " {}", i + 1);
            if !std::mem::replace(&mut seen[i as usize], true) {
                first_use.push(i as u32);
            }
        }
        text.push('\n');
    }
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // No material file is ever opened.
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        Ok((Vec::new(), Default::default()))
    })
    .map_err(|e| disagree(&e.to_string()))?;
    let [model] = models.as_slice() else {
        return Err(disagree(&format!("{} models", models.len())));
    };
    let mesh = &model.mesh;
    let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let agrees = mesh.positions.len() == 3 * first_use.len()
        && first_use
            .iter()
            .zip(mesh.positions.chunks_exact(3))
            .all(|(&i, q)| {
                let p = positions[i as usize];
                same(p.x, q[0]) && same(p.y, q[1]) && same(p.z, q[2])
            });
    if !agrees {
        return Err(disagree("positions"));
    }
    // No arities: every face is a triangle.
    let arities: Vec<u32> = if mesh.face_arities.is_empty() {
        vec![3; mesh.indices.len() / 3]
    } else {
        mesh.face_arities.clone()
    };
    let mut out = Vec::with_capacity(arities.len());
    let mut at = 0usize;
    for arity in arities {
        let Some(corners) = mesh.indices.get(at..at + arity as usize) else {
            return Err(disagree("face sizes"));
        };
        at += arity as usize;
        let face = corners
            .iter()
            .map(|&k| first_use.get(k as usize).copied())
            .collect::<Option<Vec<u32>>>()
            .ok_or_else(|| disagree("indices"))?;
        out.push(face);
    }
    Ok(out)
}

/// Writes OBJ text: `v` lines (shortest exact decimal form), `vn` lines when the soup carries
/// vertex normals (one per position, numbered as the positions), then `f` lines (1-based; `v//vn`
/// with normals).
pub fn write(soup: &PolygonSoup) -> Vec<u8> {
    let normals = soup
        .vertex_normals
        .as_deref()
        .filter(|v| v.len() == soup.positions.len());
    let mut out = String::with_capacity(soup.positions.len() * 64 + soup.indices.len() * 16);
    out.push_str("# written by Pappus\n");
    for p in &soup.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in normals.into_iter().flatten() {
        let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
    }
    for face in soup.faces() {
        out.push('f');
        for &i in face {
            let i = u64::from(i) + 1;
            match normals {
                Some(_) => {
                    let _ = write!(out, " {i}//{i}");
                }
                None => {
                    let _ = write!(out, " {i}");
                }
            }
        }
        out.push('\n');
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_normals_are_written_as_vn_with_matching_indices() {
        let mut soup = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]);
        soup.vertex_normals = Some(vec![Vec3::Z; 3]);
        let text = String::from_utf8(write(&soup)).unwrap();
        assert_eq!(text.matches("vn 0 0 1").count(), 3);
        assert!(text.contains("f 1//1 2//2 3//3"), "{text}");
        // It reads back as the same mesh.
        let back = read(text.as_bytes()).unwrap();
        assert_eq!(back.positions, soup.positions);
        assert_eq!(back.face(0), &[0, 1, 2]);
    }

    #[test]
    fn keeps_file_order_and_unreferenced_vertices() {
        let text = b"o first\nv 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nusemtl red\nf 5 4 3\ng b\nf 1 3 4\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions.len(), 5);
        assert_eq!(soup.positions[1], Vec3::splat(9.0));
        assert_eq!(soup.face_count(), 2);
        assert_eq!(soup.face(0), &[4, 3, 2]);
        assert_eq!(soup.face(1), &[0, 2, 3]);
    }

    #[test]
    fn reads_quads_and_relative_indices() {
        let text = b"mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -4/1/1 -3/1/1 -2//1 -1\nv 2 0 0\nf 2 -1 3\nf 1/1 2/1 3/1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 3);
        assert_eq!(soup.face(0), &[0, 1, 2, 3]);
        assert_eq!(soup.face(1), &[1, 4, 2]);
        assert_eq!(soup.face(2), &[0, 1, 2]);
    }

    #[test]
    fn faces_may_name_vertices_defined_later() {
        let soup = read(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(soup.face(0), &[0, 1, 2]);
    }

    #[test]
    fn bad_faces_stay_in_place_for_the_builder_to_drop() {
        let text =
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\nf 1 2\nf 0 1 2\nf -9 1 2\nf 3 2 1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 6);
        assert_eq!(soup.face(0), &[0, 1, 2]);
        assert_eq!(soup.face(1), &[0, 1, 6]);
        assert_eq!(soup.face(2), &[0, 1]);
        assert_eq!(soup.face(3), &[u32::MAX, 0, 1]);
        assert_eq!(soup.face(4), &[u32::MAX, 0, 1]);
        assert_eq!(soup.face(5), &[2, 1, 0]);
    }

    #[test]
    fn odd_but_readable_text() {
        // A Latin-1 comment, CRLF line ends, a NaN coordinate, a `w`, a colour.
        let text = b"# caf\xe9\r\nv 0 0 0 1\r\nv NaN 0 0\r\nv 0 1 0 0.5 0.5 0.5\r\nf 1 2 3\r\n";
        let soup = read(text).unwrap();
        assert!(soup.positions[1].x.is_nan());
        assert_eq!(soup.face(0), &[0, 1, 2]);
        let empty = read(b"").unwrap();
        assert_eq!((empty.positions.len(), empty.face_count()), (0, 0));
    }

    #[test]
    fn malformed_lines_name_the_line() {
        let cases: [(&[u8], &str, &str); 5] = [
            (b"v 0 0 0\nv 1 x 0\n", "line 2", "`x` is not a number (y)"),
            (
                b"v 0 0 0\n\n# c\nv 1 0\n",
                "line 4",
                "expected 3 coordinates, found 2",
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n",
                "line 4",
                "`q` is not a vertex reference",
            ),
            (
                b"v 0 0 0\nf 1 2.5 3\n",
                "line 2",
                "`2.5` is not a vertex reference",
            ),
            (
                b"v 0 0 0\nv\xff 1 0 0\0",
                "byte 16",
                "NUL byte: this is not a text file",
            ),
        ];
        for (text, location, message) in cases {
            let err = read(text).unwrap_err();
            assert_eq!(
                (err.location.as_str(), err.message.as_str()),
                (location, message)
            );
        }
    }
}
