//! Stanford PLY: ASCII, binary little-endian and binary big-endian.
//!
//! Reads the `vertex` element's `x y z` (any of the eight numeric types, converted to `f32`)
//! and the `face` element's `vertex_indices` (or `vertex_index`) list, whose count and index
//! may be any integer type. Two optional vertex properties are kept too, as MeshLab writes
//! them: `quality` (any numeric type, converted to `f32`) becomes the soup's
//! [`vertex_quality`](PolygonSoup::vertex_quality), and `red green blue` (all three, else
//! none) its [`vertex_colors`](PolygonSoup::vertex_colors): integer channels are taken as
//! they are, clamped to 0–255, floating-point ones as fractions of full intensity (0–1,
//! scaled by 255 and rounded). `nx ny nz` become vertex normals. Texture coordinates: per
//! vertex as `u v`, `s t`, `texture_u texture_v` or `texture_s texture_t` (every corner of the
//! vertex takes it), or per corner as a face's `texcoord` list of `u v` pairs (MeshLab's
//! convention; it wins over per-vertex ones), both becoming the soup's
//! [`corner_uvs`](PolygonSoup::corner_uvs). A `tristrips` element's `vertex_indices` list
//! holds triangle strips separated by `-1` ([`super::strips`]; the degenerate triangles that
//! turn a strip's corners are left out), as some Stanford scans were saved. Up to
//! [`MAX_SCALARS`] other scalar properties of the vertex (`confidence`, `intensity`, `alpha`,
//! …) become the soup's named [`vertex_scalars`](PolygonSoup::vertex_scalars); every other
//! property (a list, a normal missing a component) and every other element is read past, in
//! the order the header declares them, and named in the soup's notes. Up to [`MAX_SCALARS`]
//! scalar properties of the face (`quality`, `flags`, `area`, …, any name: a face has no column
//! of its own) become the soup's [`face_scalars`](PolygonSoup::face_scalars). The vertex element must have
//! `x`, `y` and `z`, and a face or strips element its index list. Indices
//! must be non-negative integers; out-of-range ones are kept for the builder to drop. In an
//! ASCII body a `float` property is parsed as an `f32` directly (not through `f64`), so what
//! the writer prints reads back bit for bit.
//!
//! Writes `float x y z`, then `float nx ny nz` with normals, `uchar red green blue` with
//! colours, `float quality` with a quality (MeshLab's order, without its `alpha`), a `float`
//! property for each other vertex scalar, and `float u
//! v` when the soup's corner UVs agree at every vertex, each only when it holds one value per
//! position; then `list uchar int vertex_indices` (`list int int` when a
//! face has more than 255 corners, `uint` indices when one exceeds `i32::MAX`), binary
//! little-endian by default or ASCII / big-endian on request, followed by `list uchar float
//! texcoord` when the corner UVs differ at some vertex (a seam), and a `float` property for each
//! face scalar with one value per face. A soup without attributes gets
//! exactly the plain `x y z` header.

mod fixed_rows;
mod rows;

use bevy::math::{Vec2, Vec3};
use std::fmt::Write as _;

use super::strips::strip_triangles;
use super::text::Numbers;
use crate::io::error::ParseError;
use crate::mesh::soup::PolygonSoup;
use rows::{
    Element, MAX_SCALARS, Property, Role, Row, Scalar, corner_uvs_of_vertices, finish_face_columns,
    push_face_scalars, reserve_face_columns, reserve_vertex_columns,
};

/// How a PLY body is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    /// Text, one element per line.
    Ascii,
    /// Binary, little-endian (the usual one, and what [`crate::io::write()`] saves).
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

/// Where values come from: text tokens or binary bytes.
trait Values {
    /// The next value, of type `ty`, for the property `what`.
    fn next(&mut self, ty: Scalar, what: &str) -> Result<f64, ParseError>;
    /// An error at the current position.
    fn error(&self, message: String) -> ParseError;
}

/// An ASCII body: whitespace-separated tokens, lines counted for messages.
struct Text<'a> {
    lines: std::str::Lines<'a>,
    tokens: std::str::SplitWhitespace<'a>,
    line: usize,
    numbers: Numbers,
}

impl Values for Text<'_> {
    fn error(&self, message: String) -> ParseError {
        ParseError::line(self.line, message)
    }

    fn next(&mut self, ty: Scalar, what: &str) -> Result<f64, ParseError> {
        loop {
            if let Some(t) = self.tokens.next() {
                // A `float` parsed through `f64` and rounded again could, rarely, land one ulp
                // off the value the writer printed.
                let value = if ty == Scalar::F32 {
                    self.numbers.parse::<f32>(t, self.line).map(f64::from)
                } else {
                    self.numbers.parse::<f64>(t, self.line)
                };
                return value.ok_or_else(|| {
                    ParseError::line(self.line, format!("`{t}` is not a number ({what})"))
                });
            }
            let text = self.lines.next().ok_or_else(|| {
                ParseError::line(self.line, format!("file ends while reading `{what}`"))
            })?;
            self.line += 1;
            self.tokens = text.split_whitespace();
        }
    }
}

/// A binary body.
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
        let bytes = self.data.get(self.at..self.at + n).ok_or_else(|| {
            ParseError::byte(self.at, format!("file ends while reading `{what}`"))
        })?;
        self.at += n;
        Ok(ty.decode(bytes, self.big_endian))
    }
}

/// Parses a PLY file.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let Header {
        encoding,
        elements,
        body,
        foreign,
    } = header(bytes)?;
    let header_lines = bytes[..body].iter().filter(|&&b| b == b'\n').count();
    let mut soup = match encoding {
        PlyEncoding::Ascii => {
            let text = std::str::from_utf8(&bytes[body..]).map_err(|e| {
                let valid = &bytes[body..body + e.valid_up_to()];
                let line = header_lines + 1 + valid.iter().filter(|&&b| b == b'\n').count();
                ParseError::line(line, "the ASCII body is not text")
            })?;
            let mut values = Text {
                lines: text.lines(),
                tokens: "".split_whitespace(),
                line: header_lines,
                numbers: Numbers::default(),
            };
            body_values(&elements, &mut values, bytes.len()).map(|mut soup| {
                soup.notes.extend(values.numbers.note());
                soup
            })
        }
        PlyEncoding::BinaryLittleEndian | PlyEncoding::BinaryBigEndian => {
            let big_endian = encoding == PlyEncoding::BinaryBigEndian;
            match fixed_rows::read(bytes, body, big_endian, &elements) {
                Some(soup) => Ok(soup),
                None => {
                    let mut values = Binary {
                        data: bytes,
                        at: body,
                        big_endian,
                    };
                    body_values(&elements, &mut values, bytes.len())
                }
            }
        }
    }?;
    if let (count, Some((line, text))) = foreign {
        soup.notes.push(format!(
            "read past {count} header line(s) that are not PLY keywords, as comments (the \
             first, line {line}: `{text}`)"
        ));
    }
    soup.notes.extend(skipped_note(&elements));
    Ok(soup)
}

/// A PLY header, read.
struct Header {
    encoding: PlyEncoding,
    elements: Vec<Element>,
    /// The byte offset where the body starts.
    body: usize,
    /// How many lines start with no PLY keyword (an exporter's `Created by …` between `format`
    /// and the elements), and the first with its line number: read past as comments, as other
    /// readers do.
    foreign: (usize, Option<(usize, String)>),
}

/// Reads the header: the encoding, the elements, and where the body starts.
fn header(bytes: &[u8]) -> Result<Header, ParseError> {
    let first = bytes.split(|&b| b == b'\n').next().unwrap_or_default();
    if first.trim_ascii() != b"ply" {
        return Err(ParseError::line(1, "expected `ply`"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut foreign = (0, None);
    // The names of the vertex and the face scalars kept as columns, by column.
    let mut scalars: [Vec<String>; 2] = Default::default();
    let mut at = 0;
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = i + 1;
        at += raw.len() + 1;
        let text = std::str::from_utf8(raw)
            .map_err(|_| ParseError::line(line, "the header is not text"))?;
        let mut t = text.split_whitespace();
        match t.next() {
            Some("ply" | "comment" | "obj_info") | None => {}
            Some("format") => {
                encoding = Some(match t.next() {
                    Some("ascii") => PlyEncoding::Ascii,
                    Some("binary_little_endian") => PlyEncoding::BinaryLittleEndian,
                    Some("binary_big_endian") => PlyEncoding::BinaryBigEndian,
                    other => {
                        let other = other.unwrap_or("");
                        return Err(
                            ParseError::line(line, format!("format `{other}`")).unsupported()
                        );
                    }
                });
            }
            Some("element") => {
                let name = t.next().unwrap_or("").to_string();
                let count = t.next();
                let count = count.and_then(|c| c.parse::<usize>().ok()).ok_or_else(|| {
                    ParseError::line(
                        line,
                        format!("element `{name}` needs a count, found {count:?}"),
                    )
                })?;
                elements.push(Element {
                    name,
                    count,
                    properties: Vec::new(),
                    line,
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| ParseError::line(line, "property before any element"))?;
                let mut property = property(&element.name, &mut t, line)?;
                keep_as_column(&element.name, &mut property, &mut scalars);
                element.properties.push(property);
            }
            Some("end_header") => {
                let encoding = encoding.ok_or_else(|| {
                    ParseError::line(line, "no `format` line before `end_header`")
                })?;
                for element in &elements {
                    check_element(element)?;
                }
                return Ok(Header {
                    encoding,
                    elements,
                    body: at.min(bytes.len()),
                    foreign,
                });
            }
            Some(_) => {
                foreign.0 += 1;
                foreign
                    .1
                    .get_or_insert_with(|| (line, text.trim().to_owned()));
            }
        }
    }
    Err(ParseError::byte(bytes.len(), "file ends inside the header"))
}

/// Makes a `vertex` or `face` element's scalar property that has no role of its own a kept
/// column ([`Role::Scalar`], [`Role::FaceScalar`]), the same column for the same name in
/// another element of that name. `scalars` holds the vertex columns' names, then the faces'.
fn keep_as_column(element: &str, property: &mut Property, scalars: &mut [Vec<String>; 2]) {
    let Property::Scalar { name, role, .. } = property else {
        return;
    };
    let (scalars, kept): (_, fn(usize) -> Role) = match element {
        "vertex" => (&mut scalars[0], Role::Scalar),
        "face" => (&mut scalars[1], Role::FaceScalar),
        _ => return,
    };
    if *role != Role::Skip {
        return;
    }
    let column = match scalars.iter().position(|s| s == name) {
        Some(k) => k,
        None if scalars.len() < MAX_SCALARS && !name.is_empty() => {
            scalars.push(name.clone());
            scalars.len() - 1
        }
        None => return,
    };
    *role = kept(column);
}

/// A `property` line's declaration after its keyword (`float x`, `list uchar int
/// vertex_indices`), with the role its name has in `element`.
fn property<'a>(
    element: &str,
    t: &mut impl Iterator<Item = &'a str>,
    line: usize,
) -> Result<Property, ParseError> {
    let ty = |name: Option<&str>| {
        let name = name.unwrap_or("");
        Scalar::parse(name)
            .ok_or_else(|| ParseError::line(line, format!("property type `{name}`")).unsupported())
    };
    let first = t.next();
    if first == Some("list") {
        let count = ty(t.next())?;
        let item = ty(t.next())?;
        if !count.is_integer() {
            return Err(ParseError::line(line, "a list's count must be an integer"));
        }
        let name = t.next().unwrap_or("").to_string();
        let indices = name == "vertex_indices" || name == "vertex_index";
        let role = if indices && element == "face" {
            Role::Corners
        } else if indices && element == "tristrips" {
            Role::Strip
        } else if element == "face" && name == "texcoord" && !item.is_integer() {
            Role::TexCoord
        } else {
            Role::Skip
        };
        Ok(Property::List {
            name,
            count,
            item,
            role,
        })
    } else {
        let ty = ty(first)?;
        let name = t.next().unwrap_or("").to_string();
        let role = match element {
            "vertex" => vertex_role(&name),
            _ => Role::Skip,
        };
        Ok(Property::Scalar { name, ty, role })
    }
}

/// What a vertex property called `name` is read as: a column of the mesh's own, or a named
/// scalar ([`Role::Skip`] here; the reader keeps it by name).
fn vertex_role(name: &str) -> Role {
    match name {
        "x" => Role::Coordinate(0),
        "y" => Role::Coordinate(1),
        "z" => Role::Coordinate(2),
        "quality" => Role::Quality,
        "nx" => Role::Normal(0),
        "ny" => Role::Normal(1),
        "nz" => Role::Normal(2),
        "red" => Role::Color(0),
        "green" => Role::Color(1),
        "blue" => Role::Color(2),
        "u" | "s" | "texture_u" | "texture_s" => Role::Uv(0),
        "v" | "t" | "texture_v" | "texture_t" => Role::Uv(1),
        _ => Role::Skip,
    }
}

/// Whether a vertex scalar called `name` would come back from a PLY as itself: a name with no
/// whitespace that is none of the columns Pappus reads by name (`x`, `nx`, `red`, `u`, …; a
/// scalar `x` would be read as the vertices' x). `quality` is its own column and comes back.
pub fn keeps_vertex_scalar(name: &str) -> bool {
    !name.is_empty()
        && !name.chars().any(char::is_whitespace)
        && matches!(vertex_role(name), Role::Skip | Role::Quality)
}

/// Whether a face scalar called `name` would come back from a PLY as itself: a name with no
/// whitespace that is not one of the face's lists (`vertex_indices`, `vertex_index`,
/// `texcoord`).
pub fn keeps_face_scalar(name: &str) -> bool {
    !name.is_empty()
        && !name.chars().any(char::is_whitespace)
        && !matches!(name, "vertex_indices" | "vertex_index" | "texcoord")
}

/// A non-empty `vertex` element needs `x y z`; a non-empty `face` element needs its index list.
fn check_element(element: &Element) -> Result<(), ParseError> {
    let has = |role: Role| {
        element.properties.iter().any(|p| match p {
            Property::Scalar { role: r, .. } | Property::List { role: r, .. } => *r == role,
        })
    };
    if element.count == 0 {
        return Ok(());
    }
    let missing = match element.name.as_str() {
        "vertex" => (0..3)
            .find(|&k| !has(Role::Coordinate(k)))
            .map(|k| ["property `x`", "property `y`", "property `z`"][k]),
        "face" => (!has(Role::Corners)).then_some("list `vertex_indices`"),
        "tristrips" => (!has(Role::Strip)).then_some("list `vertex_indices`"),
        _ => None,
    };
    match missing {
        Some(what) => Err(ParseError::line(
            element.line,
            format!("element `{}` has no {what}", element.name),
        )),
        None => Ok(()),
    }
}

/// Reads every element's values in header order, keeping positions, faces, and the vertices'
/// quality and colours when the vertex element has them.
///
/// Every value read consumes at least one byte or token, so a huge count in the header makes
/// the reader run out of input, not memory (an element without properties is not looped over).
fn body_values<V: Values>(
    elements: &[Element],
    values: &mut V,
    len: usize,
) -> Result<PolygonSoup, ParseError> {
    let mut soup = PolygonSoup::default();
    // Per-vertex UVs (one per position when any vertex element has them), and per-corner ones
    // from faces' `texcoord` lists (one per corner of every face read, when any face has one).
    let mut vertex_uv: Option<Vec<Vec2>> = None;
    let mut face_uv: Option<Vec<Vec2>> = None;
    let mut bad_texcoords = 0usize;
    let mut lists = Lists::default();
    for element in elements {
        if element.properties.is_empty() {
            continue;
        }
        let has_texcoord = element.properties.iter().any(|p| {
            matches!(
                p,
                Property::List {
                    role: Role::TexCoord,
                    ..
                }
            )
        });
        if has_texcoord && face_uv.is_none() {
            face_uv = Some(vec![Vec2::ZERO; soup.indices.len()]);
        }
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        if is_vertex {
            reserve_vertex_columns(element, &mut soup, &mut vertex_uv, len);
        }
        if is_face {
            reserve_face_columns(element, &mut soup);
        }
        for _ in 0..element.count {
            let corners_before = soup.indices.len();
            lists.texcoord.clear();
            let mut row = Row::default();
            for property in &element.properties {
                match property {
                    Property::Scalar { name, ty, role } => {
                        row.set(*role, *ty, values.next(*ty, name)?);
                    }
                    Property::List {
                        name,
                        count,
                        item,
                        role,
                    } => lists.read(values, name, (*count, *item), *role, &mut soup)?,
                }
            }
            if is_vertex {
                row.push_vertex(&mut soup, &mut vertex_uv);
            }
            if is_face {
                push_face_scalars(&row, &mut soup);
            }
            if let Some(face_uv) = &mut face_uv {
                let corners = soup.indices.len() - corners_before;
                if has_texcoord && lists.texcoord.len() == 2 * corners {
                    let uvs = lists.texcoord.chunks_exact(2);
                    face_uv.extend(uvs.map(|c| Vec2::new(c[0], c[1])));
                } else {
                    if has_texcoord && corners > 0 {
                        bad_texcoords += 1;
                    }
                    face_uv.extend(std::iter::repeat_n(Vec2::ZERO, corners));
                }
            }
        }
    }
    if bad_texcoords > 0 {
        soup.notes.push(format!(
            "{bad_texcoords} face(s) whose `texcoord` list does not hold 2 values per corner: their UVs are (0, 0)"
        ));
    }
    finish_face_columns(&mut soup);
    // Per-face UVs win; per-vertex ones give every corner of a vertex the same UV.
    soup.corner_uvs = face_uv.or_else(|| corner_uvs_of_vertices(&soup, vertex_uv));
    Ok(soup)
}

/// The list properties of the row being read: its corners (or strips) and its `texcoord`
/// values.
#[derive(Default)]
struct Lists {
    corners: Vec<u32>,
    texcoord: Vec<f32>,
}

impl Lists {
    /// Reads one list property (its count and item types in `types`): corners become a face
    /// (strips their triangles), `texcoord` values are kept for the row, others are read past.
    fn read<V: Values>(
        &mut self,
        values: &mut V,
        name: &str,
        (count, item): (Scalar, Scalar),
        role: Role,
        soup: &mut PolygonSoup,
    ) -> Result<(), ParseError> {
        let n = values.next(count, name)?;
        if n < 0.0 || n.fract() != 0.0 {
            return Err(values.error(format!("`{name}` has {n} items")));
        }
        let corners = matches!(role, Role::Corners | Role::Strip);
        self.corners.clear();
        for _ in 0..n as u64 {
            let v = values.next(item, name)?;
            if role == Role::TexCoord {
                self.texcoord.push(v as f32);
            }
            if corners {
                let restart = role == Role::Strip && v == -1.0;
                if !restart && (v < 0.0 || v.fract() != 0.0 || v > f64::from(u32::MAX)) {
                    return Err(values.error(format!("bad vertex index {v}")));
                }
                self.corners
                    .push(if restart { STRIP_RESTART } else { v as u32 });
            }
        }
        match role {
            Role::Corners => soup.push_face(&self.corners),
            Role::Strip => push_strips(soup, &self.corners),
            _ => {}
        }
        Ok(())
    }
}

/// A `-1` in a `tristrips` list: the strip ends and the next begins.
const STRIP_RESTART: u32 = u32::MAX;

/// Pushes the triangles of a `tristrips` list (strips separated by `-1`), leaving out the
/// degenerate ones strips use to turn corners.
fn push_strips(soup: &mut PolygonSoup, list: &[u32]) {
    for strip in list.split(|&v| v == STRIP_RESTART) {
        for triangle in strip_triangles(strip, |v| v) {
            soup.push_face(&triangle);
        }
    }
}

/// What the header declares that the reader reads past (elements other than `vertex`, `face`
/// and `tristrips`, and properties it has no use for), as one note; `None` when nothing is.
fn skipped_note(elements: &[Element]) -> Option<String> {
    let mut skipped = Vec::new();
    for element in elements.iter().filter(|e| e.count > 0) {
        if !matches!(element.name.as_str(), "vertex" | "face" | "tristrips") {
            skipped.push(format!("element `{}` ({})", element.name, element.count));
            continue;
        }
        let roles: Vec<Role> = element
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar { role, .. } | Property::List { role, .. } => *role,
            })
            .collect();
        // A normal, colour or UV is kept only when all its components are there.
        let whole = |part: fn(usize) -> Role, n: usize| (0..n).all(|k| roles.contains(&part(k)));
        for property in &element.properties {
            let (Property::Scalar { name, role, .. } | Property::List { name, role, .. }) =
                property;
            let read = match role {
                Role::Skip => false,
                Role::Normal(_) => whole(Role::Normal, 3),
                Role::Color(_) => whole(Role::Color, 3),
                Role::Uv(_) => whole(Role::Uv, 2),
                _ => true,
            };
            if !read {
                skipped.push(format!("`{}` property `{name}`", element.name));
            }
        }
    }
    (!skipped.is_empty()).then(|| format!("skipped: {}", skipped.join(", ")))
}

/// The UV of each vertex when every corner of every vertex has the same one (bit for bit;
/// a vertex no face uses gets (0, 0)), else `None`.
fn per_vertex_uv(soup: &PolygonSoup, uvs: &[Vec2]) -> Option<Vec<Vec2>> {
    let mut out: Vec<Option<Vec2>> = vec![None; soup.positions.len()];
    let bits = |uv: Vec2| uv.to_array().map(f32::to_bits);
    for (&i, &uv) in soup.indices.iter().zip(uvs) {
        let slot = out.get_mut(i as usize)?;
        match slot {
            Some(seen) if bits(*seen) != bits(uv) => return None,
            Some(_) => {}
            None => *slot = Some(uv),
        }
    }
    Some(out.into_iter().map(|uv| uv.unwrap_or(Vec2::ZERO)).collect())
}

/// Encodes a soup as PLY: positions, then normals, colours, quality, other scalars and UVs when the soup
/// carries them (one per position; an attribute of another length is left out), then faces
/// (with a `texcoord` list per face when the UVs differ between corners of one vertex).
pub fn write(soup: &PolygonSoup, encoding: PlyEncoding) -> Vec<u8> {
    let layout = Layout::of(soup);
    let mut out = layout.header(soup, encoding).into_bytes();
    match encoding {
        PlyEncoding::Ascii => {
            let mut body =
                String::with_capacity(soup.positions.len() * 48 + soup.indices.len() * 8);
            layout.ascii_vertices(soup, &mut body);
            layout.ascii_faces(soup, &mut body);
            out.extend_from_slice(body.as_bytes());
        }
        PlyEncoding::BinaryLittleEndian | PlyEncoding::BinaryBigEndian => {
            let big = encoding == PlyEncoding::BinaryBigEndian;
            out.reserve(soup.positions.len() * 31 + soup.indices.len() * 4 + soup.face_count() * 4);
            layout.binary_vertices(soup, big, &mut out);
            layout.binary_faces(soup, big, &mut out);
        }
    }
    out
}

/// What a written PLY holds: the vertex properties the soup has whole, where its UVs go, and the
/// list types its faces need.
struct Layout<'a> {
    quality: Option<&'a [f32]>,
    /// The other vertex scalars with one value per position and a name PLY can hold.
    scalars: Vec<(&'a str, &'a [f32])>,
    /// The face scalars with one value per face and a name PLY can hold.
    face_scalars: Vec<(&'a str, &'a [f32])>,
    colors: Option<&'a [[u8; 3]]>,
    normals: Option<&'a [Vec3]>,
    /// One UV a vertex, when every corner of each vertex has the same UV (bit for bit).
    vertex_uv: Option<Vec<Vec2>>,
    /// Else the corners' UVs, in the faces' `texcoord` lists: never one UV lost.
    face_uv: Option<&'a [Vec2]>,
    /// A face's corner count: `uchar`, or `int` past 255.
    count_type: Scalar,
    /// `int`, or `uint` past `i32::MAX`.
    index_type: Scalar,
    /// A `texcoord` list's count (two values a corner): `uchar`, or `int` past 255.
    texcoord_count: Scalar,
}

/// `value`'s four bytes in the file's byte order.
fn put(value: [u8; 4], big: bool, out: &mut Vec<u8>) {
    if big {
        out.extend(value.iter().rev());
    } else {
        out.extend_from_slice(&value);
    }
}

/// A list's count in its type (`uchar` or a four-byte integer).
fn put_count(count: usize, scalar: Scalar, big: bool, out: &mut Vec<u8>) {
    if scalar == Scalar::U8 {
        out.push(count as u8);
    } else {
        put((count as u32).to_le_bytes(), big, out);
    }
}

impl<'a> Layout<'a> {
    fn of(soup: &'a PolygonSoup) -> Self {
        let n = soup.positions.len();
        let corner_uvs = soup
            .corner_uvs
            .as_deref()
            .filter(|u| u.len() == soup.indices.len());
        let vertex_uv = corner_uvs.and_then(|uvs| per_vertex_uv(soup, uvs));
        let list_type = |longest_past_255: bool| match longest_past_255 {
            true => Scalar::I32,
            false => Scalar::U8,
        };
        let whole = |columns: &'a [(String, Vec<f32>)], len: usize, keeps: fn(&str) -> bool| {
            columns
                .iter()
                .filter(move |(name, column)| column.len() == len && keeps(name))
                .map(|(name, column)| (name.as_str(), column.as_slice()))
                .collect()
        };
        Self {
            quality: soup.vertex_quality.as_deref().filter(|q| q.len() == n),
            scalars: whole(&soup.vertex_scalars, n, keeps_vertex_scalar),
            face_scalars: whole(&soup.face_scalars, soup.face_count(), keeps_face_scalar),
            colors: soup.vertex_colors.as_deref().filter(|c| c.len() == n),
            normals: soup.vertex_normals.as_deref().filter(|v| v.len() == n),
            face_uv: corner_uvs.filter(|_| vertex_uv.is_none()),
            vertex_uv,
            count_type: list_type(soup.faces().any(|f| f.len() > 255)),
            index_type: match soup.indices.iter().any(|&i| i > i32::MAX as u32) {
                true => Scalar::U32,
                false => Scalar::I32,
            },
            texcoord_count: list_type(soup.faces().any(|f| 2 * f.len() > 255)),
        }
    }

    fn header(&self, soup: &PolygonSoup, encoding: PlyEncoding) -> String {
        let format = match encoding {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        };
        let type_name = |s: Scalar| match s {
            Scalar::U8 => "uchar",
            Scalar::U32 => "uint",
            _ => "int",
        };
        let mut header = String::new();
        let _ = write!(
            header,
            "ply\nformat {format} 1.0\ncomment written by Pappus\nelement vertex {}\n\
             property float x\nproperty float y\nproperty float z\n",
            soup.positions.len()
        );
        if self.normals.is_some() {
            header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
        }
        if self.colors.is_some() {
            header.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
        }
        if self.quality.is_some() {
            header.push_str("property float quality\n");
        }
        for (name, _) in &self.scalars {
            let _ = writeln!(header, "property float {name}");
        }
        if self.vertex_uv.is_some() {
            header.push_str("property float u\nproperty float v\n");
        }
        let _ = write!(
            header,
            "element face {}\nproperty list {} {} vertex_indices\n",
            soup.face_count(),
            type_name(self.count_type),
            type_name(self.index_type),
        );
        if self.face_uv.is_some() {
            let _ = writeln!(
                header,
                "property list {} float texcoord",
                type_name(self.texcoord_count)
            );
        }
        for (name, _) in &self.face_scalars {
            let _ = writeln!(header, "property float {name}");
        }
        header.push_str("end_header\n");
        header
    }

    fn ascii_vertices(&self, soup: &PolygonSoup, body: &mut String) {
        for (i, p) in soup.positions.iter().enumerate() {
            let _ = write!(body, "{} {} {}", p.x, p.y, p.z);
            if let Some(normals) = self.normals {
                let v = normals[i];
                let _ = write!(body, " {} {} {}", v.x, v.y, v.z);
            }
            if let Some(colors) = self.colors {
                let [r, g, b] = colors[i];
                let _ = write!(body, " {r} {g} {b}");
            }
            if let Some(quality) = self.quality {
                let _ = write!(body, " {}", quality[i]);
            }
            for (_, column) in &self.scalars {
                let _ = write!(body, " {}", column[i]);
            }
            if let Some(uv) = &self.vertex_uv {
                let _ = write!(body, " {} {}", uv[i].x, uv[i].y);
            }
            body.push('\n');
        }
    }

    fn ascii_faces(&self, soup: &PolygonSoup, body: &mut String) {
        for (f, face) in soup.faces().enumerate() {
            let _ = write!(body, "{}", face.len());
            for &i in face {
                let _ = write!(body, " {i}");
            }
            if let Some(uvs) = self.face_uv {
                let start = soup.face_starts[f] as usize;
                let _ = write!(body, " {}", 2 * face.len());
                for uv in &uvs[start..start + face.len()] {
                    let _ = write!(body, " {} {}", uv.x, uv.y);
                }
            }
            for (_, column) in &self.face_scalars {
                let _ = write!(body, " {}", column[f]);
            }
            body.push('\n');
        }
    }

    fn binary_vertices(&self, soup: &PolygonSoup, big: bool, out: &mut Vec<u8>) {
        for (i, p) in soup.positions.iter().enumerate() {
            for c in [p.x, p.y, p.z] {
                put(c.to_le_bytes(), big, out);
            }
            if let Some(normals) = self.normals {
                for c in normals[i].to_array() {
                    put(c.to_le_bytes(), big, out);
                }
            }
            if let Some(colors) = self.colors {
                out.extend_from_slice(&colors[i]);
            }
            if let Some(quality) = self.quality {
                put(quality[i].to_le_bytes(), big, out);
            }
            for (_, column) in &self.scalars {
                put(column[i].to_le_bytes(), big, out);
            }
            if let Some(uv) = &self.vertex_uv {
                put(uv[i].x.to_le_bytes(), big, out);
                put(uv[i].y.to_le_bytes(), big, out);
            }
        }
    }

    fn binary_faces(&self, soup: &PolygonSoup, big: bool, out: &mut Vec<u8>) {
        for (f, face) in soup.faces().enumerate() {
            put_count(face.len(), self.count_type, big, out);
            // An index fits `int` unless `uint` was chosen; the bytes are the same.
            for &i in face {
                put(i.to_le_bytes(), big, out);
            }
            if let Some(uvs) = self.face_uv {
                let start = soup.face_starts[f] as usize;
                put_count(2 * face.len(), self.texcoord_count, big, out);
                for uv in &uvs[start..start + face.len()] {
                    put(uv.x.to_le_bytes(), big, out);
                    put(uv.y.to_le_bytes(), big, out);
                }
            }
            for (_, column) in &self.face_scalars {
                put(column[f].to_le_bytes(), big, out);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::tests::{mixed, same_bits};

    const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

    #[test]
    fn every_encoding_round_trips() {
        for e in [
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
            PlyEncoding::Ascii,
        ] {
            assert!(
                same_bits(&read(&write(&mixed(), e)).unwrap(), &mixed()),
                "{e:?}"
            );
        }
    }

    /// A scanner's vertex scalars (and MeshLab's `alpha` after the colours) are kept by name,
    /// value for value, in every encoding and through the writer; a ninth is read past and
    /// named.
    #[test]
    fn a_scalar_comes_back_unless_its_name_is_a_column_of_its_own() {
        for kept in ["confidence", "quality", "height_2"] {
            assert!(keeps_vertex_scalar(kept), "{kept}");
        }
        for taken in ["x", "nz", "red", "u", "t", "texture_v", "a b", ""] {
            assert!(!keeps_vertex_scalar(taken), "{taken}");
        }
        for kept in ["quality", "red", "x", "label"] {
            assert!(keeps_face_scalar(kept), "{kept}");
        }
        for taken in ["vertex_indices", "vertex_index", "texcoord", "a\tb", ""] {
            assert!(!keeps_face_scalar(taken), "{taken}");
        }
    }

    #[test]
    fn other_vertex_scalars_are_kept_by_name() {
        let mut header = format!(
            "element vertex 3\n{XYZ}property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\nproperty double confidence\nproperty short intensity\n"
        );
        for k in 0..6 {
            let _ = writeln!(header, "property float extra{k}");
        }
        header.push_str("element face 1\nproperty list uchar int vertex_indices\nproperty float area\nend_header\n");
        let extras = " 0 0 0 0 0 0";
        let ascii = format!(
            "ply\nformat ascii 1.0\n{header}0 0 0 1 2 3 255 0.25 -7{extras}\n1 0 0 1 2 3 128 0.5 8{extras}\n0 1 0 1 2 3 0 1e-3 9{extras}\n3 0 1 2 0.5\n"
        );
        let soup = read(ascii.as_bytes()).unwrap();
        let names: Vec<&str> = soup
            .vertex_scalars
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(
            names,
            [
                "alpha",
                "confidence",
                "intensity",
                "extra0",
                "extra1",
                "extra2",
                "extra3",
                "extra4"
            ]
        );
        assert_eq!(soup.vertex_scalars[0].1, [255.0, 128.0, 0.0]);
        assert_eq!(soup.vertex_scalars[1].1, [0.25, 0.5, 1e-3_f64 as f32]);
        assert_eq!(soup.vertex_scalars[2].1, [-7.0, 8.0, 9.0]);
        assert_eq!(soup.vertex_colors, Some(vec![[1, 2, 3]; 3]));
        assert_eq!(soup.notes, ["skipped: `vertex` property `extra5`"]);
        assert_eq!(soup.vertex_attributes(), names);
        for e in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let back = read(&write(&soup, e)).unwrap();
            assert_eq!(back.vertex_scalars, soup.vertex_scalars, "{e:?}");
        }
    }

    /// A face's scalars are kept by name, whatever the name, one value a face in face order:
    /// before or after the corners list, in every encoding and through the writer (binary
    /// bodies through the general reader, which the fixed-row one leaves them to). A face of a
    /// later element without the property, or of strips, gets NaN; a ninth is read past.
    #[test]
    fn face_scalars_are_kept_by_name_with_nan_where_a_face_has_none() {
        let mut header = format!(
            "element vertex 4\n{XYZ}element face 2\nproperty uchar flags\n\
             property list uchar int vertex_indices\nproperty double quality\nproperty float red\n"
        );
        for k in 0..6 {
            let _ = writeln!(header, "property float extra{k}");
        }
        header.push_str(
            "element tristrips 1\nproperty list int int vertex_indices\n\
             element face 1\nproperty list uchar int vertex_indices\nproperty float quality\n\
             end_header\n",
        );
        let extras = " 0 0 0 0 0 0";
        let ascii = format!(
            "ply\nformat ascii 1.0\n{header}0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
             7 3 0 1 2 0.25 255{extras}\n3 3 0 2 3 -1.5 0{extras}\n4 0 1 2 3\n3 1 2 3 8\n"
        );
        let soup = read(ascii.as_bytes()).unwrap();
        let names: Vec<&str> = soup.face_scalars.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "flags", "quality", "red", "extra0", "extra1", "extra2", "extra3", "extra4"
            ]
        );
        let bits = |s: &PolygonSoup| -> Vec<Vec<u32>> {
            let column = |c: &Vec<f32>| c.iter().map(|x| x.to_bits()).collect();
            s.face_scalars.iter().map(|(_, c)| column(c)).collect()
        };
        let nan = f32::NAN.to_bits();
        // Two faces of the first element, two triangles of the strip, one of the last element.
        assert_eq!(soup.face_count(), 5);
        assert_eq!(
            bits(&soup)[0],
            [7.0f32.to_bits(), 3.0f32.to_bits(), nan, nan, nan]
        );
        let quality = [0.25f32, -1.5].map(f32::to_bits);
        assert_eq!(
            bits(&soup)[1],
            [quality[0], quality[1], nan, nan, 8.0f32.to_bits()]
        );
        assert_eq!(bits(&soup)[2][..2], [255.0f32.to_bits(), 0]);
        assert_eq!(soup.notes, ["skipped: `face` property `extra5`"]);
        assert_eq!(
            soup.scalars_not_kept().as_deref(),
            Some("face flags, quality, red, extra0, extra1, extra2, extra3 and extra4")
        );
        for e in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let back = read(&write(&soup, e)).unwrap();
            assert_eq!(bits(&back), bits(&soup), "{e:?}");
            assert!(same_bits(&back, &soup), "{e:?}");
        }
    }

    /// `mixed()` with a quality and a colour on each of its five vertices: a third, a
    /// negative zero, a subnormal, the most negative `f32`, infinity.
    fn attributed() -> PolygonSoup {
        let mut soup = mixed();
        soup.vertex_quality = Some(vec![1.0 / 3.0, -0.0, 1.0e-40, f32::MIN, f32::INFINITY]);
        soup.vertex_colors = Some(vec![
            [0, 0, 0],
            [255, 255, 255],
            [255, 0, 128],
            [1, 2, 3],
            [200, 100, 50],
        ]);
        soup
    }

    fn quality_bits(soup: &PolygonSoup) -> Option<Vec<u32>> {
        let q = soup.vertex_quality.as_ref()?;
        Some(q.iter().map(|q| q.to_bits()).collect())
    }

    #[test]
    fn normals_round_trip_bit_for_bit_before_colours() {
        let mut soup = attributed();
        soup.vertex_normals = Some(
            (0..soup.positions.len())
                .map(|i| Vec3::new(1.0 / (i as f32 + 3.0), -0.0, 1.0))
                .collect(),
        );
        for e in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let bytes = write(&soup, e);
            let header = String::from_utf8_lossy(&bytes);
            assert!(
                header.contains("property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"),
                "{e:?}: {header}"
            );
            let back = read(&bytes).unwrap();
            let bits = |s: &PolygonSoup| {
                s.vertex_normals.as_ref().map(|v| {
                    v.iter()
                        .flat_map(|n| n.to_array().map(f32::to_bits))
                        .collect::<Vec<u32>>()
                })
            };
            assert_eq!(bits(&back), bits(&soup), "{e:?}");
            assert_eq!(quality_bits(&back), quality_bits(&soup), "{e:?}");
        }
    }

    #[test]
    fn quality_and_colours_round_trip_bit_for_bit() {
        let soup = attributed();
        for e in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let bytes = write(&soup, e);
            let header = String::from_utf8_lossy(&bytes);
            assert!(
                header.contains(
                    "property float z\nproperty uchar red\nproperty uchar green\n\
                     property uchar blue\nproperty float quality\nelement face 2\n"
                ),
                "{e:?}: {header}"
            );
            let back = read(&bytes).unwrap();
            assert!(same_bits(&back, &soup), "{e:?}");
            assert_eq!(quality_bits(&back), quality_bits(&soup), "{e:?}");
            assert_eq!(back.vertex_colors, soup.vertex_colors, "{e:?}");
        }
    }

    #[test]
    fn ascii_with_attributes_is_as_meshlab_lays_it_out() {
        let soup = PolygonSoup {
            vertex_quality: Some(vec![0.5, -2.0, 0.1]),
            vertex_colors: Some(vec![[255, 0, 0], [0, 255, 0], [0, 0, 255]]),
            ..PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]])
        };
        let text = String::from_utf8(write(&soup, PlyEncoding::Ascii)).unwrap();
        assert_eq!(
            text,
            format!(
                "ply\nformat ascii 1.0\ncomment written by Pappus\nelement vertex 3\n{XYZ}\
                 property uchar red\nproperty uchar green\nproperty uchar blue\n\
                 property float quality\nelement face 1\nproperty list uchar int vertex_indices\n\
                 end_header\n0 0 0 255 0 0 0.5\n1 0 0 0 255 0 -2\n0 1 0 0 0 255 0.1\n3 0 1 2\n"
            )
        );
    }

    #[test]
    fn colours_alone_round_trip() {
        let mut soup = attributed();
        soup.vertex_quality = None;
        for e in [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian] {
            let bytes = write(&soup, e);
            let header = String::from_utf8_lossy(&bytes);
            assert!(
                header.contains("property uchar blue\nelement face"),
                "{e:?}"
            );
            assert!(!header.contains("quality"), "{e:?}");
            let back = read(&bytes).unwrap();
            assert!(same_bits(&back, &soup), "{e:?}");
            assert_eq!(back.vertex_quality, None, "{e:?}");
            assert_eq!(back.vertex_colors, soup.vertex_colors, "{e:?}");
        }
        // A quality alone, likewise.
        let mut soup = attributed();
        soup.vertex_colors = None;
        let back = read(&write(&soup, PlyEncoding::BinaryLittleEndian)).unwrap();
        assert_eq!(quality_bits(&back), quality_bits(&soup));
        assert_eq!(back.vertex_colors, None);
    }

    #[test]
    fn a_soup_without_attributes_writes_the_plain_header() {
        let plain = format!(
            "comment written by Pappus\nelement vertex 5\n{XYZ}element face 2\n\
             property list uchar int vertex_indices\nend_header\n"
        );
        for (e, format) in [
            (PlyEncoding::Ascii, "ascii"),
            (PlyEncoding::BinaryLittleEndian, "binary_little_endian"),
            (PlyEncoding::BinaryBigEndian, "binary_big_endian"),
        ] {
            let bytes = write(&mixed(), e);
            let header = format!("ply\nformat {format} 1.0\n{plain}");
            assert!(bytes.starts_with(header.as_bytes()), "{e:?}");
            let back = read(&bytes).unwrap();
            assert_eq!((back.vertex_quality, back.vertex_colors), (None, None));
        }
        // Attributes that do not hold one value per position are left out.
        let mut soup = mixed();
        soup.vertex_quality = Some(vec![1.0; 4]);
        soup.vertex_colors = Some(vec![[1, 2, 3]; 6]);
        assert_eq!(
            write(&soup, PlyEncoding::Ascii),
            write(&mixed(), PlyEncoding::Ascii)
        );
    }

    #[test]
    fn reads_meshlab_quality_and_float_colours() {
        // As pymeshlab's `save_current_mesh(binary=False)` writes it: double quality after
        // an `alpha` this reader skips.
        let meshlab = b"ply\nformat ascii 1.0\ncomment VCGLIB generated\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\nproperty double quality\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0 255 0.5 \n1 0 0 0 255 0 255 1.5 \n0 1 0 0 0 255 255 -2 \n3 0 1 2 \n";
        let soup = read(meshlab).unwrap();
        assert_eq!(soup.vertex_quality, Some(vec![0.5, 1.5, -2.0]));
        assert_eq!(
            soup.vertex_colors,
            Some(vec![[255, 0, 0], [0, 255, 0], [0, 0, 255]])
        );
        // Float channels are fractions; out-of-range integers are clamped; a lone `red` is no
        // colour.
        let floats = format!(
            "ply\nformat ascii 1.0\nelement vertex 2\n{XYZ}property float blue\nproperty float green\nproperty double red\nend_header\n0 0 0 0.5 1 0\n1 0 0 2 -1 0.1\n"
        );
        let soup = read(floats.as_bytes()).unwrap();
        assert_eq!(soup.vertex_colors, Some(vec![[0, 255, 128], [26, 0, 255]]));
        assert_eq!(soup.vertex_quality, None);
        let ints = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\n{XYZ}property short red\nproperty int green\nproperty uchar blue\nend_header\n0 0 0 -4 300 7\n"
        );
        assert_eq!(
            read(ints.as_bytes()).unwrap().vertex_colors,
            Some(vec![[0, 255, 7]])
        );
        let lone = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\n{XYZ}property uchar red\nend_header\n0 0 0 9\n"
        );
        assert_eq!(read(lone.as_bytes()).unwrap().vertex_colors, None);
    }

    #[test]
    fn truncated_files_with_attributes_never_panic() {
        for e in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let bytes = write(&attributed(), e);
            for cut in 0..bytes.len() {
                let result = read(&bytes[..cut]);
                // An ASCII file may lose only its final newline and still read.
                assert!(
                    result.is_err() || cut + 1 == bytes.len(),
                    "{e:?} cut at {cut}"
                );
            }
        }
    }

    #[test]
    fn wide_faces_and_huge_indices_change_the_list_types() {
        let n = 300u32;
        let mut soup = PolygonSoup::from_faces(
            (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect(),
            &[(0..n).collect::<Vec<_>>()],
        );
        let bytes = write(&soup, PlyEncoding::BinaryLittleEndian);
        assert!(String::from_utf8_lossy(&bytes).contains("property list int int vertex_indices"));
        assert_eq!(read(&bytes).unwrap(), soup);
        soup.push_face(&[0, 1, u32::MAX - 1]);
        for e in [PlyEncoding::BinaryBigEndian, PlyEncoding::Ascii] {
            let bytes = write(&soup, e);
            assert!(
                String::from_utf8_lossy(&bytes).contains("property list int uint vertex_indices")
            );
            assert_eq!(read(&bytes).unwrap(), soup, "{e:?}");
        }
    }

    #[test]
    fn skips_other_properties_and_elements() {
        let text = b"ply\nformat ascii 1.0\ncomment hi\nobj_info made by hand\nelement vertex 3\nproperty double x\nproperty float nx\nproperty double y\nproperty int16 z\nproperty list uchar int junk\nelement face 1\nproperty uchar flags\nproperty list uint8 uint vertex_index\nelement edge 1\nproperty int a\nproperty int b\nend_header\n0 9 0 0 2 7 7\n1 9 0 0 0\n0 9 1 0 1 5\n3 3 0 1 2\n0 1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(soup.face(0), &[0, 1, 2]);
        assert_eq!(
            soup.notes,
            vec!["skipped: `vertex` property `nx`, `vertex` property `junk`, element `edge` (1)"]
        );
        assert_eq!(soup.face_scalars, [("flags".to_string(), vec![3.0])]);
    }

    /// A 3 × 3 grid of vertices as two strips with a restart between them, in ASCII and in
    /// binary: eight triangles, one winding, a valid disk.
    #[test]
    fn tristrips_make_their_triangles_with_one_winding() {
        let strips: [i32; 13] = [0, 3, 1, 4, 2, 5, -1, 3, 6, 4, 7, 5, 8];
        let head = |format: &str| {
            format!(
                "ply\nformat {format} 1.0\nelement vertex 9\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
            )
        };
        let grid = (0..9).map(|i| [(i % 3) as f32, (i / 3) as f32, 0.0]);
        let mut ascii = head("ascii");
        for p in grid.clone() {
            let _ = writeln!(ascii, "{} {} {}", p[0], p[1], p[2]);
        }
        let _ = writeln!(ascii, "13 {}", strips.map(|i| i.to_string()).join(" "));
        let mut binary = head("binary_little_endian").into_bytes();
        for p in grid {
            binary.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        }
        binary.extend(13i32.to_le_bytes());
        binary.extend(strips.iter().flat_map(|i| i.to_le_bytes()));
        for bytes in [ascii.into_bytes(), binary] {
            let soup = read(&bytes).unwrap();
            let faces: Vec<&[u32]> = soup.faces().collect();
            assert_eq!(
                faces,
                vec![
                    &[0, 3, 1][..],
                    &[1, 3, 4],
                    &[1, 4, 2],
                    &[2, 4, 5],
                    &[3, 6, 4],
                    &[4, 6, 7],
                    &[4, 7, 5],
                    &[5, 7, 8]
                ]
            );
            let mut world = bevy::prelude::World::new();
            let built = crate::mesh::build_mesh(&mut world, &soup, Default::default()).unwrap();
            assert!(built.report.is_clean(), "{}", built.report);
            let stats = crate::mesh::mesh_stats(&world, built.mesh);
            assert_eq!(
                (
                    stats.faces,
                    stats.boundary_loops,
                    stats.euler_characteristic
                ),
                (8, 1, 1)
            );
        }
        // A negative index other than the restart is an error.
        let bad = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -2 1\n";
        assert!(
            read(bad)
                .unwrap_err()
                .message
                .contains("bad vertex index -2")
        );
    }

    #[test]
    fn reads_big_endian_doubles_and_an_element_before_the_vertices() {
        let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement material 2\nproperty list uchar float rgb\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nelement face 1\nproperty list int16 uint16 vertex_indices\nend_header\n".to_vec();
        for material in [[1.0f32, 0.5], [0.25, 0.0]] {
            bytes.push(2);
            for c in material {
                bytes.extend(c.to_be_bytes());
            }
        }
        for p in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]] {
            for c in p {
                bytes.extend(c.to_be_bytes());
            }
            bytes.push(200);
        }
        bytes.extend(3i16.to_be_bytes());
        for i in [2u16, 1, 0] {
            bytes.extend(i.to_be_bytes());
        }
        let soup = read(&bytes).unwrap();
        assert_eq!(
            soup.positions,
            vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 0.5)]
        );
        assert_eq!(soup.face(0), &[2, 1, 0]);
    }

    #[test]
    fn truncated_binary_files_are_errors_at_the_offset() {
        let bytes = write(&mixed(), PlyEncoding::BinaryLittleEndian);
        let body = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        // Five vertices of 12 bytes, then the first face's count (1 byte) and 3 of its 4 bytes.
        let cut = body + 60 + 1 + 3;
        let err = read(&bytes[..cut]).unwrap_err();
        assert_eq!(err.location, format!("byte {}", body + 61));
        assert_eq!(err.message, "file ends while reading `vertex_indices`");
        let err = read(&bytes[..body + 5]).unwrap_err();
        assert_eq!(err.location, format!("byte {}", body + 4));
        for cut in 0..bytes.len() {
            assert!(read(&bytes[..cut]).is_err(), "cut at {cut}");
        }
    }

    #[test]
    fn errors_name_the_line() {
        let ascii = |body: &str| {
            format!(
                "ply\nformat ascii 1.0\nelement vertex 2\n{XYZ}element face 1\nproperty list uchar int vertex_indices\nend_header\n{body}"
            )
        };
        let cases: [(String, &str, &str); 9] = [
            (ascii("0 0 0\n"), "line 10", "file ends while reading `x`"),
            (ascii("0 0 0\n1 q 0\n3 0 1 1\n"), "line 11", "`q` is not a number (y)"),
            (ascii("0 0 0\n1 0 0\n3 0 -1 1\n"), "line 12", "bad vertex index -1"),
            (ascii("0 0 0\n1 0 0\n3 0 1.5 1\n"), "line 12", "bad vertex index 1.5"),
            (ascii("0 0 0\n1 0 0\n-3 0 1 1\n"), "line 12", "`vertex_indices` has -3 items"),
            ("plx\n".into(), "line 1", "expected `ply`"),
            ("ply\nformat ascii 1.0\nelement vertex\n".into(), "line 3", "element `vertex` needs a count, found None"),
            ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n".into(), "line 3", "element `vertex` has no property `z`"),
            ("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int corners\nend_header\n3 0 1 2\n".into(), "line 3", "element `face` has no list `vertex_indices`"),
        ];
        for (text, location, message) in cases {
            let err = read(text.as_bytes()).unwrap_err();
            assert_eq!(
                (err.location.as_str(), err.message.as_str()),
                (location, message),
                "{text}"
            );
        }
        let err = read(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty int64 x\nend_header\n")
            .unwrap_err();
        assert!(err.unsupported && err.location == "line 4", "{err:?}");
        let err = read(b"ply\nformat binary_middle_endian 1.0\nend_header\n").unwrap_err();
        assert!(err.unsupported && err.location == "line 2", "{err:?}");
        let err = read(b"ply\nformat ascii 1.0\nelement vertex 1\n").unwrap_err();
        assert_eq!(err.message, "file ends inside the header");
    }

    #[test]
    fn huge_counts_do_not_allocate_or_panic() {
        let text = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n{XYZ}element nothing 18446744073709551615\nend_header\n"
        );
        assert!(read(text.as_bytes()).is_err());
        let text = "ply\nformat ascii 1.0\nelement nothing 18446744073709551615\nelement face 1\nproperty list uint int vertex_indices\nend_header\n4000000000 1 2 3\n";
        assert_eq!(read(text.as_bytes()).unwrap_err().location, "line 7");
    }

    #[test]
    fn header_lines_that_are_not_keywords_are_read_as_comments_and_said() {
        let text = "ply\nformat ascii 1.0\nCreated by SomeScanner 2.1\nelement vertex 3\n\
                    property float x\nproperty float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0\n1,5 0 0\n0 3.1+e2 0\n3 0 1 2\n";
        let soup = read(text.as_bytes()).unwrap();
        assert_eq!(
            soup.positions,
            vec![
                Vec3::ZERO,
                Vec3::new(1.5, 0.0, 0.0),
                Vec3::new(0.0, 310.0, 0.0)
            ]
        );
        assert_eq!(soup.face_count(), 1);
        assert_eq!(
            soup.notes,
            [
                "read 1 number(s) with a decimal comma, read as a decimal point (the first \
                 `1,5`, line 12); 1 number(s) with the exponent's sign before its `e`, read as \
                 `e` then the sign (the first `3.1+e2`, line 13)",
                "read past 1 header line(s) that are not PLY keywords, as comments (the first, \
                 line 3: `Created by SomeScanner 2.1`)"
            ]
        );
    }
}
