//! Where the bytes of a loaded mesh go (issue 40): heap bytes counted by a global allocator
//! while a mesh is read, built into a `World` and written back as binary PLY, then the World's
//! bytes per element, and per kind what an entity of that kind costs on its own.
//!
//! - **phases**: the soup as read; the build's peak above it (the repaired faces, the
//!   connectivity tables, the spawned rows) and what it leaves (the World, the input numbering);
//!   the save's peak (the soup read back out of the World, the file's bytes);
//! - **per kind**: a fresh World holding as many entities of one kind as the mesh has (and one
//!   holding as many entities as the mesh has elements, with no component: the entity floor),
//!   heap bytes per entity, beside the components' own sizes: what is left is Bevy's per-row
//!   bookkeeping (the entity's location, change ticks) and the capacity its tables and entity
//!   list hold spare after growing.
//!
//! Each phase also gives the process's resident high-water mark, which `/usr/bin/time` reports:
//! the live bytes plus what the allocator holds (freed blocks kept for reuse, as the `pappus`
//! program asks of it; `--no-keep` measures glibc's defaults instead).
//!
//! Run: `cargo bench --bench world_bytes [-- MESH] [--no-keep]` (default `shape:icosphere:8`,
//! 1.3 M triangles; any file Pappus reads).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use bevy::ecs::bundle::NoBundleEffect;
use bevy::math::Vec3;
use bevy::prelude::{Bundle, Entity, World};
use pappus::io::{Format, write_bytes};
use pappus::mesh::ids::{EdgeId, HalfedgeId, MeshId, VertexId};
use pappus::mesh::{
    Edge, Face, Halfedge, InMesh, MeshInfo, MeshMembers, Position, Vertex, build_mesh, shapes,
    to_soup,
};

/// The system allocator, counting the bytes live and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    let now = LIVE.fetch_add(bytes, Relaxed) + bytes;
    PEAK.fetch_max(now, Relaxed);
}

// SAFETY: every call is forwarded to `System` with the same arguments; the counters only watch.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grew(layout.size());
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        grew(layout.size());
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_sub(layout.size(), Relaxed);
        grew(new_size);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn live() -> usize {
    LIVE.load(Relaxed)
}

/// Starts a new peak from the bytes live now.
fn reset_peak() -> usize {
    let now = live();
    PEAK.store(now, Relaxed);
    now
}

/// The process's resident high-water mark (`VmHWM`), in MiB: what `/usr/bin/time` reports as
/// the peak, the allocator's kept and scattered pages included (0 where `/proc` is missing).
fn resident_high_water_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kb.unwrap_or(0.0) / 1024.0
}

fn mb(bytes: usize) -> f64 {
    bytes as f64 / (1 << 20) as f64
}

/// Heap bytes per entity of a fresh World holding `n` entities made by `bundle`.
fn bytes_per_entity<B: Bundle<Effect: NoBundleEffect>>(n: usize, bundle: impl Fn() -> B) -> f64 {
    let before = live();
    let mut world = World::new();
    let empty = live();
    world.spawn_batch((0..n).map(|_| bundle()));
    let bytes = live() - empty;
    drop(world);
    assert!(live() <= before + 4096, "the World's bytes came back");
    bytes as f64 / n as f64
}

fn main() {
    let arg = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    // As the `pappus` program runs, unless told not to: freed memory kept for reuse.
    let kept =
        !std::env::args().any(|a| a == "--no-keep") && pappus::process_memory::keep_freed_memory();
    let source = arg.unwrap_or_else(|| "shape:icosphere:8".into());
    let start = live();
    let soup = match source.strip_prefix("shape:icosphere:") {
        Some(level) => shapes::icosphere(level.parse().expect("a level")),
        None => pappus::io::read(std::path::Path::new(&source)).expect("a mesh file"),
    };
    let soup_bytes = live() - start;
    let faces = soup.face_count();
    println!("{source}: {faces} faces, freed memory kept: {kept}");
    println!("| phase | MB | bytes per face | resident high-water MB |");
    println!("|---|---:|---:|---:|");
    let row = |name: &str, bytes: usize| {
        println!(
            "| {name} | {:.1} | {:.0} | {:.0} |",
            mb(bytes),
            bytes as f64 / faces as f64,
            resident_high_water_mb()
        );
    };
    row("the soup as read", soup_bytes);

    let mut world = World::new();
    let base = reset_peak();
    let built = build_mesh(&mut world, &soup, MeshInfo::default()).expect("a mesh");
    row("build: peak above the soup", PEAK.load(Relaxed) - base);
    let numbering = built.input_vertices.capacity() * size_of::<Option<VertexId>>();
    row("… left: the World and the input numbering", live() - base);
    row("… of which the input numbering", numbering);
    let world_bytes = live() - base - numbering;
    drop(soup);
    let members = MeshMembers::collect(&world, built.mesh);
    let counts = [
        members.vertices.len(),
        members.halfedges.len(),
        members.edges.len(),
        members.faces.len(),
    ];
    drop(members);
    let save_base = reset_peak();
    let out = to_soup(&world, built.mesh);
    let bytes = write_bytes(Format::Ply, &out).expect("PLY writes");
    row(
        "save: peak above the World (soup out, file bytes)",
        PEAK.load(Relaxed) - save_base,
    );
    drop((out, bytes));
    let elements: usize = counts.iter().sum();
    println!(
        "\nthe World: {:.1} MB for {} vertices, {} halfedges, {} edges, {} faces: \
         {:.1} bytes per element, {:.0} per face",
        mb(world_bytes),
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        world_bytes as f64 / elements as f64,
        world_bytes as f64 / faces as f64
    );
    drop(world);

    // Each kind on its own, as many as the mesh has of it, in a fresh World (so each table and
    // the entity list grow as they did there); the floor: as many entities as the mesh has
    // elements, with no component.
    let [vertices, halfedges, edges, faces_n] = counts;
    let mesh = InMesh(MeshId(Entity::PLACEHOLDER));
    let h = HalfedgeId(Entity::PLACEHOLDER);
    let halfedge = Halfedge {
        twin: h,
        next: h,
        prev: h,
        vertex: VertexId(Entity::PLACEHOLDER),
        edge: EdgeId(Entity::PLACEHOLDER),
        face: None,
    };
    println!("\n| entity | components' bytes | heap bytes per entity | per-row bookkeeping |");
    println!("|---|---:|---:|---:|");
    let kind = |name: &str, own: usize, measured: f64| {
        println!(
            "| {name} | {own} | {measured:.1} | {:.1} |",
            measured - own as f64
        );
    };
    kind("no component", 0, bytes_per_entity(elements, || ()));
    kind(
        "InMesh only",
        size_of::<InMesh>(),
        bytes_per_entity(elements, || mesh),
    );
    kind(
        "vertex: Vertex, Position, InMesh",
        size_of::<(Vertex, Position, InMesh)>(),
        bytes_per_entity(vertices, || {
            (Vertex { halfedge: h }, Position(Vec3::ZERO), mesh)
        }),
    );
    kind(
        "halfedge: Halfedge, InMesh",
        size_of::<Halfedge>() + size_of::<InMesh>(),
        bytes_per_entity(halfedges, || (halfedge, mesh)),
    );
    kind(
        "edge: Edge, InMesh",
        size_of::<Edge>() + size_of::<InMesh>(),
        bytes_per_entity(edges, || (Edge { halfedge: h }, mesh)),
    );
    kind(
        "face: Face, InMesh",
        size_of::<Face>() + size_of::<InMesh>(),
        bytes_per_entity(faces_n, || (Face { halfedge: h }, mesh)),
    );
}
