//! QEM simplification as the user invokes it (Garland & Heckbert; the algorithm is
//! [`crate::ops::simplify`]): `simplify[:RATIO][:DISTANCE][:FIT]` (Shift+S) keeps a fraction
//! of the faces, `simplify-faces[:FACES][:DISTANCE][:FIT]` a number of them, DISTANCE the
//! weight of the input's farthest point in a collapse's cost (0, the default: the quadrics
//! alone), FIT `fit` to fit the result's vertices to the input at the end (`no-fit`, the
//! default: where the quadrics put them). Each
//! records every collapse in the mesh's simplification history ([`ProgressiveMesh`], Hoppe
//! 1996), which `refine[:FACES]` — the level-of-detail slider — and `vertex-split` (U) then
//! move along.
//!
//! A module of its own because it joins the two below it: the history records what the
//! simplification does, so `progressive` imports `simplify`, and this imports both. The vertex
//! split's adapter is here rather than beside its algorithm in `ops/local` because it moves
//! along the history, which is built from the local operations.

use bevy::prelude::World;

use crate::mesh::ids::{ElementId, FaceId, MeshId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::{DROPPED_BY_SIMPLIFICATION, Declaration, Names, Parameter, Section};
use crate::ops::operation::stepping::Steps;
use crate::ops::operation::{Applied, EditContext, Invocation, MeshOperation, Redraw, Values};
use crate::ops::progressive::{LEVEL_OF_DETAIL, ProgressiveMesh};
use crate::ops::simplification_history::SimplificationHistory;
use crate::ops::simplify::SimplifyParams;

mod stepping;
pub use stepping::{CANDIDATES, QemSteps};

/// Simplifying to a fraction of the faces: a job on a large mesh; it makes the history that
/// level of detail and vertex splits move along, and drops attributes.
pub const SIMPLIFY: Declaration = Declaration::new("simplify")
    .titled("Simplify")
    .described(
        "QEM edge collapses (Garland & Heckbert) until RATIO of the faces are left; DISTANCE > 0 \
         also weighs how far a collapse takes the input away (8: closer, in about three times \
         the time); FIT fit moves the result's vertices to fit the input at the end",
    )
    .on_key("Shift+S")
    .with_parameters(&[Parameter::real("RATIO", 0.5, 1e-6, 1.0), DISTANCE, FIT])
    .as_job()
    .stepping()
    .keeping_history()
    .dropping(DROPPED_BY_SIMPLIFICATION);

/// Simplifying to a number of faces: as [`SIMPLIFY`].
pub const SIMPLIFY_FACES: Declaration = Declaration::new("simplify-faces")
    .titled("Simplify to faces")
    .described(
        "QEM edge collapses (Garland & Heckbert) until FACES faces are left; DISTANCE and FIT \
         as for simplify",
    )
    .with_parameters(&[Parameter::whole("FACES", 1000, 0, u32::MAX), DISTANCE, FIT])
    .as_job()
    .stepping()
    .keeping_history()
    .dropping(DROPPED_BY_SIMPLIFICATION);

/// The weight of the input's farthest point in a collapse's cost
/// ([`SimplifyParams::distance_weight`]): 0, the default, leaves the quadric error alone.
const DISTANCE: Parameter = Parameter::real("DISTANCE", 0.0, 0.0, 1000.0);

/// Whether the result is fitted to the input at the end ([`SimplifyParams::fit_to_input`]):
/// `no-fit`, the default, or `fit`.
const FIT: Parameter = Parameter::choice("FIT", &["no-fit", "fit"], 0);

/// `simplify[:RATIO[:DISTANCE[:FIT]]]`.
pub struct Simplify;

/// `refine[:FACES]`: along the history to FACES faces, or to the full mesh.
pub struct Refine;

impl Refine {
    /// Refine (or coarsen) along the history to `faces` faces (`None`: the full mesh), as the
    /// level-of-detail slider asks while it is dragged.
    pub fn to(faces: Option<usize>) -> Invocation {
        let mut invocation = Invocation::with_defaults(&Refine);
        let faces = faces.map(|n| n.min(u32::MAX as usize) as f64);
        // Clamped into the parameter's range, so always taken.
        let _ = invocation.set(0, faces);
        invocation
    }
}

/// `simplify-faces[:FACES[:DISTANCE[:FIT]]]`.
pub struct SimplifyFaces;

/// The simplification an invocation of [`Simplify`] or [`SimplifyFaces`] asks for (`None` for
/// any other operation): what step mode steps through collapse by collapse.
pub fn simplification(invocation: &Invocation) -> Option<SimplifyParams> {
    let values = invocation.values();
    if invocation.is(&SIMPLIFY) {
        Some(Simplify::params(values))
    } else if invocation.is(&SIMPLIFY_FACES) {
        Some(SimplifyFaces::params(values))
    } else {
        None
    }
}

impl Simplify {
    /// The simplification its values name: to RATIO of the faces at the DISTANCE weight,
    /// fitted if FIT says so, the default limits.
    fn params(values: Values<'_>) -> SimplifyParams {
        SimplifyParams {
            distance_weight: values.number(1),
            fit_to_input: values.choice(2) == 1,
            ..SimplifyParams::ratio(values.number(0))
        }
    }
}

impl SimplifyFaces {
    /// The simplification its values name: to FACES faces at the DISTANCE weight, fitted if
    /// FIT says so, the default limits.
    fn params(values: Values<'_>) -> SimplifyParams {
        SimplifyParams {
            distance_weight: values.number(1),
            fit_to_input: values.choice(2) == 1,
            ..SimplifyParams::faces(values.whole(0) as usize)
        }
    }
}

impl MeshOperation for Simplify {
    fn declaration(&self) -> &'static Declaration {
        &SIMPLIFY
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        simplify(world, mesh, &Self::params(values), context)
    }

    /// A collapse a step ([`QemSteps`]).
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let steps = QemSteps::start(world, mesh, &Self::params(values));
        Some(steps.map(|s| Box::new(s) as Box<dyn Steps>))
    }
}

impl MeshOperation for SimplifyFaces {
    fn declaration(&self) -> &'static Declaration {
        &SIMPLIFY_FACES
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        simplify(world, mesh, &Self::params(values), context)
    }

    /// A collapse a step ([`QemSteps`]).
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let steps = QemSteps::start(world, mesh, &Self::params(values));
        Some(steps.map(|s| Box::new(s) as Box<dyn Steps>))
    }
}

impl MeshOperation for Refine {
    fn declaration(&self) -> &'static Declaration {
        &LEVEL_OF_DETAIL
    }

    /// Only the faces around the vertices each step touches are redrawn, unless the move
    /// rewrote the whole mesh (a long refine); progress is the steps taken of those the move
    /// needs (a collapse or a split changes the faces by two), every 1000 steps, and a move
    /// cannot stop half-way. Refused without a history. A refine that meets a record the mesh
    /// no longer fits stops there and is applied as far as it went (its summary says why); it
    /// is refused only if it moved nowhere.
    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let faces = values.given(0).map_or(usize::MAX, |n| n as usize);
        let progress = &mut *context.progress;
        SimplificationHistory::move_along(world, mesh, |pm, world| {
            refine_to(world, pm, faces, progress)
        })
    }
}

/// Moves `pm` (the history of the mesh in `world`) to `faces` faces, reporting to `progress`.
fn refine_to(
    world: &mut World,
    pm: &mut ProgressiveMesh,
    faces: usize,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<Applied, Refusal> {
    let before = pm.faces();
    let mut touched: Vec<FaceId> = Vec::new();
    let needed = (before.abs_diff(faces.min(pm.full_faces)) / 2).max(1);
    let mut steps = 0usize;
    let moved = pm.go_to_faces_watching(world, faces, |w, v| {
        touched.extend(MeshRef::new(w).faces_around(&[v]));
        steps += 1;
        if steps.is_multiple_of(1000) {
            progress((steps as f32 / needed as f32).min(0.99));
        }
    });
    progress(1.0);
    let now = pm.faces();
    match moved {
        Ok(moved) => Ok(Applied {
            summary: format!("{} step(s), {now} faces", moved.steps),
            redraw: if moved.rewritten {
                Redraw::Whole
            } else {
                Redraw::Near {
                    faces: touched,
                    vertices: Vec::new(),
                }
            },
            made: None,
        }),
        // A bulk refine that stopped on a refusal has still rewritten the mesh.
        Err(refusal) if now != before => {
            Ok(Applied::whole(format!("stopped at {now} faces: {refusal}")))
        }
        Err(refusal) => Err(refusal),
    }
}

/// Simplifies `mesh` as `params` say, recording the history on it.
fn simplify(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    context: &mut EditContext<'_>,
) -> Result<Applied, Refusal> {
    let (pm, s) =
        ProgressiveMesh::simplify_with_progress(world, mesh, params, &mut *context.progress)?;
    SimplificationHistory::keep(world, mesh, pm);
    let reached = if s.reached_target {
        ""
    } else {
        " (no legal collapse left before the target)"
    };
    Ok(Applied::whole(format!(
        "{} -> {} faces in {} collapses{reached}",
        s.faces_before, s.faces_after, s.collapses
    )))
}

/// Splitting back the last collapse of a simplification: it moves along the history, so the
/// history survives it, and like the simplification it drops attributes.
pub const VERTEX_SPLIT: Declaration = Declaration::new("vertex-split")
    .titled("Split vertex back")
    .described("split the vertex back as it was before the simplification's last collapse into it")
    .on_key("U")
    .naming(Names::Vertex)
    .in_section(Section::Local)
    .keeping_history()
    .dropping(DROPPED_BY_SIMPLIFICATION);

/// [`crate::ops::progressive::ProgressiveMesh::refine_vertex`] as a registered operation:
/// `vertex-split:A` after a `simplify` step, U in the editor.
pub struct VertexSplit;

impl MeshOperation for VertexSplit {
    fn declaration(&self) -> &'static Declaration {
        &VERTEX_SPLIT
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let v = values.vertex()?;
        let b =
            SimplificationHistory::move_along(world, mesh, |pm, world| pm.refine_vertex(world, v))?;
        Ok(Applied {
            summary: format!("split back {b}"),
            redraw: Redraw::Whole,
            made: Some(ElementId::Vertex(v)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_names_its_simplification_and_no_other_operation_does() {
        let ratio = Invocation::parse(&Simplify, "0.25").unwrap();
        assert_eq!(simplification(&ratio), Some(SimplifyParams::ratio(0.25)));
        let faces = Invocation::parse(&SimplifyFaces, "300").unwrap();
        assert_eq!(simplification(&faces), Some(SimplifyParams::faces(300)));
        let other = Invocation::with_defaults(&crate::ops::triangulate::Triangulate);
        assert_eq!(simplification(&other), None);
        assert_eq!(
            simplification(&Invocation::with_defaults(&Simplify)),
            Some(SimplifyParams::default())
        );
    }
}
