//! A simplification that can stop between any two collapses: the state of the loop in
//! [`super::simplify`] (quadrics, the queue of edges) kept in a value, so that the editor's
//! step mode can show the next edge, make one collapse, and go on later.
//!
//! Each step collapses on the entities, where [`super::simplify`] collapses on flat tables;
//! both start from the same quadrics and keys, order ties by entity and check and rewrite a
//! collapse alike, so stepping to the end makes the same collapses in the same order (see
//! `tests/qem_run.rs`). [`QemRun::peek`] pops and plans exactly what the next
//! [`QemRun::collapse_next`] would, and keeps the popped entry for it.
//!
//! **Moving along the history in between.** A stepped run records its collapses in a
//! [`ProgressiveMesh`](crate::ops::progressive::ProgressiveMesh), so the mesh can be moved back (vertex splits) and forward again (the
//! same collapses replayed) while the run waits. The run's tables name vertices and edges by
//! entity. A split brings back the removed vertex and the edges its collapse removed, as new
//! entities, and the replayed collapse removes exactly those again: back at the run's coarsest
//! level, every vertex and queued edge is the entity it was. [`QemRun::reattach`] checks that
//! before the run goes on, and refuses where it does not hold (the mesh was edited in between).

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use crate::mesh::ids::{EdgeId, ElementId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::indexed_heap::{IndexedHeap, slot_of};
use crate::ops::local::{
    CollapseOptions, CollapsePlan, CollapseResult, apply_collapse_deferred, plan_collapse_in,
};

use super::fidelity::DistanceCheck;
use super::fit::InputSurface;
use super::{
    FaceRows, Key, Setup, SimplifyParams, SimplifySummary, VertexTable, keyed_ends, ring_matches,
    setup,
};

/// An edge in the queue: where it would collapse to and at what cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QueuedEdge {
    /// The edge.
    pub edge: EdgeId,
    /// The cost of its collapse as queued (an `f32`): its quadric error, or with the distance
    /// check ([`super::SimplifyParams::distance_weight`]) what the check measured, if more.
    pub cost: f32,
    /// Where its ends would merge.
    pub position: Vec3,
}

/// The collapse the next step makes, planned and accepted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NextCollapse {
    /// The edge, its cost and where its ends merge.
    pub queued: QueuedEdge,
    /// The vertex that stays (and moves to the merged position).
    pub kept: VertexId,
    /// The vertex that goes.
    pub removed: VertexId,
}

/// An edge taken off the queue whose collapse was refused: it waits until a neighbouring
/// collapse queues it again.
#[derive(Clone, Debug, PartialEq)]
pub struct Refused {
    /// The edge, as queued.
    pub queued: QueuedEdge,
    /// Why (the link condition, a normal that would turn too far, …).
    pub why: Refusal,
}

/// A QEM simplification in progress (see the module doc).
pub struct QemRun {
    mesh: MeshId,
    table: VertexTable,
    heap: IndexedHeap,
    max_normal_change_deg: f32,
    faces_before: usize,
    faces: usize,
    target_faces: usize,
    collapses: usize,
    /// The entry [`QemRun::peek`] took off the queue for the next collapse.
    next: Option<Key>,
    /// Set between [`QemRun::detach`] and [`QemRun::reattach`].
    detached: bool,
    ring: Vec<(EdgeId, VertexId, Vec3)>,
    /// With a distance weight: the check ([`super::fidelity`]) and the rows it names faces by.
    check: Option<(DistanceCheck, FaceRows)>,
    /// With [`SimplifyParams::fit_to_input`]: the input, to fit the result to at the end.
    input: Option<InputSurface>,
}

impl QemRun {
    /// Reads `mesh` and queues every edge: the simplification [`super::simplify`] would run,
    /// before its first collapse.
    ///
    /// # Refusals
    /// As [`super::simplify`]: a stale mesh, a face that is not a triangle.
    pub fn start(world: &World, mesh: MeshId, params: &SimplifyParams) -> Result<Self, Refusal> {
        if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        let Setup {
            table,
            heap,
            faces_before,
            check,
            input,
        } = setup(world, mesh, params)?;
        Ok(Self {
            mesh,
            table,
            heap,
            max_normal_change_deg: params.max_normal_change_deg,
            faces_before,
            faces: faces_before,
            target_faces: params.target.faces(faces_before),
            collapses: 0,
            next: None,
            detached: false,
            ring: Vec::new(),
            check,
            input,
        })
    }

    /// Fits the mesh to the input as it was at the start ([`super::fit`]), as
    /// [`super::simplify`] does after its last collapse: meant for the run's end. `unmoved`
    /// are the vertices no collapse kept, which stay. Returns whether it fitted: not unless
    /// the run was started with [`SimplifyParams::fit_to_input`].
    pub fn fit_to_input(&self, world: &mut World, unmoved: &EntityHashSet) -> bool {
        let Some(input) = &self.input else {
            return false;
        };
        input.fit(world, self.mesh, unmoved);
        true
    }

    /// The mesh being simplified.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }

    /// Faces now, at the run's coarsest level.
    pub fn faces(&self) -> usize {
        self.faces
    }

    /// The face count the run stops at.
    pub fn target_faces(&self) -> usize {
        self.target_faces
    }

    /// Collapses made so far.
    pub fn collapses(&self) -> usize {
        self.collapses
    }

    /// Edges waiting in the queue (the one [`QemRun::peek`] took counted).
    pub fn queued(&self) -> usize {
        self.heap.len() + usize::from(self.next.is_some())
    }

    /// What the run has done so far, as [`super::simplify`] reports it.
    pub fn summary(&self) -> SimplifySummary {
        SimplifySummary {
            faces_before: self.faces_before,
            faces_after: self.faces,
            collapses: self.collapses,
            reached_target: self.faces <= self.target_faces,
        }
    }

    /// The `n` cheapest edges in the queue, cheapest first, as they are queued (the first may
    /// still be refused when its turn comes, or with the distance check queued again at a
    /// higher cost; [`QemRun::peek`] says which will not be).
    pub fn candidates(&self, n: usize) -> Vec<QueuedEdge> {
        let rest = self
            .heap
            .smallest(n.saturating_sub(usize::from(self.next.is_some())));
        self.next
            .into_iter()
            .chain(rest)
            .map(|key| self.queued_edge(key))
            .collect()
    }

    /// The collapse the next [`QemRun::collapse_next`] makes, or `None` when the run is over
    /// (the target reached, or no edge left whose collapse is allowed). Edges refused on the
    /// way leave the queue as they would in an unstepped run, each handed to `refused`; with the
    /// distance check, an edge measured farther than its key goes back in the queue at that
    /// cost, as in the unstepped run, and is not a refusal.
    ///
    /// # Panics
    /// While detached.
    pub fn peek(
        &mut self,
        world: &World,
        mut refused: impl FnMut(Refused),
    ) -> Option<NextCollapse> {
        let (key, plan) = self.plan_next(MeshRef::new(world), &mut refused)?;
        self.next = Some(key);
        Some(NextCollapse {
            queued: self.queued_edge(key),
            kept: plan.kept(),
            removed: plan.removed(),
        })
    }

    /// Makes the next collapse (the one [`QemRun::peek`] shows) and despawns what it removed.
    /// `None` when the run is over.
    ///
    /// # Panics
    /// While detached.
    pub fn collapse_next(
        &mut self,
        world: &mut World,
        mut refused: impl FnMut(Refused),
    ) -> Option<CollapseResult> {
        let mut gone = Vec::new();
        let plan = self.plan_next(MeshRef::new(world), &mut refused)?.1;
        let result = self.apply(world, plan, &mut gone);
        // A handful of elements, highest index first.
        gone.sort_unstable_by_key(|e| std::cmp::Reverse(e.index()));
        for e in gone {
            world.despawn(e);
        }
        Some(result)
    }

    /// Takes edges off the queue until one may collapse, and plans it.
    fn plan_next(
        &mut self,
        m: MeshRef<'_>,
        refused: &mut dyn FnMut(Refused),
    ) -> Option<(Key, CollapsePlan)> {
        assert!(!self.detached, "a detached run cannot collapse");
        if self.faces <= self.target_faces {
            return None;
        }
        loop {
            let key = match self.next.take() {
                Some(key) => key,
                None => self.heap.pop()?,
            };
            // Edges a collapse removes leave the queue with it, so this one is live; its
            // target still holds: both ends are as they were when the edge was last keyed.
            let queued = self.queued_edge(key);
            let options = CollapseOptions {
                position: Some(queued.position),
                max_normal_change_deg: Some(self.max_normal_change_deg),
            };
            match plan_collapse_in(m, queued.edge, options) {
                Ok(plan) => {
                    let Some((check, rows)) = &mut self.check else {
                        return Some((key, plan));
                    };
                    check.read_faces(
                        plan.reshaped_faces()
                            .map(|(face, corners)| (rows.of(face), corners)),
                    );
                    let ends = [plan.kept().slot(), plan.removed().slot()];
                    match check.review(key, ends, super::heap_key) {
                        // Farther from the input than its key says: queued again.
                        Some(key) => self.heap.set(key),
                        None => return Some((key, plan)),
                    }
                }
                Err(why) => refused(Refused { queued, why }),
            }
        }
    }

    /// Applies a planned collapse and requeues the edges around the merged vertex.
    fn apply(
        &mut self,
        world: &mut World,
        plan: CollapsePlan,
        graveyard: &mut Vec<Entity>,
    ) -> CollapseResult {
        // The edges around the merged vertex, read by the plan already.
        self.ring.clear();
        self.ring.extend(plan.merged_ring());
        let merged = (plan.kept(), plan.position());
        let (result, removed_edges) = apply_collapse_deferred(world, plan, graveyard);
        for e in removed_edges.into_iter().flatten() {
            self.heap.remove(self.table.row(e));
        }
        self.faces -= result.record.triangles_removed();
        self.collapses += 1;
        let (a, b) = (result.kept, result.removed);
        let quadric = &mut self.table.quadric;
        quadric[a.slot()] = quadric[a.slot()] + quadric[b.slot()];
        crate::checks::checked_assert!(
            ring_matches(&MeshRef::new(world), a, &self.ring),
            "the plan's ring of {a} differs from the mesh after the collapse"
        );
        if let Some((check, _)) = &mut self.check {
            check.collapsed(a.slot(), self.ring.iter().map(|(_, tip, _)| tip.slot()));
        }
        for &(e, tip, at) in &self.ring {
            let key = keyed_ends(&mut self.table, e, [merged, (tip, at)]);
            if let Some((check, _)) = &mut self.check {
                check.queued(key);
            }
            self.heap.set(key);
        }
        result
    }

    fn queued_edge(&self, key: Key) -> QueuedEdge {
        let row = slot_of(key) as usize;
        QueuedEdge {
            edge: self.table.edge[row],
            cost: f32::from_bits((key >> 32) as u32),
            position: self.table.target[row],
        }
    }

    /// Readies the run for the mesh to move along its history: the edge [`QemRun::peek`] took
    /// goes back in the queue. Until [`QemRun::reattach`], the run makes no collapse.
    pub fn detach(&mut self) {
        if let Some(key) = self.next.take() {
            self.heap.set(key);
        }
        self.detached = true;
    }

    /// Takes up the run again once the mesh is back at the run's coarsest level, where
    /// `vertices` are the vertices the run's history holds there
    /// ([`ProgressiveMesh::slots`](crate::ops::progressive::ProgressiveMesh::slots)). Nothing
    /// to do if it was not detached.
    ///
    /// # Refusals
    /// [`Refusal::HistoryMismatch`] when one of `vertices` or an edge in the queue is gone
    /// (the mesh is not at the run's coarsest level, or was edited in between); the run then
    /// stays detached.
    pub fn reattach(
        &mut self,
        world: &World,
        vertices: &[Option<VertexId>],
    ) -> Result<(), Refusal> {
        if !self.detached {
            return Ok(());
        }
        let m = MeshRef::new(world);
        let gone = vertices
            .iter()
            .flatten()
            .map(|&v| ElementId::Vertex(v))
            .chain(
                self.heap
                    .entries()
                    .iter()
                    .map(|&key| ElementId::Edge(self.table.edge[slot_of(key) as usize])),
            )
            .find(|&x| match x {
                ElementId::Vertex(v) => m.try_vertex(v).is_none(),
                ElementId::Edge(e) => m.try_edge(e).is_none(),
                _ => false,
            });
        if let Some(x) = gone {
            return Err(Refusal::HistoryMismatch(format!(
                "{x} is gone: the mesh changed outside the simplification"
            )));
        }
        self.detached = false;
        Ok(())
    }
}
