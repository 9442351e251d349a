//! Isotropic remeshing: valid, χ unchanged, edge lengths in [4/5 L, 4/3 L] for ≥ 95 % of
//! edges, boundaries and features kept (fandisk's corners to the bit, its creases to L/8).

mod common;

use bevy::math::Vec3;
use common::build;
use pappus::mesh::{MeshMembers, MeshRef, mesh_stats, shapes, validate};
use pappus::ops::remesh::{RemeshParams, remesh};

fn in_band(world: &bevy::prelude::World, mesh: pappus::mesh::MeshId, length: f32) -> f64 {
    let m = MeshRef::new(world);
    let edges = MeshMembers::collect(world, mesh).edges;
    let good = edges
        .iter()
        .filter(|&&e| {
            let (a, b) = m.edge_vertices(e);
            let l = m.position(a).distance(m.position(b));
            l >= 0.8 * length * 0.999 && l <= 4.0 / 3.0 * length * 1.001
        })
        .count();
    good as f64 / edges.len() as f64
}

#[test]
fn icosphere_and_torus_get_even_edges() {
    for (name, soup, length) in [
        ("icosphere", shapes::icosphere(3), 0.1f32),
        (
            "torus",
            shapes::triangulate_fans(&shapes::torus(24, 12)),
            0.12,
        ),
    ] {
        let (mut world, built) = build(&soup);
        let chi = mesh_stats(&world, built.mesh).euler_characteristic;
        let params = RemeshParams {
            target_length: Some(length),
            ..Default::default()
        };
        remesh(&mut world, built.mesh, &params).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(
            mesh_stats(&world, built.mesh).euler_characteristic,
            chi,
            "{name}"
        );
        let share = in_band(&world, built.mesh, length);
        println!("{name}: {:.1} % of edges in band", share * 100.0);
        assert!(
            share >= 0.95,
            "{name}: only {:.1} % of edges in [4/5 L, 4/3 L]",
            share * 100.0
        );
        if name == "icosphere" {
            let m = MeshRef::new(&world);
            for v in MeshMembers::collect(&world, built.mesh).vertices {
                let r = m.position(v).length();
                assert!((r - 1.0).abs() < 0.01, "{r}: reprojection keeps the sphere");
            }
        }
    }
}

#[test]
fn an_open_grid_keeps_its_border() {
    let (mut world, built) = build(&shapes::grid(8, 8));
    remesh(
        &mut world,
        built.mesh,
        &RemeshParams {
            target_length: Some(0.06),
            ..Default::default()
        },
    )
    .unwrap();
    validate(&world, built.mesh).unwrap();
    let s = mesh_stats(&world, built.mesh);
    assert_eq!((s.boundary_loops, s.euler_characteristic), (1, 1));
    let m = MeshRef::new(&world);
    for v in MeshMembers::collect(&world, built.mesh).vertices {
        let p = m.position(v);
        assert!(p.z.abs() < 1e-6);
        if m.is_boundary_vertex(v) {
            assert!(
                [p.x, p.y]
                    .iter()
                    .any(|c| c.abs() < 1e-5 || (c - 1.0).abs() < 1e-5),
                "{p}"
            );
        }
    }
}

/// Fandisk's sharp CAD edges are kept: every feature corner (a vertex with other than two
/// sharp edges, dihedral angle above 45°) is still there at its exact position, every other
/// crease vertex is within L/8 of an edge of the result (collapses along a crease are
/// allowed only where it is straight to L/20), and the mesh stays valid with its χ.
#[test]
fn fandisk_keeps_its_creases() {
    let Some(path) = common::model("fandisk.obj") else {
        return;
    };
    let soup = pappus::io::read(&path).unwrap();
    let (mut world, built) = build(&soup);
    let mesh = built.mesh;
    let chi = mesh_stats(&world, mesh).euler_characteristic;
    let creases = sharp_edges(&world, mesh);
    assert!(creases.len() > 100, "fandisk has long creases");
    let mut degree: std::collections::HashMap<[u32; 3], usize> = Default::default();
    for [a, b] in &creases {
        *degree.entry(key(*a)).or_default() += 1;
        *degree.entry(key(*b)).or_default() += 1;
    }
    let summary = remesh(&mut world, mesh, &RemeshParams::default()).unwrap();
    validate(&world, mesh).unwrap();
    assert_eq!(mesh_stats(&world, mesh).euler_characteristic, chi);
    let m = MeshRef::new(&world);
    let now: std::collections::HashSet<[u32; 3]> = MeshMembers::collect(&world, mesh)
        .vertices
        .into_iter()
        .map(|v| key(m.position(v)))
        .collect();
    let corners: Vec<_> = degree.iter().filter(|(_, d)| **d != 2).collect();
    assert!(corners.len() >= 8, "fandisk has feature corners");
    for (corner, _) in corners {
        assert!(now.contains(corner), "a feature corner moved");
    }
    // The result's edges, all of them: along a crease of about 45° the result's dihedral angle
    // can fall either side of the threshold, since the faces beside the crease change.
    let after: Vec<[Vec3; 2]> = MeshMembers::collect(&world, mesh)
        .edges
        .into_iter()
        .map(|e| {
            let (a, b) = m.edge_vertices(e);
            [m.position(a), m.position(b)]
        })
        .collect();
    let tolerance = summary.target_length / 8.0;
    let mut worst = 0f32;
    for [a, b] in &creases {
        for p in [*a, *b] {
            let near = after
                .iter()
                .map(|&[c, d]| distance_to_segment(p, c, d))
                .fold(f32::MAX, f32::min);
            assert!(
                near <= tolerance,
                "crease vertex {p} is {near} from the result"
            );
            worst = worst.max(near);
        }
    }
    println!(
        "fandisk: crease vertices within {:.4} L of the result",
        worst / summary.target_length
    );
    let share = in_band(&world, mesh, summary.target_length);
    println!("fandisk: {:.1} % of edges in band", share * 100.0);
    assert!(
        share >= 0.95,
        "only {:.1} % of edges in band",
        share * 100.0
    );
}

fn key(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// The ends of every edge whose dihedral angle exceeds 45° (and of every boundary edge).
fn sharp_edges(world: &bevy::prelude::World, mesh: pappus::mesh::MeshId) -> Vec<[Vec3; 2]> {
    let cos_limit = 45f32.to_radians().cos();
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .edges
        .into_iter()
        .filter(|&e| {
            let h = m.edge_halfedge(e);
            let (Some(f), Some(g)) = (m.face(h), m.face(m.twin(h))) else {
                return true;
            };
            let (n0, n1) = (
                m.face_area_vector(f).normalize(),
                m.face_area_vector(g).normalize(),
            );
            n0.dot(n1) < cos_limit
        })
        .map(|e| {
            let (a, b) = m.edge_vertices(e);
            [m.position(a), m.position(b)]
        })
        .collect()
}

fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + ab * t).distance(p)
}
