//! Polygon soup → entities (with repairs), and entities → polygon soup.
//!
//! [`build_mesh`] is the one way a mesh enters a world: it repairs the soup
//! ([`super::repair`]), lays out the halfedge tables ([`Connectivity::from_corners`]) and
//! spawns them ([`spawn_connectivity`]). Every element is spawned once, already linked, so no
//! element is ever seen half-built. The flat tables, and the passes between them and the
//! entities, live in [`super::tables`]; this module only joins the soup to them.

use bevy::prelude::World;
use thiserror::Error;

use super::elements::MeshInfo;
use super::ids::{MeshId, VertexId};
use super::members::MeshMembers;
use super::repair::{RepairReport, repair};
use super::soup::PolygonSoup;
use super::tables::{Connectivity, NONE, spawn_connectivity};
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
    let connectivity = Connectivity::from_corners(faces.corners());
    let (mesh, rows) = spawn_connectivity(world, &connectivity, info);
    let vertices = rows.vertices;
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

/// The mesh as a polygon soup: vertices in table order, faces as vertex cycles. The inverse of
/// [`build_mesh`] up to the repairs.
pub fn to_soup(world: &World, mesh: MeshId) -> PolygonSoup {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let index = members.vertex_rows();
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
