//! Step mode in the editor, without a window: F9 then Shift+S runs QEM a collapse at a time;
//! the drawn next edge is the one the next step collapses; a run stepped to its end leaves the
//! unstepped edit's mesh element for element (every id, link and position bit; a saved file
//! lists the same lines, ordered as Bevy stores them) and one undo entry of the same label; scrubbing
//! back to step k and forward again gives the same mesh at k; the selection follows what an
//! element became; Esc puts the mesh back; any other edit ends the run first. A run fitted to
//! its input ends as the unstepped one does, the fit made as it finishes.

mod common;

use common::{last_ok, press, send};

use bevy::prelude::*;
use pappus::editor::gestures::overlay::{Overlay, Shape};
use pappus::editor::panels::step_view::{NEXT, StepView};
use pappus::editor::pipeline::stepping::{SteppedRun, Stepping};
use pappus::editor::session::history::UndoHistory;
use pappus::editor::session::requests::StepMove;
use pappus::editor::session::requests::{OutcomeLog, Request};
use pappus::editor::session::selection::{ActiveMesh, Selection};
use pappus::mesh::ids::ElementId;
use pappus::mesh::{MeshRef, to_soup, validate};
use pappus::ops::subdivide::SubdivideSteps;

/// A closed mesh with many equal costs (ties decide the order) and one with boundaries.
const SHAPES: [&str; 2] = ["shape:icosphere:3", "shape:grid:16"];

fn opened(source: &str) -> App {
    let mut app = common::headless_editor();
    send(&mut app, Request::Open(source.into()));
    app
}

/// The file the editor would save, as bytes.
fn saved(app: &App) -> Vec<u8> {
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    let soup = to_soup(app.world(), mesh);
    let path = std::env::temp_dir().join(format!(
        "pappus-step-mode-{}-{:?}.obj",
        std::process::id(),
        std::thread::current().id()
    ));
    pappus::io::write(&path, &soup).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).ok();
    bytes
}

/// The active mesh's elements, to the entity and the bit.
fn elements(app: &App) -> common::Elements {
    common::elements(app.world(), active(app))
}

/// The saved file's vertex lines, sorted (face lines name vertices by their place in the file).
fn sorted_lines(app: &App) -> Vec<String> {
    let text = String::from_utf8(saved(app)).unwrap();
    let mut lines: Vec<String> = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(str::to_owned)
        .collect();
    lines.sort_unstable();
    lines
}

/// The stepped run in progress.
fn run(app: &App) -> &SteppedRun {
    app.world()
        .resource::<Stepping>()
        .run
        .as_ref()
        .expect("a run")
}

/// The collapse the QEM run in progress makes next.
fn qem_next(app: &App) -> pappus::ops::simplify::NextCollapse {
    let qem = run(app)
        .steps
        .downcast_ref::<pappus::ops::decimate::QemSteps>();
    qem.expect("a QEM run").next.expect("a next collapse")
}

fn step_at(app: &App) -> (usize, usize) {
    let steps = &run(app).steps;
    (steps.at(), steps.made())
}

/// The next edge the overlay draws: the thick line in the next-collapse colour.
fn drawn_next(app: &App) -> Option<(Vec3, Vec3)> {
    app.world()
        .resource::<Overlay>()
        .shapes
        .iter()
        .find_map(|s| match *s {
            Shape::Highlight(a, b, c) if c == NEXT => Some((a, b)),
            _ => None,
        })
}

fn start_stepped(app: &mut App) {
    press(app, None, KeyCode::F9);
    press(app, Some(KeyCode::ShiftLeft), KeyCode::KeyS);
    assert!(
        last_ok(app).starts_with("stepping simplify"),
        "{}",
        last_ok(app)
    );
}

/// The label of the oldest entry on the undo stack.
fn oldest_undo_label(app: &App) -> String {
    app.world().resource::<UndoHistory>().undo_entries()[0]
        .label
        .clone()
}

#[test]
fn a_run_stepped_to_its_end_is_the_unstepped_edit_element_for_element_and_one_undo_entry() {
    for shape in SHAPES {
        let mut whole = opened(shape);
        press(&mut whole, Some(KeyCode::ShiftLeft), KeyCode::KeyS);
        let unstepped = last_ok(&whole);
        let label = oldest_undo_label(&whole);

        let mut app = opened(shape);
        start_stepped(&mut app);
        press(&mut app, None, KeyCode::ArrowRight);
        press(&mut app, Some(KeyCode::ShiftLeft), KeyCode::ArrowRight);
        press(&mut app, Some(KeyCode::ControlLeft), KeyCode::ArrowRight);
        assert_eq!(step_at(&app), (111, 111), "{shape}");
        press(&mut app, None, KeyCode::End);
        assert!(last_ok(&app).contains("the end"), "{}", last_ok(&app));
        assert!(
            elements(&app) == elements(&whole),
            "{shape}: the meshes differ"
        );
        assert_eq!(sorted_lines(&app), sorted_lines(&whole), "{shape}");
        press(&mut app, None, KeyCode::Enter);
        assert!(app.world().resource::<Stepping>().run.is_none());
        let history = app.world().resource::<UndoHistory>();
        assert_eq!(history.undo_entries().len(), 1, "{shape}");
        assert_eq!(history.undo_entries()[0].label, label, "{shape}");
        // The level-of-detail history is the run's: moving along it works as after the edit.
        send(
            &mut app,
            pappus::edit::Edit::Operation(pappus::ops::decimate::Refine::to(None)),
        );
        assert!(last_ok(&app).contains("faces"), "{}", last_ok(&app));
        send(&mut app, Request::Undo);
        let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
        validate(app.world(), mesh).unwrap();
        println!("{shape}: {unstepped}");
    }
}

#[test]
fn a_fitted_run_stepped_to_its_end_and_finished_is_the_unstepped_fitted_edit() {
    // The fit to the input comes after the last collapse: the run makes it as it finishes.
    let invocation = "simplify:0.5:0:fit";
    for shape in SHAPES {
        let mut whole = opened(shape);
        send(
            &mut whole,
            Request::Edit(pappus::edit::Edit::invoked(invocation).unwrap()),
        );
        let mut app = opened(shape);
        let edit = pappus::edit::Edit::invoked(invocation).unwrap();
        send(&mut app, Request::StartStepped(edit));
        press(&mut app, None, KeyCode::End);
        assert!(last_ok(&app).contains("the end"), "{}", last_ok(&app));
        let unfitted = elements(&app);
        press(&mut app, None, KeyCode::Enter);
        assert!(app.world().resource::<Stepping>().run.is_none());
        // The sphere's vertices move; the flat grid has nothing to fit.
        let curved = shape == SHAPES[0];
        assert_eq!(
            elements(&app) != unfitted,
            curved,
            "{shape}: what the finish fitted"
        );
        assert!(
            elements(&app) == elements(&whole),
            "{shape}: the meshes differ"
        );
        // The history's coarsest level is the fitted mesh: back to the full one and forth.
        let refine =
            |faces| pappus::edit::Edit::Operation(pappus::ops::decimate::Refine::to(faces));
        send(&mut app, refine(None));
        send(&mut app, refine(Some(0)));
        assert_eq!(
            sorted_lines(&app),
            sorted_lines(&whole),
            "{shape}: after refining"
        );
    }
}

#[test]
fn the_drawn_next_edge_is_the_one_the_next_step_collapses() {
    let mut app = opened(SHAPES[0]);
    start_stepped(&mut app);
    for _ in 0..25 {
        let (a, b) = drawn_next(&app).expect("the next edge is drawn");
        let next = qem_next(&app);
        let edge = next.queued.edge;
        let m = MeshRef::new(app.world());
        let (p, q) = m.edge_vertices(edge);
        assert_eq!(
            [next.kept, next.removed].map(|v| m.position(v)),
            [a, b],
            "the drawn edge is the next one's, kept end first"
        );
        assert!([p, q].contains(&next.kept) && [p, q].contains(&next.removed));
        press(&mut app, None, KeyCode::ArrowRight);
        let m = MeshRef::new(app.world());
        assert!(m.try_edge(edge).is_none(), "{edge} was not collapsed");
        assert_eq!(m.position(next.kept), next.queued.position);
    }
}

#[test]
fn scrubbing_back_to_step_k_and_forward_again_gives_the_same_mesh_at_k() {
    for shape in SHAPES {
        let mut app = opened(shape);
        start_stepped(&mut app);
        let mut at = Vec::new();
        for k in [0usize, 7, 25, 50, 70] {
            send(&mut app, Request::Step(StepMove::To(k)));
            at.push((k, common::canonical(&to_soup(app.world(), active(&app)))));
        }
        for &(k, ref expected) in at.iter().rev().chain(at.iter()) {
            send(&mut app, Request::Step(StepMove::To(k)));
            assert_eq!(step_at(&app).0, k, "{shape}");
            assert_eq!(
                common::canonical(&to_soup(app.world(), active(&app))),
                *expected,
                "{shape}: step {k}"
            );
            validate(app.world(), active(&app)).unwrap();
        }
        // Forward past the front again: new collapses, as an unscrubbed run would make.
        send(&mut app, Request::Step(StepMove::Forward(usize::MAX)));
        let mut whole = opened(shape);
        press(&mut whole, Some(KeyCode::ShiftLeft), KeyCode::KeyS);
        assert_eq!(
            common::canonical(&to_soup(app.world(), active(&app))),
            common::canonical(&to_soup(whole.world(), active(&whole))),
            "{shape}: the end after scrubbing"
        );
    }
}

fn active(app: &App) -> pappus::mesh::MeshId {
    app.world().resource::<ActiveMesh>().0.unwrap()
}

#[test]
fn a_collapsed_selection_follows_to_what_it_became_and_esc_puts_the_mesh_back() {
    let mut app = opened(SHAPES[0]);
    let before = saved(&app);
    let first = pappus::mesh::MeshMembers::collect(app.world(), active(&app)).vertices[0];
    let before_position = MeshRef::new(app.world()).position(first);
    send(&mut app, Request::Select(Some(ElementId::Vertex(first))));
    start_stepped(&mut app);
    let next = qem_next(&app);
    send(
        &mut app,
        Request::Select(Some(ElementId::Vertex(next.removed))),
    );
    press(&mut app, None, KeyCode::ArrowRight);
    assert_eq!(
        app.world().resource::<Selection>().element,
        Some(ElementId::Vertex(next.kept))
    );
    let fate = run(&app).fate.clone();
    assert_eq!(
        fate.map(|(_, line)| line),
        Some(format!(
            "{} is gone: collapsed into {}",
            next.removed, next.kept
        ))
    );
    // A hundred steps on, the selection is still on a live element: each collapse that
    // removes it moves it on.
    press(&mut app, Some(KeyCode::ControlLeft), KeyCode::ArrowRight);
    let selected = app.world().resource::<Selection>().element.unwrap();
    assert!(pappus::editor::session::selection::exists(
        &MeshRef::new(app.world()),
        selected
    ));
    press(&mut app, None, KeyCode::Escape);
    assert!(app.world().resource::<Stepping>().run.is_none());
    assert!(saved(&app) == before, "Esc left a different mesh");
    // The selection from before the run, on the restored mesh's ids.
    let m = MeshRef::new(app.world());
    let now = app.world().resource::<Selection>().element;
    let Some(ElementId::Vertex(v)) = now else {
        panic!("the selection from before the run: {now:?}");
    };
    assert_eq!(m.position(v), before_position);
    assert!(
        app.world()
            .resource::<UndoHistory>()
            .undo_entries()
            .is_empty()
    );
}

#[test]
fn another_edit_ends_the_run_as_one_undo_entry_first() {
    let mut app = opened(SHAPES[1]);
    start_stepped(&mut app);
    send(&mut app, Request::Step(StepMove::Forward(30)));
    send(&mut app, Request::Undo);
    assert!(app.world().resource::<Stepping>().run.is_none());
    assert_eq!(
        app.world().resource::<UndoHistory>().redo_entries().len(),
        1,
        "the run was recorded, then undone"
    );
    send(&mut app, Request::Step(StepMove::Forward(1)));
    let last = app
        .world()
        .resource::<OutcomeLog>()
        .entries
        .last()
        .unwrap()
        .clone();
    assert!(last.result.is_err(), "a step with no run is declined");
}

#[test]
fn a_transform_started_during_a_run_keeps_the_run_when_it_is_cancelled() {
    let mut app = opened(SHAPES[1]);
    start_stepped(&mut app);
    send(&mut app, Request::Step(StepMove::Forward(20)));
    send(
        &mut app,
        Request::Selection(pappus::editor::session::requests::SelectionEdit::All),
    );
    press(&mut app, None, KeyCode::KeyG);
    assert!(app.world().resource::<Stepping>().run.is_none());
    press(&mut app, None, KeyCode::Escape);
    let history = app.world().resource::<UndoHistory>();
    assert_eq!(history.undo_entries().len(), 1, "the run's entry stays");
    assert_eq!(
        history.undo_entries()[0].label,
        "simplify (ratio 0.5, distance 0, no-fit)"
    );
}

#[test]
fn saving_during_a_run_ends_it_first() {
    let mut app = opened(SHAPES[1]);
    start_stepped(&mut app);
    send(&mut app, Request::Step(StepMove::Forward(5)));
    let path = std::env::temp_dir().join(format!("pappus-step-save-{}.obj", std::process::id()));
    send(&mut app, Request::Save(Some(path.clone())));
    std::fs::remove_file(&path).ok();
    assert!(app.world().resource::<Stepping>().run.is_none());
    assert_eq!(
        app.world().resource::<UndoHistory>().undo_entries().len(),
        1
    );
}

/// Presses `k` (with `modifier`) in a fresh editor on `shape`, unstepped, and returns it.
fn unstepped(shape: &str, modifier: Option<KeyCode>, k: KeyCode) -> App {
    let mut app = opened(shape);
    press(&mut app, modifier, k);
    last_ok(&app);
    app
}

#[test]
fn a_remeshing_run_steps_pass_by_pass_highlights_each_and_ends_as_the_unstepped_edit() {
    let shape = "shape:icosphere:2";
    let whole = unstepped(shape, None, KeyCode::KeyM);
    let mut app = opened(shape);
    press(&mut app, None, KeyCode::F9);
    press(&mut app, None, KeyCode::KeyM);
    assert!(last_ok(&app).contains("next: split"), "{}", last_ok(&app));
    for pass in ["split", "collapse", "flip", "relax", "project"] {
        press(&mut app, None, KeyCode::ArrowRight);
        assert!(
            last_ok(&app).contains(&format!("1 {pass}:")),
            "{}",
            last_ok(&app)
        );
        let steps = run(&app)
            .steps
            .downcast_ref::<pappus::ops::remesh::RemeshSteps>();
        let steps = steps.expect("a remeshing run");
        let report = steps.last.as_ref().unwrap();
        // What the pass touched is drawn (green), as far as it touched anything.
        let drawn = app
            .world()
            .resource::<Overlay>()
            .shapes
            .iter()
            .filter(|s| {
                matches!(s, Shape::Dot(_, _, c) | Shape::Highlight(_, _, c)
                    if *c == pappus::editor::panels::step_view::TOUCHED)
            })
            .count();
        let touched = report.touched.vertices.len() + report.touched.edges.len();
        assert_eq!(
            drawn,
            touched.min(2 * pappus::ops::operation::stepping::MAX_DRAWN),
            "{pass}"
        );
    }
    press(&mut app, None, KeyCode::ArrowLeft);
    assert!(
        app.world()
            .resource::<OutcomeLog>()
            .entries
            .last()
            .unwrap()
            .result
            .is_err()
    );
    press(&mut app, None, KeyCode::End);
    assert!(
        elements(&app) == elements(&whole),
        "the stepped remesh differs"
    );
    press(&mut app, None, KeyCode::Enter);
    assert_eq!(oldest_undo_label(&app), oldest_undo_label(&whole));
}

#[test]
fn a_subdivision_run_shows_new_points_then_moved_vertices_then_commits_the_level() {
    for (shape, k) in [
        ("shape:icosahedron", KeyCode::KeyL),
        ("shape:cube", KeyCode::KeyQ),
    ] {
        let whole = unstepped(shape, None, k);
        let mut app = opened(shape);
        let before = elements(&app);
        press(&mut app, None, KeyCode::F9);
        press(&mut app, None, k);
        let v = MeshRef::new(app.world())
            .face_vertices(pappus::mesh::MeshMembers::collect(app.world(), active(&app)).faces[0])
            .next()
            .unwrap();
        send(&mut app, Request::Select(Some(ElementId::Vertex(v))));
        let stencil = |app: &App| {
            let steps = run(app).steps.downcast_ref::<SubdivideSteps>();
            let selected = app.world().resource::<Selection>().element;
            steps
                .expect("a subdivision run")
                .stencil(app.world(), selected)
        };
        let stencil = stencil(&app).expect("the selected vertex's stencil");
        let window = app.world().resource::<StepView>();
        let table = window.show.table.as_ref().expect("the stencil's table");
        assert_eq!(table.rows.len(), stencil.terms.len(), "{shape}");
        let total: f32 = stencil.terms.iter().map(|t| t.1).sum();
        assert!(
            (total - 1.0).abs() < 1e-6,
            "{shape}: weights sum to {total}"
        );
        assert!(
            elements(&app) == before,
            "{shape}: the preview changed the mesh"
        );
        press(&mut app, None, KeyCode::ArrowRight);
        assert!(last_ok(&app).contains("moved as well"), "{}", last_ok(&app));
        assert!(
            elements(&app) == before,
            "{shape}: the preview changed the mesh"
        );
        press(&mut app, None, KeyCode::ArrowRight);
        assert!(
            elements(&app) == elements(&whole),
            "{shape}: the level differs"
        );
        // The old vertex kept its id and went where its stencil said.
        let m = MeshRef::new(app.world());
        assert!(
            (m.position(v) - stencil.position).length() < 1e-6,
            "{shape}"
        );
        press(&mut app, None, KeyCode::Enter);
        assert_eq!(
            oldest_undo_label(&app),
            oldest_undo_label(&whole),
            "{shape}"
        );
    }
}

/// The editor with `shape` open and the panel's smoothing set to `method` for `iterations`.
fn smoothing(shape: &str, method: usize, iterations: u32) -> App {
    let mut app = opened(shape);
    let mut ui = app
        .world_mut()
        .resource_mut::<pappus::editor::session::panel_state::UiState>();
    ui.set_parameter("smooth", 0, Some(method as f64)).unwrap();
    ui.set_parameter("smooth", 1, Some(iterations as f64))
        .unwrap();
    app
}

#[test]
fn a_smoothing_run_steps_an_iteration_at_a_time_goes_back_and_ends_as_the_unstepped_edit() {
    // A closed sphere: every vertex is free, and each iteration shrinks it.
    let shape = "shape:icosphere:2";
    for method in [0, 2] {
        let mut whole = smoothing(shape, method, 20);
        press(&mut whole, None, KeyCode::KeyO);
        last_ok(&whole);
        let mut app = smoothing(shape, method, 20);
        let before = elements(&app);
        press(&mut app, None, KeyCode::F9);
        press(&mut app, None, KeyCode::KeyO);
        assert_eq!(step_at(&app), (0, 20), "method {method}");
        assert!(elements(&app) == before, "step 0 is the mesh as it was");
        for _ in 0..5 {
            press(&mut app, None, KeyCode::ArrowRight);
        }
        assert_eq!(step_at(&app).0, 5);
        assert!(
            last_ok(&app).contains("iteration 5 of 20"),
            "{}",
            last_ok(&app)
        );
        // Each free vertex's path is drawn, and each iteration's mean move listed.
        let paths = app
            .world()
            .resource::<Overlay>()
            .shapes
            .iter()
            .filter(|s| matches!(s, Shape::Line(_, _, c) if *c == pappus::editor::panels::step_view::TOUCHED))
            .count();
        assert_eq!(paths, 162, "every vertex's path");
        let view = app.world().resource::<StepView>().clone();
        assert_eq!(view.show.lists[0].lines.len(), 5);
        // Back two and forward two again: the same bits at 3 and at 5.
        let at_five = elements(&app);
        press(&mut app, None, KeyCode::ArrowLeft);
        press(&mut app, None, KeyCode::ArrowLeft);
        assert_eq!(step_at(&app).0, 3);
        let at_three = elements(&app);
        assert!(at_three != at_five);
        press(&mut app, None, KeyCode::ArrowRight);
        press(&mut app, None, KeyCode::ArrowRight);
        assert!(elements(&app) == at_five, "method {method}: forward again");
        send(&mut app, Request::Step(StepMove::To(3)));
        assert!(elements(&app) == at_three, "method {method}: scrubbed to 3");
        send(&mut app, Request::Step(StepMove::Forward(usize::MAX)));
        assert_eq!(step_at(&app).0, 20);
        assert!(
            elements(&app) == elements(&whole),
            "method {method}: the end differs from the unstepped smoothing"
        );
        press(&mut app, None, KeyCode::Enter);
        assert_eq!(oldest_undo_label(&app), oldest_undo_label(&whole));
        assert!(app.world().resource::<Stepping>().run.is_none());
    }
}
