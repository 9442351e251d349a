//! Per-vertex quantities out and positions in: `Mesh.quantity(name)`, `Mesh.vertex_normals`
//! and `Mesh.vertices = V`.
//!
//! A quantity is the one the editor colours by and `pappus process --quantity NAME` writes
//! ([`Quantity::per_vertex`], on the mesh's tables, so rows are the rows of `Mesh.vertices`);
//! the normals are what a save writes ([`soup_to_save`]: the file's while no edit made them
//! stale, else angle-weighted ones).

use bevy::math::Vec3;
use bevy::prelude::World;
use numpy::{AllowTypeChange, PyArrayLike2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use pappus::edit::soup_to_save;
use pappus::mesh::MeshId;
use pappus::mesh::tables::extract;
use pappus::ops::geometry::closest::Reference;
use pappus::ops::geometry::{NormalWeighting, Quantity, Surface, vertex_normals};
use pappus::ops::named::Named;

/// The quantity called `name` (any case); `ValueError` naming the known ones otherwise.
pub(crate) fn quantity_named(name: &str) -> PyResult<Quantity> {
    Quantity::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown quantity `{name}`; known: {}",
            Quantity::names().replace('|', ", ")
        ))
    })
}

/// `quantity` at every vertex of `mesh`, by row. `distance` measures to `to` (its world and
/// mesh), which it needs and the others refuse.
pub(crate) fn per_vertex(
    world: &World,
    mesh: MeshId,
    quantity: Quantity,
    to: Option<(&World, MeshId)>,
) -> PyResult<Vec<f64>> {
    match (quantity, to) {
        (Quantity::Distance, None) => {
            return Err(PyValueError::new_err(
                "the distance quantity measures to another mesh: give it as `to=`",
            ));
        }
        (Quantity::Distance, Some(_)) => {}
        (_, Some(_)) => {
            return Err(PyValueError::new_err(format!(
                "`to=` is for the distance quantity, not `{}`",
                quantity.name()
            )));
        }
        (_, None) => {}
    }
    let reference = to.map(|(w, m)| Reference::of_tables(&extract(w, m).tables));
    Ok(quantity.per_vertex(&extract(world, mesh).tables, reference.as_ref()))
}

/// The vertex normals a save writes, by row: the file's while no edit made them stale, else
/// the angle-weighted normals of the surface.
pub(crate) fn normals(world: &World, mesh: MeshId) -> Vec<Vec3> {
    if let (soup, _) = soup_to_save(world, mesh)
        && let Some(normals) = soup.vertex_normals
    {
        return normals;
    }
    let surface = Surface::from_tables(&extract(world, mesh).tables);
    vertex_normals(&surface, NormalWeighting::Angle)
        .iter()
        .map(|n| n.as_vec3())
        .collect()
}

/// New positions for `count` vertices from an `N×3` float array-like (any float dtype):
/// `ValueError` for another shape or a coordinate that is not finite, naming its row.
pub(crate) fn positions(
    array: &PyArrayLike2<'_, f64, AllowTypeChange>,
    count: usize,
) -> PyResult<Vec<Vec3>> {
    let shape = array.shape();
    if shape != [count, 3] {
        return Err(PyValueError::new_err(format!(
            "vertices must be a {count}×3 array (one row a vertex), not {}×{}",
            shape[0], shape[1]
        )));
    }
    array
        .as_array()
        .outer_iter()
        .enumerate()
        .map(|(row, p)| {
            let q = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
            if q.is_finite() {
                Ok(q)
            } else {
                Err(PyValueError::new_err(format!(
                    "vertex row {row} is not finite: ({}, {}, {})",
                    p[0], p[1], p[2]
                )))
            }
        })
        .collect()
}
