//! Colouring the mesh by a quantity (curvature, valence, angles, edge lengths): the values, the
//! colour map and its range, kept on the mesh entity and recomputed when the mesh changes, never
//! per frame.
//!
//! The panel picks the quantity ([`ColorBy`]); in the `Sync` set, before the render copy is
//! rebuilt, [`update_vertex_values`] computes it for every mesh that changed (or all of them when
//! the choice changed) into [`VertexValues`], which the render sync turns into vertex colours
//! and the panel into a legend and the value at the selection. The range is clamped at the 1st
//! and 99th percentiles ([`Range::robust`]), so that one near-degenerate triangle does not wash
//! the map out; a local edit keeps the range it had, so its few redrawn chunks match the rest.

use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::{Component, Entity, Resource, With, World};

use crate::colormap::{ColorMap, Range};
use crate::mesh::MeshInfo;
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::tables::{EntityRows, VertexRow, extract};
use crate::mesh::{MeshMembers, MeshRef};
use crate::ops::geometry::Quantity;
use crate::ops::geometry::quantity::{Given, Needs};

use crate::editor::session::selection::{DirtyFaces, LooksDirty, MeshDirty, Selection};
use crate::editor::session::state::PreviousShape;

/// The quantity the meshes are coloured by, if any (set by the panel).
#[derive(Resource, Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct ColorBy(pub Option<Quantity>);

/// A mesh's values of the quantity on display, by vertex (by face for a quantity on the
/// faces), and how they map to colours.
#[derive(Component, Debug, Clone)]
pub struct VertexValues {
    /// The quantity.
    pub quantity: Quantity,
    /// Its value at each vertex, or at each face when [`VertexValues::on_faces`].
    pub values: EntityHashMap<f64>,
    /// The values are the faces' ([`crate::ops::geometry::quantity::VertexQuantity::per_face`]):
    /// each face is drawn in one colour.
    pub on_faces: bool,
    /// The colour map.
    pub map: ColorMap,
    /// The values the map spans.
    pub range: Range,
}

impl VertexValues {
    /// The colour of `element`, a vertex (a face for values on faces), in linear RGBA for
    /// the renderer; mid-grey if it has no value (none, or NaN: a quantity that cannot be
    /// computed there, a given array's new element).
    pub fn colour(&self, element: Entity) -> [f32; 4] {
        let srgb = match self.values.get(&element) {
            Some(&value) if !value.is_nan() => self.map.at(self.range.fraction(value)),
            _ => [128, 128, 128],
        };
        let [r, g, b] = srgb.map(|c| srgb_to_linear(c as f32 / 255.0));
        [r, g, b, 1.0]
    }
}

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The percentile at which the colour range is clamped at each end.
pub const CLAMP_PERCENTILE: f64 = 1.0;

/// Computes the values of `quantity` on `mesh`. `range` keeps a range already shown (a local
/// edit); `None` takes the robust range of the new values.
pub fn vertex_values(
    world: &World,
    mesh: MeshId,
    quantity: Quantity,
    range: Option<Range>,
) -> VertexValues {
    let read = extract(world, mesh);
    // A distance is to the mesh before its last whole-mesh edit, where there was one; a
    // quantity from sources starts at the selection's vertices.
    let other = (quantity.needs() == Needs::Other)
        .then(|| world.get_resource::<PreviousShape>())
        .flatten()
        .and_then(|p| p.surface(mesh));
    let sources = match quantity.needs() {
        Needs::Sources => selected_rows(world, &read.members),
        _ => Vec::new(),
    };
    let given = Given {
        other,
        sources: &sources,
        vertices: &read.members.vertices,
        faces: &read.members.faces,
    };
    let (values, elements, on_faces): (Vec<f64>, Vec<Entity>, bool) =
        match quantity.per_face(&read.tables, &given) {
            Some(values) => (
                values,
                read.members.faces.iter().map(|f| f.0).collect(),
                true,
            ),
            None => (
                quantity.per_vertex(&read.tables, &given),
                read.members.vertices.iter().map(|v| v.0).collect(),
                false,
            ),
        };
    let map = quantity.colormap();
    let range = range.unwrap_or_else(|| Range::robust(&values, CLAMP_PERCENTILE, map));
    VertexValues {
        quantity,
        values: elements.into_iter().zip(values).collect(),
        on_faces,
        map,
        range,
    }
}

/// The rows of the selected elements' corners among `members` (those of other meshes left out).
fn selected_rows(world: &World, members: &MeshMembers) -> Vec<VertexRow> {
    let Some(selection) = world.get_resource::<Selection>() else {
        return Vec::new();
    };
    let rows = EntityRows::new(members);
    let m = MeshRef::new(world);
    let mut sources: Vec<VertexRow> = selection
        .elements()
        .iter()
        .flat_map(|&x| m.corners(x))
        .filter_map(|v| rows.row(v.0))
        .map(VertexRow::new)
        .collect();
    sources.sort_unstable();
    sources.dedup();
    sources
}

/// Keeps [`VertexValues`] in step with the meshes and [`ColorBy`] (the `Sync` set, before the
/// render sync): recomputed for meshes about to be redrawn; on a change of quantity, or of the
/// selection for a quantity from sources, for every mesh, each then redrawn whole.
pub fn update_vertex_values(
    world: &mut World,
    mut shown: bevy::prelude::Local<(Option<Quantity>, Vec<ElementId>)>,
) {
    let wanted = world
        .get_resource::<ColorBy>()
        .copied()
        .unwrap_or_default()
        .0;
    let meshes: Vec<Entity> = world
        .query_filtered::<Entity, With<MeshInfo>>()
        .iter(world)
        .collect();
    let sources: Vec<ElementId> = match wanted.map(Quantity::needs) {
        Some(Needs::Sources) => world
            .get_resource::<Selection>()
            .map(|s| s.elements().to_vec())
            .unwrap_or_default(),
        _ => Vec::new(),
    };
    let switched = shown.0 != wanted || shown.1 != sources;
    *shown = (wanted, sources);
    for entity in meshes {
        let changed = world.get::<MeshDirty>(entity).is_some();
        let local = world.get::<DirtyFaces>(entity).is_some();
        let Some(quantity) = wanted else {
            if world.entity_mut(entity).take::<VertexValues>().is_some() {
                world.entity_mut(entity).insert(LooksDirty);
            }
            continue;
        };
        let missing = world.get::<VertexValues>(entity).is_none();
        if !(switched || changed || local || missing) {
            continue;
        }
        let keep = world
            .get::<VertexValues>(entity)
            .filter(|v| local && !changed && !switched && v.quantity == quantity)
            .map(|v| v.range);
        let values = vertex_values(world, MeshId(entity), quantity, keep);
        let mut e = world.entity_mut(entity);
        e.insert(values);
        if switched || missing {
            e.insert(LooksDirty);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    #[test]
    fn values_cover_every_vertex_and_colour_by_the_range() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let v = vertex_values(&world, built.mesh, Quantity::VALENCE, None);
        assert_eq!(v.values.len(), 8);
        assert!(v.values.values().all(|&x| x == 3.0));
        let corner = built.input_vertices[0].unwrap().0;
        // Every value equal: the range is [3, 4] and 3 is its low end.
        assert_eq!(v.colour(corner)[3], 1.0);
        assert_eq!(v.range.fraction(3.0), 0.0);
    }
}
