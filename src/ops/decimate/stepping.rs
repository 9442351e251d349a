//! QEM simplification stepped collapse by collapse ([`QemSteps`]).
//!
//! A step is one edge collapse, the queue's cheapest that is allowed: the next edge is drawn
//! with the point its ends merge at, the window lists the queue's cheapest edges and the
//! collapses the queue refused on the way, with why. Moving back splits collapses back
//! through the run's [`ProgressiveMesh`] (the history the level-of-detail slider moves along),
//! and forward again replays them before the run makes new ones; a slider scrubs along them.
//! A selected element a new collapse removes is replaced by what it became (the vertex an
//! edge collapsed into, the edge a wing merged into).

use bevy::prelude::World;

use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::IdsKept;
use crate::ops::operation::Redraw;
use crate::ops::operation::stepping::{
    Ended, GoesBack, Moved, NEXT, QUEUED, StepLine, StepList, StepShape, StepShow, Steps,
};
use crate::ops::progressive::{ProgressiveMesh, SlotIndex};
use crate::ops::simplification_history::SimplificationHistory;
use crate::ops::simplify::{NextCollapse, QemRun, QueuedEdge, Refused, SimplifyParams};

/// How many refusals the window keeps (the latest).
const REFUSALS_KEPT: usize = 8;
/// How many of the queue's cheapest edges are drawn and listed.
pub const CANDIDATES: usize = 10;

/// A QEM simplification stepped collapse by collapse (see the module doc).
pub struct QemSteps {
    run: QemRun,
    /// Every collapse made so far, and where along them the mesh is.
    pub history: ProgressiveMesh,
    index: SlotIndex,
    /// The collapse the next step makes (at the run's front; `None` at its end).
    pub next: Option<NextCollapse>,
    /// The latest edges the queue refused, newest last.
    pub refused: Vec<Refused>,
}

impl QemSteps {
    /// A stepped simplification of `mesh` as `params` say, looking at its first collapse.
    ///
    /// # Errors
    /// The simplification's refusal (the mesh is untouched).
    pub fn start(world: &World, mesh: MeshId, params: &SimplifyParams) -> Result<Self, Refusal> {
        let run = QemRun::start(world, mesh, params)?;
        let history = ProgressiveMesh::start(world, mesh, run.faces());
        let index = SlotIndex::of(&history);
        let mut steps = QemSteps {
            run,
            history,
            index,
            next: None,
            refused: Vec::new(),
        };
        steps.look_ahead(world);
        Ok(steps)
    }

    /// Whether the mesh is at the run's front (where new collapses are made).
    pub fn at_front(&self) -> bool {
        self.at() == self.made()
    }

    /// Faces at the step the mesh is at.
    pub fn faces(&self) -> usize {
        self.faces_at(self.at())
    }

    /// The `n` cheapest edges waiting, cheapest first.
    pub fn candidates(&self, n: usize) -> Vec<QueuedEdge> {
        self.run.candidates(n)
    }

    /// Faces at step `k` (each collapse removes at least one, so this is one-to-one).
    fn faces_at(&self, k: usize) -> usize {
        self.history.full_faces
            - self.history.records[..k]
                .iter()
                .map(|r| r.faces)
                .sum::<usize>()
    }

    fn look_ahead(&mut self, world: &World) {
        let refused = &mut self.refused;
        self.next = self.run.peek(world, |r| refused.push(r));
        let extra = refused.len().saturating_sub(REFUSALS_KEPT);
        refused.drain(..extra);
    }

    /// Back or forward along the collapses made, to step `k` (at most the front).
    fn go_along(&mut self, world: &mut World, k: usize) -> Result<Redraw, Refusal> {
        if self.at_front() {
            self.run.detach();
            self.next = None;
        }
        let faces = self.faces_at(k.min(self.made()));
        let mut touched = Vec::new();
        let moved = self.history.go_to_faces_watching(world, faces, |w, v| {
            touched.extend(MeshRef::new(w).vertex_faces(v));
        })?;
        Ok(match moved.rewritten {
            true => Redraw::Whole,
            false => Redraw::Near {
                faces: touched,
                vertices: Vec::new(),
            },
        })
    }

    /// New collapses from the front up to step `k`, following `selected`.
    fn collapse_to(
        &mut self,
        world: &mut World,
        k: usize,
        mut selected: Option<ElementId>,
    ) -> (Vec<FaceId>, Option<(ElementId, String)>) {
        let mut dirty = Vec::new();
        let mut became = None;
        while self.at() < k {
            // Faces around both ends: the kept vertex's faces after the collapse are among them.
            let Some(next) = self.next.or_else(|| {
                self.look_ahead(world);
                self.next
            }) else {
                break;
            };
            let m = MeshRef::new(world);
            dirty.extend(m.vertex_faces(next.kept));
            dirty.extend(m.vertex_faces(next.removed));
            let before = selected.map(|x| ends_of(&m, x));
            let refused = &mut self.refused;
            let Some(result) = self.run.collapse_next(world, |r| refused.push(r)) else {
                break;
            };
            self.history.push(world, &self.index, &result);
            self.next = None;
            if let (Some(x), Some(ends)) = (selected, before)
                && !MeshRef::new(world).exists(x)
            {
                let fate = fate(world, x, ends, result.kept, result.removed);
                selected = Some(fate.0);
                became = Some(fate);
            }
        }
        self.look_ahead(world);
        (dirty, became)
    }
}

impl Steps for QemSteps {
    fn at(&self) -> usize {
        self.history.applied
    }

    fn made(&self) -> usize {
        self.history.records.len()
    }

    fn finished(&self) -> bool {
        self.at_front() && self.next.is_none()
    }

    fn goes_back(&self) -> GoesBack {
        GoesBack::Scrubs
    }

    fn go_to(
        &mut self,
        world: &mut World,
        _: MeshId,
        k: usize,
        selected: Option<ElementId>,
    ) -> Result<Moved, Refusal> {
        let mut redraw = None;
        if k < self.made() || !self.at_front() {
            redraw = Some(self.go_along(world, k)?);
        }
        if k <= self.made() {
            if self.at_front() {
                self.run.reattach(world, self.history.slots())?;
                self.look_ahead(world);
            }
            return Ok(Moved {
                redraw,
                ids: IdsKept::All,
                became: None,
            });
        }
        self.run.reattach(world, self.history.slots())?;
        let (dirty, became) = self.collapse_to(world, k, selected);
        let redraw = match redraw {
            Some(Redraw::Whole) => Redraw::Whole,
            Some(Redraw::Near { mut faces, .. }) => {
                faces.extend(dirty);
                Redraw::Near {
                    faces,
                    vertices: Vec::new(),
                }
            }
            _ => Redraw::Near {
                faces: dirty,
                vertices: Vec::new(),
            },
        };
        Ok(Moved {
            redraw: Some(redraw),
            ids: IdsKept::All,
            became,
        })
    }

    fn describe(&self) -> String {
        match (&self.next, self.at_front()) {
            (Some(next), true) => format!(
                "step {}: {} faces, target {}; next {} (cost {:.3e})",
                self.at(),
                self.faces(),
                self.run.target_faces(),
                next.queued.edge,
                next.queued.cost
            ),
            (None, true) => format!(
                "step {}: {} faces, the end ({})",
                self.at(),
                self.faces(),
                match self.run.summary().reached_target {
                    true => "target reached",
                    false => "no collapse left that is allowed",
                }
            ),
            (_, false) => format!(
                "step {} of {}: {} faces",
                self.at(),
                self.made(),
                self.faces()
            ),
        }
    }

    fn show(&self, world: &World, _: Option<ElementId>) -> StepShow {
        let mut show = StepShow::default();
        if self.at_front() {
            let m = MeshRef::new(world);
            let queue = self.candidates(CANDIDATES);
            for queued in queue.iter().skip(1) {
                if m.try_edge(queued.edge).is_some() {
                    let (a, b) = m.edge_vertices(queued.edge);
                    show.shapes
                        .push(StepShape::Highlight(m.position(a), m.position(b), QUEUED));
                }
            }
            if let Some(next) = &self.next {
                let (a, b) = (m.position(next.kept), m.position(next.removed));
                let at = next.queued.position;
                show.shapes.extend([
                    StepShape::Highlight(a, b, NEXT),
                    StepShape::Line(a, at, NEXT),
                    StepShape::Line(b, at, NEXT),
                    StepShape::HighlightDot(at, a.distance(b) * 0.15, NEXT),
                ]);
                show.label = Some((
                    at,
                    format!("{}  cost {:.3e}", next.queued.edge, next.queued.cost),
                ));
            }
            show.lists.push(StepList {
                title: "queue, cheapest first (click selects)".into(),
                lines: queue
                    .iter()
                    .map(|q| StepLine {
                        element: Some(ElementId::Edge(q.edge)),
                        text: format!("{:.3e}", q.cost),
                    })
                    .collect(),
            });
        }
        show.lists.push(StepList {
            title: "refused on the way (newest first)".into(),
            lines: self
                .refused
                .iter()
                .rev()
                .map(|r| {
                    StepLine::text(format!(
                        "{} ({:.2e}): {}",
                        r.queued.edge, r.queued.cost, r.why
                    ))
                })
                .collect(),
        });
        show
    }

    fn focus(&self) -> Vec<VertexId> {
        match (self.at_front(), &self.next) {
            (true, Some(next)) => vec![next.kept, next.removed],
            _ => Vec::new(),
        }
    }

    /// Leaves the run's history on the mesh, for the level-of-detail slider, as the unstepped
    /// simplification does; at the run's end, fits the mesh to the input first when asked
    /// ([`SimplifyParams::fit_to_input`]), as the unstepped one does.
    fn finish(mut self: Box<Self>, world: &mut World, mesh: MeshId) -> Ended {
        let s = self.run.summary();
        if self.finished() && self.run.fit_to_input(world, &self.history.never_kept()) {
            self.history.settle_coarsest(world);
        }
        self.run.detach();
        let summary = format!(
            "{} -> {} faces in {} collapses (stepped; kept at step {})",
            s.faces_before,
            self.faces(),
            self.made(),
            self.at()
        );
        SimplificationHistory::keep(world, mesh, self.history);
        Ended::with(summary)
    }
}

/// The vertices an element touches, read before a step.
fn ends_of(m: &MeshRef<'_>, x: ElementId) -> Vec<VertexId> {
    match x {
        ElementId::Vertex(v) => vec![v],
        ElementId::Edge(e) if m.try_edge(e).is_some() => {
            let (a, b) = m.edge_vertices(e);
            vec![a, b]
        }
        ElementId::Halfedge(h) if m.try_halfedge(h).is_some() => {
            vec![m.from_vertex(h), m.to_vertex(h)]
        }
        ElementId::Face(f) if m.try_face(f).is_some() => m.face_vertices(f).collect(),
        _ => Vec::new(),
    }
}

/// What the selected element `x` became when the collapse of `removed` into `kept` removed
/// it, and the line that says so.
fn fate(
    world: &World,
    x: ElementId,
    ends: Vec<VertexId>,
    kept: VertexId,
    removed: VertexId,
) -> (ElementId, String) {
    let m = MeshRef::new(world);
    // An edge or halfedge beside the collapsed one merged into the edge from the kept vertex
    // to the same third vertex.
    let third = ends
        .iter()
        .copied()
        .find(|&v| v != kept && v != removed && m.try_vertex(v).is_some());
    let became = match (x, third) {
        (ElementId::Edge(_) | ElementId::Halfedge(_), Some(w)) if ends.len() == 2 => m
            .find_halfedge(kept, w)
            .map(|h| ElementId::Edge(m.edge(h)))
            .unwrap_or(ElementId::Vertex(kept)),
        _ => ElementId::Vertex(kept),
    };
    let how = match x {
        ElementId::Vertex(_) => "collapsed into",
        ElementId::Face(_) => "collapsed to",
        _ => "merged into",
    };
    (became, format!("{x} is gone: {how} {became}"))
}
