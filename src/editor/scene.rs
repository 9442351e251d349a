//! The 3D scene around the meshes: an orbit camera and the surface material.
//!
//! Camera controls follow Blender: middle- or right-drag orbits, Shift + drag pans, the wheel
//! zooms, `.` or Home frames the selection (or the whole mesh). Nothing moves while egui has
//! the pointer.

use bevy::camera::CameraOutputMode;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseButton};
use bevy::math::{EulerRot, Quat, Vec3};
use bevy::prelude::*;

use crate::mesh::ids::ElementId;
use crate::mesh::topology::MeshRef;

use super::selection::{ActiveMesh, Selection};
use super::surface::SurfaceMaterial;
use super::transform::Gestures;

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
    /// The surface of meshes.
    pub surface: Handle<SurfaceMaterial>,
}

/// Spawns the camera and makes the materials. There are no lights: the surface material
/// carries its own, fixed to the camera (see [`super::surface`]). No tonemapping or dithering
/// either: colours (and colour maps) show as given, and a full-window pass is saved.
pub fn setup_scene(mut commands: Commands, mut materials: ResMut<Assets<SurfaceMaterial>>) {
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
    ));
    commands.insert_resource(ClearColor(Color::srgb(0.32, 0.34, 0.38)));
    commands.insert_resource(SceneMaterials {
        surface: materials.add(SurfaceMaterial {
            color: SURFACE_COLOR.into(),
            back_color: BACK_COLOR.into(),
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

/// Mouse orbit, pan and zoom (skipped while egui has the pointer; the wheel does not zoom
/// while a proportional gesture uses it for its radius).
pub fn orbit_controls(
    buttons: Res<ButtonInput<MouseButton>>,
    keys: Res<ButtonInput<KeyCode>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    gestures: Option<Res<Gestures>>,
    mut cameras: Query<(&mut OrbitCamera, &mut Transform)>,
) {
    let wheel_taken = gestures
        .as_ref()
        .and_then(|g| g.active.as_ref())
        .is_some_and(|g| g.follow.is_some());
    let dragging = buttons.pressed(MouseButton::Middle) || buttons.pressed(MouseButton::Right);
    for (mut orbit, mut transform) in &mut cameras {
        let before = *orbit;
        if dragging && motion.delta != Vec2::ZERO {
            if keys.pressed(KeyCode::ShiftLeft) || keys.pressed(KeyCode::ShiftRight) {
                let scale = orbit.radius * 0.0015;
                let right = transform.right();
                let up = transform.up();
                orbit.focus += (-motion.delta.x * *right + motion.delta.y * *up) * scale;
            } else {
                orbit.yaw -= motion.delta.x * 0.006;
                orbit.pitch = (orbit.pitch - motion.delta.y * 0.006).clamp(-1.55, 1.55);
            }
        }
        if scroll.delta.y != 0.0 && !wheel_taken {
            orbit.radius = (orbit.radius * (1.0 - 0.1 * scroll.delta.y.clamp(-3.0, 3.0))).max(1e-3);
        }
        if *orbit != before {
            *transform = orbit.transform();
        }
    }
}

/// Frames the selection, or the whole active mesh when nothing is selected.
pub fn frame_selection(world: &mut World) {
    let Some(mesh) = world.resource::<ActiveMesh>().0 else {
        return;
    };
    if world.get_entity(mesh.0).is_err() {
        return;
    }
    let m = MeshRef::new(world);
    // Framing the next collapse also turns the camera to face the surface there (it may be on
    // the far side of the mesh).
    let mut facing = None;
    let points: Vec<Vec3> = match world.resource::<Selection>().element {
        Some(ElementId::Vertex(v)) if m.try_vertex(v).is_some() => {
            let p = m.position(v);
            let mut pts = vec![p];
            pts.extend(m.vertex_neighbors(v).map(|n| m.position(n)));
            pts
        }
        Some(ElementId::Edge(e)) if m.try_edge(e).is_some() => {
            let (a, b) = m.edge_vertices(e);
            vec![m.position(a), m.position(b)]
        }
        Some(ElementId::Halfedge(h)) if m.try_halfedge(h).is_some() => {
            vec![m.position(m.from_vertex(h)), m.position(m.to_vertex(h))]
        }
        Some(ElementId::Face(f)) if m.try_face(f).is_some() => {
            m.face_vertices(f).map(|v| m.position(v)).collect()
        }
        // In a stepped simplification, the next collapse and the two rings around it.
        _ if let Some(next) = super::stepping::next_collapse(world) => {
            let normal: Vec3 = [next.kept, next.removed]
                .into_iter()
                .flat_map(|v| m.vertex_faces(v))
                .map(|f| m.face_area_vector(f))
                .sum();
            facing = normal.try_normalize();
            let mut pts = Vec::new();
            for v in [next.kept, next.removed] {
                for w in m.vertex_neighbors(v) {
                    pts.extend(m.vertex_neighbors(w).map(|x| m.position(x)));
                }
            }
            pts
        }
        _ => crate::mesh::members::of_kind::<crate::mesh::Vertex, _>(
            world,
            mesh,
            crate::mesh::VertexId,
        )
        .into_iter()
        .map(|v| m.position(v))
        .collect(),
    };
    if points.is_empty() {
        return;
    }
    let (lo, hi) = points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let focus = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() * 1.4).max(0.05);
    move_orbit(world, |orbit| {
        orbit.focus = focus;
        orbit.radius = radius;
        // The camera sits at `(cos p sin y, −sin p, cos p cos y)` from the focus.
        if let Some(n) = facing {
            orbit.pitch = (-n.y).asin().clamp(-1.55, 1.55);
            orbit.yaw = n.x.atan2(n.z);
        }
    });
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
