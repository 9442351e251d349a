//! QEM simplification: hits the face target, stays valid, keeps planes planar and boundaries
//! on the boundary, refuses what it cannot do.

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

#[test]
fn the_distance_check_keeps_a_scan_closer_to_its_input() {
    let Some(path) = common::model("spot.obj") else {
        return;
    };
    let soup = pappus::io::read(&path).unwrap();
    // The input's vertices and face centroids, where its farthest points from a
    // simplification mostly lie.
    let mut samples = soup.positions.clone();
    samples.extend(soup.faces().map(|f| {
        f.iter()
            .map(|&v| soup.positions[v as usize])
            .sum::<bevy::math::Vec3>()
            / f.len() as f32
    }));
    let farthest = |params: SimplifyParams| {
        let (mut world, built) = build(&soup);
        let s = simplify(&mut world, built.mesh, &params).unwrap();
        assert!(s.reached_target);
        validate(&world, built.mesh).unwrap();
        let out = pappus::mesh::to_soup(&world, built.mesh);
        let triangles = out
            .faces()
            .map(|f| [0, 1, 2].map(|i| out.positions[f[i] as usize]))
            .collect();
        let surface = pappus::ops::geometry::closest::Reference::from_triangles(triangles);
        samples
            .iter()
            .map(|&p| surface.distance(p))
            .fold(0.0f32, f32::max)
    };
    let plain = farthest(SimplifyParams::ratio(0.25));
    let checked = farthest(SimplifyParams {
        distance_weight: 8.0,
        ..SimplifyParams::ratio(0.25)
    });
    assert!(checked < 0.9 * plain, "{checked} against {plain}");
}
