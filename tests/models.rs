//! The shared real-world models (`../shared/models`): every one loads without a panic, is
//! repaired into a valid mesh, and reports what its README says is awkward about it.
//! Skipped with a notice where the folder is absent.

mod common;

use bevy::prelude::World;
use pappus::mesh::{MeshInfo, build_mesh, mesh_stats, to_soup, validate};

struct Loaded {
    world: World,
    built: pappus::mesh::BuiltMesh,
}

fn load(name: &str) -> Option<Loaded> {
    let path = common::model(name)?;
    let soup = pappus::io::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut world = World::new();
    let built = build_mesh(&mut world, &soup, MeshInfo::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    if let Err(e) = validate(&world, built.mesh) {
        panic!("{name}: invalid after repair: {e}");
    }
    Some(Loaded { world, built })
}

const MODELS: [&str; 9] = [
    "spot.obj",
    "cow.obj",
    "fandisk.obj",
    "homer.obj",
    "teapot.obj",
    "stanford-bunny.obj",
    "ogre.obj",
    "suzanne.obj",
    "beast.obj",
];

#[test]
fn every_shared_model_loads_and_validates() {
    for name in MODELS {
        let Some(l) = load(name) else { return };
        let s = mesh_stats(&l.world, l.built.mesh);
        println!(
            "{name}: V {} F {} χ {} genus {} components {} loops {}; {}",
            s.vertices,
            s.faces,
            s.euler_characteristic,
            s.genus,
            s.components,
            s.boundary_loops,
            l.built.report
        );
        assert!(s.faces > 0);
    }
}

#[test]
fn clean_closed_models_need_no_repair() {
    for name in ["spot.obj", "homer.obj"] {
        let Some(l) = load(name) else { return };
        assert!(l.built.report.is_clean(), "{name}: {}", l.built.report);
        let s = mesh_stats(&l.world, l.built.mesh);
        assert!(s.closed, "{name}");
        assert_eq!(s.euler_characteristic, 2, "{name}");
    }
}

#[test]
fn spot_has_its_published_counts() {
    let Some(l) = load("spot.obj") else { return };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert_eq!((s.vertices, s.faces, s.genus), (2930, 5856, 0));
}

#[test]
fn cow_has_one_non_manifold_vertex_split() {
    let Some(l) = load("cow.obj") else { return };
    assert_eq!(
        l.built.report.non_manifold_vertices, 1,
        "{}",
        l.built.report
    );
}

#[test]
fn teapot_parts_and_boundaries_are_kept() {
    let Some(l) = load("teapot.obj") else { return };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert!(s.boundary_loops >= 10, "{}", s.boundary_loops);
    assert!(
        l.built.report.non_manifold_vertices > 0,
        "{}",
        l.built.report
    );
}

#[test]
fn ogre_keeps_its_components() {
    let Some(l) = load("ogre.obj") else { return };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert!(s.components >= 44, "{}", s.components);
}

#[test]
fn bunny_has_holes() {
    let Some(l) = load("stanford-bunny.obj") else {
        return;
    };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert!(s.boundary_loops >= 5, "{}", s.boundary_loops);
    assert_eq!(s.faces, 69451);
}

#[test]
fn polygon_models_keep_their_faces() {
    let Some(l) = load("suzanne.obj") else { return };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert_eq!(s.face_sizes.get(&4), Some(&468));
    assert_eq!(s.face_sizes.get(&3), Some(&32));
    let Some(l) = load("beast.obj") else { return };
    let s = mesh_stats(&l.world, l.built.mesh);
    assert_eq!(s.face_sizes.get(&4), Some(&32228));
    assert_eq!(s.face_sizes.get(&3), Some(&124));
    assert_eq!(s.face_sizes.get(&5), Some(&10));
    assert_eq!(s.face_sizes.get(&6), Some(&2));
    assert!(s.closed);
    assert_eq!(s.genus, 0);
}

#[test]
fn polygon_models_save_and_reload_unchanged() {
    for name in ["suzanne.obj", "beast.obj"] {
        let Some(l) = load(name) else { return };
        let soup = to_soup(&l.world, l.built.mesh);
        for ext in ["obj", "off", "ply"] {
            let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
                .join(format!("roundtrip-{name}.{ext}"));
            pappus::io::write(&path, &soup).unwrap();
            let back = pappus::io::read(&path).unwrap();
            assert_eq!(back.positions, soup.positions, "{name} via {ext}");
            assert_eq!(back.indices, soup.indices, "{name} via {ext}");
        }
    }
}

#[test]
fn catmull_clark_subdivides_the_polygon_models() {
    for name in ["suzanne.obj", "beast.obj"] {
        let Some(mut l) = load(name) else { return };
        let before = mesh_stats(&l.world, l.built.mesh);
        pappus::ops::subdivide::catmull_clark(&mut l.world, l.built.mesh, 1).unwrap();
        validate(&l.world, l.built.mesh).unwrap();
        let after = mesh_stats(&l.world, l.built.mesh);
        assert_eq!(
            after.euler_characteristic, before.euler_characteristic,
            "{name}"
        );
        assert_eq!(
            after.vertices,
            before.vertices + before.edges + before.faces,
            "{name}"
        );
        assert_eq!(
            after.face_sizes.keys().copied().collect::<Vec<_>>(),
            vec![4],
            "{name}"
        );
    }
}
