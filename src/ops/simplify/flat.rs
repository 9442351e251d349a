//! Edge collapses on flat triangle tables: the simplifier's inner loop without entities, and
//! the remesher's collapse pass ([`crate::ops::remesh`]), which reads and writes them the same
//! way.
//!
//! [`super::simplify`] reads the mesh into tables once ([`crate::mesh::tables::extract`]), makes
//! every collapse here on `u32` rows, and writes the surviving rows back in one pass
//! ([`FlatTriangles::write_back`]). A collapse here is the one the stepped run ([`super::QemRun`])
//! makes on entities ([`crate::ops::local::plan_collapse`] and its deferred apply,
//! [`crate::ops::local::apply_collapse_deferred`]), specialised to meshes of triangles (which a
//! collapse keeps triangles), and like it carries no attributes: the same checks accept the same
//! edges (boundary pinch, the link condition of Dey, Edelsbrunner et al. 1999, a wing's valence, a
//! boundary loop's length, the merged vertex's valence, a face normal's turn), and the same links
//! are rewritten, down to the halfedge each vertex and edge names afterwards, since an edge's
//! halfedge decides which end the next collapse of it keeps. So a simplification here makes the
//! stepped run's collapses in the same order and leaves the same mesh, element for element; a test
//! holds the two side by side. Only the storage order differs: the stepped run despawns as it goes,
//! this one at the end ([`super::despawn_dead`]), so a saved file lists the same vertices and faces
//! in another order, and freed ids come back in another order.
//!
//! Why tables: a collapse reads two vertex rings, three halfedge and position reads a spoke,
//! and on entities each read is a lookup from entity to table row and a column each. Here a
//! halfedge's six links are one 24-byte record, a face's three halfedges neighbours, so a
//! spoke costs fewer and closer reads, and nothing is despawned until the end. A face's
//! halfedge never changes (only a polygon side would move it), so faces are not written back.

use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use super::SlotRecord;
use crate::mesh::despawn::Despawner;
use crate::mesh::elements::{Edge, Halfedge, Position, Vertex};
use crate::mesh::ids::{EdgeId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::mesh::tables::{Connectivity, NONE};
use crate::mesh::topology::{MAX_LOOP, newell_area_vector};
use crate::ops::geometry::surface_fit::FitElements;
use crate::ops::local::{SpokeView, Wing, wing_check};

/// One halfedge's links, as rows ([`NONE`]: no face).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Links {
    twin: u32,
    next: u32,
    prev: u32,
    /// The tip vertex.
    to: u32,
    edge: u32,
    face: u32,
}

/// A triangle mesh as flat rows, with what the collapses removed.
pub(crate) struct FlatTriangles {
    he: Vec<Links>,
    position: Vec<Vec3>,
    vertex_halfedge: Vec<u32>,
    edge_halfedge: Vec<u32>,
    /// Rows removed so far, by kind.
    gone: Gone,
    /// The two rings of the last plan, kept for its apply (and reused, not reallocated).
    rings: [Vec<Spoke>; 2],
}

/// The rows the collapses removed.
#[derive(Default)]
struct Gone {
    vertices: Vec<u32>,
    halfedges: Vec<u32>,
    edges: Vec<u32>,
    faces: Vec<u32>,
}

/// One outgoing halfedge of a ring's centre: its row, its links and its tip's position.
#[derive(Clone, Copy, Debug)]
struct Spoke {
    id: u32,
    links: Links,
    tip: Vec3,
}

impl Spoke {
    /// Whether a face (a triangle, in this mesh) lies left of the spoke.
    fn has_face(&self) -> bool {
        self.links.face != NONE
    }
}

/// One side of the collapsing edge.
#[derive(Clone, Copy, Debug)]
enum Side {
    /// No face: `x` is a boundary halfedge, which goes; `prev` and `next` are joined.
    Boundary { x: u32, next: u32, prev: u32 },
    /// A triangle that goes, with its halfedges `x`, `next`, `prev` and its third corner.
    Triangle {
        face: u32,
        x: u32,
        next: u32,
        prev: u32,
        opposite: u32,
    },
}

impl Side {
    /// The third corner of a triangle side.
    fn opposite(&self) -> Option<u32> {
        match *self {
            Side::Triangle { opposite, .. } => Some(opposite),
            Side::Boundary { .. } => None,
        }
    }

    /// Whether the collapse removes halfedge `h` on this side.
    fn removes(&self, h: u32) -> bool {
        match *self {
            Side::Triangle { x, next, prev, .. } => h == x || h == next || h == prev,
            Side::Boundary { x, .. } => h == x,
        }
    }
}

/// An accepted collapse of the edge of halfedge `h`: its start `a` stays, moved to
/// `position`, its tip `b` goes. Its two rings stay in [`FlatTriangles`] until it is applied.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plan {
    a: u32,
    b: u32,
    edge: u32,
    position: Vec3,
    sides: [Side; 2],
    merged_boundary: bool,
}

impl Plan {
    /// Its two ends: the vertex that stays and the one that goes.
    pub fn ends(&self) -> [u32; 2] {
        [self.a, self.b]
    }
}

/// What one collapse did, by row.
pub(crate) struct Collapsed {
    /// The vertex that stayed and the one that went.
    pub kept: u32,
    pub removed: u32,
    /// Where the kept vertex went.
    pub position: Vec3,
    /// Positions before the collapse.
    pub kept_position: Vec3,
    pub removed_position: Vec3,
    /// The wings: the third corners of the triangles removed, left of the kept → removed
    /// halfedge and right of it.
    pub wings: [Option<u32>; 2],
    /// The edges removed (the collapsed one first).
    pub removed_edges: [Option<u32>; 3],
}

impl Collapsed {
    /// Triangles removed: one a wing.
    pub fn triangles_removed(&self) -> usize {
        self.wings.iter().flatten().count()
    }

    /// The collapse as a history keeps it, by vertex row.
    pub fn record(&self) -> SlotRecord {
        SlotRecord {
            kept: self.kept,
            removed: self.removed,
            merged_position: self.position,
            kept_position: self.kept_position,
            removed_position: self.removed_position,
            left: self.wings[0],
            right: self.wings[1],
            faces: self.triangles_removed(),
        }
    }
}

impl FlatTriangles {
    /// The tables of a triangle mesh (every face a triangle: a collapse keeps it so), with
    /// the edges renumbered: edge row `e` becomes edge `edge_number[e]`, each below `edges`
    /// (the simplifier numbers them by heap slot, so that a number serves as both).
    pub fn new(t: &Connectivity, edge_number: &[u32], edges: usize) -> Self {
        let he = (0..t.twin.len())
            .map(|h| Links {
                twin: t.twin[h],
                next: t.next[h],
                prev: t.prev[h],
                to: t.to_vertex[h],
                edge: edge_number[t.edge[h] as usize],
                face: t.face[h],
            })
            .collect();
        let mut edge_halfedge = vec![NONE; edges];
        for (&number, &h) in edge_number.iter().zip(&t.edge_halfedge) {
            edge_halfedge[number as usize] = h;
        }
        Self {
            he,
            position: t.positions.clone(),
            vertex_halfedge: t.vertex_halfedge.clone(),
            edge_halfedge,
            gone: Gone::default(),
            rings: [Vec::with_capacity(16), Vec::with_capacity(16)],
        }
    }

    /// The halfedge an edge names: its start is the end a collapse of the edge keeps.
    pub fn edge_halfedge(&self, e: u32) -> u32 {
        self.edge_halfedge[e as usize]
    }

    /// The tip of halfedge `h`.
    pub fn tip(&self, h: u32) -> u32 {
        self.he[h as usize].to
    }

    /// The twin of halfedge `h`.
    pub fn twin(&self, h: u32) -> u32 {
        self.he[h as usize].twin
    }

    /// The halfedge after `h` around its face (or its boundary loop).
    pub fn next(&self, h: u32) -> u32 {
        self.he[h as usize].next
    }

    /// The edge of halfedge `h`, as numbered in [`FlatTriangles::new`].
    pub fn edge(&self, h: u32) -> u32 {
        self.he[h as usize].edge
    }

    /// Whether a triangle lies left of halfedge `h`.
    pub fn has_face(&self, h: u32) -> bool {
        self.he[h as usize].face != NONE
    }

    /// Where vertex `v` is now.
    pub fn position(&self, v: u32) -> Vec3 {
        self.position[v as usize]
    }

    /// The halfedges leaving `v`, counter-clockwise from its own (none for a vertex without
    /// one); at most [`MAX_LOOP`], as the walks on entities are bounded.
    pub fn outgoing(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let start = self.vertex_halfedge[v as usize];
        let mut at = (start != NONE).then_some(start);
        let mut left = MAX_LOOP;
        std::iter::from_fn(move || {
            let h = at?;
            left -= 1;
            let next = self.he[self.he[h as usize].prev as usize].twin;
            at = (next != start && left > 0).then_some(next);
            Some(h)
        })
    }

    /// Reads both rings of the edge of `h` into `self.rings`, counter-clockwise, starting with
    /// `h` around its start and with its twin around its tip. The two walks take turns, so
    /// that the reads of one overlap those of the other (as the walk on entities does).
    fn read_rings(&mut self, h: u32) {
        let he = &self.he;
        let position = &self.position;
        let [ring_a, ring_b] = &mut self.rings;
        ring_a.clear();
        ring_b.clear();
        let twin = he[h as usize].twin;
        let mut walks = [(h, Some(h), &mut *ring_a), (twin, Some(twin), &mut *ring_b)];
        loop {
            let mut walking = false;
            for (start, at, ring) in &mut walks {
                let Some(id) = *at else { continue };
                walking = true;
                let links = he[id as usize];
                ring.push(Spoke {
                    id,
                    links,
                    tip: position[links.to as usize],
                });
                let next = he[links.prev as usize].twin;
                *at = (next != *start && ring.len() < MAX_LOOP).then_some(next);
            }
            if !walking {
                break;
            }
        }
    }

    /// Every face around the edge of `p` (the last plan made) once, each with its corners once
    /// the plan is applied (the merged vertex first, at the planned position, then the others
    /// counter-clockwise), or `None` for the edge's own triangles, which go: what
    /// [`crate::ops::local::CollapsePlan::reshaped_faces`] lists for the same collapse.
    pub fn reshaped_faces(&self, p: &Plan) -> impl Iterator<Item = (u32, Option<[Vec3; 3]>)> + '_ {
        let [ring_a, ring_b] = &self.rings;
        let position = p.position;
        [(ring_a, p.b, true), (ring_b, p.a, false)]
            .into_iter()
            .flat_map(move |(ring, other, first)| {
                ring.iter().enumerate().filter_map(move |(i, s)| {
                    if !s.has_face() {
                        return None;
                    }
                    let o = &ring[(i + 1) % ring.len()];
                    if s.links.to == other || o.links.to == other {
                        // The edge's own triangles, in both rings: listed once.
                        first.then_some((s.links.face, None))
                    } else {
                        Some((s.links.face, Some([position, s.tip, o.tip])))
                    }
                })
            })
    }

    /// Whether the edge of `h` may collapse into its start at `position`, no face turning by
    /// more than the angle whose cosine is `limit`; the plan if so. The checks are
    /// [`crate::ops::local::plan_collapse`]'s for a triangle mesh (see the module doc).
    pub fn plan(&mut self, h: u32, position: Vec3, limit: f32) -> Option<Plan> {
        self.read_rings(h);
        let [ra, rb] = &self.rings;
        let (a, b) = (rb[0].links.to, ra[0].links.to);
        let side = |ring: &[Spoke]| {
            let s = ring[0];
            let (x, next, prev) = (s.id, s.links.next, s.links.prev);
            if s.has_face() {
                Side::Triangle {
                    face: s.links.face,
                    x,
                    next,
                    prev,
                    opposite: ring[1 % ring.len()].links.to,
                }
            } else {
                Side::Boundary { x, next, prev }
            }
        };
        let sides = [side(ra), side(rb)];
        let on_boundary = |ring: &[Spoke]| ring.iter().any(|s| !s.has_face());
        let boundary_edge = !ra[0].has_face() || !rb[0].has_face();
        let (a_open, b_open) = (on_boundary(ra), on_boundary(rb));
        if !boundary_edge && a_open && b_open {
            return None;
        }
        let opposite = sides.map(|s| s.opposite());
        if !self.link_condition(a, opposite) || !self.sides_allow(a, b, &sides) {
            return None;
        }
        let wings = match opposite {
            [Some(c), Some(d)] if c == d => 1,
            _ => opposite.iter().flatten().count(),
        };
        let merged_boundary = a_open || b_open;
        let minimum = if merged_boundary { 2 } else { 3 };
        if (ra.len() + rb.len()).saturating_sub(2 + wings) < minimum || !position.is_finite() {
            return None;
        }
        let plan = Plan {
            a,
            b,
            edge: ra[0].links.edge,
            position,
            sides,
            merged_boundary,
        };
        let (at_a, at_b) = (rb[0].tip, ra[0].tip);
        (plan.normals_hold(a, at_a, ra, limit) && plan.normals_hold(b, at_b, rb, limit))
            .then_some(plan)
    }

    /// The link condition for the edge from `a` (rings in `self.rings`): no vertex but the
    /// wings `opposite` is a neighbour of both ends, and the triangles a c d and b c d are not
    /// both there (on a manifold mesh, a tetrahedron).
    fn link_condition(&self, a: u32, opposite: [Option<u32>; 2]) -> bool {
        let [ra, rb] = &self.rings;
        for n in rb.iter().map(|s| s.links.to) {
            if n != a && ra.iter().any(|s| s.links.to == n) && !opposite.contains(&Some(n)) {
                return false;
            }
        }
        if let [Some(c), Some(d)] = opposite {
            let has_triangle = |ring: &[Spoke]| {
                ring.iter().enumerate().any(|(i, s)| {
                    let o = ring[(i + 1) % ring.len()].links.to;
                    s.has_face() && ((s.links.to == c && o == d) || (s.links.to == d && o == c))
                })
            };
            if has_triangle(ra) && has_triangle(rb) {
                return false;
            }
        }
        true
    }

    /// What each side allows: a triangle's wing keeps a face beside it and enough edges, a
    /// boundary loop has more than three sides.
    fn sides_allow(&self, a: u32, b: u32, sides: &[Side; 2]) -> bool {
        let [ra, rb] = &self.rings;
        sides.iter().all(|side| match *side {
            Side::Triangle { opposite, .. } => {
                let view = |s: &Spoke| SpokeView {
                    tip: s.links.to,
                    has_face: s.has_face(),
                    triangle: s.has_face(),
                };
                match wing_check((a, ra), (b, rb), opposite, view) {
                    Wing::Dangling => return false,
                    Wing::Enough => return true,
                    Wing::Count => {}
                }
                let start = self.vertex_halfedge[opposite as usize];
                let minimum = if self.he[start as usize].face == NONE {
                    2
                } else {
                    3
                };
                self.valence_exceeds(start, minimum)
            }
            Side::Boundary { x, .. } => self.loop_longer_than_three(x),
        })
    }

    /// Whether the vertex whose outgoing halfedge is `start` has more than `minimum` edges.
    fn valence_exceeds(&self, start: u32, minimum: usize) -> bool {
        let mut h = start;
        for _ in 0..minimum {
            h = self.he[self.he[h as usize].prev as usize].twin;
            if h == start {
                return false;
            }
        }
        true
    }

    /// Whether the boundary loop through `x` has more than three sides.
    fn loop_longer_than_three(&self, x: u32) -> bool {
        let mut h = x;
        for _ in 0..3 {
            h = self.he[h as usize].next;
            if h == x {
                return false;
            }
        }
        true
    }

    /// Carries out `plan` (the last one [`FlatTriangles::plan`] made) and hands each edge the
    /// merged vertex has afterwards to `ring`, with its other end and that end's position.
    pub fn apply(&mut self, p: Plan, mut ring: impl FnMut(u32, u32, Vec3)) -> Collapsed {
        let [ra, rb] = &self.rings;
        crate::checks::checked_assert!(
            ra[0].links.edge == p.edge && ra[0].links.to == p.b && rb[0].links.to == p.a,
            "a plan is applied right after it is made"
        );
        let removes = |h: u32| p.sides.iter().any(|s| s.removes(h));
        let mut removed_edges = [Some(p.edge), None, None];
        self.gone.edges.push(p.edge);
        // Every halfedge into b now points at a.
        for s in rb.iter() {
            if !removes(s.links.twin) {
                self.he[s.links.twin as usize].to = p.a;
            }
        }
        for (i, side) in p.sides.iter().enumerate() {
            match *side {
                Side::Triangle {
                    face,
                    x,
                    next,
                    prev,
                    opposite,
                } => {
                    let drop = fold_triangle(
                        &mut self.he,
                        &mut self.edge_halfedge,
                        &mut self.vertex_halfedge,
                        &self.rings,
                        (i, prev, opposite),
                    );
                    removed_edges[1 + i] = Some(drop);
                    self.gone.edges.push(drop);
                    self.gone.faces.push(face);
                    self.gone.halfedges.extend([x, next, prev]);
                }
                Side::Boundary { x, next, prev } => {
                    self.he[prev as usize].next = next;
                    self.he[next as usize].prev = prev;
                    self.gone.halfedges.push(x);
                }
            }
        }
        self.gone.vertices.push(p.b);
        let (kept_position, removed_position) = (rb[0].tip, ra[0].tip);
        self.position[p.a as usize] = p.position;
        // The merged vertex's halfedge: on the boundary its boundary one; inside, its own if
        // that stays, else the one to a wing, else one of b's.
        let best = if p.merged_boundary {
            ra.iter()
                .chain(rb.iter())
                .find(|s| !s.has_face() && !removes(s.id))
                .map(|s| s.id)
        } else {
            let own = self.vertex_halfedge[p.a as usize];
            let to_wing = |i: usize| {
                let ring = &self.rings[i];
                matches!(p.sides[i], Side::Triangle { .. }).then(|| ring[1 % ring.len()].id)
            };
            (!removes(own))
                .then_some(own)
                .or_else(|| to_wing(0))
                .or_else(|| to_wing(1))
                .or_else(|| {
                    rb.iter()
                        .find(|s| !removes(s.id) && !removes(s.links.twin))
                        .map(|s| s.id)
                })
        };
        let Some(best) = best else {
            unreachable!("the merged vertex keeps an edge after a planned collapse");
        };
        self.vertex_halfedge[p.a as usize] = best;
        // The merged vertex's edges: a's but the collapsed one, then b's but the collapsed
        // one and those to the wings (merged into a's).
        let wings = p.sides.map(|s| s.opposite());
        for s in ra.iter().filter(|s| s.links.to != p.b) {
            ring(s.links.edge, s.links.to, s.tip);
        }
        for s in rb
            .iter()
            .filter(|s| s.links.to != p.a && !wings.contains(&Some(s.links.to)))
        {
            ring(s.links.edge, s.links.to, s.tip);
        }
        Collapsed {
            kept: p.a,
            removed: p.b,
            position: p.position,
            kept_position,
            removed_position,
            wings,
            removed_edges,
        }
    }

    /// The surviving rows as the fit to the input reads them ([`FitElements`]), before they
    /// are written back: `members` and `edge_number` as [`FlatTriangles::write_back`] takes
    /// them, `face_halfedge` each face row's halfedge as read (a collapse never changes it),
    /// and a vertex row stays where `held(row, whether it is on the boundary)` says.
    pub fn fit_elements(
        &self,
        members: &MeshMembers,
        edge_number: &[u32],
        face_halfedge: &[u32],
        held: impl Fn(usize, bool) -> bool,
    ) -> FitElements {
        let mut index = vec![NONE; members.vertices.len()];
        let mut vertices = Vec::with_capacity(members.vertices.len() - self.gone.vertices.len());
        let vertex_alive = alive(members.vertices.len(), &self.gone.vertices);
        for (row, &v) in members.vertices.iter().enumerate() {
            if vertex_alive[row] {
                index[row] = vertices.len() as u32;
                let boundary = self.he[self.vertex_halfedge[row] as usize].face == NONE;
                vertices.push((v.0, self.position[row], held(row, boundary)));
            }
        }
        let tip = |h: u32| index[self.he[h as usize].to as usize];
        let face_alive = alive(members.faces.len(), &self.gone.faces);
        let triangles = (members.faces.iter().zip(face_halfedge).zip(face_alive))
            .filter(|&(_, alive)| alive)
            .map(|((f, &h), _)| {
                let l = self.he[h as usize];
                (f.0, [h, l.next, l.prev].map(tip))
            })
            .collect();
        let number_alive = alive(self.edge_halfedge.len(), &self.gone.edges);
        let edges = (edge_number.iter().zip(&members.edges))
            .filter(|&(&n, _)| number_alive[n as usize])
            .map(|(&n, e)| {
                let h = self.edge_halfedge[n as usize];
                (e.0, [h, self.he[h as usize].twin].map(tip))
            })
            .collect();
        FitElements {
            vertices,
            triangles,
            edges,
        }
    }

    /// Writes the surviving rows into their entities (`members`, row for row: the entities
    /// [`crate::mesh::tables::extract`] read, the edges numbered by `edge_number` as in
    /// [`FlatTriangles::new`]), despawns the removed ones ([`super::despawn_dead`]) and
    /// returns the vertex behind each row now (`None`: removed). Attributes stay as the
    /// entities hold them.
    pub fn write_back(
        self,
        world: &mut World,
        members: &MeshMembers,
        edge_number: &[u32],
    ) -> Vec<Option<VertexId>> {
        let vertex_alive = alive(members.vertices.len(), &self.gone.vertices);
        let halfedge_alive = alive(members.halfedges.len(), &self.gone.halfedges);
        let number_alive = alive(self.edge_halfedge.len(), &self.gone.edges);
        let edge_alive: Vec<bool> = edge_number
            .iter()
            .map(|&n| number_alive[n as usize])
            .collect();
        let face_alive = alive(members.faces.len(), &self.gone.faces);
        let mut edge_of_number = vec![EdgeId(Entity::PLACEHOLDER); self.edge_halfedge.len()];
        for (&n, &e) in edge_number.iter().zip(&members.edges) {
            edge_of_number[n as usize] = e;
        }
        let h = |row: u32| members.halfedges[row as usize];
        let mut q = world.query::<(&mut Vertex, &mut Position)>();
        for (row, &v) in members.vertices.iter().enumerate() {
            if vertex_alive[row]
                && let Ok((mut x, mut p)) = q.get_mut(world, v.0)
            {
                x.halfedge = h(self.vertex_halfedge[row]);
                p.0 = self.position[row];
            }
        }
        let mut q = world.query::<&mut Halfedge>();
        for (row, &e) in members.halfedges.iter().enumerate() {
            if halfedge_alive[row]
                && let Ok(mut x) = q.get_mut(world, e.0)
            {
                let l = self.he[row];
                *x = Halfedge {
                    twin: h(l.twin),
                    next: h(l.next),
                    prev: h(l.prev),
                    vertex: members.vertices[l.to as usize],
                    edge: edge_of_number[l.edge as usize],
                    face: (l.face != NONE).then(|| members.faces[l.face as usize]),
                };
            }
        }
        let mut q = world.query::<&mut Edge>();
        for (&n, &e) in edge_number.iter().zip(&members.edges) {
            if number_alive[n as usize]
                && let Ok(mut x) = q.get_mut(world, e.0)
            {
                x.halfedge = h(self.edge_halfedge[n as usize]);
            }
        }
        let mut despawner = Despawner::new(world);
        super::despawn_dead(&mut despawner, &members.vertices, |v| v.0, &vertex_alive);
        super::despawn_dead(&mut despawner, &members.halfedges, |h| h.0, &halfedge_alive);
        super::despawn_dead(&mut despawner, &members.edges, |e| e.0, &edge_alive);
        super::despawn_dead(&mut despawner, &members.faces, |f| f.0, &face_alive);
        members
            .vertices
            .iter()
            .zip(&vertex_alive)
            .map(|(&v, &alive)| alive.then_some(v))
            .collect()
    }
}

/// Whether each of `n` rows is alive, `gone` listing the dead ones.
fn alive(n: usize, gone: &[u32]) -> Vec<bool> {
    let mut alive = vec![true; n];
    for &row in gone {
        alive[row as usize] = false;
    }
    alive
}

/// Folds the triangle on side `side` (0: left of the halfedge from a) into one edge: its
/// two sides to the wing `opposite` become one, on the edge of the one from a, and the edge
/// of the one from b goes (returned). `prev` is the triangle's halfedge from the wing, which
/// goes; if the wing named it, the wing names the glued halfedge that leaves it instead.
fn fold_triangle(
    he: &mut [Links],
    edge_halfedge: &mut [u32],
    vertex_halfedge: &mut [u32],
    rings: &[Vec<Spoke>; 2],
    (side, prev, opposite): (usize, u32, u32),
) -> u32 {
    // Around the side's own end, the spoke after the edge runs back along `prev` to the wing;
    // around the other end, the spoke before the edge's twin is the triangle's `next`. Their
    // twins become each other's.
    let (own, other) = (&rings[side], &rings[1 - side]);
    let (to_wing, along_next) = (own[1 % own.len()], other[other.len() - 1]);
    let (on, op) = (along_next.links.twin, to_wing.id);
    let (from_a, from_b) = if side == 0 {
        (to_wing, along_next)
    } else {
        (along_next, to_wing)
    };
    let (keep, drop) = (from_a.links.edge, from_b.links.edge);
    let interior = if he[on as usize].face == NONE { op } else { on };
    for (x, twin) in [(on, op), (op, on)] {
        let links = &mut he[x as usize];
        links.twin = twin;
        links.edge = keep;
    }
    edge_halfedge[keep as usize] = interior;
    if vertex_halfedge[opposite as usize] == prev {
        vertex_halfedge[opposite as usize] = on;
    }
    drop
}

impl Plan {
    /// Whether no face around `centre` (at `centre_at`, spokes `ring`) that survives the
    /// collapse turns by more than the angle whose cosine is `limit`, nor vanishes.
    fn normals_hold(&self, centre: u32, centre_at: Vec3, ring: &[Spoke], limit: f32) -> bool {
        let moved = |v: u32, p: Vec3| {
            if v == self.a || v == self.b {
                self.position
            } else {
                p
            }
        };
        let vanishes = |f: u32| {
            self.sides
                .iter()
                .any(|s| matches!(*s, Side::Triangle { face, .. } if face == f))
        };
        ring.iter().enumerate().all(|(i, s)| {
            if !s.has_face() || vanishes(s.links.face) {
                return true;
            }
            let o = ring[(i + 1) % ring.len()];
            let corners = [
                (centre, centre_at),
                (s.links.to, s.tip),
                (o.links.to, o.tip),
            ];
            let n0 = newell_area_vector(&corners.map(|(_, p)| p));
            let n1 = newell_area_vector(&corners.map(|(v, p)| moved(v, p)));
            // As the collapse on entities compares them (one square root, no normalising), and
            // refusing on the same comparison, so that a NaN decides alike.
            let lengths = (f64::from(n0.length_squared()) * f64::from(n1.length_squared())).sqrt();
            let turns = f64::from(n0.dot(n1)) < f64::from(limit) * lengths;
            lengths > 0.0 && lengths.is_finite() && !turns
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::{MeshTables, VertexRow, extract};
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    /// Each vertex, triangle and edge of a mesh with its corners named by their entities.
    type ByEntity = (
        Vec<(Entity, Vec3, bool)>,
        Vec<[Entity; 4]>,
        Vec<[Entity; 3]>,
    );

    /// Each vertex, triangle and edge of `elements` with its corners named by their entities,
    /// in entity order: what the fit takes from them, whatever order they were read in.
    fn by_entity(elements: &FitElements) -> ByEntity {
        let entity = |v: u32| elements.vertices[v as usize].0;
        let mut vertices = elements.vertices.clone();
        vertices.sort_by_key(|v| v.0);
        let mut triangles: Vec<[Entity; 4]> = (elements.triangles.iter())
            .map(|&(f, [a, b, c])| [f, entity(a), entity(b), entity(c)])
            .collect();
        triangles.sort();
        let mut edges: Vec<[Entity; 3]> = (elements.edges.iter())
            .map(|&(e, [a, b])| [e, entity(a), entity(b)])
            .collect();
        edges.sort();
        (vertices, triangles, edges)
    }

    #[test]
    fn the_fits_elements_from_the_rows_are_those_of_the_mesh_written_back() {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &shapes::grid(8, 8), MeshInfo::default())
            .unwrap()
            .mesh;
        let MeshTables { tables: t, members } = extract(&world, mesh);
        let numbers: Vec<u32> = (0..t.edge_count() as u32).collect();
        let mut flat = FlatTriangles::new(&t, &numbers, numbers.len());
        let mut removed = std::collections::HashSet::new();
        let mut collapses = 0;
        for e in (0..numbers.len() as u32).step_by(5) {
            if removed.contains(&e) {
                continue;
            }
            let h = flat.edge_halfedge(e);
            let (a, b) = (
                flat.he[flat.he[h as usize].twin as usize].to,
                flat.he[h as usize].to,
            );
            let middle = (flat.position[a as usize] + flat.position[b as usize]) / 2.0;
            if let Some(plan) = flat.plan(h, middle, 0.0) {
                removed.extend(
                    flat.apply(plan, |_, _, _| {})
                        .removed_edges
                        .into_iter()
                        .flatten(),
                );
                collapses += 1;
            }
        }
        assert!(collapses >= 10, "{collapses} collapses");
        // Every third vertex row held, besides the boundary.
        let held = |row: usize, boundary: bool| boundary || row.is_multiple_of(3);
        let from_rows = flat.fit_elements(&members, &numbers, &t.face_halfedge, held);
        flat.write_back(&mut world, &members, &numbers);
        let after = extract(&world, mesh);
        let row_of: std::collections::HashMap<Entity, usize> = members
            .vertices
            .iter()
            .enumerate()
            .map(|(row, v)| (v.0, row))
            .collect();
        let held_after: Vec<bool> = (0..after.tables.vertex_count())
            .map(|v| {
                let row = row_of[&after.members.vertices[v].0];
                held(
                    row,
                    after.tables.is_boundary_vertex(VertexRow::new(v as u32)),
                )
            })
            .collect();
        let from_mesh = FitElements::of_tables(&after.tables, &after.members, &held_after);
        assert_eq!(from_rows.vertices.len(), after.tables.vertex_count());
        assert!(from_rows.vertices.iter().any(|v| v.2) && from_rows.vertices.iter().any(|v| !v.2));
        assert_eq!(by_entity(&from_rows), by_entity(&from_mesh));
    }
}
