//! One frame of a vertex drag in the editor's logic (no window): the move request, its apply,
//! the render copy's update of the touched chunks, and the panel's snapshot — with the mouse
//! button held, as in a drag (statistics wait for the release), and without (statistics and
//! validation recomputed after the frame's rebuild, as every drag frame did before).
//!
//! And one frame of a handle deformation (the editor's `G` with anchors marked): one
//! as-rigid-as-possible iteration from the last frame's result (its local step, right-hand side
//! and triangular solves; the factor is made once, before), the move of every free vertex and
//! the handle as one request, its apply, and the render copy's update — measured whole, and the
//! ARAP iteration alone beside it. The anchors are the bunny's lowest fifth, the handle its
//! highest seventh (the ears), moved a little further each frame.
//!
//! Uses the shared Stanford bunny when present, else an icosphere of similar size. Run:
//! `cargo bench --bench drag_frame`.

use bevy::input::ButtonState;
use bevy::input::mouse::{MouseButton, MouseButtonInput};
use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::edit::Edit;
use pappus::editor::EditorSystems;
use pappus::editor::panels::{state::InspectorView, ui::snapshot};
use pappus::editor::session::history::UndoHistory;
use pappus::editor::session::requests::Request;
use pappus::editor::session::selection::ActiveMesh;
use pappus::mesh::{MeshMembers, MeshRef};
use pappus::ops::deform::{DeformMethod, LiveDeform};
use std::path::Path;

/// The editor's logic with the panel's snapshot, the bunny open.
fn editor() -> App {
    let mut app = pappus::editor::headless_app();
    app.init_resource::<InspectorView>()
        .add_systems(Update, snapshot.in_set(EditorSystems::Ui));
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    let source = if bunny.exists() {
        bunny
    } else {
        println!("NOTICE: no shared bunny; using icosphere:6 instead");
        "shape:icosphere:6".into()
    };
    app.world_mut().write_message(Request::Open(source));
    app.update();
    app.update();
    app
}

fn mouse(app: &mut App, state: ButtonState) {
    app.world_mut().write_message(MouseButtonInput {
        button: MouseButton::Left,
        state,
        window: Entity::PLACEHOLDER,
    });
}

fn drag_frame(c: &mut Criterion) {
    for held in [true, false] {
        let mut app = editor();
        let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
        let v = MeshMembers::collect(app.world(), mesh).vertices[100];
        if held {
            mouse(&mut app, ButtonState::Pressed);
            app.update();
        }
        let name = if held {
            "drag frame, bunny (button held: statistics wait)"
        } else {
            "drag frame, bunny (statistics and validation every frame)"
        };
        let mut step = 0u32;
        c.bench_function(name, |b| {
            b.iter(|| {
                step += 1;
                let p = MeshRef::new(app.world()).position(v)
                    + Vec3::splat(if step.is_multiple_of(2) { 1e-4 } else { -1e-4 });
                app.world_mut()
                    .write_message(Request::Edit(Edit::Move(vec![(v, p)])));
                app.update();
            });
        });
    }
}

fn handle_frame(c: &mut Criterion) {
    let mut app = editor();
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    let vertices = MeshMembers::collect(app.world(), mesh).vertices;
    let m = MeshRef::new(app.world());
    let heights: Vec<f32> = vertices.iter().map(|&v| m.position(v).y).collect();
    let (low, high) = heights
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &y| (a.min(y), b.max(y)));
    let part = |keep: &dyn Fn(f32) -> bool| -> Vec<_> {
        vertices
            .iter()
            .zip(&heights)
            .filter(|&(_, &y)| keep(y))
            .map(|(&v, _)| v)
            .collect()
    };
    let anchors = part(&|y| y < low + 0.2 * (high - low));
    let handle = part(&|y| y > high - 0.15 * (high - low));
    let start: Vec<Vec3> = handle.iter().map(|&v| m.position(v)).collect();
    let mut live = LiveDeform::new(app.world(), mesh, DeformMethod::Arap, &anchors, &handle)
        .expect("the bunny's system factors");
    // As `G` does: the frames merge into one undo entry, recorded by the first, and the
    // statistics wait for its end (here by the button held, which they also wait for).
    app.world_mut()
        .resource_mut::<UndoHistory>()
        .begin_gesture();
    mouse(&mut app, ButtonState::Pressed);
    app.update();
    let mut frame = 0u32;
    let mut targets = move || {
        frame += 1;
        // Out and back over 50 frames, as a hand drags: each frame starts near the last.
        let t = 0.02 * (frame % 50).min(50 - frame % 50) as f32 / 25.0;
        start
            .iter()
            .map(|p| *p + Vec3::new(t, 0.3 * t, 0.0))
            .collect::<Vec<_>>()
    };
    let name = format!(
        "handle drag frame, bunny ARAP ({} free vertices): iteration, move, redraw",
        live.free()
    );
    c.bench_function(&name, |b| {
        b.iter(|| {
            let moves = live.solve(&targets(), 1).expect("finite");
            app.world_mut()
                .write_message(Request::Edit(Edit::Move(moves)));
            app.update();
        });
    });
    c.bench_function("handle drag frame, bunny ARAP: the iteration alone", |b| {
        b.iter(|| live.solve(&targets(), 1).expect("finite"));
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = drag_frame, handle_frame
}
criterion_main!(benches);
