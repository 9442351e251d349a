//! `Mesh.vertex_data`: named per-vertex scalars the halfedge mesh has no column for, kept
//! beside the mesh by vertex: those a file carried (a PLY's `quality` and its other vertex
//! properties: `confidence`, `intensity`, …) and a script's own (`mesh.vertex_data["d"] = a`).
//! A PLY save writes them all as vertex properties, and a load reads them back.
//!
//! Each value belongs to its vertex's entity, so it follows the vertex through every edit that
//! keeps it (flips, collapses of its neighbours, subdivision, which keeps vertex ids) and goes
//! with it. A vertex an edit made gets the value interpolated at its place on the surface
//! before the edit ([`pappus::ops::geometry::carry`]: a split's midpoint the mean of its edge's
//! ends, a subdivision's new vertex its face's blend). Keyed by the whole entity, generation
//! included, so a vertex that reuses a removed one's slot never inherits a value.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::World;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pappus::mesh::topology::MeshRef;
use pappus::mesh::{MeshId, MeshMembers, PolygonSoup, VertexId};
use pappus::ops::geometry::carry::SurfaceBefore;
use pyo3::exceptions::{PyKeyError, PyValueError};

use crate::mesh::Mesh;

/// Named per-vertex scalars, each a value by vertex entity.
#[derive(Default)]
pub(crate) struct VertexData {
    /// `(name, value by vertex)`, in the order the file listed them, then as set.
    columns: Vec<(String, EntityHashMap<f32>)>,
    /// The surface when a hand edit (`with mesh.edit()`) opened, for the vertices it makes.
    surface_at_edit: Option<SurfaceBefore>,
}

impl VertexData {
    /// The scalars `soup` carries, given to the vertices its rows became (`built[i]`: input
    /// vertex `i`'s vertex, `None` where the repairs dropped it). NaN values are not kept.
    pub(crate) fn of_soup(soup: &PolygonSoup, built: &[Option<VertexId>]) -> Self {
        let quality = soup.vertex_quality.as_ref().map(|q| ("quality", q));
        let others = soup.vertex_scalars.iter().map(|(n, c)| (n.as_str(), c));
        let columns = quality
            .into_iter()
            .chain(others)
            .map(|(name, values)| {
                let by_vertex = built
                    .iter()
                    .zip(values)
                    .filter_map(|(v, &x)| Some((v.as_ref()?.0, x)).filter(|_| !x.is_nan()))
                    .collect();
                (name.to_string(), by_vertex)
            })
            .collect();
        Self {
            columns,
            surface_at_edit: None,
        }
    }

    /// Whether there is no column (then nothing is read before an edit).
    pub(crate) fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// The surface of `mesh` before an edit, when there are values to carry through it.
    pub(crate) fn surface_before(&self, world: &World, mesh: MeshId) -> Option<SurfaceBefore> {
        (!self.is_empty()).then(|| SurfaceBefore::of(world, mesh))
    }

    /// After an edit: each vertex of `mesh` the edit made (not on `before`) gets the value
    /// interpolated at its place on `before` (see the module doc); a vertex that had no value
    /// keeps none. Values of vertices the edit
    /// removed are dropped once a column holds more values than the mesh has vertices (their
    /// keys, generation included, never name a later vertex).
    pub(crate) fn carry(&mut self, before: &SurfaceBefore, world: &World, mesh: MeshId) {
        let vertices = MeshMembers::collect(world, mesh).vertices;
        let m = MeshRef::new(world);
        for (_, column) in &mut self.columns {
            let made: Vec<(VertexId, f32)> = vertices
                .iter()
                .filter(|v| !before.had(**v) && !column.contains_key(&v.0))
                .map(|&v| {
                    let value = before.value_at(m.position(v), |c| {
                        column.get(&c.0).copied().unwrap_or(f32::NAN)
                    });
                    (v, value)
                })
                .collect();
            column.extend(
                made.into_iter()
                    .filter(|(_, x)| !x.is_nan())
                    .map(|(v, x)| (v.0, x)),
            );
            if column.len() > vertices.len() {
                let live: bevy::ecs::entity::EntityHashSet = vertices.iter().map(|v| v.0).collect();
                column.retain(|e, _| live.contains(e));
            }
        }
    }

    /// Keeps the surface as a hand edit opens, for [`VertexData::closed_edit`].
    pub(crate) fn opened_edit(&mut self, world: &World, mesh: MeshId) {
        self.surface_at_edit = self.surface_before(world, mesh);
    }

    /// A hand edit closed: committed, its new vertices get their values.
    pub(crate) fn closed_edit(&mut self, committed: bool, world: &World, mesh: MeshId) {
        if let Some(before) = self.surface_at_edit.take()
            && committed
        {
            self.carry(&before, world, mesh);
        }
    }

    /// Column `name` by row of `mesh`'s vertices (NaN where a vertex has none), if there is one.
    pub(crate) fn column(&self, name: &str, world: &World, mesh: MeshId) -> Option<Vec<f32>> {
        let (_, values) = self.columns.iter().find(|(n, _)| n == name)?;
        let vertices = MeshMembers::collect(world, mesh).vertices;
        Some(
            vertices
                .iter()
                .map(|v| values.get(&v.0).copied().unwrap_or(f32::NAN))
                .collect(),
        )
    }

    /// Sets column `name` (replacing one of that name, else added last) from values by row of
    /// `mesh`'s vertices; NaN values are not kept. `ValueError` for another count.
    pub(crate) fn set(
        &mut self,
        name: &str,
        values: &[f32],
        world: &World,
        mesh: MeshId,
    ) -> PyResult<()> {
        if !pappus::io::keeps_vertex_scalar(name) {
            return Err(PyValueError::new_err(format!(
                "vertex_data[{name:?}]: a name a PLY file would not give back as itself (empty, \
                 with whitespace, or a column of its own: x y z nx ny nz red green blue u v s t \
                 texture_u texture_v texture_s texture_t); choose another"
            )));
        }
        let vertices = MeshMembers::collect(world, mesh).vertices;
        if values.len() != vertices.len() {
            return Err(PyValueError::new_err(format!(
                "vertex_data[{name:?}] takes one value per vertex: {} given, the mesh has {}",
                values.len(),
                vertices.len()
            )));
        }
        let column: EntityHashMap<f32> = vertices
            .iter()
            .zip(values)
            .filter(|(_, x)| !x.is_nan())
            .map(|(v, &x)| (v.0, x))
            .collect();
        match self.columns.iter_mut().find(|(n, _)| n == name) {
            Some((_, old)) => *old = column,
            None => self.columns.push((name.to_string(), column)),
        }
        Ok(())
    }

    /// Removes column `name`; whether there was one.
    pub(crate) fn remove(&mut self, name: &str) -> bool {
        let before = self.columns.len();
        self.columns.retain(|(n, _)| n != name);
        self.columns.len() != before
    }

    /// The columns' names, in order.
    pub(crate) fn names(&self) -> Vec<String> {
        self.columns.iter().map(|(n, _)| n.clone()).collect()
    }

    /// Puts every column into `soup` by row of `mesh` (NaN where a vertex has none): `quality`
    /// as its quality, the others as its named scalars, for a pickle to carry.
    pub(crate) fn put_into(&self, world: &World, mesh: MeshId, soup: &mut PolygonSoup) {
        for (name, column) in self.by_row(world, mesh) {
            if name == "quality" {
                soup.vertex_quality = Some(column);
            } else {
                soup.vertex_scalars.push((name.to_string(), column));
            }
        }
    }

    /// Every column by row of `mesh`'s vertices (NaN where a vertex has none), the vertices
    /// listed once for all of them.
    fn by_row(&self, world: &World, mesh: MeshId) -> impl Iterator<Item = (&str, Vec<f32>)> {
        let vertices = match self.columns.is_empty() {
            true => Vec::new(),
            false => MeshMembers::collect(world, mesh).vertices,
        };
        self.columns.iter().map(move |(name, values)| {
            let column = vertices
                .iter()
                .map(|v| values.get(&v.0).copied().unwrap_or(f32::NAN))
                .collect();
            (name.as_str(), column)
        })
    }

    /// Every column as a dict of float32 arrays by row of `Mesh.vertices`.
    pub(crate) fn dict<'py>(
        &self,
        py: Python<'py>,
        world: &World,
        mesh: MeshId,
    ) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (name, column) in self.by_row(world, mesh) {
            dict.set_item(name, PyArray1::from_vec(py, column))?;
        }
        Ok(dict)
    }
}

/// `Mesh.vertex_data`: the mesh's named per-vertex scalars as a mapping of names to float32
/// arrays by row of `vertices` (NaN where a vertex has none). Reading gives a copy; assigning
/// an array of one value per vertex (any float dtype) sets a column, `del` removes one. A view
/// of the mesh: it sees every later edit.
#[pyclass(module = "pappus", name = "VertexData")]
pub(crate) struct VertexDataView {
    pub(crate) mesh: Py<Mesh>,
}

#[pymethods]
impl VertexDataView {
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let mesh = self.mesh.bind(py).try_borrow()?;
        let column = mesh
            .vertex_data_column(name)?
            .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
        Ok(PyArray1::from_vec(py, column))
    }

    fn __setitem__(
        &self,
        py: Python<'_>,
        name: &str,
        values: numpy::PyArrayLike1<'_, f32, numpy::AllowTypeChange>,
    ) -> PyResult<()> {
        let values = values.as_array().to_vec();
        self.mesh
            .bind(py)
            .try_borrow_mut()?
            .set_vertex_data(name, &values)
    }

    fn __delitem__(&self, py: Python<'_>, name: &str) -> PyResult<()> {
        match self
            .mesh
            .bind(py)
            .try_borrow_mut()?
            .remove_vertex_data(name)
        {
            true => Ok(()),
            false => Err(PyKeyError::new_err(name.to_string())),
        }
    }

    fn __contains__(&self, py: Python<'_>, name: &Bound<'_, PyAny>) -> PyResult<bool> {
        let Ok(name) = name.extract::<String>() else {
            return Ok(false);
        };
        Ok(self.keys(py)?.contains(&name))
    }

    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.keys(py)?.len())
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.keys(py)?
            .into_pyobject(py)?
            .try_iter()
            .map(Bound::into_any)
    }

    /// The columns' names, in order (a file's first, then as set).
    fn keys(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.mesh.bind(py).try_borrow()?.vertex_data_names())
    }

    /// `(name, array)` for every column.
    fn items<'py>(&self, py: Python<'py>) -> PyResult<Vec<(String, Bound<'py, PyArray1<f32>>)>> {
        self.keys(py)?
            .into_iter()
            .map(|name| Ok((name.clone(), self.__getitem__(py, &name)?)))
            .collect()
    }

    /// Every column's array, in the order of `keys()`.
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArray1<f32>>>> {
        Ok(self.items(py)?.into_iter().map(|(_, a)| a).collect())
    }

    /// Column `name`, or `default` without one.
    #[pyo3(signature = (name, default=None))]
    fn get<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        default: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.keys(py)?.iter().any(|n| n == name) {
            true => Ok(Some(self.__getitem__(py, name)?.into_any())),
            false => Ok(default),
        }
    }

    /// Column `name`, removed; `default` without one (`KeyError` without either).
    #[pyo3(signature = (name, default=None))]
    fn pop<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        default: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match self.get(py, name, None)? {
            Some(column) => {
                self.__delitem__(py, name)?;
                Ok(column)
            }
            None => default.ok_or_else(|| PyKeyError::new_err(name.to_string())),
        }
    }

    /// Sets every column of `columns` (a mapping, or `(name, array)` pairs), as assignment does.
    fn update(&self, py: Python<'_>, columns: &Bound<'_, PyAny>) -> PyResult<()> {
        let pairs = match columns.cast::<PyDict>() {
            Ok(dict) => dict.items().into_any(),
            Err(_) if columns.hasattr("keys")? => columns.call_method0("items")?,
            Err(_) => columns.clone(),
        };
        for pair in pairs.try_iter()? {
            let (name, values): (String, numpy::PyArrayLike1<'_, f32, numpy::AllowTypeChange>) =
                pair?.extract()?;
            self.__setitem__(py, &name, values)?;
        }
        Ok(())
    }

    /// Removes every column.
    fn clear(&self, py: Python<'_>) -> PyResult<()> {
        for name in self.keys(py)? {
            self.__delitem__(py, &name)?;
        }
        Ok(())
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!("<pappus.VertexData {:?}>", self.keys(py)?))
    }
}
