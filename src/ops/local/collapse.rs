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
//! Attributes follow the position: the merged vertex sits at `s` along a → b (½ for the
//! midpoint), and so do its corners' UVs between the UVs a face beside the edge has at a and b
//! (a corner across a seam keeps its own), its normal (renormalised) and its colour.
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
//! - `NotFinite`: a position that is not finite;
//! - `NormalFlip`, only when [`CollapseOptions::max_normal_change_deg`] is set: a surviving face
//!   around `a` or `b` (polygon sides included) whose normal would turn by more than that angle,
//!   or would vanish.

use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Entity, World};

use crate::mesh::elements::{Edge, Face, Halfedge, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::{MAX_LOOP, MeshRef, newell_area_vector};
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

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
    /// What [`fn@super::vertex_split`] needs to undo the collapse exactly.
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
    /// The spokes of `a` and of `b` as the plan read them, counter-clockwise from `h` and from
    /// its twin: a side's wing is the tip of its ring's second spoke, and the other ring's last
    /// spoke is the side's `next`.
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

    /// On a triangle mesh, every face around the collapsing edge once, each with its corners
    /// once the collapse is applied (the merged vertex first, at the planned position, then
    /// the others counter-clockwise), or `None` for the edge's own triangles, which go: the
    /// faces whose shape the collapse changes, as the plan read them.
    pub fn reshaped_faces(&self) -> impl Iterator<Item = (FaceId, Option<[Vec3; 3]>)> + '_ {
        let [around_a, around_b] = &self.around;
        [(around_a, self.b, true), (around_b, self.a, false)]
            .into_iter()
            .flat_map(move |(ring, other, first)| {
                ring.iter().enumerate().filter_map(move |(i, s)| {
                    let face = s.links.face?;
                    let o = &ring[(i + 1) % ring.len()];
                    if s.links.vertex == other || o.links.vertex == other {
                        // The edge's own triangles, in both rings: listed once.
                        first.then_some((face, None))
                    } else {
                        Some((face, Some([self.position, s.tip, o.tip])))
                    }
                })
            })
    }

    /// The vertex that survives (the edge's halfedge's start unless planned from another).
    pub fn kept(&self) -> VertexId {
        self.a
    }

    /// The vertex that goes.
    pub fn removed(&self) -> VertexId {
        self.b
    }

    /// Where the surviving vertex goes.
    pub fn position(&self) -> Vec3 {
        self.position
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

/// [`plan_collapse`], reading through `m`.
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

/// One outgoing halfedge of a vertex, read once for all the checks of a plan: its id and links,
/// its tip's position, and whether the face on its left is a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Spoke {
    id: HalfedgeId,
    links: Halfedge,
    tip: Vec3,
    triangle: bool,
}

/// A walk counter-clockwise around a vertex, from one of its outgoing halfedges.
struct RingWalk {
    start: HalfedgeId,
    /// The spoke to read next, with its links; `None` once the walk has closed.
    at: Option<(HalfedgeId, Halfedge)>,
    spokes: Vec<Spoke>,
}

impl RingWalk {
    fn from(start: HalfedgeId, links: Halfedge) -> Self {
        Self {
            start,
            at: Some((start, links)),
            spokes: Vec::with_capacity(8),
        }
    }

    /// Reads one spoke: the halfedge coming back into the centre in the face on its left gives
    /// both whether that face is a triangle (the halfedge before it is then the spoke's next) and
    /// the next spoke (its twin). Stops after [`MAX_LOOP`] spokes like every circulator.
    fn step(&mut self, m: &MeshRef<'_>) {
        let Some((id, links)) = self.at else { return };
        let back = m.halfedge(links.prev);
        self.spokes.push(Spoke {
            id,
            links,
            tip: m.position(links.vertex),
            triangle: links.face.is_some() && back.prev == links.next,
        });
        let next = back.twin;
        self.at =
            (next != self.start && self.spokes.len() < MAX_LOOP).then(|| (next, *m.halfedge(next)));
    }
}

/// The spokes of both ends of the edge of `h`, counter-clockwise, starting with `h` (links
/// `links[0]`) around its start and with its twin (links `links[1]`) around its tip.
///
/// Each spoke costs three lookups (the spoke, the halfedge back into the centre in the face on
/// its left, the tip's position), and going round a vertex each spoke waits on the one before:
/// the time goes on waiting for memory. The two walks take turns, so that the lookups of one
/// overlap those of the other (plan 40 % faster on the bunny than one walk after the other; a
/// walk from both sides of each vertex, four chains, measured no faster than two).
fn rings(m: &MeshRef<'_>, h: HalfedgeId, links: [Halfedge; 2]) -> [Vec<Spoke>; 2] {
    let mut walks = [
        RingWalk::from(h, links[0]),
        RingWalk::from(links[0].twin, links[1]),
    ];
    while walks.iter().any(|w| w.at.is_some()) {
        for w in &mut walks {
            w.step(m);
        }
    }
    walks.map(|w| w.spokes)
}

/// The side of the edge left of `ring[0]`, the spoke along the edge: its face is left of the
/// first spoke, and a triangle's third corner is the second spoke's tip.
fn side(ring: &[Spoke]) -> Side {
    let s = ring[0];
    let (x, next, prev) = (s.id, s.links.next, s.links.prev);
    match s.links.face {
        None => Side::Boundary { x, next, prev },
        Some(face) if s.triangle => Side::Triangle {
            face,
            x,
            next,
            prev,
            opposite: ring[1 % ring.len()].links.vertex,
        },
        Some(face) => Side::Polygon {
            face,
            x,
            next,
            prev,
        },
    }
}

/// What the checks read of one spoke of a ring: its tip, whether a face lies left of it, and
/// whether that face is a triangle. Both collapses (on entities here, on flat tables in the
/// simplifier) read their spokes into this for [`wing_check`].
#[derive(Clone, Copy)]
pub(crate) struct SpokeView<V> {
    pub tip: V,
    pub has_face: bool,
    pub triangle: bool,
}

/// What a triangle beside a collapsing edge a b says of its wing (its third corner).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Wing {
    /// Both the wing's edges to a and to b lie on the boundary: the merged edge would have
    /// no face (a lone triangle).
    Dangling,
    /// A corner across each of the wing's two edges, other than a and b and distinct: with
    /// a and b, four neighbours, which clear any valence minimum.
    Enough,
    /// Neither: the wing's valence must be counted.
    Count,
}

/// What the rings of a (`around_a`) and b (`around_b`), counter-clockwise, show of the wing
/// `w` of a triangle on the edge a b, each spoke read through `view`. The faces on the two
/// sides of spoke `i` are the ones left of spokes `i` and `i − 1`; a triangle's third corner
/// beyond the edge to `w` is the tip of the spoke after or before it.
pub(crate) fn wing_check<S, V: Copy + PartialEq + std::fmt::Display>(
    (a, around_a): (V, &[S]),
    (b, around_b): (V, &[S]),
    w: V,
    view: impl Fn(&S) -> SpokeView<V>,
) -> Wing {
    let sighting = |ring: &[S]| {
        let i = ring.iter().position(|s| view(s).tip == w)?;
        let n = ring.len();
        let (before, at, after) = (
            view(&ring[(i + n - 1) % n]),
            view(&ring[i]),
            view(&ring[(i + 1) % n]),
        );
        let open = !at.has_face || !before.has_face;
        let beyond = [
            at.triangle.then_some(after.tip),
            before.triangle.then_some(before.tip),
        ];
        Some((open, beyond))
    };
    let (Some((open_a, beyond_a)), Some((open_b, beyond_b))) =
        (sighting(around_a), sighting(around_b))
    else {
        unreachable!("{w} is a corner of a triangle on the edge {a} {b}");
    };
    if open_a && open_b {
        return Wing::Dangling;
    }
    let across =
        |beyond: [Option<V>; 2], other: V| beyond.into_iter().flatten().find(|&n| n != other);
    match (across(beyond_a, b), across(beyond_b, a)) {
        (Some(p), Some(q)) if p != q => Wing::Enough,
        _ => Wing::Count,
    }
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
    let h_links = *m
        .try_halfedge(h)
        .ok_or(Refusal::Stale(ElementId::Halfedge(h)))?;
    let e = h_links.edge;
    let t_links = *m.halfedge(h_links.twin);
    let (a, b) = (t_links.vertex, h_links.vertex);
    let vx = |v: VertexId| ElementId::Vertex(v);
    let [around_a, around_b] = rings(&m, h, [h_links, t_links]);
    let sides = [side(&around_a), side(&around_b)];
    // Where a and b are: the tips of the spokes along the edge.
    let (at_a, at_b) = (around_b[0].tip, around_a[0].tip);
    let on_boundary = |ring: &[Spoke]| ring.iter().any(|s| s.links.face.is_none());

    let boundary_edge = h_links.face.is_none() || t_links.face.is_none();
    if !boundary_edge && on_boundary(&around_a) && on_boundary(&around_b) {
        return Err(Refusal::BoundaryPinch);
    }
    // The wings: the opposite corners of the triangles on either side.
    let opposite = sides.map(|s| match s {
        Side::Triangle { opposite, .. } => Some(opposite),
        _ => None,
    });
    check_link(&m, (a, &around_a), &around_b, opposite, boundary_edge)?;
    check_sides(&m, e, (a, &around_a), (b, &around_b), &sides)?;
    check_no_face_holds_both(&m, a, &around_b, &sides)?;
    // The merged vertex: its neighbours are both endpoints' neighbours but a and b, with the
    // opposite vertices (the only shared ones, by the link condition) counted once. Two quads
    // glued along an edge chain, for instance, would leave it with two edges inside the surface.
    let wings = match opposite {
        [Some(c), Some(d)] if c == d => 1,
        _ => opposite.iter().flatten().count(),
    };
    let merged_boundary = on_boundary(&around_a) || on_boundary(&around_b);
    let minimum = if merged_boundary { 2 } else { 3 };
    if (around_a.len() + around_b.len()).saturating_sub(2 + wings) < minimum {
        return Err(Refusal::ValenceTooLow(vx(a), minimum));
    }
    let position = options.position.unwrap_or((at_a + at_b) / 2.0);
    if !position.is_finite() {
        return Err(Refusal::NotFinite(position));
    }
    if let Some(max) = options.max_normal_change_deg {
        let merge = Merge {
            a,
            b,
            position,
            limit: max.to_radians().cos(),
        };
        merge.check_normals(&m, (a, at_a), &around_a, &sides)?;
        merge.check_normals(&m, (b, at_b), &around_b, &sides)?;
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

/// The link condition (Dey, Edelsbrunner et al. 1999) for the edge a b: no vertex but the
/// wings (`opposite`) is a neighbour of both, and the triangles a c d and b c d are not both
/// there (a tetrahedron, which is [`Refusal::TooSmall`] when it is the whole closed mesh).
fn check_link(
    m: &MeshRef<'_>,
    (a, around_a): (VertexId, &[Spoke]),
    around_b: &[Spoke],
    opposite: [Option<VertexId>; 2],
    boundary_edge: bool,
) -> Result<(), Refusal> {
    let vx = |v: VertexId| ElementId::Vertex(v);
    // The vertex part.
    for n in around_b.iter().map(|s| s.links.vertex) {
        if n != a && around_a.iter().any(|s| s.links.vertex == n) && !opposite.contains(&Some(n)) {
            return Err(Refusal::LinkCondition(vx(n)));
        }
    }
    // The edge part (the tetrahedron): triangles a c d and b c d both present
    // (their sides then join c and d). The face left of a triangle spoke is centre, its tip,
    // and the next spoke's tip.
    if let [Some(c), Some(d)] = opposite {
        let has_triangle = |ring: &[Spoke]| {
            ring.iter().enumerate().any(|(i, s)| {
                let o = ring[(i + 1) % ring.len()].links.vertex;
                s.triangle && ((s.links.vertex == c && o == d) || (s.links.vertex == d && o == c))
            })
        };
        if has_triangle(around_a) && has_triangle(around_b) {
            let closed_tiny = !boundary_edge && count_vertices(m, a) <= 4;
            return Err(if closed_tiny {
                Refusal::TooSmall
            } else {
                Refusal::LinkCondition(vx(c))
            });
        }
    }
    Ok(())
}

/// What each side of the edge a b allows: a triangle's wing keeps a face beside it and enough
/// edges, a polygon keeps at least three corners, a boundary loop more than three sides.
fn check_sides(
    m: &MeshRef<'_>,
    e: EdgeId,
    (a, around_a): (VertexId, &[Spoke]),
    (b, around_b): (VertexId, &[Spoke]),
    sides: &[Side; 2],
) -> Result<(), Refusal> {
    let vx = |v: VertexId| ElementId::Vertex(v);
    for s in sides {
        match *s {
            Side::Triangle { face, opposite, .. } => {
                // The two rings already show both sides of the edges to the wing.
                let view = |s: &Spoke| SpokeView {
                    tip: s.links.vertex,
                    has_face: s.links.face.is_some(),
                    triangle: s.triangle,
                };
                match wing_check((a, around_a), (b, around_b), opposite, view) {
                    Wing::Dangling => return Err(Refusal::DanglingEdge(ElementId::Face(face))),
                    Wing::Enough => {}
                    Wing::Count => {
                        let minimum = if m.is_boundary_vertex(opposite) { 2 } else { 3 };
                        // Only whether the valence exceeds the minimum matters: stop counting
                        // past it.
                        if m.vertex_outgoing(opposite).take(minimum + 1).count() <= minimum {
                            return Err(Refusal::ValenceTooLow(vx(opposite), minimum));
                        }
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
    Ok(())
}

/// No other face may hold both a and b (it would visit the merged vertex twice). A triangle
/// holding both would hold the edge a b, so it is one of the edge's own faces: only polygons
/// need looking at.
fn check_no_face_holds_both(
    m: &MeshRef<'_>,
    a: VertexId,
    around_b: &[Spoke],
    sides: &[Side; 2],
) -> Result<(), Refusal> {
    let own_face = |f: FaceId| {
        sides.iter().any(
            |s| matches!(*s, Side::Triangle { face, .. } | Side::Polygon { face, .. } if face == f),
        )
    };
    for s in around_b {
        let Some(f) = s.links.face else { continue };
        if !s.triangle && !own_face(f) && m.face_vertices(f).any(|v| v == a) {
            return Err(Refusal::DegenerateFace(ElementId::Face(f)));
        }
    }
    Ok(())
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

    /// Refuses when a surviving face around `centre` (`a` or `b` with its position, with spokes
    /// `ring`) would turn by
    /// more than the limit. Triangle sides of the edge disappear; polygon sides survive with
    /// `a` and `b` merged (the repeated corner adds nothing to a Newell normal), so they are
    /// checked like every other face.
    fn check_normals(
        &self,
        m: &MeshRef<'_>,
        (centre, centre_at): (VertexId, Vec3),
        ring: &[Spoke],
        sides: &[Side; 2],
    ) -> Result<(), Refusal> {
        let vanishes = |f: FaceId| {
            sides
                .iter()
                .any(|s| matches!(*s, Side::Triangle { face, .. } if face == f))
        };
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
            // The angle's cosine against the limit, without normalising either vector: one
            // square root where two normalisations took two and six divisions.
            let lengths = (f64::from(n0.length_squared()) * f64::from(n1.length_squared())).sqrt();
            if !(lengths > 0.0 && lengths.is_finite())
                || f64::from(n0.dot(n1)) < f64::from(self.limit) * lengths
            {
                return Err(Refusal::NormalFlip(ElementId::Face(f)));
            }
        }
        Ok(())
    }
}

/// Carries out a collapse planned by [`plan_collapse`] on the unchanged world, attributes
/// included: UVs, normals and colours follow the position rule (see the module doc).
pub fn apply_collapse(world: &mut World, p: CollapsePlan) -> CollapseResult {
    let carry = CarryCollapse::read(world, &p);
    let mut removed = Vec::new();
    let (result, _) = apply_collapse_deferred(world, p, &mut removed);
    for e in removed {
        world.despawn(e);
    }
    if let Some(carry) = carry {
        carry_collapse(world, carry);
    }
    result
}

/// What a collapse needs to carry the mesh's attributes: the merged vertex's position as a
/// parameter `s` along a → b, each edge face's UVs at a and at b, and the corners of both ends.
struct CarryCollapse {
    has: crate::mesh::attributes::MeshAttributes,
    kept: VertexId,
    s: f32,
    /// Per face beside the edge: (UV at a, UV at b).
    sides: Vec<(Vec2, Vec2)>,
    /// Every corner at a or b before the collapse (halfedges into either, with a face), with its
    /// UV and whether it was at b.
    corners: Vec<(HalfedgeId, Vec2, bool)>,
    normal: Option<Vec3>,
    color: Option<[u8; 3]>,
}

impl CarryCollapse {
    fn read(world: &World, p: &CollapsePlan) -> Option<Self> {
        let has = crate::mesh::attributes::of_element(world, p.a.0);
        if has.is_empty() {
            return None;
        }
        let m = MeshRef::new(world);
        let (pa, pb) = (m.position(p.a), m.position(p.b));
        let d = pb - pa;
        let s = if d.length_squared() > 0.0 {
            ((p.position - pa).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let uv = |h: HalfedgeId| crate::mesh::attributes::corner_uv(world, h).unwrap_or_default();
        let mut sides = Vec::new();
        let mut corners = Vec::new();
        if has.uv {
            let t = m.twin(p.h);
            if m.face(p.h).is_some() {
                sides.push((uv(m.prev(p.h)), uv(p.h)));
            }
            if m.face(t).is_some() {
                sides.push((uv(t), uv(m.prev(t))));
            }
            for (v, at_b) in [(p.a, false), (p.b, true)] {
                for out in m.vertex_outgoing(v) {
                    let into = m.twin(out);
                    if m.face(into).is_some() {
                        corners.push((into, uv(into), at_b));
                    }
                }
            }
        }
        let normal = has.normals.then(|| {
            let n = |v: VertexId| {
                world
                    .get::<crate::mesh::attributes::VertexNormal>(v.0)
                    .map_or(Vec3::ZERO, |n| n.0)
            };
            n(p.a).lerp(n(p.b), s).normalize_or_zero()
        });
        let color = has.colors.then(|| {
            let c = |v: VertexId| {
                world
                    .get::<crate::mesh::attributes::VertexColor>(v.0)
                    .map_or([0; 3], |c| c.0)
            };
            crate::mesh::attributes::lerp_color(c(p.a), c(p.b), s)
        });
        Some(Self {
            has,
            kept: p.a,
            s,
            sides,
            corners,
            normal,
            color,
        })
    }
}

/// The attribute rule of a collapse, matching its position rule: the merged vertex sits at
/// `s` along a → b, so a corner of either end whose UV is that end's UV in a face beside the
/// edge moves to the same point between that face's UVs at a and b; a corner across a seam
/// (another UV) keeps its own. The normal is interpolated at `s` (renormalised), the colour
/// too (rounded).
fn carry_collapse(world: &mut World, c: CarryCollapse) {
    use crate::mesh::attributes::{VertexColor, VertexNormal, set_corner_uv};
    let bits = |u: Vec2| u.to_array().map(f32::to_bits);
    for &(h, uv, at_b) in &c.corners {
        if world.get::<Halfedge>(h.0).is_none_or(|x| x.face.is_none()) {
            continue;
        }
        let matched = c.sides.iter().find(|(ua, ub)| {
            let own = if at_b { *ub } else { *ua };
            bits(own) == bits(uv)
        });
        if let Some(&(ua, ub)) = matched {
            set_corner_uv(world, h, ua.lerp(ub, c.s));
        }
    }
    if let Some(n) = c.normal.filter(|_| c.has.normals) {
        world.entity_mut(c.kept.0).insert(VertexNormal(n));
    }
    if let Some(x) = c.color.filter(|_| c.has.colors) {
        world.entity_mut(c.kept.0).insert(VertexColor(x));
    }
}

impl Side {
    /// The halfedges the collapse removes on this side: a triangle's three, else the edge's own.
    fn removed_halfedges(&self) -> [Option<HalfedgeId>; 3] {
        match *self {
            Side::Triangle { x, next, prev, .. } => [Some(x), Some(next), Some(prev)],
            Side::Polygon { x, .. } | Side::Boundary { x, .. } => [Some(x), None, None],
        }
    }
}

/// [`apply_collapse`], leaving the removed elements spawned: their entities are pushed onto
/// `removed` for the caller to despawn, and the edges among them are returned. No live element
/// links to them any more, but they are still in the world: until they are despawned the mesh
/// must be read only by walking its links (never by listing its members, nor by asking whether
/// an id is live). The stepped simplification ([`crate::ops::simplify::QemRun`]) despawns
/// them right after each collapse; the simplification to the end collapses on flat tables
/// instead.
///
/// Every link it rewrites comes from the plan's two rings: all it reads besides are the vertex
/// records of the kept vertex and the wings (whose outgoing halfedge may be going) and whether
/// each pair of halfedges it glues has a boundary one. Against the plan-free version it
/// replaced, which re-walked rings and allocated a list per kind of change, this took the
/// simplifier's apply step (then on entities) from 2.3 to 1.0 µs a collapse (bunny).
pub(crate) fn apply_collapse_deferred(
    world: &mut World,
    p: CollapsePlan,
    removed: &mut Vec<Entity>,
) -> (CollapseResult, [Option<EdgeId>; 3]) {
    crate::checks::checked_assert_eq!(
        plan_collapse_halfedge(world, p.h, p.options).as_ref(),
        Ok(&p),
        "stale collapse plan"
    );
    let around_b = &p.around[1];
    let record = p.record();
    let gone = |h: HalfedgeId| p.removes(h);
    let mut removed_edges = [Some(p.edge), None, None];
    removed.push(p.edge.0);
    // Every halfedge into b now points at a.
    for s in around_b {
        if !gone(s.links.twin) {
            he(world, s.links.twin).vertex = p.a;
        }
    }
    for (i, side) in p.sides.iter().enumerate() {
        removed.extend(side.removed_halfedges().into_iter().flatten().map(|h| h.0));
        match *side {
            Side::Triangle {
                face,
                next,
                prev,
                opposite,
                ..
            } => {
                let fold = Fold {
                    side: i,
                    next,
                    prev,
                    opposite,
                };
                let drop = fold_triangle(world, &p, fold);
                removed.extend([face.0, drop.0]);
                removed_edges[1 + i] = Some(drop);
            }
            Side::Polygon {
                face, next, prev, ..
            } => {
                link(world, prev, next);
                world.get_mut::<Face>(face.0).expect("planned").halfedge = next;
            }
            Side::Boundary { next, prev, .. } => link(world, prev, next),
        }
    }
    removed.push(p.b.0);
    world.get_mut::<Position>(p.a.0).expect("planned").0 = p.position;
    let Some(best) = merged_vertex_halfedge(world, &p) else {
        unreachable!("{} keeps at least one edge after a planned collapse", p.a);
    };
    world.get_mut::<Vertex>(p.a.0).expect("planned").halfedge = best;
    let result = CollapseResult {
        kept: p.a,
        removed: p.b,
        record,
    };
    (result, removed_edges)
}

impl CollapsePlan {
    /// What a vertex split needs to undo this collapse.
    fn record(&self) -> CollapseRecord {
        let [around_a, around_b] = &self.around;
        let wing = |s: &Side| match *s {
            Side::Triangle { opposite, .. } => (Some(opposite), true),
            Side::Boundary { .. } => (None, true),
            Side::Polygon { .. } => (None, false),
        };
        let ((left, left_ok), (right, right_ok)) = (wing(&self.sides[0]), wing(&self.sides[1]));
        CollapseRecord {
            kept: self.a,
            kept_position: around_b[0].tip,
            removed_position: around_a[0].tip,
            left,
            right,
            invertible: left_ok && right_ok && (left.is_some() || right.is_some()),
        }
    }

    /// Whether the collapse removes halfedge `h`.
    fn removes(&self, h: HalfedgeId) -> bool {
        self.sides
            .iter()
            .any(|s| s.removed_halfedges().contains(&Some(h)))
    }
}

/// A triangle beside the collapsing edge, on side `side` (0: left of the halfedge): the
/// halfedges `next` and `prev` of its two other sides, and its wing vertex `opposite`.
#[derive(Clone, Copy)]
struct Fold {
    side: usize,
    next: HalfedgeId,
    prev: HalfedgeId,
    opposite: VertexId,
}

/// Folds a triangle beside the edge into one edge: its two sides to the wing become one, on
/// the edge of the one from a. Returns the edge that goes.
fn fold_triangle(world: &mut World, p: &CollapsePlan, fold: Fold) -> EdgeId {
    // Around the side's own end, the spoke after `x` runs back along `prev` to the
    // wing; around the other end, the spoke before `x`'s twin is `next`. Their twins
    // `op` and `on` become each other's, on the edge of the one from a (the other
    // edge touches b and goes).
    let (own, other) = (&p.around[fold.side], &p.around[1 - fold.side]);
    let (to_wing, along_next) = (own[1 % own.len()], other[other.len() - 1]);
    crate::checks::checked_assert_eq!((to_wing.links.twin, along_next.id), (fold.prev, fold.next));
    let (on, op) = (along_next.links.twin, to_wing.id);
    let (from_a, from_b) = if fold.side == 0 {
        (to_wing, along_next)
    } else {
        (along_next, to_wing)
    };
    let (keep, drop) = (from_a.links.edge, from_b.links.edge);
    let interior = if MeshRef::new(world).is_boundary(on) {
        op
    } else {
        on
    };
    for (x, twin) in [(on, op), (op, on)] {
        let mut links = he(world, x);
        links.twin = twin;
        links.edge = keep;
    }
    world.get_mut::<Edge>(keep.0).expect("planned").halfedge = interior;
    // The wing's outgoing halfedge may be `prev`, which goes: `on` leaves it too.
    // (On the boundary it is the boundary halfedge, which stays.)
    let mut w = world.get_mut::<Vertex>(fold.opposite.0).expect("planned");
    if w.halfedge == fold.prev {
        w.halfedge = on;
    }
    drop
}

/// The merged vertex's halfedge: on the boundary its boundary one; inside, its own if that
/// stays, else the one to a wing that the collapse glued, else one of b's.
fn merged_vertex_halfedge(world: &World, p: &CollapsePlan) -> Option<HalfedgeId> {
    let [around_a, around_b] = &p.around;
    if p.merged_boundary {
        around_a
            .iter()
            .chain(around_b)
            .find(|s| s.links.face.is_none() && !p.removes(s.id))
            .map(|s| s.id)
    } else {
        let own = world.get::<Vertex>(p.a.0).expect("planned").halfedge;
        let to_wing = |i: usize| {
            let ring = &p.around[i];
            matches!(p.sides[i], Side::Triangle { .. }).then(|| ring[1 % ring.len()].id)
        };
        (!p.removes(own))
            .then_some(own)
            .or_else(|| to_wing(0))
            .or_else(|| to_wing(1))
            .or_else(|| {
                around_b
                    .iter()
                    .find(|s| !p.removes(s.id) && !p.removes(s.links.twin))
                    .map(|s| s.id)
            })
    }
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

/// Collapsing an edge: a local edit.
pub const COLLAPSE: Declaration = Declaration::new("collapse")
    .titled("Collapse")
    .described("collapse the active edge (to its midpoint) or face (to its centroid)")
    .on_key("C")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`collapse_edge`] to the midpoint as a registered operation: `collapse:A,B`, C on an edge.
pub struct Collapse;

impl MeshOperation for Collapse {
    fn declaration(&self) -> &'static Declaration {
        &COLLAPSE
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        Applied::on_edge(world, e, |world| {
            let r = collapse_edge(world, e, CollapseOptions::default())?;
            Ok((
                format!("kept {}, removed {}", r.kept, r.removed),
                r.kept.into(),
            ))
        })
    }
}
