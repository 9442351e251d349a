//! The Selection section: what a click selects, and the selection's own operations (all,
//! none, more, less, box).

use bevy_egui::egui;

use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::PanelSection;
use crate::editor::panels::state::PendingActions;
use crate::editor::panels::widgets::buttons;
use crate::editor::session::selection::SelectMode;

/// The Selection section.
pub const SECTION: PanelSection = PanelSection {
    title: "Selection",
    open_at_first: false,
    draw: |ui, cx| selection_controls(ui, cx.mode, cx.pending),
};

/// What a click selects, and the selection's own operations.
fn selection_controls(ui: &mut egui::Ui, mode: &mut SelectMode, pending: &mut PendingActions) {
    ui.horizontal(|ui| {
        ui.label("click selects");
        for m in [
            SelectMode::Auto,
            SelectMode::Vertex,
            SelectMode::Edge,
            SelectMode::Face,
            SelectMode::Halfedge,
        ] {
            ui.selectable_value(mode, m, m.name());
        }
    });
    buttons(
        ui,
        pending,
        &[
            (Action::SelectAll, "All"),
            (Action::SelectNone, "None"),
            (Action::Grow, "More"),
            (Action::Shrink, "Less"),
            (Action::BoxSelect, "Box"),
        ],
    );
    ui.label("Alt-click: an edge loop; Ctrl+Alt-click: an edge ring.");
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn the_click_modes_and_the_selection_buttons_with_their_keys() {
        let (text, _) = draw(&super::SECTION, &mut Resources::default());
        for shown in [
            "click selects",
            "All (A)",
            "None (Alt+A)",
            "More (Ctrl+=)",
            "Box (B)",
        ] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
    }
}
