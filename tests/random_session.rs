//! A long random editing session through the editor's own pipeline: every kind of request — each
//! local and whole-mesh edit, moves along the simplification history, undo, redo, jobs started
//! and cancelled or let finish, selections of live and stale ids, navigation — in a seeded random
//! order. After each request the mesh validates (and every applied edit validated it already:
//! `Edit::run` checks in debug builds); a refused request leaves no undo entry. At the end,
//! undoing everything gives back the input bit for bit.

mod common;

use bevy::prelude::*;
use common::canonical;
use pappus::edit::Edit;
use pappus::editor::pipeline::jobs::{JobSettings, Jobs};
use pappus::editor::session::history::UndoHistory;
use pappus::editor::session::requests::{Relation, Request};
use pappus::editor::session::selection::ActiveMesh;
use pappus::mesh::ids::{EdgeId, ElementId, FaceId, VertexId};
use pappus::mesh::{MeshMembers, MeshRef, to_soup, validate};
use pappus::ops::named::Named;
use pappus::ops::smooth::SmoothMethod;

/// How many requests the session makes.
const REQUESTS: usize = 10_000;

/// Whole-mesh edits that grow the mesh are asked only below this many faces.
const GROW_BELOW_FACES: usize = 700;

/// A small deterministic generator (xorshift64*): the session is the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<T: Copy>(&mut self, items: &[T]) -> Option<T> {
        (!items.is_empty()).then(|| items[self.below(items.len())])
    }
}

fn members(app: &App) -> MeshMembers {
    MeshMembers::collect(app.world(), app.world().resource::<ActiveMesh>().0.unwrap())
}

fn undo_depth(app: &App) -> usize {
    app.world().resource::<UndoHistory>().undo_entries().len()
}

/// The next request, drawn from the app's current state.
fn draw(app: &App, rng: &mut Rng, stale: &[ElementId]) -> Request {
    let m = members(app);
    let world = app.world();
    let r = MeshRef::new(world);
    let edge = |rng: &mut Rng| -> Option<EdgeId> { rng.pick(&m.edges) };
    let vertex = |rng: &mut Rng| -> Option<VertexId> { rng.pick(&m.vertices) };
    let face = |rng: &mut Rng| -> Option<FaceId> { rng.pick(&m.faces) };
    let faces = m.faces.len();
    let roll = rng.below(100);
    let edit = match roll {
        0..=11 => edge(rng).map(|e| Edit::local("flip", e)),
        12..=18 => edge(rng).map(|e| Edit::local("split", e)),
        19..=21 => edge(rng).map(|e| Edit::local("bisect", e)),
        22..=35 => edge(rng).map(|e| Edit::local("collapse", e)),
        36..=40 => edge(rng).map(|e| Edit::local("dissolve", e)),
        41 => edge(rng).map(|e| Edit::local("fill-hole", e)),
        42..=45 => face(rng).map(|f| {
            let corners: Vec<VertexId> = r.face_vertices(f).collect();
            let a = rng.below(corners.len());
            let b = (a + 2 + rng.below(corners.len().saturating_sub(2).max(1))) % corners.len();
            Edit::local_on(
                "split-face",
                [f.into(), corners[a].into(), corners[b].into()] as [ElementId; 3],
                &[],
            )
        }),
        46..=50 => vertex(rng).map(|v| {
            let nudge = Vec3::new(
                rng.below(1000) as f32 / 1e5 - 0.005,
                rng.below(1000) as f32 / 1e5 - 0.005,
                rng.below(1000) as f32 / 1e5 - 0.005,
            );
            Edit::Move(vec![(v, r.position(v) + nudge)])
        }),
        51..=52 => vertex(rng).map(|v| Edit::local("vertex-split", v)),
        53..=54 => Some(Edit::Operation(pappus::ops::decimate::Refine::to(Some(
            rng.below(2 * faces + 2),
        )))),
        // Any registered whole-mesh operation with its defaults (triangulate, reverse, normalize, remesh,
        // param, …), subdivision only while the mesh is small, as below.
        55 => {
            let whole: Vec<_> = pappus::ops::registry::operations()
                .into_iter()
                .filter(|op| op.declaration().names == pappus::ops::declaration::Names::Mesh)
                .collect();
            let op = whole[rng.below(whole.len())];
            let invocation = pappus::edit::Invocation::with_defaults(op);
            let grows = pappus::ops::subdivide::subdivision(&invocation).is_some();
            (!grows || faces < GROW_BELOW_FACES).then_some(Edit::Operation(invocation))
        }
        56..=57 => Some(
            Edit::invoked(&format!("simplify:{}", 0.5 + rng.below(40) as f64 / 100.0)).unwrap(),
        ),
        58 if faces < GROW_BELOW_FACES => Some(Edit::registered("loop").unwrap()),
        59 if faces < GROW_BELOW_FACES => Some(Edit::registered("catmull-clark").unwrap()),
        60 => Some(Edit::invoked("remesh:1").unwrap()),
        61 => {
            let method = SmoothMethod::ALL[rng.below(4)].1;
            Some(Edit::invoked(&format!("smooth:{method}:2")).unwrap())
        }
        _ => None,
    };
    if let Some(edit) = edit {
        return Request::Edit(edit);
    }
    match roll {
        62..=74 => Request::Undo,
        75..=81 => Request::Redo,
        82..=85 => Request::Select(rng.pick(stale)),
        86..=91 => Request::Select(edge(rng).map(ElementId::Edge)),
        92..=95 => Request::Navigate(rng.pick(&Relation::ALL).unwrap()),
        96..=97 => Request::CancelJob,
        _ => Request::Select(vertex(rng).map(ElementId::Vertex)),
    }
}

#[test]
fn ten_thousand_random_requests_keep_the_mesh_valid_and_undo_to_the_input() {
    let mut app = common::headless_editor();
    app.world_mut()
        .write_message(Request::Open("shape:grid-with-holes:3".into()));
    app.update();
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    let input = canonical(&to_soup(app.world(), mesh));
    // Meshes of a few hundred faces run whole-mesh edits as jobs: some are cancelled before
    // they finish, some finish while other requests wait.
    app.world_mut().resource_mut::<JobSettings>().min_faces = 400;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut stale: Vec<ElementId> = Vec::new();
    let (mut applied, mut declined, mut jobs) = (0, 0, 0);
    for i in 0..REQUESTS {
        let before = members(&app);
        let request = draw(&app, &mut rng, &stale);
        let depth = undo_depth(&app);
        let job_before = app.world().resource::<Jobs>().running.is_some();
        app.world_mut().write_message(request.clone());
        app.update();
        let outcome = common::last_outcome(&app);
        let job_now = app.world().resource::<Jobs>().running.is_some();
        if job_now && !job_before {
            jobs += 1;
            // Half the jobs are cancelled at once; the others finish while the editor waits.
            if rng.below(2) == 0 {
                app.world_mut().write_message(Request::CancelJob);
                app.update();
            } else {
                while app.world().resource::<Jobs>().running.is_some() {
                    std::thread::sleep(std::time::Duration::from_millis(1));
                    app.update();
                }
            }
        }
        match &outcome.result {
            Ok(_) => applied += 1,
            Err(_) => {
                declined += 1;
                if matches!(request, Request::Edit(_)) && !job_now {
                    assert_eq!(
                        undo_depth(&app),
                        depth,
                        "request {i} ({}) was declined but left an undo entry",
                        outcome.request
                    );
                }
            }
        }
        if let Err(e) = validate(app.world(), mesh) {
            panic!(
                "request {i} ({}) left an invalid mesh: {e}",
                outcome.request
            );
        }
        // Ids of elements that are gone become the stale ids later selections try.
        let now: std::collections::HashSet<VertexId> = members(&app).vertices.into_iter().collect();
        let gone = before
            .vertices
            .iter()
            .filter(|v| !now.contains(v))
            .map(|&v| ElementId::Vertex(v));
        stale.extend(gone.take(4));
        if stale.len() > 64 {
            stale.drain(..32);
        }
    }
    assert!(applied > REQUESTS / 3, "applied {applied} of {REQUESTS}");
    assert!(
        declined > 100,
        "declined {declined}: the refusals were exercised"
    );
    assert!(jobs > 10, "started {jobs} jobs");
    // Undo everything: the input again, bit for bit.
    while undo_depth(&app) > 0 {
        app.world_mut().write_message(Request::Undo);
        app.update();
        assert!(common::last_outcome(&app).result.is_ok());
    }
    assert_eq!(canonical(&to_soup(app.world(), mesh)), input);
}
