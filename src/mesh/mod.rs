//! The data model: a halfedge mesh whose every element is an ECS entity.
//!
//! # Glossary and conventions
//! - A **halfedge** points from one vertex to another (its tip is [`Halfedge::vertex`], PMP's
//!   `to_vertex`); its **twin** points back. An **edge** is the pair. A **face** is the `next`
//!   cycle of its halfedges, counter-clockwise seen from outside.
//! - **Boundary**: a halfedge with `face: None`. The `next` cycles of boundary halfedges are the
//!   boundary loops; there are no fake boundary faces. A boundary vertex's [`Vertex::halfedge`]
//!   is its outgoing boundary halfedge, so `is_boundary` is O(1) for halfedges, edges and
//!   vertices.
//! - Every element carries [`InMesh`]: several meshes can share a world.
//!
//! # Invariants
//! Every mesh built by [`build::build_mesh`] and left by an operation passes
//! [`validate::validate`]: links are mutual, faces and vertex fans close, every vertex is
//! manifold (one fan), no two edges join the same vertices, faces have ≥ 3 sides.
//!
//! Whole-mesh work reads and writes a mesh in bulk through its flat-table form, [`tables`]:
//! index tables with typed rows, and the two passes between them and the entities.
//!
//! This module knows nothing of operations, files or rendering.

pub mod attributes;
pub mod build;
pub mod change;
pub mod closure;
pub mod despawn;
pub mod elements;
pub mod groups;
pub mod ids;
pub mod loops;
pub mod members;
pub mod raw_edit;
pub mod repair;
pub mod shapes;
pub mod soup;
pub mod stats;
pub mod tables;
pub mod topology;
pub mod untangle;
pub mod validate;
pub mod validate_edit;

pub use build::{
    BuildError, BuiltMesh, PreparedMesh, build_mesh, despawn_mesh, prepare_mesh, soup_of_tables,
    spawn_prepared, to_soup,
};
pub use elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
pub use ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
pub use members::MeshMembers;
pub use raw_edit::{Journal, RawEdit, RawEditError};
pub use repair::RepairReport;
pub use soup::PolygonSoup;
pub use stats::{MeshStats, mesh_stats, stats_of_tables};
pub use topology::MeshRef;
pub use validate::{Invalid, Rule, validate, validate_without};
