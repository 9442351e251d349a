//! Local operations: edge flip, edge split, edge collapse.
//!
//! The contract, stated once: **if the result of an operation would not be a valid mesh, the
//! operation changes nothing and returns a [`Refusal`] that says why.** Each operation is a
//! read-only `plan_*` (`&World`) that checks the ids, checks every refusal and collects every id
//! it will touch, and an `apply_*` (`&mut World`) that carries out a fresh plan and cannot fail.
//! `flip_edge`, `split_edge` and `collapse_edge` do both.
//!
//! All three work on triangles and on polygons, and on boundary edges where the operation makes
//! sense. Entities are reused wherever an element survives, so ids the user is looking at stay
//! valid when they can.

mod collapse;
mod flip;
mod split;

pub use collapse::{
    CollapseOptions, CollapsePlan, CollapseResult, apply_collapse, collapse_edge, plan_collapse,
};
pub use flip::{FlipPlan, apply_flip, flip_edge, plan_flip};
pub use split::{SplitPlan, apply_split, plan_split, split_edge};

use bevy::prelude::World;

use crate::mesh::elements::Halfedge;
use crate::mesh::ids::{EdgeId, ElementId, HalfedgeId};
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
