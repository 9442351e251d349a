//! The entity-spawn floor under bulk operations (issue 26): spawning exactly the rows that Loop ×1
//! of the bunny produces (its result's tables, every vertex, halfedge, edge and face with
//! Pappus's components), timed three ways, with median, p90 and max over RUNS runs:
//!
//! - **fresh world**: a new `World` each run, as a process's first subdivision sees it;
//! - **after a mesh of that size**: the same world spawned the mesh, then despawned it, before
//!   the timed spawn (what an editor's undo-then-redo of a subdivision sees);
//! - **Loop ×1 itself**, on a freshly built bunny (reading, subdividing, writing back), beside
//!   the floor from the same run.
//!
//! Run: `cargo bench --bench spawn_floor` (uses `../shared/models/stanford-bunny.obj`, or an
//! icosphere of similar size with a notice).

use bevy::prelude::World;
use pappus::mesh::tables::{Connectivity, extract, spawn_connectivity};
use pappus::mesh::{MeshInfo, PolygonSoup, build_mesh, despawn_mesh, shapes};
use pappus::ops::subdivide::loop_subdivide;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

const RUNS: usize = 15;

fn bunny() -> PolygonSoup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    pappus::io::read(&path).unwrap_or_else(|e| {
        println!("NOTICE: {e}; using shape:icosphere:6 instead");
        shapes::icosphere(6)
    })
}

/// Median, p90 and max of `times` (ms), as a table row.
fn row(name: &str, mut times: Vec<f64>) {
    times.sort_by(f64::total_cmp);
    let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
    println!(
        "| {name} | {:.1} | {:.1} | {:.1} |",
        at(0.5),
        at(0.9),
        times[times.len() - 1]
    );
}

/// Milliseconds to spawn `tables` as a new mesh of `world`.
fn spawn_ms(world: &mut World, tables: &Connectivity) -> f64 {
    let start = Instant::now();
    black_box(spawn_connectivity(world, tables, MeshInfo::default()));
    start.elapsed().as_secs_f64() * 1e3
}

fn timed(mut run: impl FnMut() -> f64) -> Vec<f64> {
    (0..RUNS).map(|_| run()).collect()
}

fn main() {
    let soup = bunny();
    // The tables Loop ×1 produces.
    let loop_tables: Connectivity = {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        loop_subdivide(&mut world, mesh, 1).unwrap();
        extract(&world, mesh).tables
    };
    let rows = loop_tables.vertex_count()
        + loop_tables.halfedge_count()
        + loop_tables.edge_count()
        + loop_tables.face_count();
    println!("Loop x1 of the bunny: {rows} rows; median / p90 / max of {RUNS} runs, ms");
    println!();
    println!("| what | median | p90 | max |");
    println!("|---|---:|---:|---:|");
    row(
        "spawn the rows, fresh world",
        timed(|| spawn_ms(&mut World::new(), &loop_tables)),
    );
    row(
        "spawn the rows, after a mesh of that size",
        timed(|| {
            let mut world = World::new();
            let (mesh, _) = spawn_connectivity(&mut world, &loop_tables, MeshInfo::default());
            despawn_mesh(&mut world, mesh);
            spawn_ms(&mut world, &loop_tables)
        }),
    );
    row(
        "Loop x1 (read, subdivide, write back)",
        timed(|| {
            let mut world = World::new();
            let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
                .unwrap()
                .mesh;
            let start = Instant::now();
            loop_subdivide(&mut world, mesh, 1).unwrap();
            start.elapsed().as_secs_f64() * 1e3
        }),
    );
}
