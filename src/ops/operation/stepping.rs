//! Step mode's contract: an operation run a step at a time on the live mesh, so that a student
//! can watch it work, declared by the operation itself.
//!
//! An operation that steps declares it ([`crate::ops::declaration::Declaration::stepping`])
//! and gives a [`Steps`] from [`super::MeshOperation::step_through`]: the run's own state, which
//! moves to a step ([`Steps::go_to`], forward or, where it can, back), says where it is in one
//! line, shows what the step did ([`StepShow`]: shapes drawn over the mesh, lists and a table
//! for the step window) and ends ([`Steps::finish`]). The editor's stepping room drives any
//! run through this trait alone and knows no algorithm: it keeps the mesh from before the run
//! for the undo entry or a cancel, follows the selection, redraws what a move says changed,
//! and draws what the run shows.
//!
//! The one rule every run keeps: **its steps are the operation's own**, so a run taken to its
//! last step leaves the mesh exactly as [`super::MeshOperation::apply`] would — the same
//! element ids, links and position bits (`tests/step_mode.rs` checks each).
//!
//! Everything here is plain data — positions, colours as sRGB triples, lines of text — so the
//! operations need no renderer or widget library, and the headless tests read it.

use std::any::Any;

use bevy::math::{Quat, Vec3};
use bevy::prelude::World;

use super::outcome::Redraw;
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::ops::Refusal;
use crate::ops::declaration::IdsKept;

/// A colour, as sRGB components in `[0, 1]`.
pub type Rgb = [f32; 3];

/// What a step makes next (QEM's next edge and the point its ends merge at).
pub const NEXT: Rgb = [1.0, 0.45, 0.05];
/// What waits after it (the queue's next cheapest edges).
pub const QUEUED: Rgb = [0.95, 0.75, 0.2];
/// What the last step touched (a remeshing pass's edges and vertices, a smoothing's moves).
pub const TOUCHED: Rgb = [0.1, 0.8, 0.35];
/// The most shapes of one kind a run draws (they are redrawn every frame): an even sample
/// ([`even_sample`]) above that.
pub const MAX_DRAWN: usize = 3_000;

/// A shape drawn over the mesh while the run is at a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepShape {
    /// A thin line.
    Line(Vec3, Vec3, Rgb),
    /// A thick line over everything.
    Highlight(Vec3, Vec3, Rgb),
    /// A dot of the given world radius.
    Dot(Vec3, f32, Rgb),
    /// A large dot over everything, of the given world radius.
    HighlightDot(Vec3, f32, Rgb),
    /// A rotation as a frame at a point: where the X, Y and Z axes turn to, each of the given
    /// length, in the editor's axis colours.
    Frame(Vec3, Quat, f32),
}

/// Indices into `n` things, at most [`MAX_DRAWN`] of them, evenly spread.
pub fn even_sample(n: usize) -> impl Iterator<Item = usize> {
    (0..n.min(MAX_DRAWN)).map(move |i| i * n / n.clamp(1, MAX_DRAWN))
}

/// How a run goes back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoesBack {
    /// It does not (a remeshing pass rewrites much of the mesh): Esc puts the mesh back.
    Never,
    /// A step or a few at a time (the preview of a level not yet committed).
    Steps,
    /// To any step made, and a slider scrubs along them.
    Scrubs,
}

/// What a move did, for the editor to follow.
#[derive(Clone, Debug, PartialEq)]
pub struct Moved {
    /// What to redraw; `None` where the mesh did not change (a preview).
    pub redraw: Option<Redraw>,
    /// Which selected ids still mean their element (if it survived).
    pub ids: IdsKept,
    /// The selected element a step removed, replaced: what it became (selected then), and
    /// the line that says so ("e12 is gone: merged into e7").
    pub became: Option<(ElementId, String)>,
}

impl Moved {
    /// A move that redrew `redraw`, kept every id and replaced no selection.
    pub fn redrawing(redraw: Redraw) -> Self {
        Self {
            redraw: Some(redraw),
            ids: IdsKept::All,
            became: None,
        }
    }

    /// A move that changed nothing on the mesh.
    pub fn nothing() -> Self {
        Self {
            redraw: None,
            ids: IdsKept::All,
            became: None,
        }
    }
}

/// How a run ended.
#[derive(Debug)]
pub struct Ended {
    /// The undo entry's summary line; `None` when the run changed nothing (no entry is made).
    pub summary: Option<String>,
    /// The values of the operation's parameters the undo entry names where they are not those
    /// the run started with (a subdivision ended after fewer levels than asked for).
    pub recorded: Option<Vec<Option<f64>>>,
}

impl Ended {
    /// A run that made its summary line.
    pub fn with(summary: String) -> Self {
        Self {
            summary: Some(summary),
            recorded: None,
        }
    }
}

/// A list in the step window: a title over lines.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepList {
    /// Its title.
    pub title: String,
    /// Its lines, each maybe naming an element (a link that selects it).
    pub lines: Vec<StepLine>,
}

/// A line of a [`StepList`].
#[derive(Clone, Debug, PartialEq)]
pub struct StepLine {
    /// The element it names, written first as a link that selects it.
    pub element: Option<ElementId>,
    /// Its text.
    pub text: String,
}

impl StepLine {
    /// A line of text alone.
    pub fn text(text: String) -> Self {
        Self {
            element: None,
            text,
        }
    }
}

/// A table in the step window (a subdivision stencil's terms): a title, a note, two columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepTable {
    /// Its title, strong.
    pub title: String,
    /// A line under the title.
    pub note: String,
    /// The columns' headers.
    pub header: [String; 2],
    /// Its rows.
    pub rows: Vec<[String; 2]>,
    /// A line under the table.
    pub footer: String,
}

/// What a run shows at the step it is at.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepShow {
    /// Shapes over the mesh.
    pub shapes: Vec<StepShape>,
    /// A text written on the mesh at a point (QEM's next edge and its cost).
    pub label: Option<(Vec3, String)>,
    /// Lists for the step window, in order.
    pub lists: Vec<StepList>,
    /// A table for the step window.
    pub table: Option<StepTable>,
    /// A hint for the step window where there is nothing else to see ("select a vertex …").
    pub hint: Option<String>,
    /// Whether the window offers the edge-length and valence histograms (a remeshing run).
    pub histograms: bool,
}

/// An operation run a step at a time (see the module doc). Made by
/// [`super::MeshOperation::step_through`], with the mesh as it was when the run began.
pub trait Steps: Any + Send + Sync {
    /// The step the mesh is at (0 before the first).
    fn at(&self) -> usize;

    /// The steps made so far where the run cannot know its end (QEM), or the steps it has in
    /// all: the end of the window's slider.
    fn made(&self) -> usize;

    /// Whether the run has made its last step.
    fn finished(&self) -> bool;

    /// How it goes back.
    fn goes_back(&self) -> GoesBack;

    /// Shows step 0 on the mesh, once the editor has kept the mesh from before the run (a
    /// deformation places its handle); the default changes nothing.
    ///
    /// # Refusals
    /// The operation's; the run then does not start, and the editor puts the mesh back.
    fn open(&mut self, world: &mut World, mesh: MeshId) -> Result<Option<Redraw>, Refusal> {
        let _ = (world, mesh);
        Ok(None)
    }

    /// Moves the mesh to step `k` (forward beyond the last step goes to the last). `selected`
    /// is the selected element, which a step that removes it reports on ([`Moved::became`]).
    ///
    /// # Refusals
    /// A move back the run cannot make, or the operation's own refusal on the way; the mesh
    /// is then valid at some step of the run (the editor redraws it whole).
    fn go_to(
        &mut self,
        world: &mut World,
        mesh: MeshId,
        k: usize,
        selected: Option<ElementId>,
    ) -> Result<Moved, Refusal>;

    /// Where the run is, in one line (the status line's and the step window's).
    fn describe(&self) -> String;

    /// What the run shows at the step it is at, `selected` being the selected element.
    fn show(&self, world: &World, selected: Option<ElementId>) -> StepShow;

    /// The vertices the camera frames when asked to frame nothing selected (QEM's next
    /// collapse); the default, none (the camera frames the mesh).
    fn focus(&self) -> Vec<VertexId> {
        Vec::new()
    }

    /// Ends the run where it is: the undo entry's line and the invocation it stands for. What
    /// the run leaves on the mesh besides its elements it puts there (a simplification its
    /// history, [`crate::ops::simplification_history`]).
    fn finish(self: Box<Self>, world: &mut World, mesh: MeshId) -> Ended;
}

impl dyn Steps {
    /// The run as the operation's own type, if it is one (the tests look inside).
    pub fn downcast_ref<T: Steps>(&self) -> Option<&T> {
        (self as &dyn Any).downcast_ref()
    }
}
