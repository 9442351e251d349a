//! Feature edges, which the remesh holds in place: the boundary and sharp creases keep their
//! line through the split, collapse, flip and relaxation steps of Botsch & Kobbelt 2004.
//!
//! An edge is a feature when it is on the boundary or its two faces meet at more than
//! [`RemeshParams::feature_angle_deg`](super::RemeshParams::feature_angle_deg), less the three
//! sides of every triangle dented by scanner noise ([`without_noise`]). A feature edge is split
//! (both halves stay features) but never flipped. A vertex's feature degree (how many feature
//! edges meet there) says what it may do: 0, free; 2, on a feature line, which it may leave
//! only by merging into its neighbour along the line, and move only along it (in the
//! thin-triangle clean-up), both only where the line is straight there; any other count, a
//! feature corner, which never moves or goes. The degrees of a collapse pass are read from the
//! flat tables in one pass ([`EdgeTable::feature_degree_rows`]) and stay right through it.

use bevy::math::Vec3;

use crate::mesh::tables::{Connectivity, EdgeRow};

use super::EdgeTable;

/// The feature edges of the triangle mesh in `t`, by edge row: the sharp ones (on the
/// boundary, or with a dihedral angle whose cosine is under `cos_limit`: their faces' normals
/// turn by more than the feature angle), less the sides of dented triangles
/// ([`without_noise`]).
pub(super) fn feature_rows(t: &Connectivity, cos_limit: f32) -> Vec<bool> {
    let normal: Vec<Vec3> = t
        .faces()
        .map(|f| t.triangle_area_vector(f).normalize_or_zero())
        .collect();
    let sharp = t
        .edges()
        .map(|e| {
            let h = t.edge_halfedge(e);
            match (t.face(h), t.face(t.twin(h))) {
                (Some(f), Some(g)) => normal[f.index()].dot(normal[g.index()]) < cos_limit,
                _ => true,
            }
        })
        .collect();
    without_noise(t, sharp)
}

/// The sharp edges (`sharp`, by edge row: boundary edges and edges over the dihedral limit)
/// less the three sides of every dented triangle, one whose three sides are all sharp and none
/// on the boundary: scanner noise (a single triangle tilted against all its neighbours), not a
/// crease.
///
/// Kept as features, a dent's sides would pin a knot of vertices that the triangles around
/// cannot fit; a crease never dents a lone triangle. A sharp line folded back on itself (two
/// sharp edges at under 30°) looks like noise too, but real creases do that, so those stay.
/// (What this measured: `docs/remesh.md`.)
pub(super) fn without_noise(t: &Connectivity, mut sharp: Vec<bool>) -> Vec<bool> {
    let creased = |e: EdgeRow| sharp[e.index()] && !t.is_boundary_edge(e);
    let mut noise: Vec<EdgeRow> = Vec::new();
    for f in t.faces() {
        // Every face is a triangle (checked before).
        let h = t.face_halfedge(f);
        let sides = [h, t.next(h), t.prev(h)].map(|h| t.edge(h));
        if sides.iter().all(|&e| creased(e)) {
            noise.extend(sides);
        }
    }
    for e in noise {
        sharp[e.index()] = false;
    }
    sharp
}

impl EdgeTable {
    /// How many feature edges meet at each vertex (boundary edges included; 0
    /// for a free vertex, 2 on a feature line, any other count a feature corner), by vertex row,
    /// where `feature` says by edge row which edges are features. They stay right through a
    /// collapse pass: a collapse removes a free vertex, or a line vertex whose two feature
    /// edges become the survivor's one, and feature edges never merge (see
    /// [`super::collapse`]).
    pub(super) fn feature_degree_rows(&self, feature: &[bool]) -> Vec<u8> {
        let t = &self.tables;
        let mut degree = vec![0u8; t.positions.len()];
        for (&h, _) in t.edge_halfedge.iter().zip(feature).filter(|(_, f)| **f) {
            for end in [h, t.twin[h as usize]] {
                let v = t.to_vertex[end as usize] as usize;
                degree[v] = degree[v].saturating_add(1);
            }
        }
        degree
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::{MeshTables, extract};
    use crate::mesh::topology::MeshRef;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh};
    use bevy::prelude::World;

    /// The sharp edges `without_noise` keeps of `pairs` (input vertex indices) on `soup`, as
    /// the same pairs.
    fn kept_of(soup: &PolygonSoup, pairs: &[(usize, usize)]) -> Vec<(usize, usize)> {
        let mut world = World::new();
        let built = build_mesh(&mut world, soup, MeshInfo::default()).unwrap();
        let MeshTables { tables, members } = extract(&world, built.mesh);
        let m = MeshRef::new(&world);
        let v = |i: usize| built.input_vertices[i].unwrap();
        let row = |(a, b): (usize, usize)| {
            let e = m.edge(m.find_halfedge(v(a), v(b)).unwrap());
            members.edges.iter().position(|&x| x == e).unwrap()
        };
        let mut sharp = vec![false; members.edges.len()];
        for &p in pairs {
            sharp[row(p)] = true;
        }
        let kept = without_noise(&tables, sharp);
        pairs.iter().copied().filter(|&p| kept[row(p)]).collect()
    }

    #[test]
    fn dented_triangles_are_noise_lines_and_boundaries_are_not() {
        // A 4 × 4 grid: vertex (i, j) is 5 j + i. The cell at (1, 1) has the triangle
        // 6 7 12 (its rising diagonal 6 12); the line j = 3 runs 16 17 18 19; 0 1 is boundary.
        let grid = crate::mesh::shapes::grid(4, 4);
        let dent = [(6, 7), (7, 12), (12, 6)];
        let line = [(16, 17), (17, 18), (18, 19)];
        let mut all = dent.to_vec();
        all.extend(line);
        all.push((0, 1));
        let mut expected = line.to_vec();
        expected.push((0, 1));
        assert_eq!(kept_of(&grid, &all), expected);
        // Two sides of the triangle are a corner, not a dent.
        assert_eq!(kept_of(&grid, &dent[..2]), dent[..2].to_vec());
        // A triangle in the grid's corner: its two boundary sides stay, being boundary.
        assert_eq!(
            kept_of(&grid, &[(0, 1), (1, 6), (0, 6), (0, 5)]),
            vec![(0, 1), (1, 6), (0, 6), (0, 5)]
        );
    }
}
