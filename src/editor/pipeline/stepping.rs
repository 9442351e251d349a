//! Step mode: an operation run a step at a time on the live mesh, so that a student can watch
//! it work.
//!
//! With step mode on (`F9`, or the panel's button), the keys and buttons of an operation that
//! declares it steps ([`Edit::can_step`]: simplification, remeshing, Loop and Catmull–Clark,
//! smoothing, an as-rigid-as-possible handle drag) start a [`SteppedRun`] instead of running
//! to the end. The run pauses between the operation's own steps and moves on [`StepMove`]s:
//! forward 1, 10, 100 or to the end, or back where the operation goes back.
//!
//! This room knows no algorithm: each operation declares its steps in its own file
//! ([`Steps`], in [`crate::ops::operation::stepping`]: what a step is, what it draws and
//! lists, how it goes back). The room keeps the mesh from before the run for the undo entry
//! or a cancel, follows the selection, redraws what a move says changed and ends the run.
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
//! The selection follows: an element a step removes is replaced by what the operation says it
//! became (the vertex an edge collapsed into), and the window says so; otherwise removed
//! elements, and those whose ids the step renumbered, drop out of the selection.

use bevy::prelude::{Resource, World};

use crate::edit::{Applied, Edit, Invocation, Redraw};
use crate::mesh::attributes::MeshAttributes;
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::ops::operation::stepping::{Moved, Steps};
use crate::ops::progressive::ProgressiveMesh;

use crate::editor::session::finish::{Finished, finish_edit, mark_redraw};
use crate::editor::session::history::{self, Pending};
use crate::editor::session::requests::{Declined, StepMove};
use crate::editor::session::selection::{ActiveMesh, MeshDirty, Selection, keep_live_selection};
use crate::editor::session::state::Modified;
use crate::ops::simplification_history::SimplificationHistory;

/// Step mode and the run in progress.
#[derive(Resource, Default)]
pub struct Stepping {
    /// Whether global operations start a stepped run instead of running to the end.
    pub enabled: bool,
    /// The run in progress.
    pub run: Option<SteppedRun>,
}

/// An edit being stepped through (see the module doc).
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
    /// The operation's own run.
    pub steps: Box<dyn Steps>,
    /// What became of the selected element at the last move that removed it: the element it
    /// became (selected then) and the line that says so.
    pub fate: Option<(ElementId, String)>,
    /// The mesh's simplification history from before the run, taken off it while the run
    /// changes the mesh, put back if the run changes nothing or is cancelled.
    previous_history: Option<ProgressiveMesh>,
    /// Whether the mesh had unsaved changes before the run (a cancel leaves it so).
    was_modified: bool,
}

/// The vertices the run in progress asks the camera to frame ([`Steps::focus`]).
pub fn focus(world: &World) -> Vec<VertexId> {
    match world
        .get_resource::<Stepping>()
        .and_then(|s| s.run.as_ref())
    {
        Some(run) => run.steps.focus(),
        None => Vec::new(),
    }
}

/// Starts a stepped run of `edit` on the active mesh (ending the run in progress first).
///
/// # Errors
/// No mesh; an edit that cannot be stepped; the operation's refusal (the mesh is untouched).
pub fn start(world: &mut World, edit: &Edit) -> Result<String, Declined> {
    let mesh = edit.target(world, world.resource::<ActiveMesh>().0)?;
    // Planned on the mesh as the run in progress left it; that run ends only now, so a
    // refused start leaves it going.
    let mut steps = edit.step_through(world, mesh)?;
    end_run(world)?;
    let pending = history::begin_edit(world, edit, mesh);
    let had = MeshAttributes::of(world, mesh);
    let was_modified = world.get::<Modified>(mesh.0).is_some();
    let previous_history = SimplificationHistory::take(world, mesh);
    // A deformation shows its iteration 0 (the handle placed) once the mesh before it is kept.
    match steps.open(world, mesh) {
        Ok(Some(redraw)) => mark_redraw(world, mesh, redraw),
        Ok(None) => {}
        Err(refusal) => {
            if let Some(pending) = pending {
                history::restore(world, pending);
            }
            if let Some(pm) = previous_history {
                SimplificationHistory::keep(world, mesh, pm);
            }
            world.entity_mut(mesh.0).insert(MeshDirty);
            return Err(Declined::Refused(refusal));
        }
    }
    let summary = format!("stepping {}: {}", edit.label(), steps.describe());
    world.resource_mut::<Stepping>().run = Some(SteppedRun {
        mesh,
        edit: edit.clone(),
        pending,
        had,
        steps,
        fate: None,
        previous_history,
        was_modified,
    });
    Ok(summary)
}

/// Applies a move to the run in progress.
///
/// # Errors
/// No run; a move the operation refuses (back where it does not go back, its own refusal on
/// the way).
pub fn step(world: &mut World, movement: StepMove) -> Result<String, Declined> {
    let mut run = world
        .resource_mut::<Stepping>()
        .run
        .take()
        .ok_or(Declined::NoSteppedRun)?;
    run.fate = None;
    let to = match movement {
        StepMove::Finish => return finish(world, run),
        StepMove::Cancel => return cancel(world, run),
        StepMove::Forward(n) => run.steps.at().saturating_add(n),
        StepMove::Back(n) => run.steps.at().saturating_sub(n),
        StepMove::To(k) => k,
    };
    let selected = world.resource::<Selection>().element;
    let result = run.steps.go_to(world, run.mesh, to, selected);
    let result = match result {
        Ok(moved) => {
            follow(world, &mut run, moved);
            Ok(run.steps.describe())
        }
        Err(refusal) => {
            // The mesh is valid at some step of the run: redraw it all.
            world.entity_mut(run.mesh.0).insert((MeshDirty, Modified));
            keep_live_selection(world, |_| true);
            Err(Declined::Refused(refusal))
        }
    };
    world.resource_mut::<Stepping>().run = Some(run);
    result
}

/// Redraws what a move changed and moves the selection as it says.
fn follow(world: &mut World, run: &mut SteppedRun, moved: Moved) {
    if let Some(redraw) = moved.redraw {
        mark_redraw(world, run.mesh, redraw);
    }
    if let Some((became, line)) = moved.became {
        world.resource_mut::<Selection>().select_only(Some(became));
        run.fate = Some((became, line));
    }
    keep_live_selection(world, |x| moved.ids.keeps(x));
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

/// Records the run as one undo entry, as the unstepped edit would be (a simplification
/// leaves its history for the level-of-detail slider). A run that changed nothing records
/// nothing.
fn finish(world: &mut World, run: SteppedRun) -> Result<String, Declined> {
    let SteppedRun {
        mesh,
        mut edit,
        pending,
        had,
        steps,
        previous_history,
        ..
    } = run;
    let ended = steps.finish(world, mesh);
    let Some(mut summary) = ended.summary else {
        if let Some(pm) = previous_history {
            SimplificationHistory::keep(world, mesh, pm);
        }
        return Ok("nothing committed: the mesh is as before".into());
    };
    if let (Some(values), Edit::Operation(started)) = (ended.recorded, &edit)
        && let Ok(recorded) = Invocation::new(started.operation(), &values)
    {
        edit = Edit::Operation(recorded);
    }
    summary.push_str(&edit.settle_attributes(world, mesh, had));
    crate::edit::mark_normals_stale(world, mesh, &edit);
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
    finish_edit(
        world,
        Finished {
            edit,
            mesh,
            result: Ok(applied),
            pending,
        },
    )
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
    if let Some(pm) = previous {
        SimplificationHistory::keep(world, run.mesh, pm);
    }
    let mut mesh = world.entity_mut(run.mesh.0);
    mesh.insert(MeshDirty);
    if !run.was_modified {
        mesh.remove::<Modified>();
    }
    keep_live_selection(world, |_| true);
    Ok(format!("{label}: cancelled, the mesh is as before"))
}
