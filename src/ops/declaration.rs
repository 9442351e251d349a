//! What an operation declares about itself, once, beside its algorithm: the name of its
//! `process` step, whether it may run as a job, which element ids survive it, whether the
//! simplification history does, and what becomes of the mesh's attributes.
//!
//! Blender's operators are the model: a class declares its id and flags (`bl_idname`,
//! `bl_options = {'UNDO'}`), and the keymap, the menus and the undo system read them instead of
//! knowing each operator. Here each operation's module holds a `const` [`Declaration`];
//! [`crate::edit::Edit::declaration`] maps every edit to one, and the undo history, the job
//! runner, the attribute bookkeeping and the step syntax's checks read it.

/// Why a simplification, and the moves along its history (level of detail, vertex splits),
/// drop the attributes: the summary's note.
pub const DROPPED_BY_SIMPLIFICATION: &str = "simplification does not carry attributes";

/// Which element ids mean the same element after an edit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IdsKept {
    /// Every element that survives keeps its id.
    All,
    /// Only vertices keep theirs (the tables were rewritten: subdivision).
    VerticesOnly,
}

impl IdsKept {
    /// Whether `x`'s id still names the same element after the edit (if it survived).
    pub fn keeps(self, x: crate::mesh::ids::ElementId) -> bool {
        self == IdsKept::All || matches!(x, crate::mesh::ids::ElementId::Vertex(_))
    }
}

/// What an operation does with the mesh's attributes (UVs, normals, colours, seams, groups).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Carries {
    /// It carries every attribute through.
    All,
    /// It carries some; the reason the others go, for the summary's note.
    Some(&'static str),
    /// It drops them all (a mesh made anew); the reason, for the summary's note.
    None(&'static str),
}

/// An operation's declaration. Built with [`Declaration::new`] and the `const` setters below,
/// so that a declaration reads as a sentence beside the operation:
/// `Declaration::new("simplify").as_job().keeping_history().dropping(WHY)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Declaration {
    /// The name of its `process` step (and Python method), or of the edit where it has no
    /// step (`"move"`).
    pub name: &'static str,
    /// Whether it has a `process` step of that name.
    pub is_step: bool,
    /// Whether it may run as a job (on a copy of the mesh, on a thread of its own) when the
    /// mesh is large: a whole-mesh operation that computes a new mesh from the old.
    pub job: bool,
    /// Which element ids keep their meaning through it.
    pub ids: IdsKept,
    /// Whether the simplification history still describes the mesh after it.
    pub keeps_history: bool,
    /// What becomes of the attributes.
    pub carries: Carries,
}

impl Declaration {
    /// A step called `name` that keeps every id and attribute, ends the simplification
    /// history and runs at once.
    pub const fn new(name: &'static str) -> Self {
        Self {
            name,
            is_step: true,
            job: false,
            ids: IdsKept::All,
            keeps_history: false,
            carries: Carries::All,
        }
    }

    /// An edit the editor makes that has no `process` step (a vertex move).
    pub const fn editor_only(self) -> Self {
        Self {
            is_step: false,
            ..self
        }
    }

    /// It may run as a job on a large mesh.
    pub const fn as_job(self) -> Self {
        Self { job: true, ..self }
    }

    /// Only vertex ids survive it.
    pub const fn renumbering(self) -> Self {
        Self {
            ids: IdsKept::VerticesOnly,
            ..self
        }
    }

    /// The simplification history survives it (it makes or moves along the history).
    pub const fn keeping_history(self) -> Self {
        Self {
            keeps_history: true,
            ..self
        }
    }

    /// It carries some attributes; `why` the others go.
    pub const fn carrying_some(self, why: &'static str) -> Self {
        Self {
            carries: Carries::Some(why),
            ..self
        }
    }

    /// It drops every attribute, for `why`.
    pub const fn dropping(self, why: &'static str) -> Self {
        Self {
            carries: Carries::None(why),
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_declaration_reads_as_it_is_built() {
        let d = Declaration::new("simplify")
            .as_job()
            .keeping_history()
            .dropping("simplification does not carry attributes");
        assert_eq!(d.name, "simplify");
        assert!(d.is_step && d.job && d.keeps_history);
        assert_eq!(d.ids, IdsKept::All);
        assert_eq!(
            d.carries,
            Carries::None("simplification does not carry attributes")
        );
        let moved = Declaration::new("move").editor_only();
        assert!(!moved.is_step && !moved.job && !moved.keeps_history);
        assert_eq!(moved.carries, Carries::All);
        assert_eq!(
            Declaration::new("loop").renumbering().ids,
            IdsKept::VerticesOnly
        );
    }
}
