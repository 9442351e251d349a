//! Listing the elements of one mesh.
//!
//! Every element carries [`InMesh`]; these queries filter on it and on the element's kind
//! component (in Bevy 0.19 resources are entities too, so a bare `Query<Entity>` would match
//! them). Order is the world's storage order: spawn order for a freshly built mesh.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::{Entity, World};

use super::elements::{Edge, Face, Halfedge, InMesh, Vertex};
use super::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};

/// The elements of one mesh, by kind.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshMembers {
    /// Its vertices.
    pub vertices: Vec<VertexId>,
    /// Its halfedges.
    pub halfedges: Vec<HalfedgeId>,
    /// Its edges.
    pub edges: Vec<EdgeId>,
    /// Its faces.
    pub faces: Vec<FaceId>,
}

impl MeshMembers {
    /// Lists every element of `mesh` (O(elements in the world)).
    pub fn collect(world: &World, mesh: MeshId) -> Self {
        Self {
            vertices: of_kind::<Vertex, _>(world, mesh, VertexId),
            halfedges: of_kind::<Halfedge, _>(world, mesh, HalfedgeId),
            edges: of_kind::<Edge, _>(world, mesh, EdgeId),
            faces: of_kind::<Face, _>(world, mesh, FaceId),
        }
    }

    /// Each vertex's position in [`MeshMembers::vertices`], by entity.
    pub fn vertex_rows(&self) -> EntityHashMap<u32> {
        self.vertices
            .iter()
            .enumerate()
            .map(|(i, v)| (v.0, i as u32))
            .collect()
    }

    /// Every element entity.
    pub fn entities(&self) -> impl Iterator<Item = Entity> + '_ {
        self.vertices
            .iter()
            .map(|v| v.0)
            .chain(self.halfedges.iter().map(|h| h.0))
            .chain(self.edges.iter().map(|e| e.0))
            .chain(self.faces.iter().map(|f| f.0))
    }
}

/// The entities of kind `K` in `mesh`, wrapped as ids.
pub fn of_kind<K: bevy::prelude::Component, T>(
    world: &World,
    mesh: MeshId,
    wrap: fn(Entity) -> T,
) -> Vec<T> {
    let Some(mut query) = world.try_query_filtered::<(Entity, &InMesh), bevy::prelude::With<K>>()
    else {
        return Vec::new();
    };
    query
        .iter(world)
        .filter(|(_, m)| m.0 == mesh)
        .map(|(e, _)| wrap(e))
        .collect()
}

/// Every mesh entity in the world.
pub fn meshes(world: &World) -> Vec<MeshId> {
    let Some(mut query) =
        world.try_query_filtered::<Entity, bevy::prelude::With<super::elements::MeshInfo>>()
    else {
        return Vec::new();
    };
    query.iter(world).map(MeshId).collect()
}
