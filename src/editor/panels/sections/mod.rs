//! The panel's sections (as Blender's N-panel and MeshLab's filter menu group them): File ·
//! Mesh · Selection · Element · Modelling · Local operations · Whole mesh · Shape · UV ·
//! Analysis · History · Log, in that order ([`SECTIONS`]).
//!
//! A section is a small value, [`PanelSection`]: a title, whether it is open the first time,
//! and a draw function over a [`PanelContext`], the copy of the world the panel shows
//! ([`InspectorView`](super::state::InspectorView)), the panel's own state, and the requests
//! and actions its clicks make.
//! A section reads and asks, as the whole panel does: it never touches a mesh. Each lives in
//! its own file; [`folding`] remembers which are open. A new section is a file and a line in
//! [`SECTIONS`].

pub mod analysis;
pub mod element;
pub mod file;
pub mod folding;
pub mod history;
pub mod log;
pub mod mesh;
pub mod operations;
pub mod selection;
pub mod shape;
pub mod uv;

pub use crate::editor::panels::state::{PanelContext, PanelSection};

/// The sections, in the panel's order.
pub const SECTIONS: [PanelSection; 12] = [
    file::SECTION,
    mesh::SECTION,
    selection::SECTION,
    element::SECTION,
    operations::MODELLING,
    operations::LOCAL,
    operations::WHOLE_MESH,
    shape::SECTION,
    uv::SECTION,
    analysis::SECTION,
    history::SECTION,
    log::SECTION,
];

#[cfg(test)]
pub(crate) mod testing {
    //! Drawing a section headless: egui without a window, its output's text read back.
    use super::*;
    use crate::editor::gestures::handle_deform::Anchors;
    use crate::editor::panels::state::{InspectorView, PendingActions, UiFields};
    use crate::editor::session::panel_state::UiState;
    use crate::editor::session::requests::{OutcomeLog, Request};
    use crate::editor::session::selection::SelectMode;
    use crate::editor::view::colouring::ColorBy;
    use crate::editor::view::readability::WireframeDensity;
    use crate::editor::view::render_sync::ViewSettings;
    use bevy_egui::egui;

    /// The panel's resources as the editor starts with them.
    #[derive(Default)]
    pub struct Resources {
        pub view: InspectorView,
        pub log: OutcomeLog,
        pub fields: UiFields,
        pub state: UiState,
        pub mode: SelectMode,
        pub settings: ViewSettings,
        pub density: WireframeDensity,
        pub colour_by: ColorBy,
        pub anchors: Anchors,
        pub pending: PendingActions,
    }

    /// Draws `section` over `resources` in a frame of a headless egui: every text it drew, a
    /// line each, and the requests it made.
    pub fn draw(section: &PanelSection, resources: &mut Resources) -> (String, Vec<Request>) {
        let ctx = egui::Context::default();
        let mut requests = Vec::new();
        let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
            let mut cx = PanelContext {
                view: &resources.view,
                log: &resources.log,
                fields: &mut resources.fields,
                state: &mut resources.state,
                mode: &mut resources.mode,
                settings: &mut resources.settings,
                density: &resources.density,
                colour_by: &mut resources.colour_by,
                anchors: &mut resources.anchors,
                pending: &mut resources.pending,
                requests: Vec::new(),
            };
            (section.draw)(ui, &mut cx);
            requests = cx.requests;
        });
        // No renderer takes the font atlas: its upload is dropped.
        output.textures_delta.clear();
        let mut text = String::new();
        for clipped in &output.shapes {
            collect_text(&clipped.shape, &mut text);
        }
        (text, requests)
    }

    fn collect_text(shape: &egui::Shape, text: &mut String) {
        match shape {
            egui::Shape::Text(t) => {
                text.push_str(t.galley.text());
                text.push('\n');
            }
            egui::Shape::Vec(shapes) => shapes.iter().for_each(|s| collect_text(s, text)),
            _ => {}
        }
    }

    #[test]
    fn every_section_is_listed_once_and_draws() {
        for (i, a) in SECTIONS.iter().enumerate() {
            assert!(
                SECTIONS[i + 1..].iter().all(|b| b.title != a.title),
                "{}",
                a.title
            );
            let (text, requests) = draw(a, &mut Resources::default());
            assert!(!text.is_empty(), "{} drew nothing", a.title);
            assert!(
                requests.is_empty(),
                "{} asked for {requests:?} unasked",
                a.title
            );
        }
    }
}
