//! Box selection (B, as in Blender): after B, a left drag draws a rectangle; on release the
//! elements of the click mode's kind inside it and facing the camera are selected (added to the
//! selection when Shift is held at the release). Esc or a right click disarms it.

use bevy::input::mouse::MouseButton;
use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use bevy_egui::{EguiContexts, egui};

use crate::mesh::MeshMembers;
use crate::mesh::topology::MeshRef;

use super::transform::Gestures;
use crate::editor::session::requests::{Request, SelectionEdit};
use crate::editor::session::select_many::inside_box;
use crate::editor::session::selection::{ActiveMesh, SelectMode};

/// The box selection: armed by B, then the corners of the rectangle being dragged.
#[derive(Resource, Default, Debug, Clone, Copy)]
pub struct BoxSelect {
    /// B was pressed: the next left drag draws a box.
    pub armed: bool,
    /// Where the drag started and where the pointer is, while it lasts.
    pub drag: Option<(Vec2, Vec2)>,
}

/// Drives the box: starts it on a left press while armed, follows the pointer, and selects
/// on release (the `Input` set).
pub fn drive_box_select(world: &mut World) {
    let gesture = world
        .get_resource::<Gestures>()
        .is_some_and(|g| g.active.is_some() || g.swallow_click);
    if !world.resource::<BoxSelect>().armed || gesture {
        return;
    }
    let (buttons, keys) = (
        world.resource::<ButtonInput<MouseButton>>(),
        world.resource::<ButtonInput<KeyCode>>(),
    );
    if keys.just_pressed(KeyCode::Escape) || buttons.just_pressed(MouseButton::Right) {
        *world.resource_mut::<BoxSelect>() = BoxSelect::default();
        world.resource_mut::<Gestures>().keys_taken = true;
        return;
    }
    let (pressed, released) = (
        buttons.just_pressed(MouseButton::Left),
        buttons.just_released(MouseButton::Left),
    );
    let buttons = buttons.clone();
    let add = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    let mut state = *world.resource::<BoxSelect>();
    // A release outside the window ends the box where the pointer last was inside it.
    let Some(cursor) = world
        .query_filtered::<&Window, With<PrimaryWindow>>()
        .iter(world)
        .next()
        .and_then(Window::cursor_position)
        .or(state.drag.map(|(_, to)| to))
    else {
        return;
    };
    if pressed && state.drag.is_none() {
        state.drag = Some((cursor, cursor));
    }
    match state.drag {
        Some((from, _)) if released => {
            *world.resource_mut::<BoxSelect>() = BoxSelect::default();
            // The release would also be a click on the mesh: picking ignores clicks while a box
            // is armed (see `picking::on_click`).
            let elements = elements_in(world, from, cursor);
            let edit = match add {
                true => SelectionEdit::Add(elements),
                false => SelectionEdit::Replace(elements),
            };
            world.write_message(Request::Selection(edit));
            return;
        }
        Some((from, _)) if buttons.pressed(MouseButton::Left) => {
            state.drag = Some((from, cursor));
        }
        _ => {}
    }
    *world.resource_mut::<BoxSelect>() = state;
}

/// The elements inside the rectangle with corners `a` and `b` (viewport pixels).
pub fn elements_in(world: &mut World, a: Vec2, b: Vec2) -> Vec<crate::mesh::ElementId> {
    let Some(mesh) = world.resource::<ActiveMesh>().0 else {
        return Vec::new();
    };
    let Some((camera, transform)) = world
        .query_filtered::<(&Camera, &GlobalTransform), With<Camera3d>>()
        .iter(world)
        .find(|(c, _)| c.is_active)
        .map(|(c, t)| (c.clone(), *t))
    else {
        return Vec::new();
    };
    let mode = *world.resource::<SelectMode>();
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    inside_box(
        &m,
        &members,
        mode,
        (a.min(b), a.max(b)),
        transform.translation(),
        |p| camera.world_to_viewport(&transform, p).ok(),
    )
}

/// Draws the rectangle being dragged, and a hint while armed.
pub fn draw_box(mut contexts: EguiContexts, state: Res<BoxSelect>) -> Result {
    if !state.armed {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?;
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::new("box select"),
    ));
    let colour = egui::Color32::from_rgb(255, 170, 60);
    match state.drag {
        Some((a, b)) => {
            let rect = egui::Rect::from_two_pos(egui::pos2(a.x, a.y), egui::pos2(b.x, b.y));
            painter.rect_filled(rect, 0.0, colour.gamma_multiply(0.12));
            painter.rect_stroke(
                rect,
                0.0,
                egui::Stroke::new(1.5, colour),
                egui::StrokeKind::Middle,
            );
        }
        None => {
            let at = ctx.viewport_rect().center_top() + egui::vec2(0.0, 12.0);
            painter.text(
                at,
                egui::Align2::CENTER_TOP,
                "box select: drag a rectangle (Shift at release adds; Esc cancels)",
                egui::FontId::proportional(15.0),
                colour,
            );
        }
    }
    Ok(())
}
