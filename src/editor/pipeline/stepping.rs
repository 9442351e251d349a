//! Step mode: a global operation run a step at a time on the live mesh, so that a student can
//! watch it work.
//!
//! With step mode on (`F9`, or the panel's button), the keys and buttons of simplification,
//! remeshing and subdivision start a [`SteppedRun`] instead of running to the end. The run
//! pauses between the operation's natural steps and moves on [`StepMove`]s: forward 1, 10, 100
//! or to the end, or back.
//!
//! - **QEM** ([`QemRun`]), a step is one edge collapse: the next edge is drawn with the point
//!   its ends merge at, the panel lists the queue's cheapest edges, and a collapse the queue
//!   refused says why. Moving back splits collapses back through the run's
//!   [`ProgressiveMesh`] (the history the level-of-detail slider moves along), and forward
//!   again replays them before the run makes new ones; a slider scrubs along them.
//! - **Isotropic remeshing** ([`RemeshRun`]), a step is one pass (split, collapse, flip, relax,
//!   project; a finish after the last iteration): what the pass made or moved is highlighted
//!   and its count listed. A pass rewrites much of the mesh, so a remeshing run does not step
//!   back; Esc puts the mesh back as it was before the run.
//! - **Loop and Catmull–Clark**, two steps a level: the run opens on the level's new edge (and
//!   face) points drawn over the mesh, a step adds the old vertices at their moved positions,
//!   the next commits the level; the selected element's stencil (its old vertices and their
//!   weights, [`crate::ops::stencil`]) is drawn and listed meanwhile. Back takes back the
//!   preview step of the level not yet committed.
//!
//! - **As-rigid-as-possible handle deformation** ([`DeformSteps`]), a step per iteration: a
//!   `G` / `R` / `S` of a handle with anchors marked, in step mode, moves the handle alone and,
//!   confirmed, starts the run from the rest of the mesh as it was (the handle placed, nothing
//!   else moved yet). Each step is one local–global iteration (Sorkine & Alexa 2007); each
//!   vertex's best rotation for the positions shown is drawn as a small frame, and the energy of
//!   every iteration is listed. Back shows an earlier iteration (each one's positions are kept).
//!
//! Every step is the operation's own step on the world, so a run stepped to the end leaves the
//! same mesh, bit for bit, as the unstepped edit run in place (a large mesh runs the unstepped
//! edit as a job, whose result gets other entity ids; a stepped run always runs in place).
//! Ending the run ([`StepMove::Finish`], or any other edit, undo, save or file request, which
//! end it first, as does the start of a transform) records it as one undo entry under the
//! edit's own label, as the unstepped edit would be; [`StepMove::Cancel`] puts the mesh (and
//! the selection and the level-of-detail history) back as they were before the run and records
//! nothing.
//!
//! The selection follows new collapses: an element one removes is replaced by what it became
//! (the vertex an edge collapsed into, the edge a wing merged into), and the window says so.
//! Elsewhere (collapses replayed or split back, remeshing passes) removed elements drop out of
//! the selection.

use bevy::math::{Quat, Vec3};
use bevy::prelude::{Resource, World};

use crate::edit::{Applied, Edit, Invocation, Redraw, Scheme};
use crate::mesh::attributes::MeshAttributes;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::members::of_kind;
use crate::mesh::topology::MeshRef;
use crate::mesh::{Edge, Face, Position};
use crate::ops::Refusal;
use crate::ops::decimate::simplification;
use crate::ops::deform::{DeformMethod, DeformParams, LiveDeform};
use crate::ops::progressive::{ProgressiveMesh, SlotIndex};
use crate::ops::remesh::{Pass, PassReport, REMESH, Remesh, RemeshRun};
use crate::ops::simplify::{NextCollapse, QemRun, QueuedEdge, Refused, SimplifyParams};
use crate::ops::stencil::{NextLevelPoints, Stencil, next_level_points, stencil_of_element};
use crate::ops::subdivide::subdivision;

use crate::editor::session::finish::{Finished, finish_edit};
use crate::editor::session::history::{self, Pending};
use crate::editor::session::requests::{Declined, StepMove};
use crate::editor::session::selection::{
    ActiveMesh, MeshDirty, Selection, exists, mark_faces_dirty,
};
use crate::editor::session::state::{Modified, SimplificationHistory};

/// How many refusals the panel keeps (the latest).
const REFUSALS_KEPT: usize = 8;

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
    /// The attributes the mesh had before the run: those the edit does not carry are dropped
    /// when it ends, as after the unstepped edit.
    had: MeshAttributes,
    /// The operation's own state.
    pub steps: Steps,
    /// What became of the selected element at the last move that removed it: the element it
    /// became (selected then) and the line that says so.
    pub fate: Option<(ElementId, String)>,
    /// The level-of-detail history from before the run, put back if the run changes nothing.
    previous_history: Option<ProgressiveMesh>,
    /// Whether the mesh had unsaved changes before the run (a cancel leaves it so).
    was_modified: bool,
}

/// The state of each kind of stepped run.
pub enum Steps {
    /// QEM, a collapse a step.
    Qem(QemSteps),
    /// Isotropic remeshing, a pass a step.
    Remesh(RemeshSteps),
    /// Subdivision, previewed then committed a level at a time.
    Subdivide(SubdivideSteps),
    /// An as-rigid-as-possible deformation, an iteration a step.
    Deform(DeformSteps),
}

impl Steps {
    /// The step the mesh is at.
    pub fn at(&self) -> usize {
        match self {
            Steps::Qem(q) => q.at(),
            Steps::Remesh(r) => r.run.passes_done(),
            Steps::Subdivide(s) => s.at(),
            Steps::Deform(d) => d.at,
        }
    }

    /// The steps made so far (QEM), or the steps the run has in all (the others).
    pub fn made(&self) -> usize {
        match self {
            Steps::Qem(q) => q.made(),
            Steps::Remesh(r) => r.run.passes_total(),
            Steps::Subdivide(s) => 2 * s.levels as usize,
            Steps::Deform(d) => d.total,
        }
    }

    /// Whether the run has made its last step.
    pub fn finished(&self) -> bool {
        match self {
            Steps::Qem(q) => q.finished(),
            Steps::Remesh(r) => r.run.upcoming().is_none(),
            Steps::Subdivide(s) => s.done == s.levels,
            Steps::Deform(d) => d.at == d.total,
        }
    }
}

/// An as-rigid-as-possible deformation stepped iteration by iteration.
pub struct DeformSteps {
    live: Box<LiveDeform>,
    /// The vertices each iteration places: the handle, then every vertex that is not held.
    vertices: Vec<VertexId>,
    /// Each iteration's result, the handle placed before the first (iteration 0).
    pub iterations: Vec<DeformIteration>,
    /// The iteration the mesh shows.
    pub at: usize,
    /// The iterations the run makes in all.
    pub total: usize,
    /// The length of the rotation frames drawn ([`FRAME_SIZE`] of the mean edge length).
    pub frame_size: f32,
}

/// The length of a stepped deformation's rotation frames, in mean edge lengths.
pub const FRAME_SIZE: f32 = 0.7;

/// One iteration of a stepped deformation.
pub struct DeformIteration {
    /// Where the iteration put [`DeformSteps`]' vertices.
    pub positions: Vec<Vec3>,
    /// Each free vertex's best rotation for these positions (after the handle's in
    /// [`DeformSteps`]' order): what the next iteration's local step starts from.
    pub rotations: Vec<Quat>,
    /// The as-rigid-as-possible energy of these positions with those rotations.
    pub energy: f64,
}

impl DeformSteps {
    /// Checks the edit and factors its system on the mesh as it is (the rest pose), then places
    /// the handle where the motion sends it: iteration 0.
    fn start(world: &World, mesh: MeshId, params: &DeformParams) -> Result<Self, Refusal> {
        let (mut live, targets) = crate::ops::deform::prepare(world, mesh, params)?;
        let moves = live.solve(&targets, 0)?;
        let m = MeshRef::new(world);
        let energy = live.energy();
        let edges: Vec<_> = of_kind::<Edge, _>(world, mesh, EdgeId);
        let mean_edge = edges
            .iter()
            .map(|&e| {
                let (a, b) = m.edge_vertices(e);
                m.position(a).distance(m.position(b))
            })
            .sum::<f32>()
            / edges.len().max(1) as f32;
        Ok(Self {
            vertices: moves.iter().map(|(v, _)| *v).collect(),
            iterations: vec![DeformIteration {
                positions: moves.iter().map(|(_, p)| *p).collect(),
                rotations: live.free_rotations(),
                energy,
            }],
            live: Box::new(live),
            at: 0,
            total: params.iterations as usize,
            frame_size: FRAME_SIZE * mean_edge,
        })
    }

    /// Each free vertex of the iteration shown, where it is and its best rotation.
    pub fn frames(&self) -> impl Iterator<Item = (Vec3, Quat)> + '_ {
        let shown = &self.iterations[self.at];
        // The free vertices come last, one rotation each.
        let handle = shown.positions.len() - shown.rotations.len();
        shown.positions[handle..]
            .iter()
            .copied()
            .zip(shown.rotations.iter().copied())
    }

    /// The energy at the iteration shown.
    pub fn energy_line(&self) -> String {
        let energy = self.iterations[self.at].energy;
        match self.at {
            0 => format!("energy {energy:.6e}, the handle placed, the rest as it was"),
            _ => format!("energy {energy:.6e}"),
        }
    }

    /// Runs iterations up to `k` (at most the run's total) and shows iteration `k`.
    fn go_to(&mut self, world: &mut World, mesh: MeshId, k: usize) -> Result<(), Refusal> {
        let k = k.min(self.total);
        while self.iterations.len() <= k {
            self.live.iterate(1);
            let moves = self.live.moves()?;
            // This local step is the one the next iteration would run on the same positions,
            // and the next iteration reuses it, so measuring here leaves every later
            // iteration as an unstepped run makes it.
            let energy = self.live.energy();
            self.iterations.push(DeformIteration {
                positions: moves.into_iter().map(|(_, p)| p).collect(),
                rotations: self.live.free_rotations(),
                energy,
            });
        }
        self.at = k;
        for (v, &p) in self.vertices.iter().zip(&self.iterations[k].positions) {
            if let Some(mut at) = world.get_mut::<Position>(v.0) {
                at.0 = p;
            }
        }
        world.entity_mut(mesh.0).insert((MeshDirty, Modified));
        Ok(())
    }
}

/// Isotropic remeshing stepped pass by pass.
pub struct RemeshSteps {
    run: RemeshRun,
    /// What the last pass did.
    pub last: Option<PassReport>,
    /// Each pass so far, one line each ("1 split: 5587").
    pub passes: Vec<String>,
}

impl RemeshSteps {
    /// The pass the next step runs, if any.
    pub fn upcoming(&self) -> Option<(Pass, u32)> {
        self.run.upcoming()
    }
}

/// Subdivision previewed and committed a level at a time.
pub struct SubdivideSteps {
    /// The scheme.
    pub scheme: Scheme,
    /// Levels asked for.
    pub levels: u32,
    /// Levels committed.
    pub done: u32,
    /// Whether the moved old vertices are shown (the level's second step) beside the new
    /// points (its first).
    pub moved_shown: bool,
    /// The next level's points, while it is previewed.
    pub points: Option<NextLevelPoints>,
    /// The mesh's vertex and face counts now (read at the start, then given by each level).
    counts: (usize, usize),
}

impl SubdivideSteps {
    fn at(&self) -> usize {
        2 * self.done as usize + usize::from(self.moved_shown)
    }

    /// The stencil of the selected element's point in the level being previewed (none once
    /// the last level is committed).
    pub fn selected_stencil(&self, world: &World) -> Option<Stencil> {
        self.points.as_ref()?;
        let selected = world.resource::<Selection>().element?;
        stencil_of_element(&MeshRef::new(world), self.scheme, selected)
    }
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
    /// A stepped simplification of `mesh` as `params` say, looking at its first collapse.
    ///
    /// # Errors
    /// The simplification's refusal (the mesh is untouched).
    fn start(world: &mut World, mesh: MeshId, params: &SimplifyParams) -> Result<Self, Refusal> {
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
        Ok(steps)
    }

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

/// The collapse a stepped QEM run at its front makes next, if one is in progress.
pub fn next_collapse(world: &World) -> Option<NextCollapse> {
    match &world.get_resource::<Stepping>()?.run.as_ref()?.steps {
        Steps::Qem(q) if q.at_front() => q.next,
        _ => None,
    }
}

/// Whether `edit` can be stepped through.
pub fn steppable(edit: &Edit) -> bool {
    match edit {
        Edit::Operation(op) => {
            op.is(&REMESH) || simplification(op).is_some() || subdivision(op).is_some()
        }
        Edit::Deform(params) => params.method == DeformMethod::Arap,
        _ => false,
    }
}

/// Starts a stepped run of `edit` on the active mesh (ending the run in progress first).
///
/// # Errors
/// No mesh; an edit that cannot be stepped; the operation's refusal (the mesh is untouched).
pub fn start(world: &mut World, edit: &Edit) -> Result<String, Declined> {
    let mesh = edit.target(world, world.resource::<ActiveMesh>().0)?;
    let steps = match edit {
        Edit::Operation(op) if let Some(params) = simplification(op) => {
            Steps::Qem(QemSteps::start(world, mesh, &params)?)
        }
        Edit::Operation(op) if op.is(&REMESH) => Steps::Remesh(RemeshSteps {
            run: RemeshRun::start(world, mesh, &Remesh::params(op.values()))?,
            last: None,
            passes: Vec::new(),
        }),
        Edit::Operation(op) if let Some((scheme, levels)) = subdivision(op) => {
            let points = next_level_points(world, mesh, scheme)?;
            let faces = of_kind::<Face, _>(world, mesh, |f| f).len();
            Steps::Subdivide(SubdivideSteps {
                scheme,
                levels,
                done: 0,
                moved_shown: false,
                counts: (points.vertex.len(), faces),
                points: Some(points),
            })
        }
        Edit::Deform(params) if params.method == DeformMethod::Arap => {
            Steps::Deform(DeformSteps::start(world, mesh, params)?)
        }
        _ => {
            return Err(Declined::Refused(Refusal::BadParameter(format!(
                "{} cannot be stepped through",
                edit.label()
            ))));
        }
    };
    // Planned on the mesh as the run in progress left it; that run ends only now, so a
    // refused start leaves it going.
    end_run(world)?;
    let pending = history::begin_edit(world, edit, mesh);
    let had = MeshAttributes::of(world, mesh);
    let was_modified = world.get::<Modified>(mesh.0).is_some();
    let summary = format!("stepping {}: {}", edit.label(), describe(&steps));
    let previous_history = world.resource_mut::<SimplificationHistory>().pm.take();
    let mut run = SteppedRun {
        mesh,
        edit: edit.clone(),
        pending,
        had,
        steps,
        fate: None,
        previous_history,
        was_modified,
    };
    // A deformation shows its iteration 0 (the handle placed) once the mesh before it is kept.
    if let Steps::Deform(d) = &mut run.steps {
        d.go_to(world, mesh, 0)?;
    }
    world.resource_mut::<Stepping>().run = Some(run);
    Ok(summary)
}

/// Where a run is, in one line (the status line's and the step window's).
pub fn describe(steps: &Steps) -> String {
    match steps {
        Steps::Qem(q) => match (&q.next, q.at_front()) {
            (Some(next), true) => format!(
                "step {}: {} faces, target {}; next {} (cost {:.3e})",
                q.at(),
                q.faces(),
                q.target_faces(),
                next.queued.edge,
                next.queued.cost
            ),
            (None, true) => format!(
                "step {}: {} faces, the end ({})",
                q.at(),
                q.faces(),
                match q.run.summary().reached_target {
                    true => "target reached",
                    false => "no collapse left that is allowed",
                }
            ),
            (_, false) => format!("step {} of {}: {} faces", q.at(), q.made(), q.faces()),
        },
        Steps::Remesh(r) => {
            let last = r.passes.last().map_or("", String::as_str);
            match r.upcoming() {
                Some((pass, i)) => format!(
                    "pass {} of {}{}; next: {} (iteration {})",
                    r.run.passes_done(),
                    r.run.passes_total(),
                    if last.is_empty() {
                        String::new()
                    } else {
                        format!(", {last}")
                    },
                    pass.name(),
                    i + 1
                ),
                None => format!("the end, {last}"),
            }
        }
        Steps::Deform(d) => format!("iteration {} of {}: {}", d.at, d.total, d.energy_line()),
        Steps::Subdivide(s) => {
            let faces = s.counts.1;
            match (s.done == s.levels, s.moved_shown) {
                (true, _) => format!("{} level(s) committed, {faces} faces", s.done),
                (false, false) => format!(
                    "level {}: the new points shown ({faces} faces now)",
                    s.done + 1
                ),
                (false, true) => format!(
                    "level {}: the old vertices moved as well; the next step commits it",
                    s.done + 1
                ),
            }
        }
    }
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
    run.fate = None;
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
    let summary = result.map(|()| describe(&run.steps));
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

/// Moves `run` to step `k`.
fn go_to(world: &mut World, run: &mut SteppedRun, k: usize) -> Result<(), Refusal> {
    let mesh = run.mesh;
    match &mut run.steps {
        Steps::Qem(steps) => qem_go_to(world, mesh, steps, &mut run.fate, k),
        Steps::Remesh(steps) => remesh_go_to(world, mesh, steps, k),
        Steps::Deform(steps) => steps.go_to(world, mesh, k),
        Steps::Subdivide(steps) => {
            let result = subdivide_go_to(world, mesh, steps, k);
            // A later level refused still leaves the levels made: the entry names those.
            if steps.done > 0 {
                let done =
                    Invocation::new(steps.scheme.operation(), &[Some(f64::from(steps.done))]);
                if let Ok(done) = done {
                    run.edit = Edit::Operation(done);
                }
            }
            result
        }
    }
}

/// Runs passes up to pass `k` (a remeshing run does not go back).
fn remesh_go_to(
    world: &mut World,
    mesh: MeshId,
    steps: &mut RemeshSteps,
    k: usize,
) -> Result<(), Refusal> {
    if k < steps.run.passes_done() {
        return Err(Refusal::BadParameter(
            "a remeshing run does not step back: Esc puts the mesh back as it was before it".into(),
        ));
    }
    while steps.run.passes_done() < k {
        let Some(report) = steps.run.next_pass(world) else {
            break;
        };
        steps.passes.push(format!(
            "{} {}: {}",
            match report.pass {
                Pass::Finish => "end".to_string(),
                _ => (report.iteration + 1).to_string(),
            },
            report.pass.name(),
            report.count
        ));
        steps.last = Some(report);
    }
    world.entity_mut(mesh.0).insert((MeshDirty, Modified));
    follow_selection(world);
    Ok(())
}

/// Moves a subdivision run to step `k`: shows the next level's new points, then its moved
/// vertices, then commits it.
fn subdivide_go_to(
    world: &mut World,
    mesh: MeshId,
    steps: &mut SubdivideSteps,
    k: usize,
) -> Result<(), Refusal> {
    if k < 2 * steps.done as usize {
        return Err(Refusal::BadParameter(
            "a committed level does not step back: Esc puts the mesh back as it was before \
             the run"
                .into(),
        ));
    }
    while steps.at() < k && steps.done < steps.levels {
        if !steps.moved_shown {
            steps.moved_shown = true;
            continue;
        }
        let level = steps.scheme.subdivide(world, mesh, 1)?;
        steps.counts = (level.vertices, level.faces);
        steps.done += 1;
        steps.moved_shown = false;
        world.entity_mut(mesh.0).insert((Modified, MeshDirty));
        steps.points = match steps.done < steps.levels {
            true => Some(next_level_points(world, mesh, steps.scheme)?),
            false => None,
        };
        // Subdivision keeps vertex ids only.
        crate::editor::session::selection::keep_live_selection(world, |x| {
            matches!(x, ElementId::Vertex(_))
        });
    }
    if k < steps.at() {
        steps.moved_shown = false;
    }
    Ok(())
}

/// Moves a QEM run to step `k`: back or forward along what has run, then new collapses.
fn qem_go_to(
    world: &mut World,
    mesh: MeshId,
    steps: &mut QemSteps,
    fate_line: &mut Option<(ElementId, String)>,
    k: usize,
) -> Result<(), Refusal> {
    world.entity_mut(mesh.0).insert(Modified);
    if k < steps.made() || !steps.at_front() {
        if steps.at_front() {
            steps.run.detach();
            steps.next = None;
        }
        let faces = steps.faces_at(k.min(steps.made()));
        let mut touched = Vec::new();
        let moved = steps.history.go_to_faces_watching(world, faces, |w, v| {
            touched.extend(MeshRef::new(w).vertex_faces(v));
        })?;
        match moved.rewritten {
            true => {
                world.entity_mut(mesh.0).insert(MeshDirty);
            }
            false => mark_faces_dirty(world, mesh, touched),
        }
        *fate_line = None;
    }
    if k <= steps.made() {
        if steps.at_front() {
            steps.run.reattach(world, steps.history.slots())?;
            steps.look_ahead(world);
        }
        follow_selection(world);
        return Ok(());
    }
    steps.run.reattach(world, steps.history.slots())?;
    let mut dirty: Vec<FaceId> = Vec::new();
    while steps.at() < k {
        let selected = world.resource::<Selection>().element;
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
            *fate_line = Some(fate(world, x, ends, result.kept, result.removed));
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
/// it; selects that, and returns it with the line that says so.
fn fate(
    world: &mut World,
    x: ElementId,
    ends: Vec<VertexId>,
    kept: VertexId,
    removed: VertexId,
) -> (ElementId, String) {
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
    (became, format!("{x} is gone: {how} {became}"))
}

/// Keeps the selection on live elements after a move (a split back or a replayed collapse may
/// have removed what was selected).
fn follow_selection(world: &mut World) {
    crate::editor::session::selection::keep_live_selection(world, |_| true);
}

/// Records the run as one undo entry, as the unstepped edit would be (a simplification
/// leaves its history for the level-of-detail slider). A subdivision that committed no level
/// changed nothing and records nothing.
fn finish(world: &mut World, run: SteppedRun) -> Result<String, Declined> {
    let SteppedRun {
        mesh,
        edit,
        pending,
        had,
        steps,
        previous_history: run_previous,
        ..
    } = run;
    let (mut summary, history) = match steps {
        Steps::Qem(mut q) => {
            let s = q.run.summary();
            q.run.detach();
            let line = format!(
                "{} -> {} faces in {} collapses (stepped; kept at step {})",
                s.faces_before,
                q.faces(),
                q.made(),
                q.at()
            );
            (line, Some(q.history))
        }
        Steps::Remesh(r) => {
            let s = r.run.summary();
            let line = format!(
                "L {:.5}: {} splits, {} collapses, {} flips (stepped; {} of {} passes)",
                s.target_length,
                s.splits,
                s.collapses,
                s.flips,
                r.run.passes_done(),
                r.run.passes_total()
            );
            (line, None)
        }
        Steps::Deform(d) => {
            crate::edit::mark_normals_stale(world, mesh, &edit);
            let line = format!(
                "{} ARAP iterations (stepped; kept at iteration {} of {}), {}",
                d.iterations.len() - 1,
                d.at,
                d.total,
                d.energy_line()
            );
            (line, None)
        }
        Steps::Subdivide(s) if s.done == 0 => {
            world.resource_mut::<SimplificationHistory>().pm = run_previous;
            return Ok("nothing committed: the mesh is as before".into());
        }
        Steps::Subdivide(s) => {
            let (vertices, faces) = s.counts;
            let line = format!(
                "{} level(s): {vertices} vertices, {faces} faces (stepped)",
                s.done
            );
            (line, None)
        }
    };
    summary.push_str(&edit.settle_attributes(world, mesh, had));
    let applied = Applied {
        summary,
        // Every step redrew what it changed; attributes dropped now change every face.
        redraw: match had.is_empty() {
            true => Redraw::Near {
                faces: Vec::new(),
                vertices: Vec::new(),
            },
            false => Redraw::Whole,
        },
        made: None,
    };
    let result = finish_edit(
        world,
        Finished {
            edit,
            mesh,
            result: Ok(applied),
            pending,
        },
    );
    if history.is_some() {
        world.resource_mut::<SimplificationHistory>().pm = history;
    }
    result
}

/// Puts the mesh back as it was before the run.
fn cancel(world: &mut World, run: SteppedRun) -> Result<String, Declined> {
    let label = run.edit.label();
    let map = run
        .pending
        .and_then(|pending| history::restore(world, pending));
    let mut previous = run.previous_history;
    if let (Some(pm), Some(map)) = (&mut previous, &map) {
        pm.remap(run.mesh, map);
    }
    world.resource_mut::<SimplificationHistory>().pm = previous;
    let mut mesh = world.entity_mut(run.mesh.0);
    mesh.insert(MeshDirty);
    if !run.was_modified {
        mesh.remove::<Modified>();
    }
    follow_selection(world);
    Ok(format!("{label}: cancelled, the mesh is as before"))
}
