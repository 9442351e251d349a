//! Fill hole: a boundary loop becomes one polygon face.
//!
//! ```text
//!   d ------ c          d ------ c
//!   |        |          |        |
//!   |  hole  |    →     |   f    |     the loop a b c d (boundary halfedges) gets a face
//!   |        |          |        |
//!   a ------ b          a ------ b
//! ```
//!
//! The loop's halfedges keep their entities and links and take the new face; nothing else
//! changes but the vertices' outgoing halfedges: a vertex of the loop that is still on the
//! boundary (another loop passes through it) points to that loop's outgoing halfedge, as every
//! boundary vertex must. Counts: one face more, χ up by one, one boundary loop fewer. The face is
//! a polygon of as many sides as the loop had; triangulate it (Ctrl+T) for triangles.
//!
//! Refusals (each leaves the world untouched):
//! - `Stale`: `e` is not a live edge;
//! - `NotBoundary`: `e` is not on the boundary (no hole beside it).

use bevy::prelude::World;

use crate::mesh::elements::{Face, InMesh, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;

use super::{Refusal, he, live_edge, spawn_at};

/// What filling a hole touches, collected by [`plan_fill_hole`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FillHolePlan {
    mesh: MeshId,
    /// The boundary loop, in `next` order.
    ring: Vec<HalfedgeId>,
}

impl FillHolePlan {
    /// The mesh the hole is in.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }

    /// The boundary loop, in `next` order (the new face's halfedges).
    pub fn ring(&self) -> &[HalfedgeId] {
        &self.ring
    }
}

/// Checks that the boundary loop beside `e` can be filled.
///
/// # Refusals
/// See the module doc.
pub fn plan_fill_hole(world: &World, e: EdgeId) -> Result<FillHolePlan, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    let start = if m.is_boundary(h) {
        h
    } else if m.is_boundary(m.twin(h)) {
        m.twin(h)
    } else {
        return Err(Refusal::NotBoundary(ElementId::Edge(e)));
    };
    let mesh = world
        .get::<InMesh>(e.0)
        .ok_or(Refusal::Stale(ElementId::Edge(e)))?
        .0;
    Ok(FillHolePlan {
        mesh,
        ring: m.loop_from(start).collect(),
    })
}

/// Carries out a fill planned by [`plan_fill_hole`]. Returns the new face.
pub fn apply_fill_hole(world: &mut World, plan: FillHolePlan) -> FaceId {
    // Each new corner takes the UV its vertex has in the face across the boundary edge (the
    // corner before the twin): the fill continues the texture of its rim.
    let uvs: Option<Vec<_>> = crate::mesh::attributes::MeshAttributes::of(world, plan.mesh)
        .uv
        .then(|| {
            let m = MeshRef::new(world);
            plan.ring
                .iter()
                .map(|&h| {
                    crate::mesh::attributes::corner_uv(world, m.prev(m.twin(h))).unwrap_or_default()
                })
                .collect()
        });
    let face = FaceId(world.entity_allocator().alloc());
    for &h in &plan.ring {
        he(world, h).face = Some(face);
    }
    for (&h, uv) in plan.ring.iter().zip(uvs.into_iter().flatten()) {
        crate::mesh::attributes::set_corner_uv(world, h, uv);
    }
    spawn_at(
        world,
        face.0,
        (
            Face {
                halfedge: plan.ring[0],
            },
            InMesh(plan.mesh),
        ),
    );
    // Each vertex of the loop was pointing to its outgoing boundary halfedge, now interior:
    // it keeps one that is still on the boundary, if another loop passes through it.
    let vertices: Vec<VertexId> = {
        let m = MeshRef::new(world);
        plan.ring.iter().map(|&h| m.from_vertex(h)).collect()
    };
    for v in vertices {
        let m = MeshRef::new(world);
        if let Some(out) = m.vertex_outgoing(v).find(|&h| m.is_boundary(h)) {
            world.get_mut::<Vertex>(v.0).expect("planned").halfedge = out;
        }
    }
    face
}

/// Fills the boundary loop beside `e` with one face. Returns the face.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn fill_hole(world: &mut World, e: EdgeId) -> Result<FaceId, Refusal> {
    let plan = plan_fill_hole(world, e)?;
    Ok(apply_fill_hole(world, plan))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, mesh_stats, shapes, validate};

    #[test]
    fn a_grids_border_becomes_one_face_and_closes_the_surface() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(2, 2), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        let (a, b) = (
            built.input_vertices[0].unwrap(),
            built.input_vertices[1].unwrap(),
        );
        let e = m.edge(m.find_halfedge(a, b).unwrap());
        let before = mesh_stats(&world, built.mesh);
        let f = fill_hole(&mut world, e).unwrap();
        validate(&world, built.mesh).unwrap();
        let after = mesh_stats(&world, built.mesh);
        assert_eq!(MeshRef::new(&world).face_degree(f), 8);
        assert_eq!(after.faces, before.faces + 1);
        assert_eq!((after.boundary_loops, after.euler_characteristic), (0, 2));
        assert!(after.closed);
    }

    #[test]
    fn an_interior_edge_is_refused_and_changes_nothing() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosahedron(), MeshInfo::default()).unwrap();
        let e = crate::mesh::MeshMembers::collect(&world, built.mesh).edges[0];
        assert_eq!(
            fill_hole(&mut world, e),
            Err(Refusal::NotBoundary(ElementId::Edge(e)))
        );
        assert_eq!(mesh_stats(&world, built.mesh).faces, 20);
    }

    #[test]
    fn filling_one_of_several_loops_leaves_the_others_open() {
        let mut world = World::new();
        let built =
            build_mesh(&mut world, &shapes::grid_with_holes(2), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        let members = crate::mesh::MeshMembers::collect(&world, built.mesh);
        let boundary = members
            .edges
            .iter()
            .copied()
            .find(|&e| m.is_boundary_edge(e))
            .unwrap();
        let before = mesh_stats(&world, built.mesh);
        fill_hole(&mut world, boundary).unwrap();
        validate(&world, built.mesh).unwrap();
        let after = mesh_stats(&world, built.mesh);
        assert_eq!(after.boundary_loops, before.boundary_loops - 1);
        assert_eq!(after.euler_characteristic, before.euler_characteristic + 1);
    }
}
