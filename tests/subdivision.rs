//! Loop and Catmull–Clark subdivision: exact positions from the formulas (computed here,
//! independently), counts after N levels, validity and χ.

mod common;

use bevy::math::Vec3;
use common::build;
use pappus::mesh::{MeshRef, PolygonSoup, mesh_stats, shapes, to_soup, validate};
use pappus::ops::Refusal;
use pappus::ops::subdivide::{catmull_clark, loop_subdivide};

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

/// Neighbours of each input vertex in a soup.
fn neighbours(soup: &PolygonSoup) -> Vec<Vec<u32>> {
    let mut n = vec![Vec::new(); soup.positions.len()];
    for f in soup.faces() {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            if !n[a as usize].contains(&b) {
                n[a as usize].push(b);
            }
            if !n[b as usize].contains(&a) {
                n[b as usize].push(a);
            }
        }
    }
    n
}

fn contains_point(points: &[Vec3], p: Vec3) -> bool {
    points.iter().any(|&q| close(p, q))
}

#[test]
fn loop_on_a_tetrahedron_follows_the_formulas() {
    let soup = shapes::tetrahedron();
    let (mut world, built) = build(&soup);
    let s = loop_subdivide(&mut world, built.mesh, 1).unwrap();
    assert_eq!((s.vertices, s.faces), (10, 16));
    validate(&world, built.mesh).unwrap();
    let st = mesh_stats(&world, built.mesh);
    assert_eq!(
        (st.vertices, st.edges, st.faces, st.euler_characteristic),
        (10, 24, 16, 2)
    );
    let m = MeshRef::new(&world);
    let n = neighbours(&soup);
    for (i, v) in built.input_vertices.iter().enumerate() {
        // Valence 3: u = 3/16.
        let sum: Vec3 = n[i].iter().map(|&j| soup.positions[j as usize]).sum();
        let expected = (1.0 - 3.0 * 3.0 / 16.0) * soup.positions[i] + 3.0 / 16.0 * sum;
        assert!(close(m.position(v.unwrap()), expected), "vertex {i}");
    }
    // Edge points: 3/8 (a + b) + 1/8 (c + d), c and d the other two vertices.
    let out = to_soup(&world, built.mesh).positions;
    for a in 0..4u32 {
        for b in a + 1..4 {
            let others: Vec3 = (0..4u32)
                .filter(|&x| x != a && x != b)
                .map(|x| soup.positions[x as usize])
                .sum();
            let e =
                0.375 * (soup.positions[a as usize] + soup.positions[b as usize]) + 0.125 * others;
            assert!(contains_point(&out, e), "edge point {a}-{b}");
        }
    }
}

#[test]
fn loop_counts_after_levels() {
    for levels in 1..=3u32 {
        let (mut world, built) = build(&shapes::icosahedron());
        loop_subdivide(&mut world, built.mesh, levels).unwrap();
        validate(&world, built.mesh).unwrap();
        let s = mesh_stats(&world, built.mesh);
        let p = 4usize.pow(levels);
        assert_eq!((s.faces, s.vertices, s.edges), (20 * p, 10 * p + 2, 30 * p));
        assert_eq!(s.euler_characteristic, 2);
    }
}

#[test]
fn loop_on_an_open_grid_uses_the_boundary_rules() {
    // A bumpy grid so that the rules matter.
    let mut soup = shapes::grid(3, 3);
    for (i, p) in soup.positions.iter_mut().enumerate() {
        p.z = ((i * 7) % 5) as f32 * 0.1;
    }
    let n = neighbours(&soup);
    let (mut world, built) = build(&soup);
    let (v, e, f) = (16usize, 33usize, 18usize);
    loop_subdivide(&mut world, built.mesh, 1).unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    assert_eq!(
        (
            s.vertices,
            s.faces,
            s.boundary_loops,
            s.euler_characteristic
        ),
        (v + e, 4 * f, 1, 1)
    );
    let m = MeshRef::new(&world);
    let at = |x: u32, y: u32| (y * 4 + x) as usize;
    let p = |i: usize| soup.positions[i];
    // The corner (3, 0) has two edges: it stays put.
    assert!(close(
        m.position(built.input_vertices[at(3, 0)].unwrap()),
        p(at(3, 0))
    ));
    // A boundary vertex: 3/4 v + 1/8 (a + b) along the boundary.
    let b = at(1, 0);
    let expected = 0.75 * p(b) + 0.125 * (p(at(0, 0)) + p(at(2, 0)));
    assert!(close(
        m.position(built.input_vertices[b].unwrap()),
        expected
    ));
    // An interior vertex of valence 6: u = 3/48.
    let c = at(1, 1);
    assert_eq!(n[c].len(), 6);
    let sum: Vec3 = n[c].iter().map(|&j| p(j as usize)).sum();
    let expected = (1.0 - 6.0 / 16.0) * p(c) + sum / 16.0;
    assert!(close(
        m.position(built.input_vertices[c].unwrap()),
        expected
    ));
    // A boundary edge point is the midpoint.
    let out = to_soup(&world, built.mesh).positions;
    assert!(contains_point(&out, (p(at(0, 0)) + p(at(1, 0))) / 2.0));
}

#[test]
fn loop_refuses_polygons_and_leaves_the_mesh() {
    let (mut world, built) = build(&shapes::cube());
    let before = to_soup(&world, built.mesh);
    let err = loop_subdivide(&mut world, built.mesh, 1).unwrap_err();
    assert!(matches!(err, Refusal::NotTriangle(_)), "{err}");
    assert!(err.to_string().contains("triangulate"));
    assert_eq!(to_soup(&world, built.mesh), before);
}

#[test]
fn catmull_clark_on_a_cube_gives_the_known_corners() {
    let (mut world, built) = build(&shapes::cube());
    let s = catmull_clark(&mut world, built.mesh, 1).unwrap();
    assert_eq!((s.vertices, s.faces), (26, 24));
    validate(&world, built.mesh).unwrap();
    let st = mesh_stats(&world, built.mesh);
    assert_eq!((st.edges, st.euler_characteristic), (48, 2));
    assert_eq!(st.face_sizes.get(&4), Some(&24));
    let m = MeshRef::new(&world);
    // (Q + 2R + (n-3)P)/n with n = 3: Q = (1/3,1/3,1/3)·sign, R = (2/3,...): 5/9.
    for v in built.input_vertices.iter().map(|v| v.unwrap()) {
        let p = m.position(v);
        assert!(close(p.abs(), Vec3::splat(5.0 / 9.0)), "{p}");
    }
    let out = to_soup(&world, built.mesh).positions;
    // Face points are the face centres; edge points (a + b + f1 + f2)/4.
    assert!(contains_point(&out, Vec3::new(0.0, 0.0, 1.0)));
    assert!(contains_point(&out, Vec3::new(0.75, 0.75, 0.0)));
}

#[test]
fn catmull_clark_on_a_single_quad_keeps_corners_and_halves_edges() {
    let soup = shapes::quad_grid(1, 1);
    let (mut world, built) = build(&soup);
    catmull_clark(&mut world, built.mesh, 1).unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    assert_eq!((s.vertices, s.faces, s.boundary_loops), (9, 4, 1));
    let m = MeshRef::new(&world);
    for (i, v) in built.input_vertices.iter().enumerate() {
        assert!(close(m.position(v.unwrap()), soup.positions[i]));
    }
    let out = to_soup(&world, built.mesh).positions;
    assert!(contains_point(&out, Vec3::new(0.5, 0.5, 0.0)));
    assert!(contains_point(&out, Vec3::new(0.5, 0.0, 0.0)));
}

#[test]
fn catmull_clark_takes_polygons_and_gives_quads() {
    // Triangles, quads and a boundary: the result is all quads, valid, same χ.
    for soup in [
        shapes::tetrahedron(),
        shapes::grid_with_holes(2),
        shapes::torus(6, 5),
        shapes::slab_with_holes(2),
    ] {
        let (mut world, built) = build(&soup);
        let before = mesh_stats(&world, built.mesh);
        catmull_clark(&mut world, built.mesh, 2).unwrap();
        validate(&world, built.mesh).unwrap();
        let after = mesh_stats(&world, built.mesh);
        assert_eq!(after.euler_characteristic, before.euler_characteristic);
        assert_eq!(after.boundary_loops, before.boundary_loops);
        assert_eq!(after.face_sizes.len(), 1);
        assert!(after.face_sizes.contains_key(&4));
        // Level 1: one quad per face corner; level 2: four per quad.
        let corners: usize = before.face_sizes.iter().map(|(k, n)| k * n).sum();
        assert_eq!(after.faces, 4 * corners);
    }
}
