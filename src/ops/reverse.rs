//! Reversing a mesh's orientation (Blender's Flip Normals, MeshLab's Invert Faces
//! Orientation): every face's corners in the opposite order, so every normal points the other
//! way — what a mesh read inside out (its faces wound clockwise) needs.
//!
//! On the halfedges, each one turns round: it runs from its old tip back to its old start, so
//! its `vertex` becomes its old `from_vertex` and `next` and `prev` swap; twins, edges and faces
//! stay. A vertex's outgoing halfedge becomes the twin of its old one, then its boundary one
//! where it has a boundary (the invariant [`fn@crate::mesh::validate`] checks). A corner's UV, kept
//! on the halfedge into the corner, moves to the halfedge that now runs into it (the old
//! `prev`); vertex normals change sign; seams and face groups stay where they are.
//!
//! Every id survives and V, E, F and χ do not change; reversing twice gives back the same
//! links, UVs and normals, bit for bit. It never refuses.
//!
//! [`orient_outward`] (Blender's Recalculate Outside) turns only the parts that face inward:
//! each set of faces joined across edges whose signed volume about its centroid is negative.

use bevy::math::{DVec3, Vec2};
use bevy::prelude::World;

use crate::mesh::attributes::{CornerUv, VertexNormal};
use crate::mesh::elements::{Face, Halfedge, Vertex};
use crate::mesh::ids::{FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::Declaration;
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values, count};

/// Reversing the orientation: a whole-mesh edit (every halfedge turns round) that keeps every
/// id and attribute, done in one pass, never a job.
pub const REVERSE: Declaration = Declaration::new("reverse")
    .titled("Reverse orientation")
    .described("reverse the orientation: every face turned round, its normal the other way")
    .on_key("Alt+N")
    .keeping_normals();

/// [`reverse_orientation`] as an operation (the `reverse` step, Alt+N).
pub struct Reverse;

impl MeshOperation for Reverse {
    fn declaration(&self) -> &'static Declaration {
        &REVERSE
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        _: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let turned = reverse_orientation(world, mesh).faces;
        Ok(Applied::whole(format!(
            "{} turned round",
            count(turned, "face")
        )))
    }
}

/// What reversing a mesh did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReverseSummary {
    /// Faces turned round (all of them).
    pub faces: usize,
}

/// Orienting every part outward (Blender's Recalculate Outside): a whole-mesh edit that
/// keeps every id and attribute.
pub const ORIENT_OUTSIDE: Declaration = Declaration::new("orient-outside")
    .titled("Orient outside")
    .described("orient outside: turn round each part whose faces point inward")
    .on_key("Shift+N");

/// [`orient_outward`] as an operation (the `orient-outside` step, Shift+N).
pub struct OrientOutside;

impl MeshOperation for OrientOutside {
    fn declaration(&self) -> &'static Declaration {
        &ORIENT_OUTSIDE
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        _: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        Ok(Applied::whole(orient_outward(world, mesh).describe()))
    }
}

/// What orienting a mesh's parts outward did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OrientSummary {
    /// Parts (faces joined across edges) of the mesh.
    pub parts: usize,
    /// Parts that faced inward and were turned round.
    pub turned: usize,
    /// Parts too flat or too open to tell which way they face, left as they were.
    pub undecided: usize,
    /// Faces turned round.
    pub faces: usize,
}

impl OrientSummary {
    /// The summary's line: "no part faces inward (3 parts)", "1 of 2 parts turned outward
    /// (40 faces turned round)", and the open parts left as found, if any.
    pub fn describe(&self) -> String {
        let turned = match self.turned {
            0 => format!("no part faces inward ({})", count(self.parts, "part")),
            n => format!(
                "{n} of {} turned outward ({} turned round)",
                count(self.parts, "part"),
                count(self.faces, "face")
            ),
        };
        match self.undecided {
            0 => turned,
            n => format!(
                "{turned}; {} left as found (no clear inside)",
                count(n, "open part")
            ),
        }
    }
}

/// Reverses the orientation of every face of `mesh` (see the module doc).
pub fn reverse_orientation(world: &mut World, mesh: MeshId) -> ReverseSummary {
    let members = MeshMembers::collect(world, mesh);
    turn(world, &members.halfedges, &members.vertices);
    ReverseSummary {
        faces: members.faces.len(),
    }
}

/// Turns round each part of `mesh` (a set of faces joined across edges) whose signed volume,
/// measured about the part's centroid, is negative: its faces pointed inward. A closed part
/// faces outward exactly when that volume is positive (it is left as it is when the volume is
/// nought to within 1e-9 of the cube of its bounding box's diagonal: flat). An open part has
/// no inside, so it is judged only when it clearly wraps round its centroid — a scan with
/// holes, a bowl: a volume of at least 1 % of that cube — and otherwise left as it is (a
/// strip or a gently curved patch could face either way).
pub fn orient_outward(world: &mut World, mesh: MeshId) -> OrientSummary {
    let faces = crate::mesh::members::of_kind::<Face, _>(world, mesh, FaceId);
    let parts = parts(world, &faces);
    let mut summary = OrientSummary {
        parts: parts.len(),
        ..OrientSummary::default()
    };
    for part in &parts {
        match signed_volume(world, part) {
            None => {
                summary.undecided += 1;
                continue;
            }
            Some(volume) if volume > 0.0 => continue,
            Some(_) => {}
        }
        // Whole parts only: every halfedge of the part's faces, and the boundary ones beside.
        let (halfedges, vertices) = {
            let m = MeshRef::new(world);
            let mut halfedges = Vec::new();
            let mut seen = bevy::ecs::entity::EntityHashSet::default();
            let mut vertices = Vec::new();
            for &f in part {
                for h in m.face_halfedges(f) {
                    halfedges.push(h);
                    let t = m.twin(h);
                    if m.face(t).is_none() {
                        halfedges.push(t);
                    }
                    let v = m.to_vertex(h);
                    if seen.insert(v.0) {
                        vertices.push(v);
                    }
                }
            }
            (halfedges, vertices)
        };
        turn(world, &halfedges, &vertices);
        summary.turned += 1;
        summary.faces += part.len();
    }
    summary
}

/// The parts of a mesh: its faces grouped by whether they are joined across edges.
fn parts(world: &World, faces: &[FaceId]) -> Vec<Vec<FaceId>> {
    let m = MeshRef::new(world);
    let mut seen = bevy::ecs::entity::EntityHashSet::default();
    let mut parts = Vec::new();
    for &start in faces {
        if !seen.insert(start.0) {
            continue;
        }
        let mut part = vec![start];
        let mut i = 0;
        while i < part.len() {
            for h in m.face_halfedges(part[i]) {
                if let Some(g) = m.face(m.twin(h))
                    && seen.insert(g.0)
                {
                    part.push(g);
                }
            }
            i += 1;
        }
        parts.push(part);
    }
    parts
}

/// The signed volume the faces of `part` enclose about their corners' centroid (each polygon
/// as a fan), in f64; `None` when it is too small, against the cube of the bounding box's
/// diagonal, to tell which way the part faces (see [`orient_outward`]).
fn signed_volume(world: &World, part: &[FaceId]) -> Option<f64> {
    let m = MeshRef::new(world);
    let open = part
        .iter()
        .any(|&f| m.face_halfedges(f).any(|h| m.face(m.twin(h)).is_none()));
    let corners: Vec<Vec<DVec3>> = part
        .iter()
        .map(|&f| {
            m.face_vertices(f)
                .map(|v| m.position(v).as_dvec3())
                .collect()
        })
        .collect();
    let count = corners.iter().map(Vec::len).sum::<usize>().max(1);
    let centre = corners.iter().flatten().sum::<DVec3>() / count as f64;
    let (mut low, mut high) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
    let mut volume = 0.0;
    for face in &corners {
        for p in face {
            low = low.min(*p);
            high = high.max(*p);
        }
        let a = face[0] - centre;
        for pair in face[1..].windows(2) {
            volume += a.dot((pair[0] - centre).cross(pair[1] - centre)) / 6.0;
        }
    }
    let scale = (high - low).length().powi(3);
    let telling = if open { 1e-2 } else { 1e-9 };
    (volume.abs() >= telling * scale).then_some(volume)
}

/// Turns round `halfedges` (each face halfedge of some faces and the boundary halfedges beside
/// them) and points each of `vertices` (their corners) at an outgoing halfedge of the result.
fn turn(world: &mut World, halfedges: &[HalfedgeId], vertices: &[VertexId]) {
    // Everything read before anything changes: each halfedge's new links, and the UV of the
    // corner it will run into.
    let turned: Vec<(HalfedgeId, Halfedge, Option<Vec2>)> = {
        let m = MeshRef::new(world);
        halfedges
            .iter()
            .map(|&h| {
                let old = *m.halfedge(h);
                let links = Halfedge {
                    next: old.prev,
                    prev: old.next,
                    vertex: m.halfedge(old.twin).vertex,
                    ..old
                };
                let uv = world.get::<CornerUv>(old.prev.0).map(|c| c.0);
                (h, links, uv)
            })
            .collect()
    };
    for (h, links, uv) in turned {
        if let Some(mut x) = world.get_mut::<Halfedge>(h.0) {
            *x = links;
        }
        if let (Some(uv), Some(_)) = (uv, links.face) {
            world.entity_mut(h.0).insert(CornerUv(uv));
        }
    }
    for &v in vertices {
        turn_vertex(world, v);
    }
}

/// Points `v` at an outgoing halfedge of the reversed mesh (its boundary one, if it has one)
/// and turns its normal round.
fn turn_vertex(world: &mut World, v: VertexId) {
    let out = {
        let m = MeshRef::new(world);
        let start = m.twin(m.vertex_halfedge(v));
        m.vertex_outgoing_from(start)
            .find(|&h| m.is_boundary(h))
            .unwrap_or(start)
    };
    if let Some(mut vertex) = world.get_mut::<Vertex>(v.0) {
        vertex.halfedge = out;
    }
    if let Some(mut normal) = world.get_mut::<VertexNormal>(v.0) {
        normal.0 = -normal.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh, mesh_stats, shapes, validate};
    use bevy::math::Vec3;

    /// A grid with holes (so with boundaries), each corner's UV its position's x and y and each
    /// vertex's normal its position plus z, built into a world of its own.
    fn holed_grid_with_attributes() -> (World, crate::mesh::BuiltMesh) {
        let mut soup = shapes::grid_with_holes(2);
        soup.corner_uvs = Some(
            soup.indices
                .iter()
                .map(|&i| soup.positions[i as usize].truncate())
                .collect(),
        );
        soup.vertex_normals = Some(soup.positions.iter().map(|p| *p + Vec3::Z).collect());
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        (world, built)
    }

    /// Each face's corners and their UVs, in order from the face's halfedge.
    fn corners(world: &World, f: FaceId) -> Vec<(VertexId, Option<Vec2>)> {
        let m = MeshRef::new(world);
        m.face_halfedges(f)
            .map(|h| (m.to_vertex(h), world.get::<CornerUv>(h.0).map(|c| c.0)))
            .collect()
    }

    /// The same cycle read backwards: `b` is `a` reversed, up to where it starts.
    fn is_reversed_cycle<T: PartialEq + Copy>(a: &[T], b: &[T]) -> bool {
        let reversed: Vec<T> = a.iter().rev().copied().collect();
        (0..b.len()).any(|shift| (0..b.len()).all(|i| b[(i + shift) % b.len()] == reversed[i]))
    }

    #[test]
    fn every_face_turns_round_with_its_uvs_and_the_mesh_stays_valid() {
        let (mut world, built) = holed_grid_with_attributes();
        let mesh = built.mesh;
        let members = MeshMembers::collect(&world, mesh);
        let before_stats = mesh_stats(&world, mesh);
        let before: Vec<_> = members.faces.iter().map(|&f| corners(&world, f)).collect();
        let normals_before: Vec<Vec3> = {
            let m = MeshRef::new(&world);
            members
                .faces
                .iter()
                .map(|&f| m.face_area_vector(f))
                .collect()
        };
        let summary = reverse_orientation(&mut world, mesh);
        assert_eq!(summary.faces, members.faces.len());
        validate(&world, mesh).unwrap();
        let after_stats = mesh_stats(&world, mesh);
        assert_eq!(
            (after_stats.vertices, after_stats.edges, after_stats.faces),
            (
                before_stats.vertices,
                before_stats.edges,
                before_stats.faces
            )
        );
        assert_eq!(
            after_stats.euler_characteristic,
            before_stats.euler_characteristic
        );
        assert_eq!(after_stats.boundary_loops, before_stats.boundary_loops);
        let m = MeshRef::new(&world);
        for (i, &f) in members.faces.iter().enumerate() {
            // Each corner keeps its UV: the (vertex, UV) pairs run the other way round.
            assert!(is_reversed_cycle(&before[i], &corners(&world, f)), "{f}");
            let (now, then) = (m.face_area_vector(f), normals_before[i]);
            assert!(
                (now + then).length() <= 1e-6 * then.length(),
                "{f}: {now} {then}"
            );
        }
        for &v in &members.vertices {
            let p = m.position(v);
            assert_eq!(world.get::<VertexNormal>(v.0).unwrap().0, -(p + Vec3::Z));
        }
    }

    #[test]
    fn reversing_twice_gives_back_every_link_bit_for_bit() {
        let (mut world, built) = holed_grid_with_attributes();
        let members = MeshMembers::collect(&world, built.mesh);
        let snapshot = |world: &World| {
            let links: Vec<Halfedge> = members
                .halfedges
                .iter()
                .map(|&h| *world.get::<Halfedge>(h.0).unwrap())
                .collect();
            let uvs: Vec<Option<Vec2>> = members
                .halfedges
                .iter()
                .map(|&h| world.get::<CornerUv>(h.0).map(|c| c.0))
                .collect();
            let normals: Vec<Vec3> = members
                .vertices
                .iter()
                .map(|&v| world.get::<VertexNormal>(v.0).unwrap().0)
                .collect();
            (links, uvs, normals)
        };
        let before = snapshot(&world);
        reverse_orientation(&mut world, built.mesh);
        assert_ne!(snapshot(&world).0, before.0);
        reverse_orientation(&mut world, built.mesh);
        validate(&world, built.mesh).unwrap();
        let after = snapshot(&world);
        assert_eq!(after.0, before.0);
        assert_eq!(after.1, before.1);
        assert_eq!(after.2, before.2);
    }

    /// Two cubes side by side, the second with every face wound the other way (inside out).
    fn cube_and_inverted_cube() -> PolygonSoup {
        let cube = shapes::cube();
        let mut soup = cube.clone();
        let offset = soup.positions.len() as u32;
        soup.positions
            .extend(cube.positions.iter().map(|p| *p + Vec3::new(3.0, 0.0, 0.0)));
        for w in cube.face_starts.windows(2) {
            let face = &cube.indices[w[0] as usize..w[1] as usize];
            soup.indices.extend(face.iter().rev().map(|&i| i + offset));
            soup.face_starts.push(soup.indices.len() as u32);
        }
        soup
    }

    /// Whether every face of `mesh` points away from the centre of its part (each cube's).
    fn every_face_points_out(world: &World, mesh: MeshId) -> bool {
        let m = MeshRef::new(world);
        MeshMembers::collect(world, mesh).faces.iter().all(|&f| {
            let c = m.face_centroid(f);
            let centre = if c.x > 1.5 {
                Vec3::new(3.0, 0.0, 0.0)
            } else {
                Vec3::ZERO
            };
            m.face_area_vector(f).dot(c - centre) > 0.0
        })
    }

    #[test]
    fn only_the_parts_that_face_inward_are_turned() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &cube_and_inverted_cube(), MeshInfo::default()).unwrap();
        let mesh = built.mesh;
        assert!(!every_face_points_out(&world, mesh));
        let summary = orient_outward(&mut world, mesh);
        assert_eq!(
            summary,
            OrientSummary {
                parts: 2,
                turned: 1,
                undecided: 0,
                faces: 6
            }
        );
        validate(&world, mesh).unwrap();
        assert!(every_face_points_out(&world, mesh));
        // Outward already: nothing to turn.
        assert_eq!(orient_outward(&mut world, mesh).turned, 0);
        // Inside out as a whole: both turned back.
        reverse_orientation(&mut world, mesh);
        assert_eq!(orient_outward(&mut world, mesh).turned, 2);
        validate(&world, mesh).unwrap();
        assert!(every_face_points_out(&world, mesh));
    }

    #[test]
    fn a_flat_part_is_left_as_it_is_and_said_undecided() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(4, 4), MeshInfo::default()).unwrap();
        let undecided = OrientSummary {
            parts: 1,
            undecided: 1,
            ..OrientSummary::default()
        };
        assert_eq!(orient_outward(&mut world, built.mesh), undecided);
        reverse_orientation(&mut world, built.mesh);
        assert_eq!(orient_outward(&mut world, built.mesh), undecided);
    }
}
