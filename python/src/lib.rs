//! `pappus._pappus`: the Python extension module behind the `pappus` package.
//!
//! A [`Mesh`] owns one Bevy `World` holding one halfedge mesh, the map from the vertices it was
//! built from (a file's vertex numbers, or the rows of the vertex array) to the vertices they
//! became, and the simplification history a `refine` moves along. Every operation is the
//! command line's `process` step of the same name, parsed from the same text
//! ([`pappus::edit::Step::parse`]) and run by the same code, so its parameters, defaults,
//! refusals and summary are the command line's. Long operations run with the GIL released and
//! report to an optional progress callback.
//!
//! Errors: a refused operation raises `Refused` (the mesh is untouched); a malformed file raises
//! `ParseError` (with `path`, `location` and, for text formats, `line`); a parameter outside its
//! range raises `ValueError` with the command line's message; file-system failures raise
//! `OSError` (`FileNotFoundError` for a missing file).

use std::path::PathBuf;
use std::time::Instant;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pappus::memory_budget::Budget;
use pappus::source::{SourceError, read_source};

mod arrays;
mod connectivity;
mod element_data;
mod elements;
mod errors;
mod groups;
mod handles;
mod lab_mode;
mod mesh;
mod mesh_edit;
mod outcome;
mod quantities;
mod run;

use connectivity::ConnectivityArrays;
use element_data::ElementDataView;
use errors::{InvalidMesh, PappusError, ParseError, Refused, StaleElement, io_error, user_warning};
use handles::{EdgeHandle, FaceHandle, HalfedgeHandle, VertexHandle};
use lab_mode::{LabReportPy, lab};
use mesh::Mesh;
use mesh_edit::MeshEdit;

/// Milliseconds since `start`.
pub(crate) fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1000.0
}

/// Sets the memory budget of every operation in this process: a size in bytes (`int`), a
/// string as the command line's `--max-memory` takes (`"2G"`, `"512M"`, `"50%"`), or `None`
/// for the default (75 % of the available memory). An operation whose result's size follows
/// from its parameters (subdivision, remeshing, shapes, extrusions) estimates it before it
/// starts and raises `Refused` with the estimate when it would pass the budget, rather than
/// exhausting the memory. Returns the limit now, in bytes.
///
/// Raises `ValueError` for a budget it cannot read.
#[pyfunction]
#[pyo3(signature = (limit=None))]
fn set_memory_budget(limit: Option<Bound<'_, PyAny>>) -> PyResult<u64> {
    let budget = match limit {
        None => Budget::default(),
        Some(value) => match value.extract::<u64>() {
            Ok(bytes) if bytes > 0 => Budget::Bytes(bytes),
            Ok(_) => return Err(PyValueError::new_err("a memory budget of 0 bytes")),
            Err(_) => Budget::parse(&value.extract::<String>()?).map_err(PyValueError::new_err)?,
        },
    };
    pappus::memory_budget::set(budget);
    Ok(budget.limit().0)
}

/// The memory budget now: `(limit_bytes, how_it_was_chosen)`, e.g.
/// `(17_000_000_000, "75 % of available memory")`.
#[pyfunction]
fn memory_budget() -> (u64, String) {
    pappus::memory_budget::get().limit()
}

/// Loads a mesh from a file (.obj .off .ply .stl .glb .gltf .dae, by extension) or a procedural shape
/// (`"shape:torus"`, `"shape:icosphere:6"`), repaired as the command line repairs it. The GIL
/// is released while it reads and builds. A PLY's vertex quality and other vertex and face
/// properties are kept in `Mesh.vertex_data` and `Mesh.face_data`; what a reader had to approximate is reported with `warnings.warn`.
///
/// Raises `ParseError` (with the line) for a malformed file, `FileNotFoundError` / `OSError` for the
/// file system, `ValueError` for an unknown extension or shape, or a file with no usable face.
#[pyfunction]
fn load(py: Python<'_>, path: PathBuf) -> PyResult<Mesh> {
    let start = Instant::now();
    let (soup, info) = py.detach(|| read_source(&path)).map_err(|e| match e {
        SourceError::Io(e) => io_error(py, e),
        shape @ SourceError::Shape(_) => PyValueError::new_err(shape.to_string()),
    })?;
    let read_ms = ms_since(start);
    let name = path.display().to_string();
    let warn = |message: String| user_warning(py, message);
    // The scalars the mesh has no column for are kept in `Mesh.vertex_data` and `face_data`.
    for note in &soup.notes {
        warn(format!("{name}: {note}"))?;
    }
    py.detach(|| Mesh::build(&soup, info, read_ms))
        .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// Every operation that declares itself whole (`pappus::ops::registry::operations()`), as the command
/// line's steps, the editor's keys and its panel know them: one dict each, `{"name", "title",
/// "help", "key", "job", "names", "parameters": [...]}`, in the panel's order (`"names"`: what
/// it names beside the mesh, see [`names`]), each parameter
/// `{"name", "kind", "default", "automatic"}` with `"min"`, `"max"` for a `"real"` or
/// `"whole"` kind and `"choices"` for a `"choice"`; the default is written as a step writes it
/// (a number, a choice's word, or `"auto"` where `"automatic"` says what the operation then
/// does). Each runs as `mesh.step("NAME[:VALUE…]")`, missing values taking their defaults,
/// a local one as `mesh.step("NAME:ELEMENT[:VALUE…]")` (`"flip:3,17"`).
#[pyfunction]
fn operations(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    pappus::ops::registry::operations()
        .iter()
        .map(|op| {
            let d = op.declaration();
            let parameters = d
                .parameters
                .iter()
                .map(|p| parameter(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            let x = PyDict::new(py);
            x.set_item("name", d.name)?;
            x.set_item("title", d.title)?;
            x.set_item("help", d.help)?;
            x.set_item("key", d.key)?;
            x.set_item("job", d.job)?;
            x.set_item("names", names(d.names))?;
            x.set_item("parameters", parameters)?;
            Ok(x)
        })
        .collect()
}

/// What an operation names beside the mesh, as [`operations`] lists it: `"mesh"` (nothing in
/// a step; smoothing's held vertices come from the editor's selection alone), `"edge"` (`A,B`
/// in its step), `"vertex"` (`A`), `"vertices"` (`A/B/C`), `"face"` (`A,B,C`), `"faces"`
/// (`A,B,C/D,E,F`), `"two-edges"` (`A,B/C,D`), `"face-corners"` (`A,B`: the face two vertices
/// share), `"elements"` (any, joined by `/`).
fn names(names: pappus::ops::declaration::Names) -> &'static str {
    use pappus::ops::declaration::Names;
    match names {
        Names::Mesh | Names::MeshHolding => "mesh",
        Names::Edge => "edge",
        Names::Vertices => "vertices",
        Names::FaceCorners => "face-corners",
        Names::Vertex => "vertex",
        Names::Face => "face",
        Names::Faces => "faces",
        Names::TwoEdges => "two-edges",
        Names::Elements => "elements",
    }
}

/// One declared parameter as [`operations`] lists it.
fn parameter<'py>(
    py: Python<'py>,
    p: &pappus::ops::declaration::Parameter,
) -> PyResult<Bound<'py, PyDict>> {
    use pappus::ops::declaration::ParameterKind;
    let x = PyDict::new(py);
    x.set_item("name", p.name)?;
    match p.kind {
        ParameterKind::Choice(words) => {
            x.set_item("kind", "choice")?;
            x.set_item("choices", words.to_vec())?;
            x.set_item("default", p.write(p.default))?;
        }
        ParameterKind::Real { min, max } | ParameterKind::Whole { min, max } => {
            let whole = matches!(p.kind, ParameterKind::Whole { .. });
            x.set_item("kind", if whole { "whole" } else { "real" })?;
            x.set_item("min", min)?;
            x.set_item("max", max)?;
            match p.default {
                Some(d) => x.set_item("default", d)?,
                None => x.set_item("default", "auto")?,
            }
        }
    }
    x.set_item("automatic", p.automatic)?;
    Ok(x)
}

/// Pappus from Python: load, build, edit and save halfedge meshes with the command line's
/// operations (see the `pappus` package's documentation).
#[pymodule]
mod _pappus {
    #[pymodule_export]
    use super::{
        ConnectivityArrays, EdgeHandle, ElementDataView, FaceHandle, HalfedgeHandle, InvalidMesh,
        LabReportPy, Mesh, MeshEdit, PappusError, ParseError, Refused, StaleElement, VertexHandle,
        lab, load, memory_budget, operations, set_memory_budget,
    };

    use pyo3::prelude::*;

    /// Adds the constants: the version and the procedural shapes' names.
    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        // A save past the file-size limit fails with a message instead of killing Python.
        pappus::io::ignore_file_size_signal();
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("SHAPES", pappus::mesh::shapes::SHAPE_NAMES.to_vec())?;
        Ok(())
    }
}
