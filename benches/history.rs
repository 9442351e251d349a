//! What undo costs: recording and undoing a local edit, capturing and restoring a whole mesh,
//! and the memory the history holds against the mesh's own.
//!
//! Uses the shared Stanford bunny when present, else an icosphere of similar size. The memory
//! figures are printed once before the timings: the mesh's own size is the growth of the
//! process's resident memory while a second copy of it is built into entities. Run: `cargo bench --bench
//! history`.

use bevy::prelude::World;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::mesh::change::{LocalRecorder, SavedContents, component_bytes, remapped};
use pappus::mesh::{
    EdgeId, MeshId, MeshInfo, MeshMembers, MeshRef, PolygonSoup, build_mesh, shapes,
};
use pappus::ops::local::{CollapseOptions, collapse_edge, flip_edge};
use pappus::ops::remesh::{RemeshParams, remesh};
use std::path::Path;
use std::time::{Duration, Instant};

fn bunny() -> PolygonSoup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    pappus::io::read(&path).unwrap_or_else(|e| {
        println!("NOTICE: {e}; using icosphere(6) instead");
        shapes::icosphere(6)
    })
}

/// The process's resident memory, in bytes (Linux).
fn resident_bytes() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: usize = statm
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .unwrap_or(0);
    pages * 4096
}

fn interior_edges(world: &World, mesh: MeshId) -> Vec<EdgeId> {
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .edges
        .into_iter()
        .filter(|&e| !m.is_boundary_edge(e))
        .collect()
}

/// Prints the history's size for remeshing, against the mesh's resident size.
fn memory(soup: &PolygonSoup) {
    // A first copy takes the builder's temporary buffers' high-water mark (the allocator
    // keeps them); the growth while building the second copy is one mesh's own memory.
    let mut world = World::new();
    build_mesh(&mut world, soup, MeshInfo::default()).unwrap();
    let before = resident_bytes();
    let mesh = build_mesh(&mut world, soup, MeshInfo::default())
        .unwrap()
        .mesh;
    let own = resident_bytes().saturating_sub(before);
    let components = component_bytes(&world, mesh);
    let mib = |b: usize| b as f64 / (1 << 20) as f64;
    println!(
        "mesh: {:.1} MiB resident, {:.1} MiB of components",
        mib(own),
        mib(components)
    );
    // One remesh of 10 iterations is one entry: the tables before it.
    let one = SavedContents::capture(&world, mesh).bytes();
    println!(
        "history of one remesh (any number of iterations): {:.1} MiB = {:.2}x resident, {:.2}x components",
        mib(one),
        one as f64 / own as f64,
        one as f64 / components as f64
    );
    // Ten remeshes of one iteration each: ten entries.
    let params = RemeshParams {
        iterations: 1,
        ..RemeshParams::default()
    };
    let mut entries = Vec::new();
    for _ in 0..10 {
        entries.push(SavedContents::capture(&world, mesh));
        remesh(&mut world, mesh, &params).unwrap();
    }
    let held: usize = entries.iter().map(SavedContents::bytes).sum();
    println!(
        "history of 10 one-iteration remeshes (10 entries): {:.1} MiB = {:.2}x resident, {:.2}x components",
        mib(held),
        held as f64 / own as f64,
        held as f64 / components as f64
    );
}

fn bench(c: &mut Criterion) {
    let soup = bunny();
    memory(&soup);
    let mut world = World::new();
    let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
        .unwrap()
        .mesh;
    let mut edges = interior_edges(&world, mesh);
    let stride = 7919;
    c.bench_function("flip, recorded, then undone (bunny)", |b| {
        let mut i = 0usize;
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                let e = edges[(i * stride) % edges.len()];
                i += 1;
                let (a, b) = MeshRef::new(&world).edge_vertices(e);
                let recorder = LocalRecorder::begin(&world, mesh, &[a, b]);
                if flip_edge(&mut world, e).is_ok() {
                    recorder.finish(&world).apply(&mut world);
                }
            }
            start.elapsed()
        });
    });
    c.bench_function("collapse, recorded, then undone (bunny)", |b| {
        let mut i = 0usize;
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                let k = (i * stride) % edges.len();
                i += 1;
                let e = edges[k];
                let (a, b) = MeshRef::new(&world).edge_vertices(e);
                let recorder = LocalRecorder::begin(&world, mesh, &[a, b]);
                if collapse_edge(&mut world, e, CollapseOptions::default()).is_ok() {
                    let (_, map, _) = recorder.finish(&world).apply(&mut world);
                    // The edge came back under a new id, and so did its neighbours.
                    for x in &mut edges {
                        x.0 = remapped(&map, x.0);
                    }
                }
            }
            start.elapsed()
        });
    });
    c.bench_function("capture the whole mesh (bunny)", |b| {
        b.iter(|| SavedContents::capture(&world, mesh));
    });
    let mut tables = Some(SavedContents::capture(&world, mesh));
    c.bench_function(
        "restore the whole mesh, undo of a global edit (bunny)",
        |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let t = tables.take().unwrap();
                    let start = Instant::now();
                    let (inverse, _) = t.apply(&mut world);
                    total += start.elapsed();
                    tables = Some(inverse);
                }
                total
            });
        },
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(4));
    targets = bench
}
criterion_main!(benches);
