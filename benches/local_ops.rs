//! Local operations must cost O(1), whatever the mesh size: flip, split and collapse timed on
//! a ~10k-face and a ~1M-face triangle grid. Run: `cargo bench --bench local_ops`.

use bevy::prelude::World;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::mesh::{EdgeId, MeshInfo, MeshMembers, MeshRef, build_mesh, shapes};
use pappus::ops::local::{CollapseOptions, collapse_edge, flip_edge, split_edge};
use std::time::{Duration, Instant};

fn interior_edges(world: &World, mesh: pappus::mesh::MeshId) -> Vec<EdgeId> {
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .edges
        .into_iter()
        .filter(|&e| !m.is_boundary_edge(e))
        .collect()
}

fn bench(c: &mut Criterion) {
    for (label, n) in [("10k faces", 70u32), ("1M faces", 707)] {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &shapes::grid(n, n), MeshInfo::default())
            .unwrap()
            .mesh;
        let edges = interior_edges(&world, mesh);
        // A stride through the edge list touches the mesh all over, as a user or an algorithm
        // would; flipping twice restores the mesh, so the flip bench can run forever.
        let stride = 7919;
        c.bench_function(&format!("flip ({label})"), |b| {
            let mut i = 0usize;
            b.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    let e = edges[(i * stride) % edges.len()];
                    let _ = flip_edge(&mut world, e);
                    let _ = flip_edge(&mut world, e);
                    i += 1;
                }
                start.elapsed() / 2
            });
        });
        c.bench_function(&format!("split ({label})"), |b| {
            let mut i = 0usize;
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let e = edges[(i * stride) % edges.len()];
                    i += 1;
                    let start = Instant::now();
                    let _ = split_edge(&mut world, e, 0.5);
                    total += start.elapsed();
                }
                total
            });
        });
        let mut candidates = interior_edges(&world, mesh);
        c.bench_function(&format!("collapse ({label})"), |b| {
            let mut i = 0usize;
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    if candidates.is_empty() {
                        candidates = interior_edges(&world, mesh);
                    }
                    let e = candidates.swap_remove((i * stride) % candidates.len());
                    i += 1;
                    if world.get_entity(e.0).is_err() {
                        continue;
                    }
                    let start = Instant::now();
                    let _ = collapse_edge(&mut world, e, CollapseOptions::default());
                    total += start.elapsed();
                }
                total
            });
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
