//! The Mesh section: the active mesh's name, path and statistics (counted off the frame,
//! [`crate::editor::panels::mesh_figures`]), its validity, how it is drawn, and the memory
//! budget.

use bevy_egui::egui;

use crate::editor::input::shortcuts::Action;
use crate::editor::panels::state::{InspectorView, PendingActions};
use crate::editor::panels::state::{PanelContext, PanelSection};
use crate::editor::panels::widgets::shortcut_label;
use crate::editor::view::readability::WireframeDensity;
use crate::editor::view::render_sync::ViewSettings;

/// The Mesh section.
pub const SECTION: PanelSection = PanelSection {
    title: "Mesh",
    open_at_first: true,
    draw,
};

fn draw(ui: &mut egui::Ui, cx: &mut PanelContext) {
    mesh_section(ui, cx.view, &mut cx.state.check_validity);
    view_toggles(ui, (cx.settings, cx.density), cx.pending);
    budget_row(ui);
}

fn mesh_section(ui: &mut egui::Ui, view: &InspectorView, check_validity: &mut bool) {
    let Some(mesh) = &view.mesh else {
        ui.label("No mesh. Open a file or drop one on the window.");
        return;
    };
    ui.label(egui::RichText::new(&mesh.name).strong());
    if let Some(p) = &mesh.path {
        ui.label(egui::RichText::new(p.display().to_string()).small());
    }
    let Some(s) = &mesh.stats else {
        ui.label("counting …");
        return;
    };
    if mesh.counting {
        ui.label(egui::RichText::new("counting the changed mesh …").small());
    }
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        let sizes: Vec<String> = s
            .face_sizes
            .iter()
            .map(|(k, n)| format!("{k}: {n}"))
            .collect();
        for (k, v) in [
            (
                "V / E / F",
                format!("{} / {} / {}", s.vertices, s.edges, s.faces),
            ),
            ("halfedges", s.halfedges.to_string()),
            (
                "Euler char. / genus",
                format!("{} / {}", s.euler_characteristic, s.genus),
            ),
            ("components", s.components.to_string()),
            ("boundary loops", s.boundary_loops.to_string()),
            ("face sizes", sizes.join(", ")),
            ("min angle", format!("{:.2}°", s.min_angle_deg)),
            (
                "angles < 30°",
                format!("{:.2} % of triangles", s.pct_min_angle_below_30),
            ),
        ] {
            ui.label(k);
            ui.label(v);
            ui.end_row();
        }
    });
    match &mesh.validation {
        Some(Ok(())) => ui.colored_label(egui::Color32::from_rgb(120, 200, 120), "valid"),
        Some(Err(e)) => ui.colored_label(
            egui::Color32::from_rgb(230, 120, 90),
            format!("INVALID: {e}"),
        ),
        None => {
            let check = ui
                .button("check validity")
                .on_hover_text("a large mesh is checked when asked: a few seconds of waiting");
            *check_validity |= check.clicked();
            check
        }
    };
}

/// How the mesh is drawn: shading, wireframe, halfedge arrows, the UV checkerboard.
fn view_toggles(
    ui: &mut egui::Ui,
    (settings, density): (&mut ViewSettings, &WireframeDensity),
    pending: &mut PendingActions,
) {
    ui.horizontal_wrapped(|ui| {
        for (action, name, on) in [
            (Action::ToggleSmooth, "smooth", settings.smooth),
            (Action::ToggleWireframe, "wireframe", settings.wireframe),
            (Action::ToggleHalfedges, "halfedges", settings.halfedges),
            (Action::ToggleChecker, "checker", settings.checker),
        ] {
            if ui
                .selectable_label(on, format!("{name} ({})", shortcut_label(action)))
                .clicked()
            {
                pending.0.push(action);
            }
        }
    });
    if density.hidden || settings.dense_wireframe {
        ui.horizontal_wrapped(|ui| {
            if let Some(px) = density.edge_px.filter(|_| density.hidden) {
                ui.label(format!(
                    "wireframe hidden: edges {px:.1} px apart, zoom in or"
                ));
            }
            ui.checkbox(&mut settings.dense_wireframe, "draw dense wireframe");
        });
    }
}

/// The memory budget ([`crate::memory_budget`]): 75 % of the available memory, or a fixed
/// number of gigabytes. An operation whose result would pass it is refused with its estimate.
fn budget_row(ui: &mut egui::Ui) {
    use crate::memory_budget::{self, Budget};
    const GB: f64 = 1e9;
    let budget = memory_budget::get();
    let (limit, _) = budget.limit();
    ui.horizontal(|ui| {
        ui.label("memory budget").on_hover_text(
            "Operations whose result would need more (subdivision levels, a remeshing length, \
             shape sizes) are refused with their estimate instead of running out of memory.",
        );
        let mut share = matches!(budget, Budget::Share(_));
        if ui.checkbox(&mut share, "75 % of free").changed() {
            memory_budget::set(if share {
                Budget::default()
            } else {
                Budget::Bytes(limit.min(1 << 50))
            });
        }
        match budget {
            Budget::Bytes(bytes) => {
                let mut gb = bytes as f64 / GB;
                let field = egui::DragValue::new(&mut gb)
                    .range(0.1..=1e4)
                    .speed(0.1)
                    .suffix(" GB");
                if ui.add(field).changed() {
                    memory_budget::set(Budget::Bytes((gb * GB) as u64));
                }
            }
            Budget::Share(_) => {
                ui.weak(memory_budget::size(limit));
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};

    #[test]
    fn without_a_mesh_it_says_how_to_get_one_and_shows_the_view_and_the_budget() {
        let mut r = Resources::default();
        let (text, _) = draw(&super::SECTION, &mut r);
        for shown in [
            "No mesh. Open a file or drop one on the window.",
            "smooth (Z)",
            "wireframe (W)",
            "halfedges (Shift+W)",
            "checker (Shift+C)",
            "memory budget",
            "75 % of free",
        ] {
            assert!(text.contains(shown), "{shown} not in {text}");
        }
    }
}
