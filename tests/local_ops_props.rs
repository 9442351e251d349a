//! Random sequences of flips, splits, collapses (with and without the normal check), dissolves
//! and face splits on random shapes (closed and open, triangles, quads and both mixed): the mesh
//! validates after every step, χ never changes (every one of them preserves it), and a refused
//! operation changes no count. 256 cases × 400 operations = 102 400 operations per run.

mod common;

use bevy::prelude::World;
use pappus::mesh::MeshRef;
use pappus::mesh::{MeshId, MeshMembers, PolygonSoup, mesh_stats, shapes, validate};
use pappus::ops::local::{
    CollapseOptions, bisect_edge, collapse_edge, dissolve_edge, flip_edge, split_edge, split_face,
};
use proptest::prelude::*;

/// The shapes a case starts from (`SHAPES` of them).
fn shape(i: u8) -> PolygonSoup {
    match i % SHAPES {
        0 => shapes::icosphere(1),
        1 => shapes::torus(6, 5),
        2 => shapes::grid(4, 3),
        3 => shapes::quad_grid(4, 4),
        4 => shapes::tetrahedron(),
        5 => shapes::grid_with_holes(2),
        6 => shapes::icosphere(2),
        7 => shapes::cube(),
        _ => checkerboard(),
    }
}

const SHAPES: u8 = 9;

/// A 4 × 4 quad grid with every other cell split into two triangles: quads and triangles mixed.
fn checkerboard() -> PolygonSoup {
    let quads = shapes::quad_grid(4, 4);
    let mut out = PolygonSoup::from_faces::<[u32; 3]>(quads.positions.clone(), &[]);
    for (i, f) in quads.faces().enumerate() {
        if (i + i / 4) % 2 == 0 {
            out.push_face(f);
        } else {
            out.push_face(&[f[0], f[1], f[2]]);
            out.push_face(&[f[0], f[2], f[3]]);
        }
    }
    out
}

fn counts(world: &World, mesh: MeshId) -> (usize, usize, usize) {
    let m = MeshMembers::collect(world, mesh);
    (m.vertices.len(), m.edges.len(), m.faces.len())
}

proptest! {
    #![proptest_config(common::proptest_config())]

    #[test]
    fn random_local_edits_keep_the_mesh_valid(
        which in 0u8..SHAPES,
        ops in proptest::collection::vec((0u8..7, any::<u32>(), common::edge_fraction()), 400),
    ) {
        let (mut world, built) = common::build(&shape(which));
        let mesh = built.mesh;
        let chi = mesh_stats(&world, mesh).euler_characteristic;
        let mut edges = MeshMembers::collect(&world, mesh).edges;
        for (kind, pick, t) in ops {
            if edges.is_empty() {
                break;
            }
            let e = edges[pick as usize % edges.len()];
            let before = counts(&world, mesh);
            let applied = match kind {
                0 => flip_edge(&mut world, e).is_ok(),
                1 => split_edge(&mut world, e, t).is_ok(),
                2 => collapse_edge(&mut world, e, CollapseOptions::default()).is_ok(),
                3 => dissolve_edge(&mut world, e).is_ok(),
                6 => bisect_edge(&mut world, e, t).is_ok(),
                4 => {
                    // A collapse towards a point along the edge, refused if a face turns over.
                    let m = MeshRef::new(&world);
                    let (a, b) = m.edge_vertices(e);
                    let options = CollapseOptions {
                        position: Some(m.position(a).lerp(m.position(b), t)),
                        max_normal_change_deg: Some(60.0),
                    };
                    collapse_edge(&mut world, e, options).is_ok()
                }
                _ => {
                    // Join the corners two apart in the face of the edge's halfedge.
                    let m = MeshRef::new(&world);
                    let h = m.edge_halfedge(e);
                    match m.face(h) {
                        Some(f) => {
                            let (a, b) = (m.to_vertex(h), m.to_vertex(m.next(m.next(h))));
                            split_face(&mut world, f, a, b).is_ok()
                        }
                        None => false,
                    }
                }
            };
            if let Err(invalid) = validate(&world, mesh) {
                prop_assert!(false, "op {kind} on {e} broke the mesh: {invalid}");
            }
            if applied {
                let (v, ed, f) = counts(&world, mesh);
                prop_assert_eq!(v as i64 - ed as i64 + f as i64, chi);
                if kind != 0 {
                    edges = MeshMembers::collect(&world, mesh).edges;
                }
            } else {
                prop_assert_eq!(counts(&world, mesh), before);
            }
        }
    }
}
