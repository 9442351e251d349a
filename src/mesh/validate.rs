//! Every invariant of a halfedge mesh, checked; the first broken one is named with its element.
//!
//! Rules, in the order they are checked (Scotty3D's and Dandelion's lists, plus what they miss):
//!
//! - vertices: a finite position; an outgoing halfedge that starts at the vertex; rotating
//!   around it (`twin(prev(h))`) closes and meets *every* halfedge leaving it (one fan: a
//!   manifold vertex); at most one boundary halfedge leaves it, and if one does it is the
//!   vertex's halfedge (so `is_boundary` is O(1)); no two of its edges lead to the same
//!   neighbour (no duplicate edges).
//! - halfedges: every link names a live element of the right kind in the same mesh; `twin` is
//!   another halfedge whose twin is this one, on the same edge; `next(prev(h)) == h` and
//!   `prev(next(h)) == h`; `next` stays in the same face (or boundary loop); `prev` ends where
//!   this one starts.
//! - edges: its halfedge is on it; exactly two halfedges are on it; at least one has a face.
//! - faces: its halfedge is on it; the `next` loop closes, has at least 3 sides, visits no
//!   vertex twice, and is every halfedge of the face.
//! - boundary loops close and have at least 3 sides.
//!
//! [`validate`] never panics and never loops forever, whatever the links say.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::prelude::{Entity, World};
use std::fmt;

use super::elements::InMesh;
use super::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use super::members::MeshMembers;
use super::topology::MeshRef;

/// A broken invariant: which rule, and the first element found breaking it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{element}: {rule}")]
pub struct Invalid {
    /// The offending element.
    pub element: ElementId,
    /// The rule it breaks.
    pub rule: Rule,
}

/// The invariants [`validate`] checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// A vertex position is NaN or infinite, or missing.
    NonFinitePosition,
    /// A link names an element that does not exist, is of another kind, or is in another mesh.
    DanglingLink(&'static str),
    /// `twin(h) == h` or `twin(twin(h)) != h`.
    TwinNotMutual,
    /// A halfedge and its twin are on different edges.
    TwinEdgeDiffers,
    /// `next(prev(h)) != h` or `prev(next(h)) != h`.
    NextPrevDisagree,
    /// `next(h)` is in another face (or boundary loop).
    NextLeavesFace,
    /// `prev(h)` does not end where `h` starts.
    PrevEndsElsewhere,
    /// An edge's halfedge is not on that edge.
    EdgeHalfedgeElsewhere,
    /// An edge has other than two halfedges on it.
    EdgeNotTwoHalfedges,
    /// Neither side of an edge has a face.
    EdgeWithoutFace,
    /// A face's halfedge is not in that face.
    FaceHalfedgeElsewhere,
    /// A face's `next` loop does not close.
    FaceLoopOpen,
    /// A face has fewer than 3 sides.
    FaceTooSmall,
    /// A face visits a vertex twice.
    FaceNotSimple,
    /// A halfedge names a face whose loop does not contain it.
    FaceLoopIncomplete,
    /// A vertex's halfedge does not start at the vertex.
    VertexHalfedgeElsewhere,
    /// Rotating around a vertex does not close, or leaves the vertex.
    VertexFanOpen,
    /// The rotation around a vertex misses some of its halfedges: several fans (non-manifold).
    NonManifoldVertex,
    /// More than one boundary halfedge leaves a vertex.
    PinchedBoundary,
    /// A boundary vertex's halfedge is not its boundary halfedge.
    BoundaryVertexHalfedge,
    /// Two edges join the same two vertices.
    DuplicateEdge,
    /// A boundary loop does not close or has fewer than 3 sides.
    BoundaryLoopBroken,
    /// The mesh has no faces.
    Empty,
}

impl fmt::Display for Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match self {
            Self::NonFinitePosition => "position is missing, NaN or infinite",
            Self::DanglingLink(link) => {
                return write!(f, "link `{link}` names no live element of this mesh");
            }
            Self::TwinNotMutual => "twin is not mutual (twin(twin(h)) != h, or twin(h) == h)",
            Self::TwinEdgeDiffers => "halfedge and twin are on different edges",
            Self::NextPrevDisagree => {
                "next and prev disagree (next(prev(h)) != h or prev(next(h)) != h)"
            }
            Self::NextLeavesFace => "next(h) is in a different face",
            Self::PrevEndsElsewhere => "prev(h) does not end where h starts",
            Self::EdgeHalfedgeElsewhere => "the edge's halfedge is not on this edge",
            Self::EdgeNotTwoHalfedges => "edge does not have exactly two halfedges",
            Self::EdgeWithoutFace => "edge has no face on either side",
            Self::FaceHalfedgeElsewhere => "the face's halfedge is not in this face",
            Self::FaceLoopOpen => "face loop does not close",
            Self::FaceTooSmall => "face has fewer than 3 sides",
            Self::FaceNotSimple => "face visits a vertex twice",
            Self::FaceLoopIncomplete => "halfedges name this face but are not in its loop",
            Self::VertexHalfedgeElsewhere => "the vertex's halfedge does not start at it",
            Self::VertexFanOpen => "rotation around the vertex does not close",
            Self::NonManifoldVertex => "non-manifold vertex: its faces form more than one fan",
            Self::PinchedBoundary => "more than one boundary halfedge leaves the vertex",
            Self::BoundaryVertexHalfedge => {
                "boundary vertex's halfedge is not its boundary halfedge"
            }
            Self::DuplicateEdge => "two edges join the same two vertices",
            Self::BoundaryLoopBroken => "boundary loop does not close or has fewer than 3 sides",
            Self::Empty => "mesh has no faces",
        };
        f.write_str(text)
    }
}

/// Checks every invariant of `mesh` (see the module doc).
///
/// # Errors
/// The first broken rule, with the element that breaks it.
pub fn validate(world: &World, mesh: MeshId) -> Result<(), Invalid> {
    validate_without(world, mesh, &EntityHashSet::default())
}

/// Checks every invariant of `mesh` as though the elements `removed` were gone: they are not
/// checked, and a link naming one is dangling (what a [`super::RawEdit`] commit checks before
/// it despawns them).
///
/// # Errors
/// The first broken rule, with the element that breaks it.
pub fn validate_without(
    world: &World,
    mesh: MeshId,
    removed: &EntityHashSet,
) -> Result<(), Invalid> {
    let mut members = MeshMembers::collect(world, mesh);
    if !removed.is_empty() {
        members.vertices.retain(|v| !removed.contains(&v.0));
        members.halfedges.retain(|h| !removed.contains(&h.0));
        members.edges.retain(|e| !removed.contains(&e.0));
        members.faces.retain(|f| !removed.contains(&f.0));
    }
    Checker::new(world, mesh, removed, members.halfedges.len() + 1).run(&members)
}

/// The rules, element by element: the whole check ([`validate`]) runs them on every element
/// with counts taken over the mesh; an edit's check (`super::validate_edit`) on the elements
/// it touched, with counts kept by difference.
pub(super) struct Checker<'w> {
    m: MeshRef<'w>,
    world: &'w World,
    mesh: MeshId,
    /// Elements to take as gone.
    removed: &'w EntityHashSet,
    /// No loop in this mesh can be longer than its halfedge count.
    limit: usize,
}

pub(super) fn fail<T>(element: impl Into<ElementId>, rule: Rule) -> Result<T, Invalid> {
    Err(Invalid {
        element: element.into(),
        rule,
    })
}

impl<'w> Checker<'w> {
    /// A checker of `mesh` that takes `removed` as gone and walks no loop longer than `limit`.
    pub(super) fn new(
        world: &'w World,
        mesh: MeshId,
        removed: &'w EntityHashSet,
        limit: usize,
    ) -> Self {
        Checker {
            m: MeshRef::new(world),
            world,
            mesh,
            removed,
            limit,
        }
    }

    fn run(&self, members: &MeshMembers) -> Result<(), Invalid> {
        if members.faces.is_empty() {
            return fail(self.mesh, Rule::Empty);
        }
        for &h in &members.halfedges {
            self.check_links(h)?;
        }
        for &h in &members.halfedges {
            self.check_halfedge(h)?;
        }
        self.check_edges(members)?;
        self.check_faces(members)?;
        self.check_vertices(members)?;
        self.check_boundary_loops(members)
    }

    fn in_mesh(&self, e: Entity) -> bool {
        self.world
            .get::<InMesh>(e)
            .is_some_and(|m| m.0 == self.mesh)
            && !self.removed.contains(&e)
    }

    pub(super) fn check_links(&self, h: HalfedgeId) -> Result<(), Invalid> {
        let Some(x) = self.m.try_halfedge(h) else {
            return fail(h, Rule::DanglingLink("self"));
        };
        let halfedge_ok = |t: HalfedgeId| self.m.try_halfedge(t).is_some() && self.in_mesh(t.0);
        for (name, t) in [("twin", x.twin), ("next", x.next), ("prev", x.prev)] {
            if !halfedge_ok(t) {
                return fail(h, Rule::DanglingLink(name));
            }
        }
        if self.m.try_vertex(x.vertex).is_none() || !self.in_mesh(x.vertex.0) {
            return fail(h, Rule::DanglingLink("vertex"));
        }
        if self.m.try_edge(x.edge).is_none() || !self.in_mesh(x.edge.0) {
            return fail(h, Rule::DanglingLink("edge"));
        }
        if let Some(f) = x.face
            && (self.m.try_face(f).is_none() || !self.in_mesh(f.0))
        {
            return fail(h, Rule::DanglingLink("face"));
        }
        Ok(())
    }

    /// Local halfedge rules; all links are known to be live.
    pub(super) fn check_halfedge(&self, h: HalfedgeId) -> Result<(), Invalid> {
        let m = &self.m;
        let x = m.halfedge(h);
        if x.twin == h || m.twin(x.twin) != h {
            return fail(h, Rule::TwinNotMutual);
        }
        if m.edge(x.twin) != x.edge {
            return fail(h, Rule::TwinEdgeDiffers);
        }
        if m.next(x.prev) != h || m.prev(x.next) != h {
            return fail(h, Rule::NextPrevDisagree);
        }
        if m.face(x.next) != x.face {
            return fail(h, Rule::NextLeavesFace);
        }
        if m.to_vertex(x.prev) != m.to_vertex(x.twin) {
            return fail(h, Rule::PrevEndsElsewhere);
        }
        Ok(())
    }

    fn check_edges(&self, members: &MeshMembers) -> Result<(), Invalid> {
        let mut on_edge: EntityHashMap<u32> = EntityHashMap::default();
        for &h in &members.halfedges {
            *on_edge.entry(self.m.edge(h).0).or_default() += 1;
        }
        for &e in &members.edges {
            self.check_edge(e, on_edge.get(&e.0).copied().unwrap_or(0))?;
        }
        if on_edge.len() != members.edges.len() {
            // Some halfedge names an edge that is not listed in this mesh: caught by
            // check_links already, so this is unreachable on a checked mesh.
            let h = members.halfedges[0];
            return fail(h, Rule::DanglingLink("edge"));
        }
        Ok(())
    }

    /// Edge `e`'s rules, `on` halfedges naming it.
    pub(super) fn check_edge(&self, e: EdgeId, on: u32) -> Result<(), Invalid> {
        let Some(x) = self.m.try_edge(e) else {
            return fail(e, Rule::DanglingLink("self"));
        };
        if self.m.try_halfedge(x.halfedge).is_none() || !self.in_mesh(x.halfedge.0) {
            return fail(e, Rule::DanglingLink("halfedge"));
        }
        if self.m.edge(x.halfedge) != e {
            return fail(e, Rule::EdgeHalfedgeElsewhere);
        }
        if on != 2 {
            return fail(e, Rule::EdgeNotTwoHalfedges);
        }
        if self.m.is_boundary(x.halfedge) && self.m.is_boundary(self.m.twin(x.halfedge)) {
            return fail(e, Rule::EdgeWithoutFace);
        }
        Ok(())
    }

    fn check_faces(&self, members: &MeshMembers) -> Result<(), Invalid> {
        let mut claimed: EntityHashMap<u32> = EntityHashMap::default();
        for &h in &members.halfedges {
            if let Some(f) = self.m.face(h) {
                *claimed.entry(f.0).or_default() += 1;
            }
        }
        let mut seen = Vec::new();
        for &f in &members.faces {
            self.check_face(f, claimed.get(&f.0).copied().unwrap_or(0), &mut seen)?;
        }
        Ok(())
    }

    /// Face `f`'s rules, `claimed` halfedges naming it; `seen` is scratch space.
    pub(super) fn check_face(
        &self,
        f: FaceId,
        claimed: u32,
        seen: &mut Vec<VertexId>,
    ) -> Result<(), Invalid> {
        let Some(x) = self.m.try_face(f) else {
            return fail(f, Rule::DanglingLink("self"));
        };
        if self.m.try_halfedge(x.halfedge).is_none() || !self.in_mesh(x.halfedge.0) {
            return fail(f, Rule::DanglingLink("halfedge"));
        }
        if self.m.face(x.halfedge) != Some(f) {
            return fail(f, Rule::FaceHalfedgeElsewhere);
        }
        seen.clear();
        let mut h = x.halfedge;
        loop {
            seen.push(self.m.to_vertex(h));
            h = self.m.next(h);
            if h == x.halfedge {
                break;
            }
            if seen.len() > self.limit {
                return fail(f, Rule::FaceLoopOpen);
            }
        }
        if seen.len() < 3 {
            return fail(f, Rule::FaceTooSmall);
        }
        if claimed != seen.len() as u32 {
            return fail(f, Rule::FaceLoopIncomplete);
        }
        seen.sort_unstable();
        if seen.windows(2).any(|w| w[0] == w[1]) {
            return fail(f, Rule::FaceNotSimple);
        }
        Ok(())
    }

    fn check_vertices(&self, members: &MeshMembers) -> Result<(), Invalid> {
        let mut leaving: EntityHashMap<u32> = EntityHashMap::default();
        for &h in &members.halfedges {
            *leaving.entry(self.m.from_vertex(h).0).or_default() += 1;
        }
        let mut neighbours = Vec::new();
        for &v in &members.vertices {
            self.check_vertex(v, leaving.get(&v.0).copied().unwrap_or(0), &mut neighbours)?;
        }
        Ok(())
    }

    /// Vertex `v`'s rules, `leaving` halfedges starting at it; `neighbours` is scratch space.
    pub(super) fn check_vertex(
        &self,
        v: VertexId,
        leaving: u32,
        neighbours: &mut Vec<VertexId>,
    ) -> Result<(), Invalid> {
        match self.m.try_position(v) {
            Some(p) if p.is_finite() => {}
            _ => return fail(v, Rule::NonFinitePosition),
        }
        let Some(x) = self.m.try_vertex(v) else {
            return fail(v, Rule::DanglingLink("self"));
        };
        if self.m.try_halfedge(x.halfedge).is_none() || !self.in_mesh(x.halfedge.0) {
            return fail(v, Rule::DanglingLink("halfedge"));
        }
        if self.m.from_vertex(x.halfedge) != v {
            return fail(v, Rule::VertexHalfedgeElsewhere);
        }
        neighbours.clear();
        let mut boundary = 0;
        let mut h = x.halfedge;
        loop {
            if self.m.from_vertex(h) != v {
                return fail(v, Rule::VertexFanOpen);
            }
            boundary += usize::from(self.m.is_boundary(h));
            neighbours.push(self.m.to_vertex(h));
            h = self.m.ccw_rotated(h);
            if h == x.halfedge {
                break;
            }
            if neighbours.len() > self.limit {
                return fail(v, Rule::VertexFanOpen);
            }
        }
        if leaving != neighbours.len() as u32 {
            return fail(v, Rule::NonManifoldVertex);
        }
        if boundary > 1 {
            return fail(v, Rule::PinchedBoundary);
        }
        if boundary == 1 && !self.m.is_boundary(x.halfedge) {
            return fail(v, Rule::BoundaryVertexHalfedge);
        }
        neighbours.sort_unstable();
        if neighbours.windows(2).any(|w| w[0] == w[1]) {
            return fail(v, Rule::DuplicateEdge);
        }
        Ok(())
    }

    fn check_boundary_loops(&self, members: &MeshMembers) -> Result<(), Invalid> {
        let mut visited = EntityHashSet::default();
        for &start in &members.halfedges {
            if self.m.is_boundary(start) && !visited.contains(&start.0) {
                self.check_boundary_loop(start, &mut visited)?;
            }
        }
        Ok(())
    }

    /// The boundary loop through `start` closes and has at least 3 sides; its halfedges join
    /// `visited`.
    pub(super) fn check_boundary_loop(
        &self,
        start: HalfedgeId,
        visited: &mut EntityHashSet,
    ) -> Result<(), Invalid> {
        let mut h = start;
        let mut len = 0;
        loop {
            visited.insert(h.0);
            len += 1;
            h = self.m.next(h);
            if h == start {
                break;
            }
            if len > self.limit {
                return fail(start, Rule::BoundaryLoopBroken);
            }
        }
        if len < 3 {
            return fail(start, Rule::BoundaryLoopBroken);
        }
        Ok(())
    }
}
