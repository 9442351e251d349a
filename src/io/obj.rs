//! Wavefront OBJ, read with `tobj` and written here.
//!
//! `tobj` renumbers vertices in order of first use, drops unreferenced ones, splits the file
//! into models at `o`/`g`/`usemtl` (duplicating vertices shared across them) and rejects the
//! whole file for one out-of-range face. Pappus wants the file's own numbering (scripts name
//! vertices by it), every vertex (unreferenced ones are counted as repairs) and one connected
//! mesh. So a first pass lists the `v` lines and each face's vertex numbers (resolving negative,
//! relative ones), faces naming a missing vertex are set aside (the builder drops and counts
//! them), grouping statements are left out, and `tobj` parses what remains as one model; its
//! first-use numbering is then mapped back to the file's. Materials, texture coordinates and
//! normals are ignored.

use bevy::math::Vec3;
use std::fmt::Write as _;

use super::ParseError;
use super::text::{cap, float, lines};
use crate::mesh::soup::PolygonSoup;

/// Parses OBJ text.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let mut positions = Vec::new();
    let mut faces: Vec<(usize, Vec<u32>)> = Vec::new();
    let mut kept = String::with_capacity(cap(bytes.len(), 1 << 30));
    let mut bad_faces = 0usize;
    for (line, text) in lines(bytes) {
        let mut tokens = text.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let p = Vec3::new(
                    float(tokens.next(), line, "x")?,
                    float(tokens.next(), line, "y")?,
                    float(tokens.next(), line, "z")?,
                );
                positions.push(p);
                let _ = writeln!(kept, "v {} {} {}", p.x, p.y, p.z);
            }
            Some("f") => {
                let mut face = Vec::new();
                let mut in_range = true;
                for token in tokens {
                    let number = token.split('/').next().unwrap_or("");
                    let n: i64 = number.parse().map_err(|_| {
                        ParseError::line(line, format!("`{token}` is not a vertex reference"))
                    })?;
                    let count = positions.len() as i64;
                    let i = if n < 0 { count + n } else { n - 1 };
                    if n == 0 || i < 0 || i >= count {
                        in_range = false;
                    }
                    face.push(i.clamp(0, u32::MAX as i64) as u32);
                }
                if face.len() < 3 || !in_range {
                    bad_faces += 1;
                    continue;
                }
                let _ = write!(kept, "f");
                for &i in &face {
                    let _ = write!(kept, " {}", i + 1);
                }
                kept.push('\n');
                faces.push((line, face));
            }
            _ => {}
        }
    }
    if std::str::from_utf8(bytes).is_err() && positions.is_empty() {
        return Err(ParseError::byte(0, "not a text file"));
    }

    let mut soup = PolygonSoup::with_capacity(positions.len(), faces.len(), 0);
    soup.positions = positions;
    if !faces.is_empty() {
        let options = tobj::LoadOptions {
            single_index: false,
            triangulate: false,
            ignore_points: true,
            ignore_lines: true,
        };
        let (models, _) = tobj::load_obj_buf(&mut kept.as_bytes(), &options, |_| {
            Ok((Vec::new(), Default::default()))
        })
        .map_err(|e| ParseError::line(faces[0].0, format!("tobj: {e}")))?;
        append_models(&mut soup, &models, &faces)?;
    }
    // Faces naming missing vertices stay in the soup with an out-of-range index, so the builder
    // drops and counts them.
    for _ in 0..bad_faces {
        soup.push_face(&[u32::MAX, u32::MAX, u32::MAX]);
    }
    Ok(soup)
}

/// Maps `tobj`'s first-use numbering back to the file's and appends the faces.
fn append_models(
    soup: &mut PolygonSoup,
    models: &[tobj::Model],
    faces: &[(usize, Vec<u32>)],
) -> Result<(), ParseError> {
    let mut first_use = Vec::new();
    let mut seen = vec![false; soup.positions.len()];
    for (_, face) in faces {
        for &i in face {
            if !std::mem::replace(&mut seen[i as usize], true) {
                first_use.push(i);
            }
        }
    }
    let [model] = models else {
        return Err(ParseError::line(
            faces[0].0,
            "tobj split the file into several models",
        ));
    };
    let mesh = &model.mesh;
    let agrees = mesh.positions.len() == 3 * first_use.len()
        && first_use.iter().enumerate().all(|(k, &i)| {
            let p = soup.positions[i as usize];
            mesh.positions[3 * k..3 * k + 3] == [p.x, p.y, p.z]
        });
    if !agrees {
        return Err(ParseError::line(
            faces[0].0,
            "tobj and the vertex list disagree",
        ));
    }
    let arities: Vec<u32> = if mesh.face_arities.is_empty() {
        vec![3; mesh.indices.len() / 3]
    } else {
        mesh.face_arities.clone()
    };
    let mut at = 0usize;
    let mut face = Vec::new();
    for arity in arities {
        face.clear();
        for &k in &mesh.indices[at..at + arity as usize] {
            face.push(first_use[k as usize]);
        }
        at += arity as usize;
        soup.push_face(&face);
    }
    Ok(())
}

/// Writes OBJ text: `v` lines (shortest exact decimal form), then `f` lines (1-based).
pub fn write(soup: &PolygonSoup) -> Vec<u8> {
    let mut out = String::with_capacity(soup.positions.len() * 32 + soup.indices.len() * 8);
    out.push_str("# written by Pappus\n");
    for p in &soup.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for face in soup.faces() {
        out.push('f');
        for &i in face {
            let _ = write!(out, " {}", u64::from(i) + 1);
        }
        out.push('\n');
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_file_order_and_unreferenced_vertices() {
        let text = b"v 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nf 5 4 3\ng b\nf 1 3 4\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions.len(), 5);
        assert_eq!(soup.face(0), &[4, 3, 2]);
        assert_eq!(soup.face(1), &[0, 2, 3]);
    }

    #[test]
    fn reads_polygons_and_relative_indices() {
        let text = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4/1/1 -3/2/2 -2//3 -1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 1);
        assert_eq!(soup.face(0), &[0, 1, 2, 3]);
    }

    #[test]
    fn out_of_range_faces_are_kept_for_the_builder_to_drop() {
        let soup = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n").unwrap();
        assert_eq!(soup.face_count(), 2);
        assert_eq!(soup.face(1), &[u32::MAX; 3]);
    }

    #[test]
    fn malformed_lines_name_the_line() {
        let err = read(b"v 0 0 0\nv 1 x 0\n").unwrap_err();
        assert_eq!(err.location, "line 2");
        let err = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n").unwrap_err();
        assert_eq!(err.location, "line 4");
        let err = read(b"v 0 0\n").unwrap_err();
        assert!(err.message.contains("missing z"), "{}", err.message);
    }
}
