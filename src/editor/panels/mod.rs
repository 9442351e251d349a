//! The panels room: the egui side panel ([`ui`]) in sections, one file each ([`sections`],
//! sharing the rows of [`widgets`], drawing what [`state`] holds), its
//! figures of the mesh counted off the frame ([`mesh_figures`]) and drawn as histograms
//! ([`plots`]), the UV layout window ([`uv_view`]), and the step mode's window and overlays
//! ([`step_view`]). It reads every room but automation.

pub mod mesh_figures;
pub mod plots;
pub mod sections;
pub mod state;
pub mod step_view;
pub mod ui;
pub mod uv_view;
pub mod widgets;

use bevy::prelude::*;

use crate::editor::gestures::overlay::gather_overlay;
use crate::editor::pipeline::recovery;
use crate::editor::session::schedule::EditorSystems;

/// What the panels gather each frame without a window: the step view (its shapes and the
/// window's contents) and the UV layout (the headless tests read them).
pub struct PanelsPlugin;

impl Plugin for PanelsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<mesh_figures::Counting>()
            .init_resource::<uv_view::UvLayout>()
            .init_resource::<step_view::StepView>()
            .add_systems(
                Update,
                ((step_view::gather_step_view, uv_view::refresh_uv_layout)
                    .chain()
                    .after(gather_overlay)
                    .in_set(EditorSystems::Sync),),
            );
    }
}

/// The egui panels and windows.
pub struct PanelsWindowPlugin;

impl Plugin for PanelsWindowPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(ui::UiPlugin).add_systems(
            bevy_egui::EguiPrimaryContextPass,
            (step_view::step_window, recovery::offer_window).after(ui::panels),
        );
    }
}
