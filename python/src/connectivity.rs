//! `Mesh.connectivity()`: the halfedge structure as `NumPy` arrays, one per link.
//!
//! The core already keeps a mesh's links as flat tables with a row in place of each entity
//! ([`pappus::mesh::tables`]); this hands those tables over as int64 arrays, one conversion per
//! table and no Python object per element. The rows are the rows of `Mesh.vertices` and
//! `Mesh.faces` (both come from [`MeshMembers::collect`](pappus::mesh::MeshMembers::collect)'s
//! order), and a face's halfedge is the one leaving the first corner `Mesh.faces` lists, so
//! walking `next` from `face_halfedge[f]` visits the corners of `faces[f]` in order (each
//! halfedge's tail, `from_vertex`, is the corner). "No row" (a boundary halfedge's face, an
//! isolated vertex's halfedge) is −1, the `NumPy` convention, where the core writes
//! [`NONE`](pappus::mesh::tables::NONE).

use bevy::prelude::World;
use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;

use pappus::mesh::MeshId;
use pappus::mesh::tables::{NONE, extract};

/// The halfedge structure of a mesh as it was when `Mesh.connectivity()` was called: int64
/// arrays indexed by row (halfedge rows for the per-halfedge arrays, vertex, edge and face rows
/// for the others), −1 where there is no element. A snapshot: an edit of the mesh later does
/// not change it.
#[pyclass(module = "pappus", name = "Connectivity", frozen)]
pub struct ConnectivityArrays {
    /// Per halfedge: the next halfedge around its face (or its boundary loop).
    #[pyo3(get)]
    next: Py<PyArray1<i64>>,
    /// Per halfedge: the previous halfedge around its face (or its boundary loop).
    #[pyo3(get)]
    prev: Py<PyArray1<i64>>,
    /// Per halfedge: the opposite halfedge of its edge.
    #[pyo3(get)]
    twin: Py<PyArray1<i64>>,
    /// Per halfedge: the vertex it points to (its tip).
    #[pyo3(get)]
    to_vertex: Py<PyArray1<i64>>,
    /// Per halfedge: the vertex it leaves (its tail: `to_vertex[twin]`).
    #[pyo3(get)]
    from_vertex: Py<PyArray1<i64>>,
    /// Per halfedge: its edge.
    #[pyo3(get)]
    edge: Py<PyArray1<i64>>,
    /// Per halfedge: its face, −1 for a boundary halfedge.
    #[pyo3(get)]
    face: Py<PyArray1<i64>>,
    /// Per vertex: one outgoing halfedge, the boundary one where the vertex is on a boundary;
    /// −1 for an isolated vertex.
    #[pyo3(get)]
    vertex_halfedge: Py<PyArray1<i64>>,
    /// Per edge: one of its halfedges, an interior one where it has one.
    #[pyo3(get)]
    edge_halfedge: Py<PyArray1<i64>>,
    /// Per face: the halfedge leaving the first corner of its row of `Mesh.faces`.
    #[pyo3(get)]
    face_halfedge: Py<PyArray1<i64>>,
}

/// A table of rows as int64, [`NONE`] written as −1.
fn signed(py: Python<'_>, rows: &[u32]) -> Py<PyArray1<i64>> {
    let values: Vec<i64> = rows
        .iter()
        .map(|&r| if r == NONE { -1 } else { i64::from(r) })
        .collect();
    PyArray1::from_vec(py, values).unbind()
}

impl ConnectivityArrays {
    /// Reads `mesh`'s tables and converts each to an array.
    pub(crate) fn of(py: Python<'_>, world: &World, mesh: MeshId) -> Self {
        let t = py.detach(|| extract(world, mesh).tables);
        let from_vertex: Vec<u32> = t.twin.iter().map(|&h| t.to_vertex[h as usize]).collect();
        Self {
            next: signed(py, &t.next),
            prev: signed(py, &t.prev),
            twin: signed(py, &t.twin),
            to_vertex: signed(py, &t.to_vertex),
            from_vertex: signed(py, &from_vertex),
            edge: signed(py, &t.edge),
            face: signed(py, &t.face),
            vertex_halfedge: signed(py, &t.vertex_halfedge),
            edge_halfedge: signed(py, &t.edge_halfedge),
            face_halfedge: signed(py, &t.face_halfedge),
        }
    }
}

#[pymethods]
impl ConnectivityArrays {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "pappus.Connectivity({} vertices, {} halfedges, {} edges, {} faces)",
            self.vertex_halfedge.bind(py).len(),
            self.next.bind(py).len(),
            self.edge_halfedge.bind(py).len(),
            self.face_halfedge.bind(py).len(),
        )
    }
}
