//! The example lab: a student's edge flip, split and collapse (`student.rs`, written from
//! scratch with the checked low-level edit) on keys of their own in the editor, each checked
//! against Pappus's own as it is applied.
//!
//! ```text
//! cargo run --release --example lab -- [FILE]
//! ```
//!
//! Select an edge and press Alt+1 (flip), Alt+2 (split) or Alt+3 (collapse); Alt+4 and Alt+5
//! are flips with a mistake in them (`mistakes.rs`), to see what a wrong result reports. The lab's report is
//! in the status line and the log: "same as flip", "valid, but not what flip makes: …",
//! "invalid: …; the mesh is as it was". The student's operations log what they touched at the
//! `trace` level, which the Log section shows from the start here.

mod mistakes;
mod student;

use pappus::editor::AddOperation;
use pappus::editor::session::panel_state::UiState;

fn main() {
    let file = std::env::args_os().nth(1).map(std::path::PathBuf::from);
    let code = pappus::editor::run_with(file, |app| {
        for op in student::LAB.into_iter().chain(mistakes::MISTAKES) {
            app.add_operation(op);
        }
        // The Log section shows the lab's trace lines from the start.
        let mut panel = app.world_mut().resource_mut::<UiState>();
        panel.log_level = bevy::log::Level::TRACE;
    });
    std::process::exit(code);
}
