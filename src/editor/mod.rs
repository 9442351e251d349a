//! The Bevy application, in rooms: each sub-folder owns one concern, has a plugin (and a
//! window plugin for what needs a window) and a module doc that says what it owns. Imports
//! point one way, down this list (`tests/architecture.rs` checks it):
//!
//! ```text
//!  automation   scripts, frame pacing, frame statistics
//!  panels       the egui panel in sections, plots, UV view, step-mode windows
//!  input        the keymap, dropped files
//!  gestures     picking, G/R/S transforms, box select, vertex drag, camera, overlay
//!  view         render copies, colouring, readable wireframes, scene, surface shader
//!  pipeline     apply (the one system that edits), jobs, opening, recovery, step mode
//!  session      requests, selection, undo history, finish, unsaved state, dialogs, stages
//! ```
//!
//! A frame runs the stages of [`EditorSystems`] in order:
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

pub mod automation;
pub mod gestures;
pub mod input;
pub mod panels;
pub mod pipeline;
pub mod session;
pub mod view;

use bevy::prelude::*;
use std::path::PathBuf;

pub use input::add_operation::AddOperation;
use session::requests::Request;
pub use session::schedule::EditorSystems;

/// The model file the editor opens when none is given.
pub const DEFAULT_MODEL: &str = "assets/torus.obj";

/// Everything that needs no window: messages, resources, and the systems from keys to render
/// data, room by room. `Assets<Mesh>` must exist (add `AssetPlugin` and
/// `bevy::mesh::MeshPlugin`).
pub struct EditorLogicPlugin;

impl Plugin for EditorLogicPlugin {
    fn build(&self, app: &mut App) {
        app.configure_sets(
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
        .add_plugins((
            session::SessionPlugin,
            pipeline::PipelinePlugin,
            view::ViewPlugin,
            gestures::GesturesPlugin,
            input::ShortcutsPlugin,
            panels::PanelsPlugin,
        ));
    }
}

/// The windowed part of every room: scene, camera controls, picking observers, gizmos,
/// dialogs, panels, scripts and pacing.
pub struct EditorWindowPlugin {
    /// The file to open at start-up.
    pub open: Option<PathBuf>,
}

impl Plugin for EditorWindowPlugin {
    fn build(&self, app: &mut App) {
        let open = self.open.clone();
        app.add_systems(Startup, move |mut requests: MessageWriter<Request>| {
            if let Some(path) = open.clone() {
                requests.write(Request::Open(path));
            }
        })
        .add_plugins((
            session::SessionWindowPlugin,
            pipeline::PipelineWindowPlugin,
            view::ViewWindowPlugin,
            gestures::GesturesWindowPlugin,
            panels::PanelsWindowPlugin,
            automation::AutomationWindowPlugin,
        ));
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
    run_with(path, |_| {})
}

/// Runs the editor on what a script hands over (`pappus --show REQUEST`, what Python's
/// `pappus.show` runs; [`automation::show`] says what the request holds and what goes back
/// when the window closes). Returns the process exit code: 2 when the request cannot be read.
pub fn run_show(request: &std::path::Path) -> i32 {
    let request = match automation::show::ShowRequest::read(request) {
        Ok(request) => request,
        Err(e) => {
            eprintln!("pappus: --show: {e}");
            return 2;
        }
    };
    let mesh = request.mesh.clone();
    run_with(Some(mesh), move |app| {
        app.add_plugins(automation::show::ShowPlugin { request });
    })
}

/// [`run`], with `extend` given the app before it starts: a lab or a plugin adds its
/// operations there (`app.add_operation(MyFlip)`, [`AddOperation`]), its systems and
/// resources.
pub fn run_with(path: Option<PathBuf>, extend: impl FnOnce(&mut App)) -> i32 {
    let open = path.or_else(|| {
        let default = PathBuf::from(DEFAULT_MODEL);
        Some(if default.exists() {
            default
        } else {
            PathBuf::from("shape:torus")
        })
    });
    let script = match std::env::var("PAPPUS_SCRIPT") {
        Ok(text) => match automation::script::Script::parse(&text) {
            Ok(script) => Some(script),
            Err(e) => {
                eprintln!("pappus: PAPPUS_SCRIPT: {e}");
                return 2;
            }
        },
        Err(_) => None,
    };
    let mut app = App::new();
    let plugins = DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "Pappus".into(),
            resolution: (1280u32, 800u32).into(),
            ..default()
        }),
        ..default()
    });
    // The log's messages are kept for the Log section, a lab's at every level.
    app.add_plugins(plugins.set(bevy::log::LogPlugin {
        filter: session::log_capture::log_filter(),
        custom_layer: session::capture_layer,
        ..default()
    }))
    .add_plugins((
        MeshPickingPlugin,
        bevy_egui::EguiPlugin::default(),
        EditorLogicPlugin,
        EditorWindowPlugin { open },
    ));
    if std::env::var_os("PAPPUS_FRAME_STATS").is_some() {
        app.add_plugins(automation::frame_stats::FrameStatsPlugin);
    }
    if let Some(script) = script {
        app.insert_resource(script);
    }
    extend(&mut app);
    // Unsaved work goes to a recovery file once the editor is idle after an edit, and a panic
    // finishes a recovery write in flight before the process ends.
    app.insert_resource(pipeline::recovery::Autosave::into_folder(
        crate::recovery::folder(),
    ));
    pipeline::recovery::install_panic_hook();
    let exit = app.run();
    match exit {
        AppExit::Success => 0,
        AppExit::Error(code) => i32::from(code.get()),
    }
}
