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

use crate::mesh::ids::ElementId;

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

/// How an operation that renumbers the faces (subdivision) lays out the faces it makes: each
/// old face's children one after another, in the old face order, and the same again at each
/// further level (a subdivision run LEVELS times). What lets a value on a face (a script's
/// `face_data`) follow it to its children exactly, where geometry alone would give a face near
/// an edge its neighbour's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceChildren {
    /// Each face becomes this many faces of as many sides as it had (Loop: 4 triangles).
    Each(u32),
    /// Each face becomes one face per corner, each of this many sides (Catmull–Clark: quads).
    PerCorner(u32),
}

impl FaceChildren {
    /// The old face (its row) each of `made` faces came from, for old faces of `sides`
    /// corners each: the layout applied level after level until it makes `made` faces. `None`
    /// when no number of levels (up to 16) makes exactly that many: the faces were not laid out
    /// this way, and the caller must not assume they were.
    pub fn parents(self, sides: &[u32], made: usize) -> Option<Vec<u32>> {
        let (mut children, mut sides_now) = (vec![1u64; sides.len()], sides.to_vec());
        for _ in 0..16 {
            for (c, s) in children.iter_mut().zip(&mut sides_now) {
                let factor = match self {
                    FaceChildren::Each(n) => n,
                    FaceChildren::PerCorner(k) => std::mem::replace(s, k),
                };
                *c = c.saturating_mul(u64::from(factor));
            }
            let total = children.iter().fold(0u64, |t, &c| t.saturating_add(c));
            if total == made as u64 {
                let rows = children.iter().enumerate();
                return Some(
                    rows.flat_map(|(f, &c)| std::iter::repeat_n(f as u32, c as usize))
                        .collect(),
                );
            }
            if total > made as u64 {
                return None;
            }
        }
        None
    }
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
    /// The elements it names beside the mesh (none for a whole-mesh operation, or only the
    /// vertices it holds: smoothing): what the editor takes from the selection and a step
    /// names by input vertex numbers.
    pub names: Names,
    /// Its parameters, in the order a step gives them.
    pub parameters: &'static [Parameter],
    /// The section of the editor's panel that shows its button and parameters.
    pub section: Section,
    /// Whether it has a `process` step of that name.
    pub is_step: bool,
    /// Whether it may run as a job (on a copy of the mesh, on a thread of its own) when the
    /// mesh is large: a whole-mesh operation that computes a new mesh from the old.
    pub job: bool,
    /// Whether it computes its result from the mesh's tables alone
    /// (`MeshOperation::run_on_tables`), so a job need not copy the entities.
    pub on_tables: bool,
    /// Which element ids keep their meaning through it.
    pub ids: IdsKept,
    /// How it lays out the faces it makes, when it renumbers them (subdivision).
    pub face_children: Option<FaceChildren>,
    /// Whether the simplification history still describes the mesh after it.
    pub keeps_history: bool,
    /// Whether its uses merge into one undo step while one mouse press lasts (the frames of a
    /// slider's drag).
    pub merges_while_held: bool,
    /// Whether the vertex normals it leaves still describe the surface (it moves nothing, or
    /// turns and scales them with it), so a save writes them as they are rather than
    /// recomputing them.
    pub keeps_normals: bool,
    /// What becomes of the attributes.
    pub carries: Carries,
    /// Whether step mode runs it a step at a time
    /// (`crate::ops::operation::MeshOperation::step_through`).
    pub steps: bool,
    /// The operation it claims to reproduce (`"flip"`), for a lab: applying it runs both on
    /// copies of the mesh and compares them ([`crate::edit::lab`]); `None` for an operation
    /// that is its own reference.
    pub reference: Option<&'static str>,
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
            names: Names::Mesh,
            parameters: &[],
            section: Section::WholeMesh,
            is_step: true,
            job: false,
            on_tables: false,
            ids: IdsKept::All,
            face_children: None,
            keeps_history: false,
            merges_while_held: false,
            keeps_normals: false,
            carries: Carries::All,
            steps: false,
            reference: None,
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

    /// The elements it names (an edge, a vertex, faces): a local operation.
    pub const fn naming(self, names: Names) -> Self {
        Self { names, ..self }
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

    /// Its button goes in `section` of the editor's panel (*Whole mesh* unless said).
    pub const fn in_section(self, section: Section) -> Self {
        Self { section, ..self }
    }

    /// Its uses merge into one undo step while one mouse press lasts.
    pub const fn merging_while_held(self) -> Self {
        Self {
            merges_while_held: true,
            ..self
        }
    }

    /// The vertex normals it leaves still describe the surface.
    pub const fn keeping_normals(self) -> Self {
        Self {
            keeps_normals: true,
            ..self
        }
    }

    /// Its step's syntax for the usage text: the name, each parameter as `[:NAME]` (a choice
    /// as its words), and the help line with the defaults (`normalize[:SIZE]   (centre …; by
    /// default SIZE 1)`).
    pub fn syntax(&self) -> String {
        let mut text = self.name.to_string();
        if let Some(elements) = self.names.placeholder() {
            text.push(':');
            text.push_str(elements);
        }
        for p in self.parameters {
            text.push_str(&format!("[:{}]", p.placeholder()));
        }
        let defaults: Vec<String> = self
            .parameters
            .iter()
            .map(|p| match (p.default, p.automatic) {
                (None, Some(what)) => format!("{} auto ({what})", p.name),
                (x, _) => format!("{} {}", p.name, p.write(x)),
            })
            .collect();
        match (self.help, defaults.is_empty()) {
            ("", true) => text,
            (help, true) => format!("{text}   ({help})"),
            (help, false) => format!("{text}   ({help}; by default {})", defaults.join(", ")),
        }
    }

    /// An edit the editor makes that has no `process` step (a vertex move).
    pub const fn editor_only(self) -> Self {
        Self {
            is_step: false,
            ..self
        }
    }

    /// It reproduces the registered operation called `reference` (a student's flip claims
    /// `"flip"`): each application is checked against it on copies of the mesh first, and an
    /// invalid or panicking result is refused with the mesh untouched ([`crate::edit::lab`]).
    pub const fn checked_against(self, reference: &'static str) -> Self {
        Self {
            reference: Some(reference),
            ..self
        }
    }

    /// Step mode runs it a step at a time: it gives a run from `step_through`.
    pub const fn stepping(self) -> Self {
        Self {
            steps: true,
            ..self
        }
    }

    /// It may run as a job on a large mesh.
    pub const fn as_job(self) -> Self {
        Self { job: true, ..self }
    }

    /// It computes its result from the tables alone (and implements
    /// `MeshOperation::run_on_tables`).
    pub const fn computed_on_tables(self) -> Self {
        Self {
            on_tables: true,
            ..self
        }
    }

    /// Only vertex ids survive it; the faces it makes are laid out as `children` say.
    pub const fn renumbering(self, children: FaceChildren) -> Self {
        Self {
            ids: IdsKept::VerticesOnly,
            face_children: Some(children),
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

/// The sections of the editor's panel an operation's button may go in (the editor owns the
/// rest of each section).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// *Whole mesh*: operations that rework the whole mesh.
    WholeMesh,
    /// *Shape*: fairing, hole filling, deformation.
    Shape,
    /// *UV*: parameterization.
    Uv,
    /// *Local operations*: the halfedge operations on the selected element.
    Local,
    /// *Modelling*: Blender's edit-mode operations on the selection.
    Modelling,
}

/// What elements an operation names, beside the mesh it acts on. The editor takes them from
/// the selection; a `process` step names them by the input file's vertex numbers (`A` a
/// vertex, `A,B` the edge between two, or for [`Names::FaceCorners`] the face the two share).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Names {
    /// None: it acts on the whole mesh.
    Mesh,
    /// The whole mesh, with the vertices named held where they are (none in a step; the
    /// selected vertices in the editor): smoothing.
    MeshHolding,
    /// One edge: the selected edge, or the selected halfedge's.
    Edge,
    /// One vertex.
    Vertex,
    /// One face.
    Face,
    /// One face or more (`A,B,C/D,E,F`): the selected faces.
    Faces,
    /// Two edges, in order (`A,B/C,D`): the first two selected.
    TwoEdges,
    /// One vertex or more (`A/B/C`): the selected vertices.
    Vertices,
    /// A face and two of its corners, in that order (`A,B`: the face the two vertices share;
    /// the selected halfedge's face, its tip and the corner two ahead): a face split.
    FaceCorners,
    /// One element or more, of any kind (`4/0,1/0,1,2`): the selection.
    Elements,
}

impl Names {
    /// How a step writes the elements (`A,B`), `None` for a whole-mesh operation.
    pub fn placeholder(self) -> Option<&'static str> {
        match self {
            Names::Mesh | Names::MeshHolding => None,
            Names::Edge | Names::FaceCorners => Some("A,B"),
            Names::Vertex => Some("A"),
            Names::Face => Some("A,B,C"),
            Names::Faces => Some("FACES"),
            Names::TwoEdges => Some("A,B/C,D"),
            Names::Elements => Some("ELEMENTS"),
            Names::Vertices => Some("VERTICES"),
        }
    }

    /// What it names, in a person's words ("an edge", "two edges").
    pub fn what(self) -> &'static str {
        match self {
            Names::Mesh | Names::MeshHolding => "the mesh",
            Names::Edge => "an edge",
            Names::Vertex => "a vertex",
            Names::Face => "a face",
            Names::Faces => "faces",
            Names::TwoEdges => "two edges",
            Names::Elements => "elements",
            Names::Vertices => "vertices",
            Names::FaceCorners => "two corners of a face",
        }
    }

    /// What the user must select first, in the editor's words ("an edge (or halfedge)").
    pub fn select_first(self) -> &'static str {
        match self {
            Names::Mesh | Names::MeshHolding => "a mesh",
            Names::Edge => "an edge (or halfedge)",
            Names::Vertex => "a vertex",
            Names::Face => "a face",
            Names::Faces => "faces (mode 3)",
            Names::TwoEdges => "two edges (Shift-click)",
            Names::Elements => "elements",
            Names::Vertices => "vertices",
            Names::FaceCorners => "a halfedge of a face (mode 4)",
        }
    }

    /// Whether it names no element in a step: the whole mesh (held vertices come from the
    /// editor's selection alone).
    pub fn is_whole_mesh(self) -> bool {
        matches!(self, Names::Mesh | Names::MeshHolding)
    }

    /// Whether `elements` are what it names: their number and kinds.
    pub fn admits(self, elements: &[ElementId]) -> bool {
        match self {
            Names::Mesh => elements.is_empty(),
            Names::Edge => matches!(elements, [ElementId::Edge(_)]),
            Names::Vertex => matches!(elements, [ElementId::Vertex(_)]),
            Names::Face => matches!(elements, [ElementId::Face(_)]),
            Names::Faces => {
                !elements.is_empty() && elements.iter().all(|x| matches!(x, ElementId::Face(_)))
            }
            Names::TwoEdges => matches!(elements, [ElementId::Edge(_), ElementId::Edge(_)]),
            Names::Elements => !elements.is_empty(),
            Names::MeshHolding => elements.iter().all(|x| matches!(x, ElementId::Vertex(_))),
            Names::Vertices => {
                !elements.is_empty() && elements.iter().all(|x| matches!(x, ElementId::Vertex(_)))
            }
            Names::FaceCorners => matches!(
                elements,
                [
                    ElementId::Face(_),
                    ElementId::Vertex(_),
                    ElementId::Vertex(_)
                ]
            ),
        }
    }

    /// Whether a step's elements, given as the counts of vertex numbers naming each (`[2]`
    /// for `A,B`, `[3, 3]` for `A,B,C/D,E,F`), are what it names: one number a vertex, two an
    /// edge (or two corners of the face they share), three or more a face.
    pub fn fits(self, counts: &[usize]) -> bool {
        match (self, counts) {
            (_, []) | (Names::Mesh | Names::MeshHolding, _) => false,
            (Names::Vertex, [1])
            | (Names::Edge | Names::FaceCorners, [2])
            | (Names::TwoEdges, [2, 2]) => true,
            (Names::Vertices, _) => counts.iter().all(|&n| n == 1),
            (Names::Face, [n]) => *n >= 3,
            (Names::Faces, _) => counts.iter().all(|&n| n >= 3),
            (Names::Elements, _) => counts.iter().all(|&n| n >= 1),
            _ => false,
        }
    }
}

/// One parameter of an operation: its name (in the usage text, the panel and labels), what
/// values it takes, its default, and whether it may be left to the operation (`auto`).
///
/// Every value is held as an `f64`: a real or whole number as itself, a choice as the index
/// of its word — exact for whole numbers up to 2⁵³ and for a decimal read from a step as it
/// was read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameter {
    /// Its name, in capitals in the usage text (`normalize[:SIZE]`).
    pub name: &'static str,
    /// What values it takes.
    pub kind: ParameterKind,
    /// Its value when the step or the panel gives none (`None`: automatic).
    pub default: Option<f64>,
    /// The value its field starts from when one is first given: the default, or, for a
    /// parameter automatic by default, the typical value it was declared with.
    pub suggested: f64,
    /// What the operation does when the value is left out (`auto`), if it may be: "the mean
    /// edge length". `None`: a value is always needed.
    pub automatic: Option<&'static str>,
}

/// The values a [`Parameter`] takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterKind {
    /// A number in `min..=max`.
    Real {
        /// The least value.
        min: f64,
        /// The greatest value.
        max: f64,
    },
    /// A whole number in `min..=max` (iterations, levels, face counts).
    Whole {
        /// The least value.
        min: f64,
        /// The greatest value.
        max: f64,
    },
    /// One of these words (a method, a shape), held as its index.
    Choice(&'static [&'static str]),
}

impl Parameter {
    /// A real parameter in `min..=max`.
    pub const fn real(name: &'static str, default: f64, min: f64, max: f64) -> Self {
        Self {
            name,
            kind: ParameterKind::Real { min, max },
            default: Some(default),
            suggested: default,
            automatic: None,
        }
    }

    /// A whole-number parameter in `min..=max`.
    pub const fn whole(name: &'static str, default: u32, min: u32, max: u32) -> Self {
        Self {
            name,
            kind: ParameterKind::Whole {
                min: min as f64,
                max: max as f64,
            },
            default: Some(default as f64),
            suggested: default as f64,
            automatic: None,
        }
    }

    /// One of `words`, `words[default]` by default.
    pub const fn choice(
        name: &'static str,
        words: &'static [&'static str],
        default: usize,
    ) -> Self {
        assert!(default < words.len(), "the default is one of the words");
        Self {
            name,
            kind: ParameterKind::Choice(words),
            default: Some(default as f64),
            suggested: default as f64,
            automatic: None,
        }
    }

    /// Left to the operation by default (`auto`), which then does `what` ("the mean edge
    /// length"); the value it was declared with is where its field starts when one is given.
    pub const fn automatic_by_default(self, what: &'static str) -> Self {
        Self {
            default: None,
            automatic: Some(what),
            ..self
        }
    }

    /// Whether `x` is a value it takes (`None`: automatic).
    pub fn admits(&self, x: Option<f64>) -> bool {
        let Some(x) = x else {
            return self.automatic.is_some();
        };
        match self.kind {
            ParameterKind::Real { min, max } => (min..=max).contains(&x),
            ParameterKind::Whole { min, max } => (min..=max).contains(&x) && x.fract() == 0.0,
            ParameterKind::Choice(words) => {
                x.fract() == 0.0 && (0.0..words.len() as f64).contains(&x)
            }
        }
    }

    /// Reads a value as a step writes it: a number, one of a choice's words (any case), or
    /// `auto`.
    ///
    /// # Errors
    /// Text that is none of those, or a value it does not take: the message says what it takes.
    pub fn read(&self, text: &str) -> Result<Option<f64>, String> {
        if text.is_empty() {
            return Err(format!("a value of {} is missing", self.name));
        }
        if text.eq_ignore_ascii_case("auto") && self.automatic.is_some() {
            return Ok(None);
        }
        let x = match self.kind {
            ParameterKind::Choice(words) => words
                .iter()
                .position(|w| w.eq_ignore_ascii_case(text))
                .map(|i| i as f64),
            _ => text.parse::<f64>().ok(),
        };
        x.filter(|&x| self.admits(Some(x)))
            .map(Some)
            .ok_or_else(|| format!("{} must be {}", self.name, self.range_words()))
    }

    /// A value as a step writes it: the number, the choice's word, or `auto`.
    pub fn write(&self, x: Option<f64>) -> String {
        match (x, self.kind) {
            (None, _) => "auto".into(),
            (Some(i), ParameterKind::Choice(words)) => words[i as usize].into(),
            (Some(x), _) => x.to_string(),
        }
    }

    /// What it takes, in words, for refusals: "a number from 0.001 to 1000", "a whole number
    /// from 1 to 100", "one of polygon, fair", each with "or auto (…)" where it may be left out.
    pub fn range_words(&self) -> String {
        let words = match self.kind {
            ParameterKind::Real { min, max } => format!("a number from {min} to {max}"),
            ParameterKind::Whole { min, max } => format!("a whole number from {min} to {max}"),
            ParameterKind::Choice(words) => format!("one of {}", words.join(", ")),
        };
        match self.automatic {
            Some(what) => format!("{words}, or auto ({what})"),
            None => words,
        }
    }

    /// How the usage text writes it: `NAME`, or a choice's words joined by `|`.
    pub fn placeholder(&self) -> String {
        match self.kind {
            ParameterKind::Choice(words) => words.join("|"),
            _ => self.name.into(),
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
            Declaration::new("loop")
                .renumbering(FaceChildren::Each(4))
                .ids,
            IdsKept::VerticesOnly
        );
    }

    /// Children listed after their parent, level after level; a count no level makes is not
    /// taken for this layout.
    #[test]
    fn face_children_name_their_parents_at_every_level() {
        let each = FaceChildren::Each(4);
        assert_eq!(each.parents(&[3, 3], 8), Some(vec![0, 0, 0, 0, 1, 1, 1, 1]));
        assert_eq!(each.parents(&[3], 16), Some(vec![0; 16]));
        assert_eq!(each.parents(&[3, 3], 9), None);
        let quads = FaceChildren::PerCorner(4);
        // A triangle and a pentagon: 3 + 5 quads, then 4 of each.
        assert_eq!(
            quads.parents(&[3, 5], 8),
            Some([vec![0; 3], vec![1; 5]].concat())
        );
        assert_eq!(
            quads.parents(&[3, 5], 32),
            Some([vec![0; 12], vec![1; 20]].concat())
        );
        assert_eq!(quads.parents(&[3, 5], 7), None);
    }
}
