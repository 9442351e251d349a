//! The whole-mesh operations against the targets of their issues: Loop ×1 / ×2 on the bunny,
//! Catmull–Clark ×1 on beast, QEM simplification of the bunny to 25 % and 10 % of its faces,
//! and the progressive mesh (record the history while simplifying, refine all the way back,
//! one slider step of 1 % of the faces).
//!
//! Every figure includes reading the mesh out of the world and writing the result back into
//! entities; the world is rebuilt outside the timing. Uses the shared models
//! (`../shared/models/`); a model that is missing is replaced by a procedural shape of similar
//! size, with a notice. Run: `cargo bench --bench global_ops [FILTER]`.

use bevy::prelude::World;
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pappus::mesh::{MeshId, MeshInfo, PolygonSoup, build_mesh, shapes};
use pappus::ops::progressive::ProgressiveMesh;
use pappus::ops::simplify::{SimplifyParams, simplify};
use pappus::ops::subdivide::{catmull_clark, loop_subdivide};
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

fn model(name: &str, fallback: fn() -> PolygonSoup) -> PolygonSoup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/models")
        .join(name);
    pappus::io::read(&path).unwrap_or_else(|e| {
        println!("NOTICE: {e}; using a procedural shape instead");
        fallback()
    })
}

fn built(soup: &PolygonSoup) -> (World, MeshId) {
    let mut world = World::new();
    let mesh = build_mesh(&mut world, soup, MeshInfo::default())
        .unwrap()
        .mesh;
    (world, mesh)
}

/// Times `op` on a freshly built copy of `soup` each iteration.
fn on_fresh_mesh(
    c: &mut Criterion,
    name: &str,
    soup: &PolygonSoup,
    op: impl Fn(&mut World, MeshId),
) {
    c.bench_function(name, |b| {
        b.iter_batched(
            || built(soup),
            |(mut world, mesh)| {
                op(&mut world, mesh);
                world
            },
            BatchSize::LargeInput,
        );
    });
}

fn bench(c: &mut Criterion) {
    let bunny = model("stanford-bunny.obj", || shapes::icosphere(6));
    let beast = model("beast.obj", || shapes::icosphere(5));

    on_fresh_mesh(c, "loop x1 (bunny)", &bunny, |world, mesh| {
        black_box(loop_subdivide(world, mesh, 1).unwrap());
    });
    on_fresh_mesh(c, "loop x2 (bunny)", &bunny, |world, mesh| {
        black_box(loop_subdivide(world, mesh, 2).unwrap());
    });
    on_fresh_mesh(c, "catmull-clark x1 (beast)", &beast, |world, mesh| {
        black_box(catmull_clark(world, mesh, 1).unwrap());
    });
    let faces = bunny.face_count();
    for ratio in [0.25, 0.1] {
        on_fresh_mesh(
            c,
            &format!("simplify to {} % (bunny)", ratio * 100.0),
            &bunny,
            |world, mesh| {
                black_box(simplify(world, mesh, &SimplifyParams::ratio(ratio)).unwrap());
            },
        );
    }
    on_fresh_mesh(
        c,
        "progressive: record while simplifying to 1 % (bunny)",
        &bunny,
        |world, mesh| {
            black_box(
                ProgressiveMesh::simplify(world, mesh, &SimplifyParams::ratio(0.01)).unwrap(),
            );
        },
    );

    // Refining needs the coarsest level first; build it outside the timing.
    let coarsest = || {
        let (mut world, mesh) = built(&bunny);
        let (pm, _) =
            ProgressiveMesh::simplify(&mut world, mesh, &SimplifyParams::ratio(0.01)).unwrap();
        (world, pm)
    };
    c.bench_function("progressive: refine 1 % -> full (bunny)", |b| {
        b.iter_batched(
            coarsest,
            |(mut world, mut pm)| {
                let full = pm.full_faces;
                black_box(pm.go_to_faces(&mut world, full).unwrap());
                (world, pm)
            },
            BatchSize::LargeInput,
        );
    });
    let (mut world, mut pm) = coarsest();
    let step = faces / 100;
    c.bench_function("progressive: one slider step of 1 % (bunny)", |b| {
        let mut up = true;
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let now = pm.faces();
                if now + step > pm.full_faces {
                    up = false;
                } else if now < 2 * step {
                    up = true;
                }
                let target = if up { now + step } else { now - step };
                let start = Instant::now();
                black_box(pm.go_to_faces(&mut world, target).unwrap());
                total += start.elapsed();
            }
            total
        });
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
