//! Step 3 of an iteration (Botsch & Kobbelt 2004): flip edges towards valence 6 (4 on the
//! boundary); and, after the last iteration, the sides of thin triangles.
//!
//! An edge is flipped when that brings the valences of its four vertices closer to 6 (4 on the
//! boundary), or leaves them as close and the edge is not locally Delaunay
//! ([`locally_delaunay`]): the flip then raises the pair's smallest angle. After the last
//! iteration, the sides of triangles with an angle under 30° are flipped where that raises the
//! pair's smallest angle ([`flip_thin`]). A flip moves no vertex, so the surface stays where the
//! projection put it. No feature or boundary edge is flipped, and no flip folds a triangle over
//! or leaves one nearly flat ([`flip_keeps_shape`]).

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, HalfedgeId, MeshId};
use crate::mesh::members::MeshMembers;
use crate::mesh::stats::{THIN_ANGLE_DEG, min_corner_angle_deg};
use crate::mesh::tables::write::write_listed_rows;
use crate::mesh::tables::{
    Connectivity, EdgeRow, FaceRow, HalfedgeRow, MeshTables, NONE, VertexRow, extract,
};
use crate::mesh::topology::MeshRef;
use crate::ops::geometry::closest::Reference;
use crate::ops::local::flip_edge;

/// Flips the interior non-feature edges of `mesh` where that brings the valences of their
/// four vertices closer to 6 (4 on the boundary), or leaves them as close and the edge was
/// not [`locally_delaunay`]; only flips that [`flip_keeps_shape`]. Returns the flipped edges
/// (each edge is visited once, in table order, and a flip keeps its id).
///
/// The pass runs on the tables read by [`extract`]: each flip is checked as
/// [`crate::ops::local::plan_flip`] checks it and made as [`crate::ops::local::apply_flip`]
/// makes it, row for row ([`flip_rows`]), and only the rows the flips changed are written
/// back. Reading each edge through its entity cost most of the pass.
pub(super) fn flip_to_valence(
    world: &mut World,
    mesh: MeshId,
    features: &EntityHashSet,
) -> Vec<EdgeId> {
    let MeshTables {
        tables: mut t,
        members,
    } = extract(world, mesh);
    // Valences and targets by vertex row, kept up to date flip by flip (a flip changes only
    // its four vertices' valences, and never which vertices are on the boundary).
    let mut valence = vec![0i32; t.vertex_count()];
    let mut target = vec![6i32; valence.len()];
    // Every halfedge into a vertex pairs with one out of it.
    for &v in &t.to_vertex {
        valence[v as usize] += 1;
    }
    for (v, &h) in t.vertex_halfedge.iter().enumerate() {
        // A boundary vertex's halfedge is its boundary one.
        if t.face[h as usize] == NONE {
            target[v] = 4;
        }
    }
    let mut flipped = Vec::new();
    let mut changed = ChangedRows::default();
    for (row, &e) in members.edges.iter().enumerate() {
        let row = EdgeRow::new(row as u32);
        if features.contains(&e.0) || t.is_boundary_edge(row) {
            continue;
        }
        let h = t.edge_halfedge(row);
        let ends = quad_rows(&t, h);
        let change = [-1, -1, 1, 1];
        let deviation = |k: usize, delta: i32| {
            let v = ends[k].index();
            (valence[v] + delta - target[v]).abs()
        };
        let before: i32 = (0..4).map(|k| deviation(k, 0)).sum();
        let after: i32 = (0..4).map(|k| deviation(k, change[k])).sum();
        let corners = ends.map(|v| t.position(v));
        // Closer valences; or as close, and a better-shaped pair.
        let better = after < before || (after == before && !delaunay(corners));
        if better && keeps_shape(corners) && flip_allowed(&t, h, &valence) {
            flip_rows(&mut t, h, &mut changed);
            for k in 0..4 {
                valence[ends[k].index()] += change[k];
            }
            flipped.push(e);
        }
    }
    changed.write(world, &t, &members);
    flipped
}

/// The rows a pass on the tables changed, to write back.
#[derive(Default)]
struct ChangedRows {
    vertices: Vec<VertexRow>,
    halfedges: Vec<HalfedgeRow>,
    faces: Vec<FaceRow>,
}

impl ChangedRows {
    /// Writes each changed row of `t` into its entity (`members`, row for row), once.
    fn write(mut self, world: &mut World, t: &Connectivity, members: &MeshMembers) {
        self.vertices.sort_unstable();
        self.vertices.dedup();
        self.halfedges.sort_unstable();
        self.halfedges.dedup();
        self.faces.sort_unstable();
        self.faces.dedup();
        let listed = (&self.vertices[..], &self.halfedges[..], &self.faces[..]);
        write_listed_rows(world, t, members, listed);
    }
}

/// The rows `a b c d` around the edge of `h`, between triangles a b c and b a d.
fn quad_rows(t: &Connectivity, h: HalfedgeRow) -> [VertexRow; 4] {
    let twin = t.twin(h);
    [
        t.to_vertex(twin),
        t.to_vertex(h),
        t.to_vertex(t.next(h)),
        t.to_vertex(t.next(twin)),
    ]
}

/// Whether the interior edge of `h` may flip, as [`crate::ops::local::plan_flip`] decides
/// (see its module doc): the new diagonal's ends differ and are not joined already, each end
/// of the old one keeps at least 3 edges (2 on the boundary; `valence` by vertex row), and
/// neither face already holds the corner it would gain.
fn flip_allowed(t: &Connectivity, h: HalfedgeRow, valence: &[i32]) -> bool {
    let twin = t.twin(h);
    let [a, b, c, d] = quad_rows(t, h);
    let (Some(f), Some(g)) = (t.face(h), t.face(twin)) else {
        return false;
    };
    if c == d || t.find_halfedge(c, d).is_some() {
        return false;
    }
    let holds = |f: FaceRow, v: VertexRow| t.face_halfedges(f).any(|x| t.to_vertex(x) == v);
    [a, b].into_iter().all(|v| {
        let minimum = if t.is_boundary_vertex(v) { 2 } else { 3 };
        valence[v.index()] > minimum
    }) && !holds(f, d)
        && !holds(g, c)
}

/// Flips the edge of `h` in the tables as [`crate::ops::local::apply_flip`] flips it on the
/// entities (`h` comes to run d → c in its face, its twin c → d; each face names its flipped
/// halfedge; an end that named the halfedge it loses names the one after it), and lists the
/// rows it changed in `changed`.
fn flip_rows(t: &mut Connectivity, h: HalfedgeRow, changed: &mut ChangedRows) {
    let twin = t.twin(h);
    let (hn, hp, tn, tp) = (t.next(h), t.prev(h), t.next(twin), t.prev(twin));
    let [a, b, c, d] = quad_rows(t, h);
    let (f, g) = (t.face(h), t.face(twin));
    let (hnn, tnn) = (t.next(hn), t.next(tn));
    t.set_to_vertex(h, c);
    t.set_to_vertex(twin, d);
    t.link(h, hnn);
    t.link(hp, tn);
    t.link(tn, h);
    t.set_face(tn, f);
    t.link(twin, tnn);
    t.link(tp, hn);
    t.link(hn, twin);
    t.set_face(hn, g);
    for (face, halfedge) in [(f, h), (g, twin)] {
        if let Some(face) = face {
            t.face_halfedge[face.index()] = halfedge.get();
            changed.faces.push(face);
        }
    }
    for (v, lost, replacement) in [(a, h, tn), (b, twin, hn)] {
        if t.vertex_halfedge(v) == lost {
            t.set_vertex_halfedge(v, replacement);
            changed.vertices.push(v);
        }
    }
    changed
        .halfedges
        .extend([h, twin, hn, hp, tn, tp, hnn, tnn]);
}

/// The sides of the triangles with an angle under [`THIN_ANGLE_DEG`].
pub(super) fn thin_triangle_edges(world: &World, mesh: MeshId) -> Vec<EdgeId> {
    let MeshTables { tables: t, members } = extract(world, mesh);
    let mut edges: Vec<EdgeId> = Vec::new();
    for f in 0..t.face_count() {
        let sides = t.triangle(f);
        let corners = sides.map(|h| t.positions[t.to_vertex[h as usize] as usize]);
        if min_corner_angle_deg(&corners) < THIN_ANGLE_DEG {
            edges.extend(sides.map(|h| members.edges[t.edge[h as usize] as usize]));
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// What a flip after the last smoothing must keep: the surface within `tolerance` of the
/// `input` ([`flip_thin`]).
pub(super) struct Fidelity<'a> {
    /// The input surface.
    pub input: &'a Reference,
    /// How far from it a new edge's middle may lie (the finish's detail tolerance).
    pub tolerance: f32,
}

impl Fidelity<'_> {
    /// Whether the new diagonal `c d` of the pair a b c, b a d keeps the surface on the input:
    /// its middle within the tolerance, or no farther than the old diagonal's.
    fn keeps(&self, [a, b, c, d]: [Vec3; 4]) -> bool {
        let new = self.input.distance((c + d) / 2.0);
        new <= self.tolerance || new <= self.input.distance((a + b) / 2.0)
    }
}

/// After the last smoothing, flips those of `edges` that are sides of thin triangles (an angle
/// under [`THIN_ANGLE_DEG`]) where that raises the smaller of the pair's smallest angles,
/// leaves both triangles in shape and keeps the surface on the input ([`Fidelity`]: a flip
/// across a fold or groove would bridge it, and the finish has just put that detail back);
/// features, the boundary and the edges at a `pinned` vertex (a tip put back by
/// [`super::finish::restore_tips`], where a flip could bridge the side of the spike and undo
/// the tip) are not flipped. Smoothing moves vertices after each iteration's valence flips and
/// leaves a few triangles thin; a flip moves no vertex. Returns the flipped edges (a flip
/// keeps the edge's id).
pub(super) fn flip_thin(
    world: &mut World,
    edges: &[EdgeId],
    features: &EntityHashSet,
    pinned: &EntityHashSet,
    fidelity: &Fidelity<'_>,
) -> Vec<EdgeId> {
    let mut flipped = Vec::new();
    for &e in edges {
        let m = MeshRef::new(world);
        if m.try_edge(e).is_none() || features.contains(&e.0) || m.is_boundary_edge(e) {
            continue;
        }
        let (a, b) = m.edge_vertices(e);
        if pinned.contains(&a.0) || pinned.contains(&b.0) {
            continue;
        }
        let h = m.edge_halfedge(e);
        let corners = quad_corners(&m, h);
        let [a, b, c, d] = corners;
        let before = min_corner_angle_deg(&[a, b, c]).min(min_corner_angle_deg(&[b, a, d]));
        let after = min_corner_angle_deg(&[a, d, c]).min(min_corner_angle_deg(&[d, b, c]));
        if before < THIN_ANGLE_DEG
            && after > before
            && flip_keeps_shape(&m, h)
            && fidelity.keeps(corners)
            && flip_edge(world, e).is_ok()
        {
            flipped.push(e);
        }
    }
    flipped
}

/// The positions of `a b c d` around the edge of `h`, between triangles a b c and b a d.
pub(super) fn quad_corners(m: &MeshRef<'_>, h: HalfedgeId) -> [Vec3; 4] {
    [
        m.from_vertex(h),
        m.to_vertex(h),
        m.to_vertex(m.next(h)),
        m.to_vertex(m.next(m.twin(h))),
    ]
    .map(|v| m.position(v))
}

/// Whether the edge of `h` (between triangles a b c and b a d) is locally Delaunay: the angles
/// facing it, at c and at d, sum to at most 180°. Flipping an edge that is not makes the
/// pair's smallest angle larger.
pub(crate) fn locally_delaunay(m: &MeshRef<'_>, h: HalfedgeId) -> bool {
    delaunay(quad_corners(m, h))
}

/// [`locally_delaunay`] on the corners `a b c d` of the pair a b c, b a d.
fn delaunay([a, b, c, d]: [Vec3; 4]) -> bool {
    let angle = |apex: Vec3| (a - apex).angle_between(b - apex);
    angle(c) + angle(d) <= std::f32::consts::PI + 1e-4
}

/// Whether flipping the edge of `h` (between triangles a b c and b a d) gives two triangles
/// that neither fold over (against the old pair's normal) nor nearly collapse to a segment
/// (height under 1/1000 of the longest side). A valence-only rule would flip across a
/// non-convex quad, for instance one whose corner is a locked vertex split onto a crease,
/// and leave a zero-area triangle that nothing can move.
fn flip_keeps_shape(m: &MeshRef<'_>, h: HalfedgeId) -> bool {
    keeps_shape(quad_corners(m, h))
}

/// [`flip_keeps_shape`] on the corners `a b c d` of the pair a b c, b a d.
fn keeps_shape([a, b, c, d]: [Vec3; 4]) -> bool {
    let normal = (b - a).cross(c - a) + (a - b).cross(d - b);
    // The quad is a d b c; the new diagonal is d c.
    [[a, d, c], [d, b, c]].iter().all(|&[p, q, r]| {
        let n = (q - p).cross(r - p);
        let longest = (q - p)
            .length_squared()
            .max((r - q).length_squared())
            .max((p - r).length_squared());
        n.dot(normal) > 0.0 && n.length_squared() > 1e-6 * longest * longest
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ids::VertexId;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh};

    /// Triangles a b c and b a d; whether flipping a b keeps both new triangles in shape.
    fn flip_ok(a: Vec3) -> bool {
        let (b, c, d) = (Vec3::X, Vec3::Y, -Vec3::Y);
        let soup = PolygonSoup::from_faces(vec![a, b, c, d], &[[0, 1, 2], [1, 0, 3]]);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let v = |i: usize| built.input_vertices[i].unwrap();
        let m = MeshRef::new(&world);
        flip_keeps_shape(&m, m.find_halfedge(v(0), v(1)).unwrap())
    }

    /// The kite a b c d, thin along its long diagonal a b: triangles a b c and b a d, with
    /// angles of 5.7° at a and b.
    fn thin_kite() -> (World, MeshId, [VertexId; 4]) {
        raised_kite(0.0)
    }

    /// The corners a b c d of [`thin_kite`], `c` and `d` raised by `rise` (a groove along a b).
    fn kite_corners(rise: f32) -> [Vec3; 4] {
        [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.1, rise),
            Vec3::new(0.0, -0.1, rise),
        ]
    }

    /// [`thin_kite`] with `c` and `d` raised by `rise`.
    fn raised_kite(rise: f32) -> (World, MeshId, [VertexId; 4]) {
        let points = kite_corners(rise).to_vec();
        let soup = PolygonSoup::from_faces(points, &[[0, 1, 2], [1, 0, 3]]);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let v = |i: usize| built.input_vertices[i].unwrap();
        (world, built.mesh, [v(0), v(1), v(2), v(3)])
    }

    #[test]
    fn thin_triangles_get_the_other_diagonal_unless_it_is_a_feature() {
        let (mut world, mesh, [a, b, c, d]) = thin_kite();
        let m = MeshRef::new(&world);
        let diagonal = m.edge(m.find_halfedge(a, b).unwrap());
        let edges = thin_triangle_edges(&world, mesh);
        assert_eq!(edges.len(), 5);
        let input = kite_surface(0.0);
        let fidelity = Fidelity {
            input: &input,
            tolerance: 0.01,
        };
        let none = EntityHashSet::default();
        assert_eq!(
            flip_thin(&mut world, &edges, &none, &none, &fidelity),
            vec![diagonal]
        );
        let m = MeshRef::new(&world);
        assert!(m.find_halfedge(a, b).is_none());
        // The flipped edge keeps its id.
        assert_eq!(m.edge(m.find_halfedge(c, d).unwrap()), diagonal);
        crate::mesh::validate(&world, mesh).unwrap();

        let (mut world, mesh, [a, b, ..]) = thin_kite();
        let m = MeshRef::new(&world);
        let diagonal = m.edge(m.find_halfedge(a, b).unwrap());
        let features: EntityHashSet = [diagonal.0].into_iter().collect();
        let edges = thin_triangle_edges(&world, mesh);
        assert_eq!(
            flip_thin(&mut world, &edges, &features, &none, &fidelity),
            vec![]
        );
    }

    /// The triangles of [`raised_kite`] as an input surface.
    fn kite_surface(rise: f32) -> Reference {
        let [a, b, c, d] = kite_corners(rise);
        Reference::from_triangles(vec![[a, b, c], [b, a, d]])
    }

    #[test]
    fn a_thin_flip_that_would_bridge_a_groove_is_refused() {
        // A groove along a b, 0.05 deep: the new diagonal c d would bridge it, its middle
        // 0.045 from the input where a b's lies on it.
        let (mut world, mesh, _) = raised_kite(0.05);
        let edges = thin_triangle_edges(&world, mesh);
        let none = EntityHashSet::default();
        let input = kite_surface(0.05);
        let strict = Fidelity {
            input: &input,
            tolerance: 0.01,
        };
        assert_eq!(flip_thin(&mut world, &edges, &none, &none, &strict), vec![]);
        // Within a looser tolerance the same flip is made.
        let loose = Fidelity {
            input: &input,
            tolerance: 0.1,
        };
        assert_eq!(flip_thin(&mut world, &edges, &none, &none, &loose).len(), 1);
    }

    #[test]
    fn flips_that_fold_or_flatten_a_triangle_are_refused() {
        // Convex quad: the new diagonal c d runs inside it.
        assert!(flip_ok(Vec3::new(-0.5, 0.0, 0.0)));
        // a on the new diagonal: one new triangle would have zero area.
        assert!(!flip_ok(Vec3::ZERO));
        // a past it (a dart): the new triangles would fold over each other.
        assert!(!flip_ok(Vec3::new(0.3, 0.0, 0.0)));
    }
}
