//! Step mode: a global operation run a step at a time on the live mesh, so that a student can
//! watch it work.
//!
//! With step mode on (`F9`, or the panel's box), the keys and buttons of simplification start a
//! [`SteppedRun`] instead of running to the end. The run pauses between the operation's natural
//! steps — one edge collapse of QEM — and moves on [`StepMove`]s: forward 1, 10, 100 or to the
//! end, or back and forth along what has run so far.
//!
//! - **QEM** ([`QemRun`]): the next edge to collapse is drawn with the point its ends merge at,
//!   the panel lists the queue's cheapest edges, and a collapse the queue refused says why.
//!   Moving back splits collapses back through the run's [`ProgressiveMesh`] (the same history
//!   the level-of-detail slider moves along), and forward again replays them before the run
//!   makes new ones.
//!
//! Every step is the operation's own step on the world, so a run stepped to the end leaves the
//! same mesh, bit for bit, as the unstepped edit. Ending the run ([`StepMove::Finish`], or any
//! other edit, undo or file request, which end it first) records it as one undo entry under the
//! edit's own label, as the unstepped edit would be; [`StepMove::Cancel`] puts the mesh back as
//! it was before the run and records nothing.
//!
//! The selection follows: an element a step removes is replaced by what it became (the vertex
//! an edge collapsed into, the edge a wing merged into), and the panel says so.

use bevy::prelude::{Resource, World};

use crate::edit::{Applied, Edit, Redraw};
use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::progressive::{ProgressiveMesh, SlotIndex};
use crate::ops::simplify::{NextCollapse, QemRun, QueuedEdge, Refused};

use super::finish::{Finished, finish_edit};
use super::history::{self, Pending};
use super::requests::Declined;
use super::selection::{ActiveMesh, MeshDirty, Selection, exists, mark_faces_dirty};
use super::session::{Modified, SimplificationHistory};

/// How many refusals the panel keeps (the latest).
const REFUSALS_KEPT: usize = 8;

/// A move of a stepped run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StepMove {
    /// This many steps forward (`usize::MAX`: to the end).
    Forward(usize),
    /// This many steps back.
    Back(usize),
    /// To step `k` (0: before the first), within what has run or beyond it.
    To(usize),
    /// End the run where it is, as one undo entry.
    Finish,
    /// End the run and put the mesh back as it was before it.
    Cancel,
}

impl StepMove {
    /// A short label for logs.
    pub fn label(self) -> String {
        match self {
            StepMove::Forward(usize::MAX) => "step to the end".into(),
            StepMove::Forward(n) => format!("step {n} forward"),
            StepMove::Back(n) => format!("step {n} back"),
            StepMove::To(k) => format!("go to step {k}"),
            StepMove::Finish => "finish the stepped run".into(),
            StepMove::Cancel => "cancel the stepped run".into(),
        }
    }
}

/// Step mode and the run in progress.
#[derive(Resource, Default)]
pub struct Stepping {
    /// Whether global operations start a stepped run instead of running to the end.
    pub enabled: bool,
    /// The run in progress.
    pub run: Option<SteppedRun>,
}

/// A global operation being stepped through (see the module doc).
pub struct SteppedRun {
    /// The mesh it runs on.
    pub mesh: MeshId,
    /// The edit it stands for: its label names the undo entry.
    pub edit: Edit,
    /// The mesh before the run, for the undo entry or a cancel.
    pending: Option<Pending>,
    /// The operation's own state.
    pub steps: QemSteps,
    /// What became of the selected element at the last step that removed it.
    pub fate: Option<String>,
}

/// A QEM simplification stepped collapse by collapse.
pub struct QemSteps {
    run: QemRun,
    /// Every collapse made so far, and where along them the mesh is.
    pub history: ProgressiveMesh,
    index: SlotIndex,
    /// The collapse the next step makes (at the run's front; `None` at its end).
    pub next: Option<NextCollapse>,
    /// The latest edges the queue refused, newest last.
    pub refused: Vec<Refused>,
}

impl QemSteps {
    /// The step the mesh is at (collapses applied).
    pub fn at(&self) -> usize {
        self.history.applied
    }

    /// Collapses made so far (the run's front).
    pub fn made(&self) -> usize {
        self.history.records.len()
    }

    /// Whether the mesh is at the run's front (where new collapses are made).
    pub fn at_front(&self) -> bool {
        self.at() == self.made()
    }

    /// Faces at the step the mesh is at.
    pub fn faces(&self) -> usize {
        self.faces_at(self.at())
    }

    /// The run's face target.
    pub fn target_faces(&self) -> usize {
        self.run.target_faces()
    }

    /// The `n` cheapest edges waiting, cheapest first.
    pub fn candidates(&self, n: usize) -> Vec<QueuedEdge> {
        self.run.candidates(n)
    }

    /// Whether the run has made its last collapse.
    pub fn finished(&self) -> bool {
        self.at_front() && self.next.is_none()
    }

    /// Faces at step `k` (each collapse removes at least one, so this is one-to-one).
    fn faces_at(&self, k: usize) -> usize {
        self.history.full_faces
            - self.history.records[..k]
                .iter()
                .map(|r| r.faces)
                .sum::<usize>()
    }

    fn look_ahead(&mut self, world: &World) {
        let refused = &mut self.refused;
        self.next = self.run.peek(world, |r| refused.push(r));
        let extra = refused.len().saturating_sub(REFUSALS_KEPT);
        refused.drain(..extra);
    }
}

/// Whether `edit` can be stepped through.
pub fn steppable(edit: &Edit) -> bool {
    matches!(edit, Edit::Simplify(_))
}

/// Starts a stepped run of `edit` on the active mesh (ending the run in progress first).
///
/// # Errors
/// No mesh; an edit that cannot be stepped; the operation's refusal (the mesh is untouched).
pub fn start(world: &mut World, edit: &Edit) -> Result<String, Declined> {
    end_run(world)?;
    let mesh = edit.target(world, world.resource::<ActiveMesh>().0)?;
    let Edit::Simplify(params) = edit else {
        return Err(Declined::Refused(Refusal::BadParameter(format!(
            "{} cannot be stepped through",
            edit.label()
        ))));
    };
    let pending = history::begin_edit(world, edit, mesh);
    let run = QemRun::start(world, mesh, params)?;
    let history = ProgressiveMesh::start(world, mesh, run.faces());
    let index = SlotIndex::of(&history);
    let mut steps = QemSteps {
        run,
        history,
        index,
        next: None,
        refused: Vec::new(),
    };
    steps.look_ahead(world);
    let summary = format!(
        "stepping {}: {} faces, target {}",
        edit.label(),
        steps.history.full_faces,
        steps.target_faces()
    );
    world.resource_mut::<SimplificationHistory>().pm = None;
    world.resource_mut::<Stepping>().run = Some(SteppedRun {
        mesh,
        edit: edit.clone(),
        pending,
        steps,
        fate: None,
    });
    Ok(summary)
}

/// Applies a move to the run in progress.
///
/// # Errors
/// No run; a move the history refuses (the mesh was changed outside the run).
pub fn step(world: &mut World, movement: StepMove) -> Result<String, Declined> {
    let mut run = world
        .resource_mut::<Stepping>()
        .run
        .take()
        .ok_or(Declined::NoSteppedRun)?;
    let result = match movement {
        StepMove::Finish => return finish(world, run),
        StepMove::Cancel => return cancel(world, run),
        StepMove::Forward(n) => {
            let to = run.steps.at().saturating_add(n);
            go_to(world, &mut run, to)
        }
        StepMove::Back(n) => {
            let to = run.steps.at().saturating_sub(n);
            go_to(world, &mut run, to)
        }
        StepMove::To(k) => go_to(world, &mut run, k),
    };
    let steps = &run.steps;
    let summary = result.map(|()| match (&steps.next, steps.at_front()) {
        (Some(next), true) => format!(
            "step {}: {} faces; next {} (cost {:.3e})",
            steps.at(),
            steps.faces_at(steps.at()),
            next.queued.edge,
            next.queued.cost
        ),
        (None, true) => format!(
            "step {}: {} faces, the end ({})",
            steps.at(),
            steps.faces_at(steps.at()),
            match steps.run.summary().reached_target {
                true => "target reached",
                false => "no collapse left that is allowed",
            }
        ),
        (_, false) => format!(
            "step {} of {}: {} faces",
            steps.at(),
            steps.made(),
            steps.faces_at(steps.at())
        ),
    });
    world.entity_mut(run.mesh.0).insert(Modified);
    world.resource_mut::<Stepping>().run = Some(run);
    summary.map_err(Declined::Refused)
}

/// Ends the run in progress, if any, as one undo entry (what every other edit does first).
///
/// # Errors
/// As [`finish`]'s bookkeeping: none in practice (the run has applied its steps).
pub fn end_run(world: &mut World) -> Result<(), Declined> {
    match world.resource_mut::<Stepping>().run.take() {
        Some(run) => finish(world, run).map(|_| ()),
        None => Ok(()),
    }
}

/// Moves `run` to step `k`: back or forward along what has run, then new collapses.
fn go_to(world: &mut World, run: &mut SteppedRun, k: usize) -> Result<(), Refusal> {
    let steps = &mut run.steps;
    let mesh = run.mesh;
    if k < steps.made() || !steps.at_front() {
        if steps.at_front() {
            steps.run.detach();
            steps.next = None;
        }
        let faces = steps.faces_at(k.min(steps.made()));
        let mut touched = Vec::new();
        let moved = steps.history.go_to_faces_watching(world, faces, |w, v| {
            touched.extend(MeshRef::new(w).vertex_faces(v))
        })?;
        match moved.rewritten {
            true => {
                world.entity_mut(mesh.0).insert(MeshDirty);
            }
            false => mark_faces_dirty(world, mesh, touched),
        }
        run.fate = None;
    }
    if k <= steps.made() {
        if steps.at_front() {
            steps.run.reattach(world, &steps.history)?;
            steps.look_ahead(world);
        }
        follow_selection(world);
        return Ok(());
    }
    steps.run.reattach(world, &steps.history)?;
    let mut dirty: Vec<FaceId> = Vec::new();
    let selected = world.resource::<Selection>().element;
    while steps.at() < k {
        // Faces around both ends: the kept vertex's faces after the collapse are among them.
        let Some(next) = steps.next.or_else(|| {
            steps.look_ahead(world);
            steps.next
        }) else {
            break;
        };
        let m = MeshRef::new(world);
        dirty.extend(m.vertex_faces(next.kept));
        dirty.extend(m.vertex_faces(next.removed));
        let before = selected.map(|x| ends_of(&m, x));
        let refused = &mut steps.refused;
        let Some(result) = steps.run.collapse_next(world, |r| refused.push(r)) else {
            break;
        };
        steps.history.push(world, &steps.index, &result);
        steps.next = None;
        if let (Some(x), Some(ends)) = (selected, before)
            && !exists(&MeshRef::new(world), x)
        {
            run.fate = Some(fate(world, x, ends, result.kept, result.removed));
        }
    }
    steps.look_ahead(world);
    mark_faces_dirty(world, mesh, dirty);
    follow_selection(world);
    Ok(())
}

/// The vertices an element touches, read before a step.
fn ends_of(m: &MeshRef<'_>, x: ElementId) -> Vec<VertexId> {
    match x {
        ElementId::Vertex(v) => vec![v],
        ElementId::Edge(e) if m.try_edge(e).is_some() => {
            let (a, b) = m.edge_vertices(e);
            vec![a, b]
        }
        ElementId::Halfedge(h) if m.try_halfedge(h).is_some() => {
            vec![m.from_vertex(h), m.to_vertex(h)]
        }
        ElementId::Face(f) if m.try_face(f).is_some() => m.face_vertices(f).collect(),
        _ => Vec::new(),
    }
}

/// What the selected element `x` became when the collapse of `removed` into `kept` removed
/// it; selects that and says it.
fn fate(
    world: &mut World,
    x: ElementId,
    ends: Vec<VertexId>,
    kept: VertexId,
    removed: VertexId,
) -> String {
    let m = MeshRef::new(world);
    // An edge or halfedge beside the collapsed one merged into the edge from the kept vertex
    // to the same third vertex.
    let third = ends
        .iter()
        .copied()
        .find(|&v| v != kept && v != removed && m.try_vertex(v).is_some());
    let became = match (x, third) {
        (ElementId::Edge(_) | ElementId::Halfedge(_), Some(w)) if ends.len() == 2 => m
            .find_halfedge(kept, w)
            .map(|h| ElementId::Edge(m.edge(h)))
            .unwrap_or(ElementId::Vertex(kept)),
        _ => ElementId::Vertex(kept),
    };
    world.resource_mut::<Selection>().select_only(Some(became));
    let how = match x {
        ElementId::Vertex(_) => "collapsed into",
        ElementId::Face(_) => "collapsed to",
        _ => "merged into",
    };
    format!("{x} is gone: {how} {became}")
}

/// Keeps the selection on live elements after a move (a split back or a replayed collapse may
/// have removed what was selected).
fn follow_selection(world: &mut World) {
    super::selection::keep_live_selection(world, |_| true);
}

/// Records the run as one undo entry, as the unstepped edit would be, and leaves its
/// history for the level-of-detail slider.
fn finish(world: &mut World, run: SteppedRun) -> Result<String, Declined> {
    let SteppedRun {
        mesh,
        edit,
        pending,
        mut steps,
        ..
    } = run;
    let summary = steps.run.summary();
    let applied = Applied {
        summary: format!(
            "{} -> {} faces in {} collapses (stepped; at step {})",
            summary.faces_before,
            steps.faces_at(steps.at()),
            steps.made(),
            steps.at()
        ),
        // Every step redrew what it changed.
        redraw: Redraw::Near {
            faces: Vec::new(),
            vertices: Vec::new(),
        },
        made: None,
    };
    steps.run.detach();
    let result = finish_edit(
        world,
        Finished {
            edit,
            mesh,
            result: Ok(applied),
            pending,
        },
    );
    world.resource_mut::<SimplificationHistory>().pm = Some(steps.history);
    result
}

/// Puts the mesh back as it was before the run.
fn cancel(world: &mut World, run: SteppedRun) -> Result<String, Declined> {
    let label = run.edit.label();
    if let Some(pending) = run.pending {
        history::restore(world, pending);
    }
    world.entity_mut(run.mesh.0).insert(MeshDirty);
    follow_selection(world);
    Ok(format!("{label}: cancelled, the mesh is as before"))
}
