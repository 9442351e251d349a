//! QEM simplification: hits the face target, stays valid, keeps planes planar and boundaries
//! on the boundary, refuses what it cannot do; the distance check and the fit to the input
//! bring a scan closer to its input.

mod common;

use common::build;
use pappus::mesh::{MeshMembers, MeshRef, mesh_stats, shapes, validate};
use pappus::ops::Refusal;
use pappus::ops::simplify::{SimplifyParams, simplify};

#[test]
fn icosphere_reaches_the_target_and_stays_a_sphere() {
    let (mut world, built) = build(&shapes::icosphere(4));
    // Entities in the world besides the mesh's elements (the mesh itself, and Bevy's own).
    let others = |world: &bevy::prelude::World| {
        world.entities().count_spawned() as usize
            - MeshMembers::collect(world, built.mesh).entities().count()
    };
    let before = others(&world);
    for target in [2560, 1000, 200] {
        let s = simplify(&mut world, built.mesh, &SimplifyParams::faces(target)).unwrap();
        validate(&world, built.mesh).unwrap();
        let st = mesh_stats(&world, built.mesh);
        assert!(s.reached_target);
        assert!(
            st.faces <= target && st.faces + 2 >= target,
            "{} for {target}",
            st.faces
        );
        assert_eq!((st.euler_characteristic, st.boundary_loops), (2, 0));
        // Nothing the collapses removed is left in the world: a closed triangle mesh of F
        // faces and χ = 2 has 3F/2 edges, 3F halfedges and 2 + F/2 vertices.
        assert_eq!(others(&world), before);
        let f = st.faces;
        assert_eq!(
            MeshMembers::collect(&world, built.mesh).entities().count(),
            (2 + f / 2) + 3 * f + 3 * f / 2 + f
        );
        // Every vertex is still on the unit sphere, up to the simplification's error.
        let m = MeshRef::new(&world);
        for v in MeshMembers::collect(&world, built.mesh).vertices {
            let r = m.position(v).length();
            assert!((r - 1.0).abs() < 0.05, "{r}");
        }
    }
}

#[test]
fn a_planar_grid_stays_in_its_plane_and_keeps_its_border() {
    let (mut world, built) = build(&shapes::grid(20, 20));
    let s = simplify(&mut world, built.mesh, &SimplifyParams::ratio(0.3)).unwrap();
    assert!(s.reached_target, "{s:?}");
    validate(&world, built.mesh).unwrap();
    let st = mesh_stats(&world, built.mesh);
    assert_eq!((st.boundary_loops, st.euler_characteristic), (1, 1));
    let m = MeshRef::new(&world);
    for v in MeshMembers::collect(&world, built.mesh).vertices {
        let p = m.position(v);
        assert!(p.z.abs() < 1e-6, "{p} left the plane");
        if m.is_boundary_vertex(v) {
            let on_border = [p.x, p.y]
                .iter()
                .any(|c| c.abs() < 1e-4 || (c - 1.0).abs() < 1e-4);
            assert!(on_border, "{p} left the border");
        }
    }
    // The four corners survive.
    for corner in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
        let found = MeshMembers::collect(&world, built.mesh)
            .vertices
            .iter()
            .any(|&v| {
                (m.position(v).truncate() - bevy::math::Vec2::new(corner.0, corner.1)).length()
                    < 1e-5
            });
        assert!(found, "corner {corner:?} moved");
    }
}

#[test]
fn polygons_are_refused_and_small_meshes_stop_early() {
    let (mut world, built) = build(&shapes::cube());
    let r = simplify(&mut world, built.mesh, &SimplifyParams::faces(4)).unwrap_err();
    assert!(matches!(r, Refusal::NotTriangle(_)), "{r}");
    assert_eq!(mesh_stats(&world, built.mesh).faces, 6);
    let (mut world, built) = build(&shapes::tetrahedron());
    let s = simplify(&mut world, built.mesh, &SimplifyParams::faces(1)).unwrap();
    assert!(!s.reached_target);
    assert_eq!(s.faces_after, 4);
    validate(&world, built.mesh).unwrap();
}

#[test]
fn shared_models_simplify_to_the_target() {
    for (name, ratio) in [("spot.obj", 0.25), ("stanford-bunny.obj", 0.25)] {
        let Some(path) = common::model(name) else {
            return;
        };
        let soup = pappus::io::read(&path).unwrap();
        let (mut world, built) = build(&soup);
        let before = mesh_stats(&world, built.mesh);
        let params = SimplifyParams::ratio(ratio);
        let s = simplify(&mut world, built.mesh, &params).unwrap();
        validate(&world, built.mesh).unwrap();
        let after = mesh_stats(&world, built.mesh);
        assert!(s.reached_target, "{name}: {s:?}");
        let target = params.target.faces(before.faces);
        assert!(after.faces <= target && after.faces + 2 >= target);
        assert_eq!(
            after.boundary_loops, before.boundary_loops,
            "{name}: holes kept open"
        );
        assert_eq!(
            after.euler_characteristic, before.euler_characteristic,
            "{name}"
        );
    }
}

/// Points of a triangle mesh: its vertices and a barycentric grid of 4 steps a side on every
/// triangle, where its farthest points from another lie.
fn samples(soup: &pappus::mesh::PolygonSoup) -> Vec<bevy::math::Vec3> {
    let mut samples = soup.positions.clone();
    for f in soup.faces() {
        let [a, b, c] = [0, 1, 2].map(|k| soup.positions[f[k] as usize]);
        for i in 0..=4 {
            for j in 0..=4 - i {
                let (u, v) = (i as f32 / 4.0, j as f32 / 4.0);
                samples.push(a + (b - a) * u + (c - a) * v);
            }
        }
    }
    samples
}

/// The largest distance from any of `points` to the triangles of `soup`.
fn farthest(points: &[bevy::math::Vec3], soup: &pappus::mesh::PolygonSoup) -> f32 {
    let triangles = soup
        .faces()
        .map(|f| [0, 1, 2].map(|i| soup.positions[f[i] as usize]))
        .collect();
    let surface = pappus::ops::geometry::closest::Reference::from_triangles(triangles);
    points
        .iter()
        .map(|&p| surface.distance(p))
        .fold(0.0f32, f32::max)
}

/// `soup` simplified as `params` say (to the target, valid), and how far the farthest of
/// `soup`'s samples lies from it and the farthest of its samples from `soup`.
fn distances(soup: &pappus::mesh::PolygonSoup, params: SimplifyParams) -> (f32, f32) {
    let (mut world, built) = build(soup);
    let s = simplify(&mut world, built.mesh, &params).unwrap();
    assert!(s.reached_target);
    validate(&world, built.mesh).unwrap();
    let out = pappus::mesh::to_soup(&world, built.mesh);
    (
        farthest(&samples(soup), &out),
        farthest(&samples(&out), soup),
    )
}

#[test]
fn the_distance_check_keeps_a_scan_closer_to_its_input() {
    let Some(path) = common::model("spot.obj") else {
        return;
    };
    let soup = pappus::io::read(&path).unwrap();
    let plain = distances(&soup, SimplifyParams::ratio(0.25)).0;
    let checked = distances(
        &soup,
        SimplifyParams {
            distance_weight: 8.0,
            ..SimplifyParams::ratio(0.25)
        },
    )
    .0;
    assert!(checked < 0.9 * plain, "{checked} against {plain}");
}

#[test]
fn the_fit_brings_a_scan_closer_to_its_input_and_leaves_its_boundary() {
    let Some(path) = common::model("spot.obj") else {
        return;
    };
    let soup = pappus::io::read(&path).unwrap();
    let params = SimplifyParams::ratio(0.25);
    let fitted = SimplifyParams {
        fit_to_input: true,
        ..params
    };
    // Both ways: the farthest spot of the spot's result is a vertex off the input (at the
    // tip of its tail), which the input's samples do not see.
    let (plain_in, plain_out) = distances(&soup, params);
    let (fitted_in, fitted_out) = distances(&soup, fitted);
    let (plain, closer) = (plain_in.max(plain_out), fitted_in.max(fitted_out));
    assert!(closer < 0.95 * plain, "{closer} against {plain}");
    // The same collapses, the boundary where they left it.
    let simplified = |params: &SimplifyParams| {
        let (mut world, built) = build(&soup);
        let s = simplify(&mut world, built.mesh, params).unwrap();
        let m = MeshRef::new(&world);
        let members = MeshMembers::collect(&world, built.mesh);
        let corners: Vec<(bool, bevy::math::Vec3)> = members
            .vertices
            .iter()
            .map(|&v| (m.is_boundary_vertex(v), m.position(v)))
            .collect();
        (s, corners)
    };
    let (plain_summary, plain_corners) = simplified(&params);
    let (fitted_summary, fitted_corners) = simplified(&fitted);
    assert_eq!(plain_summary, fitted_summary);
    let mut moved = 0;
    for (&(boundary, p), &(_, q)) in plain_corners.iter().zip(&fitted_corners) {
        if boundary {
            assert_eq!(p, q, "a boundary vertex moved");
        }
        moved += usize::from(p != q);
    }
    assert!(
        moved > plain_corners.len() / 2,
        "{moved} of {}",
        plain_corners.len()
    );
}
