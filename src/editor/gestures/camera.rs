//! Camera navigation: mouse orbit, pan and zoom, and framing the selection.
//!
//! Controls follow Blender: middle- or right-drag orbits, Shift + drag pans, the wheel zooms,
//! `.` or Home frames the selection (or the whole mesh). Nothing moves while egui has the
//! pointer, and the wheel is left to a proportional gesture that uses it for its radius.

use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseButton};
use bevy::math::Vec3;
use bevy::prelude::*;

use crate::editor::session::selection::{ActiveMesh, Selection};
use crate::editor::view::scene::{OrbitCamera, move_orbit};
use crate::mesh::ids::ElementId;
use crate::mesh::topology::MeshRef;

use super::transform::Gestures;

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
    // Framing a stepped run's focus (the next collapse) also turns the camera to face the surface there (it may be on
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
        // In a stepped run, what it asks to frame (the next collapse) and two rings around.
        _ if let focus = crate::editor::pipeline::stepping::focus(world)
            && !focus.is_empty() =>
        {
            let normal: Vec3 = focus.iter().map(|&v| m.vertex_area_vector(v)).sum();
            facing = normal.try_normalize();
            let mut pts = Vec::new();
            for &v in &focus {
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
