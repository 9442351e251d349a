//! What the editing session knows beside the meshes themselves: which mesh has unsaved
//! changes, and the last simplification's history. Every stage of the pipeline (apply, undo,
//! jobs, the panel) reads these, so they live here, below all of them.

use bevy::prelude::{Component, Resource, World};

use crate::mesh::MeshId;
use crate::ops::progressive::ProgressiveMesh;

/// Marks a mesh changed since it was opened or saved.
#[derive(Component, Debug, Default, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct Modified;

/// The last simplification's history: the level-of-detail slider and vertex splits move along
/// it. An edit that does not [`crate::edit::Edit::keeps_history`] ends it (the history would no
/// longer describe the mesh).
#[derive(Resource, Default)]
pub struct SimplificationHistory {
    /// The progressive mesh, while it still matches the mesh.
    pub pm: Option<ProgressiveMesh>,
}

impl SimplificationHistory {
    /// The levels as the slider shows them: (coarsest, current, full) face counts.
    pub fn levels(&self) -> Option<(usize, usize, usize)> {
        self.pm.as_ref().map(|pm| {
            let coarsest = pm.full_faces - pm.records.iter().map(|r| r.faces).sum::<usize>();
            (coarsest, pm.faces(), pm.full_faces)
        })
    }
}

/// The surface of the mesh as it was before the last whole-mesh edit, ready for closest-point
/// queries: what the distance colouring measures against (how far simplification or remeshing
/// moved the surface). Built once, when the edit is recorded.
#[derive(Resource, Default)]
pub struct PreviousShape {
    /// The mesh, and its surface before the edit.
    pub shape: Option<(MeshId, crate::ops::geometry::closest::Reference)>,
}

/// Whether `mesh` has changes that are not saved.
pub fn is_modified(world: &World, mesh: MeshId) -> bool {
    world.get::<Modified>(mesh.0).is_some()
}
