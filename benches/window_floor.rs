//! The floor under the editor's frame: what Bevy itself costs a frame on this machine, with no
//! mesh, no overlay and no editor systems.
//!
//! The editor's frame time (`benches/frame_time.sh`) is the sum of its own work and Bevy's fixed
//! work per frame: the render graph, the copy of the camera's texture to the window, presenting
//! the frame. Under a software rasterizer (Mesa's lavapipe) that fixed work is not small, and no
//! change in Pappus can take the frame below it. This bench measures it in the same window the
//! editor opens (1280×800, `DefaultPlugins`), in three steps that add what the editor cannot do
//! without:
//!
//! - `clear`: one 3D camera that clears the window (no MSAA, no tonemapping, light clustering
//!   on the CPU as the editor has it), nothing to draw;
//! - `cameras`: the editor's two cameras: a 3D camera whose output is skipped and a 2D camera
//!   that writes the window, as `editor::scene` and `editor::ui` set them up;
//! - `panels`: the same, plus egui side and bottom panels with a few lines of text, as the
//!   editor's inspector and status bar.
//!
//! Run it under a display, e.g. `xvfb-run -a -s "-screen 0 1280x800x24" cargo bench --bench
//! window_floor -- panels` (default: all three, one process each, by re-running itself).
//! Each prints `floor <step>: mean frame time X ms over N frames` after `WAIT` frames of
//! settling. `benches/frame_time.sh` prints the `panels` figure beside the editor's.

use bevy::camera::CameraOutputMode;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiGlobalSettings, EguiPlugin, EguiPrimaryContextPass, egui};
use std::time::Instant;

const STEPS: [&str; 3] = ["clear", "cameras", "panels"];
const WAIT: u32 = 15;
const FRAMES: u32 = 40;

/// Frames counted so far and when the measured span began.
#[derive(Resource, Default)]
struct Count {
    frames: u32,
    since: Option<Instant>,
}

#[derive(Resource, Clone, Copy)]
struct Step(&'static str);

fn main() {
    let asked: Vec<&'static str> = std::env::args()
        .skip(1)
        .filter_map(|a| STEPS.iter().copied().find(|s| *s == a))
        .collect();
    if asked.len() == 1 {
        run(asked[0]);
        return;
    }
    // Every step in a process of its own, so each starts from the same fresh window.
    let me = std::env::current_exe().expect("the bench's own path");
    for step in if asked.is_empty() {
        STEPS.to_vec()
    } else {
        asked
    } {
        let status = std::process::Command::new(&me)
            .arg(step)
            .status()
            .expect("the bench runs itself");
        assert!(status.success(), "window_floor {step} failed: {status}");
    }
}

fn run(step: &'static str) {
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "Pappus window floor".into(),
            resolution: (1280u32, 800u32).into(),
            ..default()
        }),
        ..default()
    }))
    .insert_resource(Step(step))
    .init_resource::<Count>()
    .add_systems(Startup, setup)
    .add_systems(Update, count);
    if step == "panels" {
        app.add_plugins(EguiPlugin::default())
            .add_systems(EguiPrimaryContextPass, panels);
        app.world_mut()
            .resource_mut::<EguiGlobalSettings>()
            .auto_create_primary_context = false;
    }
    app.run();
}

fn setup(
    mut commands: Commands,
    step: Res<Step>,
    clusters: Option<ResMut<bevy::light::cluster::GlobalClusterSettings>>,
) {
    // As the editor: no light, so no clustering pass.
    if let Some(mut clusters) = clusters {
        clusters.gpu_clustering = None;
    }
    let two_cameras = step.0 != "clear";
    commands.spawn((
        Camera3d::default(),
        Camera {
            output_mode: if two_cameras {
                CameraOutputMode::Skip
            } else {
                CameraOutputMode::default()
            },
            clear_color: ClearColorConfig::Custom(Color::srgb(0.12, 0.12, 0.14)),
            ..default()
        },
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        // As the editor's camera: one light cluster.
        bevy::light::cluster::ClusterConfig::Single,
        Transform::from_xyz(0.0, 0.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    if two_cameras {
        let mut second = commands.spawn((
            Camera2d,
            Camera {
                order: 1,
                clear_color: ClearColorConfig::None,
                ..default()
            },
            RenderLayers::layer(31),
            Msaa::Off,
            Tonemapping::None,
            DebandDither::Disabled,
        ));
        if step.0 == "panels" {
            second.insert(bevy_egui::PrimaryEguiContext);
        }
    }
}

fn panels(mut contexts: EguiContexts) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let mut root = egui::Ui::new(
        ctx.clone(),
        "root".into(),
        egui::UiBuilder::new()
            .layer_id(egui::LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );
    egui::Panel::bottom("status").show(&mut root, |ui| {
        ui.label("288 faces · 576 edges · 288 vertices");
    });
    egui::Panel::left("inspector")
        .default_size(300.0)
        .show(&mut root, |ui| {
            ui.heading("Inspector");
            for line in 0..12 {
                ui.label(format!("line {line}: v12 → h40 → e7 → f3"));
            }
        });
    Ok(())
}

fn count(mut state: ResMut<Count>, step: Res<Step>, mut exit: MessageWriter<AppExit>) {
    state.frames += 1;
    if state.frames == WAIT {
        state.since = Some(Instant::now());
    } else if state.frames == WAIT + FRAMES
        && let Some(since) = state.since
    {
        let ms = since.elapsed().as_secs_f64() * 1000.0 / f64::from(FRAMES);
        println!(
            "floor {}: mean frame time {ms:.1} ms over {FRAMES} frames",
            step.0
        );
        exit.write(AppExit::Success);
    }
}
