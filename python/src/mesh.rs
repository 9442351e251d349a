//! `pappus.Mesh`: one World holding one halfedge mesh, its input numbering and its
//! simplification history, with one method per `process` step.

use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::{Entity, World};
use numpy::{
    AllowTypeChange, PyArray1, PyArrayLike2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use bevy::math::{Vec2, Vec3};
use pappus::cli::info_with_load_times;
use pappus::edit::{Declaration, Edit, IdsKept, Invocation};
use pappus::edit::{EditContext, Step};
use pappus::io;
use pappus::mesh::attributes::{MeshAttributes, StaleNormals};
use pappus::mesh::ids::parse_element;
use pappus::mesh::tables::EntityRows;
use pappus::mesh::{
    Edge, ElementId, Face, Halfedge, Invalid, Journal, MeshId, MeshInfo, MeshMembers, PolygonSoup,
    RawEdit, RepairReport, Vertex, VertexId, build_mesh, to_soup, validate,
};
use pappus::ops::simplification_history::SimplificationHistory;

use crate::arrays::{
    faces_array, float_rows, positions_and_faces, read_faces, vec2_array, vec3_array,
};
use crate::connectivity::ConnectivityArrays;
use crate::element_data::{ElementData, ElementDataView, Per};
use crate::elements::number;
use crate::errors::{InvalidMesh, Refused, io_error, user_warning, with_outcome_note};
use crate::groups::{face_groups_dict, face_groups_from};
use crate::handles::{At, handle, stale};
use crate::mesh_edit::{MeshEdit, edit_open};
use crate::ms_since;
use crate::outcome::Made;
use crate::quantities;
use crate::run::{self, Before, Changes};

/// One halfedge mesh (polygons allowed), owned by Python.
///
/// Operations name elements by the indices of the vertices the mesh was made from (the file's
/// vertex numbers, or the rows of the `vertices` array given to the constructor), as the command
/// line's steps do; those numbers keep meaning the same vertices across edits for as long as
/// the vertices live.
#[pyclass(module = "pappus", name = "Mesh")]
pub struct Mesh {
    /// The world holding the mesh's entities, and nothing else.
    world: World,
    /// The mesh entity.
    mesh: MeshId,
    /// What building the mesh repaired.
    report: RepairReport,
    /// For each vertex the mesh was made from, the vertex it became (`None`: dropped).
    input_vertices: Vec<Option<VertexId>>,
    /// What reading the source took, in ms (array conversion, for a mesh made from arrays).
    read_ms: f64,
    /// What building the entities took, in ms.
    build_ms: f64,
    /// Moves on with every edit that rewrote the non-vertex elements in place (subdivision:
    /// [`IdsKept::VerticesOnly`]), so that a handle taken before it knows it names nothing.
    element_revision: u64,
    /// The element revision from which vertex handles are good: a vertex handle survives the
    /// edits that move `element_revision` on (subdivision keeps vertices), but not a mesh
    /// replaced whole (`_take`, a lab's copy given back), whose entities are another world's.
    vertex_epoch: u64,
    /// Each element's row, found when a handle first asks after an edit.
    rows: OnceLock<Rows>,
    /// The named scalars of vertices and faces (a PLY's quality, a script's own), by element.
    element_data: ElementData,
    /// The journal of the low-level edit open on the mesh (`with mesh.edit()`), if one is.
    open_edit: Option<Journal>,
    /// The rule the last commit of such an edit found broken, until `pappus.lab` reads it.
    broken: Option<Invalid>,
    /// What the user selected in the editor's window when `pappus.show` last returned.
    selection: Option<Py<PyAny>>,
}

/// Each element's row in its kind's arrays.
struct Rows {
    /// The rows, by entity.
    index: EntityRows,
    /// The elements by kind and row.
    members: MeshMembers,
}

impl Rows {
    /// The rows of `mesh`'s elements now.
    fn of(world: &World, mesh: MeshId) -> Self {
        let members = MeshMembers::collect(world, mesh);
        Self {
            index: EntityRows::new(&members),
            members,
        }
    }
}

impl Mesh {
    /// This mesh's input numbering for `to`, whose vertex at row `j` is this mesh's vertex at
    /// row `sources[j]` (-1: none): an input number names the same vertex, or none where the
    /// vertex is gone.
    fn inputs_handed_over(&self, to: &Mesh, sources: &[i64]) -> Vec<Option<VertexId>> {
        let old = MeshMembers::collect(&self.world, self.mesh).vertices;
        let new = MeshMembers::collect(&to.world, to.mesh).vertices;
        let mut now: EntityHashMap<VertexId> = EntityHashMap::default();
        for (&v, &row) in new.iter().zip(sources) {
            if let Some(was) = usize::try_from(row).ok().and_then(|r| old.get(r)) {
                now.insert(was.0, v);
            }
        }
        (self.input_vertices.iter())
            .map(|v| now.get(&(*v)?.0).copied())
            .collect()
    }

    /// Builds `soup` into a fresh world.
    pub(crate) fn build(soup: &PolygonSoup, info: MeshInfo, read_ms: f64) -> Result<Mesh, String> {
        let start = Instant::now();
        let mut world = World::new();
        let built = build_mesh(&mut world, soup, info).map_err(|e| e.to_string())?;
        let element_data = ElementData::of_soup(soup, &built);
        Ok(Mesh {
            world,
            mesh: built.mesh,
            report: built.report,
            input_vertices: built.input_vertices,
            read_ms,
            build_ms: ms_since(start),
            element_revision: 0,
            vertex_epoch: 0,
            rows: OnceLock::new(),
            element_data,
            open_edit: None,
            broken: None,
            selection: None,
        })
    }

    /// A copy's world lent to a lab's function (`pappus.lab`, [`crate::lab_mode`]): the mesh alone,
    /// with no repair report, input numbering or file data.
    pub(crate) fn lent(world: World, mesh: MeshId) -> Mesh {
        Mesh {
            world,
            mesh,
            report: RepairReport::default(),
            input_vertices: Vec::new(),
            read_ms: 0.0,
            build_ms: 0.0,
            element_revision: 0,
            vertex_epoch: 0,
            rows: OnceLock::new(),
            element_data: ElementData::default(),
            open_edit: None,
            broken: None,
            selection: None,
        }
    }

    /// Gives a lent world back: the world (an edit left open rolled back first), whether one
    /// was open, and the rule the last commit found broken. The mesh then holds nothing, and
    /// every handle on it is stale.
    pub(crate) fn give_back(&mut self) -> (World, bool, Option<Invalid>) {
        let left_open = match self.open_edit.take() {
            Some(journal) => {
                RawEdit::resume(&mut self.world, journal).rollback();
                true
            }
            None => false,
        };
        self.element_revision += 1;
        self.vertex_epoch = self.element_revision;
        self.rows = OnceLock::new();
        (
            std::mem::take(&mut self.world),
            left_open,
            self.broken.take(),
        )
    }

    /// Records the rule a commit found broken.
    pub(crate) fn broke(&mut self, invalid: Invalid) {
        self.broken = Some(invalid);
    }

    /// The mesh entity.
    pub(crate) fn id(&self) -> MeshId {
        self.mesh
    }

    /// The registered operation `name` on `targets` with these keyword values, as `run` reads
    /// them.
    pub(crate) fn invocation_of(
        &self,
        name: &str,
        targets: &[run::Target],
        parameters: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Invocation> {
        run::invocation(&self.world, &self.input_vertices, name, targets, parameters)
    }

    /// The mesh as a soup: vertices in table order, faces as vertex cycles, attributes.
    fn soup(&self) -> PolygonSoup {
        to_soup(&self.world, self.mesh)
    }

    /// Runs a parsed step, the GIL released, reporting to `progress` if given. Returns the
    /// summary; a refusal becomes `Refused`. `progress` returning `False` stops the edit where
    /// it can stop (the summary says so). An exception raised by `progress` is never a
    /// half-told result: the callback is not called again, the edit runs to its end (or its
    /// refusal, which changes nothing), and the exception is re-raised with a note that says
    /// which ([`with_outcome_note`]).
    fn run_step(
        &mut self,
        py: Python<'_>,
        step: Step,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<String> {
        self.run_tracked(py, step, progress, false)
            .map(|(summary, _)| summary)
    }

    /// As [`Mesh::run_step`], and with `track`, what the edit made and removed (see
    /// [`crate::run`]; tracking reads every element once more).
    pub(crate) fn run_tracked(
        &mut self,
        py: Python<'_>,
        step: Step,
        progress: Option<Py<PyAny>>,
        track: bool,
    ) -> PyResult<(String, Changes)> {
        self.no_open_edit()?;
        let ids = ids_kept(&step);
        let before = track.then(|| Before::start(&mut self.world, self.mesh, ids));
        let surface = self.element_data.surface_before(&self.world, self.mesh);
        let Mesh {
            world,
            mesh,
            input_vertices,
            ..
        } = self;
        let (outcome, failure) = py.detach(|| {
            let mut failure: Option<PyErr> = None;
            let mut report = |fraction: f32| -> bool {
                let Some(callback) = &progress else {
                    return true;
                };
                if failure.is_some() {
                    return true;
                }
                Python::attach(|py| match callback.call1(py, (fraction,)) {
                    // None (or any true value) goes on; False stops where the edit can.
                    Ok(answer) => answer.is_none(py) || answer.is_truthy(py).unwrap_or(true),
                    // The edit goes on to its end: stopping it here would change the mesh
                    // and then report a failure.
                    Err(e) => {
                        failure = Some(e);
                        true
                    }
                })
            };
            let outcome = match &step {
                // Whole-mesh edits run here rather than through `Step::run` so that they can
                // report progress; the rest is the same.
                Step::Edit(edit) => {
                    let mut context = EditContext {
                        progress: &mut report,
                    };
                    let applied = edit.run(world, *mesh, &mut context);
                    applied.map(|a| (a.summary, Some(a.redraw)))
                }
                other => other
                    .run(world, *mesh, input_vertices)
                    .map(|summary| (summary, None)),
            };
            (outcome, failure)
        });
        self.rows = OnceLock::new();
        if outcome.is_ok() && ids == IdsKept::VerticesOnly {
            self.element_revision += 1;
        }
        if let (Ok(_), Some(surface)) = (&outcome, &surface) {
            let renumbered = declaration(&step).and_then(|d| d.face_children);
            (self.element_data).carry(surface, &self.world, self.mesh, renumbered);
        }
        if let Some(e) = failure {
            let summary = outcome.as_ref().map(|(summary, _)| summary.clone());
            return Err(with_outcome_note(py, e, &summary.map_err(Clone::clone)));
        }
        let (summary, redraw) = outcome.map_err(|refusal| Refused::new_err(refusal.to_string()))?;
        let changes = before.map_or_else(Changes::default, |b| {
            b.changes(&mut self.world, self.mesh, redraw.as_ref())
        });
        Ok((summary, changes))
    }

    /// Runs `invocation` as [`Mesh::run_tracked`] does, and returns a `pappus.Outcome`: the
    /// summary, with handles on what it made and removed (for an operation on elements; a
    /// whole-mesh one records nothing).
    pub(crate) fn run_invocation(
        slf: &Bound<'_, Self>,
        invocation: Invocation,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let mut mesh = slf.try_borrow_mut()?;
        let before = mesh.element_revision;
        // A whole-mesh edit may make millions of elements: it keeps no record of them.
        let track = !invocation.declaration().names.is_whole_mesh();
        let step = Step::Edit(Edit::Operation(invocation));
        let (summary, changes) = mesh.run_tracked(py, step, progress, track)?;
        let after = mesh.element_revision;
        drop(mesh);
        let changes = track.then_some(changes);
        let made = Made::new(slf.clone().unbind(), changes, before, after);
        let outcome = py.import("pappus")?.getattr("Outcome")?;
        Ok(outcome.call1((summary, made))?.unbind())
    }

    /// Runs the whole-mesh operation `name` with these keyword values (None: automatic).
    fn run_whole(
        slf: &Bound<'_, Self>,
        name: &str,
        values: &[(&str, Bound<'_, PyAny>)],
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_named(slf, name, &PyTuple::empty(slf.py()), values, progress)
    }

    /// Runs `name` on `elements` (as `run` reads its arguments) with these keyword values,
    /// reporting to `progress`: what every method named after an operation comes down to.
    fn run_named(
        slf: &Bound<'_, Self>,
        name: &str,
        elements: &Bound<'_, PyTuple>,
        values: &[(&str, Bound<'_, PyAny>)],
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let parameters = PyDict::new(slf.py());
        for (key, value) in values {
            parameters.set_item(key, value)?;
        }
        Mesh::run(slf, name, elements, progress, Some(&parameters))
    }

    /// Runs `name` on `elements` (one element or a list, as `run` reads its arguments) with
    /// these keyword values.
    fn run_with(
        slf: &Bound<'_, Self>,
        name: &str,
        elements: &Bound<'_, PyAny>,
        values: &[(&str, f64)],
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let values = values
            .iter()
            .map(|&(key, x)| Ok((key, x.into_pyobject(py)?.into_any())))
            .collect::<PyResult<Vec<_>>>()?;
        Mesh::run_named(slf, name, &PyTuple::new(py, [elements])?, &values, None)
    }

    /// Runs `name` on the edge between input vertices `a` and `b`, or, without `b`, on the
    /// element `a` names (a handle, a vertex number, a face's corners), with one choice.
    fn run_on_pair(
        slf: &Bound<'_, Self>,
        name: &str,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        choice: Option<(&str, &str)>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let element = match b {
            Some(b) => PyTuple::new(py, [a, b])?.into_any(),
            None => a.clone(),
        };
        let values: Vec<_> = choice
            .map(|(key, word)| (key, PyString::new(py, word).into_any()))
            .into_iter()
            .collect();
        Mesh::run_named(slf, name, &PyTuple::new(py, [element])?, &values, None)
    }

    /// The world holding the mesh.
    pub(crate) fn world(&self) -> &World {
        &self.world
    }

    /// The element revision now (see [`Mesh::element_revision`]).
    pub(crate) fn element_revision(&self) -> u64 {
        self.element_revision
    }

    /// `RuntimeError` while a low-level edit is open: mid-edit the structure need not close,
    /// and what reads the mesh whole walks it.
    pub(crate) fn no_open_edit(&self) -> PyResult<()> {
        match self.open_edit {
            Some(_) => Err(edit_open()),
            None => Ok(()),
        }
    }

    /// Whether a low-level edit is open.
    pub(crate) fn edit_is_open(&self) -> bool {
        self.open_edit.is_some()
    }

    /// Opens a low-level edit (`RuntimeError` when one is open).
    pub(crate) fn open_edit(&mut self) -> PyResult<()> {
        self.no_open_edit()?;
        self.element_data.opened_edit(&self.world, self.mesh);
        self.open_edit = Some(RawEdit::new(&mut self.world, self.mesh).suspend());
        Ok(())
    }

    /// `vertex_data[name]` or `face_data[name]` by row, if there is such a column.
    pub(crate) fn data_column(&self, per: Per, name: &str) -> PyResult<Option<Vec<f32>>> {
        self.no_open_edit()?;
        Ok(self.element_data.column(per, name, &self.world, self.mesh))
    }

    /// Sets `vertex_data[name]` or `face_data[name]` from values by row.
    pub(crate) fn set_data(&mut self, per: Per, name: &str, values: &[f32]) -> PyResult<()> {
        self.no_open_edit()?;
        (self.element_data).set(per, name, values, &self.world, self.mesh)
    }

    /// Removes `vertex_data[name]` or `face_data[name]`; whether it was there.
    pub(crate) fn remove_data(&mut self, per: Per, name: &str) -> bool {
        self.element_data.remove(per, name)
    }

    /// The names of `vertex_data`'s or `face_data`'s columns.
    pub(crate) fn data_names(&self, per: Per) -> Vec<String> {
        self.element_data.names(per)
    }

    /// The world and the open edit's journal, taken out until [`Mesh::set_aside`] or
    /// [`Mesh::closed_edit`]; `RuntimeError` when no edit is open.
    pub(crate) fn edit_parts(&mut self) -> PyResult<(&mut World, Journal)> {
        let journal = self.open_edit.take().ok_or_else(|| {
            PyRuntimeError::new_err("the edit is not open: use it as `with mesh.edit() as e:`")
        })?;
        self.rows = OnceLock::new();
        Ok((&mut self.world, journal))
    }

    /// Sets the open edit's journal aside again after a change.
    pub(crate) fn set_aside(&mut self, journal: Journal) {
        self.open_edit = Some(journal);
        self.rows = OnceLock::new();
    }

    /// The edit is closed: committed (the simplification history no longer describes the
    /// mesh; the file's normals no longer describe its surface) or rolled back.
    pub(crate) fn closed_edit(&mut self, committed: bool) {
        self.rows = OnceLock::new();
        self.element_data
            .closed_edit(committed, &self.world, self.mesh);
        if committed {
            SimplificationHistory::end(&mut self.world, self.mesh);
            if MeshAttributes::of(&self.world, self.mesh).normals {
                self.world.entity_mut(self.mesh.0).insert(StaleNormals);
            }
        }
    }

    /// Whether `id` is still an element of this mesh, the same one it was at `revision`.
    pub(crate) fn holds(&self, id: ElementId, revision: u64) -> bool {
        let same = match id {
            ElementId::Vertex(_) => revision >= self.vertex_epoch,
            _ => revision == self.element_revision,
        };
        same && match id {
            ElementId::Vertex(v) => self.world.get::<Vertex>(v.0).is_some(),
            ElementId::Halfedge(h) => self.world.get::<Halfedge>(h.0).is_some(),
            ElementId::Edge(e) => self.world.get::<Edge>(e.0).is_some(),
            ElementId::Face(f) => self.world.get::<Face>(f.0).is_some(),
            ElementId::Mesh(m) => m == self.mesh,
        }
    }

    /// The rows of the elements now.
    fn rows(&self) -> &Rows {
        self.rows.get_or_init(|| Rows::of(&self.world, self.mesh))
    }

    /// The row of a live element's entity (`None` for one an open edit took out).
    pub(crate) fn row_of(&self, e: Entity) -> Option<usize> {
        self.rows().index.row(e).map(|r| r as usize)
    }

    /// Moves vertices as one edit (`Edit::Move`): a refusal (a position not finite) changes
    /// nothing and raises `Refused`.
    pub(crate) fn set_positions(
        &mut self,
        py: Python<'_>,
        moves: Vec<(VertexId, Vec3)>,
    ) -> PyResult<()> {
        self.run_step(py, Step::Edit(Edit::Move(moves)), None)
            .map(drop)
    }

    /// A handle on the element in `row` of the kind `list` picks from the members (a negative
    /// row counts from the end, as Python's indexing does); `IndexError` outside.
    fn handle_at<T: Copy + Into<ElementId>>(
        slf: &Bound<'_, Self>,
        row: i64,
        kind: &str,
        list: fn(&MeshMembers) -> &[T],
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let mesh = slf.borrow();
        let elements = list(&mesh.rows().members);
        let count = elements.len();
        let index = if row < 0 { row + count as i64 } else { row };
        if !(0..count as i64).contains(&index) {
            return Err(PyIndexError::new_err(format!(
                "{kind} row {row} is out of range: the mesh has {count}"
            )));
        }
        let at = At::new(
            py,
            &slf.clone().unbind(),
            elements[index as usize].into(),
            mesh.element_revision,
        );
        drop(mesh);
        handle(py, at)
    }

    /// Parses `text` as a `process` step (a malformed one is a `ValueError` with the command
    /// line's message) and runs it.
    fn run_text(
        &mut self,
        py: Python<'_>,
        text: &str,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<String> {
        let step = Step::parse(text).map_err(PyValueError::new_err)?;
        self.run_step(py, step, progress)
    }

    /// The state a pickle carries: arrays of the soup, the input-vertex map as rows of those
    /// arrays, the name and the repair counts.
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.no_open_edit()?;
        let members = MeshMembers::collect(&self.world, self.mesh);
        let rows = members.vertex_rows();
        let input_rows: Vec<i64> = self
            .input_vertices
            .iter()
            .map(|v| {
                v.and_then(|v| rows.get(&v.0).copied())
                    .map_or(-1, i64::from)
            })
            .collect();
        let soup = self.soup();
        let state = PyDict::new(py);
        state.set_item("vertices", vec3_array(py, &soup.positions)?)?;
        state.set_item("indices", PyArray1::from_slice(py, &soup.indices))?;
        state.set_item("face_starts", PyArray1::from_slice(py, &soup.face_starts))?;
        state.set_item("input_rows", PyArray1::from_vec(py, input_rows))?;
        let uvs = soup
            .corner_uvs
            .as_ref()
            .map(|uv| vec2_array(py, uv))
            .transpose()?;
        state.set_item("corner_uvs", uvs)?;
        let normals = soup
            .vertex_normals
            .as_ref()
            .map(|n| vec3_array(py, n))
            .transpose()?;
        state.set_item("vertex_normals", normals)?;
        let colors = soup
            .vertex_colors
            .as_ref()
            .map(|c| {
                let flat: Vec<u8> = c.iter().flatten().copied().collect();
                PyArray1::from_vec(py, flat).reshape([c.len(), 3])
            })
            .transpose()?;
        state.set_item("vertex_colors", colors)?;
        state.set_item(
            "face_groups",
            face_groups_dict(py, soup.face_groups.as_ref())?,
        )?;
        let data = |per| self.element_data.dict(py, per, &self.world, self.mesh);
        state.set_item("vertex_data", data(Per::Vertex)?)?;
        state.set_item("face_data", data(Per::Face)?)?;
        state.set_item("name", self.name())?;
        let repairs: Vec<usize> = self.report.entries().iter().map(|&(_, n)| n).collect();
        state.set_item("repairs", repairs)?;
        state.set_item("read_ms", self.read_ms)?;
        Ok(state)
    }

    /// The mesh's name (the file name, the shape, or `arrays`).
    fn name(&self) -> String {
        self.world
            .get::<MeshInfo>(self.mesh.0)
            .map_or_else(String::new, |i| i.name.clone())
    }
}

#[pymethods]
impl Mesh {
    /// Makes a mesh from arrays: `vertices` an N×3 array-like of floats (any float dtype, kept
    /// as float32), `faces` an M×3 or M×4 integer array or a sequence of index sequences
    /// (polygons of any sizes, 0-based rows of `vertices`).
    ///
    /// The input is repaired as a file is (see `info()["repairs"]`): faces that repeat a vertex
    /// dropped, faces turned to agree with their neighbours, non-manifold vertices split.
    /// Raises `ValueError` for an index outside `vertices`, a wrong shape, or when no face is
    /// left after the repairs.
    #[new]
    fn new(
        py: Python<'_>,
        vertices: PyArrayLike2<'_, f32, AllowTypeChange>,
        faces: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let start = Instant::now();
        let flat = float_rows(&vertices, 3, "vertices")?;
        let positions: Vec<Vec3> = flat
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        let faces = read_faces(faces, positions.len())?;
        let soup = PolygonSoup::from_faces(positions, &faces);
        let read_ms = ms_since(start);
        let info = MeshInfo {
            name: "arrays".into(),
            path: None,
        };
        py.detach(|| Mesh::build(&soup, info, read_ms))
            .map_err(PyValueError::new_err)
    }

    /// The vertex positions, N×3 float32 (the mesh's storage precision), in the mesh's table
    /// order: the order they were given in, less what the repairs dropped or added, until an
    /// edit renumbers them. A copy: writing to it does not move the mesh.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = pappus::mesh::MeshRef::new(&self.world);
        let members = MeshMembers::collect(&self.world, self.mesh);
        let positions: Vec<Vec3> = members.vertices.iter().map(|&v| m.position(v)).collect();
        vec3_array(py, &positions)
    }

    /// Sets every vertex's position as one edit: an N×3 array-like of floats (any float
    /// dtype, stored as float32), one row a vertex in the order of `vertices`. `ValueError` for
    /// another shape or a coordinate that is not finite (naming its row); the mesh is then
    /// untouched.
    #[setter]
    fn set_vertices(
        &mut self,
        py: Python<'_>,
        vertices: PyArrayLike2<'_, f64, AllowTypeChange>,
    ) -> PyResult<()> {
        let members = MeshMembers::collect(&self.world, self.mesh);
        let positions = quantities::positions(&vertices, members.vertices.len())?;
        let moves = members.vertices.into_iter().zip(positions).collect();
        self.set_positions(py, moves)
    }

    /// The mesh's named per-vertex scalars: those the source carried that the mesh has no
    /// column for (a PLY's `quality`) and the script's own (`mesh.vertex_data["d"] = array`,
    /// one value per vertex). A mapping of float32 arrays by row of `vertices`; each value
    /// follows its vertex through edits, a vertex an edit made gets the value interpolated at
    /// its place on the surface before, and a PLY save writes them as vertex properties.
    #[getter]
    fn vertex_data(slf: &Bound<'_, Self>) -> ElementDataView {
        ElementDataView {
            mesh: slf.clone().unbind(),
            per: Per::Vertex,
        }
    }

    /// The mesh's named per-face scalars: a PLY's face properties (`quality`, `flags`, …) and
    /// the script's own (`mesh.face_data["label"] = array`, one value per face). A mapping of
    /// float32 arrays by row of `faces`; each value follows its face through edits (a flip
    /// keeps both faces), a face an edit made takes the value of the face it was cut from (the
    /// one its centroid lies on before the edit), and a PLY save writes them as face
    /// properties.
    #[getter]
    fn face_data(slf: &Bound<'_, Self>) -> ElementDataView {
        ElementDataView {
            mesh: slf.clone().unbind(),
            per: Per::Face,
        }
    }

    /// The vertex normals, N×3 float32 by row of `vertices`: what a save writes (the file's
    /// normals while no edit changed the surface, else angle-weighted normals of it). A copy.
    #[getter]
    fn vertex_normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.no_open_edit()?;
        let normals = py.detach(|| quantities::normals(&self.world, self.mesh));
        vec3_array(py, &normals)
    }

    /// A per-vertex quantity as float64 by row of `vertices`, the values the editor colours by
    /// and `pappus process --quantity NAME` writes: `mean`, `gaussian`, `angle-defect`,
    /// `max-curvature`, `min-curvature`, `valence`, `min-angle` (degrees), `edge-length` (the
    /// mean of the vertex's edges), `distance` (to the mesh given as `to`, which only it takes),
    /// or any other registered quantity (one that starts from vertices takes their rows as
    /// `sources`). `ValueError` for an unknown name, a missing or misplaced `to` or `sources`,
    /// or a source row out of range. The GIL is released meanwhile.
    #[pyo3(signature = (name, *, to=None, sources=None))]
    fn quantity<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        to: Option<PyRef<'py, Mesh>>,
        sources: Option<Vec<i64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.no_open_edit()?;
        if let Some(other) = &to {
            other.no_open_edit()?;
        }
        let quantity = quantities::quantity_named(name)?;
        let to = to.as_deref().map(|m| (&m.world, m.mesh));
        let values =
            py.detach(|| quantities::per_vertex(&self.world, self.mesh, quantity, to, sources))?;
        Ok(PyArray1::from_vec(py, values))
    }

    /// The faces as rows of `vertices`: an M×k int64 array when every face has k sides, else a
    /// list of int64 arrays (one per face). A copy.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.no_open_edit()?;
        let (_, indices, starts) = positions_and_faces(&self.world, self.mesh);
        faces_array(py, &indices, &starts)
    }

    /// `(vertices, faces)` in one pass over the mesh: what the two properties give.
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        self.no_open_edit()?;
        let (positions, indices, starts) = positions_and_faces(&self.world, self.mesh);
        Ok((
            vec3_array(py, &positions)?,
            faces_array(py, &indices, &starts)?,
        ))
    }

    /// The halfedge structure as int64 arrays (`pappus.Connectivity`): per halfedge `next`,
    /// `prev`, `twin`, `to_vertex`, `from_vertex`, `edge` and `face` (−1 on the boundary); per
    /// vertex `vertex_halfedge` (outgoing, the boundary one on a boundary, −1 when isolated);
    /// `edge_halfedge`; `face_halfedge`. Vertex and face rows are those of `vertices` and
    /// `faces`: walking `next` from `face_halfedge[f]` visits `faces[f]`'s corners in order.
    /// A snapshot, taken with the GIL released.
    fn connectivity(&self, py: Python<'_>) -> PyResult<ConnectivityArrays> {
        self.no_open_edit()?;
        Ok(ConnectivityArrays::of(py, &self.world, self.mesh))
    }

    /// A low-level edit of the mesh, used as `with mesh.edit() as e:` (`pappus.MeshEdit`):
    /// inside, `e.set_next(h, n)`, `e.set_twin`, `e.set_to_vertex`, `e.set_edge`,
    /// `e.set_face`, `e.set_halfedge`, `e.set_position`, `e.new_vertex`, `e.new_edge`,
    /// `e.new_face`, `e.remove` rewire the structure freely; leaving the block commits, or
    /// raises `InvalidMesh` naming the broken rule with the mesh exactly as before. An
    /// exception inside the block rolls back. While it is open, the mesh runs nothing that
    /// reads it whole.
    fn edit(slf: &Bound<'_, Self>) -> MeshEdit {
        MeshEdit::of(slf.clone().unbind())
    }

    /// Runs the operation called `name` (as `pappus.operations()` lists it; `_` reads as `-`)
    /// on `elements` (handles, input vertex numbers, or sequences of numbers naming an edge or
    /// a face), with its declared parameters as keywords (lower case; a choice by its word;
    /// None for automatic; the rest their defaults), reporting to `progress` as the whole-mesh
    /// methods do. Returns a `pappus.Outcome`: the summary string, with `.created` and
    /// `.removed` handles. `ValueError` for an unknown name, elements the operation does not
    /// name, an unknown keyword or a value out of range; `StaleElement` for a removed handle;
    /// `Refused` (the mesh untouched) when the operation refuses.
    #[pyo3(signature = (name, *elements, progress=None, **parameters))]
    fn run(
        slf: &Bound<'_, Self>,
        name: &str,
        elements: &Bound<'_, PyTuple>,
        progress: Option<Py<PyAny>>,
        parameters: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyAny>> {
        let targets = run::targets(slf, elements)?;
        let invocation = slf
            .try_borrow()?
            .invocation_of(name, &targets, parameters)?;
        Mesh::run_invocation(slf, invocation, progress)
    }

    /// The vertex in `row` of `vertices` (negative rows count from the end): a handle with its
    /// `id`, `position`, `halfedge` and circulators. `IndexError` outside the rows.
    fn vertex(slf: &Bound<'_, Self>, row: i64) -> PyResult<Py<PyAny>> {
        Mesh::handle_at(slf, row, "vertex", |m| &m.vertices)
    }

    /// The halfedge in `row` of `connectivity()`'s halfedge arrays. `IndexError` outside.
    fn halfedge(slf: &Bound<'_, Self>, row: i64) -> PyResult<Py<PyAny>> {
        Mesh::handle_at(slf, row, "halfedge", |m| &m.halfedges)
    }

    /// The edge in `row` of `connectivity()`'s edge arrays. `IndexError` outside.
    fn edge(slf: &Bound<'_, Self>, row: i64) -> PyResult<Py<PyAny>> {
        Mesh::handle_at(slf, row, "edge", |m| &m.edges)
    }

    /// The face in `row` of `faces`. `IndexError` outside.
    fn face(slf: &Bound<'_, Self>, row: i64) -> PyResult<Py<PyAny>> {
        Mesh::handle_at(slf, row, "face", |m| &m.faces)
    }

    /// The element the editor's inspector calls `id` (`"v12v0"`, `"h7v0"`, `"e3v0"`,
    /// `"f5v0"`; a missing generation means 0). `ValueError` for text that is no element id,
    /// `StaleElement` for an id that names no element of this mesh now.
    fn element(slf: &Bound<'_, Self>, id: &str) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let parsed = parse_element(id).ok_or_else(|| {
            PyValueError::new_err(format!(
                "`{id}` is no element id: a kind (v, h, e, f) and an entity, as `v12v0`"
            ))
        })?;
        let mesh = slf.borrow();
        let revision = mesh.element_revision;
        if matches!(parsed, ElementId::Mesh(_)) || !mesh.holds(parsed, revision) {
            return Err(match parsed {
                ElementId::Mesh(_) => {
                    PyValueError::new_err(format!("`{id}` names a mesh, not an element"))
                }
                _ => stale(parsed),
            });
        }
        drop(mesh);
        handle(py, At::new(py, &slf.clone().unbind(), parsed, revision))
    }

    /// The texture coordinates per face corner, K×2 float32 in the order of the faces' corners
    /// (face by face, as `faces` lists them), or None when the mesh has none.
    #[getter]
    fn corner_uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.no_open_edit()?;
        self.soup()
            .corner_uvs
            .as_ref()
            .map(|uv| vec2_array(py, uv))
            .transpose()
    }

    /// The object, group, material and smoothing group of each face (OBJ's `o`, `g`, `usemtl`,
    /// `s`; glTF's and COLLADA's node and material names): a dict of `groups` (one dict of
    /// `object`, `group`, `material`, `smoothing` per distinct combination, each a string or
    /// None), `face` (each face's row in `groups`, uint32, in the order of `faces`) and
    /// `material_libraries` (the `mtllib` names); None when the mesh has none.
    #[getter]
    fn face_groups<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.no_open_edit()?;
        face_groups_dict(py, self.soup().face_groups.as_ref())
    }

    /// The mesh's name: the file name, the shape's name, or `arrays`.
    #[getter(name)]
    fn py_name(&self) -> String {
        self.name()
    }

    /// Statistics, validation and repairs: a dict with the keys of `pappus info --json`
    /// (`vertices`, `faces`, `genus`, `valid`, `repairs`, `curvature`, …, `read_ms`, `build_ms`,
    /// `load_ms`), computed by the command line's own code.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.no_open_edit()?;
        let object = py.detach(|| {
            info_with_load_times(
                &self.world,
                self.mesh,
                &self.report,
                self.read_ms,
                self.build_ms,
            )
        });
        let text = serde_json::Value::Object(object).to_string();
        py.import("json")?.call_method1("loads", (text,))
    }

    /// Checks every invariant of the halfedge structure. Returns None when they all hold;
    /// raises `InvalidMesh` naming the broken rule and element otherwise.
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        py.detach(|| validate(&self.world, self.mesh))
            .map_err(|e| InvalidMesh::new_err(e.to_string()))
    }

    /// Writes the mesh to `path`, the format chosen by its extension (.obj .off .ply .stl .glb .gltf), with
    /// the attributes it has (UVs, normals, colours, and `vertex_data` and `face_data`, which
    /// PLY holds). Writes
    /// a temporary file and renames it over the target, so a failed save leaves the old file.
    /// Raises `ValueError` for an unknown extension or `.dae` (read only), `OSError` when the
    /// file system refuses. What the format cannot hold (OFF and STL: UVs, normals, colours;
    /// all but PLY: `vertex_data` and `face_data`; STL and glTF: polygons, written as
    /// triangles) is dropped
    /// with a `UserWarning` naming it.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        self.no_open_edit()?;
        let (mut soup, recomputed) = pappus::edit::soup_to_save(&self.world, self.mesh);
        self.element_data
            .put_into(&self.world, self.mesh, &mut soup);
        let dropped = io::dropped(&path, &soup);
        py.detach(|| io::write(&path, &soup))
            .map_err(|e| io_error(py, e))?;
        if let Some(note) = recomputed {
            user_warning(py, format!("{}: {note}", path.display()))?;
        }
        if dropped.is_empty() {
            Ok(())
        } else {
            user_warning(py, io::dropped_note(&path, &dropped))
        }
    }

    /// Runs one command-line step as `pappus process` writes it (`"simplify:0.25"`,
    /// `"flip:3,17"`, `"extrude:0,1,2:0.5"`, …) and returns its summary. Raises `ValueError` for a
    /// malformed step, `Refused` when the step is refused.
    #[pyo3(signature = (step, *, progress=None))]
    fn step(
        &mut self,
        py: Python<'_>,
        step: &str,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<String> {
        self.run_text(py, step, progress)
    }

    /// QEM simplification (Garland–Heckbert) to `ratio` (0–1] of the faces or to `faces` faces
    /// (give at most one; neither: half the faces), recording the history `refine` splits back;
    /// `distance` > 0 weighs how far each collapse takes the input away (8: closer, in about
    /// three times the time); `fit=True` fits the result's vertices to the input at the end.
    /// Returns the summary. The GIL is released; `progress(fraction)` is called now and then
    /// (return False to stop early: the mesh stays valid, partly simplified).
    #[pyo3(signature = (ratio=None, faces=None, distance=0.0, fit=false, *, progress=None))]
    fn simplify(
        slf: &Bound<'_, Self>,
        ratio: Option<f64>,
        faces: Option<usize>,
        distance: f64,
        fit: bool,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let distance = ("distance", distance.into_pyobject(py)?.into_any());
        let fit = (
            "fit",
            if fit { "fit" } else { "no-fit" }
                .into_pyobject(py)?
                .into_any(),
        );
        match (ratio, faces) {
            (Some(_), Some(_)) => Err(PyValueError::new_err(
                "give a ratio or a face count, not both",
            )),
            (None, Some(n)) => Mesh::run_whole(
                slf,
                "simplify-faces",
                &[("faces", n.into_pyobject(py)?.into_any()), distance, fit],
                progress,
            ),
            (r, None) => {
                let ratio = r.unwrap_or(0.5).into_pyobject(py)?.into_any();
                Mesh::run_whole(
                    slf,
                    "simplify",
                    &[("ratio", ratio), distance, fit],
                    progress,
                )
            }
        }
    }

    /// Isotropic remeshing (Botsch–Kobbelt): `iterations` (1–100) rounds of split, collapse,
    /// flip and relax toward edges of `length` (default: the mean edge length), features over
    /// 45° kept. Triangulates first. Returns the summary; GIL released, `progress` as for
    /// `simplify`.
    #[pyo3(signature = (iterations=5, length=None, *, progress=None))]
    fn remesh(
        slf: &Bound<'_, Self>,
        iterations: u32,
        length: Option<f64>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let values = [
            ("iterations", iterations.into_pyobject(py)?.into_any()),
            ("length", length.into_pyobject(py)?.into_any()),
        ];
        Mesh::run_whole(slf, "remesh", &values, progress)
    }

    /// Loop subdivision, `levels` (1–8) times; triangles only (`Refused` otherwise). Returns the
    /// summary; GIL released, `progress` as for `simplify`.
    #[pyo3(name = "loop", signature = (levels=1, *, progress=None))]
    fn loop_subdivide(
        slf: &Bound<'_, Self>,
        levels: u32,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let levels = levels.into_pyobject(slf.py())?.into_any();
        Mesh::run_whole(slf, "loop", &[("levels", levels)], progress)
    }

    /// Catmull–Clark subdivision, `levels` (1–8) times: any polygons become quads. Returns the
    /// summary; GIL released, `progress` as for `simplify`.
    #[pyo3(signature = (levels=1, *, progress=None))]
    fn catmull_clark(
        slf: &Bound<'_, Self>,
        levels: u32,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let levels = levels.into_pyobject(slf.py())?.into_any();
        Mesh::run_whole(slf, "catmull-clark", &[("levels", levels)], progress)
    }

    /// Cuts every polygon into triangles. Returns the summary; GIL released.
    #[pyo3(signature = (*, progress=None))]
    fn triangulate(slf: &Bound<'_, Self>, progress: Option<Py<PyAny>>) -> PyResult<Py<PyAny>> {
        Mesh::run_whole(slf, "triangulate", &[], progress)
    }

    /// Turns every face round (its corners in the opposite order, its normal the other way);
    /// ids, UVs and groups stay, vertex normals change sign. Returns the summary.
    fn reverse(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        Mesh::run_whole(slf, "reverse", &[], None)
    }

    /// Turns round each part (faces joined across edges) whose faces point inward, as
    /// Blender's Recalculate Outside does. Returns the summary.
    fn orient_outside(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        Mesh::run_whole(slf, "orient-outside", &[], None)
    }

    /// Smooths with `method` (`uniform`, `cotan`, `implicit`, `taubin`), `iterations` times
    /// (1–10000) with `step` (default 0.5; implicit: 1.0, in units of the squared mean edge
    /// length). The boundary stays. Returns the summary; GIL released.
    #[pyo3(signature = (method="uniform", iterations=1, step=None, *, progress=None))]
    fn smooth(
        slf: &Bound<'_, Self>,
        method: &str,
        iterations: u32,
        step: Option<f64>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let values = [
            ("method", method.into_pyobject(py)?.into_any()),
            ("iterations", iterations.into_pyobject(py)?.into_any()),
            ("step", step.into_pyobject(py)?.into_any()),
        ];
        Mesh::run_whole(slf, "smooth", &values, progress)
    }

    /// A UV per face corner: `method` `uniform`, `mean-value`, `harmonic` (the boundary on a
    /// `circle` or a `square`) or `lscm` (free boundary). A closed genus-0 mesh is cut open
    /// automatically (or along the edges marked with `seam`); anything else not a disk is
    /// `Refused`, naming its genus and loops. Returns the summary (flipped triangles,
    /// distortion); GIL released.
    #[pyo3(signature = (method="mean-value", boundary="circle", *, progress=None))]
    fn parameterize(
        slf: &Bound<'_, Self>,
        method: &str,
        boundary: &str,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let values = [
            ("method", method.into_pyobject(py)?.into_any()),
            ("boundary", boundary.into_pyobject(py)?.into_any()),
        ];
        Mesh::run_whole(slf, "param", &values, progress)
    }

    /// Splits the last `simplify`'s collapses back, up to `faces` faces (default: all of them,
    /// exactly the mesh before the simplification). `Refused` with no history (none recorded, or
    /// an edit since that does not keep it). Returns the summary; GIL released.
    #[pyo3(signature = (faces=None, *, progress=None))]
    fn refine(
        slf: &Bound<'_, Self>,
        faces: Option<usize>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let faces = faces.into_pyobject(slf.py())?.into_any();
        Mesh::run_whole(slf, "refine", &[("faces", faces)], progress)
    }

    /// Flips the edge between input vertices `a` and `b` (two triangles). `Refused` on a boundary
    /// edge, when the new edge exists, or when no edge joins them.
    #[pyo3(signature = (a, b=None))]
    fn flip(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "flip", a, b, None)
    }

    /// Splits the edge between input vertices `a` and `b` at its midpoint (the faces beside it
    /// are cut in two).
    #[pyo3(signature = (a, b=None))]
    fn split(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "split", a, b, None)
    }

    /// Puts a vertex at the midpoint of edge `a`–`b` without cutting a face (each gains a side).
    #[pyo3(signature = (a, b=None))]
    fn bisect(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "bisect", a, b, None)
    }

    /// Collapses the edge `a`–`b` to its midpoint. `Refused` when the link condition fails (the
    /// mesh would stop being a manifold), as on any edge of a tetrahedron.
    #[pyo3(signature = (a, b=None))]
    fn collapse(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "collapse", a, b, None)
    }

    /// Merges the two faces of edge `a`–`b` into one polygon. `Refused` on a boundary edge.
    #[pyo3(signature = (a, b=None))]
    fn dissolve(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "dissolve", a, b, None)
    }

    /// Fills the hole beside the boundary edge `a`–`b`: its loop becomes one face, or with
    /// `fair=True` a patch of triangles at the surrounding density that continues the surface's
    /// curvature (Liepa 2003). `Refused` on an interior edge.
    #[pyo3(signature = (a, b=None, *, fair=false))]
    fn fill_hole(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
        fair: bool,
    ) -> PyResult<Py<PyAny>> {
        let fill = if fair { "fair" } else { "polygon" };
        Mesh::run_on_pair(slf, "fill-hole", a, b, Some(("fill", fill)))
    }

    /// Fills every hole: with fair patches of triangles (`fair=True`, the default), else one
    /// polygon each. Holes a fair fill refuses are left open and named in the summary; `Refused`
    /// when the mesh has none.
    #[pyo3(signature = (fair=true))]
    fn fill_holes(slf: &Bound<'_, Self>, fair: bool) -> PyResult<Py<PyAny>> {
        let fill = if fair { "fair" } else { "polygon" };
        let fill = fill.into_pyobject(slf.py())?.into_any();
        Mesh::run_whole(slf, "fill-holes", &[("fill", fill)], None)
    }

    /// Handle deformation: the input vertices `fixed` stay, `handle` moves by `offset`
    /// (dx, dy, dz), the rest follows by `method`: `"arap"` (as-rigid-as-possible,
    /// `iterations` local/global steps, default 10) or `"laplace"` (thin plate, one solve).
    /// Returns the summary (energy before and after, the factor and iteration times). `Refused`
    /// for an empty handle or a vertex in both lists; GIL released.
    #[pyo3(signature = (method, fixed, handle, offset, iterations=10))]
    fn deform(
        &mut self,
        py: Python<'_>,
        method: &str,
        fixed: Vec<u32>,
        handle: Vec<u32>,
        offset: (f64, f64, f64),
        iterations: u32,
    ) -> PyResult<String> {
        let list = |v: &[u32]| v.iter().map(u32::to_string).collect::<Vec<_>>().join("/");
        let text = format!(
            "deform:{method}:{}:{}:{},{},{}:{iterations}",
            list(&fixed),
            list(&handle),
            number(offset.0),
            number(offset.1),
            number(offset.2)
        );
        self.run_text(py, &text, None)
    }

    /// Fairs the input vertices `vertices`: they solve the k-harmonic equation (`k` 1, 2 or 3,
    /// default 2), every other vertex held. Returns the summary.
    #[pyo3(signature = (vertices, k=2))]
    fn fair(slf: &Bound<'_, Self>, vertices: &Bound<'_, PyAny>, k: u32) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let parameters = PyDict::new(py);
        parameters.set_item("k", k)?;
        // Input vertex numbers are each a vertex here (elsewhere a list of them is one face).
        let elements = match vertices.extract::<Vec<u32>>() {
            Ok(numbers) => PyTuple::new(py, numbers)?,
            Err(_) => PyTuple::new(py, [vertices])?,
        };
        Mesh::run(slf, "fair", &elements, None, Some(&parameters))
    }

    /// Splits the face that input vertices `a` and `b` share with a new edge between them.
    #[pyo3(signature = (a, b=None))]
    fn split_face(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "split-face", a, b, None)
    }

    /// Marks the edge `a`–`b` as a seam for `parameterize` to cut along (again: unmarks it).
    #[pyo3(signature = (a, b=None))]
    fn seam(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "seam", a, b, None)
    }

    /// Extrudes `faces` (one face as its corners `(a, b, c, …)`, or a sequence of them) as one
    /// region, pushed `distance` along its normals on a wall of quads.
    fn extrude(
        slf: &Bound<'_, Self>,
        faces: &Bound<'_, PyAny>,
        distance: f64,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_with(slf, "extrude", faces, &[("distance", distance)])
    }

    /// Insets each of `faces`: a ring of quads inside it, its corners moved `amount` (0–1) of
    /// the way to its centre and `depth` along its normal.
    #[pyo3(signature = (faces, amount, depth=0.0))]
    fn inset(
        slf: &Bound<'_, Self>,
        faces: &Bound<'_, PyAny>,
        amount: f64,
        depth: f64,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_with(slf, "inset", faces, &[("amount", amount), ("depth", depth)])
    }

    /// Bevels one element: a vertex (`a`) or an edge (`(a, b)`) becomes a face whose corners
    /// lie `amount` (0–0.5) along its edges; a face (`(a, b, c, …)`) is inset by `amount` with
    /// `depth`.
    #[pyo3(signature = (element, amount=0.25, depth=0.0))]
    fn bevel(
        slf: &Bound<'_, Self>,
        element: &Bound<'_, PyAny>,
        amount: f64,
        depth: f64,
    ) -> PyResult<Py<PyAny>> {
        Mesh::run_with(
            slf,
            "bevel",
            element,
            &[("amount", amount), ("depth", depth)],
        )
    }

    /// Erases elements (vertices, edges, faces; one or a sequence): their faces become holes,
    /// and edges and vertices left with no face go too.
    fn erase(slf: &Bound<'_, Self>, elements: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        Mesh::run_with(slf, "erase", elements, &[])
    }

    /// Merges the faces around input vertex `a` into one polygon and removes the vertex.
    fn dissolve_vertex(slf: &Bound<'_, Self>, a: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "dissolve", a, None, None)
    }

    /// Collapses the face with corners `(a, b, c, …)` to its centroid.
    fn collapse_face(slf: &Bound<'_, Self>, face: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        Mesh::run_on_pair(slf, "collapse", face, None, None)
    }

    /// Glues boundary edge `second` (a pair of input vertices) onto boundary edge `first`;
    /// their ends merge at the midpoints.
    fn weld(
        slf: &Bound<'_, Self>,
        first: &Bound<'_, PyAny>,
        second: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let both = PyList::new(py, [first, second])?;
        Mesh::run_with(slf, "weld", both.as_any(), &[])
    }

    /// An independent copy (same vertex numbering for the operations; the simplification
    /// history and seam marks are not copied).
    fn copy(&self, py: Python<'_>) -> PyResult<Mesh> {
        Mesh::from_state(&self.state(py)?)
    }

    /// `copy.copy(mesh)`: as `copy()`.
    fn __copy__(&self, py: Python<'_>) -> PyResult<Mesh> {
        self.copy(py)
    }

    /// `copy.deepcopy(mesh)`: as `copy()`.
    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> PyResult<Mesh> {
        self.copy(py)
    }

    /// Pickling: the vertices, faces, attributes (UVs, normals, colours, face groups), name, repair counts
    /// and the input-vertex numbering, so operations name the same vertices after unpickling.
    /// The simplification history and seam marks are not carried.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let restore = py.import("pappus")?.getattr("_restore")?;
        let state = self.state(py)?;
        Ok((restore, (state,)).into_pyobject(py)?.into_any())
    }

    /// A mesh from a `trimesh.Trimesh`: `Mesh(t.vertices, t.faces)`, its rows in trimesh's
    /// order (repaired as any input is). Raises `AttributeError` for an object without
    /// `vertices` and `faces`, and as `Mesh(...)` does.
    #[staticmethod]
    fn from_trimesh(py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<Mesh> {
        let vertices = t.getattr("vertices")?;
        let mut mesh = Mesh::new(py, vertices.extract()?, &t.getattr("faces")?)?;
        mesh.world
            .get_mut::<MeshInfo>(mesh.mesh.0)
            .expect("the mesh entity")
            .name = "trimesh".into();
        Ok(mesh)
    }

    /// This mesh as a `trimesh.Trimesh`, with `process=False` so that its rows stay this
    /// mesh's (`vertices`, `faces`). Raises `ValueError` for a mesh with polygons, which trimesh
    /// cannot hold (`triangulate()` first), and `ImportError` without trimesh installed.
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (vertices, faces) = self.arrays(py)?;
        let triangles = faces
            .getattr("shape")
            .ok()
            .and_then(|s| s.extract::<(usize, usize)>().ok())
            .is_some_and(|(_, k)| k == 3);
        if !triangles {
            return Err(PyValueError::new_err(
                "trimesh holds triangles only: triangulate() the mesh first",
            ));
        }
        let trimesh = py.import("trimesh").map_err(|e| {
            pyo3::exceptions::PyImportError::new_err(format!(
                "to_trimesh needs trimesh (pip install trimesh): {e}"
            ))
        })?;
        let keywords = PyDict::new(py);
        keywords.set_item("vertices", vertices)?;
        keywords.set_item("faces", faces)?;
        keywords.set_item("process", false)?;
        trimesh.getattr("Trimesh")?.call((), Some(&keywords))
    }

    /// Rebuilds a mesh from `__reduce__`'s state dict.
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyDict>) -> PyResult<Mesh> {
        Mesh::from_state(state)
    }

    /// What the user selected in the editor's window when `pappus.show` last returned on
    /// this mesh (a `pappus.Selection`: handles and rows by kind), or `None` before. Its
    /// handles go stale with an edit as any handle does; its rows are the rows when the window
    /// closed.
    #[getter]
    fn selection(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.selection.as_ref().map(|s| s.clone_ref(py))
    }

    /// What Python's garbage collector follows: the selection, whose handles point back here.
    fn __traverse__(&self, visit: pyo3::PyVisit<'_>) -> Result<(), pyo3::PyTraverseError> {
        if let Some(selection) = &self.selection {
            visit.call(selection)?;
        }
        Ok(())
    }

    /// Breaks a cycle through the selection for the garbage collector.
    fn __clear__(&mut self) {
        self.selection = None;
    }

    /// Keeps what `pappus.show` read back as [`Mesh::selection`].
    fn _set_selection(&mut self, selection: Py<PyAny>) {
        self.selection = Some(selection);
    }

    /// Takes `other`'s mesh as this one's (what `pappus.show` does with the mesh the editor
    /// hands back after an edit): its elements, numbering and file data; the name stays this
    /// mesh's. Every handle
    /// taken on this mesh before is stale afterwards; `other` is left with this mesh's old
    /// contents. `RuntimeError` while an edit is open on either.
    ///
    /// With `vertex_sources` (for each of `other`'s vertices, the row of this mesh's vertex it
    /// is, -1 for one made since), this mesh's input numbers and `vertex_data` go over to
    /// `other`'s vertices, and with `face_sources` too (the same for faces) its `face_data`
    /// ([`ElementData::handed_over`]); `ValueError` when a list does not have one row per
    /// element of `other`.
    #[pyo3(signature = (other, vertex_sources=None, face_sources=None))]
    fn _take(
        &mut self,
        mut other: PyRefMut<'_, Mesh>,
        vertex_sources: Option<Vec<i64>>,
        face_sources: Option<Vec<i64>>,
    ) -> PyResult<()> {
        if self.open_edit.is_some() || other.open_edit.is_some() {
            return Err(edit_open());
        }
        if let Some(sources) = vertex_sources {
            let to = (&other.world, other.mesh);
            let faces = face_sources.as_deref();
            let data = (self.element_data)
                .handed_over((&self.world, self.mesh), to, &sources, faces)
                .ok_or_else(|| {
                    PyValueError::new_err("the sources need one row per element of the mesh")
                })?;
            let inputs = self.inputs_handed_over(&other, &sources);
            other.element_data = data;
            other.input_vertices = inputs;
        }
        let revision = self.element_revision.max(other.element_revision) + 1;
        let name = self.name();
        std::mem::swap(self, &mut *other);
        if let Some(mut info) = self.world.get_mut::<MeshInfo>(self.mesh.0) {
            info.name = name;
        }
        for mesh in [&mut *self, &mut *other] {
            mesh.element_revision = revision;
            mesh.vertex_epoch = revision;
            mesh.rows = OnceLock::new();
        }
        Ok(())
    }

    /// `<pappus.Mesh 'name': V vertices, F faces>`.
    fn __repr__(&self) -> String {
        let members = MeshMembers::collect(&self.world, self.mesh);
        format!(
            "<pappus.Mesh '{}': {} vertices, {} faces>",
            self.name(),
            members.vertices.len(),
            members.faces.len()
        )
    }
}

impl Mesh {
    /// The inverse of [`Mesh::state`].
    fn from_state(state: &Bound<'_, PyDict>) -> PyResult<Mesh> {
        let py = state.py();
        let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
            state
                .get_item(key)?
                .ok_or_else(|| PyValueError::new_err(format!("mesh state without `{key}`")))
        };
        let vertices: PyArrayLike2<'_, f32, AllowTypeChange> = get("vertices")?.extract()?;
        let flat = float_rows(&vertices, 3, "vertices")?;
        let positions: Vec<Vec3> = flat
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        let indices: PyReadonlyArray1<'_, u32> = get("indices")?.extract()?;
        let starts: PyReadonlyArray1<'_, u32> = get("face_starts")?.extract()?;
        let mut soup = PolygonSoup::with_capacity(positions.len(), 0, 0);
        soup.positions = positions;
        soup.indices = indices.as_array().to_vec();
        soup.face_starts = starts.as_array().to_vec();
        let valid_starts = soup.face_starts.first().is_none_or(|&s| s == 0)
            && soup.face_starts.windows(2).all(|w| w[0] <= w[1])
            && soup
                .face_starts
                .last()
                .is_none_or(|&s| s as usize == soup.indices.len());
        if !valid_starts {
            return Err(PyValueError::new_err(
                "mesh state with malformed face_starts",
            ));
        }
        let optional = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
            let value = get(key)?;
            Ok((!value.is_none()).then_some(value))
        };
        if let Some(uv) = optional("corner_uvs")? {
            let uv: PyArrayLike2<'_, f32, AllowTypeChange> = uv.extract()?;
            let flat = float_rows(&uv, 2, "corner_uvs")?;
            soup.corner_uvs = Some(
                flat.chunks_exact(2)
                    .map(|p| Vec2::new(p[0], p[1]))
                    .collect(),
            );
        }
        if let Some(n) = optional("vertex_normals")? {
            let n: PyArrayLike2<'_, f32, AllowTypeChange> = n.extract()?;
            let flat = float_rows(&n, 3, "vertex_normals")?;
            soup.vertex_normals = Some(
                flat.chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2]))
                    .collect(),
            );
        }
        if let Some(c) = optional("vertex_colors")? {
            let c: PyReadonlyArray2<'_, u8> = c.extract()?;
            let flat: Vec<u8> = c.as_array().iter().copied().collect();
            soup.vertex_colors = Some(flat.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect());
        }
        // Absent from the state of an older version (as are the groups).
        if let Some(data) = state.get_item("vertex_data")?.filter(|d| !d.is_none()) {
            for (name, values) in data.cast::<PyDict>()?.iter() {
                let name: String = name.extract()?;
                let values: PyReadonlyArray1<'_, f32> = values.extract()?;
                let values = values.as_array().to_vec();
                if name == "quality" {
                    soup.vertex_quality = Some(values);
                } else {
                    soup.vertex_scalars.push((name, values));
                }
            }
        }
        if let Some(data) = state.get_item("face_data")?.filter(|d| !d.is_none()) {
            for (name, values) in data.cast::<PyDict>()?.iter() {
                let values: PyReadonlyArray1<'_, f32> = values.extract()?;
                (soup.face_scalars).push((name.extract()?, values.as_array().to_vec()));
            }
        }
        if let Some(groups) = state.get_item("face_groups")?.filter(|g| !g.is_none()) {
            soup.face_groups = Some(face_groups_from(&groups)?);
        }
        let name: String = get("name")?.extract()?;
        let read_ms: f64 = get("read_ms")?.extract()?;
        let rows: PyReadonlyArray1<'_, i64> = get("input_rows")?.extract()?;
        let rows = rows.as_array().to_vec();
        let repairs: Vec<usize> = get("repairs")?.extract()?;
        let info = MeshInfo { name, path: None };
        let mut mesh = py
            .detach(|| Mesh::build(&soup, info, read_ms))
            .map_err(PyValueError::new_err)?;
        // The soup was the mesh's own, so it builds with no repairs and its rows are the new
        // mesh's vertices: the input numbering maps through them.
        let built_rows = std::mem::take(&mut mesh.input_vertices);
        mesh.input_vertices = rows
            .iter()
            .map(|&r| {
                usize::try_from(r)
                    .ok()
                    .and_then(|r| built_rows.get(r).copied().flatten())
            })
            .collect();
        mesh.report = report_from(&repairs);
        Ok(mesh)
    }
}

/// A repair report from its counts in [`RepairReport::entries`] order (missing ones zero).
fn report_from(counts: &[usize]) -> RepairReport {
    let mut report = RepairReport::default();
    let names = report.entries().map(|(name, _)| name);
    for (name, &n) in names.iter().zip(counts) {
        let field = match *name {
            "unreferenced_vertices" => &mut report.unreferenced_vertices,
            "too_few_corners" => &mut report.too_few_corners,
            "out_of_range_faces" => &mut report.out_of_range_faces,
            "repeated_vertex_faces" => &mut report.repeated_vertex_faces,
            "untangled_faces" => &mut report.untangled_faces,
            "non_finite_faces" => &mut report.non_finite_faces,
            "non_manifold_edge_faces" => &mut report.non_manifold_edge_faces,
            "non_orientable_faces" => &mut report.non_orientable_faces,
            "reoriented_faces" => &mut report.reoriented_faces,
            "non_manifold_vertices" => &mut report.non_manifold_vertices,
            "added_vertices" => &mut report.added_vertices,
            _ => continue,
        };
        *field = n;
    }
    report
}

/// The declaration of the operation a step runs, if it runs one.
fn declaration(step: &Step) -> Option<&'static Declaration> {
    match step {
        Step::Edit(edit) => Some(edit.declaration()),
        Step::On(invocation, _) => Some(invocation.declaration()),
        Step::Validate | Step::Deform(_) => None,
    }
}

/// Which element ids a step keeps (see [`IdsKept`]).
fn ids_kept(step: &Step) -> IdsKept {
    declaration(step).map_or(IdsKept::All, |d| d.ids)
}
