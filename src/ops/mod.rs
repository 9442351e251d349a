//! Operations on the entity mesh.
//!
//! The contract, in Scotty3D's words and PMP's shape: **check, then mutate; a refusal is a
//! value.** Each operation has a read-only `plan_*` that validates its input and collects every
//! id it will touch, returning a [`Refusal`] when the result would not be a valid mesh, and an
//! `apply_*` that cannot fail on a plan just made. A refused operation leaves the world exactly
//! as it was.
//!
//! Operations are plain functions over `&World` / `&mut World`, callable from a unit test, the
//! command line and the editor alike; the editor's systems are thin adapters around them. The
//! ones that declare themselves whole are listed in the process's [`registry`], which takes
//! operations from other crates too.

pub mod decimate;
pub mod declaration;
pub mod deform;
pub mod geodesic;
pub mod geometry;
pub mod hole;
pub mod indexed_heap;
pub mod local;
pub mod named;
pub mod normalize;
pub mod operation;
pub(crate) mod parallel;
pub mod param;
pub mod progressive;
pub mod refusal;
pub mod registry;
pub mod remesh;
pub mod reverse;
pub mod simplification_history;
pub mod simplify;
pub mod smooth;
pub mod subdivide;
pub mod table_split;
pub mod triangulate;

/// Why an operation was not carried out (defined in [`refusal`], which imports nothing else
/// of `ops` but the parameterization's error it wraps).
pub use refusal::Refusal;
