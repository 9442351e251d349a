//! [`Refusal`]: why an operation was not carried out, a value every operation returns rather
//! than a panic (Scotty3D's "check, then mutate"; see [`super`]).
//!
//! It sits in a module of its own, at the bottom of `ops`, so that what needs only the reason
//! need not import the operations: the memory budget's own error ([`OverBudget`]) and the
//! parameterization's ([`ParamError`](super::param::ParamError)) convert into it.

use thiserror::Error;

use crate::memory_budget::OverBudget;
use crate::mesh::ids::ElementId;

/// Why an operation was not carried out. Expected, shown to the user, never a bug.
#[derive(Clone, Debug, PartialEq, Error)]
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
    /// The operation needs a boundary edge (a hole beside it).
    #[error("{0} is not on the boundary")]
    NotBoundary(ElementId),
    /// There is no mesh to act on.
    #[error("there is no mesh")]
    NoMesh,
    /// A position or a parameter that would put a point at infinity or NaN.
    #[error("{0} is not a finite position")]
    NotFinite(bevy::math::Vec3),
    /// A parameter out of its range; the text names it and the range.
    #[error("{0}")]
    BadParameter(String),
    /// A split parameter outside the open interval (0, 1).
    #[error("split parameter {0} is not strictly between 0 and 1")]
    SplitParameter(f32),
    /// The split point would coincide with an end of the edge (the edge is too short for the
    /// floating-point grid there).
    #[error("the split point would coincide with an endpoint of {0}")]
    SplitAtEndpoint(ElementId),
    /// The vertex is not a corner of the face.
    #[error("{0} is not a corner of {1}")]
    NotACorner(ElementId, ElementId),
    /// The result would need more rows than 32-bit indices address.
    #[error("the result would have {0} halfedges, more than 32-bit indices can address")]
    TooLarge(usize),
    /// The result would take more memory than the budget allows
    /// ([`crate::memory_budget`]); the text gives the estimate, the limit and what to do.
    #[error("{0}")]
    OverBudget(String),
    /// The progress callback asked a long edit to stop before it changed anything.
    #[error("stopped by the progress callback before anything changed")]
    Stopped,
    /// A collapse that removed a polygon corner: only triangle collapses can be split back.
    #[error("this collapse removed a polygon corner: only triangle collapses can be split back")]
    NotInvertible,
    /// The simplification history no longer describes the mesh (it was edited since); the
    /// text names what no longer fits.
    #[error("the simplification history no longer fits the mesh: {0}")]
    HistoryMismatch(String),
    /// There is no simplification history to move along.
    #[error("no simplification to move along: simplify first")]
    NoHistory,
    /// The mesh is already at the full level of its simplification history.
    #[error("the mesh is at its full level")]
    AtFullLevel,
    /// Only the vertex kept by the last collapse can be split back.
    #[error("{0} is not the next vertex to split (that is {1}); use the level slider")]
    NotNextSplit(ElementId, ElementId),
    /// A lab's operation checked against its reference ([`crate::edit::lab`]) left an invalid
    /// mesh, panicked, or was refused where the reference applies: the text is the lab's
    /// report.
    #[error("{0}")]
    Lab(String),
    /// A checked low-level edit ([`RawEdit`](crate::mesh::RawEdit)) broke a rule at its
    /// commit, and was rolled back: the element and the rule.
    #[error("the edit would break the mesh: {0}")]
    Broken(crate::mesh::Invalid),
    /// The mesh breaks an invariant (the text says which, and where).
    #[error("invalid: {0}")]
    Invalid(String),
    /// A `process` step names a vertex number the input file does not have.
    #[error("the input has no vertex {0}")]
    NoInputVertex(u32),
    /// A `process` step names two input vertices that share no edge.
    #[error("input vertices {0} and {1} share no edge")]
    NoEdgeBetween(u32, u32),
    /// The mesh cannot be parameterized as it is (the text says why and how to fix it).
    #[error(transparent)]
    Param(#[from] crate::ops::param::ParamError),
    /// A `process` step names two input vertices that share no face.
    #[error("input vertices {0} and {1} share no face")]
    NoSharedFace(u32, u32),
    /// The selected faces around the named one make up a whole closed surface: an extrusion
    /// needs a rim (an edge with a selected face on one side only) to raise its walls from.
    #[error("the selection around {0} is a whole closed surface: there is no rim to extrude from")]
    ClosedRegion(ElementId),
    /// The vertex would touch the boundary twice (two boundary gaps in its fan): the surface
    /// would be pinched there, a non-manifold vertex.
    #[error("{0} would touch the boundary twice (the surface would be pinched there)")]
    PinchedVertex(ElementId),
    /// The operation would leave the mesh without a face.
    #[error("the mesh would be left with no faces")]
    NoFacesLeft,
    /// A boundary vertex with a single face: dissolving it has no faces to merge and would only
    /// cut that face's corner off.
    #[error("{0} is the corner of a single face: there are no faces around it to merge")]
    SingleFace(ElementId),
}

impl From<OverBudget> for Refusal {
    fn from(e: OverBudget) -> Self {
        Refusal::OverBudget(e.0)
    }
}

/// A raw edit's error as an operation's refusal, so that an operation written with
/// [`RawEdit`](crate::mesh::RawEdit) (a lab's flip) can pass its errors on with `?`: an
/// element not of the mesh is stale, a position not finite is said so, a broken rule is
/// [`Refusal::Broken`].
impl From<crate::mesh::RawEditError> for Refusal {
    fn from(e: crate::mesh::RawEditError) -> Self {
        use crate::mesh::RawEditError as E;
        match e {
            E::NotInMesh(x) => Refusal::Stale(x),
            E::NotFinite(_, p) | E::NewVertexNotFinite(p) => Refusal::NotFinite(p),
            E::Invalid(invalid) => Refusal::Broken(invalid),
        }
    }
}
