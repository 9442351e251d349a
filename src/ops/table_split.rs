//! Vertex split on flat tables: the bulk path of progressive refinement.
//!
//! [`split_in_tables`] is [`crate::ops::local::vertex_split`] done on a [`Connectivity`]
//! instead of on entities: the same fan walk, the same new elements, the same links, with the
//! new rows appended. Refining thousands of records this way and writing the tables back once
//! (`write_links`, into rows spawned in one batch meanwhile) costs a batch spawn per element
//! instead of a spawn and a dozen lookups each, which is what makes a full refine of the bunny
//! fit a frame budget. The entity version stays the one the editor's single splits use; the tests check
//! that both give the same mesh.

use bevy::math::Vec3;

use crate::mesh::connectivity::Connectivity;
use crate::mesh::repair::NONE;
use crate::mesh::topology::MAX_LOOP;

/// One split to make, by table row: the vertex the collapse kept, its wings (`None` on a
/// boundary side), and the two positions to restore.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableSplit {
    /// The vertex the collapse kept.
    pub kept: u32,
    /// The wing on the kept → removed side.
    pub left: Option<u32>,
    /// The wing on the other side.
    pub right: Option<u32>,
    /// Where the kept vertex goes back to.
    pub kept_position: Vec3,
    /// Where the vertex made again goes.
    pub removed_position: Vec3,
}

/// Why a split does not fit the tables (the mesh was edited outside the history).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitMismatch {
    /// This wing is no longer a neighbour of the kept vertex.
    NotNeighbour(u32),
    /// The record undoes a boundary collapse, but the kept vertex is not on the boundary.
    NotOnBoundary,
    /// The record names no wing at all (no face to make again).
    NoWing,
}

/// Splits `s.kept` back into the kept vertex and a new one, appended as the last vertex row,
/// whose index is returned; new halfedges, edges and faces are appended too, nothing is
/// removed or renumbered. Counts: V + 1, E + 3 (+ 2 on the boundary), F + 2 (+ 1).
///
/// # Errors
/// A [`SplitMismatch`]; every check runs before the first write, so the tables are then
/// unchanged.
pub fn split_in_tables(t: &mut Connectivity, s: &TableSplit) -> Result<u32, SplitMismatch> {
    let a = s.kept;
    if s.left.is_none() && s.right.is_none() {
        return Err(SplitMismatch::NoWing);
    }
    let towards = |w: Option<u32>| -> Result<Option<u32>, SplitMismatch> {
        w.map(|w| find_halfedge(t, a, w).ok_or(SplitMismatch::NotNeighbour(w)))
            .transpose()
    };
    let (hc, hd) = (towards(s.left)?, towards(s.right)?);
    let boundary_out = t.vertex_halfedge[a as usize];
    if (hc.is_none() || hd.is_none()) && t.face[boundary_out as usize] != NONE {
        return Err(SplitMismatch::NotOnBoundary);
    }
    // The removed vertex's fan, counter-clockwise from the right wing (or just past the
    // boundary) to the left wing (or the boundary halfedge itself).
    let start = hd.unwrap_or_else(|| t.ccw_rotated(boundary_out));
    let stop = hc.unwrap_or_else(|| t.ccw_rotated(boundary_out));
    let pin = t.prev[boundary_out as usize];
    let twin_edge = |h: Option<u32>| h.map(|h| (t.twin[h as usize], t.edge[h as usize]));
    let (left_old, right_old) = (twin_edge(hc), twin_edge(hd));

    // From here on nothing can fail. The fan goes to the new vertex b: every halfedge coming
    // into the fan's outgoing ones, and the one from the left wing.
    let b = push_vertex(t, s.removed_position);
    let mut h = start;
    let mut steps = 0;
    while h != stop && steps <= MAX_LOOP {
        if Some(h) != hd {
            let into = t.twin[h as usize];
            t.to_vertex[into as usize] = b;
        }
        h = t.ccw_rotated(h);
        steps += 1;
    }
    if let Some((tc, _)) = left_old {
        t.to_vertex[tc as usize] = b;
    }
    let (ab, ba) = (halfedge_row(t), halfedge_row(t) + 1);
    let eab = push_edge(t, if hc.is_some() { ab } else { ba });
    push_halfedge(t, [ba, ab, ab, b, eab, NONE]);
    push_halfedge(t, [ab, ab, ab, a, eab, NONE]);

    // Left: the triangle a b c (gbc: b → c, gca: c → a), or the boundary.
    match (s.left, hc, left_old) {
        (Some(c), Some(hc), Some((tc, edge_c))) => {
            let (gbc, gca) = (halfedge_row(t), halfedge_row(t) + 1);
            let ebc = push_edge(t, gbc);
            let f = push_face(t, ab);
            push_halfedge(t, [tc, gca, ab, c, ebc, f]);
            push_halfedge(t, [hc, ab, gbc, a, edge_c, f]);
            set_links(t, ab, gbc, gca, f);
            t.twin[tc as usize] = gbc;
            t.edge[tc as usize] = ebc;
            t.twin[hc as usize] = gca;
            t.edge_halfedge[edge_c as usize] = hc;
        }
        _ => {
            link(t, pin, ab);
            link(t, ab, boundary_out);
        }
    }
    // Right: the triangle b a d (gad: a → d, gdb: d → b), or the boundary.
    match (s.right, hd, right_old) {
        (Some(d), Some(hd), Some((td, edge_d))) => {
            let (gad, gdb) = (halfedge_row(t), halfedge_row(t) + 1);
            let ebd = push_edge(t, gdb);
            let g = push_face(t, ba);
            push_halfedge(t, [td, gdb, ba, d, edge_d, g]);
            push_halfedge(t, [hd, ba, gad, b, ebd, g]);
            set_links(t, ba, gad, gdb, g);
            t.twin[td as usize] = gad;
            t.twin[hd as usize] = gdb;
            t.edge[hd as usize] = ebd;
            t.edge_halfedge[edge_d as usize] = td;
        }
        _ => {
            link(t, pin, ba);
            link(t, ba, boundary_out);
        }
    }
    t.vertex_halfedge[b as usize] = ba;
    t.vertex_halfedge[a as usize] = ab;
    t.positions[a as usize] = s.kept_position;
    // Each vertex points at its boundary halfedge if it has one.
    for v in [a, b] {
        let boundary = t.outgoing(v).find(|&h| t.face[h as usize] == NONE);
        if let Some(h) = boundary {
            t.vertex_halfedge[v as usize] = h;
        }
    }
    Ok(b)
}

/// The halfedge from `a` to `w`, if they are neighbours.
fn find_halfedge(t: &Connectivity, a: u32, w: u32) -> Option<u32> {
    t.outgoing(a).find(|&h| t.to_vertex[h as usize] == w)
}

/// The index the next halfedge row gets.
fn halfedge_row(t: &Connectivity) -> u32 {
    t.twin.len() as u32
}

fn push_vertex(t: &mut Connectivity, position: Vec3) -> u32 {
    let v = t.positions.len() as u32;
    t.positions.push(position);
    t.vertex_halfedge.push(NONE);
    v
}

fn push_edge(t: &mut Connectivity, halfedge: u32) -> u32 {
    let e = t.edge_halfedge.len() as u32;
    t.edge_halfedge.push(halfedge);
    e
}

fn push_face(t: &mut Connectivity, halfedge: u32) -> u32 {
    let f = t.face_halfedge.len() as u32;
    t.face_halfedge.push(halfedge);
    f
}

/// Appends a halfedge: `[twin, next, prev, tip vertex, edge, face]`.
fn push_halfedge(t: &mut Connectivity, [twin, next, prev, vertex, edge, face]: [u32; 6]) {
    t.twin.push(twin);
    t.next.push(next);
    t.prev.push(prev);
    t.to_vertex.push(vertex);
    t.edge.push(edge);
    t.face.push(face);
}

/// Puts `h` into the triangle `h → next → prev` of face `f`.
fn set_links(t: &mut Connectivity, h: u32, next: u32, prev: u32, f: u32) {
    t.next[h as usize] = next;
    t.prev[h as usize] = prev;
    t.face[h as usize] = f;
}

fn link(t: &mut Connectivity, from: u32, to: u32) {
    t.next[from as usize] = to;
    t.prev[to as usize] = from;
}
