//! The components that make an entity a mesh element, and the mesh entity itself.
//!
//! One component per element kind holds all of that element's links, so one lookup returns them
//! together and an operation rewires a halfedge with one write:
//!
//! | kind     | components                                   |
//! |----------|----------------------------------------------|
//! | vertex   | [`Vertex`], [`Position`], [`InMesh`]         |
//! | halfedge | [`Halfedge`], [`InMesh`]                     |
//! | edge     | [`Edge`], [`InMesh`]                         |
//! | face     | [`Face`], [`InMesh`]                         |
//! | mesh     | [`MeshInfo`]                                 |
//!
//! Element entities carry no `Transform`, `Visibility` or render mesh: they are data. The editor
//! draws each mesh with one render entity of its own.

use super::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use bevy::math::Vec3;
use bevy::prelude::Component;
use std::path::PathBuf;

/// A vertex: its outgoing halfedge. On a boundary vertex this is always the outgoing boundary
/// halfedge, so [`crate::mesh::MeshRef::is_boundary_vertex`] is one lookup.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Vertex {
    /// An outgoing halfedge (`from_vertex == this vertex`); the boundary one if there is one.
    #[entities]
    pub halfedge: HalfedgeId,
}

/// A vertex position.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Position(pub Vec3);

/// A halfedge: one side of an edge, pointing at `vertex`.
///
/// `face` is `None` on a boundary halfedge: boundary loops are the `next` cycles of halfedges
/// without a face (the PMP and geometry-central convention), so no fake face entities exist.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Halfedge {
    /// The opposite halfedge of the same edge.
    #[entities]
    pub twin: HalfedgeId,
    /// The next halfedge around the face (or boundary loop).
    #[entities]
    pub next: HalfedgeId,
    /// The previous halfedge around the face (or boundary loop).
    #[entities]
    pub prev: HalfedgeId,
    /// The vertex this halfedge points to (its tip, PMP's `to_vertex`).
    #[entities]
    pub vertex: VertexId,
    /// The edge this halfedge is one side of.
    #[entities]
    pub edge: EdgeId,
    /// The face to the left, or `None` on the boundary.
    #[entities]
    pub face: Option<FaceId>,
}

/// An edge: one of its two halfedges (an interior one where there is one).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// One of the two halfedges.
    #[entities]
    pub halfedge: HalfedgeId,
}

/// A face: one of the halfedges around it.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Face {
    /// A halfedge whose `face` is this face.
    #[entities]
    pub halfedge: HalfedgeId,
}

/// Which mesh an element belongs to.
///
/// A plain component rather than a Bevy relationship: the relationship's hooks cost ~0.6 µs per
/// spawn against ~0.1 µs without (measured in `shared/reference/anchors.md`), and building the
/// bunny spawns about 420 000 elements. A mesh's elements are despawned by
/// [`crate::mesh::despawn_mesh`].
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InMesh(#[entities] pub MeshId);

/// The mesh entity: what a set of elements is called and where it came from.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct MeshInfo {
    /// A display name (the file name, or the shape's name).
    pub name: String,
    /// The file the mesh was read from, if any.
    pub path: Option<PathBuf>,
}
