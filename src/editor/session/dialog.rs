//! Native file dialogs (through `rfd`), run on a thread of their own so the window keeps
//! drawing while one is open. The chosen path comes back as an ordinary [`Request`]. Where
//! no dialog can be shown (no desktop portal, as under Xvfb) nothing comes back, and the path
//! field in the panel, which the same shortcut focuses, is the way to type a path.

use bevy::prelude::*;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use super::requests::Request;

/// What a path is being chosen for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPurpose {
    /// Open the file.
    Open,
    /// Save to the file.
    SaveAs,
}

/// What a dialog thread hands back: nothing yet, or its answer (`None`: cancelled or none).
type Answer = Arc<Mutex<Option<Option<PathBuf>>>>;

/// A dialog that is open, and where its answer will arrive.
#[derive(Resource, Default)]
pub struct OpenDialog {
    pending: Option<(PathPurpose, Answer)>,
}

impl OpenDialog {
    /// Whether a dialog is open and its answer not yet received.
    pub fn is_open(&self) -> bool {
        self.pending.is_some()
    }
}

/// Opens a native dialog to choose a file to open or to save to (one at a time).
pub fn show(world: &mut World, purpose: PathPurpose) {
    let mut state = world.resource_mut::<OpenDialog>();
    if state.pending.is_some() {
        return;
    }
    let answer: Answer = Arc::default();
    let slot = answer.clone();
    let spawned = std::thread::Builder::new()
        .name("file dialog".into())
        .spawn(move || {
            let dialog = rfd::FileDialog::new();
            let choice = match purpose {
                PathPurpose::Open => dialog
                    .add_filter("meshes", &crate::io::extensions(false))
                    .pick_file(),
                PathPurpose::SaveAs => dialog
                    .add_filter("meshes", &crate::io::extensions(true))
                    .save_file(),
            };
            if let Ok(mut slot) = slot.lock() {
                *slot = Some(choice);
            }
        });
    if spawned.is_ok() {
        state.pending = Some((purpose, answer));
    }
}

/// Turns a chosen path into a request (the `Input` set).
pub fn receive(mut state: ResMut<OpenDialog>, mut requests: MessageWriter<Request>) {
    let Some((purpose, answer)) = &state.pending else {
        return;
    };
    let purpose = *purpose;
    let Some(choice) = answer.lock().ok().and_then(|mut a| a.take()) else {
        return;
    };
    if let Some(path) = choice {
        requests.write(match purpose {
            PathPurpose::Open => Request::Open(path),
            PathPurpose::SaveAs => Request::Save(Some(path)),
        });
    }
    state.pending = None;
}
