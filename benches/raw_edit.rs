//! A checked low-level edit's commit on a bunny-sized mesh: a flip written by hand with
//! `RawEdit` and committed (which checks `validate`'s rules on what the edit touched) against
//! the library's `flip_edge` (which plans, then applies, checking only the edge's
//! neighbourhood), and the whole mesh's `validate` alone. Run: `cargo bench --no-default-features --bench raw_edit` (the Stanford
//! bunny from ../shared/models when present, else an icosphere of 81 920 faces).

use bevy::prelude::World;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::mesh::{EdgeId, MeshId, MeshInfo, MeshMembers, RawEdit, build_mesh, shapes, validate};
use pappus::ops::local::flip_edge;
use std::path::Path;
use std::time::Instant;

#[path = "../tests/common/hand_edits.rs"]
mod hand_edits;
use hand_edits::flip_by_hand;

/// The bunny (or the icosphere) and its interior edges that the library flips both ways.
fn mesh() -> (World, MeshId, Vec<EdgeId>) {
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    let soup = match pappus::source::read_source(&bunny) {
        Ok((soup, _)) => soup,
        Err(_) => shapes::icosphere(6),
    };
    let mut world = World::new();
    let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
        .expect("builds")
        .mesh;
    let all = MeshMembers::collect(&world, mesh).edges;
    let edges = all
        .into_iter()
        .step_by(997)
        .filter(|&e| flip_edge(&mut world, e).is_ok() && flip_edge(&mut world, e).is_ok())
        .collect();
    (world, mesh, edges)
}

fn bench(c: &mut Criterion) {
    let (mut world, mesh, edges) = mesh();
    c.bench_function("validate (bunny)", |b| {
        b.iter(|| validate(&world, mesh).expect("valid"));
    });
    c.bench_function("flip by hand + commit (bunny)", |b| {
        let mut i = 0usize;
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                let e = edges[i % edges.len()];
                i += 1;
                for _ in 0..2 {
                    let mut edit = RawEdit::new(&mut world, mesh);
                    flip_by_hand(&mut edit, e).expect("the mesh's elements");
                    edit.commit().expect("a flip the library makes is valid");
                }
            }
            start.elapsed() / 2
        });
    });
    c.bench_function("flip_edge (bunny)", |b| {
        let mut i = 0usize;
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                let e = edges[i % edges.len()];
                i += 1;
                flip_edge(&mut world, e).expect("flips");
                flip_edge(&mut world, e).expect("flips back");
            }
            start.elapsed() / 2
        });
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
