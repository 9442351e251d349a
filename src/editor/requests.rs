//! The messages that drive the editor: requests in, outcomes out.
//!
//! Every way of asking for an edit — a key, a panel button, a test — writes the same
//! [`EditRequest`]. One exclusive system ([`super::apply`]) applies them in order, in the
//! `Apply` set, and writes one [`EditOutcome`] per request, which the status line, the log and
//! (later) the history read. Nothing but that system changes a mesh.

use bevy::math::Vec3;
use bevy::prelude::{Message, Resource};
use std::path::PathBuf;

use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};

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

/// An edit or navigation the user asked for.
#[derive(Message, Clone, Debug, PartialEq)]
pub enum EditRequest {
    /// Flip an edge.
    Flip(EdgeId),
    /// Split an edge at its midpoint.
    Split(EdgeId),
    /// Collapse an edge to its midpoint.
    Collapse(EdgeId),
    /// Merge the two faces of an edge.
    Dissolve(EdgeId),
    /// Split a face between two of its corners.
    SplitFace(FaceId, VertexId, VertexId),
    /// Triangulate every polygon of a mesh.
    Triangulate(MeshId),
    /// QEM simplification to a ratio of the faces (recording its history).
    Simplify(MeshId, f32),
    /// Move along the last simplification's history to about this many faces.
    LevelOfDetail(usize),
    /// Split back the last collapse of the simplification history, if it kept this vertex.
    SplitVertex(VertexId),
    /// One level of Loop subdivision.
    LoopSubdivide(MeshId),
    /// One level of Catmull–Clark subdivision.
    CatmullClark(MeshId),
    /// Isotropic remeshing with the default parameters (mean edge length, 5 iterations).
    Remesh(MeshId),
    /// Move a vertex.
    MoveVertex(VertexId, Vec3),
    /// Select an element (or nothing).
    Select(Option<ElementId>),
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
    /// Redo the last undone edit.
    Redo,
    /// Answer the unsaved-changes question: `true` discards the changes and goes on with what
    /// was asked (opening another file, quitting), `false` cancels it.
    ConfirmDiscard(bool),
}

impl EditRequest {
    /// A short label for logs.
    pub fn label(&self) -> String {
        match self {
            EditRequest::Flip(e) => format!("flip {e}"),
            EditRequest::Split(e) => format!("split {e}"),
            EditRequest::Collapse(e) => format!("collapse {e}"),
            EditRequest::Dissolve(e) => format!("dissolve {e}"),
            EditRequest::SplitFace(f, a, b) => format!("split {f} between {a} and {b}"),
            EditRequest::Triangulate(m) => format!("triangulate {m}"),
            EditRequest::Simplify(m, r) => format!("simplify {m} to {:.0} %", r * 100.0),
            EditRequest::LevelOfDetail(n) => format!("level of detail {n} faces"),
            EditRequest::SplitVertex(v) => format!("split {v} back"),
            EditRequest::LoopSubdivide(m) => format!("Loop subdivision {m}"),
            EditRequest::CatmullClark(m) => format!("Catmull-Clark subdivision {m}"),
            EditRequest::Remesh(m) => format!("remesh {m}"),
            EditRequest::MoveVertex(v, _) => format!("move {v}"),
            EditRequest::Select(Some(x)) => format!("select {x}"),
            EditRequest::Select(None) => "select nothing".into(),
            EditRequest::Navigate(r) => format!("go to {}", r.name()),
            EditRequest::Open(p) => format!("open {}", p.display()),
            EditRequest::Save(Some(p)) => format!("save as {}", p.display()),
            EditRequest::Save(None) => "save".into(),
            EditRequest::DeleteMesh => "delete mesh".into(),
            EditRequest::CancelJob => "cancel".into(),
            EditRequest::Undo => "undo".into(),
            EditRequest::Redo => "redo".into(),
            EditRequest::ConfirmDiscard(true) => "discard changes".into(),
            EditRequest::ConfirmDiscard(false) => "keep changes".into(),
        }
    }

    /// Whether the request changes a mesh (and so marks it for re-rendering).
    pub fn edits(&self) -> bool {
        !matches!(
            self,
            EditRequest::Select(_)
                | EditRequest::Navigate(_)
                | EditRequest::Save(_)
                | EditRequest::ConfirmDiscard(_)
                | EditRequest::CancelJob
        )
    }
}

/// What waits for the user to say whether unsaved changes may be discarded.
#[derive(Clone, Debug, PartialEq)]
pub enum PendingDiscard {
    /// Opening this file over the modified mesh.
    Open(PathBuf),
    /// Closing the window.
    Quit,
}

/// The unsaved-changes question, while it is open.
#[derive(Resource, Default, Debug, Clone)]
pub struct ConfirmDiscard(pub Option<PendingDiscard>);

/// What became of one [`EditRequest`].
#[derive(Message, Clone, Debug, PartialEq)]
pub struct EditOutcome {
    /// The request's label.
    pub request: String,
    /// `Ok(summary)` if applied, `Err(reason)` if refused (the mesh is then unchanged).
    pub result: Result<String, String>,
}

/// The last outcomes, newest last, for the status line and the log panel.
#[derive(Resource, Default, Debug)]
pub struct OutcomeLog {
    /// Up to [`OutcomeLog::CAPACITY`] entries.
    pub entries: Vec<EditOutcome>,
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
