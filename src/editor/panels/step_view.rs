//! What step mode shows: the shapes the run in progress draws over the mesh, a label written
//! on it, and a window that drives the run and lists what the operation says about its step.
//!
//! The window knows no algorithm. Each operation's run ([`Steps`](stepping::Steps)) says what it
//! shows at the step it is at ([`StepShow`]: shapes, a label, lists, a table, a hint);
//! [`gather_step_view`] asks it once a frame, turns its shapes into the frame's [`Overlay`] (logic
//! side: headless tests see them) and copies the rest into [`StepView`]; [`step_window`] draws
//! that.

use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

use super::state::PendingActions;
use crate::editor::gestures::overlay::{AXIS_COLORS, Overlay, Shape};
use crate::editor::input::shortcuts::Action;
use crate::editor::pipeline::stepping::Stepping;
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::{Request, StepMove};
use crate::editor::session::selection::Selection;
use crate::ops::operation::stepping::{self, GoesBack, Rgb, StepList, StepShape, StepShow};

/// The next edge and the point it collapses to.
pub const NEXT: Color = color(stepping::NEXT);
/// The edges after it in the queue.
pub const QUEUED: Color = color(stepping::QUEUED);
/// What the last step touched.
pub const TOUCHED: Color = color(stepping::TOUCHED);
/// The most lines of one list the window shows.
const LINES_SHOWN: usize = 12;

const fn color([r, g, b]: Rgb) -> Color {
    Color::srgb(r, g, b)
}

/// What the step window shows, copied out of the world once a frame.
#[derive(Resource, Default, Debug, Clone)]
pub struct StepView {
    /// Whether step mode is on.
    pub enabled: bool,
    /// The run's title (the edit's label), if a run is in progress.
    pub title: Option<String>,
    /// Where the run is, in one line.
    pub line: String,
    /// The step the mesh is at.
    pub at: usize,
    /// The end of the slider ([`stepping::Steps::made`]).
    pub made: usize,
    /// How the run goes back.
    pub goes_back: Option<GoesBack>,
    /// What the run shows at its step, its shapes taken out (they are in the overlay).
    pub show: StepShow,
    /// What became of the selected element.
    pub fate: Option<String>,
    /// Whether the run has made its last step.
    pub finished: bool,
}

/// Asks the run in progress what it shows: its shapes join the frame's overlay (after
/// `overlay::gather_overlay`), the rest goes to [`StepView`].
pub fn gather_step_view(world: &mut World) {
    let stepping = world.resource::<Stepping>();
    let mut view = StepView {
        enabled: stepping.enabled,
        ..default()
    };
    if let Some(run) = &stepping.run {
        let selected = world.resource::<Selection>().element;
        view.title = Some(run.edit.label());
        view.line = run.steps.describe();
        view.at = run.steps.at();
        view.made = run.steps.made();
        view.finished = run.steps.finished();
        view.goes_back = Some(run.steps.goes_back());
        view.fate = run
            .fate
            .as_ref()
            .filter(|(became, _)| selected == Some(*became))
            .map(|(_, line)| line.clone());
        view.show = run.steps.show(world, selected);
        for list in &mut view.show.lists {
            list.lines.truncate(LINES_SHOWN);
        }
    }
    let shapes: Vec<Shape> = std::mem::take(&mut view.show.shapes)
        .into_iter()
        .flat_map(overlay_shapes)
        .collect();
    world.resource_mut::<Overlay>().shapes.extend(shapes);
    *world.resource_mut::<StepView>() = view;
}

/// A run's shape as the overlay draws it (a frame as three lines in the axis colours).
fn overlay_shapes(shape: StepShape) -> Vec<Shape> {
    match shape {
        StepShape::Line(a, b, c) => vec![Shape::Line(a, b, color(c))],
        StepShape::Highlight(a, b, c) => vec![Shape::Highlight(a, b, color(c))],
        StepShape::Dot(p, r, c) => vec![Shape::Dot(p, r, color(c))],
        StepShape::HighlightDot(p, r, c) => vec![Shape::HighlightDot(p, r, color(c))],
        StepShape::Frame(p, q, size) => [Vec3::X, Vec3::Y, Vec3::Z]
            .into_iter()
            .zip(AXIS_COLORS)
            .map(|(axis, c)| Shape::Line(p, p + q * axis * size, c))
            .collect(),
    }
}

fn keys_of(action: Action) -> &'static str {
    crate::editor::input::shortcuts::keys_of(action).unwrap_or("")
}

/// The step window, and the run's label written on the mesh.
pub fn step_window(
    mut contexts: EguiContexts,
    view: Res<StepView>,
    mut pending: ResMut<PendingActions>,
    mut requests: MessageWriter<Request>,
    mut ui_state: ResMut<UiState>,
    camera: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Some(title) = &view.title else {
        if view.enabled {
            idle_window(ctx, &mut pending);
        }
        return Ok(());
    };
    if let (Some((at, text)), Ok((camera, eye))) = (&view.show.label, camera.single()) {
        label_on_mesh(ctx, *at, text, camera, eye);
    }
    egui::Window::new(format!("Step through: {title}"))
        .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-12.0, 12.0))
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(&view.line);
            move_buttons(ui, &view, &mut pending);
            if view.goes_back == Some(GoesBack::Scrubs) {
                let mut at = view.at;
                let slider = egui::Slider::new(&mut at, 0..=view.made.max(1)).text("scrub");
                if ui.add_enabled(view.made > 0, slider).changed() && at != view.at {
                    requests.write(Request::Step(StepMove::To(at)));
                }
            }
            if view.finished {
                ui.label("the run is at its end: keep it (Enter) or cancel (Esc)");
            }
            if let Some(fate) = &view.fate {
                ui.colored_label(egui::Color32::from_rgb(230, 150, 60), fate);
            }
            let show = &view.show;
            for list in show.lists.iter().filter(|l| !l.lines.is_empty()) {
                list_section(ui, list, &mut requests);
            }
            if show.histograms {
                ui.checkbox(
                    &mut ui_state.histograms,
                    "edge-length and valence histograms",
                );
            }
            if let Some(table) = &show.table {
                ui.separator();
                ui.label(egui::RichText::new(&table.title).strong());
                ui.label(&table.note);
                egui::Grid::new("step table").striped(true).show(ui, |ui| {
                    ui.label(egui::RichText::new(&table.header[0]).strong());
                    ui.label(egui::RichText::new(&table.header[1]).strong());
                    ui.end_row();
                    for [a, b] in &table.rows {
                        ui.monospace(a);
                        ui.monospace(b);
                        ui.end_row();
                    }
                });
                ui.label(&table.footer);
            }
            if let Some(hint) = &show.hint {
                ui.label(hint);
            }
            ui.separator();
            ui.horizontal(|ui| {
                let keep = Action::Step(StepMove::Finish);
                if ui.button(format!("Keep ({})", keys_of(keep))).clicked() {
                    pending.0.push(keep);
                }
                if ui.button("Cancel (Esc)").clicked() {
                    pending.0.push(Action::Step(StepMove::Cancel));
                }
            });
        });
    Ok(())
}

/// The buttons that move the run: back where it goes back, forward, to the end.
fn move_buttons(ui: &mut egui::Ui, view: &StepView, pending: &mut PendingActions) {
    let backs = view.goes_back != Some(GoesBack::Never);
    ui.horizontal(|ui| {
        for (movement, text) in [
            (StepMove::Back(100), "−100"),
            (StepMove::Back(10), "−10"),
            (StepMove::Back(1), "−1"),
            (StepMove::Forward(1), "+1"),
            (StepMove::Forward(10), "+10"),
            (StepMove::Forward(100), "+100"),
            (StepMove::Forward(usize::MAX), "end"),
        ] {
            if matches!(movement, StepMove::Back(_)) && !backs {
                continue;
            }
            let keys = keys_of(Action::Step(movement));
            if ui.button(text).on_hover_text(keys).clicked() {
                pending.0.push(Action::Step(movement));
            }
        }
    });
}

/// A titled list, in monospace; a line naming an element starts with a link that selects it.
fn list_section(ui: &mut egui::Ui, list: &StepList, requests: &mut MessageWriter<Request>) {
    ui.separator();
    ui.label(egui::RichText::new(&list.title).strong());
    egui::Grid::new(&list.title).striped(true).show(ui, |ui| {
        for line in &list.lines {
            if let Some(element) = line.element
                && ui.link(element.to_string()).clicked()
            {
                requests.write(Request::Select(Some(element)));
            }
            ui.monospace(&line.text);
            ui.end_row();
        }
    });
}

/// The step window with no run in progress: the operations that step (their declarations
/// say which), and a way out.
fn idle_window(ctx: &egui::Context, pending: &mut PendingActions) {
    let stepping: Vec<String> = crate::ops::registry::operations()
        .iter()
        .map(|op| op.declaration())
        .filter(|d| d.steps)
        .map(|d| match d.key {
            Some(key) => format!("{} ({key})", d.title),
            None => d.title.to_string(),
        })
        .collect();
    egui::Window::new("Step mode")
        .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-12.0, 12.0))
        .resizable(false)
        .show(ctx, |ui| {
            ui.label("These now run a step at a time:");
            for line in &stepping {
                ui.label(format!("  • {line}"));
            }
            ui.label("  • an as-rigid-as-possible handle drag (G, R, S with anchors)");
            if ui.button("Turn step mode off (F9)").clicked() {
                pending.0.push(Action::ToggleStepMode);
            }
        });
}

/// A run's label, written on the mesh up and to the left of its point (the step window sits
/// on the right).
fn label_on_mesh(
    ctx: &egui::Context,
    at: Vec3,
    text: &str,
    camera: &Camera,
    eye: &GlobalTransform,
) {
    let Ok(p) = camera.world_to_viewport(eye, at) else {
        return;
    };
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Background,
        egui::Id::new("step label"),
    ));
    let galley = painter.layout_no_wrap(
        text.to_string(),
        egui::FontId::proportional(15.0),
        egui::Color32::WHITE,
    );
    let corner = egui::pos2(p.x - 14.0 - galley.size().x, p.y - 10.0 - galley.size().y);
    let rect = egui::Rect::from_min_size(corner, galley.size()).expand(4.0);
    painter.rect_filled(rect, 3.0, egui::Color32::from_rgb(190, 80, 10));
    painter.galley(corner, galley, egui::Color32::WHITE);
}
