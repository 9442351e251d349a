//! Lab mode: a student's operation checked against the operation it claims to reproduce.
//!
//! A course lab (CMU 15-462's Scotty3D, the halfedge labs built on OpenMesh) hands a student a
//! skeleton in which they write edge flip, split and collapse, and leaves them to find their
//! mistakes from traces and by eye. Here an operation declares the registered operation it
//! reproduces ([`crate::ops::declaration::Declaration::checked_against`]), and every
//! application of it is checked first: [`compare`] copies the mesh into two scratch worlds whose
//! elements have the same ids, runs the student's operation on one and the reference on the
//! other, each under `catch_unwind` (and with its log messages dropped: they would name the
//! copies' elements), validates both and compares them:
//!
//! - surviving elements by id: the same vertices, edges, faces and halfedges kept, each vertex
//!   at the same place (within a millionth of the mesh's size, as a midpoint computed two
//!   ways may differ in its last bit), each face with the same corner cycle, each edge with
//!   the same ends, each halfedge between the same vertices on the same face;
//! - what is new by what it is: new vertices by position, new faces by their corner cycles,
//!   new edges by their ends (a student's new elements get other ids than the reference's, in
//!   whatever order they were made; new halfedges are those of the new faces and edges).
//!
//! The report ([`LabReport`]) is one [`Verdict`] and names elements by the mesh's own ids.
//! [`apply_checked`] is what [`super::Edit::run`] does with an operation that declares a
//! reference: an invalid, panicking or lone refused result is refused with the report and the
//! mesh untouched (only the copies saw it); a valid one, the same or not, is applied to the
//! mesh (it is the student's result to look at: the operation runs once more, on the mesh
//! itself, as a function of the mesh), the report appended to its summary. A check costs one
//! read of the mesh's tables, two fresh worlds written from them and a whole validation of
//! each: about 25 ms on a 6 000-triangle mesh and 0.5 s on the 69 451-triangle bunny (release
//! build). A lab's meshes are small, and a lab is about being told, not speed.
//!
//! ```
//! use bevy::prelude::World;
//! use pappus::edit::lab::{Verdict, compare};
//! use pappus::edit::{EditContext, Invocation};
//! use pappus::mesh::{MeshId, MeshInfo, MeshMembers, build_mesh, shapes};
//! use pappus::ops::Refusal;
//! use pappus::ops::declaration::{Declaration, Names};
//! use pappus::ops::operation::{Applied, MeshOperation, Values};
//!
//! /// A "student's" flip that calls Pappus's own: the lab finds it the same.
//! struct MyFlip;
//!
//! const MY_FLIP: Declaration = Declaration::new("my-flip")
//!     .naming(Names::Edge)
//!     .checked_against("flip");
//!
//! impl MeshOperation for MyFlip {
//!     fn declaration(&self) -> &'static Declaration {
//!         &MY_FLIP
//!     }
//!
//!     fn apply(
//!         &self,
//!         world: &mut World,
//!         _: MeshId,
//!         values: Values<'_>,
//!         _: &mut EditContext<'_>,
//!     ) -> Result<Applied, Refusal> {
//!         let e = pappus::ops::local::flip_edge(world, values.edge()?)?;
//!         Ok(Applied::whole(format!("flipped {e}")))
//!     }
//! }
//!
//! let mut world = World::new();
//! let built = build_mesh(&mut world, &shapes::icosphere(1), MeshInfo::default()).unwrap();
//! let e = MeshMembers::collect(&world, built.mesh).edges[0];
//! let flip = Invocation::with_defaults(&MyFlip).on(vec![e.into()]).unwrap();
//! let report = compare(&world, built.mesh, &flip).unwrap();
//! assert_eq!(report.verdict, Verdict::Same);
//! assert_eq!(report.to_string(), "same as flip");
//! ```

use std::fmt;
use std::panic::{AssertUnwindSafe, catch_unwind};

use bevy::ecs::entity::EntityHashMap;
use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::tables::{extract, spawn_connectivity};
use crate::mesh::{MeshInfo, MeshMembers, MeshRef, validate};
use crate::ops::Refusal;
use crate::ops::operation::{Applied, EditContext, Invocation, count};

/// What checking a lab's operation against its reference found.
#[derive(Clone, Debug, PartialEq)]
pub struct LabReport {
    /// The reference's name (`"flip"`).
    pub reference: &'static str,
    /// What was found.
    pub verdict: Verdict,
}

/// How a lab's operation compares with its reference, on copies of the mesh.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// A valid mesh, the reference's: the same elements kept, each the same, and what is new
    /// the same.
    Same,
    /// A valid mesh that is not the reference's: the first difference found.
    Different(String),
    /// An invalid mesh: the element (by the mesh's id, or what it is where it is new) and the
    /// rule it breaks.
    Invalid(String),
    /// It panicked: the message.
    Panicked(String),
    /// It raised an exception (a Python function, [`compare_with`]): its type and message.
    Raised(String),
    /// Refused where the reference applies.
    RefusedAlone(Refusal),
    /// Applied (validly) where the reference refuses: the reference's reason.
    AppliedAlone(Refusal),
    /// Refused, as the reference is: its own reason.
    BothRefused(Refusal),
    /// The reference itself left an invalid mesh or panicked (a bug in it): nothing to compare
    /// a valid result with.
    ReferenceFailed(String),
}

impl Verdict {
    /// Whether the student's result may be applied to the mesh: it is valid (the same as the
    /// reference's or not). An invalid, panicking or refused result is not.
    pub fn admits(&self) -> bool {
        matches!(
            self,
            Verdict::Same
                | Verdict::Different(_)
                | Verdict::AppliedAlone(_)
                | Verdict::ReferenceFailed(_)
        )
    }
}

impl fmt::Display for LabReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let reference = self.reference;
        match &self.verdict {
            Verdict::Same => write!(f, "same as {reference}"),
            Verdict::Different(what) => write!(f, "valid, but not what {reference} makes: {what}"),
            Verdict::Invalid(what) => write!(f, "invalid: {what}; the mesh is as it was"),
            Verdict::Panicked(what) => write!(f, "panicked: {what}; the mesh is as it was"),
            Verdict::Raised(what) => write!(f, "raised {what}; the mesh is as it was"),
            Verdict::RefusedAlone(why) => write!(f, "refused ({why}) where {reference} applies"),
            Verdict::AppliedAlone(why) => write!(f, "applied where {reference} refuses ({why})"),
            Verdict::BothRefused(why) => write!(f, "refused, as {reference} is: {why}"),
            Verdict::ReferenceFailed(what) => {
                write!(
                    f,
                    "{reference} itself failed here ({what}): nothing to compare with"
                )
            }
        }
    }
}

/// Applies `student` (an invocation of an operation that declares a reference) to `mesh` if
/// [`compare`] finds its result valid, appending the report to its summary.
///
/// # Refusals
/// [`Refusal::Lab`] with the report where the result was invalid, panicked or was refused
/// (the mesh is untouched: only the copies saw it); [`compare`]'s own refusals.
pub fn apply_checked(
    student: &Invocation,
    world: &mut World,
    mesh: MeshId,
    context: &mut EditContext<'_>,
) -> Result<Applied, Refusal> {
    let report = compare(world, mesh, student)?;
    if !report.verdict.admits() {
        return Err(Refusal::Lab(report.to_string()));
    }
    // The copy showed the result valid; the operation, a function of the mesh, makes it again.
    let mut applied = student.apply(world, mesh, context)?;
    applied.summary = format!("{}; lab: {report}", applied.summary);
    Ok(applied)
}

/// Runs `student` and the reference it declares on two copies of `mesh` (with the same element
/// ids) and compares the results; `world` is only read.
///
/// # Refusals
/// [`Refusal::BadParameter`] where the operation declares no reference, or no registered
/// operation of that name takes the elements; [`Refusal::Stale`] where an element it names is
/// not one of `mesh`'s.
pub fn compare(world: &World, mesh: MeshId, student: &Invocation) -> Result<LabReport, Refusal> {
    let declared = student.declaration();
    let name = declared.reference.ok_or_else(|| {
        Refusal::BadParameter(format!(
            "{} declares no reference to compare with",
            declared.name
        ))
    })?;
    let mut reference = crate::ops::registry::invocation_on(name, student.elements().to_vec())
        .map_err(Refusal::BadParameter)?;
    let given = student.values();
    for i in 0..declared
        .parameters
        .len()
        .min(reference.declaration().parameters.len())
    {
        // A value the reference does not take leaves its default.
        let _ = reference.set(i, given.given(i));
    }
    compare_with(
        world,
        mesh,
        &reference,
        |world, copy, elements| match student.clone().on(elements.to_vec()) {
            Ok(student) => applied(&student, world, copy),
            Err(why) => Ended::Refused(Refusal::BadParameter(why)),
        },
    )
}

/// How applying `invocation` to `mesh` ended (a panic is the caller's to catch).
fn applied(invocation: &Invocation, world: &mut World, mesh: MeshId) -> Ended {
    let mut context = EditContext {
        progress: &mut |_| true,
    };
    match invocation.apply(world, mesh, &mut context) {
        Ok(_) => Ended::Done,
        Err(why) => Ended::Refused(why),
    }
}

/// How a student's attempt on its copy ended, before the copy is validated: what
/// [`compare_with`] takes from an attempt that is not a registered operation (a Python
/// function). A panic is caught by [`compare_with`] itself.
#[derive(Clone, Debug, PartialEq)]
pub enum Ended {
    /// It finished: the copy is then validated and compared.
    Done,
    /// It refused, with its reason ([`Refusal::Broken`] where its checked edit broke a rule:
    /// the report names the rule and the element).
    Refused(Refusal),
    /// It raised an exception: its type and message.
    Raised(String),
}

/// Runs `attempt` — given a copy of `mesh` and the elements `reference` names, by the copy's
/// ids — and `reference` on another copy with the same ids, and compares the results; `world`
/// is only read. [`compare`] is this with a registered operation as the attempt.
///
/// # Refusals
/// [`Refusal::Stale`] where an element `reference` names is not one of `mesh`'s.
pub fn compare_with(
    world: &World,
    mesh: MeshId,
    reference: &Invocation,
    attempt: impl FnOnce(&mut World, MeshId, &[ElementId]) -> Ended,
) -> Result<LabReport, Refusal> {
    let mut copy = Copy::of(world, mesh);
    let theirs = copy.renamed(reference)?;
    let elements = theirs.elements().to_vec();
    let yours = copy.attempt(|world, mesh| attempt(world, mesh, &elements));
    let theirs = copy.attempt(|world, mesh| applied(&theirs, world, mesh));
    let verdict = match (yours, theirs) {
        (Ran::Panicked(why), _) => Verdict::Panicked(why),
        (Ran::Raised(why), _) => Verdict::Raised(why),
        (Ran::Invalid(why), _) => Verdict::Invalid(why),
        (Ran::Refused(why), Ran::Refused(_)) => Verdict::BothRefused(why),
        (Ran::Refused(why), _) => Verdict::RefusedAlone(why),
        (Ran::Valid(..), Ran::Refused(why)) => Verdict::AppliedAlone(why),
        (Ran::Valid(..), Ran::Invalid(why) | Ran::Panicked(why) | Ran::Raised(why)) => {
            Verdict::ReferenceFailed(why)
        }
        (Ran::Valid(a, ma), Ran::Valid(b, mb)) => match copy.difference((&a, ma), (&b, mb)) {
            None => Verdict::Same,
            Some(what) => Verdict::Different(what),
        },
    };
    Ok(LabReport {
        reference: reference.declaration().name,
        verdict,
    })
}

/// A mesh read once, to be spawned as any number of copies with the same element ids, and the
/// way back from a copy's ids to the mesh's.
struct Copy {
    tables: crate::mesh::tables::Connectivity,
    /// The copy's elements before any operation, by kind and row.
    rows: MeshMembers,
    /// The mesh's elements, by kind and row.
    original: MeshMembers,
    /// Each element of a copy before any operation, by its entity's index (a fresh world
    /// numbers its entities from 0): the copy's entity and the mesh's.
    initial: Vec<Option<(Entity, Entity)>>,
    /// The copy spawned to learn the copies' ids, kept for the first attempt.
    spare: Option<(World, MeshId)>,
    /// Positions closer than this are one position.
    tolerance: f32,
}

/// What an operation did to a copy.
enum Ran {
    Valid(Box<World>, MeshId),
    Invalid(String),
    Panicked(String),
    Raised(String),
    Refused(Refusal),
}

impl Copy {
    fn of(world: &World, mesh: MeshId) -> Self {
        let original = extract(world, mesh);
        let (spare, rows, copy) = Self::spawned(&original.tables);
        let mut initial = vec![None; crate::mesh::ids::slots_for(rows.entities())];
        for (c, o) in rows.entities().zip(original.members.entities()) {
            initial[crate::mesh::ids::slot(c)] = Some((c, o));
        }
        let (lo, hi) = original.tables.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        Self {
            initial,
            spare: Some((spare, copy)),
            tolerance: (hi - lo).length().max(f32::MIN_POSITIVE) * 1e-6,
            tables: original.tables,
            original: original.members,
            rows,
        }
    }

    /// The mesh's element that `e` was in a copy before any operation, if it was one.
    fn original_of(&self, e: Entity) -> Option<Entity> {
        let (copy, original) = (*self.initial.get(crate::mesh::ids::slot(e))?)?;
        (copy == e).then_some(original)
    }

    /// A fresh world holding the tables as its only mesh: the same ids each time (a fresh
    /// world hands out entities in order).
    fn spawned(tables: &crate::mesh::tables::Connectivity) -> (World, MeshMembers, MeshId) {
        let mut world = World::new();
        let (mesh, rows) = spawn_connectivity(&mut world, tables, MeshInfo::default());
        (world, rows, mesh)
    }

    /// `invocation` naming the copy's elements.
    fn renamed(&self, invocation: &Invocation) -> Result<Invocation, Refusal> {
        let elements = invocation.elements().iter().map(|&x| {
            let row = self.original.entities().position(|e| e == x.entity());
            let e = row.and_then(|row| self.rows.entities().nth(row));
            Ok(x.with_entity(e.ok_or(Refusal::Stale(x))?))
        });
        let elements = elements.collect::<Result<Vec<_>, Refusal>>()?;
        invocation
            .clone()
            .on(elements)
            .map_err(Refusal::BadParameter)
    }

    /// Runs `attempt` on a fresh copy: how it ended, and the copy where it is valid.
    fn attempt(&mut self, attempt: impl FnOnce(&mut World, MeshId) -> Ended) -> Ran {
        let (mut world, mesh) = self.spare.take().unwrap_or_else(|| {
            let (world, rows, mesh) = Self::spawned(&self.tables);
            crate::checks::checked_assert_eq!(
                rows.vertices,
                self.rows.vertices,
                "copies share their ids"
            );
            (world, mesh)
        });
        // Its log messages would name the copy's elements: only the run on the mesh itself
        // speaks.
        let quiet = tracing::subscriber::NoSubscriber::default();
        let ended = tracing::subscriber::with_default(quiet, || {
            catch_unwind(AssertUnwindSafe(|| attempt(&mut world, mesh)))
        });
        match ended {
            Err(payload) => Ran::Panicked(panic_message(payload.as_ref())),
            Ok(Ended::Raised(why)) => Ran::Raised(why),
            // A raw edit's commit found the broken rule first (and rolled back).
            Ok(Ended::Refused(Refusal::Broken(invalid))) => Ran::Invalid(self.said(&invalid)),
            Ok(Ended::Refused(why)) => Ran::Refused(why),
            Ok(Ended::Done) => match validate(&world, mesh) {
                Ok(()) => Ran::Valid(Box::new(world), mesh),
                Err(invalid) => Ran::Invalid(self.said(&invalid)),
            },
        }
    }

    /// A broken rule, its element named by the mesh's id.
    fn said(&self, invalid: &crate::mesh::Invalid) -> String {
        format!("{}: {}", self.name(invalid.element), invalid.rule)
    }

    /// An element of a copy by the mesh's id, or as new.
    fn name(&self, x: ElementId) -> String {
        match self.original_of(x.entity()) {
            Some(e) => x.with_entity(e).to_string(),
            None => format!("a new {}", x.kind()),
        }
    }

    /// The first way in which `a` (the student's copy) is not `b` (the reference's), or
    /// `None` where they are the same mesh.
    fn difference(&self, a: (&World, MeshId), b: (&World, MeshId)) -> Option<String> {
        let (a, b) = (Side::of(a, self), Side::of(b, self));
        let made = match match_made_vertices(&a, &b, self.tolerance) {
            Ok(made) => made,
            Err(what) => return Some(what),
        };
        let (ka, kb) = (Keys::of(&a, &made), Keys::of(&b, &identity(b.made.len())));
        let say = |cs: &[Corner]| {
            let named = cs.iter().map(|&c| match c {
                Corner::Kept(v) => self.name(ElementId::Vertex(VertexId(v))),
                Corner::Made(i) => format!("a new vertex at {}", b.made[i].1),
            });
            named.collect::<Vec<_>>().join(" ")
        };
        let compared = self
            .vertices_differ(&a, &b)
            .and_then(|()| self.faces_differ((&a, &ka), (&b, &kb), &say))
            .and_then(|()| self.edges_differ((&a, &ka), (&b, &kb), &say))
            .and_then(|()| self.halfedges_differ((&a, &ka), (&b, &kb), &say));
        compared.err()
    }

    /// The first vertex kept by one and not the other, or put elsewhere.
    fn vertices_differ(&self, a: &Side, b: &Side) -> Result<(), String> {
        for &v in &self.rows.vertices {
            match (a.m.try_position(v), b.m.try_position(v)) {
                (Some(p), Some(q)) if p.distance(q) > self.tolerance => {
                    let name = self.name(ElementId::Vertex(v));
                    return Err(format!(
                        "{name}: yours puts it at {p}, the reference at {q}"
                    ));
                }
                (p, q) => self.survival(ElementId::Vertex(v), p.is_some(), q.is_some())?,
            }
        }
        Ok(())
    }

    /// The first face kept by one and not the other or with other corners, or a new face
    /// that only one makes.
    fn faces_differ(
        &self,
        (a, ka): (&Side, &Keys),
        (b, kb): (&Side, &Keys),
        say: &dyn Fn(&[Corner]) -> String,
    ) -> Result<(), String> {
        for &f in &self.rows.faces {
            match (ka.face(a, f), kb.face(b, f)) {
                (Some(x), Some(y)) if x != y => {
                    let (name, x, y) = (self.name(ElementId::Face(f)), say(&x), say(&y));
                    return Err(format!("{name}: corners {x}, the reference has {y}"));
                }
                (x, y) => self.survival(ElementId::Face(f), x.is_some(), y.is_some())?,
            }
        }
        let made = |s: &Side, k: &Keys| sorted(s.made_faces.iter().filter_map(|&f| k.face(s, f)));
        first_unshared(&made(a, ka), &made(b, kb), "a new face with corners", say)
    }

    /// The first edge kept by one and not the other or with other ends, or a new edge that
    /// only one makes.
    fn edges_differ(
        &self,
        (a, ka): (&Side, &Keys),
        (b, kb): (&Side, &Keys),
        say: &dyn Fn(&[Corner]) -> String,
    ) -> Result<(), String> {
        for &e in &self.rows.edges {
            let ends = |s: &Side, k: &Keys| s.m.try_edge(e).map(|_| k.ends(s, e));
            match (ends(a, ka), ends(b, kb)) {
                (Some(x), Some(y)) if x != y => {
                    let (name, x, y) = (self.name(ElementId::Edge(e)), say(&x), say(&y));
                    return Err(format!("{name}: joins {x}, the reference's joins {y}"));
                }
                (x, y) => self.survival(ElementId::Edge(e), x.is_some(), y.is_some())?,
            }
        }
        let made = |s: &Side, k: &Keys| sorted(s.made_edges.iter().map(|&e| k.ends(s, e)));
        first_unshared(&made(a, ka), &made(b, kb), "a new edge joining", say)
    }

    /// The first halfedge kept by one and not the other, or between other vertices, or on
    /// another face.
    fn halfedges_differ(
        &self,
        (a, ka): (&Side, &Keys),
        (b, kb): (&Side, &Keys),
        say: &dyn Fn(&[Corner]) -> String,
    ) -> Result<(), String> {
        // Its ends, and its face: a kept one by id (the faces are the same by now), a new one by
        // its corners.
        let way = |s: &Side, k: &Keys, h| {
            s.m.try_halfedge(h)?;
            let on = s.m.face(h).map(|f| match self.original_of(f.0) {
                Some(_) => (Some(f), None),
                None => (None, k.face(s, f)),
            });
            Some((k.directed(s, h), on))
        };
        let said = |s: &Side, k: &Keys, h| {
            let ends = k.directed(s, h);
            let on = s.m.face(h).and_then(|f| k.face(s, f));
            let on = on.map_or("the boundary".into(), |c| format!("the face {}", say(&c)));
            format!("from {} to {} on {on}", say(&ends[..1]), say(&ends[1..]))
        };
        for &h in &self.rows.halfedges {
            match (way(a, ka, h), way(b, kb, h)) {
                (Some(x), Some(y)) if x != y => {
                    let name = self.name(ElementId::Halfedge(h));
                    let (x, y) = (said(a, ka, h), said(b, kb, h));
                    return Err(format!("{name}: {x}, the reference's {y}"));
                }
                (x, y) => self.survival(ElementId::Halfedge(h), x.is_some(), y.is_some())?,
            }
        }
        Ok(())
    }

    /// The difference where one side kept the element `x` and the other removed it.
    fn survival(&self, x: ElementId, yours: bool, reference: bool) -> Result<(), String> {
        let name = || self.name(x);
        match (yours, reference) {
            (true, false) => Err(format!(
                "{}: yours keeps it, the reference removes it",
                name()
            )),
            (false, true) => Err(format!(
                "{}: yours removes it, the reference keeps it",
                name()
            )),
            _ => Ok(()),
        }
    }
}

/// A copy after an operation: its walker, and what it made (elements not among the copy's
/// rows before).
struct Side<'w> {
    m: MeshRef<'w>,
    made: Vec<(VertexId, Vec3)>,
    made_faces: Vec<FaceId>,
    made_edges: Vec<EdgeId>,
}

impl<'w> Side<'w> {
    fn of((world, mesh): (&'w World, MeshId), copy: &Copy) -> Self {
        let now = MeshMembers::collect(world, mesh);
        let m = MeshRef::new(world);
        let made = |e: Entity| copy.original_of(e).is_none();
        let mut vertices: Vec<(VertexId, Vec3)> = (now.vertices.iter())
            .filter(|v| made(v.0))
            .map(|&v| (v, m.position(v)))
            .collect();
        vertices.sort_unstable_by_key(|(v, _)| *v);
        Self {
            made: vertices,
            made_faces: sorted(now.faces.into_iter().filter(|f| made(f.0))),
            made_edges: sorted(now.edges.into_iter().filter(|e| made(e.0))),
            m,
        }
    }
}

/// A vertex of a copy as both copies can name it: one of the mesh's, by id, or the `i`th of the
/// vertices the reference made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Corner {
    Kept(Entity),
    Made(usize),
}

/// Names a side's vertices as [`Corner`]s: the side's `i`th made vertex is the reference's
/// `made[i]`th.
struct Keys {
    made: EntityHashMap<usize>,
}

impl Keys {
    fn of(side: &Side, made: &[usize]) -> Self {
        let pairs = side.made.iter().zip(made).map(|(&(v, _), &i)| (v.0, i));
        Self {
            made: pairs.collect(),
        }
    }

    fn corner(&self, v: VertexId) -> Corner {
        match self.made.get(&v.0) {
            Some(&i) => Corner::Made(i),
            None => Corner::Kept(v.0),
        }
    }

    /// A face's corner cycle, started at its least corner (the orientation kept); `None` for a
    /// face the side does not have.
    fn face(&self, side: &Side, f: FaceId) -> Option<Vec<Corner>> {
        side.m.try_face(f)?;
        let mut cycle: Vec<Corner> = side.m.face_vertices(f).map(|v| self.corner(v)).collect();
        let least = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap_or(0);
        cycle.rotate_left(least);
        Some(cycle)
    }

    /// A halfedge's ends, in its direction.
    fn directed(&self, side: &Side, h: HalfedgeId) -> [Corner; 2] {
        [
            self.corner(side.m.from_vertex(h)),
            self.corner(side.m.to_vertex(h)),
        ]
    }

    /// An edge's ends, in order.
    fn ends(&self, side: &Side, e: EdgeId) -> [Corner; 2] {
        let mut ends = self.directed(side, side.m.edge_halfedge(e));
        ends.sort_unstable();
        ends
    }
}

/// `0, 1, …, n - 1`.
fn identity(n: usize) -> Vec<usize> {
    (0..n).collect()
}

/// The items, sorted.
fn sorted<T: Ord>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut items: Vec<T> = items.collect();
    items.sort_unstable();
    items
}

/// Which of the reference's made vertices each of the student's is (the nearest within the
/// tolerance, each taken once), or the difference: another number of them, or one with none
/// of the reference's near it.
fn match_made_vertices(a: &Side, b: &Side, tolerance: f32) -> Result<Vec<usize>, String> {
    if a.made.len() != b.made.len() {
        return Err(format!(
            "yours makes {}, the reference {}",
            count(a.made.len(), "new vertex"),
            b.made.len()
        ));
    }
    let mut taken = vec![false; b.made.len()];
    let mut matched = Vec::with_capacity(a.made.len());
    for &(_, p) in &a.made {
        let far = |i: usize| p.distance(b.made[i].1);
        let nearest = (0..b.made.len())
            .filter(|&i| !taken[i])
            .min_by(|&i, &j| far(i).total_cmp(&far(j)))
            .filter(|&i| far(i) <= tolerance)
            .ok_or_else(|| format!("yours makes a new vertex at {p}, the reference none there"))?;
        taken[nearest] = true;
        matched.push(nearest);
    }
    Ok(matched)
}

/// The first item of sorted `a` not in sorted `b` (counting repeats), or of `b` not in `a`,
/// said as `what` and the item as `say` writes it.
fn first_unshared<T: Ord + AsRef<[Corner]>>(
    a: &[T],
    b: &[T],
    what: &str,
    say: &dyn Fn(&[Corner]) -> String,
) -> Result<(), String> {
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x == y => (i, j) = (i + 1, j + 1),
            (Some(x), y) if y.is_none_or(|y| x < y) => {
                return Err(format!(
                    "yours makes {what} {}, the reference does not",
                    say(x.as_ref())
                ));
            }
            (_, Some(y)) => {
                return Err(format!(
                    "the reference makes {what} {}, yours does not",
                    say(y.as_ref())
                ));
            }
            _ => break,
        }
    }
    Ok(())
}

/// A panic's message, where it carried one.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    match (
        payload.downcast_ref::<&str>(),
        payload.downcast_ref::<String>(),
    ) {
        (Some(s), _) => (*s).to_string(),
        (_, Some(s)) => s.clone(),
        _ => "no message".into(),
    }
}
