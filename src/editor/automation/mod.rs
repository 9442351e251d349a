//! The automation room: the editor driven without a person. Scripts of keys, clicks and
//! screenshots (`PAPPUS_SCRIPT`, [`script`]), the frame pacing that lets an idle window sleep
//! ([`pacing`]), the frame-time breakdown a script logs ([`frame_stats`]) and a Python
//! script's mesh shown and handed back (`pappus.show`, [`show`]). The top room: it
//! reads the others, none reads it.

pub mod frame_stats;
pub mod pacing;
pub mod script;
pub mod show;

use bevy::prelude::*;

use crate::editor::input::keyboard::keyboard_shortcuts;
use crate::editor::session::schedule::EditorSystems;

/// Scripts (run before the shortcuts, as keys typed that frame) and frame pacing.
pub struct AutomationWindowPlugin;

impl Plugin for AutomationWindowPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<script::PendingShots>()
            .insert_resource(pacing::settings(None))
            .add_systems(
                Update,
                (
                    script::run_script
                        .in_set(EditorSystems::Input)
                        .before(keyboard_shortcuts),
                    pacing::keep_drawing.in_set(EditorSystems::Ui),
                ),
            )
            .add_systems(
                PreUpdate,
                pacing::drop_unchanged_modifiers
                    .after(bevy_egui::EguiPreUpdateSet::ProcessInput)
                    .before(bevy_egui::EguiPreUpdateSet::BeginPass),
            );
    }
}
