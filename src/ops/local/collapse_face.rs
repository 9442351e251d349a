//! Face collapse (Scotty3D's collapse face): every corner of a face merges into one vertex at
//! the face's centroid.
//!
//! ```text
//!   o ---- o ---- o ---- o          o ---- o ---- o ---- o
//!   |      |      |      |          |      |\    /|      |
//!   |      |      |      |          |      | \  / |      |
//!   o ---- d ---- c ---- o          o ---- o- k  -o ---- o     the centre quad a b c d
//!   |      |  f   |      |    →     |      | /  \ |      |     collapses to k, its centroid:
//!   |      |      |      |          |      |/    \|      |     the four quads beside it
//!   o ---- a ---- b ---- o          o ---- o      o ---- o     become triangles, the corner
//!   |      |      |      |          |      |      |      |     quads keep four corners
//!   o ---- o ---- o ---- o          o ---- o ---- o ---- o
//! ```
//!
//! The first corner (the tip of the face's halfedge's twin, i.e. `from_vertex` of
//! [`MeshRef::face_halfedge`]) survives as the merged vertex `k`, moved to the centroid; the
//! other corners are removed and every halfedge that pointed at them points at `k`. The face
//! and its edges go. Across each side of the face: a polygon loses that side (one corner
//! fewer: a quad becomes a triangle); a triangle degenerates to an edge, so it is removed and
//! its two other sides become one edge (as an edge collapse does). Triangles in a row across
//! consecutive sides that share their third corner all fold into one edge. Counts for a face of
//! n sides with t triangles beside it: V − (n − 1), E − n − t, F − 1 − t; χ unchanged.
//!
//! Attributes follow the position: `k` takes the mean of the corners' normals (renormalised)
//! and colours; a corner at `k` whose UV is the face's own UV at that corner (no seam between
//! them) takes the face's mean UV, the UV of its centroid; a corner across a seam keeps its own.
//!
//! Refusals, in the order they are checked, each leaving the world untouched:
//! - `Stale`: `f` is not a live face;
//! - `BoundaryEdge`: a side of `f` is on the boundary (Scotty3D refuses boundary faces);
//! - `TooSmall`: nothing of the face's component would be left (a tetrahedron);
//! - `PinchedVertex`: two corners on the boundary (the merged vertex would touch it twice);
//! - `DegenerateFace`: another face holding two corners of `f` that are not the ends of the one
//!   side it shares with `f` (it would visit `k` twice; this includes an edge joining two
//!   corners across the face);
//! - `LinkCondition` (the link condition of Dey, Edelsbrunner et al. 1999, for a face): a vertex
//!   joined to two corners other than through a row of triangles beside `f` (two edges would
//!   join it to `k`);
//! - `DanglingEdge`: a row of triangles whose two outer sides are both on the boundary (the
//!   merged edge would have no face);
//! - `ValenceTooLow`: the third corner of a triangle beside `f`, or `k` itself, left with fewer
//!   than 3 edges (2 on the boundary);
//! - `NotFinite`: the centroid is not finite.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;

use crate::mesh::attributes::{
    VertexColor, VertexNormal, corner_uv, mean_color, of_element, set_corner_uv,
};
use crate::mesh::elements::{Edge, Face, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values};

use super::{Refusal, he, link};

/// The face across one side `t` (the twin of the face's side) of the collapsing face.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    /// A polygon of four or more sides: it loses `t`, `prev` then runs into `next`.
    Polygon {
        face: FaceId,
        prev: HalfedgeId,
        next: HalfedgeId,
    },
    /// A triangle `t`, `x`, `y` with third corner `apex`: it goes.
    Triangle {
        face: FaceId,
        x: HalfedgeId,
        y: HalfedgeId,
        apex: VertexId,
    },
}

impl Side {
    fn apex(&self) -> Option<VertexId> {
        match *self {
            Side::Triangle { apex, .. } => Some(apex),
            Side::Polygon { .. } => None,
        }
    }
}

/// A row of triangles beside consecutive sides with one apex: their outer halfedges `o1`
/// (apex → the row's first corner) and `o2` (the row's last corner → apex) become twins on
/// `edge` (the edge of `o1`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Glue {
    apex: VertexId,
    o1: HalfedgeId,
    o2: HalfedgeId,
    edge: EdgeId,
    /// The halfedge `edge` names afterwards (an interior one).
    interior: HalfedgeId,
    /// The apex's new halfedge, when its old one goes.
    apex_halfedge: Option<HalfedgeId>,
}

/// Everything a face collapse touches, collected by [`plan_collapse_face`].
#[derive(Clone, Debug, PartialEq)]
pub struct CollapseFacePlan {
    face: FaceId,
    /// The face's halfedges, in order; corner `i` is the start of halfedge `i`.
    ring: Vec<HalfedgeId>,
    corners: Vec<VertexId>,
    /// Every other vertex joined to a corner.
    around: Vec<VertexId>,
    position: Vec3,
    sides: Vec<Side>,
    glues: Vec<Glue>,
    /// Surviving halfedges into the removed corners: they will point at the kept one.
    retarget: Vec<HalfedgeId>,
    /// The kept corner's halfedge afterwards.
    kept_halfedge: HalfedgeId,
    removed_halfedges: Vec<HalfedgeId>,
    removed_edges: Vec<EdgeId>,
    removed_faces: Vec<FaceId>,
}

impl CollapseFacePlan {
    /// The corners and every vertex joined to them: their neighbourhood (see
    /// [`crate::mesh::change::neighbourhood`]) covers every face around the corners with all
    /// their corners before, and everything around the merged vertex after.
    pub fn seeds(&self) -> Vec<VertexId> {
        self.corners.iter().chain(&self.around).copied().collect()
    }

    /// The vertex that survives.
    pub fn kept(&self) -> VertexId {
        self.corners[0]
    }

    /// Where it goes: the face's centroid.
    pub fn position(&self) -> Vec3 {
        self.position
    }
}

/// Whether the faces reachable from `f` across edges number at most `limit`.
fn component_within(m: &MeshRef<'_>, f: FaceId, limit: usize) -> bool {
    let mut seen = EntityHashSet::default();
    seen.insert(f.0);
    let mut stack = vec![f];
    while let Some(g) = stack.pop() {
        for h in m.face_halfedges(g) {
            if let Some(n) = m.face(m.twin(h))
                && seen.insert(n.0)
            {
                if seen.len() > limit {
                    return false;
                }
                stack.push(n);
            }
        }
    }
    true
}

/// Checks that `f` can be collapsed and collects everything the collapse touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_collapse_face(world: &World, f: FaceId) -> Result<CollapseFacePlan, Refusal> {
    let m = MeshRef::new(world);
    let stale = Refusal::Stale(ElementId::Face(f));
    let start = m.try_face(f).ok_or(stale.clone())?.halfedge;
    m.try_halfedge(start).ok_or(stale)?;
    let ring: Vec<HalfedgeId> = m.face_halfedges(f).collect();
    let corners: Vec<VertexId> = ring.iter().map(|&h| m.from_vertex(h)).collect();
    let sides = sides_across(&m, &ring)?;
    let mut removed_faces = vec![f];
    for s in &sides {
        if let Side::Triangle { face, .. } = *s
            && !removed_faces.contains(&face)
        {
            removed_faces.push(face);
        }
    }
    if component_within(&m, f, removed_faces.len()) {
        return Err(Refusal::TooSmall);
    }
    let boundary: Vec<VertexId> = corners
        .iter()
        .copied()
        .filter(|&c| m.is_boundary_vertex(c))
        .collect();
    if let [_, second, ..] = boundary[..] {
        return Err(Refusal::PinchedVertex(ElementId::Vertex(second)));
    }
    check_faces_around(&m, f, &corners, &sides)?;
    let joins = Joins::count(&m, &corners, &sides)?;
    let rows = Rows::find(&m, &ring, &sides)?;
    check_valences(&m, &joins, &corners, boundary.is_empty())?;
    let position = m.face_centroid(f);
    if !position.is_finite() {
        return Err(Refusal::NotFinite(position));
    }
    let gone: EntityHashSet = rows.removed_halfedges.iter().map(|h| h.0).collect();
    let mut retarget = Vec::new();
    for &c in &corners[1..] {
        for o in m.vertex_outgoing(c) {
            let into = m.twin(o);
            if !gone.contains(&into.0) {
                retarget.push(into);
            }
        }
    }
    let kept_halfedge = match boundary.first() {
        Some(&c) => m.vertex_halfedge(c),
        None => corners
            .iter()
            .flat_map(|&c| m.vertex_outgoing(c))
            .find(|h| !gone.contains(&h.0))
            .ok_or(Refusal::TooSmall)?,
    };
    Ok(CollapseFacePlan {
        face: f,
        ring,
        corners,
        around: joins.around,
        position,
        sides,
        glues: rows.glues,
        retarget,
        kept_halfedge,
        removed_halfedges: rows.removed_halfedges,
        removed_edges: rows.removed_edges,
        removed_faces,
    })
}

/// The face across each side of the face whose halfedges are `ring`.
///
/// # Refusals
/// [`Refusal::BoundaryEdge`] for a side on the boundary.
fn sides_across(m: &MeshRef<'_>, ring: &[HalfedgeId]) -> Result<Vec<Side>, Refusal> {
    let mut sides = Vec::with_capacity(ring.len());
    for &h in ring {
        let t = m.twin(h);
        let Some(face) = m.face(t) else {
            return Err(Refusal::BoundaryEdge(ElementId::Edge(m.edge(h))));
        };
        let (x, y) = (m.next(t), m.prev(t));
        sides.push(if m.next(x) == y {
            Side::Triangle {
                face,
                x,
                y,
                apex: m.to_vertex(x),
            }
        } else {
            Side::Polygon {
                face,
                prev: y,
                next: x,
            }
        });
    }
    Ok(sides)
}

/// Every face but `f` may hold one corner, or the two ends of the one side it shares with `f`.
///
/// # Refusals
/// [`Refusal::DegenerateFace`] for a face that holds more.
fn check_faces_around(
    m: &MeshRef<'_>,
    f: FaceId,
    corners: &[VertexId],
    sides: &[Side],
) -> Result<(), Refusal> {
    let n = corners.len();
    let is_corner: EntityHashSet = corners.iter().map(|c| c.0).collect();
    let mut checked = EntityHashSet::default();
    checked.insert(f.0);
    for &c in corners {
        for g in m.vertex_faces(c) {
            if !checked.insert(g.0) {
                continue;
            }
            let held: Vec<VertexId> = m
                .face_vertices(g)
                .filter(|v| is_corner.contains(&v.0))
                .collect();
            let across_one_side = held.len() == 2
                && (0..n).any(|i| {
                    let face = match sides[i] {
                        Side::Triangle { face, .. } | Side::Polygon { face, .. } => face,
                    };
                    let ends = [corners[i], corners[(i + 1) % n]];
                    face == g && held.iter().all(|v| ends.contains(v))
                });
            if held.len() > 1 && !across_one_side {
                return Err(Refusal::DegenerateFace(ElementId::Face(g)));
            }
        }
    }
    Ok(())
}

/// Every other vertex joined to the corners (`around`, in the order met), and for each by how
/// many edges and as the third corner of how many triangles beside the face (each folds two of
/// those edges into one).
struct Joins {
    around: Vec<VertexId>,
    counts: EntityHashMap<(usize, usize)>,
}

impl Joins {
    /// Counts the joins.
    ///
    /// # Refusals
    /// [`Refusal::LinkCondition`] for a vertex joined to two corners other than through a row
    /// of triangles.
    fn count(m: &MeshRef<'_>, corners: &[VertexId], sides: &[Side]) -> Result<Joins, Refusal> {
        let is_corner: EntityHashSet = corners.iter().map(|c| c.0).collect();
        let mut around: Vec<VertexId> = Vec::new();
        let mut counts: EntityHashMap<(usize, usize)> = EntityHashMap::default();
        for &c in corners {
            for h in m.vertex_outgoing(c) {
                let w = m.to_vertex(h);
                if is_corner.contains(&w.0) {
                    continue;
                }
                let entry = counts.entry(w.0).or_insert((0, 0));
                if entry.0 == 0 {
                    around.push(w);
                }
                entry.0 += 1;
            }
        }
        for s in sides {
            if let Some(apex) = s.apex() {
                counts.entry(apex.0).or_insert((0, 0)).1 += 1;
            }
        }
        for &w in &around {
            let (edges, triangles) = counts[&w.0];
            if edges.saturating_sub(triangles) > 1 {
                return Err(Refusal::LinkCondition(ElementId::Vertex(w)));
            }
        }
        Ok(Joins { around, counts })
    }
}

/// The rows of triangles with one apex across consecutive sides, each glued into one edge, and
/// every halfedge and edge the collapse removes.
struct Rows {
    glues: Vec<Glue>,
    removed_halfedges: Vec<HalfedgeId>,
    removed_edges: Vec<EdgeId>,
}

impl Rows {
    /// Finds the rows.
    ///
    /// # Refusals
    /// [`Refusal::DanglingEdge`] for a row whose two outer sides are on the boundary,
    /// [`Refusal::TooSmall`] for one apex all round (a closed pyramid).
    fn find(m: &MeshRef<'_>, ring: &[HalfedgeId], sides: &[Side]) -> Result<Rows, Refusal> {
        let n = ring.len();
        let same_row = |i: usize, j: usize| matches!((sides[i].apex(), sides[j].apex()), (Some(p), Some(q)) if p == q);
        let mut glues = Vec::new();
        let mut removed_halfedges: Vec<HalfedgeId> = Vec::new();
        let mut removed_edges: Vec<EdgeId> = ring.iter().map(|&h| m.edge(h)).collect();
        for &h in ring {
            removed_halfedges.extend([h, m.twin(h)]);
        }
        for s in 0..n {
            let Side::Triangle { face, x, apex, .. } = sides[s] else {
                continue;
            };
            if same_row((s + n - 1) % n, s) {
                continue;
            }
            let mut row = vec![s];
            while row.len() < n && same_row(row[row.len() - 1], (row[row.len() - 1] + 1) % n) {
                row.push((row[row.len() - 1] + 1) % n);
            }
            let mut row_halfedges = Vec::new();
            let mut last_y = x;
            for &k in &row {
                if let Side::Triangle { x, y, .. } = sides[k] {
                    row_halfedges.extend([x, y]);
                    removed_edges.push(m.edge(y));
                    last_y = y;
                }
            }
            let (o1, o2) = (m.twin(x), m.twin(last_y));
            if m.is_boundary(o1) && m.is_boundary(o2) {
                return Err(Refusal::DanglingEdge(ElementId::Face(face)));
            }
            let apex_halfedge = row_halfedges
                .contains(&m.vertex_halfedge(apex))
                .then_some(o1);
            removed_halfedges.extend(row_halfedges);
            glues.push(Glue {
                apex,
                o1,
                o2,
                edge: m.edge(x),
                interior: if m.is_boundary(o1) { o2 } else { o1 },
                apex_halfedge,
            });
        }
        if glues.is_empty() && sides.iter().all(|s| s.apex().is_some()) {
            // One apex all round: a closed pyramid, which the size check has refused.
            return Err(Refusal::TooSmall);
        }
        Ok(Rows {
            glues,
            removed_halfedges,
            removed_edges,
        })
    }
}

/// The third corner of every triangle beside the face, and the merged vertex, keep at least 3
/// edges (2 on the boundary).
///
/// # Refusals
/// [`Refusal::ValenceTooLow`] naming the vertex that would not.
fn check_valences(
    m: &MeshRef<'_>,
    joins: &Joins,
    corners: &[VertexId],
    closed: bool,
) -> Result<(), Refusal> {
    for &w in &joins.around {
        let (edges, triangles) = joins.counts[&w.0];
        if triangles == 0 {
            continue;
        }
        let minimum = if m.is_boundary_vertex(w) { 2 } else { 3 };
        if m.valence(w) + 1 - edges < minimum {
            return Err(Refusal::ValenceTooLow(ElementId::Vertex(w), minimum));
        }
    }
    let minimum = if closed { 3 } else { 2 };
    if joins.around.len() < minimum {
        return Err(Refusal::ValenceTooLow(
            ElementId::Vertex(corners[0]),
            minimum,
        ));
    }
    Ok(())
}

/// What a face collapse needs to carry the mesh's attributes (read before anything changes).
struct Carry {
    /// Every surviving corner at a corner of the face, to be given the face's mean UV.
    corners: Vec<HalfedgeId>,
    uv: Vec2,
    normal: Option<Vec3>,
    color: Option<[u8; 3]>,
}

impl Carry {
    fn read(world: &World, p: &CollapseFacePlan) -> Option<Self> {
        let has = of_element(world, p.face.0);
        if has.is_empty() {
            return None;
        }
        let m = MeshRef::new(world);
        let gone: EntityHashSet = p.removed_halfedges.iter().map(|h| h.0).collect();
        let mut corners = Vec::new();
        let mut uv = Vec2::ZERO;
        if has.uv {
            // The face's UV at corner i + 1 is the one of halfedge i (its tip).
            let own: Vec<Vec2> = p
                .ring
                .iter()
                .map(|&h| corner_uv(world, h).unwrap_or_default())
                .collect();
            uv = own.iter().copied().sum::<Vec2>() / own.len() as f32;
            let bits = |u: Vec2| u.to_array().map(f32::to_bits);
            let n = p.corners.len();
            for (i, &c) in p.corners.iter().enumerate() {
                let at_c = own[(i + n - 1) % n];
                for o in m.vertex_outgoing(c) {
                    let into = m.twin(o);
                    if m.face(into).is_some()
                        && !gone.contains(&into.0)
                        && corner_uv(world, into).is_some_and(|u| bits(u) == bits(at_c))
                    {
                        corners.push(into);
                    }
                }
            }
        }
        let normal = has.normals.then(|| {
            let sum: Vec3 = p
                .corners
                .iter()
                .map(|c| world.get::<VertexNormal>(c.0).map_or(Vec3::ZERO, |x| x.0))
                .sum();
            (sum / p.corners.len() as f32).normalize_or_zero()
        });
        let color = has.colors.then(|| {
            mean_color(
                p.corners
                    .iter()
                    .map(|c| world.get::<VertexColor>(c.0).map_or([0; 3], |x| x.0)),
            )
        });
        Some(Self {
            corners,
            uv,
            normal,
            color,
        })
    }

    fn write(self, world: &mut World, kept: VertexId) {
        for h in self.corners {
            set_corner_uv(world, h, self.uv);
        }
        if let Some(n) = self.normal {
            world.entity_mut(kept.0).insert(VertexNormal(n));
        }
        if let Some(c) = self.color {
            world.entity_mut(kept.0).insert(VertexColor(c));
        }
    }
}

/// Carries out a collapse planned by [`plan_collapse_face`] on the unchanged world, attributes
/// included. Returns the merged vertex.
pub fn apply_collapse_face(world: &mut World, p: CollapseFacePlan) -> VertexId {
    crate::checks::checked_assert_eq!(
        plan_collapse_face(world, p.face).as_ref(),
        Ok(&p),
        "stale face collapse plan"
    );
    let carry = Carry::read(world, &p);
    let kept = p.corners[0];
    for &h in &p.retarget {
        he(world, h).vertex = kept;
    }
    for s in &p.sides {
        if let Side::Polygon { face, prev, next } = *s {
            link(world, prev, next);
            world.get_mut::<Face>(face.0).expect("planned").halfedge = next;
        }
    }
    for g in &p.glues {
        for (x, twin) in [(g.o1, g.o2), (g.o2, g.o1)] {
            let mut links = he(world, x);
            links.twin = twin;
            links.edge = g.edge;
        }
        world.get_mut::<Edge>(g.edge.0).expect("planned").halfedge = g.interior;
        if let Some(h) = g.apex_halfedge {
            world.get_mut::<Vertex>(g.apex.0).expect("planned").halfedge = h;
        }
    }
    world.get_mut::<Vertex>(kept.0).expect("planned").halfedge = p.kept_halfedge;
    world.get_mut::<Position>(kept.0).expect("planned").0 = p.position;
    let entities = p
        .removed_faces
        .iter()
        .map(|f| f.0)
        .chain(p.removed_halfedges.iter().map(|h| h.0))
        .chain(p.removed_edges.iter().map(|e| e.0))
        .chain(p.corners[1..].iter().map(|v| v.0));
    for e in entities {
        world.despawn(e);
    }
    if let Some(carry) = carry {
        carry.write(world, kept);
    }
    kept
}

/// Collapses `f` to its centroid (see the module doc): plan, then apply. Returns the merged
/// vertex.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn collapse_face(world: &mut World, f: FaceId) -> Result<VertexId, Refusal> {
    let plan = plan_collapse_face(world, f)?;
    Ok(apply_collapse_face(world, plan))
}

/// Collapsing a face (the `collapse:A,B,C` step): a local edit.
pub const COLLAPSE_FACE: Declaration = Declaration::new("collapse")
    .titled("Collapse")
    .described("collapse the active face to its centroid")
    .on_key("C")
    .naming(Names::Face)
    .in_section(Section::Local);

/// [`collapse_face`] as a registered operation: `collapse:A,B,C`, C on a face.
pub struct CollapseFace;

impl MeshOperation for CollapseFace {
    fn declaration(&self) -> &'static Declaration {
        &COLLAPSE_FACE
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_collapse_face(world, values.face().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = plan_collapse_face(world, values.face()?)?;
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
            let made = apply_collapse_face(world, plan);
            let summary = format!("collapsed to {made}");
            (summary, Some(made.into()))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::attributes::CornerUv;
    use crate::mesh::{MeshMembers, PolygonSoup, shapes, validate};
    use crate::ops::local::testkit::*;

    #[test]
    fn the_centre_quad_of_a_grid_goes_to_its_centroid() {
        // Scotty3D's test: the centre quad of a 3 × 3 quad grid.
        let (mut world, built) = build(&shapes::quad_grid(3, 3));
        let f = face_of(&world, &built, &[5, 6, 10, 9]);
        let k = MeshRef::new(&world).face_centroid(f);
        assert!((k - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
        let kept = collapse_face(&mut world, f).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(MeshRef::new(&world).position(kept), k);
        assert_eq!(counts(&world, built.mesh), (13, 20, 8, 1, 1));
        let p = |i: usize| [(i % 4) as f32 / 3.0, (i / 4) as f32 / 3.0, 0.0];
        let k = k.to_array();
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[
                &[p(0), p(1), k, p(4)],
                &[p(1), p(2), k],
                &[p(2), p(3), p(7), k],
                &[p(4), k, p(8)],
                &[k, p(7), p(11)],
                &[p(8), k, p(13), p(12)],
                &[k, p(14), p(13)],
                &[k, p(11), p(15), p(14)],
            ])
        );
    }

    #[test]
    fn a_triangle_of_a_closed_mesh_takes_its_three_neighbours_with_it() {
        let (mut world, built) = build(&shapes::icosahedron());
        let f = MeshMembers::collect(&world, built.mesh).faces[0];
        let kept = collapse_face(&mut world, f).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (10, 24, 16, 2, 0));
        assert_eq!(MeshRef::new(&world).valence(kept), 6);
    }

    #[test]
    fn a_face_with_one_corner_on_the_border_leaves_it_there() {
        // Triangle 1 6 5 of a triangulated 3 × 3 grid touches the border at vertex 1 only.
        let (mut world, built) = build(&shapes::grid(3, 3));
        let f = face_of(&world, &built, &[1, 6, 5]);
        let kept = collapse_face(&mut world, f).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (14, 27, 14, 1, 1));
        assert!(MeshRef::new(&world).is_boundary_vertex(kept));
    }

    #[test]
    fn a_row_of_triangles_with_one_apex_folds_into_one_edge() {
        // An icosahedron whose face a b c is split into three around its centre o: collapsing
        // o a b, the triangles o b c and o c a beside two of its sides share the apex c, and
        // their three edges to c fold into one.
        let ico = shapes::icosahedron();
        let [a, b, c] = [0, 1, 2].map(|k| ico.face(0)[k]);
        let mut soup = PolygonSoup::from_faces(ico.positions.clone(), &[[0u32; 0]; 0]);
        let o = soup.positions.len() as u32;
        let centre = [a, b, c]
            .iter()
            .map(|&i| soup.positions[i as usize])
            .sum::<Vec3>()
            / 3.0;
        soup.positions.push(centre);
        for face in ico.faces().skip(1) {
            soup.push_face(face);
        }
        for face in [[o, a, b], [o, b, c], [o, c, a]] {
            soup.push_face(&face);
        }
        let (mut world, built) = build(&soup);
        assert_eq!(counts(&world, built.mesh), (13, 33, 22, 2, 0));
        let apex = vertex(&built, c as usize);
        assert_eq!(MeshRef::new(&world).valence(apex), 6);
        let f = face_of(&world, &built, &[o as usize, a as usize, b as usize]);
        collapse_face(&mut world, f).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (11, 27, 18, 2, 0));
        assert_eq!(MeshRef::new(&world).valence(apex), 4);
    }

    /// A triangular bipyramid: apexes 0 (top) and 1 (bottom) around the triangle 2 3 4.
    fn bipyramid() -> PolygonSoup {
        let ring = |i: f32| {
            let a = i * std::f32::consts::TAU / 3.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        };
        PolygonSoup::from_faces(
            vec![Vec3::Z, -Vec3::Z, ring(0.0), ring(1.0), ring(2.0)],
            &[
                [0, 2, 3],
                [0, 3, 4],
                [0, 4, 2],
                [1, 3, 2],
                [1, 4, 3],
                [1, 2, 4],
            ],
        )
    }

    #[test]
    fn refusals_leave_the_mesh_untouched() {
        // A face on the border (Scotty3D's refusal).
        let (mut world, built) = build(&shapes::quad_grid(3, 3));
        let corner = face_of(&world, &built, &[0, 1, 5, 4]);
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::BoundaryEdge(_)),
            |w| collapse_face(w, corner),
        );
        // A stale face.
        let centre = face_of(&world, &built, &[5, 6, 10, 9]);
        collapse_face(&mut world, centre).unwrap();
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Face(centre)),
            |w| collapse_face(w, centre),
        );
        // Any face of a tetrahedron.
        let (mut world, built) = build(&shapes::tetrahedron());
        let f = MeshMembers::collect(&world, built.mesh).faces[0];
        assert_refused(&mut world, built.mesh, Refusal::TooSmall, |w| {
            collapse_face(w, f)
        });
        // Two corners on the border, no side on it.
        let (mut world, built) = build(&shapes::grid(2, 2));
        let f = face_of(&world, &built, &[1, 5, 4]);
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::PinchedVertex(_)),
            |w| collapse_face(w, f),
        );
        // A 3 × 3 torus: the vertex two steps along a ring from a corner is joined to two
        // corners by two quads' edges.
        let (mut world, built) = build(&shapes::torus(3, 3));
        let f = MeshMembers::collect(&world, built.mesh).faces[0];
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::LinkCondition(_)),
            |w| collapse_face(w, f),
        );
        // A bipyramid's face: the equator's third vertex and the bottom apex would keep two
        // edges each.
        let (mut world, built) = build(&bipyramid());
        let f = face_of(&world, &built, &[0, 2, 3]);
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::ValenceTooLow(_, 3)),
            |w| collapse_face(w, f),
        );
    }

    #[test]
    fn corners_at_the_merged_vertex_take_the_faces_mean_uv() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(3, 3), Uvs::Continuous));
        let f = face_of(&world, &built, &[5, 6, 10, 9]);
        let (mean_uv, colour) = {
            let m = MeshRef::new(&world);
            let uvs: Vec<Vec2> = m
                .face_halfedges(f)
                .map(|h| world.get::<CornerUv>(h.0).unwrap().0)
                .collect();
            let colours: Vec<[u8; 3]> = m
                .face_vertices(f)
                .map(|v| world.get::<VertexColor>(v.0).unwrap().0)
                .collect();
            (uvs.iter().copied().sum::<Vec2>() / 4.0, mean_color(colours))
        };
        let kept = collapse_face(&mut world, f).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_attributes_complete(&world, built.mesh);
        assert_eq!(world.get::<VertexColor>(kept.0).unwrap().0, colour);
        let m = MeshRef::new(&world);
        let mut seen = 0;
        for o in m.vertex_outgoing(kept) {
            let into = m.twin(o);
            if m.face(into).is_some() {
                assert_eq!(world.get::<CornerUv>(into.0).unwrap().0, mean_uv);
                seen += 1;
            }
        }
        assert_eq!(seen, 8);
    }

    #[test]
    fn undo_and_redo_restore_both_meshes() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(3, 3), Uvs::Continuous));
        let f = face_of(&world, &built, &[5, 6, 10, 9]);
        let plan = plan_collapse_face(&world, f).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, built.mesh, &seeds, |w| {
            apply_collapse_face(w, plan);
        });
        let (mut world, built) = build(&with_attributes(shapes::grid(3, 3), Uvs::Continuous));
        let f = face_of(&world, &built, &[1, 6, 5]);
        let plan = plan_collapse_face(&world, f).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, built.mesh, &seeds, |w| {
            apply_collapse_face(w, plan);
        });
    }
}
