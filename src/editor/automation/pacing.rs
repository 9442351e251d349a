//! When the editor draws: on input, and while something is under way — never otherwise.
//!
//! A desktop editor left alone should leave the machine alone. The window runs in winit's
//! reactive mode ([`WinitSettings::desktop_app`]): a frame is drawn when input arrives (keys,
//! the pointer, the wheel, a resize, a dropped file) or when egui asks for one (an animation, a
//! tooltip). [`keep_drawing`] asks for the next frame while work is under way that no input
//! drives: a running job (its progress bar), a script (screenshots, the frame-time bench); the
//! panel's figures and the autosave ask for their own while they read a large mesh a slice a
//! frame ([`crate::mesh::tables::GradualRead`]), and the figures while their thread counts. A
//! native file dialog answers on another thread, so while one is open the editor looks for the
//! answer ten times a second instead of drawing continuously; an autosave waiting for the editor
//! to be idle ([`crate::editor::pipeline::recovery`]) wakes it four times a second until the recovery is written.
//!
//! `bevy_egui` 0.42 tells egui "the modifier keys are now …" every frame, changed or not, and egui
//! answers any input event by asking for another frame: the editor never slept (177 % of the two
//! cores, idle, on the torus). [`drop_unchanged_modifiers`] removes that event when the modifiers
//! are what egui already knows; egui carries its modifier state from frame to frame, so nothing
//! is lost.
//!
//! An edit is applied and its render data rebuilt in the frame of the key press (`Apply` then
//! `Sync` in one update), and drawn by the render thread in the next one.

use bevy::prelude::*;
use bevy::window::RequestRedraw;
use bevy::winit::{UpdateMode, WinitSettings};
use bevy_egui::egui;
use std::time::Duration;

use super::script::Script;
use crate::editor::pipeline::jobs::Jobs;
use crate::editor::pipeline::recovery::Autosave;
use crate::editor::session::dialog::OpenDialog;

/// How often the editor looks for a file dialog's answer while one is open.
pub const DIALOG_POLL: Duration = Duration::from_millis(100);

/// How often the editor wakes while an autosave waits for it to be idle.
pub const AUTOSAVE_POLL: Duration = Duration::from_millis(250);

/// The update modes for the editor's window: reactive, waking after `poll` at the latest when
/// something waits on time rather than input (a dialog's answer, an autosave).
pub fn settings(poll: Option<Duration>) -> WinitSettings {
    let mut settings = WinitSettings::desktop_app();
    if let Some(poll) = poll {
        settings.focused_mode = UpdateMode::reactive(poll);
        settings.unfocused_mode = UpdateMode::reactive_low_power(poll);
    }
    settings
}

/// Asks for another frame while a job runs or a script plays, and shortens the wait while a
/// file dialog is open or an autosave waits (see the module doc).
pub fn keep_drawing(
    jobs: Res<Jobs>,
    script: Option<Res<Script>>,
    dialog: Res<OpenDialog>,
    autosave: Res<Autosave>,
    mut winit: ResMut<WinitSettings>,
    mut redraw: MessageWriter<RequestRedraw>,
) {
    if jobs.running.is_some() || script.is_some_and(|s| s.is_running()) {
        redraw.write(RequestRedraw);
    }
    let poll = if dialog.is_open() {
        Some(DIALOG_POLL)
    } else {
        autosave.is_pending().then_some(AUTOSAVE_POLL)
    };
    let wanted = settings(poll);
    if winit.focused_mode != wanted.focused_mode || winit.unfocused_mode != wanted.unfocused_mode {
        *winit = wanted;
    }
}

/// Removes egui's per-frame "modifiers changed" event when the modifiers did not change (see the
/// module doc). Runs between `bevy_egui`'s input processing and the start of the egui pass.
pub fn drop_unchanged_modifiers(
    mut inputs: Query<&mut bevy_egui::EguiInput>,
    mut known: Local<Option<egui::Modifiers>>,
) {
    for mut input in &mut inputs {
        let before = *known;
        input.events.retain(|event| match event {
            egui::Event::ModifiersChanged(m) => {
                let changed = before != Some(*m);
                *known = Some(*m);
                changed
            }
            _ => true,
        });
    }
}
