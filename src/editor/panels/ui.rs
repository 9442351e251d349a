//! The egui panels: the inspector, mesh statistics, operation buttons, the log, the status line
//! and the help overlay.
//!
//! The UI only reads and asks. An exclusive system ([`snapshot`]) copies what the panels show
//! into [`InspectorView`] in the `Ui` set; the egui system ([`panels`]) draws that copy and
//! answers clicks by writing [`Request`]s, exactly as the keyboard does. Statistics and
//! validation (O(mesh)) are recomputed only when a mesh was opened or edited or the quantity
//! shown on it changed ([`FiguresKey`]), not every frame nor for a change of looks.

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use crate::mesh::ids::ElementId;
use crate::mesh::topology::MeshRef;
use crate::mesh::{InMesh, MeshInfo};

use super::mesh_figures::FiguresKey;
use super::sections::SECTIONS;
use super::sections::folding::PanelSections;
use super::state::PanelContext;
use super::state::{InspectorView, PendingActions, SelectedView, UiFields};
use crate::editor::input::keyboard::perform;
use crate::editor::input::shortcuts::shortcuts;
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::{OutcomeLog, Relation, Request};
use crate::editor::session::schedule::EditorSystems;
use crate::editor::session::schedule::KeyboardCaptured;
use crate::editor::session::selection::{ActiveMesh, SelectMode, Selection, navigate};
use crate::editor::view::colouring::{ColorBy, VertexValues};
use crate::editor::view::render_sync::ViewSettings;
use crate::ops::simplification_history::SimplificationHistory;

/// The panels' plugin.
pub struct UiPlugin;

impl Plugin for UiPlugin {
    fn build(&self, app: &mut App) {
        // egui gets a camera of its own covering the whole window, so the 3D camera can render
        // only beside the panels (see `scene::fit_camera_viewport`).
        if let Some(mut settings) = app
            .world_mut()
            .get_resource_mut::<bevy_egui::EguiGlobalSettings>()
        {
            settings.auto_create_primary_context = false;
        }
        app.add_systems(Startup, spawn_ui_camera);
        app.init_resource::<InspectorView>()
            .init_resource::<UiFields>()
            .init_resource::<PanelSections>()
            .init_resource::<PendingActions>()
            .add_systems(
                Update,
                (
                    run_pending_actions.in_set(EditorSystems::Input),
                    snapshot.in_set(EditorSystems::Ui),
                ),
            )
            .add_systems(
                EguiPrimaryContextPass,
                (panels, super::uv_view::uv_window).chain(),
            );
    }
}

/// The camera egui draws with: after the 3D view, clearing nothing, seeing no mesh (its own
/// render layer). A 2D camera without multisampling: a second 3D camera would run the whole 3D
/// pipeline again for nothing. It shares the 3D camera's picture (which skips its own output)
/// and writes the window once.
fn spawn_ui_camera(mut commands: Commands) {
    commands.spawn((
        Camera2d,
        Camera {
            order: 1,
            clear_color: ClearColorConfig::None,
            ..default()
        },
        bevy::camera::visibility::RenderLayers::layer(31),
        Msaa::Off,
        bevy::core_pipeline::tonemapping::Tonemapping::None,
        bevy::core_pipeline::tonemapping::DebandDither::Disabled,
        bevy_egui::PrimaryEguiContext,
    ));
}

fn run_pending_actions(world: &mut World) {
    let actions = std::mem::take(&mut world.resource_mut::<PendingActions>().0);
    for action in actions {
        perform(world, action);
    }
}

/// Changes that come within this of the last count of the O(mesh) statistics, validation and
/// histograms are counted once the mesh has stood still this long (see [`snapshot`]).
pub const STATS_QUIET: std::time::Duration = std::time::Duration::from_millis(300);

/// Copies what the panels show out of the world.
pub fn snapshot(world: &mut World) {
    let active = world.resource::<ActiveMesh>().0;
    let mut view = std::mem::take(&mut *world.resource_mut::<InspectorView>());
    match active.filter(|m| world.get::<MeshInfo>(m.0).is_some()) {
        None => view.mesh = None,
        Some(mesh) => {
            let key = FiguresKey::of(world, mesh);
            refresh_figures(world, &mut view, mesh, key);
        }
    }
    view.colour = active
        .and_then(|m| world.get::<VertexValues>(m.0))
        .map(|v| (v.quantity.label().to_string(), v.map, v.range));
    show_history_and_work(world, &mut view);
    let selection = world.resource::<Selection>();
    let drawn = crate::editor::gestures::overlay::MAX_SET_DRAWN;
    view.selected_set = match selection.len() {
        0 | 1 => String::new(),
        n if n > drawn => format!(
            "{} (the first {drawn} drawn)",
            crate::editor::session::select_many::describe(selection)
        ),
        _ => crate::editor::session::select_many::describe(selection),
    };
    view.gesture = world
        .resource::<crate::editor::gestures::transform::Gestures>()
        .hint();
    let m = MeshRef::new(world);
    view.selected = world
        .resource::<Selection>()
        .element
        .filter(|&x| crate::editor::session::selection::exists(&m, x))
        .map(|id| describe(&m, id));
    // The group (object, group, material) of a selected face, where the mesh has groups.
    if let Some(selected) = view.selected.as_mut()
        && let ElementId::Face(f) = selected.id
        && let Some(mesh) = world.get::<InMesh>(f.0).map(|m| m.0)
        && let Some(group) = crate::mesh::groups::describe_face_group(world, mesh, f)
    {
        selected.facts.push(("group".into(), group));
    }
    // The value of the quantity on display at a selected vertex (a face, for values on faces).
    if let Some(selected) = view.selected.as_mut()
        && let Some(values) = active.and_then(|mesh| world.get::<VertexValues>(mesh.0))
        && let Some(value) = values.values.get(&selected.id.entity())
    {
        selected
            .facts
            .push((values.quantity.label().to_string(), format!("{value:.6}")));
    }
    *world.resource_mut::<InspectorView>() = view;
}

/// Counts the mesh's statistics, validity and histograms when they are due. They are O(mesh):
/// they wait for the end of a drag (the mouse button held on a vertex or a panel field, a
/// G / R / S gesture) instead of slowing each frame.
fn refresh_figures(
    world: &mut World,
    view: &mut InspectorView,
    mesh: crate::mesh::MeshId,
    key: FiguresKey,
) {
    let dragging = world
        .get_resource::<ButtonInput<MouseButton>>()
        .is_some_and(|b| b.pressed(MouseButton::Left))
        || world
            .get_resource::<crate::editor::gestures::transform::Gestures>()
            .is_some_and(|g| g.active.is_some());
    // They take ~150 ms on the bunny (100 of it validation). The first change after a
    // quiet spell is counted in the next frame; changes that follow within `STATS_QUIET`
    // (a key held down in step mode, flips one after another) wait until the mesh has
    // stood still that long, so they run at the frame rate.
    let now = std::time::Instant::now();
    let quiet = |at: Option<std::time::Instant>| at.is_none_or(|t| now - t >= STATS_QUIET);
    // Never in the frame of the change itself: that frame hands the changed mesh to the
    // renderer, which draws it while the next frame counts.
    let just_changed = view.seen_key != key;
    if just_changed {
        view.seen_key = key;
        view.after_quiet = quiet(view.changed_at);
        view.changed_at = Some(now);
    }
    let changed = view.figures_key != key;
    let due = !just_changed && (view.after_quiet || quiet(view.changed_at));
    if changed && !due {
        world.write_message(bevy::window::RequestRedraw);
    }
    let stale = changed && !dragging && due;
    if view.mesh.is_none() || stale {
        super::mesh_figures::count(world, &mut view.mesh, &mut view.histograms, mesh, key);
        view.figures_key = key;
        view.after_quiet = false;
    }
    super::mesh_figures::collect(world, &mut view.mesh, &mut view.histograms, key);
    if std::mem::take(&mut world.resource_mut::<UiState>().check_validity) {
        super::mesh_figures::check_validity(world, &mut view.mesh, mesh);
    }
}

/// The undo history, the simplification's levels and the job or opening under way.
fn show_history_and_work(world: &World, view: &mut InspectorView) {
    view.lod = world
        .resource::<ActiveMesh>()
        .0
        .and_then(|mesh| SimplificationHistory::levels(world, mesh));
    let history = world.resource::<crate::editor::session::history::UndoHistory>();
    view.history.clear();
    view.history.extend(
        history
            .undo_entries()
            .iter()
            .map(|e| (e.label.clone(), false))
            .chain(
                history
                    .redo_entries()
                    .iter()
                    .rev()
                    .map(|e| (e.label.clone(), true)),
            ),
    );
    view.history_bytes = history.bytes();
    let opening = world
        .resource::<crate::editor::pipeline::opening::Opening>()
        .0
        .as_ref()
        .map(|o| {
            (
                o.label.clone(),
                o.progress.fraction(),
                o.started.elapsed().as_secs_f32(),
            )
        });
    view.job = world
        .resource::<crate::editor::pipeline::jobs::Jobs>()
        .running
        .as_ref()
        .map(|j| {
            (
                j.label.clone(),
                j.progress.fraction(),
                j.started.elapsed().as_secs_f32(),
            )
        })
        .or(opening);
}

fn describe(m: &MeshRef<'_>, id: ElementId) -> SelectedView {
    let relations = Relation::ALL
        .iter()
        .filter(|&&r| matches!(id, ElementId::Halfedge(_)) || r != Relation::Twin)
        .map(|&r| (r, navigate(m, id, r)))
        .collect();
    let yes_no = |b: bool| if b { "yes" } else { "no" }.to_string();
    let (position, facts) = match id {
        ElementId::Vertex(v) => (
            Some(m.position(v)),
            vec![
                ("valence".into(), m.valence(v).to_string()),
                ("boundary".into(), yes_no(m.is_boundary_vertex(v))),
            ],
        ),
        ElementId::Halfedge(h) => (
            None,
            vec![
                ("from".into(), m.from_vertex(h).to_string()),
                ("to".into(), m.to_vertex(h).to_string()),
                ("boundary".into(), yes_no(m.is_boundary(h))),
            ],
        ),
        ElementId::Edge(e) => {
            let (a, b) = m.edge_vertices(e);
            let length = m.position(a).distance(m.position(b));
            (
                None,
                vec![
                    ("vertices".into(), format!("{a} – {b}")),
                    ("length".into(), format!("{length:.5}")),
                    ("boundary".into(), yes_no(m.is_boundary_edge(e))),
                ],
            )
        }
        ElementId::Face(f) => {
            let boundary = m.face_halfedges(f).any(|h| m.is_boundary(m.twin(h)));
            (
                None,
                vec![
                    ("degree".into(), m.face_degree(f).to_string()),
                    (
                        "area".into(),
                        format!("{:.5}", m.face_area_vector(f).length() / 2.0),
                    ),
                    ("on boundary".into(), yes_no(boundary)),
                ],
            )
        }
        ElementId::Mesh(_) => (None, Vec::new()),
    };
    SelectedView {
        id,
        relations,
        position,
        facts,
    }
}

/// Draws the panels and turns clicks into requests: the status line, the side panel's
/// sections ([`SECTIONS`], each folded as [`PanelSections`] remembers), and the windows.
#[allow(
    clippy::too_many_arguments,
    reason = "a UI system reads many small resources"
)]
pub fn panels(
    mut contexts: EguiContexts,
    view: Res<InspectorView>,
    log: Res<OutcomeLog>,
    mut fields: ResMut<UiFields>,
    mut ui_state: ResMut<UiState>,
    (mut mode, mut settings, mut sections): (
        ResMut<SelectMode>,
        ResMut<ViewSettings>,
        ResMut<PanelSections>,
    ),
    density: Res<crate::editor::view::readability::WireframeDensity>,
    mut captured: ResMut<KeyboardCaptured>,
    mut pointer: ResMut<crate::editor::gestures::drag::PointerCaptured>,
    mut insets: ResMut<crate::editor::view::scene::PanelInsets>,
    confirm: Res<crate::editor::session::requests::ConfirmDiscard>,
    mut colour_by: ResMut<ColorBy>,
    mut pending: ResMut<PendingActions>,
    mut anchors: ResMut<crate::editor::gestures::handle_deform::Anchors>,
    mut requests: MessageWriter<Request>,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let mut root = egui::Ui::new(
        ctx.clone(),
        "root".into(),
        egui::UiBuilder::new()
            .layer_id(egui::LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );

    let status = status_bar(&mut root, &view, &log);

    // The small settings are drawn from copies and written back only when they differ, so
    // that an open section does not mark them changed every frame.
    let (mut shown_mode, mut shown_settings, mut shown_colour) = (*mode, *settings, *colour_by);
    let mut cx = PanelContext {
        view: &view,
        log: &log,
        fields: &mut fields,
        state: &mut ui_state,
        mode: &mut shown_mode,
        settings: &mut shown_settings,
        density: &density,
        colour_by: &mut shown_colour,
        anchors: &mut anchors,
        pending: &mut pending,
        requests: Vec::new(),
    };
    // Never narrower than its rows (with every section closed it would shrink to the titles,
    // and a job's progress bar with it).
    let inspector = egui::Panel::left("inspector")
        .resizable(true)
        .default_size(300.0)
        .min_size(260.0)
        .show(&mut root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("Pappus");
                // A job's progress shows whatever sections are open.
                if let Some(job) = &cx.view.job {
                    job_progress(ui, job, &mut cx.requests);
                }
                for section in &SECTIONS {
                    sections.show(ui, section.title, |ui| (section.draw)(ui, &mut cx));
                }
            });
        });
    let made = std::mem::take(&mut cx.requests);
    requests.write_batch(made);
    mode.set_if_neq(shown_mode);
    settings.set_if_neq(shown_settings);
    colour_by.set_if_neq(shown_colour);

    let new_insets = crate::editor::view::scene::PanelInsets {
        left: inspector.response.rect.width(),
        bottom: status.response.rect.height(),
        ..*insets
    };
    if *insets != new_insets {
        *insets = new_insets;
    }

    if let Some(pending) = &confirm.0 {
        discard_question(&ctx, pending, &mut requests);
    }

    histogram_window(&ctx, &view, ui_state.histograms);

    if ui_state.show_help {
        ui_state.show_help = help_window(&ctx);
    }

    captured.0 = ctx.egui_wants_keyboard_input();
    pointer.0 = ctx.egui_wants_pointer_input() || ctx.is_pointer_over_egui();
    Ok(())
}

/// A running job's progress bar and its Cancel button.
fn job_progress(
    ui: &mut egui::Ui,
    (label, fraction, seconds): &(String, f32, f32),
    requests: &mut Vec<Request>,
) {
    ui.horizontal(|ui| {
        let text = format!("{label}: {:.0} % ({seconds:.1} s)", fraction * 100.0);
        let bar = egui::ProgressBar::new(*fraction).text(text).animate(true);
        ui.add(bar.desired_width(ui.available_width() - 70.0));
        if ui.button("Cancel").clicked() {
            requests.push(Request::CancelJob);
        }
    });
}

/// The status line: a gesture's hint, or the last outcome.
fn status_bar(
    root: &mut egui::Ui,
    view: &InspectorView,
    log: &OutcomeLog,
) -> egui::InnerResponse<()> {
    egui::Panel::bottom("status").show(root, |ui| {
        ui.horizontal(|ui| {
            if let Some(hint) = &view.gesture {
                ui.colored_label(egui::Color32::from_rgb(255, 190, 90), hint);
                return;
            }
            match log.entries.last() {
                Some(last) => match &last.result {
                    Ok(s) => ui.label(format!("✔ {}: {s}", last.request)),
                    Err(r) => ui.colored_label(
                        egui::Color32::from_rgb(230, 120, 90),
                        format!("x {}: {r}", last.request),
                    ),
                },
                None => ui.label("Ready. Press F1 or ? for help."),
            };
        });
    })
}

/// The help window listing every key; returns whether it stays open.
fn help_window(ctx: &egui::Context) -> bool {
    let mut open = true;
    // Taller than a laptop's screen: the list scrolls, in a window as tall as the screen.
    let room = (ctx.content_rect().height() - 120.0).max(200.0);
    egui::Window::new("Shortcuts")
        .open(&mut open)
        .collapsible(false)
        .default_height(room)
        .show(ctx, |ui| {
            egui::ScrollArea::vertical()
                .max_height(room)
                .min_scrolled_height(room)
                .show(ui, help_grid);
        });
    open
}

/// Every shortcut (the editor's and the operations' declared keys), then the mouse.
fn help_grid(ui: &mut egui::Ui) {
    egui::Grid::new("help").striped(true).show(ui, |ui| {
        for s in shortcuts() {
            ui.monospace(s.keys);
            ui.label(s.description);
            ui.end_row();
        }
        for (keys, what) in [
            ("left click", "select (mode: 1 2 3 4 `)"),
            ("middle / right drag", "orbit"),
            ("Shift + drag", "pan"),
            ("wheel", "zoom"),
            ("drop a file", "open it"),
        ] {
            ui.monospace(keys);
            ui.label(what);
            ui.end_row();
        }
    });
}

/// The histograms, in a window beside the mesh: while it is coloured by a quantity, or when
/// asked for.
fn histogram_window(ctx: &egui::Context, view: &InspectorView, asked: bool) {
    if (view.colour.is_none() && !asked) || view.histograms.is_empty() {
        return;
    }
    egui::Window::new("Histograms")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .default_width(260.0)
        .resizable(false)
        .show(ctx, |ui| {
            for h in &view.histograms {
                super::plots::draw(ui, h);
            }
        });
}

/// The window that asks whether something may be discarded: unsaved changes (before an open
/// or quitting) or what a save's format cannot hold.
fn discard_question(
    ctx: &egui::Context,
    pending: &crate::editor::session::requests::PendingDiscard,
    requests: &mut MessageWriter<Request>,
) {
    use crate::editor::session::requests::PendingDiscard;
    let (title, question, hint, confirm) = match pending {
        PendingDiscard::Open(path) => (
            "Unsaved changes",
            format!(
                "The mesh has changes that are not saved. Discard them and open {}?",
                path.display()
            ),
            "(Cancel, then Ctrl+S, to keep them.)".to_string(),
            "Discard changes",
        ),
        PendingDiscard::Quit => (
            "Unsaved changes",
            "The mesh has changes that are not saved. Discard them and quit?".to_string(),
            "(Cancel, then Ctrl+S, to keep them.)".to_string(),
            "Discard changes",
        ),
        PendingDiscard::Save { path, dropped } => (
            "Save drops data",
            format!(
                "{} cannot hold the mesh's {}: saving drops them.",
                path.display(),
                dropped.join(", ")
            ),
            "(Cancel, then Save as .ply, to keep everything.)".to_string(),
            "Save anyway",
        ),
    };
    egui::Window::new(title)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            ui.label(question);
            ui.label(hint);
            ui.horizontal(|ui| {
                if ui.button(confirm).clicked() {
                    requests.write(Request::ConfirmDiscard(true));
                }
                if ui.button("Cancel").clicked() {
                    requests.write(Request::ConfirmDiscard(false));
                }
            });
        });
}
