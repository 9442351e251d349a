//! Vertex split: the exact inverse of an edge collapse (Hoppe, "Progressive Meshes", 1996).
//!
//! ```text
//!         c                     c
//!         |                    / \
//!         |                   /   \
//!         a'       →         a ---- b        the fan of a' between the wings d and c
//!         |                   \   /          goes to the new vertex b
//!         |                    \ /
//!         d                     d
//! ```
//!
//! Rotating counter-clockwise around the merged vertex, the outgoing halfedges from the wing
//! `d` (the `right` one) up to the wing `c` (`left`) were the removed vertex's; they go back to
//! a new vertex `b`, the edge `a b` and the triangles `a b c` and `b a d` are made again, and
//! both positions are restored. Where a wing is missing the collapsed edge was on the boundary
//! and the boundary loop gets its side back. Counts: V + 1, E + 3 (+ 2 on the boundary),
//! F + 2 (+ 1). The mesh equals the one before the collapse up to relabeling, positions bitwise.
//!
//! Refusals: a record that is not invertible (a polygon side), a stale kept vertex or wing, a
//! wing that is no longer a neighbour, a boundary record on a vertex that is not on the
//! boundary.

use bevy::prelude::World;

use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::topology::MeshRef;

use super::{CollapseRecord, Refusal, he, link, spawn_at};

/// Undoes the collapse described by `record` and returns the vertex it makes again (a new
/// entity: the removed one's id stays stale).
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn vertex_split(world: &mut World, record: &CollapseRecord) -> Result<VertexId, Refusal> {
    let plan = plan_split(world, record)?;
    let new = NewElements::allocate(world, &plan);
    let member = InMesh(plan.mesh);
    // The fan goes back to b: every halfedge coming into the fan's outgoing ones.
    for &x in &plan.arc {
        if Some(x) != plan.hd {
            let t = MeshRef::new(world).twin(x);
            he(world, t).vertex = new.b;
        }
    }
    if let Some(tc) = plan.tc {
        he(world, tc).vertex = new.b;
    }
    spawn_middle_edge(world, &new, plan.a, member);
    match (new.left, plan.hc, plan.tc, plan.edge_c, record.left) {
        (Some(made), Some(hc), Some(tc), Some(edge_c), Some(c)) => {
            let old = OldWing {
                inner: hc,
                outer: tc,
                edge: edge_c,
                far: c,
            };
            make_left_triangle(world, &new, made, old, plan.a, member);
        }
        _ => {
            // ab lies on the boundary, between the incoming boundary halfedge and the fan's.
            link(world, plan.pin, new.ab);
            link(world, new.ab, plan.boundary_out);
        }
    }
    match (new.right, plan.hd, plan.td, plan.edge_d, record.right) {
        (Some(made), Some(hd), Some(td), Some(edge_d), Some(d)) => {
            let old = OldWing {
                inner: hd,
                outer: td,
                edge: edge_d,
                far: d,
            };
            make_right_triangle(world, &new, made, old, member);
        }
        _ => {
            link(world, plan.pin, new.ba);
            link(world, new.ba, plan.boundary_out);
        }
    }
    restore_vertices(world, record, &new, member);
    Ok(new.b)
}

/// What the split reads before it changes anything: the kept vertex `a`, its halfedges towards
/// the wings (`hc` to the left wing `c`, `hd` to the right wing `d`; `None` where the collapsed
/// edge was on the boundary) and their twins and edges, the removed vertex's fan (`arc`), and
/// `a`'s boundary halfedge with the one before it (`pin`).
struct SplitPlan {
    mesh: crate::mesh::MeshId,
    a: VertexId,
    hc: Option<HalfedgeId>,
    hd: Option<HalfedgeId>,
    tc: Option<HalfedgeId>,
    td: Option<HalfedgeId>,
    edge_c: Option<EdgeId>,
    edge_d: Option<EdgeId>,
    arc: Vec<HalfedgeId>,
    boundary_out: HalfedgeId,
    pin: HalfedgeId,
}

/// Checks the record against the mesh and reads what the split needs.
fn plan_split(world: &World, record: &CollapseRecord) -> Result<SplitPlan, Refusal> {
    let m = MeshRef::new(world);
    let a = record.kept;
    if !record.invertible {
        return Err(Refusal::NotInvertible);
    }
    m.try_vertex(a)
        .ok_or(Refusal::Stale(ElementId::Vertex(a)))?;
    let mesh = world
        .get::<InMesh>(a.0)
        .ok_or(Refusal::Stale(ElementId::Vertex(a)))?
        .0;
    let towards = |w: Option<VertexId>| -> Result<Option<HalfedgeId>, Refusal> {
        match w {
            None => Ok(None),
            Some(w) => {
                m.try_vertex(w)
                    .ok_or(Refusal::Stale(ElementId::Vertex(w)))?;
                m.find_halfedge(a, w).map(Some).ok_or_else(|| {
                    Refusal::HistoryMismatch(format!("{w} is no longer a neighbour of {a}"))
                })
            }
        }
    };
    let (hc, hd) = (towards(record.left)?, towards(record.right)?);
    let boundary_out = m.vertex_halfedge(a);
    if (hc.is_none() || hd.is_none()) && !m.is_boundary(boundary_out) {
        return Err(Refusal::HistoryMismatch(format!(
            "{a} is not on the boundary, but the collapse it undoes was"
        )));
    }
    // The removed vertex's fan: from the right wing (or just past the boundary) round to the
    // left wing (or the boundary halfedge itself), counter-clockwise.
    let start = hd.unwrap_or_else(|| m.ccw_rotated(boundary_out));
    let stop = hc.unwrap_or_else(|| m.ccw_rotated(boundary_out));
    let mut arc = Vec::new();
    let mut h = start;
    // Empty when the removed vertex had no face but the ones the collapse removed (a corner).
    while h != stop && arc.len() <= crate::mesh::topology::MAX_LOOP {
        arc.push(h);
        h = m.ccw_rotated(h);
    }
    Ok(SplitPlan {
        mesh,
        a,
        hc,
        hd,
        tc: hc.map(|h| m.twin(h)),
        td: hd.map(|h| m.twin(h)),
        edge_c: hc.map(|h| m.edge(h)),
        edge_d: hd.map(|h| m.edge(h)),
        arc,
        boundary_out,
        pin: m.prev(boundary_out),
    })
}

/// A wing's triangle made again: its two new halfedges, its new edge and the face.
type WingTriangle = (HalfedgeId, HalfedgeId, EdgeId, FaceId);

/// A wing as the collapse left it: `a`'s halfedge towards the wing vertex `far`, its twin and
/// their edge.
#[derive(Clone, Copy)]
struct OldWing {
    inner: HalfedgeId,
    outer: HalfedgeId,
    edge: EdgeId,
    far: VertexId,
}

/// The ids the split makes: the vertex `b`, the edge between `a` and `b` (its halfedges `ab`:
/// a → b and `ba`: b → a) and a triangle for each wing there is.
struct NewElements {
    b: VertexId,
    ab: HalfedgeId,
    ba: HalfedgeId,
    eab: EdgeId,
    left: Option<WingTriangle>,
    right: Option<WingTriangle>,
}

impl NewElements {
    fn allocate(world: &World, plan: &SplitPlan) -> Self {
        let alloc = world.entity_allocator();
        let triangle = || {
            (
                HalfedgeId(alloc.alloc()),
                HalfedgeId(alloc.alloc()),
                EdgeId(alloc.alloc()),
                FaceId(alloc.alloc()),
            )
        };
        Self {
            b: VertexId(alloc.alloc()),
            ab: HalfedgeId(alloc.alloc()),
            ba: HalfedgeId(alloc.alloc()),
            eab: EdgeId(alloc.alloc()),
            left: plan.hc.map(|_| triangle()),
            right: plan.hd.map(|_| triangle()),
        }
    }
}

/// Spawns the halfedges and the edge between `a` and the new vertex (their faces and links are
/// set by the wings, or the boundary).
fn spawn_middle_edge(world: &mut World, new: &NewElements, a: VertexId, member: InMesh) {
    let placeholder = Halfedge {
        twin: new.ba,
        next: new.ab,
        prev: new.ab,
        vertex: new.b,
        edge: new.eab,
        face: None,
    };
    let into_b = Halfedge {
        twin: new.ba,
        vertex: new.b,
        ..placeholder
    };
    let into_a = Halfedge {
        twin: new.ab,
        vertex: a,
        ..placeholder
    };
    spawn_at(world, new.ab.0, (into_b, member));
    spawn_at(world, new.ba.0, (into_a, member));
    let interior = if new.left.is_some() { new.ab } else { new.ba };
    spawn_at(world, new.eab.0, (Edge { halfedge: interior }, member));
}

/// The triangle a b c (`gbc`: b → c, `gca`: c → a) on the left wing.
fn make_left_triangle(
    world: &mut World,
    new: &NewElements,
    (gbc, gca, ebc, f): WingTriangle,
    old: OldWing,
    a: VertexId,
    member: InMesh,
) {
    let b_to_c = Halfedge {
        twin: old.outer,
        next: gca,
        prev: new.ab,
        vertex: old.far,
        edge: ebc,
        face: Some(f),
    };
    let c_to_a = Halfedge {
        twin: old.inner,
        next: new.ab,
        prev: gbc,
        vertex: a,
        edge: old.edge,
        face: Some(f),
    };
    spawn_at(world, gbc.0, (b_to_c, member));
    spawn_at(world, gca.0, (c_to_a, member));
    spawn_at(world, ebc.0, (Edge { halfedge: gbc }, member));
    spawn_at(world, f.0, (Face { halfedge: new.ab }, member));
    {
        let mut x = he(world, new.ab);
        x.next = gbc;
        x.prev = gca;
        x.face = Some(f);
    }
    {
        let mut x = he(world, old.outer);
        x.twin = gbc;
        x.edge = ebc;
    }
    he(world, old.inner).twin = gca;
    if let Some(mut edge) = world.get_mut::<Edge>(old.edge.0) {
        edge.halfedge = old.inner;
    }
}

/// The triangle b a d (`gad`: a → d, `gdb`: d → b) on the right wing.
fn make_right_triangle(
    world: &mut World,
    new: &NewElements,
    (gad, gdb, ebd, g): WingTriangle,
    old: OldWing,
    member: InMesh,
) {
    let a_to_d = Halfedge {
        twin: old.outer,
        next: gdb,
        prev: new.ba,
        vertex: old.far,
        edge: old.edge,
        face: Some(g),
    };
    let d_to_b = Halfedge {
        twin: old.inner,
        next: new.ba,
        prev: gad,
        vertex: new.b,
        edge: ebd,
        face: Some(g),
    };
    spawn_at(world, gad.0, (a_to_d, member));
    spawn_at(world, gdb.0, (d_to_b, member));
    spawn_at(world, ebd.0, (Edge { halfedge: gdb }, member));
    spawn_at(world, g.0, (Face { halfedge: new.ba }, member));
    {
        let mut x = he(world, new.ba);
        x.next = gad;
        x.prev = gdb;
        x.face = Some(g);
    }
    he(world, old.outer).twin = gad;
    {
        let mut x = he(world, old.inner);
        x.twin = gdb;
        x.edge = ebd;
    }
    if let Some(mut edge) = world.get_mut::<Edge>(old.edge.0) {
        edge.halfedge = old.outer;
    }
}

/// Spawns `b` at the removed position, puts `a` back where it was, and points each at its
/// boundary halfedge if it has one (either may be on the boundary).
fn restore_vertices(world: &mut World, record: &CollapseRecord, new: &NewElements, member: InMesh) {
    let (a, b) = (record.kept, new.b);
    let back = (
        Vertex { halfedge: new.ba },
        Position(record.removed_position),
        member,
    );
    spawn_at(world, b.0, back);
    if let Some(mut vertex) = world.get_mut::<Vertex>(a.0) {
        vertex.halfedge = new.ab;
    }
    if let Some(mut position) = world.get_mut::<Position>(a.0) {
        position.0 = record.kept_position;
    }
    for v in [a, b] {
        let m = MeshRef::new(world);
        let start = m.vertex_halfedge(v);
        if let Some(out) = m.vertex_outgoing_from(start).find(|&h| m.is_boundary(h)) {
            world.get_mut::<Vertex>(v.0).expect("just made").halfedge = out;
        }
    }
}
