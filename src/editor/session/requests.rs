//! The messages that drive the editor: requests in, outcomes out.
//!
//! Every way of asking for an edit — a key, a panel button, a script, a test — writes the same
//! [`Request`]. One exclusive system (`apply::apply_requests`) applies them in order, in the
//! `Apply` set, and writes one [`EditOutcome`] per request (a job's when it finishes), which the
//! status line and the log read. Nothing else changes a mesh.

use bevy::prelude::{Message, Resource};
use std::path::PathBuf;

use thiserror::Error;

use crate::edit::Edit;
use crate::mesh::ids::EdgeId;
use crate::mesh::ids::ElementId;
use crate::ops::Refusal;

/// A step along a halfedge relation, from the selected element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Relation {
    /// The halfedge's twin.
    Twin,
    /// The next halfedge around the face.
    Next,
    /// The previous halfedge around the face.
    Prev,
    /// The vertex (a halfedge's tip; an element's representative vertex).
    Vertex,
    /// The edge of a halfedge.
    Edge,
    /// The face of a halfedge (none on the boundary).
    Face,
    /// The element's halfedge (a vertex's outgoing, an edge's, a face's).
    Halfedge,
}

impl Relation {
    /// Every relation, in the order the inspector lists them.
    pub const ALL: [Relation; 7] = [
        Relation::Halfedge,
        Relation::Twin,
        Relation::Next,
        Relation::Prev,
        Relation::Vertex,
        Relation::Edge,
        Relation::Face,
    ];

    /// Its name as shown to the user.
    pub fn name(self) -> &'static str {
        match self {
            Relation::Twin => "twin",
            Relation::Next => "next",
            Relation::Prev => "prev",
            Relation::Vertex => "vertex",
            Relation::Edge => "edge",
            Relation::Face => "face",
            Relation::Halfedge => "halfedge",
        }
    }
}

/// Something the user asked of the editor: an [`Edit`] of a mesh, or a request about the
/// session (selection, files, undo, jobs).
#[derive(Message, Clone, Debug, PartialEq)]
pub enum Request {
    /// Apply an edit: to the elements it names, or to the active mesh.
    Edit(Edit),
    /// Select an element alone (or nothing).
    Select(Option<ElementId>),
    /// Change the selected set (toggle, all, grow, shrink, loops, a box).
    Selection(SelectionEdit),
    /// Move the selection along a relation.
    Navigate(Relation),
    /// Open a mesh file (or `shape:NAME`), replacing the current mesh.
    Open(PathBuf),
    /// Save the current mesh (to its own file, or to the given path).
    Save(Option<PathBuf>),
    /// Delete the current mesh.
    DeleteMesh,
    /// Cancel the operation running as a job (the mesh stays as it was).
    CancelJob,
    /// Undo the last edit.
    Undo,
    /// Take back the undo entries made since this mark ([`super::history::UndoHistory::mark`]),
    /// leaving no redo: a cancelled transform.
    Retract(u64),
    /// Redo the last undone edit.
    Redo,
    /// Start a stepped run of a global edit (step mode).
    StartStepped(Edit),
    /// Move the stepped run in progress.
    Step(StepMove),
    /// Answer the unsaved-changes question: `true` discards the changes and goes on with what
    /// was asked (opening another file, quitting), `false` cancels it.
    ConfirmDiscard(bool),
    /// Answer the offer of a recovery file found at start (unsaved work of an editor that
    /// ended without saving).
    Recover(RecoveryAnswer),
}

impl From<Edit> for Request {
    fn from(edit: Edit) -> Self {
        Request::Edit(edit)
    }
}

impl From<SelectionEdit> for Request {
    fn from(edit: SelectionEdit) -> Self {
        Request::Selection(edit)
    }
}

impl Request {
    /// A short label for logs.
    pub fn label(&self) -> String {
        match self {
            Request::Edit(edit) => edit.label(),
            Request::Select(Some(x)) => format!("select {x}"),
            Request::Select(None) => "select nothing".into(),
            Request::Selection(edit) => edit.label(),
            Request::Navigate(r) => format!("go to {}", r.name()),
            Request::Open(p) => format!("open {}", p.display()),
            Request::Save(Some(p)) => format!("save as {}", p.display()),
            Request::Save(None) => "save".into(),
            Request::DeleteMesh => "delete mesh".into(),
            Request::CancelJob => "cancel".into(),
            Request::Undo => "undo".into(),
            Request::StartStepped(edit) => format!("step through {}", edit.label()),
            Request::Step(movement) => movement.label(),
            Request::Retract(_) => "cancel".into(),
            Request::Redo => "redo".into(),
            Request::ConfirmDiscard(true) => "discard changes".into(),
            Request::ConfirmDiscard(false) => "keep changes".into(),
            Request::Recover(RecoveryAnswer::Restore) => "restore the recovery".into(),
            Request::Recover(RecoveryAnswer::Discard) => "delete the recovery".into(),
            Request::Recover(RecoveryAnswer::Keep) => "keep the recovery for later".into(),
        }
    }

    /// Whether the request changes a mesh (and so must wait while a job runs).
    pub fn edits(&self) -> bool {
        matches!(
            self,
            Request::Edit(_)
                | Request::StartStepped(_)
                | Request::Step(_)
                | Request::Open(_)
                | Request::DeleteMesh
                | Request::Undo
                | Request::Retract(_)
                | Request::Redo
                | Request::ConfirmDiscard(true)
                | Request::Recover(RecoveryAnswer::Restore)
        )
    }
}

/// A move of a stepped run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StepMove {
    /// This many steps forward (`usize::MAX`: to the end).
    Forward(usize),
    /// This many steps back.
    Back(usize),
    /// To step `k` (0: before the first), within what has run or beyond it.
    To(usize),
    /// End the run where it is, as one undo entry.
    Finish,
    /// End the run and put the mesh back as it was before it.
    Cancel,
}

impl StepMove {
    /// A short label for logs.
    pub fn label(self) -> String {
        match self {
            StepMove::Forward(usize::MAX) => "step to the end".into(),
            StepMove::Forward(n) => format!("step {n} forward"),
            StepMove::Back(n) => format!("step {n} back"),
            StepMove::To(k) => format!("go to step {k}"),
            StepMove::Finish => "finish the stepped run".into(),
            StepMove::Cancel => "cancel the stepped run".into(),
        }
    }
}

/// A change of the selected set.
#[derive(Clone, Debug, PartialEq)]
pub enum SelectionEdit {
    /// Shift-click: see [`Selection::toggle`](crate::editor::session::selection::Selection::toggle).
    Toggle(ElementId),
    /// Add these elements (a box with Shift held).
    Add(Vec<ElementId>),
    /// Select exactly these elements (a box).
    Replace(Vec<ElementId>),
    /// Every element of the active mesh of the kind the click mode picks (vertices in auto
    /// mode).
    All,
    /// One ring more, each kind by itself.
    Grow,
    /// One ring less, each kind by itself.
    Shrink,
    /// The edge loop through an edge (Alt+click), added to the set with Shift.
    Loop(EdgeId, bool),
    /// The edge ring through an edge (Ctrl+Alt+click), added to the set with Shift.
    Ring(EdgeId, bool),
}

impl SelectionEdit {
    /// A short label for logs.
    pub fn label(&self) -> String {
        match self {
            SelectionEdit::Toggle(x) => format!("toggle {x}"),
            SelectionEdit::Add(xs) => format!("add {} to the selection", xs.len()),
            SelectionEdit::Replace(xs) => format!("select {}", xs.len()),
            SelectionEdit::All => "select all".into(),
            SelectionEdit::Grow => "select more".into(),
            SelectionEdit::Shrink => "select less".into(),
            SelectionEdit::Loop(e, _) => format!("select the loop through {e}"),
            SelectionEdit::Ring(e, _) => format!("select the ring through {e}"),
        }
    }
}

/// Why the editor did not do what was asked. The mesh is then unchanged.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum Declined {
    /// The operation refused (see [`Refusal`]).
    #[error(transparent)]
    Refused(#[from] Refusal),
    /// There is no mesh to act on.
    #[error("there is no mesh")]
    NoMesh,
    /// The request needs a selected element of some kind.
    #[error("select {0} first")]
    SelectFirst(String),
    /// A relation that leads nowhere from the selected element.
    #[error("{0} has no {1} (a boundary halfedge has no face)")]
    NoRelation(ElementId, &'static str),
    /// The named element does not exist.
    #[error("{0} does not exist")]
    NoSuchElement(ElementId),
    /// An edit was asked while an operation runs as a job.
    #[error("{0} is still running: wait for it, or cancel it (Esc)")]
    Busy(String),
    /// Cancel was asked with no job running.
    #[error("no operation is running")]
    NoJob,
    /// A step was asked with no stepped run in progress.
    #[error("no operation is being stepped through: turn step mode on (F9) and start one")]
    NoSteppedRun,
    /// Nothing to undo or redo.
    #[error("nothing to {0}")]
    NothingTo(&'static str),
    /// Opening over unsaved changes: the user is asked first.
    #[error("the mesh has unsaved changes: save it (Ctrl+S) or discard them first")]
    UnsavedChanges,
    /// A save into a format that cannot hold some of what the mesh has: the user is asked
    /// first. The text names what would be dropped.
    #[error("{0}: answer Save anyway, or Save as .ply (or .obj) to keep them")]
    WouldDrop(String),
    /// An answer to a question nobody asked.
    #[error("nothing is waiting for an answer")]
    NothingWaiting,
    /// Save without a path for a mesh that never had a file.
    #[error("this mesh has no file yet: use Save as")]
    NoFileYet,
    /// A file could not be read or written; the text names it and says why.
    #[error("{0}")]
    File(String),
    /// A job's thread could not start, or broke (a bug).
    #[error("{0}")]
    Job(String),
}

/// How the offer of a recovery found at start is answered ([`crate::editor::pipeline::recovery`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecoveryAnswer {
    /// Open the recovered mesh (as unsaved work on its source file).
    Restore,
    /// Delete the recovery.
    Discard,
    /// Close the offer and keep the recovery for later (`pappus recover`).
    Keep,
}

/// What waits for the user to say whether something may be discarded.
#[derive(Clone, Debug, PartialEq)]
pub enum PendingDiscard {
    /// Opening this file over the modified mesh (its unsaved changes would be lost).
    Open(PathBuf),
    /// Closing the window (the unsaved changes would be lost).
    Quit,
    /// Saving into this file, whose format cannot hold what is named (`"UVs"`, `"normals"`, …).
    Save {
        /// The file.
        path: PathBuf,
        /// What the save would drop.
        dropped: Vec<&'static str>,
    },
}

/// The question whether something may be discarded, while it is open.
#[derive(Resource, Default, Debug, Clone)]
pub struct ConfirmDiscard(pub Option<PendingDiscard>);

/// What became of one [`Request`].
#[derive(Message, Clone, Debug, PartialEq)]
pub struct EditOutcome {
    /// The request's label.
    pub request: String,
    /// `Ok(summary)` if applied, `Err(why)` if declined (the mesh is then unchanged).
    pub result: Result<String, Declined>,
}

/// The last outcomes, newest last, for the status line and the log panel.
#[derive(Resource, Default, Debug)]
pub struct OutcomeLog {
    /// Up to [`OutcomeLog::CAPACITY`] entries.
    pub entries: Vec<EditOutcome>,
    /// The log's messages, as the editor's log layer keeps them
    /// ([`super::capture_layer`]; none in an app without it).
    pub messages: super::log_capture::LogMessages,
}

impl OutcomeLog {
    /// How many outcomes are kept.
    pub const CAPACITY: usize = 200;

    /// Appends an outcome, dropping the oldest past the capacity. A repeat of the last request
    /// (each frame of a vertex drag) replaces it rather than filling the log.
    pub fn push(&mut self, outcome: EditOutcome) {
        if let Some(last) = self.entries.last_mut()
            && last.request == outcome.request
            && last.result.is_ok()
            && outcome.result.is_ok()
        {
            *last = outcome;
            return;
        }
        if self.entries.len() == Self::CAPACITY {
            self.entries.remove(0);
        }
        self.entries.push(outcome);
    }
}
