//! Values on a mesh's vertices carried to the vertices an edit makes: a new vertex takes the
//! value at its closest point on the surface as it was before the edit, interpolated linearly
//! (barycentrically) in the triangle that point lies on.
//!
//! One rule for every operation, so that no operation needs to say what it does with a user's
//! arrays: a split's midpoint lies on its edge and gets the mean of the edge's ends; a
//! subdivision's new vertex lies near the face it came from and gets that face's blend of its
//! corners; a remeshed vertex the value of the surface under it. Vertices an edit keeps keep
//! their own values (the caller's map is by entity); this module only answers for the others.
//! A corner with no value (NaN) is left out and the other corners' weights renormalised; with
//! none left the value is NaN. A value on faces is carried the same way: a face an edit made
//! takes the value of the face its centroid lies on (a split's halves: the face they were cut
//! from), or, after an edit that declares how it lays out the faces it makes (subdivision,
//! [`FaceChildren`]), its parent's, exactly. This is the attribute transfer of remeshing pipelines
//! (Botsch et al., *Polygon Mesh Processing*, 2010, §6.5: project onto the input and
//! interpolate there).

use std::sync::OnceLock;

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::tables::extract;
use crate::mesh::{FaceId, MeshId, VertexId};
use crate::ops::declaration::FaceChildren;

use super::closest::{Reference, barycentric};
use super::surface::Surface;

/// A mesh's surface as it was, for reading values at points on it (see the module doc). Its
/// closest-point grid is built at the first read, so an edit that makes no vertex (a flip, a
/// collapse) pays only for the copy of the triangles.
pub struct SurfaceBefore {
    vertices: EntityHashSet,
    faces: EntityHashSet,
    triangles: Vec<[Vec3; 3]>,
    corners: Vec<[VertexId; 3]>,
    /// The face each triangle was cut from (each face's triangles one after another, in row
    /// order).
    triangle_face: Vec<FaceId>,
    reference: OnceLock<Reference>,
}

impl SurfaceBefore {
    /// The surface of `mesh` now, read in bulk: its faces fanned into triangles as
    /// [`Surface::from_tables`] fans them.
    pub fn of(world: &World, mesh: MeshId) -> Self {
        let read = extract(world, mesh);
        let surface = Surface::from_tables(&read.tables);
        let (vertices, faces) = (&read.members.vertices, &read.members.faces);
        Self {
            vertices: vertices.iter().map(|v| v.0).collect(),
            faces: faces.iter().map(|f| f.0).collect(),
            triangles: (0..surface.triangles.len())
                .map(|i| surface.corners(i).map(|p| p.as_vec3()))
                .collect(),
            corners: surface
                .triangles
                .iter()
                .map(|t| t.map(|row| vertices[row as usize]))
                .collect(),
            triangle_face: (surface.triangle_face.iter())
                .map(|&row| faces[row as usize])
                .collect(),
            reference: OnceLock::new(),
        }
    }

    /// Whether `v` was a vertex of the mesh then (an edit since did not make it).
    pub fn had(&self, v: VertexId) -> bool {
        self.vertices.contains(&v.0)
    }

    /// Whether `f` was a face of the mesh then.
    pub fn had_face(&self, f: FaceId) -> bool {
        self.faces.contains(&f.0)
    }

    /// The point of the surface closest to `p` and the triangle it lies on; `None` for a
    /// surface without triangles.
    fn closest(&self, p: Vec3) -> Option<(Vec3, usize)> {
        if self.triangles.is_empty() {
            return None;
        }
        let reference = self
            .reference
            .get_or_init(|| Reference::from_triangles(self.triangles.clone()));
        Some(reference.closest_on(p))
    }

    /// The face (as it was) each face of a mesh of `made` faces came from, by row, when an
    /// edit laid them out as `children` say ([`FaceChildren::parents`]); `None` when it did
    /// not.
    pub fn face_parents(&self, children: FaceChildren, made: usize) -> Option<Vec<FaceId>> {
        // Each face's sides: its fan's triangles and two.
        let mut faces: Vec<(FaceId, u32)> = Vec::new();
        for &f in &self.triangle_face {
            match faces.last_mut() {
                Some((last, sides)) if *last == f => *sides += 1,
                _ => faces.push((f, 3)),
            }
        }
        let sides: Vec<u32> = faces.iter().map(|&(_, s)| s).collect();
        let parents = children.parents(&sides, made)?;
        Some(
            parents
                .into_iter()
                .map(|row| faces[row as usize].0)
                .collect(),
        )
    }

    /// The face the point of the surface closest to `p` lies on: where a new face whose
    /// centroid is `p` came from. `None` for a surface without faces.
    pub fn face_at(&self, p: Vec3) -> Option<FaceId> {
        self.closest(p).map(|(_, t)| self.triangle_face[t])
    }

    /// The value at the point of the surface closest to `p`, interpolated from its triangle's
    /// corners' values (`value` of a corner; NaN for one without), the corners where they were
    /// when the surface was read. NaN where no corner has a value or the surface has no
    /// triangle.
    pub fn value_at(&self, p: Vec3, value: impl Fn(VertexId) -> f32) -> f32 {
        let Some((q, t)) = self.closest(p) else {
            return f32::NAN;
        };
        let weights = barycentric(q, self.triangles[t]);
        let corners = self.corners[t];
        let (mut sum, mut total) = (0.0, 0.0);
        for (v, w) in corners.into_iter().zip(weights) {
            let x = value(v);
            if !x.is_nan() {
                sum += w * x;
                total += w;
            }
        }
        if total > 0.0 { sum / total } else { f32::NAN }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, MeshRef, PolygonSoup, build_mesh};

    #[test]
    fn a_point_takes_the_linear_blend_of_its_triangles_corners() {
        let mut world = World::new();
        // A unit square as two triangles.
        let soup = PolygonSoup::from_faces(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            &[vec![0, 1, 2], vec![0, 2, 3]],
        );
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let v: Vec<VertexId> = built.input_vertices.iter().map(|v| v.unwrap()).collect();
        let surface = SurfaceBefore::of(&world, built.mesh);
        assert!(v.iter().all(|&x| surface.had(x)));
        // The value is x + 2y at the corners: linear, so any point gets x + 2y exactly.
        let value = |x: VertexId| {
            let p = MeshRef::new(&world).position(x);
            p.x + 2.0 * p.y
        };
        for (p, expected) in [
            (Vec3::new(0.5, 0.5, 0.0), 1.5),
            (Vec3::new(0.25, 0.75, 0.0), 1.75),
            // Above the square: the point below it.
            (Vec3::new(0.5, 0.0, 3.0), 0.5),
        ] {
            let got = surface.value_at(p, value);
            assert!((got - expected).abs() < 1e-6, "{p}: {got}");
        }
        // A corner without a value is left out: on the edge (0, 2) only 0 and 2 count.
        // (0.75, 0.25) is 1/4 of corner 0, 1/2 of corner 1 and 1/4 of corner 2 (value 3): the
        // two kept weigh 1/2 in all, so the value is (1/4 * 3) / (1/2).
        let some = |x: VertexId| if x == v[1] { f32::NAN } else { value(x) };
        let got = surface.value_at(Vec3::new(0.75, 0.25, 0.0), some);
        assert!((got - 1.5).abs() < 1e-6, "{got}");
        assert!(surface.value_at(Vec3::ZERO, |_| f32::NAN).is_nan());
        // The two faces: the centroid of each, and a point above, lie on their own face.
        let faces = crate::mesh::MeshMembers::collect(&world, built.mesh).faces;
        assert!(faces.iter().all(|&f| surface.had_face(f)));
        assert_eq!(
            surface.face_at(Vec3::new(2.0, 1.0, 0.0) / 3.0),
            Some(faces[0])
        );
        assert_eq!(
            surface.face_at(Vec3::new(1.0, 2.0, 5.0) / 3.0),
            Some(faces[1])
        );
        let quads = surface.face_parents(FaceChildren::PerCorner(4), 6);
        assert_eq!(quads, Some([[faces[0]; 3], [faces[1]; 3]].concat()));
        assert_eq!(surface.face_parents(FaceChildren::Each(4), 6), None);
    }
}
