//! One editor frame of a modelling operation on a 1M-face mesh: the request, its apply with
//! its undo record, and the render copy's update of the touched chunks (the editor's logic
//! without a window). Each timed frame is followed by an untimed undo, so the mesh stays the
//! same size; the faces, edges and vertices operated on stride across the mesh.
//!
//! The target is one frame's CPU budget, 16 ms. Run: `cargo bench --bench edit_frame`.

use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::edit::Edit;
use pappus::editor::session::requests::{OutcomeLog, Request};
use pappus::editor::session::selection::ActiveMesh;
use pappus::mesh::{MeshMembers, MeshRef};
use std::time::{Duration, Instant};

/// The editor's logic with a 1000 × 1000 quad grid open (1M faces).
fn editor() -> App {
    let mut app = pappus::editor::headless_app();
    app.world_mut()
        .write_message(Request::Open("shape:quad-grid:1000".into()));
    app.update();
    app.update();
    app
}

fn frame(app: &mut App, request: Request) -> Duration {
    app.world_mut().write_message(request);
    let start = Instant::now();
    app.update();
    let took = start.elapsed();
    let log = app.world().resource::<OutcomeLog>();
    if let Some(Err(why)) = log.entries.last().map(|o| &o.result) {
        panic!("refused: {why}");
    }
    took
}

/// Interior faces, vertices and edges of the active mesh, spread over it.
struct Candidates {
    faces: Vec<pappus::mesh::FaceId>,
    vertices: Vec<pappus::mesh::VertexId>,
    edges: Vec<pappus::mesh::EdgeId>,
}

impl Candidates {
    fn of(app: &App) -> Self {
        let mesh = app.world().resource::<ActiveMesh>().0.expect("open");
        let members = MeshMembers::collect(app.world(), mesh);
        let m = MeshRef::new(app.world());
        Self {
            faces: members
                .faces
                .iter()
                .copied()
                .filter(|&f| m.face_halfedges(f).all(|h| !m.is_boundary(m.twin(h))))
                .step_by(997)
                .collect(),
            vertices: members
                .vertices
                .iter()
                .copied()
                .filter(|&v| !m.is_boundary_vertex(v))
                .step_by(997)
                .collect(),
            edges: members
                .edges
                .iter()
                .copied()
                .filter(|&e| !m.is_boundary_edge(e))
                .step_by(997)
                .collect(),
        }
    }
}

/// The operations timed, each on the `i`-th candidate of its kind.
const CASES: [&str; 7] = [
    "extrude a face",
    "inset a face",
    "bevel a vertex",
    "bevel an edge",
    "erase a face",
    "dissolve a vertex",
    "collapse a face",
];

fn edit(case: usize, c: &Candidates, i: usize) -> Edit {
    let face = || c.faces[i % c.faces.len()];
    let vertex = || c.vertices[i % c.vertices.len()];
    match case {
        0 => Edit::local_on("extrude", [face()], &[0.001]),
        1 => Edit::local_on("inset", [face()], &[0.3]),
        2 => Edit::local("bevel", vertex()),
        3 => Edit::local("bevel", c.edges[i % c.edges.len()]),
        4 => Edit::local("erase", face()),
        5 => Edit::local("dissolve", vertex()),
        _ => Edit::local("collapse", face()),
    }
}

fn edit_frame(c: &mut Criterion) {
    let mut app = editor();
    let mesh = app.world().resource::<ActiveMesh>().0.expect("open");
    let mut candidates = Candidates::of(&app);
    for (case, name) in CASES.iter().enumerate() {
        let mut i = 0;
        c.bench_function(&format!("{name}, op + render update (1M faces)"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    // An element the op removed comes back from the undo under a new id: stale
                    // candidates are skipped, and the lists are made anew once they run out.
                    let mut misses = 0;
                    let edit = loop {
                        let edit = edit(case, &candidates, i);
                        i += 1;
                        if edit.reach(app.world(), mesh).is_some() {
                            break edit;
                        }
                        misses += 1;
                        if misses > candidates.faces.len() {
                            candidates = Candidates::of(&app);
                            misses = 0;
                        }
                    };
                    total += frame(&mut app, Request::Edit(edit));
                    // The undo keeps the mesh the same size for the next frame.
                    frame(&mut app, Request::Undo);
                }
                total
            });
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = edit_frame
}
criterion_main!(benches);
