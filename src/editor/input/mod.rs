//! The input room: the keymap ([`shortcuts`]), the keyboard's system ([`keyboard`]) and files
//! dropped on the window ([`dropped_files`]), each turned into requests. It reads the rooms below it
//! (session, pipeline, view, gestures); the panels and the automation read it.

pub mod add_operation;
pub mod dropped_files;
pub mod key_names;
pub mod keyboard;
pub mod shortcuts;

use bevy::prelude::*;

use crate::editor::gestures::box_select::drive_box_select;
use crate::editor::gestures::drag::drive_vertex_drag;
use crate::editor::gestures::transform::drive_gesture;
use crate::editor::session::schedule::EditorSystems;

/// The shortcuts, after the gestures that may take the keys first, and dropped files.
pub struct ShortcutsPlugin;

impl Plugin for ShortcutsPlugin {
    fn build(&self, app: &mut App) {
        // The window plugin adds the drop message too; headless, a test writes it.
        app.add_message::<bevy::window::FileDragAndDrop>()
            .init_resource::<crate::editor::session::panel_state::UiState>()
            .add_systems(
                Update,
                (
                    keyboard::keyboard_shortcuts
                        .after(drive_gesture)
                        .after(drive_box_select)
                        .after(drive_vertex_drag),
                    dropped_files::open_dropped_files,
                )
                    .in_set(EditorSystems::Input),
            );
    }
}
