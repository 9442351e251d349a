//! A student's edge flip, edge split and edge collapse, written from scratch as a course lab
//! asks: read the structure with [`MeshRef`], check that the operation may run, then rewire the
//! halfedges by hand in a [`RawEdit`] and commit. Nothing here calls Pappus's own flip, split or
//! collapse; each declares the one it reproduces (`checked_against`), so that Pappus runs both
//! on copies of the mesh and reports whether this one is valid and the same.
//!
//! The conventions are the reference's (each `ops/local/` file's module doc draws them): which
//! halfedge, edge and face keep their ids, which are new, where the new vertex goes. Each
//! application logs every element it touched, by id, at the `trace` level under the target
//! `lab` (which the editor keeps at every level for its Log section).

use bevy::log::trace;
use bevy::prelude::World;
use pappus::mesh::{
    EdgeId, ElementId, FaceId, HalfedgeId, MeshId, MeshRef, RawEdit, RawEditError, VertexId,
};
use pappus::ops::Refusal;
use pappus::ops::declaration::{Declaration, Names, Section};
use pappus::ops::operation::{Applied, EditContext, MeshOperation, Values};

/// The student's edge flip, on key Alt+1.
pub const LAB_FLIP: Declaration = Declaration::new("lab-flip")
    .titled("Lab flip")
    .described("the student's edge flip, checked against flip")
    .on_key("Alt+1")
    .naming(Names::Edge)
    .in_section(Section::Local)
    .checked_against("flip");

/// The student's edge split, on key Alt+2.
pub const LAB_SPLIT: Declaration = Declaration::new("lab-split")
    .titled("Lab split")
    .described("the student's edge split, checked against split")
    .on_key("Alt+2")
    .naming(Names::Edge)
    .in_section(Section::Local)
    .checked_against("split");

/// The student's edge collapse, on key Alt+3.
pub const LAB_COLLAPSE: Declaration = Declaration::new("lab-collapse")
    .titled("Lab collapse")
    .described("the student's edge collapse, checked against collapse")
    .on_key("Alt+3")
    .naming(Names::Edge)
    .in_section(Section::Local)
    .checked_against("collapse");

/// An operation on one edge from a function that does it and returns what to select: the
/// student's flip, split and collapse, and the mistakes.
pub struct OnEdge {
    /// What it declares (its name, key, and the reference it is checked against).
    pub declaration: &'static Declaration,
    /// What it does; `Err` leaves the world as it was.
    pub run: fn(&mut World, MeshId, EdgeId) -> Result<ElementId, Refusal>,
    /// What its summary says before the element it returns ("turned", "new vertex").
    pub says: &'static str,
}

/// The student's three operations, as the example registers them.
pub const LAB: [OnEdge; 3] = [
    OnEdge {
        declaration: &LAB_FLIP,
        run: |world, mesh, e| flip(world, mesh, e).map(|()| e.into()),
        says: "turned",
    },
    OnEdge {
        declaration: &LAB_SPLIT,
        run: |world, mesh, e| split(world, mesh, e).map(Into::into),
        says: "new vertex",
    },
    OnEdge {
        declaration: &LAB_COLLAPSE,
        run: |world, mesh, e| collapse(world, mesh, e).map(Into::into),
        says: "kept",
    },
];

impl MeshOperation for OnEdge {
    fn declaration(&self) -> &'static Declaration {
        self.declaration
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        Applied::on_edge(world, e, |world| {
            let made = (self.run)(world, mesh, e)?;
            Ok((format!("{} {made}", self.says), made))
        })
    }
}

/// The two triangles on an interior edge, as a lab names them: `h` runs a -> b in face `f`
/// (a, b, c), its twin `t` runs b -> a in face `g` (b, a, d); `a_out` and `b_out` are the
/// halfedges a and b start with.
pub struct Wings {
    pub h: HalfedgeId,
    pub hn: HalfedgeId,
    pub hp: HalfedgeId,
    pub t: HalfedgeId,
    pub tn: HalfedgeId,
    pub tp: HalfedgeId,
    pub a: VertexId,
    pub b: VertexId,
    pub c: VertexId,
    pub d: VertexId,
    pub f: FaceId,
    pub g: FaceId,
    pub a_out: HalfedgeId,
    pub b_out: HalfedgeId,
}

impl Wings {
    /// The wings of `e`, which must be an interior edge between two triangles.
    pub fn of(m: &MeshRef, e: EdgeId) -> Result<Self, Refusal> {
        m.try_edge(e).ok_or(Refusal::Stale(e.into()))?;
        let h = m.edge_halfedge(e);
        let t = m.twin(h);
        let mut faces = [h, t].into_iter().map(|x| {
            let f = m.face(x).ok_or(Refusal::BoundaryEdge(e.into()))?;
            match m.face_degree(f) {
                3 => Ok(f),
                _ => Err(Refusal::NotTriangle(f.into())),
            }
        });
        let (f, g) = (faces.next().expect("two")?, faces.next().expect("two")?);
        let (hn, tn) = (m.next(h), m.next(t));
        let (a, b) = (m.from_vertex(h), m.to_vertex(h));
        Ok(Self {
            h,
            hn,
            hp: m.next(hn),
            t,
            tn,
            tp: m.next(tn),
            a,
            b,
            c: m.to_vertex(hn),
            d: m.to_vertex(tn),
            f,
            g,
            a_out: m.vertex_halfedge(a),
            b_out: m.vertex_halfedge(b),
        })
    }
}

/// Flips `e`: the edge turns to join c and d; every element keeps its id. `h` becomes d -> c,
/// `t` becomes c -> d; `tn` moves into `h`'s face, `hn` into `t`'s.
///
/// # Refusals
/// As [`check_flip`].
pub fn flip(world: &mut World, mesh: MeshId, e: EdgeId) -> Result<(), Refusal> {
    let w = check_flip(&MeshRef::new(world), e)?;
    let mut edit = RawEdit::new(world, mesh);
    rewire_flip(&mut edit, &w)?;
    edit.commit()?;
    trace!(
        target: "lab",
        "lab flip {e}: {} now {} -> {}, {} now {} -> {}; {} moved to {}, {} to {}",
        w.h, w.d, w.c, w.t, w.c, w.d, w.tn, w.f, w.hn, w.g
    );
    Ok(())
}

/// The wings of `e` if it may flip.
///
/// # Refusals
/// A boundary edge, a polygon beside it, c and d already joined, or an end that would be left
/// with fewer than 3 edges (2 on the boundary).
pub fn check_flip(m: &MeshRef, e: EdgeId) -> Result<Wings, Refusal> {
    let w = Wings::of(m, e)?;
    if w.c == w.d {
        return Err(Refusal::DegenerateFace(w.f.into()));
    }
    if m.find_halfedge(w.c, w.d).is_some() {
        return Err(Refusal::WouldDuplicateEdge(w.c.into(), w.d.into()));
    }
    for v in [w.a, w.b] {
        let least = if m.is_boundary_vertex(v) { 2 } else { 3 };
        if m.valence(v) <= least {
            return Err(Refusal::ValenceTooLow(v.into(), least));
        }
    }
    Ok(w)
}

/// The flip's surgery on `w`'s six halfedges and two faces.
pub fn rewire_flip(edit: &mut RawEdit, w: &Wings) -> Result<(), RawEditError> {
    edit.set_to_vertex(w.h, w.c)?;
    edit.set_to_vertex(w.t, w.d)?;
    // f: h (d -> c), hp (c -> a), tn (a -> d); g: t (c -> d), tp (d -> b), hn (b -> c).
    for (x, next) in [(w.h, w.hp), (w.hp, w.tn), (w.tn, w.h)] {
        edit.set_next(x, next)?;
    }
    for (x, next) in [(w.t, w.tp), (w.tp, w.hn), (w.hn, w.t)] {
        edit.set_next(x, next)?;
    }
    edit.set_face(w.tn, Some(w.f))?;
    edit.set_face(w.hn, Some(w.g))?;
    edit.set_face_halfedge(w.f, w.h)?;
    edit.set_face_halfedge(w.g, w.t)?;
    // a and b no longer start h and t.
    if w.a_out == w.h {
        edit.set_vertex_halfedge(w.a, w.tn)?;
    }
    if w.b_out == w.t {
        edit.set_vertex_halfedge(w.b, w.hn)?;
    }
    Ok(())
}

/// Splits `e` at its midpoint m, joining m to c and d: two triangles become four. The edge
/// keeps `h` (now a -> m) with a new twin; `t` (now b -> m) moves to a new edge m b with a new
/// twin; `f` keeps (a, m, c), `g` keeps (b, m, d), two new faces take (m, b, c) and (m, a, d).
/// Returns m.
///
/// # Refusals
/// A boundary edge, a polygon beside it, or c = d.
pub fn split(world: &mut World, mesh: MeshId, e: EdgeId) -> Result<VertexId, Refusal> {
    let m = MeshRef::new(world);
    let w = Wings::of(&m, e)?;
    if w.c == w.d {
        return Err(Refusal::DegenerateFace(w.f.into()));
    }
    let (f, g) = (w.f, w.g);
    let middle = m.position(w.a).lerp(m.position(w.b), 0.5);
    let mut edit = RawEdit::new(world, mesh);
    let mid = edit.new_vertex(middle)?;
    // The new edge m b, with t and t2 (m -> b); h2 (m -> a) joins h on the old edge.
    let (mb, t2, h2) = edit.new_edge();
    let (mc, n1, n2) = edit.new_edge(); // n1: m -> c in f, n2: c -> m
    let (md, n3, n4) = edit.new_edge(); // n3: m -> d in g, n4: d -> m
    let (f2, g2) = (edit.new_face(), edit.new_face());
    edit.set_twin(w.h, h2)?;
    edit.set_twin(w.t, t2)?;
    edit.set_edge(h2, e)?;
    edit.set_edge(w.t, mb)?;
    for (x, to) in [(w.h, mid), (w.t, mid), (t2, w.b), (h2, w.a)] {
        edit.set_to_vertex(x, to)?;
    }
    for (x, to) in [(n1, w.c), (n2, mid), (n3, w.d), (n4, mid)] {
        edit.set_to_vertex(x, to)?;
    }
    let faces = [
        (f, [w.h, n1, w.hp]),
        (f2, [t2, w.hn, n2]),
        (g, [w.t, n3, w.tp]),
        (g2, [h2, w.tn, n4]),
    ];
    for (face, cycle) in faces {
        for i in 0..3 {
            edit.set_next(cycle[i], cycle[(i + 1) % 3])?;
            edit.set_face(cycle[i], Some(face))?;
        }
        edit.set_face_halfedge(face, cycle[0])?;
    }
    edit.set_edge_halfedge(mb, w.t)?;
    edit.set_vertex_halfedge(mid, t2)?;
    edit.commit()?;
    trace!(
        target: "lab",
        "lab split {e}: new vertex {mid}, edges {mb} {mc} {md}, faces {f2} {g2}; \
         {} now -> {mid}, {} now on {mb}",
        w.h, w.t
    );
    Ok(mid)
}

/// Collapses `e` to its midpoint: a survives there, b goes, and with it each triangle beside
/// the edge, its two halfedges on the edge's ends, and its side at b (the side at a is kept,
/// joined to the twin of the side at b). Returns a.
///
/// # Refusals
/// A boundary edge, a polygon beside it, both ends on the boundary, a neighbour of both ends
/// other than c and d (the link condition), a tetrahedron, or a vertex left with fewer than 3
/// edges.
pub fn collapse(world: &mut World, mesh: MeshId, e: EdgeId) -> Result<VertexId, Refusal> {
    let m = MeshRef::new(world);
    let w = Wings::of(&m, e)?;
    check_collapse(&m, &w)?;
    let around_b: Vec<HalfedgeId> = m.vertex_outgoing(w.b).map(|x| m.twin(x)).collect();
    let (hn_twin, hp_twin) = (m.twin(w.hn), m.twin(w.hp));
    let (tn_twin, tp_twin) = (m.twin(w.tn), m.twin(w.tp));
    let (kept_c, kept_d) = (m.edge(w.hp), m.edge(w.tn));
    let (gone_c, gone_d) = (m.edge(w.hn), m.edge(w.tp));
    let (f, g) = (w.f, w.g);
    let (c_out, d_out) = (m.vertex_halfedge(w.c), m.vertex_halfedge(w.d));
    let middle = m.position(w.a).lerp(m.position(w.b), 0.5);
    let gone = [w.h, w.hn, w.hp, w.t, w.tn, w.tp];
    let mut edit = RawEdit::new(world, mesh);
    for x in around_b.into_iter().filter(|x| !gone.contains(x)) {
        edit.set_to_vertex(x, w.a)?;
    }
    edit.set_twin(hp_twin, hn_twin)?;
    edit.set_edge(hn_twin, kept_c)?;
    edit.set_edge_halfedge(kept_c, hp_twin)?;
    edit.set_twin(tn_twin, tp_twin)?;
    edit.set_edge(tp_twin, kept_d)?;
    edit.set_edge_halfedge(kept_d, tn_twin)?;
    edit.set_vertex_halfedge(w.a, hp_twin)?;
    if c_out == w.hp {
        edit.set_vertex_halfedge(w.c, hn_twin)?;
    }
    if d_out == w.tp {
        edit.set_vertex_halfedge(w.d, tn_twin)?;
    }
    edit.set_position(w.a, middle)?;
    let removed: [ElementId; 12] = [
        w.h.into(),
        w.hn.into(),
        w.hp.into(),
        w.t.into(),
        w.tn.into(),
        w.tp.into(),
        f.into(),
        g.into(),
        e.into(),
        gone_c.into(),
        gone_d.into(),
        w.b.into(),
    ];
    for x in removed {
        edit.remove(x)?;
    }
    edit.commit()?;
    trace!(
        target: "lab",
        "lab collapse {e}: kept {} at {middle}, removed {} {f} {g} {gone_c} {gone_d} and six halfedges",
        w.a, w.b
    );
    Ok(w.a)
}

/// Whether `w`'s edge may collapse (see [`collapse`]'s refusals).
fn check_collapse(m: &MeshRef, w: &Wings) -> Result<(), Refusal> {
    if m.is_boundary_vertex(w.a) && m.is_boundary_vertex(w.b) {
        return Err(Refusal::BoundaryPinch);
    }
    let of_a: Vec<VertexId> = m.vertex_neighbors(w.a).collect();
    let shared = m
        .vertex_neighbors(w.b)
        .find(|v| of_a.contains(v) && *v != w.c && *v != w.d);
    if let Some(v) = shared {
        return Err(Refusal::LinkCondition(v.into()));
    }
    if m.find_halfedge(w.c, w.d).is_some() && m.valence(w.a) == 3 && m.valence(w.b) == 3 {
        return Err(Refusal::TooSmall);
    }
    for v in [w.c, w.d] {
        let least = if m.is_boundary_vertex(v) { 2 } else { 3 };
        if m.valence(v) - 1 < least {
            return Err(Refusal::ValenceTooLow(v.into(), least));
        }
    }
    let least = if m.is_boundary_vertex(w.a) || m.is_boundary_vertex(w.b) {
        2
    } else {
        3
    };
    if m.valence(w.a) + m.valence(w.b) - 4 < least {
        return Err(Refusal::ValenceTooLow(w.a.into(), least));
    }
    Ok(())
}
