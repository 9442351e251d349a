//! The foundation: every procedural shape builds and validates with exact counts, χ and genus;
//! repairs are counted; validate catches each broken invariant.

mod common;

use bevy::math::Vec3;
use bevy::prelude::World;
use common::build;
use pappus::mesh::{
    Halfedge, MeshRef, PolygonSoup, Position, Rule, Vertex, mesh_stats, shapes, to_soup, validate,
};

struct Expect {
    v: usize,
    e: usize,
    f: usize,
    chi: i64,
    genus: i64,
    loops: usize,
    components: usize,
}

fn check(soup: PolygonSoup, x: Expect) {
    let (world, built) = build(&soup);
    assert!(built.report.is_clean(), "{}", built.report);
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(
        (s.vertices, s.edges, s.faces, s.halfedges),
        (x.v, x.e, x.f, 2 * x.e)
    );
    assert_eq!(s.euler_characteristic, x.chi);
    assert_eq!(s.genus, x.genus);
    assert_eq!(s.boundary_loops, x.loops);
    assert_eq!(s.components, x.components);
    assert_eq!(s.closed, x.loops == 0);
}

#[test]
fn tetrahedron_is_a_sphere() {
    check(
        shapes::tetrahedron(),
        Expect {
            v: 4,
            e: 6,
            f: 4,
            chi: 2,
            genus: 0,
            loops: 0,
            components: 1,
        },
    );
}

#[test]
fn cube_is_a_sphere_of_quads() {
    check(
        shapes::cube(),
        Expect {
            v: 8,
            e: 12,
            f: 6,
            chi: 2,
            genus: 0,
            loops: 0,
            components: 1,
        },
    );
    let (world, built) = build(&shapes::cube());
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(s.face_sizes.get(&4), Some(&6));
    assert!((s.min_angle_deg - 90.0).abs() < 1e-4);
    assert!((s.bbox_diag - 12f64.sqrt()).abs() < 1e-5);
}

#[test]
fn icospheres_have_exact_counts() {
    for n in 0..4u32 {
        let p = 4usize.pow(n);
        check(
            shapes::icosphere(n),
            Expect {
                v: 10 * p + 2,
                e: 30 * p,
                f: 20 * p,
                chi: 2,
                genus: 0,
                loops: 0,
                components: 1,
            },
        );
    }
}

#[test]
fn torus_has_genus_one() {
    check(
        shapes::torus(12, 8),
        Expect {
            v: 96,
            e: 192,
            f: 96,
            chi: 0,
            genus: 1,
            loops: 0,
            components: 1,
        },
    );
}

#[test]
fn double_torus_has_genus_two() {
    let (world, built) = build(&shapes::slab_with_holes(2));
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(s.euler_characteristic, -2);
    assert_eq!(s.genus, 2);
    assert!(s.closed);
    let (world, built) = build(&shapes::slab_with_holes(3));
    assert_eq!(mesh_stats(&world, built.mesh).genus, 3);
}

#[test]
fn open_grid_is_a_disc() {
    check(
        shapes::grid(4, 3),
        Expect {
            v: 20,
            e: 4 * 4 + 5 * 3 + 12,
            f: 24,
            chi: 1,
            genus: 0,
            loops: 1,
            components: 1,
        },
    );
    let (world, built) = build(&shapes::grid_with_holes(2));
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(
        (s.euler_characteristic, s.boundary_loops, s.genus),
        (-1, 3, 0)
    );
}

#[test]
fn every_named_shape_builds_and_validates() {
    for name in shapes::SHAPE_NAMES {
        let soup = shapes::by_name(name).unwrap();
        let (world, built) = build(&soup);
        assert!(built.report.is_clean(), "{name}: {}", built.report);
        assert_eq!(
            mesh_stats(&world, built.mesh).faces,
            soup.face_count(),
            "{name}"
        );
    }
}

#[test]
fn to_soup_gives_back_the_input() {
    for soup in [shapes::cube(), shapes::icosphere(2), shapes::grid(3, 5)] {
        let (world, built) = build(&soup);
        assert_eq!(to_soup(&world, built.mesh), soup);
    }
}

#[test]
fn two_meshes_share_a_world_without_mixing() {
    let mut world = World::new();
    let info = pappus::mesh::MeshInfo::default;
    let a = pappus::mesh::build_mesh(&mut world, &shapes::cube(), info()).unwrap();
    let b = pappus::mesh::build_mesh(&mut world, &shapes::torus(6, 4), info()).unwrap();
    validate(&world, a.mesh).unwrap();
    validate(&world, b.mesh).unwrap();
    assert_eq!(mesh_stats(&world, a.mesh).faces, 6);
    assert_eq!(mesh_stats(&world, b.mesh).faces, 24);
    let removed = pappus::mesh::despawn_mesh(&mut world, a.mesh);
    assert_eq!(removed, 8 + 24 + 12 + 6 + 1);
    validate(&world, b.mesh).unwrap();
}

#[test]
fn circulators_walk_the_one_ring() {
    let (world, built) = build(&shapes::icosahedron());
    let m = MeshRef::new(&world);
    let v = built.input_vertices[0].unwrap();
    assert_eq!(m.valence(v), 5);
    assert_eq!(m.vertex_faces(v).count(), 5);
    for n in m.vertex_neighbors(v) {
        assert!(m.find_halfedge(v, n).is_some());
        assert_eq!(m.from_vertex(m.find_halfedge(v, n).unwrap()), v);
    }
    // The grid's corner (0,0) has two boundary edges and the rising diagonal: 3 edges, 2 faces.
    let (world, built) = build(&shapes::grid(2, 2));
    let m = MeshRef::new(&world);
    let corner = built.input_vertices[0].unwrap();
    assert!(m.is_boundary_vertex(corner));
    assert_eq!(m.valence(corner), 3);
    assert_eq!(m.vertex_faces(corner).count(), 2);
    let centre = built.input_vertices[4].unwrap();
    assert!(!m.is_boundary_vertex(centre));
    assert_eq!(m.valence(centre), 6);
}

// ---- repairs, on small hand-made soups ----------------------------------------------------

fn soup(n: usize, faces: &[&[u32]]) -> PolygonSoup {
    let positions = (0..n)
        .map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, (i * 7 % 5) as f32))
        .collect();
    PolygonSoup::from_faces(positions, faces)
}

#[test]
fn bow_tie_becomes_two_valid_components() {
    let (world, built) = build(&soup(5, &[&[0, 1, 2], &[0, 3, 4]]));
    assert_eq!(built.report.non_manifold_vertices, 1);
    let s = mesh_stats(&world, built.mesh);
    assert_eq!((s.vertices, s.components, s.boundary_loops), (6, 2, 2));
}

#[test]
fn a_keyhole_polygon_becomes_a_ring_of_triangles_around_its_hole() {
    // A 4 × 4 square with a 2 × 2 hole, written as one polygon: the outline, a bridge to the
    // hole, the hole backwards, the bridge back; beside it a triangle with a corner written
    // twice, and a polygon on a line, which cannot be cut.
    let mut positions: Vec<Vec3> = [
        (0, 0),
        (4, 0),
        (4, 4),
        (0, 4),
        (1, 1),
        (3, 1),
        (3, 3),
        (1, 3),
    ]
    .map(|(x, y)| Vec3::new(x as f32, y as f32, 0.0))
    .to_vec();
    positions.extend([
        Vec3::new(9.0, 0.0, 0.0),
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(9.0, 1.0, 0.0),
    ]);
    positions.extend([
        Vec3::new(20.0, 0.0, 0.0),
        Vec3::new(21.0, 0.0, 0.0),
        Vec3::new(22.0, 0.0, 0.0),
    ]);
    let faces: &[&[u32]] = &[
        &[0, 1, 2, 3, 0, 4, 7, 6, 5, 4],
        &[8, 9, 9, 10],
        &[11, 12, 13, 12],
    ];
    let (world, built) = build(&PolygonSoup::from_faces(positions, faces));
    let r = &built.report;
    assert_eq!((r.untangled_faces, r.repeated_vertex_faces), (2, 1), "{r}");
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    // The ring: 8 vertices, 8 triangles, 16 edges, χ = 0, its two boundaries the outline and
    // the hole; and the triangle.
    assert_eq!(
        (s.vertices, s.faces, s.edges, s.boundary_loops, s.components),
        (8 + 3, 8 + 1, 16 + 3, 2 + 1, 2)
    );
    assert_eq!(s.euler_characteristic, 1);
}

#[test]
fn two_cones_touching_at_the_tip_are_split() {
    // Two closed-fan tips at vertex 0 would be a double cone; open fans here keep it small.
    let faces: &[&[u32]] = &[
        &[0, 1, 2],
        &[0, 2, 3],
        &[0, 3, 1],
        &[0, 4, 5],
        &[0, 5, 6],
        &[0, 6, 4],
    ];
    let (world, built) = build(&soup(7, faces));
    assert_eq!(built.report.non_manifold_vertices, 1);
    assert_eq!(mesh_stats(&world, built.mesh).components, 2);
}

#[test]
fn three_faces_on_an_edge_detach_the_third() {
    let (world, built) = build(&soup(5, &[&[0, 1, 2], &[1, 0, 3], &[0, 1, 4]]));
    assert_eq!(built.report.non_manifold_edge_faces, 1);
    let s = mesh_stats(&world, built.mesh);
    assert_eq!((s.faces, s.components), (3, 2));
}

#[test]
fn flipped_face_is_reoriented() {
    // A closed tetrahedron with one face written backwards.
    let mut t = shapes::tetrahedron();
    t.indices[0..3].reverse();
    let (world, built) = build(&t);
    assert_eq!(built.report.reoriented_faces, 1);
    assert_eq!(mesh_stats(&world, built.mesh).euler_characteristic, 2);
}

#[test]
fn bad_faces_and_unreferenced_vertices_are_counted() {
    let mut s = soup(
        8,
        &[&[0, 1, 2], &[2, 1], &[0, 1, 42], &[3, 3, 4], &[5, 6, 4]],
    );
    s.positions[6] = Vec3::new(f32::INFINITY, 0.0, 0.0);
    let (world, built) = build(&s);
    let r = &built.report;
    assert_eq!(
        (
            r.too_few_corners,
            r.out_of_range_faces,
            r.repeated_vertex_faces,
            r.non_finite_faces
        ),
        (1, 1, 1, 1)
    );
    assert_eq!(r.unreferenced_vertices, 5);
    assert_eq!(mesh_stats(&world, built.mesh).faces, 1);
    assert!(built.input_vertices[7].is_none());
}

#[test]
fn nothing_left_is_an_error_and_leaves_the_world_empty() {
    let mut world = World::new();
    let before = world.entities().count_spawned();
    let s = soup(3, &[&[0, 1]]);
    let err = pappus::mesh::build_mesh(&mut world, &s, Default::default()).unwrap_err();
    assert!(err.to_string().contains("no usable faces"), "{err}");
    assert_eq!(world.entities().count_spawned(), before);
}

// ---- validate catches each broken invariant -------------------------------------------------

fn broken(edit: impl FnOnce(&mut World, &pappus::mesh::MeshMembers)) -> Rule {
    let (mut world, built) = build(&shapes::icosphere(1));
    let members = pappus::mesh::MeshMembers::collect(&world, built.mesh);
    edit(&mut world, &members);
    validate(&world, built.mesh)
        .expect_err("the edit must break the mesh")
        .rule
}

fn halfedge_mut<'a>(
    world: &'a mut World,
    h: pappus::mesh::HalfedgeId,
) -> bevy::prelude::Mut<'a, Halfedge> {
    world.get_mut::<Halfedge>(h.0).unwrap()
}

#[test]
fn validate_catches_broken_twins() {
    let rule = broken(|w, m| {
        let (a, b) = (m.halfedges[0], m.halfedges[5]);
        halfedge_mut(w, a).twin = b;
    });
    assert_eq!(rule, Rule::TwinNotMutual);
}

#[test]
fn validate_catches_next_prev_disagreement() {
    let rule = broken(|w, m| {
        let h = m.halfedges[0];
        let other = m.halfedges[9];
        halfedge_mut(w, h).next = other;
    });
    assert!(matches!(rule, Rule::NextPrevDisagree), "{rule}");
}

#[test]
fn validate_catches_dangling_links() {
    let rule = broken(|w, m| {
        let f = m.faces[3];
        w.despawn(f.0);
    });
    assert_eq!(rule, Rule::DanglingLink("face"));
    let rule = broken(|w, m| {
        let v = m.vertices[0];
        halfedge_mut(w, m.halfedges[2]).vertex = pappus::mesh::VertexId(m.faces[0].0);
        let _ = v;
    });
    assert_eq!(rule, Rule::DanglingLink("vertex"));
}

#[test]
fn validate_catches_bad_positions_and_vertex_halfedges() {
    let rule = broken(|w, m| {
        w.get_mut::<Position>(m.vertices[1].0).unwrap().0.y = f32::NAN;
    });
    assert_eq!(rule, Rule::NonFinitePosition);
    let rule = broken(|w, m| {
        let mesh = MeshRef::new(w);
        let v = m.vertices[1];
        let incoming = mesh.twin(mesh.vertex_halfedge(v));
        w.get_mut::<Vertex>(v.0).unwrap().halfedge = incoming;
    });
    assert_eq!(rule, Rule::VertexHalfedgeElsewhere);
}

#[test]
fn validate_catches_edge_and_face_bookkeeping() {
    let rule = broken(|w, m| {
        let e = m.edges[0];
        let other = m
            .halfedges
            .iter()
            .copied()
            .find(|&h| MeshRef::new(w).edge(h) != e)
            .unwrap();
        w.get_mut::<pappus::mesh::Edge>(e.0).unwrap().halfedge = other;
    });
    assert_eq!(rule, Rule::EdgeHalfedgeElsewhere);
    let rule = broken(|w, m| {
        let f = m.faces[0];
        let other = m
            .halfedges
            .iter()
            .copied()
            .find(|&h| MeshRef::new(w).face(h) != Some(f))
            .unwrap();
        w.get_mut::<pappus::mesh::Face>(f.0).unwrap().halfedge = other;
    });
    assert_eq!(rule, Rule::FaceHalfedgeElsewhere);
}

#[test]
fn validate_catches_a_boundary_vertex_pointing_inside() {
    let (mut world, built) = build(&shapes::grid(2, 2));
    let v = built.input_vertices[1].unwrap();
    let m = MeshRef::new(&world);
    let inner = m.vertex_outgoing(v).find(|&h| !m.is_boundary(h)).unwrap();
    world.get_mut::<Vertex>(v.0).unwrap().halfedge = inner;
    assert_eq!(
        validate(&world, built.mesh).unwrap_err().rule,
        Rule::BoundaryVertexHalfedge
    );
}

#[test]
fn validate_catches_a_face_hole() {
    // Turning one face's halfedges into boundary ones leaves the face with no halfedge of its own.
    let rule = broken(|w, m| {
        let f = m.faces[0];
        let hs: Vec<_> = MeshRef::new(w).face_halfedges(f).collect();
        for h in hs {
            halfedge_mut(w, h).face = None;
        }
    });
    assert_eq!(rule, Rule::FaceHalfedgeElsewhere);
}

#[test]
fn validate_catches_twin_edge_and_face_mismatches() {
    let rule = broken(|w, m| {
        let mesh = MeshRef::new(w);
        let h = m.halfedges[0];
        let other = m
            .edges
            .iter()
            .copied()
            .find(|&e| e != mesh.edge(h))
            .unwrap();
        halfedge_mut(w, h).edge = other;
    });
    assert_eq!(rule, Rule::TwinEdgeDiffers);
    let rule = broken(|w, m| {
        let mesh = MeshRef::new(w);
        let h = m.halfedges[0];
        let other = m
            .faces
            .iter()
            .copied()
            .find(|&f| Some(f) != mesh.face(h))
            .unwrap();
        halfedge_mut(w, h).face = Some(other);
    });
    assert_eq!(rule, Rule::NextLeavesFace);
}

#[test]
fn validate_catches_a_non_manifold_vertex_and_an_empty_mesh() {
    // The bow tie is repaired into two components; gluing the split vertex back by hand makes
    // one vertex with two fans.
    let positions = (0..5)
        .map(|i| Vec3::new(i as f32, (i * i) as f32, 0.0))
        .collect();
    let (mut world, built) = build(&PolygonSoup::from_faces(
        positions,
        &[[0u32, 1, 2], [0, 3, 4]],
    ));
    let members = pappus::mesh::MeshMembers::collect(&world, built.mesh);
    let keep = built.input_vertices[0].unwrap();
    let copy = *members.vertices.last().unwrap();
    assert_ne!(keep, copy);
    for &h in &members.halfedges {
        if MeshRef::new(&world).to_vertex(h) == copy {
            halfedge_mut(&mut world, h).vertex = keep;
        }
    }
    world.despawn(copy.0);
    assert_eq!(
        validate(&world, built.mesh).unwrap_err().rule,
        Rule::NonManifoldVertex
    );

    let mut world = World::new();
    let empty = pappus::mesh::MeshId(world.spawn(pappus::mesh::MeshInfo::default()).id());
    assert_eq!(validate(&world, empty).unwrap_err().rule, Rule::Empty);
}
