//! Attributes (corner UVs, vertex normals and colours) through edits and undo: carried with
//! exact values where an operation interpolates, dropped with a message where it cannot.

mod common;

use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;
use pappus::edit::Edit;
use pappus::mesh::attributes::{CornerUv, MeshAttributes, Seam, VertexColor, VertexNormal};
use pappus::mesh::change::{LocalRecorder, SavedContents};
use pappus::mesh::{MeshId, MeshMembers, MeshRef, PolygonSoup, VertexId, shapes, to_soup};

use common::run_edit as run;

/// The invariant of the record: every face halfedge has a UV, no boundary one does.
fn assert_every_corner_has_a_uv(world: &World, mesh: MeshId) {
    assert!(MeshAttributes::of(world, mesh).uv);
    let m = MeshRef::new(world);
    for h in MeshMembers::collect(world, mesh).halfedges {
        let has = world.get::<CornerUv>(h.0).is_some();
        assert_eq!(has, m.face(h).is_some(), "{h}");
    }
}

/// The UV of `v` inside the face of every halfedge into it (one per face around it).
fn corner_uvs_of(world: &World, v: VertexId) -> Vec<Vec2> {
    let m = MeshRef::new(world);
    m.vertex_outgoing(v)
        .map(|h| m.twin(h))
        .filter(|&h| m.face(h).is_some())
        .map(|h| world.get::<CornerUv>(h.0).unwrap().0)
        .collect()
}

/// A unit square of two triangles with UV = 2 × (x, y) + (1, 0) at every corner, normals and
/// colours; the diagonal is 0–2.
fn square() -> PolygonSoup {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let mut soup = PolygonSoup::from_faces(positions, &[[0u32, 1, 2], [0, 2, 3]]);
    let uv = |p: Vec3| Vec2::new(2.0 * p.x + 1.0, 2.0 * p.y);
    soup.corner_uvs = Some(
        soup.indices
            .iter()
            .map(|&i| uv(soup.positions[i as usize]))
            .collect(),
    );
    soup.vertex_normals = Some(vec![Vec3::Z, Vec3::Z, Vec3::X, Vec3::Z]);
    soup.vertex_colors = Some(vec![[0, 0, 0], [10, 20, 30], [255, 255, 255], [1, 1, 1]]);
    soup
}

fn edge_between(world: &World, a: VertexId, b: VertexId) -> pappus::mesh::EdgeId {
    let m = MeshRef::new(world);
    m.edge(m.find_halfedge(a, b).unwrap())
}

#[test]
fn a_split_interpolates_uvs_normals_and_colours() {
    let (mut world, built) = common::build(&square());
    let v = |i: usize| built.input_vertices[i].unwrap();
    let summary = {
        let e = Edit::local("split", edge_between(&world, v(0), v(2)));
        run(&mut world, built.mesh, &e)
    };
    assert!(!summary.contains("dropped"), "{summary}");
    assert_every_corner_has_a_uv(&world, built.mesh);
    let m = MeshRef::new(&world);
    let mid = m
        .vertex_neighbors(v(1))
        .find(|&x| x != v(0) && x != v(2))
        .unwrap();
    assert_eq!(m.position(mid), Vec3::new(0.5, 0.5, 0.0));
    // Four faces meet at the new vertex, each with the UV of the midpoint: (2, 1).
    let uvs = corner_uvs_of(&world, mid);
    assert_eq!(uvs, vec![Vec2::new(2.0, 1.0); 4]);
    // Every old corner kept its UV.
    for (i, p) in [(0, Vec3::ZERO), (1, Vec3::X), (3, Vec3::Y)] {
        for uv in corner_uvs_of(&world, v(i)) {
            assert_eq!(uv, Vec2::new(2.0 * p.x + 1.0, 2.0 * p.y));
        }
    }
    assert_eq!(
        world.get::<VertexNormal>(mid.0).unwrap().0,
        Vec3::new(1.0, 0.0, 1.0).normalize()
    );
    assert_eq!(world.get::<VertexColor>(mid.0).unwrap().0, [128, 128, 128]);
}

#[test]
fn a_flip_and_a_collapse_keep_each_vertex_its_uv() {
    let (mut world, built) = common::build(&square());
    let v = |i: usize| built.input_vertices[i].unwrap();
    let flipped = {
        let e = Edit::local("flip", edge_between(&world, v(0), v(2)));
        run(&mut world, built.mesh, &e)
    };
    assert!(!flipped.contains("dropped"), "{flipped}");
    assert_every_corner_has_a_uv(&world, built.mesh);
    for i in 0..4 {
        let p = MeshRef::new(&world).position(v(i));
        for uv in corner_uvs_of(&world, v(i)) {
            assert_eq!(uv, Vec2::new(2.0 * p.x + 1.0, 2.0 * p.y), "vertex {i}");
        }
    }
    // Split the new diagonal 1–3, then collapse the half towards 1: the kept vertex moves to
    // the midpoint (0.75, 0.25) and so do its UVs.
    let split = Edit::local("split", edge_between(&world, v(1), v(3)));
    run(&mut world, built.mesh, &split);
    let m = MeshRef::new(&world);
    let mid = m
        .vertex_neighbors(v(0))
        .find(|&x| m.position(x) == Vec3::new(0.5, 0.5, 0.0))
        .unwrap();
    {
        let e = Edit::local("collapse", edge_between(&world, mid, v(1)));
        run(&mut world, built.mesh, &e)
    };
    assert_every_corner_has_a_uv(&world, built.mesh);
    let m = MeshRef::new(&world);
    let kept = if m.try_vertex(mid).is_some() {
        mid
    } else {
        v(1)
    };
    assert_eq!(m.position(kept), Vec3::new(0.75, 0.25, 0.0));
    for uv in corner_uvs_of(&world, kept) {
        assert_eq!(uv, Vec2::new(2.5, 0.5));
    }
}

#[test]
fn one_loop_level_interpolates_uvs_linearly_and_drops_normals() {
    let (mut world, built) = common::build(&square());
    let summary = run(&mut world, built.mesh, &Edit::registered("loop").unwrap());
    assert!(
        summary.ends_with(
            "— normals dropped: subdivision carries UVs, colours and groups, not normals or seam marks"
        ),
        "{summary}"
    );
    assert_every_corner_has_a_uv(&world, built.mesh);
    let has = MeshAttributes::of(&world, built.mesh);
    assert!(has.uv && has.colors && !has.normals);
    // Linear in UV: every corner's UV is the affine map of its vertex's *unsmoothed* position,
    // i.e. of the midpoint of the old edge for new vertices. On this square (boundary rules
    // keep the boundary straight) the new vertices are the old edges' midpoints.
    let soup = to_soup(&world, built.mesh);
    let uvs = soup.corner_uvs.as_ref().unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for (k, &i) in soup.indices.iter().enumerate() {
        if i >= 4 {
            seen.insert((uvs[k].x.to_bits(), uvs[k].y.to_bits()));
        }
    }
    let expected: std::collections::BTreeSet<(u32, u32)> =
        [(2.0, 0.0), (3.0, 1.0), (2.0, 2.0), (1.0, 1.0), (2.0, 1.0)]
            .into_iter()
            .map(|(x, y): (f32, f32)| (x.to_bits(), y.to_bits()))
            .collect();
    assert_eq!(seen, expected);
    // The colour of the diagonal's midpoint is the mean of its ends.
    assert!(soup.vertex_colors.unwrap().contains(&[128, 128, 128]));
}

#[test]
fn catmull_clark_puts_the_face_point_at_the_uv_centroid() {
    let mut soup = PolygonSoup::from_faces(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        &[[0u32, 1, 2, 3]],
    );
    soup.corner_uvs = Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::new(0.0, 3.0)]);
    let (mut world, built) = common::build(&soup);
    run(
        &mut world,
        built.mesh,
        &Edit::registered("catmull-clark").unwrap(),
    );
    assert_every_corner_has_a_uv(&world, built.mesh);
    let out = to_soup(&world, built.mesh);
    let uvs = out.corner_uvs.unwrap();
    // Vertex 8 is the face point (4 old vertices, 4 edge points), at the UV centroid.
    for (k, &i) in out.indices.iter().enumerate() {
        if i == 8 {
            assert_eq!(uvs[k], Vec2::new(0.5, 1.0));
        }
    }
}

#[test]
fn remeshing_and_simplifying_say_they_dropped_the_attributes() {
    let mut soup = shapes::icosphere(2);
    soup.corner_uvs = Some(
        soup.indices
            .iter()
            .map(|&i| soup.positions[i as usize].truncate())
            .collect(),
    );
    soup.vertex_colors = Some(vec![[9, 9, 9]; soup.positions.len()]);
    let (mut world, built) = common::build(&soup);
    let summary = run(&mut world, built.mesh, &Edit::registered("remesh").unwrap());
    assert!(
        summary.ends_with(" — UVs and colours dropped: remeshing does not carry attributes"),
        "{summary}"
    );
    assert!(MeshAttributes::of(&world, built.mesh).is_empty());
    assert!(world.query::<&CornerUv>().iter(&world).next().is_none());
    let out = to_soup(&world, built.mesh);
    assert_eq!((out.corner_uvs, out.vertex_colors), (None, None));
}

/// Vertices with their attributes (bitwise), and faces as cycles of (vertex, UV bits) rotated
/// to start at their smallest vertex, sorted: equal for the same mesh whatever its face order.
#[allow(clippy::type_complexity)]
fn same_up_to_face_order(
    s: &PolygonSoup,
) -> (
    Vec<[u32; 3]>,
    Option<Vec<[u8; 3]>>,
    Option<Vec<[u32; 3]>>,
    Vec<Vec<(u32, [u32; 2])>>,
) {
    let bits3 = |v: &Vec3| v.to_array().map(f32::to_bits);
    let uvs = s.corner_uvs.as_ref().unwrap();
    let mut faces: Vec<Vec<(u32, [u32; 2])>> = (0..s.face_count())
        .map(|f| {
            let start = s.face_starts[f] as usize;
            let mut face: Vec<(u32, [u32; 2])> = s
                .face(f)
                .iter()
                .enumerate()
                .map(|(k, &i)| (i, uvs[start + k].to_array().map(f32::to_bits)))
                .collect();
            let first = (0..face.len()).min_by_key(|&k| face[k].0).unwrap();
            face.rotate_left(first);
            face
        })
        .collect();
    faces.sort();
    (
        s.positions.iter().map(bits3).collect(),
        s.vertex_colors.clone(),
        s.vertex_normals
            .as_ref()
            .map(|n| n.iter().map(bits3).collect()),
        faces,
    )
}

#[test]
fn undo_restores_attributes_exactly() {
    let (mut world, built) = common::build(&square());
    let mesh = built.mesh;
    let before = to_soup(&world, mesh);
    let v = |i: usize| built.input_vertices[i].unwrap();
    // A local edit, recorded as the editor records it.
    let recorder = LocalRecorder::begin(&world, mesh, &[v(0), v(2)]);
    {
        let e = Edit::local("split", edge_between(&world, v(0), v(2)));
        run(&mut world, mesh, &e)
    };
    let undo = recorder.finish(&world);
    let after = to_soup(&world, mesh);
    let (redo, _, _) = undo.apply(&mut world);
    let same =
        |a: &PolygonSoup, b: &PolygonSoup| same_up_to_face_order(a) == same_up_to_face_order(b);
    assert!(same(&to_soup(&world, mesh), &before));
    assert_every_corner_has_a_uv(&world, mesh);
    redo.apply(&mut world);
    assert!(same(&to_soup(&world, mesh), &after));
    // A whole-mesh edit that drops them: the undo brings them back.
    let saved = SavedContents::capture(&world, mesh);
    run(&mut world, mesh, &Edit::registered("remesh").unwrap());
    assert!(MeshAttributes::of(&world, mesh).is_empty());
    saved.apply(&mut world);
    assert_eq!(
        same_up_to_face_order(&to_soup(&world, mesh)),
        same_up_to_face_order(&after)
    );
    assert_eq!(
        MeshAttributes::of(&world, mesh),
        MeshAttributes {
            uv: true,
            normals: true,
            colors: true,
            seams: false,
            groups: false,
        }
    );
    assert_every_corner_has_a_uv(&world, mesh);
}

#[test]
fn a_seam_mark_undoes_and_survives_a_whole_mesh_record() {
    let (mut world, built) = common::build(&square());
    let mesh = built.mesh;
    let v = |i: usize| built.input_vertices[i].unwrap();
    let diagonal = edge_between(&world, v(0), v(2));
    let recorder = LocalRecorder::begin(&world, mesh, &[v(0), v(2)]);
    let summary = run(&mut world, mesh, &Edit::local("seam", diagonal));
    assert!(summary.ends_with("is a seam"), "{summary}");
    assert!(world.get::<Seam>(diagonal.0).is_some());
    assert!(MeshAttributes::of(&world, mesh).seams);
    let undo = recorder.finish(&world);
    let (redo, _, _) = undo.apply(&mut world);
    assert!(world.get::<Seam>(diagonal.0).is_none(), "undo unmarks");
    redo.apply(&mut world);
    assert!(world.get::<Seam>(diagonal.0).is_some(), "redo marks again");
    // The whole-mesh record carries the marks: a remesh drops them (and says so), undo brings
    // them back on the same edge.
    let saved = SavedContents::capture(&world, mesh);
    let summary = run(&mut world, mesh, &Edit::registered("remesh").unwrap());
    assert!(summary.contains("seam marks"), "{summary}");
    assert!(!MeshAttributes::of(&world, mesh).seams);
    saved.apply(&mut world);
    let marked: Vec<_> = world
        .query_filtered::<bevy::prelude::Entity, bevy::prelude::With<Seam>>()
        .iter(&world)
        .collect();
    assert_eq!(marked.len(), 1);
    let m = MeshRef::new(&world);
    let (a, b) = m.edge_vertices(pappus::mesh::EdgeId(marked[0]));
    let ends = [m.position(a), m.position(b)];
    assert!(ends.contains(&Vec3::ZERO) && ends.contains(&Vec3::new(1.0, 1.0, 0.0)));
}

#[test]
fn splitting_a_seam_leaves_both_halves_seams() {
    let (mut world, built) = common::build(&square());
    let mesh = built.mesh;
    let v = |i: usize| built.input_vertices[i].unwrap();
    let diagonal = edge_between(&world, v(0), v(2));
    run(&mut world, mesh, &Edit::local("seam", diagonal));
    run(&mut world, mesh, &Edit::local("split", diagonal));
    let seams: Vec<bevy::prelude::Entity> = world
        .query_filtered::<bevy::prelude::Entity, bevy::prelude::With<Seam>>()
        .iter(&world)
        .collect();
    let m = MeshRef::new(&world);
    let marked: Vec<(Vec3, Vec3)> = seams
        .into_iter()
        .map(|e| {
            let (a, b) = m.edge_vertices(pappus::mesh::EdgeId(e));
            (m.position(a), m.position(b))
        })
        .collect();
    // The two halves of the diagonal, meeting at its midpoint; the split's cross edges are not.
    assert_eq!(marked.len(), 2, "{marked:?}");
    let mid = Vec3::new(0.5, 0.5, 0.0);
    for (a, b) in marked {
        assert!(a == mid || b == mid);
        let other = if a == mid { b } else { a };
        assert!(other == Vec3::ZERO || other == Vec3::new(1.0, 1.0, 0.0));
    }
}
