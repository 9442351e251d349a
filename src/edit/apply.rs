//! What each edit runs and how it says what it did: [`Edit::apply`] dispatches to one small
//! function an operation, each calling its algorithm in `ops/` and turning the result into an
//! [`Applied`] — the summary that prints, what to redraw (the faces around what changed, only
//! the positions, or the whole mesh) and what to select.
//!
//! The checks every edit shares (the mesh exists, the memory budget, attributes settled,
//! normals marked stale, validation in test builds) are [`Edit::run`]'s, around this.

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::mesh::{InMesh, MeshInfo, MeshRef};
use crate::ops::Refusal;
use crate::ops::deform::{DeformSummary, FairParams, deform, fair};
use crate::ops::local::split_face;
use crate::ops::smooth::{SmoothParams, smooth_with_progress};

use super::{Applied, Edit, EditContext, Redraw, count};

impl Edit {
    /// Applies the edit to `mesh` (which must exist), or says why not and changes nothing.
    pub(super) fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        if world.get::<MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        match self {
            Edit::SplitFace(f, a, b) => cut_face(world, *f, *a, *b),
            Edit::MoveVertex(v, p) => Ok(Applied {
                summary: format!("{v} at {p}"),
                redraw: move_vertices(world, &[(*v, *p)])?,
                made: None,
            }),
            Edit::MoveVertices(moves) => Ok(Applied {
                summary: format!("{} vertices moved", moves.len()),
                redraw: move_vertices(world, moves)?,
                made: None,
            }),
            Edit::SplitVertex(v) => split_vertex(world, *v, context),
            Edit::Operation(op) => op.apply(world, mesh, context),
            Edit::Smooth(params) => smooth(world, mesh, params, context),
            Edit::Deform(params) => Ok(Applied::whole(deformed(&deform(world, mesh, params)?))),
            Edit::Fair(params) => fair_region(world, mesh, params),
        }
    }
}

fn cut_face(world: &mut World, f: FaceId, a: VertexId, b: VertexId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &[a, b]);
    let e = split_face(world, f, a, b)?;
    Ok(Applied {
        summary: format!("new edge {e}"),
        redraw: Redraw::near(world, before, vec![a, b]),
        made: Some(ElementId::Edge(e)),
    })
}

/// Splits back the vertex a simplification collapsed last into `v`.
fn split_vertex(
    world: &mut World,
    v: VertexId,
    context: &mut EditContext<'_>,
) -> Result<Applied, Refusal> {
    let pm = context.history.as_mut().ok_or(Refusal::NoHistory)?;
    let b = pm.refine_vertex(world, v)?;
    Ok(Applied {
        summary: format!("split back {b}"),
        redraw: Redraw::Whole,
        made: Some(ElementId::Vertex(v)),
    })
}

fn smooth(
    world: &mut World,
    mesh: MeshId,
    params: &SmoothParams,
    context: &mut EditContext<'_>,
) -> Result<Applied, Refusal> {
    let s = smooth_with_progress(world, mesh, params, &mut *context.progress)?;
    let stopped = if s.iterations < params.iterations {
        format!(
            " (stopped after {} of {} iterations)",
            s.iterations, params.iterations
        )
    } else {
        String::new()
    };
    Ok(Applied::whole(format!(
        "{} free vertices moved {:.3e} on average{stopped}",
        s.free, s.mean_move
    )))
}

fn fair_region(world: &mut World, mesh: MeshId, params: &FairParams) -> Result<Applied, Refusal> {
    let s = fair(world, mesh, params)?;
    let loose = loose_note(s.loose_parts);
    Ok(Applied {
        summary: format!(
            "{} faired (k = {}), moved {:.3e} on average{loose}",
            count(s.free, "vertex"),
            params.k,
            s.mean_move
        ),
        redraw: Redraw::near(world, Vec::new(), params.vertices.clone()),
        made: None,
    })
}

/// The summary of a deformation.
fn deformed(s: &DeformSummary) -> String {
    let loose = loose_note(s.loose_parts);
    let ms = |seconds: f64| seconds * 1e3;
    if s.iterations == 0 {
        return format!(
            "thin plate: {} moved; factored in {:.1} ms, solved in {:.1} ms{loose}",
            count(s.free, "free vertex"),
            ms(s.factor_seconds),
            ms(s.iteration_seconds)
        );
    }
    format!(
        "ARAP: {} moved, {} iterations, energy {:.4e} -> {:.4e}; factored in {:.1} ms, \
         {:.2} ms an iteration{loose}",
        count(s.free, "free vertex"),
        s.iterations,
        s.energy_before,
        s.energy,
        ms(s.factor_seconds),
        ms(s.iteration_seconds)
    )
}

/// The note on parts of the mesh a solve left alone (none held there).
fn loose_note(parts: usize) -> String {
    match parts {
        0 => String::new(),
        n => format!(" ({} with nothing held stayed)", count(n, "part")),
    }
}

/// Moves vertices; returns what to redraw: the faces around them and their neighbours (whose
/// smooth normals change too), or every position when the moves reach a quarter of its
/// vertices (an ARAP frame moves most of them, and walking every one-ring then costs more than
/// the refresh it leads to).
///
/// # Refusals
/// [`Refusal::NotFinite`] for a position that is not finite, [`Refusal::Stale`] for a vertex
/// that is gone; both before anything moves.
fn move_vertices(world: &mut World, moves: &[(VertexId, Vec3)]) -> Result<Redraw, Refusal> {
    let m = MeshRef::new(world);
    for &(v, p) in moves {
        if !p.is_finite() {
            return Err(Refusal::NotFinite(p));
        }
        m.try_vertex(v)
            .ok_or(Refusal::Stale(ElementId::Vertex(v)))?;
    }
    let many = moves.len() >= WHOLE_REDRAW_MOVES
        && moves
            .first()
            .and_then(|(v, _)| world.get::<InMesh>(v.0))
            .is_some_and(|mesh| {
                let vertices = crate::mesh::members::of_kind::<crate::mesh::Vertex, _>(
                    world, mesh.0, VertexId,
                );
                4 * moves.len() > vertices.len()
            });
    let redraw = if many {
        Redraw::Positions
    } else {
        let mut ring: Vec<VertexId> = moves
            .iter()
            .flat_map(|&(v, _)| m.vertex_neighbors(v).chain([v]))
            .collect();
        ring.sort_unstable();
        ring.dedup();
        Redraw::Near {
            faces: faces_around(world, &ring),
            vertices: ring,
        }
    };
    for &(v, p) in moves {
        if let Some(mut position) = world.get_mut::<crate::mesh::Position>(v.0) {
            position.0 = p;
        }
    }
    Ok(redraw)
}

/// Moves of fewer vertices than this are always redrawn by their neighbourhoods (counting the
/// mesh's vertices is not free either).
pub(super) const WHOLE_REDRAW_MOVES: usize = 1024;

/// The faces around some vertices (dead vertices skipped): [`MeshRef::faces_around`].
fn faces_around(world: &World, vertices: &[VertexId]) -> Vec<FaceId> {
    MeshRef::new(world).faces_around(vertices)
}
