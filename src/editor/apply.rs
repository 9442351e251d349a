//! The one system that changes meshes: it applies [`EditRequest`]s in order and reports each.
//!
//! It is exclusive (`&mut World`): every request sees the result of the one before, and the
//! operations it calls are the same plain functions the command line and the tests use.

use bevy::ecs::message::{MessageCursor, Messages};
use bevy::prelude::{Local, World};
use std::path::Path;

use crate::io;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::{InMesh, MeshInfo, Position, build_mesh, despawn_mesh, to_soup};
use crate::ops::local::{
    CollapseOptions, collapse_edge, dissolve_edge, flip_edge, split_edge, split_face,
};
use crate::ops::progressive::ProgressiveMesh;

use super::history::Redraw;
use super::jobs::GlobalOp;
use super::render_sync::DirtyFaces;
use super::requests::{ConfirmDiscard, EditOutcome, EditRequest, OutcomeLog, PendingDiscard};
use super::selection::{ActiveMesh, MeshDirty, Selection, navigate};
use crate::mesh::topology::MeshRef;

/// Applies every request written since the last run, in order (the `Apply` set).
pub fn apply_requests(world: &mut World, mut cursor: Local<MessageCursor<EditRequest>>) {
    let requests: Vec<EditRequest> = cursor
        .read(world.resource::<Messages<EditRequest>>())
        .cloned()
        .collect();
    for request in requests {
        let start = std::time::Instant::now();
        let result = apply(world, &request);
        let ms = start.elapsed().as_secs_f64() * 1000.0;
        let outcome = EditOutcome {
            request: request.label(),
            result,
        };
        match &outcome.result {
            Ok(summary) => bevy::log::info!("{}: {summary} ({ms:.2} ms)", outcome.request),
            Err(reason) => bevy::log::info!("{}: refused: {reason}", outcome.request),
        }
        world.write_message(outcome.clone());
        world.resource_mut::<OutcomeLog>().push(outcome);
    }
}

/// Marks a mesh changed since it was opened or saved.
#[derive(bevy::prelude::Component, Debug, Default, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct Modified;

/// Asks before closing the window over unsaved changes (the window's close button only
/// requests; this decides).
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
    let modified = world
        .resource::<ActiveMesh>()
        .0
        .is_some_and(|m| world.get::<Modified>(m.0).is_some());
    if modified {
        world.resource_mut::<ConfirmDiscard>().0 = Some(PendingDiscard::Quit);
    } else {
        world.write_message(bevy::app::AppExit::Success);
    }
}

/// The last simplification's history: the level-of-detail slider and vertex splits move along
/// it. Any other edit of the mesh ends it (the history would no longer describe the mesh).
#[derive(bevy::prelude::Resource, Default)]
pub struct History {
    /// The progressive mesh, while it still matches the mesh.
    pub pm: Option<ProgressiveMesh>,
}

/// Applies one request. `Ok` carries a summary, `Err` the reason it was refused (the world is
/// then unchanged).
pub fn apply(world: &mut World, request: &EditRequest) -> Result<String, String> {
    let keeps_history = matches!(
        request,
        EditRequest::Select(_)
            | EditRequest::Navigate(_)
            | EditRequest::Save(_)
            | EditRequest::LevelOfDetail(_)
            | EditRequest::SplitVertex(_)
            | EditRequest::Simplify(..)
            | EditRequest::CancelJob
            | EditRequest::ConfirmDiscard(false)
    );
    if request.edits()
        && let Some(job) = &world.resource::<super::jobs::Jobs>().running
    {
        return Err(format!(
            "{} is still running: wait for it, or cancel it (Esc)",
            job.label
        ));
    }
    let pending = super::history::begin(world, request);
    if let Some((mesh, op)) = super::jobs::wants_job(world, request) {
        return super::jobs::start(world, mesh, op, request.label(), pending);
    }
    let result = apply_request(world, request);
    if result.is_ok()
        && let Some(pending) = pending
    {
        super::history::commit(world, pending, request.label());
    }
    if result.is_ok() && !keeps_history {
        world.resource_mut::<History>().pm = None;
    }
    // The mesh now differs from its file (or is new since it was saved).
    if result.is_ok()
        && request.edits()
        && !matches!(
            request,
            EditRequest::Open(_) | EditRequest::DeleteMesh | EditRequest::ConfirmDiscard(_)
        )
        && let Some(mesh) = world.resource::<ActiveMesh>().0
        && world.get_entity(mesh.0).is_ok()
    {
        world.entity_mut(mesh.0).insert(Modified);
    }
    result
}

fn apply_request(world: &mut World, request: &EditRequest) -> Result<String, String> {
    match request {
        EditRequest::Undo | EditRequest::Redo => {
            let redo = matches!(request, EditRequest::Redo);
            let stepped = super::history::step(world, redo)?;
            let selection = world.resource::<Selection>().element;
            match stepped.redraw {
                Redraw::Near {
                    mesh,
                    vertices,
                    removed,
                } => edited_locally(world, mesh, removed, &vertices, selection),
                Redraw::Whole(Some(mesh)) => edited(world, mesh, selection),
                Redraw::Whole(None) => {}
            }
            Ok(format!(
                "{} {}",
                if redo { "redid" } else { "undid" },
                stepped.label
            ))
        }
        EditRequest::LevelOfDetail(faces) => {
            let Some(mut pm) = world.resource_mut::<History>().pm.take() else {
                return Err("no simplification to move along: simplify first (Shift+S)".into());
            };
            // Only the faces around the vertices each step touches are redrawn, unless the
            // move rewrote the whole mesh (a long refine).
            let mut near: Vec<FaceId> = Vec::new();
            let result = pm.go_to_faces_watching(world, *faces, |w, v| {
                near.extend(faces_near(w, &[v]));
            });
            let (mesh, now) = (pm.mesh, pm.faces());
            world.resource_mut::<History>().pm = Some(pm);
            let selection = world
                .resource::<Selection>()
                .element
                .filter(|&x| super::selection::exists(&MeshRef::new(world), x));
            // A bulk refine that stopped on a refusal has still rewritten the mesh.
            let rewritten = result.as_ref().map_or(true, |moved| moved.rewritten);
            if rewritten {
                edited(world, mesh, selection);
            } else {
                edited_locally(world, mesh, near, &[], selection);
            }
            let moved = result.map_err(|r| r.to_string())?;
            Ok(format!("{} step(s), {now} faces", moved.steps))
        }
        EditRequest::SplitVertex(v) => {
            let Some(mut pm) = world.resource_mut::<History>().pm.take() else {
                return Err("this vertex has no history: simplify first (Shift+S)".into());
            };
            let result = pm.refine_vertex(world, *v);
            let mesh = pm.mesh;
            world.resource_mut::<History>().pm = Some(pm);
            let b = result.map_err(|r| r.to_string())?;
            edited(world, mesh, Some(ElementId::Vertex(*v)));
            Ok(format!("split back {b}"))
        }
        EditRequest::Flip(e) => {
            let mesh = mesh_of(world, e.0)?;
            let near = edge_ends(world, *e);
            let before = faces_near(world, &near);
            let flipped = flip_edge(world, *e).map_err(|r| r.to_string())?;
            let after = edge_ends(world, flipped);
            edited_locally(world, mesh, before, &after, Some(ElementId::Edge(flipped)));
            Ok(format!("flipped to {flipped}"))
        }
        EditRequest::Split(e) => {
            let mesh = mesh_of(world, e.0)?;
            let before = faces_near(world, &edge_ends(world, *e));
            let v = split_edge(world, *e, 0.5).map_err(|r| r.to_string())?;
            edited_locally(world, mesh, before, &[v], Some(ElementId::Vertex(v)));
            Ok(format!("new vertex {v}"))
        }
        EditRequest::Collapse(e) => {
            let mesh = mesh_of(world, e.0)?;
            let before = faces_near(world, &edge_ends(world, *e));
            let result =
                collapse_edge(world, *e, CollapseOptions::default()).map_err(|r| r.to_string())?;
            let kept = result.kept;
            edited_locally(world, mesh, before, &[kept], Some(ElementId::Vertex(kept)));
            Ok(format!("kept {}, removed {}", result.kept, result.removed))
        }
        EditRequest::Dissolve(e) => {
            let mesh = mesh_of(world, e.0)?;
            let ends = edge_ends(world, *e);
            let before = faces_near(world, &ends);
            let f = dissolve_edge(world, *e).map_err(|r| r.to_string())?;
            edited_locally(world, mesh, before, &ends, Some(ElementId::Face(f)));
            Ok(format!("merged into {f}"))
        }
        EditRequest::SplitFace(f, a, b) => {
            let mesh = mesh_of(world, f.0)?;
            let before = faces_near(world, &[*a, *b]);
            let e = split_face(world, *f, *a, *b).map_err(|r| r.to_string())?;
            edited_locally(world, mesh, before, &[*a, *b], Some(ElementId::Edge(e)));
            Ok(format!("new edge {e}"))
        }
        EditRequest::Triangulate(_)
        | EditRequest::Simplify(..)
        | EditRequest::LoopSubdivide(_)
        | EditRequest::CatmullClark(_)
        | EditRequest::Remesh(_) => {
            let Some((mesh, op)) = GlobalOp::of(request) else {
                unreachable!("every whole-mesh request has an operation")
            };
            let done = op.run(world, mesh, |_| true)?;
            if let Some(pm) = done.progressive {
                world.resource_mut::<History>().pm = Some(pm);
            }
            // Subdivision renumbers everything but the vertices.
            let selection = world.resource::<Selection>().element.filter(|&x| {
                (op.keeps_element_ids() || matches!(x, ElementId::Vertex(_)))
                    && super::selection::exists(&MeshRef::new(world), x)
            });
            edited(world, mesh, selection);
            Ok(done.summary)
        }
        EditRequest::CancelJob => super::jobs::cancel(world),
        EditRequest::MoveVertex(v, p) => {
            if !p.is_finite() {
                return Err(format!("{p} is not a finite position"));
            }
            let mesh = mesh_of(world, v.0)?;
            let Some(mut position) = world.get_mut::<Position>(v.0) else {
                return Err(format!("{v} is not a vertex"));
            };
            position.0 = *p;
            // Smooth normals of the neighbours change too: their faces are redrawn as well.
            let m = MeshRef::new(world);
            let mut ring: Vec<VertexId> = m.vertex_neighbors(*v).collect();
            ring.push(*v);
            let selection = world.resource::<Selection>().element;
            edited_locally(world, mesh, Vec::new(), &ring, selection);
            Ok(format!("{v} at {p}"))
        }
        EditRequest::Select(element) => {
            if let Some(x) = element
                && !super::selection::exists(&MeshRef::new(world), *x)
            {
                return Err(format!("{x} does not exist"));
            }
            world.resource_mut::<Selection>().element = *element;
            Ok(element.map_or("nothing selected".into(), |x| format!("{x} selected")))
        }
        EditRequest::Navigate(relation) => {
            let Some(from) = world.resource::<Selection>().element else {
                return Err("nothing is selected".into());
            };
            let to = navigate(&MeshRef::new(world), from, *relation).ok_or_else(|| {
                format!(
                    "{from} has no {} (a boundary halfedge has no face)",
                    relation.name()
                )
            })?;
            world.resource_mut::<Selection>().element = Some(to);
            Ok(format!("{to}"))
        }
        EditRequest::Open(path) => {
            if let Some(mesh) = world.resource::<ActiveMesh>().0
                && world.get::<Modified>(mesh.0).is_some()
            {
                world.resource_mut::<ConfirmDiscard>().0 = Some(PendingDiscard::Open(path.clone()));
                return Err(
                    "the mesh has unsaved changes: save it (Ctrl+S) or discard them first".into(),
                );
            }
            open(world, path)
        }
        EditRequest::ConfirmDiscard(discard) => {
            let Some(pending) = world.resource_mut::<ConfirmDiscard>().0.take() else {
                return Err("nothing is waiting for an answer".into());
            };
            if !discard {
                return Ok("changes kept".into());
            }
            match pending {
                PendingDiscard::Open(path) => open(world, &path),
                PendingDiscard::Quit => {
                    world.write_message(bevy::app::AppExit::Success);
                    Ok("changes discarded, quitting".into())
                }
            }
        }
        EditRequest::Save(path) => save(world, path.as_deref()),
        EditRequest::DeleteMesh => {
            let Some(mesh) = world.resource::<ActiveMesh>().0 else {
                return Err("there is no mesh to delete".into());
            };
            let count = despawn_mesh(world, mesh);
            world.resource_mut::<ActiveMesh>().0 = None;
            world.resource_mut::<Selection>().element = None;
            Ok(format!("{mesh} deleted ({count} entities)"))
        }
    }
}

fn mesh_of(world: &World, e: bevy::prelude::Entity) -> Result<MeshId, String> {
    world
        .get::<InMesh>(e)
        .map(|m| m.0)
        .ok_or_else(|| format!("{e} does not exist (stale id)"))
}

/// The two ends of an edge (none if it is gone).
fn edge_ends(world: &World, e: EdgeId) -> Vec<VertexId> {
    let m = MeshRef::new(world);
    if m.try_edge(e).is_none() {
        return Vec::new();
    }
    let (a, b) = m.edge_vertices(e);
    vec![a, b]
}

/// The faces around some vertices (dead vertices skipped).
fn faces_near(world: &World, vertices: &[VertexId]) -> Vec<FaceId> {
    let m = MeshRef::new(world);
    let mut faces = Vec::new();
    for &v in vertices {
        if m.try_vertex(v).is_some() {
            faces.extend(m.vertex_faces(v));
        }
    }
    faces
}

/// After a local edit: the faces it touched (those around the edit before, which may now be
/// gone, and around `after`) are redrawn, and the selection moves to what the edit made.
fn edited_locally(
    world: &mut World,
    mesh: MeshId,
    mut faces: Vec<FaceId>,
    after: &[VertexId],
    select: Option<ElementId>,
) {
    faces.extend(faces_near(world, after));
    let mut entity = world.entity_mut(mesh.0);
    match entity.get_mut::<DirtyFaces>() {
        Some(mut dirty) => dirty.0.extend(faces),
        None => {
            entity.insert(DirtyFaces(faces));
        }
    }
    world.resource_mut::<Selection>().element = select;
}

/// After an edit: the mesh is re-rendered and the selection moves to what the edit made.
fn edited(world: &mut World, mesh: MeshId, select: Option<ElementId>) {
    world.entity_mut(mesh.0).insert(MeshDirty);
    world.resource_mut::<Selection>().element = select;
}

/// Opens a mesh, replacing the active one only once the new one has been read and built.
fn open(world: &mut World, path: &Path) -> Result<String, String> {
    let (soup, info) = crate::source::read_source(path)?;
    let built = build_mesh(world, &soup, info).map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(old) = world.resource::<ActiveMesh>().0 {
        despawn_mesh(world, old);
    }
    world.resource_mut::<ActiveMesh>().0 = Some(built.mesh);
    world.resource_mut::<Selection>().element = None;
    world.entity_mut(built.mesh.0).insert(MeshDirty);
    let stats = crate::mesh::mesh_stats(world, built.mesh);
    Ok(format!(
        "{}: {} vertices, {} faces; {}",
        path.display(),
        stats.vertices,
        stats.faces,
        built.report
    ))
}

fn save(world: &mut World, path: Option<&Path>) -> Result<String, String> {
    let Some(mesh) = world.resource::<ActiveMesh>().0 else {
        return Err("there is no mesh to save".into());
    };
    let target = match path {
        Some(p) => p.to_path_buf(),
        None => world
            .get::<MeshInfo>(mesh.0)
            .and_then(|i| i.path.clone())
            .ok_or("this mesh has no file yet: use Save as")?,
    };
    let soup = to_soup(world, mesh);
    io::write(&target, &soup).map_err(|e| e.to_string())?;
    if let Some(mut info) = world.get_mut::<MeshInfo>(mesh.0) {
        info.path = Some(target.clone());
    }
    world.entity_mut(mesh.0).remove::<Modified>();
    Ok(format!("saved {}", target.display()))
}

/// The edge under a selection, for operations on edges: the edge itself, or a halfedge's edge.
pub fn selected_edge(world: &World) -> Option<EdgeId> {
    let m = MeshRef::new(world);
    match world.resource::<Selection>().element? {
        ElementId::Edge(e) => m.try_edge(e).map(|_| e),
        ElementId::Halfedge(h) => m.try_halfedge(h).map(|x| x.edge),
        _ => None,
    }
}
