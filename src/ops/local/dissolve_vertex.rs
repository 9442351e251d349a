//! Vertex dissolve: the faces around a vertex become one polygon, and the vertex goes.
//!
//! ```text
//!   d ------ c          d ------ c
//!   | \    / |          |        |
//!   |  \  /  |          |        |
//!   |    v   |    →     |   f    |     dissolve v: its edges go, its four triangles
//!   |  /  \  |          |        |     become the quad a b c d
//!   | /    \ |          |        |
//!   a ------ b          a ------ b
//! ```
//!
//! Inside the surface, the merged face is the faces around `v` with their sides at `v` taken
//! out, joined in order around `v`: a polygon of Σ (degree − 2) sides. `v`, its edges and their
//! halfedges are removed; the first face around `v` (the face of [`MeshRef::vertex_halfedge`])
//! survives as the merged face, the others are removed. Counts: V − 1, E − valence,
//! F − (valence − 1), χ unchanged.
//!
//! On the boundary (Scotty3D: the vertex "does not merge with the boundary face"), the faces
//! around `v` merge the same way and one new side joins `v`'s two boundary neighbours, taking
//! the place of `v`'s two boundary edges along the border. The new side reuses the entities of
//! `v`'s outgoing boundary edge (its boundary halfedge stays on the border, its twin becomes the
//! face's side); its corner takes the UV the first face had at that neighbour.
//!
//! ```text
//!   d ---- c ---- e          d ---- c ---- e
//!   |      |      |          |             |
//!   |      |      |    →     |      f      |     dissolve v on the border: b a is the new
//!   |      |      |          |             |     side (the two quads become the pentagon
//!   a ---- v ---- b          a ----------- b     a b e c d)
//! ```
//!
//! Counts: V − 1, E − (valence − 1), F − (valence − 2), χ unchanged. No vertex moves; every
//! other corner keeps its UV; the neighbours' halfedges are kept valid (a boundary neighbour
//! keeps its boundary one).
//!
//! Refusals, in the order they are checked, each leaving the world untouched:
//! - `Stale`: `v` is not a live vertex;
//! - `SingleFace`: a boundary vertex with one face (the corner of a lone quad: there is nothing
//!   to merge; Scotty3D refuses it too);
//! - `WouldDuplicateEdge`: on the boundary, the two boundary neighbours are already joined
//!   (e.g. `v` is a corner of a triangular hole);
//! - `DegenerateFace`: the merged face would have fewer than 3 sides, or visit a vertex twice
//!   (two faces around `v` that share a corner away from `v`'s edges; a neighbour left with a
//!   single edge).

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec2;
use bevy::prelude::World;

use crate::mesh::attributes::{corner_uv, set_corner_uv};
use crate::mesh::elements::{Edge, Face, Vertex};
use crate::mesh::ids::{ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values};

use super::{Refusal, he, link};

/// The new side of a boundary dissolve, made from `v`'s outgoing boundary edge.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Closing {
    /// The edge's halfedge into `v` (in the last face): it becomes the face's side a₀ → a₁.
    side: HalfedgeId,
    /// `v`'s outgoing boundary halfedge: it stays on the border, as a₁ → a₀.
    border: HalfedgeId,
    /// The boundary halfedge into a₁, whose `next` becomes `border`.
    before: HalfedgeId,
    /// a₁, the boundary neighbour the border ran through before `v`.
    a1: VertexId,
    /// The UV the first face had at a₁, where the mesh has UVs.
    uv: Option<Vec2>,
}

/// Everything a vertex dissolve touches, collected by [`plan_dissolve_vertex`].
#[derive(Clone, Debug, PartialEq)]
pub struct DissolveVertexPlan {
    v: VertexId,
    /// `v`'s neighbours, counter-clockwise from its halfedge's tip.
    neighbours: Vec<VertexId>,
    /// The merged face's halfedges in order.
    ring: Vec<HalfedgeId>,
    /// The surviving face.
    face: FaceId,
    removed_faces: Vec<FaceId>,
    removed_halfedges: Vec<HalfedgeId>,
    removed_edges: Vec<crate::mesh::ids::EdgeId>,
    /// Neighbours whose halfedge goes, with the one they take.
    vertex_halfedges: Vec<(VertexId, HalfedgeId)>,
    closing: Option<Closing>,
}

impl DissolveVertexPlan {
    /// `v` and its neighbours: their neighbourhood (see [`crate::mesh::change::neighbourhood`])
    /// covers every face around `v` with all its corners before, and the merged face after.
    pub fn seeds(&self) -> Vec<VertexId> {
        let mut seeds = vec![self.v];
        seeds.extend(&self.neighbours);
        seeds
    }

    /// The face that survives as the merged face.
    pub fn face(&self) -> FaceId {
        self.face
    }
}

/// Checks that `v` can be dissolved and collects everything the dissolve touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_dissolve_vertex(world: &World, v: VertexId) -> Result<DissolveVertexPlan, Refusal> {
    let m = MeshRef::new(world);
    let stale = Refusal::Stale(ElementId::Vertex(v));
    let start = m.try_vertex(v).ok_or(stale.clone())?.halfedge;
    m.try_halfedge(start).ok_or(stale)?;
    let fan: Vec<HalfedgeId> = m.vertex_outgoing(v).collect();
    let neighbours: Vec<VertexId> = fan.iter().map(|&h| m.to_vertex(h)).collect();
    let boundary = m.is_boundary(start);
    // The faces to merge are left of fan[first..]; on the boundary fan[0] is the gap.
    let first = usize::from(boundary);
    if boundary && fan.len() <= 2 {
        return Err(Refusal::SingleFace(ElementId::Vertex(v)));
    }
    if boundary {
        let (a0, a1) = (neighbours[0], neighbours[1]);
        if m.find_halfedge(a0, a1).is_some() {
            return Err(Refusal::WouldDuplicateEdge(
                ElementId::Vertex(a0),
                ElementId::Vertex(a1),
            ));
        }
    }
    // Each face's chain: its halfedges but the two at v, from the one after v's outgoing side.
    let mut ring = Vec::new();
    for &o in &fan[first..] {
        let back = m.prev(o);
        ring.extend(m.loop_from(m.next(o)).take_while(|&h| h != back));
    }
    let mut corners: Vec<VertexId> = ring.iter().map(|&h| m.to_vertex(h)).collect();
    let closing = boundary.then(|| Closing {
        side: m.twin(fan[0]),
        border: fan[0],
        before: m.prev(m.twin(fan[1])),
        a1: neighbours[1],
        uv: corner_uv(world, fan[1]),
    });
    if let Some(c) = &closing {
        ring.push(c.side);
        corners.push(c.a1);
    }
    let face = m.face(fan[first]).expect("a face side of v");
    if corners.len() < 3 {
        return Err(Refusal::DegenerateFace(ElementId::Face(face)));
    }
    let mut seen = EntityHashSet::default();
    if let Some(&twice) = corners.iter().find(|c| !seen.insert(c.0)) {
        return Err(Refusal::DegenerateFace(ElementId::Vertex(twice)));
    }
    let removed_faces = fan[first + 1..]
        .iter()
        .map(|&o| m.face(o).expect("a face side of v"))
        .collect();
    let mut removed_halfedges = Vec::new();
    let mut removed_edges = Vec::new();
    let mut vertex_halfedges = Vec::new();
    for (i, &o) in fan.iter().enumerate().skip(first) {
        let t = m.twin(o);
        removed_halfedges.extend([o, t]);
        removed_edges.push(m.edge(o));
        let a = neighbours[i];
        if m.vertex_halfedge(a) == t {
            // On the boundary, a₁'s halfedge is t (its boundary one): it takes the border.
            let replacement = match &closing {
                Some(c) if i == 1 => c.border,
                _ => m.next(o),
            };
            vertex_halfedges.push((a, replacement));
        }
    }
    Ok(DissolveVertexPlan {
        v,
        neighbours,
        ring,
        face,
        removed_faces,
        removed_halfedges,
        removed_edges,
        vertex_halfedges,
        closing,
    })
}

/// Carries out a dissolve planned by [`plan_dissolve_vertex`] on the unchanged world. Returns
/// the merged face.
pub fn apply_dissolve_vertex(world: &mut World, p: DissolveVertexPlan) -> FaceId {
    crate::checks::checked_assert_eq!(
        plan_dissolve_vertex(world, p.v).as_ref(),
        Ok(&p),
        "stale vertex dissolve plan"
    );
    if let Some(c) = &p.closing {
        he(world, c.side).vertex = c.a1;
        link(world, c.before, c.border);
        let edge = MeshRef::new(world).edge(c.side);
        world.get_mut::<Edge>(edge.0).expect("planned").halfedge = c.side;
        if let Some(uv) = c.uv {
            set_corner_uv(world, c.side, uv);
        }
    }
    let n = p.ring.len();
    for i in 0..n {
        let (h, following) = (p.ring[i], p.ring[(i + 1) % n]);
        link(world, h, following);
        he(world, h).face = Some(p.face);
    }
    world.get_mut::<Face>(p.face.0).expect("planned").halfedge = p.ring[0];
    for &(a, h) in &p.vertex_halfedges {
        world.get_mut::<Vertex>(a.0).expect("planned").halfedge = h;
    }
    let entities = p
        .removed_faces
        .iter()
        .map(|f| f.0)
        .chain(p.removed_halfedges.iter().map(|h| h.0))
        .chain(p.removed_edges.iter().map(|e| e.0))
        .chain([p.v.0]);
    for e in entities {
        world.despawn(e);
    }
    p.face
}

/// Dissolves `v` (see the module doc): plan, then apply. Returns the merged face.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn dissolve_vertex(world: &mut World, v: VertexId) -> Result<FaceId, Refusal> {
    let plan = plan_dissolve_vertex(world, v)?;
    Ok(apply_dissolve_vertex(world, plan))
}

/// Dissolving a vertex (the `dissolve:A` step): a local edit.
pub const DISSOLVE_VERTEX: Declaration = Declaration::new("dissolve")
    .titled("Dissolve")
    .described("dissolve the active vertex: merge the faces around it")
    .on_key("D")
    .naming(Names::Vertex)
    .in_section(Section::Local);

/// [`dissolve_vertex`] as a registered operation: `dissolve:A`, D on a vertex.
pub struct DissolveVertex;

impl MeshOperation for DissolveVertex {
    fn declaration(&self) -> &'static Declaration {
        &DISSOLVE_VERTEX
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_dissolve_vertex(world, values.vertex().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = plan_dissolve_vertex(world, values.vertex()?)?;
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
            let made = apply_dissolve_vertex(world, plan);
            let summary = format!("merged into {made}");
            (summary, Some(made.into()))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshMembers, PolygonSoup, shapes, validate};
    use crate::ops::local::testkit::*;
    use bevy::math::Vec3;

    #[test]
    fn the_centre_of_a_triangle_fan_leaves_a_quad() {
        // Scotty3D's test: the centre of four triangles; the surviving ids stay valid.
        let (mut world, built) = build(&shapes::triangle_fan(4, true));
        let rim: Vec<VertexId> = (1..5).map(|i| vertex(&built, i)).collect();
        let faces_before = MeshMembers::collect(&world, built.mesh).faces;
        let f = dissolve_vertex(&mut world, vertex(&built, 0)).unwrap();
        assert!(
            faces_before.contains(&f),
            "the merged face is one of the old ones"
        );
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (4, 4, 1, 1, 1));
        let m = MeshRef::new(&world);
        assert_eq!(m.face_degree(f), 4);
        let around: Vec<VertexId> = m.face_vertices(f).collect();
        let at = around.iter().position(|&x| x == rim[0]).unwrap();
        let turned: Vec<VertexId> = (0..4).map(|i| around[(at + i) % 4]).collect();
        assert_eq!(turned, rim);
    }

    #[test]
    fn an_inner_vertex_of_quads_leaves_an_octagon() {
        let (mut world, built) = build(&shapes::quad_grid(2, 2));
        dissolve_vertex(&mut world, vertex(&built, 4)).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (8, 8, 1, 1, 1));
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[&[
                [0.0, 0.0, 0.0],
                [0.5, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 0.5, 0.0],
                [1.0, 1.0, 0.0],
                [0.5, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.5, 0.0],
            ]])
        );
    }

    #[test]
    fn a_vertex_of_a_closed_triangle_mesh_leaves_a_pentagon() {
        let (mut world, built) = build(&shapes::icosahedron());
        let v = MeshMembers::collect(&world, built.mesh).vertices[0];
        let f = dissolve_vertex(&mut world, v).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (11, 25, 16, 2, 0));
        assert_eq!(MeshRef::new(&world).face_degree(f), 5);
    }

    #[test]
    fn a_border_vertex_between_two_quads_leaves_a_pentagon() {
        let (mut world, built) = build(&shapes::quad_grid(2, 1));
        let (a, b) = (vertex(&built, 0), vertex(&built, 2));
        let f = dissolve_vertex(&mut world, vertex(&built, 1)).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (5, 5, 1, 1, 1));
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[&[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.5, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ]])
        );
        let m = MeshRef::new(&world);
        assert!(m.find_halfedge(a, b).is_some_and(|h| m.face(h) == Some(f)));
        assert!(m.is_boundary_vertex(a) && m.is_boundary_vertex(b));
    }

    #[test]
    fn a_border_vertex_of_triangles_cuts_the_square_to_a_triangle() {
        // The square 0 1 3 2 as triangles 0 1 3 and 0 3 2; vertex 0 has both.
        let (mut world, built) = build(&shapes::grid(1, 1));
        dissolve_vertex(&mut world, vertex(&built, 0)).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (3, 3, 1, 1, 1));
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[&[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]])
        );
    }

    /// A square whose inside vertex w = (1, ½) has only two edges (to v = (1, 1) and to the
    /// corner (0, 0)): the faces c0 w v c3 and c0 c1 v w share both.
    fn square_with_a_two_edge_vertex() -> PolygonSoup {
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        PolygonSoup::from_faces(
            vec![
                p(0.0, 0.0),
                p(2.0, 0.0),
                p(2.0, 2.0),
                p(0.0, 2.0),
                p(1.0, 1.0),
                p(1.0, 0.5),
            ],
            &[
                vec![0, 5, 4, 3],
                vec![0, 1, 4, 5],
                vec![1, 2, 4],
                vec![2, 3, 4],
            ],
        )
    }

    #[test]
    fn a_two_edge_vertex_joins_its_two_faces() {
        let (mut world, built) = build(&square_with_a_two_edge_vertex());
        dissolve_vertex(&mut world, vertex(&built, 5)).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (5, 7, 3, 1, 1));
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[
                &[
                    [0.0, 0.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [0.0, 2.0, 0.0]
                ],
                &[[2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [1.0, 1.0, 0.0]],
                &[[2.0, 2.0, 0.0], [0.0, 2.0, 0.0], [1.0, 1.0, 0.0]],
            ])
        );
    }

    #[test]
    fn refusals_leave_the_mesh_untouched() {
        // The corner of a lone quad (Scotty3D's refusal).
        let (mut world, built) = build(&shapes::quad_grid(1, 1));
        let corner = vertex(&built, 0);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::SingleFace(ElementId::Vertex(corner)),
            |w| dissolve_vertex(w, corner),
        );
        // A stale vertex.
        let (mut world, built) = build(&shapes::quad_grid(2, 2));
        let v = vertex(&built, 4);
        dissolve_vertex(&mut world, v).unwrap();
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Vertex(v)),
            |w| dissolve_vertex(w, v),
        );
        // A corner of a triangular hole: its two boundary neighbours are joined already.
        let (mut world, built) = build(&shapes::icosahedron());
        let f = MeshMembers::collect(&world, built.mesh).faces[0];
        let m = MeshRef::new(&world);
        let corner = m.to_vertex(m.face_halfedge(f));
        super::super::erase_faces(&mut world, &[f]).unwrap();
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::WouldDuplicateEdge(..)),
            |w| dissolve_vertex(w, corner),
        );
        // Two faces around v that share the corner (0, 0) away from v: it would be visited
        // twice.
        let (mut world, built) = build(&square_with_a_two_edge_vertex());
        let v = vertex(&built, 4);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::DegenerateFace(ElementId::Vertex(vertex(&built, 0))),
            |w| dissolve_vertex(w, v),
        );
    }

    #[test]
    fn corners_keep_their_uvs_and_the_new_side_takes_its_neighbours() {
        let (mut world, built) = build(&with_attributes(shapes::grid(2, 2), Uvs::Continuous));
        // The middle of the bottom border (boundary, three triangles), then the centre.
        for i in [1, 4] {
            dissolve_vertex(&mut world, vertex(&built, i)).unwrap();
            validate(&world, built.mesh).unwrap();
            assert_attributes_complete(&world, built.mesh);
        }
        // Every corner's UV is still `uv_at` of its vertex: 2 (x, y) + (1, 0) in the plane.
        assert_uvs_follow_positions(&world, built.mesh);
    }

    #[test]
    fn undo_and_redo_restore_both_meshes() {
        let (mut world, built) = build(&with_attributes(shapes::grid(3, 3), Uvs::Continuous));
        for i in [5, 2] {
            let plan = plan_dissolve_vertex(&world, vertex(&built, i)).unwrap();
            let seeds = plan.seeds();
            assert_undo_redo(&mut world, built.mesh, &seeds, |w| {
                apply_dissolve_vertex(w, plan);
            });
        }
    }
}
