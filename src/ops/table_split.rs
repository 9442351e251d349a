//! Vertex split on flat tables: the bulk path of progressive refinement.
//!
//! [`split_in_tables`] is [`crate::ops::local::vertex_split`] done on a [`Connectivity`]
//! instead of on entities: the same fan walk, the same new elements, the same links, with the
//! new rows appended (through the tables' typed setters and `push_*` calls). Refining
//! thousands of records this way and writing the tables back once (`write_links`, into rows
//! spawned in one batch meanwhile) costs a batch spawn per element instead of a spawn and a
//! dozen lookups each, which is what makes a full refine of the bunny fit a frame budget. The
//! entity version stays the one the editor's single splits use; the tests check that both give
//! the same mesh.

use bevy::math::Vec3;

use crate::mesh::tables::{Connectivity, EdgeRow, FaceRow, HalfedgeLinks, HalfedgeRow, VertexRow};
use crate::mesh::topology::MAX_LOOP;

/// One split to make, by table row: the vertex the collapse kept, its wings (`None` on a
/// boundary side), and the two positions to restore.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableSplit {
    /// The vertex the collapse kept.
    pub kept: VertexRow,
    /// The wing on the kept → removed side.
    pub left: Option<VertexRow>,
    /// The wing on the other side.
    pub right: Option<VertexRow>,
    /// Where the kept vertex goes back to.
    pub kept_position: Vec3,
    /// Where the vertex made again goes.
    pub removed_position: Vec3,
}

/// Why a split does not fit the tables (the mesh was edited outside the history).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitMismatch {
    /// This wing is no longer a neighbour of the kept vertex.
    NotNeighbour(VertexRow),
    /// The record undoes a boundary collapse, but the kept vertex is not on the boundary.
    NotOnBoundary,
    /// The record names no wing at all (no face to make again).
    NoWing,
}

/// Splits `s.kept` back into the kept vertex and a new one, appended as the last vertex row,
/// whose row is returned; new halfedges, edges and faces are appended too, nothing is
/// removed or renumbered. Counts: V + 1, E + 3 (+ 2 on the boundary), F + 2 (+ 1).
///
/// # Errors
/// A [`SplitMismatch`]; every check runs before the first write, so the tables are then
/// unchanged.
pub fn split_in_tables(t: &mut Connectivity, s: &TableSplit) -> Result<VertexRow, SplitMismatch> {
    let a = s.kept;
    if s.left.is_none() && s.right.is_none() {
        return Err(SplitMismatch::NoWing);
    }
    let towards = |w: Option<VertexRow>| -> Result<Option<HalfedgeRow>, SplitMismatch> {
        w.map(|w| t.find_halfedge(a, w).ok_or(SplitMismatch::NotNeighbour(w)))
            .transpose()
    };
    let (hc, hd) = (towards(s.left)?, towards(s.right)?);
    let boundary_out = t.vertex_halfedge(a);
    if (hc.is_none() || hd.is_none()) && !t.is_boundary(boundary_out) {
        return Err(SplitMismatch::NotOnBoundary);
    }
    // The removed vertex's fan, counter-clockwise from the right wing (or just past the
    // boundary) to the left wing (or the boundary halfedge itself).
    let start = hd.unwrap_or_else(|| t.ccw_rotated(boundary_out));
    let stop = hc.unwrap_or_else(|| t.ccw_rotated(boundary_out));
    let pin = t.prev(boundary_out);
    let twin_edge = |h: Option<HalfedgeRow>| h.map(|h| (t.twin(h), t.edge(h)));
    let (left_old, right_old) = (twin_edge(hc), twin_edge(hd));

    // From here on nothing can fail. The fan goes to the new vertex b: every halfedge coming
    // into the fan's outgoing ones, and the one from the left wing.
    let b = t.push_vertex(s.removed_position);
    let mut h = start;
    let mut steps = 0;
    while h != stop && steps <= MAX_LOOP {
        if Some(h) != hd {
            let into = t.twin(h);
            t.set_to_vertex(into, b);
        }
        h = t.ccw_rotated(h);
        steps += 1;
    }
    if let Some((tc, _)) = left_old {
        t.set_to_vertex(tc, b);
    }
    let (ab, ba) = next_two_halfedges(t);
    let eab = t.push_edge(if hc.is_some() { ab } else { ba });
    push_halfedge(t, [ba, ab, ab], b, eab, None);
    push_halfedge(t, [ab, ab, ab], a, eab, None);

    // Left: the triangle a b c (gbc: b → c, gca: c → a), or the boundary.
    match (s.left, hc, left_old) {
        (Some(c), Some(hc), Some((tc, edge_c))) => {
            let (gbc, gca) = next_two_halfedges(t);
            let ebc = t.push_edge(gbc);
            let f = t.push_face(ab);
            push_halfedge(t, [tc, gca, ab], c, ebc, Some(f));
            push_halfedge(t, [hc, ab, gbc], a, edge_c, Some(f));
            set_links(t, ab, gbc, gca, f);
            t.set_twin(tc, gbc);
            t.set_edge(tc, ebc);
            t.set_twin(hc, gca);
            t.set_edge_halfedge(edge_c, hc);
        }
        _ => {
            t.link(pin, ab);
            t.link(ab, boundary_out);
        }
    }
    // Right: the triangle b a d (gad: a → d, gdb: d → b), or the boundary.
    match (s.right, hd, right_old) {
        (Some(d), Some(hd), Some((td, edge_d))) => {
            let (gad, gdb) = next_two_halfedges(t);
            let ebd = t.push_edge(gdb);
            let g = t.push_face(ba);
            push_halfedge(t, [td, gdb, ba], d, edge_d, Some(g));
            push_halfedge(t, [hd, ba, gad], b, ebd, Some(g));
            set_links(t, ba, gad, gdb, g);
            t.set_twin(td, gad);
            t.set_twin(hd, gdb);
            t.set_edge(hd, ebd);
            t.set_edge_halfedge(edge_d, td);
        }
        _ => {
            t.link(pin, ba);
            t.link(ba, boundary_out);
        }
    }
    t.set_vertex_halfedge(b, ba);
    t.set_vertex_halfedge(a, ab);
    t.set_position(a, s.kept_position);
    // Each vertex points at its boundary halfedge if it has one.
    for v in [a, b] {
        let boundary = t.vertex_outgoing(v).find(|&h| t.is_boundary(h));
        if let Some(h) = boundary {
            t.set_vertex_halfedge(v, h);
        }
    }
    Ok(b)
}

/// The rows the next two halfedges pushed get.
fn next_two_halfedges(t: &Connectivity) -> (HalfedgeRow, HalfedgeRow) {
    let first = t.next_halfedge_row();
    (first, HalfedgeRow::new(first.get() + 1))
}

/// Appends a halfedge with its `[twin, next, prev]`, tip vertex, edge and face.
fn push_halfedge(
    t: &mut Connectivity,
    [twin, next, prev]: [HalfedgeRow; 3],
    to_vertex: VertexRow,
    edge: EdgeRow,
    face: Option<FaceRow>,
) {
    t.push_halfedge(HalfedgeLinks {
        twin,
        next,
        prev,
        to_vertex,
        edge,
        face,
    });
}

/// Puts `h` into the triangle `h → next → prev` of face `f` (only `h`'s own entries).
fn set_links(
    t: &mut Connectivity,
    h: HalfedgeRow,
    next: HalfedgeRow,
    prev: HalfedgeRow,
    f: FaceRow,
) {
    t.set_next(h, next);
    t.set_prev(h, prev);
    t.set_face(h, Some(f));
}
