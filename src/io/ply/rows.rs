//! What a PLY header declares (the scalar types, each property's role, the elements) and what a
//! vertex row holds on its way into the soup: shared by the general reader ([`super`]) and the
//! fixed-layout one ([`super::fixed_rows`]), which take them from here.

use bevy::math::{Vec2, Vec3};

use crate::io::text::cap;
use crate::mesh::soup::PolygonSoup;

/// The eight PLY scalar types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
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
    pub(super) fn parse(name: &str) -> Option<Scalar> {
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

    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The value whose bytes start `b` (which holds at least [`Scalar::size`] of them).
    #[inline]
    pub(super) fn decode(self, b: &[u8], big_endian: bool) -> f64 {
        fn take<const N: usize>(b: &[u8], big_endian: bool) -> [u8; N] {
            let mut a: [u8; N] = b[..N].try_into().expect("N bytes");
            if big_endian {
                a.reverse();
            }
            a
        }
        match self {
            Scalar::I8 => f64::from(i8::from_le_bytes([b[0]])),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes(take(b, big_endian))),
            Scalar::U16 => f64::from(u16::from_le_bytes(take(b, big_endian))),
            Scalar::I32 => f64::from(i32::from_le_bytes(take(b, big_endian))),
            Scalar::U32 => f64::from(u32::from_le_bytes(take(b, big_endian))),
            Scalar::F32 => f64::from(f32::from_le_bytes(take(b, big_endian))),
            Scalar::F64 => f64::from_le_bytes(take(b, big_endian)),
        }
    }
}

/// What the reader does with a property's values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    /// Coordinate 0, 1 or 2 of a vertex.
    Coordinate(usize),
    /// A vertex's `quality`.
    Quality,
    /// A vertex's `nx` (0), `ny` (1) or `nz` (2).
    Normal(usize),
    /// A vertex's `red` (0), `green` (1) or `blue` (2).
    Color(usize),
    /// A vertex's texture coordinate `u` (0) or `v` (1) (also `s t`, `texture_u texture_v`,
    /// `texture_s texture_t`).
    Uv(usize),
    /// A face's `texcoord` list: `u v` per corner (MeshLab's per-corner UVs).
    TexCoord,
    /// Another scalar of a vertex, kept as column `k` of the soup's
    /// [`vertex_scalars`](PolygonSoup::vertex_scalars) (columns numbered across the header in
    /// order of first appearance; at most [`MAX_SCALARS`]).
    Scalar(usize),
    /// A scalar of a face, kept as column `k` of the soup's
    /// [`face_scalars`](PolygonSoup::face_scalars) (numbered as the vertex ones are).
    FaceScalar(usize),
    /// The corners of a face.
    Corners,
    /// A `tristrips` element's `vertex_indices`: strips, `-1` between them.
    Strip,
    /// Read past.
    Skip,
}

#[derive(Debug)]
pub(super) enum Property {
    Scalar {
        name: String,
        ty: Scalar,
        role: Role,
    },
    List {
        name: String,
        count: Scalar,
        item: Scalar,
        role: Role,
    },
}

#[derive(Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) properties: Vec<Property>,
    /// The header line declaring it.
    pub(super) line: usize,
}

/// The most vertex scalars kept beside the ones Pappus has a column for; more are read past
/// (and named in the load's note).
pub(super) const MAX_SCALARS: usize = 8;

/// A colour channel as a byte: an integer as it is, a floating-point value as a fraction of
/// full intensity (scaled by 255 and rounded); clamped to 0–255 (NaN gives 0).
fn channel(v: f64, ty: Scalar) -> u8 {
    let v = if ty.is_integer() {
        v
    } else {
        (v * 255.0).round()
    };
    v.clamp(0.0, 255.0) as u8
}

/// Per-vertex UVs as corner UVs: each corner takes its vertex's ((0, 0) for an index out of
/// range, a face the builder drops).
pub(super) fn corner_uvs_of_vertices(
    soup: &PolygonSoup,
    vertex_uv: Option<Vec<Vec2>>,
) -> Option<Vec<Vec2>> {
    vertex_uv.map(|uv| {
        let at = |&i: &u32| uv.get(i as usize).copied().unwrap_or(Vec2::ZERO);
        soup.indices.iter().map(at).collect()
    })
}

/// Makes room for a `vertex` element's rows in the soup's columns, and starts the columns its
/// properties bring (quality, normals, colours, UVs). Vertices read before (another `vertex`
/// element, in an odd file) get 0 and black, so that the columns keep one value per position.
pub(super) fn reserve_vertex_columns(
    element: &Element,
    soup: &mut PolygonSoup,
    vertex_uv: &mut Option<Vec<Vec2>>,
    len: usize,
) {
    let has = |role: Role| {
        element
            .properties
            .iter()
            .any(|p| matches!(p, Property::Scalar { role: r, .. } if *r == role))
    };
    let before = soup.positions.len();
    if (0..2).all(|k| has(Role::Uv(k))) {
        vertex_uv.get_or_insert_with(|| vec![Vec2::ZERO; before]);
    }
    let n = cap(element.count, len / 12);
    soup.positions.reserve(n);
    if has(Role::Quality) {
        let q = soup.vertex_quality.get_or_insert_with(|| vec![0.0; before]);
        q.reserve(n);
    }
    if (0..3).all(|k| has(Role::Normal(k))) {
        let v = soup
            .vertex_normals
            .get_or_insert_with(|| vec![Vec3::ZERO; before]);
        v.reserve(n);
    }
    if (0..3).all(|k| has(Role::Color(k))) {
        let c = soup
            .vertex_colors
            .get_or_insert_with(|| vec![[0; 3]; before]);
        c.reserve(n);
    }
    let vertex_column = |role: Role| match role {
        Role::Scalar(k) => Some(k),
        _ => None,
    };
    start_columns(
        element,
        vertex_column,
        &mut soup.vertex_scalars,
        before,
        0.0,
    );
    for (_, column) in &mut soup.vertex_scalars {
        column.reserve(n);
    }
}

/// One row's scalar properties, by role.
pub(super) struct Row {
    pub(super) position: [f32; 3],
    pub(super) quality: f32,
    pub(super) color: [u8; 3],
    pub(super) normal: [f32; 3],
    pub(super) uv: [f32; 2],
    pub(super) scalars: [f32; MAX_SCALARS],
    /// A face's kept scalars (NaN for a column its element does not declare).
    pub(super) face: [f32; MAX_SCALARS],
}

impl Default for Row {
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            quality: 0.0,
            color: [0; 3],
            normal: [0.0; 3],
            uv: [0.0; 2],
            scalars: [0.0; MAX_SCALARS],
            face: [f32::NAN; MAX_SCALARS],
        }
    }
}

impl Row {
    pub(super) fn set(&mut self, role: Role, ty: Scalar, v: f64) {
        match role {
            Role::Coordinate(k) => self.position[k] = v as f32,
            Role::Quality => self.quality = v as f32,
            Role::Color(k) => self.color[k] = channel(v, ty),
            Role::Normal(k) => self.normal[k] = v as f32,
            Role::Uv(k) => self.uv[k] = v as f32,
            Role::Scalar(k) => self.scalars[k] = v as f32,
            Role::FaceScalar(k) => self.face[k] = v as f32,
            Role::Corners | Role::Strip | Role::TexCoord | Role::Skip => {}
        }
    }

    /// Adds the row as a vertex, with a value in every column the soup has.
    pub(super) fn push_vertex(&self, soup: &mut PolygonSoup, vertex_uv: &mut Option<Vec<Vec2>>) {
        soup.positions.push(Vec3::from_array(self.position));
        if let Some(q) = &mut soup.vertex_quality {
            q.push(self.quality);
        }
        if let Some(c) = &mut soup.vertex_colors {
            c.push(self.color);
        }
        if let Some(v) = &mut soup.vertex_normals {
            v.push(Vec3::from_array(self.normal));
        }
        if let Some(v) = vertex_uv {
            v.push(Vec2::from_array(self.uv));
        }
        for (k, (_, column)) in soup.vertex_scalars.iter_mut().enumerate() {
            column.push(self.scalars[k]);
        }
    }
}

/// Starts the face columns a `face` element's properties bring: the faces read before it
/// (another face element, a strips element) get NaN.
pub(super) fn reserve_face_columns(element: &Element, soup: &mut PolygonSoup) {
    let face_column = |role: Role| match role {
        Role::FaceScalar(k) => Some(k),
        _ => None,
    };
    let faces = soup.face_count();
    start_columns(
        element,
        face_column,
        &mut soup.face_scalars,
        faces,
        f32::NAN,
    );
}

/// Adds to `columns` each column `element`'s scalar properties bring (those `column_of`
/// numbers as the next one: columns are numbered across the header in order of first
/// appearance), with `fill` for the `before` rows read before it.
fn start_columns(
    element: &Element,
    column_of: impl Fn(Role) -> Option<usize>,
    columns: &mut Vec<(String, Vec<f32>)>,
    before: usize,
    fill: f32,
) {
    for property in &element.properties {
        if let Property::Scalar { name, role, .. } = property
            && column_of(*role) == Some(columns.len())
        {
            columns.push((name.clone(), vec![fill; before]));
        }
    }
}

/// Ends the face columns once the body is read: a face read after the last face element's
/// rows (from strips) gets NaN.
pub(super) fn finish_face_columns(soup: &mut PolygonSoup) {
    let faces = soup.face_count();
    for (_, column) in &mut soup.face_scalars {
        column.resize(faces, f32::NAN);
    }
}

/// Gives the face just read (the soup's last) its row's value in every face column; a face
/// read without one (from a strips element) gets NaN.
pub(super) fn push_face_scalars(row: &Row, soup: &mut PolygonSoup) {
    let faces = soup.face_count();
    for (k, (_, column)) in soup.face_scalars.iter_mut().enumerate() {
        column.resize(faces.saturating_sub(1), f32::NAN);
        column.push(row.face[k]);
    }
}
