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
use crate::ops::deform::{DeformSummary, deform, loose_note};

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
            // A lab's operation is checked against the one it reproduces first.
            Edit::Operation(op) if op.declaration().reference.is_some() => {
                super::lab::apply_checked(op, world, mesh, context)
            }
            Edit::Operation(op) => op.apply(world, mesh, context),
            Edit::Move(moves) => Ok(Applied {
                summary: match moves.as_slice() {
                    [(v, p)] => format!("{v} at {p}"),
                    _ => format!("{} vertices moved", moves.len()),
                },
                redraw: move_vertices(world, moves)?,
                made: None,
            }),
            Edit::Deform(params) => Ok(Applied::whole(deformed(&deform(world, mesh, params)?))),
        }
    }
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
