//! The remesh's results pinned to the bit: a fingerprint of the mesh each input remeshes to,
//! recorded from the loop before it was split into passes ([`super::RemeshRun`]), so that no
//! refactoring of the loop can change a result unnoticed.
//!
//! The fingerprint sees the mesh up to relabeling: the sorted bit patterns of the vertex
//! positions, then every face as the cycle of its corners' bit patterns rotated to start at the
//! smallest, the faces sorted (orientation kept), hashed with 64-bit FNV-1a (stable across
//! Rust versions, unlike `DefaultHasher`).

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::MeshId;
use crate::mesh::{MeshInfo, PolygonSoup, build_mesh, mesh_stats, shapes, to_soup, validate};

use super::{RemeshParams, RemeshSummary, remesh};

/// A mesh up to relabeling: its vertex and face counts and the FNV-1a hash of its canonical
/// form (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Fingerprint {
    /// The vertex count.
    pub vertices: usize,
    /// The face count.
    pub faces: usize,
    /// The hash of the canonical form.
    pub hash: u64,
}

/// The fingerprint of `mesh` as it is in `world`.
pub(super) fn fingerprint(world: &World, mesh: MeshId) -> Fingerprint {
    let soup = to_soup(world, mesh);
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut points: Vec<[u32; 3]> = soup.positions.iter().map(|&p| key(p)).collect();
    points.sort_unstable();
    let mut faces: Vec<Vec<[u32; 3]>> = soup
        .faces()
        .map(|f| {
            let corners: Vec<[u32; 3]> =
                f.iter().map(|&i| key(soup.positions[i as usize])).collect();
            let start = (0..corners.len()).min_by_key(|&i| corners[i]).unwrap_or(0);
            corners[start..]
                .iter()
                .chain(&corners[..start])
                .copied()
                .collect()
        })
        .collect();
    faces.sort_unstable();
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |word: u32| {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    points.iter().flatten().for_each(|&w| eat(w));
    for face in &faces {
        // The length first, so that the cycles cannot run into each other.
        eat(face.len() as u32);
        face.iter().flatten().for_each(|&w| eat(w));
    }
    Fingerprint {
        vertices: soup.positions.len(),
        faces: faces.len(),
        hash,
    }
}

/// One pinned input: a name, the soup and the parameters.
pub(super) struct Case {
    /// What the pinned results call it.
    pub name: &'static str,
    /// The input.
    pub soup: PolygonSoup,
    /// How it is remeshed.
    pub params: RemeshParams,
}

/// The inputs whose results are pinned: the cube (feature lines and corners), a wavy open
/// grid (a boundary, and a curved surface to project onto), and, when the shared models are
/// there (`../shared/models/`; skipped, with a notice, when not), fandisk (CAD creases) and
/// the Stanford bunny (holes, scanner noise), with the default parameters.
pub(super) fn cases() -> Vec<Case> {
    let mut wavy = shapes::grid(10, 10);
    for p in &mut wavy.positions {
        p.z = 0.1 * (5.0 * p.x).sin() * (3.0 * p.y).cos();
    }
    let mut cases = vec![
        Case {
            name: "cube",
            soup: shapes::triangulate_fans(&shapes::cube()),
            params: RemeshParams {
                target_length: Some(0.3),
                ..Default::default()
            },
        },
        Case {
            name: "wavy grid",
            soup: wavy,
            params: RemeshParams {
                target_length: Some(0.07),
                iterations: 4,
                ..Default::default()
            },
        },
    ];
    for (name, file) in [("fandisk", "fandisk.obj"), ("bunny", "stanford-bunny.obj")] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/models")
            .join(file);
        if path.is_file() {
            cases.push(Case {
                name,
                soup: crate::io::read(&path).expect("the shared model reads"),
                params: RemeshParams::default(),
            });
        } else if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") {
            panic!(
                "{} is absent, and under CI=true a test may not pass by skipping",
                path.display()
            );
        } else {
            println!("NOTICE: {} is absent; {name} is skipped", path.display());
        }
    }
    cases
}

/// `case`'s input built into a fresh world.
pub(super) fn built(case: &Case) -> (World, MeshId) {
    let mut world = World::new();
    let mesh = build_mesh(&mut world, &case.soup, MeshInfo::default())
        .expect("builds")
        .mesh;
    (world, mesh)
}

/// What each case remeshes to: the summary's splits, collapses and flips, and the result's
/// fingerprint. Pinned again when the collapse pass moved onto flat tables: its collapses are
/// the same, element for element, but the survivors lie in another storage order, so the
/// later passes meet the edges in another order. Pinned again when the finish began fitting
/// the vertices to the input (`fit.rs`): the same counts, the positions moved; and when the
/// relaxation's target became the centre of mass of the fan (`relax.rs`): other splits,
/// collapses and flips follow; and when the finish began pulling corners towards the far
/// spots left after the fit (`far_spots.rs`): the bunny's positions moved.
const PINNED: [(&str, [usize; 3], Fingerprint); 4] = [
    (
        "cube",
        [462, 134, 361],
        Fingerprint {
            vertices: 336,
            faces: 668,
            hash: 0xf8ea6f3225a12cfa,
        },
    ),
    (
        "wavy grid",
        [336, 176, 83],
        Fingerprint {
            vertices: 281,
            faces: 480,
            hash: 0x8780f487f54c377a,
        },
    ),
    (
        "fandisk",
        [1698, 2055, 1553],
        Fingerprint {
            vertices: 6118,
            faces: 12232,
            hash: 0xa052170cc7667018,
        },
    ),
    (
        "bunny",
        [6609, 11493, 6404],
        Fingerprint {
            vertices: 29950,
            faces: 59633,
            hash: 0xe70b7a4de70a3651,
        },
    ),
];

/// The pinned summary counts and fingerprint of the case named `name`.
pub(super) fn pinned(name: &str) -> ([usize; 3], Fingerprint) {
    let (_, counts, print) = PINNED
        .iter()
        .find(|(n, ..)| *n == name)
        .expect("every case is pinned");
    (*counts, *print)
}

/// The summary's splits, collapses and flips.
pub(super) fn counts(s: &RemeshSummary) -> [usize; 3] {
    [s.splits, s.collapses, s.flips]
}

#[test]
fn every_case_remeshes_to_its_pinned_result_to_the_bit() {
    let mut results = Vec::new();
    for case in cases() {
        let (mut world, mesh) = built(&case);
        let chi = mesh_stats(&world, mesh).euler_characteristic;
        let summary = remesh(&mut world, mesh, &case.params).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(mesh_stats(&world, mesh).euler_characteristic, chi);
        let print = fingerprint(&world, mesh);
        println!(
            "{}: {:?} {print:?} ({:.4})",
            case.name,
            counts(&summary),
            summary.target_length
        );
        results.push((case.name, counts(&summary), print));
    }
    // All printed before the first mismatch fails.
    for (name, counts, print) in results {
        assert_eq!((counts, print), pinned(name), "{name}");
    }
}

#[test]
fn the_fingerprint_sees_one_bit_and_not_the_labels() {
    let soup = shapes::triangulate_fans(&shapes::cube());
    let mut world = World::new();
    let a = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
    // The same faces listed the other way round, with the vertices renumbered backwards.
    let n = soup.positions.len() as u32;
    let mut reversed: Vec<[u32; 3]> = soup
        .faces()
        .map(|f| [f[1], f[2], f[0]].map(|i| n - 1 - i))
        .collect();
    reversed.reverse();
    let positions = soup.positions.iter().rev().copied().collect();
    let b = build_mesh(
        &mut world,
        &PolygonSoup::from_faces(positions, &reversed),
        MeshInfo::default(),
    )
    .unwrap();
    let print = fingerprint(&world, a.mesh);
    assert_eq!((print.vertices, print.faces), (8, 12));
    assert_eq!(print, fingerprint(&world, b.mesh));
    // One position's last bit.
    let v = b.input_vertices[0].unwrap();
    let mut p = world.get_mut::<crate::mesh::Position>(v.0).unwrap();
    p.0.x = f32::from_bits(p.0.x.to_bits() ^ 1);
    assert_ne!(print, fingerprint(&world, b.mesh));
}
