//! Weld two boundary edges (Scotty3D's weld edges): the second is glued onto the first, and
//! they become one interior edge.
//!
//! ```text
//!   d ---- b     b' ---- e          d ---- B ---- e
//!   |      ^     |       |          |      |      |
//!   |  f   h1   h2   g   |    →     |  f   |   g  |    B = (b + b') / 2
//!   |      |     v       |          |      |      |    A = (a + a') / 2
//!   c ---- a     a' ---- x          c ---- A ---- x
//! ```
//!
//! `e1`'s boundary halfedge `h1` runs a → b and `e2`'s `h2` runs b' → a' (opposite ways along
//! the seam, as the faces beside them are oriented). Their ends merge pairwise, a with a' and
//! b with b', each pair at its midpoint; the faces' halfedges `t1` (b → a) and `t2` (a' → b',
//! now a → b) become twins on `e1`. `h1`, `h2`, `e2`, a' and b' are removed; `e1`, a, b and
//! every face keep their entities. The two boundary loops are joined where the edges were (or
//! one loop splits in two, when both edges are on it). Counts for two distinct pairs: V − 2,
//! E − 1, F unchanged.
//!
//! **Zipping**: when the edges share an end (h2 runs straight into h1, so a' is a, or h1 into
//! h2, so b' is b), that end stays where it is and becomes an inner vertex, and only the other
//! pair merges: the boundary closes up like a zip by one edge (V − 1, E − 1). That is allowed
//! whenever the result is valid.
//!
//! Attributes: a merged vertex takes the mean of the pair's normals (renormalised) and colours;
//! every corner keeps its UV (the two sides of the new edge keep their own texture, as a seam
//! does). `e1` keeps its seam mark; `e2`'s goes with it.
//!
//! Refusals, in the order they are checked, each leaving the world untouched:
//! - `Stale`: `e1` or `e2` is not a live edge;
//! - `BadParameter`: the same edge twice, or edges of two meshes;
//! - `NotBoundary`: `e1`, then `e2`, is not on the boundary;
//! - `DegenerateFace`: a face holding both vertices of a pair that would merge (it would visit
//!   the merged vertex twice; this includes an edge joining the pair, whose faces would lose a
//!   side);
//! - `WouldDuplicateEdge`: a vertex joined to both vertices of a pair (or to a and b′, or a′
//!   and b, besides the welded edges): the merge would make two edges between the same
//!   vertices. This also covers every boundary loop that would be left with fewer than three
//!   sides.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::attributes::{MeshAttributes, interpolate_vertex};
use crate::mesh::elements::{Edge, InMesh, Position, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values};

use super::{Refusal, he, link, live_edge};

/// One pair of vertices that become one: `keep` survives at `position`; `gone` (when it is
/// another vertex) is removed, and the halfedges into it point at `keep`.
#[derive(Clone, Debug, PartialEq)]
struct Pair {
    keep: VertexId,
    gone: VertexId,
    position: Vec3,
    into_gone: Vec<HalfedgeId>,
    /// The boundary halfedges coming in and going out of the merged vertex, to be linked; `None`
    /// when the pair zips (the vertex becomes an inner one).
    join: Option<(HalfedgeId, HalfedgeId)>,
    /// The merged vertex's halfedge afterwards.
    halfedge: HalfedgeId,
}

/// Everything a weld touches, collected by [`plan_weld`].
#[derive(Clone, Debug, PartialEq)]
pub struct WeldPlan {
    mesh: MeshId,
    e1: EdgeId,
    e2: EdgeId,
    h1: HalfedgeId,
    h2: HalfedgeId,
    t1: HalfedgeId,
    t2: HalfedgeId,
    /// a with a′, then b with b′.
    pairs: [Pair; 2],
}

impl WeldPlan {
    /// The four ends of the two edges (three when they share one): their neighbourhood (see
    /// [`crate::mesh::change::neighbourhood`]) covers every halfedge that is relinked or
    /// retargeted and everything removed before, and the merged vertices' fans after.
    pub fn seeds(&self) -> Vec<VertexId> {
        let mut seeds = Vec::with_capacity(4);
        for p in &self.pairs {
            seeds.push(p.keep);
            if p.gone != p.keep {
                seeds.push(p.gone);
            }
        }
        seeds
    }

    /// The edge that stays (`e1`).
    pub fn kept(&self) -> EdgeId {
        self.e1
    }
}

/// The boundary halfedge of `e` (whose halfedge is `h`), or a refusal.
fn boundary_side(m: &MeshRef<'_>, e: EdgeId, h: HalfedgeId) -> Result<HalfedgeId, Refusal> {
    if m.is_boundary(h) {
        Ok(h)
    } else if m.is_boundary(m.twin(h)) {
        Ok(m.twin(h))
    } else {
        Err(Refusal::NotBoundary(ElementId::Edge(e)))
    }
}

/// Checks that `e2` can be welded onto `e1` and collects everything the weld touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_weld(world: &World, e1: EdgeId, e2: EdgeId) -> Result<WeldPlan, Refusal> {
    let m = MeshRef::new(world);
    let (x1, x2) = (live_edge(&m, e1)?, live_edge(&m, e2)?);
    if e1 == e2 {
        return Err(Refusal::BadParameter(format!(
            "a weld needs two different edges ({e1} twice)"
        )));
    }
    let mesh_of = |e: EdgeId| world.get::<InMesh>(e.0).map(|x| x.0);
    let mesh = mesh_of(e1).ok_or(Refusal::Stale(ElementId::Edge(e1)))?;
    if mesh_of(e2) != Some(mesh) {
        return Err(Refusal::BadParameter(format!(
            "{e1} and {e2} are in different meshes"
        )));
    }
    let h1 = boundary_side(&m, e1, x1)?;
    let h2 = boundary_side(&m, e2, x2)?;
    let (t1, t2) = (m.twin(h1), m.twin(h2));
    let (a, b) = (m.from_vertex(h1), m.to_vertex(h1));
    let (b2, a2) = (m.from_vertex(h2), m.to_vertex(h2));
    if a == a2 && b == b2 {
        unreachable!("{e1} and {e2} join the same two vertices in a valid mesh");
    }
    let merged = |v: VertexId| {
        if v == a2 {
            a
        } else if v == b2 {
            b
        } else {
            v
        }
    };
    // A face holding both vertices of a pair would visit the merged vertex twice.
    for (keep, gone) in [(a, a2), (b, b2)] {
        if keep == gone {
            continue;
        }
        for f in m.vertex_faces(gone) {
            if m.face_vertices(f).any(|x| x == keep) {
                return Err(Refusal::DegenerateFace(ElementId::Face(f)));
            }
        }
    }
    // Each merged vertex's edges (e2 merges into e1) must lead to distinct other vertices.
    for (keep, gone) in [(a, a2), (b, b2)] {
        let mut seen = EntityHashSet::default();
        let ends = if keep == gone {
            vec![keep]
        } else {
            vec![keep, gone]
        };
        for v in ends {
            for h in m.vertex_outgoing(v) {
                if m.edge(h) == e2 {
                    continue;
                }
                let w = merged(m.to_vertex(h));
                if w == keep {
                    return Err(Refusal::DegenerateFace(ElementId::Edge(m.edge(h))));
                }
                if !seen.insert(w.0) {
                    return Err(Refusal::WouldDuplicateEdge(
                        ElementId::Vertex(keep),
                        ElementId::Vertex(w),
                    ));
                }
            }
        }
    }
    let (p1, n1, p2, n2) = (m.prev(h1), m.next(h1), m.prev(h2), m.next(h2));
    let into = |v: VertexId, keep: VertexId| -> Vec<HalfedgeId> {
        if v == keep {
            return Vec::new();
        }
        m.vertex_outgoing(v)
            .map(|h| m.twin(h))
            .filter(|&h| h != h1 && h != h2)
            .collect()
    };
    let mid = |x: VertexId, y: VertexId| (m.position(x) + m.position(y)) / 2.0;
    let pairs = [
        Pair {
            keep: a,
            gone: a2,
            position: if a == a2 { m.position(a) } else { mid(a, a2) },
            into_gone: into(a2, a),
            join: (a != a2).then_some((p1, n2)),
            halfedge: if a == a2 { t2 } else { n2 },
        },
        Pair {
            keep: b,
            gone: b2,
            position: if b == b2 { m.position(b) } else { mid(b, b2) },
            into_gone: into(b2, b),
            join: (b != b2).then_some((p2, n1)),
            halfedge: if b == b2 { t1 } else { n1 },
        },
    ];
    Ok(WeldPlan {
        mesh,
        e1,
        e2,
        h1,
        h2,
        t1,
        t2,
        pairs,
    })
}

/// Carries out a weld planned by [`plan_weld`] on the unchanged world. Returns the kept edge.
pub fn apply_weld(world: &mut World, p: WeldPlan) -> EdgeId {
    crate::checks::checked_assert_eq!(
        plan_weld(world, p.e1, p.e2).as_ref(),
        Ok(&p),
        "stale weld plan"
    );
    let has = MeshAttributes::of(world, p.mesh);
    for pair in &p.pairs {
        for &h in &pair.into_gone {
            he(world, h).vertex = pair.keep;
        }
        if let Some((into, out)) = pair.join {
            link(world, into, out);
        }
        world
            .get_mut::<Vertex>(pair.keep.0)
            .expect("planned")
            .halfedge = pair.halfedge;
        world.get_mut::<Position>(pair.keep.0).expect("planned").0 = pair.position;
        if pair.gone != pair.keep {
            interpolate_vertex(world, has, pair.keep, (pair.keep, pair.gone), 0.5);
        }
    }
    for (x, twin) in [(p.t1, p.t2), (p.t2, p.t1)] {
        let mut links = he(world, x);
        links.twin = twin;
        links.edge = p.e1;
    }
    world.get_mut::<Edge>(p.e1.0).expect("planned").halfedge = p.t1;
    let mut removed = vec![p.h1.0, p.h2.0, p.e2.0];
    for pair in &p.pairs {
        if pair.gone != pair.keep {
            removed.push(pair.gone.0);
        }
    }
    for e in removed {
        world.despawn(e);
    }
    p.e1
}

/// Welds boundary edge `e2` onto boundary edge `e1` (see the module doc): plan, then apply.
/// Returns the kept edge, `e1`.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn weld_edges(world: &mut World, e1: EdgeId, e2: EdgeId) -> Result<EdgeId, Refusal> {
    let plan = plan_weld(world, e1, e2)?;
    Ok(apply_weld(world, plan))
}

/// Welding two boundary edges: a local edit.
pub const WELD: Declaration = Declaration::new("weld")
    .titled("Weld")
    .described("weld the first two selected boundary edges: the second onto the first")
    .on_key("Alt+M")
    .naming(Names::TwoEdges)
    .in_section(Section::Modelling);

/// [`plan_weld`] and [`apply_weld`] as a registered operation: `weld:A,B/C,D`, Alt+M.
pub struct Weld;

impl MeshOperation for Weld {
    fn declaration(&self) -> &'static Declaration {
        &WELD
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = {
            let [a, b] = values.two_edges().ok()?;
            plan_weld(world, a, b).ok()?
        };
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = {
            let [a, b] = values.two_edges()?;
            plan_weld(world, a, b)?
        };
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
            let e = apply_weld(world, plan);
            (format!("welded into {e}"), Some(ElementId::Edge(e)))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::attributes::VertexColor;
    use crate::mesh::{PolygonSoup, mesh_stats, shapes, validate};
    use crate::ops::local::testkit::*;

    /// Two unit squares one unit apart: 0 1 2 3 and 4 5 6 7 (x from 2 to 3).
    fn two_squares() -> PolygonSoup {
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        PolygonSoup::from_faces(
            vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
                p(2.0, 0.0),
                p(3.0, 0.0),
                p(3.0, 1.0),
                p(2.0, 1.0),
            ],
            &[[0, 1, 2, 3], [4, 5, 6, 7]],
        )
    }

    #[test]
    fn two_squares_meet_at_the_midpoints() {
        // Scotty3D's weld test: two boundary edges merged at their midpoints.
        let (mut world, built) = build(&two_squares());
        let (e1, e2) = (edge(&world, &built, 1, 2), edge(&world, &built, 4, 7));
        let kept = weld_edges(&mut world, e1, e2).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(kept, e1);
        assert!(world.get_entity(e2.0).is_err());
        assert_eq!(counts(&world, built.mesh), (6, 7, 2, 1, 1));
        assert_eq!(mesh_stats(&world, built.mesh).components, 1);
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[
                &[
                    [0.0, 0.0, 0.0],
                    [1.5, 0.0, 0.0],
                    [1.5, 1.0, 0.0],
                    [0.0, 1.0, 0.0]
                ],
                &[
                    [1.5, 0.0, 0.0],
                    [3.0, 0.0, 0.0],
                    [3.0, 1.0, 0.0],
                    [1.5, 1.0, 0.0]
                ],
            ])
        );
        assert!(!MeshRef::new(&world).is_boundary_edge(kept));
    }

    #[test]
    fn the_ends_of_a_strip_close_into_a_tube() {
        let (mut world, built) = build(&shapes::quad_grid(3, 1));
        let (left, right) = (edge(&world, &built, 0, 4), edge(&world, &built, 3, 7));
        weld_edges(&mut world, left, right).unwrap();
        validate(&world, built.mesh).unwrap();
        // One loop split in two: the tube's rims.
        assert_eq!(counts(&world, built.mesh), (6, 9, 3, 0, 2));
        let m = MeshRef::new(&world);
        let seam = m.position(vertex(&built, 0));
        assert_eq!(seam, Vec3::new(0.5, 0.0, 0.0));
    }

    #[test]
    fn two_edges_that_share_an_end_zip_up() {
        // Three quarters of a disc around vertex 0; its two straight sides 0 1 and 4 0 share
        // the centre, which becomes an inner vertex, and 1 and 4 merge.
        let (mut world, built) = build(&shapes::triangle_fan(3, false));
        let (e1, e2) = (edge(&world, &built, 0, 4), edge(&world, &built, 0, 1));
        let centre = vertex(&built, 0);
        weld_edges(&mut world, e1, e2).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(counts(&world, built.mesh), (4, 6, 3, 1, 1));
        let m = MeshRef::new(&world);
        assert!(!m.is_boundary_vertex(centre));
        assert_eq!(m.position(centre), Vec3::ZERO);
        let p1 = Vec3::new(1.0, 0.0, 0.0);
        let p4 = Vec3::new(
            (1.5 * std::f32::consts::PI).cos(),
            (1.5 * std::f32::consts::PI).sin(),
            0.0,
        );
        let merged = m.position(vertex(&built, 4));
        assert!((merged - (p1 + p4) / 2.0).length() < 1e-6, "{merged}");
    }

    #[test]
    fn refusals_leave_the_mesh_untouched() {
        let (mut world, built) = build(&two_squares());
        let (e1, e2) = (edge(&world, &built, 1, 2), edge(&world, &built, 4, 7));
        // Same edge.
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::BadParameter(format!("a weld needs two different edges ({e1} twice)")),
            |w| weld_edges(w, e1, e1),
        );
        // A stale edge: e2 is gone once welded.
        weld_edges(&mut world, e1, e2).unwrap();
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Edge(e2)),
            |w| weld_edges(w, e1, e2),
        );
        // The first edge inside the surface (Scotty3D's refusal).
        let (mut world, built) = build(&shapes::quad_grid(3, 1));
        let inner = edge(&world, &built, 1, 5);
        let border = edge(&world, &built, 3, 7);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::NotBoundary(ElementId::Edge(inner)),
            |w| weld_edges(w, inner, border),
        );
        // Both sides of a lone quad: the quad would hold the merged vertices twice.
        let (mut world, built) = build(&shapes::quad_grid(1, 1));
        let (left, right) = (edge(&world, &built, 0, 2), edge(&world, &built, 1, 3));
        let quad = MeshRef::new(&world).face(MeshRef::new(&world).edge_halfedge(left));
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::DegenerateFace(ElementId::Face(quad.unwrap())),
            |w| weld_edges(w, left, right),
        );
        // The ends of a strip of two quads: the rims would be loops of two sides (both merged
        // corners joined to the middle vertex).
        let (mut world, built) = build(&shapes::quad_grid(2, 1));
        let (left, right) = (edge(&world, &built, 0, 3), edge(&world, &built, 2, 5));
        assert_refused_like(
            &mut world,
            built.mesh,
            |r| matches!(r, Refusal::WouldDuplicateEdge(..)),
            |w| weld_edges(w, left, right),
        );
    }

    #[test]
    fn merged_vertices_average_their_attributes_and_corners_keep_their_uvs() {
        let (mut world, built) = build(&with_attributes(two_squares(), Uvs::Continuous));
        let before = faces(&world, built.mesh);
        let (e1, e2) = (edge(&world, &built, 1, 2), edge(&world, &built, 4, 7));
        weld_edges(&mut world, e1, e2).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_attributes_complete(&world, built.mesh);
        // Colours are (60 x, 60 y, 7): (1, 0) and (2, 0) average to (90, 0, 7).
        let a = vertex(&built, 1);
        assert_eq!(world.get::<VertexColor>(a.0).unwrap().0, [90, 0, 7]);
        // Corners keep their UVs, 2 (x, y) + (1, 0) of where they were: the corner at 1 in
        // the first square, at 4 in the second (both merged into 1, at (1.5, 0)); 7 merged
        // into 2, so the second square's side 7 4 is now 2 → 1.
        let m = MeshRef::new(&world);
        for (i, j, x) in [(0, 1, 1.0), (2, 1, 2.0)] {
            let h = m
                .find_halfedge(vertex(&built, i), vertex(&built, j))
                .unwrap();
            let uv = world
                .get::<crate::mesh::attributes::CornerUv>(h.0)
                .unwrap()
                .0;
            assert_eq!(uv, bevy::math::Vec2::new(2.0 * x + 1.0, 0.0), "{i} {j}");
        }
        assert_eq!(faces(&world, built.mesh).len(), before.len());
    }

    #[test]
    fn undo_and_redo_restore_both_meshes() {
        let (mut world, built) = build(&with_attributes(two_squares(), Uvs::Continuous));
        let plan = plan_weld(
            &world,
            edge(&world, &built, 1, 2),
            edge(&world, &built, 4, 7),
        )
        .unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, built.mesh, &seeds, |w| {
            apply_weld(w, plan);
        });
        let (mut world, built) = build(&with_attributes(
            shapes::triangle_fan(3, false),
            Uvs::Continuous,
        ));
        let plan = plan_weld(
            &world,
            edge(&world, &built, 0, 4),
            edge(&world, &built, 0, 1),
        )
        .unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, built.mesh, &seeds, |w| {
            apply_weld(w, plan);
        });
    }
}
