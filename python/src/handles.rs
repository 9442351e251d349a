//! Element handles: `pappus.Vertex`, `pappus.Halfedge`, `pappus.Edge` and `pappus.Face`, each
//! one element of one mesh, with its relations and circulators (PMP's and OpenMesh's
//! navigation, Botsch et al., *Polygon Mesh Processing*, 2010, §2.2).
//!
//! A handle holds its mesh, its element's entity and the mesh's element revision when it was
//! taken, and checks on every use that the element still exists: an entity an edit despawned
//! fails the world's generation check, and an edit that rewrote the non-vertex elements in
//! place (subdivision: [`IdsKept::VerticesOnly`](pappus::edit::IdsKept)) moved the revision on.
//! Either way the handle raises `pappus.StaleElement` naming its id, never answers for another
//! element. Its `id` is the editor inspector's (`v12v0`); its `row` is its row of the mesh's
//! arrays now (rows move when an edit renumbers storage, ids do not).

use bevy::math::Vec3;
use bevy::prelude::Entity;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use pappus::mesh::{ElementId, HalfedgeId, MeshRef};

use crate::errors::StaleElement;
use crate::mesh::Mesh;

/// Where a handle points: its mesh, its element, and the mesh's element revision when taken.
pub(crate) struct At {
    /// The mesh.
    mesh: Py<Mesh>,
    /// The element.
    id: ElementId,
    /// [`Mesh::element_revision`] when the handle was made.
    revision: u64,
}

impl At {
    /// A handle's place: `id` in `mesh` as it is now.
    pub(crate) fn new(py: Python<'_>, mesh: &Py<Mesh>, id: ElementId, revision: u64) -> Self {
        Self {
            mesh: mesh.clone_ref(py),
            id,
            revision,
        }
    }

    /// The mesh, borrowed, while the element is in it; `StaleElement` once an edit removed it.
    fn live<'py>(&self, py: Python<'py>) -> PyResult<PyRef<'py, Mesh>> {
        let mesh = self.mesh.bind(py).try_borrow().map_err(|_| busy())?;
        if !mesh.holds(self.id, self.revision) {
            return Err(stale(self.id));
        }
        Ok(mesh)
    }

    /// Another element of the same mesh, as a handle of its kind.
    fn to<T: From<At>>(&self, py: Python<'_>, id: impl Into<ElementId>) -> T {
        T::from(At::new(py, &self.mesh, id.into(), self.revision))
    }

    /// Handles of the same mesh for `ids`.
    fn all<T: From<At>, I: Into<ElementId>>(
        &self,
        py: Python<'_>,
        ids: impl IntoIterator<Item = I>,
    ) -> Vec<T> {
        ids.into_iter().map(|id| self.to(py, id)).collect()
    }

    /// Whether two handles name one element of one mesh.
    fn same(&self, other: &At) -> bool {
        self.id == other.id && self.mesh.is(&other.mesh)
    }

    /// The mesh's element revision when the handle was made.
    pub(crate) fn revision(&self) -> u64 {
        self.revision
    }

    /// Its element, checked to be of `mesh` (`ValueError` naming the element if not).
    pub(crate) fn check_mesh(&self, mesh: &Bound<'_, Mesh>) -> PyResult<ElementId> {
        if !self.mesh.is(mesh) {
            return Err(PyValueError::new_err(format!(
                "{} is an element of another mesh",
                self.id
            )));
        }
        Ok(self.id)
    }

    /// The element's entity.
    fn entity(&self) -> Entity {
        self.id.entity()
    }

    /// The element's row in its kind's arrays.
    fn row(&self, py: Python<'_>) -> PyResult<usize> {
        let mesh = self.live(py)?;
        mesh.row_of(self.entity()).ok_or_else(|| stale(self.id))
    }

    /// The mesh, borrowed, while the element is in it and no low-level edit is open: what a
    /// walk around a vertex or a face needs (mid-edit the structure need not close).
    fn walkable<'py>(&self, py: Python<'py>) -> PyResult<PyRef<'py, Mesh>> {
        let mesh = self.live(py)?;
        if mesh.edit_is_open() {
            return Err(PyRuntimeError::new_err(format!(
                "{}: a walk needs a valid mesh, and an edit is open: leave its `with` block first",
                self.id
            )));
        }
        Ok(mesh)
    }
}

/// The error for a handle whose element an edit removed.
pub(crate) fn stale(id: ElementId) -> PyErr {
    StaleElement::new_err(format!("{id} is gone"))
}

/// The error for a handle used while its mesh is being edited (from another thread).
fn busy() -> PyErr {
    PyRuntimeError::new_err("the mesh is being edited")
}

/// The handle's element, which `live` has checked exists, as its typed id.
macro_rules! typed {
    ($at:expr, $variant:ident) => {
        match $at.id {
            ElementId::$variant(x) => x,
            _ => unreachable!("a handle's kind is its class's"),
        }
    };
}

/// A handle class: the struct, its construction from an [`At`], and the methods every kind
/// shares (`id`, `row`, equality, hashing, `repr`), followed by `$extra`, its own.
macro_rules! handle_class {
    ($(#[$doc:meta])* $name:ident, $py_name:literal, { $($extra:tt)* }) => {
        $(#[$doc])*
        #[pyclass(module = "pappus", name = $py_name, frozen)]
        pub struct $name {
            at: At,
        }

        impl From<At> for $name {
            fn from(at: At) -> Self {
                Self { at }
            }
        }

        impl $name {
            /// Where it points.
            pub(crate) fn at(&self) -> &At {
                &self.at
            }
        }

        #[pymethods]
        impl $name {
            /// What Python's garbage collector follows: the mesh (a mesh's selection holds
            /// handles, a cycle only the collector can free).
            fn __traverse__(&self, visit: pyo3::PyVisit<'_>) -> Result<(), pyo3::PyTraverseError> {
                visit.call(&self.at.mesh)
            }

            /// The editor inspector's id (`v12v0`): the same element for as long as it exists.
            #[getter]
            fn id(&self) -> String {
                self.at.id.to_string()
            }

            /// Its row in the mesh's arrays now (`vertices`, `faces`, `connectivity()`'s).
            /// Raises `StaleElement` when an edit removed it.
            #[getter]
            fn row(&self, py: Python<'_>) -> PyResult<usize> {
                self.at.row(py)
            }

            fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
                other
                    .cast::<$name>()
                    .is_ok_and(|o| self.at.same(&o.get().at))
            }

            fn __hash__(&self) -> u64 {
                self.at.entity().to_bits()
            }

            fn __repr__(&self) -> String {
                format!("pappus.{}({})", $py_name, self.at.id)
            }

            $($extra)*
        }
    };
}

handle_class!(
    /// One vertex of a mesh: its position, outgoing halfedge and one-ring circulators.
    VertexHandle,
    "Vertex",
    {
        /// Its position, `(x, y, z)` (float32 precision). Setting it moves the vertex as one
        /// edit; a position that is not finite raises `ValueError` and moves nothing.
        #[getter]
        fn position(&self, py: Python<'_>) -> PyResult<(f32, f32, f32)> {
            let mesh = self.at.live(py)?;
            let p = MeshRef::new(mesh.world()).position(typed!(self.at, Vertex));
            Ok((p.x, p.y, p.z))
        }

        #[setter]
        fn set_position(&self, py: Python<'_>, position: (f64, f64, f64)) -> PyResult<()> {
            drop(self.at.live(py)?);
            let p = Vec3::new(position.0 as f32, position.1 as f32, position.2 as f32);
            if !p.is_finite() {
                return Err(PyValueError::new_err(format!(
                    "{}: a position must be finite, not {position:?}",
                    self.at.id
                )));
            }
            let mut mesh = self.at.mesh.bind(py).try_borrow_mut().map_err(|_| busy())?;
            mesh.set_positions(py, vec![(typed!(self.at, Vertex), p)])
        }

        /// An outgoing halfedge: the boundary one where the vertex is on a boundary.
        #[getter]
        fn halfedge(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            let mesh = self.at.live(py)?;
            let h = MeshRef::new(mesh.world()).vertex_halfedge(typed!(self.at, Vertex));
            Ok(self.at.to(py, h))
        }

        /// Whether it lies on a boundary.
        #[getter]
        fn is_boundary(&self, py: Python<'_>) -> PyResult<bool> {
            let mesh = self.at.walkable(py)?;
            Ok(MeshRef::new(mesh.world()).is_boundary_vertex(typed!(self.at, Vertex)))
        }

        /// Its number of edges.
        #[getter]
        fn valence(&self, py: Python<'_>) -> PyResult<usize> {
            let mesh = self.at.walkable(py)?;
            Ok(MeshRef::new(mesh.world()).valence(typed!(self.at, Vertex)))
        }

        /// Its outgoing halfedges, counter-clockwise (`twin(prev(h))` after `h`), starting at
        /// `halfedge`.
        fn outgoing(&self, py: Python<'_>) -> PyResult<Vec<HalfedgeHandle>> {
            let mesh = self.at.walkable(py)?;
            let ring = MeshRef::new(mesh.world()).vertex_outgoing(typed!(self.at, Vertex));
            Ok(self.at.all(py, ring))
        }

        /// The vertices its edges lead to, in the order of `outgoing()`.
        fn neighbours(&self, py: Python<'_>) -> PyResult<Vec<VertexHandle>> {
            let mesh = self.at.walkable(py)?;
            let ring = MeshRef::new(mesh.world()).vertex_neighbors(typed!(self.at, Vertex));
            Ok(self.at.all(py, ring))
        }

        /// The faces around it, in the order of `outgoing()` (a boundary gap skipped).
        fn faces(&self, py: Python<'_>) -> PyResult<Vec<FaceHandle>> {
            let mesh = self.at.walkable(py)?;
            let ring = MeshRef::new(mesh.world()).vertex_faces(typed!(self.at, Vertex));
            Ok(self.at.all(py, ring))
        }
    }
);

handle_class!(
    /// One halfedge of a mesh: one side of an edge, pointing at `to_vertex`.
    HalfedgeHandle,
    "Halfedge",
    {
        /// The next halfedge round its face (or boundary loop).
        #[getter]
        fn next(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            self.link(py, |m, h| m.next(h))
        }

        /// The previous halfedge round its face (or boundary loop).
        #[getter]
        fn prev(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            self.link(py, |m, h| m.prev(h))
        }

        /// The opposite halfedge of its edge.
        #[getter]
        fn twin(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            self.link(py, |m, h| m.twin(h))
        }

        /// The vertex it points to (its tip).
        #[getter]
        fn to_vertex(&self, py: Python<'_>) -> PyResult<VertexHandle> {
            self.link(py, |m, h| m.to_vertex(h))
        }

        /// The vertex it leaves (its tail).
        #[getter(from_vertex)]
        fn tail(&self, py: Python<'_>) -> PyResult<VertexHandle> {
            self.link(py, |m, h| m.from_vertex(h))
        }

        /// Its edge.
        #[getter]
        fn edge(&self, py: Python<'_>) -> PyResult<EdgeHandle> {
            self.link(py, |m, h| m.edge(h))
        }

        /// Its face, None on the boundary.
        #[getter]
        fn face(&self, py: Python<'_>) -> PyResult<Option<FaceHandle>> {
            let mesh = self.at.live(py)?;
            let f = MeshRef::new(mesh.world()).face(typed!(self.at, Halfedge));
            Ok(f.map(|f| self.at.to(py, f)))
        }

        /// Whether it is a boundary halfedge (it has no face).
        #[getter]
        fn is_boundary(&self, py: Python<'_>) -> PyResult<bool> {
            let mesh = self.at.live(py)?;
            Ok(MeshRef::new(mesh.world()).is_boundary(typed!(self.at, Halfedge)))
        }
    }
);

impl HalfedgeHandle {
    /// The element `link` reads from this halfedge, as a handle.
    fn link<T: From<At>, I: Into<ElementId>>(
        &self,
        py: Python<'_>,
        link: impl Fn(&MeshRef<'_>, HalfedgeId) -> I,
    ) -> PyResult<T> {
        let mesh = self.at.live(py)?;
        let to = link(&MeshRef::new(mesh.world()), typed!(self.at, Halfedge));
        Ok(self.at.to(py, to))
    }
}

handle_class!(
    /// One edge of a mesh: a pair of twin halfedges.
    EdgeHandle,
    "Edge",
    {
        /// One of its halfedges, an interior one where it has one.
        #[getter]
        fn halfedge(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            let mesh = self.at.live(py)?;
            let h = MeshRef::new(mesh.world()).edge_halfedge(typed!(self.at, Edge));
            Ok(self.at.to(py, h))
        }

        /// Whether it lies on a boundary (one of its halfedges has no face).
        #[getter]
        fn is_boundary(&self, py: Python<'_>) -> PyResult<bool> {
            let mesh = self.at.live(py)?;
            Ok(MeshRef::new(mesh.world()).is_boundary_edge(typed!(self.at, Edge)))
        }

        /// Its two vertices: `halfedge`'s tail, then its tip.
        fn vertices(&self, py: Python<'_>) -> PyResult<(VertexHandle, VertexHandle)> {
            let mesh = self.at.live(py)?;
            let (a, b) = MeshRef::new(mesh.world()).edge_vertices(typed!(self.at, Edge));
            Ok((self.at.to(py, a), self.at.to(py, b)))
        }

        /// The faces on its two sides: two inside the mesh, one on a boundary.
        fn faces(&self, py: Python<'_>) -> PyResult<Vec<FaceHandle>> {
            let mesh = self.at.live(py)?;
            let m = MeshRef::new(mesh.world());
            let h = m.edge_halfedge(typed!(self.at, Edge));
            Ok(self.at.all(py, [m.face(h), m.face(m.twin(h))].into_iter().flatten()))
        }
    }
);

handle_class!(
    /// One face of a mesh: a cycle of halfedges.
    FaceHandle,
    "Face",
    {
        /// The halfedge leaving its first corner (the first of its row of `Mesh.faces`).
        #[getter]
        fn halfedge(&self, py: Python<'_>) -> PyResult<HalfedgeHandle> {
            let mesh = self.at.live(py)?;
            let h = MeshRef::new(mesh.world()).face_halfedge(typed!(self.at, Face));
            Ok(self.at.to(py, h))
        }

        /// Whether one of its edges lies on a boundary.
        #[getter]
        fn is_boundary(&self, py: Python<'_>) -> PyResult<bool> {
            let mesh = self.at.walkable(py)?;
            let m = MeshRef::new(mesh.world());
            Ok(m.face_halfedges(typed!(self.at, Face))
                .any(|h| m.is_boundary(m.twin(h))))
        }

        /// Its halfedges in order, from `halfedge`.
        fn halfedges(&self, py: Python<'_>) -> PyResult<Vec<HalfedgeHandle>> {
            let mesh = self.at.walkable(py)?;
            let cycle = MeshRef::new(mesh.world()).face_halfedges(typed!(self.at, Face));
            Ok(self.at.all(py, cycle))
        }

        /// Its corners in order: its row of `Mesh.faces`.
        fn vertices(&self, py: Python<'_>) -> PyResult<Vec<VertexHandle>> {
            let mesh = self.at.walkable(py)?;
            let m = MeshRef::new(mesh.world());
            let corners = m
                .face_halfedges(typed!(self.at, Face))
                .map(|h| m.from_vertex(h));
            Ok(self.at.all(py, corners))
        }
    }
);

/// A handle of the right class for `id`.
pub(crate) fn handle(py: Python<'_>, at: At) -> PyResult<Py<PyAny>> {
    Ok(match at.id {
        ElementId::Vertex(_) => Py::new(py, VertexHandle::from(at))?.into_any(),
        ElementId::Halfedge(_) => Py::new(py, HalfedgeHandle::from(at))?.into_any(),
        ElementId::Edge(_) => Py::new(py, EdgeHandle::from(at))?.into_any(),
        ElementId::Face(_) => Py::new(py, FaceHandle::from(at))?.into_any(),
        ElementId::Mesh(_) => {
            return Err(PyValueError::new_err(
                "a mesh id names no element: give a vertex, halfedge, edge or face id",
            ));
        }
    })
}
