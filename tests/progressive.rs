//! Progressive meshes: simplify with a history, then refine and coarsen along it; every level
//! is valid and the full level is the original mesh (positions bitwise, faces as cycles).

mod common;

use common::{build, canonical};
use pappus::mesh::{PolygonSoup, mesh_stats, shapes, to_soup, validate};
use pappus::ops::progressive::ProgressiveMesh;
use pappus::ops::simplify::SimplifyParams;

fn round_trip(soup: &PolygonSoup, ratio: f64) {
    let (mut world, built) = build(soup);
    let original = canonical(&to_soup(&world, built.mesh));
    let faces = mesh_stats(&world, built.mesh).faces;
    let (mut pm, summary) =
        ProgressiveMesh::simplify(&mut world, built.mesh, &SimplifyParams::ratio(ratio)).unwrap();
    assert_eq!(pm.faces(), summary.faces_after);
    validate(&world, built.mesh).unwrap();
    // All the way up: the original mesh, exactly.
    pm.go_to_faces(&mut world, usize::MAX).unwrap();
    validate(&world, built.mesh).unwrap();
    assert_eq!(pm.faces(), faces);
    assert_eq!(canonical(&to_soup(&world, built.mesh)), original);
    // Down and up again, in random-sized steps.
    let mut seed = 12345u64;
    for _ in 0..20 {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let target =
            summary.faces_after + (seed >> 33) as usize % (faces - summary.faces_after + 1);
        pm.go_to_faces(&mut world, target).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(mesh_stats(&world, built.mesh).faces, pm.faces());
        assert!(
            pm.faces().abs_diff(target) <= 1,
            "{} for {target}",
            pm.faces()
        );
    }
    pm.go_to_faces(&mut world, usize::MAX).unwrap();
    assert_eq!(canonical(&to_soup(&world, built.mesh)), original);
}

#[test]
fn icosphere_and_open_grid_round_trip() {
    round_trip(&shapes::icosphere(3), 0.05);
    round_trip(&shapes::grid(12, 12), 0.1);
}

#[test]
fn the_bunny_simplified_to_one_percent_refines_back_exactly() {
    let Some(path) = common::model("stanford-bunny.obj") else {
        return;
    };
    let soup = pappus::io::read(&path).unwrap();
    round_trip(&soup, 0.01);
}

/// A long refine goes in bulk (tables, then one write); a short one split by split. Both must
/// make the same mesh: refine one copy in bulk and the other one split at a time, to the same
/// level, and compare.
#[test]
fn bulk_and_single_refines_make_the_same_mesh() {
    for soup in [shapes::icosphere(3), shapes::grid(12, 12)] {
        let (mut bulk_world, bulk) = build(&soup);
        let (mut single_world, single) = build(&soup);
        let faces = mesh_stats(&bulk_world, bulk.mesh).faces;
        let params = SimplifyParams::ratio(0.05);
        let (mut by_bulk, _) =
            ProgressiveMesh::simplify(&mut bulk_world, bulk.mesh, &params).unwrap();
        let (mut by_single, _) =
            ProgressiveMesh::simplify(&mut single_world, single.mesh, &params).unwrap();
        let halfway = (faces + by_bulk.faces()) / 2;
        let steps = by_bulk.go_to_faces(&mut bulk_world, halfway).unwrap();
        assert!(steps > 10);
        while by_single.faces() < by_bulk.faces() {
            assert!(by_single.refine_one(&mut single_world).unwrap());
        }
        validate(&bulk_world, bulk.mesh).unwrap();
        validate(&single_world, single.mesh).unwrap();
        assert_eq!(
            canonical(&to_soup(&bulk_world, bulk.mesh)),
            canonical(&to_soup(&single_world, single.mesh))
        );
        // The history still works from the level the bulk path left: down a little, then
        // all the way up.
        by_bulk.go_to_faces(&mut bulk_world, halfway - 8).unwrap();
        by_bulk.go_to_faces(&mut bulk_world, usize::MAX).unwrap();
        validate(&bulk_world, bulk.mesh).unwrap();
        let (fresh_world, fresh) = build(&soup);
        assert_eq!(
            canonical(&to_soup(&bulk_world, bulk.mesh)),
            canonical(&to_soup(&fresh_world, fresh.mesh))
        );
    }
}
