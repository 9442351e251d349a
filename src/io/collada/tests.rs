//! COLLADA reading on hand-written documents: each primitive, the inputs and their offsets,
//! the scene's transforms, instancing, the up axis, what is skipped, and broken files.

use bevy::math::{Vec2, Vec3};

use super::read;
use crate::mesh::soup::PolygonSoup;

/// A document around `geometries` and a visual scene of `nodes`, with `up` as the up axis.
fn document(up: &str, geometries: &str, nodes: &str) -> String {
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>{up}</up_axis></asset>
  <library_geometries>{geometries}</library_geometries>
  <library_visual_scenes><visual_scene id="Scene">{nodes}</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>"##
    )
}

/// A `<source>` of `values` read `stride` at a time.
fn source(id: &str, stride: usize, values: &str) -> String {
    let count = values.split_whitespace().count() / stride;
    format!(
        r##"<source id="{id}"><float_array id="{id}-array" count="{}">{values}</float_array>
        <technique_common><accessor source="#{id}-array" count="{count}" stride="{stride}"/></technique_common></source>"##,
        count * stride
    )
}

/// A unit square's four corners in the z = 0 plane, as a `<mesh>` with `primitive`.
fn square(id: &str, extra_sources: &str, primitive: &str) -> String {
    format!(
        r##"<geometry id="{id}" name="{id}"><mesh>
        {}{extra_sources}
        <vertices id="{id}-v"><input semantic="POSITION" source="#{id}-p"/></vertices>
        {primitive}</mesh></geometry>"##,
        source(&format!("{id}-p"), 3, "0 0 0  1 0 0  1 1 0  0 1 0")
    )
}

fn place(geometry: &str, transforms: &str) -> String {
    format!(
        r##"<node name="{geometry}-node">{transforms}<instance_geometry url="#{geometry}"/></node>"##
    )
}

fn read_text(text: &str) -> PolygonSoup {
    read(text.as_bytes()).unwrap_or_else(|e| panic!("{e:?}"))
}

fn faces(soup: &PolygonSoup) -> Vec<Vec<u32>> {
    soup.faces().map(<[u32]>::to_vec).collect()
}

#[test]
fn a_polylist_keeps_its_polygons_and_reads_inputs_at_their_offsets() {
    let sources = source("n", 3, "0 0 1  0 0 -1")
        + &source("uv0", 2, "0 0  1 0  1 1  0 1  0.5 0.5")
        + &source("uv1", 2, "9 9")
        + &source("c", 4, "1 0 0 1  0 0.5 1 1");
    // A quad and a triangle; tuples are (vertex, normal, uv set 1, uv set 0, colour).
    let primitive = r##"<polylist count="2">
        <input semantic="VERTEX" source="#sq-v" offset="0"/>
        <input semantic="NORMAL" source="#n" offset="1"/>
        <input semantic="TEXCOORD" source="#uv1" offset="2" set="1"/>
        <input semantic="TEXCOORD" source="#uv0" offset="3" set="0"/>
        <input semantic="COLOR" source="#c" offset="4"/>
        <vcount>4 3</vcount>
        <p>0 0 0 0 0  1 0 0 1 0  2 0 0 2 0  3 0 0 3 1    0 1 0 4 1  2 1 0 2 1  1 1 0 1 1</p>
      </polylist>"##;
    let soup = read_text(&document(
        "Y_UP",
        &square("sq", &sources, primitive),
        &place("sq", ""),
    ));
    assert_eq!(faces(&soup), vec![vec![0, 1, 2, 3], vec![0, 2, 1]]);
    assert_eq!(soup.positions[2], Vec3::new(1.0, 1.0, 0.0));
    let uvs = soup.corner_uvs.as_ref().unwrap();
    assert_eq!(uvs[3], Vec2::new(0.0, 1.0));
    assert_eq!(uvs[4], Vec2::new(0.5, 0.5), "set 0, not set 1");
    // Vertex 3 is only in the quad (+z); vertices 0–2 have +z and −z corners: the mean is zero.
    let normals = soup.vertex_normals.as_ref().unwrap();
    assert_eq!(normals[3], Vec3::Z);
    assert_eq!(normals[0], Vec3::ZERO);
    let colors = soup.vertex_colors.as_ref().unwrap();
    assert_eq!(colors[3], [0, 128, 255]);
    // Vertex 0 is red in the quad and blue-ish in the triangle: the mean.
    assert_eq!(colors[0], [128, 64, 128]);
    assert!(
        soup.notes
            .iter()
            .any(|n| n.contains("3 vertex(es) had different normals")),
        "{:?}",
        soup.notes
    );
    assert!(
        soup.notes.iter().any(|n| n.contains("different colours")),
        "{:?}",
        soup.notes
    );
}

#[test]
fn triangles_polygons_fans_and_strips_make_the_faces_they_describe() {
    let primitives = r##"
      <triangles count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2</p></triangles>
      <polygons count="2"><input semantic="VERTEX" source="#sq-v" offset="0"/>
        <p>0 1 2 3</p>
        <ph><p>3 2 1 0</p><h>0 1 2</h><h>1 2 3</h></ph>
      </polygons>
      <trifans count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2 3</p></trifans>
      <tristrips count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 3 2 2 2</p></tristrips>
      <lines count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1</p></lines>"##;
    let soup = read_text(&document(
        "Y_UP",
        &square("sq", "", primitives),
        &place("sq", ""),
    ));
    assert_eq!(
        faces(&soup),
        vec![
            vec![0, 1, 2],
            vec![0, 1, 2, 3],
            vec![3, 2, 1, 0],
            // The fan.
            vec![0, 1, 2],
            vec![0, 2, 3],
            // The strip: (0 1 3), then (1 3 2) with its first two swapped; the rest repeat a
            // corner and make no face.
            vec![0, 1, 3],
            vec![3, 1, 2],
        ]
    );
    let note = soup
        .notes
        .iter()
        .find(|n| n.starts_with("skipped"))
        .unwrap();
    assert!(
        note.contains("1 line primitive(s)") && note.contains("2 polygon hole(s)"),
        "{note}"
    );
}

#[test]
fn node_transforms_compose_in_document_order_and_each_instance_is_a_copy() {
    let triangle = r##"<triangles count="2"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2 0 2 3</p></triangles>"##;
    let nodes = place("sq", "<translate>10 0 0</translate><scale>2 2 2</scale>")
        + r##"<node name="parent"><translate>0 5 0</translate>
              <node name="child"><rotate>0 0 1 90</rotate><instance_geometry url="#sq"/></node></node>"##
        + &place("sq", "<matrix>1 0 0 1  0 1 0 2  0 0 1 3  0 0 0 1</matrix>");
    let soup = read_text(&document("Y_UP", &square("sq", "", triangle), &nodes));
    assert_eq!(soup.positions.len(), 12, "three copies of four positions");
    assert_eq!(soup.face_count(), 6);
    // Scale then translate: (1, 1, 0) → (12, 2, 0).
    assert_eq!(soup.positions[2], Vec3::new(12.0, 2.0, 0.0));
    // Rotated a quarter turn about z, then moved up 5: (1, 0, 0) → (0, 6, 0).
    assert!(
        soup.positions[5].abs_diff_eq(Vec3::new(0.0, 6.0, 0.0), 1e-6),
        "{}",
        soup.positions[5]
    );
    // The matrix is read row by row: its last column is the translation.
    assert_eq!(soup.positions[8], Vec3::new(1.0, 2.0, 3.0));
    // Each copy's faces name its own positions.
    assert_eq!(soup.face(4), &[8, 9, 10]);
    assert!(
        soup.notes[0].starts_with("3 objects (sq-node, child, sq-node)"),
        "{:?}",
        soup.notes
    );
}

#[test]
fn a_z_up_scene_is_turned_y_up_and_a_mirror_keeps_faces_facing_out() {
    let triangle = r##"<triangles count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/>
        <input semantic="NORMAL" source="#n" offset="0"/><p>0 1 2</p></triangles>"##;
    let normals = source("n", 3, "0 0 1  0 0 1  0 0 1  0 0 1");
    let soup = read_text(&document(
        "Z_UP",
        &square("sq", &normals, triangle),
        &place("sq", ""),
    ));
    // (x, y, z) → (x, z, −y).
    assert_eq!(soup.positions[2], Vec3::new(1.0, 0.0, -1.0));
    assert_eq!(soup.vertex_normals.as_ref().unwrap()[0], Vec3::Y);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2]]);
    let mirrored = read_text(&document(
        "Y_UP",
        &square("sq", &normals, triangle),
        &place("sq", "<scale>1 1 -1</scale>"),
    ));
    assert_eq!(faces(&mirrored), vec![vec![2, 1, 0]]);
    assert_eq!(mirrored.vertex_normals.as_ref().unwrap()[0], Vec3::NEG_Z);
}

#[test]
fn a_file_without_a_scene_places_each_geometry_once_and_instance_nodes_are_walked() {
    let triangle = r##"<triangles count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2</p></triangles>"##;
    let text = format!(
        r##"<COLLADA version="1.5.0"><library_geometries>{}</library_geometries></COLLADA>"##,
        square("sq", "", triangle)
    );
    let soup = read_text(&text);
    assert_eq!((soup.positions.len(), soup.face_count()), (4, 1));
    let library = r##"<library_nodes><node id="shared"><translate>0 0 7</translate><instance_geometry url="#sq"/></node></library_nodes>"##;
    let text = document(
        "Y_UP",
        &square("sq", "", triangle),
        r##"<node><instance_node url="#shared"/></node>"##,
    )
    .replace(
        "<library_visual_scenes>",
        &format!("{library}<library_visual_scenes>"),
    );
    let soup = read_text(&text);
    assert_eq!(soup.positions[0], Vec3::new(0.0, 0.0, 7.0));
}

#[test]
fn broken_documents_are_errors_that_name_the_line() {
    let triangle = r##"<triangles count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 x</p></triangles>"##;
    let cases = [
        ("<COLLADA><asset>".to_string(), "line 1"),
        ("<mesh/>".to_string(), "is not a COLLADA document"),
        (
            document("Y_UP", &square("sq", "", triangle), &place("sq", "")),
            "`x` is not an index",
        ),
        (
            document("Y_UP", "", &place("nowhere", "")),
            "names `#nowhere`, which does not exist",
        ),
        (
            document(
                "Y_UP",
                "",
                r##"<node id="loop"><instance_node url="#loop"/></node>"##,
            ),
            "nested deeper than",
        ),
        (
            document(
                "Y_UP",
                &square("sq", "", triangle),
                &place("sq", "<matrix>1 2 3</matrix>"),
            ),
            "holds 3 numbers, expected 16",
        ),
    ];
    for (text, expected) in cases {
        let err = read(text.as_bytes()).unwrap_err();
        assert!(
            format!("{} {}", err.location, err.message).contains(expected),
            "{err:?}"
        );
    }
    assert!(
        read(b"\xff\xfe<")
            .unwrap_err()
            .message
            .contains("not UTF-8")
    );
}

#[test]
fn corners_naming_missing_positions_are_left_for_the_builder() {
    let triangle = r##"<triangles count="2"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2 0 2 9</p></triangles>"##;
    let soup = read_text(&document(
        "Y_UP",
        &square("sq", "", triangle),
        &place("sq", ""),
    ));
    assert_eq!(soup.face(1), &[0, 2, u32::MAX]);
    let mut world = bevy::prelude::World::new();
    let built = crate::mesh::build_mesh(&mut world, &soup, Default::default()).unwrap();
    assert_eq!(crate::mesh::mesh_stats(&world, built.mesh).faces, 1);
}

/// Every prefix of a document, and copies with bytes overwritten, read without a panic.
#[test]
fn damaged_documents_never_panic() {
    let primitive = r##"<polylist count="2"><input semantic="VERTEX" source="#sq-v" offset="0"/>
        <input semantic="NORMAL" source="#n" offset="1"/><vcount>4 3</vcount>
        <p>0 0 1 0 2 0 3 0 0 1 2 1 1 1</p></polylist>"##;
    let bytes = document(
        "Z_UP",
        &square("sq", &source("n", 3, "0 0 1 0 0 -1"), primitive),
        &place("sq", "<rotate>1 0 0 30</rotate>"),
    )
    .into_bytes();
    for cut in 0..bytes.len() {
        let _ = read(&bytes[..cut]);
    }
    let mut seed = 0x9e37_79b9_u32;
    for _ in 0..2000 {
        let mut damaged = bytes.clone();
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        let at = seed as usize % damaged.len();
        damaged[at] = [b'9', b'-', b' ', b'<', b'>', b'"', b'#', 0xff][(seed >> 24) as usize % 8];
        let _ = read(&damaged);
    }
}

#[test]
fn each_face_keeps_its_node_and_its_bound_material_as_its_group() {
    let primitives = r##"<triangles count="1" material="wood-symbol"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2</p></triangles>
        <triangles count="1" material="unbound"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 2 3</p></triangles>"##;
    let nodes = r##"<node name="Table"><instance_geometry url="#sq"><bind_material><technique_common>
            <instance_material symbol="wood-symbol" target="#wood-id"/>
        </technique_common></bind_material></instance_geometry></node>"##;
    let text = document("Y_UP", &square("sq", "", primitives), nodes).replace(
        "<library_geometries>",
        r##"<library_materials><material id="wood-id" name="Wood"/></library_materials><library_geometries>"##,
    );
    let soup = read_text(&text);
    let groups = soup.face_groups.unwrap();
    assert_eq!(groups.of_face, [0, 1]);
    let names: Vec<String> = groups.table.groups.iter().map(|g| g.describe()).collect();
    assert_eq!(
        names,
        [
            "object Table · material Wood",
            "object Table · material unbound"
        ]
    );
}

#[test]
fn decimal_commas_of_a_european_locale_are_read_as_decimal_points_and_said() {
    let geometry = r##"<geometry id="sq" name="sq"><mesh>
        <source id="sq-p"><float_array id="sq-p-array" count="9">0 0 0  1,5 0 0  1,450607 -0,25 0</float_array>
        <technique_common><accessor source="#sq-p-array" count="3" stride="3"/></technique_common></source>
        <vertices id="sq-v"><input semantic="POSITION" source="#sq-p"/></vertices>
        <triangles count="1"><input semantic="VERTEX" source="#sq-v" offset="0"/><p>0 1 2</p></triangles>
        </mesh></geometry>"##;
    let soup = read_text(&document(
        "Y_UP",
        geometry,
        &place("sq", "<translate>0,5 0 0</translate>"),
    ));
    assert_eq!(
        soup.positions,
        vec![
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.450607 + 0.5, -0.25, 0.0)
        ]
    );
    assert_eq!(
        soup.notes[0],
        "read 4 number(s) with a decimal comma, read as a decimal point (the first `1,5`, line 5)"
    );
    // A comma that could be a separator is not guessed at.
    let two = document(
        "Y_UP",
        &square("sq", "", ""),
        &place("sq", "<translate>1,5,0 0 0</translate>"),
    );
    let err = read(two.as_bytes()).unwrap_err();
    assert_eq!(err.message, "`1,5,0` is not a number");
}
