//! Polygon soup → entities (with repairs), and entities → polygon soup.
//!
//! [`build_mesh`] is the one way a mesh enters a world: it repairs the soup
//! ([`super::repair`]), lays out the halfedge tables ([`super::connectivity`]) and spawns them
//! ([`spawn_connectivity`]). Ids are allocated first and every element is spawned once, already
//! linked, so no element is ever seen half-built.

use bevy::prelude::{Entity, World};
use thiserror::Error;

use super::connectivity::Connectivity;
use super::elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
use super::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use super::members::MeshMembers;
use super::repair::{NONE, RepairReport, repair};
use super::soup::PolygonSoup;
use super::topology::MeshRef;

/// Why a soup could not become a mesh at all (local defects are repaired, not errors).
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BuildError {
    /// Nothing was left to build after the repairs (or the input had no faces).
    #[error("no usable faces: {faces} face(s) in the input, {report}")]
    NoFaces {
        /// Faces in the input.
        faces: usize,
        /// What the repair dropped.
        report: RepairReport,
    },
    /// The mesh is larger than 32-bit indices can address.
    #[error("mesh too large: {0} face corners (the limit is 2^31)")]
    TooLarge(usize),
}

/// A freshly built mesh and what it took to build it.
#[derive(Clone, Debug)]
pub struct BuiltMesh {
    /// The new mesh entity.
    pub mesh: MeshId,
    /// Every repair made on the way.
    pub report: RepairReport,
    /// For each vertex of the input soup, the vertex it became (`None` if dropped). Lets scripts
    /// name elements by their index in the input file.
    pub input_vertices: Vec<Option<VertexId>>,
}

/// Builds a mesh from `soup` into `world`, repairing what it must (see [`super::repair`]).
///
/// # Errors
/// [`BuildError::NoFaces`] if no face survives the repairs; the world is then untouched.
pub fn build_mesh(
    world: &mut World,
    soup: &PolygonSoup,
    info: MeshInfo,
) -> Result<BuiltMesh, BuildError> {
    if soup.indices.len() >= 1 << 31 {
        return Err(BuildError::TooLarge(soup.indices.len()));
    }
    let (faces, report) = repair(soup);
    if faces.face_count() == 0 {
        return Err(BuildError::NoFaces {
            faces: soup.face_count(),
            report,
        });
    }
    let connectivity = Connectivity::from_repaired(&faces);
    let (mesh, vertices) = spawn_connectivity(world, &connectivity, info);
    let input_vertices = faces
        .input_vertex
        .iter()
        .map(|&v| (v != NONE).then(|| vertices[v as usize]))
        .collect();
    Ok(BuiltMesh {
        mesh,
        report,
        input_vertices,
    })
}

/// Spawns halfedge tables as a new mesh: one entity per element, all links set. Returns the
/// mesh and the vertex entities in table order.
///
/// The tables must be consistent (as [`Connectivity::from_repaired`] makes them); the result is
/// then a mesh that passes [`super::validate`].
pub fn spawn_connectivity(
    world: &mut World,
    c: &Connectivity,
    info: MeshInfo,
) -> (MeshId, Vec<VertexId>) {
    let mesh = MeshId(world.spawn(info).id());
    let ids = allocate(world, c);
    spawn_into(world, c, &ids, mesh, 0);
    (mesh, ids.vertices)
}

/// Entities for every element of a [`Connectivity`], allocated before any is spawned so that
/// elements can name each other.
pub(crate) struct AllocatedIds {
    pub vertices: Vec<VertexId>,
    pub halfedges: Vec<HalfedgeId>,
    pub edges: Vec<EdgeId>,
    pub faces: Vec<FaceId>,
}

pub(crate) fn allocate(world: &World, c: &Connectivity) -> AllocatedIds {
    fn take<T>(world: &World, n: usize, wrap: fn(Entity) -> T) -> Vec<T> {
        world
            .entity_allocator()
            .alloc_many(n as u32)
            .map(wrap)
            .collect()
    }
    AllocatedIds {
        vertices: take(world, c.vertex_count(), VertexId),
        halfedges: take(world, c.halfedge_count(), HalfedgeId),
        edges: take(world, c.edge_count(), EdgeId),
        faces: take(world, c.face_count(), FaceId),
    }
}

/// Spawns every element of `c` at its allocated id, except the first `existing_vertices`
/// vertices, which already exist.
pub(crate) fn spawn_into(
    world: &mut World,
    c: &Connectivity,
    ids: &AllocatedIds,
    mesh: MeshId,
    existing_vertices: usize,
) {
    let member = InMesh(mesh);
    let h = |i: u32| ids.halfedges[i as usize];
    for (i, &v) in ids.vertices.iter().enumerate().skip(existing_vertices) {
        let bundle = (
            Vertex {
                halfedge: h(c.vertex_halfedge[i]),
            },
            Position(c.positions[i]),
            member,
        );
        spawn(world, v.0, bundle);
    }
    for (i, &id) in ids.halfedges.iter().enumerate() {
        let face = c.face[i];
        let bundle = (
            Halfedge {
                twin: h(c.twin[i]),
                next: h(c.next[i]),
                prev: h(c.prev[i]),
                vertex: ids.vertices[c.to_vertex[i] as usize],
                edge: ids.edges[c.edge[i] as usize],
                face: (face != NONE).then(|| ids.faces[face as usize]),
            },
            member,
        );
        spawn(world, id.0, bundle);
    }
    for (i, &e) in ids.edges.iter().enumerate() {
        let bundle = (
            Edge {
                halfedge: h(c.edge_halfedge[i]),
            },
            member,
        );
        spawn(world, e.0, bundle);
    }
    for (i, &f) in ids.faces.iter().enumerate() {
        let bundle = (
            Face {
                halfedge: h(c.face_halfedge[i]),
            },
            member,
        );
        spawn(world, f.0, bundle);
    }
}

fn spawn<B: bevy::prelude::Bundle>(world: &mut World, entity: Entity, bundle: B) {
    if let Err(error) = world.spawn_at(entity, bundle) {
        // The ids came from this world's allocator a moment ago: failing here is a bug.
        unreachable!("spawning a freshly allocated element {entity} failed: {error}");
    }
}

/// The mesh as a polygon soup: vertices in table order, faces as vertex cycles. The inverse of
/// [`build_mesh`] up to the repairs.
pub fn to_soup(world: &World, mesh: MeshId) -> PolygonSoup {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let index: bevy::ecs::entity::EntityHashMap<u32> = members
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (v.0, i as u32))
        .collect();
    let mut soup = PolygonSoup::with_capacity(
        members.vertices.len(),
        members.faces.len(),
        members.halfedges.len(),
    );
    soup.positions
        .extend(members.vertices.iter().map(|&v| m.position(v)));
    let mut face = Vec::new();
    for &f in &members.faces {
        face.clear();
        // Start one halfedge back so the face lists its vertices in the order it was built from.
        let first = m.prev(m.face_halfedge(f));
        face.extend(m.loop_from(first).map(|h| index[&m.to_vertex(h).0]));
        soup.push_face(&face);
    }
    soup
}

/// Despawns a mesh and every element in it. Returns how many entities went.
pub fn despawn_mesh(world: &mut World, mesh: MeshId) -> usize {
    let members = MeshMembers::collect(world, mesh);
    let mut count = 0;
    for e in members.entities() {
        count += usize::from(world.despawn(e));
    }
    count + usize::from(world.despawn(mesh.0))
}
