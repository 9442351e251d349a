//! The three sections of operations drawn from the registered operations' declarations
//! ([`crate::ops::declaration::Section`] says whose each is): Modelling (Blender's edit-mode
//! operations on the selection), Local operations (the halfedge mesh's, on the selected
//! element) and Whole mesh (with step mode and, after a simplification, the level-of-detail
//! slider).

use bevy_egui::egui;

use crate::edit::Edit;
use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::PendingActions;
use crate::editor::panels::state::{PanelContext, PanelSection};
use crate::editor::panels::widgets::{buttons, registered_operations};
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::Request;
use crate::ops::declaration::Section;

/// The Modelling section.
pub const MODELLING: PanelSection = PanelSection {
    title: "Modelling",
    open_at_first: true,
    draw: |ui, cx| modelling_section(ui, cx.state, cx.pending),
};

/// The Local operations section.
pub const LOCAL: PanelSection = PanelSection {
    title: "Local operations",
    open_at_first: false,
    draw: |ui, cx| local_section(ui, cx.state, cx.pending),
};

/// The Whole mesh section.
pub const WHOLE_MESH: PanelSection = PanelSection {
    title: "Whole mesh",
    open_at_first: false,
    draw: whole_mesh_section,
};

/// The registered whole-mesh operations and step mode (see [`registered_operations`]), and the
/// level of detail of a simplified mesh.
fn whole_mesh_section(ui: &mut egui::Ui, cx: &mut PanelContext) {
    registered_operations(ui, cx.state, cx.pending, Section::WholeMesh);
    if let Some(lod) = cx.view.lod {
        level_of_detail(ui, lod, &mut cx.requests);
    }
}

/// Blender's edit-mode operations on the selection.
fn modelling_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    buttons(
        ui,
        pending,
        &[
            (Action::Grab, "Move"),
            (Action::Rotate, "Rotate"),
            (Action::Scale, "Scale"),
            (Action::DeleteMesh, "Delete mesh"),
        ],
    );
    registered_operations(ui, state, pending, Section::Modelling);
}

/// The local operations of the halfedge mesh on the selected element: the registered ones
/// that declare this section, then the editor's own.
fn local_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    registered_operations(ui, state, pending, Section::Local);
    buttons(ui, pending, &[(Action::Frame, "Frame")]);
}

/// The level-of-detail slider of a simplified mesh (its coarsest, current and full face
/// counts): a drag moves along the simplification history.
fn level_of_detail(
    ui: &mut egui::Ui,
    (coarsest, now, full): (usize, usize, usize),
    requests: &mut Vec<Request>,
) {
    let mut faces = now;
    let slider = egui::Slider::new(&mut faces, coarsest..=full).text("faces (level of detail)");
    if ui.add(slider).changed() && faces != now {
        let refine = crate::ops::decimate::Refine::to(Some(faces));
        requests.push(Request::Edit(Edit::Operation(refine)));
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn each_section_draws_its_declared_operations_with_their_keys() {
        let mut r = Resources::default();
        let (modelling, _) = draw(&super::MODELLING, &mut r);
        assert!(modelling.contains("Move (G)"), "{modelling}");
        let (whole, _) = draw(&super::WHOLE_MESH, &mut r);
        assert!(whole.contains("Step mode (F9)"), "{whole}");
        let (local, _) = draw(&super::LOCAL, &mut r);
        assert!(local.contains("Frame (.)"), "{local}");
        for (section, text) in [
            (crate::ops::declaration::Section::Modelling, &modelling),
            (crate::ops::declaration::Section::WholeMesh, &whole),
            (crate::ops::declaration::Section::Local, &local),
        ] {
            for op in crate::ops::registry::operations() {
                let d = op.declaration();
                if d.section == section {
                    assert!(text.contains(d.title), "{} not in {text}", d.title);
                }
            }
        }
        assert!(!whole.contains("level of detail"));
        r.view.lod = Some((100, 150, 200));
        let (whole, _) = draw(&super::WHOLE_MESH, &mut r);
        assert!(whole.contains("faces (level of detail)"), "{whole}");
    }
}
