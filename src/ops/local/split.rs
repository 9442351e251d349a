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

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::elements::{Edge, Halfedge, InMesh, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::topology::MeshRef;

use super::{Refusal, cut, he, link, live_edge, spawn_at};

/// Everything a split touches, collected by [`plan_split`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitPlan {
    edge: EdgeId,
    h: HalfedgeId,
    t: HalfedgeId,
    /// `next(h)`, `next(t)`: where the new halfedges link in.
    hn: HalfedgeId,
    tn: HalfedgeId,
    /// The faces of `h` and `t` (`None` on the boundary side).
    f: Option<FaceId>,
    g: Option<FaceId>,
    a: VertexId,
    b: VertexId,
    param: f32,
    position: Vec3,
    mesh: crate::mesh::ids::MeshId,
}

/// Checks that `e` can be split at parameter `t` (from the edge's halfedge's start).
///
/// # Refusals
/// See the module doc.
pub fn plan_split(world: &World, e: EdgeId, t: f32) -> Result<SplitPlan, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    if !(t > 0.0 && t < 1.0) {
        return Err(Refusal::SplitParameter(t));
    }
    let (a, b) = (m.position(m.from_vertex(h)), m.position(m.to_vertex(h)));
    let position = a.lerp(b, t);
    if !position.is_finite() {
        return Err(Refusal::NotFinite(position));
    }
    if position == a || position == b {
        return Err(Refusal::SplitAtEndpoint(ElementId::Edge(e)));
    }
    let mesh = world
        .get::<InMesh>(e.0)
        .ok_or(Refusal::Stale(ElementId::Edge(e)))?
        .0;
    let twin = m.twin(h);
    Ok(SplitPlan {
        edge: e,
        h,
        t: twin,
        hn: m.next(h),
        tn: m.next(twin),
        f: m.face(h),
        g: m.face(twin),
        a: m.from_vertex(h),
        b: m.to_vertex(h),
        param: t,
        position,
        mesh,
    })
}

/// Carries out a split planned by [`plan_split`]. Returns the new vertex.
pub fn apply_split(world: &mut World, p: SplitPlan) -> VertexId {
    debug_assert_eq!(
        plan_split(world, p.edge, p.param),
        Ok(p),
        "stale split plan"
    );
    let SplitPlan {
        h,
        t,
        hn,
        tn,
        f,
        g,
        a,
        b,
        ..
    } = p;
    let member = InMesh(p.mesh);
    let alloc = world.entity_allocator();
    let (mid, h2, t2, e2) = (
        VertexId(alloc.alloc()),
        HalfedgeId(alloc.alloc()),
        HalfedgeId(alloc.alloc()),
        EdgeId(alloc.alloc()),
    );
    // h: a → m, h2: m → b (same face as h); t: b → m, t2: m → a (same face as t).
    // Twins: (h, t2) on the old edge, (h2, t) on the new one.
    he(world, h).vertex = mid;
    he(world, h).twin = t2;
    he(world, t).vertex = mid;
    he(world, t).twin = h2;
    he(world, t).edge = e2;
    spawn_at(
        world,
        h2.0,
        (
            Halfedge {
                twin: t,
                next: hn,
                prev: h,
                vertex: b,
                edge: e2,
                face: f,
            },
            member,
        ),
    );
    spawn_at(
        world,
        t2.0,
        (
            Halfedge {
                twin: h,
                next: tn,
                prev: t,
                vertex: a,
                edge: p.edge,
                face: g,
            },
            member,
        ),
    );
    link(world, h, h2);
    link(world, h2, hn);
    link(world, t, t2);
    link(world, t2, tn);
    let boundary_out = if f.is_none() {
        h2
    } else if g.is_none() {
        t2
    } else {
        h2
    };
    spawn_at(
        world,
        mid.0,
        (
            Vertex {
                halfedge: boundary_out,
            },
            Position(p.position),
            member,
        ),
    );
    // Each edge names an interior halfedge where it has one.
    world.get_mut::<Edge>(p.edge.0).expect("planned").halfedge = if f.is_some() { h } else { t2 };
    spawn_at(
        world,
        e2.0,
        (
            Edge {
                halfedge: if f.is_some() { h2 } else { t },
            },
            member,
        ),
    );
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
