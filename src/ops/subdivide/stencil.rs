//! Subdivision stencils: which old vertices, with which weights, make each point of the next
//! level — what a student watches in the step mode before a level is committed.
//!
//! Every point of a subdivided mesh is an affine combination of the old vertices near it. A
//! [`Stencil`] names the new point ([`NewPoint`]: an old vertex moved, an edge point or a face
//! point), lists the old vertices with their weights and says in one line which rule made it.
//! The rules are those of [`super`], case for case:
//!
//! **Loop** (Loop 1987, *Smooth subdivision surfaces based on triangles*), triangles only:
//!
//! ```text
//!   interior edge            interior vertex, valence n       boundary vertex
//!        1/8                    u ─── u                        1/8 ── 3/4 ── 1/8
//!       /   \                  / \   / \
//!    3/8 ─── 3/8             u ─ 1−nu ─ u                    (a corner with two
//!       \   /                  \ /   \ /                      edges stays put)
//!        1/8                    u ─── u
//! ```
//!
//! with `u = 3/16` for n = 3, else `3 / (8 n)` (so `1 − n u = 5/8` for every n but 3), and a
//! boundary edge's point at its midpoint.
//!
//! **Catmull–Clark** (Catmull & Clark 1978, *Recursively generated B-spline surfaces on
//! arbitrary topological meshes*), any polygons: a face point is the centroid (`1/k` on each
//! of `k` corners); an interior edge point `(a + b + f1 + f2) / 4` with `f1`, `f2` the face
//! points beside it, expanded onto the corners of those faces (on a quad: `3/8` on each end,
//! `1/16` on the four far corners); a boundary edge point the midpoint; an interior vertex of
//! valence n `(Q + 2 R + (n − 3) P) / n`, with Q the mean of the face points around it and R of
//! its edge midpoints, expanded onto the corners of the faces around it (regular valence 4:
//! `9/16` on itself, `3/32` on each edge neighbour, `1/64` on each diagonal one); a boundary
//! vertex `3/4 P + 1/8 (a + b)`, one with a single face staying put.
//!
//! # Guarantees
//! A stencil's weights sum to 1 (each vertex once, weights merged where a vertex is reached
//! twice, heaviest first) and its position is `Σ w·p`, summed in `f64`. It agrees to `f32`
//! rounding with [`next_level_points`], whose positions come from the very functions a
//! committed level takes them from ([`super::loop_points`],
//! [`super::catmull_clark_points`]); the tests check both against the subdivided
//! mesh for every vertex, edge and face of several meshes.
//!
//! [`stencil`] walks the few elements around one point through [`MeshRef`] (the selected
//! element, each frame if need be); [`next_level_points`] computes every new point of the mesh
//! at once from its tables (the preview of the whole level). Measured on the Stanford bunny
//! (69 451 faces, dev profile): [`next_level_points`] 9 ms under Loop and 10 ms under
//! Catmull–Clark, about 5 ms of it reading the mesh into tables ([`extract`]); [`stencil`]
//! about 4 µs for a Catmull–Clark vertex.

use bevy::math::{DVec3, Vec3};
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::tables::{MeshTables, extract};
use crate::mesh::{MeshInfo, MeshRef};

use super::{Scheme, catmull_clark_points, loop_points};
use crate::ops::Refusal;

/// Which point of the next level: where an old vertex moves, or a point a scheme inserts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NewPoint {
    /// The old vertex, moved (it keeps its entity through the subdivision).
    Vertex(VertexId),
    /// The point inserted on an old edge.
    Edge(EdgeId),
    /// The point inserted in an old face (Catmull–Clark only).
    Face(FaceId),
}

impl NewPoint {
    /// The old element the point belongs to.
    pub fn element(self) -> ElementId {
        match self {
            Self::Vertex(v) => ElementId::Vertex(v),
            Self::Edge(e) => ElementId::Edge(e),
            Self::Face(f) => ElementId::Face(f),
        }
    }
}

/// One point of the next level and the old vertices that make it.
#[derive(Clone, Debug, PartialEq)]
pub struct Stencil {
    /// The point.
    pub point: NewPoint,
    /// Its position: `Σ w·p` over [`Stencil::terms`].
    pub position: Vec3,
    /// The old vertices and their weights: each vertex once, weights summing to 1, heaviest
    /// first (ties in the order the rule reaches them: itself or the edge's ends first, then
    /// counter-clockwise).
    pub terms: Vec<(VertexId, f32)>,
    /// The rule in one line, for the panel ("boundary edge: midpoint", …).
    pub rule: String,
}

/// Weights gathered in `f64`, merged per vertex in the order first reached.
#[derive(Default)]
struct Terms(Vec<(VertexId, f64)>);

impl Terms {
    fn add(&mut self, v: VertexId, w: f64) {
        match self.0.iter_mut().find(|(x, _)| *x == v) {
            Some((_, sum)) => *sum += w,
            None => self.0.push((v, w)),
        }
    }

    /// The stencil of `point` made by these weights.
    fn into_stencil(mut self, m: &MeshRef<'_>, point: NewPoint, rule: String) -> Stencil {
        let position: DVec3 = self
            .0
            .iter()
            .map(|&(v, w)| m.position(v).as_dvec3() * w)
            .sum();
        // Stable: equal weights keep the order the rule reached them in.
        self.0.sort_by(|a, b| b.1.total_cmp(&a.1));
        Stencil {
            point,
            position: position.as_vec3(),
            terms: self.0.into_iter().map(|(v, w)| (v, w as f32)).collect(),
            rule,
        }
    }
}

/// `num / den` in lowest terms, as text ("1/16", "5/8", "1").
fn ratio(num: u64, den: u64) -> String {
    let g = gcd(num, den).max(1);
    let (n, d) = (num / g, den / g);
    if d == 1 {
        n.to_string()
    } else {
        format!("{n}/{d}")
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The stencil of one point of the next level of `scheme`.
///
/// Reads only the elements around the point, so it is cheap enough for every frame.
///
/// # Refusals
/// - [`Refusal::Stale`] if the point's vertex, edge or face does not exist;
/// - [`Refusal::BadParameter`] for a face point under Loop (Loop inserts none);
/// - [`Refusal::NotTriangle`] under Loop, naming a face the point's rule reads (the faces
///   around the vertex, or beside the edge) that is not a triangle. Only those faces are
///   checked: [`next_level_points`] and [`super::loop_subdivide`] refuse a mesh
///   with any non-triangle face anywhere.
pub fn stencil(m: &MeshRef<'_>, scheme: Scheme, point: NewPoint) -> Result<Stencil, Refusal> {
    let live = match point {
        NewPoint::Vertex(v) => m.try_vertex(v).is_some() && m.try_position(v).is_some(),
        NewPoint::Edge(e) => m.try_edge(e).is_some(),
        NewPoint::Face(f) => m.try_face(f).is_some(),
    };
    if !live {
        return Err(Refusal::Stale(point.element()));
    }
    match (scheme, point) {
        (Scheme::Loop, NewPoint::Face(_)) => Err(Refusal::BadParameter(
            "Loop subdivision inserts no face points, only edge points".into(),
        )),
        (Scheme::Loop, NewPoint::Vertex(v)) => {
            triangles_only(m, m.vertex_faces(v))?;
            Ok(loop_vertex(m, v))
        }
        (Scheme::Loop, NewPoint::Edge(e)) => {
            let h = m.edge_halfedge(e);
            triangles_only(m, [m.face(h), m.face(m.twin(h))].into_iter().flatten())?;
            Ok(loop_edge(m, e))
        }
        (Scheme::CatmullClark, NewPoint::Vertex(v)) => Ok(cc_vertex(m, v)),
        (Scheme::CatmullClark, NewPoint::Edge(e)) => Ok(cc_edge(m, e)),
        (Scheme::CatmullClark, NewPoint::Face(f)) => Ok(cc_face(m, f)),
    }
}

/// The natural point of a selected element under `scheme`: a vertex's moved position, an
/// edge's edge point, a face's face point (Catmull–Clark), a halfedge's edge point. `None`
/// where there is none (a face under Loop, a mesh) or where [`stencil`] refuses (a stale id,
/// a non-triangle face under Loop).
pub fn stencil_of_element(m: &MeshRef<'_>, scheme: Scheme, x: ElementId) -> Option<Stencil> {
    let point = match x {
        ElementId::Vertex(v) => NewPoint::Vertex(v),
        ElementId::Edge(e) => NewPoint::Edge(e),
        ElementId::Face(f) => NewPoint::Face(f),
        ElementId::Halfedge(h) => NewPoint::Edge(m.try_halfedge(h)?.edge),
        ElementId::Mesh(_) => return None,
    };
    stencil(m, scheme, point).ok()
}

/// `Err(NotTriangle)` naming the first of `faces` with other than three sides.
fn triangles_only(m: &MeshRef<'_>, mut faces: impl Iterator<Item = FaceId>) -> Result<(), Refusal> {
    match faces.find(|&f| m.face_degree(f) != 3) {
        Some(f) => Err(Refusal::NotTriangle(ElementId::Face(f))),
        None => Ok(()),
    }
}

/// The boundary rule both schemes share, `3/4 P + 1/8 (a + b)` with `v`'s two boundary
/// neighbours (its halfedge is its outgoing boundary one), into `terms`.
fn boundary_terms(m: &MeshRef<'_>, v: VertexId) -> Terms {
    let h = m.vertex_halfedge(v);
    let mut t = Terms::default();
    t.add(v, 0.75);
    t.add(m.to_vertex(h), 0.125);
    t.add(m.from_vertex(m.prev(h)), 0.125);
    t
}

const BOUNDARY_RULE: &str =
    "boundary vertex: 3/4 on itself, 1/8 on each of its two boundary neighbours";

/// A vertex that keeps its place.
fn stays(m: &MeshRef<'_>, v: VertexId, rule: &str) -> Stencil {
    let mut t = Terms::default();
    t.add(v, 1.0);
    t.into_stencil(m, NewPoint::Vertex(v), rule.into())
}

fn loop_vertex(m: &MeshRef<'_>, v: VertexId) -> Stencil {
    let point = NewPoint::Vertex(v);
    let n = m.valence(v);
    if m.is_boundary_vertex(v) {
        if n <= 2 {
            return stays(m, v, "corner vertex (two edges): stays put");
        }
        return boundary_terms(m, v).into_stencil(m, point, BOUNDARY_RULE.into());
    }
    // u = 3/16 for valence 3, else 3/(8n): as a fraction num/den.
    let (num, den) = if n == 3 { (3, 16) } else { (3, 8 * n as u64) };
    let u = num as f64 / den as f64;
    let mut t = Terms::default();
    t.add(v, 1.0 - n as f64 * u);
    for w in m.vertex_neighbors(v) {
        t.add(w, u);
    }
    let own = ratio(den - n as u64 * num, den);
    let u_text = ratio(num, den);
    let rule = if n == 3 {
        format!(
            "interior vertex, valence 3: 1 − 3u = {own} on itself, u = {u_text} on each \
             neighbour (Loop's special case for valence 3)"
        )
    } else {
        format!(
            "interior vertex, valence {n}: 1 − {n}u = {own} on itself, u = 3/(8·{n}) = \
             {u_text} on each neighbour"
        )
    };
    t.into_stencil(m, point, rule)
}

fn loop_edge(m: &MeshRef<'_>, e: EdgeId) -> Stencil {
    let point = NewPoint::Edge(e);
    let h = m.edge_halfedge(e);
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    if m.is_boundary_edge(e) {
        return boundary_edge(m, e);
    }
    let mut t = Terms::default();
    t.add(a, 0.375);
    t.add(b, 0.375);
    t.add(m.to_vertex(m.next(h)), 0.125);
    t.add(m.to_vertex(m.next(m.twin(h))), 0.125);
    t.into_stencil(
        m,
        point,
        "interior edge: 3/8 on each end, 1/8 on each of the two opposite vertices".into(),
    )
}

/// A boundary edge's point under either scheme: its midpoint.
fn boundary_edge(m: &MeshRef<'_>, e: EdgeId) -> Stencil {
    let (a, b) = m.edge_vertices(e);
    let mut t = Terms::default();
    t.add(a, 0.5);
    t.add(b, 0.5);
    t.into_stencil(
        m,
        NewPoint::Edge(e),
        "boundary edge: midpoint, 1/2 on each end".into(),
    )
}

/// Adds `weight` times the centroid of the face of `h` (its face point) to `t`.
fn add_face_point(m: &MeshRef<'_>, h: HalfedgeId, weight: f64, t: &mut Terms) {
    let f = m.face(h).expect("an interior halfedge has a face");
    let k = m.face_degree(f) as f64;
    for c in m.face_vertices(f) {
        t.add(c, weight / k);
    }
}

fn cc_face(m: &MeshRef<'_>, f: FaceId) -> Stencil {
    let mut t = Terms::default();
    add_face_point(m, m.face_halfedge(f), 1.0, &mut t);
    let k = m.face_degree(f);
    let rule = format!("face point: the centroid, 1/{k} on each of its {k} corners");
    t.into_stencil(m, NewPoint::Face(f), rule)
}

fn cc_edge(m: &MeshRef<'_>, e: EdgeId) -> Stencil {
    let point = NewPoint::Edge(e);
    let h = m.edge_halfedge(e);
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    if m.is_boundary_edge(e) {
        return boundary_edge(m, e);
    }
    let mut t = Terms::default();
    t.add(a, 0.25);
    t.add(b, 0.25);
    add_face_point(m, h, 0.25, &mut t);
    add_face_point(m, m.twin(h), 0.25, &mut t);
    let rule = "interior edge: (a + b + f1 + f2) / 4, f1 and f2 the face points (centroids) \
                of the two faces beside it"
        .into();
    t.into_stencil(m, point, rule)
}

fn cc_vertex(m: &MeshRef<'_>, v: VertexId) -> Stencil {
    let point = NewPoint::Vertex(v);
    if m.is_boundary_vertex(v) {
        if m.vertex_faces(v).count() <= 1 {
            return stays(m, v, "boundary vertex of a single face: stays put");
        }
        return boundary_terms(m, v).into_stencil(m, point, BOUNDARY_RULE.into());
    }
    // (Q + 2R + (n − 3)P)/n with Q = Σ face points / n and R = Σ (P + neighbour)/2 / n.
    let n = m.valence(v) as f64;
    let mut t = Terms::default();
    t.add(v, (n - 3.0) / n);
    for h in m.vertex_outgoing(v) {
        add_face_point(m, h, 1.0 / (n * n), &mut t);
        t.add(v, 1.0 / (n * n));
        t.add(m.to_vertex(h), 1.0 / (n * n));
    }
    let n = n as usize;
    let rule = format!(
        "interior vertex, valence {n}: (Q + 2R + ({n} − 3)P) / {n}, Q the mean of the {n} face \
         points around it, R the mean of its {n} edge midpoints"
    );
    t.into_stencil(m, point, rule)
}

/// Every point of the next level of a mesh, paired with the old element it belongs to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NextLevelPoints {
    /// Each old vertex with its moved position.
    pub vertex: Vec<(VertexId, Vec3)>,
    /// Each old edge with its edge point.
    pub edge: Vec<(EdgeId, Vec3)>,
    /// Each old face with its face point (empty under Loop).
    pub face: Vec<(FaceId, Vec3)>,
}

/// Every new point of the next level of `scheme` on `mesh`, in the mesh's storage order.
///
/// Computes the positions with [`loop_points`] / [`catmull_clark_points`], the functions
/// [`super::loop_tables`] / [`super::catmull_clark_tables`] take a
/// committed level's positions from, so the points are exactly those a committed level gets;
/// the connectivity is not built. Their rows are laid out as the old vertices (by vertex row),
/// then one edge point per old edge (by edge row), then, for Catmull–Clark, one face point per
/// old face (by face row); [`extract`]'s members give the entity behind each row. Nothing in
/// the world changes. For its cost on a large mesh see the module doc.
///
/// # Refusals
/// [`Refusal::Stale`] if `mesh` is not a mesh; under Loop [`Refusal::NotTriangle`] naming a
/// face with other than three sides (as [`super::loop_subdivide`] does).
pub fn next_level_points(
    world: &World,
    mesh: MeshId,
    scheme: Scheme,
) -> Result<NextLevelPoints, Refusal> {
    if world.get::<MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    let MeshTables { tables, members } = extract(world, mesh);
    let p = match scheme {
        Scheme::Loop => loop_points(&tables)
            .map_err(|f| Refusal::NotTriangle(ElementId::Face(members.faces[f.index()])))?,
        Scheme::CatmullClark => catmull_clark_points(&tables),
    };
    let (nv, ne) = (members.vertices.len(), members.edges.len());
    let faces = match scheme {
        Scheme::Loop => Vec::new(),
        Scheme::CatmullClark => members
            .faces
            .iter()
            .copied()
            .zip(p[nv + ne..].iter().copied())
            .collect(),
    };
    crate::checks::checked_assert_eq!(
        p.len(),
        nv + ne + faces.len(),
        "the new vertex rows' layout"
    );
    Ok(NextLevelPoints {
        vertex: members
            .vertices
            .iter()
            .copied()
            .zip(p[..nv].iter().copied())
            .collect(),
        edge: members
            .edges
            .iter()
            .copied()
            .zip(p[nv..nv + ne].iter().copied())
            .collect(),
        face: faces,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::{MeshMembers, PolygonSoup, build_mesh, despawn_mesh, validate};
    use std::collections::HashSet;

    fn build(world: &mut World, soup: &PolygonSoup) -> MeshId {
        build_mesh(world, soup, MeshInfo::default()).unwrap().mesh
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        a.distance(b) <= 2e-6 * (1.0 + a.length())
    }

    /// The one vertex of the subdivided mesh joined to both `a` and `b` and not in `old`.
    fn common_new_neighbour(
        m: &MeshRef<'_>,
        a: VertexId,
        b: VertexId,
        old: &HashSet<VertexId>,
    ) -> VertexId {
        let around_a: HashSet<VertexId> = m.vertex_neighbors(a).collect();
        let both: Vec<VertexId> = m
            .vertex_neighbors(b)
            .filter(|w| around_a.contains(w) && !old.contains(w))
            .collect();
        assert_eq!(both.len(), 1, "{a} and {b} share one new neighbour");
        both[0]
    }

    /// Checks every stencil of `soup` under `scheme` against the tables and against the
    /// committed level; returns how many points were checked.
    fn check_every_point(soup: &PolygonSoup, scheme: Scheme) -> usize {
        let mut world = World::new();
        let mesh = build(&mut world, soup);
        let members = MeshMembers::collect(&world, mesh);
        let points = next_level_points(&world, mesh, scheme).unwrap();
        assert_eq!(points.vertex.len(), members.vertices.len());
        assert_eq!(points.edge.len(), members.edges.len());
        let face_points = match scheme {
            Scheme::Loop => 0,
            Scheme::CatmullClark => members.faces.len(),
        };
        assert_eq!(points.face.len(), face_points);

        // Each stencil, with the old vertices that locate its point after the level.
        let m = MeshRef::new(&world);
        let mut expected = Vec::new();
        let mut check = |point: NewPoint, from_tables: Vec3, locate: Vec<VertexId>| {
            let s = stencil(&m, scheme, point).unwrap();
            assert_eq!(s.point, point);
            let sum: f32 = s.terms.iter().map(|t| t.1).sum();
            assert!((sum - 1.0).abs() < 1e-6, "{point:?}: weights sum to {sum}");
            let seen: HashSet<VertexId> = s.terms.iter().map(|t| t.0).collect();
            assert_eq!(seen.len(), s.terms.len(), "each vertex once");
            assert!(
                s.terms.windows(2).all(|w| w[0].1 >= w[1].1),
                "heaviest first"
            );
            let combined: Vec3 = s.terms.iter().map(|&(v, w)| m.position(v) * w).sum();
            assert!(close(s.position, combined), "{point:?}: Σ w·p");
            assert!(
                close(s.position, from_tables),
                "{point:?}: stencil {} vs tables {from_tables}",
                s.position
            );
            expected.push((locate, s.position));
        };
        for &(v, p) in &points.vertex {
            check(NewPoint::Vertex(v), p, vec![v]);
        }
        for &(e, p) in &points.edge {
            let (a, b) = m.edge_vertices(e);
            check(NewPoint::Edge(e), p, vec![a, b]);
        }
        for &(f, p) in &points.face {
            // The face point is joined to the edge points of two sides at one corner.
            let h = m.face_halfedge(f);
            let corner = m.to_vertex(h);
            let ends = vec![m.from_vertex(h), corner, m.to_vertex(m.next(h))];
            check(NewPoint::Face(f), p, ends);
        }
        let checked = expected.len();

        scheme.subdivide(&mut world, mesh, 1).unwrap();
        validate(&world, mesh).unwrap();
        let after = MeshMembers::collect(&world, mesh);
        assert_eq!(after.vertices.len(), checked, "one new vertex per point");
        let old: HashSet<VertexId> = members.vertices.iter().copied().collect();
        let m = MeshRef::new(&world);
        for (locate, position) in expected {
            let at = match locate[..] {
                [v] => v,
                [a, b] => common_new_neighbour(&m, a, b, &old),
                [a, corner, b] => {
                    let (ma, mb) = (
                        common_new_neighbour(&m, a, corner, &old),
                        common_new_neighbour(&m, corner, b, &old),
                    );
                    let mut skip = old.clone();
                    skip.insert(corner);
                    common_new_neighbour(&m, ma, mb, &skip)
                }
                _ => unreachable!(),
            };
            assert!(
                close(m.position(at), position),
                "{at}: subdivided {} vs stencil {position}",
                m.position(at)
            );
        }
        checked
    }

    /// A pentagon, a quad and two triangles around one vertex, open.
    fn polygons() -> PolygonSoup {
        let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let positions = vec![
            p(0.0, 0.0, 0.3),
            p(1.0, 0.0, 0.0),
            p(1.3, 1.0, 0.1),
            p(0.4, 1.6, 0.0),
            p(-0.8, 1.0, 0.2),
            p(-1.0, -0.4, 0.0),
            p(0.2, -1.2, 0.1),
            p(1.4, -0.9, 0.0),
        ];
        let mut soup = PolygonSoup::with_capacity(positions.len(), 4, 0);
        soup.positions = positions;
        soup.push_face(&[0, 1, 2, 3, 4]);
        soup.push_face(&[0, 4, 5]);
        soup.push_face(&[0, 5, 6]);
        soup.push_face(&[0, 6, 7, 1]);
        soup
    }

    #[test]
    fn loop_stencils_agree_with_the_tables_and_the_subdivided_mesh() {
        // Closed valence 3 and 5 / 6, open with boundary and corner vertices, a fan.
        for soup in [
            shapes::tetrahedron(),
            shapes::icosphere(1),
            shapes::grid(3, 3),
            shapes::triangle_fan(5, false),
            shapes::diamond(),
        ] {
            let n = soup.positions.len();
            assert!(check_every_point(&soup, Scheme::Loop) > n);
        }
    }

    #[test]
    fn catmull_clark_stencils_agree_with_the_tables_and_the_subdivided_mesh() {
        // Quads closed (valence 3 on the cube), a torus, an open grid with single-face
        // corners, a grid with a hole, mixed polygons, triangles.
        for soup in [
            shapes::cube(),
            shapes::torus(5, 4),
            shapes::quad_grid(3, 2),
            shapes::grid_with_holes(1),
            polygons(),
            shapes::icosahedron(),
            shapes::triangle_fan(6, true),
        ] {
            let n = soup.positions.len();
            assert!(check_every_point(&soup, Scheme::CatmullClark) > n);
        }
    }

    /// The vertex of `world`'s mesh at `p`.
    pub(crate) fn vertex_at(world: &World, mesh: MeshId, p: Vec3) -> VertexId {
        let m = MeshRef::new(world);
        MeshMembers::collect(world, mesh)
            .vertices
            .into_iter()
            .find(|&v| m.position(v).distance(p) < 1e-6)
            .unwrap()
    }

    fn weights(s: &Stencil) -> Vec<f32> {
        s.terms.iter().map(|t| t.1).collect()
    }

    #[test]
    fn loop_weights_of_named_cases() {
        let mut world = World::new();
        let mesh = build(&mut world, &shapes::grid(4, 4));
        let m = MeshRef::new(&world);
        // An interior vertex of the regular grid: valence 6.
        let v = vertex_at(&world, mesh, Vec3::new(0.5, 0.5, 0.0));
        let s = stencil(&m, Scheme::Loop, NewPoint::Vertex(v)).unwrap();
        assert_eq!(s.terms[0], (v, 10.0 / 16.0));
        assert_eq!(weights(&s)[1..], [1.0 / 16.0; 6]);
        assert_eq!(
            s.rule,
            "interior vertex, valence 6: 1 − 6u = 5/8 on itself, u = 3/(8·6) = 1/16 on each \
             neighbour"
        );
        // An interior edge: 3/8 on its ends, 1/8 on the opposite vertices.
        let e = m.find_halfedge(v, vertex_at(&world, mesh, Vec3::new(0.75, 0.5, 0.0)));
        let s = stencil(&m, Scheme::Loop, NewPoint::Edge(m.edge(e.unwrap()))).unwrap();
        assert_eq!(weights(&s), [0.375, 0.375, 0.125, 0.125]);
        // A boundary vertex with three edges: 3/4, 1/8, 1/8; a corner with two stays.
        let b = vertex_at(&world, mesh, Vec3::new(0.5, 0.0, 0.0));
        let s = stencil(&m, Scheme::Loop, NewPoint::Vertex(b)).unwrap();
        assert_eq!(weights(&s), [0.75, 0.125, 0.125]);
        assert_eq!(s.rule, BOUNDARY_RULE);
        let corner = vertex_at(&world, mesh, Vec3::new(1.0, 0.0, 0.0));
        let s = stencil(&m, Scheme::Loop, NewPoint::Vertex(corner)).unwrap();
        assert_eq!(
            (s.terms.clone(), s.position),
            (vec![(corner, 1.0)], m.position(corner))
        );
        // A boundary edge: the midpoint.
        let c = vertex_at(&world, mesh, Vec3::new(0.75, 0.0, 0.0));
        let s = stencil_of_element(
            &m,
            Scheme::Loop,
            ElementId::Halfedge(m.find_halfedge(b, c).unwrap()),
        )
        .unwrap();
        assert_eq!(weights(&s), [0.5, 0.5]);
        assert_eq!(s.position, Vec3::new(0.625, 0.0, 0.0));
        assert_eq!(s.rule, "boundary edge: midpoint, 1/2 on each end");

        // Valence 3 (the tetrahedron): u = 3/16, 7/16 on itself.
        let mut world = World::new();
        let mesh = build(&mut world, &shapes::tetrahedron());
        let m = MeshRef::new(&world);
        let v = MeshMembers::collect(&world, mesh).vertices[0];
        let s = stencil(&m, Scheme::Loop, NewPoint::Vertex(v)).unwrap();
        assert_eq!(
            weights(&s),
            [7.0 / 16.0, 3.0 / 16.0, 3.0 / 16.0, 3.0 / 16.0]
        );
        assert!(
            s.rule
                .starts_with("interior vertex, valence 3: 1 − 3u = 7/16 on itself, u = 3/16")
        );
    }

    #[test]
    fn catmull_clark_weights_of_named_cases() {
        let mut world = World::new();
        let mesh = build(&mut world, &shapes::quad_grid(4, 4));
        let m = MeshRef::new(&world);
        let at = |x: f32, y: f32| vertex_at(&world, mesh, Vec3::new(x, y, 0.0));
        // Interior, valence 4, regular: 9/16 own, 3/32 edge neighbours, 1/64 diagonals.
        let v = at(0.5, 0.5);
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(v)).unwrap();
        assert_eq!(s.terms.len(), 9);
        assert_eq!(s.terms[0], (v, 9.0 / 16.0));
        let weight_of = |x: f32, y: f32| s.terms.iter().find(|t| t.0 == at(x, y)).unwrap().1;
        for (x, y) in [(0.75, 0.5), (0.25, 0.5), (0.5, 0.75), (0.5, 0.25)] {
            assert_eq!(weight_of(x, y), 3.0 / 32.0);
        }
        for (x, y) in [(0.75, 0.75), (0.25, 0.75), (0.75, 0.25), (0.25, 0.25)] {
            assert_eq!(weight_of(x, y), 1.0 / 64.0);
        }
        assert_eq!(
            s.position,
            m.position(v),
            "a flat regular grid is a fixed point"
        );
        // Interior edge between two quads: 3/8 on each end, 1/16 on the four far corners.
        let e = m.edge(m.find_halfedge(v, at(0.75, 0.5)).unwrap());
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Edge(e)).unwrap();
        assert_eq!(weights(&s), [0.375, 0.375, 0.0625, 0.0625, 0.0625, 0.0625]);
        assert_eq!(s.position, Vec3::new(0.625, 0.5, 0.0));
        // A face point: the centroid.
        let f = m.face(m.find_halfedge(v, at(0.75, 0.5)).unwrap()).unwrap();
        let s = stencil_of_element(&m, Scheme::CatmullClark, ElementId::Face(f)).unwrap();
        assert_eq!(weights(&s), [0.25; 4]);
        assert_eq!(
            s.rule,
            "face point: the centroid, 1/4 on each of its 4 corners"
        );
        // A corner of a single face stays; the next boundary vertex takes 3/4, 1/8, 1/8.
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(at(0.0, 0.0))).unwrap();
        assert_eq!(s.rule, "boundary vertex of a single face: stays put");
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(at(0.25, 0.0))).unwrap();
        assert_eq!(weights(&s), [0.75, 0.125, 0.125]);

        // The cube's corner: valence 3, (Q + 2R)/3 over three quads.
        let mut world = World::new();
        let mesh = build(&mut world, &shapes::cube());
        let m = MeshRef::new(&world);
        let v = vertex_at(&world, mesh, Vec3::ONE);
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(v)).unwrap();
        // P: 0 + 3·1/9 (R) + 3·1/36 (Q) = 5/12; edge neighbours 1/9 + 2/36 = 1/6;
        // face diagonals 1/36.
        assert_eq!(s.terms.len(), 7);
        assert!((s.terms[0].1 - 5.0 / 12.0).abs() < 1e-7);
        assert!(
            weights(&s)[1..4]
                .iter()
                .all(|w| (w - 1.0 / 6.0).abs() < 1e-7)
        );
        assert!(
            weights(&s)[4..]
                .iter()
                .all(|w| (w - 1.0 / 36.0).abs() < 1e-7)
        );
        assert!(close(s.position, Vec3::splat(5.0 / 9.0)), "{}", s.position);
    }

    #[test]
    fn refusals_and_elements_without_a_point() {
        let mut world = World::new();
        let quads = build(&mut world, &shapes::quad_grid(2, 2));
        let tris = build(&mut world, &shapes::icosahedron());
        let m = MeshRef::new(&world);
        let quad_members = MeshMembers::collect(&world, quads);
        let f = MeshMembers::collect(&world, tris).faces[0];
        // Loop has no face points.
        assert!(matches!(
            stencil(&m, Scheme::Loop, NewPoint::Face(f)),
            Err(Refusal::BadParameter(_))
        ));
        assert_eq!(
            stencil_of_element(&m, Scheme::Loop, ElementId::Face(f)),
            None
        );
        assert_eq!(
            stencil_of_element(&m, Scheme::Loop, ElementId::Mesh(tris)),
            None
        );
        // Loop on quads: refused locally and for the whole mesh.
        let v = quad_members.vertices[4];
        assert!(matches!(
            stencil(&m, Scheme::Loop, NewPoint::Vertex(v)),
            Err(Refusal::NotTriangle(ElementId::Face(_)))
        ));
        assert!(matches!(
            next_level_points(&world, quads, Scheme::Loop),
            Err(Refusal::NotTriangle(ElementId::Face(_)))
        ));
        assert!(stencil_of_element(&m, Scheme::CatmullClark, ElementId::Vertex(v)).is_some());
        // Stale ids, after the mesh is gone.
        let e = quad_members.edges[0];
        despawn_mesh(&mut world, quads);
        let m = MeshRef::new(&world);
        assert_eq!(
            stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(v)),
            Err(Refusal::Stale(ElementId::Vertex(v)))
        );
        assert_eq!(
            stencil(&m, Scheme::CatmullClark, NewPoint::Edge(e)),
            Err(Refusal::Stale(ElementId::Edge(e)))
        );
        assert_eq!(
            next_level_points(&world, quads, Scheme::CatmullClark),
            Err(Refusal::Stale(ElementId::Mesh(quads)))
        );
        assert_eq!(
            stencil_of_element(&m, Scheme::CatmullClark, ElementId::Vertex(v)),
            None
        );
    }

    #[test]
    fn a_halfedge_gives_its_edges_point() {
        let mut world = World::new();
        let mesh = build(&mut world, &shapes::icosahedron());
        let m = MeshRef::new(&world);
        for &h in &MeshMembers::collect(&world, mesh).halfedges {
            for scheme in [Scheme::Loop, Scheme::CatmullClark] {
                let s = stencil_of_element(&m, scheme, ElementId::Halfedge(h)).unwrap();
                assert_eq!(s.point, NewPoint::Edge(m.edge(h)));
            }
        }
    }

    #[test]
    fn fractions_in_lowest_terms() {
        assert_eq!(ratio(3, 48), "1/16");
        assert_eq!(ratio(30, 48), "5/8");
        assert_eq!(ratio(3, 40), "3/40");
        assert_eq!(ratio(8, 8), "1");
    }
}
