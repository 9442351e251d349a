//! What the panels draw and keep: the copy of the world they show ([`InspectorView`], made by
//! [`super::ui::snapshot`]), their text fields, and the actions their clicks leave for the
//! world. The panel's parameters of the operations are the session's
//! ([`crate::editor::session::panel_state::UiState`]), which the keys read too.

use bevy::math::Vec3;
use bevy::prelude::*;

use super::mesh_figures::{FiguresKey, MeshView};
use super::plots::Histogram;
use bevy_egui::egui;

use crate::colormap::{ColorMap, Range};
use crate::editor::gestures::handle_deform::Anchors;
use crate::editor::input::shortcuts::Action;
use crate::editor::session::dialog::PathPurpose;
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::Relation;
use crate::editor::session::requests::{OutcomeLog, Request};
use crate::editor::session::selection::SelectMode;
use crate::editor::view::colouring::ColorBy;
use crate::editor::view::readability::WireframeDensity;
use crate::editor::view::render_sync::ViewSettings;
use crate::mesh::ids::ElementId;

/// Everything the panels show, copied out of the world once a frame.
#[derive(Resource, Default, Debug, Clone)]
pub struct InspectorView {
    /// The active mesh, if any.
    pub mesh: Option<MeshView>,
    /// The selected element, if any.
    pub selected: Option<SelectedView>,
    /// The selected set, counted ("3 faces selected"); empty when at most one is selected.
    pub selected_set: String,
    /// The transform under way, as the status line says it.
    pub gesture: Option<String>,
    /// What the figures shown were counted at.
    pub figures_key: FiguresKey,
    /// What the figures would be counted at, as last seen.
    pub seen_key: FiguresKey,
    /// When that last changed.
    pub changed_at: Option<std::time::Instant>,
    /// Whether the last change came after the mesh had stood still (it is counted at once).
    pub after_quiet: bool,
    /// The simplification history: (coarsest, current, full) face counts.
    pub lod: Option<(usize, usize, usize)>,
    /// The undo history, oldest first: each entry's label and whether it is undone (redoable).
    pub history: Vec<(String, bool)>,
    /// Bytes the undo history holds.
    pub history_bytes: usize,
    /// The running job: its label, the fraction done and the seconds since it started.
    pub job: Option<(String, f32, f32)>,
    /// The histograms of the active mesh (counted with the statistics).
    pub histograms: Vec<Histogram>,
    /// The quantity the mesh is coloured by: its label, colour map and range (the legend).
    pub colour: Option<(String, ColorMap, Range)>,
}

/// The selected element as shown.
#[derive(Debug, Clone)]
pub struct SelectedView {
    /// Its id.
    pub id: ElementId,
    /// Each relation and where it leads.
    pub relations: Vec<(Relation, Option<ElementId>)>,
    /// Its position (vertices).
    pub position: Option<Vec3>,
    /// Facts: valence, degree, boundary.
    pub facts: Vec<(String, String)>,
}

/// Text fields that keep their contents between frames.
#[derive(Resource, Debug)]
pub struct UiFields {
    /// The path field (open / save as).
    pub path: String,
    /// The "go to id" field.
    pub jump: String,
    /// What Enter in the path field does.
    pub enter_means: PathPurpose,
    /// The path field takes the keyboard next frame.
    pub focus: bool,
}

impl Default for UiFields {
    fn default() -> Self {
        Self {
            path: String::new(),
            jump: String::new(),
            enter_means: PathPurpose::Open,
            focus: false,
        }
    }
}

/// Actions chosen in the panel that need the world (run in the next `Input` set).
#[derive(Resource, Default, Debug)]
pub struct PendingActions(pub Vec<Action>);

/// What a section draws from and what it may change: the snapshot and the log (read), the
/// panel's state and the view's settings (changed in place; the panel writes them back to the
/// world only when they differ), and the requests and actions its clicks make (sent after the
/// panel is drawn, in the order made).
pub struct PanelContext<'a> {
    /// What the panels show, copied out of the world this frame.
    pub view: &'a InspectorView,
    /// The outcomes of the requests so far.
    pub log: &'a OutcomeLog,
    /// The text fields.
    pub fields: &'a mut UiFields,
    /// The panel's state: the operations' parameters, the overlays.
    pub state: &'a mut UiState,
    /// What a click selects.
    pub mode: &'a mut SelectMode,
    /// How the mesh is drawn.
    pub settings: &'a mut ViewSettings,
    /// How dense the wireframe is on screen.
    pub density: &'a WireframeDensity,
    /// The quantity the mesh is coloured by.
    pub colour_by: &'a mut ColorBy,
    /// The deformation's anchors and method.
    pub anchors: &'a mut Anchors,
    /// Actions that need the world, run in the next `Input` set.
    pub pending: &'a mut PendingActions,
    /// Requests made this frame.
    pub requests: Vec<Request>,
}

/// One section of the panel.
#[derive(Clone, Copy)]
pub struct PanelSection {
    /// Its title, which also names it in the remembered list of open sections.
    pub title: &'static str,
    /// Whether it is open before the user has folded anything.
    pub open_at_first: bool,
    /// Draws its contents (the title and the folding are the panel's).
    pub draw: fn(&mut egui::Ui, &mut PanelContext),
}
