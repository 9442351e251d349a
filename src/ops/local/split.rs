//! Edge split: a new vertex on the edge, joined to the vertex after the edge in each face.
//!
//! ```text
//!         c                     c
//!        / \                   /|\
//!       /   \                 / | \
//!      a --h-> b     →       a--m--b        m at a + t (b − a)
//!       \  t  /               \ | /
//!        \   /                 \|/
//!         d                     d
//! ```
//!
//! On each side that has a face, `m` is joined to the vertex that follows the edge in that
//! face: for a triangle that is the opposite vertex (two triangles become four); a polygon of
//! `k` sides becomes a triangle and a polygon of `k` sides (a quad: a triangle and a quad). The
//! boundary side of a boundary edge only gains `m` in its loop. If both faces would join `m` to
//! the same vertex (they share another edge there), only the first is cut, so no edge is made
//! twice; the other face keeps `m` as an extra corner. Counts: an interior edge adds
//! 1 vertex, 3 edges, 2 faces; a boundary edge 1 vertex, 2 edges, 1 face.
//!
//! The rule for a polygon side, stated once: `m` is joined to the vertex two steps ahead of it
//! along the face (`m → b → c`, so `c`), which cuts the triangle `m b c` off and leaves a
//! polygon `a m c …` of the same degree `k`:
//!
//! ```text
//!   d ------- c          d ------- c
//!   |         |          |      .' |
//!   |    f    |    →     |   .'    |     the quad a b c d gives the quad a m c d
//!   |         |          | .'      |     and the triangle m b c
//!   a ---h--> b          a -- m -- b
//! ```
//!
//! A split is a bisection ([`super::bisect`]: the vertex `m` on the edge) followed by the cuts.
//! Entities: the old edge keeps `h` (now `a → m`) and gets a new twin; `t` (now `b → m`) moves
//! to a new edge `m b` with a new twin; each cut face keeps its entity for the side holding `h`
//! (or `t`) and a new face takes the cut-off triangle. Nothing is despawned.
//!
//! Refusals (each leaves the world untouched):
//! - `Stale`: `e` is not a live edge;
//! - `SplitParameter`: `t` is not strictly between 0 and 1 (NaN included);
//! - `SplitAtEndpoint`: the new point would coincide with an endpoint (a zero-length edge, or
//!   `t` so close to 0 or 1 that it rounds onto one);
//! - `NotFinite`: the new point would not be finite.

use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

use super::bisect::{BisectPlan, apply_bisect, plan_bisect};
use super::{Refusal, cut};

/// Everything a split touches: the bisection's plan (a split is a bisection, then a cut of each
/// face from the new vertex).
pub type SplitPlan = BisectPlan;

/// Checks that `e` can be split at parameter `t` (from the edge's halfedge's start).
///
/// # Refusals
/// See the module doc.
pub fn plan_split(world: &World, e: EdgeId, t: f32) -> Result<SplitPlan, Refusal> {
    plan_bisect(world, e, t)
}

/// Carries out a split planned by [`plan_split`]. Returns the new vertex.
pub fn apply_split(world: &mut World, p: SplitPlan) -> VertexId {
    let BisectPlan { h, t, tn, f, g, .. } = p;
    let mid = apply_bisect(world, p);
    let hn = p.hn;
    let h2 = MeshRef::new(world).next(h);
    // b's outgoing halfedge may have been t (b → a), which is now b → m: still outgoing.
    // Cut each real face from m to the vertex after the edge.
    if let Some(f) = f {
        let _ = cut(world, p.mesh, f, h, hn);
    }
    if let Some(g) = g {
        // When both faces would send m to the same vertex (two faces that also share the edge
        // after the split one), a second cut would duplicate that edge: g keeps m as a corner.
        let m = MeshRef::new(world);
        let target_f = f.map(|_| m.to_vertex(m.next(h2)));
        if target_f != Some(m.to_vertex(tn)) {
            let _ = cut(world, p.mesh, g, t, tn);
        }
    }
    mid
}

/// Splits `e` at parameter `t` along its halfedge (0.5: the midpoint). Returns the new vertex.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn split_edge(world: &mut World, e: EdgeId, t: f32) -> Result<VertexId, Refusal> {
    let plan = plan_split(world, e, t)?;
    Ok(apply_split(world, plan))
}

/// Splits `e` at its midpoint: [`split_edge`] with `t = 0.5`. Returns the new vertex.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn split_edge_midpoint(world: &mut World, e: EdgeId) -> Result<VertexId, Refusal> {
    split_edge(world, e, 0.5)
}

/// Splitting an edge: a local edit.
pub const SPLIT: Declaration = Declaration::new("split")
    .titled("Split")
    .described("split the selected edge at its midpoint")
    .on_key("Alt+S")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`split_edge`] at the midpoint as a registered operation: `split:A,B`, Alt+S.
pub struct Split;

impl MeshOperation for Split {
    fn declaration(&self) -> &'static Declaration {
        &SPLIT
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        Applied::on_edge(world, e, |world| {
            let v = split_edge(world, e, 0.5)?;
            Ok((format!("new vertex {v}"), v.into()))
        })
    }
}
