//! The 3D scene around the meshes: the orbit camera's state, the light and the surface
//! material, and the camera's fit to the window beside the panels. The controls that move the
//! camera are gestures ([`crate::editor::gestures::camera`]).

use bevy::camera::CameraOutputMode;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::math::{EulerRot, Quat, Vec3};
use bevy::prelude::*;
use bevy::render::renderer::RenderAdapterInfo;

use super::lines::{DEPTH_PULL, LinesMaterial};
use super::surface::SurfaceMaterial;

/// The orbit camera's state: it looks at `focus` from `radius` away, turned by `yaw`/`pitch`.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub focus: Vec3,
    /// Distance from the focus.
    pub radius: f32,
    /// Turn around the vertical axis, radians.
    pub yaw: f32,
    /// Turn up or down, radians (kept within ±89°).
    pub pitch: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            focus: Vec3::ZERO,
            radius: 4.0,
            yaw: 0.6,
            pitch: -0.35,
        }
    }
}

impl OrbitCamera {
    /// The camera transform this state gives.
    pub fn transform(&self) -> Transform {
        let rotation = Quat::from_euler(EulerRot::YXZ, self.yaw, self.pitch, 0.0);
        Transform::from_translation(self.focus + rotation * Vec3::new(0.0, 0.0, self.radius))
            .looking_at(self.focus, Vec3::Y)
    }
}

/// The surface colour of meshes (when no quantity is shown).
pub const SURFACE_COLOR: Color = Color::srgb(0.78, 0.74, 0.66);
/// The colour of back faces (seen through holes, or on faces turned the wrong way).
pub const BACK_COLOR: Color = Color::srgb(0.42, 0.47, 0.58);

/// Materials shared by every mesh.
#[derive(Resource, Debug, Clone)]
pub struct SceneMaterials {
    /// The surface of meshes, both sides drawn.
    pub surface: Handle<SurfaceMaterial>,
    /// The same surface with back faces left undrawn, for a mesh none of whose back faces can
    /// be seen (see [`super::culling`]).
    pub surface_culled: Handle<SurfaceMaterial>,
    /// The wireframe's lines.
    pub wireframe: Handle<LinesMaterial>,
}

/// Width of the wireframe's lines on screen, in pixels.
pub const WIREFRAME_WIDTH_PX: f32 = 1.0;

/// Spawns the camera and makes the materials. There are no lights: the surface material
/// carries its own, fixed to the camera (see [`super::surface`]), and Bevy's light clustering
/// runs on the CPU, where it has nothing to do. No tonemapping or dithering either: colours
/// (and colour maps) show as given, and a full-window pass is saved.
pub fn setup_scene(
    mut commands: Commands,
    clusters: Option<ResMut<bevy::light::cluster::GlobalClusterSettings>>,
    mut materials: ResMut<Assets<SurfaceMaterial>>,
    mut lines: ResMut<Assets<LinesMaterial>>,
) {
    // Bevy assigns lights to clusters on the GPU where it can: passes that cost a software
    // rasterizer 0.6–0.8 ms a frame, and the opaque pass about 1 ms more, for a scene without
    // lights. On the CPU, one cluster and no light cost nothing.
    if let Some(mut clusters) = clusters {
        clusters.gpu_clustering = None;
    }
    let orbit = OrbitCamera::default();
    commands.spawn((
        Camera3d::default(),
        // The panels' camera (order 1) draws over this one's picture and writes the window once.
        Camera {
            output_mode: CameraOutputMode::Skip,
            ..default()
        },
        orbit.transform(),
        orbit,
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        // No light to assign to clusters (the surface carries its own, see `surface`): one
        // cluster keeps Bevy's clustering passes small. (`ClusterConfig::None` fails wgpu's
        // validation in Bevy 0.19.)
        bevy::light::cluster::ClusterConfig::Single,
    ));
    commands.insert_resource(ClearColor(Color::srgb(0.32, 0.34, 0.38)));
    let surface = SurfaceMaterial {
        color: SURFACE_COLOR.into(),
        back_color: BACK_COLOR.into(),
        cull_back_faces: false,
    };
    commands.insert_resource(SceneMaterials {
        surface_culled: materials.add(SurfaceMaterial {
            cull_back_faces: true,
            ..surface.clone()
        }),
        surface: materials.add(surface),
        wireframe: lines.add(LinesMaterial {
            width: WIREFRAME_WIDTH_PX,
            depth_pull: DEPTH_PULL,
        }),
    });
}

/// Keeps the near plane a hundredth of the distance to what the camera looks at: Bevy's
/// default of 0.1 cut through small meshes (the bunny is 0.25 across) as soon as the camera
/// came close to a vertex. Writes only when it changes, so an idle editor stays idle.
pub fn fit_near_plane(mut cameras: Query<(&OrbitCamera, &mut Projection)>) {
    for (orbit, mut projection) in &mut cameras {
        let near = (orbit.radius * 0.01).clamp(1.0e-6, 0.1);
        if let Projection::Perspective(p) = &*projection
            && p.near != near
        {
            let Projection::Perspective(p) = &mut *projection else {
                unreachable!()
            };
            p.near = near;
        }
    }
}

/// Changes every orbit camera's state with `change` and places the camera where it now says.
pub fn move_orbit(world: &mut World, change: impl Fn(&mut OrbitCamera)) {
    let mut cameras = world.query::<(&mut OrbitCamera, &mut Transform)>();
    for (mut orbit, mut transform) in cameras.iter_mut(world) {
        change(&mut orbit);
        *transform = orbit.transform();
    }
}

/// How much of the window the panels cover, in logical pixels (set by the UI).
#[derive(Resource, Default, Debug, Clone, Copy, PartialEq)]
pub struct PanelInsets {
    /// Width of the left panel.
    pub left: f32,
    /// Height of the bottom status line.
    pub bottom: f32,
    /// Width kept free on the right (the UV view, so the mesh is seen beside it).
    pub right: f32,
}

/// Renders the 3D view only where the panels are not, so the mesh is centred in what is seen.
pub fn fit_camera_viewport(
    insets: Res<PanelInsets>,
    windows: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut cameras: Query<&mut Camera, With<OrbitCamera>>,
) {
    let Some(window) = windows.iter().next() else {
        return;
    };
    let scale = window.scale_factor();
    let (w, h) = (window.physical_width(), window.physical_height());
    let left = ((insets.left * scale) as u32).min(w.saturating_sub(1));
    let bottom = ((insets.bottom * scale) as u32).min(h.saturating_sub(1));
    // The right inset never takes the view below a quarter of what the left panel leaves.
    let right = ((insets.right * scale) as u32).min((w - left) * 3 / 4);
    let viewport = bevy::camera::Viewport {
        physical_position: UVec2::new(left, 0),
        physical_size: UVec2::new((w - left - right).max(1), (h - bottom).max(1)),
        ..default()
    };
    for mut camera in &mut cameras {
        let same = camera.viewport.as_ref().is_some_and(|v| {
            v.physical_position == viewport.physical_position
                && v.physical_size == viewport.physical_size
        });
        if !same {
            camera.viewport = Some(viewport.clone());
        }
    }
}

/// Whether the frames are drawn by a software rasterizer (a CPU adapter): the only renderer
/// that culls back faces (see [`super::culling`]). Absent, none is.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SoftwareRenderer(pub bool);

/// Reads the adapter's kind into [`SoftwareRenderer`] (at startup).
pub fn detect_software_renderer(mut commands: Commands, adapter: Option<Res<RenderAdapterInfo>>) {
    let software = adapter.is_some_and(|info| info.device_type == wgpu_types::DeviceType::Cpu);
    commands.insert_resource(SoftwareRenderer(software));
}
