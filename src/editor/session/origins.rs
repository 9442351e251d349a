//! Where each vertex and face came from: its row in the mesh a session opened with (a
//! script's mesh under `pappus.show`), so that what the editor hands back can say which of the
//! script's rows each element is, and the script's per-element arrays and input numbers follow
//! the user's edits.
//!
//! Kept by entity. An edit keeps an element's entity (subdivision keeps the old vertices'); one
//! it makes has no origin. An undo or redo that brings an element back gives it a new entity,
//! so [`history`](super::history) passes its remap here, as it does to the selection. An edit
//! that rewrites the faces in place (subdivision) leaves every face without an origin
//! ([`Origins::faces_renumbered`], called by [`finish`](super::finish)): a face entity then
//! names another face.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::{Entity, Resource};

use crate::mesh::change::{Remap, follow_renamed};
use crate::mesh::{FaceId, VertexId};

/// Each vertex's and face's row in the mesh the session opened with (see the module doc).
#[derive(Resource, Debug, Default)]
pub struct Origins {
    vertices: EntityHashMap<u32>,
    faces: EntityHashMap<u32>,
}

/// Each entity of `elements` with its row.
fn by_row(elements: impl Iterator<Item = Entity>) -> EntityHashMap<u32> {
    elements
        .enumerate()
        .map(|(row, e)| (e, row as u32))
        .collect()
}

/// The row of each of `elements` in `origins`, -1 for one without.
fn rows_of(origins: &EntityHashMap<u32>, elements: impl Iterator<Item = Entity>) -> Vec<i64> {
    elements
        .map(|e| origins.get(&e).map_or(-1, |&row| i64::from(row)))
        .collect()
}

impl Origins {
    /// The origins of a mesh as it opened: its `vertices` and `faces` by row.
    pub fn of(vertices: &[VertexId], faces: &[FaceId]) -> Self {
        Self {
            vertices: by_row(vertices.iter().map(|v| v.0)),
            faces: by_row(faces.iter().map(|f| f.0)),
        }
    }

    /// An undo or redo brought elements back under new entities (`map`: from the entity each
    /// had to the one that stands for it now): they keep their origins.
    pub fn follow(&mut self, map: &Remap) {
        follow_renamed(&mut self.vertices, map);
        follow_renamed(&mut self.faces, map);
    }

    /// An edit rewrote the faces in place: no face has an origin any more.
    pub fn faces_renumbered(&mut self) {
        self.faces.clear();
    }

    /// The origin of each of `vertices`, -1 for a vertex made since the session opened.
    pub fn vertex_rows(&self, vertices: &[VertexId]) -> Vec<i64> {
        rows_of(&self.vertices, vertices.iter().map(|v| v.0))
    }

    /// The origin of each of `faces`, -1 for a face made since the session opened (or since
    /// the faces were renumbered).
    pub fn face_rows(&self, faces: &[FaceId]) -> Vec<i64> {
        rows_of(&self.faces, faces.iter().map(|f| f.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::prelude::World;

    #[test]
    fn an_element_keeps_its_origin_under_a_new_entity_and_a_new_one_has_none() {
        let mut world = World::new();
        let [a, b, c, d, e] = [(); 5].map(|()| VertexId(world.spawn_empty().id()));
        let [f, g, h] = [(); 3].map(|()| FaceId(world.spawn_empty().id()));
        let mut origins = Origins::of(&[a, b, c], &[f, g]);
        // b was removed and brought back as d, g as h.
        origins.follow(&Remap::from_iter([(b.0, d.0), (g.0, h.0)]));
        assert_eq!(origins.vertex_rows(&[a, c, d, e]), [0, 2, 1, -1]);
        assert_eq!(origins.face_rows(&[h, f]), [1, 0]);
        origins.faces_renumbered();
        assert_eq!(origins.face_rows(&[h, f]), [-1, -1]);
        assert_eq!(origins.vertex_rows(&[a]), [0]);
    }
}
