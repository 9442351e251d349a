//! glTF on hand-made and written documents: round trips bit for bit, welding, the vertex count
//! a write produces, strips and fans, transforms, and broken files.

use bevy::math::{Vec2, Vec3};
use serde_json::json;

use super::{read, write};
use crate::mesh::soup::PolygonSoup;

/// A cube of quads whose faces each have their own UV square (a seam at every edge), with
/// normals and colours: the case glTF splits.
fn seamed_cube() -> PolygonSoup {
    let mut soup = crate::mesh::shapes::cube();
    let corners = soup.indices.len();
    let square = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    // Face f's square sits at u = 0.15 f: no two faces share a UV.
    let uv = |k: usize| square[k % 4] * 0.1 + Vec2::new(0.15 * (k / 4) as f32, 0.3);
    soup.corner_uvs = Some((0..corners).map(uv).collect());
    soup.vertex_normals = Some(soup.positions.iter().map(|p| p.normalize()).collect());
    soup.vertex_colors = Some(
        (0..soup.positions.len() as u8)
            .map(|i| [i * 30, 255 - i, 7])
            .collect(),
    );
    soup
}

fn bits3(v: &[Vec3]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

#[test]
fn a_written_file_reads_back_welded_with_every_value() {
    let soup = seamed_cube();
    for binary in [true, false] {
        let bytes = write(&soup, binary);
        // The crate itself accepts what is written.
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let primitive = gltf.meshes().next().unwrap().primitives().next().unwrap();
        // One vertex per (position, UV): each cube corner is in three faces with three UVs.
        assert_eq!(
            primitive.get(&gltf::Semantic::Positions).unwrap().count(),
            24
        );
        let back = read(&bytes, None).unwrap();
        assert_eq!(
            bits3(&back.positions),
            bits3(&soup.positions),
            "welded back to 8, in order"
        );
        assert_eq!(
            back.face_count(),
            12,
            "quads come back as two triangles each"
        );
        assert_eq!(
            bits3(back.vertex_normals.as_ref().unwrap()),
            bits3(soup.vertex_normals.as_ref().unwrap())
        );
        assert_eq!(back.vertex_colors, soup.vertex_colors);
        // Each triangle's corners carry their face's UVs (v flipped twice: within an ulp of 1).
        let uvs = back.corner_uvs.as_ref().unwrap();
        let original = soup.corner_uvs.as_ref().unwrap();
        for (f, face) in back.faces().enumerate() {
            let quad = f / 2;
            for (c, &v) in face.iter().enumerate() {
                let k = quad * 4 + soup.face(quad).iter().position(|&x| x == v).unwrap();
                assert!(uvs[f * 3 + c].abs_diff_eq(original[k], 1e-7), "face {f}");
            }
        }
        assert!(back.notes.is_empty(), "{:?}", back.notes);
    }
}

#[test]
fn a_written_file_read_again_writes_the_same_bytes() {
    let once = write(&seamed_cube(), true);
    let mut back = read(&once, None).unwrap();
    back.notes.clear();
    let twice = write(&back, true);
    let third = write(&read(&twice, None).unwrap(), true);
    assert_eq!(twice, third);
}

/// A document with `positions` (flat f32 triples) and a primitive of `mode` over `indices`
/// (u16), placed by `nodes` (the scene's node list is `[0]`).
fn document(positions: &[f32], indices: &[u16], mode: u32, nodes: serde_json::Value) -> Vec<u8> {
    let mut bytes: Vec<u8> = positions.iter().flat_map(|c| c.to_le_bytes()).collect();
    let index_offset = bytes.len();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let count = positions.len() / 3;
    let (mut min, mut max) = ([f32::MAX; 3], [f32::MIN; 3]);
    for p in positions.chunks(3) {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &bytes)
    );
    serde_json::to_vec(&json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": mode}]}],
        "buffers": [{"byteLength": bytes.len(), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": index_offset},
            {"buffer": 0, "byteOffset": index_offset, "byteLength": bytes.len() - index_offset}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3", "min": min, "max": max},
            {"bufferView": 1, "componentType": 5123, "count": indices.len(), "type": "SCALAR"}
        ]
    }))
    .unwrap()
}

const SQUARE: [f32; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];

#[test]
fn strips_fans_and_node_transforms() {
    let node = json!([{"mesh": 0}]);
    let strip = read(&document(&SQUARE, &[0, 1, 3, 2], 5, node.clone()), None).unwrap();
    let faces: Vec<&[u32]> = strip.faces().collect();
    assert_eq!(faces, vec![&[0, 1, 3][..], &[3, 1, 2]]);
    let fan = read(&document(&SQUARE, &[0, 1, 2, 3], 6, node), None).unwrap();
    let faces: Vec<&[u32]> = fan.faces().collect();
    assert_eq!(faces, vec![&[0, 1, 2][..], &[0, 2, 3]]);
    // A parent moves, its child scales; the mesh is placed twice.
    let nodes = json!([
        {"translation": [0.0, 0.0, 5.0], "children": [1], "name": "parent"},
        {"scale": [2.0, 2.0, 2.0], "mesh": 0, "name": "child"},
        {"mesh": 0}
    ]);
    let mut bytes = document(&SQUARE, &[0, 1, 2, 0, 2, 3], 4, nodes);
    let mut value: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    value["scenes"][0]["nodes"] = json!([0, 2]);
    bytes = serde_json::to_vec(&value).unwrap();
    let placed = read(&bytes, None).unwrap();
    assert_eq!(placed.positions.len(), 8);
    assert_eq!(placed.positions[2], Vec3::new(2.0, 2.0, 5.0));
    assert_eq!(placed.positions[6], Vec3::new(1.0, 1.0, 0.0));
    assert!(
        placed.notes[0].starts_with("2 objects (child, node 2)"),
        "{:?}",
        placed.notes
    );
}

#[test]
fn split_vertices_are_welded_so_a_closed_surface_stays_closed() {
    // A tetrahedron written glTF-style: each triangle with its own three vertices.
    let corners = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let triangles = [[0usize, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let positions: Vec<f32> = triangles
        .iter()
        .flatten()
        .flat_map(|&v| corners[v])
        .collect();
    let indices: Vec<u16> = (0..12).collect();
    let soup = read(
        &document(&positions, &indices, 4, json!([{"mesh": 0}])),
        None,
    )
    .unwrap();
    assert_eq!(soup.positions.len(), 4);
    let mut world = bevy::prelude::World::new();
    let built = crate::mesh::build_mesh(&mut world, &soup, Default::default()).unwrap();
    let stats = crate::mesh::mesh_stats(&world, built.mesh);
    assert!(stats.closed && stats.euler_characteristic == 2);
}

#[test]
fn broken_files_are_errors_not_panics() {
    let good = document(&SQUARE, &[0, 1, 2], 4, json!([{"mesh": 0}]));
    let mut value: serde_json::Value = serde_json::from_slice(&good).unwrap();
    let cases = [
        ("/accessors/0/count", json!(0), "is empty"),
        ("/accessors/0/count", json!(100), "reaches past the end"),
        (
            "/bufferViews/0/byteLength",
            json!(4),
            "reaches past the end",
        ),
        (
            "/buffers/0/byteLength",
            json!(10_000),
            "declares 10000 bytes",
        ),
        (
            "/buffers/0/uri",
            json!("missing.bin"),
            "open the .gltf from its folder",
        ),
        ("/nodes/0/children", json!([0]), "a cycle"),
    ];
    for (pointer, replacement, expected) in cases {
        let original = value.pointer(pointer).cloned();
        let (parent, key) = pointer.rsplit_once('/').unwrap();
        value.pointer_mut(parent).unwrap()[key] = replacement;
        let err = read(&serde_json::to_vec(&value).unwrap(), None).unwrap_err();
        assert!(err.message.contains(expected), "{pointer}: {err:?}");
        match original {
            Some(v) => *value.pointer_mut(pointer).unwrap() = v,
            None => {
                let (parent, key) = pointer.rsplit_once('/').unwrap();
                value
                    .pointer_mut(parent)
                    .unwrap()
                    .as_object_mut()
                    .unwrap()
                    .remove(key);
            }
        }
    }
    assert!(read(b"{", None).is_err());
    // A GLB header declaring fewer bytes than the header (found by the fuzzer).
    assert!(read(b"glTF\x02\0\0\0\x05\0\0\0\x10\0\0\0JSON{}", None).is_err());
    assert!(read(b"glTF\x02\0\0\0", None).is_err());
    for cut in 0..good.len() {
        let _ = read(&good[..cut], None);
    }
    let glb = write(&seamed_cube(), true);
    for cut in 0..glb.len() {
        let _ = read(&glb[..cut], None);
    }
    let mut seed = 0x1234_5678_u32;
    for _ in 0..3000 {
        let mut damaged = glb.clone();
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        let at = seed as usize % damaged.len();
        damaged[at] = (seed >> 24) as u8;
        let _ = read(&damaged, None);
    }
}

/// The seamed cube with its top and bottom in a red lid group and its sides in a blue body,
/// and a library.
fn grouped_cube() -> PolygonSoup {
    use crate::mesh::groups::{FaceGroups, Group, GroupTable};
    let mut soup = seamed_cube();
    let group = |g: &str, m: &str| Group {
        object: Some("cube".into()),
        group: Some(g.into()),
        material: Some(m.into()),
        smoothing: None,
    };
    // Faces alternate between the groups, so writing reorders them by group.
    let of_face = (0..soup.face_count() as u32).map(|f| f % 2).collect();
    soup.face_groups = Some(FaceGroups {
        table: GroupTable {
            material_libraries: vec!["cube.mtl".into()],
            groups: vec![group("body", "blue"), group("lid", "red")],
        },
        of_face,
    });
    soup
}

#[test]
fn groups_are_written_as_primitives_with_materials_and_read_back_exactly() {
    let soup = grouped_cube();
    let bytes = write(&soup, false);
    let json: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    assert_eq!(
        json["materials"],
        json!([{"name": "blue"}, {"name": "red"}])
    );
    assert_eq!(primitives[1]["material"], json!(1));
    let back = read(&bytes, None).unwrap();
    let groups = back.face_groups.as_ref().unwrap();
    assert_eq!(groups.table, soup.face_groups.as_ref().unwrap().table);
    // Each quad comes back as two triangles in its group, the faces of a group together.
    let expected: Vec<u32> = [0, 1]
        .iter()
        .flat_map(|&g| std::iter::repeat_n(g, soup.face_count()))
        .collect();
    assert_eq!(groups.of_face, expected);
    // Read again and written again: the same bytes.
    assert_eq!(
        write(&back, false),
        write(&read(&write(&back, false), None).unwrap(), false)
    );
}

#[test]
fn other_files_give_each_face_its_material_and_node_as_groups() {
    let mut value: serde_json::Value = serde_json::from_slice(&document(
        &SQUARE,
        &[0, 1, 2, 0, 2, 3],
        4,
        json!([{"mesh": 0, "name": "Plane"}]),
    ))
    .unwrap();
    value["meshes"][0]["primitives"][0]["material"] = json!(0);
    value["materials"] = json!([{"name": "Wood"}]);
    let soup = read(&serde_json::to_vec(&value).unwrap(), None).unwrap();
    let groups = soup.face_groups.unwrap();
    assert_eq!(groups.of_face, [0, 0]);
    assert_eq!(
        groups.table.groups[0].describe(),
        "object Plane · material Wood"
    );
    assert_eq!(
        soup.notes,
        ["skipped: 1 material(s) (their names kept as face groups, not their properties)"]
    );
}

/// A document of one triangle, edited at JSON pointers (a `null` removes the key).
fn edited(edits: &[(&str, serde_json::Value)]) -> Vec<u8> {
    let good = document(&SQUARE, &[0, 1, 2], 4, json!([{"mesh": 0}]));
    let mut value: serde_json::Value = serde_json::from_slice(&good).unwrap();
    for (pointer, replacement) in edits {
        let (parent, key) = pointer.rsplit_once('/').unwrap();
        let parent = value.pointer_mut(parent).unwrap().as_object_mut().unwrap();
        if replacement.is_null() {
            parent.remove(key);
        } else {
            parent.insert(key.to_owned(), replacement.clone());
        }
    }
    serde_json::to_vec(&value).unwrap()
}

#[test]
fn bounds_left_out_and_extensions_of_appearance_alone_are_tolerated_and_said() {
    let bytes = edited(&[
        ("/accessors/0/min", json!(null)),
        ("/accessors/0/max", json!(null)),
    ]);
    let soup = read(&bytes, None).unwrap();
    assert_eq!(soup.face_count(), 1);
    assert_eq!(
        soup.notes,
        [
            "read 1 primitive(s) whose POSITION accessor lacks its min/max bounds (the positions \
          themselves are read)"
        ]
    );
    for extension in [
        "KHR_materials_pbrSpecularGlossiness",
        "KHR_technique_webgl",
        "KHR_texture_transform",
    ] {
        let bytes = edited(&[
            ("/extensionsUsed", json!([extension])),
            ("/extensionsRequired", json!([extension])),
        ]);
        let soup = read(&bytes, None).unwrap();
        assert_eq!(soup.face_count(), 1, "{extension}");
        assert!(
            soup.notes[0].starts_with(&format!(
                "read without the required extension(s) {extension}: they concern only"
            )),
            "{:?}",
            soup.notes
        );
    }
}

#[test]
fn old_versions_compression_and_unknown_requirements_are_refused_by_name() {
    let refused = |bytes: &[u8]| {
        let err = read(bytes, None).unwrap_err();
        assert!(err.unsupported, "{err:?}");
        err.message
    };
    // glTF 1.0: its meshes, accessors, … are objects keyed by id.
    let one = serde_json::to_vec(&json!({
        "asset": {"version": "1.0"},
        "meshes": {"box": {"primitives": [{"attributes": {"POSITION": "acc"}, "mode": 4}]}},
        "accessors": {"acc": {"bufferView": "view", "count": 3, "componentType": 5126, "type": "VEC3"}}
    }))
    .unwrap();
    assert_eq!(
        refused(&one),
        "glTF 1.0 is not supported: re-export as glTF 2.0"
    );
    // Without its asset block, shaped as 1.0 is.
    let bare = serde_json::to_vec(&json!({"meshes": {"box": {"primitives": []}}})).unwrap();
    assert_eq!(
        refused(&bare),
        "glTF 1.0 is not supported: re-export as glTF 2.0"
    );
    assert_eq!(
        refused(&edited(&[("/asset/version", json!("3.0"))])),
        "glTF 3.0 is not supported: re-export as glTF 2.0"
    );
    // Binary glTF 1.0: GLB version 1.
    let mut glb_one = b"glTF\x01\0\0\0".to_vec();
    glb_one.extend(40u32.to_le_bytes());
    glb_one.extend([0u8; 28]);
    assert!(refused(&glb_one).starts_with("binary glTF 1.0 (GLB version 1) is not supported"));
    // Draco is read (`super::draco`'s tests): requiring it refuses nothing, and an accessor
    // without data is refused unless a compressed primitive uses it.
    let draco = "KHR_draco_mesh_compression";
    let required = edited(&[
        ("/extensionsUsed", json!([draco])),
        ("/extensionsRequired", json!([draco])),
    ]);
    assert_eq!(read(&required, None).unwrap().face_count(), 1);
    assert_eq!(
        refused(&edited(&[(
            "/extensionsRequired",
            json!(["EXT_meshopt_compression"])
        )])),
        "meshopt-compressed buffers are not supported: re-export without meshopt compression"
    );
    let err = read(&edited(&[("/accessors/0/bufferView", json!(null))]), None).unwrap_err();
    assert_eq!(
        err.message,
        "invalid glTF: accessors[0].bufferView: Missing data"
    );
    assert_eq!(
        refused(&edited(&[(
            "/extensionsRequired",
            json!(["EXT_mesh_gpu_instancing"])
        )])),
        "the file requires the extension `EXT_mesh_gpu_instancing`, which Pappus does not read"
    );
}

#[test]
fn quantized_positions_normals_and_uvs_are_read_as_their_accessors_say() {
    // Positions as i16 (not normalised: the node's scale brings them back), normals as
    // normalised i8, UVs as normalised u16, as gltfpack writes them (each item padded to 4).
    let mut bytes = Vec::new();
    for p in [[0i16, 0, 0], [2000, 0, 0], [0, 2000, 0]] {
        bytes.extend(p.iter().chain(&[0]).flat_map(|c| c.to_le_bytes()));
    }
    let normals = bytes.len();
    for _ in 0..3 {
        bytes.extend([0u8, 0, 127, 0]);
    }
    let uvs = bytes.len();
    for uv in [[0u16, 0], [65535, 0], [0, 65535]] {
        bytes.extend(uv.iter().flat_map(|c| c.to_le_bytes()));
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &bytes)
    );
    let document = serde_json::to_vec(&json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [0.001, 0.001, 0.001]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}]}],
        "buffers": [{"byteLength": bytes.len(), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": normals, "byteStride": 8},
            {"buffer": 0, "byteOffset": normals, "byteLength": uvs - normals, "byteStride": 4},
            {"buffer": 0, "byteOffset": uvs, "byteLength": bytes.len() - uvs}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [2000, 2000, 0]},
            {"bufferView": 1, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC2"}
        ]
    }))
    .unwrap();
    let soup = read(&document, None).unwrap();
    assert_eq!(
        soup.positions,
        vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0)
        ]
    );
    assert_eq!(soup.vertex_normals, Some(vec![Vec3::Z; 3]));
    assert_eq!(
        soup.corner_uvs,
        Some(vec![
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 0.0)
        ])
    );
    assert!(
        soup.notes.iter().all(|n| !n.contains("required")),
        "{:?}",
        soup.notes
    );
}
