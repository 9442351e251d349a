//! The History section: undo and redo, the memory the history holds, and its entries.

use bevy_egui::egui;

use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::PanelSection;
use crate::editor::panels::state::{InspectorView, PendingActions};
use crate::editor::panels::widgets::shortcut_label;

/// The History section.
pub const SECTION: PanelSection = PanelSection {
    title: "History",
    open_at_first: false,
    draw: |ui, cx| history_section(ui, cx.view, cx.pending),
};

/// Undo / redo buttons and the list of entries, the newest first; undone ones are greyed.
fn history_section(ui: &mut egui::Ui, view: &InspectorView, pending: &mut PendingActions) {
    let done = view.history.iter().filter(|(_, undone)| !undone).count();
    ui.horizontal(|ui| {
        let undo = format!("Undo ({})", shortcut_label(Action::Undo));
        if ui.add_enabled(done > 0, egui::Button::new(undo)).clicked() {
            pending.0.push(Action::Undo);
        }
        let redo = format!("Redo ({})", shortcut_label(Action::Redo));
        let can_redo = done < view.history.len();
        if ui.add_enabled(can_redo, egui::Button::new(redo)).clicked() {
            pending.0.push(Action::Redo);
        }
    });
    let bytes = view.history_bytes as f64;
    let held = if bytes < 1e6 {
        format!("{:.1} kB", bytes / 1e3)
    } else {
        format!("{:.1} MB", bytes / 1e6)
    };
    ui.label(egui::RichText::new(format!("{} step(s), {held}", view.history.len())).small());
    for (label, undone) in view.history.iter().rev().take(12) {
        let text = egui::RichText::new(label).small();
        ui.label(if *undone { text.weak().italics() } else { text });
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn undo_redo_the_memory_held_and_the_entries() {
        let mut r = Resources::default();
        let (text, _) = draw(&super::SECTION, &mut r);
        assert!(
            text.contains("Undo (Ctrl+Z)") && text.contains("0 step(s), 0.0 kB"),
            "{text}"
        );
        r.view.history = vec![("flip e3v0".into(), false), ("split e9v0".into(), true)];
        r.view.history_bytes = 2_500_000;
        let (text, _) = draw(&super::SECTION, &mut r);
        for shown in ["flip e3v0", "split e9v0", "2 step(s), 2.5 MB"] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
    }
}
