//! The Element section, the inspector: the selected element's id (`v12v0`, `h7v0`, …), each
//! relation a link that selects where it leads (with the key that walks it), its facts, a
//! vertex's position to drag, and a field that selects any element by id.

use bevy_egui::egui;

use crate::edit::Edit;
use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::PanelSection;
use crate::editor::panels::state::{InspectorView, UiFields};
use crate::editor::session::requests::{Relation, Request};
use crate::mesh::ids::{ElementId, parse_element};

/// The Element section.
pub const SECTION: PanelSection = PanelSection {
    title: "Element",
    open_at_first: true,
    draw: |ui, cx| selection_section(ui, cx.view, cx.fields, &mut cx.requests),
};

fn selection_section(
    ui: &mut egui::Ui,
    view: &InspectorView,
    fields: &mut UiFields,
    requests: &mut Vec<Request>,
) {
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(&mut fields.jump)
                .hint_text("go to id: v12v0, h7, e3, f5")
                .desired_width(170.0),
        );
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Go").clicked() || entered {
            match parse_element(&fields.jump) {
                Some(id) => {
                    requests.push(Request::Select(Some(id)));
                }
                None => {
                    fields.jump = format!("not an id: {}", fields.jump);
                }
            }
        }
    });
    if !view.selected_set.is_empty() {
        ui.label(egui::RichText::new(&view.selected_set).strong());
    }
    let Some(sel) = &view.selected else {
        ui.label(
            "Nothing selected: click the mesh (Shift-click adds, B draws a box, A selects all).",
        );
        return;
    };
    let kind = sel.id.kind();
    ui.label(
        egui::RichText::new(format!("{kind} {}", sel.id))
            .strong()
            .monospace(),
    );
    egui::Grid::new("relations").num_columns(2).show(ui, |ui| {
        for (relation, target) in &sel.relations {
            // E and F go to a halfedge's edge and face (the keys extrude and fill otherwise).
            let key = crate::editor::input::shortcuts::keys_of(Action::Navigate(*relation)).or(
                match (sel.id, relation) {
                    (ElementId::Halfedge(_), Relation::Edge) => Some("E"),
                    (ElementId::Halfedge(_), Relation::Face) => Some("F"),
                    _ => None,
                },
            );
            ui.label(match key {
                Some(key) => format!("{} ({key})", relation.name()),
                None => relation.name().to_string(),
            });
            match target {
                Some(t) => {
                    if ui
                        .link(egui::RichText::new(t.to_string()).monospace())
                        .clicked()
                    {
                        requests.push(Request::Select(Some(*t)));
                    }
                }
                None => {
                    ui.label("— (boundary)");
                }
            }
            ui.end_row();
        }
        for (k, v) in &sel.facts {
            ui.label(k);
            ui.monospace(v);
            ui.end_row();
        }
    });
    if let (Some(p), ElementId::Vertex(v)) = (sel.position, sel.id) {
        let mut q = p;
        ui.horizontal(|ui| {
            ui.label("position");
            let speed = 0.002;
            let changed = ui
                .add(egui::DragValue::new(&mut q.x).speed(speed).prefix("x "))
                .changed()
                | ui.add(egui::DragValue::new(&mut q.y).speed(speed).prefix("y "))
                    .changed()
                | ui.add(egui::DragValue::new(&mut q.z).speed(speed).prefix("z "))
                    .changed();
            if changed && q != p {
                requests.push(Request::Edit(Edit::Move(vec![(v, q)])));
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};
    use crate::editor::panels::state::SelectedView;
    use crate::editor::session::requests::Relation;
    use crate::mesh::ids::parse_element;

    #[test]
    fn the_selected_element_its_relations_as_links_and_its_facts() {
        let mut r = Resources::default();
        let (text, _) = draw(&super::SECTION, &mut r);
        assert!(text.contains("Nothing selected: click the mesh"), "{text}");
        let halfedge = parse_element("h7v0").unwrap();
        r.view.selected = Some(SelectedView {
            id: halfedge,
            relations: vec![
                (Relation::Twin, parse_element("h8v0")),
                (Relation::Face, None),
            ],
            position: None,
            facts: vec![("boundary".into(), "yes".into())],
        });
        let (text, _) = draw(&super::SECTION, &mut r);
        for shown in ["halfedge h7v0", "h8v0", "— (boundary)", "boundary", "yes"] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
        // The face of a halfedge is walked with F (the key fills a hole otherwise).
        assert!(text.contains("(F)"), "{text}");
    }
}
