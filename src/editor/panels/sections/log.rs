//! The Log section: the last 30 outcomes, the newest first, each the request and what came of
//! it; then the log's messages (as the editor's log layer keeps them), the newest first, at or
//! above the level its switch is set to — info by default, trace to read what a lab's
//! operations say they touched — but for the editor's own, which repeat the outcomes.

use bevy::log::Level;
use bevy_egui::egui;

use crate::editor::session::log_capture::LogMessage;

use crate::editor::panels::state::{PanelContext, PanelSection};

/// The Log section.
pub const SECTION: PanelSection = PanelSection {
    title: "Log",
    open_at_first: false,
    draw,
};

/// The levels the switch offers, the least verbose first.
const LEVELS: [(Level, &str); 3] = [
    (Level::INFO, "info"),
    (Level::DEBUG, "debug"),
    (Level::TRACE, "trace"),
];

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
    ui.separator();
    ui.horizontal(|ui| {
        ui.label("Messages down to");
        for (level, name) in LEVELS {
            ui.selectable_value(&mut cx.state.log_level, level, name);
        }
    });
    // The editor's own messages repeat the outcomes above (and time its redraws).
    let elsewhere = |m: &LogMessage| !m.target.starts_with("pappus::editor");
    for m in cx.log.messages.newest(cx.state.log_level, 30, elsewhere) {
        let module = m.target.rsplit("::").next().unwrap_or_default();
        let text = format!("{} {module}: {}", m.level, m.text);
        ui.add(egui::Label::new(egui::RichText::new(text).small()).wrap());
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

    /// The messages show down to the switch's level: a lab's trace lines only at trace.
    #[test]
    fn the_messages_down_to_the_level_switched_to() {
        use crate::editor::session::log_capture::LogMessage;
        use bevy::log::Level;
        let mut r = Resources::default();
        for (level, text) in [
            (Level::INFO, "opened spot.obj"),
            (Level::TRACE, "lab flip e7v0"),
        ] {
            let target = if level == Level::TRACE {
                "lab"
            } else {
                "pappus::io::obj"
            };
            r.log.messages.push(LogMessage {
                level,
                target: target.into(),
                text: text.into(),
            });
        }
        r.log.messages.push(LogMessage {
            level: Level::INFO,
            target: "pappus::editor::session::finish".into(),
            text: "an outcome, listed above".into(),
        });
        let (text, _) = draw(&super::SECTION, &mut r);
        assert!(text.contains("INFO obj: opened spot.obj"), "{text}");
        assert!(!text.contains("listed above"), "{text}");
        assert!(!text.contains("lab flip"), "{text}");
        r.state.log_level = Level::TRACE;
        let (text, _) = draw(&super::SECTION, &mut r);
        let lab = text.find("TRACE lab: lab flip e7v0").expect(&text);
        assert!(
            lab < text.find("opened spot.obj").expect(&text),
            "newest first: {text}"
        );
    }
}
