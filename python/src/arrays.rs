//! `NumPy` arrays to and from a mesh: positions as N×3 float32, faces as M×k int64 (or a list of
//! arrays when sizes differ), UVs as K×2 float32, and the checks on arrays handed in.

use bevy::prelude::World;
use numpy::{
    AllowTypeChange, PyArray1, PyArrayDescrMethods, PyArrayLike2, PyArrayMethods, PyReadonlyArray2,
    PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PySequence};

use bevy::math::{Vec2, Vec3};
use pappus::mesh::{MeshId, MeshMembers};

/// `N×3` float32 array of points.
pub(crate) fn vec3_array<'py>(py: Python<'py>, points: &[Vec3]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([points.len(), 3])?
        .into_any())
}

/// `N×2` float32 array of points.
pub(crate) fn vec2_array<'py>(py: Python<'py>, points: &[Vec2]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([points.len(), 2])?
        .into_any())
}

/// The mesh's positions and faces as [`to_soup`] lists them (vertices in table order, each face
/// starting one halfedge back), without its attributes, and faster: vertex rows are found in a
/// table indexed by entity index rather than a hash map, and each halfedge is read once.
pub(crate) fn positions_and_faces(world: &World, mesh: MeshId) -> (Vec<Vec3>, Vec<u32>, Vec<u32>) {
    let members = MeshMembers::collect(world, mesh);
    let m = pappus::mesh::MeshRef::new(world);
    let positions: Vec<Vec3> = members.vertices.iter().map(|&v| m.position(v)).collect();
    let top = members
        .vertices
        .iter()
        .map(|v| v.0.index_u32() as usize + 1)
        .max()
        .unwrap_or(0);
    let mut row = vec![u32::MAX; top];
    for (r, v) in members.vertices.iter().enumerate() {
        row[v.0.index_u32() as usize] = r as u32;
    }
    let mut indices = Vec::with_capacity(members.halfedges.len());
    let mut starts = Vec::with_capacity(members.faces.len() + 1);
    starts.push(0);
    let link = |h: pappus::mesh::HalfedgeId| {
        world
            .get::<pappus::mesh::Halfedge>(h.0)
            .expect("a face's halfedges are live")
    };
    for &f in &members.faces {
        let start = link(m.face_halfedge(f)).prev;
        let mut h = start;
        // A face's loop closes (the mesh validates); the bound only keeps a broken one finite.
        for _ in 0..members.halfedges.len() {
            let he = link(h);
            indices.push(row[he.vertex.0.index_u32() as usize]);
            h = he.next;
            if h == start {
                break;
            }
        }
        starts.push(indices.len() as u32);
    }
    (positions, indices, starts)
}

/// Reads an `N×k` array-like of floats as `k`-vectors (`ValueError` for another shape).
pub(crate) fn float_rows(
    array: &PyArrayLike2<'_, f32, AllowTypeChange>,
    k: usize,
    what: &str,
) -> PyResult<Vec<f32>> {
    let shape = array.shape();
    if shape[1] != k {
        return Err(PyValueError::new_err(format!(
            "{what} must be an N×{k} array, not {}×{}",
            shape[0], shape[1]
        )));
    }
    Ok(array.as_array().iter().copied().collect())
}

/// The faces given to `Mesh(...)`: an `M×k` integer array, or a sequence of index sequences
/// (polygons of any sizes), checked against `vertices` vertices.
pub(crate) fn read_faces(faces: &Bound<'_, PyAny>, vertices: usize) -> PyResult<Vec<Vec<u32>>> {
    let check = |face: usize, i: i64| -> PyResult<u32> {
        if i < 0 || i as usize >= vertices {
            return Err(PyValueError::new_err(format!(
                "face {face} names vertex {i}, but there are {vertices} vertices"
            )));
        }
        Ok(i as u32)
    };
    if let Ok(array) = faces.cast::<PyUntypedArray>()
        && array.ndim() == 2
    {
        if !matches!(array.dtype().kind(), b'i' | b'u') {
            return Err(PyValueError::new_err(format!(
                "faces must be an integer array, not {}",
                array.dtype()
            )));
        }
        let array = faces.call_method1("astype", ("int64",))?;
        let array: PyReadonlyArray2<'_, i64> = array.extract()?;
        let view = array.as_array();
        return view
            .outer_iter()
            .enumerate()
            .map(|(f, row)| row.iter().map(|&i| check(f, i)).collect())
            .collect();
    }
    let sequence = faces.cast::<PySequence>().map_err(|_| {
        PyValueError::new_err("faces must be an M×k integer array or a sequence of index sequences")
    })?;
    let mut out = Vec::with_capacity(sequence.len()?);
    for (f, face) in sequence.try_iter()?.enumerate() {
        let indices: Vec<i64> = face?.extract().map_err(|_| {
            PyValueError::new_err(format!("face {f} is not a sequence of vertex indices"))
        })?;
        out.push(
            indices
                .into_iter()
                .map(|i| check(f, i))
                .collect::<PyResult<_>>()?,
        );
    }
    Ok(out)
}

/// Faces stored flat (`indices`, with `starts` as in [`PolygonSoup`]) as `faces` returns
/// them: one M×k int64 array when every face has k sides, else a list of int64 arrays.
pub(crate) fn faces_array<'py>(
    py: Python<'py>,
    indices: &[u32],
    starts: &[u32],
) -> PyResult<Bound<'py, PyAny>> {
    let count = starts.len().saturating_sub(1);
    let size = |i: usize| (starts[i + 1] - starts[i]) as usize;
    let first = if count > 0 { size(0) } else { 3 };
    if (0..count).all(|i| size(i) == first) {
        let flat: Vec<i64> = indices.iter().map(|&i| i64::from(i)).collect();
        return Ok(PyArray1::from_vec(py, flat)
            .reshape([count, first])?
            .into_any());
    }
    let list = PyList::empty(py);
    for w in starts.windows(2) {
        let face: Vec<i64> = indices[w[0] as usize..w[1] as usize]
            .iter()
            .map(|&i| i64::from(i))
            .collect();
        list.append(PyArray1::from_vec(py, face))?;
    }
    Ok(list.into_any())
}
