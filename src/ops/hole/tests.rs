use bevy::math::Vec3;
use bevy::prelude::World;

use super::*;
use crate::mesh::stats::{mesh_stats, min_corner_angle_deg};
use crate::mesh::{build_mesh, shapes, validate};
use crate::ops::local::erase_faces;

/// An icosphere with the faces above `height` erased: one round hole.
fn capped_sphere(levels: u32, height: f32) -> (World, MeshId) {
    let mut world = World::new();
    let built = build_mesh(&mut world, &shapes::icosphere(levels), MeshInfo::default()).unwrap();
    let m = MeshRef::new(&world);
    let cap: Vec<FaceId> = MeshMembers::collect(&world, built.mesh)
        .faces
        .into_iter()
        .filter(|&f| m.face_centroid(f).y > height)
        .collect();
    erase_faces(&mut world, &cap).unwrap();
    (world, built.mesh)
}

fn a_boundary_edge(world: &World, mesh: MeshId) -> EdgeId {
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .edges
        .into_iter()
        .find(|&e| m.is_boundary_edge(e))
        .unwrap()
}

/// The shape of the faces not in `before` (the patch).
#[derive(Debug)]
struct PatchShape {
    /// The mean, shortest and longest edge over the target length.
    mean: f32,
    shortest: f32,
    longest: f32,
    /// The smallest angle, in degrees.
    smallest_angle: f64,
}

fn patch_shape(world: &World, mesh: MeshId, before: &EntityHashSet, length: f32) -> PatchShape {
    let m = MeshRef::new(world);
    let (mut sum, mut count) = (0.0, 0.0);
    let mut shape = PatchShape {
        mean: 0.0,
        shortest: f32::MAX,
        longest: 0.0,
        smallest_angle: f64::MAX,
    };
    for f in MeshMembers::collect(world, mesh).faces {
        if before.contains(&f.0) {
            continue;
        }
        let points: Vec<Vec3> = m.face_vertices(f).map(|v| m.position(v)).collect();
        for k in 0..points.len() {
            let l = points[k].distance(points[(k + 1) % points.len()]) / length;
            (sum, count) = (sum + l, count + 1.0);
            shape.shortest = shape.shortest.min(l);
            shape.longest = shape.longest.max(l);
        }
        shape.smallest_angle = shape.smallest_angle.min(min_corner_angle_deg(&points));
    }
    shape.mean = sum / count;
    shape
}

#[test]
fn a_cap_cut_from_a_sphere_comes_back_round_closed_and_well_shaped() {
    let (mut world, mesh) = capped_sphere(4, 0.75);
    let e = a_boundary_edge(&world, mesh);
    let plan = plan_fair_fill(&world, e).unwrap();
    let before: EntityHashSet = MeshMembers::collect(&world, mesh)
        .faces
        .iter()
        .map(|f| f.0)
        .collect();
    let filled = fill_hole_fair(&mut world, e).unwrap();
    validate(&world, mesh).unwrap();
    let stats = mesh_stats(&world, mesh);
    assert!(stats.closed, "{stats:?}");
    assert_eq!(stats.euler_characteristic, 2);
    assert!(filled.new_vertices > 10, "{filled:?}");
    let m = MeshRef::new(&world);
    let radius = MeshMembers::collect(&world, mesh)
        .vertices
        .iter()
        .map(|&v| (m.position(v).length() - 1.0).abs())
        .fold(0.0f32, f32::max);
    let shape = patch_shape(&world, mesh, &before, plan.length);
    eprintln!("{filled:?}: radius off by {radius}, {shape:?}");
    // Within 1 % of the radius, the density of the surroundings, no sliver.
    assert!(radius < 0.01, "radius off by {radius}");
    assert!((shape.mean - 1.0).abs() < 0.25, "{shape:?}");
    assert!(shape.smallest_angle > 20.0, "{shape:?}");
}

#[test]
fn every_hole_is_filled_as_polygons_or_fair_patches() {
    for fair in [false, true] {
        let mut world = World::new();
        let built =
            build_mesh(&mut world, &shapes::grid_with_holes(3), MeshInfo::default()).unwrap();
        let done = fill_holes(&mut world, built.mesh, fair).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(done.filled, 4, "{done:?}");
        assert!(done.refused.is_empty());
        let stats = mesh_stats(&world, built.mesh);
        assert!(stats.closed);
        assert_eq!(stats.euler_characteristic, 2);
    }
}

#[test]
fn an_edge_with_no_hole_beside_it_is_refused_and_changes_nothing() {
    let mut world = World::new();
    let built = build_mesh(&mut world, &shapes::icosphere(1), MeshInfo::default()).unwrap();
    let e = MeshMembers::collect(&world, built.mesh).edges[0];
    let before = mesh_stats(&world, built.mesh);
    assert!(matches!(
        fill_hole_fair(&mut world, e),
        Err(Refusal::NotBoundary(_))
    ));
    assert_eq!(mesh_stats(&world, built.mesh), before);
}
