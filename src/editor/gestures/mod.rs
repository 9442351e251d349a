//! The gestures room: what the pointer and the modal keys do in the viewport. Picking an
//! element ([`picking`]), Blender's modal transforms ([`transform`]) with
//! proportional editing ([`proportional`]) and handle deformation ([`handle_deform`]), box selection
//! ([`box_select`]), dragging a vertex ([`drag`]), the camera's orbit, pan, zoom and framing
//! ([`camera`]), and what is drawn over the surface to show them and the selection
//! ([`overlay`]). It reads the session, pipeline and view rooms.

pub mod box_select;
pub mod camera;
pub mod drag;
pub mod handle_deform;
pub mod overlay;
pub mod overlay_lines;
pub mod picking;
pub mod proportional;
pub mod transform;
pub mod typed_value;

use bevy::prelude::*;

use crate::editor::session::history::track_presses;
use crate::editor::session::schedule::{EditorSystems, KeyboardCaptured};
use crate::editor::session::selection::ActiveMesh;
use crate::editor::view::render_sync::sync_render_meshes;
use crate::editor::view::scene::fit_near_plane;

/// Picks turned into requests, the modal gestures driven by the keys, and the overlay gathered
/// (no window needed: the headless tests drive gestures and read the overlay).
pub struct GesturesPlugin;

impl Plugin for GesturesPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<picking::PickRequest>()
            .init_resource::<overlay::Overlay>()
            .init_resource::<transform::Gestures>()
            .init_resource::<handle_deform::Anchors>()
            .init_resource::<box_select::BoxSelect>()
            .add_systems(
                Update,
                (
                    transform::drive_gesture
                        .after(track_presses)
                        .in_set(EditorSystems::Input),
                    picking::resolve_picks.in_set(EditorSystems::Request),
                    overlay::gather_overlay
                        .after(sync_render_meshes)
                        .in_set(EditorSystems::Sync),
                ),
            );
    }
}

/// The pointer's part: picking observers, the box and the vertex drag, the camera controls,
/// and the overlay's gizmos and lines.
pub struct GesturesWindowPlugin;

impl Plugin for GesturesWindowPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(overlay_lines::OverlayLinesPlugin)
            .init_gizmo_group::<overlay::HighlightGizmos>()
            .init_resource::<drag::VertexDrag>()
            .init_resource::<drag::PointerCaptured>()
            .add_systems(Startup, overlay::configure_gizmos)
            .add_systems(
                Update,
                (
                    camera::orbit_controls
                        .run_if(|k: Res<KeyboardCaptured>| !k.0)
                        .in_set(EditorSystems::Input),
                    (box_select::drive_box_select, drag::drive_vertex_drag)
                        .chain()
                        .after(transform::drive_gesture)
                        .in_set(EditorSystems::Input),
                    frame_new_meshes
                        .after(EditorSystems::Apply)
                        .before(fit_near_plane)
                        .before(EditorSystems::Sync),
                    (overlay::draw_overlay, overlay_lines::update_overlay_lines)
                        .after(EditorSystems::Sync),
                ),
            )
            .add_systems(bevy_egui::EguiPrimaryContextPass, box_select::draw_box)
            .add_observer(picking::on_click)
            .add_observer(picking::on_move)
            .add_observer(picking::on_out);
    }
}

/// Frames a mesh the first time it becomes the active one.
fn frame_new_meshes(world: &mut World, mut last: Local<Option<crate::mesh::MeshId>>) {
    let active = world.resource::<ActiveMesh>().0;
    if active != *last {
        *last = active;
        if active.is_some() {
            camera::frame_selection(world);
        }
    }
}
