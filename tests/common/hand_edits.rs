//! An edge flip written by hand with `RawEdit`, shared by `tests/raw_edit.rs` and
//! `benches/raw_edit.rs` (each includes this file by path).

use pappus::mesh::{EdgeId, MeshRef, RawEdit, RawEditError};

/// An edge flip written as a student writes it: the two triangles' six halfedges rewired so
/// that the edge joins the two opposite corners.
pub fn flip_by_hand(edit: &mut RawEdit<'_>, e: EdgeId) -> Result<(), RawEditError> {
    let m = MeshRef::new(edit.world());
    let h = m.edge_halfedge(e);
    let t = m.twin(h);
    let (h1, t1) = (m.next(h), m.next(t));
    let (h2, t2) = (m.next(h1), m.next(t1));
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    let (c, d) = (m.to_vertex(h1), m.to_vertex(t1));
    let (f, g) = (m.face(h).expect("interior"), m.face(t).expect("interior"));
    let (a_out, b_out) = (m.vertex_halfedge(a), m.vertex_halfedge(b));
    edit.set_to_vertex(h, c)?;
    edit.set_to_vertex(t, d)?;
    for (x, y) in [(h, h2), (h2, t1), (t1, h), (t, t2), (t2, h1), (h1, t)] {
        edit.set_next(x, y)?;
    }
    edit.set_face(t1, Some(f))?;
    edit.set_face(h1, Some(g))?;
    edit.set_face_halfedge(f, h)?;
    edit.set_face_halfedge(g, t)?;
    if a_out == h {
        edit.set_vertex_halfedge(a, t1)?;
    }
    if b_out == t {
        edit.set_vertex_halfedge(b, h1)?;
    }
    Ok(())
}
