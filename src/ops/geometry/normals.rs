//! Normals of faces and vertices.
//!
//! - A **face normal** is the unit direction of the face's area vector (the sum of its fan
//!   triangles' cross products: Newell's normal for a planar polygon, its best plane's for a
//!   warped one).
//! - A **vertex normal weighted by angle** (Thürmer & Wüthrich, "Computing vertex normals from
//!   polygonal facets", 1998) sums the normals of the faces around the vertex, each times the
//!   face's angle at the vertex: it does not change when a face is cut into more triangles, which
//!   the area- and count-weighted normals do.
//! - A **vertex normal weighted by area** sums the faces' area vectors (each face counts by its
//!   area): cheaper, and what most loaders compute.
//!
//! Degenerate faces and isolated vertices have the zero vector, never NaN.

use bevy::math::DVec3;

use super::surface::Surface;

/// How vertex normals weigh the faces around a vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalWeighting {
    /// By the face's angle at the vertex (Thürmer & Wüthrich 1998). The default.
    #[default]
    Angle,
    /// By the face's area.
    Area,
}

/// The area vector of each face (twice its area, along its normal), by face row; `faces` is
/// the number of faces (a face of the mesh with no triangle keeps the zero vector).
fn face_area_vectors(s: &Surface, faces: usize) -> Vec<DVec3> {
    let mut v = vec![DVec3::ZERO; faces];
    for (t, &f) in s.triangle_face.iter().enumerate() {
        let [a, b, c] = s.corners(t);
        v[f as usize] += (b - a).cross(c - a);
    }
    v
}

/// The unit normal of each face, by face row (zero for a degenerate face).
pub fn face_normals(s: &Surface, faces: usize) -> Vec<DVec3> {
    face_area_vectors(s, faces)
        .into_iter()
        .map(DVec3::normalize_or_zero)
        .collect()
}

/// The unit vertex normals, weighted as asked (zero for a vertex with no face).
pub fn vertex_normals(s: &Surface, weighting: NormalWeighting) -> Vec<DVec3> {
    match weighting {
        NormalWeighting::Angle => vertex_normals_by_angle(s),
        NormalWeighting::Area => {
            let faces = s.triangle_face.iter().max().map_or(0, |&f| f as usize + 1);
            let area = face_area_vectors(s, faces);
            let mut n = vec![DVec3::ZERO; s.vertex_count()];
            for (tri, &f) in s.triangles.iter().zip(&s.triangle_face) {
                // Each face counts once at each of its corners: its first triangle carries the
                // corners it has, the others only their new far corner.
                for &v in tri {
                    n[v as usize] += area[f as usize];
                }
            }
            dedupe_fan_corners(s, &area, &mut n);
            n.into_iter().map(DVec3::normalize_or_zero).collect()
        }
    }
}

/// A fanned polygon touches its apex with every triangle and its inner corners with two: take
/// the extra counts back off, so each face adds its area vector once at each of its corners.
fn dedupe_fan_corners(s: &Surface, area: &[DVec3], n: &mut [DVec3]) {
    let mut t = 0;
    while t < s.triangles.len() {
        let f = s.triangle_face[t];
        let mut end = t + 1;
        while end < s.triangles.len() && s.triangle_face[end] == f {
            end += 1;
        }
        for k in t + 1..end {
            // Triangle k shares the apex and its first side's far corner with triangle k − 1.
            let [apex, b, _] = s.triangles[k];
            n[apex as usize] -= area[f as usize];
            n[b as usize] -= area[f as usize];
        }
        t = end;
    }
}

/// The angle-weighted unit vertex normals (Thürmer & Wüthrich 1998): each face's unit normal
/// times its angle at the vertex. A polygon's fan adds up to its corner angles, each with the
/// polygon's own normal.
pub fn vertex_normals_by_angle(s: &Surface) -> Vec<DVec3> {
    let faces = s.triangle_face.iter().max().map_or(0, |&f| f as usize + 1);
    let normal = face_normals(s, faces);
    let mut n = vec![DVec3::ZERO; s.vertex_count()];
    for (t, (tri, &f)) in s.triangles.iter().zip(&s.triangle_face).enumerate() {
        let p = s.corners(t);
        for k in 0..3 {
            let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
            if angle.is_finite() {
                n[tri[k] as usize] += angle * normal[f as usize];
            }
        }
    }
    n.into_iter().map(DVec3::normalize_or_zero).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use crate::ops::geometry::surface::of_soup as surface;
    use bevy::prelude::World;

    #[test]
    fn a_cube_corner_normal_points_along_the_diagonal_either_way() {
        let s = surface(&shapes::cube());
        for weighting in [NormalWeighting::Angle, NormalWeighting::Area] {
            for (i, n) in vertex_normals(&s, weighting).iter().enumerate() {
                let diagonal = s.positions[i].normalize();
                assert!((n.dot(diagonal) - 1.0).abs() < 1e-12, "{weighting:?}: {n}");
            }
        }
        let faces = face_normals(&s, 6);
        assert!(faces.iter().all(|n| (n.length() - 1.0).abs() < 1e-12));
        assert!(faces.iter().all(|n| n.abs().max_element() == 1.0));
    }

    #[test]
    fn angle_weights_do_not_change_when_a_quad_is_cut() {
        // One vertex between a quad and two triangles: cutting the quad changes the area-count
        // of the faces around it, not their angles.
        let quads = surface(&shapes::quad_grid(2, 2));
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::quad_grid(2, 2), MeshInfo::default()).unwrap();
        crate::ops::triangulate::triangulate(&mut world, built.mesh);
        let triangles = Surface::from_tables(&extract(&world, built.mesh).tables);
        let a = vertex_normals_by_angle(&quads);
        let b = vertex_normals_by_angle(&triangles);
        for (x, y) in a.iter().zip(&b) {
            assert!((*x - *y).length() < 1e-12);
        }
    }
}
