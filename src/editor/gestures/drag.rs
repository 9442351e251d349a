//! Moving the selected vertex by dragging it in the viewport.
//!
//! A left press within [`super::picking::VERTEX_RADIUS_PX`] of the selected vertex starts a
//! drag; while the button is held the vertex follows the pointer in the plane through its
//! starting position that faces the camera; releasing ends it. Each frame of the drag writes an
//! [`Edit::Move`](crate::edit::Edit::Move) of the one vertex, so the mesh (and its render
//! copy) updates live through the same path as every other edit.

use bevy::input::mouse::MouseButton;
use bevy::math::primitives::InfinitePlane3d;
use bevy::prelude::*;
use bevy::window::PrimaryWindow;

use crate::mesh::ids::{ElementId, VertexId};
use crate::mesh::topology::MeshRef;

use super::picking::VERTEX_RADIUS_PX;
use crate::editor::session::requests::Request;
use crate::editor::session::selection::Selection;

/// Whether egui is using the pointer this frame (set by the UI); drags do not start then.
#[derive(Resource, Default, Debug, Clone, Copy)]
pub struct PointerCaptured(pub bool);

/// The vertex being dragged, and the plane it moves in.
#[derive(Resource, Default, Debug, Clone, Copy)]
pub struct VertexDrag {
    /// The vertex and a point of its plane, while a drag is on.
    pub active: Option<(VertexId, Vec3)>,
}

/// Starts, continues and ends vertex drags (the `Input` set).
pub fn drive_vertex_drag(world: &mut World) {
    let buttons = world.resource::<ButtonInput<MouseButton>>();
    let (pressed, just_pressed) = (
        buttons.pressed(MouseButton::Left),
        buttons.just_pressed(MouseButton::Left),
    );
    if !pressed {
        world.resource_mut::<VertexDrag>().active = None;
        return;
    }
    let Some(cursor) = world
        .query_filtered::<&Window, With<PrimaryWindow>>()
        .iter(world)
        .next()
        .and_then(Window::cursor_position)
    else {
        return;
    };
    let Some((camera, transform)) = world
        .query::<(&Camera, &GlobalTransform)>()
        .iter(world)
        .find(|(c, _)| c.is_active)
        .map(|(c, t)| (c.clone(), *t))
    else {
        return;
    };
    if just_pressed {
        let busy = world
            .get_resource::<super::transform::Gestures>()
            .is_some_and(|g| g.active.is_some() || g.swallow_click)
            || world
                .get_resource::<super::box_select::BoxSelect>()
                .is_some_and(|b| b.armed);
        if busy || world.get_resource::<PointerCaptured>().is_some_and(|p| p.0) {
            return;
        }
        let Some(ElementId::Vertex(v)) = world.resource::<Selection>().element else {
            return;
        };
        let m = MeshRef::new(world);
        let Some(p) = m.try_position(v) else {
            return;
        };
        let near = camera
            .world_to_viewport(&transform, p)
            .is_ok_and(|s| s.distance(cursor) <= VERTEX_RADIUS_PX);
        if near {
            world.resource_mut::<VertexDrag>().active = Some((v, p));
        }
        return;
    }
    let Some((v, origin)) = world.resource::<VertexDrag>().active else {
        return;
    };
    let Ok(ray) = camera.viewport_to_world(&transform, cursor) else {
        return;
    };
    let plane = InfinitePlane3d::new(transform.forward());
    if let Some(target) = ray.plane_intersection_point(origin, plane)
        && MeshRef::new(world).try_position(v) != Some(target)
    {
        world.write_message(Request::Edit(crate::edit::Edit::Move(vec![(v, target)])));
    }
}
