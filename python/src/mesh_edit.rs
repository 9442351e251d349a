//! `with mesh.edit() as e:`: the checked low-level edit ([`pappus::mesh::RawEdit`]) from
//! Python, on handles.
//!
//! Entering the block opens an edit; inside it, `e.set_next(h, n)` and the other setters
//! rewire the structure freely (each journalled); leaving the block commits: the mesh is
//! checked with `validate`'s rules, and a broken one raises `pappus.InvalidMesh` naming the
//! rule and the element, with the mesh rolled back to exactly what it was. An exception raised
//! inside the block rolls back too, and goes on. While the edit is open the mesh runs no other
//! method that reads it whole (operations, arrays, saving, copying), and handles read their
//! own links but walk no circulator: mid-edit the structure need not close.

use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use bevy::math::Vec3;
use pappus::mesh::{ElementId, RawEdit, RawEditError};

use crate::errors::InvalidMesh;
use crate::handles::{At, EdgeHandle, FaceHandle, HalfedgeHandle, VertexHandle, stale};
use crate::mesh::Mesh;

/// A low-level edit of one mesh, used as a context manager (see the module doc).
#[pyclass(module = "pappus", name = "MeshEdit", frozen)]
pub struct MeshEdit {
    /// The mesh it edits.
    mesh: Py<Mesh>,
}

impl MeshEdit {
    /// An edit of `mesh`, not yet open.
    pub(crate) fn of(mesh: Py<Mesh>) -> Self {
        Self { mesh }
    }

    /// Runs `change` on the open edit, then sets it aside again. A refused change changes
    /// nothing and raises `ValueError` naming the element.
    fn with<T>(
        &self,
        py: Python<'_>,
        change: impl FnOnce(&mut RawEdit<'_>) -> Result<T, RawEditError>,
    ) -> PyResult<T> {
        let mut mesh = self.mesh.bind(py).try_borrow_mut()?;
        let (world, journal) = mesh.edit_parts()?;
        let mut edit = RawEdit::resume(world, journal);
        let result = change(&mut edit);
        let journal = edit.suspend();
        mesh.set_aside(journal);
        result.map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The element a handle of kind `T` names, checked to be of this mesh and not stale;
    /// `TypeError` for a handle of another kind.
    fn id<T: pyo3::PyClass + Sync>(
        &self,
        x: &Bound<'_, PyAny>,
        at: fn(&T) -> &At,
        kind: &str,
    ) -> PyResult<ElementId> {
        let handle = x.cast::<T>().map_err(|_| {
            let given = x
                .get_type()
                .name()
                .map_or_else(|_| "that".to_string(), |n| n.to_string());
            PyTypeError::new_err(format!("expected a pappus.{kind}, not {given}"))
        })?;
        let handle = handle.borrow();
        let place = at(&handle);
        let id = place.check_mesh(self.mesh.bind(x.py()))?;
        if !self
            .mesh
            .bind(x.py())
            .try_borrow()?
            .holds(id, place.revision())
        {
            return Err(stale(id));
        }
        Ok(id)
    }

    /// A halfedge handle's id.
    fn halfedge(&self, x: &Bound<'_, PyAny>) -> PyResult<pappus::mesh::HalfedgeId> {
        match self.id::<HalfedgeHandle>(x, HalfedgeHandle::at, "Halfedge")? {
            ElementId::Halfedge(h) => Ok(h),
            _ => unreachable!("a halfedge handle names a halfedge"),
        }
    }

    /// A vertex handle's id.
    fn vertex(&self, x: &Bound<'_, PyAny>) -> PyResult<pappus::mesh::VertexId> {
        match self.id::<VertexHandle>(x, VertexHandle::at, "Vertex")? {
            ElementId::Vertex(v) => Ok(v),
            _ => unreachable!("a vertex handle names a vertex"),
        }
    }

    /// Any handle's id.
    fn any(&self, x: &Bound<'_, PyAny>) -> PyResult<ElementId> {
        if x.cast::<VertexHandle>().is_ok() {
            self.id::<VertexHandle>(x, VertexHandle::at, "Vertex")
        } else if x.cast::<EdgeHandle>().is_ok() {
            self.id::<EdgeHandle>(x, EdgeHandle::at, "Edge")
        } else if x.cast::<FaceHandle>().is_ok() {
            self.id::<FaceHandle>(x, FaceHandle::at, "Face")
        } else {
            self.id::<HalfedgeHandle>(x, HalfedgeHandle::at, "Halfedge")
        }
    }

    /// A handle on `id`, an element of this mesh now.
    fn handle<T: From<At>>(&self, py: Python<'_>, id: impl Into<ElementId>) -> PyResult<T> {
        let revision = self.mesh.bind(py).try_borrow()?.element_revision();
        Ok(T::from(At::new(py, &self.mesh, id.into(), revision)))
    }
}

#[pymethods]
impl MeshEdit {
    /// Opens the edit. `RuntimeError` when one is open already.
    fn __enter__(slf: PyRef<'_, Self>) -> PyResult<PyRef<'_, Self>> {
        slf.mesh.bind(slf.py()).try_borrow_mut()?.open_edit()?;
        Ok(slf)
    }

    /// Commits the edit, or rolls it back when the block raised (the exception goes on). A
    /// commit that finds a broken rule rolls back and raises `InvalidMesh` naming it.
    #[pyo3(signature = (kind, _value, _traceback))]
    fn __exit__(
        &self,
        py: Python<'_>,
        kind: Option<Bound<'_, PyAny>>,
        _value: Option<Bound<'_, PyAny>>,
        _traceback: Option<Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        let mut mesh = self.mesh.bind(py).try_borrow_mut()?;
        let (world, journal) = mesh.edit_parts()?;
        let edit = RawEdit::resume(world, journal);
        if kind.is_some_and(|k| !k.is_none()) {
            edit.rollback();
            mesh.closed_edit(false);
            return Ok(false);
        }
        let committed = edit.commit();
        mesh.closed_edit(committed.is_ok());
        if let Err(RawEditError::Invalid(invalid)) = &committed {
            mesh.broke(invalid.clone());
        }
        match committed {
            Ok(()) => Ok(false),
            Err(e) => Err(InvalidMesh::new_err(format!(
                "{e}; the edit was rolled back and the mesh is as it was"
            ))),
        }
    }

    /// Sets `h`'s next to `next` and `next`'s prev to `h`.
    fn set_next(
        &self,
        py: Python<'_>,
        h: &Bound<'_, PyAny>,
        next: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let (h, next) = (self.halfedge(h)?, self.halfedge(next)?);
        self.with(py, |e| e.set_next(h, next))
    }

    /// Makes `a` and `b` each other's twin.
    fn set_twin(&self, py: Python<'_>, a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>) -> PyResult<()> {
        let (a, b) = (self.halfedge(a)?, self.halfedge(b)?);
        self.with(py, |e| e.set_twin(a, b))
    }

    /// Sets the vertex `h` points to.
    fn set_to_vertex(
        &self,
        py: Python<'_>,
        h: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let (h, v) = (self.halfedge(h)?, self.vertex(v)?);
        self.with(py, |e| e.set_to_vertex(h, v))
    }

    /// Sets `h`'s edge.
    fn set_edge(
        &self,
        py: Python<'_>,
        h: &Bound<'_, PyAny>,
        edge: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let h = self.halfedge(h)?;
        let ElementId::Edge(edge) = self.id::<EdgeHandle>(edge, EdgeHandle::at, "Edge")? else {
            unreachable!("an edge handle names an edge")
        };
        self.with(py, |e| e.set_edge(h, edge))
    }

    /// Sets `h`'s face (`None`: a boundary halfedge).
    fn set_face(
        &self,
        py: Python<'_>,
        h: &Bound<'_, PyAny>,
        face: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let h = self.halfedge(h)?;
        let face = match face {
            Some(f) => match self.id::<FaceHandle>(f, FaceHandle::at, "Face")? {
                ElementId::Face(f) => Some(f),
                _ => unreachable!("a face handle names a face"),
            },
            None => None,
        };
        self.with(py, |e| e.set_face(h, face))
    }

    /// Sets the halfedge of a vertex (outgoing), an edge or a face.
    fn set_halfedge(
        &self,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        h: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let h = self.halfedge(h)?;
        match self.any(x)? {
            ElementId::Vertex(v) => self.with(py, |e| e.set_vertex_halfedge(v, h)),
            ElementId::Edge(edge) => self.with(py, |e| e.set_edge_halfedge(edge, h)),
            ElementId::Face(f) => self.with(py, |e| e.set_face_halfedge(f, h)),
            other => Err(PyTypeError::new_err(format!(
                "set_halfedge sets a vertex's, an edge's or a face's halfedge, not {other}'s"
            ))),
        }
    }

    /// Moves a vertex (`ValueError` for a position that is not finite).
    fn set_position(
        &self,
        py: Python<'_>,
        v: &Bound<'_, PyAny>,
        position: [f64; 3],
    ) -> PyResult<()> {
        let v = self.vertex(v)?;
        let p = Vec3::new(position[0] as f32, position[1] as f32, position[2] as f32);
        self.with(py, |e| e.set_position(v, p))
    }

    /// A new vertex at `position`; set its halfedge before leaving the block.
    fn new_vertex(&self, py: Python<'_>, position: [f64; 3]) -> PyResult<VertexHandle> {
        let p = Vec3::new(position[0] as f32, position[1] as f32, position[2] as f32);
        let v = self.with(py, |e| e.new_vertex(p))?;
        self.handle(py, v)
    }

    /// A new edge and its two halfedges `(edge, first, second)`: twins of each other, each its
    /// own next and prev, pointing at no vertex, on no face; the edge's halfedge the first.
    fn new_edge(&self, py: Python<'_>) -> PyResult<(EdgeHandle, HalfedgeHandle, HalfedgeHandle)> {
        let (edge, a, b) = self.with(py, |e| Ok(e.new_edge()))?;
        Ok((
            self.handle(py, edge)?,
            self.handle(py, a)?,
            self.handle(py, b)?,
        ))
    }

    /// A new face; set its halfedge before leaving the block.
    fn new_face(&self, py: Python<'_>) -> PyResult<FaceHandle> {
        let f = self.with(py, |e| Ok(e.new_face()))?;
        self.handle(py, f)
    }

    /// Takes an element out of the mesh (links still naming it break the commit's check);
    /// leaving the block removes it for good.
    fn remove(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<()> {
        let id = self.any(x)?;
        self.with(py, |e| e.remove(id))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let open = self
            .mesh
            .bind(py)
            .try_borrow()
            .is_ok_and(|m| m.edit_is_open());
        format!(
            "pappus.MeshEdit({})",
            if open { "open" } else { "not open" }
        )
    }
}

/// The error for a method a mesh cannot run while one of its edits is open.
pub(crate) fn edit_open() -> PyErr {
    PyRuntimeError::new_err(
        "an edit of this mesh is open: leave its `with mesh.edit()` block first",
    )
}
