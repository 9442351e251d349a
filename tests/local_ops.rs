//! Flip, split and collapse: exact expected meshes (up to relabeling), counts, χ, validity, and
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
use pappus::ops::local::{CollapseOptions, collapse_edge, flip_edge, split_edge};

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
    // Every edge of a tetrahedron: the new edge exists already (or a valence-3 endpoint).
    for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let r = refused(shapes::tetrahedron(), a, b, flip);
        assert!(
            matches!(
                r,
                Refusal::WouldDuplicateEdge(..) | Refusal::ValenceTooLow(..)
            ),
            "{r}"
        );
    }
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
        assert!(matches!(r, Refusal::Unsuitable(_)), "{t}: {r}");
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
    // Every edge of a tetrahedron.
    for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let r = refused(shapes::tetrahedron(), a, b, collapse);
        assert!(
            matches!(
                r,
                Refusal::TooSmall | Refusal::LinkCondition(_) | Refusal::ValenceTooLow(..)
            ),
            "{r}"
        );
    }
    // An interior edge joining two boundary vertices: the middle edge of a 2×1 grid, and the
    // diamond's diagonal.
    let r = refused(shapes::grid(2, 1), 1, 4, collapse);
    assert!(matches!(r, Refusal::BoundaryPinch), "{r}");
    let r = refused(shapes::diamond(), 0, 2, collapse);
    assert!(matches!(r, Refusal::BoundaryPinch), "{r}");
    // A single triangle: its boundary loop would close into a 2-gon.
    let tri = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]);
    let r = refused(tri, 0, 1, collapse);
    assert!(
        matches!(r, Refusal::DegenerateFace(_) | Refusal::DanglingEdge(_)),
        "{r}"
    );
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
        Err(Refusal::Unsuitable(_))
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
        Err(Refusal::Unsuitable(_))
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
