//! `Mesh.vertex_data`: the per-vertex scalars a file carried that the halfedge mesh has no
//! column for (a PLY's `quality` and its other vertex properties: `confidence`, `intensity`,
//! …), kept beside the mesh by vertex.
//!
//! Each value belongs to its vertex's entity, so it follows the vertex through every edit that
//! keeps it (flips, collapses of its neighbours, subdivision, which keeps vertex ids) and goes
//! with it; a vertex an edit made has none (NaN when read). Keyed by the whole entity,
//! generation included, so a vertex that reuses a removed one's slot never inherits its value.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::World;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pappus::mesh::{MeshId, MeshMembers, PolygonSoup, VertexId};

/// Named per-vertex scalars, each a value by vertex entity.
#[derive(Default)]
pub(crate) struct VertexData {
    /// `(name, value by vertex)`, in the order the file listed them.
    columns: Vec<(String, EntityHashMap<f32>)>,
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
        Self { columns }
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
