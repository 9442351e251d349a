//! What each edit runs and how it says what it did: [`Edit::apply`] dispatches to one small
//! function an operation, each calling its algorithm in `ops/` and turning the result into an
//! [`Applied`] — the summary that prints, what to redraw (the faces around what changed, only
//! the positions, or the whole mesh) and what to select.
//!
//! The checks every edit shares (the mesh exists, the memory budget, attributes settled,
//! normals marked stale, validation in test builds) are [`Edit::run`]'s, around this.

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::{InMesh, MeshInfo, MeshRef};
use crate::ops::Refusal;
use crate::ops::deform::{DeformSummary, FairParams, deform, fair};
use crate::ops::hole::fill_hole_fair;
use crate::ops::local::{
    CollapseOptions, bisect_edge, collapse_edge, dissolve_edge, fill_hole, flip_edge, split_edge,
    split_face,
};
use crate::ops::smooth::{SmoothParams, smooth_with_progress};

use super::{Applied, Edit, EditContext, Redraw, count, toggle_seam};

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
            Edit::Flip(e) => flip(world, *e),
            Edit::Split(e) => split(world, *e),
            Edit::Bisect(e) => bisect(world, *e),
            Edit::Collapse(e) => collapse(world, *e),
            Edit::Dissolve(e) => dissolve(world, *e),
            Edit::ToggleSeam(e) => seam(world, *e),
            Edit::FillHole(e) => fill_one_hole(world, *e),
            Edit::SplitFace(f, a, b) => cut_face(world, *f, *a, *b),
            Edit::Extrude(..)
            | Edit::Inset(..)
            | Edit::BevelVertex(..)
            | Edit::BevelEdge(..)
            | Edit::Erase(_)
            | Edit::DissolveVertex(_)
            | Edit::CollapseFace(_)
            | Edit::Weld(..) => self.apply_planned(world),
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
            Edit::FillHoleFair(e) => fill_one_hole_fair(world, *e),
        }
    }

    /// A planned local edit (extrude, inset, bevel, erase, dissolve a vertex, collapse a face,
    /// weld): planned, then applied; what is new lies around the seeds that survive and what
    /// the edit made.
    fn apply_planned(&self, world: &mut World) -> Result<Applied, Refusal> {
        let plan = self.plan(world).ok_or(Refusal::BadParameter(format!(
            "{} has no plan",
            self.label()
        )))??;
        let seeds = plan.seeds();
        let before = faces_around(world, &seeds);
        let (summary, made) = plan.apply(world);
        let mut after = seeds;
        if let Some(x) = made {
            after.extend(element_corners(world, x));
        }
        Ok(Applied {
            summary,
            redraw: near(world, before, after),
            made,
        })
    }
}

/// The faces around `vertices` as they are now, and `faces` from before the edit.
fn near(world: &World, faces: Vec<FaceId>, vertices: Vec<VertexId>) -> Redraw {
    Redraw::Near {
        faces: [faces_around(world, &vertices), faces].concat(),
        vertices,
    }
}

fn flip(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &edge_ends(world, e));
    let flipped = flip_edge(world, e)?;
    Ok(Applied {
        summary: format!("flipped to {flipped}"),
        redraw: near(world, before, edge_ends(world, flipped)),
        made: Some(ElementId::Edge(flipped)),
    })
}

fn split(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &edge_ends(world, e));
    let v = split_edge(world, e, 0.5)?;
    Ok(Applied {
        summary: format!("new vertex {v}"),
        redraw: near(world, before, vec![v]),
        made: Some(ElementId::Vertex(v)),
    })
}

fn bisect(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &edge_ends(world, e));
    let v = bisect_edge(world, e, 0.5)?;
    Ok(Applied {
        summary: format!("new vertex {v} on {e}"),
        redraw: near(world, before, vec![v]),
        made: Some(ElementId::Vertex(v)),
    })
}

fn collapse(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &edge_ends(world, e));
    let r = collapse_edge(world, e, CollapseOptions::default())?;
    Ok(Applied {
        summary: format!("kept {}, removed {}", r.kept, r.removed),
        redraw: near(world, before, vec![r.kept]),
        made: Some(ElementId::Vertex(r.kept)),
    })
}

fn dissolve(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let ends = edge_ends(world, e);
    let before = faces_around(world, &ends);
    let f = dissolve_edge(world, e)?;
    Ok(Applied {
        summary: format!("merged into {f}"),
        redraw: near(world, before, ends),
        made: Some(ElementId::Face(f)),
    })
}

fn seam(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let marked = toggle_seam(world, e)?;
    Ok(Applied {
        summary: if marked {
            format!("{e} is a seam")
        } else {
            format!("{e} is no longer a seam")
        },
        redraw: near(world, Vec::new(), edge_ends(world, e)),
        made: None,
    })
}

fn fill_one_hole(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let f = fill_hole(world, e)?;
    let ring: Vec<VertexId> = MeshRef::new(world).face_vertices(f).collect();
    Ok(Applied {
        summary: format!("new face {f} of {} sides", ring.len()),
        redraw: near(world, Vec::new(), ring),
        made: Some(ElementId::Face(f)),
    })
}

fn cut_face(world: &mut World, f: FaceId, a: VertexId, b: VertexId) -> Result<Applied, Refusal> {
    let before = faces_around(world, &[a, b]);
    let e = split_face(world, f, a, b)?;
    Ok(Applied {
        summary: format!("new edge {e}"),
        redraw: near(world, before, vec![a, b]),
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
        redraw: near(world, Vec::new(), params.vertices.clone()),
        made: None,
    })
}

fn fill_one_hole_fair(world: &mut World, e: EdgeId) -> Result<Applied, Refusal> {
    let r = fill_hole_fair(world, e)?;
    Ok(Applied {
        summary: format!(
            "a hole of {} sides filled with {}, {} new",
            r.sides,
            count(r.triangles, "triangle"),
            count(r.new_vertices, "vertex")
        ),
        redraw: Redraw::Whole,
        made: Some(ElementId::Face(r.face)),
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

/// The corners of a live element (none if it is gone).
fn element_corners(world: &World, x: ElementId) -> Vec<VertexId> {
    let m = MeshRef::new(world);
    match x {
        ElementId::Vertex(v) if m.try_vertex(v).is_some() => vec![v],
        ElementId::Edge(e) => edge_ends(world, e),
        ElementId::Face(f) if m.try_face(f).is_some() => m.face_vertices(f).collect(),
        _ => Vec::new(),
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

/// The two ends of an edge (none if it is gone).
fn edge_ends(world: &World, e: EdgeId) -> Vec<VertexId> {
    let m = MeshRef::new(world);
    if m.try_edge(e).is_none() {
        return Vec::new();
    }
    let (a, b) = m.edge_vertices(e);
    vec![a, b]
}

/// The faces around some vertices (dead vertices skipped): [`MeshRef::faces_around`].
fn faces_around(world: &World, vertices: &[VertexId]) -> Vec<FaceId> {
    MeshRef::new(world).faces_around(vertices)
}
