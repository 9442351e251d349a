//! The entity-spawn floor under bulk operations (issue 26): spawning exactly the rows that Loop ×1
//! of the bunny produces (its result's tables, every vertex, halfedge, edge and face with
//! Pappus's components), timed three ways, with median, p90 and max over RUNS runs:
//!
//! - **fresh world**: a new `World` each run, as a process's first subdivision sees it;
//! - **after a mesh of that size**: the same world spawned the mesh, then despawned it, before
//!   the timed spawn (what an editor's undo-then-redo of a subdivision sees);
//! - **Loop ×1 itself**, on a freshly built bunny (reading, subdividing, writing back), beside
//!   the floor from the same run;
//! - **Loop ×1 again after an undo**: the bunny written back into the world Loop ×1 left (as
//!   the editor's undo of a whole-mesh edit does), then Loop ×1 again;
//! - **the kernel's floor**: writing as many fresh pages as the process's first Loop ×1
//!   touched (one byte a page), which is what a fresh process pays before any work.
//!
//! A first row spawns the bunny's own rows, the floor under building a mesh from arrays.
//!
//! Every row is timed twice: with glibc's allocator as it comes, then as the `pappus` program
//! sets it ([`pappus::process_memory::keep_freed_memory`]: freed memory kept for reuse).
//!
//! Run: `cargo bench --bench spawn_floor` (uses `../shared/models/stanford-bunny.obj`, or an
//! icosphere of similar size with a notice).

use bevy::prelude::World;
use pappus::mesh::tables::{Connectivity, extract, spawn_connectivity};
use pappus::mesh::{MeshId, MeshInfo, PolygonSoup, build_mesh, despawn_mesh, shapes};
use pappus::ops::subdivide::loop_subdivide;
use pappus::process_memory::keep_freed_memory;
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

/// Page faults this process has taken that needed no disk (`/proc/self/stat`'s `minflt`): one
/// per fresh page touched.
fn minor_faults() -> u64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // The fields after the command name (which may hold spaces); minflt is the 10th of the line.
    stat.rfind(')')
        .and_then(|at| stat[at + 2..].split_whitespace().nth(7)?.parse().ok())
        .unwrap_or(0)
}

/// Milliseconds to touch `pages` fresh pages of a new block, one byte each.
fn fault_in_ms(pages: usize) -> f64 {
    const PAGE: usize = 4096;
    let start = Instant::now();
    let mut block: Vec<u8> = Vec::with_capacity(pages * PAGE);
    for page in block.spare_capacity_mut().chunks_mut(PAGE) {
        page[0].write(1);
    }
    black_box(&block);
    start.elapsed().as_secs_f64() * 1e3
}

/// A new world holding the bunny, and its mesh.
fn bunny_world(soup: &PolygonSoup) -> (World, MeshId) {
    let mut world = World::new();
    let mesh = build_mesh(&mut world, soup, MeshInfo::default())
        .unwrap()
        .mesh;
    (world, mesh)
}

/// Milliseconds of Loop ×1 of `mesh`.
fn loop_ms(world: &mut World, mesh: MeshId) -> f64 {
    let start = Instant::now();
    loop_subdivide(world, mesh, 1).unwrap();
    start.elapsed().as_secs_f64() * 1e3
}

/// Every row, under the allocator settings of the moment.
fn rows(soup: &PolygonSoup, loop_tables: &Connectivity, fresh_pages: usize) {
    let bunny_tables = {
        let (world, mesh) = bunny_world(soup);
        extract(&world, mesh).tables
    };
    row(
        "spawn the bunny's own rows (what `pappus.Mesh(v, f)` spawns), world that held them",
        timed(|| {
            let mut world = World::new();
            let (mesh, _) = spawn_connectivity(&mut world, &bunny_tables, MeshInfo::default());
            despawn_mesh(&mut world, mesh);
            spawn_ms(&mut world, &bunny_tables)
        }),
    );
    row(
        "spawn the rows, fresh world",
        timed(|| spawn_ms(&mut World::new(), loop_tables)),
    );
    row(
        "spawn the rows, after a mesh of that size",
        timed(|| {
            let mut world = World::new();
            let (mesh, _) = spawn_connectivity(&mut world, loop_tables, MeshInfo::default());
            despawn_mesh(&mut world, mesh);
            spawn_ms(&mut world, loop_tables)
        }),
    );
    let mut again = Vec::with_capacity(RUNS);
    let first = timed(|| {
        let (mut world, mesh) = bunny_world(soup);
        let first = loop_ms(&mut world, mesh);
        // The undo: the bunny written back in place of the subdivided mesh.
        despawn_mesh(&mut world, mesh);
        let mesh = build_mesh(&mut world, soup, MeshInfo::default())
            .unwrap()
            .mesh;
        again.push(loop_ms(&mut world, mesh));
        first
    });
    row("Loop x1 (read, subdivide, write back)", first);
    row("Loop x1 again, after an undo in the same world", again);
    row(
        &format!(
            "the kernel's floor: write to {} MB of newly allocated memory",
            (fresh_pages * 4096) >> 20
        ),
        timed(|| fault_in_ms(fresh_pages)),
    );
}

fn main() {
    let soup = bunny();
    // The tables Loop ×1 produces, and how many fresh pages the process's first Loop ×1 took.
    let (loop_tables, fresh_pages) = {
        let (mut world, mesh) = bunny_world(&soup);
        let before = minor_faults();
        loop_subdivide(&mut world, mesh, 1).unwrap();
        let pages = (minor_faults() - before) as usize;
        (extract(&world, mesh).tables, pages)
    };
    let rows_spawned = loop_tables.vertex_count()
        + loop_tables.halfedge_count()
        + loop_tables.edge_count()
        + loop_tables.face_count();
    println!(
        "Loop x1 of the bunny: {rows_spawned} rows; the process's first Loop x1 touched {} MB \
         of fresh pages; median / p90 / max of {RUNS} runs, ms",
        (fresh_pages * 4096) >> 20
    );
    println!();
    println!("| what | median | p90 | max |");
    println!("|---|---:|---:|---:|");
    println!("| **glibc's defaults** | | | |");
    rows(&soup, &loop_tables, fresh_pages);
    if keep_freed_memory() {
        println!("| **freed memory kept, as `pappus` sets it** | | | |");
        rows(&soup, &loop_tables, fresh_pages);
    }
}
