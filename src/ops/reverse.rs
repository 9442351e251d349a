//! Reversing a mesh's orientation (Blender's Flip Normals, MeshLab's Invert Faces
//! Orientation): every face's corners in the opposite order, so every normal points the other
//! way — what a mesh read inside out (its faces wound clockwise) needs.
//!
//! On the halfedges, each one turns round: it runs from its old tip back to its old start, so
//! its `vertex` becomes its old `from_vertex` and `next` and `prev` swap; twins, edges and faces
//! stay. A vertex's outgoing halfedge becomes the twin of its old one, then its boundary one
//! where it has a boundary (the invariant [`crate::mesh::validate`] checks). A corner's UV, kept
//! on the halfedge into the corner, moves to the halfedge that now runs into it (the old
//! `prev`); vertex normals change sign; seams and face groups stay where they are.
//!
//! Every id survives and V, E, F and χ do not change; reversing twice gives back the same
//! links, UVs and normals, bit for bit. It never refuses.

use bevy::math::Vec2;
use bevy::prelude::World;

use crate::mesh::attributes::{CornerUv, VertexNormal};
use crate::mesh::elements::{Halfedge, Vertex};
use crate::mesh::ids::{HalfedgeId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::Declaration;

/// Reversing the orientation: a whole-mesh edit (every halfedge turns round) that keeps every
/// id and attribute, done in one pass, never a job.
pub const REVERSE: Declaration = Declaration::new("reverse");

/// What reversing a mesh did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReverseSummary {
    /// Faces turned round (all of them).
    pub faces: usize,
}

/// Reverses the orientation of every face of `mesh` (see the module doc).
pub fn reverse_orientation(world: &mut World, mesh: MeshId) -> ReverseSummary {
    let members = MeshMembers::collect(world, mesh);
    // Everything read before anything changes: each halfedge's new links, and the UV of the
    // corner it will run into.
    let turned: Vec<(HalfedgeId, Halfedge, Option<Vec2>)> = {
        let m = MeshRef::new(world);
        members
            .halfedges
            .iter()
            .map(|&h| {
                let old = *m.halfedge(h);
                let links = Halfedge {
                    next: old.prev,
                    prev: old.next,
                    vertex: m.halfedge(old.twin).vertex,
                    ..old
                };
                let uv = world.get::<CornerUv>(old.prev.0).map(|c| c.0);
                (h, links, uv)
            })
            .collect()
    };
    for (h, links, uv) in turned {
        if let Some(mut x) = world.get_mut::<Halfedge>(h.0) {
            *x = links;
        }
        if let (Some(uv), Some(_)) = (uv, links.face) {
            world.entity_mut(h.0).insert(CornerUv(uv));
        }
    }
    for &v in &members.vertices {
        turn_vertex(world, v);
    }
    ReverseSummary {
        faces: members.faces.len(),
    }
}

/// Points `v` at an outgoing halfedge of the reversed mesh (its boundary one, if it has one)
/// and turns its normal round.
fn turn_vertex(world: &mut World, v: VertexId) {
    let out = {
        let m = MeshRef::new(world);
        let start = m.twin(m.vertex_halfedge(v));
        m.vertex_outgoing_from(start)
            .find(|&h| m.is_boundary(h))
            .unwrap_or(start)
    };
    if let Some(mut vertex) = world.get_mut::<Vertex>(v.0) {
        vertex.halfedge = out;
    }
    if let Some(mut normal) = world.get_mut::<VertexNormal>(v.0) {
        normal.0 = -normal.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ids::FaceId;
    use crate::mesh::{MeshInfo, build_mesh, mesh_stats, shapes, validate};
    use bevy::math::Vec3;

    /// A grid with holes (so with boundaries), each corner's UV its position's x and y and each
    /// vertex's normal its position plus z, built into a world of its own.
    fn holed_grid_with_attributes() -> (World, crate::mesh::BuiltMesh) {
        let mut soup = shapes::grid_with_holes(2);
        soup.corner_uvs = Some(
            soup.indices
                .iter()
                .map(|&i| soup.positions[i as usize].truncate())
                .collect(),
        );
        soup.vertex_normals = Some(soup.positions.iter().map(|p| *p + Vec3::Z).collect());
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        (world, built)
    }

    /// Each face's corners and their UVs, in order from the face's halfedge.
    fn corners(world: &World, f: FaceId) -> Vec<(VertexId, Option<Vec2>)> {
        let m = MeshRef::new(world);
        m.face_halfedges(f)
            .map(|h| (m.to_vertex(h), world.get::<CornerUv>(h.0).map(|c| c.0)))
            .collect()
    }

    /// The same cycle read backwards: `b` is `a` reversed, up to where it starts.
    fn is_reversed_cycle<T: PartialEq + Copy>(a: &[T], b: &[T]) -> bool {
        let reversed: Vec<T> = a.iter().rev().copied().collect();
        (0..b.len()).any(|shift| (0..b.len()).all(|i| b[(i + shift) % b.len()] == reversed[i]))
    }

    #[test]
    fn every_face_turns_round_with_its_uvs_and_the_mesh_stays_valid() {
        let (mut world, built) = holed_grid_with_attributes();
        let mesh = built.mesh;
        let members = MeshMembers::collect(&world, mesh);
        let before_stats = mesh_stats(&world, mesh);
        let before: Vec<_> = members.faces.iter().map(|&f| corners(&world, f)).collect();
        let normals_before: Vec<Vec3> = {
            let m = MeshRef::new(&world);
            members
                .faces
                .iter()
                .map(|&f| m.face_area_vector(f))
                .collect()
        };
        let summary = reverse_orientation(&mut world, mesh);
        assert_eq!(summary.faces, members.faces.len());
        validate(&world, mesh).unwrap();
        let after_stats = mesh_stats(&world, mesh);
        assert_eq!(
            (after_stats.vertices, after_stats.edges, after_stats.faces),
            (
                before_stats.vertices,
                before_stats.edges,
                before_stats.faces
            )
        );
        assert_eq!(
            after_stats.euler_characteristic,
            before_stats.euler_characteristic
        );
        assert_eq!(after_stats.boundary_loops, before_stats.boundary_loops);
        let m = MeshRef::new(&world);
        for (i, &f) in members.faces.iter().enumerate() {
            // Each corner keeps its UV: the (vertex, UV) pairs run the other way round.
            assert!(is_reversed_cycle(&before[i], &corners(&world, f)), "{f}");
            let (now, then) = (m.face_area_vector(f), normals_before[i]);
            assert!(
                (now + then).length() <= 1e-6 * then.length(),
                "{f}: {now} {then}"
            );
        }
        for &v in &members.vertices {
            let p = m.position(v);
            assert_eq!(world.get::<VertexNormal>(v.0).unwrap().0, -(p + Vec3::Z));
        }
    }

    #[test]
    fn reversing_twice_gives_back_every_link_bit_for_bit() {
        let (mut world, built) = holed_grid_with_attributes();
        let members = MeshMembers::collect(&world, built.mesh);
        let snapshot = |world: &World| {
            let links: Vec<Halfedge> = members
                .halfedges
                .iter()
                .map(|&h| *world.get::<Halfedge>(h.0).unwrap())
                .collect();
            let uvs: Vec<Option<Vec2>> = members
                .halfedges
                .iter()
                .map(|&h| world.get::<CornerUv>(h.0).map(|c| c.0))
                .collect();
            let normals: Vec<Vec3> = members
                .vertices
                .iter()
                .map(|&v| world.get::<VertexNormal>(v.0).unwrap().0)
                .collect();
            (links, uvs, normals)
        };
        let before = snapshot(&world);
        reverse_orientation(&mut world, built.mesh);
        assert_ne!(snapshot(&world).0, before.0);
        reverse_orientation(&mut world, built.mesh);
        validate(&world, built.mesh).unwrap();
        let after = snapshot(&world);
        assert_eq!(after.0, before.0);
        assert_eq!(after.1, before.1);
        assert_eq!(after.2, before.2);
    }
}
