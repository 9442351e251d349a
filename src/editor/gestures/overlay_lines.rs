//! The overlay's thin lines — halfedge arrows, vertex dots, axis lines — drawn as one mesh in
//! one draw ([`crate::editor::view::lines`]), rebuilt only when the lines change.
//!
//! Under a software rasterizer the overlay's cost goes with the triangles set up, not the
//! pixels they cover: the default torus's 1 152 arrows (five segments each as gizmos, a shaft
//! and four tips) and 288 dots (six each) took 4.2–5.8 ms of a 29–35 ms frame, where the
//! torus's whole surface takes 2 ms. The same segments in one mesh cost about as much, so what
//! saves the time is fewer triangles: an arrow is two segments here (its shaft and one barb)
//! and a dot a filled hexagon of four triangles.
//!
//! [`update_overlay_lines`] compares this frame's thin shapes with the ones drawn and rebuilds
//! the buffer only when they differ: after an edit, a change of the settings or of the
//! selection's neighbourhood. The thick highlights (the selection, the hover) are few and stay
//! gizmos.

use bevy::camera::visibility::NoFrustumCulling;
use bevy::color::LinearRgba;
use bevy::math::Vec3;
use bevy::picking::Pickable;
use bevy::prelude::*;

use super::overlay::{Overlay, Shape, barb};
use crate::editor::view::lines::{DEPTH_PULL, Dot, LinesMaterial, Segment, ThinLines, line_mesh};

/// Width of the thin lines on screen, in pixels.
pub const LINE_WIDTH_PX: f32 = 1.5;

/// Whether a shape is one of the thin shapes this module draws (the rest are gizmos).
pub fn is_thin(shape: &Shape) -> bool {
    matches!(shape, Shape::Line(..) | Shape::Arrow(..) | Shape::Dot(..))
}

/// The thin shapes among `shapes`: a line is one segment, an arrow two (its shaft and one
/// barb, on its face's side), a dot a dot.
pub fn thin_lines(shapes: &[Shape]) -> ThinLines {
    let mut out = ThinLines::default();
    for shape in shapes {
        match *shape {
            Shape::Line(a, b, c) => out.segments.push(fixed(a, b, c)),
            Shape::Arrow(a, b, inside, c) => arrow(a, b, inside, c.into(), &mut out.segments),
            Shape::Dot(centre, radius, c) => out.dots.push(Dot {
                centre,
                radius,
                color: c.into(),
            }),
            _ => {}
        }
    }
    out
}

fn fixed(a: Vec3, b: Vec3, color: impl Into<LinearRgba>) -> Segment {
    Segment {
        ends: [a, b],
        color: color.into(),
    }
}

/// The shaft from `a` to `b` and its [`barb`].
fn arrow(a: Vec3, b: Vec3, inside: Vec3, color: LinearRgba, out: &mut Vec<Segment>) {
    out.push(fixed(a, b, color));
    if let Some(tip) = barb(a, b, inside) {
        out.push(fixed(b, tip, color));
    }
}

/// The entity that draws the thin lines.
#[derive(Component)]
pub struct OverlayLines;

/// Spawns the lines' entity (without a mesh until there are lines; the material is registered
/// by [`crate::editor::view::lines::LinesPlugin`]).
pub struct OverlayLinesPlugin;

impl Plugin for OverlayLinesPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_overlay_lines);
    }
}

fn spawn_overlay_lines(mut commands: Commands, mut materials: ResMut<Assets<LinesMaterial>>) {
    commands.spawn((
        OverlayLines,
        MeshMaterial3d(materials.add(LinesMaterial {
            width: LINE_WIDTH_PX,
            depth_pull: DEPTH_PULL,
        })),
        Transform::IDENTITY,
        Visibility::Hidden,
        // The vertices' positions are segment ends; the shader widens them on screen.
        NoFrustumCulling,
        Pickable::IGNORE,
    ));
}

/// Puts this frame's thin shapes in the lines' mesh when they differ from the ones drawn.
///
/// A mesh without vertices is not drawn, and Bevy's mesh allocator logs an error for one (it
/// has no room to copy it to): the entity gets its mesh with its first lines, and keeps the
/// last one, hidden, while there are none.
pub fn update_overlay_lines(
    overlay: Res<Overlay>,
    mut lines: Query<(Entity, Option<&Mesh3d>, &mut Visibility), With<OverlayLines>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut commands: Commands,
    mut drawn: Local<Vec<Shape>>,
) {
    let Ok((entity, mesh, mut visibility)) = lines.single_mut() else {
        return;
    };
    let thin = overlay.shapes.iter().filter(|s| is_thin(s));
    if thin.clone().eq(drawn.iter()) {
        return;
    }
    *drawn = thin.copied().collect();
    *visibility = if drawn.is_empty() {
        Visibility::Hidden
    } else {
        Visibility::Inherited
    };
    if drawn.is_empty() {
        return;
    }
    let lines = line_mesh(&thin_lines(&drawn));
    match mesh {
        Some(mesh) => {
            if let Err(e) = meshes.insert(&mesh.0, lines) {
                bevy::log::warn!("overlay lines not redrawn: {e}");
            }
        }
        None => {
            commands.entity(entity).insert(Mesh3d(meshes.add(lines)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::color::Color;

    #[test]
    fn an_arrow_is_its_shaft_and_one_barb_a_fifth_its_length_at_45_degrees_on_its_faces_side() {
        let (a, b) = (Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0));
        let inside = Vec3::new(-3.0, 0.0, 1.0);
        let s = thin_lines(&[Shape::Arrow(a, b, inside, Color::WHITE)]).segments;
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].ends, [a, b]);
        let barb = s[1].ends[1] - b;
        assert_eq!(s[1].ends[0], b);
        assert!((barb.length() - 0.4).abs() < 1e-6);
        let half = 0.4 * std::f32::consts::FRAC_1_SQRT_2;
        assert!(barb.distance(Vec3::new(-half, 0.0, -half)) < 1e-6, "{barb}");
    }

    #[test]
    fn an_arrow_with_its_face_side_on_its_line_is_its_shaft_alone() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        let s = thin_lines(&[Shape::Arrow(a, b, Vec3::X * 3.0, Color::WHITE)]).segments;
        assert_eq!(s.len(), 1);
    }

    #[test]
    fn highlights_are_left_to_the_gizmos() {
        let shapes = [
            Shape::Highlight(Vec3::ZERO, Vec3::X, Color::WHITE),
            Shape::HighlightDot(Vec3::ZERO, 1.0, Color::WHITE),
            Shape::Line(Vec3::ZERO, Vec3::Y, Color::WHITE),
        ];
        assert_eq!(shapes.iter().filter(|s| is_thin(s)).count(), 1);
        assert_eq!(thin_lines(&shapes).segments.len(), 1);
    }
}
