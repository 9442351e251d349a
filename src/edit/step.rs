//! The steps of `pappus process`: text in, [`Edit`] out.
//!
//! Whole-mesh steps name their parameters (`simplify:0.25`, `remesh:3:0.5`); local steps name
//! their elements by the input file's vertex numbers (0-based), so a script written against a
//! file keeps working whatever ids the elements get: `A` is a vertex, `A,B` the edge between
//! two vertices, `A,B,C` the face with those three consecutive corners (either way round), and
//! several elements are separated by `/` (`extrude:0,1,2/1,2,3:0.5`).

use bevy::math::{Affine3A, Vec3};
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, ElementId, VertexId};
use crate::mesh::{MeshId, MeshRef, validate};
use crate::ops::Refusal;
use crate::ops::deform::{DeformMethod, DeformParams, FairParams};
use crate::ops::local::faces_of;
use crate::ops::named::Named;
use crate::ops::progressive::ProgressiveMesh;
use crate::ops::smooth::{SmoothMethod, SmoothParams};

use super::{Edit, EditContext, Invocation};

/// A local edit as a `process` step writes it: by the input file's vertex numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LocalKind {
    /// `flip:A,B`.
    Flip,
    /// `split:A,B`.
    Split,
    /// `bisect:A,B`.
    Bisect,
    /// `collapse:A,B`.
    Collapse,
    /// `dissolve:A,B`.
    Dissolve,
    /// `fill-hole:A,B`: the hole beside the boundary edge.
    FillHole,
    /// `split-face:A,B`: the face the two vertices share, between them.
    SplitFace,
    /// `seam:A,B`: mark the edge a seam (or unmark it).
    Seam,
}

impl Named for LocalKind {
    /// Every kind, with its step name.
    const ALL: &'static [(Self, &'static str)] = &[
        (LocalKind::Flip, "flip"),
        (LocalKind::Split, "split"),
        (LocalKind::Bisect, "bisect"),
        (LocalKind::Collapse, "collapse"),
        (LocalKind::Dissolve, "dissolve"),
        (LocalKind::FillHole, "fill-hole"),
        (LocalKind::SplitFace, "split-face"),
        (LocalKind::Seam, "seam"),
    ];
}

impl LocalKind {
    /// The edit on the elements between the live vertices `a` and `b` (the input file's
    /// vertices `ia` and `ib`, named in refusals).
    ///
    /// # Refusals
    /// [`Refusal::NoEdgeBetween`] / [`Refusal::NoSharedFace`] when the two share none.
    pub fn between(
        self,
        world: &World,
        (a, b): (VertexId, VertexId),
        (ia, ib): (u32, u32),
    ) -> Result<Edit, Refusal> {
        let m = MeshRef::new(world);
        if self == LocalKind::SplitFace {
            let face = m
                .vertex_faces(a)
                .find(|&f| m.face_vertices(f).any(|v| v == b))
                .ok_or(Refusal::NoSharedFace(ia, ib))?;
            return Ok(Edit::SplitFace(face, a, b));
        }
        let e = m
            .find_halfedge(a, b)
            .map(|h| m.edge(h))
            .ok_or(Refusal::NoEdgeBetween(ia, ib))?;
        Ok(self
            .on_edge(e)
            .expect("every kind but split-face acts on an edge"))
    }

    /// The edit of this kind on edge `e`; `None` for the kinds that do not act on an edge.
    pub fn on_edge(self, e: EdgeId) -> Option<Edit> {
        Some(match self {
            LocalKind::Flip => Edit::Flip(e),
            LocalKind::Split => Edit::Split(e),
            LocalKind::Bisect => Edit::Bisect(e),
            LocalKind::Collapse => Edit::Collapse(e),
            LocalKind::Dissolve => Edit::Dissolve(e),
            LocalKind::FillHole => Edit::FillHole(e),
            LocalKind::Seam => Edit::ToggleSeam(e),
            LocalKind::SplitFace => return None,
        })
    }
}

/// One step of `pappus process`, as parsed from its text (`simplify:0.25`, `flip:3,17`, …).
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Check every invariant; refused (with the broken rule) if one fails.
    Validate,
    /// An edit that names no element (a whole-mesh edit, or a move along the history).
    Edit(Edit),
    /// A local edit on the elements between two of the input file's vertices.
    Local(LocalKind, u32, u32),
    /// An edit of elements named by vertex numbers (`A`, `A,B`, `A,B,C`, several joined by
    /// `/`), with its numbers (a distance, an amount).
    Elements(ElementStep, Vec<Vec<u32>>, Vec<f32>),
    /// `deform:arap|laplace:FIXED:HANDLE:DX,DY,DZ[:ITERATIONS]`.
    Deform(DeformStep),
    /// `fair:VERTICES[:K]`: the vertices, and the order k.
    Fair(Vec<u32>, u32),
    /// `fill-hole:A,B:fair`: the hole beside the boundary edge, filled with a fair patch.
    FillHoleFair(u32, u32),
}

/// A handle deformation as a step names it: by the input file's vertex numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct DeformStep {
    /// The method.
    pub method: DeformMethod,
    /// The anchors (may be none).
    pub fixed: Vec<u32>,
    /// The handle (at least one vertex).
    pub handle: Vec<u32>,
    /// The handle's translation.
    pub offset: Vec3,
    /// ARAP iterations.
    pub iterations: u32,
}

impl DeformStep {
    /// Parses `METHOD:FIXED:HANDLE:DX,DY,DZ[:ITERATIONS]`.
    fn parse(args: &str) -> Option<Self> {
        let parts: Vec<&str> = args.split(':').collect();
        let [method, fixed, handle, offset, rest @ ..] = parts.as_slice() else {
            return None;
        };
        let (method, _) = DeformMethod::ALL.iter().find(|(_, n)| n == method)?;
        let offset: Vec<f32> = offset
            .split(',')
            .map(|x| x.trim().parse::<f32>().ok().filter(|x| x.is_finite()))
            .collect::<Option<_>>()?;
        let iterations = match rest {
            [] => DeformParams::DEFAULT_ITERATIONS,
            [n] => n
                .parse()
                .ok()
                .filter(|n| (1..=DeformParams::MAX_ITERATIONS).contains(n))?,
            _ => return None,
        };
        let handle = parse_vertices(handle).filter(|h| !h.is_empty())?;
        Some(Self {
            method: *method,
            fixed: parse_vertices(fixed)?,
            handle,
            offset: Vec3::from_slice(offset.get(..3).filter(|_| offset.len() == 3)?),
            iterations,
        })
    }
}

/// `A/B/C` → `[A, B, C]`; the empty text → none.
fn parse_vertices(text: &str) -> Option<Vec<u32>> {
    if text.is_empty() {
        return Some(Vec::new());
    }
    text.split('/').map(|i| i.trim().parse().ok()).collect()
}

/// `[A, B, C]` → `A/B/C`.
fn vertices_text(vertices: &[u32]) -> String {
    vertices
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join("/")
}

/// The live vertex that the input file's vertex `i` became.
///
/// # Refusals
/// [`Refusal::NoInputVertex`] when the input had no such vertex, [`Refusal::Stale`] when an
/// edit since removed it.
fn live_vertex(
    world: &World,
    input_vertices: &[Option<VertexId>],
    i: u32,
) -> Result<VertexId, Refusal> {
    let v = input_vertices
        .get(i as usize)
        .copied()
        .flatten()
        .ok_or(Refusal::NoInputVertex(i))?;
    MeshRef::new(world)
        .try_vertex(v)
        .map(|_| v)
        .ok_or(Refusal::Stale(ElementId::Vertex(v)))
}

/// The steps that name elements of any kind, and how many numbers follow them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementStep {
    /// `extrude:FACES:DISTANCE`: the faces as one region.
    Extrude,
    /// `inset:FACES:AMOUNT[:DEPTH]`: each face (AMOUNT of the way to its centre, 0–1).
    Inset,
    /// `bevel:ELEMENT[:AMOUNT[:DEPTH]]`: a vertex or an edge (AMOUNT along its edges, 0–0.5,
    /// default 0.25), or a face (an inset by AMOUNT with DEPTH).
    Bevel,
    /// `erase:ELEMENTS`: the faces (of the vertices, edges) become holes.
    Erase,
    /// `dissolve:A`: merge the faces around a vertex.
    Dissolve,
    /// `collapse:A,B,C`: a face to its centroid.
    Collapse,
    /// `weld:A,B/C,D`: two boundary edges into one.
    Weld,
}

impl Named for ElementStep {
    const ALL: &'static [(Self, &'static str)] = &[
        (ElementStep::Extrude, "extrude"),
        (ElementStep::Inset, "inset"),
        (ElementStep::Bevel, "bevel"),
        (ElementStep::Erase, "erase"),
        (ElementStep::Dissolve, "dissolve"),
        (ElementStep::Collapse, "collapse"),
        (ElementStep::Weld, "weld"),
    ];
}

impl ElementStep {
    /// Checks the shape of the step's arguments: the kinds of elements it names and its
    /// numbers. Returns what is wrong.
    fn check(self, targets: &[Vec<u32>], numbers: &[f32]) -> Result<(), &'static str> {
        let all = |n: std::ops::RangeFrom<usize>| targets.iter().all(|t| n.contains(&t.len()));
        let (shape, numbers_ok) = match self {
            ElementStep::Extrude => (all(3..), numbers.len() == 1),
            ElementStep::Inset => (all(3..), (1..=2).contains(&numbers.len())),
            ElementStep::Bevel => (targets.len() == 1, numbers.len() <= 2),
            ElementStep::Erase => (true, numbers.is_empty()),
            ElementStep::Dissolve => (
                targets.len() == 1 && targets[0].len() == 1,
                numbers.is_empty(),
            ),
            ElementStep::Collapse => (
                targets.len() == 1 && targets[0].len() >= 3,
                numbers.is_empty(),
            ),
            ElementStep::Weld => (
                targets.len() == 2 && targets.iter().all(|t| t.len() == 2),
                numbers.is_empty(),
            ),
        };
        match (shape && !targets.is_empty(), numbers_ok) {
            (true, true) => Ok(()),
            _ => Err(match self {
                ElementStep::Extrude => {
                    "expected faces and a distance, as in `extrude:0,1,2/1,2,3:0.5`"
                }
                ElementStep::Inset => {
                    "expected faces and an amount, as in `inset:0,1,2:0.3[:DEPTH]`"
                }
                ElementStep::Bevel => "expected one element, as in `bevel:4:0.25` or `bevel:0,1`",
                ElementStep::Erase => "expected elements, as in `erase:4` or `erase:0,1,2/5,6`",
                ElementStep::Dissolve => {
                    "expected a vertex (`dissolve:A`) or an edge (`dissolve:A,B`)"
                }
                ElementStep::Collapse => {
                    "expected an edge (`collapse:A,B`) or a face (`collapse:A,B,C`)"
                }
                ElementStep::Weld => "expected two boundary edges, as in `weld:0,1/7,8`",
            }),
        }
    }

    /// The edit on the named live elements.
    fn edit(self, world: &World, elements: &[ElementId], numbers: &[f32]) -> Result<Edit, Refusal> {
        let faces = || faces_of(world, elements);
        let number = |i: usize, default: f32| numbers.get(i).copied().unwrap_or(default);
        Ok(match (self, elements) {
            (ElementStep::Extrude, _) => Edit::Extrude(faces()?, number(0, 0.0)),
            (ElementStep::Inset, _) => Edit::Inset(faces()?, number(0, 0.0), number(1, 0.0)),
            (ElementStep::Bevel, [ElementId::Vertex(v)]) => Edit::BevelVertex(*v, number(0, 0.25)),
            (ElementStep::Bevel, [ElementId::Edge(e)]) => Edit::BevelEdge(*e, number(0, 0.25)),
            (ElementStep::Bevel, [ElementId::Face(f)]) => {
                Edit::Inset(vec![*f], number(0, 0.25), number(1, 0.0))
            }
            (ElementStep::Erase, _) => Edit::Erase(faces()?),
            (ElementStep::Dissolve, [ElementId::Vertex(v)]) => Edit::DissolveVertex(*v),
            (ElementStep::Collapse, [ElementId::Face(f)]) => Edit::CollapseFace(*f),
            (ElementStep::Weld, [ElementId::Edge(a), ElementId::Edge(b)]) => Edit::Weld(*a, *b),
            _ => unreachable!("checked when parsed"),
        })
    }
}

/// `A,B,C/D,E` → `[[A, B, C], [D, E]]`.
fn parse_targets(text: &str) -> Option<Vec<Vec<u32>>> {
    text.split('/')
        .map(|t| t.split(',').map(|i| i.trim().parse().ok()).collect())
        .collect()
}

/// The element named by input vertex numbers: a vertex, the edge between two, the face with
/// three consecutive corners (either way round).
fn element_at(
    world: &World,
    input_vertices: &[Option<VertexId>],
    target: &[u32],
) -> Result<ElementId, Refusal> {
    let m = MeshRef::new(world);
    let corners: Vec<VertexId> = target
        .iter()
        .map(|&i| live_vertex(world, input_vertices, i))
        .collect::<Result<_, _>>()?;
    match corners[..] {
        [v] => Ok(ElementId::Vertex(v)),
        [a, b] => m
            .find_halfedge(a, b)
            .map(|h| ElementId::Edge(m.edge(h)))
            .ok_or(Refusal::NoEdgeBetween(target[0], target[1])),
        [a, b, c, ..] => [(a, b, c), (c, b, a)]
            .into_iter()
            .find_map(|(a, b, c)| {
                let h = m.find_halfedge(a, b)?;
                (m.to_vertex(m.next(h)) == c).then_some(m.face(h)?)
            })
            .map(ElementId::Face)
            .ok_or(Refusal::NoSharedFace(target[0], target[2])),
        [] => unreachable!("targets are never empty"),
    }
}

/// The step syntax, for usage texts: `validate`, each registered operation's (from its
/// declaration, with its help line), then the others'.
pub fn step_syntax() -> String {
    let mut text = String::from("validate |\n");
    for op in crate::ops::OPERATIONS {
        text.push_str(&op.declaration().syntax());
        text.push_str(" |\n");
    }
    text + OTHER_STEPS
}

/// The syntax of the steps that are not registered operations.
const OTHER_STEPS: &str = "\
flip:A,B | split:A,B | bisect:A,B | collapse:A,B |
dissolve:A,B | split-face:A,B | fill-hole:A,B | seam:A,B (mark, for param) |
smooth:uniform|cotan|implicit|taubin[:ITERATIONS[:STEP]]   (the boundary held) |
extrude:FACES:DISTANCE | inset:FACES:AMOUNT[:DEPTH] | bevel:ELEMENT[:AMOUNT[:DEPTH]] |
erase:ELEMENTS | dissolve:A | collapse:A,B,C | weld:A,B/C,D |
deform:arap|laplace:FIXED:HANDLE:DX,DY,DZ[:ITERATIONS]   (FIXED stays, HANDLE moves by DX,DY,DZ) |
fair:VERTICES[:K]   (k-harmonic, K 1-3, default 2) | fill-hole:A,B:fair
A, B, C: 0-based indices of the input file's vertices: A a vertex, A,B the edge between two,
A,B,C the face with those consecutive corners; several elements joined by /";

impl Step {
    /// Parses a step as written on the command line.
    ///
    /// # Errors
    /// A message naming the step when it is unknown or its arguments are malformed.
    pub fn parse(text: &str) -> Result<Step, String> {
        let (name, args) = text.split_once(':').unwrap_or((text, ""));
        let pair = || -> Result<(u32, u32), String> {
            let bad = || format!("step `{text}`: expected two vertex numbers, as in `{name}:3,17`");
            let (a, b) = args.split_once(',').ok_or_else(bad)?;
            Ok((
                a.trim().parse().map_err(|_| bad())?,
                b.trim().parse().map_err(|_| bad())?,
            ))
        };
        if let Some(edge) = args.strip_suffix(":fair").filter(|_| name == "fill-hole") {
            let (a, b) = edge
                .split_once(',')
                .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
                .ok_or_else(|| format!("step `{text}`: expected fill-hole:A,B:fair"))?;
            return Ok(Step::FillHoleFair(a, b));
        }
        let element_step = ElementStep::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|x| x.0);
        if let Some(&(kind, _)) = LocalKind::ALL.iter().find(|(_, n)| *n == name) {
            // `dissolve` and `collapse` name an edge here, a vertex or a face below.
            let is_pair = args.split(',').count() == 2 && !args.contains([':', '/']);
            if element_step.is_none() || is_pair {
                return pair().map(|(a, b)| Step::Local(kind, a, b));
            }
        }
        if let Some(op) = element_step {
            let mut parts = args.split(':');
            let targets = parts.next().and_then(parse_targets);
            let numbers: Option<Vec<f32>> = parts
                .map(|x| x.parse::<f32>().ok().filter(|x| x.is_finite()))
                .collect();
            let bad = |why: &str| format!("step `{text}`: {why}");
            let (Some(targets), Some(numbers)) = (targets, numbers) else {
                return Err(bad(op.check(&[], &[]).expect_err("empty targets")));
            };
            op.check(&targets, &numbers).map_err(bad)?;
            return Ok(Step::Elements(op, targets, numbers));
        }
        Self::parse_named(text, name, args)
    }

    /// The steps named by a word and parameters (not elements): `loop:2`, `simplify:0.25`,
    /// `remesh`, `smooth:cotan`, `deform:…`, `fair:…`, `fill-holes`, `param:…`, `validate`.
    fn parse_named(text: &str, name: &str, args: &str) -> Result<Step, String> {
        let edit = match name {
            "validate" => return Ok(Step::Validate),
            "smooth" => Edit::Smooth(parse_smooth(args).ok_or_else(|| {
                format!(
                    "step `{text}`: expected smooth:uniform|cotan|implicit|taubin[:ITERATIONS[:STEP]]"
                )
            })?),
            "deform" => {
                return DeformStep::parse(args).map(Step::Deform).ok_or_else(|| {
                    format!(
                        "step `{text}`: expected deform:arap|laplace:FIXED:HANDLE:DX,DY,DZ\
                         [:ITERATIONS] (vertex lists joined by /, HANDLE not empty, 1 to {} \
                         iterations)",
                        DeformParams::MAX_ITERATIONS
                    )
                });
            }
            "fair" => {
                let bad = || format!("step `{text}`: expected fair:VERTICES[:K], K 1, 2 or 3");
                let (vertices, k) = args.split_once(':').unwrap_or((args, "2"));
                let k = k.parse().ok().filter(|k| (1..=3).contains(k)).ok_or_else(bad)?;
                let vertices = parse_vertices(vertices)
                    .filter(|v| !v.is_empty())
                    .ok_or_else(bad)?;
                return Ok(Step::Fair(vertices, k));
            }
            _ => {
                let op = crate::ops::operation(name).ok_or_else(|| {
                    format!("unknown step `{text}` (see `pappus process --help`)")
                })?;
                Edit::Operation(Invocation::parse(op, args).map_err(|why| {
                    format!(
                        "step `{text}`: {why}; expected {}",
                        op.declaration().syntax()
                    )
                })?)
            }
        };
        Ok(Step::Edit(edit))
    }

    /// Runs the step on `mesh`. `input_vertices` maps the input file's vertex numbers to the
    /// vertices they became; `history` is the simplification history a `refine` moves along.
    ///
    /// # Refusals
    /// As [`Edit::run`]; a local step naming vertices the input lacks or that share no
    /// edge (face); `validate` on an invalid mesh.
    pub fn run(
        &self,
        world: &mut World,
        mesh: MeshId,
        input_vertices: &[Option<VertexId>],
        history: &mut Option<ProgressiveMesh>,
    ) -> Result<String, Refusal> {
        let edit = match self {
            Step::Validate => {
                return validate(world, mesh)
                    .map(|()| "valid".to_string())
                    .map_err(|e| Refusal::Invalid(e.to_string()));
            }
            Step::Edit(edit) => edit.clone(),
            Step::Local(kind, a, b) => {
                let live = |i: u32| live_vertex(world, input_vertices, i);
                kind.between(world, (live(*a)?, live(*b)?), (*a, *b))?
            }
            Step::FillHoleFair(a, b) => {
                let live = |i: u32| live_vertex(world, input_vertices, i);
                let (va, vb) = (live(*a)?, live(*b)?);
                let m = MeshRef::new(world);
                let h = m
                    .find_halfedge(va, vb)
                    .ok_or(Refusal::NoEdgeBetween(*a, *b))?;
                Edit::FillHoleFair(m.edge(h))
            }
            Step::Deform(d) => {
                let live = |list: &[u32]| -> Result<Vec<VertexId>, Refusal> {
                    list.iter()
                        .map(|&i| live_vertex(world, input_vertices, i))
                        .collect()
                };
                Edit::Deform(DeformParams {
                    method: d.method,
                    fixed: live(&d.fixed)?,
                    handle: live(&d.handle)?,
                    motion: Affine3A::from_translation(d.offset),
                    iterations: d.iterations,
                })
            }
            Step::Fair(vertices, k) => Edit::Fair(FairParams {
                vertices: vertices
                    .iter()
                    .map(|&i| live_vertex(world, input_vertices, i))
                    .collect::<Result<_, _>>()?,
                k: *k,
            }),
            Step::Elements(op, targets, numbers) => {
                let elements: Vec<ElementId> = targets
                    .iter()
                    .map(|t| element_at(world, input_vertices, t))
                    .collect::<Result<_, _>>()?;
                op.edit(world, &elements, numbers)?
            }
        };
        let mut context = EditContext {
            history,
            progress: &mut |_| true,
        };
        let applied = edit.run(world, mesh, &mut context)?;
        if !edit.keeps_history() {
            *history = None;
        }
        Ok(applied.summary)
    }
}

/// `METHOD[:ITERATIONS[:STEP]]` of a `smooth` step.
fn parse_smooth(args: &str) -> Option<SmoothParams> {
    let mut parts = args.split(':');
    let method = parts.next()?;
    let (method, _) = SmoothMethod::ALL.iter().find(|(_, n)| *n == method)?;
    let mut params = SmoothParams::new(*method);
    if let Some(n) = parts.next() {
        params.iterations = n.parse().ok().filter(|n| (1..=10_000).contains(n))?;
    }
    if let Some(step) = parts.next() {
        params.step = step
            .parse()
            .ok()
            .filter(|s: &f64| *s > 0.0 && s.is_finite())?;
    }
    parts.next().is_none().then_some(params)
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Step::Validate => write!(f, "validate"),
            Step::Local(kind, a, b) => write!(f, "{}:{a},{b}", kind.name()),
            Step::FillHoleFair(a, b) => write!(f, "fill-hole:{a},{b}:fair"),
            Step::Fair(vertices, k) => write!(f, "fair:{}:{k}", vertices_text(vertices)),
            Step::Deform(d) => write!(
                f,
                "deform:{}:{}:{}:{},{},{}:{}",
                d.method.name(),
                vertices_text(&d.fixed),
                vertices_text(&d.handle),
                d.offset.x,
                d.offset.y,
                d.offset.z,
                d.iterations
            ),
            Step::Elements(op, targets, numbers) => {
                let targets: Vec<String> = targets
                    .iter()
                    .map(|t| t.iter().map(u32::to_string).collect::<Vec<_>>().join(","))
                    .collect();
                write!(f, "{}:{}", op.name(), targets.join("/"))?;
                numbers.iter().try_for_each(|x| write!(f, ":{x}"))
            }
            Step::Edit(edit) => match edit {
                Edit::Operation(op) => write!(f, "{op}"),
                Edit::Smooth(p) => {
                    write!(f, "smooth:{}:{}:{}", p.method.name(), p.iterations, p.step)
                }
                other => write!(f, "{}", other.label()),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_step_prints_as_it_parses() {
        for text in [
            "validate",
            "triangulate",
            "reverse",
            "orient-outside",
            "normalize:2",
            "flip:3,17",
            "split:0,1",
            "bisect:0,1",
            "collapse:1,2",
            "dissolve:4,5",
            "fill-hole:0,1",
            "split-face:0,2",
            "seam:0,1",
            "loop",
            "loop:3",
            "catmull-clark:2",
            "simplify:0.25",
            "simplify-faces:500",
            "refine",
            "refine:5000",
            "remesh",
            "remesh:3",
            "remesh:3:0.5",
            "remesh:5:auto:30",
            "smooth:taubin:10:0.5",
            "smooth:implicit:1:2",
            "param:harmonic",
            "param:lscm:square",
            "extrude:0,1,2/1,2,3:0.5",
            "inset:0,1,2:0.3",
            "inset:0,1,2:0.3:-0.1",
            "bevel:4:0.25",
            "bevel:0,1:0.1",
            "bevel:0,1,2:0.2:0.1",
            "erase:4/0,1/0,1,2",
            "dissolve:4",
            "collapse:0,1,2",
            "weld:0,1/7,8",
            "deform:arap:0/1/2:5/6:0,0.5,-1:10",
            "deform:laplace::5:1,0,0:10",
            "fair:3/4/5:2",
            "fill-hole:0,1:fair",
            "fill-holes",
            "fill-holes:fair",
            "param",
        ] {
            let step = Step::parse(text).unwrap();
            assert_eq!(step.to_string(), text);
            assert_eq!(Step::parse(&step.to_string()).unwrap(), step);
        }
        assert_eq!(Step::parse("loop:1").unwrap().to_string(), "loop");
        assert_eq!(
            Step::parse("param:mean-value:circle").unwrap().to_string(),
            "param"
        );
        assert_eq!(
            Step::parse("remesh:5:auto:45").unwrap().to_string(),
            "remesh"
        );
        assert_eq!(Step::parse("normalize:1").unwrap().to_string(), "normalize");
        assert_eq!(
            Step::parse("fill-holes:polygon").unwrap().to_string(),
            "fill-holes"
        );
        assert_eq!(
            Step::parse("smooth:cotan").unwrap().to_string(),
            "smooth:cotan:1:0.5"
        );
    }

    /// Every registered operation has its own name (no built-in step hides it), a title and
    /// a help line, defaults its ranges admit, and parses by its name alone to itself with them.
    #[test]
    fn every_registered_operation_parses_by_its_name_to_its_defaults() {
        let mut names = std::collections::HashSet::new();
        for &op in crate::ops::OPERATIONS {
            let d = op.declaration();
            assert!(names.insert(d.name), "{} registered twice", d.name);
            assert!(!d.title.is_empty() && !d.help.is_empty(), "{}", d.name);
            assert!(
                d.parameters
                    .iter()
                    .all(|p| p.admits(p.default) && p.admits(Some(p.suggested))),
                "{}",
                d.name
            );
            assert_eq!(
                Step::parse(d.name).unwrap(),
                Step::Edit(Edit::Operation(Invocation::with_defaults(op))),
                "{}",
                d.name
            );
        }
    }

    #[test]
    fn malformed_steps_say_what_is_expected() {
        for (text, expected) in [
            ("frobnicate", "unknown step"),
            ("flip:3", "two vertex numbers"),
            ("loop:9", "from 1 to 8"),
            ("simplify:0", "RATIO must be a number from 0.000001 to 1"),
            ("simplify:1.5", "RATIO must be a number from 0.000001 to 1"),
            (
                "simplify-faces:0.5",
                "FACES must be a whole number from 0 to",
            ),
            ("remesh:0", "ITERATIONS"),
            ("remesh:3:-1", "LENGTH"),
            ("refine:lots", "FACES must be a whole number"),
            ("smooth:gaussian", "uniform|cotan"),
            ("smooth:uniform:0", "ITERATIONS"),
            (
                "param:spectral",
                "METHOD must be one of uniform, mean-value, harmonic, lscm",
            ),
            (
                "param:harmonic:hexagon",
                "BOUNDARY must be one of circle, square",
            ),
            (
                "param:harmonic:circle:x",
                "param takes at most 2 parameter(s)",
            ),
            ("extrude:0,1,2", "a distance"),
            ("extrude:0,1:0.5", "faces and a distance"),
            ("weld:0,1", "two boundary edges"),
            ("bevel:0/1", "one element"),
            ("dissolve:1,2,3", "a vertex"),
            ("erase:x", "expected elements"),
            ("deform:arap:0:1:1,2", "DX,DY,DZ"),
            ("deform:arap:0::1,2,3", "HANDLE not empty"),
            ("deform:spring:0:1:1,2,3", "arap|laplace"),
            ("deform:arap:0:1:1,2,3:0", "iterations"),
            ("fair:1/2:4", "K 1, 2 or 3"),
            ("fill-hole:0:fair", "fill-hole:A,B:fair"),
            ("fill-holes:smooth", "FILL must be one of polygon, fair"),
            ("normalize:0", "SIZE must be a number from"),
            ("normalize:x", "expected normalize[:SIZE]"),
            ("reverse:1", "reverse takes no parameters"),
        ] {
            let e = Step::parse(text).unwrap_err();
            assert!(e.contains(expected), "{text}: {e}");
        }
    }
}
