//! Edge flip: the edge turns one step counter-clockwise inside the two faces it separates.
//!
//! ```text
//!         c                     c
//!        / \                   /|\
//!       /   \                 / | \
//!      a --h-> b     →       a  h  b        h: a→b becomes h: d→c
//!       \  t  /                 \ | /
//!        \   /                   \|/
//!         d                       d
//! ```
//!
//! For polygons the same rule: each endpoint gives up the edge, which now joins the vertex after
//! `b` in `h`'s face to the vertex after `a` in `t`'s face; each face keeps its number of sides
//! (`h`'s face trades `b` for `d`, `t`'s face trades `a` for `c`). Nothing is spawned or
//! despawned: the edge, its two halfedges and both faces keep their entities.
//!
//! ```text
//!   3 ---- 4 ---- 5          3 ---- 4 ---- 5
//!   |      |      |          | '.          |
//!   |      |      |    →     |    '.       |     two quads: 1–4 becomes 3–2,
//!   |      |      |          |       '.    |     faces 0 1 2 3 and 3 2 5 4
//!   0 ---- 1 ---- 2          0 ---- 1 ---- 2
//! ```
//!
//! Refusals, in the order they are checked (each leaves the world untouched):
//! - `Stale`: `e` is not a live edge;
//! - `BoundaryEdge`: `e` has a side without a face;
//! - `DegenerateFace`: both faces would gain the same vertex (`c == d`);
//! - `WouldDuplicateEdge`: `c` and `d` are already joined (every edge of a tetrahedron);
//! - `ValenceTooLow`: an endpoint would be left with fewer than 3 edges (2 on the boundary),
//!   i.e. an interior endpoint of valence 3 or a boundary endpoint of valence 2 — for triangles
//!   a valence-3 endpoint always fails the previous check first, so this one shows on polygons
//!   (every edge of a cube);
//! - `DegenerateFace`: a face would visit a vertex twice (a polygon that already holds the vertex
//!   it would gain).

use bevy::prelude::World;

use crate::mesh::elements::{Face, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

use super::{Refusal, he, link, live_edge};

/// Everything a flip touches, collected by [`plan_flip`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlipPlan {
    edge: EdgeId,
    h: HalfedgeId,
    t: HalfedgeId,
    hn: HalfedgeId,
    hp: HalfedgeId,
    tn: HalfedgeId,
    tp: HalfedgeId,
    f: FaceId,
    g: FaceId,
    a: VertexId,
    b: VertexId,
    c: VertexId,
    d: VertexId,
}

/// Checks that `e` can be flipped and collects what the flip touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_flip(world: &World, e: EdgeId) -> Result<FlipPlan, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    let t = m.twin(h);
    let (Some(f), Some(g)) = (m.face(h), m.face(t)) else {
        return Err(Refusal::BoundaryEdge(ElementId::Edge(e)));
    };
    let (hn, hp, tn, tp) = (m.next(h), m.prev(h), m.next(t), m.prev(t));
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    let (c, d) = (m.to_vertex(hn), m.to_vertex(tn));
    if c == d {
        return Err(Refusal::DegenerateFace(ElementId::Face(f)));
    }
    // Checked before the valences, so that every edge of a tetrahedron reports the edge that
    // already exists (its endpoints have valence 3 too).
    if m.find_halfedge(c, d).is_some() {
        return Err(Refusal::WouldDuplicateEdge(
            ElementId::Vertex(c),
            ElementId::Vertex(d),
        ));
    }
    for v in [a, b] {
        let minimum = if m.is_boundary_vertex(v) { 2 } else { 3 };
        if m.valence(v) <= minimum {
            return Err(Refusal::ValenceTooLow(ElementId::Vertex(v), minimum));
        }
    }
    // The new faces: f gains d, g gains c; neither may already hold it.
    if m.face_vertices(f).any(|v| v == d) {
        return Err(Refusal::DegenerateFace(ElementId::Face(f)));
    }
    if m.face_vertices(g).any(|v| v == c) {
        return Err(Refusal::DegenerateFace(ElementId::Face(g)));
    }
    Ok(FlipPlan {
        edge: e,
        h,
        t,
        hn,
        hp,
        tn,
        tp,
        f,
        g,
        a,
        b,
        c,
        d,
    })
}

/// Carries out a flip planned by [`plan_flip`] on the unchanged world. Returns the edge (the
/// same entity, now joining the other two vertices).
pub fn apply_flip(world: &mut World, p: FlipPlan) -> EdgeId {
    crate::checks::checked_assert_eq!(plan_flip(world, p.edge), Ok(p), "stale flip plan");
    // `h` comes to point at c inside f and `t` at d inside g: they take the UVs of those
    // corners, which `hn` (at c in f) and `tn` (at d in g) hold; every other corner keeps its own.
    let uvs = crate::mesh::attributes::of_element(world, p.edge.0)
        .uv
        .then(|| {
            let uv =
                |x: HalfedgeId| crate::mesh::attributes::corner_uv(world, x).unwrap_or_default();
            (uv(p.hn), uv(p.tn))
        });
    let hnn = MeshRef::new(world).next(p.hn);
    let tnn = MeshRef::new(world).next(p.tn);
    // h: d → c in f; t: c → d in g. hn moves to g, tn moves to f.
    {
        let mut h = he(world, p.h);
        h.vertex = p.c;
    }
    {
        let mut t = he(world, p.t);
        t.vertex = p.d;
    }
    // f: h, hnn … hp, tn.
    link(world, p.h, hnn);
    link(world, p.hp, p.tn);
    link(world, p.tn, p.h);
    he(world, p.tn).face = Some(p.f);
    // g: t, tnn … tp, hn.
    link(world, p.t, tnn);
    link(world, p.tp, p.hn);
    link(world, p.hn, p.t);
    he(world, p.hn).face = Some(p.g);
    world.get_mut::<Face>(p.f.0).expect("planned").halfedge = p.h;
    world.get_mut::<Face>(p.g.0).expect("planned").halfedge = p.t;
    // a and b no longer start h / t.
    for (v, lost, replacement) in [(p.a, p.h, p.tn), (p.b, p.t, p.hn)] {
        let mut x = world.get_mut::<Vertex>(v.0).expect("planned");
        if x.halfedge == lost {
            x.halfedge = replacement;
        }
    }
    if let Some((at_c, at_d)) = uvs {
        crate::mesh::attributes::set_corner_uv(world, p.h, at_c);
        crate::mesh::attributes::set_corner_uv(world, p.t, at_d);
    }
    p.edge
}

/// Flips `e` (see the module doc): plan, then apply.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn flip_edge(world: &mut World, e: EdgeId) -> Result<EdgeId, Refusal> {
    let plan = plan_flip(world, e)?;
    Ok(apply_flip(world, plan))
}

/// Flipping an edge: a local edit that keeps every id and attribute.
pub const FLIP: Declaration = Declaration::new("flip")
    .titled("Flip")
    .described("flip (rotate) the selected edge")
    .on_key("Alt+R")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`flip_edge`] as a registered operation: `flip:A,B`, Alt+R, the *Local operations* button.
pub struct Flip;

impl MeshOperation for Flip {
    fn declaration(&self) -> &'static Declaration {
        &FLIP
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
            let flipped = flip_edge(world, e)?;
            Ok((format!("flipped to {flipped}"), flipped.into()))
        })
    }
}
