//! Edge collapse: the edge's two vertices become one.
//!
//! ```text
//!         c                     c
//!        / \                    |
//!       /   \                   |
//!      a --h-> b     →          a'        a' at the midpoint (or a given position)
//!       \  t  /                 |
//!        \   /                  |
//!         d                     d
//! ```
//!
//! `h` is the edge's halfedge ([`MeshRef::edge_halfedge`]; [`plan_collapse_halfedge`] picks
//! another): its start `a` survives (the entity is kept, moved to the midpoint or the given
//! position) and its tip `b` is despawned, every halfedge that pointed at `b` now pointing at
//! `a`. A triangle on either side disappears and its two other edges become one (the edge `c a`
//! is kept, `c b` despawned, with the triangle's face and three halfedges); a polygon side just
//! loses `b`'s corner (a quad becomes a triangle). A boundary edge has one real side: its
//! boundary loop loses a side. Counts: an interior edge between two triangles V − 1, E − 3,
//! F − 2; a boundary edge with a triangle V − 1, E − 2, F − 1; each polygon side instead of a
//! triangle gives back one edge and one face (two quads: V − 1, E − 1); χ never changes.
//!
//! ```text
//!         c                         c
//!        / \                        |
//!       /   \                       |
//!      a --h-> b         →          a'         a triangle above: gone, c a and c b merge;
//!      |   t   |                   / \         a quad below: loses b, becomes a' x y
//!      |   g   |                  /   \
//!      x ----- y                 x --- y
//! ```
//!
//! Afterwards `a` points at an outgoing halfedge that still exists, its boundary one if it is
//! on the boundary; so does every opposite vertex `c`, `d`; each surviving edge names an
//! interior halfedge where it has one.
//!
//! Refusals, in the order they are checked, each leaving the world untouched:
//! - `Stale`: the edge (or halfedge) is not live;
//! - `BoundaryPinch`: an interior edge whose endpoints are both on the boundary (the merged
//!   vertex would touch the boundary twice);
//! - `LinkCondition`, vertex part (Dey, Edelsbrunner et al. 1999; Hoppe 1996): a vertex joined
//!   to both `a` and `b` other than the opposite vertices of the triangles on the edge (the
//!   collapse would make two edges between the same vertices);
//! - `TooSmall`, the edge part of the link condition: both opposite vertices `c`, `d` joined
//!   and the triangles `a c d`, `b c d` both present — on a manifold mesh that is exactly a
//!   tetrahedron (a closed component of 4 vertices; a larger one would be reported as
//!   `LinkCondition`, but the four triangles close up, so there is none); PMP's vertex-only test
//!   lets it through;
//! - per side: `DanglingEdge`, a triangle whose other two sides are both on the boundary (the
//!   merged edge would have no face; a lone triangle); `ValenceTooLow`, an opposite vertex left
//!   with fewer than 3 edges (2 on the boundary); `DegenerateFace`, a boundary loop of 3 sides
//!   (it would close into a 2-gon);
//! - `DegenerateFace`: another face holding both `a` and `b` (it would visit the merged vertex
//!   twice);
//! - `ValenceTooLow`: the merged vertex would be left with fewer than 3 edges (2 on the
//!   boundary), e.g. two quads glued along the chain `c a d` and `c b d`;
//! - `Unsuitable`: a position that is not finite;
//! - `NormalFlip`, only when [`CollapseOptions::max_normal_change_deg`] is set: a surviving face
//!   around `a` or `b` (polygon sides included) whose normal would turn by more than that angle,
//!   or would vanish.

use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use crate::mesh::elements::{Edge, Face, Halfedge, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::topology::{Lookups, MAX_LOOP, MeshRef, newell_area_vector};

use super::{Refusal, he, link, live_edge};

/// How to collapse.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CollapseOptions {
    /// Where the surviving vertex goes; `None`: the edge's midpoint.
    pub position: Option<Vec3>,
    /// Refuse when a surviving face's normal would turn by more than this many degrees
    /// (`None`: no check). The simplifier uses it.
    pub max_normal_change_deg: Option<f32>,
}

/// What a collapse did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollapseResult {
    /// The surviving vertex.
    pub kept: VertexId,
    /// The removed vertex (its id is now stale).
    pub removed: VertexId,
    /// What [`super::vertex_split`] needs to undo the collapse exactly.
    pub record: CollapseRecord,
}

/// What undoing a collapse needs (Hoppe 1996): the surviving vertex, both positions before the
/// collapse, and the opposite vertices ("wings") of the triangles that disappeared — on the
/// side of the halfedge from the kept to the removed vertex (`left`) and on the other (`right`);
/// `None` where that side was the boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollapseRecord {
    /// The vertex that survived.
    pub kept: VertexId,
    /// Its position before the collapse.
    pub kept_position: Vec3,
    /// The removed vertex's position before the collapse.
    pub removed_position: Vec3,
    /// The wing on the kept → removed halfedge's side.
    pub left: Option<VertexId>,
    /// The wing on the other side.
    pub right: Option<VertexId>,
    /// Whether both sides were triangles or boundary, so that a split restores the mesh.
    pub invertible: bool,
}

impl CollapseRecord {
    /// The triangles the collapse removed: one per wing (2 inside, 1 on the boundary; a
    /// polygon side loses a corner, not the face).
    pub fn triangles_removed(&self) -> usize {
        usize::from(self.left.is_some()) + usize::from(self.right.is_some())
    }
}

/// One side of the collapsing edge.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    /// No face: `x` is a boundary halfedge.
    Boundary {
        x: HalfedgeId,
        next: HalfedgeId,
        prev: HalfedgeId,
    },
    /// A triangle that disappears: its halfedges `x`, `next`, `prev`, and the twins of the two
    /// other sides, which become twins of each other.
    Triangle {
        face: FaceId,
        x: HalfedgeId,
        next: HalfedgeId,
        prev: HalfedgeId,
        opposite: VertexId,
    },
    /// A polygon that loses a corner.
    Polygon {
        face: FaceId,
        x: HalfedgeId,
        next: HalfedgeId,
        prev: HalfedgeId,
    },
}

/// Everything a collapse touches, collected by [`plan_collapse`].
#[derive(Clone, Debug, PartialEq)]
pub struct CollapsePlan {
    edge: EdgeId,
    /// The halfedge from the kept to the removed vertex, and the options: what re-planning needs.
    h: HalfedgeId,
    options: CollapseOptions,
    a: VertexId,
    b: VertexId,
    position: Vec3,
    sides: [Side; 2],
    /// The spokes of `a` and of `b` as the plan read them.
    around: [Vec<Spoke>; 2],
    /// Whether the merged vertex is on the boundary (either end was).
    merged_boundary: bool,
}

impl CollapsePlan {
    /// The edges the merged vertex will have once the collapse is applied, each with its other
    /// end and that end's position (which the collapse does not move), as the plan read them:
    /// what a caller that re-weighs those edges needs without reading the mesh again. The
    /// edge to the removed vertex and the edges from it to the wings (which merge into the
    /// kept vertex's) are left out.
    pub fn merged_ring(&self) -> impl Iterator<Item = (EdgeId, VertexId, Vec3)> + '_ {
        let wing = |v: VertexId| {
            self.sides
                .iter()
                .any(|s| matches!(*s, Side::Triangle { opposite, .. } if opposite == v))
        };
        let [around_a, around_b] = &self.around;
        around_a
            .iter()
            .filter(|s| s.links.vertex != self.b)
            .chain(
                around_b
                    .iter()
                    .filter(move |s| s.links.vertex != self.a && !wing(s.links.vertex)),
            )
            .map(|s| (s.links.edge, s.links.vertex, s.tip))
    }

    /// The vertex that survives (the edge's halfedge's start unless planned from another).
    pub fn kept(&self) -> VertexId {
        self.a
    }

    /// Where the surviving vertex goes.
    pub fn position(&self) -> Vec3 {
        self.position
    }
}

fn side(m: &MeshRef<'_>, x: HalfedgeId) -> Side {
    let (next, prev) = (m.next(x), m.prev(x));
    match m.face(x) {
        None => Side::Boundary { x, next, prev },
        Some(face) if m.next(next) == prev => Side::Triangle {
            face,
            x,
            next,
            prev,
            opposite: m.to_vertex(next),
        },
        Some(face) => Side::Polygon {
            face,
            x,
            next,
            prev,
        },
    }
}

/// Checks that `e` can be collapsed and collects what the collapse touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_collapse(
    world: &World,
    e: EdgeId,
    options: CollapseOptions,
) -> Result<CollapsePlan, Refusal> {
    plan_collapse_in(MeshRef::new(world), e, options)
}

/// [`plan_collapse`], reading through `m` (which may carry cached [`crate::mesh::topology::Lookups`]).
///
/// # Refusals
/// See the module doc.
pub(crate) fn plan_collapse_in(
    m: MeshRef<'_>,
    e: EdgeId,
    options: CollapseOptions,
) -> Result<CollapsePlan, Refusal> {
    let h = live_edge(&m, e)?;
    plan_halfedge(m, h, options)
}

/// One outgoing halfedge of a vertex, read once for all the checks of a plan: its links, its
/// tip's position, and whether the face on its left is a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Spoke {
    links: Halfedge,
    tip: Vec3,
    triangle: bool,
}

/// The spokes of `v`, counter-clockwise from its halfedge (bounded like every circulator).
/// Three lookups a spoke, against the dozen the separate walks of a plan used to take: the
/// spoke, its tip's position, and the halfedge coming back into `v` in the face on its left,
/// which gives both the next spoke (its twin) and whether that face is a triangle (then the
/// halfedge before it is the spoke's next).
fn spokes(m: &MeshRef<'_>, v: VertexId) -> Vec<Spoke> {
    let start = m.vertex_halfedge(v);
    let mut out = Vec::with_capacity(8);
    let mut h = start;
    for _ in 0..MAX_LOOP {
        let links = *m.halfedge(h);
        let back = m.halfedge(links.prev);
        out.push(Spoke {
            links,
            tip: m.position(links.vertex),
            triangle: links.face.is_some() && back.prev == links.next,
        });
        h = back.twin;
        if h == start {
            break;
        }
    }
    out
}

/// What a vertex's spokes show of one neighbour `o`.
struct Sighting {
    /// Whether the edge to `o` lacks a face on one side (is on the boundary).
    open: bool,
    /// The third corners of the triangles on either side of that edge: other neighbours of `o`.
    beyond: [Option<VertexId>; 2],
}

/// What `ring` (a vertex's spokes) shows of its neighbour `o`, or `None` if `o` is not one.
/// The faces on the two sides of spoke `i` are the ones left of spokes `i` and `i − 1`.
fn seen_from(ring: &[Spoke], o: VertexId) -> Option<Sighting> {
    let i = ring.iter().position(|s| s.links.vertex == o)?;
    let n = ring.len();
    let (before, at, after) = (&ring[(i + n - 1) % n], &ring[i], &ring[(i + 1) % n]);
    Some(Sighting {
        open: at.links.face.is_none() || before.links.face.is_none(),
        beyond: [
            at.triangle.then_some(after.links.vertex),
            before.triangle.then_some(before.links.vertex),
        ],
    })
}

/// [`plan_collapse`] for the edge of `h`, keeping `h`'s start and removing its tip.
///
/// # Refusals
/// See the module doc.
pub fn plan_collapse_halfedge(
    world: &World,
    h: HalfedgeId,
    options: CollapseOptions,
) -> Result<CollapsePlan, Refusal> {
    plan_halfedge(MeshRef::new(world), h, options)
}

fn plan_halfedge(
    m: MeshRef<'_>,
    h: HalfedgeId,
    options: CollapseOptions,
) -> Result<CollapsePlan, Refusal> {
    let e = m
        .try_halfedge(h)
        .ok_or(Refusal::Stale(ElementId::Halfedge(h)))?
        .edge;
    let t = m.twin(h);
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    let sides = [side(&m, h), side(&m, t)];
    let vx = |v: VertexId| ElementId::Vertex(v);
    let (around_a, around_b) = (spokes(&m, a), spokes(&m, b));
    // A boundary vertex's halfedge, its first spoke, is its boundary one.
    let on_boundary = |ring: &[Spoke]| ring[0].links.face.is_none();

    let boundary_edge = m.is_boundary(h) || m.is_boundary(t);
    if !boundary_edge && on_boundary(&around_a) && on_boundary(&around_b) {
        return Err(Refusal::BoundaryPinch);
    }
    let opposite: Vec<VertexId> = sides
        .iter()
        .filter_map(|s| match s {
            Side::Triangle { opposite, .. } => Some(*opposite),
            _ => None,
        })
        .collect();
    // Link condition, vertex part.
    for n in around_b.iter().map(|s| s.links.vertex) {
        if n != a && around_a.iter().any(|s| s.links.vertex == n) && !opposite.contains(&n) {
            return Err(Refusal::LinkCondition(vx(n)));
        }
    }
    // Link condition, edge part (the tetrahedron): triangles a c d and b c d both present
    // (their sides then join c and d). The face left of a triangle spoke is centre, its tip,
    // and the next spoke's tip.
    if let [c, d] = opposite[..] {
        let has_triangle = |ring: &[Spoke]| {
            ring.iter().enumerate().any(|(i, s)| {
                let o = ring[(i + 1) % ring.len()].links.vertex;
                s.triangle && ((s.links.vertex == c && o == d) || (s.links.vertex == d && o == c))
            })
        };
        if has_triangle(&around_a) && has_triangle(&around_b) {
            let closed_tiny = !boundary_edge && count_vertices(&m, a) <= 4;
            return Err(if closed_tiny {
                Refusal::TooSmall
            } else {
                Refusal::LinkCondition(vx(c))
            });
        }
    }
    for s in &sides {
        match *s {
            Side::Triangle { face, opposite, .. } => {
                // The two rings already show both sides of the edges to the wing.
                let (Some(from_a), Some(from_b)) = (
                    seen_from(&around_a, opposite),
                    seen_from(&around_b, opposite),
                ) else {
                    unreachable!("{opposite} is a corner of a triangle on the edge {a} {b}");
                };
                if from_a.open && from_b.open {
                    return Err(Refusal::DanglingEdge(ElementId::Face(face)));
                }
                // a, b and a distinct corner across each of the wing's two edges are four
                // neighbours, which clear any minimum; else count them.
                let across = |seen: &Sighting, other: VertexId| {
                    seen.beyond.into_iter().flatten().find(|&n| n != other)
                };
                if !matches!(
                    (across(&from_a, b), across(&from_b, a)),
                    (Some(p), Some(q)) if p != q
                ) {
                    let minimum = if m.is_boundary_vertex(opposite) { 2 } else { 3 };
                    // Only whether the valence exceeds the minimum matters: stop counting past it.
                    if m.vertex_outgoing(opposite).take(minimum + 1).count() <= minimum {
                        return Err(Refusal::ValenceTooLow(vx(opposite), minimum));
                    }
                }
            }
            Side::Polygon { face, .. } => {
                if m.face_degree(face) <= 3 {
                    return Err(Refusal::DegenerateFace(ElementId::Face(face)));
                }
            }
            Side::Boundary { x, .. } => {
                // Only whether the loop has more than three sides matters: stop counting at four.
                if m.loop_from(x).take(4).count() <= 3 {
                    return Err(Refusal::DegenerateFace(ElementId::Edge(e)));
                }
            }
        }
    }
    // No other face may hold both a and b (it would visit the merged vertex twice). A triangle
    // holding both would hold the edge a b, so it is one of the edge's own faces: only polygons
    // need looking at.
    let own_face = |f: FaceId| {
        sides.iter().any(
            |s| matches!(*s, Side::Triangle { face, .. } | Side::Polygon { face, .. } if face == f),
        )
    };
    for s in &around_b {
        let Some(f) = s.links.face else { continue };
        if !s.triangle && !own_face(f) && m.face_vertices(f).any(|v| v == a) {
            return Err(Refusal::DegenerateFace(ElementId::Face(f)));
        }
    }
    // The merged vertex: its neighbours are both endpoints' neighbours but a and b, with the
    // opposite vertices (the only shared ones, by the link condition) counted once. Two quads
    // glued along an edge chain, for instance, would leave it with two edges inside the surface.
    let wings = match opposite[..] {
        [c, d] if c == d => 1,
        _ => opposite.len(),
    };
    let merged_boundary = on_boundary(&around_a) || on_boundary(&around_b);
    let minimum = if merged_boundary { 2 } else { 3 };
    if (around_a.len() + around_b.len()).saturating_sub(2 + wings) < minimum {
        return Err(Refusal::ValenceTooLow(vx(a), minimum));
    }
    let position = options
        .position
        .unwrap_or_else(|| (m.position(a) + m.position(b)) / 2.0);
    if !position.is_finite() {
        return Err(Refusal::Unsuitable(format!(
            "{position} is not a finite position"
        )));
    }
    if let Some(max) = options.max_normal_change_deg {
        let merge = Merge {
            a,
            b,
            position,
            limit: max.to_radians().cos(),
        };
        merge.check_normals(&m, a, &around_a, &sides)?;
        merge.check_normals(&m, b, &around_b, &sides)?;
    }
    Ok(CollapsePlan {
        edge: e,
        h,
        options,
        a,
        b,
        position,
        sides,
        around: [around_a, around_b],
        merged_boundary,
    })
}

fn count_vertices(m: &MeshRef<'_>, v: VertexId) -> usize {
    // Only called to tell a tetrahedron from a larger mesh: stop early.
    let mut seen = vec![v];
    let mut i = 0;
    while i < seen.len() && seen.len() <= 5 {
        for n in m.vertex_neighbors(seen[i]) {
            if !seen.contains(&n) {
                seen.push(n);
            }
        }
        i += 1;
    }
    seen.len()
}

/// The two vertices of a collapse going to one position, for the normal check.
struct Merge {
    a: VertexId,
    b: VertexId,
    position: Vec3,
    /// The cosine of the largest turn allowed.
    limit: f32,
}

impl Merge {
    /// Where vertex `v` at `p` will be after the collapse.
    fn moved(&self, v: VertexId, p: Vec3) -> Vec3 {
        if v == self.a || v == self.b {
            self.position
        } else {
            p
        }
    }

    /// Refuses when a surviving face around `centre` (`a` or `b`, with spokes `ring`) would turn by
    /// more than the limit. Triangle sides of the edge disappear; polygon sides survive with
    /// `a` and `b` merged (the repeated corner adds nothing to a Newell normal), so they are
    /// checked like every other face.
    fn check_normals(
        &self,
        m: &MeshRef<'_>,
        centre: VertexId,
        ring: &[Spoke],
        sides: &[Side; 2],
    ) -> Result<(), Refusal> {
        let vanishes = |f: FaceId| {
            sides
                .iter()
                .any(|s| matches!(*s, Side::Triangle { face, .. } if face == f))
        };
        let centre_at = m.position(centre);
        for (i, s) in ring.iter().enumerate() {
            let Some(f) = s.links.face else { continue };
            if vanishes(f) {
                continue;
            }
            let (n0, n1) = if s.triangle {
                // The triangle centre → tip → the next spoke's tip.
                let o = ring[(i + 1) % ring.len()];
                let corners = [
                    (centre, centre_at),
                    (s.links.vertex, s.tip),
                    (o.links.vertex, o.tip),
                ];
                (
                    newell_area_vector(&corners.map(|(_, p)| p)),
                    newell_area_vector(&corners.map(|(v, p)| self.moved(v, p))),
                )
            } else {
                let corners: Vec<(VertexId, Vec3)> =
                    m.face_vertices(f).map(|x| (x, m.position(x))).collect();
                let before: Vec<Vec3> = corners.iter().map(|&(_, p)| p).collect();
                let after: Vec<Vec3> = corners.iter().map(|&(v, p)| self.moved(v, p)).collect();
                (newell_area_vector(&before), newell_area_vector(&after))
            };
            let (Some(n0), Some(n1)) = (n0.try_normalize(), n1.try_normalize()) else {
                return Err(Refusal::NormalFlip(ElementId::Face(f)));
            };
            if n0.dot(n1) < self.limit {
                return Err(Refusal::NormalFlip(ElementId::Face(f)));
            }
        }
        Ok(())
    }
}

/// Carries out a collapse planned by [`plan_collapse`] on the unchanged world.
pub fn apply_collapse(world: &mut World, p: CollapsePlan) -> CollapseResult {
    let (result, removed) = apply_collapse_deferred(world, p, None);
    removed.despawn(world);
    result
}

/// The elements a collapse took out of the mesh.
#[derive(Debug, Default)]
pub(crate) struct Removed {
    /// Halfedges, edges, faces and the vertex, as entities.
    pub entities: Vec<Entity>,
    /// The edges among them (the simplifier drops them from its queue).
    pub edges: Vec<EdgeId>,
}

impl Removed {
    /// Despawns them.
    pub fn despawn(self, world: &mut World) {
        for e in self.entities {
            world.despawn(e);
        }
    }
}

/// [`apply_collapse`], leaving the removed elements spawned for the caller to despawn. No
/// live element links to them any more, but they are still in the world: until they are
/// despawned the mesh must be read only by walking its links (never by listing its members,
/// nor by asking whether an id is live). The simplifier makes tens of thousands of collapses
/// this way and despawns all the removed elements at the end, in index order, which costs
/// much less than despawning them one collapse at a time.
///
/// `lookups`, when given, must have been made for this world: the reads go through them.
pub(crate) fn apply_collapse_deferred(
    world: &mut World,
    p: CollapsePlan,
    lookups: Option<&Lookups>,
) -> (CollapseResult, Removed) {
    debug_assert_eq!(
        plan_collapse_halfedge(world, p.h, p.options).as_ref(),
        Ok(&p),
        "stale collapse plan"
    );
    let m = MeshRef::through(world, lookups);
    let wing = |s: &Side| match *s {
        Side::Triangle { opposite, .. } => (Some(opposite), true),
        Side::Boundary { .. } => (None, true),
        Side::Polygon { .. } => (None, false),
    };
    let ((left, left_ok), (right, right_ok)) = (wing(&p.sides[0]), wing(&p.sides[1]));
    let record = CollapseRecord {
        kept: p.a,
        kept_position: m.position(p.a),
        removed_position: m.position(p.b),
        left,
        right,
        invertible: left_ok && right_ok && (left.is_some() || right.is_some()),
    };
    // Work out the relinking first (reads), then write.
    let mut removed_halfedges = Vec::new();
    let mut removed_edges = vec![p.edge];
    let mut removed_faces = Vec::new();
    let mut glue = Vec::new(); // (twin of next, twin of prev, the edge they share)
    // Halfedges pointing at `b` (they will point at `a`).
    let into_b: Vec<HalfedgeId> = p.around[1].iter().map(|s| s.links.twin).collect();
    let mut candidates: Vec<HalfedgeId> = into_b.clone();
    let mut unlink = Vec::new(); // (prev, next, face to re-point)
    // Whether each vertex to re-point is on the boundary (the merged one if either end was): an
    // interior vertex needs just a live outgoing halfedge, a boundary one its boundary halfedge.
    let mut fix_vertex = vec![(p.a, p.merged_boundary)];
    for s in &p.sides {
        match *s {
            Side::Triangle {
                face,
                x,
                next,
                prev,
                opposite,
            } => {
                // Sides: next runs b → c (or a → d), prev runs c → a (or d → b).
                let (on, op) = (m.twin(next), m.twin(prev));
                let (en, ep) = (m.edge(next), m.edge(prev));
                removed_halfedges.extend([x, next, prev]);
                removed_faces.push(face);
                // Keep the edge that does not touch b.
                let (keep, drop) = if m.to_vertex(next) == opposite && m.from_vertex(next) == p.b {
                    (ep, en)
                } else {
                    (en, ep)
                };
                removed_edges.push(drop);
                glue.push((on, op, keep));
                candidates.extend([on, op]);
                fix_vertex.push((opposite, m.is_boundary_vertex(opposite)));
            }
            Side::Polygon {
                face,
                x,
                next,
                prev,
            } => {
                removed_halfedges.push(x);
                unlink.push((prev, next, Some(face)));
            }
            Side::Boundary { x, next, prev } => {
                removed_halfedges.push(x);
                unlink.push((prev, next, None));
            }
        }
    }
    for &x in &into_b {
        if !removed_halfedges.contains(&x) {
            he(world, x).vertex = p.a;
        }
    }
    for (prev, next, face) in unlink {
        link(world, prev, next);
        if let Some(f) = face {
            world.get_mut::<Face>(f.0).expect("planned").halfedge = next;
        }
    }
    for (on, op, keep) in glue {
        {
            let mut x = he(world, on);
            x.twin = op;
            x.edge = keep;
        }
        {
            let mut x = he(world, op);
            x.twin = on;
            x.edge = keep;
        }
        let interior = if MeshRef::through(world, lookups).is_boundary(on) {
            op
        } else {
            on
        };
        world.get_mut::<Edge>(keep.0).expect("planned").halfedge = interior;
    }
    world.get_mut::<Position>(p.a.0).expect("planned").0 = p.position;
    // Every vertex whose outgoing halfedge may be gone, or whose boundary halfedge may have
    // changed, gets a fresh one: the boundary one if it has one.
    let gone = |h: &HalfedgeId| removed_halfedges.contains(h);
    let twins: Vec<HalfedgeId> = candidates
        .iter()
        .filter(|h| !gone(h))
        .map(|&h| MeshRef::through(world, lookups).twin(h))
        .collect();
    candidates.extend(twins);
    candidates.retain(|h| !gone(h));
    for (v, boundary) in fix_vertex {
        repoint(world, lookups, v, boundary, &candidates, &removed_halfedges);
    }
    let mut entities: Vec<Entity> = removed_halfedges.iter().map(|h| h.0).collect();
    entities.extend(removed_edges.iter().map(|e| e.0));
    entities.extend(removed_faces.iter().map(|f| f.0));
    entities.push(p.b.0);
    let result = CollapseResult {
        kept: p.a,
        removed: p.b,
        record,
    };
    let removed = Removed {
        entities,
        edges: removed_edges,
    };
    (result, removed)
}

/// Points `v` at a live outgoing halfedge, its boundary one if it is on the `boundary`.
/// `candidates` are live halfedges that may now leave `v`; `removed` are those the collapse
/// took out (perhaps not despawned yet).
fn repoint(
    world: &mut World,
    lookups: Option<&Lookups>,
    v: VertexId,
    boundary: bool,
    candidates: &[HalfedgeId],
    removed: &[HalfedgeId],
) {
    let m = MeshRef::through(world, lookups);
    let current = m.try_vertex(v).map(|x| x.halfedge);
    let leaves_v = |h: HalfedgeId| !removed.contains(&h) && m.from_vertex(h) == v;
    let start = current
        .filter(|&h| leaves_v(h))
        .or_else(|| candidates.iter().copied().find(|&h| leaves_v(h)));
    let Some(start) = start else {
        unreachable!("{v} keeps at least one edge after a planned collapse");
    };
    let best = if boundary {
        m.vertex_outgoing_from(start)
            .find(|&h| m.is_boundary(h))
            .unwrap_or(start)
    } else {
        start
    };
    world.get_mut::<Vertex>(v.0).expect("planned").halfedge = best;
}

/// Collapses `e` (see the module doc): plan, then apply.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn collapse_edge(
    world: &mut World,
    e: EdgeId,
    options: CollapseOptions,
) -> Result<CollapseResult, Refusal> {
    let plan = plan_collapse(world, e, options)?;
    Ok(apply_collapse(world, plan))
}
