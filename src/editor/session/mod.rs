//! The session room: what the editor holds and the messages it runs on. The [`requests`] in
//! and outcomes out, the [`selection`] and its changes ([`select_many`]), undo
//! ([`history`]) and where each vertex and face came from ([`origins`]), the bookkeeping that
//! ends every edit ([`finish`]), which meshes have unsaved
//! work ([`state`]), the native file dialogs ([`dialog`]), the frame's stages
//! ([`schedule`]) and the log's messages kept for the panel ([`log_capture`]). It is the lowest room: every other one reads it, it reads none of them.

pub mod dialog;
pub mod finish;
pub mod history;
pub mod log_capture;
pub mod origins;
pub mod panel_state;
pub mod requests;
pub mod schedule;
pub mod select_many;
pub mod selection;
pub mod state;

use bevy::prelude::*;

use requests::{ConfirmDiscard, EditOutcome, OutcomeLog, Request};
use schedule::{EditorSystems, KeyboardCaptured};
use selection::{ActiveMesh, Hover, SelectMode, Selection};

/// The session's messages and resources, and undo's watch on the keys (no window needed).
pub struct SessionPlugin;

impl Plugin for SessionPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<Request>()
            .add_message::<EditOutcome>()
            .init_resource::<Selection>()
            .init_resource::<Hover>()
            .init_resource::<SelectMode>()
            .init_resource::<ActiveMesh>()
            .init_resource::<OutcomeLog>()
            .init_resource::<state::PreviousShape>()
            .init_resource::<history::UndoHistory>()
            .init_resource::<ConfirmDiscard>()
            .init_resource::<KeyboardCaptured>()
            .add_systems(Update, history::track_presses.in_set(EditorSystems::Input));
    }
}

/// The file dialogs, whose answers come back as requests.
pub struct SessionWindowPlugin;

impl Plugin for SessionWindowPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<dialog::OpenDialog>()
            .add_systems(Update, dialog::receive.in_set(EditorSystems::Input));
    }
}

/// The log layer the editor gives Bevy's `LogPlugin`: it keeps the messages in the
/// [`OutcomeLog`] (made here if the session has not made it yet, so that the messages of the
/// app's start are kept too), for the Log section.
pub fn capture_layer(app: &mut App) -> Option<bevy::log::BoxedLayer> {
    app.init_resource::<OutcomeLog>();
    let messages = app.world().resource::<OutcomeLog>().messages.clone();
    Some(log_capture::layer(messages))
}
