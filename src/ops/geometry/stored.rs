//! A quantity whose values are given rather than computed: an array a script hands to the
//! editor (`pappus.show(mesh, quantities={"geodesic": d})`), shown beside Pappus's own
//! quantities with its colour map and legend.
//!
//! The values are kept by vertex (or face) entity, not by row, so they follow the elements
//! through edits: an element an edit keeps keeps its value; one it makes has none (NaN, which
//! the editor draws grey and the colour range leaves out); one an undo brings back under a new
//! entity gets its value again ([`VertexQuantity::follow`]). Values on faces are forgotten
//! when an edit rewrites the faces in place (subdivision, [`VertexQuantity::faces_renumbered`]),
//! and then drawn grey: never on faces they were not given for. A caller that reads it without the
//! entities behind the rows ([`Given::vertices`], [`Given::faces`] empty) gets NaN everywhere.
//! Values on faces are also read per vertex, as the mean of the vertex's faces' values, for
//! what colours vertices (the command line, Python).

use bevy::ecs::entity::EntityHashMap;
use bevy::ecs::world::WorldId;
use bevy::prelude::Entity;
use std::sync::{PoisonError, RwLock};

use crate::colormap::ColorMap;
use crate::mesh::change::{Remap, follow_renamed};
use crate::mesh::tables::Connectivity;
use crate::mesh::{FaceId, VertexId};

use super::quantity::{Given, Needs, QuantityDeclaration, VertexQuantity};

/// Values given per vertex or per face, by entity (see the module doc).
pub struct StoredQuantity {
    declaration: &'static QuantityDeclaration,
    /// Written only when an undo or redo gives elements new entities, or an edit renumbers the
    /// faces ([`VertexQuantity::follow`], [`VertexQuantity::faces_renumbered`]): a registered
    /// quantity is shared.
    values: RwLock<EntityHashMap<f64>>,
    on_faces: bool,
    /// The world whose entities the values are keyed by, once told ([`StoredQuantity::of_world`]):
    /// only that world's undo and renumbering edits move them (entity ids of two worlds may
    /// coincide).
    world: Option<WorldId>,
}

impl StoredQuantity {
    /// A quantity named `name` (unique among the registered ones: the caller checks) and
    /// labelled `label`, with `values` at these vertices. Its colour map is diverging when the
    /// finite values have both signs, viridis otherwise.
    ///
    /// The declaration's strings live as long as the process (a registered quantity's do);
    /// a process registers a handful of these, never one per frame.
    pub fn new(name: &str, label: &str, values: impl IntoIterator<Item = (VertexId, f64)>) -> Self {
        Self::by_entity(
            name,
            label,
            values.into_iter().map(|(v, x)| (v.0, x)),
            false,
        )
    }

    /// As [`StoredQuantity::new`], with the values on these faces.
    pub fn on_faces(
        name: &str,
        label: &str,
        values: impl IntoIterator<Item = (FaceId, f64)>,
    ) -> Self {
        Self::by_entity(name, label, values.into_iter().map(|(f, x)| (f.0, x)), true)
    }

    fn by_entity(
        name: &str,
        label: &str,
        values: impl IntoIterator<Item = (Entity, f64)>,
        on_faces: bool,
    ) -> Self {
        let values: EntityHashMap<f64> = values.into_iter().collect();
        let finite = || values.values().filter(|x| x.is_finite());
        let signed = finite().any(|&x| x < 0.0) && finite().any(|&x| x > 0.0);
        let declaration = Box::leak(Box::new(QuantityDeclaration {
            name: Box::leak(name.into()),
            label: Box::leak(label.into()),
            colormap: if signed {
                ColorMap::Diverging
            } else {
                ColorMap::Viridis
            },
            needs: Needs::Mesh,
        }));
        Self {
            declaration,
            values: RwLock::new(values),
            on_faces,
            world: None,
        }
    }

    /// The same, its values keyed by the entities of `world`: that world's undo and redo and
    /// its edits that renumber faces move them ([`VertexQuantity::follow`],
    /// [`VertexQuantity::faces_renumbered`]); without it they stay as given.
    pub fn of_world(self, world: WorldId) -> Self {
        Self {
            world: Some(world),
            ..self
        }
    }

    /// The value of each of these elements (NaN for one without).
    fn read(&self, elements: impl Iterator<Item = Entity>) -> Vec<f64> {
        let values = self.values.read().unwrap_or_else(PoisonError::into_inner);
        elements
            .map(|e| values.get(&e).copied().unwrap_or(f64::NAN))
            .collect()
    }
}

impl VertexQuantity for StoredQuantity {
    fn declaration(&self) -> &'static QuantityDeclaration {
        self.declaration
    }

    fn per_vertex(&self, t: &Connectivity, given: &Given<'_>) -> Vec<f64> {
        if !self.on_faces {
            if given.vertices.len() != t.vertex_count() {
                return vec![f64::NAN; t.vertex_count()];
            }
            return self.read(given.vertices.iter().map(|v| v.0));
        }
        let Some(faces) = self.per_face(t, given) else {
            return vec![f64::NAN; t.vertex_count()];
        };
        t.vertices()
            .map(|v| {
                let (sum, n) = t
                    .vertex_outgoing(v)
                    .filter_map(|h| t.face(h))
                    .map(|f| faces[f.index()])
                    .filter(|x| !x.is_nan())
                    .fold((0.0, 0.0), |(s, n), x| (s + x, n + 1.0));
                if n > 0.0 { sum / n } else { f64::NAN }
            })
            .collect()
    }

    fn per_face(&self, t: &Connectivity, given: &Given<'_>) -> Option<Vec<f64>> {
        if !self.on_faces {
            return None;
        }
        if given.faces.len() != t.face_count() {
            return Some(vec![f64::NAN; t.face_count()]);
        }
        Some(self.read(given.faces.iter().map(|f| f.0)))
    }

    fn faces_renumbered(&self, world: WorldId) -> bool {
        if !self.on_faces || self.world != Some(world) {
            return false;
        }
        let mut values = self.values.write().unwrap_or_else(PoisonError::into_inner);
        let had = !values.is_empty();
        values.clear();
        had
    }

    fn follow(&self, world: WorldId, map: &Remap) {
        if self.world != Some(world) {
            return;
        }
        let mut values = self.values.write().unwrap_or_else(PoisonError::into_inner);
        follow_renamed(&mut values, map);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use bevy::prelude::World;

    #[test]
    fn values_follow_the_vertices_and_are_nan_where_none_was_given() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let read = extract(&world, built.mesh);
        // A value on every vertex but the first, equal to its input number.
        let given: Vec<(VertexId, f64)> = built
            .input_vertices
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, v)| (v.unwrap(), i as f64))
            .collect();
        let q = StoredQuantity::new("heights", "heights", given);
        assert_eq!(q.declaration().colormap, ColorMap::Viridis);
        let values = q.per_vertex(
            &read.tables,
            &Given {
                vertices: &read.members.vertices,
                ..Given::default()
            },
        );
        for (row, v) in read.members.vertices.iter().enumerate() {
            let input = built.input_vertices.iter().position(|&w| w == Some(*v));
            match input {
                Some(0) => assert!(values[row].is_nan()),
                Some(i) => assert_eq!(values[row], i as f64),
                None => unreachable!("every vertex of a cube is an input vertex"),
            }
        }
        // Without the entities behind the rows, nothing can be read.
        let blind = q.per_vertex(&read.tables, &Given::default());
        assert!(blind.iter().all(|x| x.is_nan()));
        let signed = StoredQuantity::new("s", "s", [(read.members.vertices[0], -1.0)]);
        assert_eq!(signed.declaration().colormap, ColorMap::Viridis);
        let signed = StoredQuantity::new(
            "t",
            "t",
            [
                (read.members.vertices[0], -1.0),
                (read.members.vertices[1], 2.0),
            ],
        );
        assert_eq!(signed.declaration().colormap, ColorMap::Diverging);
    }

    /// An undo's remap and a renumbering edit move the values of their own world's quantity
    /// only; a renumbering forgets values on faces, never on vertices.
    #[test]
    fn only_its_own_worlds_undo_and_renumbering_move_the_values() {
        let (mut mine, other) = (World::new(), World::new());
        let built = build_mesh(&mut mine, &shapes::cube(), MeshInfo::default()).unwrap();
        let read = extract(&mine, built.mesh);
        let v = read.members.vertices[0];
        let face = read.members.faces[0];
        let back = VertexId(mine.spawn_empty().id());
        let at = |q: &StoredQuantity, e: Entity| q.read(std::iter::once(e))[0];
        let on_vertices = StoredQuantity::new("v", "v", [(v, 2.0)]).of_world(mine.id());
        let map = Remap::from_iter([(v.0, back.0)]);
        on_vertices.follow(other.id(), &map);
        assert!(at(&on_vertices, back.0).is_nan());
        on_vertices.follow(mine.id(), &map);
        assert_eq!(at(&on_vertices, back.0), 2.0);
        assert!(!on_vertices.faces_renumbered(mine.id()));
        assert_eq!(at(&on_vertices, v.0), 2.0);
        let on_faces = StoredQuantity::on_faces("f", "f", [(face, 3.0)]).of_world(mine.id());
        assert!(!on_faces.faces_renumbered(other.id()));
        assert_eq!(at(&on_faces, face.0), 3.0);
        assert!(on_faces.faces_renumbered(mine.id()));
        assert!(at(&on_faces, face.0).is_nan());
    }
}
