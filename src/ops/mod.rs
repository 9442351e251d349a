//! Operations on the entity mesh.
//!
//! The contract, in Scotty3D's words and PMP's shape: **check, then mutate; a refusal is a
//! value.** Each operation has a read-only `plan_*` that validates its input and collects every
//! id it will touch, returning a [`Refusal`] when the result would not be a valid mesh, and an
//! `apply_*` that cannot fail on a plan just made. A refused operation leaves the world exactly
//! as it was.
//!
//! Operations are plain functions over `&World` / `&mut World`, callable from a unit test, the
//! command line and the editor alike; the editor's systems are thin adapters around them.

pub mod indexed_heap;
pub mod local;
pub mod progressive;
pub mod remesh;
pub mod simplify;
pub mod subdivide;
pub mod table_split;
pub mod triangulate;

use crate::mesh::ids::ElementId;
use thiserror::Error;

/// Why an operation was not carried out. Expected, shown to the user, never a bug.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum Refusal {
    /// The id names no live element of the expected kind (despawned, or never existed).
    #[error("{0} does not exist (stale or wrong id)")]
    Stale(ElementId),
    /// The operation does not apply to a boundary edge.
    #[error("{0} is a boundary edge")]
    BoundaryEdge(ElementId),
    /// An endpoint would be left with too few edges.
    #[error("{0} would be left with fewer than {1} edges")]
    ValenceTooLow(ElementId, usize),
    /// The edge the operation would create already exists.
    #[error("the new edge would duplicate the existing edge between {0} and {1}")]
    WouldDuplicateEdge(ElementId, ElementId),
    /// A collapse whose endpoints share neighbours other than the opposite vertices of its
    /// faces: the result would be non-manifold.
    #[error("link condition fails: {0} is a neighbour of both endpoints")]
    LinkCondition(ElementId),
    /// The operation would leave a face with fewer than 3 sides.
    #[error("{0} would be left with fewer than 3 sides")]
    DegenerateFace(ElementId),
    /// Collapsing would shrink a closed mesh below a tetrahedron.
    #[error("the mesh is a tetrahedron: any collapse would make it degenerate")]
    TooSmall,
    /// A collapse would join two boundary vertices through the interior (pinching the surface).
    #[error(
        "both endpoints are on the boundary but the edge is not: the collapse would pinch the surface"
    )]
    BoundaryPinch,
    /// A face's normal would turn over (more than the allowed angle).
    #[error("{0} would flip over")]
    NormalFlip(ElementId),
    /// Removing a triangle would leave an edge with no face on either side.
    #[error("collapsing would leave an edge of {0} with no face on either side")]
    DanglingEdge(ElementId),
    /// The operation needs triangles.
    #[error("{0} is not a triangle (triangulate first)")]
    NotTriangle(ElementId),
    /// The input is otherwise unsuitable; the text says why.
    #[error("{0}")]
    Unsuitable(String),
}
