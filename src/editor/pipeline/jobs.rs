//! Long operations that keep the window alive: progress, cancel, atomic commit.
//!
//! Whole-mesh edits that [`Edit::may_run_as_job`] (simplification, remeshing, subdivision,
//! triangulation) on a mesh of at least [`JobSettings::min_faces`] faces run as a **job**. The
//! mesh's tables are copied into a scratch world, the edit runs there on a thread of its own,
//! reporting its progress and watching for a cancel, and the editor keeps drawing frames meanwhile. When
//! the thread is done, [`finish_jobs`] writes the result into the mesh in one step (the same
//! table write an undo uses) and hands it to [`finish_edit`], the path every edit ends on.
//!
//! An edit that is a function of the tables alone (subdivision, [`Edit::runs_on_tables`]) skips
//! the scratch world: the thread computes the result's tables from the undo record's copy, and
//! the commit writes them. Spawning the copy and reading the result back from it took more than
//! the subdivision itself.
//!
//! Cancelling (Esc, or the panel's button) drops the job; the mesh was never touched, so it is
//! exactly as it was. While a job runs, edits of its mesh (undo and redo included) are refused
//! with a message; selecting and looking around still work.

use bevy::ecs::message::{MessageCursor, Messages};
use bevy::prelude::{Local, Resource, World};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::thread::JoinHandle;

use crate::edit::{Applied, Edit, EditContext};
use crate::mesh::change::{Remap, row_map};
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::tables::{
    Connectivity, MeshTables, extract, replace_contents, spawn_connectivity,
};
use crate::mesh::{MeshInfo, MeshMembers, MeshRef};
use crate::ops::Refusal;
use crate::ops::progressive::ProgressiveMesh;

use crate::editor::session::finish::{Finished, finish_edit, report};
use crate::editor::session::history::Pending;
use crate::editor::session::requests::{Declined, Request};
use crate::editor::session::selection::{Selection, exists};
use crate::ops::simplification_history::SimplificationHistory;

/// What a frame may spend reading a large mesh a slice at a time
/// ([`crate::mesh::tables::GradualRead`]), for the panel's figures or the autosave.
pub const READ_SLICE: std::time::Duration = std::time::Duration::from_millis(6);

/// When an operation runs as a job.
#[derive(Resource, Debug, Clone, Copy)]
pub struct JobSettings {
    /// Meshes with at least this many faces run whole-mesh operations as jobs. Default 20 000
    /// (below that every operation takes well under a tenth of a second).
    pub min_faces: usize,
    /// Files of at least this many bytes open in the background ([`super::opening`]).
    /// Default 8 MB (a 300 k-face binary PLY; the shared models open in a fraction of a second).
    pub min_open_bytes: u64,
    /// Meshes of at least this many faces have the panel's figures counted on a thread and
    /// their validity checked when asked ([`crate::editor::panels::mesh_figures`]). Default 200 000.
    pub min_faces_figures_apart: usize,
}

impl Default for JobSettings {
    fn default() -> Self {
        Self {
            min_faces: 20_000,
            min_open_bytes: 8 << 20,
            min_faces_figures_apart: 200_000,
        }
    }
}

/// Shared between a job's thread and the editor: how far it got, and whether to stop.
#[derive(Debug, Default)]
pub struct Progress {
    fraction_bits: AtomicU32,
    cancelled: AtomicBool,
}

impl Progress {
    /// Records the fraction done (0–1).
    pub fn set(&self, fraction: f32) {
        self.fraction_bits
            .store(fraction.clamp(0.0, 1.0).to_bits(), Ordering::Relaxed);
    }

    /// The fraction done (0–1).
    pub fn fraction(&self) -> f32 {
        f32::from_bits(self.fraction_bits.load(Ordering::Relaxed))
    }

    /// Asks the job to stop.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether the job was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}

/// What a job's thread hands back.
enum JobOutput {
    /// The edit ran on a copy of the mesh in a scratch world: the result's tables with the
    /// scratch entity behind every row, and the scratch entities the input's rows were spawned
    /// as (the two carry the selection and the simplification history over).
    Copy {
        result: MeshTables,
        input: MeshMembers,
        applied: Applied,
        history: Option<Box<ProgressiveMesh>>,
    },
    /// The edit was computed on the tables alone ([`Edit::run_on_tables`]): the result's
    /// tables, and the mesh's entities row by row as the input's tables had them (written over
    /// row for row, so the first rows of each kind keep their entities).
    Tables {
        tables: Connectivity,
        input: MeshMembers,
        applied: Applied,
    },
}

/// The job in flight.
pub struct RunningJob {
    /// The mesh it works on.
    pub mesh: MeshId,
    /// The request's label.
    pub label: String,
    /// Its progress, shared with the thread.
    pub progress: Arc<Progress>,
    /// When it started.
    pub started: std::time::Instant,
    edit: Edit,
    pending: Option<Pending>,
    /// The mesh's entities, row by row, as copied into the scratch world (none when the job
    /// works on the tables alone).
    rows: Option<MeshMembers>,
    /// The thread, until it is joined.
    thread: Option<JoinHandle<Result<JobOutput, Refusal>>>,
}

/// The job in flight, if any (one at a time).
#[derive(Resource, Default)]
pub struct Jobs {
    /// The running job.
    pub running: Option<RunningJob>,
    /// The last job failed (a bug: its thread panicked); set until the autosave has seen it
    /// ([`super::recovery`]).
    pub failed: bool,
}

/// Whether `edit` should run as a job on `mesh` (a whole-mesh computation on a large enough
/// mesh).
pub fn wants_job(world: &World, edit: &Edit, mesh: MeshId) -> bool {
    let Some(settings) = world.get_resource::<JobSettings>() else {
        return false;
    };
    edit.may_run_as_job()
        && world.get::<MeshInfo>(mesh.0).is_some()
        && crate::mesh::members::of_kind::<crate::mesh::Face, _>(world, mesh, |e| e).len()
            >= settings.min_faces
}

/// Starts `edit` on a thread of its own: on the mesh's tables when the edit is a function of
/// them ([`Edit::runs_on_tables`]), on a copy of `mesh` in a scratch world otherwise.
/// `pending` is the undo record the result will be committed with.
///
/// # Errors
/// When a job is running already, or no thread can be started.
pub fn start(
    world: &mut World,
    mesh: MeshId,
    edit: Edit,
    pending: Option<Pending>,
) -> Result<String, Declined> {
    if let Some(job) = &world.resource::<Jobs>().running {
        return Err(Declined::Busy(job.label.clone()));
    }
    // The undo record has read the mesh already: copying its tables is cheaper than reading
    // the entities again.
    let MeshTables { tables, members } = match pending.as_ref().and_then(Pending::tables) {
        Some(record) => record.clone(),
        None => extract(world, mesh),
    };
    let label = edit.label();
    let progress = Arc::new(Progress::default());
    let shared = Arc::clone(&progress);
    let mut job = edit.clone();
    // The vertices a job's operation names (smoothing's held ones; an operation that runs as
    // a job names no other element) by row, to be named again by the scratch copy's entities:
    // every one of them, or the job is refused.
    let named_rows: Vec<usize> = match &edit {
        Edit::Operation(op) => {
            let rows = members.vertex_rows();
            let row = |&x: &ElementId| match x {
                ElementId::Vertex(v) => {
                    rows.get(&v.0).map(|&r| r as usize).ok_or(Refusal::Stale(x))
                }
                _ => Err(Refusal::BadParameter(format!(
                    "a job names vertices only, not {x}"
                ))),
            };
            op.elements().iter().map(row).collect::<Result<_, _>>()?
        }
        _ => Vec::new(),
    };
    let name = format!("pappus job: {label}");
    let spawned = if job.runs_on_tables() {
        // The edit is a function of the tables: no copy of the mesh to spawn or read back.
        let before = MeshTables { tables, members };
        let thread = std::thread::Builder::new().name(name).spawn(move || {
            let (tables, applied) = job.run_on_tables(&before).expect("checked above")?;
            shared.set(1.0);
            Ok(JobOutput::Tables {
                tables,
                input: before.members,
                applied,
            })
        });
        thread.map(|thread| (thread, None))
    } else {
        let thread = std::thread::Builder::new().name(name).spawn(move || {
            let mut scratch = World::new();
            let (copy, input) = spawn_connectivity(&mut scratch, &tables, MeshInfo::default());
            if let Edit::Operation(op) = &mut job {
                let renamed = named_rows.iter().map(|&r| input.vertices[r].into());
                *op = op
                    .clone()
                    .on(renamed.collect())
                    .map_err(Refusal::BadParameter)?;
            }
            let applied = job.run(
                &mut scratch,
                copy,
                &mut EditContext {
                    progress: &mut |f| {
                        shared.set(f);
                        !shared.is_cancelled()
                    },
                },
            )?;
            let history = SimplificationHistory::take(&mut scratch, copy);
            Ok(JobOutput::Copy {
                result: extract(&scratch, copy),
                input,
                applied,
                history: history.map(Box::new),
            })
        });
        thread.map(|thread| (thread, Some(members)))
    };
    let (thread, rows) =
        spawned.map_err(|e| Declined::Job(format!("could not start a thread: {e}")))?;
    world.resource_mut::<Jobs>().running = Some(RunningJob {
        mesh,
        label,
        progress,
        started: std::time::Instant::now(),
        edit,
        pending,
        rows,
        thread: Some(thread),
    });
    Ok("running (Esc cancels)".into())
}

/// Cancels the running job; the mesh stays as it was.
///
/// # Errors
/// When no job is running.
pub fn cancel(world: &mut World) -> Result<String, Declined> {
    let Some(job) = world.resource_mut::<Jobs>().running.take() else {
        return Err(Declined::NoJob);
    };
    job.progress.cancel();
    // The thread stops at its next progress report; its result is dropped unread.
    Ok(format!("cancelled {}, the mesh is unchanged", job.label))
}

/// Commits a finished job: the mesh takes the result in one step, as one undo entry, and the
/// outcome is reported (the `Apply` set, before the requests of the frame).
pub fn finish_jobs(world: &mut World, mut requests: Local<MessageCursor<Request>>) {
    if cancel_asked(world, &mut requests) {
        // The cancel is applied after this, and wins over a job that ended meanwhile.
        return;
    }
    let done = world
        .resource::<Jobs>()
        .running
        .as_ref()
        .and_then(|j| j.thread.as_ref())
        .is_some_and(JoinHandle::is_finished);
    if !done {
        return;
    }
    let Some(mut job) = world.resource_mut::<Jobs>().running.take() else {
        return;
    };
    let Some(thread) = job.thread.take() else {
        return;
    };
    let ms = job.started.elapsed().as_secs_f64() * 1000.0;
    let result = match thread.join() {
        Ok(Ok(output)) => commit(world, &mut job, output),
        Ok(Err(refusal)) => Err(Declined::Refused(refusal)),
        Err(_) => Err(Declined::Job(
            "the operation failed (a bug: please report it); the mesh is unchanged".into(),
        )),
    };
    // The mesh is as it was; the autosave writes its unsaved changes now rather than after
    // a wait.
    world.resource_mut::<Jobs>().failed = matches!(result, Err(Declined::Job(_)));
    report(world, job.label, result, ms);
}

/// Writes a finished job's result into its mesh and ends it as every edit ends.
fn commit(world: &mut World, job: &mut RunningJob, output: JobOutput) -> Result<String, Declined> {
    let mesh = job.mesh;
    if world.get::<MeshInfo>(mesh.0).is_none() {
        return Err(Declined::Refused(Refusal::Stale(ElementId::Mesh(mesh))));
    }
    let kept = job.edit.keeps_ids();
    // The selected set (the active element last), as far as its ids outlive the edit.
    let (set, active) = {
        let selection = world.resource::<Selection>();
        let set: Vec<ElementId> = selection
            .elements()
            .iter()
            .copied()
            .filter(|&x| kept.keeps(x))
            .collect();
        (set, selection.element.filter(|&x| kept.keeps(x)))
    };
    let (applied, follow): (Applied, Option<(Remap, Remap)>) = match output {
        JobOutput::Tables {
            tables,
            input,
            applied,
        } => {
            // Written over the input's rows in their order: the rows whose ids are kept keep
            // their entities, the selected ones included.
            replace_contents(world, mesh, &input, &tables);
            (applied, None)
        }
        JobOutput::Copy {
            result,
            input,
            applied,
            history,
        } => {
            let old = MeshMembers::collect(world, mesh);
            let rows = replace_contents(world, mesh, &old, &result.tables);
            // Scratch entities of the result → the entities that hold those rows now.
            let to_main = row_map(&result.members, &rows);
            // A simplification's history, on the copy's entities → on the mesh's; any other
            // edit's history is settled when the edit finishes.
            if let Some(mut pm) = history {
                pm.remap(mesh, &to_main);
                SimplificationHistory::keep(world, mesh, *pm);
            }
            // The selection's entities → their rows in the copy → those rows' entities in the
            // result.
            let to_scratch = job
                .rows
                .as_ref()
                .map(|rows| row_map(rows, &input))
                .unwrap_or_default();
            (applied, Some((to_scratch, to_main)))
        }
    };
    crate::edit::mark_normals_stale(world, mesh, &job.edit);
    #[cfg(any(debug_assertions, feature = "checked"))]
    if let Err(e) = crate::mesh::validate(world, mesh) {
        panic!("{} left an invalid mesh: {e}", job.label);
    }
    let followed = |x: ElementId| match &follow {
        None => Some(x),
        Some((to_scratch, to_main)) => {
            let now = to_main.get(to_scratch.get(&x.entity())?)?;
            Some(x.with_entity(*now))
        }
    };
    let m = MeshRef::new(world);
    let set: Vec<ElementId> = set
        .into_iter()
        .filter_map(followed)
        .filter(|&x| exists(&m, x))
        .collect();
    let active = active.and_then(followed).filter(|&x| exists(&m, x));
    let mut selection = world.resource_mut::<Selection>();
    selection.select_only(None);
    selection.extend(set);
    if let Some(x) = active {
        selection.add(x);
    }
    finish_edit(
        world,
        Finished {
            edit: job.edit.clone(),
            mesh,
            result: Ok(applied),
            pending: job.pending.take(),
        },
    )
}

/// Whether a cancel ([`Request::CancelJob`]) was asked for since `cursor` last looked: the
/// job or the file read it cancels must then not be finished in the same frame, before the
/// request is applied (a cancel pressed as the thread ends cancels, as the user meant).
pub(super) fn cancel_asked(world: &World, cursor: &mut MessageCursor<Request>) -> bool {
    cursor
        .read(world.resource::<Messages<Request>>())
        .any(|r| matches!(r, Request::CancelJob))
}
