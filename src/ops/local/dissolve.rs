//! Edge dissolve: the two faces of an edge become one polygon.
//!
//! ```text
//!   d ------ c          d ------ c
//!   |      / |          |        |
//!   |  f  /  |    →     |   f    |     dissolve a–c
//!   |   / g  |          |        |
//!   a ------ b          a ------ b
//! ```
//!
//! `f` (the face of the edge's halfedge) survives and takes `g`'s sides. Refusals: a boundary
//! edge; an edge with the same face on both sides; an endpoint that would keep a single edge;
//! faces that share a corner besides the edge's ends (the merged face would visit it twice).

use bevy::prelude::World;

use crate::mesh::elements::{Face, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Redraw, Values};

use super::{Refusal, he, link, live_edge};

/// What a dissolve touches, collected by [`plan_dissolve`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DissolvePlan {
    edge: EdgeId,
    h: HalfedgeId,
    t: HalfedgeId,
    f: FaceId,
    g: FaceId,
    a: VertexId,
    b: VertexId,
    g_ring: Vec<HalfedgeId>,
}

/// Checks that `e` can be dissolved.
///
/// # Refusals
/// See the module doc.
pub fn plan_dissolve(world: &World, e: EdgeId) -> Result<DissolvePlan, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    let t = m.twin(h);
    let (Some(f), Some(g)) = (m.face(h), m.face(t)) else {
        return Err(Refusal::BoundaryEdge(ElementId::Edge(e)));
    };
    if f == g {
        return Err(Refusal::DegenerateFace(ElementId::Face(f)));
    }
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    for v in [a, b] {
        if m.valence(v) <= 2 {
            return Err(Refusal::ValenceTooLow(ElementId::Vertex(v), 2));
        }
    }
    let in_f: Vec<VertexId> = m.face_vertices(f).collect();
    if let Some(shared) = m
        .face_vertices(g)
        .find(|v| *v != a && *v != b && in_f.contains(v))
    {
        return Err(Refusal::DegenerateFace(ElementId::Vertex(shared)));
    }
    Ok(DissolvePlan {
        edge: e,
        h,
        t,
        f,
        g,
        a,
        b,
        g_ring: m.face_halfedges(g).collect(),
    })
}

/// Carries out a dissolve planned by [`plan_dissolve`]. Returns the merged face.
pub fn apply_dissolve(world: &mut World, p: DissolvePlan) -> FaceId {
    let m = MeshRef::new(world);
    let (hp, hn, tp, tn) = (m.prev(p.h), m.next(p.h), m.prev(p.t), m.next(p.t));
    link(world, hp, tn);
    link(world, tp, hn);
    for &x in &p.g_ring {
        if x != p.t {
            he(world, x).face = Some(p.f);
        }
    }
    world.get_mut::<Face>(p.f.0).expect("planned").halfedge = hn;
    for (v, lost, replacement) in [(p.a, p.h, tn), (p.b, p.t, hn)] {
        let mut x = world.get_mut::<Vertex>(v.0).expect("planned");
        if x.halfedge == lost {
            x.halfedge = replacement;
        }
    }
    for entity in [p.h.0, p.t.0, p.edge.0, p.g.0] {
        world.despawn(entity);
    }
    p.f
}

/// Dissolves `e`, merging its two faces (see the module doc). Returns the merged face.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn dissolve_edge(world: &mut World, e: EdgeId) -> Result<FaceId, Refusal> {
    let plan = plan_dissolve(world, e)?;
    Ok(apply_dissolve(world, plan))
}

/// Dissolving an edge: a local edit.
pub const DISSOLVE: Declaration = Declaration::new("dissolve")
    .titled("Dissolve")
    .described("dissolve the active edge (merge its two faces) or vertex (merge its faces)")
    .on_key("D")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`dissolve_edge`] as a registered operation: `dissolve:A,B`, D on an edge.
pub struct Dissolve;

impl MeshOperation for Dissolve {
    fn declaration(&self) -> &'static Declaration {
        &DISSOLVE
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        let m = MeshRef::new(world);
        let ends = m.corners(e.into());
        let before = m.faces_around(&ends);
        let f = dissolve_edge(world, e)?;
        Ok(Applied {
            summary: format!("merged into {f}"),
            redraw: Redraw::near(world, before, ends),
            made: Some(ElementId::Face(f)),
        })
    }
}
