//! Flip, split, bisect and collapse: exact expected meshes (up to relabeling), counts, χ, validity, and
//! every classic refusal with the world compared element by element before and after.

mod common;

use bevy::math::Vec3;
use bevy::prelude::World;
use common::{build, canonical};
use pappus::mesh::{
    Edge, EdgeId, Face, Halfedge, MeshId, MeshMembers, MeshRef, PolygonSoup, Position, Vertex,
    VertexId, mesh_stats, shapes, to_soup, validate,
};
use pappus::ops::Refusal;
use pappus::ops::local::{CollapseOptions, bisect_edge, collapse_edge, flip_edge, split_edge};

fn assert_same_mesh(world: &World, mesh: MeshId, expected: &PolygonSoup) {
    validate(world, mesh).unwrap();
    assert_eq!(canonical(&to_soup(world, mesh)), canonical(expected));
}

/// Every component of every element, sorted: equal snapshots mean an untouched mesh.
fn snapshot(world: &World, mesh: MeshId) -> Vec<String> {
    let members = MeshMembers::collect(world, mesh);
    let mut out: Vec<String> = Vec::new();
    for v in &members.vertices {
        out.push(format!(
            "{v:?} {:?} {:?}",
            world.get::<Vertex>(v.0),
            world.get::<Position>(v.0)
        ));
    }
    for h in &members.halfedges {
        out.push(format!("{h:?} {:?}", world.get::<Halfedge>(h.0)));
    }
    for e in &members.edges {
        out.push(format!("{e:?} {:?}", world.get::<Edge>(e.0)));
    }
    for f in &members.faces {
        out.push(format!("{f:?} {:?}", world.get::<Face>(f.0)));
    }
    out.sort();
    out
}

fn edge(world: &World, built: &pappus::mesh::BuiltMesh, a: usize, b: usize) -> EdgeId {
    let m = MeshRef::new(world);
    let (va, vb) = (
        built.input_vertices[a].unwrap(),
        built.input_vertices[b].unwrap(),
    );
    m.edge(
        m.find_halfedge(va, vb)
            .unwrap_or_else(|| panic!("no edge {a}-{b}")),
    )
}

fn refused(
    soup: PolygonSoup,
    a: usize,
    b: usize,
    op: impl Fn(&mut World, EdgeId) -> Result<(), Refusal>,
) -> Refusal {
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, a, b);
    let before = snapshot(&world, built.mesh);
    let refusal = op(&mut world, e).expect_err("the operation must be refused");
    assert_eq!(
        snapshot(&world, built.mesh),
        before,
        "a refusal changed the mesh"
    );
    refusal
}

fn flip(w: &mut World, e: EdgeId) -> Result<(), Refusal> {
    flip_edge(w, e).map(|_| ())
}
fn collapse(w: &mut World, e: EdgeId) -> Result<(), Refusal> {
    collapse_edge(w, e, CollapseOptions::default()).map(|_| ())
}

fn counts(world: &World, mesh: MeshId) -> (usize, usize, usize, i64) {
    let s = mesh_stats(world, mesh);
    (s.vertices, s.edges, s.faces, s.euler_characteristic)
}

// ---- flip ----------------------------------------------------------------------------------

#[test]
fn flip_the_diamond() {
    // 0 (0,-1), 1 (1,0), 2 (0,1), 3 (-1,0); faces 012, 023. Flipping 0-2 gives 1-3.
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 2);
    flip_edge(&mut world, e).unwrap();
    let expected = PolygonSoup::from_faces(soup.positions.clone(), &[[1u32, 2, 3], [1, 3, 0]]);
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (4, 5, 2, 1));
    // Flipping back restores the input.
    let e = edge(&world, &built, 1, 3);
    flip_edge(&mut world, e).unwrap();
    assert_same_mesh(&world, built.mesh, &soup);
}

#[test]
fn flip_an_interior_edge_of_a_fan_and_back() {
    let soup = shapes::triangle_fan(6, true);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    // Centre 0, rim 1..6: flip the spoke 0-1 → rim chord 6-2.
    let e = edge(&world, &built, 0, 1);
    let flipped = flip_edge(&mut world, e).unwrap();
    assert_eq!(flipped, e, "the edge entity is kept");
    let mut expected = soup.clone();
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [
        [0, 2, 3],
        [0, 3, 4],
        [0, 4, 5],
        [0, 5, 6],
        [0, 6, 2],
        [6, 1, 2],
    ] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), before);
    let m = MeshRef::new(&world);
    let (a, b) = m.edge_vertices(flipped);
    let ends = [a, b];
    assert!(
        ends.contains(&built.input_vertices[6].unwrap())
            && ends.contains(&built.input_vertices[2].unwrap())
    );
}

#[test]
fn flip_on_an_icosphere_keeps_counts_and_validity() {
    let (mut world, built) = build(&shapes::icosphere(2));
    let before = counts(&world, built.mesh);
    let edges = MeshMembers::collect(&world, built.mesh).edges;
    let mut applied = 0;
    for e in edges.into_iter().step_by(7) {
        if flip_edge(&mut world, e).is_ok() {
            applied += 1;
            validate(&world, built.mesh).unwrap();
        }
    }
    assert!(applied > 10);
    assert_eq!(counts(&world, built.mesh), before);
}

#[test]
fn flip_refusals_leave_the_mesh_untouched() {
    // A boundary edge of the grid.
    assert!(matches!(
        refused(shapes::grid(2, 2), 0, 1, flip),
        Refusal::BoundaryEdge(_)
    ));
    // Every edge of a tetrahedron: the new edge exists already.
    for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let r = refused(shapes::tetrahedron(), a, b, flip);
        assert!(matches!(r, Refusal::WouldDuplicateEdge(..)), "{r}");
    }
    // Every edge of a cube: both endpoints have valence 3 and would be left with 2.
    for (a, b) in [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (5, 6), (2, 6)] {
        let r = refused(shapes::cube(), a, b, flip);
        assert!(matches!(r, Refusal::ValenceTooLow(_, 3)), "{a}-{b}: {r}");
    }
    // A polygon that already holds the vertex it would gain.
    let r = refused(flip_would_repeat_a_corner(), 0, 1, flip);
    assert!(matches!(r, Refusal::DegenerateFace(_)), "{r}");
    // A stale id.
    let (mut world, built) = build(&shapes::icosahedron());
    let e = edge(&world, &built, 0, 11);
    flip_edge(&mut world, e).unwrap();
    let before = snapshot(&world, built.mesh);
    let stale = EdgeId(bevy::prelude::Entity::from_raw_u32(900_000).unwrap());
    assert!(matches!(
        flip_edge(&mut world, stale),
        Err(Refusal::Stale(_))
    ));
    assert_eq!(snapshot(&world, built.mesh), before);
}

#[test]
fn flip_in_a_quad_grid_rotates_within_the_two_quads() {
    // 2×1 quads over 0 1 2 / 3 4 5: the shared edge 1-4 moves one step counter-clockwise in
    // both quads and becomes 2-3; each face keeps four sides.
    let soup = shapes::quad_grid(2, 1);
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 1, 4);
    flip_edge(&mut world, e).unwrap();
    let expected =
        PolygonSoup::from_faces(soup.positions.clone(), &[[0u32, 1, 2, 3], [3, 2, 5, 4]]);
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(mesh_stats(&world, built.mesh).face_sizes.get(&4), Some(&2));
}

// ---- split ---------------------------------------------------------------------------------

#[test]
fn split_the_diamond_interior_edge() {
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 2);
    let v = split_edge(&mut world, e, 0.5).unwrap();
    let m = MeshRef::new(&world);
    assert_eq!(m.position(v), Vec3::ZERO);
    let mut expected = soup.clone();
    expected.positions.push(Vec3::ZERO); // 4
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [[0, 1, 4], [4, 1, 2], [0, 4, 3], [4, 2, 3]] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (5, 8, 4, 1));
    assert_eq!(m.valence(v), 4);
}

// ---- bisect -------------------------------------------------------------------------------

#[test]
fn bisect_the_diamond_interior_edge_makes_two_quads() {
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 2);
    // A quarter of the way along the edge's halfedge, from 0 (0,-1) to 2 (0,1) or back.
    let h = MeshRef::new(&world).edge_halfedge(e);
    let from = MeshRef::new(&world).position(MeshRef::new(&world).from_vertex(h));
    let at = Vec3::new(0.0, from.y / 2.0, 0.0);
    let v = bisect_edge(&mut world, e, 0.25).unwrap();
    let m = MeshRef::new(&world);
    assert_eq!(m.position(v), at);
    let mut expected = soup.clone();
    expected.positions.push(at); // 4
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [[0, 1, 2, 4], [0, 4, 2, 3]] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    // One vertex and one edge more, no face more: χ unchanged.
    assert_eq!(counts(&world, built.mesh), (5, 6, 2, 1));
    assert_eq!(m.valence(v), 2);
}

#[test]
fn bisect_a_boundary_edge_adds_a_corner_to_its_face_and_loop() {
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    let v = bisect_edge(&mut world, e, 0.5).unwrap();
    let m = MeshRef::new(&world);
    assert!(m.is_boundary_vertex(v));
    assert!(m.is_boundary(m.vertex_halfedge(v)));
    let mut expected = soup.clone();
    expected.positions.push(Vec3::new(0.5, -0.5, 0.0));
    expected.indices.clear();
    expected.face_starts = vec![0];
    expected.push_face(&[0, 4, 1, 2]);
    expected.push_face(&[0, 2, 3]);
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (5, 6, 2, 1));
    assert_eq!(mesh_stats(&world, built.mesh).boundary_loops, 1);
}

#[test]
fn bisect_refuses_what_split_refuses_and_changes_nothing() {
    for t in [0.0, 1.0, f32::NAN] {
        let r = refused(shapes::diamond(), 0, 2, |w, e| {
            bisect_edge(w, e, t).map(|_| ())
        });
        assert!(matches!(r, Refusal::SplitParameter(_)), "{t}: {r}");
    }
    let mut soup = shapes::diamond();
    soup.positions[2] = soup.positions[0];
    let r = refused(soup, 0, 2, |w, e| bisect_edge(w, e, 0.5).map(|_| ()));
    assert!(matches!(r, Refusal::SplitAtEndpoint(_)), "{r}");
    // A stale edge: the diamond's edge after the diamond is gone.
    let (mut world, built) = build(&shapes::diamond());
    let e = edge(&world, &built, 0, 2);
    pappus::mesh::despawn_mesh(&mut world, built.mesh);
    assert_eq!(
        bisect_edge(&mut world, e, 0.5),
        Err(Refusal::Stale(pappus::mesh::ElementId::Edge(e)))
    );
}

#[test]
fn split_a_boundary_edge_splits_only_the_real_side() {
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    let v = split_edge(&mut world, e, 0.5).unwrap();
    let m = MeshRef::new(&world);
    assert!(m.is_boundary_vertex(v));
    assert_eq!(m.valence(v), 3);
    let mid = Vec3::new(0.5, -0.5, 0.0);
    let mut expected = soup.clone();
    expected.positions.push(mid);
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [[0, 4, 2], [4, 1, 2], [0, 2, 3]] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (5, 7, 3, 1));
}

#[test]
fn split_counts_on_closed_and_open_meshes() {
    for (soup, a, b, boundary) in [
        (shapes::icosphere(1), 0usize, 12usize, false),
        (shapes::tetrahedron(), 0, 1, false),
        (shapes::grid(3, 3), 0, 1, true),
        (shapes::grid(3, 3), 5, 6, false),
    ] {
        let (mut world, built) = build(&soup);
        let m = MeshRef::new(&world);
        let (va, vb) = (
            built.input_vertices[a].unwrap(),
            built.input_vertices[b].unwrap(),
        );
        let Some(h) = m.find_halfedge(va, vb) else {
            continue;
        };
        let e = m.edge(h);
        let (v, ed, f, chi) = counts(&world, built.mesh);
        split_edge(&mut world, e, 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        let expected = if boundary {
            (v + 1, ed + 2, f + 1, chi)
        } else {
            (v + 1, ed + 3, f + 2, chi)
        };
        assert_eq!(counts(&world, built.mesh), expected);
    }
}

#[test]
fn split_a_quad_side_cuts_a_triangle_off() {
    let soup = shapes::quad_grid(2, 1);
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 1, 4);
    split_edge(&mut world, e, 0.5).unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    // Each quad: a triangle plus a quad.
    assert_eq!(
        (s.face_sizes.get(&3), s.face_sizes.get(&4)),
        (Some(&2), Some(&2))
    );
    assert_eq!(s.euler_characteristic, 1);
}

#[test]
fn split_refuses_bad_parameters_and_stale_edges() {
    for t in [0.0, 1.0, -0.5, f32::NAN] {
        let r = refused(shapes::icosahedron(), 0, 11, |w, e| {
            split_edge(w, e, t).map(|_| ())
        });
        assert!(matches!(r, Refusal::SplitParameter(_)), "{t}: {r}");
    }
}

// ---- collapse ------------------------------------------------------------------------------

#[test]
fn collapse_an_interior_edge_of_a_fan() {
    // Closed fan of 6 around 0; collapse the spoke 0-1: the centre moves to the middle, the two
    // triangles on the spoke disappear.
    let soup = shapes::triangle_fan(6, true);
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    // The rim vertex 1 is on the boundary but the centre is not: no pinch.
    let r = collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let m = MeshRef::new(&world);
    let mid = (soup.positions[0] + soup.positions[1]) / 2.0;
    assert_eq!(m.position(r.kept), mid);
    assert!(m.try_vertex(r.removed).is_none());
    validate(&world, built.mesh).unwrap();
    // 7 vertices, 12 edges, 6 faces before; two triangles and three edges go.
    assert_eq!(counts(&world, built.mesh), (6, 9, 4, 1));
}

#[test]
fn collapse_counts_interior_and_boundary() {
    for (soup, a, b, boundary) in [
        (shapes::icosphere(1), 0usize, 12usize, false),
        (shapes::grid(4, 4), 6, 7, false),
        (shapes::grid(4, 4), 1, 2, true),
    ] {
        let (mut world, built) = build(&soup);
        let m = MeshRef::new(&world);
        let (va, vb) = (
            built.input_vertices[a].unwrap(),
            built.input_vertices[b].unwrap(),
        );
        let Some(h) = m.find_halfedge(va, vb) else {
            panic!("no edge {a}-{b}");
        };
        let e = m.edge(h);
        let (v, ed, f, chi) = counts(&world, built.mesh);
        collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
        validate(&world, built.mesh).unwrap();
        let expected = if boundary {
            (v - 1, ed - 2, f - 1, chi)
        } else {
            (v - 1, ed - 3, f - 2, chi)
        };
        assert_eq!(counts(&world, built.mesh), expected);
    }
}

#[test]
fn collapse_from_either_halfedge_keeps_the_mesh_valid() {
    use pappus::ops::local::{apply_collapse, plan_collapse_halfedge};
    // Interior and boundary sides, boundary halfedges as the one planned from, polygon sides.
    let cases = [
        ("fan", shapes::triangle_fan(5, false)),
        (
            "holes",
            shapes::triangulate_fans(&shapes::grid_with_holes(2)),
        ),
        ("quads", shapes::quad_grid(3, 3)),
        ("icosphere", shapes::icosphere(1)),
    ];
    for (name, soup) in cases {
        let halfedges = {
            let (world, built) = build(&soup);
            MeshMembers::collect(&world, built.mesh).halfedges.len()
        };
        let mut applied = 0;
        for i in 0..halfedges {
            let (mut world, built) = build(&soup);
            let h = MeshMembers::collect(&world, built.mesh).halfedges[i];
            let m = MeshRef::new(&world);
            let (kept, gone) = (m.from_vertex(h), m.to_vertex(h));
            let (v, e, f, chi) = counts(&world, built.mesh);
            let Ok(plan) = plan_collapse_halfedge(&world, h, CollapseOptions::default()) else {
                continue;
            };
            let result = apply_collapse(&mut world, plan);
            validate(&world, built.mesh).unwrap_or_else(|x| panic!("{name} halfedge {i}: {x}"));
            assert_eq!((result.kept, result.removed), (kept, gone), "{name} {i}");
            // Each triangle side takes a face and merges two edges; a polygon side loses a
            // corner; the boundary loses a side.
            let triangles = result.record.triangles_removed();
            assert_eq!(
                counts(&world, built.mesh),
                (v - 1, e - 1 - triangles, f - triangles, chi),
                "{name} halfedge {i}"
            );
            applied += 1;
        }
        assert!(applied > halfedges / 3, "{name}: {applied} of {halfedges}");
    }
}

#[test]
fn collapse_at_a_given_position() {
    let (mut world, built) = build(&shapes::icosphere(1));
    let e = edge(&world, &built, 0, 12);
    let target = Vec3::new(0.1, 0.9, 0.2);
    let r = collapse_edge(
        &mut world,
        e,
        CollapseOptions {
            position: Some(target),
            max_normal_change_deg: None,
        },
    )
    .unwrap();
    assert_eq!(MeshRef::new(&world).position(r.kept), target);
    validate(&world, built.mesh).unwrap();
}

#[test]
fn collapse_a_quad_side_leaves_triangles() {
    let soup = shapes::quad_grid(2, 2);
    let (mut world, built) = build(&soup);
    // Interior edge 1-4 (vertex 4 is the centre): both sides are quads; each becomes a triangle.
    let e = edge(&world, &built, 1, 4);
    let r = collapse_edge(&mut world, e, CollapseOptions::default());
    // 1 is on the boundary, 4 is interior: allowed.
    r.unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(
        (s.face_sizes.get(&3), s.face_sizes.get(&4)),
        (Some(&2), Some(&2))
    );
    assert_eq!((s.vertices, s.faces, s.euler_characteristic), (8, 4, 1));
}

#[test]
fn collapse_refusals_leave_the_mesh_untouched() {
    // Every edge of a tetrahedron (the edge part of the link condition).
    for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let r = refused(shapes::tetrahedron(), a, b, collapse);
        assert!(matches!(r, Refusal::TooSmall), "{r}");
    }
    // An interior edge joining two boundary vertices: the middle edge of a 2×1 grid, and the
    // diamond's diagonal.
    let r = refused(shapes::grid(2, 1), 1, 4, collapse);
    assert!(matches!(r, Refusal::BoundaryPinch), "{r}");
    let r = refused(shapes::diamond(), 0, 2, collapse);
    assert!(matches!(r, Refusal::BoundaryPinch), "{r}");
    // A single triangle: the merged edge would have no face on either side.
    let tri = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]);
    let r = refused(tri, 0, 1, collapse);
    assert!(matches!(r, Refusal::DanglingEdge(_)), "{r}");
    // A normal flip when asked to check.
    let r = refused(shapes::icosphere(1), 0, 12, |w, e| {
        collapse_edge(
            w,
            e,
            CollapseOptions {
                position: Some(Vec3::new(0.0, -5.0, 0.0)),
                max_normal_change_deg: Some(60.0),
            },
        )
        .map(|_| ())
    });
    assert!(matches!(r, Refusal::NormalFlip(_)), "{r}");
}

#[test]
fn link_condition_refuses_a_shared_neighbour() {
    // Collapse the icosahedron edge by edge until no collapse is legal: on the way, edges whose
    // endpoints share a neighbour other than their opposite vertices must be refused, and each
    // refusal must leave the mesh as it was.
    let (mut world, built) = build(&shapes::icosahedron());
    let mut refused_link = 0;
    for _ in 0..30 {
        let edges = MeshMembers::collect(&world, built.mesh).edges;
        let mut progressed = false;
        for e in edges {
            let before = snapshot(&world, built.mesh);
            match collapse_edge(&mut world, e, CollapseOptions::default()) {
                Ok(_) => {
                    validate(&world, built.mesh).unwrap();
                    progressed = true;
                    break;
                }
                Err(r) => {
                    if matches!(r, Refusal::LinkCondition(_)) {
                        refused_link += 1;
                    }
                    assert_eq!(snapshot(&world, built.mesh), before);
                }
            }
        }
        if !progressed {
            break;
        }
    }
    // Collapsing until nothing more is legal ends at a tetrahedron-like minimum, and on the way
    // the link condition refused something.
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(s.euler_characteristic, 2);
    assert!(s.vertices >= 4);
    assert!(refused_link > 0);
}

// ---- mixed meshes and grid corners -------------------------------------------------------------

/// A quad with a triangle on each of two sides: 0 1 2 3 the quad, 4 below, 5 right.
fn mixed() -> PolygonSoup {
    PolygonSoup::from_faces(
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.5, -0.8, 0.0),
            Vec3::new(1.8, 0.5, 0.0),
        ],
        &[vec![0u32, 1, 2, 3], vec![0, 4, 1], vec![1, 5, 2]],
    )
}

#[test]
fn operations_on_a_mixed_quad_and_triangle_mesh() {
    // Flip the quad-triangle edge 0-1: it turns one step counter-clockwise in both faces and
    // becomes 4-2; the quad stays a quad (0 4 2 3), the triangle a triangle (4 1 2).
    let soup = mixed();
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    flip_edge(&mut world, e).unwrap();
    let expected = PolygonSoup::from_faces(
        soup.positions.clone(),
        &[vec![0u32, 4, 2, 3], vec![4, 1, 2], vec![1, 5, 2]],
    );
    assert_same_mesh(&world, built.mesh, &expected);

    // Split 1-2 (quad | triangle): the quad gives a triangle and a quad, the triangle two.
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 1, 2);
    let v = split_edge(&mut world, e, 0.5).unwrap();
    let mut expected = soup.clone();
    expected.positions.push(Vec3::new(1.0, 0.5, 0.0)); // 6
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [
        vec![0u32, 1, 6, 3],
        vec![6, 2, 3],
        vec![0, 4, 1],
        vec![1, 5, 6],
        vec![6, 5, 2],
    ] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(MeshRef::new(&world).valence(v), 4);

    // Collapse: 1-2 is interior with both ends on the boundary (refused); the boundary edge 1-5
    // collapses, its triangle goes and the quad keeps four sides.
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 1, 2);
    let r = collapse_edge(&mut world, e, CollapseOptions::default());
    assert!(matches!(r, Err(Refusal::BoundaryPinch)), "{r:?}");
    let e = edge(&world, &built, 1, 5);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let mut expected = soup.clone();
    let k = (soup.positions[1] + soup.positions[5]) / 2.0;
    expected.positions = vec![
        soup.positions[0],
        k,
        soup.positions[2],
        soup.positions[3],
        soup.positions[4],
    ];
    expected.indices.clear();
    expected.face_starts = vec![0];
    for f in [vec![0u32, 1, 2, 3], vec![0, 4, 1]] {
        expected.push_face(&f);
    }
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (5, 6, 2, 1));
}

#[test]
fn grid_corner_edges() {
    // The corner (3, 0) of a 3×3 triangle grid (vertex 3) has two boundary edges, to 2 and to
    // 7, and one triangle 2-3-7. Its edges cannot be flipped; the diagonal 2-7 joins two
    // boundary vertices through the interior (refused); the boundary edge 3-7 collapses.
    let soup = shapes::grid(3, 3);
    let r = refused(soup.clone(), 3, 2, flip);
    assert!(matches!(r, Refusal::BoundaryEdge(_)), "{r}");
    let r = refused(soup.clone(), 2, 7, collapse);
    assert!(matches!(r, Refusal::BoundaryPinch), "{r}");
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 3, 7);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    validate(&world, built.mesh).unwrap();
    assert_eq!(counts(&world, built.mesh), (15, 31, 17, 1));
    // The corner (0, 0) has the diagonal: its boundary edge 0-1 collapses too.
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    validate(&world, built.mesh).unwrap();
    assert_eq!(counts(&world, built.mesh), (15, 31, 17, 1));
}

// ---- the polygon toolkit: dissolve an edge, split a face ---------------------------------------

#[test]
fn dissolve_and_split_face_are_inverse_on_a_quad_grid() {
    use pappus::ops::local::{dissolve_edge, split_face};
    // 2×1 quads over 0 1 2 / 3 4 5: dissolving 1-4 gives one hexagon.
    let soup = shapes::quad_grid(2, 1);
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 1, 4);
    let f = dissolve_edge(&mut world, e).unwrap();
    let hexagon = PolygonSoup::from_faces(soup.positions.clone(), &[[0u32, 1, 2, 5, 4, 3]]);
    assert_same_mesh(&world, built.mesh, &hexagon);
    assert_eq!(counts(&world, built.mesh), (6, 6, 1, 1));
    // Splitting the hexagon between 1 and 4 gives the two quads back.
    let (v1, v4) = (
        built.input_vertices[1].unwrap(),
        built.input_vertices[4].unwrap(),
    );
    split_face(&mut world, f, v1, v4).unwrap();
    assert_same_mesh(&world, built.mesh, &soup);
    // On a 2×2 grid, a quad split across its diagonal gives two triangles.
    let soup = shapes::quad_grid(2, 2);
    let (mut world, built) = build(&soup);
    let m = MeshRef::new(&world);
    let (v0, v4) = (
        built.input_vertices[0].unwrap(),
        built.input_vertices[4].unwrap(),
    );
    let quad = m.vertex_faces(v0).next().unwrap();
    split_face(&mut world, quad, v0, v4).unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(
        (s.face_sizes.get(&3), s.face_sizes.get(&4)),
        (Some(&2), Some(&3))
    );
}

#[test]
fn dissolve_and_split_face_refusals_leave_the_mesh_untouched() {
    use pappus::ops::local::{dissolve_edge, split_face};
    let r = refused(shapes::quad_grid(2, 1), 0, 1, |w, e| {
        dissolve_edge(w, e).map(|_| ())
    });
    assert!(matches!(r, Refusal::BoundaryEdge(_)), "{r}");
    // The two triangles of a quad-split share the diagonal only: fine. Two faces that share a
    // corner besides the edge's ends: a strip of two quads folded so that they touch.
    let soup = shapes::quad_grid(2, 1);
    let (mut world, built) = build(&soup);
    let m = MeshRef::new(&world);
    let (v0, v1, v4) = (
        built.input_vertices[0].unwrap(),
        built.input_vertices[1].unwrap(),
        built.input_vertices[4].unwrap(),
    );
    let quad = m.vertex_faces(v0).next().unwrap();
    let before = snapshot(&world, built.mesh);
    // Neighbouring corners: their edge exists.
    assert!(matches!(
        split_face(&mut world, quad, v0, v1),
        Err(Refusal::WouldDuplicateEdge(..))
    ));
    // A vertex that is not a corner of the face.
    let v2 = built.input_vertices[2].unwrap();
    assert!(matches!(
        split_face(&mut world, quad, v0, v2),
        Err(Refusal::NotACorner(..))
    ));
    // Corners already joined elsewhere: 1-4 is the shared edge, so splitting the quad 0 1 4 3
    // between 1 and 4 would duplicate it.
    assert!(matches!(
        split_face(&mut world, quad, v1, v4),
        Err(Refusal::WouldDuplicateEdge(..))
    ));
    assert_eq!(snapshot(&world, built.mesh), before);
}

// ---- vertex split: the exact inverse of collapse -------------------------------------------

#[test]
fn split_undoes_every_collapse_exactly() {
    use pappus::ops::local::vertex_split;
    let cases = [
        ("icosphere", shapes::icosphere(1)),
        ("grid", shapes::grid(4, 4)),
        ("torus", shapes::triangulate_fans(&shapes::torus(6, 5))),
        (
            "holes",
            shapes::triangulate_fans(&shapes::grid_with_holes(2)),
        ),
        ("fan", shapes::triangle_fan(5, false)),
    ];
    for (name, soup) in cases {
        let edge_count = build(&soup).1;
        let edges = MeshMembers::collect(&build(&soup).0, edge_count.mesh)
            .edges
            .len();
        let (mut undone, mut boundary) = (0, 0);
        for i in 0..edges {
            let (mut world, built) = build(&soup);
            let original = canonical(&to_soup(&world, built.mesh));
            let before = counts(&world, built.mesh);
            let e = MeshMembers::collect(&world, built.mesh).edges[i];
            let on_boundary = MeshRef::new(&world).is_boundary_edge(e);
            let Ok(result) = collapse_edge(&mut world, e, CollapseOptions::default()) else {
                continue;
            };
            vertex_split(&mut world, &result.record)
                .unwrap_or_else(|r| panic!("{name} edge {i}: {r}"));
            validate(&world, built.mesh).unwrap_or_else(|x| panic!("{name} edge {i}: {x}"));
            assert_eq!(
                canonical(&to_soup(&world, built.mesh)),
                original,
                "{name} edge {i}"
            );
            assert_eq!(counts(&world, built.mesh), before);
            undone += 1;
            boundary += usize::from(on_boundary);
        }
        assert!(
            undone > edges / 3,
            "{name}: only {undone} of {edges} edges collapsed"
        );
        if name != "icosphere" && name != "torus" {
            assert!(boundary > 0, "{name}: no boundary edge was tried");
        }
    }
}

#[test]
fn split_refuses_a_stale_or_polygon_record() {
    use pappus::ops::local::vertex_split;
    let (mut world, built) = build(&shapes::quad_grid(2, 2));
    let e = edge(&world, &built, 1, 4);
    let result = collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    assert!(!result.record.invertible);
    let before = snapshot(&world, built.mesh);
    assert!(matches!(
        vertex_split(&mut world, &result.record),
        Err(Refusal::NotInvertible)
    ));
    assert_eq!(snapshot(&world, built.mesh), before);
    let (mut world, built) = build(&shapes::icosphere(1));
    let e = edge(&world, &built, 0, 12);
    let mut record = collapse_edge(&mut world, e, CollapseOptions::default())
        .unwrap()
        .record;
    record.kept = VertexId(bevy::prelude::Entity::from_raw_u32(999_999).unwrap());
    let before = snapshot(&world, built.mesh);
    assert!(matches!(
        vertex_split(&mut world, &record),
        Err(Refusal::Stale(_))
    ));
    assert_eq!(snapshot(&world, built.mesh), before);
}

// ---- fixtures for the rarer refusals -----------------------------------------------------------

/// Positions on a circle, one per vertex: the refusal fixtures below are about connectivity.
fn ring(n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            Vec3::new(a.cos(), a.sin(), 0.1 * i as f32)
        })
        .collect()
}

/// A hexagon `a b c y d z` (0 1 2 3 4 5), a quad `b a d x` (x = 6) and a triangle `d y x`: an
/// annulus. Flipping `a b` would give the hexagon the corner `d` a second time.
fn flip_would_repeat_a_corner() -> PolygonSoup {
    PolygonSoup::from_faces(
        ring(7),
        &[vec![0u32, 1, 2, 3, 4, 5], vec![1, 0, 4, 6], vec![4, 3, 6]],
    )
}

/// A hexagon `a x y b z w` holding both ends of the edge `a b` (a = 0, b = 1), which lies
/// between the triangles `a b c` and `b a d`; the rest (c = 2, d = 3, x = 4, y = 5, z = 6,
/// w = 7, s = 8) makes a disc in which `b` is interior. Collapsing `a b` would make the hexagon
/// visit the merged vertex twice.
fn collapse_would_repeat_a_corner() -> PolygonSoup {
    PolygonSoup::from_faces(
        ring(9),
        &[
            vec![0u32, 4, 5, 1, 6, 7],
            vec![0, 1, 2],
            vec![1, 0, 3],
            vec![3, 0, 7],
            vec![2, 1, 5],
            vec![1, 3, 8],
            vec![3, 7, 8],
            vec![7, 6, 8],
            vec![6, 1, 8],
        ],
    )
}

/// A sphere: triangles `a b c`, `b a d` (a = 0, b = 1, c = 2, d = 3), quads `d a c y` and
/// `c b d z` (y = 4, z = 5) and triangles `y c z`, `y z d`. Collapsing `a b` passes the link
/// condition but would leave the merged vertex with two edges, between the two quads.
fn collapse_would_leave_valence_two() -> PolygonSoup {
    PolygonSoup::from_faces(
        ring(6),
        &[
            vec![0u32, 1, 2],
            vec![1, 0, 3],
            vec![3, 0, 2, 4],
            vec![2, 1, 3, 5],
            vec![4, 2, 5],
            vec![4, 5, 3],
        ],
    )
}

/// The cube with its first face `0 3 2 1` split along `0–2`: collapsing the diagonal would
/// leave the cube corners 1 and 3 with two edges each.
fn cube_with_a_diagonal() -> PolygonSoup {
    let cube = shapes::cube();
    let mut faces: Vec<Vec<u32>> = vec![vec![0, 3, 2], vec![0, 2, 1]];
    faces.extend(cube.faces().skip(1).map(<[u32]>::to_vec));
    PolygonSoup::from_faces(cube.positions.clone(), &faces)
}

#[test]
fn the_fixtures_are_valid_meshes() {
    for (soup, chi) in [
        (flip_would_repeat_a_corner(), 0),
        (collapse_would_repeat_a_corner(), 1),
        (collapse_would_leave_valence_two(), 2),
        (cube_with_a_diagonal(), 2),
        (mixed(), 1),
    ] {
        let (world, built) = build(&soup);
        assert_eq!(counts(&world, built.mesh).3, chi);
    }
}

#[test]
fn collapse_refuses_each_degenerate_result() {
    // Another face holds both endpoints.
    let r = refused(collapse_would_repeat_a_corner(), 0, 1, collapse);
    assert!(matches!(r, Refusal::DegenerateFace(_)), "{r}");
    // The merged vertex would keep two edges.
    let r = refused(collapse_would_leave_valence_two(), 0, 1, collapse);
    assert!(matches!(r, Refusal::ValenceTooLow(_, 3)), "{r}");
    // An opposite vertex (a cube corner) would keep two edges.
    let soup = cube_with_a_diagonal();
    let r = refused(soup.clone(), 0, 2, collapse);
    let (world, built) = build(&soup);
    let corners = [built.input_vertices[1], built.input_vertices[3]].map(Option::unwrap);
    assert!(
        matches!(r, Refusal::ValenceTooLow(pappus::mesh::ElementId::Vertex(v), 3) if corners.contains(&v)),
        "{r}"
    );
    drop(world);
    // The link condition, vertex part: a triangle split in three around a centre (0); the rim
    // edge 1-2 has the centre opposite, but 3 is a neighbour of both ends as well.
    let soup = shapes::triangle_fan(3, true);
    let r = refused(soup.clone(), 1, 2, collapse);
    let (_, built) = build(&soup);
    assert_eq!(
        r,
        Refusal::LinkCondition(pappus::mesh::ElementId::Vertex(
            built.input_vertices[3].unwrap()
        ))
    );
    // A lone triangle, collapsed from its boundary side: the boundary loop would become a 2-gon.
    let tri = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]);
    let (world, built) = build(&tri);
    let e = edge(&world, &built, 0, 1);
    let m = MeshRef::new(&world);
    let outside = m.twin(m.edge_halfedge(e));
    assert!(m.is_boundary(outside));
    let r = pappus::ops::local::plan_collapse_halfedge(&world, outside, CollapseOptions::default());
    assert!(matches!(r, Err(Refusal::DegenerateFace(_))), "{r:?}");
    // A position that is not finite.
    let r = refused(shapes::icosphere(1), 0, 12, |w, e| {
        collapse_edge(
            w,
            e,
            CollapseOptions {
                position: Some(Vec3::NAN),
                max_normal_change_deg: None,
            },
        )
        .map(|_| ())
    });
    assert!(matches!(r, Refusal::NotFinite(_)), "{r}");
}

#[test]
fn collapse_checks_the_normal_of_a_surviving_polygon_side() {
    // One quad 0 1 3 2 (quad_grid(1, 1)): collapsing the bottom edge 0-1 leaves a triangle.
    let soup = shapes::quad_grid(1, 1);
    let above = CollapseOptions {
        position: Some(Vec3::new(0.5, 2.0, 0.0)),
        max_normal_change_deg: Some(90.0),
    };
    // Moved above the top edge, the triangle would face the other way.
    let r = refused(soup.clone(), 0, 1, |w, e| {
        collapse_edge(w, e, above).map(|_| ())
    });
    assert!(matches!(r, Refusal::NormalFlip(_)), "{r}");
    // At the midpoint it keeps its normal.
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    let options = CollapseOptions {
        position: None,
        max_normal_change_deg: Some(1.0),
    };
    collapse_edge(&mut world, e, options).unwrap();
    let mut expected = soup.clone();
    expected.positions.push(Vec3::new(0.5, 0.0, 0.0)); // 4
    expected.indices.clear();
    expected.face_starts = vec![0];
    expected.push_face(&[4, 3, 2]);
    assert_same_mesh(&world, built.mesh, &expected);
    assert_eq!(counts(&world, built.mesh), (3, 3, 1, 1));
}

#[test]
fn stale_ids_are_refused_by_every_operation() {
    // A genuinely stale id: an edge a collapse despawned.
    let (mut world, built) = build(&shapes::icosphere(1));
    let before_edges = MeshMembers::collect(&world, built.mesh).edges;
    let e = edge(&world, &built, 0, 12);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let after_edges = MeshMembers::collect(&world, built.mesh).edges;
    let gone: Vec<EdgeId> = before_edges
        .into_iter()
        .filter(|e| !after_edges.contains(e))
        .collect();
    assert_eq!(gone.len(), 3);
    let before = snapshot(&world, built.mesh);
    for stale in gone {
        assert!(matches!(
            flip_edge(&mut world, stale),
            Err(Refusal::Stale(_))
        ));
        assert!(matches!(
            split_edge(&mut world, stale, 0.5),
            Err(Refusal::Stale(_))
        ));
        assert!(matches!(
            collapse_edge(&mut world, stale, CollapseOptions::default()),
            Err(Refusal::Stale(_))
        ));
        assert_eq!(snapshot(&world, built.mesh), before);
    }
}

#[test]
fn split_refuses_a_point_on_an_endpoint() {
    // t > 0 but so small that the point rounds onto the endpoint.
    let tri = PolygonSoup::from_faces(
        vec![Vec3::ONE, Vec3::splat(2.0), Vec3::new(1.0, 2.0, 3.0)],
        &[[0u32, 1, 2]],
    );
    let r = refused(tri, 0, 1, |w, e| split_edge(w, e, 1e-12).map(|_| ()));
    assert!(matches!(r, Refusal::SplitAtEndpoint(_)), "{r}");
    // An edge of length zero.
    let mut soup = shapes::diamond();
    soup.positions[2] = soup.positions[0];
    let r = refused(soup, 0, 2, |w, e| split_edge(w, e, 0.5).map(|_| ()));
    assert!(matches!(r, Refusal::SplitAtEndpoint(_)), "{r}");
}

/// `soup` with faces replaced.
fn with_faces(soup: &PolygonSoup, extra: &[Vec3], faces: &[&[u32]]) -> PolygonSoup {
    let mut positions = soup.positions.clone();
    positions.extend_from_slice(extra);
    PolygonSoup::from_faces(positions, faces)
}

/// Checks what every successful operation must leave: a valid mesh whose counts moved by
/// `delta` (V, E, F) and whose χ did not change.
fn assert_counts_moved(
    world: &World,
    mesh: MeshId,
    before: (usize, usize, usize, i64),
    delta: (i64, i64, i64),
) {
    validate(world, mesh).unwrap();
    let after = counts(world, mesh);
    let moved = |a: usize, b: usize| a as i64 - b as i64;
    assert_eq!(
        (
            moved(after.0, before.0),
            moved(after.1, before.1),
            moved(after.2, before.2),
            after.3
        ),
        (delta.0, delta.1, delta.2, before.3)
    );
}

#[test]
fn flip_an_interior_edge_of_an_open_grid() {
    // grid(2, 2): vertex (i, j) is 3j + i; the cell 0 1 4 3 is split along 0-4 and the cell
    // 1 2 5 4 along 1-5. The edge 1-4 lies between the triangles 0 1 4 and 1 5 4: it becomes
    // 0-5.
    let soup = shapes::grid(2, 2);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 1, 4);
    flip_edge(&mut world, e).unwrap();
    let expected = with_faces(
        &soup,
        &[],
        &[
            &[0, 1, 5],
            &[0, 5, 4],
            &[0, 4, 3],
            &[1, 2, 5],
            &[3, 4, 7],
            &[3, 7, 6],
            &[4, 5, 8],
            &[4, 8, 7],
        ],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (0, 0, 0));
}

#[test]
fn split_a_spoke_of_a_fan() {
    // Open fan of 4 around 0 (rim 1..5): the spoke 0-2 lies between 0 1 2 and 0 2 3.
    let soup = shapes::triangle_fan(4, false);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 0, 2);
    let v = pappus::ops::local::split_edge_midpoint(&mut world, e).unwrap();
    let mid = MeshRef::new(&world).position(v);
    assert_eq!(mid, (soup.positions[0] + soup.positions[2]) / 2.0);
    let expected = with_faces(
        &soup,
        &[mid],
        &[
            &[0, 1, 6],
            &[6, 1, 2],
            &[0, 6, 3],
            &[6, 2, 3],
            &[0, 3, 4],
            &[0, 4, 5],
        ],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (1, 3, 2));
}

#[test]
fn split_and_collapse_at_a_grid_corner() {
    // grid(3, 3): the corner 3 has the single triangle 2 3 7; its boundary edge 3-7 splits
    // into two triangles.
    let soup = shapes::grid(3, 3);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 3, 7);
    let v = split_edge(&mut world, e, 0.5).unwrap();
    assert!(MeshRef::new(&world).is_boundary_vertex(v));
    assert_eq!(MeshRef::new(&world).valence(v), 3);
    assert_counts_moved(&world, built.mesh, before, (1, 2, 1));
    // Collapsing the new corner edge back (the new vertex into the corner) restores the grid's
    // connectivity.
    let corner = built.input_vertices[3].unwrap();
    let m = MeshRef::new(&world);
    let h = m.find_halfedge(corner, v).unwrap();
    let plan = pappus::ops::local::plan_collapse_halfedge(
        &world,
        h,
        CollapseOptions {
            position: Some(soup.positions[3]),
            max_normal_change_deg: Some(1.0),
        },
    )
    .unwrap();
    pappus::ops::local::apply_collapse(&mut world, plan);
    assert_same_mesh(&world, built.mesh, &soup);
}

#[test]
fn split_a_quad_grid_edge_exactly() {
    // quad_grid(2, 1): 0 1 2 / 3 4 5 at x = 0, 0.5, 1. The shared edge 1-4: each quad cuts off
    // the triangle ahead of the new vertex 6 = (0.5, 0.5).
    let soup = shapes::quad_grid(2, 1);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 1, 4);
    split_edge(&mut world, e, 0.5).unwrap();
    let expected = with_faces(
        &soup,
        &[Vec3::new(0.5, 0.5, 0.0)],
        &[&[0, 1, 6, 3], &[6, 4, 3], &[1, 2, 6], &[6, 2, 5, 4]],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (1, 3, 2));
    // A boundary edge of a quad: the quad gives a triangle and a quad, the loop gains a corner.
    let (mut world, built) = build(&soup);
    let e = edge(&world, &built, 0, 1);
    split_edge(&mut world, e, 0.5).unwrap();
    let expected = with_faces(
        &soup,
        &[Vec3::new(0.25, 0.0, 0.0)],
        &[&[0, 6, 4, 3], &[6, 1, 4], &[1, 2, 5, 4]],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (1, 2, 1));
}

#[test]
fn collapse_exact_results_on_the_diamond_fan_and_quad_grid() {
    // The diamond's boundary edge 0-1: the triangle 0 1 2 goes, 0 2 3 stays with 0 moved.
    let soup = shapes::diamond();
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 0, 1);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let mid = (soup.positions[0] + soup.positions[1]) / 2.0;
    let expected = with_faces(&soup, &[mid], &[&[4, 2, 3]]);
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (-1, -2, -1));

    // A spoke of the closed fan of 6: its two triangles go.
    let soup = shapes::triangle_fan(6, true);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 0, 1);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let mid = (soup.positions[0] + soup.positions[1]) / 2.0;
    let expected = with_faces(
        &soup,
        &[mid],
        &[&[7, 2, 3], &[7, 3, 4], &[7, 4, 5], &[7, 5, 6]],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (-1, -3, -2));

    // quad_grid(2, 2), interior spoke 1-4 (1 on the boundary, 4 the centre): both quads lose a
    // corner and become triangles; nothing else changes.
    let soup = shapes::quad_grid(2, 2);
    let (mut world, built) = build(&soup);
    let before = counts(&world, built.mesh);
    let e = edge(&world, &built, 1, 4);
    collapse_edge(&mut world, e, CollapseOptions::default()).unwrap();
    let mid = (soup.positions[1] + soup.positions[4]) / 2.0;
    let expected = with_faces(
        &soup,
        &[mid],
        &[&[0, 9, 3], &[9, 2, 5], &[3, 9, 7, 6], &[9, 5, 8, 7]],
    );
    assert_same_mesh(&world, built.mesh, &expected);
    assert_counts_moved(&world, built.mesh, before, (-1, -1, 0));
}

#[test]
fn every_edge_of_small_shapes_either_applies_cleanly_or_changes_nothing() {
    // Each op on each edge of each shape, from a fresh mesh: a refusal leaves every component
    // as it was; a success validates with the expected count changes.
    let shapes_list = [
        shapes::diamond(),
        shapes::triangle_fan(5, true),
        shapes::triangle_fan(5, false),
        shapes::tetrahedron(),
        shapes::cube(),
        shapes::icosahedron(),
        shapes::grid(2, 2),
        shapes::quad_grid(2, 2),
        mixed(),
        cube_with_a_diagonal(),
        collapse_would_leave_valence_two(),
    ];
    let (mut flips, mut splits, mut collapses) = (0, 0, 0);
    for soup in shapes_list {
        let edges = {
            let (world, built) = build(&soup);
            MeshMembers::collect(&world, built.mesh).edges.len()
        };
        for i in 0..edges {
            for op in 0..3 {
                let (mut world, built) = build(&soup);
                let mesh = built.mesh;
                let e = MeshMembers::collect(&world, mesh).edges[i];
                let m = MeshRef::new(&world);
                let h = m.edge_halfedge(e);
                let triangles = [h, m.twin(h)]
                    .iter()
                    .filter(|&&x| m.face(x).is_some_and(|f| m.face_degree(f) == 3))
                    .count() as i64;
                let polygons_cut = [h, m.twin(h)]
                    .iter()
                    .filter(|&&x| m.face(x).is_some())
                    .count() as i64;
                let before = counts(&world, mesh);
                let snap = snapshot(&world, mesh);
                let (result, delta) = match op {
                    0 => (flip_edge(&mut world, e).map(|_| ()), (0, 0, 0)),
                    1 => (
                        split_edge(&mut world, e, 0.5).map(|_| ()),
                        (1, 1 + polygons_cut, polygons_cut),
                    ),
                    _ => (collapse(&mut world, e), (-1, -1 - triangles, -triangles)),
                };
                match result {
                    Ok(()) => {
                        assert_counts_moved(&world, mesh, before, delta);
                        *[&mut flips, &mut splits, &mut collapses][op] += 1;
                    }
                    Err(_) => assert_eq!(snapshot(&world, mesh), snap),
                }
            }
        }
    }
    assert!(
        flips > 20 && splits > 100 && collapses > 30,
        "{flips} {splits} {collapses}"
    );
}
