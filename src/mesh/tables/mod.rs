//! The flat-table layer: a mesh as plain index tables, the step between faces and entities.
//!
//! Whole-mesh work (loading, subdivision, simplification's setup, progressive refinement, the
//! remesher's passes, undo of a global edit) reads or writes every element at once, and that
//! goes much faster on arrays than entity by entity. This module owns that form of a mesh and
//! the two ways across to the entities:
//!
//! - [`rows`]: typed row indices ([`VertexRow`], [`HalfedgeRow`], [`EdgeRow`], [`FaceRow`]),
//!   [`RowCounts`] and [`NONE`].
//! - [`connectivity`]: the tables ([`Connectivity`]), built from face corners
//!   ([`Connectivity::from_corners`]), with PMP-style navigation on typed rows.
//! - [`read`]: entities → tables ([`extract`], giving [`MeshTables`]: the tables with the entity
//!   behind every row).
//! - [`mod@write`]: tables → entities ([`spawn_connectivity`], [`replace_contents`] and the two
//!   passes under them, `reserve_rows` and `write_links`).
//! - [`spawn`]: tables → a new mesh in one pass, each link written as its row is spawned
//!   ([`spawn_tables`]): what a load uses.
//! - [`gradual`]: entities → tables a slice at a time ([`GradualRead`]), for a reader that may
//!   not hold a frame for the whole mesh.
//!
//! # Layout
//! Four kinds of rows, each numbered from 0: vertices, halfedges, edges, faces. The tables hold
//! exactly the links the entity components hold ([`crate::mesh::Vertex`],
//! [`crate::mesh::Halfedge`], …), with a row in place of each entity: per vertex its position
//! and outgoing halfedge; per halfedge its twin, next, prev, tip vertex, edge and face; per edge
//! and per face one halfedge. [`NONE`] (`u32::MAX`) stands for "no row": a boundary halfedge's
//! face, and in the corner tables a missing twin.
//!
//! # Invariants
//! Tables that come from [`extract`] of a valid mesh, from [`Connectivity::from_corners`], or
//! from an operation here, describe a mesh that passes [`crate::mesh::validate()`] once written:
//! links are mutual, faces and vertex fans close, a boundary vertex's halfedge is its outgoing
//! boundary halfedge and an edge's halfedge is an interior one where it has one. Tables laid out
//! by [`Connectivity::from_corners`] also keep the face corners first (halfedge `c` is corner
//! `c`), boundary halfedges after them. Extracted tables keep the world's storage order of each
//! kind; [`MeshTables::members`] says which entity is behind each row.
//!
//! Nothing here knows of operations, files or rendering; [`super::repair`] and
//! [`super::build`] sit above it.

pub mod connectivity;
pub mod gradual;
pub mod read;
pub mod rows;
pub mod spawn;
pub mod write;

pub use connectivity::{Connectivity, FaceCorners, HalfedgeLinks};
pub use gradual::{GradualRead, ReadBroken};
pub use read::{EntityRows, MeshTables, extract};
pub use rows::{EdgeRow, FaceRow, HalfedgeRow, NONE, RowCounts, VertexRow};
pub use spawn::{SpawnedRows, spawn_tables};
pub use write::{replace_contents, spawn_connectivity};
