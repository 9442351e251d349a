//! The cost of the entity design: building a mesh into entities, and walking every one-ring;
//! and the cost of the editor's autosave (the copy on the frame, the write on its thread).
//!
//! Uses the shared Stanford bunny (`../shared/models/stanford-bunny.obj`, 35 947 vertices,
//! 69 451 faces) when present, else an icosphere of similar size. Run: `cargo bench --bench
//! mesh_core`.

use bevy::prelude::World;
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pappus::mesh::{MeshInfo, MeshMembers, MeshRef, PolygonSoup, build_mesh, shapes};
use std::hint::black_box;
use std::path::Path;

fn bunny() -> (String, PolygonSoup) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    match pappus::io::read(&path) {
        Ok(soup) => ("bunny".into(), soup),
        Err(e) => {
            println!("NOTICE: {e}; benchmarking icosphere(6) instead");
            ("icosphere6".into(), shapes::icosphere(6))
        }
    }
}

fn bench(c: &mut Criterion) {
    let (name, soup) = bunny();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    if path.exists() {
        c.bench_function("read bunny.obj", |b| {
            b.iter(|| black_box(pappus::io::read(&path).unwrap()));
        });
    }
    c.bench_function(&format!("build {name} into entities"), |b| {
        b.iter_batched(
            World::new,
            |mut world| {
                let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
                black_box(built.mesh);
                world
            },
            BatchSize::LargeInput,
        );
    });
    let mut world = World::new();
    let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
        .unwrap()
        .mesh;
    let vertices = MeshMembers::collect(&world, mesh).vertices;
    c.bench_function(&format!("circulate every one-ring of {name}"), |b| {
        b.iter(|| {
            let m = MeshRef::new(&world);
            let mut sum = 0usize;
            for &v in &vertices {
                for n in m.vertex_neighbors(v) {
                    sum += n.0.index_u32() as usize & 1;
                }
            }
            black_box(sum)
        });
    });
    c.bench_function(&format!("validate {name}"), |b| {
        b.iter(|| black_box(pappus::mesh::validate(&world, mesh).is_ok()));
    });
    // Saving reads the mesh into a soup element by element; the editor's autosave reads its
    // tables on the frame (the part that holds a frame) and makes the soup on its thread.
    c.bench_function(&format!("copy {name} into a soup (saving)"), |b| {
        b.iter(|| black_box(pappus::mesh::to_soup(&world, mesh)));
    });
    c.bench_function(
        &format!("read {name}'s tables (autosave, on the frame)"),
        |b| {
            b.iter(|| black_box(pappus::mesh::tables::extract(&world, mesh)));
        },
    );
    let tables = pappus::mesh::tables::extract(&world, mesh).tables;
    c.bench_function(
        &format!("the soup of {name}'s tables (autosave thread)"),
        |b| {
            b.iter(|| black_box(pappus::mesh::soup_of_tables(&tables)));
        },
    );
    // The autosave's thread: the recovery written (binary PLY and its description), synced.
    let folder = std::env::temp_dir().join(format!("pappus-bench-recovery-{}", std::process::id()));
    let copy = pappus::mesh::to_soup(&world, mesh);
    let info = pappus::recovery::RecoveryInfo {
        source: None,
        name: name.clone(),
        saved_at: 0.0,
        pid: std::process::id(),
        vertices: copy.positions.len(),
        faces: copy.face_count(),
    };
    c.bench_function(
        &format!("write {name}'s recovery file (autosave thread)"),
        |b| {
            b.iter(|| black_box(pappus::recovery::write(&folder, "bench", &copy, &info).unwrap()));
        },
    );
    let _ = std::fs::remove_dir_all(&folder);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
