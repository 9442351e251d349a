//! How a local operation's outcome reads, for any crate that writes one: the faces to redraw are
//! those around the elements the operation touched, before and after, and the selection moves
//! to what it made. Pappus's own local operations (`ops/local/`) report through these two; an
//! operation written outside the crate can do the same.

use bevy::prelude::World;

use super::outcome::Applied;
use crate::mesh::ids::{EdgeId, ElementId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;

impl Applied {
    /// Changes the edge `e` with `change`, which says what it did and what it made (the
    /// selection moves there); the faces that were around the edge's ends, and those around
    /// what was made, are redrawn.
    ///
    /// # Refusals
    /// `change`'s (which must leave the world as it was when it refuses).
    pub fn on_edge(
        world: &mut World,
        e: EdgeId,
        change: impl FnOnce(&mut World) -> Result<(String, ElementId), Refusal>,
    ) -> Result<Applied, Refusal> {
        let m = MeshRef::new(world);
        let before = m.faces_around(&m.corners(e.into()));
        let (summary, made) = change(world)?;
        Ok(Applied::around(
            world,
            before,
            Vec::new(),
            summary,
            Some(made),
        ))
    }

    /// Carries out a checked plan whose undo seeds are `seeds` (the vertices whose
    /// neighbourhood it changes): `apply` makes the change and says what it did and made; the
    /// faces around the seeds before and after, and around what was made, are redrawn.
    pub fn carried_out(
        world: &mut World,
        seeds: Vec<VertexId>,
        apply: impl FnOnce(&mut World) -> (String, Option<ElementId>),
    ) -> Applied {
        let before = MeshRef::new(world).faces_around(&seeds);
        let (summary, made) = apply(world);
        Applied::around(world, before, seeds, summary, made)
    }
}
