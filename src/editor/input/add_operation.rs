//! `app.add_operation(MyFlip)`: an operation written outside Pappus joins the editor the way
//! its own do — a key in the keymap and the help overlay, a button with its parameters in the
//! panel section it declares, an undoable edit — through the process's registry
//! ([`crate::ops::registry`]), which the command line and Python read too. The panel takes up
//! an operation registered after it started ([`crate::editor::session::panel_state::UiState`]).

use bevy::prelude::App;

use super::key_names::chord;
use super::shortcuts::SHORTCUTS;
use crate::ops::operation::MeshOperation;
use crate::ops::registry;

/// Adds operations to the editor being built.
pub trait AddOperation {
    /// Registers `op` for the process and gives it its key and its place in the panel.
    ///
    /// # Panics
    /// At start, naming both, when `op` would share a step name (on the same kind of element)
    /// or a key with a registered operation, or take a key of the editor's own (G grabs);
    /// and when its key does not read (`"Alt+Y"`, `"Shift+F"`, `"K"` do).
    fn add_operation(&mut self, op: impl MeshOperation) -> &mut Self;
}

impl AddOperation for App {
    fn add_operation(&mut self, op: impl MeshOperation) -> &mut Self {
        let d = op.declaration();
        if let Some(keys) = d.key {
            let Some(c) = chord(keys) else {
                panic!(
                    "`{}` (\"{}\"): the key `{keys}` does not read",
                    d.name, d.title
                );
            };
            let own = SHORTCUTS
                .iter()
                .find(|s| (s.key, s.ctrl, s.shift, s.alt) == (c.key, c.ctrl, c.shift, c.alt));
            if let Some(own) = own {
                panic!(
                    "`{}` (\"{}\") takes the key {keys}, which the editor gives to {}",
                    d.name, d.title, own.description
                );
            }
        }
        if let Err(clash) = registry::register(op) {
            panic!("{clash}");
        }
        self
    }
}
