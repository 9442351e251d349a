//! Bevel: a vertex, or an edge, becomes a face (Scotty3D's `bevel_vertex` and `bevel_edge`,
//! with its `bevel_positions` step folded in: the new vertices are placed along the old edges).
//!
//! # Bevel a vertex
//!
//! ```text
//!          w1                          w1
//!          |                           |
//!          |                           u1
//!          |                         /    \
//!   w2 --- v --- w0      →    w2 --- u2  F  u0 --- w0     F = u0 u1 u2 u3
//!          |                         \    /
//!          |                           u3
//!          |                           |
//!          w3                          w3
//! ```
//!
//! A vertex `v` of valence `k` is replaced by a `k`-gon `F`: one new vertex `u_i` on every edge
//! `v – w_i`, at `p_v + amount · (p_w − p_v)`, joined round `v`'s fan in its counter-clockwise
//! order. Each face around `v` gains a corner (`v` gives way to the two new vertices on its two
//! sides there): a triangle becomes a quad, a quad a pentagon. Counts: `k − 1` vertices, `k`
//! edges, one face more; χ unchanged. Entities: `v` is despawned (the face replaces it); the
//! edges `v – w_i` keep their entities and halfedges and become `u_i – w_i`; the faces around
//! `v` keep theirs.
//!
//! **On the boundary** (Scotty3D allows it too) the new face sits at the border: it still has
//! `k` corners, one per edge of `v`, and its side between the new vertices on `v`'s two
//! boundary edges lies on the boundary. The boundary loop that ran `… w1 → v → w0 …` now runs
//! `… w1 → u1 → u0 → w0 …` (one side longer); no loop is split or merged.
//!
//! ```text
//!      w3       w2                 w3       w2
//!        \     /                     \     /
//!         \   /                       u3--u2
//!          \ /                       /  F   \
//!   w0 ---- v ---- w1        w0 --- u0 ------ u1 --- w1
//!       (hole below)               (the border now runs w1 u1 u0 w0)
//! ```
//!
//! # Bevel an edge
//!
//! ```text
//!   x1            y2            x1                y2
//!     \    f     /                \       f      /
//!      a ------ b        →         ua1 ------ ub2
//!     /    g     \                  |     F     |       F = ua1 ua2 ub1 ub2
//!   x2            y1                ua2 ------ ub1
//!                                 /       g      \
//!                               x2                y1
//! ```
//!
//! An interior edge `e = a – b` is replaced by a face `F` with one corner per edge leaving `a`
//! or `b` other than `e` itself: `(deg a − 1) + (deg b − 1)` corners, each at fraction `amount`
//! along its old edge as above. The two faces of `e` keep their degree (`a` and `b` give way to
//! one new vertex each); every other face around `a` or `b` gains a corner. Counts:
//! `deg a + deg b − 4` vertices, `deg a + deg b − 3` edges, one face more; χ unchanged.
//! Entities: `a`, `b` and `e` are despawned; `e`'s two halfedges stay in their faces as the
//! sides `ua1 → ub2` (in `f`) and `ub1 → ua2` (in `g`), each on a new edge; the other edges at
//! `a` and `b` keep their entities, as do the faces. A seam mark on `e` goes to both of those
//! edges.
//!
//! **Boundary endpoints** are allowed (Scotty3D's test bevels a square's diagonal, both of
//! whose ends are on the boundary): at an end on the boundary, `F`'s side between the new
//! vertices on that end's two boundary edges lies on the boundary, exactly as for a vertex.
//! With both ends on the boundary `F` touches the boundary twice; each loop through `a` or `b`
//! gains one side, and none is split or merged.
//!
//! # Attributes
//! A new corner's UV is interpolated along its old edge inside its face (`uv_v + amount ·
//! (uv_w − uv_v)`, the corners of `v` and of `w` in that face), so across a seam each face
//! keeps its own chart. A corner of `F` copies the UV its vertex got in the face across that
//! side of `F` (where that side is on the boundary, the UV it got in the one face beside its
//! old edge). A new vertex copies the normal and colour of the vertex it came from.
//!
//! # Refusals
//! Each leaves the world untouched. [`plan_bevel_vertex`], in this order:
//! - `Stale`: `v` is not a live vertex;
//! - `BadParameter`: `amount` is not in `(0, 0.5]` (NaN included);
//! - `DegenerateFace` (naming `v`): `v` has fewer than 3 edges, so its face would have fewer
//!   than 3 sides (an interior vertex of valence 2, a boundary corner of one face);
//! - `NotFinite`: a new position would not be finite.
//!
//! [`plan_bevel_edge`], in this order:
//! - `Stale`: `e` is not a live edge;
//! - `BoundaryEdge`: `e` is on the boundary (it has a face on one side only);
//! - `BadParameter`: `amount` is not in `(0, 0.5]` (NaN included);
//! - `DegenerateFace` (naming `e`): both ends have only 2 edges, so the face would have 2 sides
//!   (and its two sides would be duplicate edges). Nothing else can go wrong: each face keeps
//!   its old corners and gains only new vertices, and every new edge joins two new vertices
//!   that no other edge joins, so no face repeats a vertex and no edge is made twice
//!   (triangles around valence-3 ends included: a tetrahedron edge gives a prism-like shape);
//! - `NotFinite`: a new position would not be finite.

use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;

use crate::mesh::attributes::{self, MeshAttributes, Seam, VertexColor, VertexNormal};
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Parameter, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values};

use super::{Inset, Refusal, he, live_edge, spawn_at};

/// What bevelling a vertex touches, collected by [`plan_bevel_vertex`].
#[derive(Clone, Debug, PartialEq)]
pub struct BevelVertexPlan {
    mesh: MeshId,
    v: VertexId,
    amount: f32,
    ring: Ring,
    seeds: Vec<VertexId>,
}

impl BevelVertexPlan {
    /// The vertices whose neighbourhood ([`crate::mesh::change::neighbourhood`]) covers every
    /// element the bevel reads, writes, spawns or despawns, before and after: `v` and every
    /// corner of every face around it.
    pub fn seeds(&self) -> Vec<VertexId> {
        self.seeds.clone()
    }
}

/// What bevelling an edge touches, collected by [`plan_bevel_edge`].
#[derive(Clone, Debug, PartialEq)]
pub struct BevelEdgePlan {
    mesh: MeshId,
    edge: EdgeId,
    a: VertexId,
    b: VertexId,
    amount: f32,
    ring: Ring,
    seeds: Vec<VertexId>,
}

impl BevelEdgePlan {
    /// The vertices whose neighbourhood ([`crate::mesh::change::neighbourhood`]) covers every
    /// element the bevel reads, writes, spawns or despawns, before and after: both ends and
    /// every corner of every face around them.
    pub fn seeds(&self) -> Vec<VertexId> {
        self.seeds.clone()
    }
}

/// The new face of a bevel, as both bevels build it. Corner `j` of the face is a new vertex
/// `u_j` on spoke `s_j`, an old halfedge leaving a removed vertex, which keeps its edge and
/// becomes `u_j → w_j`. Between corners `j` and `j + 1` lies side `j`: the face's halfedge
/// `u_j → u_{j+1}` (new), whose twin `u_{j+1} → u_j` sits just before `s_j` in `s_j`'s face
/// (or boundary loop). That twin is new (inserted after `prev(s_j)`), or, where the ring passes
/// from one end of a bevelled edge to the other, it is `prev(s_j)` itself: one of the edge's
/// halfedges, which stays in its face.
#[derive(Clone, Debug, PartialEq)]
struct Ring {
    /// `s_j`, counter-clockwise round each removed vertex.
    spokes: Vec<HalfedgeId>,
    /// For side `j`: the old halfedge that becomes its twin (`prev(s_j)`), or `None` (a new one).
    reused: Vec<Option<HalfedgeId>>,
    /// `u_j`'s position.
    positions: Vec<Vec3>,
}

/// Checks `0 < amount ≤ 0.5`.
fn check_amount(amount: f32) -> Result<(), Refusal> {
    if amount > 0.0 && amount <= 0.5 {
        Ok(())
    } else {
        Err(Refusal::BadParameter(format!(
            "bevel amount {amount} is not in (0, 0.5]"
        )))
    }
}

/// The new vertices' positions, `p_v + amount · (p_w − p_v)` along each spoke `v → w`.
fn spoke_positions(
    m: &MeshRef<'_>,
    spokes: &[HalfedgeId],
    amount: f32,
) -> Result<Vec<Vec3>, Refusal> {
    spokes
        .iter()
        .map(|&s| {
            let (pv, pw) = (m.position(m.from_vertex(s)), m.position(m.to_vertex(s)));
            let p = pv + amount * (pw - pv);
            if p.is_finite() {
                Ok(p)
            } else {
                Err(Refusal::NotFinite(p))
            }
        })
        .collect()
}

/// The removed vertices and every corner of every face around them, sorted.
fn seeds_around(m: &MeshRef<'_>, removed: &[VertexId]) -> Vec<VertexId> {
    let mut seeds = removed.to_vec();
    for &c in removed {
        for f in m.vertex_faces(c) {
            seeds.extend(m.face_vertices(f));
        }
    }
    seeds.sort_unstable();
    seeds.dedup();
    seeds
}

/// Checks that `v` can be bevelled by `amount` (the new vertices at that fraction of each edge).
///
/// # Refusals
/// `Stale`, `BadParameter`, `DegenerateFace`, `NotFinite`: see the module doc.
pub fn plan_bevel_vertex(
    world: &World,
    v: VertexId,
    amount: f32,
) -> Result<BevelVertexPlan, Refusal> {
    let m = MeshRef::new(world);
    let stale = || Refusal::Stale(ElementId::Vertex(v));
    m.try_vertex(v).ok_or_else(stale)?;
    let mesh = world.get::<InMesh>(v.0).ok_or_else(stale)?.0;
    check_amount(amount)?;
    // From v's halfedge: on the boundary that is the boundary one, so side 0 is the border.
    let spokes: Vec<HalfedgeId> = m.vertex_outgoing(v).collect();
    if spokes.len() < 3 {
        return Err(Refusal::DegenerateFace(ElementId::Vertex(v)));
    }
    let positions = spoke_positions(&m, &spokes, amount)?;
    Ok(BevelVertexPlan {
        mesh,
        v,
        amount,
        ring: Ring {
            reused: vec![None; spokes.len()],
            spokes,
            positions,
        },
        seeds: seeds_around(&m, &[v]),
    })
}

/// Carries out a bevel planned by [`plan_bevel_vertex`] and returns the new face. It cannot fail
/// on a fresh plan (one made on the world as it is): the mesh then passes
/// [`crate::mesh::validate()`]. In debug builds it plans again and asserts the plan is unchanged.
pub fn apply_bevel_vertex(world: &mut World, plan: BevelVertexPlan) -> FaceId {
    crate::checks::checked_assert_eq!(
        plan_bevel_vertex(world, plan.v, plan.amount).as_ref(),
        Ok(&plan),
        "stale bevel plan"
    );
    let face = apply_ring(world, plan.mesh, &plan.ring, plan.amount);
    world.despawn(plan.v.0);
    face
}

/// Bevels `v` (see the module doc): a face in its place, its corners at `amount` along each of
/// `v`'s edges. Returns the new face.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn bevel_vertex(world: &mut World, v: VertexId, amount: f32) -> Result<FaceId, Refusal> {
    let plan = plan_bevel_vertex(world, v, amount)?;
    Ok(apply_bevel_vertex(world, plan))
}

/// Checks that `e` can be bevelled by `amount` (the new vertices at that fraction of each edge
/// at its ends).
///
/// # Refusals
/// `Stale`, `BoundaryEdge`, `BadParameter`, `DegenerateFace`, `NotFinite`: see the module doc.
pub fn plan_bevel_edge(world: &World, e: EdgeId, amount: f32) -> Result<BevelEdgePlan, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    let mesh = world
        .get::<InMesh>(e.0)
        .ok_or(Refusal::Stale(ElementId::Edge(e)))?
        .0;
    let t = m.twin(h);
    if m.is_boundary(h) || m.is_boundary(t) {
        return Err(Refusal::BoundaryEdge(ElementId::Edge(e)));
    }
    check_amount(amount)?;
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    // Round a from just after h, then round b from just after t: the last spoke at a is
    // next(t) (so side "a → b" is t, in g) and the last at b is next(h) (side "b → a" is h).
    let at_a: Vec<HalfedgeId> = m.vertex_outgoing_from(h).skip(1).collect();
    let at_b: Vec<HalfedgeId> = m.vertex_outgoing_from(t).skip(1).collect();
    if at_a.len() + at_b.len() < 3 {
        return Err(Refusal::DegenerateFace(ElementId::Edge(e)));
    }
    let mut reused = vec![None; at_a.len() + at_b.len()];
    reused[at_a.len() - 1] = Some(t);
    reused[at_a.len() + at_b.len() - 1] = Some(h);
    let spokes: Vec<HalfedgeId> = at_a.into_iter().chain(at_b).collect();
    let positions = spoke_positions(&m, &spokes, amount)?;
    Ok(BevelEdgePlan {
        mesh,
        edge: e,
        a,
        b,
        amount,
        ring: Ring {
            spokes,
            reused,
            positions,
        },
        seeds: seeds_around(&m, &[a, b]),
    })
}

/// Carries out a bevel planned by [`plan_bevel_edge`] and returns the new face. It cannot fail
/// on a fresh plan (one made on the world as it is): the mesh then passes
/// [`crate::mesh::validate()`]. In debug builds it plans again and asserts the plan is unchanged.
pub fn apply_bevel_edge(world: &mut World, plan: BevelEdgePlan) -> FaceId {
    crate::checks::checked_assert_eq!(
        plan_bevel_edge(world, plan.edge, plan.amount).as_ref(),
        Ok(&plan),
        "stale bevel plan"
    );
    let seam = world.get::<Seam>(plan.edge.0).is_some();
    let face = apply_ring(world, plan.mesh, &plan.ring, plan.amount);
    if seam {
        // e's halfedges now lie on the two sides of F that run where e ran.
        for x in plan.ring.reused.iter().flatten() {
            let edge = MeshRef::new(world).edge(*x);
            world.entity_mut(edge.0).insert(Seam);
        }
    }
    for entity in [plan.a.0, plan.b.0, plan.edge.0] {
        world.despawn(entity);
    }
    face
}

/// Bevels `e` (see the module doc): a face in its place, its corners at `amount` along each
/// other edge at its ends. Returns the new face.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn bevel_edge(world: &mut World, e: EdgeId, amount: f32) -> Result<FaceId, Refusal> {
    let plan = plan_bevel_edge(world, e, amount)?;
    Ok(apply_bevel_edge(world, plan))
}

/// `a + amount · (b − a)`, the formula of the positions, for UVs.
fn along(a: Vec2, b: Vec2, amount: f32) -> Vec2 {
    a + amount * (b - a)
}

/// Builds the ring's face and links it in (see [`Ring`]); despawns nothing. Returns the face.
fn apply_ring(world: &mut World, mesh: MeshId, ring: &Ring, amount: f32) -> FaceId {
    let n = ring.spokes.len();
    let next = |j: usize| (j + 1) % n;
    let prev = |j: usize| (j + n - 1) % n;
    let has = MeshAttributes::of(world, mesh);
    // Everything read before anything moves.
    let m = MeshRef::new(world);
    let spokes = &ring.spokes;
    let before: Vec<HalfedgeId> = spokes.iter().map(|&s| m.prev(s)).collect();
    let twins: Vec<HalfedgeId> = spokes.iter().map(|&s| m.twin(s)).collect();
    let faces: Vec<Option<FaceId>> = spokes.iter().map(|&s| m.face(s)).collect();
    let origins: Vec<VertexId> = spokes.iter().map(|&s| m.from_vertex(s)).collect();
    let uvs = has
        .uv
        .then(|| RingUvs::read(world, spokes, &before, &twins, amount));
    let carried: Vec<(Option<VertexNormal>, Option<VertexColor>)> = origins
        .iter()
        .map(|v| {
            (
                world.get::<VertexNormal>(v.0).copied(),
                world.get::<VertexColor>(v.0).copied(),
            )
        })
        .collect();
    let alloc = world.entity_allocator();
    let u: Vec<VertexId> = (0..n).map(|_| VertexId(alloc.alloc())).collect();
    let outer: Vec<HalfedgeId> = ring
        .reused
        .iter()
        .map(|r| r.unwrap_or_else(|| HalfedgeId(alloc.alloc())))
        .collect();
    let inner: Vec<HalfedgeId> = (0..n).map(|_| HalfedgeId(alloc.alloc())).collect();
    let edges: Vec<EdgeId> = (0..n).map(|_| EdgeId(alloc.alloc())).collect();
    let face = FaceId(alloc.alloc());
    let member = InMesh(mesh);
    // Each spoke now leaves u_j: its twin ends there.
    for j in 0..n {
        he(world, twins[j]).vertex = u[j];
    }
    // Side j's outer halfedge u_{j+1} → u_j, just before s_j.
    for j in 0..n {
        if ring.reused[j].is_some() {
            let mut x = he(world, outer[j]);
            x.vertex = u[j];
            x.twin = inner[j];
            x.edge = edges[j];
        } else {
            spawn_at(
                world,
                outer[j].0,
                (
                    Halfedge {
                        twin: inner[j],
                        next: spokes[j],
                        prev: before[j],
                        vertex: u[j],
                        edge: edges[j],
                        face: faces[j],
                    },
                    member,
                ),
            );
            he(world, before[j]).next = outer[j];
            he(world, spokes[j]).prev = outer[j];
        }
    }
    for j in 0..n {
        spawn_at(
            world,
            inner[j].0,
            (
                Halfedge {
                    twin: outer[j],
                    next: inner[next(j)],
                    prev: inner[prev(j)],
                    vertex: u[next(j)],
                    edge: edges[j],
                    face: Some(face),
                },
                member,
            ),
        );
        // The inner halfedge always has a face: the edge names it.
        spawn_at(world, edges[j].0, (Edge { halfedge: inner[j] }, member));
    }
    for j in 0..n {
        // A boundary side j makes its outer halfedge u_{j+1}'s one boundary halfedge; u_j's
        // is then s_j itself (the removed vertex's boundary halfedge).
        let out = if faces[prev(j)].is_none() {
            outer[prev(j)]
        } else {
            spokes[j]
        };
        spawn_at(
            world,
            u[j].0,
            (
                Vertex { halfedge: out },
                Position(ring.positions[j]),
                member,
            ),
        );
        let (normal, color) = carried[j];
        if let Some(x) = normal.filter(|_| has.normals) {
            world.entity_mut(u[j].0).insert(x);
        }
        if let Some(x) = color.filter(|_| has.colors) {
            world.entity_mut(u[j].0).insert(x);
        }
    }
    spawn_at(world, face.0, (Face { halfedge: inner[0] }, member));
    if let Some(uvs) = uvs {
        uvs.write(world, &twins, &outer, &inner);
    }
    face
}

/// The UVs of the new corners `u_j`: `inside[j]` in the face of `twin(s_j)` (the old corner of
/// the removed vertex there), `ahead[j]` in the face of `s_j` (the corner of side j's twin);
/// `None` where there is no face.
struct RingUvs {
    inside: Vec<Option<Vec2>>,
    ahead: Vec<Option<Vec2>>,
}

impl RingUvs {
    /// Reads them `amount` along each spoke, before anything moves.
    fn read(
        world: &World,
        spokes: &[HalfedgeId],
        before: &[HalfedgeId],
        twins: &[HalfedgeId],
        amount: f32,
    ) -> Self {
        let m = MeshRef::new(world);
        let uv = |x: HalfedgeId| attributes::corner_uv(world, x).unwrap_or_default();
        let inside = twins
            .iter()
            .map(|&x| m.face(x).map(|_| along(uv(x), uv(m.prev(x)), amount)))
            .collect();
        let ahead = spokes
            .iter()
            .zip(before)
            .map(|(&s, &b)| m.face(s).map(|_| along(uv(b), uv(s), amount)))
            .collect();
        Self { inside, ahead }
    }

    /// Writes them at the corners of the twins, the outer halfedges and the new face's inner
    /// ones.
    fn write(
        &self,
        world: &mut World,
        twins: &[HalfedgeId],
        outer: &[HalfedgeId],
        inner: &[HalfedgeId],
    ) {
        let n = twins.len();
        for j in 0..n {
            if let Some(x) = self.inside[j] {
                attributes::set_corner_uv(world, twins[j], x);
            }
            if let Some(x) = self.ahead[j] {
                attributes::set_corner_uv(world, outer[j], x);
            }
            // F's corner at u_{j+1}: as in the face across side j (the face of twin(s_{j+1})),
            // or, where side j is on the boundary, as in the face of s_{j+1}.
            let k = (j + 1) % n;
            let x = self.inside[k].or(self.ahead[k]).unwrap_or_default();
            attributes::set_corner_uv(world, inner[j], x);
        }
    }
}

/// Bevelling a vertex, an edge or faces: a local edit.
pub const BEVEL: Declaration = Declaration::new("bevel")
    .titled("Bevel")
    .described("bevel the selected vertex or edge into a face whose corners lie AMOUNT (0–0.5) along its edges, or inset the selected faces by AMOUNT with DEPTH")
    .on_key("Ctrl+B")
    .naming(Names::Elements)
    .with_parameters(&[
        Parameter::real("AMOUNT", 0.25, 0.0, 0.999),
        Parameter::real("DEPTH", 0.0, -1e6, 1e6),
    ])
    .in_section(Section::Modelling);

/// Blender's bevel on what it names: one vertex or one edge ([`plan_bevel_vertex`],
/// [`plan_bevel_edge`]: Scotty3D's `bevel_vertex` and `bevel_edge`), or faces (an inset with
/// depth, as [`Inset`]): `bevel:ELEMENTS[:AMOUNT[:DEPTH]]`, Ctrl+B. A halfedge names its edge.
pub struct Bevel;

/// What a [`Bevel`] works on.
enum Bevelled {
    Vertex(VertexId),
    Edge(EdgeId),
    Faces,
}

impl Bevel {
    /// What `values` name, checked for kind (not for liveness: the plans check that).
    ///
    /// # Refusals
    /// [`Refusal::BadParameter`] for anything but one vertex, one edge (or halfedge) or faces.
    fn bevelled(world: &World, values: Values<'_>) -> Result<Bevelled, Refusal> {
        let m = MeshRef::new(world);
        match values.elements() {
            [ElementId::Vertex(v)] => Ok(Bevelled::Vertex(*v)),
            [ElementId::Edge(e)] => Ok(Bevelled::Edge(*e)),
            [ElementId::Halfedge(h)] if m.try_halfedge(*h).is_some() => {
                Ok(Bevelled::Edge(m.edge(*h)))
            }
            [ElementId::Halfedge(h)] => Err(Refusal::Stale(ElementId::Halfedge(*h))),
            faces if faces.iter().all(|x| matches!(x, ElementId::Face(_))) => Ok(Bevelled::Faces),
            _ => Err(Refusal::BadParameter(
                "bevel names one vertex, one edge or faces".into(),
            )),
        }
    }
}

impl MeshOperation for Bevel {
    fn declaration(&self) -> &'static Declaration {
        &BEVEL
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, mesh: MeshId, values: Values<'_>) -> Option<Reach> {
        let amount = values.number(0) as f32;
        match Self::bevelled(world, values).ok()? {
            Bevelled::Vertex(v) => {
                Reach::local(world, plan_bevel_vertex(world, v, amount).ok()?.seeds())
            }
            Bevelled::Edge(e) => {
                Reach::local(world, plan_bevel_edge(world, e, amount).ok()?.seeds())
            }
            Bevelled::Faces => Inset.reach(world, mesh, values),
        }
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let amount = values.number(0) as f32;
        let new_face = |f: FaceId| (format!("new face {f}"), Some(ElementId::Face(f)));
        match Self::bevelled(world, values)? {
            Bevelled::Vertex(v) => {
                let plan = plan_bevel_vertex(world, v, amount)?;
                Ok(Applied::carried_out(world, plan.seeds(), |world| {
                    new_face(apply_bevel_vertex(world, plan))
                }))
            }
            Bevelled::Edge(e) => {
                let plan = plan_bevel_edge(world, e, amount)?;
                Ok(Applied::carried_out(world, plan.seeds(), |world| {
                    new_face(apply_bevel_edge(world, plan))
                }))
            }
            Bevelled::Faces => Inset.apply(world, mesh, values, context),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BuiltMesh, MeshMembers, PolygonSoup, mesh_stats};
    use crate::mesh::{shapes, validate};
    use crate::ops::local::testkit::*;

    /// Bevels the edge between input vertices `i` and `j`.
    fn bevel_between(
        world: &mut World,
        built: &BuiltMesh,
        i: usize,
        j: usize,
        amount: f32,
    ) -> Result<FaceId, Refusal> {
        let e = edge(world, built, i, j);
        bevel_edge(world, e, amount)
    }

    /// What bevelling the input vertices `removed` of `soup` (one vertex, or the two ends of
    /// an edge) must give, worked out on the soup: in every face, a removed corner gives way
    /// to a new vertex on each of its two sides that does not join it to the other removed
    /// vertex; the new face runs against every pair of new vertices a face holds in a row,
    /// its pieces joined across the boundary where it meets it.
    fn expected(soup: &PolygonSoup, removed: &[u32], amount: f32) -> Vec<Vec<Key>> {
        let p = |i: u32| soup.positions[i as usize];
        let u = |c: u32, w: u32| bits(p(c) + amount * (p(w) - p(c)));
        let gone = |i: u32| removed.contains(&i);
        let mut faces = Vec::new();
        let mut sides: Vec<(Key, Key)> = Vec::new();
        for f in soup.faces() {
            let k = f.len();
            let mut cycle: Vec<(Key, bool)> = Vec::new();
            for i in 0..k {
                let (before, c, after) = (f[(i + k - 1) % k], f[i], f[(i + 1) % k]);
                if !gone(c) {
                    cycle.push((bits(p(c)), false));
                    continue;
                }
                if !gone(before) {
                    cycle.push((u(c, before), true));
                }
                if !gone(after) {
                    cycle.push((u(c, after), true));
                }
            }
            for i in 0..cycle.len() {
                let (x, y) = (cycle[i], cycle[(i + 1) % cycle.len()]);
                if x.1 && y.1 {
                    sides.push((y.0, x.0));
                }
            }
            faces.push(canonical(cycle.into_iter().map(|(k, _)| k).collect()));
        }
        let to = |x: Key| sides.iter().find(|s| s.0 == x).map(|s| s.1);
        let mut starts: Vec<Key> = sides
            .iter()
            .map(|s| s.0)
            .filter(|&x| !sides.iter().any(|s| s.1 == x))
            .collect();
        // Each piece of the new face that ends at the boundary is followed by a boundary side.
        let boundary_sides = starts.len();
        if starts.is_empty() {
            starts.push(sides[0].0);
        }
        let mut new_face = Vec::new();
        for s in starts {
            let mut x = Some(s);
            while let Some(at) = x.filter(|at| !new_face.contains(at)) {
                new_face.push(at);
                x = to(at);
            }
        }
        assert_eq!(new_face.len(), sides.len() + boundary_sides);
        faces.push(canonical(new_face));
        faces.sort();
        faces
    }

    /// A lens: two pentagons sharing the path x – a – b – y, so `a` and `b` (input 0 and 1)
    /// have two edges each and `a – b` is interior.
    fn lens() -> PolygonSoup {
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        PolygonSoup::from_faces(
            vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(-1.0, 0.0),
                p(2.0, 0.0),
                p(0.5, 1.0),
                p(0.5, -1.0),
            ],
            &[[2u32, 0, 1, 3, 4], [3, 1, 0, 2, 5]],
        )
    }

    // ---- bevel a vertex ----------------------------------------------------------------

    #[test]
    fn a_cube_corner_becomes_a_triangle() {
        let soup = shapes::cube();
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let v = vertex(&built, 0);
        let m = MeshRef::new(&world);
        let spoke_edges: Vec<EdgeId> = m.vertex_outgoing(v).map(|h| m.edge(h)).collect();
        let old_faces: Vec<FaceId> = m.vertex_faces(v).collect();
        let f = bevel_vertex(&mut world, v, 0.25).unwrap();
        validate(&world, mesh).unwrap();
        assert_eq!(counts(&world, mesh), (10, 15, 7, 2, 0));
        let m = MeshRef::new(&world);
        assert!(m.try_vertex(v).is_none(), "the vertex is gone");
        // The corner (−1, −1, −1) moved a quarter of the way (2) along each edge.
        let mut corners: Vec<Key> = m.face_vertices(f).map(|u| bits(m.position(u))).collect();
        corners.sort_unstable();
        let mut want = [
            Vec3::new(-0.5, -1.0, -1.0),
            Vec3::new(-1.0, -0.5, -1.0),
            Vec3::new(-1.0, -1.0, -0.5),
        ]
        .map(bits);
        want.sort_unstable();
        assert_eq!(corners, want);
        let sizes = mesh_stats(&world, mesh).face_sizes;
        assert_eq!(
            sizes.into_iter().collect::<Vec<_>>(),
            [(3, 1), (4, 3), (5, 3)]
        );
        for g in old_faces {
            assert_eq!(m.face_degree(g), 5, "the quads around became pentagons");
        }
        for e in spoke_edges {
            assert!(m.try_edge(e).is_some(), "the edges at v keep their ids");
        }
        assert_eq!(position_cycles(&world, mesh), expected(&soup, &[0], 0.25));
    }

    #[test]
    fn an_interior_grid_vertex_becomes_a_quad() {
        let soup = shapes::quad_grid(2, 2);
        let (mut world, built) = build(&soup);
        let f = bevel_vertex(&mut world, vertex(&built, 4), 0.5).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (12, 16, 5, 1, 1));
        assert_eq!(MeshRef::new(&world).face_degree(f), 4);
        assert_eq!(boundary_loops(&world, built.mesh), [8]);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[4], 0.5)
        );
    }

    #[test]
    fn a_boundary_vertex_gives_a_face_with_one_side_on_the_border() {
        // The middle of the quad grid's bottom side: valence 3, two quads.
        let soup = shapes::quad_grid(2, 2);
        let (mut world, built) = build(&soup);
        let f = bevel_vertex(&mut world, vertex(&built, 1), 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (11, 15, 5, 1, 1));
        assert_eq!(boundary_loops(&world, built.mesh), [9]);
        let m = MeshRef::new(&world);
        assert_eq!(m.face_degree(f), 3);
        let on_border: Vec<HalfedgeId> = m
            .face_halfedges(f)
            .filter(|&h| m.is_boundary(m.twin(h)))
            .collect();
        assert_eq!(
            on_border.len(),
            1,
            "one side of the new face is on the border"
        );
        let h = on_border[0];
        let ends = [m.from_vertex(h), m.to_vertex(h)].map(|x| bits(m.position(x)));
        assert_eq!(
            ends,
            [Vec3::new(0.375, 0.0, 0.0), Vec3::new(0.625, 0.0, 0.0)].map(bits)
        );
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[1], 0.25)
        );
        // A triangle grid's corner (valence 3) and a side vertex (valence 4).
        for i in [0, 1] {
            let soup = shapes::grid(2, 2);
            let (mut world, built) = build(&soup);
            bevel_vertex(&mut world, vertex(&built, i), 0.5).unwrap();
            validate(&world, built.mesh).unwrap();
            assert_eq!(
                position_cycles(&world, built.mesh),
                expected(&soup, &[i as u32], 0.5)
            );
            assert_eq!(mesh_stats(&world, built.mesh).euler_characteristic, 1);
        }
    }

    #[test]
    fn triangle_mesh_vertices_bevel() {
        let soup = shapes::tetrahedron();
        let (mut world, built) = build(&soup);
        let f = bevel_vertex(&mut world, vertex(&built, 0), 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (6, 9, 5, 2, 0));
        assert_eq!(MeshRef::new(&world).face_degree(f), 3);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[0], 0.25)
        );
        let soup = shapes::icosahedron();
        let (mut world, built) = build(&soup);
        let f = bevel_vertex(&mut world, vertex(&built, 3), 0.5).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (16, 35, 21, 2, 0));
        assert_eq!(MeshRef::new(&world).face_degree(f), 5);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[3], 0.5)
        );
    }

    #[test]
    fn vertex_refusals_change_nothing() {
        let (mut world, built) = build(&with_attributes(shapes::cube(), Uvs::Continuous));
        let mesh = built.mesh;
        let v = vertex(&built, 0);
        let before = snapshot(&world, mesh);
        for amount in [0.0, -0.1, 0.51, f32::NAN, f32::INFINITY] {
            assert_refused_like(
                &mut world,
                mesh,
                |r| matches!(r, Refusal::BadParameter(_)),
                |w| bevel_vertex(w, v, amount),
            );
        }
        assert_untouched(&world, mesh, &before);
        // A quad grid's corner has two edges: its face would be a 2-gon.
        let (mut world, built) = build(&shapes::quad_grid(2, 2));
        let corner = vertex(&built, 0);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::DegenerateFace(ElementId::Vertex(corner)),
            |w| bevel_vertex(w, corner, 0.25),
        );
        // So has an interior vertex of valence 2.
        let (mut world, built) = build(&lens());
        let a = vertex(&built, 0);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::DegenerateFace(ElementId::Vertex(a)),
            |w| bevel_vertex(w, a, 0.25),
        );
        // A vertex that is gone.
        let (mut world, built) = build(&shapes::cube());
        let v = vertex(&built, 0);
        bevel_vertex(&mut world, v, 0.25).unwrap();
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Vertex(v)),
            |w| bevel_vertex(w, v, 0.25),
        );
    }

    // ---- bevel an edge -----------------------------------------------------------------

    #[test]
    fn a_cube_edge_becomes_a_quad() {
        let soup = shapes::cube();
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let e = edge(&world, &built, 0, 1);
        let (a, b) = (vertex(&built, 0), vertex(&built, 1));
        let f = bevel_edge(&mut world, e, 0.25).unwrap();
        validate(&world, mesh).unwrap();
        // Each end of valence 3 gives 2 vertices: V 8 − 2 + 4, E 12 − 1 + 4, F 6 + 1.
        assert_eq!(counts(&world, mesh), (10, 15, 7, 2, 0));
        let m = MeshRef::new(&world);
        assert!(m.try_vertex(a).is_none() && m.try_vertex(b).is_none());
        assert!(m.try_edge(e).is_none(), "the edge is gone");
        let mut corners: Vec<Key> = m.face_vertices(f).map(|u| bits(m.position(u))).collect();
        corners.sort_unstable();
        let mut want = [
            Vec3::new(-1.0, -0.5, -1.0),
            Vec3::new(-1.0, -1.0, -0.5),
            Vec3::new(1.0, -0.5, -1.0),
            Vec3::new(1.0, -1.0, -0.5),
        ]
        .map(bits);
        want.sort_unstable();
        assert_eq!(corners, want);
        let sizes = mesh_stats(&world, mesh).face_sizes;
        assert_eq!(sizes.into_iter().collect::<Vec<_>>(), [(4, 5), (5, 2)]);
        assert_eq!(
            position_cycles(&world, mesh),
            expected(&soup, &[0, 1], 0.25)
        );
    }

    #[test]
    fn triangle_mesh_edges_bevel() {
        // A tetrahedron edge: both ends of valence 3, every face a triangle.
        let soup = shapes::tetrahedron();
        let (mut world, built) = build(&soup);
        let f = bevel_between(&mut world, &built, 0, 1, 0.5).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (6, 9, 5, 2, 0));
        assert_eq!(MeshRef::new(&world).face_degree(f), 4);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[0, 1], 0.5)
        );
        // An icosahedron edge: ends of valence 5, an octagon.
        let soup = shapes::icosahedron();
        let (mut world, built) = build(&soup);
        let m = MeshRef::new(&world);
        let (a, b) = m.edge_vertices(MeshMembers::collect(&world, built.mesh).edges[7]);
        let index = |x: VertexId| built.input_vertices.iter().position(|&y| y == Some(x));
        let (ia, ib) = (index(a).unwrap(), index(b).unwrap());
        let f = bevel_between(&mut world, &built, ia, ib, 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        // V 12 − 2 + 8, E 30 + 5 + 5 − 3, F 20 + 1.
        assert_eq!(counts(&world, built.mesh), (18, 37, 21, 2, 0));
        assert_eq!(MeshRef::new(&world).face_degree(f), 8);
        let removed = [ia as u32, ib as u32];
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &removed, 0.25)
        );
    }

    #[test]
    fn edges_with_ends_on_the_boundary_bevel() {
        // Quad grid: the edge from the centre (4) down to the bottom side's middle (1).
        let soup = shapes::quad_grid(2, 2);
        let (mut world, built) = build(&soup);
        let f = bevel_between(&mut world, &built, 4, 1, 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        // V 9 − 2 + 5, E 12 + 4 + 3 − 3, F 4 + 1.
        assert_eq!(counts(&world, built.mesh), (12, 16, 5, 1, 1));
        assert_eq!(boundary_loops(&world, built.mesh), [9]);
        let m = MeshRef::new(&world);
        assert_eq!(m.face_degree(f), 5);
        let border = m.face_halfedges(f).filter(|&h| m.is_boundary(m.twin(h)));
        assert_eq!(border.count(), 1);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[4, 1], 0.25)
        );
        // Scotty3D's case: a square's diagonal, both ends on the boundary. The new quad meets
        // the border twice; the one loop goes from 4 sides to 6.
        let soup = PolygonSoup::from_faces(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            &[[0u32, 1, 2], [0, 2, 3]],
        );
        let (mut world, built) = build(&soup);
        let f = bevel_between(&mut world, &built, 0, 2, 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (6, 8, 3, 1, 1));
        assert_eq!(boundary_loops(&world, built.mesh), [6]);
        let m = MeshRef::new(&world);
        assert_eq!(m.face_degree(f), 4);
        let border = m.face_halfedges(f).filter(|&h| m.is_boundary(m.twin(h)));
        assert_eq!(border.count(), 2);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[0, 2], 0.25)
        );
    }

    #[test]
    fn edge_refusals_change_nothing() {
        let (mut world, built) = build(&shapes::quad_grid(2, 2));
        let mesh = built.mesh;
        let before = snapshot(&world, mesh);
        let border = edge(&world, &built, 0, 1);
        assert_refused(
            &mut world,
            mesh,
            Refusal::BoundaryEdge(ElementId::Edge(border)),
            |w| bevel_edge(w, border, 0.25),
        );
        let inner = edge(&world, &built, 1, 4);
        for amount in [0.0, -1.0, 0.75, f32::NAN] {
            assert_refused_like(
                &mut world,
                mesh,
                |r| matches!(r, Refusal::BadParameter(_)),
                |w| bevel_edge(w, inner, amount),
            );
        }
        assert_untouched(&world, mesh, &before);
        // Both ends with two edges: the face would have two sides.
        let (mut world, built) = build(&lens());
        let e = edge(&world, &built, 0, 1);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::DegenerateFace(ElementId::Edge(e)),
            |w| bevel_edge(w, e, 0.25),
        );
        // One end with two edges is enough: a – x has ends of valence 2 and 3 (x is on the
        // boundary), and makes a triangle.
        let soup = lens();
        let (mut world, built) = build(&soup);
        let ax = edge(&world, &built, 0, 2);
        let f = bevel_edge(&mut world, ax, 0.25).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(MeshRef::new(&world).face_degree(f), 3);
        assert_eq!(
            position_cycles(&world, built.mesh),
            expected(&soup, &[0, 2], 0.25)
        );
        // An edge that is gone.
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Edge(ax)),
            |w| bevel_edge(w, ax, 0.25),
        );
    }

    // ---- attributes and undo -----------------------------------------------------------

    #[test]
    fn uvs_normals_and_colours_are_carried() {
        let soup = with_attributes(shapes::cube(), Uvs::Continuous);
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let v = vertex(&built, 6);
        let normal = world.get::<VertexNormal>(v.0).copied().unwrap();
        let color = world.get::<VertexColor>(v.0).copied().unwrap();
        let f = bevel_vertex(&mut world, v, 0.25).unwrap();
        validate(&world, mesh).unwrap();
        assert_uvs_follow_positions(&world, mesh);
        for u in MeshRef::new(&world).face_vertices(f) {
            assert_eq!(world.get::<VertexNormal>(u.0), Some(&normal));
            assert_eq!(world.get::<VertexColor>(u.0), Some(&color));
        }
        let e = edge(&world, &built, 0, 1);
        let ends = [0, 1].map(|i| world.get::<VertexColor>(vertex(&built, i).0).unwrap().0);
        let f = bevel_edge(&mut world, e, 0.5).unwrap();
        validate(&world, mesh).unwrap();
        assert_uvs_follow_positions(&world, mesh);
        let m = MeshRef::new(&world);
        let colors: Vec<[u8; 3]> = m
            .face_vertices(f)
            .map(|u| world.get::<VertexColor>(u.0).unwrap().0)
            .collect();
        assert_eq!(colors.len(), 4);
        assert!(
            colors.iter().all(|c| ends.contains(c)),
            "each from a or b: {colors:?}"
        );
        let vertices = MeshMembers::collect(&world, mesh).vertices;
        assert!(
            vertices
                .iter()
                .all(|u| world.get::<VertexNormal>(u.0).is_some())
        );
        // A seam on a bevelled edge goes to both sides that replace it.
        let (mut world, built) = build(&soup);
        let e = edge(&world, &built, 2, 3);
        world.entity_mut(e.0).insert(Seam);
        let mut has = MeshAttributes::of(&world, built.mesh);
        has.seams = true;
        attributes::set_record(&mut world, built.mesh, has);
        let f = bevel_edge(&mut world, e, 0.25).unwrap();
        let m = MeshRef::new(&world);
        let marked = m
            .face_halfedges(f)
            .filter(|&h| world.get::<Seam>(m.edge(h).0).is_some())
            .count();
        assert_eq!(marked, 2);
    }

    #[test]
    fn uvs_across_seams_are_interpolated_inside_each_face() {
        // Every cube face its own chart: UV = uv_at(p) + (8 i, 0) for face i.
        let mut soup = with_attributes(shapes::cube(), Uvs::Continuous);
        let uvs = soup.corner_uvs.as_mut().unwrap();
        for (k, uv) in uvs.iter_mut().enumerate() {
            uv.x += 8.0 * (k / 4) as f32;
        }
        for (bevel_an_edge, amount) in [(false, 0.25), (true, 0.5)] {
            let (mut world, built) = build(&soup);
            let mesh = built.mesh;
            // Each face's chart offset, read off its first corner.
            let m = MeshRef::new(&world);
            let offset: Vec<(FaceId, Vec2)> = MeshMembers::collect(&world, mesh)
                .faces
                .iter()
                .map(|&f| {
                    let h = m.face_halfedge(f);
                    let uv = attributes::corner_uv(&world, h).unwrap();
                    (f, uv - uv_at(m.position(m.to_vertex(h))))
                })
                .collect();
            let new = if bevel_an_edge {
                bevel_between(&mut world, &built, 3, 7, amount)
            } else {
                bevel_vertex(&mut world, vertex(&built, 7), amount)
            }
            .unwrap();
            validate(&world, mesh).unwrap();
            let m = MeshRef::new(&world);
            for &(f, off) in &offset {
                for h in m.face_halfedges(f) {
                    let want = uv_at(m.position(m.to_vertex(h))) + off;
                    assert_eq!(attributes::corner_uv(&world, h), Some(want), "{h} in {f}");
                }
            }
            // The new face's corners copy a corner of the same vertex in a face beside it.
            for h in m.face_halfedges(new) {
                let u = m.to_vertex(h);
                let uv = attributes::corner_uv(&world, h).unwrap();
                let beside: Vec<Vec2> = m
                    .vertex_outgoing(u)
                    .map(|x| m.twin(x))
                    .filter(|&x| m.face(x).is_some_and(|g| g != new))
                    .map(|x| attributes::corner_uv(&world, x).unwrap())
                    .collect();
                assert!(beside.contains(&uv), "{uv} not in {beside:?}");
            }
        }
    }

    #[test]
    fn undo_by_the_seeds_restores_exactly() {
        // An interior vertex and an edge of the cube with every attribute.
        let (mut world, built) = build(&with_attributes(shapes::cube(), Uvs::Continuous));
        let plan = plan_bevel_vertex(&world, vertex(&built, 5), 0.25).unwrap();
        assert_undo_redo(&mut world, built.mesh, &plan.seeds(), |w| {
            apply_bevel_vertex(w, plan);
        });
        let (mut world, built) = build(&with_attributes(shapes::cube(), Uvs::Continuous));
        let plan = plan_bevel_edge(&world, edge(&world, &built, 2, 6), 0.5).unwrap();
        assert_undo_redo(&mut world, built.mesh, &plan.seeds(), |w| {
            apply_bevel_edge(w, plan);
        });
        // On the boundary: a grid's side vertex, and an edge with both ends on the border.
        let (mut world, built) = build(&shapes::quad_grid(3, 2));
        let plan = plan_bevel_vertex(&world, vertex(&built, 2), 0.5).unwrap();
        assert_undo_redo(&mut world, built.mesh, &plan.seeds(), |w| {
            apply_bevel_vertex(w, plan);
        });
        let (mut world, built) = build(&shapes::grid(2, 2));
        let plan = plan_bevel_edge(&world, edge(&world, &built, 1, 5), 0.25).unwrap();
        assert_undo_redo(&mut world, built.mesh, &plan.seeds(), |w| {
            apply_bevel_edge(w, plan);
        });
    }
}
