//! The exceptions Pappus raises and how Rust errors become them: a refusal `Refused`, a
//! malformed file `ParseError`, the file system `OSError`, a lost outcome a note on the error.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;

use pappus::io::IoError;
use pappus::ops::Refusal;

create_exception!(
    pappus,
    PappusError,
    PyException,
    "The base of every error Pappus raises itself."
);
create_exception!(
    pappus,
    Refused,
    PappusError,
    "An operation was refused; the message is the reason. The mesh is exactly as it was."
);
create_exception!(
    pappus,
    ParseError,
    PappusError,
    "A mesh file is malformed or uses a variant Pappus does not read. Attributes: `path`, \
     `location` (`line N` for text, `byte N` for binary) and `line` (an int, or None)."
);
create_exception!(
    pappus,
    InvalidMesh,
    PappusError,
    "`Mesh.validate` found a broken invariant; the message names the rule and the element."
);

create_exception!(
    pappus,
    StaleElement,
    PappusError,
    "A handle names an element an edit removed (`v12v0 is gone`); nothing was read or changed."
);

/// The Python exception for a file error: `ParseError` (with its location) for malformed or
/// unsupported contents, `FileNotFoundError` / `OSError` for the file system, `ValueError` for
/// an unknown extension or one Pappus only reads.
pub(crate) fn io_error(py: Python<'_>, e: IoError) -> PyErr {
    match &e {
        IoError::UnknownFormat(_) | IoError::ReadOnly(_) => PyValueError::new_err(e.to_string()),
        IoError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(e.to_string())
        }
        IoError::Io { .. } | IoError::Save { .. } => PyOSError::new_err(e.to_string()),
        IoError::Parse { path, location, .. } | IoError::Unsupported { path, location, .. } => {
            let err = ParseError::new_err(e.to_string());
            let value = err.value(py);
            let line = location
                .strip_prefix("line ")
                .and_then(|n| n.parse::<u64>().ok());
            // Setting attributes on a fresh exception instance cannot fail in practice; if it
            // did, the message still names the location.
            let _ = value.setattr("path", path.to_string_lossy().into_owned());
            let _ = value.setattr("location", location.clone());
            let _ = value.setattr("line", line);
            err
        }
    }
}

/// The exception a progress callback raised, with a note (PEP 678) on what became of the
/// edit: it completed (the mesh holds its result: `outcome`'s summary), or it was refused and
/// the mesh is unchanged.
pub(crate) fn with_outcome_note(
    py: Python<'_>,
    e: PyErr,
    outcome: &Result<String, Refusal>,
) -> PyErr {
    let note = match outcome {
        Ok(summary) => format!(
            "pappus: raised in a progress callback; the edit completed all the same and the \
             mesh holds its result ({summary})"
        ),
        Err(refusal) => format!(
            "pappus: raised in a progress callback; the edit was refused ({refusal}) and the \
             mesh is unchanged"
        ),
    };
    // `add_note` exists from Python 3.11; on older ones the exception goes up without it.
    let _ = e.value(py).call_method1("add_note", (note,));
    e
}

/// Issues a Python `UserWarning` with `message`.
pub(crate) fn user_warning(py: Python<'_>, message: String) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    let message = std::ffi::CString::new(message.replace('\0', " "))
        .expect("no interior NUL after the replace");
    PyErr::warn(py, &category, &message, 1)
}
