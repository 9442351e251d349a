//! The steps of `pappus process`: text in, [`Edit`] out.
//!
//! Whole-mesh steps name their parameters (`simplify:0.25`, `remesh:3:0.5`); local steps name
//! their elements by the input file's vertex numbers (0-based), so a script written against a
//! file keeps working whatever ids the elements get: `A` is a vertex, `A,B` the edge between
//! two vertices (for `split-face`, the face the two share, between them), `A,B,C` the face with
//! those three consecutive corners (either way round), and several elements are separated by
//! `/` (`extrude:0,1,2/1,2,3:0.5`, `fair:3/4/5`).

use bevy::math::{Affine3A, Vec3};
use bevy::prelude::World;

use crate::mesh::ids::{ElementId, VertexId};
use crate::mesh::{MeshId, MeshRef, validate};
use crate::ops::Refusal;
use crate::ops::deform::{DeformMethod, DeformParams};
use crate::ops::named::Named;

use super::{Edit, EditContext, Invocation};
use crate::ops::declaration::Names;

/// One step of `pappus process`, as parsed from its text (`simplify:0.25`, `flip:3,17`, …).
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Check every invariant; refused (with the broken rule) if one fails.
    Validate,
    /// An edit that names no element (a whole-mesh edit, or a move along the history).
    Edit(Edit),
    /// A registered operation on the elements the input file's vertex numbers name (`flip:3,17`:
    /// the edge between two), with its parameters' values; the invocation names no element yet.
    On(Invocation, Vec<Vec<u32>>),
    /// `deform:arap|laplace:FIXED:HANDLE:DX,DY,DZ[:ITERATIONS]`.
    Deform(DeformStep),
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

/// `[[A, B, C], [D, E]]` → `A,B,C/D,E`.
fn targets_text(targets: &[Vec<u32>]) -> String {
    let targets: Vec<String> = targets
        .iter()
        .map(|t| t.iter().map(u32::to_string).collect::<Vec<_>>().join(","))
        .collect();
    targets.join("/")
}

/// `A,B,C/D,E` → `[[A, B, C], [D, E]]`.
fn parse_targets(text: &str) -> Option<Vec<Vec<u32>>> {
    text.split('/')
        .map(|t| t.split(',').map(|i| i.trim().parse().ok()).collect())
        .collect()
}

/// The elements an operation that names `names` is given by the input vertex numbers
/// `targets`: for each, a vertex, the edge between two, the face with three consecutive
/// corners (either way round); for a face split, the face two vertices share and the two.
///
/// # Refusals
/// As [`element_at`]; [`Refusal::NoSharedFace`] for a face split's two vertices that share
/// none; [`Refusal::BadParameter`] for a target of no vertex.
pub fn elements_at(
    world: &World,
    input_vertices: &[Option<VertexId>],
    names: Names,
    targets: &[Vec<u32>],
) -> Result<Vec<ElementId>, Refusal> {
    if let (Names::FaceCorners, [target]) = (names, targets)
        && let &[ia, ib] = target.as_slice()
    {
        let a = live_vertex(world, input_vertices, ia)?;
        let b = live_vertex(world, input_vertices, ib)?;
        let m = MeshRef::new(world);
        let face = m
            .vertex_faces(a)
            .find(|&f| m.face_vertices(f).any(|v| v == b))
            .ok_or(Refusal::NoSharedFace(ia, ib))?;
        return Ok(vec![
            ElementId::Face(face),
            ElementId::Vertex(a),
            ElementId::Vertex(b),
        ]);
    }
    targets
        .iter()
        .map(|t| element_at(world, input_vertices, t))
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
        [] => Err(Refusal::BadParameter(
            "an element names at least one vertex".into(),
        )),
    }
}

/// The step syntax, for usage texts: `validate`, each registered operation's (from its
/// declaration, with its help line), then the others'.
pub fn step_syntax() -> String {
    let mut text = String::from("validate |\n");
    for op in crate::ops::registry::operations() {
        text.push_str(&op.declaration().syntax());
        text.push_str(" |\n");
    }
    text + OTHER_STEPS
}

/// The syntax of the steps that are not registered operations.
const OTHER_STEPS: &str = "\
deform:arap|laplace:FIXED:HANDLE:DX,DY,DZ[:ITERATIONS]   (FIXED stays, HANDLE moves by DX,DY,DZ)
A, B, C: 0-based indices of the input file's vertices: A a vertex, A,B the edge between two
(split-face: the face they share), A,B,C the face with those consecutive corners; several
elements (and VERTICES) joined by /";

impl Step {
    /// Parses a step as written on the command line.
    ///
    /// # Errors
    /// A message naming the step when it is unknown or its arguments are malformed.
    pub fn parse(text: &str) -> Result<Step, String> {
        let (name, args) = text.split_once(':').unwrap_or((text, ""));
        if let Some(step) = Self::parse_on_elements(text, name, args) {
            return step;
        }
        Self::parse_named(text, name, args)
    }

    /// A step of a registered operation that names elements (`flip:3,17`, `collapse:0,1,2`,
    /// `dissolve:4`): the elements, then its values after a colon. Of the operations that
    /// share the name, the one that names what the numbers name (`A` a vertex, `A,B` an edge,
    /// `A,B,C` a face). `None` when no registered operation of that name names elements.
    fn parse_on_elements(text: &str, name: &str, args: &str) -> Option<Result<Step, String>> {
        let ops: Vec<_> = crate::ops::registry::operations_named(name)
            .into_iter()
            .filter(|op| !op.declaration().names.is_whole_mesh())
            .collect();
        if ops.is_empty() {
            return None;
        }
        // Only a refusal needs the syntax.
        let bad = |why: String| {
            let syntax: Vec<String> = ops.iter().map(|op| op.declaration().syntax()).collect();
            format!("step `{text}`: {why}; expected {}", syntax.join(" or "))
        };
        let (targets, values) = args.split_once(':').unwrap_or((args, ""));
        let Some(targets) = parse_targets(targets) else {
            return Some(Err(bad("the elements are not input vertex numbers".into())));
        };
        let counts: Vec<usize> = targets.iter().map(Vec::len).collect();
        let Some(&op) = ops.iter().find(|op| op.declaration().names.fits(&counts)) else {
            let needs: Vec<&str> = ops.iter().map(|op| op.declaration().names.what()).collect();
            return Some(Err(bad(format!("{name} names {}", needs.join(" or ")))));
        };
        Some(
            Invocation::parse(op, values)
                .map(|invocation| Step::On(invocation, targets))
                .map_err(bad),
        )
    }

    /// The steps named by a word and parameters (not elements): `loop:2`, `simplify:0.25`,
    /// `remesh`, `smooth:cotan`, `deform:…`, `fill-holes`, `param:…`, `validate`.
    fn parse_named(text: &str, name: &str, args: &str) -> Result<Step, String> {
        let edit = match name {
            "validate" => return Ok(Step::Validate),
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
            _ => {
                let op = crate::ops::registry::operation(name).ok_or_else(|| {
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
    /// vertices they became.
    ///
    /// # Refusals
    /// As [`Edit::run`]; a local step naming vertices the input lacks or that share no
    /// edge (face); `validate` on an invalid mesh.
    pub fn run(
        &self,
        world: &mut World,
        mesh: MeshId,
        input_vertices: &[Option<VertexId>],
    ) -> Result<String, Refusal> {
        let edit = match self {
            Step::Validate => {
                return validate(world, mesh)
                    .map(|()| "valid".to_string())
                    .map_err(|e| Refusal::Invalid(e.to_string()));
            }
            Step::Edit(edit) => edit.clone(),
            Step::On(invocation, targets) => {
                let names = invocation.declaration().names;
                let elements = elements_at(world, input_vertices, names, targets)?;
                Edit::Operation(
                    invocation
                        .clone()
                        .on(elements)
                        .map_err(Refusal::BadParameter)?,
                )
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
        };
        let mut context = EditContext {
            progress: &mut |_| true,
        };
        Ok(edit.run(world, mesh, &mut context)?.summary)
    }
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Step::Validate => write!(f, "validate"),
            Step::On(invocation, targets) => {
                let mut text = invocation.to_string();
                let at = text.find(':').unwrap_or(text.len());
                text.insert_str(at, &format!(":{}", targets_text(targets)));
                write!(f, "{text}")
            }
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
            Step::Edit(edit) => match edit {
                Edit::Operation(op) => write!(f, "{op}"),
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
            "bevel:4:0.3",
            "bevel:0,1:0.1",
            "bevel:0,1,2:0.2:0.1",
            "erase:4/0,1/0,1,2",
            "dissolve:4",
            "collapse:0,1,2",
            "weld:0,1/7,8",
            "deform:arap:0/1/2:5/6:0,0.5,-1:10",
            "deform:laplace::5:1,0,0:10",
            "fair:3/4/5",
            "fair:3/4/5:3",
            "smooth",
            "smooth:cotan:5:auto:free-boundary",
            "vertex-split:3",
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
            Step::parse("smooth:cotan:1").unwrap().to_string(),
            "smooth:cotan"
        );
        assert_eq!(
            Step::parse("fair:3/4/5:2").unwrap().to_string(),
            "fair:3/4/5"
        );
    }

    /// Every registered operation has its own name (no built-in step hides it) or shares it
    /// with others that name other kinds of elements, has a title and a help line, defaults
    /// its ranges admit, and parses by its name (and its element's vertex numbers) alone to
    /// itself with them.
    #[test]
    fn every_registered_operation_parses_by_its_name_to_its_defaults() {
        let mut names = std::collections::HashSet::new();
        for op in crate::ops::registry::operations() {
            let d = op.declaration();
            assert!(
                names.insert((d.name, d.names)),
                "{} registered twice",
                d.name
            );
            assert!(!d.title.is_empty() && !d.help.is_empty(), "{}", d.name);
            assert!(
                d.parameters
                    .iter()
                    .all(|p| p.admits(p.default) && p.admits(Some(p.suggested))),
                "{}",
                d.name
            );
            let defaults = Invocation::with_defaults(op);
            let targets: Vec<Vec<u32>> = match d.names {
                Names::Mesh => Vec::new(),
                Names::Vertex => vec![vec![0]],
                Names::Edge => vec![vec![0, 1]],
                Names::Face => vec![vec![0, 1, 2]],
                Names::Faces => vec![vec![0, 1, 2], vec![1, 2, 3]],
                Names::TwoEdges => vec![vec![0, 1], vec![2, 3]],
                Names::Elements => vec![vec![0], vec![0, 1], vec![0, 1, 2]],
                Names::Vertices => vec![vec![0], vec![4]],
                Names::FaceCorners => vec![vec![0, 2]],
                Names::MeshHolding => Vec::new(),
            };
            let (text, expected) = match targets.is_empty() {
                true => (d.name.to_string(), Step::Edit(Edit::Operation(defaults))),
                false => {
                    let text = format!("{}:{}", d.name, targets_text(&targets));
                    (text, Step::On(defaults, targets))
                }
            };
            assert_eq!(Step::parse(&text).unwrap(), expected, "{text}");
        }
    }

    #[test]
    fn malformed_steps_say_what_is_expected() {
        for (text, expected) in [
            ("frobnicate", "unknown step"),
            ("flip:3", "flip names an edge; expected flip:A,B"),
            ("flip:x,1", "not input vertex numbers"),
            ("collapse:1", "collapse names an edge or a face"),
            ("split-face:3", "split-face names two corners of a face"),
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
            (
                "smooth:gaussian",
                "METHOD must be one of uniform, cotan, implicit, taubin",
            ),
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
            ("extrude:0,1:0.5", "extrude names faces"),
            ("inset:0,1,2:1.5", "AMOUNT must be a number from 0 to 0.999"),
            ("weld:0,1", "weld names two edges"),
            ("bevel:0:1.5", "AMOUNT must be a number from 0 to 0.999"),
            ("dissolve:1,2,3", "a vertex"),
            ("erase:x", "not input vertex numbers"),
            ("deform:arap:0:1:1,2", "DX,DY,DZ"),
            ("deform:arap:0::1,2,3", "HANDLE not empty"),
            ("deform:spring:0:1:1,2,3", "arap|laplace"),
            ("deform:arap:0:1:1,2,3:0", "iterations"),
            ("fair:1/2:4", "K must be a whole number from 1 to 3"),
            ("fair:1,2", "fair names vertices"),
            ("fill-hole:0:fair", "fill-hole names an edge"),
            ("fill-hole:0,1:smooth", "FILL must be one of polygon, fair"),
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
