//! The part of a mesh a local solve needs: the triangles whose operator rows reach free
//! vertices, as a [`Surface`] of its own.
//!
//! Row `i` of the k-harmonic operator `L (M⁻¹ L)^(k−1)` reads the one-rings (weights and mixed
//! areas) of the vertices up to `k − 1` rings from `i`. So the faces around the vertices within
//! `k − 1` rings of the free ones give every free row exactly as the whole mesh would, and the
//! solve costs the size of that neighbourhood, not of the mesh.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::math::DVec3;
use bevy::prelude::World;

use crate::mesh::ids::{FaceId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::geometry::Surface;

/// A neighbourhood of free vertices, ready to solve.
pub struct Region {
    /// Its triangles (polygons fanned from their first corner), by local vertex index.
    pub surface: Surface,
    /// The vertex behind each local index.
    pub vertices: Vec<VertexId>,
    /// Whether each local vertex is held (every vertex that is not free, and a free one with no
    /// face: it has no operator row).
    pub held: Vec<bool>,
}

impl Region {
    /// The neighbourhood of the live vertices in `free` for the k-harmonic operator.
    pub fn around(world: &World, free: &[VertexId], k: u32) -> Self {
        let m = MeshRef::new(world);
        let free_set: EntityHashSet = free.iter().map(|v| v.0).collect();
        let mut reached: EntityHashSet = free_set.clone();
        let mut front: Vec<VertexId> = free.to_vec();
        for _ in 1..k.max(1) {
            let mut next = Vec::new();
            for &v in &front {
                for u in m.vertex_neighbors(v) {
                    if reached.insert(u.0) {
                        next.push(u);
                    }
                }
            }
            front = next;
        }
        let mut faces: Vec<FaceId> = Vec::new();
        let mut seen_faces = EntityHashSet::default();
        for &v in reached
            .iter()
            .map(|e| VertexId(*e))
            .collect::<Vec<_>>()
            .iter()
        {
            for f in m.vertex_faces(v) {
                if seen_faces.insert(f.0) {
                    faces.push(f);
                }
            }
        }
        faces.sort_unstable();
        let mut index: EntityHashMap<u32> = EntityHashMap::default();
        let mut vertices: Vec<VertexId> = Vec::new();
        let mut local = |v: VertexId| -> u32 {
            *index.entry(v.0).or_insert_with(|| {
                vertices.push(v);
                vertices.len() as u32 - 1
            })
        };
        let mut triangles = Vec::new();
        let mut triangle_face = Vec::new();
        for (fi, &f) in faces.iter().enumerate() {
            // Fanned from the face's halfedge's tail, as the whole mesh's surface is.
            let corners: Vec<u32> = m
                .face_halfedges(f)
                .map(|h| local(m.from_vertex(h)))
                .collect();
            for w in 1..corners.len().saturating_sub(1) {
                triangles.push([corners[0], corners[w], corners[w + 1]]);
                triangle_face.push(fi as u32);
            }
        }
        let positions: Vec<DVec3> = vertices.iter().map(|&v| m.position(v).as_dvec3()).collect();
        let boundary = vertices.iter().map(|&v| m.is_boundary_vertex(v)).collect();
        let held = vertices.iter().map(|v| !free_set.contains(&v.0)).collect();
        Self {
            surface: Surface {
                positions,
                triangles,
                triangle_face,
                boundary,
            },
            vertices,
            held,
        }
    }
}
