//! Edge loops and edge rings: the selection paths of quad meshes (Blender's Alt+click and
//! Ctrl+Alt+click).
//!
//! ```text
//!   loop through e (──): at each regular vertex, go straight on
//!     +----+----+----+          ring through e (║): across each quad, to the opposite side
//!     |    |    |    |            +----+----+----+
//!     +════+═e══+════+            |    ║    |    |
//!     |    |    |    |            +----+--e-+----+   (e horizontal: the ring is the
//!     +----+----+----+            |    ║    |    |    horizontal sides stacked above
//!                                 +----+----+----+    and below it)
//! ```
//!
//! - **Loop**: from an edge's halfedge `h` (u → v), the loop goes on through `v` when `v` is an
//!   interior vertex of valence 4: the next halfedge is `next(twin(next(h)))`, the edge that
//!   leaves `v` opposite `h`. It stops at a vertex of another valence, at the boundary, or when
//!   it closes; then it is walked the other way from the start.
//! - **Ring**: from an edge's halfedge `h` in a quad, the ring goes on to the opposite side of
//!   the quad, `next(next(h))`, and crosses it to the quad beyond (its twin). It stops at a
//!   face that is not a quad, at the boundary, or when it closes.
//!
//! Both give each edge once, the start first, and visit at most every edge of the mesh.

use super::ids::{EdgeId, HalfedgeId};
use super::topology::MeshRef;

/// The edge loop through `e`: `e` first, then the edges straight on through regular (valence
/// 4, interior) vertices in both directions. Only `e` if neither end is regular. `None` if `e`
/// is gone.
pub fn edge_loop(m: &MeshRef<'_>, e: EdgeId) -> Option<Vec<EdgeId>> {
    let h = m.try_edge(e)?.halfedge;
    m.try_halfedge(h)?;
    let straight_on = |h: HalfedgeId| {
        let v = m.to_vertex(h);
        (m.valence(v) == 4 && !m.is_boundary_vertex(v)).then(|| m.next(m.twin(m.next(h))))
    };
    Some(walk(m, h, straight_on))
}

/// The edge ring through `e`: `e` first, then the opposite sides of the quads on both sides,
/// crossing from quad to quad. Only `e` if it has no quad beside it. `None` if `e` is gone.
pub fn edge_ring(m: &MeshRef<'_>, e: EdgeId) -> Option<Vec<EdgeId>> {
    let h = m.try_edge(e)?.halfedge;
    m.try_halfedge(h)?;
    // Across the quad of `h` to its opposite side, and over to the face beyond.
    let across = |h: HalfedgeId| {
        let f = m.face(h)?;
        (m.face_degree(f) == 4).then(|| m.twin(m.next(m.next(h))))
    };
    Some(walk(m, h, across))
}

/// Walks from `h` with `step` (which gives the halfedge to continue from, or `None` to stop)
/// forwards, then from `twin(h)` the other way, collecting each edge once.
fn walk(
    m: &MeshRef<'_>,
    h: HalfedgeId,
    step: impl Fn(HalfedgeId) -> Option<HalfedgeId>,
) -> Vec<EdgeId> {
    let start = m.edge(h);
    let mut edges = vec![start];
    let mut seen = std::collections::HashSet::from([start]);
    for first in [h, m.twin(h)] {
        let mut x = first;
        while let Some(y) = step(x) {
            let e = m.edge(y);
            if !seen.insert(e) {
                break;
            }
            edges.push(e);
            x = y;
        }
    }
    edges
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use bevy::prelude::World;

    /// A 4×3 grid of quads (vertices numbered row by row, 5 a row); returns the world and the edge between input vertices `a` and `b`.
    fn grid_edge(a: usize, b: usize) -> (World, EdgeId, Vec<crate::mesh::VertexId>) {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::quad_grid(4, 3), MeshInfo::default()).unwrap();
        let vs: Vec<_> = built.input_vertices.iter().map(|v| v.unwrap()).collect();
        let m = MeshRef::new(&world);
        let e = m.edge(m.find_halfedge(vs[a], vs[b]).unwrap());
        (world, e, vs)
    }

    fn ends(m: &MeshRef<'_>, edges: &[EdgeId], vs: &[crate::mesh::VertexId]) -> Vec<[usize; 2]> {
        let index = |v| vs.iter().position(|&x| x == v).unwrap();
        let mut out: Vec<[usize; 2]> = edges
            .iter()
            .map(|&e| {
                let (a, b) = m.edge_vertices(e);
                let mut p = [index(a), index(b)];
                p.sort_unstable();
                p
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn a_loop_runs_straight_across_the_grid_and_stops_at_the_boundary() {
        // Grid vertices are numbered row by row, 5 a row: the middle row's edge 6–7.
        let (world, e, vs) = grid_edge(6, 7);
        let m = MeshRef::new(&world);
        let lp = edge_loop(&m, e).unwrap();
        assert_eq!(lp[0], e);
        assert_eq!(ends(&m, &lp, &vs), vec![[5, 6], [6, 7], [7, 8], [8, 9]]);
    }

    #[test]
    fn a_ring_crosses_every_quad_of_the_column() {
        let (world, e, vs) = grid_edge(6, 7);
        let m = MeshRef::new(&world);
        let ring = edge_ring(&m, e).unwrap();
        assert_eq!(ring[0], e);
        assert_eq!(
            ends(&m, &ring, &vs),
            vec![[1, 2], [6, 7], [11, 12], [16, 17]]
        );
    }

    #[test]
    fn a_loop_on_a_closed_torus_closes() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::torus(12, 8), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        let v = built.input_vertices[0].unwrap();
        let h = m.vertex_halfedge(v);
        let lp = edge_loop(&m, m.edge(h)).unwrap();
        let ring = edge_ring(&m, m.edge(h)).unwrap();
        // One loop runs around one circle of the torus, the ring around the other.
        let mut sizes = [lp.len(), ring.len()];
        sizes.sort_unstable();
        assert_eq!(sizes, [8, 12]);
    }

    #[test]
    fn irregular_vertices_stop_a_loop_and_triangles_stop_a_ring() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosahedron(), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        let v = built.input_vertices[0].unwrap();
        let e = m.edge(m.vertex_halfedge(v));
        assert_eq!(edge_loop(&m, e).unwrap(), vec![e]);
        assert_eq!(edge_ring(&m, e).unwrap(), vec![e]);
    }
}
