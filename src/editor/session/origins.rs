//! Where each vertex came from: its row in the mesh a session opened with (a script's mesh
//! under `pappus.show`), so that what the editor hands back can say which of the script's
//! rows each vertex is, and the script's per-vertex arrays and input numbers follow the user's
//! edits.
//!
//! Kept by vertex entity. An edit keeps a vertex's entity (subdivision included: old vertices
//! keep theirs); one it makes has no origin. An undo or redo that brings a vertex back gives it
//! a new entity, so [`history`](super::history) passes its remap here, as it does to the
//! selection.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::{Entity, Resource};

use crate::mesh::VertexId;
use crate::mesh::change::Remap;

/// Each vertex's row in the mesh the session opened with (see the module doc).
#[derive(Resource, Debug, Default)]
pub struct VertexOrigins(EntityHashMap<u32>);

impl VertexOrigins {
    /// The origins of a mesh as it opened: `vertices` by row.
    pub fn of(vertices: &[VertexId]) -> Self {
        Self(
            (vertices.iter().enumerate())
                .map(|(row, v)| (v.0, row as u32))
                .collect(),
        )
    }

    /// An undo or redo brought vertices back under new entities (`map`: from the entity each
    /// had to the one that stands for it now): they keep their origins.
    pub fn follow(&mut self, map: &Remap) {
        let moved: Vec<(Entity, u32)> = (map.iter())
            .filter_map(|(old, &new)| Some((new, *self.0.get(old)?)))
            .collect();
        self.0.extend(moved);
    }

    /// The origin of each of `vertices`, -1 for a vertex made since the session opened.
    pub fn rows(&self, vertices: &[VertexId]) -> Vec<i64> {
        (vertices.iter())
            .map(|v| self.0.get(&v.0).map_or(-1, |&row| i64::from(row)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::prelude::World;

    #[test]
    fn a_vertex_keeps_its_origin_under_a_new_entity_and_a_new_one_has_none() {
        let mut world = World::new();
        let [a, b, c, d, e] = [(); 5].map(|()| VertexId(world.spawn_empty().id()));
        let mut origins = VertexOrigins::of(&[a, b, c]);
        // b was removed and brought back as d.
        origins.follow(&Remap::from_iter([(b.0, d.0)]));
        assert_eq!(origins.rows(&[a, c, d, e]), [0, 2, 1, -1]);
    }
}
