//! Isotropic remeshing stepped pass by pass ([`RemeshSteps`]).
//!
//! A step is one pass of an iteration (split, collapse, flip, relax, project; a finish after
//! the last iteration), the very pass [`super::remesh_with_progress`] makes: what the pass made
//! or moved is drawn and its count listed. A pass rewrites much of the mesh, so a remeshing
//! run does not step back; Esc puts the mesh back as it was before the run.

use bevy::prelude::World;

use super::{Pass, PassReport, RemeshParams, RemeshRun, Touched};
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::operation::Redraw;
use crate::ops::operation::stepping::{
    Ended, GoesBack, Moved, StepLine, StepList, StepShape, StepShow, Steps, TOUCHED, even_sample,
};

/// Isotropic remeshing stepped pass by pass (see the module doc).
pub struct RemeshSteps {
    run: RemeshRun,
    /// What the last pass did.
    pub last: Option<PassReport>,
    /// Each pass so far, one line each ("1 split: 5587").
    pub passes: Vec<String>,
}

impl RemeshSteps {
    /// A stepped remeshing of `mesh` as `params` say, before its first pass.
    ///
    /// # Errors
    /// The remeshing's refusal (the mesh is untouched).
    pub fn start(world: &World, mesh: MeshId, params: &RemeshParams) -> Result<Self, Refusal> {
        Ok(Self {
            run: RemeshRun::start(world, mesh, params)?,
            last: None,
            passes: Vec::new(),
        })
    }
}

impl Steps for RemeshSteps {
    fn at(&self) -> usize {
        self.run.passes_done()
    }

    fn made(&self) -> usize {
        self.run.passes_total()
    }

    fn finished(&self) -> bool {
        self.run.upcoming().is_none()
    }

    fn goes_back(&self) -> GoesBack {
        GoesBack::Never
    }

    fn go_to(
        &mut self,
        world: &mut World,
        _: MeshId,
        k: usize,
        _: Option<ElementId>,
    ) -> Result<Moved, Refusal> {
        if k < self.run.passes_done() {
            return Err(Refusal::BadParameter(
                "a remeshing run does not step back: Esc puts the mesh back as it was before it"
                    .into(),
            ));
        }
        while self.run.passes_done() < k {
            let Some(report) = self.run.next_pass(world) else {
                break;
            };
            self.passes.push(format!(
                "{} {}: {}",
                match report.pass {
                    Pass::Finish => "end".to_string(),
                    _ => (report.iteration + 1).to_string(),
                },
                report.pass.name(),
                report.count
            ));
            self.last = Some(report);
        }
        Ok(Moved::redrawing(Redraw::Whole))
    }

    fn describe(&self) -> String {
        let last = self.passes.last().map_or("", String::as_str);
        match self.run.upcoming() {
            Some((pass, i)) => format!(
                "pass {} of {}{}; next: {} (iteration {})",
                self.run.passes_done(),
                self.run.passes_total(),
                if last.is_empty() {
                    String::new()
                } else {
                    format!(", {last}")
                },
                pass.name(),
                i + 1
            ),
            None => format!("the end, {last}"),
        }
    }

    fn show(&self, world: &World, _: Option<ElementId>) -> StepShow {
        let mut shapes = Vec::new();
        if let Some(report) = &self.last {
            touched_shapes(&MeshRef::new(world), &report.touched, &mut shapes);
        }
        StepShow {
            shapes,
            lists: vec![StepList {
                title: "passes (green: what the last one touched)".into(),
                lines: self
                    .passes
                    .iter()
                    .rev()
                    .map(|line| StepLine::text(line.clone()))
                    .collect(),
            }],
            histograms: !self.passes.is_empty(),
            ..StepShow::default()
        }
    }

    fn finish(self: Box<Self>, _: &mut World, _: MeshId) -> Ended {
        let s = self.run.summary();
        Ended::with(format!(
            "L {:.5}: {} splits, {} collapses, {} flips (stepped; {} of {} passes)",
            s.target_length,
            s.splits,
            s.collapses,
            s.flips,
            self.run.passes_done(),
            self.run.passes_total()
        ))
    }
}

/// What a remeshing pass touched: its edges as thick lines, its vertices as dots, at most
/// [`crate::ops::operation::stepping::MAX_DRAWN`] of each (an even sample above that).
fn touched_shapes(m: &MeshRef<'_>, touched: &Touched, out: &mut Vec<StepShape>) {
    for i in even_sample(touched.edges.len()) {
        let e = touched.edges[i];
        if m.try_edge(e).is_some() {
            let (a, b) = m.edge_vertices(e);
            out.push(StepShape::Highlight(m.position(a), m.position(b), TOUCHED));
        }
    }
    for i in even_sample(touched.vertices.len()) {
        let v = touched.vertices[i];
        if m.try_vertex(v).is_some() {
            let p = m.position(v);
            let r = m
                .vertex_neighbors(v)
                .map(|w| m.position(w).distance(p))
                .fold(f32::INFINITY, f32::min);
            out.push(StepShape::Dot(p, 0.15 * r.min(1.0e3), TOUCHED));
        }
    }
}
