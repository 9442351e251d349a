//! Cutting a mesh open along seams, virtually: the [`CutMesh`] every parameterization solves on.
//!
//! Nothing in the mesh changes. A *cut vertex* is one wedge of corners around an original
//! vertex: the corners of a vertex's fan that are not separated by a seam edge (or the
//! boundary). A vertex with no seam edge is one cut vertex; a vertex inside a seam path (two seam
//! edges) is two, one for each side; a seam path's end (one seam edge) stays one, so the seam
//! opens into a slit. Wedges come from a union–find over corners: across every interior edge
//! that is not a seam, the two corners at each endpoint are joined.
//!
//! ```text
//!      seam            cut mesh
//!   a ---- b ---- c     a  b'  c     (b'/b'': the two wedges of b, one on either side)
//!                        \/ \/
//!                        /\ /\
//!                          b''
//! ```
//!
//! Polygons are fanned from their first corner (the corner of `prev(face_halfedge)`), as
//! [`crate::ops::geometry::Surface`] does, so every method sees triangles; each triangle keeps
//! its face.
//!
//! The cut mesh's topology is then checked: it must be one connected piece of genus 0 with at
//! least one boundary loop (χ = V − E + F = 2 − 2g − b on the fanned triangles). A closed
//! genus-0 mesh without seams is opened by [`auto_seams`]: the shortest edge path (Dijkstra over
//! edge lengths) between two far-apart vertices (the farthest from vertex 0, and the farthest
//! from that one). Anything else is refused with [`ParamError`], naming the genus, loops and
//! components, and the fix (mark seams).

use bevy::math::DVec3;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::params::ParamError;
use crate::mesh::tables::{Connectivity, EdgeRow, FaceRow, HalfedgeRow, NONE, VertexRow};

/// A mesh cut open along its seams, as fanned triangles over cut vertices (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct CutMesh {
    /// Each cut vertex's position.
    pub positions: Vec<DVec3>,
    /// Each cut vertex's original vertex.
    pub vertex: Vec<VertexRow>,
    /// By halfedge row: the cut vertex of the corner at `to_vertex(h)` in `face(h)`, or
    /// [`NONE`] for a boundary (faceless) halfedge.
    pub corner: Vec<u32>,
    /// Triangles as cut vertices, counter-clockwise (polygons fanned from their first corner).
    pub triangles: Vec<[u32; 3]>,
    /// The face each triangle was cut from.
    pub triangle_face: Vec<FaceRow>,
    /// The boundary loops of the cut mesh, as cut vertices in order with the surface on the
    /// left (counter-clockwise for the outer one), the longest (in 3D length) first.
    pub loops: Vec<Vec<u32>>,
    /// The 3D length of each loop.
    pub loop_lengths: Vec<f64>,
    /// Every edge cut open: the given seams (deduplicated, boundary edges dropped) and the
    /// automatic cut's.
    pub seams: Vec<EdgeRow>,
    /// How many of the seams the automatic cut added (0 when the mesh opened as given).
    pub auto_seams: usize,
}

impl CutMesh {
    /// Number of cut vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
}

/// Union–find with path halving, over `0..n`.
struct Sets(Vec<u32>);

impl Sets {
    fn new(n: usize) -> Self {
        Self((0..n as u32).collect())
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let parent = self.0[x as usize];
            self.0[x as usize] = self.0[parent as usize];
            x = parent;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b) as usize] = a.min(b);
        }
    }
}

/// Cuts `t` along `seams` and checks that the result is a disk (possibly with holes); cuts a
/// closed genus-0 mesh automatically when `auto_cut` is set and it has no seams that open it.
///
/// # Errors
/// [`ParamError::NoFaces`], [`ParamError::SeamOutOfRange`], [`ParamError::Components`],
/// [`ParamError::NotADisk`] (genus > 0, or closed without `auto_cut`).
pub fn cut(t: &Connectivity, seams: &[EdgeRow], auto_cut: bool) -> Result<CutMesh, ParamError> {
    if t.face_count() == 0 {
        return Err(ParamError::NoFaces);
    }
    if let Some(&e) = seams.iter().find(|e| e.index() >= t.edge_count()) {
        return Err(ParamError::SeamOutOfRange {
            edge: e.get(),
            edges: t.edge_count(),
        });
    }
    let mut cut = cut_along(t, seams);
    let before = topology(&cut);
    if before.components > 1 {
        return Err(ParamError::Components {
            components: before.components,
        });
    }
    if before.genus > 0 {
        return Err(ParamError::NotADisk {
            genus: before.genus,
            loops: before.loops,
            seams: cut.seams.len(),
        });
    }
    if before.loops == 0 {
        if !auto_cut {
            return Err(ParamError::NotADisk {
                genus: 0,
                loops: 0,
                seams: cut.seams.len(),
            });
        }
        let extra = auto_seams(t);
        let mut all = cut.seams.clone();
        all.extend_from_slice(&extra);
        cut = cut_along(t, &all);
        cut.auto_seams = extra.len();
        let after = topology(&cut);
        if after.components > 1 || after.genus > 0 || after.loops == 0 {
            return Err(ParamError::NotADisk {
                genus: after.genus,
                loops: after.loops,
                seams: cut.seams.len(),
            });
        }
    }
    Ok(cut)
}

/// The cut mesh of `t` along `seams`, unchecked.
fn cut_along(t: &Connectivity, seams: &[EdgeRow]) -> CutMesh {
    let nh = t.halfedge_count();
    let mut is_seam = vec![false; t.edge_count()];
    let mut kept = Vec::with_capacity(seams.len());
    for &e in seams {
        if !is_seam[e.index()] && !t.is_boundary_edge(e) {
            is_seam[e.index()] = true;
            kept.push(e);
        }
    }
    // Corners: one per face halfedge. Join the corners at each endpoint of every uncut edge.
    let mut sets = Sets::new(nh);
    for e in t.edges() {
        if is_seam[e.index()] || t.is_boundary_edge(e) {
            continue;
        }
        let h = t.edge_halfedge(e);
        let o = t.twin(h);
        // h: a → b. At b: corner h (face(h)) and prev(o) (face(o)); at a: o and prev(h).
        sets.union(h.get(), t.prev(o).get());
        sets.union(o.get(), t.prev(h).get());
    }
    let mut corner = vec![NONE; nh];
    let mut positions = Vec::new();
    let mut vertex = Vec::new();
    for h in t.halfedges() {
        if t.is_boundary(h) {
            continue;
        }
        let root = sets.find(h.get()) as usize;
        if corner[root] == NONE {
            corner[root] = positions.len() as u32;
            let v = t.to_vertex(h);
            positions.push(t.position(v).as_dvec3());
            vertex.push(v);
        }
        corner[h.index()] = corner[root];
    }
    // Fan every face from the corner of prev(first).
    let mut triangles = Vec::with_capacity(t.face_count() * 2);
    let mut triangle_face = Vec::with_capacity(t.face_count() * 2);
    for f in t.faces() {
        let first = t.face_halfedge(f);
        let apex = corner[t.prev(first).index()];
        let mut h = first;
        loop {
            let next = t.next(h);
            if t.next(next) == first || next == first {
                break;
            }
            triangles.push([apex, corner[h.index()], corner[next.index()]]);
            triangle_face.push(f);
            h = next;
        }
    }
    // Boundary sides: every face halfedge h whose edge is cut or on the boundary runs from the
    // corner of prev(h) to the corner of h, the face on its left. Each boundary cut vertex
    // starts exactly one side (its wedge is a fan with two ends).
    let nc = positions.len();
    let mut successor = vec![NONE; nc];
    let mut side_length = vec![0.0; nc];
    for h in t.halfedges() {
        if t.is_boundary(h) {
            continue;
        }
        let e = t.edge(h);
        if is_seam[e.index()] || t.is_boundary(t.twin(h)) {
            let from = corner[t.prev(h).index()] as usize;
            successor[from] = corner[h.index()];
            side_length[from] = t
                .position(t.from_vertex(h))
                .distance(t.position(t.to_vertex(h))) as f64;
        }
    }
    let mut seen = vec![false; nc];
    let mut loops: Vec<(f64, Vec<u32>)> = Vec::new();
    for start in 0..nc {
        if successor[start] == NONE || seen[start] {
            continue;
        }
        let (mut l, mut length, mut c) = (Vec::new(), 0.0, start as u32);
        while !seen[c as usize] && successor[c as usize] != NONE {
            seen[c as usize] = true;
            l.push(c);
            length += side_length[c as usize];
            c = successor[c as usize];
        }
        loops.push((length, l));
    }
    loops.sort_by(|a, b| b.0.total_cmp(&a.0));
    CutMesh {
        positions,
        vertex,
        corner,
        triangles,
        triangle_face,
        loop_lengths: loops.iter().map(|l| l.0).collect(),
        loops: loops.into_iter().map(|l| l.1).collect(),
        seams: kept,
        auto_seams: 0,
    }
}

/// The topology of a cut mesh's triangle complex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Topology {
    /// Connected pieces.
    pub components: usize,
    /// Boundary loops.
    pub loops: usize,
    /// The Euler characteristic V − E + F.
    pub euler: i64,
    /// The genus, from χ = 2 − 2g − b (per piece, when there is one).
    pub genus: usize,
}

/// The topology of `cut` (see [`Topology`]).
pub fn topology(cut: &CutMesh) -> Topology {
    let nc = cut.vertex_count();
    let mut sets = Sets::new(nc);
    for &[a, b, c] in &cut.triangles {
        sets.union(a, b);
        sets.union(a, c);
    }
    let mut used = vec![false; nc];
    for tri in &cut.triangles {
        for &c in tri {
            used[c as usize] = true;
        }
    }
    let components = (0..nc as u32)
        .filter(|&c| used[c as usize] && sets.find(c) == c)
        .count();
    let sides: usize = cut.loops.iter().map(Vec::len).sum();
    let (v, f) = (nc as i64, cut.triangles.len() as i64);
    let e = (3 * f + sides as i64) / 2;
    let euler = v - e + f;
    let loops = cut.loops.len();
    let genus = ((2 - loops as i64 - euler) / 2).max(0) as usize;
    Topology {
        components,
        loops,
        euler,
        genus,
    }
}

/// Seams that open a closed mesh: the shortest edge path (Dijkstra over edge lengths) from the
/// vertex farthest from vertex 0 to the vertex farthest from that one (an approximate
/// diameter). Empty when the mesh has fewer than two vertices.
pub fn auto_seams(t: &Connectivity) -> Vec<EdgeRow> {
    if t.vertex_count() < 2 {
        return Vec::new();
    }
    let (distance, _) = dijkstra(t, VertexRow::new(0));
    let a = farthest(&distance);
    let (distance, via) = dijkstra(t, a);
    let mut v = farthest(&distance);
    let mut path = Vec::new();
    while v != a {
        let h = via[v.index()];
        if h.is_none() {
            break;
        }
        path.push(t.edge(h));
        v = t.from_vertex(h);
    }
    path
}

/// The vertex with the largest finite distance.
fn farthest(distance: &[f64]) -> VertexRow {
    let mut best = (0, f64::NEG_INFINITY);
    for (i, &d) in distance.iter().enumerate() {
        if d.is_finite() && d > best.1 {
            best = (i, d);
        }
    }
    VertexRow::new(best.0 as u32)
}

/// Shortest distances from `source` along edges, and the halfedge each vertex is reached by.
fn dijkstra(t: &Connectivity, source: VertexRow) -> (Vec<f64>, Vec<HalfedgeRow>) {
    let n = t.vertex_count();
    let mut distance = vec![f64::INFINITY; n];
    let mut via = vec![HalfedgeRow::NONE; n];
    let mut heap = BinaryHeap::new();
    distance[source.index()] = 0.0;
    heap.push((Reverse(OrdF64(0.0)), source.get()));
    while let Some((Reverse(OrdF64(d)), v)) = heap.pop() {
        let v = VertexRow::new(v);
        if d > distance[v.index()] {
            continue;
        }
        for h in t.vertex_outgoing(v) {
            let w = t.to_vertex(h);
            let nd = d + t.position(v).distance(t.position(w)) as f64;
            if nd < distance[w.index()] {
                distance[w.index()] = nd;
                via[w.index()] = h;
                heap.push((Reverse(OrdF64(nd)), w.get()));
            }
        }
    }
    (distance, via)
}

/// An `f64` ordered by `total_cmp`, for the heap.
#[derive(Clone, Copy, PartialEq)]
struct OrdF64(f64);

impl Eq for OrdF64 {}

impl PartialOrd for OrdF64 {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for OrdF64 {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::ops::param::test_tables;

    #[test]
    fn a_grid_is_one_disk_with_one_cut_vertex_per_vertex() {
        let t = test_tables(&shapes::grid(4, 3));
        let c = cut(&t, &[], true).unwrap();
        assert_eq!(c.vertex_count(), t.vertex_count());
        assert_eq!(c.loops.len(), 1);
        assert_eq!(c.loops[0].len(), 2 * (4 + 3));
        let topo = topology(&c);
        assert_eq!((topo.components, topo.euler, topo.genus), (1, 1, 0));
        assert!((c.loop_lengths[0] - 4.0).abs() < 1e-6);
    }

    #[test]
    fn a_seam_path_inside_a_grid_opens_a_slit() {
        let t = test_tables(&shapes::grid(4, 4));
        // Two interior edges in a row along y = 0.5: (0.25,0.5)-(0.5,0.5)-(0.75,0.5).
        let at = |x: f32, y: f32| {
            t.vertices()
                .find(|&v| t.position(v).distance(bevy::math::Vec3::new(x, y, 0.0)) < 1e-6)
                .unwrap()
        };
        let (a, b, c) = (at(0.25, 0.5), at(0.5, 0.5), at(0.75, 0.5));
        let seams = [
            t.edge(t.find_halfedge(a, b).unwrap()),
            t.edge(t.find_halfedge(b, c).unwrap()),
        ];
        let cm = cut(&t, &seams, true).unwrap();
        // b splits in two; a and c stay one each: a slit loop of 4 sides, a hole.
        assert_eq!(cm.vertex_count(), t.vertex_count() + 1);
        assert_eq!(cm.loops.len(), 2);
        assert_eq!(cm.loops[1].len(), 4);
        assert_eq!(topology(&cm).genus, 0);
    }

    #[test]
    fn a_closed_sphere_is_cut_automatically_and_a_torus_is_refused() {
        let t = test_tables(&shapes::icosphere(2));
        let c = cut(&t, &[], true).unwrap();
        assert!(c.auto_seams >= 2);
        assert_eq!(c.loops.len(), 1);
        assert_eq!(topology(&c).euler, 1);
        assert_eq!(
            cut(&t, &[], false).unwrap_err(),
            ParamError::NotADisk {
                genus: 0,
                loops: 0,
                seams: 0
            }
        );
        let torus = test_tables(&shapes::torus(8, 6));
        assert_eq!(
            cut(&torus, &[], true).unwrap_err(),
            ParamError::NotADisk {
                genus: 1,
                loops: 0,
                seams: 0
            }
        );
    }
}
