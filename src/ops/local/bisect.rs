//! Edge bisection: a new vertex on the edge, and nothing else — the faces beside it gain a
//! corner (a triangle becomes a quad with a straight angle), no face is cut. It is the first
//! half of an edge split ([`super::split`] cuts the faces afterwards), and an operation of its
//! own in Scotty3D and Blender ("subdivide" with no cuts).
//!
//! ```text
//!         c                     c
//!        / \                   / //!       /   \                 /   //!      a --h-> b     →       a--m--b        m at a + t (b − a)
//!       \  t  /               \   /
//!        \   /                 \ /
//!         d                     d
//! ```
//!
//! Counts: 1 vertex, 1 edge, 2 halfedges more; faces unchanged (each face of the edge gains a
//! side). Entities: the old edge keeps `h` (now `a → m`) and gets a new twin `t2` (`m → a`);
//! `t` (now `b → m`) moves to a new edge `m b` with a new twin `h2` (`m → b`). Nothing is
//! despawned.
//!
//! Refusals (each leaves the world untouched):
//! - `Stale`: `e` is not a live edge;
//! - `SplitParameter`: `t` is not strictly between 0 and 1 (NaN included);
//! - `SplitAtEndpoint`: the new point would coincide with an endpoint (a zero-length edge, or
//!   `t` so close to 0 or 1 that it rounds onto one);
//! - `NotFinite`: the new point would not be finite.

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::attributes;
use crate::mesh::elements::{Edge, Halfedge, InMesh, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

use super::{Refusal, he, link, live_edge, spawn_at};

/// Everything a bisection touches, collected by [`plan_bisect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BisectPlan {
    pub(super) edge: EdgeId,
    pub(super) h: HalfedgeId,
    pub(super) t: HalfedgeId,
    /// `next(h)`, `next(t)`: where the new halfedges link in.
    pub(super) hn: HalfedgeId,
    pub(super) tn: HalfedgeId,
    /// The faces of `h` and `t` (`None` on the boundary side).
    pub(super) f: Option<FaceId>,
    pub(super) g: Option<FaceId>,
    pub(super) a: VertexId,
    pub(super) b: VertexId,
    pub(super) param: f32,
    pub(super) position: Vec3,
    pub(super) mesh: crate::mesh::ids::MeshId,
}

/// Checks that `e` can be bisected at parameter `t` (from the edge's halfedge's start).
///
/// # Refusals
/// See the module doc.
pub fn plan_bisect(world: &World, e: EdgeId, t: f32) -> Result<BisectPlan, Refusal> {
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
    Ok(BisectPlan {
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

/// Carries out a bisection planned by [`plan_bisect`]. Returns the new vertex.
pub fn apply_bisect(world: &mut World, p: BisectPlan) -> VertexId {
    crate::checks::checked_assert_eq!(
        plan_bisect(world, p.edge, p.param),
        Ok(p),
        "stale bisect plan"
    );
    let BisectPlan {
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
    // The corners' UVs before: each side's corner at a and at b.
    let has = attributes::MeshAttributes::of(world, p.mesh);
    let uvs = has.uv.then(|| {
        let m = MeshRef::new(world);
        let uv = |x: HalfedgeId| attributes::corner_uv(world, x).unwrap_or_default();
        // (at a, at b) inside f, and inside g.
        ((uv(m.prev(h)), uv(h)), (uv(t), uv(m.prev(t))))
    });
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
    let after_mid_in_f = Halfedge {
        twin: t,
        next: hn,
        prev: h,
        vertex: b,
        edge: e2,
        face: f,
    };
    let after_mid_in_g = Halfedge {
        twin: h,
        next: tn,
        prev: t,
        vertex: a,
        edge: p.edge,
        face: g,
    };
    spawn_at(world, h2.0, (after_mid_in_f, member));
    spawn_at(world, t2.0, (after_mid_in_g, member));
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
    let vertex = Vertex {
        halfedge: boundary_out,
    };
    spawn_at(world, mid.0, (vertex, Position(p.position), member));
    // Each edge names an interior halfedge where it has one.
    world.get_mut::<Edge>(p.edge.0).expect("planned").halfedge = if f.is_some() { h } else { t2 };
    let new_edge = Edge {
        halfedge: if f.is_some() { h2 } else { t },
    };
    spawn_at(world, e2.0, (new_edge, member));
    // The new corners: at `mid` interpolated along each side; `h2` and `t2` take the corners
    // `h` and `t` had (at b inside f, at a inside g).
    if let Some(((fa, fb), (ga, gb))) = uvs {
        if f.is_some() {
            attributes::set_corner_uv(world, h, fa.lerp(fb, p.param));
            attributes::set_corner_uv(world, h2, fb);
        }
        if g.is_some() {
            attributes::set_corner_uv(world, t, ga.lerp(gb, p.param));
            attributes::set_corner_uv(world, t2, ga);
        }
    }
    attributes::interpolate_vertex(world, has, mid, (a, b), p.param);
    // A seam stays a seam along both halves.
    if has.seams && world.get::<attributes::Seam>(p.edge.0).is_some() {
        world.entity_mut(e2.0).insert(attributes::Seam);
    }
    mid
}

/// Bisects `e` at parameter `t` along its halfedge (0.5: the midpoint). Returns the new vertex.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn bisect_edge(world: &mut World, e: EdgeId, t: f32) -> Result<VertexId, Refusal> {
    let plan = plan_bisect(world, e, t)?;
    Ok(apply_bisect(world, plan))
}

/// Bisecting an edge: a local edit.
pub const BISECT: Declaration = Declaration::new("bisect")
    .titled("Bisect")
    .described("bisect the selected edge: a vertex at its midpoint, no face cut")
    .on_key("K")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`bisect_edge`] at the midpoint as a registered operation: `bisect:A,B`, K.
pub struct Bisect;

impl MeshOperation for Bisect {
    fn declaration(&self) -> &'static Declaration {
        &BISECT
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
            let v = bisect_edge(world, e, 0.5)?;
            Ok((format!("new vertex {v} on {e}"), v.into()))
        })
    }
}
