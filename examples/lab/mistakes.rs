//! Two flips with a mistake in them, as a student might write them, to see what the lab
//! reports: [`flip_the_other_way`] turns the edge clockwise (a valid mesh, but not the one `flip`
//! makes: the two faces trade places), and [`flip_forgetting_a_face`] leaves one halfedge on its
//! old face (an invalid mesh, refused with the mesh as it was).

use bevy::prelude::World;
use pappus::mesh::{EdgeId, MeshId, MeshRef, RawEdit};
use pappus::ops::Refusal;
use pappus::ops::declaration::{Declaration, Names, Section};

use super::student::{OnEdge, Wings, check_flip, rewire_flip};

/// The flip that turns the edge the other way, on key Alt+4.
pub const FLIP_THE_OTHER_WAY: Declaration = Declaration::new("lab-flip-other-way")
    .titled("Lab flip, the other way")
    .described("a student's flip with a mistake: the edge turns clockwise")
    .on_key("Alt+4")
    .naming(Names::Edge)
    .in_section(Section::Local)
    .checked_against("flip");

/// The flip that forgets a line, on key Alt+5.
pub const FLIP_FORGETTING_A_FACE: Declaration = Declaration::new("lab-flip-forgetting")
    .titled("Lab flip, a line forgotten")
    .described("a student's flip with a mistake: one halfedge left on its old face")
    .on_key("Alt+5")
    .naming(Names::Edge)
    .in_section(Section::Local)
    .checked_against("flip");

/// The two mistakes, as the example registers them.
pub const MISTAKES: [OnEdge; 2] = [
    OnEdge {
        declaration: &FLIP_THE_OTHER_WAY,
        run: |world, mesh, e| flip_the_other_way(world, mesh, e).map(|()| e.into()),
        says: "turned",
    },
    OnEdge {
        declaration: &FLIP_FORGETTING_A_FACE,
        run: |world, mesh, e| flip_forgetting_a_face(world, mesh, e).map(|()| e.into()),
        says: "turned",
    },
];

/// Turns `e` clockwise: `h` becomes c → d in `f` (with `tp` and `hn`), `t` becomes d → c in
/// `g` (with `hp` and `tn`). The mesh is valid, with the same edge; but `f` and `g` hold each
/// other's triangles.
///
/// # Refusals
/// As the student's flip.
pub fn flip_the_other_way(world: &mut World, mesh: MeshId, e: EdgeId) -> Result<(), Refusal> {
    let w: Wings = check_flip(&MeshRef::new(world), e)?;
    let mut edit = RawEdit::new(world, mesh);
    edit.set_to_vertex(w.h, w.d)?;
    edit.set_to_vertex(w.t, w.c)?;
    for (x, next) in [(w.h, w.tp), (w.tp, w.hn), (w.hn, w.h)] {
        edit.set_next(x, next)?;
    }
    for (x, next) in [(w.t, w.hp), (w.hp, w.tn), (w.tn, w.t)] {
        edit.set_next(x, next)?;
    }
    edit.set_face(w.tp, Some(w.f))?;
    edit.set_face(w.hp, Some(w.g))?;
    edit.set_face_halfedge(w.f, w.h)?;
    edit.set_face_halfedge(w.g, w.t)?;
    if w.a_out == w.h {
        edit.set_vertex_halfedge(w.a, w.tn)?;
    }
    if w.b_out == w.t {
        edit.set_vertex_halfedge(w.b, w.hn)?;
    }
    edit.commit()?;
    Ok(())
}

/// The student's flip with one line forgotten: `hn` is never moved to `g`, so `g`'s loop holds
/// a halfedge that says it is on `f`; the commit refuses it, naming that halfedge.
///
/// # Refusals
/// As the student's flip, and always [`Refusal::Broken`] where that one applies.
pub fn flip_forgetting_a_face(world: &mut World, mesh: MeshId, e: EdgeId) -> Result<(), Refusal> {
    let w = check_flip(&MeshRef::new(world), e)?;
    let mut edit = RawEdit::new(world, mesh);
    rewire_flip(&mut edit, &w)?;
    // The forgotten line: hn is left on f.
    edit.set_face(w.hn, Some(w.f))?;
    edit.commit()?;
    Ok(())
}
