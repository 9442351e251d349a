//! Elements named by input vertex numbers (`3`, `(3, 4)`, `(3, 4, 5)`) written as a step's
//! text, so that every method runs the command line's own step.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// One element named by input vertex numbers (`A`, `A,B`, `A,B,C…`), as a step writes it.
pub(crate) fn element_text(element: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(v) = element.extract::<u32>() {
        return Ok(v.to_string());
    }
    let corners: Vec<u32> = element.extract().map_err(|_| {
        PyValueError::new_err(
            "an element is a vertex number, or a sequence of them (an edge: 2, a face: 3 or more)",
        )
    })?;
    if corners.is_empty() {
        return Err(PyValueError::new_err(
            "an element names at least one vertex",
        ));
    }
    Ok(corners
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(","))
}

/// One element, or a sequence of elements, as a step writes them (joined by `/`). A flat
/// sequence of numbers is one element.
pub(crate) fn elements_text(elements: &Bound<'_, PyAny>) -> PyResult<String> {
    if elements.extract::<u32>().is_ok() || elements.extract::<Vec<u32>>().is_ok() {
        return element_text(elements);
    }
    let list = elements
        .try_iter()
        .map_err(|_| PyValueError::new_err("expected an element or a sequence of elements"))?;
    let parts: Vec<String> = list.map(|e| element_text(&e?)).collect::<PyResult<_>>()?;
    if parts.is_empty() {
        return Err(PyValueError::new_err("no elements given"));
    }
    Ok(parts.join("/"))
}

/// A Python float as a step writes it (the shortest text that reads back to the same value).
pub(crate) fn number(x: f64) -> String {
    format!("{x}")
}
