//! Lab mode (`edit::lab`): the example lab's flip, split and collapse (`examples/lab/`) run
//! beside Pappus's own on random interior edges of the shared models and are the same each
//! time; a flip with a mistake is reported by what is wrong with it, and where its result is
//! invalid (or it panics) the mesh is exactly as it was.

mod common;
#[path = "../examples/lab/mistakes.rs"]
mod mistakes;
#[path = "../examples/lab/student.rs"]
mod student;

use bevy::prelude::{App, World};
use pappus::edit::lab::{LabReport, Verdict, compare};
use pappus::edit::{Edit, EditContext, Invocation};
use pappus::mesh::{EdgeId, ElementId, MeshId, MeshMembers, MeshRef, shapes, validate};
use pappus::ops::Refusal;
use pappus::ops::declaration::{Declaration, Names};
use pappus::ops::operation::MeshOperation;
use student::OnEdge;

/// `op` on the edge `e`.
fn invocation(op: &'static dyn MeshOperation, e: EdgeId) -> Invocation {
    Invocation::with_defaults(op)
        .on(vec![e.into()])
        .expect("an edge")
}

/// Runs `op` on `e` as any edit runs, checked against its reference.
fn run(
    world: &mut World,
    mesh: MeshId,
    op: &'static dyn MeshOperation,
    e: EdgeId,
) -> Result<String, Refusal> {
    let edit = Edit::Operation(invocation(op, e));
    let mut context = EditContext {
        progress: &mut |_| true,
    };
    edit.run(world, mesh, &mut context)
        .map(|applied| applied.summary)
}

/// The interior edges of `mesh`, every `step`th from a start that `seed` picks.
fn interior_edges(world: &World, mesh: MeshId, step: usize, seed: usize) -> Vec<EdgeId> {
    let m = MeshRef::new(world);
    let edges = MeshMembers::collect(world, mesh).edges;
    let interior = edges.into_iter().filter(|&e| !m.is_boundary_edge(e));
    interior.skip(seed % step).step_by(step).collect()
}

/// The student's three operations on `per_operation` interior edges of `soup` each, applied in
/// turn (so each meets the mesh the others left): each is the reference's where that applies,
/// refused as it is where it refuses. Returns how many were the same.
fn same_as_the_reference(
    soup: &pappus::mesh::PolygonSoup,
    per_operation: usize,
    label: &str,
) -> usize {
    let (mut world, built) = common::build(soup);
    let mesh = built.mesh;
    let mut same = 0;
    for (i, op) in student::LAB.iter().enumerate() {
        let step = 1 + soup.face_count() * 3 / 2 / per_operation;
        let edges = interior_edges(&world, mesh, step, 7 * i + 3);
        for e in edges {
            if MeshRef::new(&world).try_edge(e).is_none() {
                continue; // removed by an earlier collapse
            }
            let name = op.declaration.reference.expect("declared");
            match run(&mut world, mesh, op, e) {
                Ok(summary) => {
                    assert!(
                        summary.ends_with(&format!("lab: same as {name}")),
                        "{label}: {summary}"
                    );
                    same += 1;
                }
                Err(Refusal::Lab(report)) => {
                    assert!(
                        report.starts_with(&format!("refused, as {name} is")),
                        "{label}: {report}"
                    );
                }
                Err(other) => panic!("{label}: {} on {e}: {other}", op.declaration.name),
            }
        }
    }
    validate(&world, mesh).expect("valid after the lab");
    same
}

#[test]
fn the_example_labs_operations_are_the_references_on_an_icosphere() {
    assert!(same_as_the_reference(&shapes::icosphere(3), 60, "icosphere") > 120);
}

#[test]
fn the_example_labs_operations_are_the_references_on_the_shared_models() {
    let mut same = 0;
    for name in ["spot.obj", "cow.obj", "homer.obj"] {
        let Some(path) = common::model(name) else {
            return common::skip_because(
                &format!("../shared/models/{name}"),
                "the_example_labs_operations_are_the_references_on_the_shared_models",
            );
        };
        let (soup, _) = pappus::source::read_source(&path).expect("reads");
        same += same_as_the_reference(&soup, 12, name);
    }
    assert!(same > 60, "{same}");
}

/// A flip that turns the edge the other way makes a valid mesh, but not `flip`'s: the report
/// names the first face that differs, by the mesh's id, and the flip is applied.
#[test]
fn a_flip_the_other_way_is_valid_but_different_and_applied() {
    let (mut world, built) = common::build(&shapes::icosphere(2));
    let mesh = built.mesh;
    let e = interior_edges(&world, mesh, 1, 0)[5];
    let op: &'static dyn MeshOperation = &mistakes::MISTAKES[0];
    let report = compare(&world, mesh, &invocation(op, e)).unwrap();
    let Verdict::Different(what) = &report.verdict else {
        panic!("{report}");
    };
    let f = MeshRef::new(&world)
        .face(MeshRef::new(&world).edge_halfedge(e))
        .unwrap();
    assert!(what.starts_with(&format!("{f}: corners ")), "{what}");
    assert!(what.contains(", the reference has "), "{what}");
    let summary = run(&mut world, mesh, op, e).unwrap();
    assert!(
        summary.contains("lab: valid, but not what flip makes: "),
        "{summary}"
    );
    validate(&world, mesh).unwrap();
}

/// A flip that leaves a halfedge on its old face is invalid: refused, naming that halfedge by
/// the mesh's id and the rule, and the world is exactly as it was.
#[test]
fn a_flip_forgetting_a_face_is_invalid_and_leaves_the_mesh_as_it_was() {
    let (mut world, built) = common::build(&shapes::icosphere(2));
    let mesh = built.mesh;
    let e = interior_edges(&world, mesh, 1, 0)[5];
    let op: &'static dyn MeshOperation = &mistakes::MISTAKES[1];
    let report = compare(&world, mesh, &invocation(op, e)).unwrap();
    let Verdict::Invalid(what) = &report.verdict else {
        panic!("{report}");
    };
    // One of the six halfedges of the two triangles, by the mesh's id.
    let m = MeshRef::new(&world);
    let (h, t) = (m.edge_halfedge(e), m.twin(m.edge_halfedge(e)));
    let wings = [h, m.next(h), m.prev(h), t, m.next(t), m.prev(t)];
    assert!(
        wings.iter().any(|h| what.starts_with(&format!("{h}: "))),
        "{what}"
    );
    let before = common::snapshot(&mut world, mesh);
    let refusal = run(&mut world, mesh, op, e).unwrap_err();
    assert_eq!(refusal, Refusal::Lab(report.to_string()));
    assert!(
        refusal.to_string().ends_with("; the mesh is as it was"),
        "{refusal}"
    );
    assert_eq!(common::snapshot(&mut world, mesh), before);
}

const PANICS: Declaration = Declaration::new("lab-panics")
    .naming(Names::Edge)
    .checked_against("flip");
const WRITES_BY_HAND: Declaration = Declaration::new("lab-writes-by-hand")
    .naming(Names::Edge)
    .checked_against("flip");

/// A student's operation that panics, and one that corrupts the structure through the
/// components themselves (no checked edit): both refused by what they did, the mesh as it was.
#[test]
fn a_panicking_or_corrupting_operation_is_refused_and_leaves_the_mesh_as_it_was() {
    let panics: &'static dyn MeshOperation = &OnEdge {
        declaration: &PANICS,
        run: |_, _, e| panic!("the student's bug at {e}"),
        says: "",
    };
    let corrupts: &'static dyn MeshOperation = &OnEdge {
        declaration: &WRITES_BY_HAND,
        run: |world, _, e| {
            let h = MeshRef::new(world).edge_halfedge(e);
            world.get_mut::<pappus::mesh::Halfedge>(h.0).unwrap().next = h;
            Ok(e.into())
        },
        says: "",
    };
    let (mut world, built) = common::build(&shapes::icosphere(2));
    let mesh = built.mesh;
    let e = interior_edges(&world, mesh, 1, 0)[3];
    let h = MeshRef::new(&world).edge_halfedge(e);
    let before = common::snapshot(&mut world, mesh);
    let report = compare(&world, mesh, &invocation(panics, e)).unwrap();
    assert_eq!(
        report,
        LabReport {
            reference: "flip",
            verdict: Verdict::Panicked(format!("the student's bug at {e}")),
        }
    );
    assert_eq!(
        run(&mut world, mesh, panics, e).unwrap_err(),
        Refusal::Lab(report.to_string())
    );
    let report = compare(&world, mesh, &invocation(corrupts, e)).unwrap();
    let Verdict::Invalid(what) = &report.verdict else {
        panic!("{report}");
    };
    let named = [
        ElementId::Halfedge(h),
        ElementId::Halfedge(MeshRef::new(&world).next(h)),
    ];
    assert!(
        named.iter().any(|x| what.starts_with(&format!("{x}: "))),
        "{what}"
    );
    assert!(run(&mut world, mesh, corrupts, e).is_err());
    assert_eq!(common::snapshot(&mut world, mesh), before);
}

/// Where the reference refuses, so does the student's (a boundary edge), and the report says
/// both refused; an operation without a reference is no lab's.
#[test]
fn refusals_are_compared_too() {
    let (world, built) = common::build(&shapes::grid(3, 3));
    let mesh = built.mesh;
    let m = MeshRef::new(&world);
    let boundary = MeshMembers::collect(&world, mesh)
        .edges
        .into_iter()
        .find(|&e| m.is_boundary_edge(e))
        .unwrap();
    let report = compare(&world, mesh, &invocation(&student::LAB[0], boundary)).unwrap();
    assert!(
        matches!(
            report.verdict,
            Verdict::BothRefused(Refusal::BoundaryEdge(_))
        ),
        "{report}"
    );
    let flip = pappus::ops::registry::operation("flip").unwrap();
    assert!(compare(&world, mesh, &invocation(flip, boundary)).is_err());
}

/// In the editor the example's operations are keys of their own: Alt+1 on the selected edge
/// flips it and says it was the same as `flip`; Alt+5 is refused with the mesh as it was, and
/// undo takes back only the flip.
#[test]
fn the_example_labs_keys_report_in_the_editor() {
    use bevy::input::ButtonState;
    use bevy::prelude::KeyCode;
    use pappus::editor::AddOperation;
    use pappus::editor::session::requests::Request;
    use pappus::editor::session::selection::ActiveMesh;
    let mut app = common::headless_editor();
    for op in student::LAB.into_iter().chain(mistakes::MISTAKES) {
        app.add_operation(op);
    }
    common::send(&mut app, Request::Open("shape:icosphere".into()));
    let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
    let e = interior_edges(app.world(), mesh, 1, 0)[9];
    let press = |app: &mut App, k: KeyCode| {
        common::key(app, KeyCode::AltLeft, ButtonState::Pressed);
        common::key(app, k, ButtonState::Pressed);
        common::key(app, k, ButtonState::Released);
        common::key(app, KeyCode::AltLeft, ButtonState::Released);
    };
    let before = common::elements(app.world(), mesh);
    common::send(&mut app, Request::Select(Some(ElementId::Edge(e))));
    press(&mut app, KeyCode::Digit1);
    let outcome = common::last_outcome(&app);
    assert!(outcome.request.starts_with("lab flip"), "{outcome:?}");
    assert!(
        outcome
            .result
            .as_ref()
            .unwrap()
            .ends_with("lab: same as flip"),
        "{outcome:?}"
    );
    let flipped = common::elements(app.world(), mesh);
    assert_ne!(flipped, before);
    common::send(&mut app, Request::Select(Some(ElementId::Edge(e))));
    press(&mut app, KeyCode::Digit5);
    let outcome = common::last_outcome(&app);
    let refused = outcome.result.as_ref().unwrap_err();
    assert!(
        refused.to_string().contains("the mesh is as it was"),
        "{outcome:?}"
    );
    assert_eq!(common::elements(app.world(), mesh), flipped);
    common::send(&mut app, Request::Undo);
    assert_eq!(common::elements(app.world(), mesh), before);
}
