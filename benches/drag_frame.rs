//! One frame of a vertex drag in the editor's logic (no window): the move request, its apply,
//! the render copy's update of the touched chunks, and the panel's snapshot — with the mouse
//! button held, as in a drag (statistics wait for the release), and without (statistics and
//! validation recomputed after the frame's rebuild, as every drag frame did before).
//!
//! Uses the shared Stanford bunny when present, else an icosphere of similar size. Run:
//! `cargo bench --bench drag_frame`.

use bevy::input::ButtonState;
use bevy::input::mouse::{MouseButton, MouseButtonInput};
use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::edit::Edit;
use pappus::editor::EditorSystems;
use pappus::editor::requests::Request;
use pappus::editor::selection::ActiveMesh;
use pappus::editor::ui::{InspectorView, snapshot};
use pappus::mesh::{MeshMembers, MeshRef};
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
                    .write_message(Request::Edit(Edit::MoveVertex(v, p)));
                app.update();
            });
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = drag_frame
}
criterion_main!(benches);
