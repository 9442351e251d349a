//! One editor frame of a modelling operation on a 1M-face mesh: the request, its apply with
//! its undo record, and the render copy's update of the touched chunks (the editor's logic
//! without a window). Each timed frame is followed by an untimed undo, so the mesh stays the
//! same size; the faces, edges and vertices operated on stride across the mesh.
//!
//! The target is one frame's CPU budget, 16 ms. Run: `cargo bench --bench edit_frame`.

use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::edit::Edit;
use pappus::editor::EditorLogicPlugin;
use pappus::editor::requests::{OutcomeLog, Request};
use pappus::editor::selection::ActiveMesh;
use pappus::mesh::{MeshMembers, MeshRef};
use std::time::{Duration, Instant};

/// The editor's logic with a 1000 × 1000 quad grid open (1M faces).
fn editor() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        bevy::input::InputPlugin,
        AssetPlugin::default(),
        bevy::mesh::MeshPlugin,
        EditorLogicPlugin,
    ));
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

fn edit_frame(c: &mut Criterion) {
    let mut app = editor();
    let mesh = app.world().resource::<ActiveMesh>().0.expect("open");
    let members = MeshMembers::collect(app.world(), mesh);
    let m = MeshRef::new(app.world());
    // Interior elements only, spread over the grid.
    let faces: Vec<_> = members
        .faces
        .iter()
        .copied()
        .filter(|&f| m.face_halfedges(f).all(|h| !m.is_boundary(m.twin(h))))
        .step_by(997)
        .collect();
    let vertices: Vec<_> = members
        .vertices
        .iter()
        .copied()
        .filter(|&v| !m.is_boundary_vertex(v))
        .step_by(997)
        .collect();
    let edges: Vec<_> = members
        .edges
        .iter()
        .copied()
        .filter(|&e| !m.is_boundary_edge(e))
        .step_by(997)
        .collect();
    type MakeEdit = Box<dyn Fn(usize) -> Edit>;
    let cases: Vec<(&str, MakeEdit)> = vec![
        ("extrude a face", {
            let faces = faces.clone();
            Box::new(move |i| Edit::Extrude(vec![faces[i % faces.len()]], 0.001))
        }),
        ("inset a face", {
            let faces = faces.clone();
            Box::new(move |i| Edit::Inset(vec![faces[i % faces.len()]], 0.3, 0.0))
        }),
        ("bevel a vertex", {
            let vertices = vertices.clone();
            Box::new(move |i| Edit::BevelVertex(vertices[i % vertices.len()], 0.25))
        }),
        ("bevel an edge", {
            let edges = edges.clone();
            Box::new(move |i| Edit::BevelEdge(edges[i % edges.len()], 0.25))
        }),
        ("erase a face", {
            let faces = faces.clone();
            Box::new(move |i| Edit::Erase(vec![faces[i % faces.len()]]))
        }),
        ("dissolve a vertex", {
            let vertices = vertices.clone();
            Box::new(move |i| Edit::DissolveVertex(vertices[i % vertices.len()]))
        }),
        ("collapse a face", {
            let faces = faces.clone();
            Box::new(move |i| Edit::CollapseFace(faces[i % faces.len()]))
        }),
    ];
    for (name, make) in cases {
        let mut i = 0;
        c.bench_function(&format!("{name}, op + render update (1M faces)"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    // Elements the op removed come back from the undo under new ids: skip the
                    // stale ones.
                    let edit = loop {
                        let edit = make(i);
                        i += 1;
                        if edit.reach(app.world(), mesh).is_some() {
                            break edit;
                        }
                    };
                    total += frame(&mut app, Request::Edit(edit));
                    // The undo keeps the mesh as it was (ids of restored elements change, but
                    // the elements operated on next are others).
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
