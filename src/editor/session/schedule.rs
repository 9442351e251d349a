//! The editor's frame in `Update`: its stages as named system sets, in order, and whether egui
//! has the keyboard this frame. Every room places its systems in these stages, so they live in
//! the lowest room.

use bevy::prelude::{Resource, SystemSet};

/// The editor's stages, in order, in `Update` (chained by [`crate::editor::EditorLogicPlugin`]).
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub enum EditorSystems {
    /// Keys and gestures become requests.
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

/// Whether egui is using the keyboard this frame (set by the panels; the shortcuts and the
/// camera controls then stay quiet).
#[derive(Resource, Default, Debug, Clone, Copy)]
pub struct KeyboardCaptured(pub bool);
