//! Inset faces, each on its own (Scotty3D's "bevel face"): every selected face shrinks into a
//! copy of itself inside a ring of quads.
//!
//! ```text
//!   d -------- c            d ------------------ c
//!   |          |            | \                / |
//!   |    f     |     →      |  d' ---------- c'  |     f keeps its id, on the new inner
//!   |          |            |  |      f      |   |     loop a' b' c' d'; each side a b of f
//!   a -------- b            |  a' ---------- b'  |     gets the quad a b b' a'
//!                           | /                \ |
//!                           a ------------------ b
//! ```
//!
//! A face of degree `k` gets `k` new vertices, `2k` new edges and `k` new quads; χ and the
//! boundary loops are unchanged. The inset of one face is the extrusion of a one-face region
//! ([`super::extrude_faces`]) with other positions, and is built by the same code: the face and
//! its halfedges are reused (its corners keep their UVs), each old side edge stays as the
//! bottom of its quad, with whatever was across it (another face, the boundary, or the quad of
//! a neighbour inset at the same time). Selected faces that touch are inset one by one, each in
//! its own ring; nothing is despawned.
//!
//! # Positions
//! The copy of corner `p` of face `f` goes to
//! `p + amount · (centroid(f) − p) + depth · normal(f)`, with `centroid` the mean of `f`'s
//! corners and `normal` its unit Newell normal, both taken before the inset (zero for a face
//! of no area). `amount` 0 leaves the inner loop on the old one (flat quads), towards 1 it
//! shrinks to the centroid.
//!
//! # Attributes
//! As for an extrusion: the quad corners at `b` and `b'` copy the UV of `f`'s corner at `b`,
//! those at `a` and `a'` the UV of its corner at `a`; a copy takes its vertex's normal and
//! colour.
//!
//! Refusals (each leaves the world untouched), in the order they are checked:
//! - `BadParameter`: no faces were given;
//! - `Stale`: a face id is not a live face;
//! - `BadParameter`: a face is given twice;
//! - `BadParameter`: the faces belong to more than one mesh;
//!
//! and, from [`InsetPlan::check`] (which [`inset_faces`] runs):
//! - `BadParameter`: `amount` is not in `[0, 1)` (NaN included);
//! - `BadParameter`: `depth` is not finite;
//! - `NotFinite`: a new vertex would not have a finite position.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::elements::Position;
use crate::mesh::ids::{FaceId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Parameter, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values, count};

use super::extrude::{Extruded, Ring, build_ring, check_faces, face_vertices, plan_ring};
use super::{Refusal, check_growth};

/// One face's ring and where its copies go.
#[derive(Clone, Debug, PartialEq)]
struct InsetFace {
    face: FaceId,
    ring: Ring,
    centroid: Vec3,
    normal: Vec3,
    /// The position of each side's start vertex.
    corners: Vec<Vec3>,
}

impl InsetFace {
    /// Where side `r`'s copy goes.
    fn position(&self, r: usize, amount: f32, depth: f32) -> Vec3 {
        let p = self.corners[r];
        p + amount * (self.centroid - p) + depth * self.normal
    }
}

/// What an inset touches, collected by [`plan_inset`].
#[derive(Clone, Debug, PartialEq)]
pub struct InsetPlan {
    faces: Vec<InsetFace>,
    seeds: Vec<VertexId>,
}

impl InsetPlan {
    /// Every corner of the selected faces: their neighbourhood
    /// ([`crate::mesh::change::neighbourhood`]) holds everything the inset reads, writes and
    /// creates, before it and after it (the copies are neighbours of their vertices).
    pub fn seeds(&self) -> Vec<VertexId> {
        self.seeds.clone()
    }

    /// The selected faces, as given.
    pub fn faces(&self) -> Vec<FaceId> {
        self.faces.iter().map(|x| x.face).collect()
    }

    /// Checks the parameters: `amount` in `[0, 1)`, `depth` finite, every new position finite.
    ///
    /// # Refusals
    /// `BadParameter` for an `amount` or `depth` out of range; `NotFinite` for a position.
    pub fn check(&self, amount: f32, depth: f32) -> Result<(), Refusal> {
        if !(0.0..1.0).contains(&amount) {
            return Err(Refusal::BadParameter(format!(
                "the inset amount must be in [0, 1), not {amount}"
            )));
        }
        if !depth.is_finite() {
            return Err(Refusal::BadParameter(format!(
                "the inset depth must be a finite number, not {depth}"
            )));
        }
        for x in &self.faces {
            for r in 0..x.ring.len() {
                let p = x.position(r, amount, depth);
                if !p.is_finite() {
                    return Err(Refusal::NotFinite(p));
                }
            }
        }
        Ok(())
    }
}

/// Checks that the faces can be inset and collects everything the inset touches.
///
/// # Refusals
/// See the module doc (all but the parameters', which [`InsetPlan::check`] checks).
pub fn plan_inset(world: &World, faces: &[FaceId]) -> Result<InsetPlan, Refusal> {
    let m = MeshRef::new(world);
    let (mesh, _) = check_faces(world, faces, "an inset")?;
    let faces = faces
        .iter()
        .map(|&f| {
            let alone: EntityHashSet = [f.0].into_iter().collect();
            let (ring, _) = plan_ring(&m, mesh, &[f], &alone);
            InsetFace {
                face: f,
                centroid: m.face_centroid(f),
                normal: m.face_area_vector(f).normalize_or_zero(),
                corners: (0..ring.len())
                    .map(|r| m.position(ring.origin(r)))
                    .collect(),
                ring,
            }
        })
        .collect::<Vec<_>>();
    let selected: Vec<FaceId> = faces.iter().map(|x| x.face).collect();
    Ok(InsetPlan {
        seeds: face_vertices(&m, &selected),
        faces,
    })
}

/// Carries out an inset planned by [`plan_inset`] (see the module doc for the positions).
/// Returns what it made: `top` the selected faces, `sides` the quads, `moved` the new
/// vertices, each face's in its corner order.
///
/// `amount` and `depth` should pass [`InsetPlan::check`]; where they do not, any finite
/// position is still applied (an `amount` outside `[0, 1)` folds the inner face over), and a
/// copy whose position would not be finite stays on its vertex, so the mesh stays valid.
pub fn apply_inset(world: &mut World, plan: InsetPlan, amount: f32, depth: f32) -> Extruded {
    crate::checks::checked_assert_eq!(
        plan_inset(world, &plan.faces()).as_ref(),
        Ok(&plan),
        "stale inset plan"
    );
    let mut made = Extruded::default();
    for x in &plan.faces {
        // Rings of neighbouring faces share rim edges: each is built on the world as the
        // previous ones left it (build_ring reads the twins there).
        let (sides, copies) = build_ring(world, &x.ring);
        for (r, &v) in copies.iter().enumerate() {
            let p = x.position(r, amount, depth);
            let p = if p.is_finite() { p } else { x.corners[r] };
            world.get_mut::<Position>(v.0).expect("spawned").0 = p;
        }
        made.top.push(x.face);
        made.sides.extend(sides);
        made.moved.extend(MeshRef::new(world).face_vertices(x.face));
    }
    made
}

/// Insets each face on its own by `amount` towards its centroid and `depth` along its normal
/// (see the module doc). Returns what it made.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn inset_faces(
    world: &mut World,
    faces: &[FaceId],
    amount: f32,
    depth: f32,
) -> Result<Extruded, Refusal> {
    let plan = plan_inset(world, faces)?;
    plan.check(amount, depth)?;
    Ok(apply_inset(world, plan, amount, depth))
}

/// Insetting faces (with a depth, Scotty3D's bevel face): a local edit.
pub const INSET: Declaration = Declaration::new("inset")
    .titled("Inset")
    .described("inset each face: a ring of quads inside it, AMOUNT of the way to its centre, DEPTH along its normal")
    .naming(Names::Faces)
    .with_parameters(&[
        Parameter::real("AMOUNT", 0.0, 0.0, 0.999),
        Parameter::real("DEPTH", 0.0, -1e6, 1e6),
    ])
    .in_section(Section::Modelling);

/// [`plan_inset`] and [`apply_inset`] as a registered operation: `inset:FACES[:AMOUNT[:DEPTH]]`,
/// I (which then drags the amount); also the bevel of faces ([`Bevel`](super::Bevel)).
pub struct Inset;

impl MeshOperation for Inset {
    fn declaration(&self) -> &'static Declaration {
        &INSET
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_inset(world, &values.faces().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = {
            let faces = values.faces()?;
            let plan = plan_inset(world, &faces)?;
            plan.check(values.number(0) as f32, values.number(1) as f32)?;
            check_growth("insetting", faces.len(), plan.seeds().len())?;
            plan
        };
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
            let (amount, depth) = (values.number(0) as f32, values.number(1) as f32);
            let done = apply_inset(world, plan, amount, depth);
            let summary = format!(
                "{} inset, {} around them",
                count(done.top.len(), "face"),
                count(done.sides.len(), "new face")
            );
            (summary, None)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::validate;
    use crate::mesh::{MeshMembers, PolygonSoup, shapes};
    use crate::ops::local::testkit::*;

    fn unit_square() -> PolygonSoup {
        let p = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        PolygonSoup::from_faces(p.to_vec(), &[[0u32, 1, 2, 3]])
    }

    #[test]
    fn a_unit_square_insets_to_the_formula() {
        let (mut world, built) = build(&unit_square());
        let mesh = built.mesh;
        let f = face_of(&world, &built, &[0, 1, 2, 3]);
        let made = inset_faces(&mut world, &[f], 0.25, 0.5).unwrap();
        validate(&world, mesh).unwrap();
        // V + 4, E + 8, F + 4: χ 1 and one boundary loop, as before.
        assert_eq!(counts(&world, mesh), (8, 12, 5, 1, 1));
        assert_eq!(made.top, vec![f]);
        assert_eq!((made.sides.len(), made.moved.len()), (4, 4));
        // p + 0.25 (c − p) + 0.5 n, c = (0.5, 0.5, 0), n = z.
        let outer = unit_square().positions;
        let inner = [
            (0.125, 0.125),
            (0.875, 0.125),
            (0.875, 0.875),
            (0.125, 0.875),
        ]
        .map(|(x, y)| Vec3::new(x, y, 0.5));
        for (&p, &q) in outer.iter().zip(&inner) {
            let formula = p + 0.25 * (Vec3::new(0.5, 0.5, 0.0) - p) + 0.5 * Vec3::Z;
            assert_eq!(bits(formula), bits(q));
        }
        assert_eq!(position_cycle(&world, f), cycle_of(&inner));
        let m = MeshRef::new(&world);
        let top: Vec<VertexId> = m.face_vertices(f).collect();
        assert_eq!(made.moved, top, "moved in the face's corner order");
        let sides = made
            .sides
            .iter()
            .map(|&s| position_cycle(&world, s))
            .collect();
        let expected = (0..4)
            .map(|k| {
                let (a, b) = (outer[k], outer[(k + 1) % 4]);
                let (a2, b2) = (inner[k], inner[(k + 1) % 4]);
                cycle_of(&[a, b, b2, a2])
            })
            .collect();
        assert_eq!(sorted(sides), sorted(expected));
        for &v in built.input_vertices.iter().flatten() {
            assert!(
                m.is_boundary_vertex(v),
                "the old square is the border still"
            );
        }
    }

    #[test]
    fn a_pentagon_insets_into_a_pentagon() {
        let points: Vec<Vec3> = (0..5)
            .map(|k| {
                let t = k as f32 * std::f32::consts::TAU / 5.0;
                Vec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let soup = PolygonSoup::from_faces(points.clone(), &[[0u32, 1, 2, 3, 4]]);
        let (mut world, built) = build(&soup);
        let f = face_of(&world, &built, &[0, 1, 2, 3, 4]);
        let (c, n) = {
            let m = MeshRef::new(&world);
            (m.face_centroid(f), m.face_area_vector(f).normalize())
        };
        let made = inset_faces(&mut world, &[f], 0.5, -1.0).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (10, 15, 6, 1, 1));
        let m = MeshRef::new(&world);
        assert_eq!(m.face_degree(f), 5);
        let mut moved: Vec<[u32; 3]> = made.moved.iter().map(|&v| bits(m.position(v))).collect();
        let mut expected: Vec<[u32; 3]> = points
            .iter()
            .map(|&p| bits(p + 0.5 * (c - p) + -1.0 * n))
            .collect();
        moved.sort_unstable();
        expected.sort_unstable();
        assert_eq!(moved, expected);
        assert!(made.sides.iter().all(|&s| m.face_degree(s) == 4));
    }

    #[test]
    fn a_face_on_the_border_keeps_the_border() {
        let mut soup = shapes::quad_grid(3, 3);
        soup.positions.iter_mut().for_each(|p| *p *= 3.0);
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(3, 0, 0));
        let loops_before: Vec<Vec3> = {
            let m = MeshRef::new(&world);
            let mut b: Vec<Vec3> = MeshMembers::collect(&world, mesh)
                .halfedges
                .into_iter()
                .filter(|&h| m.is_boundary(h))
                .map(|h| m.position(m.to_vertex(h)))
                .collect();
            b.sort_unstable_by_key(|&p| bits(p));
            b
        };
        let made = inset_faces(&mut world, &[f], 0.5, 0.0).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (20, 32, 13, 1, 1));
        let m = MeshRef::new(&world);
        let mut loops_after: Vec<Vec3> = MeshMembers::collect(&world, mesh)
            .halfedges
            .into_iter()
            .filter(|&h| m.is_boundary(h))
            .map(|h| m.position(m.to_vertex(h)))
            .collect();
        loops_after.sort_unstable_by_key(|&p| bits(p));
        assert_eq!(loops_after, loops_before);
        let inner = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)]
            .map(|(x, y)| Vec3::new(x, y, 0.0));
        let moved: Vec<Vec3> = made.moved.iter().map(|&v| m.position(v)).collect();
        assert_eq!(cycle_of(&moved), cycle_of(&inner));
    }

    #[test]
    fn neighbouring_faces_are_inset_each_on_its_own() {
        let (mut world, built) = build(&shapes::quad_grid(2, 1));
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(2, 0, 0));
        let g = face_of(&world, &built, &cell(2, 1, 0));
        let (a, b) = (
            built.input_vertices[1].unwrap(),
            built.input_vertices[4].unwrap(),
        );
        let shared = {
            let m = MeshRef::new(&world);
            m.edge(m.find_halfedge(a, b).unwrap())
        };
        let made = inset_faces(&mut world, &[f, g], 0.2, 0.1).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (14, 23, 10, 1, 1));
        assert_eq!(made.top, vec![f, g]);
        assert_eq!((made.sides.len(), made.moved.len()), (8, 8));
        let m = MeshRef::new(&world);
        // The shared edge stayed, with a quad of each ring on its two sides.
        let h = m.edge_halfedge(shared);
        assert_eq!(m.edge_vertices(shared), (a, b));
        for x in [h, m.twin(h)] {
            assert!(made.sides.contains(&m.face(x).unwrap()));
        }
        let fv: Vec<_> = m.face_vertices(f).collect();
        assert!(m.face_vertices(g).all(|v| !fv.contains(&v)));
    }

    #[test]
    fn a_triangle_of_a_tetrahedron() {
        let (mut world, built) = build(&shapes::tetrahedron());
        let mesh = built.mesh;
        let f = face_of(&world, &built, &[0, 1, 2]);
        let corners: Vec<Vec3> = {
            let m = MeshRef::new(&world);
            m.face_vertices(f).map(|v| m.position(v)).collect()
        };
        let made = inset_faces(&mut world, &[f], 0.5, 0.25).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (7, 12, 7, 2, 0));
        let c = (corners[0] + corners[1] + corners[2]) / 3.0;
        let n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        let m = MeshRef::new(&world);
        let mut moved: Vec<Vec3> = made.moved.iter().map(|&v| m.position(v)).collect();
        let mut expected: Vec<Vec3> = corners
            .iter()
            .map(|&p| p + 0.5 * (c - p) + 0.25 * n)
            .collect();
        let key = |p: &Vec3| bits(*p);
        moved.sort_unstable_by_key(key);
        expected.sort_unstable_by_key(key);
        for (p, q) in moved.iter().zip(&expected) {
            assert!((*p - *q).length() < 1e-6, "{p} against {q}");
        }
    }

    #[test]
    fn refusals_leave_the_world_untouched() {
        let (mut world, built) = build(&shapes::cube());
        let mesh = built.mesh;
        let other = build_into(&mut world, &shapes::tetrahedron());
        let f = face_of(&world, &built, &[4, 5, 6, 7]);
        let g = face_of(&world, &other, &[0, 1, 2]);
        let gone = gone_face(&mut world);
        let before = snapshot(&world, mesh);
        let cases: Vec<(Vec<FaceId>, f32, f32, &str)> = vec![
            (vec![], 0.5, 0.0, "BadParameter"),
            (vec![gone], 0.5, 0.0, "Stale"),
            (vec![f, f], 0.5, 0.0, "BadParameter"),
            (vec![f, g], 0.5, 0.0, "BadParameter"),
            (vec![f], 1.0, 0.0, "BadParameter"),
            (vec![f], -0.1, 0.0, "BadParameter"),
            (vec![f], f32::NAN, 0.0, "BadParameter"),
            (vec![f], 0.5, f32::INFINITY, "BadParameter"),
            (vec![f], 0.5, f32::NAN, "BadParameter"),
        ];
        for (faces, amount, depth, kind) in cases {
            let refusal = inset_faces(&mut world, &faces, amount, depth).unwrap_err();
            assert_untouched(&world, mesh, &before);
            let ok = match kind {
                "Stale" => matches!(refusal, Refusal::Stale(_)),
                _ => matches!(refusal, Refusal::BadParameter(_)),
            };
            assert!(ok, "{faces:?} {amount} {depth}: {refusal}");
        }
        validate(&world, mesh).unwrap();
        validate(&world, other.mesh).unwrap();
        // A square far up the z axis, inset deep enough to leave the finite range.
        let (mut world, built) = build(&far_square());
        let f = face_of(&world, &built, &[0, 1, 2, 3]);
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::NotFinite(_)),
            |w| inset_faces(w, &[f], 0.5, f32::MAX),
        );
    }

    #[test]
    fn undo_through_the_seeds_restores_the_mesh_and_redo_repeats_it() {
        let (mut world, built) = build(&with_attributes(shapes::cube(), Uvs::PerCorner));
        let mesh = built.mesh;
        let faces = [
            face_of(&world, &built, &[4, 5, 6, 7]),
            face_of(&world, &built, &[0, 1, 5, 4]),
        ];
        let plan = plan_inset(&world, &faces).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, mesh, &seeds, |world| {
            let _ = apply_inset(world, plan, 0.3, 0.2);
        });
    }

    #[test]
    fn uvs_normals_and_colours_are_carried() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(2, 2), Uvs::PerCorner));
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(2, 1, 1));
        let (rim, uvs) = corner_uvs(&world, f);
        let made = inset_faces(&mut world, &[f], 0.5, 0.0).unwrap();
        validate(&world, mesh).unwrap();
        // Every face corner has a UV (and no other halfedge); the inner face keeps its UVs,
        // each ring quad takes its corners' UVs from the rim, each copy its vertex's normal and
        // colour.
        assert_attributes_complete(&world, mesh);
        assert_sides_carry_rim(&world, &rim, &uvs, &made.sides);
    }
}
