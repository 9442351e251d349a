//! The pipeline room: how a request is carried out. The one system that changes meshes
//! ([`apply`]), the edits that run on a thread ([`jobs`]), files opened in the background
//! ([`opening`]), the autosave and crash recovery ([`recovery`]) and step mode ([`stepping`]).
//! It reads only the session room.

pub mod apply;
pub mod jobs;
pub mod opening;
pub mod recovery;
pub mod stepping;

use bevy::prelude::*;

use crate::editor::session::schedule::EditorSystems;

/// Applying requests, finishing jobs and openings, the autosave (no window needed).
pub struct PipelinePlugin;

impl Plugin for PipelinePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<jobs::Jobs>()
            .init_resource::<jobs::JobSettings>()
            .init_resource::<opening::Opening>()
            .init_resource::<stepping::Stepping>()
            .init_resource::<recovery::Autosave>()
            .init_resource::<recovery::RecoveryOffer>()
            .add_systems(Startup, recovery::find_recovery)
            .add_systems(
                Update,
                (
                    jobs::finish_jobs,
                    opening::finish_opening,
                    apply::apply_requests,
                    recovery::autosave,
                )
                    .chain()
                    .in_set(EditorSystems::Apply),
            );
    }
}

/// The window's close button, which asks about unsaved work first.
pub struct PipelineWindowPlugin;

impl Plugin for PipelineWindowPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Update, apply::close_requested.in_set(EditorSystems::Input));
    }
}
