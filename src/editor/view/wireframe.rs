//! Each render chunk's wireframe: the real edges of its faces (a quad shows four, not five;
//! boundary edges red) as a mesh of [`super::lines`], one per chunk, beside the chunk's
//! surface. [`super::render_sync`] decides which edges a chunk draws and when; this is how they
//! are drawn, moved and shown.

use bevy::color::Color;
use bevy::ecs::change_detection::DetectChangesMut;
use bevy::prelude::*;

use super::lines::{LinesMaterial, Segment, ThinLines, line_mesh};
use crate::mesh::ids::VertexId;
use crate::mesh::topology::MeshRef;

/// The mesh of a chunk's wireframe lines.
#[derive(Component, Debug, Clone)]
pub struct WireLines(pub Handle<Mesh>);

/// The end vertices of a chunk's wireframe lines, with their colours.
#[derive(Component, Debug, Clone, Default)]
pub struct WireEnds(pub Vec<(VertexId, VertexId, Color)>);

/// The wireframe's lines between these ends, at the vertices' positions now.
pub fn wire_mesh(world: &World, ends: &[(VertexId, VertexId, Color)]) -> Mesh {
    let m = MeshRef::new(world);
    let segments = ends.iter().map(|&(a, b, color)| Segment {
        ends: [m.position(a), m.position(b)],
        color: color.into(),
    });
    line_mesh(&ThinLines {
        segments: segments.collect(),
        dots: Vec::new(),
    })
}

/// Gives the wire entity `wire` a mesh of the lines between `ends`, drawn with `material`; a
/// wire with no lines, or no material (no window), draws nothing (a mesh without vertices is
/// not drawn).
pub fn draw_wire(
    world: &mut World,
    wire: Entity,
    ends: Vec<(VertexId, VertexId, Color)>,
    material: Option<Handle<LinesMaterial>>,
) {
    match material {
        Some(material) if !ends.is_empty() => {
            let lines = wire_mesh(world, &ends);
            let handle = world.resource_mut::<Assets<Mesh>>().add(lines);
            world.entity_mut(wire).insert((
                Mesh3d(handle.clone()),
                MeshMaterial3d(material),
                WireLines(handle),
                WireEnds(ends),
                Transform::default(),
                Visibility::default(),
                bevy::picking::Pickable::IGNORE,
            ));
        }
        _ => {
            world
                .entity_mut(wire)
                .remove::<(Mesh3d, WireLines, WireEnds)>();
        }
    }
}

/// Hides or shows every wireframe (the wireframe toggle). Wireframes not built yet are built by
/// the caller's redraw.
pub fn set_wireframes_visible(world: &mut World, visible: bool) {
    let shown = if visible {
        Visibility::Inherited
    } else {
        Visibility::Hidden
    };
    let mut wires = world.query_filtered::<&mut Visibility, With<WireLines>>();
    for mut visibility in wires.iter_mut(world) {
        visibility.set_if_neq(shown);
    }
}
