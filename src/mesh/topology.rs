//! Read access to a mesh in a [`World`]: navigation and bounded circulators.
//!
//! [`MeshRef`] wraps `&World`. Its navigation names are PMP's: [`MeshRef::twin`],
//! [`MeshRef::next`], [`MeshRef::prev`], [`MeshRef::to_vertex`], [`MeshRef::from_vertex`],
//! [`MeshRef::ccw_rotated`], [`MeshRef::cw_rotated`].
//!
//! Two layers of access:
//! - `try_*` lookups return `None` for a missing or stale element. Use them on ids that come from
//!   outside (a user, a file, an old selection) and in [`crate::mesh::validate()`].
//! - The plain accessors assume a valid mesh and panic, naming the element, when a link points
//!   nowhere: on a mesh that passes `validate` that is a bug in the code that last edited it.
//!
//! Circulators never spin forever: each stops after [`MAX_LOOP`] steps even if the links do not
//! close (`validate` reports such a mesh).

use super::elements::{Edge, Face, Halfedge, Position, Vertex};
use super::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use bevy::math::Vec3;
use bevy::prelude::{Component, Entity, World};

/// The most steps a circulator takes before giving up on a loop that does not close.
pub const MAX_LOOP: usize = 1 << 22;

/// Read-only view of the mesh elements in a world.
#[derive(Clone, Copy)]
pub struct MeshRef<'w> {
    world: &'w World,
}

impl<'w> MeshRef<'w> {
    /// A view of `world`.
    pub fn new(world: &'w World) -> Self {
        Self { world }
    }

    /// The world behind the view.
    pub fn world(&self) -> &'w World {
        self.world
    }

    // ---- checked lookups -------------------------------------------------------------------

    /// `e`'s component `C`, if it has one.
    #[inline]
    fn read<C: Component>(&self, e: Entity) -> Option<&'w C> {
        self.world.get::<C>(e)
    }

    /// The halfedge's links, or `None` if `h` is not a live halfedge.
    #[inline]
    pub fn try_halfedge(&self, h: HalfedgeId) -> Option<&'w Halfedge> {
        self.read::<Halfedge>(h.0)
    }

    /// The vertex's record, or `None` if `v` is not a live vertex.
    #[inline]
    pub fn try_vertex(&self, v: VertexId) -> Option<&'w Vertex> {
        self.read::<Vertex>(v.0)
    }

    /// The edge's record, or `None` if `e` is not a live edge.
    #[inline]
    pub fn try_edge(&self, e: EdgeId) -> Option<&'w Edge> {
        self.read::<Edge>(e.0)
    }

    /// The face's record, or `None` if `f` is not a live face.
    #[inline]
    pub fn try_face(&self, f: FaceId) -> Option<&'w Face> {
        self.read::<Face>(f.0)
    }

    /// Whether `x` is a live element of its kind (a mesh: a live entity).
    pub fn exists(&self, x: ElementId) -> bool {
        match x {
            ElementId::Vertex(v) => self.try_vertex(v).is_some(),
            ElementId::Halfedge(h) => self.try_halfedge(h).is_some(),
            ElementId::Edge(e) => self.try_edge(e).is_some(),
            ElementId::Face(f) => self.try_face(f).is_some(),
            ElementId::Mesh(m) => self.world.get_entity(m.0).is_ok(),
        }
    }

    /// The vertex position, or `None` if `v` has none.
    #[inline]
    pub fn try_position(&self, v: VertexId) -> Option<Vec3> {
        self.read::<Position>(v.0).map(|p| p.0)
    }

    // ---- navigation (valid mesh) ----------------------------------------------------------

    /// The halfedge's links.
    ///
    /// # Panics
    /// If `h` is not a live halfedge (a broken mesh or a stale id).
    #[inline]
    pub fn halfedge(&self, h: HalfedgeId) -> &'w Halfedge {
        match self.try_halfedge(h) {
            Some(x) => x,
            None => broken(&h),
        }
    }

    /// The opposite halfedge.
    #[inline]
    pub fn twin(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge(h).twin
    }

    /// The next halfedge around the face or boundary loop.
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge(h).next
    }

    /// The previous halfedge around the face or boundary loop.
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge(h).prev
    }

    /// The vertex `h` points to.
    #[inline]
    pub fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        self.halfedge(h).vertex
    }

    /// The vertex `h` starts from.
    #[inline]
    pub fn from_vertex(&self, h: HalfedgeId) -> VertexId {
        self.to_vertex(self.twin(h))
    }

    /// The edge `h` is a side of.
    #[inline]
    pub fn edge(&self, h: HalfedgeId) -> EdgeId {
        self.halfedge(h).edge
    }

    /// The face of `h`, `None` on the boundary.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> Option<FaceId> {
        self.halfedge(h).face
    }

    /// Whether `h` is a boundary halfedge (has no face). O(1).
    #[inline]
    pub fn is_boundary(&self, h: HalfedgeId) -> bool {
        self.halfedge(h).face.is_none()
    }

    /// The next outgoing halfedge of `from_vertex(h)`, counter-clockwise: `twin(prev(h))`.
    #[inline]
    pub fn ccw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.twin(self.prev(h))
    }

    /// The next outgoing halfedge of `from_vertex(h)`, clockwise: `next(twin(h))`.
    #[inline]
    pub fn cw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.next(self.twin(h))
    }

    /// The vertex's outgoing halfedge (the boundary one on a boundary vertex).
    ///
    /// # Panics
    /// If `v` is not a live vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        match self.try_vertex(v) {
            Some(x) => x.halfedge,
            None => broken(&v),
        }
    }

    /// The vertex position.
    ///
    /// # Panics
    /// If `v` is not a live vertex.
    #[inline]
    pub fn position(&self, v: VertexId) -> Vec3 {
        match self.try_position(v) {
            Some(p) => p,
            None => broken(&v),
        }
    }

    /// One of the edge's halfedges (an interior one if the edge has one).
    ///
    /// # Panics
    /// If `e` is not a live edge.
    #[inline]
    pub fn edge_halfedge(&self, e: EdgeId) -> HalfedgeId {
        match self.try_edge(e) {
            Some(x) => x.halfedge,
            None => broken(&e),
        }
    }

    /// A halfedge of the face.
    ///
    /// # Panics
    /// If `f` is not a live face.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        match self.try_face(f) {
            Some(x) => x.halfedge,
            None => broken(&f),
        }
    }

    /// Whether the vertex is on the boundary. O(1): a boundary vertex's halfedge is a boundary one.
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.is_boundary(self.vertex_halfedge(v))
    }

    /// Whether the edge is on the boundary (one of its halfedges has no face). O(1).
    #[inline]
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        let h = self.edge_halfedge(e);
        self.is_boundary(h) || self.is_boundary(self.twin(h))
    }

    /// The two endpoints of an edge, `(from, to)` of [`Self::edge_halfedge`].
    pub fn edge_vertices(&self, e: EdgeId) -> (VertexId, VertexId) {
        let h = self.edge_halfedge(e);
        (self.from_vertex(h), self.to_vertex(h))
    }

    /// The halfedge from `a` to `b`, if the two vertices are joined by an edge. O(valence).
    pub fn find_halfedge(&self, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
        self.vertex_outgoing(a).find(|&h| self.to_vertex(h) == b)
    }

    // ---- circulators ----------------------------------------------------------------------

    /// The halfedges around a face (or, starting from a boundary halfedge, around a boundary
    /// loop), following `next`, starting at `start`.
    pub fn loop_from(&self, start: HalfedgeId) -> LoopIter<'w> {
        LoopIter::new(*self, start, Step::Next)
    }

    /// The halfedges of a face, following `next` from the face's halfedge.
    pub fn face_halfedges(&self, f: FaceId) -> LoopIter<'w> {
        self.loop_from(self.face_halfedge(f))
    }

    /// The vertices of a face in order (each halfedge's tip).
    pub fn face_vertices(&self, f: FaceId) -> impl Iterator<Item = VertexId> + 'w {
        let m = *self;
        self.face_halfedges(f).map(move |h| m.to_vertex(h))
    }

    /// The number of sides of a face.
    pub fn face_degree(&self, f: FaceId) -> usize {
        self.face_halfedges(f).count()
    }

    /// The outgoing halfedges of a vertex, rotating counter-clockwise from its halfedge.
    pub fn vertex_outgoing(&self, v: VertexId) -> LoopIter<'w> {
        LoopIter::new(*self, self.vertex_halfedge(v), Step::CcwRotate)
    }

    /// The outgoing halfedges of `from_vertex(h)`, rotating counter-clockwise from `h`.
    pub fn vertex_outgoing_from(&self, h: HalfedgeId) -> LoopIter<'w> {
        LoopIter::new(*self, h, Step::CcwRotate)
    }

    /// The vertices joined to `v` by an edge.
    pub fn vertex_neighbors(&self, v: VertexId) -> impl Iterator<Item = VertexId> + 'w {
        let m = *self;
        self.vertex_outgoing(v).map(move |h| m.to_vertex(h))
    }

    /// The faces around `v` (boundary gaps skipped).
    pub fn vertex_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + 'w {
        let m = *self;
        self.vertex_outgoing(v).filter_map(move |h| m.face(h))
    }

    /// The faces around each of `vertices`, in order (a face beside two of them twice; dead
    /// vertices skipped): what a local change around them touched.
    pub fn faces_around(&self, vertices: &[VertexId]) -> Vec<FaceId> {
        let mut faces = Vec::new();
        for &v in vertices {
            if self.try_vertex(v).is_some() {
                faces.extend(self.vertex_faces(v));
            }
        }
        faces
    }

    /// The corners of a live element: a vertex itself, an edge's two ends, a face's corners
    /// (none if it is gone, or for a halfedge or a mesh).
    pub fn corners(&self, x: ElementId) -> Vec<VertexId> {
        match x {
            ElementId::Vertex(v) if self.try_vertex(v).is_some() => vec![v],
            ElementId::Edge(e) if self.try_edge(e).is_some() => {
                let (a, b) = self.edge_vertices(e);
                vec![a, b]
            }
            ElementId::Face(f) if self.try_face(f).is_some() => self.face_vertices(f).collect(),
            _ => Vec::new(),
        }
    }

    /// The number of edges at `v`.
    pub fn valence(&self, v: VertexId) -> usize {
        self.vertex_outgoing(v).count()
    }

    /// The centroid of a face's vertices.
    pub fn face_centroid(&self, f: FaceId) -> Vec3 {
        let (mut sum, mut n) = (Vec3::ZERO, 0.0);
        for v in self.face_vertices(f) {
            sum += self.position(v);
            n += 1.0;
        }
        sum / n
    }

    /// The sum of the vector areas of the faces around `v` ([`MeshRef::face_area_vector`]):
    /// its area-weighted normal, unnormalised (zero where the faces cancel or there are none).
    pub fn vertex_area_vector(&self, v: VertexId) -> Vec3 {
        self.vertex_faces(v).map(|f| self.face_area_vector(f)).sum()
    }

    /// The (unnormalised) vector area of a face, by Newell's method: its length is the area
    /// times two for a planar polygon, its direction the normal. Works for any polygon.
    pub fn face_area_vector(&self, f: FaceId) -> Vec3 {
        let pts: Vec<Vec3> = self.face_vertices(f).map(|v| self.position(v)).collect();
        newell_area_vector(&pts)
    }
}

/// Twice the vector area of a closed polygon (Newell's method); zero for fewer than 3 points.
pub fn newell_area_vector(points: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, &a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        n += a.cross(b);
    }
    n
}

#[cold]
#[inline(never)]
fn broken(id: &dyn std::fmt::Display) -> ! {
    panic!("mesh invariant broken: {id} is referenced but does not exist (run validate)")
}

#[derive(Clone, Copy)]
enum Step {
    Next,
    CcwRotate,
}

/// A bounded walk around a face, a boundary loop or a vertex; see [`MeshRef::loop_from`] and
/// [`MeshRef::vertex_outgoing`]. Stops when it returns to its start or after [`MAX_LOOP`] steps.
pub struct LoopIter<'w> {
    mesh: MeshRef<'w>,
    start: HalfedgeId,
    current: Option<HalfedgeId>,
    step: Step,
    taken: usize,
}

impl<'w> LoopIter<'w> {
    fn new(mesh: MeshRef<'w>, start: HalfedgeId, step: Step) -> Self {
        Self {
            mesh,
            start,
            current: Some(start),
            step,
            taken: 0,
        }
    }
}

impl Iterator for LoopIter<'_> {
    type Item = HalfedgeId;

    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        self.taken += 1;
        let following = match self.step {
            Step::Next => self.mesh.next(h),
            Step::CcwRotate => self.mesh.ccw_rotated(h),
        };
        self.current = (following != self.start && self.taken < MAX_LOOP).then_some(following);
        Some(h)
    }
}
