//! The view room: how the meshes look. The render copies that follow the entities
//! ([`render_sync`], from what [`render_data`] builds), colouring by a quantity ([`colouring`]), the wireframe kept readable
//! ([`readability`]), the scene and its camera state ([`scene`]), the surface shader
//! ([`surface`]) and its back faces left undrawn where none can be seen ([`culling`]), and the
//! lines of a constant width on screen that draw the wireframe ([`wireframe`]) and the overlay
//! ([`lines`]). It reads only the session and pipeline rooms.

pub mod colouring;
pub mod culling;
pub mod lines;
pub mod readability;
pub mod render_data;
pub mod render_sync;
pub mod scene;
pub mod surface;
pub mod wireframe;

use bevy::prelude::*;

use crate::editor::session::schedule::EditorSystems;

/// The render copies and the colours, kept in step after every applied request.
pub struct ViewPlugin;

impl Plugin for ViewPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<render_sync::ViewSettings>()
            .init_resource::<colouring::ColorBy>()
            .init_resource::<render_sync::RenderStats>()
            .init_resource::<readability::WireframeDensity>()
            .init_resource::<culling::Closures>()
            .init_resource::<culling::drawn::DrawnCounts>()
            .add_systems(
                Update,
                (
                    colouring::update_vertex_values,
                    render_sync::sync_render_meshes,
                )
                    .chain()
                    .in_set(EditorSystems::Sync),
            );
    }
}

/// The scene, the surface material, the camera fitted beside the panels and the wireframe
/// shown only where it can be read.
pub struct ViewWindowPlugin;

impl Plugin for ViewWindowPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((surface::SurfacePlugin, lines::LinesPlugin))
            .init_resource::<scene::PanelInsets>()
            .add_systems(
                Startup,
                (scene::setup_scene, scene::detect_software_renderer),
            )
            .add_systems(
                Update,
                (
                    scene::fit_near_plane
                        .after(EditorSystems::Apply)
                        .before(EditorSystems::Sync),
                    readability::show_readable_wireframes
                        .after(EditorSystems::Sync)
                        .before(EditorSystems::Ui),
                    (culling::drawn::count_drawn, culling::choose_culling)
                        .chain()
                        .after(EditorSystems::Sync)
                        .before(EditorSystems::Ui),
                    scene::fit_camera_viewport.in_set(EditorSystems::Ui),
                ),
            );
    }
}
