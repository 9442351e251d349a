//! Undo and redo through the editor's request path: every kind of edit, undone, gives back the
//! exact mesh (positions bitwise, faces up to relabeling, valid), and redone gives the exact
//! result again; long random sequences undo to the original; drags are one entry; the memory
//! cap drops the oldest entries. Jobs: a long operation runs while frames go on, a cancel leaves
//! the mesh exactly as it was, a finished one is one undo entry, and a subdivision job
//! (computed on the tables alone) commits exactly what applying the edit at once makes.

mod common;

use bevy::input::ButtonState;
use bevy::input::mouse::{MouseButton, MouseButtonInput};
use bevy::prelude::*;
use common::canonical;
use pappus::edit::Edit;
use pappus::editor::session::history::UndoHistory;
use pappus::editor::session::requests::{EditOutcome, Request};
use pappus::editor::session::selection::{ActiveMesh, Selection};
use pappus::mesh::ids::{EdgeId, ElementId, MeshId, VertexId};
use pappus::mesh::{MeshMembers, MeshRef, mesh_stats, to_soup, validate};

fn app() -> App {
    common::headless_editor()
}

fn request(app: &mut App, r: Request) -> Result<String, String> {
    app.world_mut().write_message(r);
    app.update();
    last(app).result.map_err(|e| e.to_string())
}

fn last(app: &App) -> EditOutcome {
    common::last_outcome(app)
}

fn active(app: &App) -> Option<MeshId> {
    app.world().resource::<ActiveMesh>().0
}

/// The active mesh, canonically (or nothing), after checking it validates.
fn state(app: &App) -> Option<Vec<Vec<common::Key>>> {
    let mesh = active(app)?;
    if let Err(e) = validate(app.world(), mesh) {
        panic!("invalid after {:?}: {e}", last(app).request);
    }
    Some(canonical(&to_soup(app.world(), mesh)))
}

fn undo_depth(app: &App) -> usize {
    app.world().resource::<UndoHistory>().undo_entries().len()
}

/// Opens a shape, discarding unsaved changes if asked.
fn open(app: &mut App, shape: &str) {
    if let Err(reason) = request(app, Request::Open(shape.into())) {
        assert!(reason.contains("unsaved"), "{reason}");
        request(app, Request::ConfirmDiscard(true)).unwrap();
    }
}

/// Applies `r`, then checks undo → exactly before, redo → exactly after, undo and redo again.
fn round_trip(app: &mut App, r: Request) {
    let label = r.label();
    assert!(try_round_trip(app, r), "{label}: {:?}", last(app).result);
}

/// As [`round_trip`], but a refused request is skipped: returns whether it applied.
fn try_round_trip(app: &mut App, r: Request) -> bool {
    let before = state(app);
    let depth = undo_depth(app);
    let label = r.label();
    if request(app, r).is_err() {
        assert_eq!(
            state(app),
            before,
            "{label} was refused but changed the mesh"
        );
        assert_eq!(
            undo_depth(app),
            depth,
            "{label} was refused but left an entry"
        );
        return false;
    }
    assert_eq!(undo_depth(app), depth + 1, "{label}: one entry");
    let after = state(app);
    assert_ne!(before, after, "{label} changed nothing");
    for _ in 0..2 {
        assert!(request(app, Request::Undo).is_ok());
        assert_eq!(state(app), before, "undo of {label}");
        assert!(request(app, Request::Redo).is_ok());
        assert_eq!(state(app), after, "redo of {label}");
    }
    true
}

fn members(app: &App) -> MeshMembers {
    MeshMembers::collect(app.world(), active(app).unwrap())
}

/// Chooses edges.
type EdgePick = fn(&MeshRef<'_>, EdgeId) -> bool;

/// Makes the next request from the app's state.
type MakeRequest = Box<dyn Fn(&App) -> Request>;

fn is_interior(m: &MeshRef<'_>, e: EdgeId) -> bool {
    !m.is_boundary_edge(e)
}

fn is_boundary(m: &MeshRef<'_>, e: EdgeId) -> bool {
    m.is_boundary_edge(e)
}

/// The edges (in storage order) that `pick` accepts.
fn edges_where(app: &App, pick: EdgePick) -> Vec<EdgeId> {
    let m = MeshRef::new(app.world());
    members(app)
        .edges
        .into_iter()
        .filter(|&e| pick(&m, e))
        .collect()
}

fn edge_where(app: &App, pick: EdgePick) -> EdgeId {
    edges_where(app, pick)[0]
}

/// Round-trips the registered operation `name` on the first of the picked edges where it
/// applies; returns whether one did.
fn round_trip_some(app: &mut App, pick: EdgePick, name: &str) -> bool {
    let candidates = edges_where(app, pick);
    candidates.into_iter().take(40).any(|e| {
        MeshRef::new(app.world()).try_edge(e).is_some()
            && try_round_trip(app, Edit::local(name, e).into())
    })
}

#[test]
fn every_local_edit_undoes_and_redoes_exactly() {
    let mut app = app();
    for shape in [
        "shape:icosphere:2",
        "shape:grid-with-holes",
        "shape:quad-grid",
    ] {
        open(&mut app, shape);
        let has_boundary = !edges_where(&app, is_boundary).is_empty();
        let picks: [(EdgePick, bool); 2] = [(is_interior, true), (is_boundary, false)];
        for (pick, interior) in picks {
            if !interior && !has_boundary {
                continue;
            }
            if interior {
                assert!(round_trip_some(&mut app, pick, "flip"), "{shape}: flip");
                assert!(round_trip_some(&mut app, pick, "dissolve"), "{shape}");
            }
            assert!(round_trip_some(&mut app, pick, "split"), "{shape}: split");
            assert!(round_trip_some(&mut app, pick, "collapse"), "{shape}");
            // Last: filling the hole may leave no boundary for later picks.
            if !interior {
                assert!(
                    round_trip_some(&mut app, pick, "fill-hole"),
                    "{shape}: fill hole"
                );
            }
        }
        // Cut a polygon (the dissolve's, or a quad) between two corners.
        let (f, a, b) = {
            let m = MeshRef::new(app.world());
            let f = members(&app)
                .faces
                .into_iter()
                .find(|&f| m.face_degree(f) >= 4)
                .unwrap();
            let corners: Vec<VertexId> = m.face_vertices(f).collect();
            (f, corners[0], corners[2])
        };
        round_trip(
            &mut app,
            Request::Edit(Edit::local_on(
                "split-face",
                [ElementId::from(f), a.into(), b.into()],
                &[],
            )),
        );
        let v = members(&app).vertices[3];
        let p = MeshRef::new(app.world()).position(v);
        round_trip(
            &mut app,
            Request::Edit(Edit::Move(vec![(v, p + Vec3::new(0.1, -0.2, 0.3))])),
        );
    }
}

#[test]
fn every_global_edit_undoes_and_redoes_exactly() {
    use pappus::ops::simplification_history::SimplificationHistory as History;
    let mut app = app();
    open(&mut app, "shape:cube");
    round_trip(
        &mut app,
        Request::Edit(Edit::registered("catmull-clark").unwrap()),
    );
    round_trip(
        &mut app,
        Request::Edit(Edit::registered("triangulate").unwrap()),
    );
    round_trip(&mut app, Request::Edit(Edit::registered("loop").unwrap()));
    round_trip(&mut app, Request::Edit(Edit::registered("remesh").unwrap()));
    round_trip(
        &mut app,
        Request::Edit(Edit::invoked("simplify:0.5").unwrap()),
    );
    // Undo and redo end the simplification's own history; simplify again for the slider and
    // for splitting a vertex back.
    request(
        &mut app,
        Request::Edit(Edit::invoked("simplify:0.5").unwrap()),
    )
    .unwrap();
    let next = {
        let pm = History::of(app.world(), active(&app).unwrap()).unwrap();
        pm.next_split_vertex().unwrap()
    };
    round_trip(&mut app, Request::Edit(Edit::local("vertex-split", next)));
    request(
        &mut app,
        Request::Edit(Edit::invoked("simplify:0.5").unwrap()),
    )
    .unwrap();
    let full = History::of(app.world(), active(&app).unwrap())
        .unwrap()
        .full_faces;
    round_trip(
        &mut app,
        Request::Edit(Edit::Operation(pappus::ops::decimate::Refine::to(Some(
            full,
        )))),
    );
    // Opening over the edits (after the question) and deleting replace the mesh; undo brings
    // the old one back.
    assert!(request(&mut app, Request::Open("shape:torus".into())).is_err());
    round_trip(&mut app, Request::ConfirmDiscard(true));
    round_trip(&mut app, Request::DeleteMesh);
    assert_eq!(active(&app), None);
    // Opening over no mesh loses nothing: it is not an entry.
    let depth = undo_depth(&app);
    request(&mut app, Request::Open("shape:tetrahedron".into())).unwrap();
    assert_eq!(undo_depth(&app), depth);
}

/// A small deterministic generator (xorshift).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn random_edit(app: &App, rng: &mut Rng) -> Request {
    let m = MeshRef::new(app.world());
    let all = members(app);
    let e = all.edges[rng.below(all.edges.len())];
    match rng.below(7) {
        0 | 1 => Request::Edit(Edit::local("flip", e)),
        2 => Request::Edit(Edit::local("split", e)),
        3 | 4 => Request::Edit(Edit::local("collapse", e)),
        5 => Request::Edit(Edit::local("dissolve", e)),
        _ => {
            let v = all.vertices[rng.below(all.vertices.len())];
            let d = (rng.below(1000) as f32 - 500.0) * 1e-4;
            Request::Edit(Edit::Move(vec![(v, m.position(v) + Vec3::splat(d))]))
        }
    }
}

#[test]
fn random_edits_undo_to_the_original_and_redo_to_the_end() {
    let mut app = app();
    for (shape, seed) in [
        ("shape:icosphere:2", 7),
        ("shape:grid-with-holes", 11),
        ("shape:torus:12:8", 13),
    ] {
        open(&mut app, shape);
        let original = state(&app);
        let opened = undo_depth(&app);
        let mut rng = Rng(seed);
        let mut applied = 0;
        for step in 0..250 {
            let r = random_edit(&app, &mut rng);
            if request(&mut app, r).is_ok() {
                applied += 1;
            }
            // Now and then, step back and forth in the middle of the sequence.
            if step % 37 == 0 && applied > 2 {
                let here = state(&app);
                request(&mut app, Request::Undo).unwrap();
                request(&mut app, Request::Undo).unwrap();
                request(&mut app, Request::Redo).unwrap();
                request(&mut app, Request::Redo).unwrap();
                assert_eq!(state(&app), here, "{shape}: step {step}");
            }
            if step % 25 == 0 {
                state(&app);
            }
        }
        assert!(applied > 100, "{shape}: only {applied} edits applied");
        // Moves of one vertex in a row may merge only while a mouse button is held: none here.
        assert_eq!(
            undo_depth(&app),
            opened + applied,
            "{shape}: one entry per edit"
        );
        let end = state(&app);
        for _ in 0..applied {
            request(&mut app, Request::Undo).unwrap();
        }
        assert_eq!(state(&app), original, "{shape}: undone to the start");
        for _ in 0..applied {
            request(&mut app, Request::Redo).unwrap();
        }
        assert_eq!(state(&app), end, "{shape}: redone to the end");
        assert!(
            request(&mut app, Request::Redo).is_err(),
            "nothing left to redo"
        );
    }
}

#[test]
fn mixed_history_keeps_ids_valid_across_global_restores() {
    let mut app = app();
    open(&mut app, "shape:icosphere:1");
    let mut states = vec![state(&app)];
    let interior = is_interior;
    let steps: Vec<MakeRequest> = vec![
        Box::new(move |a| Request::Edit(Edit::local("flip", edge_where(a, interior)))),
        Box::new(move |_| Request::Edit(Edit::registered("loop").unwrap())),
        Box::new(move |a| Request::Edit(Edit::local("collapse", edge_where(a, interior)))),
        Box::new(move |a| Request::Edit(Edit::local("split", edge_where(a, interior)))),
        Box::new(move |_| Request::Edit(Edit::invoked("simplify:0.6").unwrap())),
        Box::new(move |a| Request::Edit(Edit::local("dissolve", edge_where(a, interior)))),
        Box::new(move |_| Request::Edit(Edit::registered("catmull-clark").unwrap())),
        Box::new(move |a| Request::Edit(Edit::local("collapse", edge_where(a, interior)))),
    ];
    for step in &steps {
        let r = step(&app);
        request(&mut app, r).unwrap();
        states.push(state(&app));
    }
    // All the way back, checking each state; then all the way forward.
    for expected in states.iter().rev().skip(1) {
        request(&mut app, Request::Undo).unwrap();
        assert_eq!(&state(&app), expected);
    }
    // The first open replaced nothing: there is nothing more to undo, and the mesh stays.
    assert!(request(&mut app, Request::Undo).is_err());
    assert!(active(&app).is_some());
    for expected in states.iter().skip(1) {
        request(&mut app, Request::Redo).unwrap();
        assert_eq!(&state(&app), expected);
    }
    // Half way back, then a new edit: the redo stack is gone.
    for _ in 0..4 {
        request(&mut app, Request::Undo).unwrap();
    }
    let e = edge_where(&app, interior);
    request(&mut app, Request::Edit(Edit::local("flip", e))).unwrap();
    assert!(request(&mut app, Request::Redo).is_err());
    assert_eq!(undo_depth(&app), states.len() - 1 - 4 + 1);
}

#[test]
fn the_selection_follows_undo_and_redo() {
    let mut app = app();
    request(&mut app, Request::Open("shape:icosphere:1".into())).unwrap();
    let e = edge_where(&app, is_interior);
    request(&mut app, Request::Select(Some(ElementId::Edge(e)))).unwrap();
    request(&mut app, Request::Edit(Edit::local("collapse", e))).unwrap();
    let kept = app.world().resource::<Selection>().element;
    assert!(matches!(kept, Some(ElementId::Vertex(_))));
    request(&mut app, Request::Undo).unwrap();
    // The edge was brought back under a new id, and it is selected again.
    let Some(ElementId::Edge(back)) = app.world().resource::<Selection>().element else {
        panic!("the collapsed edge should be selected again");
    };
    assert_ne!(back, e);
    let m = MeshRef::new(app.world());
    assert!(m.try_edge(back).is_some());
    request(&mut app, Request::Redo).unwrap();
    assert_eq!(app.world().resource::<Selection>().element, kept);
}

fn mouse(app: &mut App, state: ButtonState) {
    app.world_mut().write_message(MouseButtonInput {
        button: MouseButton::Left,
        state,
        window: Entity::PLACEHOLDER,
    });
    app.update();
}

#[test]
fn a_drag_is_one_entry() {
    let mut app = app();
    open(&mut app, "shape:icosphere:1");
    let v = members(&app).vertices[0];
    let start = MeshRef::new(app.world()).position(v);
    let before = undo_depth(&app);
    for drag in 0..2 {
        mouse(&mut app, ButtonState::Pressed);
        for i in 1..=5 {
            let p = start + Vec3::X * (drag * 5 + i) as f32 * 0.01;
            request(&mut app, Request::Edit(Edit::Move(vec![(v, p)]))).unwrap();
        }
        mouse(&mut app, ButtonState::Released);
    }
    assert_eq!(undo_depth(&app), before + 2, "one entry per press");
    request(&mut app, Request::Undo).unwrap();
    let p = MeshRef::new(app.world()).position(v);
    let first_end = start + Vec3::X * 5.0 * 0.01;
    assert_eq!(p, first_end, "back to the end of the first drag");
    request(&mut app, Request::Undo).unwrap();
    let p = MeshRef::new(app.world()).position(v);
    assert_eq!(
        p.to_array().map(f32::to_bits),
        start.to_array().map(f32::to_bits)
    );
}

#[test]
fn the_memory_cap_drops_the_oldest_entries() {
    let mut app = app();
    open(&mut app, "shape:quad-grid");
    request(
        &mut app,
        Request::Edit(Edit::registered("catmull-clark").unwrap()),
    )
    .unwrap();
    request(
        &mut app,
        Request::Edit(Edit::registered("triangulate").unwrap()),
    )
    .unwrap();
    request(&mut app, Request::Edit(Edit::registered("remesh").unwrap())).unwrap();
    let whole = app.world().resource::<UndoHistory>().undo_entries()[2].bytes();
    // Room for two and a half whole-mesh entries of this size.
    let cap = whole * 5 / 2;
    app.world_mut().resource_mut::<UndoHistory>().limit_bytes = cap;
    for _ in 0..4 {
        let e = edge_where(&app, is_interior);
        request(&mut app, Request::Edit(Edit::local("flip", e))).unwrap();
        request(&mut app, Request::Edit(Edit::registered("remesh").unwrap())).unwrap();
    }
    let e = edge_where(&app, is_interior);
    request(&mut app, Request::Edit(Edit::local("flip", e))).unwrap();
    let history = app.world().resource::<UndoHistory>();
    assert!(history.bytes() <= cap, "{} > {cap}", history.bytes());
    let labels: Vec<String> = history
        .undo_entries()
        .iter()
        .map(|e| e.label.clone())
        .collect();
    assert!(labels.len() >= 3, "{labels:?}");
    let early = ["Catmull", "triangulate"];
    assert!(
        !labels
            .iter()
            .any(|l| early.iter().any(|x| l.starts_with(x))),
        "the oldest go first: {labels:?}"
    );
    assert!(labels.last().unwrap().starts_with("flip"));
    // What is left still undoes cleanly, and no further.
    for _ in 0..labels.len() {
        request(&mut app, Request::Undo).unwrap();
        state(&app);
    }
    assert!(request(&mut app, Request::Undo).is_err());
}

#[test]
fn a_refused_edit_leaves_no_entry() {
    let mut app = app();
    open(&mut app, "shape:grid");
    let depth = undo_depth(&app);
    let e = edge_where(&app, is_boundary);
    assert!(request(&mut app, Request::Edit(Edit::local("flip", e))).is_err());
    assert_eq!(undo_depth(&app), depth);
    assert!(
        request(&mut app, Request::Undo)
            .unwrap_err()
            .contains("nothing to undo")
    );
}

/// Remeshing 10 iterations is one entry, and it holds less than the mesh's own components
/// (the bound is 3×).
#[test]
fn remeshing_history_is_smaller_than_the_mesh() {
    let mut app = app();
    open(&mut app, "shape:icosphere:3");
    let mesh = active(&app).unwrap();
    let own = pappus::mesh::change::component_bytes(app.world(), mesh);
    let before = app.world().resource::<UndoHistory>().bytes();
    request(&mut app, Request::Edit(Edit::registered("remesh").unwrap())).unwrap();
    request(&mut app, Request::Edit(Edit::registered("remesh").unwrap())).unwrap();
    let held = app.world().resource::<UndoHistory>().bytes() - before;
    // Two remeshes of 5 iterations: two whole-mesh entries.
    assert!(
        held < 3 * own,
        "{held} bytes of history for a {own}-byte mesh"
    );
    request(&mut app, Request::Undo).unwrap();
    request(&mut app, Request::Undo).unwrap();
    assert_eq!(mesh_stats(app.world(), mesh).faces, 1280);
}

// Jobs: whole-mesh operations on large meshes run on a thread while frames go on.

fn job_running(app: &App) -> bool {
    app.world()
        .resource::<pappus::editor::pipeline::jobs::Jobs>()
        .running
        .is_some()
}

fn job_progress(app: &App) -> f32 {
    let jobs = app
        .world()
        .resource::<pappus::editor::pipeline::jobs::Jobs>();
    jobs.running.as_ref().map_or(1.0, |j| j.progress.fraction())
}

/// Runs frames until `done`, for at most a minute; returns the frames it took.
fn frames_until(app: &mut App, done: impl Fn(&App) -> bool) -> u32 {
    let start = std::time::Instant::now();
    let mut frames = 0;
    while !done(app) {
        assert!(
            start.elapsed().as_secs() < 60,
            "timed out after {frames} frames"
        );
        app.update();
        frames += 1;
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    frames
}

fn jobs_from(app: &mut App, faces: usize) {
    app.world_mut()
        .resource_mut::<pappus::editor::pipeline::jobs::JobSettings>()
        .min_faces = faces;
}

#[test]
fn a_cancelled_job_leaves_the_mesh_exactly_as_it_was() {
    let mut app = app();
    jobs_from(&mut app, 1000);
    open(&mut app, "shape:icosphere:5");
    let before = state(&app);
    let depth = undo_depth(&app);
    let started = request(
        &mut app,
        Request::Edit(Edit::invoked("simplify:0.02").unwrap()),
    )
    .unwrap();
    assert!(started.contains("running"), "{started}");
    // Frames go on while the thread works, and its progress shows.
    let frames = frames_until(&mut app, |a| job_progress(a) > 0.0);
    assert!(
        job_running(&app),
        "the job finished before it could be cancelled"
    );
    assert!(frames >= 1);
    // Edits wait for the job.
    let e = edge_where(&app, is_interior);
    let refused = request(&mut app, Request::Edit(Edit::local("flip", e))).unwrap_err();
    assert!(refused.contains("still running"), "{refused}");
    assert!(request(&mut app, Request::Undo).is_err());
    // Esc cancels it.
    app.world_mut()
        .write_message(bevy::input::keyboard::KeyboardInput {
            key_code: KeyCode::Escape,
            logical_key: bevy::input::keyboard::Key::Escape,
            state: ButtonState::Pressed,
            text: None,
            repeat: false,
            window: Entity::PLACEHOLDER,
        });
    app.update();
    assert!(!job_running(&app));
    assert!(last(&app).result.unwrap().contains("unchanged"));
    // Nothing arrives later either.
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(state(&app), before);
    assert_eq!(undo_depth(&app), depth);
}

#[test]
fn a_finished_job_commits_as_one_undo_entry() {
    use pappus::ops::simplification_history::SimplificationHistory as History;
    let mut app = app();
    jobs_from(&mut app, 100);
    open(&mut app, "shape:icosphere:3");
    let mesh = active(&app).unwrap();
    let before = state(&app);
    let depth = undo_depth(&app);
    let v = members(&app).vertices[0];
    request(&mut app, Request::Select(Some(ElementId::Vertex(v)))).unwrap();
    assert!(
        request(
            &mut app,
            Request::Edit(Edit::invoked("simplify:0.5").unwrap())
        )
        .is_ok()
    );
    frames_until(&mut app, |a| !job_running(a));
    let outcome = last(&app);
    assert!(outcome.request.starts_with("simplify"), "{outcome:?}");
    assert!(outcome.result.unwrap().starts_with("1280 -> 640 faces"));
    assert_eq!(mesh_stats(app.world(), mesh).faces, 640);
    assert_eq!(undo_depth(&app), depth + 1);
    let after = state(&app);
    // The selection still names a live vertex, if any.
    if let Some(x) = app.world().resource::<Selection>().element {
        assert!(matches!(x, ElementId::Vertex(_)));
        assert!(
            MeshRef::new(app.world())
                .try_vertex(match x {
                    ElementId::Vertex(v) => v,
                    _ => unreachable!(),
                })
                .is_some()
        );
    }
    // The simplification's history came across: the slider moves, exactly.
    assert!(History::of(app.world(), mesh).is_some());
    request(
        &mut app,
        Request::Edit(Edit::Operation(pappus::ops::decimate::Refine::to(Some(
            1280,
        )))),
    )
    .unwrap();
    assert_eq!(
        state(&app),
        before,
        "refined all the way: the original mesh"
    );
    request(&mut app, Request::Undo).unwrap();
    assert_eq!(state(&app), after);
    request(&mut app, Request::Undo).unwrap();
    assert_eq!(state(&app), before);
    // Loop subdivision as a job too.
    request(&mut app, Request::Edit(Edit::registered("loop").unwrap())).unwrap();
    frames_until(&mut app, |a| !job_running(a));
    assert_eq!(mesh_stats(app.world(), mesh).faces, 5120);
    request(&mut app, Request::Undo).unwrap();
    assert_eq!(state(&app), before);
}

/// A 2 × 2 grid of quads (`quads`) or of triangles, with corner UVs, vertex normals and vertex
/// colours, written to a file of its own.
fn attributed_grid(quads: bool) -> std::path::PathBuf {
    let mut text = String::new();
    for y in 0..3 {
        for x in 0..3 {
            let colour = [x as f32 / 2.0, y as f32 / 2.0, 0.5];
            text += &format!(
                "v {x} {y} {} {} {} {}\n",
                (x * y) as f32 * 0.1,
                colour[0],
                colour[1],
                colour[2]
            );
            text += &format!("vt {} {}\n", x as f32 / 2.0, y as f32 / 2.0);
        }
    }
    text += "vn 0 0 1\n";
    let at = |x: usize, y: usize| 3 * y + x + 1;
    let corner = |v: usize| format!("{v}/{v}/1");
    for y in 0..2 {
        for x in 0..2 {
            let [a, b, c, d] = [at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)];
            let faces = if quads {
                vec![vec![a, b, c, d]]
            } else {
                vec![vec![a, b, c], vec![a, c, d]]
            };
            for f in faces {
                let corners: Vec<String> = f.into_iter().map(corner).collect();
                text += &format!("f {}\n", corners.join(" "));
            }
        }
    }
    let path = std::env::temp_dir().join(format!(
        "pappus-job-grid-{}-{quads}.obj",
        std::process::id()
    ));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_subdivision_job_commits_exactly_what_the_edit_makes_at_once() {
    // A job computes subdivision on the mesh's tables alone; it must give the mesh, the
    // attributes, the outcome and the selection that applying the edit at once gives.
    let cases = [
        (false, Edit::invoked("loop").unwrap()),
        (true, Edit::invoked("catmull-clark:2").unwrap()),
    ];
    for (quads, subdivision) in cases {
        let path = attributed_grid(quads);
        let run = |as_job: bool| {
            let mut app = app();
            jobs_from(&mut app, if as_job { 1 } else { usize::MAX });
            open(&mut app, path.to_str().unwrap());
            let v = members(&app).vertices[4];
            request(&mut app, Request::Select(Some(ElementId::Vertex(v)))).unwrap();
            let started = request(&mut app, Request::Edit(subdivision.clone()));
            assert_eq!(started.is_ok_and(|s| s.contains("running")), as_job);
            frames_until(&mut app, |a| !job_running(a));
            let outcome = last(&app).result.unwrap();
            let soup = to_soup(app.world(), active(&app).unwrap());
            let selected = app.world().resource::<Selection>().element;
            assert_eq!(
                selected,
                Some(ElementId::Vertex(v)),
                "the vertex stays selected"
            );
            (soup, outcome)
        };
        let (job, at_once) = (run(true), run(false));
        assert!(job.0.corner_uvs.is_some() && job.0.vertex_colors.is_some());
        assert!(
            job.1.contains("normals"),
            "the dropped normals are said: {}",
            job.1
        );
        assert_eq!(job, at_once, "{subdivision:?}");
        std::fs::remove_file(path).ok();
    }
}

#[test]
fn loop_refuses_a_quad_mesh_as_a_job_naming_a_face_of_the_mesh() {
    use pappus::editor::session::requests::Declined;
    use pappus::ops::Refusal;
    let mut app = app();
    jobs_from(&mut app, 1);
    open(&mut app, "shape:quad-grid");
    let (before, depth) = (state(&app), undo_depth(&app));
    let started = request(&mut app, Request::Edit(Edit::registered("loop").unwrap()));
    assert!(started.is_ok_and(|s| s.contains("running")));
    frames_until(&mut app, |a| !job_running(a));
    let Err(Declined::Refused(Refusal::NotTriangle(ElementId::Face(f)))) = last(&app).result else {
        panic!("{:?}", last(&app));
    };
    assert!(
        MeshRef::new(app.world()).try_face(f).is_some(),
        "the refusal names a face of the mesh, not of a copy"
    );
    assert_eq!(state(&app), before);
    assert_eq!(undo_depth(&app), depth);
}
