//! What step mode shows on the mesh — QEM's next collapse (the edge, the point its ends merge
//! at, the runners-up in the queue), what a remeshing pass touched, a subdivision level's new
//! points and the selected element's stencil, an ARAP iteration's best rotation at each vertex
//! as a small frame — and a window that drives the run.
//!
//! [`gather_step_overlay`] adds shapes to the frame's [`Overlay`] (logic side: headless tests
//! see them); [`snapshot_steps`] copies what the window shows out of the world once a frame;
//! [`step_window`] draws it, with the cost written beside the next edge on the mesh.

use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

use crate::mesh::ids::ElementId;
use crate::mesh::topology::MeshRef;

use super::state::PendingActions;
use super::stencil_view::{
    PointsShown, point_shapes, point_shapes_near, stencil_panel, stencil_shapes,
};
use crate::editor::gestures::overlay::{AXIS_COLORS, Overlay, Shape};
use crate::editor::input::keyboard::Action;
use crate::editor::pipeline::stepping::{Stepping, Steps, describe};
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::Request;
use crate::editor::session::requests::StepMove;
use crate::editor::session::selection::Selection;
use crate::ops::remesh::Touched;
use crate::ops::simplify::QueuedEdge;
use crate::ops::stencil::Stencil;

/// The next edge and the point it collapses to.
pub const NEXT: Color = Color::srgb(1.0, 0.45, 0.05);
/// The edges after it in the queue.
pub const QUEUED: Color = Color::srgb(0.95, 0.75, 0.2);
/// How many of the queue's cheapest edges are drawn and listed.
pub const CANDIDATES: usize = 10;
/// What a remeshing pass touched.
pub const TOUCHED: Color = Color::srgb(0.1, 0.8, 0.35);
/// The most elements of one kind a step draws (gizmos are redrawn every frame).
pub const MAX_DRAWN: usize = 3_000;

/// Adds the run's shapes to the frame's overlay (after `overlay::gather_overlay`).
pub fn gather_step_overlay(world: &mut World) {
    let Some(run) = &world.resource::<Stepping>().run else {
        return;
    };
    let m = MeshRef::new(world);
    let mut shapes = Vec::new();
    match &run.steps {
        Steps::Qem(steps) if steps.at_front() => {
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
        Steps::Qem(_) => {}
        Steps::Remesh(steps) => {
            if let Some(report) = &steps.last {
                touched_shapes(&m, &report.touched, &mut shapes);
            }
        }
        Steps::Deform(steps) => {
            // Each rotation as a frame: where the vertex's X, Y and Z axes turn to.
            let frames: Vec<_> = steps.frames().collect();
            for i in even_sample(frames.len()) {
                let (p, q) = frames[i];
                for (axis, color) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().zip(AXIS_COLORS) {
                    shapes.push(Shape::Line(p, p + q * axis * steps.frame_size, color));
                }
            }
        }
        Steps::Subdivide(steps) => {
            let stencil = steps.selected_stencil(world);
            if let Some(points) = &steps.points {
                let which = PointsShown {
                    new_points: true,
                    moved_vertices: steps.moved_shown,
                };
                let near = stencil.as_ref().map(|s| s.position);
                match near {
                    Some(near) => point_shapes_near(points, which, near, &mut shapes, MAX_DRAWN),
                    None => point_shapes(points, which, &mut shapes, MAX_DRAWN),
                }
            }
            if let Some(stencil) = &stencil {
                stencil_shapes(&m, stencil, &mut shapes);
            }
        }
    }
    world.resource_mut::<Overlay>().shapes.extend(shapes);
}

/// What a remeshing pass touched: its edges as thick lines, its vertices as dots, at most
/// [`MAX_DRAWN`] of each (an even sample above that).
fn touched_shapes(m: &MeshRef<'_>, touched: &Touched, out: &mut Vec<Shape>) {
    for i in even_sample(touched.edges.len()) {
        let e = touched.edges[i];
        if m.try_edge(e).is_some() {
            let (a, b) = m.edge_vertices(e);
            out.push(Shape::Highlight(m.position(a), m.position(b), TOUCHED));
        }
    }
    for i in even_sample(touched.vertices.len()) {
        let v = touched.vertices[i];
        if m.try_vertex(v).is_some() {
            let p = m.position(v);
            let r = m
                .vertex_neighbors(v)
                .map(|w| m.position(w).distance(p))
                .fold(f32::INFINITY, f32::min);
            out.push(Shape::Dot(p, 0.15 * r.min(1.0e3), TOUCHED));
        }
    }
}

/// Indices into `n` things, at most [`MAX_DRAWN`] of them, evenly spread.
fn even_sample(n: usize) -> impl Iterator<Item = usize> {
    (0..n.min(MAX_DRAWN)).map(move |i| i * n / n.clamp(1, MAX_DRAWN))
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
    /// Steps made (QEM) or steps in all (the others).
    pub made: usize,
    /// Whether the slider may scrub back (QEM).
    pub scrubs: bool,
    /// Whether the run steps back at all (not remeshing).
    pub backs: bool,
    /// The next collapse: its edge, cost, and where its ends merge (where the label goes).
    pub next: Option<QueuedEdge>,
    /// The queue's cheapest edges.
    pub queue: Vec<QueuedEdge>,
    /// The latest refusals, as lines.
    pub refused: Vec<String>,
    /// What became of the selected element.
    pub fate: Option<String>,
    /// Each remeshing pass so far.
    pub passes: Vec<String>,
    /// A stepped deformation's energy at each iteration made, newest first.
    pub energies: Vec<String>,
    /// The selected element's stencil, under subdivision.
    pub stencil: Option<Stencil>,
    /// Whether the run has made its last step.
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
        view.title = Some(run.edit.label());
        view.line = describe(&run.steps);
        view.at = run.steps.at();
        view.made = run.steps.made();
        view.finished = run.steps.finished();
        let selected = world.resource::<Selection>().element;
        view.fate = run
            .fate
            .as_ref()
            .filter(|(became, _)| selected == Some(*became))
            .map(|(_, line)| line.clone());
        view.backs = !matches!(run.steps, Steps::Remesh(_));
        match &run.steps {
            Steps::Qem(steps) => {
                view.scrubs = true;
                if steps.at_front() {
                    view.next = steps.next.map(|n| n.queued);
                    view.queue = steps.candidates(CANDIDATES);
                }
                view.refused = steps
                    .refused
                    .iter()
                    .rev()
                    .map(|r| format!("{} ({:.2e}): {}", r.queued.edge, r.queued.cost, r.why))
                    .collect();
            }
            Steps::Remesh(steps) => view.passes = steps.passes.clone(),
            Steps::Deform(steps) => {
                view.scrubs = true;
                view.energies = (0..steps.iterations.len())
                    .rev()
                    .map(|k| {
                        let shown = if k == steps.at { "  ◀" } else { "" };
                        format!("{k:>3}: {:.6e}{shown}", steps.iterations[k].energy)
                    })
                    .collect();
            }
            Steps::Subdivide(steps) => view.stencil = steps.selected_stencil(world),
        }
    }
    *world.resource_mut::<StepView>() = view;
}

fn keys_of(action: Action) -> &'static str {
    crate::editor::input::keyboard::keys_of(action).unwrap_or("")
}

/// The step window, and the next edge's cost written beside it on the mesh.
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
    if let (Some(next), Ok((camera, eye))) = (view.next, camera.single()) {
        label_next_collapse(ctx, &next, camera, eye);
    }
    egui::Window::new(format!("Step through: {title}"))
        .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-12.0, 12.0))
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(&view.line);
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
                    if matches!(movement, StepMove::Back(_)) && !view.backs {
                        continue;
                    }
                    let keys = keys_of(Action::Step(movement));
                    if ui.button(text).on_hover_text(keys).clicked() {
                        pending.0.push(Action::Step(movement));
                    }
                }
            });
            if view.scrubs {
                let mut at = view.at;
                let slider = egui::Slider::new(&mut at, 0..=view.made.max(1)).text("scrub");
                if ui.add_enabled(view.made > 0, slider).changed() && at != view.at {
                    requests.write(Request::Step(StepMove::To(at)));
                }
            }
            if view.finished {
                ui.label("the run is at its end: keep it (Enter) or cancel (Esc)");
            }
            lines_section(
                ui,
                "energy by iteration (each vertex's best rotation drawn as a frame)",
                view.energies.iter(),
            );
            if !view.passes.is_empty() {
                lines_section(
                    ui,
                    "passes (green: what the last one touched)",
                    view.passes.iter().rev(),
                );
                ui.checkbox(
                    &mut ui_state.histograms,
                    "edge-length and valence histograms",
                );
            }
            if let Some(stencil) = &view.stencil {
                ui.separator();
                stencil_panel(ui, stencil);
            } else if view.passes.is_empty() && view.next.is_none() && !view.scrubs {
                ui.label("select a vertex, an edge or a face to see its stencil");
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

/// A titled list of the first 12 `lines`, in monospace; nothing without lines.
fn lines_section<'a>(ui: &mut egui::Ui, title: &str, lines: impl Iterator<Item = &'a String>) {
    let mut lines = lines.take(12).peekable();
    if lines.peek().is_none() {
        return;
    }
    ui.separator();
    ui.label(egui::RichText::new(title).strong());
    for line in lines {
        ui.monospace(line);
    }
}

/// The step window with no run in progress: what step mode does, and a way out.
fn idle_window(ctx: &egui::Context, pending: &mut PendingActions) {
    egui::Window::new("Step mode")
        .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-12.0, 12.0))
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(
                "Simplify (Shift+S), remesh (M), Loop (L), Catmull-Clark (Q) and an \
                 as-rigid-as-possible handle drag (G, R, S with anchors) now run a step \
                 at a time.",
            );
            if ui.button("Turn step mode off (F9)").clicked() {
                pending.0.push(Action::ToggleStepMode);
            }
        });
}

/// The next collapse's edge and cost, written on the mesh beside the point its ends merge at.
fn label_next_collapse(
    ctx: &egui::Context,
    next: &QueuedEdge,
    camera: &Camera,
    eye: &GlobalTransform,
) {
    let Ok(p) = camera.world_to_viewport(eye, next.position) else {
        return;
    };
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Background,
        egui::Id::new("next collapse"),
    ));
    let text = format!("{}  cost {:.3e}", next.edge, next.cost);
    let galley =
        painter.layout_no_wrap(text, egui::FontId::proportional(15.0), egui::Color32::WHITE);
    // Up and to the left of the point: the step window sits on the right.
    let corner = egui::pos2(p.x - 14.0 - galley.size().x, p.y - 10.0 - galley.size().y);
    let rect = egui::Rect::from_min_size(corner, galley.size()).expand(4.0);
    painter.rect_filled(rect, 3.0, egui::Color32::from_rgb(190, 80, 10));
    painter.galley(corner, galley, egui::Color32::WHITE);
}
