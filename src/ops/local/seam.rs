//! Seam marks: an edge marked as a seam is one the parameterization cuts the surface along
//! ([`crate::ops::param`]). Marking changes no connectivity and no position; the mesh's
//! attribute record says it may have seams from the first mark on, so a save writes them.

use bevy::prelude::World;

use crate::mesh::InMesh;
use crate::mesh::attributes::{MeshAttributes, Seam, set_record};
use crate::mesh::ids::{EdgeId, ElementId};
use crate::ops::Refusal;

/// Marks `e` as a seam, or unmarks it; returns whether it is one now.
///
/// # Refusals
/// [`Refusal::Stale`] when `e` is not a live edge.
pub fn toggle_seam(world: &mut World, e: EdgeId) -> Result<bool, Refusal> {
    let Some(mesh) = world
        .get::<crate::mesh::Edge>(e.0)
        .and_then(|_| world.get::<InMesh>(e.0))
        .map(|m| m.0)
    else {
        return Err(Refusal::Stale(ElementId::Edge(e)));
    };
    let mut edge = world.entity_mut(e.0);
    let marked = !edge.contains::<Seam>();
    if marked {
        edge.insert(Seam);
        let mut has = MeshAttributes::of(world, mesh);
        has.seams = true;
        set_record(world, mesh, has);
    } else {
        edge.remove::<Seam>();
    }
    Ok(marked)
}
