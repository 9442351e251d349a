//! Local operations: edge flip, edge split, edge collapse, and their companions (edge
//! bisection, edge dissolve, face split, hole fill, vertex split — the exact inverse of a
//! collapse), and the modelling operations of Blender's edit mode and Scotty3D: extrude a
//! region of faces, inset faces, bevel a vertex or an edge, erase faces (make them holes),
//! dissolve a vertex, collapse a face, weld two boundary edges.
//!
//! The contract, stated once: **if the result of an operation would not be a valid mesh, the
//! operation changes nothing and returns a [`Refusal`] that says why.** Each operation is a
//! read-only `plan_*` (`&World`) that checks the ids (a stale id is [`Refusal::Stale`]), checks
//! every refusal and collects every id it will touch, and an `apply_*` (`&mut World`) that
//! carries out a fresh plan and cannot fail (in debug builds it plans again and asserts that
//! the plan is unchanged). [`flip_edge`], [`split_edge`] and [`collapse_edge`] do both.
//!
//! All of them work on triangles and on polygons, and on boundary edges where the operation
//! makes sense. Entities are reused wherever an element survives (a flip spawns and despawns
//! nothing; a split only spawns; a collapse only despawns), so ids the user is looking at stay
//! valid when they can. After every apply the mesh passes [`crate::mesh::validate()`]: in
//! particular a boundary vertex's halfedge is its boundary one, every face and edge names a
//! halfedge of its own, and an edge names an interior halfedge where it has one.
//!
//! Each operation's module doc has a before/after picture and its refusals, in the order they
//! are checked. Each file also holds its operation as the editor, the command line and Python
//! use it: its `Declaration` (`FLIP`: name, title, key, what it names, its panel section) and a
//! unit struct implementing [`crate::ops::operation::MeshOperation`] (`Flip`), whose `apply`
//! reads the elements it names and reports through [`crate::ops::operation::Applied::on_edge`]
//! or [`crate::ops::operation::Applied::carried_out`] (the same two an operation written
//! outside the crate can use). The vertex split's adapter moves along the simplification
//! history and lives with it, in [`crate::ops::decimate`].

mod bevel;
mod bisect;
mod collapse;
mod collapse_face;
mod dissolve;
mod dissolve_vertex;
mod erase;
mod extrude;
mod fill_hole;
mod flip;
mod inset;
mod seam;
mod split;
mod split_face;
#[cfg(test)]
pub(crate) mod testkit;
mod vertex_split;
mod weld;

pub use bevel::{
    BEVEL, Bevel, BevelEdgePlan, BevelVertexPlan, apply_bevel_edge, apply_bevel_vertex, bevel_edge,
    bevel_vertex, plan_bevel_edge, plan_bevel_vertex,
};
pub use bisect::{BISECT, Bisect, BisectPlan, apply_bisect, bisect_edge, plan_bisect};
pub use collapse::{
    COLLAPSE, Collapse, CollapseOptions, CollapsePlan, CollapseRecord, CollapseResult,
    apply_collapse, collapse_edge, plan_collapse, plan_collapse_halfedge,
};
pub(crate) use collapse::{SpokeView, Wing, wing_check};
pub(crate) use collapse::{apply_collapse_deferred, plan_collapse_in};
pub use collapse_face::{
    COLLAPSE_FACE, CollapseFace, CollapseFacePlan, apply_collapse_face, collapse_face,
    plan_collapse_face,
};
pub use dissolve::{
    DISSOLVE, Dissolve, DissolvePlan, apply_dissolve, dissolve_edge, plan_dissolve,
};
pub use dissolve_vertex::{
    DISSOLVE_VERTEX, DissolveVertex, DissolveVertexPlan, apply_dissolve_vertex, dissolve_vertex,
    plan_dissolve_vertex,
};
pub use erase::{
    ERASE, Erase, ErasePlan, Erased, apply_erase, erase_faces, faces_of, faces_of_edge,
    faces_of_vertex, plan_erase,
};
pub use extrude::{
    EXTRUDE, Extrude, ExtrudePlan, Extruded, apply_extrude, extrude_directions, extrude_faces,
    plan_extrude,
};
pub use fill_hole::{FillHolePlan, apply_fill_hole, fill_hole, plan_fill_hole};
pub use flip::{FLIP, Flip, FlipPlan, apply_flip, flip_edge, plan_flip};
pub use inset::{INSET, Inset, InsetPlan, apply_inset, inset_faces, plan_inset};
pub use seam::{SEAM, ToggleSeam, toggle_seam};
pub use split::{
    SPLIT, Split, SplitPlan, apply_split, plan_split, split_edge, split_edge_midpoint,
};
pub use split_face::{
    SPLIT_FACE, SplitFace, SplitFacePlan, apply_split_face, plan_split_face, split_face,
};
pub use vertex_split::vertex_split;

pub use weld::{WELD, Weld, WeldPlan, apply_weld, plan_weld, weld_edges};

use bevy::prelude::{Entity, World};

/// The memory check of an edit that adds rows in proportion to its selection (extrusion,
/// inset): at most, each corner of the selection gains a vertex, a quad beside it, two edges
/// and eight halfedges (12 rows), which bounds both.
///
/// # Refusals
/// [`Refusal::OverBudget`] past the memory budget.
pub(crate) fn check_growth(what: &str, faces: usize, corners: usize) -> Result<(), Refusal> {
    crate::memory_budget::check(&crate::memory_budget::Estimate {
        what: format!("{what} {faces} face(s)"),
        faces: corners as u64,
        rows: corners as u64 * 12,
        instead: "select fewer faces",
    })
    .map_err(Refusal::from)
}

use crate::mesh::elements::{Edge, Face, Halfedge, InMesh};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId};
use crate::mesh::topology::MeshRef;

use super::Refusal;

/// The edge's first halfedge, or a refusal if `e` is not a live edge.
pub(crate) fn live_edge(m: &MeshRef<'_>, e: EdgeId) -> Result<HalfedgeId, Refusal> {
    let h = m
        .try_edge(e)
        .ok_or(Refusal::Stale(ElementId::Edge(e)))?
        .halfedge;
    m.try_halfedge(h)
        .ok_or(Refusal::Stale(ElementId::Edge(e)))?;
    Ok(h)
}

/// Mutable access to one halfedge's links.
pub(crate) fn he(world: &mut World, h: HalfedgeId) -> bevy::prelude::Mut<'_, Halfedge> {
    match world.get_mut::<Halfedge>(h.0) {
        Some(x) => x,
        None => unreachable!("{h} was checked by the plan"),
    }
}

/// Links `a.next = b` and `b.prev = a`.
pub(crate) fn link(world: &mut World, a: HalfedgeId, b: HalfedgeId) {
    he(world, a).next = b;
    he(world, b).prev = a;
}

/// Spawns a freshly allocated entity.
pub(crate) fn spawn_at<B: bevy::prelude::Bundle>(world: &mut World, e: Entity, bundle: B) {
    if let Err(error) = world.spawn_at(e, bundle) {
        unreachable!("spawning freshly allocated {e} failed: {error}");
    }
}

/// Splits face `f` with a new edge from `to(p)` to `to(q)` (two halfedges of `f`, `q` after
/// `p`, not adjacent): `f` keeps `p`'s side, a new face takes the halfedges after `p` up to `q`.
/// Returns the new edge, or `None` (nothing done) when `p` and `q` are adjacent.
pub(crate) fn cut(
    world: &mut World,
    mesh: MeshId,
    f: FaceId,
    p: HalfedgeId,
    q: HalfedgeId,
) -> Option<EdgeId> {
    let m = MeshRef::new(world);
    let (pn, qn) = (m.next(p), m.next(q));
    let (vp, vq) = (m.to_vertex(p), m.to_vertex(q));
    if pn == q || qn == p {
        return None;
    }
    let moved: Vec<HalfedgeId> = {
        let mut list = Vec::new();
        let mut x = pn;
        loop {
            list.push(x);
            if x == q {
                break;
            }
            x = m.next(x);
        }
        list
    };
    // The new corners are copies of the face's corners at the same vertices: `n1` at `vq`
    // (as `q`), `n2` at `vp` (as `p`).
    let uvs = crate::mesh::attributes::of_element(world, f.0).uv.then(|| {
        let uv = |x: HalfedgeId| crate::mesh::attributes::corner_uv(world, x).unwrap_or_default();
        (uv(q), uv(p))
    });
    let alloc = world.entity_allocator();
    let (n1, n2, edge, f2) = (
        HalfedgeId(alloc.alloc()),
        HalfedgeId(alloc.alloc()),
        EdgeId(alloc.alloc()),
        FaceId(alloc.alloc()),
    );
    let member = InMesh(mesh);
    spawn_at(
        world,
        n1.0,
        (
            Halfedge {
                twin: n2,
                next: qn,
                prev: p,
                vertex: vq,
                edge,
                face: Some(f),
            },
            member,
        ),
    );
    spawn_at(
        world,
        n2.0,
        (
            Halfedge {
                twin: n1,
                next: pn,
                prev: q,
                vertex: vp,
                edge,
                face: Some(f2),
            },
            member,
        ),
    );
    link(world, p, n1);
    link(world, n1, qn);
    link(world, q, n2);
    link(world, n2, pn);
    for x in moved {
        he(world, x).face = Some(f2);
    }
    spawn_at(world, edge.0, (Edge { halfedge: n1 }, member));
    spawn_at(world, f2.0, (Face { halfedge: n2 }, member));
    let group = crate::mesh::groups::face_group(world, f);
    crate::mesh::groups::set_face_group(world, f2, group);
    world.get_mut::<Face>(f.0).expect("planned").halfedge = n1;
    if let Some((at_q, at_p)) = uvs {
        crate::mesh::attributes::set_corner_uv(world, n1, at_q);
        crate::mesh::attributes::set_corner_uv(world, n2, at_p);
    }
    Some(edge)
}
