//! The editor's modelling workflow without a window: the selected set (Shift-click, all,
//! grow, shrink, loops), the modelling keys (E, I, Ctrl+B, X, F, C, D, Alt+M) on that set, each
//! one undo step, a transform's frames merged into one step, and Esc taking a gesture back
//! (with the extrusion it followed) and leaving nothing to redo.

mod common;

use common::{last_ok, press, send};

use bevy::prelude::*;
use pappus::edit::Edit;
use pappus::editor::gestures::transform::Gestures;
use pappus::editor::session::history::UndoHistory;
use pappus::editor::session::requests::Request;
use pappus::editor::session::requests::SelectionEdit;
use pappus::editor::session::selection::{ActiveMesh, SelectMode, Selection};
use pappus::mesh::ids::ElementId;
use pappus::mesh::{MeshMembers, MeshRef, mesh_stats, validate};

fn open(app: &mut App, source: &str) {
    app.world_mut().write_message(Request::Open(source.into()));
    app.update();
}

fn counts(app: &App) -> (usize, usize, usize) {
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    let s = mesh_stats(app.world(), mesh);
    (s.vertices, s.edges, s.faces)
}

fn undo_steps(app: &App) -> (usize, usize) {
    let h = app.world().resource::<UndoHistory>();
    (h.undo_entries().len(), h.redo_entries().len())
}

fn members(app: &App) -> MeshMembers {
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    MeshMembers::collect(app.world(), mesh)
}

#[test]
fn the_selected_set_grows_shrinks_follows_loops_and_drops_what_an_edit_removed() {
    let mut app = common::headless_editor();
    open(&mut app, "shape:quad-grid:4");
    let vs = members(&app).vertices;
    let centre = {
        let m = MeshRef::new(app.world());
        *vs.iter()
            .find(|&&v| m.position(v) == Vec3::new(0.5, 0.5, 0.0))
            .unwrap()
    };
    send(&mut app, Request::Select(Some(ElementId::Vertex(centre))));
    send(&mut app, SelectionEdit::Grow);
    assert_eq!(app.world().resource::<Selection>().len(), 5);
    assert_eq!(last_ok(&app), "5 vertices selected");
    send(&mut app, SelectionEdit::Shrink);
    assert_eq!(
        app.world().resource::<Selection>().elements(),
        [ElementId::Vertex(centre)]
    );
    // Shift-click adds; A selects every vertex; Alt+A nothing.
    let other = ElementId::Vertex(vs[0]);
    send(&mut app, SelectionEdit::Toggle(other));
    assert_eq!(app.world().resource::<Selection>().element, Some(other));
    press(&mut app, None, KeyCode::KeyA);
    assert_eq!(app.world().resource::<Selection>().len(), 25);
    press(&mut app, Some(KeyCode::AltLeft), KeyCode::KeyA);
    assert!(app.world().resource::<Selection>().is_empty());
    // The loop through a middle edge crosses the grid: four edges.
    let e = {
        let m = MeshRef::new(app.world());
        m.edge(m.vertex_outgoing(centre).next().unwrap())
    };
    send(&mut app, SelectionEdit::Loop(e, false));
    assert_eq!(app.world().resource::<Selection>().len(), 4);
    send(&mut app, SelectionEdit::Ring(e, true));
    // The ring crosses the grid the other way: five edges, e shared with the loop.
    assert_eq!(last_ok(&app), "8 edges selected");
    // Collapsing the active edge removes it: it leaves the set, the rest stays.
    press(&mut app, None, KeyCode::KeyC);
    last_ok(&app);
    let selection = app.world().resource::<Selection>();
    assert_eq!(
        selection.len(),
        1,
        "the collapse selects the vertex it kept"
    );
    assert!(matches!(selection.element, Some(ElementId::Vertex(_))));
}

#[test]
fn modelling_keys_act_on_the_selection_one_undo_step_each() {
    let mut app = common::headless_editor();
    open(&mut app, "shape:cube");
    let start = undo_steps(&app).0;
    let faces = members(&app).faces;
    // E on two neighbouring faces of the cube: one region, a wall of 6 quads around it. With no
    // window the height gesture moves nothing; Enter keeps the extrusion.
    let (f0, f1) = {
        let m = MeshRef::new(app.world());
        let f0 = faces[0];
        let f1 = m.face(m.twin(m.face_halfedge(f0))).unwrap();
        (f0, f1)
    };
    send(&mut app, Request::Select(Some(ElementId::Face(f0))));
    send(&mut app, SelectionEdit::Toggle(ElementId::Face(f1)));
    press(&mut app, None, KeyCode::KeyE);
    assert_eq!(last_ok(&app), "2 faces lifted on 6 side faces");
    assert_eq!(counts(&app), (14, 24, 12));
    assert!(app.world().resource::<Gestures>().active.is_some());
    press(&mut app, None, KeyCode::Enter);
    assert!(app.world().resource::<Gestures>().active.is_none());
    assert_eq!(undo_steps(&app), (start + 1, 0));
    // The two faces stay selected: I insets each of them, then Esc takes the inset back and
    // leaves nothing to redo.
    assert_eq!(app.world().resource::<Selection>().len(), 2);
    press(&mut app, None, KeyCode::KeyI);
    assert_eq!(counts(&app), (22, 40, 20));
    press(&mut app, None, KeyCode::Escape);
    assert_eq!(counts(&app), (14, 24, 12));
    assert_eq!(undo_steps(&app), (start + 1, 0));
    // Ctrl+B on the selected faces: an inset by the panel's amount, one step.
    press(&mut app, Some(KeyCode::ControlLeft), KeyCode::KeyB);
    assert_eq!(last_ok(&app), "2 faces inset, 8 new faces around them");
    // X erases them: two holes.
    press(&mut app, None, KeyCode::KeyX);
    last_ok(&app);
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    assert_eq!(mesh_stats(app.world(), mesh).boundary_loops, 2);
    assert!(app.world().resource::<Selection>().is_empty());
    // F fills a hole from one of its edges (in edge mode, the boundary edge of a face).
    *app.world_mut().resource_mut::<SelectMode>() = SelectMode::Edge;
    let boundary = {
        let m = MeshRef::new(app.world());
        members(&app)
            .edges
            .into_iter()
            .find(|&e| m.is_boundary_edge(e))
            .unwrap()
    };
    send(&mut app, Request::Select(Some(ElementId::Edge(boundary))));
    press(&mut app, None, KeyCode::KeyF);
    assert!(last_ok(&app).starts_with("new face"));
    assert_eq!(mesh_stats(app.world(), mesh).boundary_loops, 1);
    assert_eq!(undo_steps(&app), (start + 4, 0));
    validate(app.world(), mesh).unwrap();
    // Every step undoes: back to the cube.
    for _ in 0..4 {
        send(&mut app, Request::Undo);
        last_ok(&app);
    }
    assert_eq!(counts(&app), (8, 12, 6));
}

#[test]
fn a_gesture_is_one_undo_step_and_esc_takes_it_back_with_the_edit_it_followed() {
    let mut app = common::headless_editor();
    open(&mut app, "shape:cube");
    let start = undo_steps(&app).0;
    let v = members(&app).vertices[0];
    let p = MeshRef::new(app.world()).position(v);
    // Three frames of one transform merge into one step.
    app.world_mut()
        .resource_mut::<UndoHistory>()
        .begin_gesture();
    for d in [0.1, 0.2, 0.3] {
        send(&mut app, Edit::Move(vec![(v, p + Vec3::splat(d))]));
    }
    app.world_mut().resource_mut::<UndoHistory>().end_gesture();
    assert_eq!(undo_steps(&app), (start + 1, 0));
    send(&mut app, Request::Undo);
    assert_eq!(MeshRef::new(app.world()).position(v), p);
    send(&mut app, Request::Redo);
    // An extrusion, then a gesture's moves; Retract to before the extrusion takes both back.
    let f = members(&app).faces[2];
    send(&mut app, Request::Select(Some(ElementId::Face(f))));
    let keep = undo_steps(&app).0;
    let mark = app.world().resource::<UndoHistory>().mark();
    send(&mut app, Edit::local("extrude", f));
    app.world_mut()
        .resource_mut::<UndoHistory>()
        .begin_gesture();
    let top: Vec<_> = MeshRef::new(app.world()).face_vertices(f).collect();
    let moves = top.iter().map(|&x| (x, Vec3::splat(5.0))).collect();
    send(&mut app, Edit::Move(moves));
    app.world_mut().resource_mut::<UndoHistory>().end_gesture();
    assert_eq!(undo_steps(&app), (keep + 2, 0));
    send(&mut app, Request::Retract(mark));
    assert_eq!(
        undo_steps(&app),
        (keep, 0),
        "nothing to redo after a cancel"
    );
    assert_eq!(counts(&app), (8, 12, 6));
    assert_eq!(MeshRef::new(app.world()).position(v), p + Vec3::splat(0.3));
}

/// Esc counts back by the entries' serial numbers, not by how many there are: the memory cap
/// may drop old entries while a gesture runs, and the cancel still takes back exactly the
/// extrusion and the gesture's moves.
#[test]
fn esc_takes_a_gesture_back_after_the_memory_cap_trimmed_the_history() {
    let mut app = common::headless_editor();
    open(&mut app, "shape:cube");
    let vs = members(&app).vertices;
    for (i, &v) in vs.iter().enumerate().take(6) {
        let p = MeshRef::new(app.world()).position(v);
        send(&mut app, Edit::Move(vec![(v, p * (1.0 + 0.01 * i as f32))]));
    }
    let before_extrusion = counts(&app);
    let old_entries = undo_steps(&app).0;
    let mark = app.world().resource::<UndoHistory>().mark();
    let f = members(&app).faces[2];
    send(&mut app, Edit::local("extrude", f));
    // From now on the cap holds about what there is, less the oldest entry: the gesture's
    // step pushes the oldest ones out.
    {
        let mut h = app.world_mut().resource_mut::<UndoHistory>();
        let oldest = h.undo_entries()[0].bytes();
        h.limit_bytes = h.bytes() - oldest + 1;
    }
    app.world_mut()
        .resource_mut::<UndoHistory>()
        .begin_gesture();
    let top: Vec<_> = MeshRef::new(app.world()).face_vertices(f).collect();
    send(
        &mut app,
        Edit::Move(top.iter().map(|&x| (x, Vec3::splat(2.0))).collect()),
    );
    app.world_mut().resource_mut::<UndoHistory>().end_gesture();
    let (now, _) = undo_steps(&app);
    assert!(now < old_entries + 2, "the cap dropped old entries: {now}");
    assert_ne!(counts(&app), before_extrusion);
    send(&mut app, Request::Retract(mark));
    assert_eq!(counts(&app), before_extrusion, "{}", last_ok(&app));
    assert_eq!(undo_steps(&app), (now - 2, 0));
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    validate(app.world(), mesh).unwrap();
}

#[test]
fn undoing_a_gesture_restores_vertices_its_first_frame_left_in_place() {
    // A constraint can keep a vertex still in the first frames and move it in later ones (S on
    // X, then free): the merged step must still restore it.
    let mut app = common::headless_editor();
    open(&mut app, "shape:cube");
    let vs = members(&app).vertices;
    let (a, b) = (vs[0], vs[1]);
    let (pa, pb) = {
        let m = MeshRef::new(app.world());
        (m.position(a), m.position(b))
    };
    app.world_mut()
        .resource_mut::<UndoHistory>()
        .begin_gesture();
    send(&mut app, Edit::Move(vec![(a, pa + Vec3::X), (b, pb)]));
    send(
        &mut app,
        Edit::Move(vec![(a, pa + Vec3::X), (b, pb + Vec3::Y)]),
    );
    app.world_mut().resource_mut::<UndoHistory>().end_gesture();
    send(&mut app, Request::Undo);
    let m = MeshRef::new(app.world());
    assert_eq!((m.position(a), m.position(b)), (pa, pb));
}
