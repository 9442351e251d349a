//! The one system that changes meshes: it applies [`Request`]s in order and reports each.
//!
//! It is exclusive (`&mut World`): every request sees the result of the one before. An
//! [`Edit`] request is captured for undo ([`history::begin_edit`]), then either started as a
//! job ([`jobs::start`]) or run at once ([`Edit::run`], the same call the command line makes),
//! and ends on [`finish_edit`] either way. Session requests (selection, files, undo) are
//! answered here.

use bevy::ecs::message::{MessageCursor, Messages};
use bevy::prelude::{Local, World};
use std::path::Path;

use crate::edit::{Edit, EditContext};
use crate::io;
use crate::mesh::topology::MeshRef;
use crate::mesh::{MeshInfo, despawn_mesh};

use super::jobs::{self, Jobs};
use super::opening::{self, open};
use super::stepping;
use crate::editor::session::finish::{Finished, finish_edit, mark_redraw, report};
use crate::editor::session::history::{self, UndoHistory};
use crate::editor::session::requests::{ConfirmDiscard, Declined, PendingDiscard, Request};
use crate::editor::session::select_many::apply_selection_edit;
use crate::editor::session::selection::{ActiveMesh, Selection, exists, navigate};
use crate::editor::session::state::{Modified, ReturnsToScript, is_modified};
use crate::ops::simplification_history::SimplificationHistory;

/// Applies every request written since the last run, in order (the `Apply` set).
pub fn apply_requests(world: &mut World, mut cursor: Local<MessageCursor<Request>>) {
    let requests: Vec<Request> = cursor
        .read(world.resource::<Messages<Request>>())
        .cloned()
        .collect();
    for request in requests {
        let start = std::time::Instant::now();
        let result = apply(world, &request);
        let ms = start.elapsed().as_secs_f64() * 1000.0;
        report(world, request.label(), result, ms);
    }
}

/// Asks before closing the window over unsaved changes (the window's close button only
/// requests; this decides), unless the mesh goes back to a script ([`ReturnsToScript`]).
pub fn close_requested(
    world: &mut World,
    mut cursor: Local<MessageCursor<bevy::window::WindowCloseRequested>>,
) {
    let requested = cursor
        .read(world.resource::<Messages<bevy::window::WindowCloseRequested>>())
        .count()
        > 0;
    if !requested {
        return;
    }
    // A mesh a script waits for goes back to it: nothing is lost by closing.
    let modified = !world.contains_resource::<ReturnsToScript>()
        && world
            .resource::<ActiveMesh>()
            .0
            .is_some_and(|m| is_modified(world, m));
    if modified {
        world.resource_mut::<ConfirmDiscard>().0 = Some(PendingDiscard::Quit);
    } else {
        world.write_message(bevy::app::AppExit::Success);
    }
}

/// Applies one request. `Ok` carries a summary; `Err` says why not (the world is then
/// unchanged).
///
/// # Errors
/// See [`Declined`].
pub fn apply(world: &mut World, request: &Request) -> Result<String, Declined> {
    if request.edits()
        && let Some(label) = world
            .resource::<Jobs>()
            .running
            .as_ref()
            .map(|job| job.label.clone())
            .or_else(|| opening::busy(world))
    {
        return Err(Declined::Busy(label));
    }
    // Any other edit, undo, save or file request ends a stepped run first, as one undo entry
    // (a new stepped run ends it once it has been planned).
    if (request.edits() || matches!(request, Request::Save(_)))
        && !matches!(request, Request::Step(_) | Request::StartStepped(_))
    {
        stepping::end_run(world)?;
    }
    match request {
        Request::Edit(edit) => apply_edit(world, edit),
        Request::StartStepped(edit) => stepping::start(world, edit),
        Request::Step(movement) => stepping::step(world, *movement),
        Request::Undo => undo_or_redo(world, false),
        Request::Retract(mark) => {
            let mut taken = Vec::new();
            while world
                .resource::<UndoHistory>()
                .undo_entries()
                .last()
                .is_some_and(|e| e.serial() >= *mark)
            {
                taken.push(undo_or_redo(world, false)?);
                world.resource_mut::<UndoHistory>().forget_undone();
            }
            Ok(match taken.is_empty() {
                true => "nothing to take back".into(),
                false => taken.join(", "),
            })
        }
        Request::Redo => undo_or_redo(world, true),
        Request::CancelJob => match opening::cancel(world) {
            Some(cancelled) => Ok(cancelled),
            None => jobs::cancel(world),
        },
        Request::Select(element) => {
            if let Some(x) = element
                && !exists(&MeshRef::new(world), *x)
            {
                return Err(Declined::NoSuchElement(*x));
            }
            world.resource_mut::<Selection>().select_only(*element);
            Ok(element.map_or("nothing selected".into(), |x| format!("{x} selected")))
        }
        Request::Selection(edit) => apply_selection_edit(world, edit),
        Request::Navigate(relation) => {
            let from = world
                .resource::<Selection>()
                .element
                .ok_or(Declined::SelectFirst("an element".into()))?;
            let to = navigate(&MeshRef::new(world), from, *relation)
                .ok_or(Declined::NoRelation(from, relation.name()))?;
            world.resource_mut::<Selection>().select_only(Some(to));
            Ok(format!("{to}"))
        }
        Request::Open(path) => {
            if let Some(mesh) = world.resource::<ActiveMesh>().0
                && is_modified(world, mesh)
            {
                world.resource_mut::<ConfirmDiscard>().0 = Some(PendingDiscard::Open(path.clone()));
                return Err(Declined::UnsavedChanges);
            }
            open(world, path)
        }
        Request::ConfirmDiscard(discard) => {
            let pending = world
                .resource_mut::<ConfirmDiscard>()
                .0
                .take()
                .ok_or(Declined::NothingWaiting)?;
            if !discard {
                return Ok("changes kept".into());
            }
            match pending {
                PendingDiscard::Open(path) => open(world, &path),
                PendingDiscard::Save { path, .. } => save(world, Some(&path), true),
                PendingDiscard::Quit => {
                    // The changes were given up on purpose: nothing to offer back next time.
                    super::recovery::forget(world);
                    world.write_message(bevy::app::AppExit::Success);
                    Ok("changes discarded, quitting".into())
                }
            }
        }
        Request::Save(path) => save(world, path.as_deref(), false),
        Request::Recover(answer) => super::recovery::answer(world, *answer, open),
        Request::DeleteMesh => {
            let mesh = world.resource::<ActiveMesh>().0.ok_or(Declined::NoMesh)?;
            let pending = history::begin_replace(world);
            let count = despawn_mesh(world, mesh);
            world.resource_mut::<ActiveMesh>().0 = None;
            world.resource_mut::<Selection>().select_only(None);
            // The mesh's simplification history went with its entity.
            if let Some(pending) = pending {
                history::commit(world, pending, request.label());
            }
            Ok(format!("{mesh} deleted ({count} entities)"))
        }
    }
}

/// Runs an edit at once, or starts it as a job on a large mesh; either way it ends on
/// [`finish_edit`].
fn apply_edit(world: &mut World, edit: &Edit) -> Result<String, Declined> {
    let mesh = edit.target(world, world.resource::<ActiveMesh>().0)?;
    let pending = history::begin_edit(world, edit, mesh);
    if jobs::wants_job(world, edit, mesh) {
        return jobs::start(world, mesh, edit.clone(), pending);
    }
    let result = edit.run(
        world,
        mesh,
        &mut EditContext {
            progress: &mut |_| true,
        },
    );
    finish_edit(
        world,
        Finished {
            edit: edit.clone(),
            mesh,
            result,
            pending,
        },
    )
}

/// Steps the undo history back (`redo == false`) or forward.
fn undo_or_redo(world: &mut World, redo: bool) -> Result<String, Declined> {
    let stepped = history::step(world, redo).ok_or(Declined::NothingTo(if redo {
        "redo"
    } else {
        "undo"
    }))?;
    // The simplification history describes the mesh as it was before the entry was applied.
    if let Some(mesh) = stepped.mesh {
        SimplificationHistory::end(world, mesh);
        mark_redraw(world, mesh, stepped.redraw);
    }
    #[cfg(any(debug_assertions, feature = "checked"))]
    if let Some(mesh) = world.resource::<ActiveMesh>().0
        && let Err(e) = crate::mesh::validate(world, mesh)
    {
        panic!(
            "{} of {} left an invalid mesh: {e}",
            if redo { "redo" } else { "undo" },
            stepped.label
        );
    }
    Ok(format!(
        "{} {}",
        if redo { "redid" } else { "undid" },
        stepped.label
    ))
}

/// Saves the active mesh to `path` (or to its own file). Unless `confirmed`, a format that
/// cannot hold what the mesh has (OFF or STL and UVs, normals or colours) asks first.
fn save(world: &mut World, path: Option<&Path>, confirmed: bool) -> Result<String, Declined> {
    let mesh = world.resource::<ActiveMesh>().0.ok_or(Declined::NoMesh)?;
    let target = match path {
        Some(p) => p.to_path_buf(),
        None => world
            .get::<MeshInfo>(mesh.0)
            .and_then(|i| i.path.clone())
            .ok_or(Declined::NoFileYet)?,
    };
    let (soup, recomputed) = crate::edit::soup_to_save(world, mesh);
    let dropped = io::dropped(&target, &soup);
    if !dropped.is_empty() && !confirmed {
        let note = io::dropped_note(&target, &dropped);
        world.resource_mut::<ConfirmDiscard>().0 = Some(PendingDiscard::Save {
            path: target,
            dropped,
        });
        return Err(Declined::WouldDrop(note));
    }
    io::write(&target, &soup).map_err(|e| Declined::File(e.to_string()))?;
    if let Some(mut info) = world.get_mut::<MeshInfo>(mesh.0) {
        info.path = Some(target.clone());
    }
    world.entity_mut(mesh.0).remove::<Modified>();
    // Files have no place for seam marks: say so rather than drop them silently.
    let seams = crate::mesh::attributes::MeshAttributes::of(world, mesh).seams;
    let note = if seams {
        " (seam marks are not saved: OBJ and PLY have no place for them; parameterize first and \
         the UVs keep the cut)"
    } else {
        ""
    };
    let dropped = match dropped.is_empty() {
        true => String::new(),
        false => format!(" ({})", io::dropped_note(&target, &dropped)),
    };
    let recomputed = recomputed.map_or(String::new(), |n| format!("; {n}"));
    Ok(format!(
        "saved {}{note}{dropped}{recomputed}",
        target.display()
    ))
}
