//! What step mode shows: the next collapse drawn on the mesh (the edge, the point its ends merge
//! at, the runners-up in the queue), and a window that drives the run and lists the queue.
//!
//! [`gather_step_overlay`] adds shapes to the frame's [`Overlay`] (logic side: headless tests
//! see them); [`snapshot_steps`] copies what the window shows out of the world once a frame;
//! [`step_window`] draws it, with the cost written beside the next edge on the mesh.

use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

use crate::mesh::ids::{EdgeId, ElementId};
use crate::mesh::topology::MeshRef;

use super::input::{Action, SHORTCUTS};
use super::overlay::{Overlay, Shape};
use super::requests::Request;
use super::stepping::{StepMove, Stepping};
use super::ui::PendingActions;

/// The next edge and the point it collapses to.
pub const NEXT: Color = Color::srgb(1.0, 0.45, 0.05);
/// The edges after it in the queue.
pub const QUEUED: Color = Color::srgb(0.95, 0.75, 0.2);
/// How many of the queue's cheapest edges are drawn and listed.
pub const CANDIDATES: usize = 10;

/// Adds the run's shapes to the frame's overlay (after `overlay::gather_overlay`).
pub fn gather_step_overlay(world: &mut World) {
    let Some(run) = &world.resource::<Stepping>().run else {
        return;
    };
    let m = MeshRef::new(world);
    let mut shapes = Vec::new();
    let steps = &run.steps;
    if steps.at_front() {
        for queued in steps.candidates(CANDIDATES).iter().skip(1) {
            if m.try_edge(queued.edge).is_some() {
                let (a, b) = m.edge_vertices(queued.edge);
                shapes.push(Shape::Highlight(m.position(a), m.position(b), QUEUED));
            }
        }
        if let Some(next) = &steps.next {
            let (a, b) = (m.position(next.kept), m.position(next.removed));
            let at = next.queued.position;
            shapes.push(Shape::Highlight(a, b, NEXT));
            shapes.push(Shape::Line(a, at, NEXT));
            shapes.push(Shape::Line(b, at, NEXT));
            shapes.push(Shape::HighlightDot(at, a.distance(b) * 0.15, NEXT));
        }
    }
    world.resource_mut::<Overlay>().shapes.extend(shapes);
}

/// One line of the queue in the window.
#[derive(Clone, Debug, PartialEq)]
pub struct QueueLine {
    /// The edge.
    pub edge: EdgeId,
    /// Its cost.
    pub cost: f32,
}

/// What the step window shows, copied out of the world once a frame.
#[derive(Resource, Default, Debug, Clone)]
pub struct StepView {
    /// Whether step mode is on.
    pub enabled: bool,
    /// The run's title (the edit's label), if a run is in progress.
    pub title: Option<String>,
    /// The step the mesh is at, the steps made, faces now and the target.
    pub at: usize,
    /// Collapses made so far.
    pub made: usize,
    /// Faces at this step.
    pub faces: usize,
    /// The face count the run stops at.
    pub target: usize,
    /// The next collapse: its edge, cost, and where it is drawn (for the label).
    pub next: Option<(EdgeId, f32, Vec3)>,
    /// The queue's cheapest edges.
    pub queue: Vec<QueueLine>,
    /// The latest refusals, as lines.
    pub refused: Vec<String>,
    /// What became of the selected element.
    pub fate: Option<String>,
    /// Whether the run has made its last collapse.
    pub finished: bool,
}

/// Copies the run's state for the window (the `Ui` set).
pub fn snapshot_steps(world: &mut World) {
    let stepping = world.resource::<Stepping>();
    let mut view = StepView {
        enabled: stepping.enabled,
        ..default()
    };
    if let Some(run) = &stepping.run {
        let steps = &run.steps;
        view.title = Some(run.edit.label());
        view.at = steps.at();
        view.made = steps.made();
        view.faces = steps.faces();
        view.target = steps.target_faces();
        view.next = steps
            .next
            .filter(|_| steps.at_front())
            .map(|n| (n.queued.edge, n.queued.cost, n.queued.position));
        view.queue = match steps.at_front() {
            true => steps
                .candidates(CANDIDATES)
                .into_iter()
                .map(|q| QueueLine {
                    edge: q.edge,
                    cost: q.cost,
                })
                .collect(),
            false => Vec::new(),
        };
        view.refused = steps
            .refused
            .iter()
            .rev()
            .map(|r| format!("{} ({:.2e}): {}", r.queued.edge, r.queued.cost, r.why))
            .collect();
        view.fate = run.fate.clone();
        view.finished = steps.finished();
    }
    *world.resource_mut::<StepView>() = view;
}

fn keys_of(action: Action) -> &'static str {
    SHORTCUTS
        .iter()
        .find(|s| s.action == action)
        .map_or("", |s| s.keys)
}

/// The step window, and the next edge's cost written beside it on the mesh.
pub fn step_window(
    mut contexts: EguiContexts,
    view: Res<StepView>,
    mut pending: ResMut<PendingActions>,
    mut requests: MessageWriter<Request>,
    camera: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Some(title) = &view.title else {
        if view.enabled {
            egui::Window::new("Step mode")
                .default_pos(egui::pos2(16.0, 16.0))
                .resizable(false)
                .show(ctx, |ui| {
                    ui.label("Simplify (Shift+S) now runs one collapse at a time.");
                    if ui.button("Turn step mode off (F9)").clicked() {
                        pending.0.push(Action::ToggleStepMode);
                    }
                });
        }
        return Ok(());
    };
    if let (Some((edge, cost, at)), Ok((camera, eye))) = (view.next, camera.single())
        && let Ok(p) = camera.world_to_viewport(eye, at)
    {
        let painter = ctx.layer_painter(egui::LayerId::new(
            egui::Order::Background,
            egui::Id::new("next collapse"),
        ));
        let text = format!("{edge}  cost {cost:.3e}");
        let galley =
            painter.layout_no_wrap(text, egui::FontId::proportional(15.0), egui::Color32::WHITE);
        let corner = egui::pos2(p.x + 14.0, p.y - 10.0 - galley.size().y);
        let rect = egui::Rect::from_min_size(corner, galley.size()).expand(4.0);
        painter.rect_filled(rect, 3.0, egui::Color32::from_rgb(190, 80, 10));
        painter.galley(corner, galley, egui::Color32::WHITE);
    }
    egui::Window::new(format!("Step through: {title}"))
        .default_pos(egui::pos2(16.0, 16.0))
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(format!(
                "step {} of {} made · {} faces (target {})",
                view.at, view.made, view.faces, view.target
            ));
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
                    let keys = keys_of(Action::Step(movement));
                    if ui.button(text).on_hover_text(keys).clicked() {
                        pending.0.push(Action::Step(movement));
                    }
                }
            });
            let mut at = view.at;
            let slider = egui::Slider::new(&mut at, 0..=view.made.max(1)).text("scrub");
            if ui.add_enabled(view.made > 0, slider).changed() && at != view.at {
                requests.write(Request::Step(StepMove::To(at)));
            }
            match (&view.next, view.finished) {
                (Some((edge, cost, _)), _) => {
                    ui.label(format!("next: collapse {edge}, cost {cost:.3e}"));
                }
                (None, true) => {
                    ui.label("the run is at its end");
                }
                (None, false) => {
                    ui.label(format!(
                        "moved back along what has run: {} forward replays it",
                        keys_of(Action::Step(StepMove::Forward(1)))
                    ));
                }
            }
            if let Some(fate) = &view.fate {
                ui.colored_label(egui::Color32::from_rgb(230, 150, 60), fate);
            }
            if !view.queue.is_empty() {
                ui.separator();
                ui.label(egui::RichText::new("queue, cheapest first (click selects)").strong());
                egui::Grid::new("queue").striped(true).show(ui, |ui| {
                    for line in &view.queue {
                        if ui.link(line.edge.to_string()).clicked() {
                            requests.write(Request::Select(Some(ElementId::Edge(line.edge))));
                        }
                        ui.monospace(format!("{:.3e}", line.cost));
                        ui.end_row();
                    }
                });
            }
            if !view.refused.is_empty() {
                ui.separator();
                ui.label(egui::RichText::new("refused on the way (newest first)").strong());
                for line in &view.refused {
                    ui.label(line);
                }
            }
            ui.separator();
            ui.horizontal(|ui| {
                if ui
                    .button(format!(
                        "Keep ({})",
                        keys_of(Action::Step(StepMove::Finish))
                    ))
                    .clicked()
                {
                    pending.0.push(Action::Step(StepMove::Finish));
                }
                if ui.button("Cancel (Esc)").clicked() {
                    pending.0.push(Action::Step(StepMove::Cancel));
                }
            });
        });
    Ok(())
}
