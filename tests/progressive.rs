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
        ProgressiveMesh::simplify(&mut world, built.mesh, &SimplifyParams::ratio(faces, ratio))
            .unwrap();
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
