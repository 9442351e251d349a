//! The Analysis section: the quantity the mesh is coloured by, its legend, and whether the
//! histograms show when it is coloured by nothing.

use bevy_egui::egui;

use crate::colormap::{ColorMap, Range};
use crate::editor::panels::state::InspectorView;
use crate::editor::panels::state::PanelSection;
use crate::editor::view::colouring::ColorBy;
use crate::ops::geometry::Quantity;

/// The Analysis section.
pub const SECTION: PanelSection = PanelSection {
    title: "Analysis",
    open_at_first: false,
    draw: |ui, cx| colour_section(ui, cx.view, cx.colour_by, &mut cx.state.histograms),
};

/// Colour by a quantity: the choice, and the legend (the map from its low to its high value, as
/// clamped).
fn colour_section(
    ui: &mut egui::Ui,
    view: &InspectorView,
    colour_by: &mut ColorBy,
    histograms: &mut bool,
) {
    ui.horizontal(|ui| {
        ui.label("colour by");
        let shown = colour_by.0.map_or("nothing", Quantity::label);
        egui::ComboBox::from_id_salt("colour by")
            .selected_text(shown)
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut colour_by.0, None, "nothing");
                for &q in crate::ops::registry::quantities().iter() {
                    ui.selectable_value(&mut colour_by.0, Some(q), q.label());
                }
            });
        ui.checkbox(histograms, "histograms");
    });
    if let Some((label, map, range)) = &view.colour {
        legend(ui, label, *map, *range);
    }
}

/// The colour map as a bar from its low to its high value, with both ends labelled.
fn legend(ui: &mut egui::Ui, label: &str, map: ColorMap, range: Range) {
    ui.label(egui::RichText::new(label).small());
    let width = ui.available_width().min(260.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 14.0), egui::Sense::hover());
    let steps = 64;
    for i in 0..steps {
        let [r, g, b] = map.at((i as f32 + 0.5) / steps as f32);
        let x0 = rect.left() + rect.width() * i as f32 / steps as f32;
        let x1 = rect.left() + rect.width() * (i + 1) as f32 / steps as f32;
        let cell =
            egui::Rect::from_min_max(egui::pos2(x0, rect.top()), egui::pos2(x1, rect.bottom()));
        ui.painter()
            .rect_filled(cell, 0.0, egui::Color32::from_rgb(r, g, b));
    }
    ui.horizontal(|ui| {
        ui.monospace(format!("{:.4}", range.low));
        ui.add_space((width - 160.0).max(0.0));
        ui.monospace(format!("{:.4}", range.high));
    });
    ui.label(
        egui::RichText::new("clamped at the 1st and 99th percentiles")
            .small()
            .weak(),
    );
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};
    use crate::colormap::{ColorMap, Range};

    #[test]
    fn the_quantity_chosen_and_its_legend_with_both_ends() {
        let mut r = Resources::default();
        let (text, _) = draw(&super::SECTION, &mut r);
        assert!(
            text.contains("colour by") && text.contains("nothing"),
            "{text}"
        );
        assert!(!text.contains("clamped at"), "no legend without a quantity");
        let range = Range {
            low: -0.25,
            high: 1.5,
        };
        r.view.colour = Some(("mean curvature".into(), ColorMap::Diverging, range));
        let (text, _) = draw(&super::SECTION, &mut r);
        for shown in [
            "mean curvature",
            "-0.2500",
            "1.5000",
            "clamped at the 1st and 99th",
        ] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
    }
}
