//! Discrete differential geometry on a mesh's triangles: normals, curvature, and the per-vertex
//! quantities the editor colours by and the command line exports.
//!
//! Everything here is computed on a [`Surface`], the mesh's triangles as flat `f64` arrays by
//! table row, and returns one value per vertex (or face) row: the caller maps rows back to
//! entities through the tables' members.

pub mod carry;
pub mod closest;
pub mod cotan;
pub mod curvature;
pub mod intrinsic;
pub mod normals;
pub mod quantity;
pub mod stored;
pub mod surface;
pub mod surface_fit;

pub use cotan::cotan_edges;
pub use curvature::{Curvature, curvature, mixed_areas, scalar_curvature};
pub use normals::{NormalWeighting, face_normals, vertex_normals, vertex_normals_by_angle};
pub use quantity::Quantity;
pub use surface::Surface;
