//! Keeps a dense mesh readable: the wireframe is drawn only while its edges are far enough
//! apart on screen to be told apart.
//!
//! A wireframe whose edges lie closer than [`MIN_EDGE_PX`] pixels is no longer a picture of
//! the edges but a dark smear over the surface (the Stanford bunny, framed whole at 1280×800,
//! has edges about 2 px long: opened with its wireframe it was a black blob), and under software
//! rendering it was also most of the frame. So each frame [`show_readable_wireframes`] measures
//! the mesh's mean edge length in pixels at the orbit distance and hides the wireframe below the
//! threshold, showing it again as soon as the user zooms in. The edges around the selection are
//! still drawn (see `overlay::gather_overlay`), so what is selected always stands out. The
//! panel's "dense wireframe" box overrides the rule for the session.

use bevy::prelude::*;

use crate::mesh::ids::MeshId;

use super::render_sync::{RenderChunks, ViewSettings, WireframeOf};
use super::scene::OrbitCamera;
use super::wireframe::WireLines;
use crate::editor::session::selection::ActiveMesh;

/// Edges closer than this on screen (mean edge length, in physical pixels) hide the wireframe.
pub const MIN_EDGE_PX: f32 = 6.0;

/// What the density rule decided for the active mesh this frame.
#[derive(Resource, Debug, Default, Clone, Copy, PartialEq)]
pub struct WireframeDensity {
    /// Mean edge length of the active mesh on screen, in pixels (at the orbit focus).
    pub edge_px: Option<f32>,
    /// Whether the active mesh's wireframe is hidden because its edges are too dense.
    pub hidden: bool,
}

/// Pixels per world unit at the orbit focus, for a perspective camera with a viewport.
fn pixels_per_unit(orbit: &OrbitCamera, camera: &Camera, projection: &Projection) -> Option<f32> {
    let Projection::Perspective(p) = projection else {
        return None;
    };
    let height = camera.physical_viewport_size()?.y as f32;
    let visible = 2.0 * orbit.radius * (p.fov / 2.0).tan();
    (visible > 0.0).then(|| height / visible)
}

/// Shows or hides each mesh's wireframe by its on-screen density (see the module doc).
pub fn show_readable_wireframes(
    settings: Res<ViewSettings>,
    active: Res<ActiveMesh>,
    cameras: Query<(&OrbitCamera, &Camera, &Projection)>,
    meshes: Query<&RenderChunks>,
    mut wires: Query<(&WireframeOf, &mut Visibility), With<WireLines>>,
    mut density: ResMut<WireframeDensity>,
) {
    let scale = cameras
        .iter()
        .next()
        .and_then(|(orbit, camera, projection)| pixels_per_unit(orbit, camera, projection));
    let mut judged = WireframeDensity::default();
    for (of, mut visibility) in &mut wires {
        let edge_px = meshes
            .get(of.0.0)
            .ok()
            .zip(scale)
            .map(|(chunks, scale)| chunks.mean_edge_length * scale);
        let dense = edge_px.is_some_and(|px| px < MIN_EDGE_PX) && !settings.dense_wireframe;
        let wanted = settings.wireframe && !dense;
        visibility.set_if_neq(if wanted {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        });
        if active.0 == Some(MeshId(of.0.0)) {
            judged = WireframeDensity {
                edge_px,
                hidden: settings.wireframe && dense,
            };
        }
    }
    density.set_if_neq(judged);
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::camera::{PerspectiveProjection, Viewport};

    #[test]
    fn pixels_per_unit_follow_the_viewport_and_the_distance() {
        let orbit = OrbitCamera {
            radius: 2.0,
            ..Default::default()
        };
        let camera = Camera {
            viewport: Some(Viewport {
                physical_size: UVec2::new(900, 800),
                ..Default::default()
            }),
            ..Default::default()
        };
        let fov = std::f32::consts::FRAC_PI_2;
        let projection = Projection::Perspective(PerspectiveProjection {
            fov,
            ..Default::default()
        });
        // A 90° field of view at distance 2 sees 4 units across 800 pixels.
        let px = pixels_per_unit(&orbit, &camera, &projection).unwrap();
        assert!((px - 200.0).abs() < 1e-3, "{px}");
        let farther = OrbitCamera {
            radius: 4.0,
            ..orbit
        };
        let px = pixels_per_unit(&farther, &camera, &projection).unwrap();
        assert!((px - 100.0).abs() < 1e-3, "{px}");
    }
}
