//! The one edit layer: every operation Pappus can apply to a mesh, as one value of [`Edit`].
//!
//! The command line parses its `process` steps into an [`Edit`] ([`Step`]); the editor's keys,
//! buttons and scripts write `Edit` requests; the undo history, the job runner and the panel
//! ask the `Edit` what they need instead of matching every operation:
//!
//! | question                                    | answer                      |
//! |---------------------------------------------|-----------------------------|
//! | what it may change (for the undo record)    | [`Edit::reach`]             |
//! | whether it may run as a job on a large mesh | [`Edit::may_run_as_job`]    |
//! | which element ids survive it                | [`Edit::keeps_ids`]         |
//! | whether the simplification history survives | [`Edit::keeps_history`]     |
//! | whether it merges into the previous edit    | [`Edit::merge_key`]         |
//! | what it is called in the log / a step       | [`Edit::label`], [`Step`]   |
//!
//! [`Edit::run`] applies it to a `&mut World` (with progress and cancel) and returns either
//! [`Applied`] — a summary that prints, what to redraw and what to select — or a [`Refusal`],
//! and then the world is exactly as it was.
//!
//! Adding an operation: its file in `ops/`, declaring itself whole
//! ([`crate::ops::operation::MeshOperation`]: what it names, its parameters, its key and
//! section), and its line in [`crate::ops::registry`]; [`Edit::Operation`] carries it, and
//! the step parser, the keymap (which resolves the elements from the selection), the panel,
//! Python, undo and jobs read its declaration. Two edits are not operations: the editor's
//! gestures carry what no declared parameter can — a position for each vertex moved
//! ([`Edit::Move`]) and the affine map a handle's drag makes ([`Edit::Deform`]).

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::attributes::{MeshAttributes, drop_attributes};
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::tables::{Connectivity, MeshTables};
use crate::mesh::{InMesh, MeshInfo};
use crate::ops::Refusal;
use crate::ops::deform::{DeformMethod, DeformParams};
use crate::ops::simplification_history::SimplificationHistory;

mod apply;
pub mod lab;
mod save;
mod step;
mod stepped;
pub use save::{RECOMPUTED_NORMALS, mark_normals_stale, soup_to_save};
pub use step::{Step, elements_at, step_syntax};

/// What an operation declares about itself (defined beside the operations, in
/// [`crate::ops::declaration`], so that `ops` need not import this layer).
pub use crate::ops::declaration::{Carries, Declaration, FaceChildren, IdsKept};

use crate::ops::operation::count;
/// What an edit returns and runs with, and one use of an operation that declares itself
/// whole (defined in [`crate::ops::operation`], so that those operations can return them).
pub use crate::ops::operation::{Applied, EditContext, Invocation, Reach, Redraw};

/// A subdivision scheme (defined beside the schemes, in [`crate::ops::subdivide`], so that
/// `ops` need not import this layer).
pub use crate::ops::subdivide::Scheme;

/// Every operation on a mesh. Local edits name their elements; whole-mesh edits act on the
/// mesh [`Edit::run`] is given.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// An operation that declares itself whole ([`crate::ops::registry`]: flip, collapse,
    /// …, triangulate, simplify, smooth, fair, …), with the elements it names and its
    /// parameters' values.
    Operation(Invocation),
    /// Vertices moved to where a gesture put them (a drag, a transform of the selection): one
    /// undo step. The editor's own edit; no step.
    Move(Vec<(VertexId, Vec3)>),
    /// Handle deformation: the anchors stay, the handle moves by its motion (any affine map a
    /// gesture makes), the rest follows (thin-plate or as-rigid-as-possible). Only positions
    /// change.
    Deform(DeformParams),
}

impl Edit {
    /// The registered operation whose step is called `name` ([`crate::ops::registry`]),
    /// with its parameters' defaults.
    pub fn registered(name: &str) -> Option<Self> {
        crate::ops::registry::operation(name)
            .map(|op| Edit::Operation(Invocation::with_defaults(op)))
    }

    /// The registered operation called `name` on `element` (of those sharing the name, the
    /// one that names such an element: `collapse` an edge or a face), with its defaults.
    ///
    /// # Panics
    /// When no registered operation called `name` names such an element: a caller's bug (the
    /// editor and the step parser resolve elements through [`crate::ops::registry::invocation_on`],
    /// which says so instead).
    pub fn local(name: &str, element: impl Into<ElementId>) -> Self {
        Self::local_on(name, [element], &[])
    }

    /// The registered operation called `name` on `elements` with these values of its first
    /// parameters (the rest their defaults): `Edit::local_on("extrude", faces, &[0.5])`.
    ///
    /// # Panics
    /// As [`Edit::local`], and for values the operation does not take.
    pub fn local_on(
        name: &str,
        elements: impl IntoIterator<Item = impl Into<ElementId>>,
        values: &[f64],
    ) -> Self {
        let elements = elements.into_iter().map(Into::into).collect();
        let mut invocation = crate::ops::registry::invocation_on(name, elements)
            .unwrap_or_else(|why| panic!("{why}"));
        for (i, &x) in values.iter().enumerate() {
            invocation
                .set(i, Some(x))
                .unwrap_or_else(|why| panic!("{why}"));
        }
        Edit::Operation(invocation)
    }

    /// The registered operation invoked as a step writes it (`"remesh:1"`, `"param:lscm"`).
    ///
    /// # Errors
    /// No registered operation of that name, or values it does not take (the message says
    /// what it takes).
    pub fn invoked(step: &str) -> Result<Self, String> {
        let (name, args) = step.split_once(':').unwrap_or((step, ""));
        let op = crate::ops::registry::operation(name)
            .ok_or_else(|| format!("no registered operation is called `{name}`"))?;
        Invocation::parse(op, args).map(Edit::Operation)
    }

    /// A short label for logs and the undo history.
    pub fn label(&self) -> String {
        match self {
            Edit::Operation(op) => op.label(),
            Edit::Move(moves) => match moves.as_slice() {
                [(v, _)] => format!("move {v}"),
                _ => format!("move {}", count(moves.len(), "vertex")),
            },
            Edit::Deform(p) => match p.method {
                DeformMethod::Arap => format!("ARAP deformation ({} iterations)", p.iterations),
                DeformMethod::Laplace => "thin-plate deformation".into(),
            },
        }
    }

    /// What the edit may change: `None` when an element it names is gone (it will be
    /// refused, and changes nothing) or, for whole-mesh edits, when `mesh` is gone.
    pub fn reach(&self, world: &World, mesh: MeshId) -> Option<Reach> {
        match self {
            Edit::Operation(op) => op.reach(world, mesh),
            // A move changes the vertices it moves, and nothing else.
            Edit::Move(moves) => Reach::vertices(world, moves.iter().map(|(v, _)| *v).collect()),
            // A deformation moves any vertex.
            Edit::Deform(_) => world.get::<MeshInfo>(mesh.0).map(|_| Reach::Whole(mesh)),
        }
    }

    /// The mesh the edit acts on: the mesh of the element it names, or `active` for a
    /// whole-mesh edit.
    ///
    /// # Refusals
    /// [`Refusal::Stale`] when the named element (or the active mesh) is gone.
    pub fn target(&self, world: &World, active: Option<MeshId>) -> Result<MeshId, Refusal> {
        let named = match self {
            Edit::Operation(op) => op.elements().first().copied(),
            Edit::Move(moves) => moves.first().map(|(v, _)| ElementId::Vertex(*v)),
            Edit::Deform(p) => p.handle.first().map(|v| ElementId::Vertex(*v)),
        };
        match named {
            Some(x) => world
                .get::<InMesh>(x.entity())
                .map(|m| m.0)
                .ok_or(Refusal::Stale(x)),
            None => {
                let mesh = active.ok_or(Refusal::NoMesh)?;
                world
                    .get::<MeshInfo>(mesh.0)
                    .map(|_| mesh)
                    .ok_or(Refusal::Stale(ElementId::Mesh(mesh)))
            }
        }
    }

    /// What the operation behind the edit declares about itself, beside its algorithm (its
    /// step's name, whether it may run as a job, which ids and whether the simplification
    /// history survive it, what becomes of the attributes).
    pub fn declaration(&self) -> &'static Declaration {
        match self {
            Edit::Operation(op) => op.declaration(),
            Edit::Move(_) => &MOVE,
            Edit::Deform(_) => &crate::ops::deform::DEFORM,
        }
    }

    /// Whether the edit may run as a job (on a copy of the mesh, on a thread of its own) when
    /// the mesh is large: the whole-mesh operations that compute a new mesh from the old.
    pub fn may_run_as_job(&self) -> bool {
        self.declaration().job
    }

    /// Which element ids keep their meaning through the edit.
    pub fn keeps_ids(&self) -> IdsKept {
        self.declaration().ids
    }

    /// Whether the simplification history still describes the mesh after the edit (the edits
    /// that move along it, and the simplification that makes it). Any other edit ends it.
    pub fn keeps_history(&self) -> bool {
        self.declaration().keeps_history
    }

    /// Ends `mesh`'s simplification history unless the edit keeps it: the one place that
    /// rule is written. [`Edit::run`] calls it after the edit; an edit carried out in pieces
    /// (a job on a copy, a stepped run) calls it when it ends.
    pub fn settle_history(&self, world: &mut World, mesh: MeshId) {
        if !self.keeps_history() {
            SimplificationHistory::end(world, mesh);
        }
    }

    /// Whether the edit carries the mesh's attributes (UVs, normals, colours, groups) through;
    /// those that do not (remeshing, simplification, moves along the simplification history)
    /// drop them, and [`Edit::run`] says so in the summary. Subdivision carries UVs, colours
    /// and groups and drops normals (see [`crate::ops::subdivide`]).
    pub fn carries_attributes(&self) -> bool {
        !matches!(self.declaration().carries, Carries::None(_))
    }

    /// Whether [`Edit::run_on_tables`] computes the edit: a registered operation that declares
    /// it computes on the tables (subdivision).
    pub fn runs_on_tables(&self) -> bool {
        matches!(self, Edit::Operation(op) if op.declaration().on_tables)
    }

    /// The edit computed from a mesh's tables alone, where that gives exactly what
    /// [`Edit::run`] would write back and return (subdivision, whose tables are a function of
    /// the tables before): the result's tables and the outcome, with its note on the attributes
    /// left out. `None` for every other edit, which needs the entities. The editor's jobs take
    /// this way when they can: it spares them spawning a copy of the mesh and reading the
    /// result back from it.
    ///
    /// # Refusals
    /// As [`Edit::run`]'s.
    pub fn run_on_tables(
        &self,
        before: &MeshTables,
    ) -> Option<Result<(Connectivity, Applied), Refusal>> {
        let Edit::Operation(op) = self else {
            return None;
        };
        let computed = op.operation().run_on_tables(before, op.values())?;
        Some(computed.map(|(after, mut applied)| {
            let had = before.tables.attributes.present();
            applied.summary += &self.lost_note(had, after.attributes.present());
            (after, applied)
        }))
    }

    /// After the edit has changed `mesh`, which had the attributes `had`: drops them if the
    /// edit does not carry them, and returns the note that says what was lost (empty if
    /// nothing). [`Edit::run`] calls it; a stepped run calls it when it ends.
    pub fn settle_attributes(
        &self,
        world: &mut World,
        mesh: MeshId,
        had: MeshAttributes,
    ) -> String {
        if had.is_empty() {
            return String::new();
        }
        if !self.carries_attributes() {
            drop_attributes(world, mesh);
        } else if had.groups {
            // Faces made where there was none take a neighbour's group.
            crate::mesh::groups::settle(world, mesh);
        }
        self.lost_note(had, MeshAttributes::of(world, mesh))
    }

    /// The summary's note on the attributes of `had` that the edit left out of `now` (empty
    /// if none), with why.
    fn lost_note(&self, had: MeshAttributes, now: MeshAttributes) -> String {
        had.lost_in(now).dropped_note(&self.why_dropped())
    }

    /// Why the edit dropped attributes, for the summary's note.
    fn why_dropped(&self) -> String {
        match self.declaration().carries {
            Carries::Some(why) | Carries::None(why) => why.into(),
            Carries::All => format!("{} does not carry them", self.label()),
        }
    }

    /// Edits with the same key merge into one undo step while one mouse press lasts (the
    /// frames of a vertex drag, a drag of the level-of-detail slider).
    pub fn merge_key(&self) -> Option<MergeKey> {
        match self {
            Edit::Move(moves) => moves.first().map(|(v, _)| MergeKey::Move(*v, moves.len())),
            Edit::Operation(op) if op.declaration().merges_while_held => {
                Some(MergeKey::Operation(op.declaration().name))
            }
            _ => None,
        }
    }

    /// Applies the edit to `mesh` (whole-mesh edits) or to the elements it names.
    ///
    /// # Refusals
    /// The operation's [`Refusal`]; the world is then exactly as it was. A level-of-detail
    /// move that meets a record the mesh no longer fits stops there and is applied as far as
    /// it went (its summary says why it stopped); it is refused only if it moved nowhere.
    ///
    /// # Panics
    /// In debug builds (and so in every test), when an applied edit left the mesh invalid: that
    /// is a bug in the operation, and loud.
    pub fn run(
        &self,
        world: &mut World,
        mesh: MeshId,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        // Every edit either carries the mesh's attributes or drops them; a drop is said.
        let had = MeshAttributes::of(world, mesh);
        let mut applied = self.apply(world, mesh, context)?;
        applied
            .summary
            .push_str(&self.settle_attributes(world, mesh, had));
        // Normals kept through an edit that changed the surface no longer describe it.
        mark_normals_stale(world, mesh, self);
        self.settle_history(world, mesh);
        #[cfg(any(debug_assertions, feature = "checked"))]
        if let Err(e) = crate::mesh::validate(world, mesh) {
            panic!("{} left an invalid mesh: {e}", self.label());
        }
        Ok(applied)
    }
}

/// Edits that merge into the undo step before them while the mouse button stays down.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MergeKey {
    /// Moves of this many vertices, the first of them this one (the frames of one drag or
    /// transform).
    Move(VertexId, usize),
    /// Uses of the registered operation of this name that declares it merges while held
    /// (the level-of-detail slider's `refine`).
    Operation(&'static str),
}

/// Moving vertices (a drag, a transform of the selection): the editor's own edit, no step.
pub const MOVE: Declaration = Declaration::new("move").editor_only();

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshRef;

    #[test]
    fn only_whole_mesh_computations_run_as_jobs_and_only_subdivision_renumbers() {
        let v = VertexId(bevy::prelude::Entity::PLACEHOLDER);
        let e = crate::mesh::ids::EdgeId(bevy::prelude::Entity::PLACEHOLDER);
        let loop1 = Edit::registered("loop").unwrap();
        assert!(loop1.may_run_as_job() && Edit::registered("remesh").unwrap().may_run_as_job());
        let refine = Edit::invoked("refine:5").unwrap();
        assert!(!Edit::local("flip", e).may_run_as_job() && !refine.may_run_as_job());
        assert_eq!(refine.merge_key(), Some(MergeKey::Operation("refine")));
        assert_eq!(loop1.keeps_ids(), IdsKept::VerticesOnly);
        let triangulate = Edit::registered("triangulate").unwrap();
        assert_eq!(triangulate.keeps_ids(), IdsKept::All);
        let split_back = Edit::local("vertex-split", v);
        assert!(split_back.keeps_history() && !Edit::local("flip", e).keeps_history());
        assert_eq!(
            Edit::Move(vec![(v, Vec3::ZERO)]).merge_key(),
            Some(MergeKey::Move(v, 1))
        );
    }

    /// Every operation declares itself, and every declared step is one the command line
    /// documents; the properties the pipeline asks for are the declaration's.
    #[test]
    fn every_edit_has_a_declaration_and_every_declared_step_exists() {
        use crate::ops::deform::{DeformMethod, DeformParams};
        let v = VertexId(bevy::prelude::Entity::PLACEHOLDER);
        let registered = crate::ops::registry::operations()
            .into_iter()
            .map(|op| Edit::Operation(Invocation::with_defaults(op)));
        let every: Vec<Edit> = registered
            .chain([
                Edit::Move(vec![(v, Vec3::ZERO)]),
                Edit::Deform(DeformParams {
                    method: DeformMethod::Arap,
                    fixed: Vec::new(),
                    handle: vec![v],
                    motion: bevy::math::Affine3A::IDENTITY,
                    iterations: 1,
                }),
            ])
            .collect();
        let syntax = step_syntax();
        // Each step's line of the usage text starts with its name.
        let documented: Vec<&str> = syntax
            .lines()
            .filter_map(|line| line.split([':', ' ', '[']).next())
            .collect();
        let mut jobs = Vec::new();
        for edit in &every {
            let d = edit.declaration();
            assert_eq!(
                d.is_step,
                documented.contains(&d.name),
                "{}: declared step `{}`",
                edit.label(),
                d.name
            );
            assert_eq!(edit.may_run_as_job(), d.job);
            assert_eq!(edit.keeps_ids(), d.ids);
            if d.job {
                // A job renames only the vertices its operation names (editor/pipeline/jobs).
                assert!(d.names.is_whole_mesh(), "{} runs as a job", d.name);
                jobs.push(d.name);
            }
        }
        assert_eq!(
            jobs,
            [
                "triangulate",
                "simplify",
                "simplify-faces",
                "loop",
                "catmull-clark",
                "remesh",
                "smooth",
                "param"
            ]
        );
        assert!(!Edit::Move(vec![(v, Vec3::ZERO)]).declaration().is_step);
    }

    /// An operation computes on the tables exactly when it declares so, and what it computes
    /// there is what applying it to the entities makes (the same counts and summary).
    #[test]
    fn operations_declared_on_tables_compute_there_as_applied() {
        use crate::mesh::tables::extract;
        use crate::mesh::{build_mesh, mesh_stats, shapes};
        for op in crate::ops::registry::operations() {
            let mut world = World::new();
            let built = build_mesh(&mut world, &shapes::icosphere(1), MeshInfo::default()).unwrap();
            let edit = Edit::Operation(Invocation::with_defaults(op));
            let on_tables = edit.run_on_tables(&extract(&world, built.mesh));
            assert_eq!(
                on_tables.is_some(),
                edit.runs_on_tables(),
                "{}",
                edit.label()
            );
            let Some(on_tables) = on_tables else {
                continue;
            };
            let (tables, computed) = on_tables.unwrap();
            let applied = edit
                .run(
                    &mut world,
                    built.mesh,
                    &mut EditContext {
                        progress: &mut |_| true,
                    },
                )
                .unwrap();
            assert_eq!(computed, applied, "{}", edit.label());
            let stats = mesh_stats(&world, built.mesh);
            assert_eq!(
                (tables.vertex_count(), tables.face_count()),
                (stats.vertices, stats.faces),
                "{}",
                edit.label()
            );
        }
    }

    /// Labels name what an operation names in words: a face split its face and corners,
    /// fairing and smoothing how many vertices they move or hold.
    #[test]
    fn labels_say_what_is_named() {
        use crate::mesh::{MeshMembers, build_mesh, shapes};
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(1), MeshInfo::default()).unwrap();
        let all = MeshMembers::collect(&world, built.mesh);
        let f = all.faces[0];
        let corners: Vec<VertexId> = MeshRef::new(&world).face_vertices(f).collect();
        let (a, b) = (corners[0], corners[2]);
        let split = Edit::local_on(
            "split-face",
            [f.into(), a.into(), b.into()] as [ElementId; 3],
            &[],
        );
        assert_eq!(split.label(), format!("split face {f} between {a} and {b}"));
        let fair = Edit::local_on("fair", all.vertices[..3].iter().copied(), &[]);
        assert_eq!(fair.label(), "fair 3 vertices (k 2)");
        let smooth = Edit::local_on("smooth", all.vertices[..2].iter().copied(), &[]);
        assert_eq!(
            smooth.label(),
            "smooth holding 2 vertices (uniform, iterations 1, step auto, hold-boundary)"
        );
        assert_eq!(
            Edit::registered("smooth").unwrap().label(),
            "smooth (uniform, iterations 1, step auto, hold-boundary)"
        );
    }

    /// A move of most of a mesh redraws it whole and is recorded (and undone) by its vertices
    /// alone; a move of a few redraws their neighbourhood.
    #[test]
    fn a_move_of_most_vertices_redraws_whole_and_records_only_them() {
        use crate::mesh::change::LocalRecorder;
        use crate::mesh::{MeshMembers, build_mesh, shapes};
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(4), MeshInfo::default()).unwrap();
        let vertices = MeshMembers::collect(&world, built.mesh).vertices;
        assert!(vertices.len() > 2 * apply::WHOLE_REDRAW_MOVES);
        let m = MeshRef::new(&world);
        let before: Vec<Vec3> = vertices.iter().map(|&v| m.position(v)).collect();
        let mut context = EditContext {
            progress: &mut |_| true,
        };
        let few = Edit::Move(vec![(vertices[0], Vec3::ONE)]);
        let applied = few.run(&mut world, built.mesh, &mut context).unwrap();
        assert!(matches!(applied.redraw, Redraw::Near { .. }));
        let moves: Vec<(VertexId, Vec3)> = vertices
            .iter()
            .zip(&before)
            .map(|(&v, p)| (v, *p * 1.5))
            .collect();
        let many = Edit::Move(moves);
        let Some(Reach::Vertices(mesh, seeds)) = many.reach(&world, built.mesh) else {
            panic!("a move reaches its vertices alone");
        };
        let recorder = LocalRecorder::begin_vertices(&world, mesh, &seeds);
        let applied = many.run(&mut world, built.mesh, &mut context).unwrap();
        assert_eq!(applied.redraw, Redraw::Positions);
        let change = recorder.finish(&world);
        assert_eq!(change.counts(), (0, 0, vertices.len()));
        change.apply(&mut world);
        let m = MeshRef::new(&world);
        assert_eq!(m.position(vertices[0]), Vec3::ONE);
        for (&v, p) in vertices.iter().zip(&before).skip(1) {
            assert_eq!(m.position(v), *p);
        }
    }
}
