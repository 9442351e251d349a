//! The Log section: the last 30 outcomes, the newest first, each the request and what came of
//! it.

use bevy_egui::egui;

use crate::editor::panels::state::{PanelContext, PanelSection};

/// The Log section.
pub const SECTION: PanelSection = PanelSection {
    title: "Log",
    open_at_first: false,
    draw,
};

fn draw(ui: &mut egui::Ui, cx: &mut PanelContext) {
    if cx.log.entries.is_empty() {
        ui.label(egui::RichText::new("nothing done yet").small().weak());
    }
    for entry in cx.log.entries.iter().rev().take(30) {
        let text = match &entry.result {
            Ok(s) => format!("✔ {}: {s}", entry.request),
            Err(r) => format!("x {}: {r}", entry.request),
        };
        ui.label(egui::RichText::new(text).small());
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Resources, draw};
    use crate::editor::session::requests::EditOutcome;

    #[test]
    fn the_outcomes_newest_first() {
        let mut r = Resources::default();
        for request in ["flip", "split"] {
            r.log.push(EditOutcome {
                request: request.into(),
                result: Ok(format!("{request} done")),
            });
        }
        let (text, _) = draw(&super::SECTION, &mut r);
        let split = text.find("✔ split: split done").expect(&text);
        let flip = text.find("✔ flip: flip done").expect(&text);
        assert!(split < flip, "{text}");
    }
}
