//! The triangles of a mesh as flat arrays in `f64`: what the discrete differential geometry of
//! [`mod@super::curvature`], [`super::normals`] and the smoothing operators is computed on.
//!
//! Polygons are fanned from their first corner (a quad gives two triangles); each triangle
//! remembers the face it came from. Vertices are the mesh's table rows (see
//! [`crate::mesh::tables::extract`]), so a value computed here belongs to the vertex entity of
//! the same row. Boundary vertices are flagged: the operators that need a closed one-ring treat
//! them apart, and say how.

use bevy::math::DVec3;

use crate::mesh::tables::Connectivity;

/// A mesh's triangles (polygons fanned), positions in `f64`, boundary vertices flagged.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// Vertex positions, by table row.
    pub positions: Vec<DVec3>,
    /// Triangles as vertex rows, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// The face (table row) each triangle was cut from.
    pub triangle_face: Vec<u32>,
    /// Whether each vertex is on the boundary.
    pub boundary: Vec<bool>,
}

impl Surface {
    /// The triangles of the mesh held in `t` (polygons fanned from their first corner).
    pub fn from_tables(t: &Connectivity) -> Self {
        let corners = t.halfedges().filter(|&h| !t.is_boundary(h)).count();
        let mut triangles = Vec::with_capacity(corners.saturating_sub(2 * t.face_count()));
        let mut triangle_face = Vec::with_capacity(triangles.capacity());
        for f in t.faces() {
            let first = t.face_halfedge(f);
            let apex = t.from_vertex(first);
            let mut h = first;
            loop {
                let next = t.next(h);
                if t.next(next) == first {
                    break;
                }
                triangles.push([apex.get(), t.to_vertex(h).get(), t.to_vertex(next).get()]);
                triangle_face.push(f.get());
                h = next;
            }
        }
        Self {
            positions: t.positions.iter().map(|p| p.as_dvec3()).collect(),
            triangles,
            triangle_face,
            boundary: t.vertices().map(|v| t.is_boundary_vertex(v)).collect(),
        }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The three corners of triangle `t`.
    #[inline]
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }
}

/// The surface of `soup` built into a fresh world (for the tests of this module's siblings).
#[cfg(test)]
pub(crate) fn of_soup(soup: &crate::mesh::PolygonSoup) -> Surface {
    let mut world = bevy::prelude::World::new();
    let built = crate::mesh::build_mesh(&mut world, soup, crate::mesh::MeshInfo::default())
        .expect("a test shape builds");
    Surface::from_tables(&crate::mesh::tables::extract(&world, built.mesh).tables)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use bevy::prelude::World;

    #[test]
    fn quads_are_fanned_into_two_triangles_each_and_boundaries_flagged() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::quad_grid(3, 2), MeshInfo::default()).unwrap();
        let s = Surface::from_tables(&extract(&world, built.mesh).tables);
        assert_eq!(s.triangles.len(), 2 * 6);
        assert_eq!(s.triangle_face.iter().filter(|&&f| f == 0).count(), 2);
        // A 3×2 grid of quads has 4×3 vertices, of which the 2 in the middle row are inside.
        assert_eq!(s.boundary.iter().filter(|&&b| !b).count(), 2);
        // Fanning keeps the orientation: every triangle faces the way its quad does.
        for t in 0..s.triangles.len() {
            let [a, b, c] = s.corners(t);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }
}
