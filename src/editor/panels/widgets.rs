//! The rows the panel's sections share: a button that runs an action with its keys beside its
//! name, a row of them, and the registered operations of a section drawn from their
//! declarations, each parameter a field of its kind and range.

use bevy_egui::egui;

use super::state::PendingActions;
use crate::edit::Invocation;
use crate::editor::input::shortcuts::Action;
use crate::editor::session::panel_state::UiState;
use crate::ops::declaration::{Declaration, Parameter, ParameterKind, Section};

/// The keys of `action` as a label shows them, or nothing.
pub fn shortcut_label(action: Action) -> &'static str {
    crate::editor::input::shortcuts::keys_of(action).unwrap_or("")
}

/// A button that runs `action`, its keys beside its name.
pub fn button(
    ui: &mut egui::Ui,
    pending: &mut PendingActions,
    action: Action,
    name: &str,
) -> egui::Response {
    let text = match shortcut_label(action) {
        "" => name.to_string(),
        keys => format!("{name} ({keys})"),
    };
    let response = ui.button(text);
    if response.clicked() {
        pending.0.push(action);
    }
    response
}

/// A row of [`button`]s.
pub fn buttons(ui: &mut egui::Ui, pending: &mut PendingActions, row: &[(Action, &str)]) {
    ui.horizontal_wrapped(|ui| {
        for &(action, name) in row {
            button(ui, pending, action, name);
        }
    });
}

/// The registered operations ([`crate::ops::registry`]) that declare `section` as theirs,
/// drawn from their declarations: a button each (its help line on hover), after the fields of
/// its parameters, whose values the button and the key use. Those without parameters share
/// one row.
pub fn registered_operations(
    ui: &mut egui::Ui,
    state: &mut UiState,
    pending: &mut PendingActions,
    section: Section,
) {
    state.take_up_registered();
    let here = |d: &Declaration| d.section == section;
    // One button for the operations that share a name (collapse an edge or a face): the
    // selection decides which runs.
    let mut plain: Vec<&Declaration> = state
        .operations
        .iter()
        .map(Invocation::declaration)
        .filter(|&d| here(d) && d.parameters.is_empty())
        .collect();
    plain.dedup_by_key(|d| d.name);
    let step_mode = section == Section::WholeMesh;
    if !plain.is_empty() || step_mode {
        ui.horizontal_wrapped(|ui| {
            for d in plain {
                button(ui, pending, Action::Operation(d.name), d.title).on_hover_text(d.help);
            }
            if step_mode {
                button(ui, pending, Action::ToggleStepMode, "Step mode");
            }
        });
    }
    for invocation in &mut state.operations {
        let d = invocation.declaration();
        if !here(d) || d.parameters.is_empty() {
            continue;
        }
        ui.horizontal_wrapped(|ui| {
            for (i, p) in d.parameters.iter().enumerate() {
                let x = invocation.values().given(i);
                if let Some(x) = parameter_field(ui, d.name, p, x) {
                    // The field offers only values the parameter takes.
                    let _ = invocation.set(i, x);
                }
            }
            button(ui, pending, Action::Operation(d.name), d.title).on_hover_text(d.help);
        });
    }
}

/// The field of one parameter of operation `operation`, showing `x`: a drop-down of a
/// choice's words, a number field in the parameter's range, and an "auto" box before it where
/// the parameter may be left to the operation. The new value when the user changed it.
pub fn parameter_field(
    ui: &mut egui::Ui,
    operation: &str,
    p: &Parameter,
    x: Option<f64>,
) -> Option<Option<f64>> {
    let label = p.name.to_lowercase();
    let (min, max, whole) = match p.kind {
        ParameterKind::Choice(words) => {
            let mut i = x.unwrap_or_default() as usize;
            // A word that names its parameter reads alone ("hold-boundary", not "boundary
            // hold-boundary").
            let shown = match words[i].contains(label.as_str()) {
                true => words[i].to_string(),
                false => format!("{label} {}", words[i]),
            };
            egui::ComboBox::from_id_salt((operation, p.name))
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    for (j, word) in words.iter().enumerate() {
                        ui.selectable_value(&mut i, j, *word);
                    }
                });
            return (Some(i as f64) != x).then_some(Some(i as f64));
        }
        ParameterKind::Real { min, max } => (min, max, false),
        ParameterKind::Whole { min, max } => (min, max, true),
    };
    let mut changed = None;
    if let Some(what) = p.automatic {
        let mut auto = x.is_none();
        let response = ui
            .checkbox(&mut auto, format!("auto {label}"))
            .on_hover_text(what);
        if response.changed() {
            changed = Some((!auto).then_some(p.suggested));
        }
        if auto {
            return changed;
        }
    }
    let mut value = changed.flatten().or(x).unwrap_or(min);
    // A real value drags by 1 % of itself a pixel: as fine for a length of 0.002 as for an
    // angle of 45. From zero (an extrusion's distance, an inset's depth) it drags by 0.001, and
    // shows three decimals rather than the six a smaller step would.
    let speed = match (whole, value == 0.0) {
        (true, _) => 1.0,
        (false, true) => 1e-3,
        (false, false) => (value.abs() * 0.01).max(1e-6),
    };
    let field = egui::DragValue::new(&mut value)
        .range(min..=max)
        .speed(speed)
        .prefix(format!("{label} "));
    let field = if whole {
        field.fixed_decimals(0)
    } else {
        field
    };
    if ui.add(field).changed() {
        changed = Some(Some(if whole { value.round() } else { value }));
    }
    changed
}
