//! A checked low-level edit's commit on a bunny-sized mesh: a flip written by hand with
//! `RawEdit` and committed (which checks the whole mesh with `validate`) against the library's
//! `flip_edge` (which plans, then applies, checking only the edge's neighbourhood), and
//! `validate` alone. Run: `cargo bench --no-default-features --bench raw_edit` (the Stanford
//! bunny from ../shared/models when present, else an icosphere of 81 920 faces).

use bevy::prelude::World;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::mesh::{
    EdgeId, MeshId, MeshInfo, MeshMembers, MeshRef, RawEdit, RawEditError, build_mesh, shapes,
    validate,
};
use pappus::ops::local::flip_edge;
use std::path::Path;
use std::time::Instant;

/// The flip a student writes: the two triangles' halfedges rewired onto the opposite corners.
fn flip_by_hand(edit: &mut RawEdit<'_>, e: EdgeId) -> Result<(), RawEditError> {
    let m = MeshRef::new(edit.world());
    let h = m.edge_halfedge(e);
    let t = m.twin(h);
    let (h1, t1) = (m.next(h), m.next(t));
    let (h2, t2) = (m.next(h1), m.next(t1));
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    let (c, d) = (m.to_vertex(h1), m.to_vertex(t1));
    let (f, g) = (m.face(h).expect("interior"), m.face(t).expect("interior"));
    let (a_out, b_out) = (m.vertex_halfedge(a), m.vertex_halfedge(b));
    edit.set_to_vertex(h, c)?;
    edit.set_to_vertex(t, d)?;
    for (x, y) in [(h, h2), (h2, t1), (t1, h), (t, t2), (t2, h1), (h1, t)] {
        edit.set_next(x, y)?;
    }
    edit.set_face(t1, Some(f))?;
    edit.set_face(h1, Some(g))?;
    edit.set_face_halfedge(f, h)?;
    edit.set_face_halfedge(g, t)?;
    if a_out == h {
        edit.set_vertex_halfedge(a, t1)?;
    }
    if b_out == t {
        edit.set_vertex_halfedge(b, h1)?;
    }
    Ok(())
}

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
