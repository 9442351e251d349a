//! `Mesh.vertex_data` and `Mesh.face_data`: named scalars per vertex and per face that the
//! halfedge mesh has no column for, kept beside the mesh by element: those a file carried (a
//! PLY's vertex `quality`, `confidence`, `intensity`, …, and its face properties) and a
//! script's own (`mesh.vertex_data["d"] = a`, `mesh.face_data["label"] = l`). A PLY save
//! writes them all as vertex and face properties, and a load reads them back.
//!
//! Each value belongs to its element's entity, so it follows the element through every edit
//! that keeps it (a flip keeps its two faces, subdivision keeps vertex ids) and goes with it.
//! An element an edit made gets the value at its place on the surface before the edit
//! ([`pappus::ops::geometry::carry`]): a vertex the value interpolated there (a split's
//! midpoint the mean of its edge's ends), a face the value of the face its centroid lies on
//! (a split's halves and a subdivision's children their parent's). Keyed by the whole entity,
//! generation included, so an element that reuses a removed one's slot never inherits a value.

use bevy::ecs::entity::{Entity, EntityHashMap, EntityHashSet};
use bevy::math::Vec3;
use bevy::prelude::World;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pappus::mesh::build::BuiltMesh;
use pappus::mesh::topology::MeshRef;
use pappus::mesh::{FaceId, MeshId, MeshMembers, PolygonSoup, VertexId};
use pappus::ops::declaration::FaceChildren;
use pappus::ops::geometry::carry::SurfaceBefore;
use pyo3::exceptions::{PyKeyError, PyValueError};

use crate::mesh::Mesh;

/// The kind of element a column has a value for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Per {
    Vertex,
    Face,
}

impl Per {
    /// `"vertex"` or `"face"`.
    fn word(self) -> &'static str {
        match self {
            Per::Vertex => "vertex",
            Per::Face => "face",
        }
    }

    /// The elements of this kind in `members`, by row.
    fn of(self, members: &MeshMembers) -> Vec<Entity> {
        match self {
            Per::Vertex => members.vertices.iter().map(|v| v.0).collect(),
            Per::Face => members.faces.iter().map(|f| f.0).collect(),
        }
    }

    /// The elements of this kind in `mesh`, by row.
    fn rows(self, world: &World, mesh: MeshId) -> Vec<Entity> {
        self.of(&MeshMembers::collect(world, mesh))
    }
}

/// Named columns of one kind of element, each a value by entity, in the order the file listed
/// them, then as set.
#[derive(Default)]
struct Columns(Vec<(String, EntityHashMap<f32>)>);

impl Columns {
    /// Columns from a soup's `(name, value by input row)` and the entity of each input row
    /// (`None` where the repairs dropped it). NaN values are not kept.
    fn of<'a>(columns: impl Iterator<Item = (&'a str, &'a [f32])>, rows: &[(Entity, u32)]) -> Self {
        let by_entity = |values: &[f32]| {
            rows.iter()
                .filter_map(|&(e, row)| Some((e, *values.get(row as usize)?)))
                .filter(|(_, x)| !x.is_nan())
                .collect()
        };
        Self(
            columns
                .map(|(name, values)| (name.to_string(), by_entity(values)))
                .collect(),
        )
    }

    /// Gives each element of `made` (with where its value is read: its place on the surface
    /// before, or the face it came from) the value `read` finds there, and drops the values of
    /// elements gone once a column holds more values than there are `live` ones.
    fn carry<T>(
        &mut self,
        live: &[Entity],
        made: &[(Entity, T)],
        read: impl Fn(&T, &EntityHashMap<f32>) -> f32,
    ) {
        for (_, column) in &mut self.0 {
            let values: Vec<(Entity, f32)> = made
                .iter()
                .map(|(e, place)| (*e, read(place, column)))
                .filter(|(_, x)| !x.is_nan())
                .collect();
            column.extend(values);
            if column.len() > live.len() {
                let live: EntityHashSet = live.iter().copied().collect();
                column.retain(|e, _| live.contains(e));
            }
        }
    }

    /// Every column anew: each element of `elements` takes the value of the element it came
    /// from (none without one), read from the columns as they were.
    fn renew(&mut self, elements: &[(Entity, Option<Entity>)]) {
        for (_, column) in &mut self.0 {
            let old = std::mem::take(column);
            let value = |&(e, from): &(Entity, Option<Entity>)| Some((e, *old.get(&from?)?));
            column.extend(elements.iter().filter_map(value));
        }
    }

    /// Every column by row of `rows` (NaN where an element has none).
    fn by_row<'a>(&'a self, rows: &'a [Entity]) -> impl Iterator<Item = (&'a str, Vec<f32>)> {
        self.0.iter().map(move |(name, values)| {
            let column = rows
                .iter()
                .map(|e| values.get(e).copied().unwrap_or(f32::NAN))
                .collect();
            (name.as_str(), column)
        })
    }
}

/// The named scalars of a mesh's vertices and faces (see the module doc).
#[derive(Default)]
pub(crate) struct ElementData {
    vertex: Columns,
    face: Columns,
    /// The surface when a hand edit (`with mesh.edit()`) opened, for the elements it makes.
    surface_at_edit: Option<SurfaceBefore>,
}

impl ElementData {
    /// The scalars `soup` carries, given to the elements its rows became.
    pub(crate) fn of_soup(soup: &PolygonSoup, built: &BuiltMesh) -> Self {
        let quality = soup.vertex_quality.as_deref().map(|q| ("quality", q));
        let others = soup
            .vertex_scalars
            .iter()
            .map(|(n, c)| (n.as_str(), c.as_slice()));
        let vertices: Vec<(Entity, u32)> = (built.input_vertices.iter().enumerate())
            .filter_map(|(row, v)| Some((v.as_ref()?.0, row as u32)))
            .collect();
        let faces: Vec<(Entity, u32)> = (built.face_sources.iter())
            .map(|&(f, row)| (f.0, row))
            .collect();
        let face_columns = soup
            .face_scalars
            .iter()
            .map(|(n, c)| (n.as_str(), c.as_slice()));
        Self {
            vertex: Columns::of(quality.into_iter().chain(others), &vertices),
            face: Columns::of(face_columns, &faces),
            surface_at_edit: None,
        }
    }

    fn columns(&self, per: Per) -> &Columns {
        match per {
            Per::Vertex => &self.vertex,
            Per::Face => &self.face,
        }
    }

    fn columns_mut(&mut self, per: Per) -> &mut Columns {
        match per {
            Per::Vertex => &mut self.vertex,
            Per::Face => &mut self.face,
        }
    }

    /// The surface of `mesh` before an edit, when there are values to carry through it.
    pub(crate) fn surface_before(&self, world: &World, mesh: MeshId) -> Option<SurfaceBefore> {
        let empty = self.vertex.0.is_empty() && self.face.0.is_empty();
        (!empty).then(|| SurfaceBefore::of(world, mesh))
    }

    /// After an edit: each vertex and face of `mesh` the edit made (not on `before`) gets its
    /// value from `before` (see the module doc); one that finds none there keeps none. Values
    /// of elements the edit removed are dropped once a column holds more values than the mesh
    /// has elements of its kind (their keys, generation included, never name a later one).
    /// With `renumbered`, the layout of an edit that rewrote the faces in place (subdivision:
    /// an old face's entity names one of its children, or another face's), every face reads
    /// its value anew: its parent's by that layout, else (counts it does not explain) the
    /// value of the face its centroid lay on.
    pub(crate) fn carry(
        &mut self,
        before: &SurfaceBefore,
        world: &World,
        mesh: MeshId,
        renumbered: Option<FaceChildren>,
    ) {
        let members = MeshMembers::collect(world, mesh);
        let m = MeshRef::new(world);
        if !self.vertex.0.is_empty() {
            let live = Per::Vertex.of(&members);
            let made: Vec<(Entity, Vec3)> = (members.vertices.iter())
                .filter(|v| !before.had(**v))
                .map(|&v| (v.0, m.position(v)))
                .collect();
            (self.vertex).carry(&live, &made, |&p, column| blend(before, column, p));
        }
        if !self.face.0.is_empty() {
            let live = Per::Face.of(&members);
            // Each face that needs a value, with the face it came from.
            let under_centroid =
                |f: &FaceId| (f.0, before.face_at(m.face_centroid(*f)).map(|g| g.0));
            let from: Vec<(Entity, Option<Entity>)> = match renumbered {
                Some(children) => match before.face_parents(children, live.len()) {
                    Some(parents) => (live.iter().copied())
                        .zip(parents.into_iter().map(|p| Some(p.0)))
                        .collect(),
                    None => members.faces.iter().map(under_centroid).collect(),
                },
                None => (members.faces.iter())
                    .filter(|f| !before.had_face(**f))
                    .map(under_centroid)
                    .collect(),
            };
            match renumbered {
                Some(_) => self.face.renew(&from),
                None => self.face.carry(&live, &from, |&from, column| {
                    from.and_then(|f| column.get(&f).copied())
                        .unwrap_or(f32::NAN)
                }),
            }
        }
    }

    /// The columns for the mesh `to`, handed back from elsewhere (the editor, under
    /// `pappus.show`), whose vertex at row `j` was this mesh's (`mesh`'s) vertex at row
    /// `vertex_sources[j]` (-1: a vertex made there), and likewise its faces by
    /// `face_sources`. A kept element keeps its value; a made one reads its value off this
    /// mesh's surface at its place, as after an edit here (a vertex the blend there, a face
    /// the value of the face under its centroid). Without `face_sources` the face columns do
    /// not go over. `None` when a list does not have one row per element of `to`.
    pub(crate) fn handed_over(
        &self,
        (world, mesh): (&World, MeshId),
        to: (&World, MeshId),
        vertex_sources: &[i64],
        face_sources: Option<&[i64]>,
    ) -> Option<ElementData> {
        let new = MeshMembers::collect(to.0, to.1);
        let faces = face_sources.unwrap_or_default();
        let counts = (
            vertex_sources.len(),
            face_sources.map_or(new.faces.len(), <[i64]>::len),
        );
        if counts != (new.vertices.len(), new.faces.len()) {
            return None;
        }
        let old = MeshMembers::collect(world, mesh);
        let made = vertex_sources.iter().chain(faces).any(|&s| s < 0);
        let surface = made.then(|| self.surface_before(world, mesh)).flatten();
        let m = MeshRef::new(to.0);
        // Each new element with its value's place: the old element it is, else where it lies.
        let was = |rows: &[Entity], row: i64| rows.get(usize::try_from(row).ok()?).copied();
        let (old_vertices, old_faces) = (Per::Vertex.of(&old), Per::Face.of(&old));
        let vertex = self.vertex.0.iter().map(|(name, column)| {
            let value = |(v, &row): (&VertexId, &i64)| match (was(&old_vertices, row), &surface) {
                (Some(e), _) => Some((v.0, *column.get(&e)?)),
                (None, Some(surface)) => Some((v.0, blend(surface, column, m.position(*v)))),
                (None, None) => None,
            };
            let values = new.vertices.iter().zip(vertex_sources).filter_map(value);
            (name.clone(), values.filter(|(_, x)| !x.is_nan()).collect())
        });
        let face = self
            .face
            .0
            .iter()
            .filter(|_| face_sources.is_some())
            .map(|(name, column)| {
                let value = |(f, &row): (&FaceId, &i64)| {
                    let from = match (was(&old_faces, row), &surface) {
                        (Some(e), _) => e,
                        (None, Some(surface)) => surface.face_at(m.face_centroid(*f))?.0,
                        (None, None) => return None,
                    };
                    Some((f.0, *column.get(&from)?))
                };
                (
                    name.clone(),
                    new.faces.iter().zip(faces).filter_map(value).collect(),
                )
            });
        Some(ElementData {
            vertex: Columns(vertex.collect()),
            face: Columns(face.collect()),
            surface_at_edit: None,
        })
    }

    /// Keeps the surface as a hand edit opens, for [`ElementData::closed_edit`].
    pub(crate) fn opened_edit(&mut self, world: &World, mesh: MeshId) {
        self.surface_at_edit = self.surface_before(world, mesh);
    }

    /// A hand edit closed: committed, the elements it made get their values.
    pub(crate) fn closed_edit(&mut self, committed: bool, world: &World, mesh: MeshId) {
        if let Some(before) = self.surface_at_edit.take()
            && committed
        {
            self.carry(&before, world, mesh, None);
        }
    }

    /// Column `name` of `per` by row of `mesh`'s elements (NaN where one has none), if there
    /// is one.
    pub(crate) fn column(
        &self,
        per: Per,
        name: &str,
        world: &World,
        mesh: MeshId,
    ) -> Option<Vec<f32>> {
        let columns = self.columns(per);
        let k = columns.0.iter().position(|(n, _)| n == name)?;
        let rows = per.rows(world, mesh);
        let (_, values) = &columns.0[k];
        Some(
            rows.iter()
                .map(|e| values.get(e).copied().unwrap_or(f32::NAN))
                .collect(),
        )
    }

    /// Sets column `name` of `per` (replacing one of that name, else added last) from values by
    /// row of `mesh`'s elements; NaN values are not kept. `ValueError` for another count, or a
    /// name a PLY file would not give back as itself.
    pub(crate) fn set(
        &mut self,
        per: Per,
        name: &str,
        values: &[f32],
        world: &World,
        mesh: MeshId,
    ) -> PyResult<()> {
        let what = per.word();
        let kept = match per {
            Per::Vertex => pappus::io::keeps_vertex_scalar(name),
            Per::Face => pappus::io::keeps_face_scalar(name),
        };
        if !kept {
            let taken = match per {
                Per::Vertex => {
                    "x y z nx ny nz red green blue u v s t texture_u texture_v texture_s texture_t"
                }
                Per::Face => "vertex_indices vertex_index texcoord",
            };
            return Err(PyValueError::new_err(format!(
                "{what}_data[{name:?}]: a name a PLY file would not give back as itself (empty, \
                 with whitespace, or a property of its own: {taken}); choose another"
            )));
        }
        let rows = per.rows(world, mesh);
        if values.len() != rows.len() {
            return Err(PyValueError::new_err(format!(
                "{what}_data[{name:?}] takes one value per {what}: {} given, the mesh has {}",
                values.len(),
                rows.len()
            )));
        }
        let column: EntityHashMap<f32> = rows
            .iter()
            .zip(values)
            .filter(|(_, x)| !x.is_nan())
            .map(|(&e, &x)| (e, x))
            .collect();
        let columns = &mut self.columns_mut(per).0;
        match columns.iter_mut().find(|(n, _)| n == name) {
            Some((_, old)) => *old = column,
            None => columns.push((name.to_string(), column)),
        }
        Ok(())
    }

    /// Removes column `name` of `per`; whether there was one.
    pub(crate) fn remove(&mut self, per: Per, name: &str) -> bool {
        let columns = &mut self.columns_mut(per).0;
        let before = columns.len();
        columns.retain(|(n, _)| n != name);
        columns.len() != before
    }

    /// The names of `per`'s columns, in order.
    pub(crate) fn names(&self, per: Per) -> Vec<String> {
        self.columns(per).0.iter().map(|(n, _)| n.clone()).collect()
    }

    /// Puts every column into `soup` by row of `mesh`'s elements (NaN where one has none):
    /// the vertices' `quality` as its quality, their others as its vertex scalars, the faces'
    /// as its face scalars, for a save or a pickle to carry.
    pub(crate) fn put_into(&self, world: &World, mesh: MeshId, soup: &mut PolygonSoup) {
        if self.vertex.0.is_empty() && self.face.0.is_empty() {
            return;
        }
        let members = MeshMembers::collect(world, mesh);
        let vertices = Per::Vertex.of(&members);
        for (name, column) in self.vertex.by_row(&vertices) {
            match name {
                "quality" => soup.vertex_quality = Some(column),
                _ => soup.vertex_scalars.push((name.to_string(), column)),
            }
        }
        let faces = Per::Face.of(&members);
        let face_columns = self.face.by_row(&faces);
        soup.face_scalars
            .extend(face_columns.map(|(n, c)| (n.to_string(), c)));
    }

    /// `per`'s columns as a dict of float32 arrays by row of its elements.
    pub(crate) fn dict<'py>(
        &self,
        py: Python<'py>,
        per: Per,
        world: &World,
        mesh: MeshId,
    ) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        let columns = self.columns(per);
        if columns.0.is_empty() {
            return Ok(dict);
        }
        let rows = per.rows(world, mesh);
        for (name, column) in columns.by_row(&rows) {
            dict.set_item(name, PyArray1::from_vec(py, column))?;
        }
        Ok(dict)
    }
}

/// The value at the point of `surface` closest to `p`, blended from its corners' values in
/// `column` (a corner without one left out).
fn blend(surface: &SurfaceBefore, column: &EntityHashMap<f32>, p: Vec3) -> f32 {
    surface.value_at(p, |c| column.get(&c.0).copied().unwrap_or(f32::NAN))
}

/// `Mesh.vertex_data` and `Mesh.face_data`: the mesh's named scalars of one kind of element as
/// a mapping of names to float32 arrays by row of `vertices` or `faces` (NaN where an element
/// has none). Reading gives a copy; assigning an array of one value per element (any float
/// dtype) sets a column, `del` removes one. A view of the mesh: it sees every later edit.
#[pyclass(module = "pappus", name = "ElementData")]
pub(crate) struct ElementDataView {
    pub(crate) mesh: Py<Mesh>,
    pub(crate) per: Per,
}

#[pymethods]
impl ElementDataView {
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let mesh = self.mesh.bind(py).try_borrow()?;
        let column = mesh
            .data_column(self.per, name)?
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
        let mut mesh = self.mesh.bind(py).try_borrow_mut()?;
        mesh.set_data(self.per, name, &values)
    }

    fn __delitem__(&self, py: Python<'_>, name: &str) -> PyResult<()> {
        match self
            .mesh
            .bind(py)
            .try_borrow_mut()?
            .remove_data(self.per, name)
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
        Ok(self.mesh.bind(py).try_borrow()?.data_names(self.per))
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
        Ok(format!(
            "<pappus.ElementData of each {}: {:?}>",
            self.per.word(),
            self.keys(py)?
        ))
    }
}
