//! What the editing session knows beside the meshes themselves: which mesh has unsaved
//! changes and the mesh before the last whole-mesh edit (a mesh's simplification history is on
//! the mesh: [`crate::ops::simplification_history`]).
//! Every stage of the pipeline (apply, undo, jobs, the panel) reads these, so they live here,
//! below all of them.

use bevy::prelude::{Component, Resource, World};

use std::sync::OnceLock;

use crate::mesh::MeshId;
use crate::mesh::tables::Connectivity;
use crate::ops::geometry::closest::Reference;

/// The mesh goes back to a script when the window closes (`pappus.show`, see
/// [`crate::editor::automation::show`]), into this folder: closing then asks nothing about
/// unsaved changes, because they are not lost.
#[derive(Resource, Debug, Clone)]
pub struct ReturnsToScript(pub std::path::PathBuf);

/// Marks a mesh changed since it was opened or saved.
#[derive(Component, Debug, Default, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct Modified;

/// The mesh as it was before the last whole-mesh edit: what the distance colouring measures
/// against (how far simplification or remeshing moved the surface). Its tables are kept when the
/// edit is recorded; the closest-point grid over them is built the first time a distance is
/// asked for, so edits never pay for it unless the distance is shown.
#[derive(Resource, Default)]
pub struct PreviousShape {
    shape: Option<(MeshId, Connectivity, OnceLock<Reference>)>,
}

impl PreviousShape {
    /// Keeps `tables`, the contents `mesh` had before a whole-mesh edit.
    pub fn set(&mut self, mesh: MeshId, tables: Connectivity) {
        self.shape = Some((mesh, tables, OnceLock::new()));
    }

    /// The surface `mesh` had before its last whole-mesh edit, if that is the edit kept.
    pub fn surface(&self, mesh: MeshId) -> Option<&Reference> {
        let (kept, tables, grid) = self.shape.as_ref()?;
        (*kept == mesh).then(|| grid.get_or_init(|| Reference::of_tables(tables)))
    }
}

/// Whether `mesh` has changes that are not saved.
pub fn is_modified(world: &World, mesh: MeshId) -> bool {
    world.get::<Modified>(mesh.0).is_some()
}
