//! Stanford PLY: ASCII, binary little-endian and binary big-endian.
//!
//! Reads the `vertex` element's `x y z` (any numeric type) and the `face` element's
//! `vertex_indices` (or `vertex_index`) list; every other property and element is read past.
//! Writes binary little-endian (`float x y z`, `list uchar int vertex_indices`, or `list int
//! int` when a face has more than 255 corners), or ASCII on request.

use bevy::math::Vec3;
use std::fmt::Write as _;

use super::ParseError;
use super::text::cap;
use crate::mesh::soup::PolygonSoup;

/// How a PLY body is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    /// Text.
    Ascii,
    /// Binary, little-endian (the usual one).
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Where values come from: text tokens or binary bytes.
trait Values {
    fn next(&mut self, ty: Scalar, what: &str) -> Result<f64, ParseError>;
    /// An error at the current position.
    fn error(&self, message: String) -> ParseError;
}

struct Text<'a> {
    lines: std::iter::Peekable<Box<dyn Iterator<Item = (usize, &'a str)> + 'a>>,
    tokens: std::str::SplitWhitespace<'a>,
    line: usize,
}

impl Values for Text<'_> {
    fn error(&self, message: String) -> ParseError {
        ParseError::line(self.line, message)
    }

    fn next(&mut self, _ty: Scalar, what: &str) -> Result<f64, ParseError> {
        loop {
            if let Some(t) = self.tokens.next() {
                return t.parse::<f64>().map_err(|_| {
                    ParseError::line(self.line, format!("`{t}` is not a number ({what})"))
                });
            }
            let (line, text) = self.lines.next().ok_or_else(|| {
                ParseError::line(self.line, format!("file ends while reading {what}"))
            })?;
            self.line = line;
            self.tokens = text.split_whitespace();
        }
    }
}

struct Binary<'a> {
    data: &'a [u8],
    at: usize,
    big_endian: bool,
}

impl Values for Binary<'_> {
    fn error(&self, message: String) -> ParseError {
        ParseError::byte(self.at, message)
    }

    fn next(&mut self, ty: Scalar, what: &str) -> Result<f64, ParseError> {
        let n = ty.size();
        let bytes = self
            .data
            .get(self.at..self.at + n)
            .ok_or_else(|| ParseError::byte(self.at, format!("file ends while reading {what}")))?;
        self.at += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(bytes);
        if self.big_endian {
            b[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }
}

/// Parses a PLY file.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let (encoding, elements, body) = header(bytes)?;
    match encoding {
        PlyEncoding::Ascii => {
            let text = std::str::from_utf8(&bytes[body..])
                .map_err(|e| ParseError::byte(body + e.valid_up_to(), "ASCII body is not text"))?;
            let header_lines = bytes[..body].iter().filter(|&&b| b == b'\n').count();
            let lines: Box<dyn Iterator<Item = (usize, &str)>> = Box::new(
                text.lines()
                    .enumerate()
                    .map(move |(i, l)| (header_lines + i + 1, l)),
            );
            let mut values = Text {
                lines: lines.peekable(),
                tokens: "".split_whitespace(),
                line: header_lines,
            };
            body_values(&elements, &mut values, bytes.len())
        }
        PlyEncoding::BinaryLittleEndian | PlyEncoding::BinaryBigEndian => {
            let mut values = Binary {
                data: bytes,
                at: body,
                big_endian: encoding == PlyEncoding::BinaryBigEndian,
            };
            body_values(&elements, &mut values, bytes.len())
        }
    }
}

fn header(bytes: &[u8]) -> Result<(PlyEncoding, Vec<Element>, usize), ParseError> {
    if !bytes.starts_with(b"ply") {
        return Err(ParseError::line(1, "expected `ply`"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut at = 0;
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = i + 1;
        at += raw.len() + 1;
        let text = std::str::from_utf8(raw)
            .map_err(|_| ParseError::line(line, "header is not text"))?
            .trim();
        let mut t = text.split_whitespace();
        match t.next() {
            Some("ply") | Some("comment") | Some("obj_info") | None => {}
            Some("format") => {
                encoding = Some(match t.next() {
                    Some("ascii") => PlyEncoding::Ascii,
                    Some("binary_little_endian") => PlyEncoding::BinaryLittleEndian,
                    Some("binary_big_endian") => PlyEncoding::BinaryBigEndian,
                    other => {
                        return Err(ParseError::line(line, format!("unknown format {other:?}")));
                    }
                });
            }
            Some("element") => {
                let name = t.next().unwrap_or("").to_string();
                let count = t
                    .next()
                    .and_then(|c| c.parse::<usize>().ok())
                    .ok_or_else(|| ParseError::line(line, "element without a count"))?;
                elements.push(Element {
                    name,
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| ParseError::line(line, "property before any element"))?;
                let ty = |name: Option<&str>| {
                    name.and_then(Scalar::parse).ok_or_else(|| {
                        ParseError::line(line, format!("unknown property type {name:?}"))
                    })
                };
                let first = t.next();
                let property = if first == Some("list") {
                    let count = ty(t.next())?;
                    let item = ty(t.next())?;
                    Property::List(t.next().unwrap_or("").to_string(), count, item)
                } else {
                    Property::Scalar(t.next().unwrap_or("").to_string(), ty(first)?)
                };
                element.properties.push(property);
            }
            Some("end_header") => {
                let encoding =
                    encoding.ok_or_else(|| ParseError::line(line, "no `format` line"))?;
                return Ok((encoding, elements, at.min(bytes.len())));
            }
            Some(other) => {
                return Err(ParseError::line(
                    line,
                    format!("unknown header line `{other}`"),
                ));
            }
        }
    }
    Err(ParseError::byte(bytes.len(), "file ends inside the header"))
}

fn body_values(
    elements: &[Element],
    values: &mut dyn Values,
    len: usize,
) -> Result<PolygonSoup, ParseError> {
    let mut soup = PolygonSoup::default();
    let mut face = Vec::new();
    for element in elements {
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        if is_vertex {
            soup.positions.reserve(cap(element.count, len / 12));
        }
        for _ in 0..element.count {
            let mut p = [0.0f32; 3];
            for property in &element.properties {
                match property {
                    Property::Scalar(name, ty) => {
                        let v = values.next(*ty, name)?;
                        if is_vertex {
                            match name.as_str() {
                                "x" => p[0] = v as f32,
                                "y" => p[1] = v as f32,
                                "z" => p[2] = v as f32,
                                _ => {}
                            }
                        }
                    }
                    Property::List(name, count_ty, item_ty) => {
                        let n = values.next(*count_ty, name)?;
                        if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                            return Err(values.error(format!("bad list length {n}")));
                        }
                        let wanted =
                            is_face && (name == "vertex_indices" || name == "vertex_index");
                        if wanted {
                            face.clear();
                        }
                        for _ in 0..n as usize {
                            let v = values.next(*item_ty, name)?;
                            if wanted {
                                if v < 0.0 || v.fract() != 0.0 || v > f64::from(u32::MAX) {
                                    return Err(values.error(format!("bad vertex index {v}")));
                                }
                                face.push(v as u32);
                            }
                        }
                        if wanted {
                            soup.push_face(&face);
                        }
                    }
                }
            }
            if is_vertex {
                soup.positions.push(Vec3::from_array(p));
            }
        }
    }
    Ok(soup)
}

/// Encodes a soup as PLY.
pub fn write(soup: &PolygonSoup, encoding: PlyEncoding) -> Vec<u8> {
    let wide = soup.faces().any(|f| f.len() > 255);
    let count_type = if wide { "int" } else { "uchar" };
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut header = String::new();
    let _ = write!(
        header,
        "ply\nformat {format} 1.0\ncomment written by Pappus\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list {count_type} int vertex_indices\nend_header\n",
        soup.positions.len(),
        soup.face_count()
    );
    let mut out = header.into_bytes();
    match encoding {
        PlyEncoding::Ascii => {
            let mut body = String::new();
            for p in &soup.positions {
                let _ = writeln!(body, "{} {} {}", p.x, p.y, p.z);
            }
            for face in soup.faces() {
                let _ = write!(body, "{}", face.len());
                for &i in face {
                    let _ = write!(body, " {i}");
                }
                body.push('\n');
            }
            out.extend_from_slice(body.as_bytes());
        }
        PlyEncoding::BinaryLittleEndian | PlyEncoding::BinaryBigEndian => {
            let big = encoding == PlyEncoding::BinaryBigEndian;
            let put = |bytes: [u8; 4], out: &mut Vec<u8>| {
                if big {
                    out.extend(bytes.iter().rev());
                } else {
                    out.extend_from_slice(&bytes);
                }
            };
            out.reserve(soup.positions.len() * 12 + soup.indices.len() * 4 + soup.face_count());
            for p in &soup.positions {
                for c in [p.x, p.y, p.z] {
                    put(c.to_le_bytes(), &mut out);
                }
            }
            for face in soup.faces() {
                if wide {
                    put((face.len() as i32).to_le_bytes(), &mut out);
                } else {
                    out.push(face.len() as u8);
                }
                for &i in face {
                    put((i as i32).to_le_bytes(), &mut out);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_round_trips_both_ways() {
        let soup = crate::io::tests::mixed();
        for e in [
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
            PlyEncoding::Ascii,
        ] {
            assert_eq!(read(&write(&soup, e)).unwrap(), soup, "{e:?}");
        }
    }

    #[test]
    fn skips_other_properties_and_elements() {
        let text = b"ply\nformat ascii 1.0\ncomment hi\nelement vertex 3\nproperty double x\nproperty float nx\nproperty double y\nproperty double z\nproperty list uchar int junk\nelement face 1\nproperty uchar flags\nproperty list uchar uint vertex_index\nelement edge 1\nproperty int a\nproperty int b\nend_header\n0 9 0 0 2 7 7\n1 9 0 0 0\n0 9 1 0 1 5\n3 3 0 1 2\n0 1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(soup.face(0), &[0, 1, 2]);
    }

    #[test]
    fn truncated_files_are_errors_with_an_offset() {
        let bytes = write(&crate::io::tests::mixed(), PlyEncoding::BinaryLittleEndian);
        for cut in [3, 40, bytes.len() - 1] {
            let err = read(&bytes[..cut]).unwrap_err();
            assert!(
                err.location.starts_with("byte") || err.location.starts_with("line"),
                "{err:?}"
            );
        }
        let err = read(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap_err();
        assert_eq!(err.location, "line 8");
        assert!(read(b"plx\n").is_err());
        assert!(
            read(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\nend_header\n")
                .is_err()
        );
    }

    #[test]
    fn huge_counts_do_not_allocate_or_panic() {
        let text = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n";
        assert!(read(text).is_err());
    }
}
