//! The File section: the path field (a file or `shape:NAME`; Enter opens, or saves where
//! Ctrl+Shift+S focused it), Open, Save, Save as.

use bevy_egui::egui;

use crate::editor::panels::state::PanelSection;
use std::path::PathBuf;

use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::UiFields;
use crate::editor::panels::widgets::shortcut_label;
use crate::editor::session::dialog::PathPurpose;
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::Request;

/// The File section.
pub const SECTION: PanelSection = PanelSection {
    title: "File",
    open_at_first: true,
    draw: |ui, cx| file_section(ui, cx.fields, cx.state, &mut cx.requests),
};

fn file_section(
    ui: &mut egui::Ui,
    fields: &mut UiFields,
    ui_state: &mut UiState,
    requests: &mut Vec<Request>,
) {
    // Ctrl+O / Ctrl+Shift+S focus the field; Enter then opens or saves, as the key asked.
    if let Some(purpose) = ui_state.focus_path.take() {
        fields.enter_means = purpose;
        fields.focus = true;
    }
    let path = PathBuf::from(fields.path.trim());
    let has_path = !fields.path.trim().is_empty();
    ui.horizontal(|ui| {
        let hint = match fields.enter_means {
            PathPurpose::Open => "file path or shape:NAME, Enter opens",
            PathPurpose::SaveAs => "file path, Enter saves",
        };
        let field = ui.add(
            egui::TextEdit::singleline(&mut fields.path)
                .hint_text(hint)
                .desired_width(170.0),
        );
        if std::mem::take(&mut fields.focus) {
            field.request_focus();
        }
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if entered && has_path {
            requests.push(match fields.enter_means {
                PathPurpose::Open => Request::Open(path.clone()),
                PathPurpose::SaveAs => Request::Save(Some(path.clone())),
            });
            fields.enter_means = PathPurpose::Open;
        }
        if ui.button("Open").clicked() && has_path {
            requests.push(Request::Open(path.clone()));
        }
    });
    ui.horizontal(|ui| {
        if ui
            .button(format!("Save ({})", shortcut_label(Action::Save)))
            .clicked()
        {
            requests.push(Request::Save(None));
        }
        let save_as = format!("Save as ({})", shortcut_label(Action::SaveAs));
        if ui.button(save_as).clicked() && has_path {
            requests.push(Request::Save(Some(path.clone())));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};
    use crate::editor::session::dialog::PathPurpose;

    #[test]
    fn the_path_field_opens_by_default_and_saves_when_save_as_focused_it() {
        let mut r = Resources::default();
        let (text, _) = draw(&super::SECTION, &mut r);
        for shown in [
            "file path or shape:NAME, Enter opens",
            "Open",
            "Save (Ctrl+S)",
        ] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
        assert!(text.contains("Save as (Ctrl+Shift+S)"), "{text}");
        r.state.focus_path = Some(PathPurpose::SaveAs);
        let (text, _) = draw(&super::SECTION, &mut r);
        assert!(text.contains("file path, Enter saves"), "{text}");
        assert_eq!(r.fields.enter_means, PathPurpose::SaveAs);
        assert!(r.state.focus_path.is_none(), "the focus is taken once");
    }
}
