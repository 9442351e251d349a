//! The Bevy application: one plugin per concern, stages as named system sets.
//!
//! ```text
//!  Input ──► Request ──► Apply ──► Sync ──► Ui
//!  keys      picks →     the one   render    egui panel,
//!  → requests requests   system    copies,   status line
//!                        that      overlay
//!                        edits
//! ```
//!
//! [`EditorLogicPlugin`] holds everything that runs without a window (the headless tests use it
//! with `MinimalPlugins`); [`EditorWindowPlugin`] adds the camera, picking observers, gizmos and
//! the egui panels. [`run`] starts the whole editor.

pub mod apply;
pub mod automation;
pub mod box_select;
pub mod colouring;
pub mod dialog;
pub mod drag;
pub mod finish;
pub mod frame_stats;
pub mod history;
pub mod input;
pub mod jobs;
pub mod mesh_figures;
pub mod opening;
pub mod overlay;
pub mod pacing;
pub mod panel_sections;
pub mod picking;
pub mod plots;
pub mod readability;
pub mod recovery;
pub mod render_sync;
pub mod requests;
pub mod scene;
pub mod select_many;
pub mod selection;
pub mod session;
pub mod stencil_view;
pub mod step_view;
pub mod stepping;
pub mod surface;
pub mod transform;
pub mod ui;
pub mod uv_view;

use bevy::prelude::*;
use std::path::PathBuf;

use requests::{EditOutcome, OutcomeLog, Request};
use selection::{ActiveMesh, Hover, SelectMode, Selection};

/// The editor's stages, in order, in `Update`.
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub enum EditorSystems {
    /// Keys become requests.
    Input,
    /// Picks become requests.
    Request,
    /// Requests are applied, outcomes written.
    Apply,
    /// Render copies and the overlay follow the meshes.
    Sync,
    /// The panels read the result.
    Ui,
}

/// The model file the editor opens when none is given.
pub const DEFAULT_MODEL: &str = "assets/torus.obj";

/// Everything that needs no window: messages, resources, and the systems from keys to render
/// data. `Assets<Mesh>` must exist (add `AssetPlugin` and `bevy::mesh::MeshPlugin`).
pub struct EditorLogicPlugin;

impl Plugin for EditorLogicPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<Request>()
            .add_message::<EditOutcome>()
            // The window plugin adds it too; headless, a test writes it.
            .add_message::<bevy::window::FileDragAndDrop>()
            .add_message::<picking::PickRequest>()
            .init_resource::<Selection>()
            .init_resource::<Hover>()
            .init_resource::<SelectMode>()
            .init_resource::<ActiveMesh>()
            .init_resource::<OutcomeLog>()
            .init_resource::<session::SimplificationHistory>()
            .init_resource::<session::PreviousShape>()
            .init_resource::<history::UndoHistory>()
            .init_resource::<jobs::Jobs>()
            .init_resource::<jobs::JobSettings>()
            .init_resource::<opening::Opening>()
            .init_resource::<mesh_figures::Counting>()
            .init_resource::<requests::ConfirmDiscard>()
            .init_resource::<render_sync::ViewSettings>()
            .init_resource::<colouring::ColorBy>()
            .init_resource::<render_sync::RenderStats>()
            .init_resource::<overlay::Overlay>()
            .init_resource::<readability::WireframeDensity>()
            .init_resource::<input::KeyboardCaptured>()
            .init_resource::<input::UiState>()
            .init_resource::<uv_view::UvLayout>()
            .init_resource::<transform::Gestures>()
            .init_resource::<transform::Anchors>()
            .init_resource::<box_select::BoxSelect>()
            .init_resource::<stepping::Stepping>()
            .init_resource::<step_view::StepView>()
            .init_resource::<recovery::Autosave>()
            .init_resource::<recovery::RecoveryOffer>()
            .add_systems(Startup, recovery::find_recovery)
            .configure_sets(
                Update,
                (
                    EditorSystems::Input,
                    EditorSystems::Request,
                    EditorSystems::Apply,
                    EditorSystems::Sync,
                    EditorSystems::Ui,
                )
                    .chain(),
            )
            .add_systems(
                Update,
                (
                    (
                        history::track_presses,
                        transform::drive_gesture,
                        input::keyboard_shortcuts,
                    )
                        .chain()
                        .in_set(EditorSystems::Input),
                    // Whatever has the keyboard: a file dropped on the window opens.
                    open_dropped_files.in_set(EditorSystems::Input),
                    picking::resolve_picks.in_set(EditorSystems::Request),
                    (
                        jobs::finish_jobs,
                        opening::finish_opening,
                        apply::apply_requests,
                        recovery::autosave,
                    )
                        .chain()
                        .in_set(EditorSystems::Apply),
                    (
                        colouring::update_vertex_values,
                        render_sync::sync_render_meshes,
                        overlay::gather_overlay,
                        step_view::gather_step_overlay,
                        uv_view::refresh_uv_layout,
                    )
                        .chain()
                        .in_set(EditorSystems::Sync),
                    step_view::snapshot_steps.in_set(EditorSystems::Ui),
                ),
            );
    }
}

/// The windowed part: scene, camera controls, picking observers, gizmos, file drops, panels.
pub struct EditorWindowPlugin {
    /// The file to open at start-up.
    pub open: Option<PathBuf>,
}

impl Plugin for EditorWindowPlugin {
    fn build(&self, app: &mut App) {
        let open = self.open.clone();
        app.init_gizmo_group::<overlay::HighlightGizmos>()
            .add_systems(Startup, (scene::setup_scene, overlay::configure_gizmos))
            .add_systems(Startup, move |mut requests: MessageWriter<Request>| {
                if let Some(path) = open.clone() {
                    requests.write(Request::Open(path));
                }
            })
            .add_systems(
                Update,
                (
                    scene::orbit_controls
                        .run_if(|k: Res<input::KeyboardCaptured>| !k.0)
                        .in_set(EditorSystems::Input),
                    frame_new_meshes
                        .after(EditorSystems::Apply)
                        .before(EditorSystems::Sync),
                    scene::fit_near_plane.after(frame_new_meshes),
                    overlay::draw_overlay.after(EditorSystems::Sync),
                    readability::show_readable_wireframes
                        .after(EditorSystems::Sync)
                        .before(EditorSystems::Ui),
                ),
            )
            .init_resource::<automation::PendingShots>()
            .init_resource::<dialog::OpenDialog>()
            .insert_resource(pacing::settings(None))
            .add_systems(Update, pacing::keep_drawing.in_set(EditorSystems::Ui))
            .add_systems(
                PreUpdate,
                pacing::drop_unchanged_modifiers
                    .after(bevy_egui::EguiPreUpdateSet::ProcessInput)
                    .before(bevy_egui::EguiPreUpdateSet::BeginPass),
            )
            .add_systems(Update, apply::close_requested.in_set(EditorSystems::Input))
            .add_systems(Update, dialog::receive.in_set(EditorSystems::Input))
            .init_resource::<drag::VertexDrag>()
            .init_resource::<scene::PanelInsets>()
            .add_systems(Update, scene::fit_camera_viewport.in_set(EditorSystems::Ui))
            .init_resource::<drag::PointerCaptured>()
            .add_systems(
                Update,
                (box_select::drive_box_select, drag::drive_vertex_drag)
                    .chain()
                    .after(transform::drive_gesture)
                    .before(input::keyboard_shortcuts)
                    .in_set(EditorSystems::Input),
            )
            .add_systems(bevy_egui::EguiPrimaryContextPass, box_select::draw_box)
            .add_systems(
                bevy_egui::EguiPrimaryContextPass,
                (step_view::step_window, recovery::offer_window).after(ui::panels),
            )
            .add_systems(
                Update,
                automation::run_script
                    .in_set(EditorSystems::Input)
                    .before(input::keyboard_shortcuts),
            )
            .add_plugins(surface::SurfacePlugin)
            .add_observer(picking::on_click)
            .add_observer(picking::on_move)
            .add_observer(picking::on_out)
            .add_plugins(ui::UiPlugin);
    }
}

/// Opens files dropped on the window, as Ctrl+O would (unsaved changes are asked about first).
fn open_dropped_files(
    mut drops: MessageReader<bevy::window::FileDragAndDrop>,
    mut requests: MessageWriter<Request>,
) {
    for drop in drops.read() {
        if let bevy::window::FileDragAndDrop::DroppedFile { path_buf, .. } = drop {
            requests.write(Request::Open(path_buf.clone()));
        }
    }
}

/// Frames a mesh the first time it becomes the active one.
fn frame_new_meshes(world: &mut World, mut last: Local<Option<crate::mesh::MeshId>>) {
    let active = world.resource::<ActiveMesh>().0;
    if active != *last {
        *last = active;
        if active.is_some() {
            scene::frame_selection(world);
        }
    }
}

/// An app with the editor's logic and no window (`MinimalPlugins`, input, assets, meshes and
/// [`EditorLogicPlugin`]), not yet updated: what the headless tests and the editor benches
/// start from.
pub fn headless_app() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        bevy::input::InputPlugin,
        AssetPlugin::default(),
        bevy::mesh::MeshPlugin,
        EditorLogicPlugin,
    ));
    app
}

/// Runs the editor until its window closes; returns the process exit code. Opens `path`, or
/// the default model.
pub fn run(path: Option<PathBuf>) -> i32 {
    let open = path.or_else(|| {
        let default = PathBuf::from(DEFAULT_MODEL);
        Some(if default.exists() {
            default
        } else {
            PathBuf::from("shape:torus")
        })
    });
    let script = match std::env::var("PAPPUS_SCRIPT") {
        Ok(text) => match automation::Script::parse(&text) {
            Ok(script) => Some(script),
            Err(e) => {
                eprintln!("pappus: PAPPUS_SCRIPT: {e}");
                return 2;
            }
        },
        Err(_) => None,
    };
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "Pappus".into(),
            resolution: (1280u32, 800u32).into(),
            ..default()
        }),
        ..default()
    }))
    .add_plugins((
        MeshPickingPlugin,
        bevy_egui::EguiPlugin::default(),
        EditorLogicPlugin,
        EditorWindowPlugin { open },
    ));
    if std::env::var_os("PAPPUS_FRAME_STATS").is_some() {
        app.add_plugins(frame_stats::FrameStatsPlugin);
    }
    if let Some(script) = script {
        app.insert_resource(script);
    }
    // Unsaved work goes to a recovery file once the editor is idle after an edit, and a panic
    // finishes a recovery write in flight before the process ends.
    app.insert_resource(recovery::Autosave::into_folder(crate::recovery::folder()));
    recovery::install_panic_hook();
    let exit = app.run();
    match exit {
        AppExit::Success => 0,
        AppExit::Error(code) => i32::from(code.get()),
    }
}
