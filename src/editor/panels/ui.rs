//! The egui panels: the inspector, mesh statistics, operation buttons, the log, the status line
//! and the help overlay.
//!
//! The UI only reads and asks. An exclusive system ([`snapshot`]) copies what the panels show
//! into [`InspectorView`] in the `Ui` set; the egui system ([`panels`]) draws that copy and
//! answers clicks by writing [`Request`]s, exactly as the keyboard does. Statistics and
//! validation (O(mesh)) are recomputed only when a mesh was rebuilt, not every frame.

use bevy::math::Vec3;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use std::path::PathBuf;

use crate::mesh::ids::{ElementId, parse_element};
use crate::mesh::topology::MeshRef;
use crate::mesh::{InMesh, MeshInfo};
use crate::ops::named::Named;

use crate::edit::Edit;
use crate::ops::declaration::{Declaration, Parameter, ParameterKind, Section};
use crate::ops::deform::{DeformMethod, Falloff};
use crate::ops::operation::Invocation;

use super::mesh_figures::MeshView;
use super::plots::Histogram;
use crate::colormap::{ColorMap, Range};
use crate::editor::input::keyboard::{Action, UiState, perform, shortcuts};
use crate::editor::session::dialog::PathPurpose;
use crate::editor::session::requests::{OutcomeLog, Relation, Request};
use crate::editor::session::schedule::EditorSystems;
use crate::editor::session::schedule::KeyboardCaptured;
use crate::editor::session::selection::{ActiveMesh, SelectMode, Selection, navigate};
use crate::editor::session::state::SimplificationHistory;
use crate::editor::view::colouring::{ColorBy, VertexValues};
use crate::editor::view::render_sync::{RenderStats, ViewSettings};
use crate::ops::geometry::Quantity;

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
            .init_resource::<super::panel_sections::PanelSections>()
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

/// Everything the panels show, copied out of the world once a frame.
#[derive(Resource, Default, Debug, Clone)]
pub struct InspectorView {
    /// The active mesh, if any.
    pub mesh: Option<MeshView>,
    /// The selected element, if any.
    pub selected: Option<SelectedView>,
    /// The selected set, counted ("3 faces selected"); empty when at most one is selected.
    pub selected_set: String,
    /// The transform under way, as the status line says it.
    pub gesture: Option<String>,
    /// Rebuild count at the last statistics refresh.
    pub stats_generation: usize,
    /// The rebuild count last seen.
    pub seen_generation: usize,
    /// When the rebuild count last changed.
    pub changed_at: Option<std::time::Instant>,
    /// Whether the last change came after the mesh had stood still (it is counted at once).
    pub after_quiet: bool,
    /// The simplification history: (coarsest, current, full) face counts.
    pub lod: Option<(usize, usize, usize)>,
    /// The undo history, oldest first: each entry's label and whether it is undone (redoable).
    pub history: Vec<(String, bool)>,
    /// Bytes the undo history holds.
    pub history_bytes: usize,
    /// The running job: its label, the fraction done and the seconds since it started.
    pub job: Option<(String, f32, f32)>,
    /// The histograms of the active mesh (counted with the statistics).
    pub histograms: Vec<Histogram>,
    /// The quantity the mesh is coloured by: its label, colour map and range (the legend).
    pub colour: Option<(String, ColorMap, Range)>,
}

/// The selected element as shown.
#[derive(Debug, Clone)]
pub struct SelectedView {
    /// Its id.
    pub id: ElementId,
    /// Each relation and where it leads.
    pub relations: Vec<(Relation, Option<ElementId>)>,
    /// Its position (vertices).
    pub position: Option<Vec3>,
    /// Facts: valence, degree, boundary.
    pub facts: Vec<(String, String)>,
}

/// Text fields that keep their contents between frames.
#[derive(Resource, Debug)]
pub struct UiFields {
    /// The path field (open / save as).
    pub path: String,
    /// The "go to id" field.
    pub jump: String,
    /// What Enter in the path field does.
    pub enter_means: PathPurpose,
    /// The path field takes the keyboard next frame.
    pub focus: bool,
}

impl Default for UiFields {
    fn default() -> Self {
        Self {
            path: String::new(),
            jump: String::new(),
            enter_means: PathPurpose::Open,
            focus: false,
        }
    }
}

/// Actions chosen in the panel that need the world (run in the next `Input` set).
#[derive(Resource, Default, Debug)]
pub struct PendingActions(pub Vec<Action>);

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
    let generation = world.resource::<RenderStats>().rebuilds;
    let active = world.resource::<ActiveMesh>().0;
    let mut view = std::mem::take(&mut *world.resource_mut::<InspectorView>());
    match active.filter(|m| world.get::<MeshInfo>(m.0).is_some()) {
        None => view.mesh = None,
        Some(mesh) => refresh_figures(world, &mut view, mesh, generation),
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
    // The value of the quantity on display at a selected vertex.
    if let Some(selected) = view.selected.as_mut()
        && let ElementId::Vertex(v) = selected.id
        && let Some(values) = active.and_then(|mesh| world.get::<VertexValues>(mesh.0))
        && let Some(value) = values.values.get(&v.0)
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
    generation: usize,
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
    let just_changed = view.seen_generation != generation;
    if just_changed {
        view.seen_generation = generation;
        view.after_quiet = quiet(view.changed_at);
        view.changed_at = Some(now);
    }
    let changed = view.stats_generation != generation;
    let due = !just_changed && (view.after_quiet || quiet(view.changed_at));
    if changed && !due {
        world.write_message(bevy::window::RequestRedraw);
    }
    let stale = changed && !dragging && due;
    if view.mesh.is_none() || stale {
        super::mesh_figures::count(
            world,
            &mut view.mesh,
            &mut view.histograms,
            mesh,
            generation,
        );
        view.stats_generation = generation;
        view.after_quiet = false;
    }
    super::mesh_figures::collect(world, &mut view.mesh, &mut view.histograms, generation);
    if std::mem::take(&mut world.resource_mut::<UiState>().check_validity) {
        super::mesh_figures::check_validity(world, &mut view.mesh, mesh);
    }
}

/// The undo history, the simplification's levels and the job or opening under way.
fn show_history_and_work(world: &World, view: &mut InspectorView) {
    view.lod = world.resource::<SimplificationHistory>().levels();
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

fn shortcut_label(action: Action) -> &'static str {
    crate::editor::input::keyboard::keys_of(action).unwrap_or("")
}

/// Draws the panels and turns clicks into requests.
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
        ResMut<super::panel_sections::PanelSections>,
    ),
    density: Res<crate::editor::view::readability::WireframeDensity>,
    mut captured: ResMut<KeyboardCaptured>,
    mut pointer: ResMut<crate::editor::gestures::drag::PointerCaptured>,
    mut insets: ResMut<crate::editor::view::scene::PanelInsets>,
    confirm: Res<crate::editor::session::requests::ConfirmDiscard>,
    mut colour_by: ResMut<ColorBy>,
    mut pending: ResMut<PendingActions>,
    mut anchors: ResMut<crate::editor::gestures::transform::Anchors>,
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
                if let Some(job) = &view.job {
                    job_progress(ui, job, &mut requests);
                }
                sections.show(ui, "File", |ui| {
                    file_section(ui, &mut fields, &mut ui_state, &mut requests);
                });
                sections.show(ui, "Mesh", |ui| {
                    mesh_section(ui, &view, &mut ui_state.check_validity);
                    let mut view_settings = *settings;
                    view_toggles(ui, (&mut view_settings, &density), &mut pending);
                    settings.set_if_neq(view_settings);
                    budget_row(ui);
                });
                sections.show(ui, "Selection", |ui| {
                    selection_controls(ui, &mut mode, &mut pending);
                });
                sections.show(ui, "Element", |ui| {
                    selection_section(ui, &view, &mut fields, &mut requests);
                });
                sections.show(ui, "Modelling", |ui| {
                    modelling_section(ui, &mut ui_state, &mut pending);
                });
                sections.show(ui, "Local operations", |ui| {
                    local_section(ui, &mut ui_state, &mut pending);
                });
                sections.show(ui, "Whole mesh", |ui| {
                    // The registered operations and step mode (see registered_operations).
                    registered_operations(ui, &mut ui_state, &mut pending, Section::WholeMesh);
                    if let Some(lod) = view.lod {
                        level_of_detail(ui, lod, &mut requests);
                    }
                });
                sections.show(ui, "Shape", |ui| {
                    shape_section(ui, &mut ui_state, &mut anchors, &mut pending);
                });
                sections.show(ui, "UV", |ui| uv_section(ui, &mut ui_state, &mut pending));
                sections.show(ui, "Analysis", |ui| {
                    colour_section(ui, &view, &mut colour_by, &mut ui_state.histograms);
                });
                sections.show(ui, "History", |ui| history_section(ui, &view, &mut pending));
                sections.show(ui, "Log", |ui| {
                    for entry in log.entries.iter().rev().take(30) {
                        let text = match &entry.result {
                            Ok(s) => format!("✔ {}: {s}", entry.request),
                            Err(r) => format!("x {}: {r}", entry.request),
                        };
                        ui.label(egui::RichText::new(text).small());
                    }
                });
            });
        });

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
    requests: &mut MessageWriter<Request>,
) {
    ui.horizontal(|ui| {
        let text = format!("{label}: {:.0} % ({seconds:.1} s)", fraction * 100.0);
        let bar = egui::ProgressBar::new(*fraction).text(text).animate(true);
        ui.add(bar.desired_width(ui.available_width() - 70.0));
        if ui.button("Cancel").clicked() {
            requests.write(Request::CancelJob);
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

fn file_section(
    ui: &mut egui::Ui,
    fields: &mut UiFields,
    ui_state: &mut UiState,
    requests: &mut MessageWriter<Request>,
) {
    // Ctrl+O / Ctrl+Shift+S focus the field; Enter then opens or saves, as the key asked.
    if let Some(purpose) = ui_state.focus_path.take() {
        fields.enter_means = purpose;
        fields.focus = true;
    }
    let path = PathBuf::from(fields.path.trim());
    let has_path = !fields.path.trim().is_empty();
    ui.horizontal(|ui| {
        let hint = match fields.enter_means {
            PathPurpose::Open => "file path or shape:NAME, Enter opens",
            PathPurpose::SaveAs => "file path, Enter saves",
        };
        let field = ui.add(
            egui::TextEdit::singleline(&mut fields.path)
                .hint_text(hint)
                .desired_width(170.0),
        );
        if std::mem::take(&mut fields.focus) {
            field.request_focus();
        }
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if entered && has_path {
            requests.write(match fields.enter_means {
                PathPurpose::Open => Request::Open(path.clone()),
                PathPurpose::SaveAs => Request::Save(Some(path.clone())),
            });
            fields.enter_means = PathPurpose::Open;
        }
        if ui.button("Open").clicked() && has_path {
            requests.write(Request::Open(path.clone()));
        }
    });
    ui.horizontal(|ui| {
        if ui
            .button(format!("Save ({})", shortcut_label(Action::Save)))
            .clicked()
        {
            requests.write(Request::Save(None));
        }
        let save_as = format!("Save as ({})", shortcut_label(Action::SaveAs));
        if ui.button(save_as).clicked() && has_path {
            requests.write(Request::Save(Some(path.clone())));
        }
    });
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

fn selection_section(
    ui: &mut egui::Ui,
    view: &InspectorView,
    fields: &mut UiFields,
    requests: &mut MessageWriter<Request>,
) {
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(&mut fields.jump)
                .hint_text("go to id: v12v0, h7, e3, f5")
                .desired_width(170.0),
        );
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Go").clicked() || entered {
            match parse_element(&fields.jump) {
                Some(id) => {
                    requests.write(Request::Select(Some(id)));
                }
                None => {
                    fields.jump = format!("not an id: {}", fields.jump);
                }
            }
        }
    });
    if !view.selected_set.is_empty() {
        ui.label(egui::RichText::new(&view.selected_set).strong());
    }
    let Some(sel) = &view.selected else {
        ui.label(
            "Nothing selected: click the mesh (Shift-click adds, B draws a box, A selects all).",
        );
        return;
    };
    let kind = match sel.id {
        ElementId::Vertex(_) => "vertex",
        ElementId::Halfedge(_) => "halfedge",
        ElementId::Edge(_) => "edge",
        ElementId::Face(_) => "face",
        ElementId::Mesh(_) => "mesh",
    };
    ui.label(
        egui::RichText::new(format!("{kind} {}", sel.id))
            .strong()
            .monospace(),
    );
    egui::Grid::new("relations").num_columns(2).show(ui, |ui| {
        for (relation, target) in &sel.relations {
            // E and F go to a halfedge's edge and face (the keys extrude and fill otherwise).
            let key = crate::editor::input::keyboard::keys_of(Action::Navigate(*relation)).or(
                match (sel.id, relation) {
                    (ElementId::Halfedge(_), Relation::Edge) => Some("E"),
                    (ElementId::Halfedge(_), Relation::Face) => Some("F"),
                    _ => None,
                },
            );
            ui.label(match key {
                Some(key) => format!("{} ({key})", relation.name()),
                None => relation.name().to_string(),
            });
            match target {
                Some(t) => {
                    if ui
                        .link(egui::RichText::new(t.to_string()).monospace())
                        .clicked()
                    {
                        requests.write(Request::Select(Some(*t)));
                    }
                }
                None => {
                    ui.label("— (boundary)");
                }
            }
            ui.end_row();
        }
        for (k, v) in &sel.facts {
            ui.label(k);
            ui.monospace(v);
            ui.end_row();
        }
    });
    if let (Some(p), ElementId::Vertex(v)) = (sel.position, sel.id) {
        let mut q = p;
        ui.horizontal(|ui| {
            ui.label("position");
            let speed = 0.002;
            let changed = ui
                .add(egui::DragValue::new(&mut q.x).speed(speed).prefix("x "))
                .changed()
                | ui.add(egui::DragValue::new(&mut q.y).speed(speed).prefix("y "))
                    .changed()
                | ui.add(egui::DragValue::new(&mut q.z).speed(speed).prefix("z "))
                    .changed();
            if changed && q != p {
                requests.write(Request::Edit(Edit::Move(vec![(v, q)])));
            }
        });
    }
}

/// Undo / redo buttons and the list of entries, the newest first; undone ones are greyed.
fn history_section(ui: &mut egui::Ui, view: &InspectorView, pending: &mut PendingActions) {
    let done = view.history.iter().filter(|(_, undone)| !undone).count();
    ui.horizontal(|ui| {
        let undo = format!("Undo ({})", shortcut_label(Action::Undo));
        if ui.add_enabled(done > 0, egui::Button::new(undo)).clicked() {
            pending.0.push(Action::Undo);
        }
        let redo = format!("Redo ({})", shortcut_label(Action::Redo));
        let can_redo = done < view.history.len();
        if ui.add_enabled(can_redo, egui::Button::new(redo)).clicked() {
            pending.0.push(Action::Redo);
        }
    });
    let bytes = view.history_bytes as f64;
    let held = if bytes < 1e6 {
        format!("{:.1} kB", bytes / 1e3)
    } else {
        format!("{:.1} MB", bytes / 1e6)
    };
    ui.label(egui::RichText::new(format!("{} step(s), {held}", view.history.len())).small());
    for (label, undone) in view.history.iter().rev().take(12) {
        let text = egui::RichText::new(label).small();
        ui.label(if *undone { text.weak().italics() } else { text });
    }
}

/// A button that runs `action`, its keys beside its name.
fn button(
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

/// The registered operations ([`crate::ops::OPERATIONS`]) that declare `section` as theirs,
/// drawn from their declarations: a button each (its help line on hover), after the fields of
/// its parameters, whose values the button and the key use. Those without parameters share
/// one row.
fn registered_operations(
    ui: &mut egui::Ui,
    state: &mut UiState,
    pending: &mut PendingActions,
    section: Section,
) {
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
fn parameter_field(
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

/// A row of [`button`]s.
fn buttons(ui: &mut egui::Ui, pending: &mut PendingActions, row: &[(Action, &str)]) {
    ui.horizontal_wrapped(|ui| {
        for &(action, name) in row {
            button(ui, pending, action, name);
        }
    });
}

/// What a click selects, and the selection's own operations.
fn selection_controls(ui: &mut egui::Ui, mode: &mut SelectMode, pending: &mut PendingActions) {
    ui.horizontal(|ui| {
        ui.label("click selects");
        for m in [
            SelectMode::Auto,
            SelectMode::Vertex,
            SelectMode::Edge,
            SelectMode::Face,
            SelectMode::Halfedge,
        ] {
            ui.selectable_value(mode, m, m.name());
        }
    });
    buttons(
        ui,
        pending,
        &[
            (Action::SelectAll, "All"),
            (Action::SelectNone, "None"),
            (Action::Grow, "More"),
            (Action::Shrink, "Less"),
            (Action::BoxSelect, "Box"),
        ],
    );
    ui.label("Alt-click: an edge loop; Ctrl+Alt-click: an edge ring.");
}

/// How the mesh is drawn: shading, wireframe, halfedge arrows, the UV checkerboard.
fn view_toggles(
    ui: &mut egui::Ui,
    (settings, density): (
        &mut ViewSettings,
        &crate::editor::view::readability::WireframeDensity,
    ),
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

/// Blender's edit-mode operations on the selection.
fn modelling_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    buttons(
        ui,
        pending,
        &[
            (Action::Grab, "Move"),
            (Action::Rotate, "Rotate"),
            (Action::Scale, "Scale"),
            (Action::DeleteMesh, "Delete mesh"),
        ],
    );
    registered_operations(ui, state, pending, Section::Modelling);
}

/// The local operations of the halfedge mesh on the selected element: the registered ones
/// that declare this section, then the editor's own.
fn local_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    registered_operations(ui, state, pending, Section::Local);
    buttons(ui, pending, &[(Action::Frame, "Frame")]);
}

/// The level-of-detail slider of a simplified mesh (its coarsest, current and full face
/// counts): a drag moves along the simplification history.
fn level_of_detail(
    ui: &mut egui::Ui,
    (coarsest, now, full): (usize, usize, usize),
    requests: &mut MessageWriter<Request>,
) {
    let mut faces = now;
    let slider = egui::Slider::new(&mut faces, coarsest..=full).text("faces (level of detail)");
    if ui.add(slider).changed() && faces != now {
        let refine = crate::ops::decimate::Refine::to(Some(faces));
        requests.write(Request::Edit(Edit::Operation(refine)));
    }
}

/// Shaping the surface: fairing, holes filled fair, proportional editing, handle deformation.
fn shape_section(
    ui: &mut egui::Ui,
    state: &mut UiState,
    anchors: &mut crate::editor::gestures::transform::Anchors,
    pending: &mut PendingActions,
) {
    registered_operations(ui, state, pending, Section::Shape);
    button(ui, pending, Action::FillFair, "Fill hole fair");
    ui.horizontal_wrapped(|ui| {
        let p = &mut state.proportional;
        ui.checkbox(
            &mut p.enabled,
            format!(
                "proportional ({})",
                shortcut_label(Action::ToggleProportional)
            ),
        );
        egui::ComboBox::from_id_salt("falloff")
            .selected_text(p.falloff.name())
            .show_ui(ui, |ui| {
                for &(falloff, name) in Falloff::ALL {
                    ui.selectable_value(&mut p.falloff, falloff, name);
                }
            });
        ui.add(
            egui::DragValue::new(&mut p.radius)
                .range(1e-6..=f32::MAX)
                .speed(0.001)
                .prefix("r "),
        );
        ui.checkbox(&mut p.connected, "connected");
    });
    // Handle deformation: the anchors, and how the rest follows a transform of the handle.
    ui.horizontal_wrapped(|ui| {
        button(ui, pending, Action::MarkAnchors, "Anchors");
        ui.label(format!("{} anchored", anchors.vertices.len()));
        egui::ComboBox::from_id_salt("deform method")
            .selected_text(anchors.method.name())
            .show_ui(ui, |ui| {
                for &(method, name) in DeformMethod::ALL {
                    ui.selectable_value(&mut anchors.method, method, name);
                }
            });
        if ui.button("Clear anchors").clicked() {
            anchors.vertices.clear();
            anchors.progress = None;
        }
    });
    if let Some(progress) = anchors.progress {
        ui.label(format!("last deformation: {progress}"));
    }
}

/// Parameterization (its method and boundary, declared), seams, the UV view.
fn uv_section(ui: &mut egui::Ui, state: &mut UiState, pending: &mut PendingActions) {
    registered_operations(ui, state, pending, Section::Uv);
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut state.uv_view, "UV view");
    });
}

/// Colour by a quantity: the choice, and the legend (the map from its low to its high value, as
/// clamped).
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
                for &(q, _) in Quantity::ALL {
                    ui.selectable_value(&mut colour_by.0, Some(q), q.label());
                }
            });
        ui.checkbox(histograms, "histograms");
    });
    if let Some((label, map, range)) = &view.colour {
        legend(ui, label, *map, *range);
    }
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
