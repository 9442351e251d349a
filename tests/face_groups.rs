//! Face groups (OBJ's objects, groups, materials, smoothing groups) from a file, through the
//! edits that make faces, undo and a save: every face keeps its group, a face made from a face
//! takes that face's, a face made in a hole a neighbour's, and OBJ writes the statements back.

mod common;

use bevy::prelude::World;
use pappus::edit::Edit;
use pappus::io::{self, Format};
use pappus::mesh::attributes::MeshAttributes;
use pappus::mesh::change::{LocalRecorder, SavedContents};
use pappus::mesh::groups::{FaceGroup, face_group};
use pappus::mesh::ids::ElementId;
use pappus::mesh::{FaceId, MeshId, MeshMembers, MeshRef, PolygonSoup, to_soup};
use std::path::Path;

/// A unit cube: the top a lid in red, the other five sides the body in blue, with the library
/// named once. Rows: 0 body, 1 lid.
const CUBE: &[u8] = b"mtllib cube.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
o cube
g body
usemtl blue
s 1
f 1 4 3 2
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
g lid
usemtl red
s off
f 5 6 7 8
";

const BODY: u32 = 0;
const LID: u32 = 1;

fn cube() -> (World, MeshId) {
    let soup = io::read_bytes(Format::Obj, CUBE, Path::new("cube.obj")).unwrap();
    let (world, built) = common::build(&soup);
    (world, built.mesh)
}

use common::run_edit as run;

/// Every face's group, checking the invariant: the record says groups and every face has one
/// naming a row of the table.
fn groups_of(world: &World, mesh: MeshId) -> Vec<(FaceId, u32)> {
    assert!(MeshAttributes::of(world, mesh).groups);
    MeshMembers::collect(world, mesh)
        .faces
        .into_iter()
        .map(|f| {
            let g = face_group(world, f).unwrap_or_else(|| panic!("{f} has no group"));
            assert!(g < 2, "{f}: row {g}");
            (f, g)
        })
        .collect()
}

/// How many faces are in each of the two groups.
fn counts(world: &World, mesh: MeshId) -> [usize; 2] {
    let mut n = [0; 2];
    for (_, g) in groups_of(world, mesh) {
        n[g as usize] += 1;
    }
    n
}

/// The face whose vertices are all at height `z` (the top or the bottom).
fn face_at_height(world: &World, mesh: MeshId, z: f32) -> FaceId {
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .faces
        .into_iter()
        .find(|&f| m.face_vertices(f).all(|v| m.position(v).z == z))
        .unwrap()
}

/// The statements and faces of OBJ text, without the vertex lines.
fn statements(text: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(text)
        .lines()
        .filter(|l| !l.starts_with('v') && !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

#[test]
fn obj_statements_survive_the_mesh_and_are_written_back() {
    let (world, mesh) = cube();
    assert_eq!(counts(&world, mesh), [5, 1]);
    let lid = face_at_height(&world, mesh, 1.0);
    assert_eq!(face_group(&world, lid), Some(LID));
    let described = pappus::mesh::groups::describe_face_group(&world, mesh, lid);
    assert_eq!(
        described.as_deref(),
        Some("object cube · group lid · material red · smoothing off")
    );
    let written = io::write_bytes(Format::Obj, &to_soup(&world, mesh)).unwrap();
    assert_eq!(statements(&written), statements(CUBE));
}

#[test]
fn faces_made_from_a_face_keep_its_group() {
    let (mut world, mesh) = cube();
    // Split the lid along a diagonal: both halves are lid.
    let lid = face_at_height(&world, mesh, 1.0);
    let (a, c) = {
        let m = MeshRef::new(&world);
        let v: Vec<_> = m.face_vertices(lid).collect();
        (v[0], v[2])
    };
    run(
        &mut world,
        mesh,
        &Edit::local_on(
            "split-face",
            [ElementId::from(lid), a.into(), c.into()],
            &[],
        ),
    );
    assert_eq!(counts(&world, mesh), [5, 2]);
    // Extrude the bottom: its four walls are body, like it.
    let bottom = face_at_height(&world, mesh, 0.0);
    run(
        &mut world,
        mesh,
        &Edit::local_on("extrude", [bottom], &[0.5]),
    );
    assert_eq!(counts(&world, mesh), [9, 2]);
    // Triangulate: each quad's two triangles in its group.
    run(&mut world, mesh, &Edit::registered("triangulate").unwrap());
    assert_eq!(counts(&world, mesh), [18, 2]);
    // Subdivide: every child in its parent's group.
    let summary = run(&mut world, mesh, &Edit::registered("loop").unwrap());
    assert!(!summary.contains("dropped"), "{summary}");
    assert_eq!(counts(&world, mesh), [72, 8]);
    let summary = run(
        &mut world,
        mesh,
        &Edit::registered("catmull-clark").unwrap(),
    );
    assert!(!summary.contains("dropped"), "{summary}");
    assert_eq!(counts(&world, mesh), [216, 24]);
}

#[test]
fn a_filled_hole_takes_a_neighbours_group() {
    let (mut world, mesh) = cube();
    let lid = face_at_height(&world, mesh, 1.0);
    run(&mut world, mesh, &Edit::local("erase", lid));
    assert_eq!(counts(&world, mesh), [5, 0]);
    let rim = {
        let m = MeshRef::new(&world);
        let members = MeshMembers::collect(&world, mesh);
        members
            .edges
            .into_iter()
            .find(|&e| m.is_boundary_edge(e))
            .unwrap()
    };
    run(&mut world, mesh, &Edit::local("fill-hole", rim));
    assert_eq!(counts(&world, mesh), [6, 0]);
    let filled = face_at_height(&world, mesh, 1.0);
    assert_eq!(face_group(&world, filled), Some(BODY));
}

#[test]
fn undo_brings_groups_back_and_remeshing_says_it_drops_them() {
    let (mut world, mesh) = cube();
    let before = groups_of(&world, mesh);
    let lid = face_at_height(&world, mesh, 1.0);
    let corners: Vec<_> = MeshRef::new(&world).face_vertices(lid).collect();
    let recorder = LocalRecorder::begin(&world, mesh, &corners);
    run(
        &mut world,
        mesh,
        &Edit::local_on(
            "split-face",
            [ElementId::from(lid), corners[0].into(), corners[2].into()],
            &[],
        ),
    );
    let undo = recorder.finish(&world);
    let (redo, _, _) = undo.apply(&mut world);
    assert_eq!(groups_of(&world, mesh), before);
    redo.apply(&mut world);
    assert_eq!(counts(&world, mesh), [5, 2]);

    run(&mut world, mesh, &Edit::registered("triangulate").unwrap());
    assert_eq!(counts(&world, mesh), [10, 2]);
    let saved = SavedContents::capture(&world, mesh);
    let summary = run(&mut world, mesh, &Edit::registered("remesh").unwrap());
    assert!(
        summary.ends_with(" — groups dropped: remeshing does not carry attributes"),
        "{summary}"
    );
    assert!(world.query::<&FaceGroup>().iter(&world).next().is_none());
    assert!(to_soup(&world, mesh).face_groups.is_none());
    saved.apply(&mut world);
    assert_eq!(counts(&world, mesh), [10, 2]);
}

#[test]
fn formats_without_groups_say_they_drop_them() {
    let (world, mesh) = cube();
    let soup: PolygonSoup = to_soup(&world, mesh);
    assert_eq!(io::dropped(Path::new("c.ply"), &soup), ["groups"]);
    assert_eq!(io::dropped(Path::new("c.off"), &soup), ["groups"]);
    assert!(io::dropped(Path::new("c.obj"), &soup).is_empty());
}
