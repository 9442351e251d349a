//! The tables themselves ([`Connectivity`]): how they are laid out from face corners, how to
//! walk them, and how to edit and grow them row by row.
//!
//! The storage is one `Vec` per link, of plain `u32` rows with [`NONE`] for "no row" (see the
//! module doc of [`super`]). Those columns are public: the code that fills whole tables at once
//! ([`super::extract`], [`Connectivity::from_corners`], the writers in [`super::write`]) and
//! the readers not yet moved to typed rows index them directly. Everything else walks the
//! tables through the accessors here, which take and return typed rows ([`VertexRow`],
//! [`HalfedgeRow`], [`EdgeRow`], [`FaceRow`]) and carry PMP's / geometry-central's names:
//! `twin`, `next`, `prev`, `to_vertex`, `from_vertex`, `edge`, `face`, `vertex_halfedge`,
//! `ccw_rotated`, `face_halfedges`, `vertex_outgoing`, … Every accessor is `#[inline]` and one
//! table read, so walking the tables this way costs what indexing them by hand did.
//!
//! Guarantees: tables laid out by [`Connectivity::from_corners`] are consistent (see
//! [`super`]); the setters and `push_*` calls write exactly the entries they name and nothing
//! else, so a caller that rewires the tables keeps them consistent itself
//! ([`crate::ops::table_split`] does). The circulators stop after [`MAX_LOOP`] steps even if
//! the links do not close, like every circulator on entities.

use bevy::math::Vec3;

use super::rows::{EdgeRow, FaceRow, HalfedgeRow, NONE, RowCounts, VertexRow};
use crate::mesh::attributes::AttributeColumns;
use crate::mesh::topology::{MAX_LOOP, newell_area_vector};

/// Halfedge connectivity as flat tables, one row per element, with the positions.
///
/// The columns are indexed by the row of their kind and hold rows of the kind they point to;
/// read them through the typed accessors ([`Connectivity::twin`], …) unless filling them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Connectivity {
    /// Vertex positions, by vertex row.
    pub positions: Vec<Vec3>,
    /// Each vertex's outgoing halfedge (the boundary one on the boundary), by vertex row.
    pub vertex_halfedge: Vec<u32>,
    /// Each halfedge's twin, by halfedge row.
    pub twin: Vec<u32>,
    /// Each halfedge's next, by halfedge row.
    pub next: Vec<u32>,
    /// Each halfedge's prev, by halfedge row.
    pub prev: Vec<u32>,
    /// Each halfedge's tip vertex, by halfedge row.
    pub to_vertex: Vec<u32>,
    /// Each halfedge's edge, by halfedge row.
    pub edge: Vec<u32>,
    /// Each halfedge's face, or [`NONE`] on the boundary, by halfedge row.
    pub face: Vec<u32>,
    /// Each edge's halfedge, by edge row.
    pub edge_halfedge: Vec<u32>,
    /// Each face's first halfedge, by face row.
    pub face_halfedge: Vec<u32>,
    /// The attribute columns (corner UVs by halfedge row, normals and colours by vertex row),
    /// where the mesh has them: carried by `extract` and the writers; tables an operation lays
    /// out afresh have none unless it fills them (see [`crate::mesh::attributes`]).
    pub attributes: AttributeColumns,
}

/// Faces given by their corners, each corner paired with its twin: what
/// [`Connectivity::from_corners`] lays out (the repaired faces of a loaded soup, or the faces a
/// subdivision step computes).
///
/// Corner `c` stands for the halfedge from `indices[c]` to the next corner's vertex.
#[derive(Clone, Copy, Debug)]
pub struct FaceCorners<'a> {
    /// Vertex positions (every vertex used by a face).
    pub positions: &'a [Vec3],
    /// Face corners, flat: each a vertex row.
    pub indices: &'a [u32],
    /// `face_starts[f]..face_starts[f + 1]` are face `f`'s corners.
    pub face_starts: &'a [u32],
    /// The corner running the other way along the same edge, or [`NONE`] on the boundary.
    pub twin: &'a [u32],
}

impl FaceCorners<'_> {
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_starts.len().saturating_sub(1)
    }
}

/// Every link of one new halfedge ([`Connectivity::push_halfedge`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HalfedgeLinks {
    /// Its twin.
    pub twin: HalfedgeRow,
    /// Its next.
    pub next: HalfedgeRow,
    /// Its prev.
    pub prev: HalfedgeRow,
    /// Its tip vertex.
    pub to_vertex: VertexRow,
    /// Its edge.
    pub edge: EdgeRow,
    /// Its face, `None` on the boundary.
    pub face: Option<FaceRow>,
}

impl Connectivity {
    /// Lays out the tables of `faces`: halfedges `0..corners` are the corners in face order,
    /// boundary halfedges are added after them and linked into loops, edges numbered in the
    /// order of their first halfedge. Every boundary vertex's halfedge is its outgoing boundary
    /// halfedge; each edge's halfedge is an interior one.
    ///
    /// `faces` must be manifold and consistently oriented, every vertex used and a single fan
    /// (what [`crate::mesh::repair::repair`] guarantees).
    pub fn from_corners(faces: FaceCorners<'_>) -> Self {
        let nv = faces.positions.len();
        let nf = faces.face_count();
        let interior = faces.indices.len();
        let boundary = faces.twin.iter().filter(|&&t| t == NONE).count();
        let nh = interior + boundary;

        let mut c = Connectivity {
            positions: faces.positions.to_vec(),
            vertex_halfedge: vec![NONE; nv],
            twin: Vec::with_capacity(nh),
            next: Vec::with_capacity(nh),
            prev: Vec::with_capacity(nh),
            to_vertex: Vec::with_capacity(nh),
            edge: vec![NONE; nh],
            face: Vec::with_capacity(nh),
            edge_halfedge: Vec::with_capacity(nh / 2),
            face_halfedge: Vec::with_capacity(nf),
            attributes: AttributeColumns::default(),
        };

        for f in 0..nf {
            let (s, e) = (
                faces.face_starts[f] as usize,
                faces.face_starts[f + 1] as usize,
            );
            c.face_halfedge.push(s as u32);
            for h in s..e {
                let n = if h + 1 == e { s } else { h + 1 };
                let p = if h == s { e - 1 } else { h - 1 };
                c.next.push(n as u32);
                c.prev.push(p as u32);
                c.to_vertex.push(faces.indices[n]);
                c.face.push(f as u32);
                c.vertex_halfedge[faces.indices[h] as usize] = h as u32;
            }
        }
        c.twin.extend_from_slice(faces.twin);

        // Boundary halfedges: the twin of interior corner h runs from to(h) back to from(h).
        let mut boundary_out = vec![NONE; nv];
        for h in 0..interior {
            if faces.twin[h] != NONE {
                continue;
            }
            let b = c.twin.len() as u32;
            c.twin[h] = b;
            c.twin.push(h as u32);
            c.to_vertex.push(faces.indices[h]);
            c.face.push(NONE);
            c.next.push(NONE);
            c.prev.push(NONE);
            let from = c.to_vertex[h];
            boundary_out[from as usize] = b;
            c.vertex_halfedge[from as usize] = b;
        }
        for b in interior..nh {
            let n = boundary_out[c.to_vertex[b] as usize];
            c.next[b] = n;
            c.prev[n as usize] = b as u32;
        }

        for h in 0..nh {
            if c.edge[h] == NONE {
                let e = c.edge_halfedge.len() as u32;
                c.edge[h] = e;
                c.edge[c.twin[h] as usize] = e;
                c.edge_halfedge.push(h as u32);
            }
        }
        c
    }

    // ---- Counts and rows ----

    /// Number of vertices.
    #[inline]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of halfedges (interior and boundary).
    #[inline]
    pub fn halfedge_count(&self) -> usize {
        self.twin.len()
    }

    /// Number of edges.
    #[inline]
    pub fn edge_count(&self) -> usize {
        self.edge_halfedge.len()
    }

    /// Number of faces.
    #[inline]
    pub fn face_count(&self) -> usize {
        self.face_halfedge.len()
    }

    /// How many rows of each kind the tables have.
    pub fn row_counts(&self) -> RowCounts {
        RowCounts {
            vertices: self.vertex_count(),
            halfedges: self.halfedge_count(),
            edges: self.edge_count(),
            faces: self.face_count(),
        }
    }

    /// Every vertex row, in order.
    #[inline]
    pub fn vertices(&self) -> impl Iterator<Item = VertexRow> + use<> {
        (0..self.vertex_count() as u32).map(VertexRow::new)
    }

    /// Every halfedge row, in order.
    #[inline]
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeRow> + use<> {
        (0..self.halfedge_count() as u32).map(HalfedgeRow::new)
    }

    /// Every edge row, in order.
    #[inline]
    pub fn edges(&self) -> impl Iterator<Item = EdgeRow> + use<> {
        (0..self.edge_count() as u32).map(EdgeRow::new)
    }

    /// Every face row, in order.
    #[inline]
    pub fn faces(&self) -> impl Iterator<Item = FaceRow> + use<> {
        (0..self.face_count() as u32).map(FaceRow::new)
    }

    // ---- Navigation ----

    /// The halfedge running the other way along `h`'s edge.
    #[inline]
    pub fn twin(&self, h: HalfedgeRow) -> HalfedgeRow {
        HalfedgeRow::new(self.twin[h.index()])
    }

    /// The halfedge after `h` around its face (or boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeRow) -> HalfedgeRow {
        HalfedgeRow::new(self.next[h.index()])
    }

    /// The halfedge before `h` around its face (or boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeRow) -> HalfedgeRow {
        HalfedgeRow::new(self.prev[h.index()])
    }

    /// The vertex `h` points to (its tip).
    #[inline]
    pub fn to_vertex(&self, h: HalfedgeRow) -> VertexRow {
        VertexRow::new(self.to_vertex[h.index()])
    }

    /// The vertex `h` starts from: its twin's tip.
    #[inline]
    pub fn from_vertex(&self, h: HalfedgeRow) -> VertexRow {
        self.to_vertex(self.twin(h))
    }

    /// The edge `h` is half of.
    #[inline]
    pub fn edge(&self, h: HalfedgeRow) -> EdgeRow {
        EdgeRow::new(self.edge[h.index()])
    }

    /// The face `h` bounds, `None` for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: HalfedgeRow) -> Option<FaceRow> {
        let f = self.face[h.index()];
        (f != NONE).then_some(FaceRow::new(f))
    }

    /// Whether `h` is a boundary halfedge (has no face).
    #[inline]
    pub fn is_boundary(&self, h: HalfedgeRow) -> bool {
        self.face[h.index()] == NONE
    }

    /// `v`'s outgoing halfedge: its outgoing boundary halfedge if it is on the boundary.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexRow) -> HalfedgeRow {
        HalfedgeRow::new(self.vertex_halfedge[v.index()])
    }

    /// One of `e`'s two halfedges (an interior one where it has one).
    #[inline]
    pub fn edge_halfedge(&self, e: EdgeRow) -> HalfedgeRow {
        HalfedgeRow::new(self.edge_halfedge[e.index()])
    }

    /// `f`'s first halfedge.
    #[inline]
    pub fn face_halfedge(&self, f: FaceRow) -> HalfedgeRow {
        HalfedgeRow::new(self.face_halfedge[f.index()])
    }

    /// The length of edge `e` (the distance between its ends).
    #[inline]
    pub fn edge_length(&self, e: EdgeRow) -> f32 {
        let h = self.edge_halfedge(e);
        self.position(self.from_vertex(h))
            .distance(self.position(self.to_vertex(h)))
    }

    /// `v`'s position.
    #[inline]
    pub fn position(&self, v: VertexRow) -> Vec3 {
        self.positions[v.index()]
    }

    /// The next outgoing halfedge of `h`'s start vertex, counter-clockwise: `twin(prev(h))`.
    #[inline]
    pub fn ccw_rotated(&self, h: HalfedgeRow) -> HalfedgeRow {
        self.twin(self.prev(h))
    }

    /// The next outgoing halfedge of `h`'s start vertex, clockwise: `next(twin(h))`.
    #[inline]
    pub fn cw_rotated(&self, h: HalfedgeRow) -> HalfedgeRow {
        self.next(self.twin(h))
    }

    /// Whether `v` is on the boundary (its halfedge is a boundary one).
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexRow) -> bool {
        self.is_boundary(self.vertex_halfedge(v))
    }

    /// Whether `e` is on the boundary (either of its halfedges is).
    #[inline]
    pub fn is_boundary_edge(&self, e: EdgeRow) -> bool {
        let h = self.edge_halfedge(e);
        self.is_boundary(h) || self.is_boundary(self.twin(h))
    }

    /// The halfedges of face `f`, in order from its first.
    #[inline]
    pub fn face_halfedges(&self, f: FaceRow) -> impl Iterator<Item = HalfedgeRow> + '_ {
        self.circulate(self.face_halfedge(f), Self::next)
    }

    /// The outgoing halfedges of `v`, counter-clockwise from its halfedge (the boundary one
    /// first on the boundary).
    #[inline]
    pub fn vertex_outgoing(&self, v: VertexRow) -> impl Iterator<Item = HalfedgeRow> + '_ {
        self.circulate(self.vertex_halfedge(v), Self::ccw_rotated)
    }

    /// The halfedge from `a` to `b`, if they are neighbours.
    #[inline]
    pub fn find_halfedge(&self, a: VertexRow, b: VertexRow) -> Option<HalfedgeRow> {
        self.vertex_outgoing(a).find(|&h| self.to_vertex(h) == b)
    }

    /// The halfedges of face `f` in order from its first: its three sides when it is a
    /// triangle (see [`Connectivity::first_non_triangle`]), the first three otherwise.
    #[inline]
    pub fn triangle_halfedges(&self, f: FaceRow) -> [HalfedgeRow; 3] {
        let first = self.face_halfedge(f);
        let second = self.next(first);
        [first, second, self.next(second)]
    }

    /// The positions of the corners of face `f`, in the order of
    /// [`Connectivity::triangle_halfedges`] (the tips of its first three halfedges).
    #[inline]
    pub fn triangle_corners(&self, f: FaceRow) -> [Vec3; 3] {
        self.triangle_halfedges(f)
            .map(|h| self.position(self.to_vertex(h)))
    }

    /// Twice the vector area of triangle `f` (Newell's, over [`Connectivity::triangle_corners`]),
    /// as [`crate::mesh::MeshRef::face_area_vector`] computes it on the entities, to the bit.
    pub fn triangle_area_vector(&self, f: FaceRow) -> Vec3 {
        newell_area_vector(&self.triangle_corners(f))
    }

    /// The first face that is not a triangle, if any (three `next` steps from its halfedge do
    /// not come back to it).
    pub fn first_non_triangle(&self) -> Option<FaceRow> {
        self.faces().find(|&f| {
            let h = self.face_halfedge(f);
            let n = self.next(h);
            n == h || self.next(self.next(n)) != h
        })
    }

    /// `first`, then `step` applied until it comes back to `first`, at most [`MAX_LOOP`]
    /// halfedges.
    #[inline]
    fn circulate<'a>(
        &'a self,
        first: HalfedgeRow,
        step: impl Fn(&Self, HalfedgeRow) -> HalfedgeRow + 'a,
    ) -> impl Iterator<Item = HalfedgeRow> + 'a {
        let mut h = Some(first);
        std::iter::from_fn(move || {
            let current = h?;
            let next = step(self, current);
            h = (next != first).then_some(next);
            Some(current)
        })
        .take(MAX_LOOP)
    }

    // ---- Untyped forms, for the readers still on bare rows ----

    /// [`Connectivity::vertex_outgoing`] on bare `u32` rows (for the remesher's passes, until
    /// they move to typed rows).
    #[inline]
    pub fn outgoing(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.vertex_outgoing(VertexRow::new(v))
            .map(HalfedgeRow::get)
    }

    /// [`Connectivity::triangle_halfedges`] on bare rows (for the remesher's passes, until
    /// they move to typed rows).
    #[inline]
    pub fn triangle(&self, f: usize) -> [u32; 3] {
        self.triangle_halfedges(FaceRow::new(f as u32))
            .map(HalfedgeRow::get)
    }

    // ---- Editing: each setter writes exactly the one entry it names ----

    /// Sets `h`'s twin (not the twin's twin).
    #[inline]
    pub fn set_twin(&mut self, h: HalfedgeRow, twin: HalfedgeRow) {
        self.twin[h.index()] = twin.get();
    }

    /// Sets `h`'s next (not `next`'s prev; [`Connectivity::link`] sets both).
    #[inline]
    pub fn set_next(&mut self, h: HalfedgeRow, next: HalfedgeRow) {
        self.next[h.index()] = next.get();
    }

    /// Sets `h`'s prev (not `prev`'s next).
    #[inline]
    pub fn set_prev(&mut self, h: HalfedgeRow, prev: HalfedgeRow) {
        self.prev[h.index()] = prev.get();
    }

    /// Makes `to` follow `from`: `next(from) = to` and `prev(to) = from`.
    #[inline]
    pub fn link(&mut self, from: HalfedgeRow, to: HalfedgeRow) {
        self.set_next(from, to);
        self.set_prev(to, from);
    }

    /// Sets the vertex `h` points to.
    #[inline]
    pub fn set_to_vertex(&mut self, h: HalfedgeRow, v: VertexRow) {
        self.to_vertex[h.index()] = v.get();
    }

    /// Sets `h`'s edge.
    #[inline]
    pub fn set_edge(&mut self, h: HalfedgeRow, e: EdgeRow) {
        self.edge[h.index()] = e.get();
    }

    /// Sets `h`'s face (`None`: a boundary halfedge).
    #[inline]
    pub fn set_face(&mut self, h: HalfedgeRow, f: Option<FaceRow>) {
        self.face[h.index()] = f.map_or(NONE, FaceRow::get);
    }

    /// Sets `v`'s outgoing halfedge.
    #[inline]
    pub fn set_vertex_halfedge(&mut self, v: VertexRow, h: HalfedgeRow) {
        self.vertex_halfedge[v.index()] = h.get();
    }

    /// Sets `e`'s halfedge.
    #[inline]
    pub fn set_edge_halfedge(&mut self, e: EdgeRow, h: HalfedgeRow) {
        self.edge_halfedge[e.index()] = h.get();
    }

    /// Moves `v` to `p`.
    #[inline]
    pub fn set_position(&mut self, v: VertexRow, p: Vec3) {
        self.positions[v.index()] = p;
    }

    // ---- Growing: each call appends one row ----

    /// Makes room for `more` rows of each kind beyond the current ones (tables that grow
    /// row by row, as the bulk refine's, then never reallocate).
    pub fn reserve(&mut self, more: RowCounts) {
        self.positions.reserve(more.vertices);
        self.vertex_halfedge.reserve(more.vertices);
        for table in [
            &mut self.twin,
            &mut self.next,
            &mut self.prev,
            &mut self.to_vertex,
            &mut self.edge,
            &mut self.face,
        ] {
            table.reserve(more.halfedges);
        }
        self.edge_halfedge.reserve(more.edges);
        self.face_halfedge.reserve(more.faces);
    }

    /// The row the next [`Connectivity::push_halfedge`] gives.
    #[inline]
    pub fn next_halfedge_row(&self) -> HalfedgeRow {
        HalfedgeRow::new(self.halfedge_count() as u32)
    }

    /// Appends a vertex at `position`, its halfedge not set yet ([`HalfedgeRow::NONE`]).
    pub fn push_vertex(&mut self, position: Vec3) -> VertexRow {
        let v = VertexRow::new(self.positions.len() as u32);
        self.positions.push(position);
        self.vertex_halfedge.push(NONE);
        v
    }

    /// Appends an edge whose halfedge is `halfedge`.
    pub fn push_edge(&mut self, halfedge: HalfedgeRow) -> EdgeRow {
        let e = EdgeRow::new(self.edge_halfedge.len() as u32);
        self.edge_halfedge.push(halfedge.get());
        e
    }

    /// Appends a face whose first halfedge is `halfedge`.
    pub fn push_face(&mut self, halfedge: HalfedgeRow) -> FaceRow {
        let f = FaceRow::new(self.face_halfedge.len() as u32);
        self.face_halfedge.push(halfedge.get());
        f
    }

    /// Appends a halfedge with the links `l`.
    pub fn push_halfedge(&mut self, l: HalfedgeLinks) -> HalfedgeRow {
        let h = self.next_halfedge_row();
        self.twin.push(l.twin.get());
        self.next.push(l.next.get());
        self.prev.push(l.prev.get());
        self.to_vertex.push(l.to_vertex.get());
        self.edge.push(l.edge.get());
        self.face.push(l.face.map_or(NONE, FaceRow::get));
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing the diagonal of a unit square: 0 1 2 and 0 2 3.
    fn square() -> Connectivity {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        // Corner 2 (2 → 0) and corner 3 (0 → 2) are the diagonal.
        Connectivity::from_corners(FaceCorners {
            positions: &positions,
            indices: &[0, 1, 2, 0, 2, 3],
            face_starts: &[0, 3, 6],
            twin: &[NONE, NONE, 3, 2, NONE, NONE],
        })
    }

    #[test]
    fn the_layout_puts_corners_first_and_links_the_boundary() {
        let t = square();
        assert_eq!(
            t.row_counts(),
            RowCounts {
                vertices: 4,
                halfedges: 10,
                edges: 5,
                faces: 2
            }
        );
        for h in t.halfedges() {
            assert_eq!(t.twin(t.twin(h)), h);
            assert_eq!(t.prev(t.next(h)), h);
            assert_eq!(t.from_vertex(t.next(h)), t.to_vertex(h));
            assert_eq!(t.edge(h), t.edge(t.twin(h)));
            assert_eq!(t.is_boundary(h), h.index() >= 6);
            assert_eq!(t.face(h).is_none(), t.is_boundary(h));
        }
        for v in t.vertices() {
            assert!(t.is_boundary_vertex(v));
            assert_eq!(t.from_vertex(t.vertex_halfedge(v)), v);
        }
        let diagonal = t.edge(HalfedgeRow::new(2));
        assert!(!t.is_boundary_edge(diagonal));
        assert_eq!(t.edges().filter(|&e| t.is_boundary_edge(e)).count(), 4);
        assert_eq!(t.first_non_triangle(), None);
    }

    #[test]
    fn the_circulators_walk_faces_and_fans() {
        let t = square();
        let f = FaceRow::new(1);
        let ring: Vec<_> = t.face_halfedges(f).collect();
        assert_eq!(ring, t.triangle_halfedges(f).to_vec());
        assert!(ring.iter().all(|&h| t.face(h) == Some(f)));
        // Vertex 0 has three neighbours: 1, 2 and 3, the boundary halfedge first.
        let v = VertexRow::new(0);
        let out: Vec<_> = t.vertex_outgoing(v).collect();
        assert_eq!(out.len(), 3);
        assert!(t.is_boundary(out[0]));
        for &h in &out {
            assert_eq!(t.from_vertex(h), v);
            assert_eq!(t.cw_rotated(t.ccw_rotated(h)), h);
        }
        let to_2 = t.find_halfedge(v, VertexRow::new(2)).unwrap();
        assert_eq!(t.edge(to_2), t.edge(HalfedgeRow::new(2)));
        assert_eq!(t.find_halfedge(VertexRow::new(1), VertexRow::new(3)), None);
        assert_eq!(
            t.outgoing(0).collect::<Vec<_>>(),
            out.iter().map(|h| h.get()).collect::<Vec<_>>()
        );
    }
}
