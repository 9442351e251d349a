//! The panel's state, which the keys read too: the help overlay, the path field's focus, the
//! histograms' and the UV window's toggles, proportional editing, and the values of every
//! registered operation's parameters (their declared defaults until the panel changes them:
//! the command line's). The panels draw and change it; a shortcut runs an operation with
//! these values.

use bevy::prelude::*;

use crate::edit::Invocation;
use crate::editor::session::dialog::PathPurpose;
use crate::ops::deform::Proportional;
use crate::ops::operation::MeshOperation;

/// UI state that shortcuts read and change: the overlay, the path field, and the parameters
/// of the whole-mesh edits (set in the panel; the command line's defaults).
#[derive(Resource, Debug, Clone)]
pub struct UiState {
    /// The help overlay is open.
    pub show_help: bool,
    /// The path field should take the keyboard focus (for Open / Save as).
    pub focus_path: Option<PathPurpose>,
    /// Show the histograms even when the mesh is not coloured by a quantity.
    pub histograms: bool,
    /// The panel asked to check the validity of a large mesh (see
    /// [`crate::editor::panels::mesh_figures`]).
    pub check_validity: bool,
    /// The UV layout window is open (it opens by itself when the mesh first gets UVs).
    pub uv_view: bool,
    /// Proportional editing: on or off, falloff, radius, distances along edges.
    pub proportional: Proportional,
    /// The panel's values of each registered operation's parameters (their defaults until
    /// changed), one invocation per operation of [`crate::ops::registry`], in its order.
    pub operations: Vec<Invocation>,
    /// The least important level of message the Log section shows (info until switched).
    pub log_level: bevy::log::Level,
}

impl UiState {
    /// Takes up the operations registered since the state was made (or last took them up),
    /// with their defaults.
    pub fn take_up_registered(&mut self) {
        let all = crate::ops::registry::operations();
        let known = self.operations.len().min(all.len());
        let new = all[known..].iter().map(|&op| Invocation::with_defaults(op));
        self.operations.extend(new);
    }

    /// `op` with the panel's values of its parameters.
    pub fn invocation(&self, op: &'static dyn MeshOperation) -> Invocation {
        let d = op.declaration();
        self.operations
            .iter()
            .find(|i| i.declaration().name == d.name && i.declaration().names == d.names)
            .cloned()
            .unwrap_or_else(|| Invocation::with_defaults(op))
    }

    /// Sets the panel's value of parameter `i` of the registered operation `name`, as its
    /// field would.
    ///
    /// # Errors
    /// No registered operation of that name, or a value its parameter does not take.
    pub fn set_parameter(&mut self, name: &str, i: usize, x: Option<f64>) -> Result<(), String> {
        self.operations
            .iter_mut()
            .find(|op| op.declaration().name == name)
            .ok_or_else(|| format!("no registered operation is called `{name}`"))?
            .set(i, x)
    }
}

impl Default for UiState {
    fn default() -> Self {
        let mut state = Self {
            show_help: false,
            focus_path: None,
            histograms: false,
            check_validity: false,
            uv_view: false,
            proportional: Proportional::default(),
            operations: crate::ops::registry::operations()
                .iter()
                .map(|&op| Invocation::with_defaults(op))
                .collect(),
            log_level: bevy::log::Level::INFO,
        };
        // Filling every hole of a scan in the editor means patches that continue the surface
        // (Liepa); the `fill-holes` step keeps its one polygon each by default.
        let faired = state.set_parameter("fill-holes", 0, Some(1.0));
        crate::checks::checked_assert!(faired.is_ok(), "{faired:?}");
        // The panel's Inset button insets a quarter of the way in (the I key drags from none).
        let quarter = state.set_parameter("inset", 0, Some(0.25));
        crate::checks::checked_assert!(quarter.is_ok(), "{quarter:?}");
        state
    }
}
