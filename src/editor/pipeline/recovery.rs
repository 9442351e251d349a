//! Crash recovery in the editor: the unsaved mesh is written to a recovery file
//! ([`crate::recovery`]) once the editor has been idle for [`Autosave::idle`] after an edit, on
//! a thread of its own, and removed after a save; at start the newest recovery that holds work
//! its source does not is offered back.
//!
//! - **When**: an edit re-marks the mesh [`Modified`]; [`autosave`] sees the marker change and
//!   waits until no edit has come for [`Autosave::idle`] (2 s; a drag or a gesture edits every
//!   frame, so it waits for its end) and no job is running. Then it reads the mesh's tables (the
//!   only part that needs the world) a slice of [`READ_SLICE`] a frame ([`GradualRead`]; read in
//!   one go they held a frame of the 1.3 M-triangle icosphere for 650–830 ms), an edit meanwhile
//!   starting it over, and a thread makes the soup, encodes and writes it, atomically, so a
//!   frame never waits for the disk.
//! - **What survives**: a kill or a power cut loses the edits of the last `idle` seconds at
//!   most. A panic anywhere in the process ([`install_panic_hook`]) finishes a write still in
//!   flight before the process ends, and says where the work is. A panic in a job ends only
//!   the job (the mesh is unchanged; `Jobs::failed` says so) and the recovery is written at
//!   once.
//! - **After a save** the mesh is no longer `Modified` and this session's recovery goes.
//!
//! The headless app leaves autosave off ([`Autosave::default`] has no folder): tests and
//! scripts that want it insert an [`Autosave`] with a folder of their own.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use bevy::ecs::change_detection::Tick;
use bevy::prelude::{DetectChanges, Resource, World};
use bevy::window::RequestRedraw;

use super::jobs::{Jobs, READ_SLICE};
use crate::editor::session::requests::{Declined, RecoveryAnswer};
use crate::editor::session::selection::ActiveMesh;
use crate::editor::session::state::{Modified, is_modified};
use crate::editor::view::render_sync::RenderStats;
use crate::mesh::tables::{Connectivity, GradualRead, extract};
use crate::mesh::{MeshId, MeshInfo, soup_of_tables};
use crate::recovery::{self, Recovery, RecoveryInfo};

/// The autosave's settings and state.
#[derive(Resource)]
pub struct Autosave {
    /// Where recoveries go; `None`: autosave is off.
    pub folder: Option<PathBuf>,
    /// How long the editor must be idle after an edit before the mesh is written. Default 2 s.
    pub idle: Duration,
    /// When this session started (in the recovery's name).
    started_at: f64,
    /// The change tick of the active mesh's `Modified` marker last seen.
    seen: Option<(MeshId, Tick)>,
    /// When the last unsaved edit came, while it is not written yet.
    edited_at: Option<Instant>,
    /// The read under way: the mesh, its `Modified` tick and the render generation it began at.
    reading: Option<Box<(MeshId, Tick, usize, GradualRead)>>,
    /// The write in flight.
    writing: Option<JoinHandle<Result<PathBuf, String>>>,
    /// This session's recovery on disk, if any.
    pub written: Option<PathBuf>,
    /// The last write's failure, said once in the log.
    pub failure: Option<String>,
}

impl Default for Autosave {
    /// Off: no folder.
    fn default() -> Self {
        Self {
            folder: None,
            idle: Duration::from_secs(2),
            started_at: recovery::now(),
            seen: None,
            edited_at: None,
            reading: None,
            writing: None,
            written: None,
            failure: None,
        }
    }
}

impl Autosave {
    /// Autosave into `folder` (the program passes [`recovery::folder`]).
    pub fn into_folder(folder: Option<PathBuf>) -> Self {
        Self {
            folder,
            ..Self::default()
        }
    }

    /// Whether an unsaved edit waits to be written, or a write to finish: the editor must
    /// wake for it even with no input ([`crate::editor::automation::pacing`]).
    pub fn is_pending(&self) -> bool {
        self.folder.is_some()
            && (self.edited_at.is_some() || self.reading.is_some() || self.writing.is_some())
    }
}

/// The recovery offered at start, until it is answered.
#[derive(Resource, Default, Debug)]
pub struct RecoveryOffer(pub Option<Recovery>);

/// The snapshot a write in flight holds, for the panic hook to finish.
struct Snapshot {
    folder: PathBuf,
    name: String,
    /// The mesh's tables: the soup is made from them on the writing thread.
    tables: Connectivity,
    info: RecoveryInfo,
}

/// The write in flight, shared with the panic hook.
static IN_FLIGHT: Mutex<Option<Arc<Snapshot>>> = Mutex::new(None);

/// Looks for a recovery to offer (at start): the newest one in the autosave's folder that holds
/// work its source does not and whose editor is not running any more.
pub fn find_recovery(world: &mut World) {
    let Some(folder) = world.resource::<Autosave>().folder.clone() else {
        return;
    };
    let offer = recovery::list(&folder)
        .into_iter()
        .find(|r| r.newer_than_source() && !r.writer_is_running());
    world.resource_mut::<RecoveryOffer>().0 = offer;
}

/// Follows the active mesh's edits and writes its recovery when the editor is idle (the
/// `Apply` set's end). Also finishes writes and removes the recovery once the mesh is saved.
pub fn autosave(world: &mut World) {
    finish_write(world);
    if world.resource::<Autosave>().folder.is_none() {
        return;
    }
    let Some(mesh) = world.resource::<ActiveMesh>().0 else {
        return;
    };
    let marker = world
        .get_entity(mesh.0)
        .ok()
        .and_then(|e| e.get_ref::<Modified>().map(|m| m.last_changed()));
    let mut state = world.resource_mut::<Autosave>();
    match marker {
        None => {
            // Saved (or freshly opened): nothing unsaved to keep.
            state.edited_at = None;
            state.seen = None;
            state.reading = None;
            if state.writing.is_none()
                && let Some(path) = state.written.take()
            {
                recovery::remove(&path);
            }
            return;
        }
        Some(tick) if state.seen != Some((mesh, tick)) => {
            state.seen = Some((mesh, tick));
            state.edited_at = Some(Instant::now());
            // Whatever was read is from before this edit.
            state.reading = None;
        }
        Some(_) => {}
    }
    let due = state.edited_at.is_some_and(|at| at.elapsed() >= state.idle);
    let idle = state.writing.is_none();
    // A job that failed left the mesh as it was: its unsaved changes go to disk now.
    let failed_job = std::mem::take(&mut world.resource_mut::<Jobs>().failed);
    let free = idle && world.resource::<Jobs>().running.is_none();
    if failed_job && free {
        world.resource_mut::<Autosave>().reading = None;
        let tables = extract(world, mesh).tables;
        start_write(world, mesh, tables);
    } else if due && free {
        read_on(world, mesh);
    }
}

/// Reads the next slice of `mesh` for its recovery (starting the read if none is under way, or
/// over if the mesh changed since it began), and starts the write once it is read.
fn read_on(world: &mut World, mesh: MeshId) {
    let generation = world
        .get_resource::<RenderStats>()
        .map_or(0, |s| s.rebuilds);
    let Some((_, tick)) = world.resource::<Autosave>().seen else {
        return;
    };
    let mut reading = match world.resource_mut::<Autosave>().reading.take() {
        Some(r) if (r.0, r.1, r.2) == (mesh, tick, generation) => r,
        _ => Box::new((mesh, tick, generation, GradualRead::new(mesh))),
    };
    match reading.3.advance(world, READ_SLICE) {
        Ok(Some(tables)) => start_write(world, mesh, tables.tables),
        Ok(None) => {
            world.resource_mut::<Autosave>().reading = Some(reading);
            world.write_message(RequestRedraw);
        }
        // Started over on the next frame.
        Err(_) => {
            world.write_message(RequestRedraw);
        }
    }
}

/// Removes this session's recovery, and forgets the edits not written yet: the user discarded
/// the unsaved changes (quitting without saving), so there is nothing to offer back.
pub fn forget(world: &mut World) {
    let mut state = world.resource_mut::<Autosave>();
    state.edited_at = None;
    state.reading = None;
    if let Some(thread) = state.writing.take()
        && let Ok(Ok(path)) = thread.join()
    {
        // The write in flight finished: its file is what goes.
        state.written = Some(path);
    }
    if let Some(path) = state.written.take() {
        recovery::remove(&path);
    }
}

/// Starts the thread that makes the soup of `tables` (`mesh`'s, just read) and writes it.
fn start_write(world: &mut World, mesh: MeshId, tables: Connectivity) {
    let (name, source) = world
        .get::<MeshInfo>(mesh.0)
        .map(|i| (i.name.clone(), i.path.clone()))
        .unwrap_or_default();
    let mut state = world.resource_mut::<Autosave>();
    let Some(folder) = state.folder.clone() else {
        return;
    };
    state.edited_at = None;
    let snapshot = Arc::new(Snapshot {
        name: recovery::session_name(&name, state.started_at),
        info: RecoveryInfo {
            source: source.map(|p| std::path::absolute(&p).unwrap_or(p)),
            name,
            saved_at: recovery::now(),
            pid: std::process::id(),
            vertices: tables.vertex_count(),
            faces: tables.face_count(),
        },
        tables,
        folder,
    });
    *IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner()) = Some(Arc::clone(&snapshot));
    let spawned = std::thread::Builder::new()
        .name("pappus recovery".into())
        .spawn(move || {
            let written = write_snapshot(&snapshot);
            let mut in_flight = IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner());
            if in_flight
                .as_ref()
                .is_some_and(|s| Arc::ptr_eq(s, &snapshot))
            {
                *in_flight = None;
            }
            written
        });
    match spawned {
        Ok(thread) => state.writing = Some(thread),
        Err(e) => {
            let message = format!("could not start the recovery writer: {e}");
            crate::editor::session::finish::report(
                world,
                "autosave".into(),
                Err(Declined::File(message)),
                0.0,
            );
        }
    }
}

fn write_snapshot(s: &Snapshot) -> Result<PathBuf, String> {
    let soup = soup_of_tables(&s.tables);
    recovery::write(&s.folder, &s.name, &soup, &s.info).map_err(|e| e.to_string())
}

/// Takes the result of a finished write: the recovery on disk, or the failure, said once in
/// the log (the next edit tries again).
fn finish_write(world: &mut World) {
    let mut state = world.resource_mut::<Autosave>();
    if !state.writing.as_ref().is_some_and(JoinHandle::is_finished) {
        return;
    }
    let Some(thread) = state.writing.take() else {
        return;
    };
    let failure = match thread.join() {
        Ok(Ok(path)) => {
            state.written = Some(path);
            None
        }
        Ok(Err(e)) => Some(format!("the recovery file could not be written: {e}")),
        Err(_) => Some("the recovery writer failed".into()),
    };
    if failure.is_some() && failure != state.failure {
        let message = failure.clone().unwrap_or_default();
        crate::editor::session::finish::report(
            world,
            "autosave".into(),
            Err(Declined::File(message)),
            0.0,
        );
    }
    world.resource_mut::<Autosave>().failure = failure;
}

/// Makes a panic on any thread finish the recovery write in flight before the process ends,
/// and say where the unsaved work is. Installed once, by the program (tests keep the default
/// hook); the hook it replaces still runs first.
pub fn install_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            previous(info);
            // `try_lock`: the panic may have come while this very lock was held.
            let snapshot = IN_FLIGHT.try_lock().ok().and_then(|mut s| s.take());
            if let Some(snapshot) = snapshot {
                match write_snapshot(&snapshot) {
                    Ok(path) => eprintln!(
                        "pappus: the unsaved mesh is kept in {} (`pappus recover --latest -o FILE` \
                         restores it)",
                        path.display()
                    ),
                    Err(e) => eprintln!("pappus: the recovery file could not be written: {e}"),
                }
            }
        }));
    });
}

/// Answers the offer: restores the recovery (its mesh opened with `open`, the pipeline's own
/// way of opening a file, as unsaved work on its source, and the recovery then removed, this
/// session keeping its own), discards it, or keeps it.
///
/// # Errors
/// No offer open; restoring over unsaved changes; a recovery that cannot be read.
pub fn answer(
    world: &mut World,
    answer: RecoveryAnswer,
    open: fn(&mut World, &Path) -> Result<String, Declined>,
) -> Result<String, Declined> {
    let offer = world
        .resource_mut::<RecoveryOffer>()
        .0
        .take()
        .ok_or(Declined::NothingWaiting)?;
    match answer {
        RecoveryAnswer::Keep => Ok(format!(
            "recovery {} kept (`pappus recover --list`)",
            offer.name
        )),
        RecoveryAnswer::Discard => {
            offer.remove();
            Ok(format!("recovery {} deleted", offer.name))
        }
        RecoveryAnswer::Restore => {
            if let Some(mesh) = world.resource::<ActiveMesh>().0
                && is_modified(world, mesh)
            {
                world.resource_mut::<RecoveryOffer>().0 = Some(offer);
                return Err(Declined::UnsavedChanges);
            }
            restore(world, &offer, open)
        }
    }
}

/// Opens `offer`'s mesh in place of the active one, names it after its source and marks it
/// unsaved.
fn restore(
    world: &mut World,
    offer: &Recovery,
    open: fn(&mut World, &Path) -> Result<String, Declined>,
) -> Result<String, Declined> {
    let summary = open(world, &offer.mesh)?;
    let mesh = world.resource::<ActiveMesh>().0.ok_or(Declined::NoMesh)?;
    if let Some(mut info) = world.get_mut::<MeshInfo>(mesh.0) {
        info.name = offer.info.name.clone();
        info.path = offer.info.source.clone();
    }
    world.entity_mut(mesh.0).insert(Modified);
    offer.remove();
    let from = offer.info.source.as_deref().map_or_else(
        || "a mesh never saved".into(),
        |p: &Path| p.display().to_string(),
    );
    let counts = summary
        .split_once(": ")
        .map_or(summary.as_str(), |(_, c)| c);
    Ok(format!(
        "recovered the unsaved work on {from} ({counts}); save it with Ctrl+S"
    ))
}

/// The offer of a recovery, while one is open: what it holds, and Restore / Delete / Later.
pub fn offer_window(
    mut contexts: bevy_egui::EguiContexts,
    offer: bevy::prelude::Res<RecoveryOffer>,
    mut requests: bevy::prelude::MessageWriter<crate::editor::session::requests::Request>,
) -> bevy::prelude::Result {
    use crate::editor::session::requests::Request;
    use bevy_egui::egui;
    let Some(recovery) = &offer.0 else {
        return Ok(());
    };
    let ctx = contexts.ctx_mut()?;
    let age = recovery::age(recovery::now() - recovery.info.saved_at);
    let file = recovery.info.source.as_ref().map_or_else(
        || "It was never saved to a file.".to_string(),
        |p| format!("Its file: {}", p.display()),
    );
    egui::Window::new("Recover unsaved work?")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            ui.label(format!(
                "An editor ended without saving {} ({} vertices, {} faces), {age} ago.",
                recovery.info.name, recovery.info.vertices, recovery.info.faces
            ));
            ui.label(file);
            ui.horizontal(|ui| {
                if ui.button("Restore").clicked() {
                    requests.write(Request::Recover(RecoveryAnswer::Restore));
                }
                if ui.button("Delete it").clicked() {
                    requests.write(Request::Recover(RecoveryAnswer::Discard));
                }
                if ui.button("Later").clicked() {
                    requests.write(Request::Recover(RecoveryAnswer::Keep));
                }
            });
        });
    Ok(())
}
