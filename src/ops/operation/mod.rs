//! Operations that declare themselves whole, and what every edit returns.
//!
//! A [`MeshOperation`] is a whole-mesh operation described entirely by its [`Declaration`] —
//! its step's name, its title and help line, its key, its parameters (numbers in a range,
//! choices of words, values left `auto`) with their defaults, its panel section, whether it may
//! run as a job, which ids and attributes survive it — and one `apply`. Registered once in
//! the process's [`crate::ops::registry`] (from this crate or another), it is then a `process` step (`name[:VALUE…]`, listed in the
//! usage text), a key in the editor's shortcut table and help overlay, a button with its
//! parameters in the panel section it declares, a `Mesh.step`
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

use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::tables::{Connectivity, MeshTables};
use crate::mesh::{InMesh, MeshInfo, MeshRef};
use crate::ops::Refusal;
use crate::ops::declaration::{Declaration, Names, ParameterKind};

mod local_outcome;
mod outcome;
pub mod stepping;
pub use outcome::{Applied, EditContext, Reach, Redraw};
use stepping::Steps;

/// A whole-mesh operation that declares itself entirely (see the module doc). Implementors
/// are unit structs, Pappus's own listed in [`crate::ops::registry::BUILT_IN`]; another
/// crate's join them through [`crate::ops::registry::register`].
pub trait MeshOperation: Sync + 'static {
    /// What it declares: name, title, help, key, parameters, job, ids, attributes.
    fn declaration(&self) -> &'static Declaration;

    /// Applies it to `mesh` (which exists) with a value for each declared parameter, each
    /// already checked against what the parameter takes.
    ///
    /// # Refusals
    /// Its own; the world is then exactly as it was.
    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal>;

    /// What it may change, for the undo record (`None` when `mesh` or an element it names is
    /// gone: it will be refused, and changes nothing). The default: any element of `mesh` for
    /// a whole-mesh operation (one that names nothing, or only vertices it holds); the
    /// neighbourhood of the corners of the one element it
    /// names (an edge's ends, a vertex, a face's corners); `None` for two elements or more, so
    /// an operation that names several (faces, vertices, a face and its corners, held
    /// vertices) says its own reach.
    fn reach(&self, world: &World, mesh: MeshId, values: Values<'_>) -> Option<Reach> {
        if self.declaration().names.is_whole_mesh() {
            return world.get::<MeshInfo>(mesh.0).map(|_| Reach::Whole(mesh));
        }
        match values.elements() {
            &[x] => {
                let corners = MeshRef::new(world).corners(x);
                let mesh = world.get::<InMesh>(corners.first()?.0)?.0;
                Some(Reach::Local(mesh, corners))
            }
            _ => None,
        }
    }

    /// A run of it a step at a time on `mesh` (which exists), for the editor's step mode: `None`,
    /// the default, for an operation that runs whole. One that declares
    /// [`Declaration::stepping`] gives `Some`, a run whose steps, taken to the end, leave the
    /// mesh exactly as [`MeshOperation::apply`] with the same values would.
    ///
    /// # Refusals
    /// As `apply`'s; the world is then exactly as it was.
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let _ = (world, mesh, values);
        None
    }

    /// Its result computed from the mesh's tables alone — the tables after and the outcome
    /// (without the attributes' note, which the edit adds) — where that is exactly what
    /// [`MeshOperation::apply`] would write back and say. `None`, the default, for an operation
    /// that needs the entities; one that declares `computed_on_tables` gives `Some`.
    ///
    /// # Refusals
    /// As `apply`'s.
    fn run_on_tables(
        &self,
        before: &MeshTables,
        values: Values<'_>,
    ) -> Option<Result<(Connectivity, Applied), Refusal>> {
        let _ = (before, values);
        None
    }
}

/// The values an operation is applied with, one a declared parameter, read by the kind the
/// operation declared, and the elements it names. Each value is in its parameter's range (an
/// [`Invocation`] admits no other), only a parameter declared automatic may be left out, and
/// the elements are what the declaration names (their number and kinds).
#[derive(Clone, Copy, Debug)]
pub struct Values<'a> {
    numbers: &'a [Option<f64>],
    elements: &'a [ElementId],
}

impl Values<'_> {
    /// Parameter `i`'s number (0 where a parameter declared automatic was left out: read
    /// those with [`Values::given`]).
    pub fn number(&self, i: usize) -> f64 {
        self.numbers[i].unwrap_or_default()
    }

    /// Parameter `i`'s whole number.
    pub fn whole(&self, i: usize) -> u32 {
        self.number(i) as u32
    }

    /// The index of parameter `i`'s word among its choices.
    pub fn choice(&self, i: usize) -> usize {
        self.number(i) as usize
    }

    /// Parameter `i`'s value, `None` where it was left to the operation (`auto`).
    pub fn given(&self, i: usize) -> Option<f64> {
        self.numbers[i]
    }

    /// The elements it names, in the order its declaration names them.
    pub fn elements(&self) -> &[ElementId] {
        self.elements
    }

    /// The edge it names (an operation that declares [`Names::Edge`]).
    ///
    /// # Refusals
    /// [`Refusal::BadParameter`] when it names no edge: the invocation was made for another
    /// declaration.
    pub fn edge(&self) -> Result<EdgeId, Refusal> {
        match self.elements {
            [ElementId::Edge(e)] => Ok(*e),
            _ => Err(self.wrong("an edge")),
        }
    }

    /// The vertex it names ([`Names::Vertex`]).
    ///
    /// # Refusals
    /// As [`Values::edge`].
    pub fn vertex(&self) -> Result<VertexId, Refusal> {
        match self.elements {
            [ElementId::Vertex(v)] => Ok(*v),
            _ => Err(self.wrong("a vertex")),
        }
    }

    /// The face it names ([`Names::Face`]).
    ///
    /// # Refusals
    /// As [`Values::edge`].
    pub fn face(&self) -> Result<FaceId, Refusal> {
        match self.elements {
            [ElementId::Face(f)] => Ok(*f),
            _ => Err(self.wrong("a face")),
        }
    }

    /// The two edges it names, in order ([`Names::TwoEdges`]).
    ///
    /// # Refusals
    /// As [`Values::edge`].
    pub fn two_edges(&self) -> Result<[EdgeId; 2], Refusal> {
        match self.elements {
            [ElementId::Edge(a), ElementId::Edge(b)] => Ok([*a, *b]),
            _ => Err(self.wrong("two edges")),
        }
    }

    /// The vertices among the elements it names, in order ([`Names::Vertices`], and the held
    /// vertices of [`Names::MeshHolding`]).
    pub fn vertices(&self) -> Vec<VertexId> {
        self.elements
            .iter()
            .filter_map(|x| match x {
                ElementId::Vertex(v) => Some(*v),
                _ => None,
            })
            .collect()
    }

    /// The face and the two corners it names ([`Names::FaceCorners`]).
    ///
    /// # Refusals
    /// As [`Values::edge`].
    pub fn face_corners(&self) -> Result<(FaceId, VertexId, VertexId), Refusal> {
        match self.elements {
            [
                ElementId::Face(f),
                ElementId::Vertex(a),
                ElementId::Vertex(b),
            ] => Ok((*f, *a, *b)),
            _ => Err(self.wrong("a face and two of its corners")),
        }
    }

    /// The faces it names ([`Names::Faces`]), each once, in entity order: however they were
    /// named (a step's order, the selection's), one set gives one result.
    ///
    /// # Refusals
    /// As [`Values::edge`].
    pub fn faces(&self) -> Result<Vec<FaceId>, Refusal> {
        let mut faces = self
            .elements
            .iter()
            .map(|x| match x {
                ElementId::Face(f) => Ok(*f),
                _ => Err(self.wrong("faces")),
            })
            .collect::<Result<Vec<_>, _>>()?;
        faces.sort_unstable();
        faces.dedup();
        Ok(faces)
    }

    fn wrong(&self, needed: &str) -> Refusal {
        Refusal::BadParameter(format!("{needed} is needed, not {:?}", self.elements))
    }
}

/// One use of a [`MeshOperation`]: the operation, a value for each of its parameters, each
/// one the parameter takes, and the elements it names (none for a whole-mesh operation).
/// Compared and labelled by the operation's name, the elements and the values.
#[derive(Clone)]
pub struct Invocation {
    operation: &'static dyn MeshOperation,
    values: [Option<f64>; Invocation::MAX_PARAMETERS],
    elements: Vec<ElementId>,
}

impl Invocation {
    /// The most parameters an operation may declare (`Declaration::with_parameters` refuses
    /// more when it is compiled).
    pub const MAX_PARAMETERS: usize = 4;

    /// `operation` with its defaults.
    pub fn with_defaults(operation: &'static dyn MeshOperation) -> Self {
        let mut values = [None; Self::MAX_PARAMETERS];
        for (v, p) in values.iter_mut().zip(operation.declaration().parameters) {
            *v = p.default;
        }
        Self {
            operation,
            values,
            elements: Vec::new(),
        }
    }

    /// This invocation on `elements` (what a local operation names: the selected edge, the
    /// edge a step names).
    ///
    /// # Errors
    /// Elements that are not what the operation names (their number or kinds): the message
    /// says what it names.
    pub fn on(mut self, elements: Vec<ElementId>) -> Result<Self, String> {
        let d = self.declaration();
        if !d.names.admits(&elements) {
            return Err(format!("{} needs {}", d.name, d.names.what()));
        }
        self.elements = elements;
        Ok(self)
    }

    /// The elements it names.
    pub fn elements(&self) -> &[ElementId] {
        &self.elements
    }

    /// `operation` with these values (missing ones take their defaults; `None`: automatic).
    ///
    /// # Errors
    /// More values than parameters, or a value its parameter does not take: the message says
    /// which and what it takes.
    pub fn new(
        operation: &'static dyn MeshOperation,
        given: &[Option<f64>],
    ) -> Result<Self, String> {
        takes(operation.declaration(), given.len())?;
        let mut invocation = Self::with_defaults(operation);
        for (i, &x) in given.iter().enumerate() {
            invocation.set(i, x)?;
        }
        Ok(invocation)
    }

    /// Parses the text after the step's name (`"2"`, `"2:0.5"`, `"lscm"`, `"5:auto:30"`, or
    /// empty for the defaults), each value as [`crate::ops::declaration::Parameter::read`] reads it.
    ///
    /// # Errors
    /// A value its parameter cannot read, or as [`Invocation::new`].
    pub fn parse(operation: &'static dyn MeshOperation, args: &str) -> Result<Self, String> {
        let declaration = operation.declaration();
        if args.is_empty() {
            return Ok(Self::with_defaults(operation));
        }
        let texts: Vec<&str> = args.split(':').map(str::trim).collect();
        takes(declaration, texts.len())?;
        let values = texts
            .iter()
            .zip(declaration.parameters)
            .map(|(text, p)| p.read(text))
            .collect::<Result<Vec<_>, _>>()?;
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

    /// Whether it invokes the operation that declares `declaration` (by name: registered
    /// operations have names of their own).
    pub fn is(&self, declaration: &Declaration) -> bool {
        self.declaration().name == declaration.name
    }

    /// One value per declared parameter.
    pub fn values(&self) -> Values<'_> {
        Values {
            numbers: &self.values[..self.declaration().parameters.len()],
            elements: &self.elements,
        }
    }

    /// Sets the value of parameter `i` (`None`: automatic).
    ///
    /// # Errors
    /// No parameter `i`, or a value it does not take: the invocation is unchanged.
    pub fn set(&mut self, i: usize, x: Option<f64>) -> Result<(), String> {
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

    /// Its label for the log and the undo history: the title in lower case, the elements it
    /// names, and each parameter's value, named, or a choice's word alone ("normalize (size
    /// 2)", "parameterize (lscm, circle)", "flip e12").
    pub fn label(&self) -> String {
        let d = self.declaration();
        let mut label = lower_first(d.title);
        let n = self.elements.len();
        match (d.names, self.elements.as_slice()) {
            (_, []) => {}
            (Names::FaceCorners, [f, a, b]) => label.push_str(&format!(" {f} between {a} and {b}")),
            (Names::MeshHolding, _) => {
                label.push_str(&format!(" holding {}", count(n, "vertex")));
            }
            (_, few @ ([_] | [_, _])) => few.iter().for_each(|x| label.push_str(&format!(" {x}"))),
            (Names::Faces, _) => label.push_str(&format!(" {}", count(n, "face"))),
            (Names::Vertices, _) => label.push_str(&format!(" {}", count(n, "vertex"))),
            _ => label.push_str(&format!(" {}", count(n, "element"))),
        }
        let values: Vec<String> = d
            .parameters
            .iter()
            .zip(self.values().numbers)
            .map(|(p, &x)| match p.kind {
                ParameterKind::Choice(_) => p.write(x),
                _ => format!("{} {}", p.name.to_lowercase(), p.write(x)),
            })
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

    /// What it may change (see [`MeshOperation::reach`]).
    pub fn reach(&self, world: &World, mesh: MeshId) -> Option<Reach> {
        self.operation.reach(world, mesh, self.values())
    }
}

/// As a `process` step: `name`, then each value after a colon as
/// [`crate::ops::declaration::Parameter::write`] writes it, up to the last that differs from
/// its default (`normalize`, `normalize:2`, `param:lscm`, `remesh:8:0.00001`); it parses back
/// to the same invocation. The elements are not written: a step names them by the input
/// file's vertex numbers, which the step keeps ([`crate::edit::Step`]).
impl fmt::Display for Invocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = self.declaration();
        let values = self.values().numbers;
        let given = d
            .parameters
            .iter()
            .zip(values)
            .rposition(|(p, &x)| x != p.default)
            .map_or(0, |last| last + 1);
        write!(f, "{}", d.name)?;
        d.parameters
            .iter()
            .zip(values)
            .take(given)
            .try_for_each(|(p, &x)| write!(f, ":{}", p.write(x)))
    }
}

impl fmt::Debug for Invocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Invocation({self})")
    }
}

impl PartialEq for Invocation {
    fn eq(&self, other: &Self) -> bool {
        self.declaration().name == other.declaration().name
            && self.declaration().names == other.declaration().names
            && self.values().numbers == other.values().numbers
            && self.elements == other.elements
    }
}

/// Whether an operation that declares `declaration` takes `given` values.
///
/// # Errors
/// More values than parameters: "reverse takes no parameters", "param takes at most 2
/// parameter(s)".
fn takes(declaration: &Declaration, given: usize) -> Result<(), String> {
    match declaration.parameters.len() {
        n if given <= n => Ok(()),
        0 => Err(format!("{} takes no parameters", declaration.name)),
        n => Err(format!(
            "{} takes at most {n} parameter(s)",
            declaration.name
        )),
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
            Parameter::choice("AXIS", &["x", "y", "z"], 2),
            Parameter::real("LIMIT", 0.0, 0.0, 10.0).automatic_by_default("no limit"),
        ]);

    impl MeshOperation for Scale {
        fn declaration(&self) -> &'static Declaration {
            &SCALE
        }

        fn apply(
            &self,
            _: &mut World,
            _: MeshId,
            values: Values<'_>,
            _: &mut EditContext<'_>,
        ) -> Result<Applied, Refusal> {
            Ok(Applied::whole(format!("{values:?}")))
        }
    }

    #[test]
    fn an_invocation_takes_defaults_checks_ranges_and_prints_as_it_parses() {
        let defaults = Invocation::parse(&Scale, "").unwrap();
        let v = defaults.values();
        assert_eq!(
            (v.number(0), v.whole(1), v.choice(2), v.given(3)),
            (1.0, 1, 2, None)
        );
        assert_eq!(defaults.to_string(), "scale-test");
        assert_eq!(
            defaults.label(),
            "scale test (factor 1, times 1, z, limit auto)"
        );
        let given = Invocation::parse(&Scale, "1.5:2:Y:0.25").unwrap();
        let v = given.values();
        assert_eq!((v.number(0), v.whole(1), v.choice(2)), (1.5, 2, 1));
        assert_eq!(v.given(3), Some(0.25));
        assert_eq!(given.to_string(), "scale-test:1.5:2:y:0.25");
        assert_eq!(
            Invocation::parse(&Scale, &given.to_string()[11..]).unwrap(),
            given
        );
        // A step's decimal is kept as read: 0.1 is the f64 nearest 0.1.
        // Trailing defaults are left out; one before a value given is written.
        let first = Invocation::parse(&Scale, "1.5:1:z:auto").unwrap();
        assert_eq!(first.to_string(), "scale-test:1.5");
        let last = Invocation::parse(&Scale, "1:1:z:3").unwrap();
        assert_eq!(last.to_string(), "scale-test:1:1:z:3");
        let tenth = Invocation::parse(&Scale, "0.5:1:x:0.1").unwrap();
        assert_eq!(tenth.values().given(3), Some(0.1));
        for (args, why) in [
            ("3", "FACTOR must be a number from 0.5 to 2"),
            ("1:1.5", "TIMES must be a whole number from 1 to 3"),
            ("1:1:w", "AXIS must be one of x, y, z"),
            (
                "1:1:x:11",
                "LIMIT must be a number from 0 to 10, or auto (no limit)",
            ),
            ("auto", "FACTOR must be a number from 0.5 to 2"),
            ("1:1:x:2:5", "scale-test takes at most 4 parameter(s)"),
            ("x", "FACTOR must be a number from 0.5 to 2"),
            (":2", "a value of FACTOR is missing"),
            ("NaN", "FACTOR must be a number from 0.5 to 2"),
        ] {
            assert_eq!(Invocation::parse(&Scale, args).unwrap_err(), why, "{args}");
        }
        assert_ne!(defaults, given);
        let mut set = defaults;
        set.set(0, Some(1.5)).unwrap();
        set.set(1, Some(2.0)).unwrap();
        set.set(2, Some(1.0)).unwrap();
        set.set(3, Some(0.25)).unwrap();
        assert_eq!(set, given);
        assert!(set.set(1, Some(7.0)).is_err() && set.set(4, Some(1.0)).is_err());
        assert!(set.set(0, None).is_err() && set.set(2, Some(3.0)).is_err());
        assert_eq!(set, given);
        set.set(3, None).unwrap();
        assert_eq!(set.values().given(3), None);
    }

    #[test]
    fn counts_read_as_words() {
        assert_eq!(count(1, "face"), "1 face");
        assert_eq!(count(3, "face"), "3 faces");
        assert_eq!(count(2, "free vertex"), "2 free vertices");
    }
}
