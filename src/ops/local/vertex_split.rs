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
    let pin = m.prev(boundary_out);
    let tc = hc.map(|h| m.twin(h));
    let td = hd.map(|h| m.twin(h));
    let edge_c = hc.map(|h| m.edge(h));
    let edge_d = hd.map(|h| m.edge(h));

    let alloc = world.entity_allocator();
    let b = VertexId(alloc.alloc());
    let (ab, ba, eab) = (
        HalfedgeId(alloc.alloc()),
        HalfedgeId(alloc.alloc()),
        EdgeId(alloc.alloc()),
    );
    let left_new = hc.map(|_| {
        (
            HalfedgeId(alloc.alloc()),
            HalfedgeId(alloc.alloc()),
            EdgeId(alloc.alloc()),
            FaceId(alloc.alloc()),
        )
    });
    let right_new = hd.map(|_| {
        (
            HalfedgeId(alloc.alloc()),
            HalfedgeId(alloc.alloc()),
            EdgeId(alloc.alloc()),
            FaceId(alloc.alloc()),
        )
    });
    let member = InMesh(mesh);

    // The fan goes back to b: every halfedge coming into the fan's outgoing ones.
    for &x in &arc {
        if Some(x) != hd {
            let t = MeshRef::new(world).twin(x);
            he(world, t).vertex = b;
        }
    }
    if let Some(tc) = tc {
        he(world, tc).vertex = b;
    }

    let placeholder = Halfedge {
        twin: ba,
        next: ab,
        prev: ab,
        vertex: b,
        edge: eab,
        face: None,
    };
    spawn_at(
        world,
        ab.0,
        (
            Halfedge {
                twin: ba,
                vertex: b,
                ..placeholder
            },
            member,
        ),
    );
    spawn_at(
        world,
        ba.0,
        (
            Halfedge {
                twin: ab,
                vertex: a,
                ..placeholder
            },
            member,
        ),
    );
    let interior = if left_new.is_some() { ab } else { ba };
    spawn_at(world, eab.0, (Edge { halfedge: interior }, member));

    // Left: the triangle a b c (gbc: b → c, gca: c → a), or the boundary.
    match (left_new, hc, tc, edge_c) {
        (Some((gbc, gca, ebc, f)), Some(hc), Some(tc), Some(edge_c)) => {
            let c = record.left.expect("left wing");
            spawn_at(
                world,
                gbc.0,
                (
                    Halfedge {
                        twin: tc,
                        next: gca,
                        prev: ab,
                        vertex: c,
                        edge: ebc,
                        face: Some(f),
                    },
                    member,
                ),
            );
            spawn_at(
                world,
                gca.0,
                (
                    Halfedge {
                        twin: hc,
                        next: ab,
                        prev: gbc,
                        vertex: a,
                        edge: edge_c,
                        face: Some(f),
                    },
                    member,
                ),
            );
            spawn_at(world, ebc.0, (Edge { halfedge: gbc }, member));
            spawn_at(world, f.0, (Face { halfedge: ab }, member));
            {
                let mut x = he(world, ab);
                x.next = gbc;
                x.prev = gca;
                x.face = Some(f);
            }
            {
                let mut x = he(world, tc);
                x.twin = gbc;
                x.edge = ebc;
            }
            he(world, hc).twin = gca;
            world.get_mut::<Edge>(edge_c.0).expect("planned").halfedge = hc;
        }
        _ => {
            // ab lies on the boundary, between the incoming boundary halfedge and the fan's.
            link(world, pin, ab);
            link(world, ab, boundary_out);
        }
    }
    // Right: the triangle b a d (gad: a → d, gdb: d → b), or the boundary.
    match (right_new, hd, td, edge_d) {
        (Some((gad, gdb, ebd, g)), Some(hd), Some(td), Some(edge_d)) => {
            let d = record.right.expect("right wing");
            spawn_at(
                world,
                gad.0,
                (
                    Halfedge {
                        twin: td,
                        next: gdb,
                        prev: ba,
                        vertex: d,
                        edge: edge_d,
                        face: Some(g),
                    },
                    member,
                ),
            );
            spawn_at(
                world,
                gdb.0,
                (
                    Halfedge {
                        twin: hd,
                        next: ba,
                        prev: gad,
                        vertex: b,
                        edge: ebd,
                        face: Some(g),
                    },
                    member,
                ),
            );
            spawn_at(world, ebd.0, (Edge { halfedge: gdb }, member));
            spawn_at(world, g.0, (Face { halfedge: ba }, member));
            {
                let mut x = he(world, ba);
                x.next = gad;
                x.prev = gdb;
                x.face = Some(g);
            }
            he(world, td).twin = gad;
            {
                let mut x = he(world, hd);
                x.twin = gdb;
                x.edge = ebd;
            }
            world.get_mut::<Edge>(edge_d.0).expect("planned").halfedge = td;
        }
        _ => {
            link(world, pin, ba);
            link(world, ba, boundary_out);
        }
    }

    spawn_at(
        world,
        b.0,
        (
            Vertex { halfedge: ba },
            Position(record.removed_position),
            member,
        ),
    );
    world.get_mut::<Vertex>(a.0).expect("checked").halfedge = ab;
    world.get_mut::<Position>(a.0).expect("checked").0 = record.kept_position;
    // Each vertex points at its boundary halfedge if it has one (either may be on the boundary).
    for v in [a, b] {
        let m = MeshRef::new(world);
        let start = m.vertex_halfedge(v);
        if let Some(out) = m.vertex_outgoing_from(start).find(|&h| m.is_boundary(h)) {
            world.get_mut::<Vertex>(v.0).expect("just made").halfedge = out;
        }
    }
    Ok(b)
}
