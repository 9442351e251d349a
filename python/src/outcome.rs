//! What an operation run from Python did: its summary, with the elements it made and removed
//! as handles (`pappus.Outcome`, a `str` subclass defined in the package, holds a [`Made`]).
//!
//! The handles are made when asked for, so an edit's record costs Python objects only when it
//! is read. A removed element's handle carries the revision from before the edit, so it reads
//! as stale even where the edit rewrote the element in place. A whole-mesh edit (which may make
//! millions of elements) keeps no record: its `created` and `removed` are None.

use pyo3::prelude::*;

use pappus::mesh::ElementId;

use crate::handles::{At, handle};
use crate::mesh::Mesh;
use crate::run::Changes;

/// The elements an edit made and removed, as ids, with the mesh's element revisions before
/// and after it.
#[pyclass(module = "pappus", name = "_Made", frozen)]
pub struct Made {
    /// The mesh.
    mesh: Py<Mesh>,
    /// The ids (`None` for a whole-mesh edit, which keeps no record).
    changes: Option<Changes>,
    /// The element revision before the edit.
    before: u64,
    /// The element revision after it.
    after: u64,
}

impl Made {
    /// The record of `changes` to `mesh`.
    pub(crate) fn new(mesh: Py<Mesh>, changes: Option<Changes>, before: u64, after: u64) -> Self {
        Self {
            mesh,
            changes,
            before,
            after,
        }
    }

    /// Handles on the ids `pick` chooses at `revision` (None without a record).
    fn handles(
        &self,
        py: Python<'_>,
        pick: fn(&Changes) -> &[ElementId],
        revision: u64,
    ) -> PyResult<Option<Vec<Py<PyAny>>>> {
        let Some(changes) = &self.changes else {
            return Ok(None);
        };
        pick(changes)
            .iter()
            .map(|&id| handle(py, At::new(py, &self.mesh, id, revision)))
            .collect::<PyResult<_>>()
            .map(Some)
    }
}

#[pymethods]
impl Made {
    /// Handles on the elements the edit made; None after a whole-mesh edit.
    fn created(&self, py: Python<'_>) -> PyResult<Option<Vec<Py<PyAny>>>> {
        self.handles(py, |c| &c.created, self.after)
    }

    /// Handles on the elements the edit removed (each raises `StaleElement` when read); None
    /// after a whole-mesh edit.
    fn removed(&self, py: Python<'_>) -> PyResult<Option<Vec<Py<PyAny>>>> {
        self.handles(py, |c| &c.removed, self.before)
    }
}
