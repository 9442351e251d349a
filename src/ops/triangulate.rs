//! Triangulation of polygon faces, in place.
//!
//! Each face with more than three sides is cut by ear clipping in the plane of its Newell
//! normal: at every step the ear (a convex corner whose triangle contains no other corner) with
//! the largest smallest angle is cut off, so convex quads get their better diagonal and a
//! non-convex ("dart") quad gets the diagonal from its reflex corner. A polygon with no ear (it
//! crosses itself or is degenerate) is cut as a fan from a corner.
//!
//! A diagonal must not join two corners that an edge outside the face already joins (a polygon
//! left by a dissolve or a bisection can have such a pair): that would make the edge twice. Ears
//! and fans that would are passed over; a polygon that no ear clipping and no fan can cut
//! without one is left whole, and counted in [`TriangulateSummary::left`].
//!
//! The face's own halfedges, edges and vertices are kept; each cut adds one edge (two
//! halfedges) and one face, and the original face entity becomes the first triangle. Ids of
//! everything that existed before survive.

use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;

use crate::mesh::elements::{Edge, Face, Halfedge, InMesh};
use crate::mesh::ids::{EdgeId, FaceId, HalfedgeId, MeshId};
use crate::mesh::members::{MeshMembers, of_kind};
use crate::mesh::topology::{MeshRef, newell_area_vector};

use crate::ops::Refusal;
use crate::ops::declaration::Declaration;
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

/// Triangulating every polygon: a whole-mesh edit that may run as a job.
pub const TRIANGULATE: Declaration = Declaration::new("triangulate")
    .titled("Triangulate")
    .described("triangulate every polygon")
    .on_key("Ctrl+T")
    .as_job();

/// [`triangulate`] as an operation (the `triangulate` step, Ctrl+T).
pub struct Triangulate;

impl MeshOperation for Triangulate {
    fn declaration(&self) -> &'static Declaration {
        &TRIANGULATE
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        _: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let s = triangulate(world, mesh);
        (context.progress)(1.0);
        let left = match s.left {
            0 => String::new(),
            n => format!("; {n} polygon(s) left whole: any cut would make an edge that exists"),
        };
        Ok(Applied::whole(format!(
            "{} polygon(s) cut into triangles, {} face(s) added{left}",
            s.polygons, s.added_faces
        )))
    }
}

/// What triangulating a mesh did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TriangulateSummary {
    /// Polygons (faces of more than three sides) that were cut.
    pub polygons: usize,
    /// Triangles added (each cut adds one).
    pub added_faces: usize,
    /// Polygons left whole: every way to cut them would join two corners already joined.
    pub left: usize,
}

/// Triangulates every face of `mesh` with more than three sides. Never refuses: a mesh of
/// triangles is left as it is.
pub fn triangulate(world: &mut World, mesh: MeshId) -> TriangulateSummary {
    let faces = of_kind::<Face, _>(world, mesh, FaceId);
    let mut summary = TriangulateSummary::default();
    for f in faces {
        match triangulate_face(world, mesh, f) {
            Some(0) => {}
            Some(added) => {
                summary.polygons += 1;
                summary.added_faces += added;
            }
            None => summary.left += 1,
        }
    }
    summary
}

/// Cuts one face into triangles (see the module doc) and returns how many faces were added;
/// `None` when every cut would join two corners already joined (the face is left whole).
pub fn triangulate_face(world: &mut World, mesh: MeshId, f: FaceId) -> Option<usize> {
    let m = MeshRef::new(world);
    let ring: Vec<HalfedgeId> = m.loop_from(m.prev(m.face_halfedge(f))).collect();
    let k = ring.len();
    if k <= 3 {
        return Some(0);
    }
    // ring[i] runs from corner i to corner i + 1.
    let points: Vec<Vec3> = ring.iter().map(|&h| m.position(m.from_vertex(h))).collect();
    let vertices: Vec<_> = ring.iter().map(|&h| m.from_vertex(h)).collect();
    let free = |i: usize, j: usize| m.find_halfedge(vertices[i], vertices[j]).is_none();
    let triangles = ear_clip_avoiding(&points, free)?;

    // Halfedge for each directed side (i, j) of a triangle: the ring's own, or a new diagonal.
    let allocator = world.entity_allocator();
    let mut diagonals: Vec<((usize, usize), HalfedgeId)> = Vec::new();
    let mut side = |i: usize, j: usize| -> HalfedgeId {
        if j == (i + 1) % k {
            return ring[i];
        }
        if let Some(&(_, h)) = diagonals.iter().find(|(key, _)| *key == (i, j)) {
            return h;
        }
        let h = HalfedgeId(allocator.alloc());
        diagonals.push(((i, j), h));
        h
    };
    let mut tri_halfedges = Vec::with_capacity(triangles.len());
    for &[a, b, c] in &triangles {
        tri_halfedges.push([side(a, b), side(b, c), side(c, a)]);
    }
    let new_faces: Vec<FaceId> = (1..triangles.len())
        .map(|_| FaceId(allocator.alloc()))
        .collect();
    let mut edges = Vec::new();
    for &((i, j), h) in &diagonals {
        if i < j {
            edges.push((EdgeId(allocator.alloc()), h, i, j));
        }
    }

    let member = InMesh(mesh);
    let twin_of = |i: usize, j: usize| diagonals.iter().find(|(key, _)| *key == (j, i)).unwrap().1;
    let edge_of = |i: usize, j: usize| {
        edges
            .iter()
            .find(|&&(_, _, a, b)| (a, b) == (i.min(j), i.max(j)))
            .unwrap()
            .0
    };
    let mut new_halfedges = Vec::new();
    for (t, (&[a, b, c], hs)) in triangles.iter().zip(&tri_halfedges).enumerate() {
        let face = if t == 0 { f } else { new_faces[t - 1] };
        let corners = [(a, b), (b, c), (c, a)];
        for s in 0..3 {
            let (h, next, prev) = (hs[s], hs[(s + 1) % 3], hs[(s + 2) % 3]);
            let (i, j) = corners[s];
            if j == (i + 1) % k {
                let mut x = world
                    .get_mut::<Halfedge>(h.0)
                    .expect("ring halfedge exists");
                x.next = next;
                x.prev = prev;
                x.face = Some(face);
            } else {
                new_halfedges.push((
                    h,
                    Halfedge {
                        twin: twin_of(i, j),
                        next,
                        prev,
                        vertex: vertices[j],
                        edge: edge_of(i, j),
                        face: Some(face),
                    },
                ));
            }
        }
        if t == 0 {
            world.get_mut::<Face>(f.0).expect("face exists").halfedge = hs[0];
        } else {
            spawn(world, face.0, (Face { halfedge: hs[0] }, member));
            let group = crate::mesh::groups::face_group(world, f);
            crate::mesh::groups::set_face_group(world, face, group);
        }
    }
    for (h, x) in new_halfedges {
        spawn(world, h.0, (x, member));
    }
    for (e, h, _, _) in edges {
        spawn(world, e.0, (Edge { halfedge: h }, member));
    }
    Some(triangles.len() - 1)
}

fn spawn<B: bevy::prelude::Bundle>(world: &mut World, e: bevy::prelude::Entity, bundle: B) {
    if let Err(error) = world.spawn_at(e, bundle) {
        unreachable!("spawning freshly allocated {e} failed: {error}");
    }
}

/// Triangles (as corner indices, counter-clockwise) covering a polygon given by its corners.
/// See the module doc for the rule.
pub fn ear_clip(points: &[Vec3]) -> Vec<[usize; 3]> {
    ear_clip_avoiding(points, |_, _| true).unwrap_or_default()
}

/// [`ear_clip`], making a diagonal between corners `i` and `j` only where `free(i, j)`; `None`
/// when no ear clipping and no fan can.
pub fn ear_clip_avoiding(
    points: &[Vec3],
    free: impl Fn(usize, usize) -> bool,
) -> Option<Vec<[usize; 3]>> {
    let k = points.len();
    let normal = newell_area_vector(points);
    if k < 3 {
        return Some(Vec::new());
    }
    let Some(n) = normal.try_normalize() else {
        return fan_avoiding(k, &free);
    };
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let flat: Vec<Vec2> = points
        .iter()
        .map(|&p| Vec2::new(p.dot(u), p.dot(v)))
        .collect();

    let mut left: Vec<usize> = (0..k).collect();
    let mut out = Vec::with_capacity(k - 2);
    while left.len() > 3 {
        let m = left.len();
        let mut best: Option<(usize, f32)> = None;
        for i in 0..m {
            let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
            if !free(a, c) || !is_ear(&flat, &left, a, b, c) {
                continue;
            }
            let quality = min_angle(flat[a], flat[b], flat[c]);
            if best.is_none_or(|(_, q)| quality > q) {
                best = Some((i, quality));
            }
        }
        let Some((i, _)) = best else {
            return fan_avoiding(k, &free);
        };
        out.push([left[(i + m - 1) % m], left[i], left[(i + 1) % m]]);
        left.remove(i);
    }
    out.push([left[0], left[1], left[2]]);
    Some(out)
}

/// A fan from the first corner whose diagonals are all free, if any.
fn fan_avoiding(k: usize, free: &impl Fn(usize, usize) -> bool) -> Option<Vec<[usize; 3]>> {
    let apex = (0..k).find(|&r| (2..k - 1).all(|d| free(r, (r + d) % k)))?;
    Some(
        (1..k - 1)
            .map(|i| [apex, (apex + i) % k, (apex + i + 1) % k])
            .collect(),
    )
}

fn cross(o: Vec2, a: Vec2, b: Vec2) -> f32 {
    (a - o).perp_dot(b - o)
}

fn is_ear(flat: &[Vec2], left: &[usize], a: usize, b: usize, c: usize) -> bool {
    let (pa, pb, pc) = (flat[a], flat[b], flat[c]);
    if cross(pa, pb, pc) <= 0.0 {
        return false;
    }
    left.iter().all(|&x| {
        if x == a || x == b || x == c {
            return true;
        }
        let p = flat[x];
        // Outside, or on the boundary only at a shared position.
        !(cross(pa, pb, p) >= 0.0 && cross(pb, pc, p) >= 0.0 && cross(pc, pa, p) >= 0.0)
    })
}

fn min_angle(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    let angle = |p: Vec2, q: Vec2, r: Vec2| (q - p).angle_to(r - p).abs();
    angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b))
}

/// Counts the faces of `mesh` that are not triangles.
pub fn non_triangle_faces(world: &World, mesh: MeshId) -> usize {
    let m = MeshRef::new(world);
    MeshMembers::collect(world, mesh)
        .faces
        .iter()
        .filter(|&&f| m.face_degree(f) != 3)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dissolved_tetrahedron_is_cut_back_along_the_dissolved_edge() {
        // Dissolving an edge of a tetrahedron leaves a quad whose other diagonal is an edge
        // already: the only valid cut is the one the dissolve removed.
        use crate::mesh::{MeshInfo, build_mesh, shapes, validate};
        for (a, b) in [(0usize, 1usize), (0, 2), (1, 3)] {
            let mut world = World::new();
            let built =
                build_mesh(&mut world, &shapes::tetrahedron(), MeshInfo::default()).unwrap();
            let (va, vb) = (
                built.input_vertices[a].unwrap(),
                built.input_vertices[b].unwrap(),
            );
            let m = MeshRef::new(&world);
            let e = m.edge(m.find_halfedge(va, vb).unwrap());
            crate::ops::local::dissolve_edge(&mut world, e).unwrap();
            let s = triangulate(&mut world, built.mesh);
            assert_eq!((s.polygons, s.added_faces, s.left), (1, 1, 0));
            validate(&world, built.mesh).unwrap();
            assert_eq!(non_triangle_faces(&world, built.mesh), 0);
            assert!(MeshRef::new(&world).find_halfedge(va, vb).is_some());
        }
    }

    #[test]
    fn diagonals_that_are_not_free_are_avoided_or_the_polygon_is_left() {
        let square = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        // 0–2 taken: the cut is 1–3.
        let t = ear_clip_avoiding(&square, |i, j| (i.min(j), i.max(j)) != (0, 2)).unwrap();
        assert!(
            t.iter().all(|tri| tri.contains(&1) && tri.contains(&3)),
            "{t:?}"
        );
        // Both taken: no cut.
        assert_eq!(ear_clip_avoiding(&square, |_, _| false), None);
    }

    #[test]
    fn convex_quad_takes_the_diagonal_with_better_angles() {
        // A rhombus: the short diagonal gives two wide triangles.
        let p = [
            Vec3::new(-2.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let t = ear_clip(&p);
        assert_eq!(t.len(), 2);
        assert!(
            t.iter().all(|tri| tri.contains(&1) && tri.contains(&3)),
            "{t:?}"
        );
    }

    #[test]
    fn dart_quad_is_cut_from_its_reflex_corner() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, -1.0, 0.0),
            Vec3::new(0.5, 0.0, 0.0), // reflex
            Vec3::new(2.0, 1.0, 0.0),
        ];
        let t = ear_clip(&p);
        assert!(
            t.iter().all(|tri| tri.contains(&0) && tri.contains(&2)),
            "{t:?}"
        );
    }

    #[test]
    fn polygon_gives_k_minus_two_triangles_of_the_same_orientation() {
        let k = 7;
        let p: Vec<Vec3> = (0..k)
            .map(|i| {
                let a = i as f32 / k as f32 * std::f32::consts::TAU;
                Vec3::new(a.cos(), a.sin(), 0.0) * if i % 2 == 0 { 1.0 } else { 0.6 }
            })
            .collect();
        let t = ear_clip(&p);
        assert_eq!(t.len(), k - 2);
        let area: f32 = t
            .iter()
            .map(|&[a, b, c]| (p[b] - p[a]).cross(p[c] - p[a]).z)
            .sum();
        let polygon = newell_area_vector(&p).z;
        assert!((area - polygon).abs() < 1e-4, "{area} vs {polygon}");
    }
}
