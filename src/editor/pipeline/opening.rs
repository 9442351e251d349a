//! Opening a mesh: a file, a shape or a recovery becomes the active mesh — at once, or for a
//! large file in the background, so the window keeps drawing.
//!
//! A file of at least [`JobSettings::min_open_bytes`] is read, repaired and laid out as tables
//! ([`crate::mesh::prepare_mesh`]) on a thread of its own, with its progress in the panel and
//! Esc (or the panel's Cancel) to give up; the active mesh stays as it was and may be looked at
//! meanwhile (edits wait, as during a job). When the thread is done, [`finish_opening`] spawns
//! the tables on the editor's frame — the one part that needs the world — and the mesh replaces
//! the active one as one undo step, as a small file's does. The 1.1 M-face scan (the bunny
//! Loop-subdivided twice, binary PLY) reads in 1.1 s this way and spawns in 1.0 s on the frame.
//!
//! On a software renderer a mesh the panel counts apart from the frame (at least
//! [`JobSettings::min_faces_figures_apart`] faces) is also closed over its holes from the same
//! tables, before they are spawned ([`ClosureAtOpen`]): its back faces are then culled from its
//! first frame, where the panel's count would read its tables back for seconds first. A smaller
//! mesh's closure is counted with its figures on the next frame.

use bevy::ecs::message::MessageCursor;
use bevy::prelude::{Local, Resource, World};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use crate::mesh::closure::Closure;
use crate::mesh::soup::PolygonSoup;
use crate::mesh::{MeshInfo, PreparedMesh, despawn_mesh, prepare_mesh, spawn_prepared};

use super::jobs::{JobSettings, Progress, cancel_asked};
use crate::editor::session::finish::report;
use crate::editor::session::history;
use crate::editor::session::requests::{Declined, Request};
use crate::editor::session::selection::{ActiveMesh, MeshDirty, Selection};
use crate::editor::view::culling::ClosureAtOpen;
use crate::editor::view::scene::SoftwareRenderer;

/// A file being read in the background; `None` when none is.
#[derive(Resource, Default)]
pub struct Opening(pub Option<OpeningFile>);

/// A file being read and prepared on another thread.
pub struct OpeningFile {
    /// The file.
    pub path: PathBuf,
    /// What the panel shows (`open scan.ply`).
    pub label: String,
    /// How far it got (reading, then preparing), and whether to stop.
    pub progress: Arc<Progress>,
    /// When it started.
    pub started: Instant,
    thread: Option<JoinHandle<Result<Read, String>>>,
}

/// What the thread hands back: the file's soup, its name and place, its tables, and the mesh
/// closed over its holes when asked.
struct Read {
    soup: PolygonSoup,
    info: MeshInfo,
    prepared: PreparedMesh,
    closure: Option<Closure>,
}

/// Reads `source` and prepares its mesh (away from the world), closing it over its holes when
/// it has at least `close_from` faces; the reason in words if it cannot.
fn read_and_prepare(
    source: &Path,
    progress: &Progress,
    close_from: Option<usize>,
) -> Result<Read, String> {
    let (soup, info) = crate::source::read_source(source).map_err(|e| e.to_string())?;
    if progress.is_cancelled() {
        return Err("cancelled".into());
    }
    progress.set(0.5);
    let prepared = prepare_mesh(&soup).map_err(|e| format!("{}: {e}", source.display()))?;
    let closure = close_from
        .is_some_and(|least| prepared.counts().1 >= least)
        .then(|| Closure::of(prepared.tables()));
    progress.set(0.9);
    Ok(Read {
        soup,
        info,
        prepared,
        closure,
    })
}

/// Opens `source` (a file, `shape:NAME`): in the background when it is a file of at least
/// [`JobSettings::min_open_bytes`], else at once. Returns the open message, or that reading
/// has started.
///
/// # Errors
/// [`Declined::File`] for a file that cannot be read or has no usable face; the active mesh is
/// then untouched.
pub(super) fn open(world: &mut World, source: &Path) -> Result<String, Declined> {
    let settings = world.get_resource::<JobSettings>();
    let min_bytes = settings.map_or(u64::MAX, |s| s.min_open_bytes);
    // Only a software renderer culls back faces (see `crate::editor::view::culling`).
    let software = world
        .get_resource::<SoftwareRenderer>()
        .is_some_and(|s| s.0);
    let close_from = settings
        .filter(|_| software)
        .map(|s| s.min_faces_figures_apart);
    let large = std::fs::metadata(source).is_ok_and(|m| m.is_file() && m.len() >= min_bytes);
    if large {
        return start(world, source, close_from);
    }
    let read =
        read_and_prepare(source, &Progress::default(), close_from).map_err(Declined::File)?;
    Ok(install(world, source, read))
}

/// Starts reading `source` on a thread of its own (closing it over its holes from `close_from`
/// faces).
fn start(world: &mut World, source: &Path, close_from: Option<usize>) -> Result<String, Declined> {
    if let Some(opening) = &world.resource::<Opening>().0 {
        return Err(Declined::Busy(opening.label.clone()));
    }
    let progress = Arc::new(Progress::default());
    progress.set(0.05);
    let path = source.to_path_buf();
    let thread = {
        let (path, progress) = (path.clone(), progress.clone());
        std::thread::Builder::new()
            .name("open".into())
            .spawn(move || read_and_prepare(&path, &progress, close_from))
            .map_err(|e| Declined::File(format!("cannot start reading: {e}")))?
    };
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let label = format!("open {name}");
    world.resource_mut::<Opening>().0 = Some(OpeningFile {
        path,
        label: label.clone(),
        progress,
        started: Instant::now(),
        thread: Some(thread),
    });
    Ok(format!("{label}: reading in the background (Esc cancels)"))
}

/// Stops waiting for the file being read (its thread finishes on its own and its result is
/// dropped); `None` when none is.
pub(super) fn cancel(world: &mut World) -> Option<String> {
    let opening = world.resource_mut::<Opening>().0.take()?;
    opening.progress.cancel();
    Some(format!(
        "{} cancelled: the mesh is as it was",
        opening.label
    ))
}

/// The label of the file being read, if one is.
pub fn busy(world: &World) -> Option<String> {
    world
        .get_resource::<Opening>()?
        .0
        .as_ref()
        .map(|o| o.label.clone())
}

/// Once the file being read is ready, spawns it and makes it the active mesh, and reports the
/// open's outcome as a request's (the `Apply` set, each frame).
pub fn finish_opening(world: &mut World, mut requests: Local<MessageCursor<Request>>) {
    if cancel_asked(world, &mut requests) {
        // The cancel is applied after this, and wins over a read that ended meanwhile.
        return;
    }
    let done = world
        .resource::<Opening>()
        .0
        .as_ref()
        .and_then(|o| o.thread.as_ref())
        .is_some_and(JoinHandle::is_finished);
    if !done {
        return;
    }
    let Some(mut opening) = world.resource_mut::<Opening>().0.take() else {
        return;
    };
    let Some(thread) = opening.thread.take() else {
        return;
    };
    let read_s = opening.started.elapsed().as_secs_f64();
    let start = Instant::now();
    let result = match thread.join() {
        Ok(Ok(read)) => {
            let message = install(world, &opening.path, read);
            let spawn_s = start.elapsed().as_secs_f64();
            Ok(format!(
                "{message} (read in the background in {read_s:.2} s, then {spawn_s:.2} s on the frame)"
            ))
        }
        Ok(Err(reason)) => Err(Declined::File(reason)),
        Err(_) => Err(Declined::File(format!(
            "{}: reading failed (a bug: its thread panicked); the mesh is as it was",
            opening.path.display()
        ))),
    };
    let ms = opening.started.elapsed().as_secs_f64() * 1e3;
    report(
        world,
        format!("open {}", opening.path.display()),
        result,
        ms,
    );
}

/// Makes a read mesh the active one, replacing the old one as one undo step; the open message
/// (counts, repairs, what the file held that is not kept, the reader's notes).
fn install(world: &mut World, source: &Path, read: Read) -> String {
    let Read {
        soup,
        info,
        prepared,
        closure,
    } = read;
    let (vertices, faces) = prepared.counts();
    let pending = history::begin_replace(world);
    let built = spawn_prepared(world, prepared, info);
    if let Some(old) = world.resource::<ActiveMesh>().0 {
        despawn_mesh(world, old);
    }
    world.resource_mut::<ActiveMesh>().0 = Some(built.mesh);
    world.resource_mut::<Selection>().select_only(None);
    world.entity_mut(built.mesh.0).insert(MeshDirty);
    if let Some(closure) = closure {
        world
            .entity_mut(built.mesh.0)
            .insert(ClosureAtOpen(closure));
    }
    if let Some(pending) = pending {
        history::commit(world, pending, format!("open {}", source.display()));
    }
    let mut dropped = match soup.scalars_not_kept() {
        None => String::new(),
        Some(names) => format!(
            "; the file's {names} is not kept (saving writes positions, faces, UVs, normals and colours)"
        ),
    };
    for note in &soup.notes {
        dropped.push_str("; ");
        dropped.push_str(note);
    }
    format!(
        "{}: {vertices} vertices, {faces} faces; {}{dropped}",
        source.display(),
        built.report
    )
}
