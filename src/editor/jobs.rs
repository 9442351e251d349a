//! Long operations that keep the window alive: progress, cancel, atomic commit.
//!
//! Whole-mesh operations ([`GlobalOp`]: simplification, remeshing, subdivision, triangulation)
//! on a mesh of at least [`JobSettings::min_faces`] faces run as a **job**. The mesh's tables
//! are copied into a scratch world, the operation runs there on a thread of its own, reporting
//! its progress and watching for a cancel, and the editor keeps drawing frames meanwhile. When
//! the thread is done, [`finish_jobs`] writes the result into the mesh in one step (the same
//! table write an undo uses), records it as one undo entry, and reports it like any other edit.
//!
//! Cancelling (Esc, or the panel's button) drops the job; the mesh was never touched, so it is
//! exactly as it was. While a job runs, edits of its mesh (undo and redo included) are refused
//! with a message; selecting and looking around still work.

use bevy::prelude::{Resource, World};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::thread::JoinHandle;

use crate::mesh::arrays::{Extracted, extract, replace_contents};
use crate::mesh::build::spawn_connectivity;
use crate::mesh::change::row_map;
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::{MeshInfo, MeshMembers, MeshRef};
use crate::ops::progressive::ProgressiveMesh;
use crate::ops::remesh::{RemeshParams, remesh_with_progress};
use crate::ops::simplify::SimplifyParams;
use crate::ops::subdivide::{catmull_clark, loop_subdivide};
use crate::ops::triangulate::triangulate;

use super::history::Pending;
use super::requests::{EditOutcome, EditRequest, OutcomeLog};
use super::selection::{MeshDirty, Selection};

/// A whole-mesh operation: runs on any world, the editor's or a job's scratch copy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GlobalOp {
    /// Cut every polygon into triangles.
    Triangulate,
    /// QEM simplification to this fraction of the faces, recording the history.
    Simplify(f32),
    /// One level of Loop subdivision.
    LoopSubdivide,
    /// One level of Catmull–Clark subdivision.
    CatmullClark,
    /// Isotropic remeshing with the default parameters.
    Remesh,
}

/// What a [`GlobalOp`] made: a summary for the log, and the simplification history if any.
pub struct GlobalResult {
    /// One line for the status bar.
    pub summary: String,
    /// The recorded simplification (for the level-of-detail slider).
    pub progressive: Option<ProgressiveMesh>,
}

impl GlobalOp {
    /// The operation a request stands for, and its mesh.
    pub fn of(request: &EditRequest) -> Option<(MeshId, GlobalOp)> {
        Some(match request {
            EditRequest::Triangulate(m) => (*m, GlobalOp::Triangulate),
            EditRequest::Simplify(m, ratio) => (*m, GlobalOp::Simplify(*ratio)),
            EditRequest::LoopSubdivide(m) => (*m, GlobalOp::LoopSubdivide),
            EditRequest::CatmullClark(m) => (*m, GlobalOp::CatmullClark),
            EditRequest::Remesh(m) => (*m, GlobalOp::Remesh),
            _ => return None,
        })
    }

    /// Whether element ids other than vertices keep their meaning (subdivision rewrites the
    /// tables: halfedges, edges and faces are renumbered).
    pub fn keeps_element_ids(self) -> bool {
        !matches!(self, GlobalOp::LoopSubdivide | GlobalOp::CatmullClark)
    }

    /// Runs the operation on `mesh` in `world`, calling `progress(fraction)` now and then;
    /// `progress` returning `false` asks it to stop early where it can.
    ///
    /// # Errors
    /// The operation's refusal, as text (the mesh is then unchanged).
    pub fn run(
        self,
        world: &mut World,
        mesh: MeshId,
        mut progress: impl FnMut(f32) -> bool,
    ) -> Result<GlobalResult, String> {
        if world.get::<MeshInfo>(mesh.0).is_none() {
            return Err(format!("{mesh} does not exist"));
        }
        let plain = |summary| GlobalResult {
            summary,
            progressive: None,
        };
        match self {
            GlobalOp::Triangulate => {
                let s = triangulate(world, mesh);
                Ok(plain(format!(
                    "{} polygon(s) cut into triangles, {} face(s) added",
                    s.polygons, s.added_faces
                )))
            }
            GlobalOp::Simplify(ratio) => {
                let faces = MeshMembers::collect(world, mesh).faces.len();
                let params = SimplifyParams::ratio(faces, f64::from(ratio));
                let (pm, s) =
                    ProgressiveMesh::simplify_with_progress(world, mesh, &params, progress)
                        .map_err(|r| r.to_string())?;
                let reached = if s.reached_target {
                    ""
                } else {
                    " (no legal collapse left before the target)"
                };
                Ok(GlobalResult {
                    summary: format!("{} -> {} faces{reached}", s.faces_before, s.faces_after),
                    progressive: Some(pm),
                })
            }
            GlobalOp::LoopSubdivide | GlobalOp::CatmullClark => {
                let s = if self == GlobalOp::LoopSubdivide {
                    loop_subdivide(world, mesh, 1)
                } else {
                    catmull_clark(world, mesh, 1)
                }
                .map_err(|r| r.to_string())?;
                progress(1.0);
                Ok(plain(format!("{} vertices, {} faces", s.vertices, s.faces)))
            }
            GlobalOp::Remesh => {
                let s = remesh_with_progress(world, mesh, &RemeshParams::default(), progress)
                    .map_err(|r| r.to_string())?;
                Ok(plain(format!(
                    "length {:.4}: {} splits, {} collapses, {} flips",
                    s.target_length, s.splits, s.collapses, s.flips
                )))
            }
        }
    }
}

/// When an operation runs as a job.
#[derive(Resource, Debug, Clone, Copy)]
pub struct JobSettings {
    /// Meshes with at least this many faces run whole-mesh operations as jobs. Default 20 000
    /// (below that every operation takes well under a tenth of a second).
    pub min_faces: usize,
}

impl Default for JobSettings {
    fn default() -> Self {
        Self { min_faces: 20_000 }
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

/// What a job's thread hands back: the result's tables in the scratch world with the scratch
/// entity behind every row, and the scratch entities the input's rows were spawned as (the two
/// carry the selection and the simplification history over).
struct JobOutput {
    result: Extracted,
    input: MeshMembers,
    global: GlobalResult,
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
    op: GlobalOp,
    pending: Option<Pending>,
    /// The mesh's entities, row by row, as copied.
    rows: MeshMembers,
    /// The thread, until it is joined.
    thread: Option<JoinHandle<Result<JobOutput, String>>>,
}

/// The job in flight, if any (one at a time).
#[derive(Resource, Default)]
pub struct Jobs {
    /// The running job.
    pub running: Option<RunningJob>,
}

/// Whether `request` should run as a job (a whole-mesh operation on a large enough mesh).
pub fn wants_job(world: &World, request: &EditRequest) -> Option<(MeshId, GlobalOp)> {
    let (mesh, op) = GlobalOp::of(request)?;
    world.get::<MeshInfo>(mesh.0)?;
    let min = world.get_resource::<JobSettings>()?.min_faces;
    let faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(world, mesh, |e| e).len();
    (faces >= min).then_some((mesh, op))
}

/// Starts `op` on a copy of `mesh` on a thread of its own. `pending` is the undo record the
/// result will be committed with.
pub fn start(
    world: &mut World,
    mesh: MeshId,
    op: GlobalOp,
    label: String,
    pending: Option<Pending>,
) -> Result<String, String> {
    if world.resource::<Jobs>().running.is_some() {
        return Err("another operation is running: wait for it, or cancel it (Esc)".into());
    }
    // The undo record has read the mesh already: copying its tables is cheaper than reading
    // the entities again.
    let (tables, members) = match pending.as_ref().and_then(Pending::tables) {
        Some(record) => (record.tables().clone(), record.members().clone()),
        None => {
            let Extracted { tables, members } = extract(world, mesh);
            (tables, members)
        }
    };
    let progress = Arc::new(Progress::default());
    let shared = Arc::clone(&progress);
    let thread = std::thread::Builder::new()
        .name(format!("pappus job: {label}"))
        .spawn(move || {
            let mut scratch = World::new();
            let (copy, input) = spawn_connectivity(&mut scratch, &tables, MeshInfo::default());
            let global = op.run(&mut scratch, copy, |f| {
                shared.set(f);
                !shared.is_cancelled()
            })?;
            if shared.is_cancelled() {
                return Err("cancelled".into());
            }
            Ok(JobOutput {
                result: extract(&scratch, copy),
                input,
                global,
            })
        })
        .map_err(|e| format!("could not start a thread: {e}"))?;
    world.resource_mut::<Jobs>().running = Some(RunningJob {
        mesh,
        label,
        progress,
        started: std::time::Instant::now(),
        op,
        pending,
        rows: members,
        thread: Some(thread),
    });
    Ok("running (Esc cancels)".into())
}

/// Cancels the running job; the mesh stays as it was.
///
/// # Errors
/// When no job is running.
pub fn cancel(world: &mut World) -> Result<String, String> {
    let Some(job) = world.resource_mut::<Jobs>().running.take() else {
        return Err("no operation is running".into());
    };
    job.progress.cancel();
    // The thread stops at its next progress report; its result is dropped unread.
    Ok(format!("cancelled {}, the mesh is unchanged", job.label))
}

/// Commits a finished job: the mesh takes the result in one step, as one undo entry, and the
/// outcome is reported (the `Apply` set, before the requests of the frame).
pub fn finish_jobs(world: &mut World) {
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
        Ok(Err(reason)) => Err(reason),
        Err(_) => {
            Err("the operation failed (a bug: please report it); the mesh is unchanged".into())
        }
    };
    match &result {
        Ok(summary) => bevy::log::info!("{}: {summary} ({ms:.0} ms, job)", job.label),
        Err(reason) => bevy::log::info!("{}: refused: {reason}", job.label),
    }
    let outcome = EditOutcome {
        request: job.label,
        result,
    };
    world.write_message(outcome.clone());
    world.resource_mut::<OutcomeLog>().push(outcome);
}

fn commit(world: &mut World, job: &mut RunningJob, output: JobOutput) -> Result<String, String> {
    let mesh = job.mesh;
    if world.get::<MeshInfo>(mesh.0).is_none() {
        return Err(format!("{mesh} is gone; the result was dropped"));
    }
    let old = MeshMembers::collect(world, mesh);
    let rows = replace_contents(world, mesh, &old, &output.result.tables);
    // Scratch entities of the result → the entities that hold those rows now.
    let to_main = row_map(&output.result.members, &rows);
    if let Some(pending) = job.pending.take() {
        super::history::commit(world, pending, job.label.clone());
    }
    let GlobalResult {
        summary,
        progressive,
    } = output.global;
    world.resource_mut::<super::apply::History>().pm = progressive.map(|mut pm| {
        pm.remap(mesh, &to_main);
        pm
    });
    world
        .entity_mut(mesh.0)
        .insert((MeshDirty, super::apply::Modified));
    // The selection, followed from its row in the copy to that element's row in the result.
    let to_scratch = row_map(&job.rows, &output.input);
    let selection = world.resource::<Selection>().element.and_then(|x| {
        if !(job.op.keeps_element_ids() || matches!(x, ElementId::Vertex(_))) {
            return None;
        }
        let now = to_main.get(to_scratch.get(&x.entity())?)?;
        let x = x.with_entity(*now);
        super::selection::exists(&MeshRef::new(world), x).then_some(x)
    });
    world.resource_mut::<Selection>().element = selection;
    Ok(summary)
}
