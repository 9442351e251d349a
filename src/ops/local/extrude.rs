//! Extrude region (Blender's "extrude region"): the selected faces are lifted off the surface
//! as one piece, and a wall of quads joins them to where they were.
//!
//! ```text
//!   seen from above (the top drawn smaller to show the walls):
//!
//!   d -------- c            d ------------------ c
//!   |          |            | \                / |
//!   |    f     |     →      |  d' ---------- c'  |     f keeps its id and its sides, now
//!   |          |            |  |      f      |   |     on the copies a' b' c' d'; each rim
//!   a -------- b            |  a' ---------- b'  |     edge a b keeps its entity at the
//!                           | /                \ |     bottom of the new quad a b b' a'
//!                           a ------------------ b
//! ```
//!
//! The **region** is the set of selected faces, taken as one whole; its **rim** is every edge
//! with a region face on exactly one side (mesh-boundary edges of region faces included). Each
//! rim vertex gets a copy that the region's faces use from then on, while the old vertex stays
//! with the rest of the mesh; each rim edge gets one quad side face (old edge at the bottom, a
//! new edge at the top, a new vertical edge at each end). A vertex strictly inside the region
//! (every face around it selected, not on the boundary) is not copied: it moves with the top.
//!
//! Where the region touches itself only at a vertex (two or more separate fans of selected
//! faces around it, like two quads meeting at a corner), each fan gets its own copy, so the
//! pieces come apart there and every vertex stays manifold. So a rim of `k` halfedges adds
//! exactly `k` vertices, `2k` edges and `k` faces: χ is unchanged, boundary loops too.
//!
//! Entities: the region's faces and halfedges are reused (every corner keeps its UV), each
//! rim halfedge moves onto the new top edge, the old rim edges and vertices stay below. Nothing
//! is despawned.
//!
//! # Positions
//! Each top vertex (a copy, or a vertex inside the region) moves by `distance · n(v)`, where
//! `n(v)` is the normalised sum of the **area-weighted** normals (the Newell vector areas) of
//! the region faces at `v` — for a copy, of the faces of its own fan. A degenerate sum (faces
//! that cancel) gives no motion. [`extrude_directions`] computes the same directions on the
//! mesh after a zero-distance extrusion, bit for bit, so the editor can extrude with distance 0
//! and then drag [`Extruded::moved`] along them. Distance 0 gives flat side faces (a valid
//! mesh); a negative distance pushes the region in.
//!
//! # Attributes
//! A top corner keeps its UV. A side face's corners at `b` and `b'` copy the UV of the region's
//! corner at `b` (the corner of the rim halfedge), those at `a` and `a'` the UV of the region's
//! corner at `a`. A copy takes its vertex's normal and colour. Seam marks stay where they were.
//!
//! Refusals (each leaves the world untouched), in the order they are checked:
//! - `BadParameter`: no faces were given;
//! - `Stale`: a face id is not a live face;
//! - `BadParameter`: a face is given twice;
//! - `BadParameter`: the faces belong to more than one mesh;
//! - `ClosedRegion`: an edge-connected piece of the selection has no rim (it is a whole closed
//!   surface, such as every face of a cube);
//!
//! and, from [`ExtrudePlan::check_distance`] (which [`extrude_faces`] runs):
//! - `BadParameter`: the distance is not finite;
//! - `NotFinite`: a moved vertex would not have a finite position.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;

use crate::mesh::attributes::{self, MeshAttributes, VertexColor, VertexNormal};
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use crate::mesh::groups;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Parameter, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values, count};

use super::{Refusal, check_growth, he, spawn_at};

/// What an extrusion (or an inset, [`super::inset_faces`]) made.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Extruded {
    /// The region's faces, the same ids as given, now on the top.
    pub top: Vec<FaceId>,
    /// The new side faces, one per rim edge.
    pub sides: Vec<FaceId>,
    /// Every vertex of the top, each once (copies and vertices inside the region), in the order
    /// they first appear around `top`'s faces (each face's corners from its halfedge, as
    /// [`MeshRef::face_vertices`] lists them): the vertices to transform further.
    pub moved: Vec<VertexId>,
}

/// One rim halfedge of a region and what its side quad needs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Side {
    /// The rim halfedge `a → b`, inside a region face (its twin is not).
    h: HalfedgeId,
    /// Its start, the vertex this side's copy is a copy of.
    a: VertexId,
    /// Its edge: stays below, as the side face's bottom.
    edge: EdgeId,
    /// The side whose rim halfedge ends at `a` in the same fan of region faces.
    before: usize,
    /// The side whose rim halfedge leaves `b` in the same fan as `h`'s face.
    after: usize,
    /// The region halfedges that end at `a` in this fan: they end at the copy afterwards.
    corners: Vec<HalfedgeId>,
}

/// The topology of a region's ring of side faces, shared by extrude and inset: one side per rim
/// halfedge, and the vertices inside the region.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Ring {
    mesh: MeshId,
    faces: Vec<FaceId>,
    sides: Vec<Side>,
    /// Vertices with every face around them in the region, not on the boundary, in order of
    /// first appearance.
    inner: Vec<VertexId>,
}

impl Ring {
    /// The number of sides (and of copies).
    pub(super) fn len(&self) -> usize {
        self.sides.len()
    }

    /// The vertex side `r`'s copy is made from.
    pub(super) fn origin(&self, r: usize) -> VertexId {
        self.sides[r].a
    }
}

/// Checks a face selection: not empty, live, no repeats, one mesh. Returns the mesh and the
/// selection as a set.
pub(super) fn check_faces(
    world: &World,
    faces: &[FaceId],
    what: &str,
) -> Result<(MeshId, EntityHashSet), Refusal> {
    let m = MeshRef::new(world);
    if faces.is_empty() {
        return Err(Refusal::BadParameter(format!(
            "{what} needs at least one face"
        )));
    }
    let mut meshes = Vec::with_capacity(faces.len());
    for &f in faces {
        let stale = Refusal::Stale(ElementId::Face(f));
        let x = m.try_face(f).ok_or(stale.clone())?;
        m.try_halfedge(x.halfedge).ok_or(stale.clone())?;
        meshes.push(world.get::<InMesh>(f.0).ok_or(stale)?.0);
    }
    let mut set = EntityHashSet::default();
    for &f in faces {
        if !set.insert(f.0) {
            return Err(Refusal::BadParameter(format!(
                "{f} is selected twice: give each face once"
            )));
        }
    }
    let mesh = meshes[0];
    if meshes.iter().any(|&x| x != mesh) {
        return Err(Refusal::BadParameter(format!(
            "{what} acts on one mesh: the faces belong to more than one"
        )));
    }
    Ok((mesh, set))
}

/// The ring of `region` (the faces `faces`, checked live and distinct), and the slot of each
/// region halfedge's corner: the side whose copy it ends at, or `len + i` for inner vertex `i`.
pub(super) fn plan_ring(
    m: &MeshRef<'_>,
    mesh: MeshId,
    faces: &[FaceId],
    region: &EntityHashSet,
) -> (Ring, EntityHashMap<usize>) {
    let in_region = |h: HalfedgeId| m.face(h).is_some_and(|f| region.contains(&f.0));
    let mut sides = Vec::new();
    let mut side_of: EntityHashMap<usize> = EntityHashMap::default();
    for &f in faces {
        for h in m.face_halfedges(f) {
            if !in_region(m.twin(h)) {
                side_of.insert(h.0, sides.len());
                sides.push(Side {
                    h,
                    a: m.from_vertex(h),
                    edge: m.edge(h),
                    before: usize::MAX,
                    after: usize::MAX,
                    corners: Vec::new(),
                });
            }
        }
    }
    // Each fan of region faces around a rim vertex is bounded by one rim halfedge leaving the
    // vertex and one entering it. Rotate counter-clockwise from the leaving one through the
    // fan's faces, collecting the corners at the vertex, up to the entering one.
    let mut slot: EntityHashMap<usize> = EntityHashMap::default();
    for r in 0..sides.len() {
        let mut before = None;
        for x in m.vertex_outgoing_from(sides[r].h) {
            let p = m.prev(x);
            sides[r].corners.push(p);
            slot.insert(p.0, r);
            if !in_region(m.twin(p)) {
                before = side_of.get(&p.0).copied();
                break;
            }
        }
        let before = before.expect("a fan of region faces at a rim vertex is bounded");
        sides[r].before = before;
        sides[before].after = r;
    }
    let mut inner = Vec::new();
    let mut inner_of: EntityHashMap<usize> = EntityHashMap::default();
    for &f in faces {
        for h in m.face_halfedges(f) {
            if slot.contains_key(&h.0) {
                continue;
            }
            let v = m.to_vertex(h);
            let i = *inner_of.entry(v.0).or_insert_with(|| {
                inner.push(v);
                inner.len() - 1
            });
            slot.insert(h.0, sides.len() + i);
        }
    }
    (
        Ring {
            mesh,
            faces: faces.to_vec(),
            sides,
            inner,
        },
        slot,
    )
}

/// Builds the ring's side faces: a copy of each side's start vertex (placed on it), the side
/// quads, the top and vertical edges, and the region's faces moved onto the copies. Reads the
/// rim's twins and the vertices' and edges' halfedges from the world as it is now, so rings of
/// neighbouring faces planned together can be built one after the other. Returns the side
/// faces and the copies, both by side.
pub(super) fn build_ring(world: &mut World, ring: &Ring) -> (Vec<FaceId>, Vec<VertexId>) {
    let has = MeshAttributes::of(world, ring.mesh);
    let (twins, positions, uvs) = {
        let m = MeshRef::new(world);
        let twins: Vec<HalfedgeId> = ring.sides.iter().map(|s| m.twin(s.h)).collect();
        let positions: Vec<Vec3> = ring.sides.iter().map(|s| m.position(s.a)).collect();
        // (the region's corner at a, at b) of each side.
        let uvs: Option<Vec<(Vec2, Vec2)>> = has.uv.then(|| {
            let uv = |x: HalfedgeId| attributes::corner_uv(world, x).unwrap_or_default();
            ring.sides
                .iter()
                .map(|s| (uv(m.prev(s.h)), uv(s.h)))
                .collect()
        });
        (twins, positions, uvs)
    };
    let made = Wall::allocate(world, ring.sides.len());
    let member = InMesh(ring.mesh);
    for (r, s) in ring.sides.iter().enumerate() {
        let (n, after, before) = (&made[r], &made[s.after], &made[s.before]);
        let b = ring.sides[s.after].a;
        let face = Some(n.face);
        // The side quad a → b → b' → a': bottom, rise, top, fall. The post at b (b b') is the
        // one of the side after this one, the post at a (a a') this side's own.
        let halfedges = [
            (n.bottom, twins[r], n.rise, n.fall, b, s.edge),
            (n.rise, after.fall, n.top, n.bottom, after.copy, after.post),
            (n.top, s.h, n.fall, n.rise, n.copy, n.top_edge),
            (n.fall, before.rise, n.bottom, n.top, s.a, n.post),
        ];
        for (x, twin, next, prev, vertex, edge) in halfedges {
            let links = Halfedge {
                twin,
                next,
                prev,
                vertex,
                edge,
                face,
            };
            spawn_at(world, x.0, (links, member));
        }
        spawn_at(world, n.top_edge.0, (Edge { halfedge: s.h }, member));
        spawn_at(world, n.post.0, (Edge { halfedge: n.fall }, member));
        spawn_at(world, n.face.0, (Face { halfedge: n.bottom }, member));
        // The side face takes the group of the region face it rises from.
        let region_face = world.get::<Halfedge>(s.h.0).and_then(|x| x.face);
        let group = region_face.and_then(|f| groups::face_group(world, f));
        groups::set_face_group(world, n.face, group);
        let copy = (Vertex { halfedge: s.h }, Position(positions[r]), member);
        spawn_at(world, n.copy.0, copy);
        if has.normals
            && let Some(x) = world.get::<VertexNormal>(s.a.0).copied()
        {
            world.entity_mut(n.copy.0).insert(x);
        }
        if has.colors
            && let Some(x) = world.get::<VertexColor>(s.a.0).copied()
        {
            world.entity_mut(n.copy.0).insert(x);
        }
        if let Some(uvs) = &uvs {
            let (at_a, at_b) = uvs[r];
            for (x, uv) in [
                (n.bottom, at_b),
                (n.rise, at_b),
                (n.top, at_a),
                (n.fall, at_a),
            ] {
                attributes::set_corner_uv(world, x, uv);
            }
        }
    }
    rewire(world, ring, &made, &twins);
    (
        made.iter().map(|n| n.face).collect(),
        made.iter().map(|n| n.copy).collect(),
    )
}

/// The elements a side of the ring rises into: the copy of its start vertex `a`, the side
/// quad's four halfedges (bottom, rise, top, fall), its top edge, the post at `a` (a a') and
/// the quad itself.
struct Wall {
    copy: VertexId,
    bottom: HalfedgeId,
    rise: HalfedgeId,
    top: HalfedgeId,
    fall: HalfedgeId,
    top_edge: EdgeId,
    post: EdgeId,
    face: FaceId,
}

impl Wall {
    /// Ids for `sides` walls.
    fn allocate(world: &World, sides: usize) -> Vec<Wall> {
        let alloc = world.entity_allocator();
        (0..sides)
            .map(|_| Wall {
                copy: VertexId(alloc.alloc()),
                bottom: HalfedgeId(alloc.alloc()),
                rise: HalfedgeId(alloc.alloc()),
                top: HalfedgeId(alloc.alloc()),
                fall: HalfedgeId(alloc.alloc()),
                top_edge: EdgeId(alloc.alloc()),
                post: EdgeId(alloc.alloc()),
                face: FaceId(alloc.alloc()),
            })
            .collect()
    }
}

/// Rewires the old elements once the walls stand: the rim halfedge moves onto the top edge,
/// its old twin faces the bottom, the fan's corners end at the copy, and a rim vertex whose
/// halfedge now leaves a copy takes the bottom of one of its sides (an interior halfedge: a
/// boundary vertex's halfedge is a boundary one, which stays).
fn rewire(world: &mut World, ring: &Ring, made: &[Wall], twins: &[HalfedgeId]) {
    let region: EntityHashSet = ring.faces.iter().map(|f| f.0).collect();
    for (r, s) in ring.sides.iter().enumerate() {
        let n = &made[r];
        he(world, twins[r]).twin = n.bottom;
        {
            let mut x = he(world, s.h);
            x.twin = n.top;
            x.edge = n.top_edge;
        }
        for &c in &s.corners {
            he(world, c).vertex = n.copy;
        }
        let mut edge = world.get_mut::<Edge>(s.edge.0).expect("planned");
        if edge.halfedge == s.h {
            edge.halfedge = n.bottom;
        }
    }
    for (r, s) in ring.sides.iter().enumerate() {
        let out = MeshRef::new(world).vertex_halfedge(s.a);
        let moved = MeshRef::new(world)
            .face(out)
            .is_some_and(|f| region.contains(&f.0));
        if moved {
            world.get_mut::<Vertex>(s.a.0).expect("planned").halfedge = made[r].bottom;
        }
    }
}

/// The distinct vertices of `faces`, in order of first appearance.
pub(super) fn face_vertices(m: &MeshRef<'_>, faces: &[FaceId]) -> Vec<VertexId> {
    let mut seen = EntityHashSet::default();
    let mut out = Vec::new();
    for &f in faces {
        for v in m.face_vertices(f) {
            if seen.insert(v.0) {
                out.push(v);
            }
        }
    }
    out
}

/// What an extrusion touches, collected by [`plan_extrude`].
#[derive(Clone, Debug, PartialEq)]
pub struct ExtrudePlan {
    ring: Ring,
    /// By slot (the sides' copies, then the inner vertices): the position at distance 0 and
    /// the unit direction of motion.
    origins: Vec<Vec3>,
    directions: Vec<Vec3>,
    /// The slots in the order their vertices first appear around the region's faces.
    order: Vec<usize>,
    seeds: Vec<VertexId>,
}

impl ExtrudePlan {
    /// Every vertex of the region's faces: their neighbourhood
    /// ([`crate::mesh::change::neighbourhood`]) holds everything the extrusion reads, writes
    /// and creates, before it (on the old mesh) and after it (the copies are neighbours of
    /// their vertices).
    pub fn seeds(&self) -> Vec<VertexId> {
        self.seeds.clone()
    }

    /// The region's faces, as given.
    pub fn faces(&self) -> &[FaceId] {
        &self.ring.faces
    }

    /// Checks that extruding by `distance` leaves every position finite.
    ///
    /// # Refusals
    /// `BadParameter` when `distance` is NaN or infinite; `NotFinite` when a moved vertex
    /// would leave the finite range.
    pub fn check_distance(&self, distance: f32) -> Result<(), Refusal> {
        if !distance.is_finite() {
            return Err(Refusal::BadParameter(format!(
                "the extrusion distance must be a finite number, not {distance}"
            )));
        }
        for (&o, &d) in self.origins.iter().zip(&self.directions) {
            let p = o + distance * d;
            if !p.is_finite() {
                return Err(Refusal::NotFinite(p));
            }
        }
        Ok(())
    }
}

/// Checks that the faces can be extruded as one region, and collects everything the
/// extrusion touches.
///
/// # Refusals
/// See the module doc (all but the distance's, which [`ExtrudePlan::check_distance`] checks).
pub fn plan_extrude(world: &World, faces: &[FaceId]) -> Result<ExtrudePlan, Refusal> {
    let m = MeshRef::new(world);
    let (mesh, region) = check_faces(world, faces, "an extrusion")?;
    // Each edge-connected piece of the selection must have a rim.
    let mut seen = EntityHashSet::default();
    for &f in faces {
        if !seen.insert(f.0) {
            continue;
        }
        let (mut stack, mut rim) = (vec![f], false);
        while let Some(g) = stack.pop() {
            for h in m.face_halfedges(g) {
                match m.face(m.twin(h)) {
                    Some(x) if region.contains(&x.0) => {
                        if seen.insert(x.0) {
                            stack.push(x);
                        }
                    }
                    _ => rim = true,
                }
            }
        }
        if !rim {
            return Err(Refusal::ClosedRegion(ElementId::Face(f)));
        }
    }
    let (ring, slot) = plan_ring(&m, mesh, faces, &region);
    let slots = ring.sides.len() + ring.inner.len();
    let mut sums = vec![Vec3::ZERO; slots];
    let mut order = Vec::with_capacity(slots);
    let mut listed = vec![false; slots];
    for &f in faces {
        let area = m.face_area_vector(f);
        for h in m.face_halfedges(f) {
            let s = slot[&h.0];
            sums[s] += area;
            if !listed[s] {
                listed[s] = true;
                order.push(s);
            }
        }
    }
    let origins = (0..slots)
        .map(|s| match s.checked_sub(ring.sides.len()) {
            None => m.position(ring.sides[s].a),
            Some(i) => m.position(ring.inner[i]),
        })
        .collect();
    Ok(ExtrudePlan {
        seeds: face_vertices(&m, faces),
        origins,
        directions: sums.into_iter().map(Vec3::normalize_or_zero).collect(),
        order,
        ring,
    })
}

/// Carries out an extrusion planned by [`plan_extrude`], moving the top by `distance` along
/// each top vertex's direction (see the module doc). Returns what it made.
///
/// `distance` should pass [`ExtrudePlan::check_distance`]; where it does not, a vertex whose
/// new position would not be finite stays at its distance-0 place, so the mesh stays valid.
pub fn apply_extrude(world: &mut World, plan: ExtrudePlan, distance: f32) -> Extruded {
    crate::checks::checked_assert_eq!(
        plan_extrude(world, &plan.ring.faces).as_ref(),
        Ok(&plan),
        "stale extrude plan"
    );
    let (sides, copies) = build_ring(world, &plan.ring);
    let vertex = |s: usize| match s.checked_sub(copies.len()) {
        None => copies[s],
        Some(i) => plan.ring.inner[i],
    };
    for (s, (&o, &d)) in plan.origins.iter().zip(&plan.directions).enumerate() {
        let p = o + distance * d;
        let p = if p.is_finite() { p } else { o };
        world.get_mut::<Position>(vertex(s).0).expect("spawned").0 = p;
    }
    Extruded {
        moved: plan.order.iter().map(|&s| vertex(s)).collect(),
        sides,
        top: plan.ring.faces,
    }
}

/// Extrudes the faces as one region by `distance` (see the module doc). Returns what it made.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn extrude_faces(
    world: &mut World,
    faces: &[FaceId],
    distance: f32,
) -> Result<Extruded, Refusal> {
    let plan = plan_extrude(world, faces)?;
    plan.check_distance(distance)?;
    Ok(apply_extrude(world, plan, distance))
}

/// Each vertex of `faces` (in order of first appearance) with its unit direction: the
/// normalised sum of the Newell vector areas of the given faces around it (zero where they
/// cancel). Stale and repeated faces are skipped.
///
/// Called with [`Extruded::top`] after a zero-distance extrusion, it gives the directions the
/// extrusion itself uses, bit for bit, and its vertices are [`Extruded::moved`] in order: moving
/// each by `distance` along its direction is the extrusion by `distance`.
pub fn extrude_directions(world: &World, faces: &[FaceId]) -> Vec<(VertexId, Vec3)> {
    let m = MeshRef::new(world);
    let mut done = EntityHashSet::default();
    let mut index: EntityHashMap<usize> = EntityHashMap::default();
    let mut out: Vec<(VertexId, Vec3)> = Vec::new();
    for &f in faces {
        if m.try_face(f).is_none() || !done.insert(f.0) {
            continue;
        }
        let area = m.face_area_vector(f);
        for v in m.face_vertices(f) {
            let i = *index.entry(v.0).or_insert_with(|| {
                out.push((v, Vec3::ZERO));
                out.len() - 1
            });
            out[i].1 += area;
        }
    }
    for (_, d) in &mut out {
        *d = d.normalize_or_zero();
    }
    out
}

/// Extruding a region of faces: a local edit (the walls take the region's groups).
pub const EXTRUDE: Declaration = Declaration::new("extrude")
    .titled("Extrude")
    .described("extrude the faces as one region and push it DISTANCE along its normals")
    .naming(Names::Faces)
    .with_parameters(&[Parameter::real("DISTANCE", 0.0, -1e6, 1e6)])
    .in_section(Section::Modelling);

/// [`plan_extrude`] and [`apply_extrude`] as a registered operation: `extrude:FACES[:DISTANCE]`,
/// E (which then drags the distance).
pub struct Extrude;

impl MeshOperation for Extrude {
    fn declaration(&self) -> &'static Declaration {
        &EXTRUDE
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_extrude(world, &values.faces().ok()?).ok()?;
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
            let plan = plan_extrude(world, &faces)?;
            plan.check_distance(values.number(0) as f32)?;
            check_growth("extruding", faces.len(), plan.seeds().len())?;
            plan
        };
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
            let done = apply_extrude(world, plan, values.number(0) as f32);
            let summary = format!(
                "{} lifted on {}",
                count(done.top.len(), "face"),
                count(done.sides.len(), "side face")
            );
            (summary, None)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::validate;
    use crate::mesh::{MeshMembers, PolygonSoup, mesh_stats, shapes, to_soup};
    use crate::ops::local::testkit::*;

    /// The side quads expected for a flat face with corners `p` (counter-clockwise) lifted by
    /// `d`: `a b b' a'` for each side `a b`.
    fn walls(p: &[Vec3], d: Vec3) -> Vec<Vec<Key>> {
        let mut out: Vec<Vec<Key>> = (0..p.len())
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % p.len()]);
                cycle_of(&[a, b, b + d, a + d])
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn one_quad_of_a_grid_rises_on_four_walls() {
        let (mut world, built) = build(&shapes::quad_grid(3, 3));
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(3, 1, 1));
        let old: Vec<VertexId> = MeshRef::new(&world).face_vertices(f).collect();
        let corners: Vec<Vec3> = {
            let m = MeshRef::new(&world);
            old.iter().map(|&v| m.position(v)).collect()
        };
        assert_eq!(counts(&world, mesh), (16, 24, 9, 1, 1));
        let made = extrude_faces(&mut world, &[f], 0.5).unwrap();
        validate(&world, mesh).unwrap();
        // V + 4, E + 8, F + 4: χ and the boundary unchanged.
        assert_eq!(counts(&world, mesh), (20, 32, 13, 1, 1));
        assert_eq!(made.top, vec![f]);
        assert_eq!(made.sides.len(), 4);
        let m = MeshRef::new(&world);
        let top: Vec<VertexId> = m.face_vertices(f).collect();
        assert_eq!(made.moved, top, "moved lists the top in face order");
        assert!(
            top.iter().all(|v| !old.contains(v)),
            "the top is all copies"
        );
        let lift = Vec3::new(0.0, 0.0, 0.5);
        let raised: Vec<Vec3> = corners.iter().map(|&p| p + lift).collect();
        assert_eq!(position_cycle(&world, f), cycle_of(&raised));
        for (&v, &p) in old.iter().zip(&corners) {
            assert_eq!(m.position(v), p, "the old corners stay");
        }
        let sides = made
            .sides
            .iter()
            .map(|&s| position_cycle(&world, s))
            .collect();
        assert_eq!(sorted(sides), walls(&corners, lift));
    }

    #[test]
    fn the_centre_of_a_grid_extrudes_as_one_piece() {
        let (mut world, built) = build(&shapes::quad_grid(4, 4));
        let mesh = built.mesh;
        let faces: Vec<FaceId> = [(1, 1), (2, 1), (1, 2), (2, 2)]
            .iter()
            .map(|&(i, j)| face_of(&world, &built, &cell(4, i, j)))
            .collect();
        let centre = built.input_vertices[12].unwrap();
        assert_eq!(counts(&world, mesh), (25, 40, 16, 1, 1));
        let made = extrude_faces(&mut world, &faces, -0.25).unwrap();
        validate(&world, mesh).unwrap();
        // The rim has 8 halfedges: V + 8 (not 9: the centre is not copied), E + 16, F + 8.
        assert_eq!(counts(&world, mesh), (33, 56, 24, 1, 1));
        assert_eq!(made.top, faces);
        assert_eq!(made.sides.len(), 8);
        assert_eq!(made.moved.len(), 9);
        assert!(made.moved.contains(&centre));
        let m = MeshRef::new(&world);
        assert_eq!(m.position(centre), Vec3::new(0.5, 0.5, -0.25));
        for &v in &made.moved {
            assert_eq!(m.position(v).z, -0.25);
        }
        for &f in &faces {
            assert!(m.face_vertices(f).all(|v| made.moved.contains(&v)));
        }
    }

    #[test]
    fn a_face_of_a_cube_keeps_the_surface_closed() {
        let (mut world, built) = build(&shapes::cube());
        let mesh = built.mesh;
        let f = face_of(&world, &built, &[4, 5, 6, 7]);
        let made = extrude_faces(&mut world, &[f], 1.0).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (12, 20, 10, 2, 0));
        assert!(mesh_stats(&world, mesh).closed);
        let p = |x: f32, y: f32| Vec3::new(x, y, 2.0);
        let top = [p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)];
        assert_eq!(position_cycle(&world, f), cycle_of(&top));
        let sides = made
            .sides
            .iter()
            .map(|&s| position_cycle(&world, s))
            .collect();
        let bottom = top.map(|q| q - Vec3::Z);
        assert_eq!(sorted(sides), walls(&bottom, Vec3::Z));
    }

    #[test]
    fn a_face_on_the_border_gets_a_wall_on_its_border_side_too() {
        // The grid scaled to cells of side 1, so the normals are exact.
        let mut soup = shapes::quad_grid(3, 3);
        soup.positions.iter_mut().for_each(|p| *p *= 3.0);
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(3, 0, 0));
        let corner = built.input_vertices[0].unwrap();
        let boundary_halfedges = |world: &World| {
            let m = MeshRef::new(world);
            MeshMembers::collect(world, mesh)
                .halfedges
                .into_iter()
                .filter(|&h| m.is_boundary(h))
                .count()
        };
        assert_eq!(boundary_halfedges(&world), 12);
        let made = extrude_faces(&mut world, &[f], 1.0).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (20, 32, 13, 1, 1));
        assert_eq!(boundary_halfedges(&world), 12, "the border is where it was");
        let m = MeshRef::new(&world);
        assert!(m.is_boundary_vertex(corner));
        assert_eq!(m.valence(corner), 3, "two bottom edges and a post");
        assert!(made.moved.iter().all(|&v| !m.is_boundary_vertex(v)));
        let bottom = [0.0, 1.0].map(|y| [0.0, 1.0].map(|x| Vec3::new(x, y, 0.0)));
        let corners = [bottom[0][0], bottom[0][1], bottom[1][1], bottom[1][0]];
        let sides = made
            .sides
            .iter()
            .map(|&s| position_cycle(&world, s))
            .collect();
        assert_eq!(sorted(sides), walls(&corners, Vec3::Z));
    }

    #[test]
    fn a_cap_of_triangles_moves_its_centre_along_the_mean_normal() {
        let (mut world, built) = build(&shapes::icosahedron());
        let mesh = built.mesh;
        let apex = built.input_vertices[0].unwrap();
        let faces: Vec<FaceId> = MeshRef::new(&world).vertex_faces(apex).collect();
        assert_eq!(faces.len(), 5);
        let (p, expected) = {
            let m = MeshRef::new(&world);
            let sum: Vec3 = faces.iter().map(|&f| m.face_area_vector(f)).sum();
            (m.position(apex), sum.normalize())
        };
        let made = extrude_faces(&mut world, &faces, 0.5).unwrap();
        validate(&world, mesh).unwrap();
        // Rim of 5: V + 5, E + 10, F + 5; the apex is inside, not copied.
        assert_eq!(counts(&world, mesh), (17, 40, 25, 2, 0));
        assert_eq!(made.moved.len(), 6);
        let m = MeshRef::new(&world);
        let moved = m.position(apex);
        assert!((moved - (p + 0.5 * expected)).length() < 1e-6);
        // By symmetry the cap's normal at the apex is the apex's direction.
        assert!(expected.dot(p.normalize()) > 1.0 - 1e-6);
        for f in made.sides {
            assert_eq!(m.face_degree(f), 4);
        }
    }

    #[test]
    fn a_triangle_of_a_tetrahedron_moves_along_its_normal() {
        let (mut world, built) = build(&shapes::tetrahedron());
        let mesh = built.mesh;
        let f = face_of(&world, &built, &[0, 1, 2]);
        let (corners, n) = {
            let m = MeshRef::new(&world);
            let c: Vec<Vec3> = m.face_vertices(f).map(|v| m.position(v)).collect();
            (c.clone(), (c[1] - c[0]).cross(c[2] - c[0]).normalize())
        };
        let made = extrude_faces(&mut world, &[f], 2.0).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (7, 12, 7, 2, 0));
        let m = MeshRef::new(&world);
        for (&v, &p) in made.moved.iter().zip(&corners) {
            assert!((m.position(v) - (p + 2.0 * n)).length() < 1e-6);
        }
    }

    #[test]
    fn directions_are_weighted_by_area() {
        // A 2 × 1 floor and a 1 × 1 wall along its x = 0 side: the shared corners move along
        // (2, 0, 4) normalised (area-weighted), not (1, 0, 1) (plain).
        let positions = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        let soup = PolygonSoup::from_faces(positions.clone(), &[[0u32, 1, 2, 3], [0, 3, 5, 4]]);
        let (mut world, built) = build(&soup);
        let faces = MeshMembers::collect(&world, built.mesh).faces;
        let made = extrude_faces(&mut world, &faces, 0.5).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(
            made.moved.len(),
            6,
            "every vertex is on the rim: all copied"
        );
        assert_eq!(counts(&world, built.mesh), (12, 19, 8, 1, 1));
        let m = MeshRef::new(&world);
        let top: Vec<Vec3> = made.moved.iter().map(|&v| m.position(v)).collect();
        let shared = Vec3::new(2.0, 0.0, 4.0).normalize();
        for (p, d) in [
            (positions[0], shared),
            (positions[3], shared),
            (positions[1], Vec3::Z),
            (positions[2], Vec3::Z),
            (positions[4], Vec3::X),
            (positions[5], Vec3::X),
        ] {
            let q = p + 0.5 * d;
            assert!(top.iter().any(|&t| bits(t) == bits(q)), "{q} missing");
        }
    }

    #[test]
    fn two_quads_meeting_at_a_corner_come_apart_there() {
        let (mut world, built) = build(&shapes::quad_grid(3, 3));
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(3, 0, 0));
        let g = face_of(&world, &built, &cell(3, 1, 1));
        let pinch = built.input_vertices[5].unwrap();
        let made = extrude_faces(&mut world, &[f, g], 1.0).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (24, 40, 17, 1, 1));
        assert_eq!(
            made.moved.len(),
            8,
            "each fan at the pinch has its own copy"
        );
        let m = MeshRef::new(&world);
        let fv: Vec<VertexId> = m.face_vertices(f).collect();
        assert!(m.face_vertices(g).all(|v| !fv.contains(&v)));
        assert_eq!(m.position(pinch), Vec3::new(1.0 / 3.0, 1.0 / 3.0, 0.0));
        assert_eq!(m.valence(pinch), 6, "four edges of the floor and two posts");
    }

    #[test]
    fn zero_and_negative_distances_keep_a_valid_mesh() {
        for d in [0.0, -0.5] {
            let (mut world, built) = build(&shapes::cube());
            let f = face_of(&world, &built, &[4, 5, 6, 7]);
            let made = extrude_faces(&mut world, &[f], d).unwrap();
            validate(&world, built.mesh).unwrap();
            let m = MeshRef::new(&world);
            for v in made.moved {
                assert_eq!(m.position(v).z, 1.0 + d);
            }
        }
    }

    #[test]
    fn extruding_flat_then_moving_along_the_directions_is_the_extrusion() {
        let soup = shapes::icosphere(1);
        let (mut once, built) = build(&soup);
        let (mut twice, _) = build(&soup);
        let v = built.input_vertices[3].unwrap();
        let mut faces: Vec<FaceId> = MeshRef::new(&once).vertex_faces(v).collect();
        let w = built.input_vertices[0].unwrap();
        faces.extend(MeshRef::new(&once).vertex_faces(w));
        faces.sort_unstable();
        faces.dedup();
        let made = extrude_faces(&mut once, &faces, 0.3).unwrap();
        let flat = extrude_faces(&mut twice, &faces, 0.0).unwrap();
        assert_eq!(made.moved, flat.moved);
        let directions = extrude_directions(&twice, &flat.top);
        let order: Vec<VertexId> = directions.iter().map(|x| x.0).collect();
        assert_eq!(order, flat.moved);
        for (v, d) in directions {
            let p = MeshRef::new(&twice).position(v);
            twice.get_mut::<Position>(v.0).unwrap().0 = p + 0.3 * d;
        }
        validate(&once, built.mesh).unwrap();
        assert_eq!(to_soup(&once, built.mesh), to_soup(&twice, built.mesh));
    }

    #[test]
    fn refusals_leave_the_world_untouched() {
        let (mut world, built) = build(&shapes::cube());
        let mesh = built.mesh;
        let other = build_into(&mut world, &shapes::tetrahedron());
        let f = face_of(&world, &built, &[4, 5, 6, 7]);
        let g = face_of(&world, &other, &[0, 1, 2]);
        let gone = gone_face(&mut world);
        let all = MeshMembers::collect(&world, mesh).faces;
        let before = snapshot(&world, mesh);
        let cases: Vec<(Vec<FaceId>, f32)> = vec![
            (vec![], 1.0),
            (vec![f, gone], 1.0),
            (vec![f, f], 1.0),
            (vec![f, g], 1.0),
            (all.clone(), 1.0),
            (vec![f], f32::NAN),
            (vec![f], f32::INFINITY),
        ];
        for (faces, d) in cases {
            let refusal = extrude_faces(&mut world, &faces, d).unwrap_err();
            assert_untouched(&world, mesh, &before);
            let expected_kind = match (faces.len(), d) {
                (2, _) if faces[1] == gone => matches!(refusal, Refusal::Stale(_)),
                (6, _) => matches!(refusal, Refusal::ClosedRegion(_)),
                _ => matches!(refusal, Refusal::BadParameter(_)),
            };
            assert!(expected_kind, "{faces:?} {d}: {refusal}");
        }
        validate(&world, mesh).unwrap();
        validate(&world, other.mesh).unwrap();
        // A square far up the z axis: a finite distance that would carry it past the largest
        // float.
        let (mut world, built) = build(&far_square());
        let f = face_of(&world, &built, &[0, 1, 2, 3]);
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::NotFinite(_)),
            |w| extrude_faces(w, &[f], f32::MAX),
        );
    }

    #[test]
    fn undo_through_the_seeds_restores_the_mesh_and_redo_repeats_it() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(4, 4), Uvs::PerCorner));
        let mesh = built.mesh;
        let faces: Vec<FaceId> = [(1, 1), (2, 1), (1, 2), (0, 0)]
            .iter()
            .map(|&(i, j)| face_of(&world, &built, &cell(4, i, j)))
            .collect();
        let plan = plan_extrude(&world, &faces).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, mesh, &seeds, |world| {
            let _ = apply_extrude(world, plan, 0.75);
        });
    }

    #[test]
    fn uvs_normals_and_colours_are_carried() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(2, 2), Uvs::PerCorner));
        let mesh = built.mesh;
        let f = face_of(&world, &built, &cell(2, 1, 0));
        let (rim, uvs) = corner_uvs(&world, f);
        let made = extrude_faces(&mut world, &[f], 1.0).unwrap();
        validate(&world, mesh).unwrap();
        // Every face corner has a UV (and no other halfedge); the top's corners kept theirs.
        assert_attributes_complete(&world, mesh);
        // Each side a b b' a': corners at b and b' take the UV of the rim corner at b, those at
        // a and a' the UV of the corner at a; the copy at a' has a's normal and colour.
        assert_sides_carry_rim(&world, &rim, &uvs, &made.sides);
    }
}
