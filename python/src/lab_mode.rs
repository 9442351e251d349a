//! `pappus.lab(mesh, reference, function, *elements, **parameters)`: a student's operation
//! written in Python (rewiring through `with mesh.edit()`) checked against Pappus's own, with
//! the core's lab mode ([`pappus::edit::lab`]).
//!
//! The function is called as `function(copy, *handles)` on a copy of the mesh with the same
//! element ids as the copy the reference runs on, the handles naming the elements given (as
//! `Mesh.run` reads them). Whatever it does there, the mesh itself is never changed: the report
//! says whether the copy came out valid and the reference's, or the first difference by the
//! mesh's ids, or the broken rule (an `InvalidMesh` its edit raised, or a mesh left invalid), or
//! the exception it raised. The copy is the function's only while it runs: a handle or the copy
//! kept after that names nothing.

use bevy::prelude::World;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use pappus::edit::lab::{Ended, LabReport, Verdict, compare_with};
use pappus::mesh::{ElementId, MeshId};
use pappus::ops::Refusal;

use crate::errors::Refused;
use crate::handles::{At, handle};
use crate::mesh::Mesh;

/// What `pappus.lab` found: `str(report)` is the report as the editor's status line says it
/// (`same as flip`, `valid, but not what flip makes: f12v0: …`, `invalid: h31v0: …`).
#[pyclass(module = "pappus", name = "LabReport", frozen)]
pub struct LabReportPy {
    /// The verdict in one word: `same`, `different`, `invalid`, `panicked`, `raised`,
    /// `refused` (where the reference applies), `applied` (where the reference refuses),
    /// `both-refused` or `reference-failed`.
    #[pyo3(get)]
    verdict: &'static str,
    /// What the verdict is about: the first difference, the broken rule, the exception, the
    /// refusal; `None` for `same`.
    #[pyo3(get)]
    detail: Option<String>,
    /// The reference's name.
    #[pyo3(get)]
    reference: &'static str,
    /// The whole report.
    text: String,
}

#[pymethods]
impl LabReportPy {
    /// Whether the result was valid and the reference's.
    #[getter]
    fn same(&self) -> bool {
        self.verdict == "same"
    }

    fn __str__(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        format!("pappus.LabReport({:?})", self.text)
    }
}

impl From<LabReport> for LabReportPy {
    fn from(report: LabReport) -> Self {
        let text = report.to_string();
        let (verdict, detail) = match report.verdict {
            Verdict::Same => ("same", None),
            Verdict::Different(d) => ("different", Some(d)),
            Verdict::Invalid(d) => ("invalid", Some(d)),
            Verdict::Panicked(d) => ("panicked", Some(d)),
            Verdict::Raised(d) => ("raised", Some(d)),
            Verdict::RefusedAlone(r) => ("refused", Some(r.to_string())),
            Verdict::AppliedAlone(r) => ("applied", Some(r.to_string())),
            Verdict::BothRefused(r) => ("both-refused", Some(r.to_string())),
            Verdict::ReferenceFailed(d) => ("reference-failed", Some(d)),
        };
        Self {
            verdict,
            detail,
            reference: report.reference,
            text,
        }
    }
}

/// Checks `function` against the registered operation `reference` on `elements` (see the
/// module doc); the mesh is not changed.
///
/// # Errors
/// `ValueError` for no operation of that name on such elements or a parameter it does not
/// take, `StaleElement` for a handle whose element is gone, `RuntimeError` while an edit of the
/// mesh is open.
#[pyfunction]
#[pyo3(signature = (mesh, reference, function, *elements, **parameters))]
pub fn lab(
    mesh: &Bound<'_, Mesh>,
    reference: &str,
    function: &Bound<'_, PyAny>,
    elements: &Bound<'_, PyTuple>,
    parameters: Option<&Bound<'_, PyDict>>,
) -> PyResult<LabReportPy> {
    let py = mesh.py();
    let targets = crate::run::targets(mesh, elements.as_any())?;
    let m = mesh.try_borrow()?;
    m.no_open_edit()?;
    let invocation = m.invocation_of(reference, &targets, parameters)?;
    let report = compare_with(m.world(), m.id(), &invocation, |world, copy, elements| {
        attempt(py, function, world, copy, elements)
    });
    report
        .map(LabReportPy::from)
        .map_err(|r| Refused::new_err(r.to_string()))
}

/// Calls `function` on the copy in `world` (lent to a Python `Mesh` while it runs) and says
/// how it ended.
fn attempt(
    py: Python<'_>,
    function: &Bound<'_, PyAny>,
    world: &mut World,
    mesh: MeshId,
    elements: &[ElementId],
) -> Ended {
    let copy = match Py::new(py, Mesh::lent(std::mem::take(world), mesh)) {
        Ok(copy) => copy,
        Err(e) => return Ended::Raised(described(py, &e)),
    };
    let called = elements
        .iter()
        .map(|&x| handle(py, At::new(py, &copy, x, 0)))
        .collect::<PyResult<Vec<_>>>()
        .and_then(|handles| {
            let mut args = vec![copy.clone_ref(py).into_any()];
            args.extend(handles);
            function.call1(PyTuple::new(py, args)?)
        });
    let (back, left_open, broken) = copy.bind(py).borrow_mut().give_back();
    *world = back;
    match (called, broken) {
        _ if left_open => Ended::Raised("left a `mesh.edit()` open (it was rolled back)".into()),
        (Ok(_), _) => Ended::Done,
        (Err(_), Some(invalid)) => Ended::Refused(Refusal::Broken(invalid)),
        (Err(e), None) if e.is_instance_of::<Refused>(py) => {
            Ended::Refused(Refusal::Lab(e.value(py).to_string()))
        }
        (Err(e), None) => Ended::Raised(described(py, &e)),
    }
}

/// An exception as `ValueError: the message`.
fn described(py: Python<'_>, e: &PyErr) -> String {
    let kind = e
        .get_type(py)
        .name()
        .map_or_else(|_| "an exception".to_string(), |n| n.to_string());
    format!("{kind}: {}", e.value(py))
}
