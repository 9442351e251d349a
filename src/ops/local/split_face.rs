//! Face split: a new edge across a polygon, between two of its corners that are not neighbours.
//!
//! ```text
//!   d ------ c          d ------ c
//!   |        |          |      / |
//!   |   f    |    →     |  f  /  |     split f between a and c
//!   |        |          |   /  f'|
//!   a ------ b          a ------ b
//! ```
//!
//! `f` keeps the side that runs from the second vertex back round to the first; a new face
//! takes the other. Refusals: a stale face; a vertex that is not a corner of the face; two
//! corners that are neighbours (their edge exists); two corners already joined by an edge
//! elsewhere.

use bevy::prelude::World;

use crate::mesh::elements::InMesh;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Redraw, Values};

use super::{Refusal, cut};

/// What a face split touches, collected by [`plan_split_face`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplitFacePlan {
    face: FaceId,
    mesh: MeshId,
    /// The halfedges of the face ending at the two corners.
    into_a: HalfedgeId,
    into_b: HalfedgeId,
}

/// Checks that face `f` can be split between its corners `a` and `b`.
///
/// # Refusals
/// See the module doc.
pub fn plan_split_face(
    world: &World,
    f: FaceId,
    a: VertexId,
    b: VertexId,
) -> Result<SplitFacePlan, Refusal> {
    let m = MeshRef::new(world);
    let stale = Refusal::Stale(ElementId::Face(f));
    m.try_face(f).ok_or(stale.clone())?;
    let mesh = world.get::<InMesh>(f.0).ok_or(stale)?.0;
    let ring: Vec<HalfedgeId> = m.face_halfedges(f).collect();
    let find = |v: VertexId| {
        ring.iter()
            .copied()
            .find(|&h| m.to_vertex(h) == v)
            .ok_or(Refusal::NotACorner(
                ElementId::Vertex(v),
                ElementId::Face(f),
            ))
    };
    let (into_a, into_b) = (find(a)?, find(b)?);
    if a == b || m.next(into_a) == into_b || m.next(into_b) == into_a {
        return Err(Refusal::WouldDuplicateEdge(
            ElementId::Vertex(a),
            ElementId::Vertex(b),
        ));
    }
    if m.find_halfedge(a, b).is_some() {
        return Err(Refusal::WouldDuplicateEdge(
            ElementId::Vertex(a),
            ElementId::Vertex(b),
        ));
    }
    Ok(SplitFacePlan {
        face: f,
        mesh,
        into_a,
        into_b,
    })
}

/// Carries out a face split planned by [`plan_split_face`]. Returns the new edge.
pub fn apply_split_face(world: &mut World, p: SplitFacePlan) -> EdgeId {
    match cut(world, p.mesh, p.face, p.into_a, p.into_b) {
        Some(e) => e,
        None => unreachable!("the plan refused neighbouring corners"),
    }
}

/// Splits face `f` between its corners `a` and `b` (see the module doc). Returns the new edge.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn split_face(
    world: &mut World,
    f: FaceId,
    a: VertexId,
    b: VertexId,
) -> Result<EdgeId, Refusal> {
    let plan = plan_split_face(world, f, a, b)?;
    Ok(apply_split_face(world, plan))
}

/// Splitting a face between two of its corners: a local edit.
pub const SPLIT_FACE: Declaration = Declaration::new("split-face")
    .titled("Split face")
    .described("join two corners of a face by a new edge (the selected halfedge's tip and the corner two ahead)")
    .on_key("J")
    .naming(Names::FaceCorners)
    .in_section(Section::Local);

/// [`split_face`] as a registered operation: `split-face:A,B` (the face the two vertices
/// share), J on a halfedge of a face.
pub struct SplitFace;

impl MeshOperation for SplitFace {
    fn declaration(&self) -> &'static Declaration {
        &SPLIT_FACE
    }

    /// The neighbourhood of the two corners (`None` when the face or a corner is gone).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let (f, a, b) = values.face_corners().ok()?;
        MeshRef::new(world).try_face(f)?;
        Reach::local(world, vec![a, b])
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let (f, a, b) = values.face_corners()?;
        let before = MeshRef::new(world).faces_around(&[a, b]);
        let e = split_face(world, f, a, b)?;
        Ok(Applied {
            summary: format!("new edge {e}"),
            redraw: Redraw::near(world, before, vec![a, b]),
            made: Some(ElementId::Edge(e)),
        })
    }
}
