//! The UV section: parameterization (its method and boundary, declared) and the UV layout
//! window.

use bevy_egui::egui;

use crate::editor::panels::state::PanelSection;
use crate::editor::panels::state::PendingActions;
use crate::editor::panels::widgets::registered_operations;
use crate::editor::session::panel_state::UiState;
use crate::ops::declaration::Section;

/// The UV section.
pub const SECTION: PanelSection = PanelSection {
    title: "UV",
    open_at_first: false,
    draw: |ui, cx| uv_section(ui, cx.state, cx.pending),
};

/// Parameterization (its method and boundary, declared), seams, the UV view.
fn uv_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    registered_operations(ui, state, pending, Section::Uv);
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut state.uv_view, "UV view");
    });
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn parameterization_and_the_uv_window_toggle() {
        let (text, _) = draw(&super::SECTION, &mut Resources::default());
        assert!(
            text.contains("UV view") && text.contains("Parameterize"),
            "{text}"
        );
    }
}
