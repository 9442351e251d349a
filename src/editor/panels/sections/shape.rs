//! The Shape section: fairing and faired hole filling (declared), proportional editing's
//! falloff and radius, and handle deformation's anchors and method.

use bevy_egui::egui;

use crate::editor::gestures::handle_deform::Anchors;
use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::PanelSection;
use crate::editor::panels::state::PendingActions;
use crate::editor::panels::widgets::{button, registered_operations, shortcut_label};
use crate::editor::session::panel_state::UiState;
use crate::ops::declaration::Section;
use crate::ops::deform::{DeformMethod, Falloff};
use crate::ops::named::Named;

/// The Shape section.
pub const SECTION: PanelSection = PanelSection {
    title: "Shape",
    open_at_first: false,
    draw: |ui, cx| shape_section(ui, cx.state, cx.anchors, cx.pending),
};

/// Shaping the surface: fairing, holes filled fair, proportional editing, handle deformation.
fn shape_section(
    ui: &mut egui::Ui,
    state: &mut UiState,
    anchors: &mut Anchors,
    pending: &mut PendingActions,
) {
    registered_operations(ui, state, pending, Section::Shape);
    button(ui, pending, Action::FillFair, "Fill hole fair");
    ui.horizontal_wrapped(|ui| {
        let p = &mut state.proportional;
        ui.checkbox(
            &mut p.enabled,
            format!(
                "proportional ({})",
                shortcut_label(Action::ToggleProportional)
            ),
        );
        egui::ComboBox::from_id_salt("falloff")
            .selected_text(p.falloff.name())
            .show_ui(ui, |ui| {
                for &(falloff, name) in Falloff::ALL {
                    ui.selectable_value(&mut p.falloff, falloff, name);
                }
            });
        ui.add(
            egui::DragValue::new(&mut p.radius)
                .range(1e-6..=f32::MAX)
                .speed(0.001)
                .prefix("r "),
        );
        ui.checkbox(&mut p.connected, "connected");
    });
    // Handle deformation: the anchors, and how the rest follows a transform of the handle.
    ui.horizontal_wrapped(|ui| {
        button(ui, pending, Action::MarkAnchors, "Anchors");
        ui.label(format!("{} anchored", anchors.vertices.len()));
        egui::ComboBox::from_id_salt("deform method")
            .selected_text(anchors.method.name())
            .show_ui(ui, |ui| {
                for &(method, name) in DeformMethod::ALL {
                    ui.selectable_value(&mut anchors.method, method, name);
                }
            });
        if ui.button("Clear anchors").clicked() {
            anchors.vertices.clear();
            anchors.progress = None;
        }
    });
    if let Some(progress) = anchors.progress {
        ui.label(format!("last deformation: {progress}"));
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn fairing_proportional_editing_and_the_anchors() {
        let (text, _) = draw(&super::SECTION, &mut Resources::default());
        for shown in [
            "Fill hole fair (Alt+F)",
            "proportional (Alt+O)",
            "Anchors (Shift+A)",
        ] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
        assert!(
            text.contains("0 anchored") && text.contains("Clear anchors"),
            "{text}"
        );
    }
}
