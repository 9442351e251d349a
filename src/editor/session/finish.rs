//! The end of every request: one path for the bookkeeping after an edit, whether it was
//! applied at once or came back from a job, and one for reporting any outcome.
//!
//! After an applied edit, [`finish_edit`]: records the undo entry, ends the simplification
//! history unless the edit keeps it, marks the mesh modified, marks what must be redrawn, moves
//! the selection to what the edit made (or keeps it where its element survived); after an edit
//! that rewrites the faces in place, values given by face entity are forgotten, and the
//! summary says so. (The edit has
//! validated the mesh already in debug builds: see [`Edit::run`].) [`report`] then logs the
//! outcome and writes it as an [`EditOutcome`] message.

use bevy::prelude::World;

use crate::edit::{Applied, Edit, IdsKept, Redraw};
use crate::mesh::MeshId;
use crate::ops::Refusal;

use super::history::{self, Pending};
use super::origins::Origins;
use super::requests::{Declined, EditOutcome, OutcomeLog};
use super::selection::{
    MeshDirty, PositionsDirty, Selection, keep_live_selection, mark_faces_dirty,
};
use super::state::{Modified, PreviousShape};

/// An edit that has run, with what its bookkeeping needs.
pub struct Finished {
    /// The edit.
    pub edit: Edit,
    /// The mesh it ran on.
    pub mesh: MeshId,
    /// What it did, or why it refused (the world is then as it was).
    pub result: Result<Applied, Refusal>,
    /// The undo record captured before it ran.
    pub pending: Option<Pending>,
}

/// Does the bookkeeping of an edit that ran (see the module doc). Returns its summary, or its
/// refusal.
///
/// # Errors
/// The edit's refusal; nothing is recorded then.
pub fn finish_edit(world: &mut World, finished: Finished) -> Result<String, Declined> {
    let Finished {
        edit,
        mesh,
        result,
        pending,
    } = finished;
    let mut applied = result?;
    if edit.keeps_ids() == IdsKept::VerticesOnly {
        if let Some(mut origins) = world.get_resource_mut::<Origins>() {
            origins.faces_renumbered();
        }
        // Face entities now name other faces: values a script gave by face are forgotten.
        let forgotten = crate::ops::registry::quantities_faces_renumbered(world.id());
        if !forgotten.is_empty() {
            let names = crate::mesh::attributes::listed(&forgotten);
            applied.summary += &format!(" — {names} forgotten: the faces were renumbered");
        }
    }
    if let Some(before) = pending.as_ref().and_then(Pending::tables) {
        let tables = before.tables.clone();
        world.resource_mut::<PreviousShape>().set(mesh, tables);
    }
    if let Some(pending) = pending {
        history::commit(world, pending, edit.label());
    }
    // Already settled by `Edit::run` for an edit run at once; a job or a stepped run ends here.
    edit.settle_history(world, mesh);
    if world.get_entity(mesh.0).is_err() {
        return Ok(applied.summary);
    }
    mark_redraw(world, mesh, applied.redraw);
    match applied.made {
        Some(made) => world.resource_mut::<Selection>().select_only(Some(made)),
        None => {
            let kept = edit.keeps_ids();
            keep_live_selection(world, |x| kept.keeps(x));
        }
    }
    Ok(applied.summary)
}

/// Marks `mesh` modified and what of it the render copy redraws: the faces `redraw` names
/// (the faces around its vertices are already among them), every face, or the positions alone.
/// What an edit, an undo and a stepped run's end all do.
pub fn mark_redraw(world: &mut World, mesh: MeshId, redraw: Redraw) {
    world.entity_mut(mesh.0).insert(Modified);
    match redraw {
        Redraw::Whole => {
            world.entity_mut(mesh.0).insert(MeshDirty);
        }
        Redraw::Near { faces, .. } => mark_faces_dirty(world, mesh, faces),
        Redraw::Positions => {
            world.entity_mut(mesh.0).insert(PositionsDirty);
        }
    }
}

/// Logs an outcome and hands it to the status line, the log panel and any reader of
/// [`EditOutcome`] messages.
pub fn report(world: &mut World, request: String, result: Result<String, Declined>, ms: f64) {
    match &result {
        Ok(summary) => bevy::log::info!("{request}: {summary} ({ms:.2} ms)"),
        Err(reason) => bevy::log::info!("{request}: declined: {reason}"),
    }
    let outcome = EditOutcome { request, result };
    world.write_message(outcome.clone());
    world.resource_mut::<OutcomeLog>().push(outcome);
}
