//! The binary body most PLY files have, read row by row without the general reader's
//! value-by-value path.
//!
//! Scanners and MeshLab write a `vertex` element of scalar properties and a `face` element
//! whose one list is `vertex_indices`: every vertex row has the same byte layout, and a face
//! row is a count and that many integer indices. [`read`] decodes such a body with the layout
//! worked out once per element (each property's offset and type), and copies the indices of a
//! little-endian `int`/`uint` list straight into the soup; a face's kept scalars (before or
//! after its list) are decoded only when the header declares some. On the 1.1 M-face scan the parse
//! took about 40 ms, against 130–150 ms through the general reader.
//!
//! It takes nothing on trust: any body it was not made for, and any body the general reader
//! would reject (truncated, a negative count or index, a list elsewhere than a face's
//! corners, strips, per-corner UVs), gives `None`, and the general reader then reads the file
//! and says what is wrong. When it returns a soup, that soup is the one the general reader
//! would have returned, value for value (the tests hold the two to that).

use bevy::math::Vec2;

use super::rows::{
    Element, Property, Role, Row, Scalar, corner_uvs_of_vertices, finish_face_columns,
    push_face_scalars, reserve_face_columns, reserve_vertex_columns,
};
use crate::mesh::soup::PolygonSoup;

/// One scalar property of a fixed-size row: where it sits in the row and what it holds.
struct Field {
    offset: usize,
    ty: Scalar,
    role: Role,
}

/// An element's scalars before and after its one list (a `face` element's corners), each half
/// a fixed-size run of bytes.
struct Layout {
    before: Vec<Field>,
    before_size: usize,
    /// The corners list's count and item types, when the element has one.
    corners: Option<(Scalar, Scalar)>,
    after: Vec<Field>,
    after_size: usize,
}

impl Layout {
    /// The layout of `element`, or `None` when its rows are not fixed scalars around at most
    /// one corners list (and a vertex element has none).
    fn of(element: &Element) -> Option<Self> {
        let mut layout = Layout {
            before: Vec::new(),
            before_size: 0,
            corners: None,
            after: Vec::new(),
            after_size: 0,
        };
        for property in &element.properties {
            match (property, layout.corners) {
                (Property::Scalar { ty, role, .. }, None) => {
                    layout.before.push(Field {
                        offset: layout.before_size,
                        ty: *ty,
                        role: *role,
                    });
                    layout.before_size += ty.size();
                }
                (Property::Scalar { ty, role, .. }, Some(_)) => {
                    layout.after.push(Field {
                        offset: layout.after_size,
                        ty: *ty,
                        role: *role,
                    });
                    layout.after_size += ty.size();
                }
                (
                    Property::List {
                        count,
                        item,
                        role: Role::Corners,
                        ..
                    },
                    None,
                ) if item.is_integer() && element.name == "face" => {
                    layout.corners = Some((*count, *item));
                }
                _ => return None,
            }
        }
        Some(layout)
    }
}

/// Reads the binary body starting at `body`, if every element fits the common layout (see the
/// module documentation); `None` otherwise, and for anything the general reader would reject.
pub(super) fn read(
    bytes: &[u8],
    body: usize,
    big_endian: bool,
    elements: &[Element],
) -> Option<PolygonSoup> {
    let layouts: Vec<Layout> = elements.iter().map(Layout::of).collect::<Option<_>>()?;
    let mut soup = PolygonSoup::default();
    let mut vertex_uv: Option<Vec<Vec2>> = None;
    let mut at = body;
    for (element, layout) in elements.iter().zip(&layouts) {
        if element.properties.is_empty() {
            continue;
        }
        let is_vertex = element.name == "vertex";
        if is_vertex {
            reserve_vertex_columns(element, &mut soup, &mut vertex_uv, bytes.len());
        }
        if element.name == "face" {
            reserve_face_columns(element, &mut soup);
        }
        match layout.corners {
            None if is_vertex => {
                let rows = fixed_rows(bytes, at, element.count, layout.before_size)?;
                for row in rows.chunks_exact(layout.before_size) {
                    let mut values = Row::default();
                    for field in &layout.before {
                        let value = field.ty.decode(&row[field.offset..], big_endian);
                        values.set(field.role, field.ty, value);
                    }
                    values.push_vertex(&mut soup, &mut vertex_uv);
                }
                at += rows.len();
            }
            // Rows of other elements hold nothing the soup keeps.
            None => at += fixed_rows(bytes, at, element.count, layout.before_size)?.len(),
            Some(types) => {
                at = read_faces(
                    bytes,
                    at,
                    element.count,
                    layout,
                    types,
                    big_endian,
                    &mut soup,
                )?;
            }
        }
    }
    finish_face_columns(&mut soup);
    soup.corner_uvs = corner_uvs_of_vertices(&soup, vertex_uv);
    Some(soup)
}

/// The bytes of `count` rows of `size` bytes from `at`, or `None` when the file is shorter.
fn fixed_rows(bytes: &[u8], at: usize, count: usize, size: usize) -> Option<&[u8]> {
    let len = count.checked_mul(size)?;
    bytes.get(at..at.checked_add(len)?)
}

/// Reads `count` face rows from `at` into the soup's faces; returns where they end, or `None`
/// at a negative count or index, or when the file ends first.
fn read_faces(
    bytes: &[u8],
    mut at: usize,
    count: usize,
    layout: &Layout,
    (count_ty, item): (Scalar, Scalar),
    big_endian: bool,
    soup: &mut PolygonSoup,
) -> Option<usize> {
    let item_size = item.size();
    // At least a count byte a face: a huge count in the header cannot reserve more than the
    // file could hold.
    let room = (bytes.len() - at.min(bytes.len())) / (layout.before_size + count_ty.size());
    soup.face_starts.reserve(count.min(room) + 1);
    soup.indices.reserve(count.min(room) * 3);
    if soup.face_starts.is_empty() && count > 0 {
        soup.face_starts.push(0);
    }
    let raw_indices = !big_endian && matches!(item, Scalar::I32 | Scalar::U32);
    let kept = |f: &Field| matches!(f.role, Role::FaceScalar(_));
    let scalars = layout.before.iter().chain(&layout.after).any(kept);
    // Decodes the kept scalars of the fields laid out from `start` into `row`.
    let decode = |fields: &[Field], start: usize, size: usize, row: &mut Row| {
        let bytes = bytes.get(start..start.checked_add(size)?)?;
        for field in fields.iter().filter(|f| kept(f)) {
            row.set(
                field.role,
                field.ty,
                field.ty.decode(&bytes[field.offset..], big_endian),
            );
        }
        Some(())
    };
    for _ in 0..count {
        let mut row = Row::default();
        if scalars {
            decode(&layout.before, at, layout.before_size, &mut row)?;
        }
        at = at.checked_add(layout.before_size)?;
        let n = count_ty.decode(bytes.get(at..at + count_ty.size())?, big_endian);
        if n < 0.0 {
            return None;
        }
        at += count_ty.size();
        let list = bytes.get(at..at.checked_add((n as usize).checked_mul(item_size)?)?)?;
        if raw_indices {
            let first = soup.indices.len();
            let index = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            soup.indices.extend(list.chunks_exact(4).map(index));
            // An `int` index past `i32::MAX` was negative.
            if item == Scalar::I32 && soup.indices[first..].iter().any(|&i| i > i32::MAX as u32) {
                return None;
            }
        } else {
            for index in list.chunks_exact(item_size) {
                let index = item.decode(index, big_endian);
                if index < 0.0 {
                    return None;
                }
                soup.indices.push(index as u32);
            }
        }
        soup.face_starts
            .push(u32::try_from(soup.indices.len()).ok()?);
        at += list.len();
        if scalars {
            decode(&layout.after, at, layout.after_size, &mut row)?;
            push_face_scalars(&row, soup);
        }
        at = at.checked_add(layout.after_size)?;
    }
    (at <= bytes.len()).then_some(at)
}

#[cfg(test)]
mod tests {
    use super::super::{Binary, Header, PlyEncoding, body_values, header, write};
    use super::*;
    use crate::io::error::ParseError;
    use crate::io::tests::mixed;
    use bevy::math::Vec3;

    /// This reader's soup (if it takes the body) and the general reader's, for a whole file.
    fn both(bytes: &[u8]) -> (Option<PolygonSoup>, Result<PolygonSoup, ParseError>) {
        let Header {
            encoding,
            elements,
            body,
            ..
        } = header(bytes).unwrap();
        let big_endian = encoding == PlyEncoding::BinaryBigEndian;
        let fixed = read(bytes, body, big_endian, &elements);
        let mut values = Binary {
            data: bytes,
            at: body,
            big_endian,
        };
        (fixed, body_values(&elements, &mut values, bytes.len()))
    }

    /// Holds this reader to the general one on `bytes` and on every cut of its body: where the
    /// general reader fails this one declines, and where this one reads, the soups are equal.
    fn agrees_on_every_cut(bytes: &[u8]) {
        let body = header(bytes).unwrap().body;
        for cut in body..=bytes.len() {
            let (fixed, general) = both(&bytes[..cut]);
            match (fixed, general) {
                (Some(fixed), Ok(general)) => assert_eq!(fixed, general, "cut at {cut}"),
                (Some(_), Err(e)) => {
                    panic!("read a body the general reader rejects ({e:?}), cut at {cut}")
                }
                (None, _) => {}
            }
        }
    }

    /// A header for `body`, binary little-endian unless `big_endian`.
    fn file(big_endian: bool, header: &str, body: &[u8]) -> Vec<u8> {
        let format = if big_endian {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut bytes = format!("ply\nformat {format} 1.0\n{header}end_header\n").into_bytes();
        bytes.extend_from_slice(body);
        bytes
    }

    #[test]
    fn what_the_writer_saves_is_read_here_as_the_general_reader_reads_it() {
        let mut attributed = mixed();
        let n = attributed.positions.len();
        attributed.vertex_quality = Some((0..n).map(|i| i as f32 / 3.0).collect());
        attributed.vertex_colors = Some((0..n).map(|i| [i as u8, 255, 7]).collect());
        attributed.vertex_normals = Some(vec![Vec3::Z; n]);
        attributed.vertex_scalars = vec![
            (
                "confidence".into(),
                (0..n).map(|i| 1.0 / (i as f32 + 1.0)).collect(),
            ),
            ("intensity".into(), vec![-0.0; n]),
        ];
        for soup in [mixed(), attributed] {
            for encoding in [
                PlyEncoding::BinaryLittleEndian,
                PlyEncoding::BinaryBigEndian,
            ] {
                let bytes = write(&soup, encoding);
                let (fixed, general) = both(&bytes);
                assert_eq!(
                    fixed.expect("the writer's layout is the common one"),
                    general.unwrap()
                );
                agrees_on_every_cut(&bytes);
            }
        }
    }

    #[test]
    fn odd_types_and_rows_read_past_agree_with_the_general_reader() {
        // An element before the vertices, doubles and shorts among the coordinates, a float
        // colour, a face row with scalars (kept) around a `ushort` count of `short` indices.
        let header = "element edge 2\nproperty int a\nproperty uchar b\n\
            element vertex 3\nproperty double x\nproperty float nx\nproperty double y\n\
            property int16 z\nproperty float red\nproperty float green\nproperty float blue\n\
            element face 2\nproperty uchar flags\nproperty list ushort short vertex_indices\n\
            property float weight\n";
        for big_endian in [false, true] {
            let mut body = Vec::new();
            let mut put = |b: &[u8]| {
                let mut b = b.to_vec();
                if big_endian {
                    b.reverse();
                }
                body.extend_from_slice(&b);
            };
            for i in 0..2 {
                put(&i32::to_le_bytes(i));
                put(&[9]);
            }
            for i in 0..3 {
                put(&(f64::from(i) * 0.1).to_le_bytes());
                put(&1.5f32.to_le_bytes());
                put(&(-f64::from(i)).to_le_bytes());
                put(&(i as i16 * 300).to_le_bytes());
                for c in [0.2f32, 1.7, f32::NAN] {
                    put(&c.to_le_bytes());
                }
            }
            for face in [&[0i16, 1, 2][..], &[2, 1, 0, 1]] {
                put(&[1]);
                put(&(face.len() as u16).to_le_bytes());
                for &i in face {
                    put(&i.to_le_bytes());
                }
                put(&0.5f32.to_le_bytes());
            }
            let bytes = file(big_endian, header, &body);
            let (fixed, general) = both(&bytes);
            let general = general.unwrap();
            assert_eq!(general.face(1), &[2, 1, 0, 1]);
            assert_eq!(general.vertex_colors.as_ref().unwrap()[0], [51, 255, 0]);
            let kept = |name: &str, v: f32| (name.to_string(), vec![v; 2]);
            assert_eq!(
                general.face_scalars,
                [kept("flags", 1.0), kept("weight", 0.5)]
            );
            assert_eq!(fixed.expect("fixed rows"), general);
            agrees_on_every_cut(&bytes);
        }
    }

    #[test]
    fn negative_counts_and_indices_are_left_to_the_general_reader() {
        let header = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
            element face 1\nproperty list char int vertex_indices\n";
        let vertex = [0u8; 12];
        for face in [
            [&[0xffu8][..]].concat(),
            [
                &[3u8][..],
                &0i32.to_le_bytes(),
                &(-1i32).to_le_bytes(),
                &0i32.to_le_bytes(),
            ]
            .concat(),
        ] {
            let bytes = file(false, header, &[&vertex[..], &face].concat());
            let (fixed, general) = both(&bytes);
            assert!(fixed.is_none());
            assert!(general.is_err());
        }
        // `uint` indices past `i32::MAX` are indices like any other.
        let header = header.replace("char int", "uchar uint");
        let face = [
            &[3u8][..],
            &0u32.to_le_bytes(),
            &u32::MAX.to_le_bytes(),
            &0u32.to_le_bytes(),
        ];
        let bytes = file(false, &header, &[&vertex[..], &face.concat()].concat());
        let (fixed, general) = both(&bytes);
        assert_eq!(fixed.unwrap().face(0), &[0, u32::MAX, 0]);
        assert_eq!(general.unwrap().face(0), &[0, u32::MAX, 0]);
    }

    #[test]
    fn strips_uvs_and_other_lists_are_left_to_the_general_reader() {
        let xyz = "element vertex 0\nproperty float x\nproperty float y\nproperty float z\n";
        for rest in [
            "element tristrips 0\nproperty list int int vertex_indices\n",
            "element face 0\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n",
            "element face 0\nproperty list uchar int vertex_indices\nproperty list uchar int junk\n",
            "element edge 0\nproperty list uchar int ends\n",
        ] {
            let bytes = file(false, &format!("{xyz}{rest}"), &[]);
            assert!(both(&bytes).0.is_none(), "{rest}");
        }
    }

    #[test]
    fn a_huge_count_in_the_header_runs_out_of_bytes_not_memory() {
        let header = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
            element face 4000000000000\nproperty list uchar int vertex_indices\n";
        let bytes = file(false, header, &[0u8; 12]);
        let (fixed, general) = both(&bytes);
        assert!(fixed.is_none());
        assert!(general.is_err());
    }
}
