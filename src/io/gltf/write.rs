//! Writing glTF 2.0: one scene, one node, one mesh of `TRIANGLES` primitives: one, or with
//! face groups one per group, each with the material of that name (materials without
//! properties, named so that Blender and other editors show the slots) and the whole group in
//! its `extras` (`pappus_group`; the `mtllib` names in the mesh's), read back exactly by
//! Pappus. All primitives share one set of vertex accessors.
//!
//! A vertex is written once per distinct (position, UV) pair — once per position when the soup
//! has no UVs, in the soup's order — so only a UV seam splits a vertex, as glTF requires.
//! Polygons are fan-triangulated, from the first corner whose diagonals are not edges already. `POSITION` (with the `min`/`max` glTF
//! requires), `NORMAL`, `TEXCOORD_0` (`v` flipped back to glTF's downward axis) and `COLOR_0`
//! (normalised bytes, padded to 4 for alignment) are written when the soup has them, and
//! [`VERTEX_ATTRIBUTE`], the soup vertex each written vertex copies;
//! indices are 32-bit. A `.glb` holds the JSON and the binary chunk; a `.gltf` embeds the buffer as a
//! base64 data URI, so either is one file.

use base64::Engine;
use bevy::platform::collections::HashMap;
use serde_json::{Value, json};

use super::VERTEX_ATTRIBUTE;
use crate::mesh::soup::PolygonSoup;

/// glTF's component type and target codes.
const FLOAT: u32 = 5126;
const UNSIGNED_BYTE: u32 = 5121;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Encodes `soup` as a `.glb` (`binary`) or a `.gltf` with its buffer embedded.
pub fn write(soup: &PolygonSoup, binary: bool) -> Vec<u8> {
    let (vertices, indices, triangle_face) = vertices_and_triangles(soup);
    let mut chunks = Chunks::default();
    let mut document = json!({
        "asset": { "version": "2.0", "generator": concat!("Pappus ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "name": "Pappus mesh" }],
    });
    // glTF accessors hold at least one item: a mesh without faces is a scene without a mesh.
    if !indices.is_empty() {
        let attributes = attributes(soup, &vertices, &mut chunks);
        let mut index_accessor = |indices: &[u32]| {
            let bytes = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            let accessor =
                json!({ "componentType": UNSIGNED_INT, "count": indices.len(), "type": "SCALAR" });
            chunks.push(bytes, None, ELEMENT_ARRAY_BUFFER, accessor)
        };
        let groups = soup
            .face_groups
            .as_ref()
            .filter(|g| g.fits(soup.face_count()));
        let mut mesh = json!({ "name": "Pappus mesh" });
        match groups {
            None => {
                let indices = index_accessor(&indices);
                mesh["primitives"] =
                    json!([{ "attributes": attributes, "indices": indices, "mode": 4 }]);
            }
            Some(groups) => {
                let mut materials: Vec<&str> = Vec::new();
                let mut primitives = Vec::new();
                for (row, triangles) in triangles_by_group(groups, &indices, &triangle_face) {
                    let group = &groups.table.groups[row as usize];
                    let mut primitive = json!({
                        "attributes": attributes,
                        "indices": index_accessor(&triangles),
                        "mode": 4,
                        "extras": { "pappus_group": {
                            "object": group.object,
                            "group": group.group,
                            "material": group.material,
                            "smoothing": group.smoothing,
                        } },
                    });
                    if let Some(name) = group.material.as_deref() {
                        let index =
                            materials
                                .iter()
                                .position(|&m| m == name)
                                .unwrap_or_else(|| {
                                    materials.push(name);
                                    materials.len() - 1
                                });
                        primitive["material"] = json!(index);
                    }
                    primitives.push(primitive);
                }
                mesh["primitives"] = json!(primitives);
                mesh["extras"] =
                    json!({ "pappus_material_libraries": groups.table.material_libraries });
                if !materials.is_empty() {
                    let materials: Vec<Value> =
                        materials.iter().map(|m| json!({ "name": m })).collect();
                    document["materials"] = json!(materials);
                }
            }
        }
        document["nodes"][0]["mesh"] = json!(0);
        document["meshes"] = json!([mesh]);
        document["accessors"] = json!(chunks.accessors);
        document["bufferViews"] = json!(chunks.views);
        let mut entry = json!({ "byteLength": chunks.buffer.len() });
        if !binary {
            let encoded = base64::engine::general_purpose::STANDARD.encode(&chunks.buffer);
            entry["uri"] = json!(format!("data:application/octet-stream;base64,{encoded}"));
        }
        document["buffers"] = json!([entry]);
    }
    let text = serde_json::to_vec(&document).expect("a JSON value always serialises");
    if binary {
        glb(text, chunks.buffer)
    } else {
        text
    }
}

/// The one buffer being written, and its views and accessors.
#[derive(Default)]
struct Chunks {
    buffer: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Chunks {
    /// Appends `bytes` (then zeros to a multiple of 4) as a buffer view of `stride` for
    /// `target`, read by `accessor`; the accessor's number.
    fn push(
        &mut self,
        bytes: Vec<u8>,
        stride: Option<usize>,
        target: u32,
        mut accessor: Value,
    ) -> usize {
        let mut view = json!({
            "buffer": 0,
            "byteOffset": self.buffer.len(),
            "byteLength": bytes.len(),
            "target": target,
        });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        self.buffer.extend_from_slice(&bytes);
        self.buffer.resize(self.buffer.len().next_multiple_of(4), 0);
        accessor["bufferView"] = json!(self.views.len());
        self.views.push(view);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }
}

/// Writes the vertices' attributes into `chunks`: the primitive's `attributes` object.
fn attributes(
    soup: &PolygonSoup,
    vertices: &[(u32, [u32; 2])],
    chunks: &mut Chunks,
) -> serde_json::Map<String, Value> {
    let count = vertices.len();
    let floats = |values: &[f32], out: &mut Vec<u8>| {
        out.extend(values.iter().flat_map(|c| c.to_le_bytes()));
    };
    let mut attributes = serde_json::Map::new();
    let positions: Vec<[f32; 3]> = vertices
        .iter()
        .map(|&(v, _)| soup.positions[v as usize].to_array())
        .collect();
    let (min, max) = bounds(&positions);
    let accessor =
        json!({ "componentType": FLOAT, "count": count, "type": "VEC3", "min": min, "max": max });
    let mut bytes = Vec::new();
    floats(positions.as_flattened(), &mut bytes);
    attributes.insert(
        "POSITION".into(),
        json!(chunks.push(bytes, None, ARRAY_BUFFER, accessor)),
    );
    let vec = |kind: &str| json!({ "componentType": FLOAT, "count": count, "type": kind });
    let n = soup.positions.len();
    if let Some(normals) = soup.vertex_normals.as_ref().filter(|x| x.len() == n) {
        let bytes = per_vertex(vertices, |v, _, out| {
            floats(&normals[v as usize].to_array(), out);
        });
        attributes.insert(
            "NORMAL".into(),
            json!(chunks.push(bytes, None, ARRAY_BUFFER, vec("VEC3"))),
        );
    }
    if soup.attributes().uv {
        // glTF's v runs down the image.
        let bytes = per_vertex(vertices, |_, [u, v], out| {
            floats(&[f32::from_bits(u), 1.0 - f32::from_bits(v)], out);
        });
        attributes.insert(
            "TEXCOORD_0".into(),
            json!(chunks.push(bytes, None, ARRAY_BUFFER, vec("VEC2"))),
        );
    }
    if let Some(colors) = soup.vertex_colors.as_ref().filter(|x| x.len() == n) {
        // Bytes, each colour padded to 4: vertex attributes are 4-byte aligned.
        let bytes = per_vertex(vertices, |v, _, out| {
            let [r, g, b] = colors[v as usize];
            out.extend([r, g, b, 0]);
        });
        let accessor = json!({ "componentType": UNSIGNED_BYTE, "normalized": true, "count": count, "type": "VEC3" });
        attributes.insert(
            "COLOR_0".into(),
            json!(chunks.push(bytes, Some(4), ARRAY_BUFFER, accessor)),
        );
    }
    // Which soup vertex each written one is (low and high 16 bits), so that Pappus joins
    // exactly the copies it split, not every two vertices that happen to coincide.
    let bytes = per_vertex(vertices, |v, _, out| {
        out.extend((v as u16).to_le_bytes());
        out.extend(((v >> 16) as u16).to_le_bytes());
    });
    let accessor = json!({ "componentType": UNSIGNED_SHORT, "count": count, "type": "VEC2" });
    attributes.insert(
        VERTEX_ATTRIBUTE.into(),
        json!(chunks.push(bytes, None, ARRAY_BUFFER, accessor)),
    );
    attributes
}

/// Every vertex's bytes, as `write` puts them, one vertex after another.
fn per_vertex(
    vertices: &[(u32, [u32; 2])],
    mut write: impl FnMut(u32, [u32; 2], &mut Vec<u8>),
) -> Vec<u8> {
    let mut out = Vec::new();
    for &(v, uv) in vertices {
        write(v, uv, &mut out);
    }
    out
}

/// [`vertices_and_triangles`]' result: the vertices to write (soup vertex, UV bits), three
/// vertex numbers a triangle, and each triangle's soup face.
type Triangulated = (Vec<(u32, [u32; 2])>, Vec<u32>, Vec<u32>);

/// The triangles of each group row that has any, rows in order: `indices` three per triangle,
/// `triangle_face` the soup face of each.
fn triangles_by_group(
    groups: &crate::mesh::groups::FaceGroups,
    indices: &[u32],
    triangle_face: &[u32],
) -> Vec<(u32, Vec<u32>)> {
    let mut by_row: Vec<Vec<u32>> = vec![Vec::new(); groups.table.groups.len()];
    for (triangle, &face) in indices.chunks_exact(3).zip(triangle_face) {
        by_row[groups.of_face[face as usize] as usize].extend_from_slice(triangle);
    }
    by_row
        .into_iter()
        .enumerate()
        .filter(|(_, t)| !t.is_empty())
        .map(|(row, t)| (row as u32, t))
        .collect()
}

/// The vertices to write, as (soup vertex, UV bits), each triangle's three vertex numbers, and
/// the soup face each triangle is part of.
/// Vertices are in the soup's order, a vertex's UV copies together in order of first use (every
/// position, used or not, when the soup has no UVs): so a reader that welds by position gets
/// the soup's vertices back in their order.
fn vertices_and_triangles(soup: &PolygonSoup) -> Triangulated {
    let uvs = soup.corner_uvs.as_ref().filter(|_| soup.attributes().uv);
    let n = soup.positions.len() as u32;
    // Each corner's key, for the triangles of every face that names existing vertices.
    let mut corners: Vec<(u32, [u32; 2])> = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    let mut triangle_face: Vec<u32> = Vec::new();
    // Only polygons need the edges (to choose their diagonals).
    let mut edges = if soup.faces().any(|f| f.len() > 3) {
        Edges::of(soup)
    } else {
        Edges(Default::default())
    };
    for (f, face) in soup.faces().enumerate() {
        if face.len() < 3 || face.iter().any(|&v| v >= n) {
            continue;
        }
        let start = soup.face_starts[f] as usize;
        let first = corners.len();
        corners.extend(face.iter().enumerate().map(|(i, &v)| {
            let uv = uvs.map_or([0, 0], |uvs| uvs[start + i].to_array().map(f32::to_bits));
            (v, uv)
        }));
        let apex = edges.fan_apex(face);
        let m = face.len();
        triangles.extend((1..m - 1).map(|i| {
            let at = |j: usize| first + (apex + j) % m;
            [at(0), at(i), at(i + 1)]
        }));
        triangle_face.extend(std::iter::repeat_n(f as u32, m - 2));
    }
    let vertices: Vec<(u32, [u32; 2])> = match uvs {
        None => (0..n).map(|v| (v, [0, 0])).collect(),
        Some(_) => {
            // Distinct keys in order of first use, then stably by vertex.
            let mut seen = bevy::platform::collections::HashSet::new();
            let mut keys: Vec<(u32, [u32; 2])> = corners
                .iter()
                .copied()
                .filter(|key| seen.insert(*key))
                .collect();
            keys.sort_by_key(|&(v, _)| v);
            keys
        }
    };
    let numbers: HashMap<(u32, [u32; 2]), u32> = vertices
        .iter()
        .enumerate()
        .map(|(i, &key)| (key, i as u32))
        .collect();
    let indices = triangles
        .iter()
        .flatten()
        .map(|&k| numbers[&corners[k]])
        .collect();
    (vertices, indices, triangle_face)
}

/// The mesh's edges, and the diagonals fans add, to triangulate polygons without making an
/// edge twice: a quad whose diagonal is already an edge elsewhere (a fold, as Suzanne has)
/// would otherwise come back with a non-manifold edge.
struct Edges(bevy::platform::collections::HashSet<(u32, u32)>);

impl Edges {
    fn key(a: u32, b: u32) -> (u32, u32) {
        (a.min(b), a.max(b))
    }

    /// Every edge of the soup's faces.
    fn of(soup: &PolygonSoup) -> Edges {
        let mut set = bevy::platform::collections::HashSet::default();
        for face in soup.faces() {
            for (i, &a) in face.iter().enumerate() {
                set.insert(Self::key(a, face[(i + 1) % face.len()]));
            }
        }
        Edges(set)
    }

    /// The corner to fan `face` from: the first whose diagonals are not edges yet (the first
    /// corner when none is, or for a triangle). Records the chosen fan's diagonals.
    fn fan_apex(&mut self, face: &[u32]) -> usize {
        let m = face.len();
        if m == 3 {
            return 0;
        }
        let diagonals = |apex: usize| (2..m - 1).map(move |j| (face[apex], face[(apex + j) % m]));
        let apex = (0..m)
            .find(|&apex| diagonals(apex).all(|(a, b)| !self.0.contains(&Self::key(a, b))))
            .unwrap_or(0);
        for (a, b) in diagonals(apex) {
            self.0.insert(Self::key(a, b));
        }
        apex
    }
}

/// The componentwise minimum and maximum of the positions.
fn bounds(positions: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    (min, max)
}

/// A `.glb`: the 12-byte header, the JSON chunk (padded with spaces) and the binary chunk
/// (padded with zeros), each chunk 4-byte aligned.
fn glb(mut json: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    json.resize(json.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let chunks = 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(12 + chunks);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + chunks) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}
