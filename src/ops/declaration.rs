//! What an operation declares about itself, once, beside its algorithm: the name of its
//! `process` step, whether it may run as a job, which element ids survive it, whether the
//! simplification history does, and what becomes of the mesh's attributes — and, for the
//! operations that declare themselves whole ([`crate::ops::operation::MeshOperation`]), its
//! title, help line, key and parameters, from which the step parser, the usage text, the
//! keymap, the help overlay and the panel are built.
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Declaration {
    /// The name of its `process` step (and Python method), or of the edit where it has no
    /// step (`"move"`).
    pub name: &'static str,
    /// Its name in a person's words, capitalised, for its button ("Reverse orientation");
    /// lower-cased, it labels the edit in the log and the undo history.
    pub title: &'static str,
    /// What it does, in one line, for the help overlay, the usage text and the button's
    /// hover text (empty where the operation has not declared one).
    pub help: &'static str,
    /// Its key in the editor, if it has one, as the help overlay writes it: modifiers and a
    /// key joined by `+` (`"Alt+C"`, `"Ctrl+T"`, `"Shift+N"`); the editor's keymap reads it.
    pub key: Option<&'static str>,
    /// Its numeric parameters, in the order a step gives them.
    pub parameters: &'static [Parameter],
    /// Whether it has a `process` step of that name.
    pub is_step: bool,
    /// Whether it may run as a job (on a copy of the mesh, on a thread of its own) when the
    /// mesh is large: a whole-mesh operation that computes a new mesh from the old.
    pub job: bool,
    /// Which element ids keep their meaning through it.
    pub ids: IdsKept,
    /// Whether the simplification history still describes the mesh after it.
    pub keeps_history: bool,
    /// Whether the vertex normals it leaves still describe the surface (it moves nothing, or
    /// turns and scales them with it), so a save writes them as they are rather than
    /// recomputing them.
    pub keeps_normals: bool,
    /// What becomes of the attributes.
    pub carries: Carries,
}

impl Declaration {
    /// A step called `name` that keeps every id and attribute, ends the simplification
    /// history and runs at once.
    pub const fn new(name: &'static str) -> Self {
        Self {
            name,
            title: name,
            help: "",
            key: None,
            parameters: &[],
            is_step: true,
            job: false,
            ids: IdsKept::All,
            keeps_history: false,
            keeps_normals: false,
            carries: Carries::All,
        }
    }

    /// Its title, for its button and (lower-cased) its label.
    pub const fn titled(self, title: &'static str) -> Self {
        Self { title, ..self }
    }

    /// What it does, in one line.
    pub const fn described(self, help: &'static str) -> Self {
        Self { help, ..self }
    }

    /// Its key in the editor (`"Alt+C"`).
    pub const fn on_key(self, key: &'static str) -> Self {
        Self {
            key: Some(key),
            ..self
        }
    }

    /// Its parameters: at most four (`Invocation::MAX_PARAMETERS`), or the declaration does
    /// not compile.
    pub const fn with_parameters(self, parameters: &'static [Parameter]) -> Self {
        assert!(
            parameters.len() <= 4,
            "an operation declares at most 4 parameters"
        );
        Self { parameters, ..self }
    }

    /// The vertex normals it leaves still describe the surface.
    pub const fn keeping_normals(self) -> Self {
        Self {
            keeps_normals: true,
            ..self
        }
    }

    /// Its step's syntax for the usage text: the name, each parameter as `[:NAME]`, and the
    /// help line with the defaults (`normalize[:SIZE]   (centre …; SIZE 1 by default)`).
    pub fn syntax(&self) -> String {
        let mut text = self.name.to_string();
        for p in self.parameters {
            text.push_str(&format!("[:{}]", p.name));
        }
        let defaults: Vec<String> = self
            .parameters
            .iter()
            .map(|p| format!("{} {} by default", p.name, p.default))
            .collect();
        match (self.help, defaults.is_empty()) {
            ("", true) => text,
            (help, true) => format!("{text}   ({help})"),
            (help, false) => format!("{text}   ({help}; {})", defaults.join(", ")),
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

/// One numeric parameter of an operation: its name (in the usage text, the panel and labels),
/// its default and the closed range it must lie in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameter {
    /// Its name, in capitals in the usage text (`normalize[:SIZE]`).
    pub name: &'static str,
    /// Its value when the step or the panel gives none.
    pub default: f32,
    /// The least value it takes.
    pub min: f32,
    /// The greatest value it takes.
    pub max: f32,
    /// Whether it takes whole numbers only (iterations, levels).
    pub whole: bool,
}

impl Parameter {
    /// A real parameter in `min..=max`.
    pub const fn real(name: &'static str, default: f32, min: f32, max: f32) -> Self {
        Self {
            name,
            default,
            min,
            max,
            whole: false,
        }
    }

    /// A whole-number parameter in `min..=max`.
    pub const fn whole(name: &'static str, default: u32, min: u32, max: u32) -> Self {
        Self {
            name,
            default: default as f32,
            min: min as f32,
            max: max as f32,
            whole: true,
        }
    }

    /// Whether `x` is a value it takes.
    pub fn admits(&self, x: f32) -> bool {
        (self.min..=self.max).contains(&x) && (!self.whole || x.fract() == 0.0)
    }

    /// Its range in words, for refusals: "a number from 0.001 to 1000", "a whole number from 1
    /// to 100".
    pub fn range_words(&self) -> String {
        let kind = if self.whole {
            "a whole number"
        } else {
            "a number"
        };
        format!("{kind} from {} to {}", self.min, self.max)
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
