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
use pappus::mesh::tables::VertexRow;
use pappus::mesh::tables::extract;
use pappus::ops::geometry::closest::Reference;
use pappus::ops::geometry::quantity::{Given, Needs};
use pappus::ops::geometry::{NormalWeighting, Quantity, Surface, vertex_normals};
use pappus::ops::registry;

/// The registered quantity called `name` (any case); `ValueError` naming the known ones
/// otherwise.
pub(crate) fn quantity_named(name: &str) -> PyResult<Quantity> {
    registry::quantity(name).ok_or_else(|| {
        let names: Vec<&str> = registry::quantities().iter().map(|q| q.name()).collect();
        PyValueError::new_err(format!(
            "unknown quantity `{name}`; known: {}",
            names.join(", ")
        ))
    })
}

/// `quantity` at every vertex of `mesh`, by row. One that measures to another surface takes
/// it as `to` (its world and mesh), one that starts from vertices takes their rows as
/// `sources`; each needs its own and refuses the other.
pub(crate) fn per_vertex(
    world: &World,
    mesh: MeshId,
    quantity: Quantity,
    to: Option<(&World, MeshId)>,
    sources: Option<Vec<i64>>,
) -> PyResult<Vec<f64>> {
    let name = quantity.name();
    match (quantity.needs(), to.is_some(), sources.is_some()) {
        (Needs::Other, false, _) => {
            return Err(PyValueError::new_err(format!(
                "{name} measures to another mesh: give it as `to=`"
            )));
        }
        (Needs::Sources, _, false) => {
            return Err(PyValueError::new_err(format!(
                "{name} starts from vertices: give their rows as `sources=`"
            )));
        }
        (Needs::Other, _, true) | (Needs::Mesh, _, true) => {
            return Err(PyValueError::new_err(format!(
                "`sources=` is for a quantity that starts from vertices, not `{name}`"
            )));
        }
        (Needs::Sources, true, _) | (Needs::Mesh, true, _) => {
            return Err(PyValueError::new_err(format!(
                "`to=` is for a quantity that measures to another mesh, not `{name}`"
            )));
        }
        _ => {}
    }
    let read = extract(world, mesh);
    let count = read.tables.vertex_count() as i64;
    let sources: Vec<VertexRow> = sources
        .unwrap_or_default()
        .into_iter()
        .map(|row| match row {
            r if (0..count).contains(&r) => Ok(VertexRow::new(r as u32)),
            r if (-count..0).contains(&r) => Ok(VertexRow::new((count + r) as u32)),
            r => Err(PyValueError::new_err(format!(
                "source row {r} is out of range for {count} vertices"
            ))),
        })
        .collect::<PyResult<_>>()?;
    let reference = to.map(|(w, m)| Reference::of_tables(&extract(w, m).tables));
    let given = Given {
        other: reference.as_ref(),
        sources: &sources,
        vertices: &read.members.vertices,
        faces: &read.members.faces,
    };
    Ok(quantity.per_vertex(&read.tables, &given))
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
