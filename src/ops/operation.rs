//! Operations that declare themselves whole, and what every edit returns.
//!
//! A [`MeshOperation`] is a whole-mesh operation described entirely by its [`Declaration`] —
//! its step's name, its title and help line, its key, its numeric parameters with their
//! defaults and ranges, whether it may run as a job, which ids and attributes survive it — and
//! one `apply`. Registered once in [`crate::ops::OPERATIONS`], it is then a `process` step
//! (`name[:VALUE…]`, listed in the usage text), a key in the editor's shortcut table and help
//! overlay, a button with its parameters in the panel's *Whole mesh* section, a `Mesh.step`
//! from Python, an undoable edit, and a job on a large mesh: nothing else names it. Blender's
//! operators are the model — a class declares `bl_idname`, `bl_label`, its properties with
//! their defaults and limits, and `execute`; the keymap and the menus refer to it by id, and
//! the redo panel draws its properties.
//!
//! [`Invocation`] is one use of an operation with its parameters' values, checked against the
//! declared ranges when it is made: what [`crate::edit::Edit::Operation`] carries.
//!
//! The edit layer's result types live here too ([`Applied`], [`Redraw`], [`EditContext`]), so
//! that an operation can return them without `ops` importing the layer above it.

use std::fmt;

use bevy::prelude::World;

use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::ops::Refusal;
use crate::ops::declaration::Declaration;
use crate::ops::progressive::ProgressiveMesh;

/// What to redraw after an edit.
#[derive(Clone, Debug, PartialEq)]
pub enum Redraw {
    /// The faces around these vertices (as they are now), and these faces (from before the
    /// edit; they may be gone).
    Near {
        /// Faces from before the edit.
        faces: Vec<FaceId>,
        /// Vertices around which the faces changed.
        vertices: Vec<VertexId>,
    },
    /// The whole mesh.
    Whole,
    /// Only vertex positions changed (a move of most of the mesh): every face keeps its
    /// corners, so a render copy keeps its triangles and refreshes its positions.
    Positions,
}

/// An edit carried out.
#[derive(Clone, Debug, PartialEq)]
pub struct Applied {
    /// One line for the status bar, the log and the command line's report.
    pub summary: String,
    /// What changed, for a renderer.
    pub redraw: Redraw,
    /// What the edit made, for the selection to move to (`None`: keep the selection, if its
    /// element survived).
    pub made: Option<ElementId>,
}

impl Applied {
    /// A whole-mesh edit's outcome: redraw everything, keep the selection.
    pub fn whole(summary: String) -> Self {
        Self {
            summary,
            redraw: Redraw::Whole,
            made: None,
        }
    }
}

/// What an edit runs with beside the world: the simplification history, and the progress
/// callback that long edits report to.
pub struct EditContext<'a> {
    /// The simplification history: a simplification replaces it, a move along the level of
    /// detail or a vertex split moves along it. The caller drops it after an edit whose
    /// declaration does not keep it.
    pub history: &'a mut Option<ProgressiveMesh>,
    /// Called with the fraction done (0–1) now and then by long edits; returning `false` asks
    /// the edit to stop early where it can (the mesh is then valid, the edit partly done).
    pub progress: &'a mut dyn FnMut(f32) -> bool,
}

/// A whole-mesh operation that declares itself entirely (see the module doc). Implementors
/// are unit structs listed in [`crate::ops::OPERATIONS`].
pub trait MeshOperation: Sync + 'static {
    /// What it declares: name, title, help, key, parameters, job, ids, attributes.
    fn declaration(&self) -> &'static Declaration;

    /// Applies it to `mesh` (which exists) with one value per declared parameter, each
    /// already checked against its range.
    ///
    /// # Refusals
    /// Its own; the world is then exactly as it was.
    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: &[f32],
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal>;
}

/// One use of a [`MeshOperation`]: the operation and a value for each of its parameters, in
/// range. Compared, printed and labelled by the operation's name and the values.
#[derive(Clone, Copy)]
pub struct Invocation {
    operation: &'static dyn MeshOperation,
    values: [f32; Invocation::MAX_PARAMETERS],
}

impl Invocation {
    /// The most parameters an operation may declare (`Declaration::with_parameters` refuses
    /// more when it is compiled).
    pub const MAX_PARAMETERS: usize = 4;

    /// `operation` with its defaults.
    pub fn with_defaults(operation: &'static dyn MeshOperation) -> Self {
        let mut values = [0.0; Self::MAX_PARAMETERS];
        for (v, p) in values.iter_mut().zip(operation.declaration().parameters) {
            *v = p.default;
        }
        Self { operation, values }
    }

    /// `operation` with these values (missing ones take their defaults).
    ///
    /// # Errors
    /// More values than parameters, or a value out of its parameter's range: the message says
    /// which and what it takes.
    pub fn new(operation: &'static dyn MeshOperation, given: &[f32]) -> Result<Self, String> {
        let declaration = operation.declaration();
        let parameters = declaration.parameters;
        if given.len() > parameters.len() {
            return Err(match parameters.len() {
                0 => format!("{} takes no parameters", declaration.name),
                n => format!("{} takes at most {n} parameter(s)", declaration.name),
            });
        }
        let mut invocation = Self::with_defaults(operation);
        for (i, &x) in given.iter().enumerate() {
            invocation.set(i, x)?;
        }
        Ok(invocation)
    }

    /// Parses the text after the step's name (`"2"`, `"2:0.5"`, or empty for the defaults).
    ///
    /// # Errors
    /// A value that is not a number, or as [`Invocation::new`].
    pub fn parse(operation: &'static dyn MeshOperation, args: &str) -> Result<Self, String> {
        let values: Vec<f32> = match args {
            "" => Vec::new(),
            _ => args
                .split(':')
                .map(|x| match x.trim() {
                    "" => Err("a value is missing".to_string()),
                    x => x
                        .parse::<f32>()
                        .map_err(|_| format!("`{x}` is not a number")),
                })
                .collect::<Result<_, _>>()?,
        };
        Self::new(operation, &values)
    }

    /// The operation.
    pub fn operation(&self) -> &'static dyn MeshOperation {
        self.operation
    }

    /// What the operation declares.
    pub fn declaration(&self) -> &'static Declaration {
        self.operation.declaration()
    }

    /// One value per declared parameter.
    pub fn values(&self) -> &[f32] {
        &self.values[..self.declaration().parameters.len()]
    }

    /// Sets the value of parameter `i`.
    ///
    /// # Errors
    /// No parameter `i`, or `x` out of its range: the invocation is unchanged.
    pub fn set(&mut self, i: usize, x: f32) -> Result<(), String> {
        let d = self.declaration();
        let p = d
            .parameters
            .get(i)
            .ok_or_else(|| format!("{} has no parameter {i}", d.name))?;
        if !p.admits(x) {
            return Err(format!("{} must be {}", p.name, p.range_words()));
        }
        self.values[i] = x;
        Ok(())
    }

    /// Its label for the log and the undo history: the title in lower case, and each
    /// parameter's value ("normalize (size 2)").
    pub fn label(&self) -> String {
        let d = self.declaration();
        let mut label = lower_first(d.title);
        let values: Vec<String> = d
            .parameters
            .iter()
            .zip(self.values())
            .map(|(p, x)| format!("{} {x}", p.name.to_lowercase()))
            .collect();
        if !values.is_empty() {
            label.push_str(&format!(" ({})", values.join(", ")));
        }
        label
    }

    /// Applies it (see [`MeshOperation::apply`]).
    ///
    /// # Refusals
    /// The operation's.
    pub fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        self.operation.apply(world, mesh, self.values(), context)
    }
}

/// As a `process` step: `name`, then each value after a colon (`normalize:2`).
impl fmt::Display for Invocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.declaration().name)?;
        self.values().iter().try_for_each(|x| write!(f, ":{x}"))
    }
}

impl fmt::Debug for Invocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Invocation({self})")
    }
}

impl PartialEq for Invocation {
    fn eq(&self, other: &Self) -> bool {
        self.declaration().name == other.declaration().name && self.values() == other.values()
    }
}

/// `"Reverse orientation"` → `"reverse orientation"`.
fn lower_first(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map(|c| c.to_lowercase().chain(chars).collect())
        .unwrap_or_default()
}

/// "1 face", "3 faces" ("vertex" → "vertices", "free vertex" → "free vertices").
pub fn count(n: usize, what: &str) -> String {
    match (n, what) {
        (1, _) => format!("1 {what}"),
        (_, w) if w.ends_with("vertex") => format!("{n} {}ices", &w[..w.len() - 2]),
        _ => format!("{n} {what}s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::declaration::Parameter;

    struct Scale;

    const SCALE: Declaration = Declaration::new("scale-test")
        .titled("Scale test")
        .with_parameters(&[
            Parameter::real("FACTOR", 1.0, 0.5, 2.0),
            Parameter::whole("TIMES", 1, 1, 3),
        ]);

    impl MeshOperation for Scale {
        fn declaration(&self) -> &'static Declaration {
            &SCALE
        }

        fn apply(
            &self,
            _: &mut World,
            _: MeshId,
            values: &[f32],
            _: &mut EditContext<'_>,
        ) -> Result<Applied, Refusal> {
            Ok(Applied::whole(format!("{values:?}")))
        }
    }

    #[test]
    fn an_invocation_takes_defaults_checks_ranges_and_prints_as_it_parses() {
        let defaults = Invocation::parse(&Scale, "").unwrap();
        assert_eq!(defaults.values(), [1.0, 1.0]);
        assert_eq!(defaults.to_string(), "scale-test:1:1");
        assert_eq!(defaults.label(), "scale test (factor 1, times 1)");
        let given = Invocation::parse(&Scale, "1.5").unwrap();
        assert_eq!(given.values(), [1.5, 1.0]);
        assert_eq!(
            Invocation::parse(&Scale, &given.to_string()[11..]).unwrap(),
            given
        );
        assert_eq!(
            Invocation::parse(&Scale, "3").unwrap_err(),
            "FACTOR must be a number from 0.5 to 2"
        );
        assert_eq!(
            Invocation::parse(&Scale, "1:1.5").unwrap_err(),
            "TIMES must be a whole number from 1 to 3"
        );
        assert_eq!(
            Invocation::parse(&Scale, "1:1:1").unwrap_err(),
            "scale-test takes at most 2 parameter(s)"
        );
        assert_eq!(
            Invocation::parse(&Scale, "x").unwrap_err(),
            "`x` is not a number"
        );
        assert_eq!(
            Invocation::parse(&Scale, ":2").unwrap_err(),
            "a value is missing"
        );
        assert_ne!(defaults, given);
        let mut set = defaults;
        set.set(0, 1.5).unwrap();
        assert_eq!(set, given);
        assert!(set.set(1, 7.0).is_err() && set.set(2, 1.0).is_err());
        assert_eq!(set, given);
    }

    #[test]
    fn counts_read_as_words() {
        assert_eq!(count(1, "face"), "1 face");
        assert_eq!(count(3, "face"), "3 faces");
        assert_eq!(count(2, "free vertex"), "2 free vertices");
    }
}
