//! Files dropped on the window open, as Ctrl+O would (whatever has the keyboard; unsaved
//! changes are asked about first).

use bevy::prelude::*;

use crate::editor::session::requests::Request;

/// Writes an open request for each file dropped on the window.
pub fn open_dropped_files(
    mut drops: MessageReader<bevy::window::FileDragAndDrop>,
    mut requests: MessageWriter<Request>,
) {
    for drop in drops.read() {
        if let bevy::window::FileDragAndDrop::DroppedFile { path_buf, .. } = drop {
            requests.write(Request::Open(path_buf.clone()));
        }
    }
}
