//! The finishing passes after the last iteration of Botsch & Kobbelt 2004's loop: the detail
//! that triangles of the target length cannot follow is put back, then the thin triangles left
//! by the smoothing are cleaned up.
//!
//! - Where the remesh strays from the input by more than [`DETAIL_TOLERANCE`] · L, the input's
//!   vertices left that far off (the tips of spikes and folds), and the centres of its
//!   triangles coarser than the remesh ([`detail_points`]), become vertices again
//!   ([`restore_tips`]), and the edges that far off at their middle or a quarter or eighth of
//!   the way along (bridging a groove) are split onto the input ([`fill_grooves`]). Each
//!   split ([`split_onto`]) happens only where the new triangles lie no farther from the input
//!   than the gap it closes, turn by at most 60° and keep every angle over 1°; features and
//!   the boundary are not split.
//! - Then, for a bounded number of rounds ([`clean_up_thin`]), the sides of triangles with an
//!   angle under 30° are flipped where that makes the pair less thin and bridges no groove
//!   (the new edge's middle within the tolerance of the input), and the corners of the
//!   triangles still thin move to where their triangles are best shaped. A restored tip is
//!   pinned: nothing flips at it or moves it.
//! - Last, the vertices are fitted to the input
//!   ([`surface_fit`](crate::ops::geometry::surface_fit)), and the corners nearest the input's
//!   points still farthest off are pulled towards them ([`far_spots`](super::far_spots)).

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, HalfedgeId, MeshId, VertexId};
use crate::mesh::stats::min_corner_angle_deg;
use crate::mesh::tables::{Connectivity, MeshTables, extract};
use crate::mesh::topology::MeshRef;
use crate::ops::local::split_edge;

use super::distance_to_segment;
use super::flip::{Fidelity, flip_thin, quad_corners, thin_triangle_edges};
use super::relax::relax_thin_corners;
use crate::ops::geometry::closest::Reference;
use crate::ops::parallel::in_parallel;

/// How far from the input (times the target length) the finished remesh may leave an input
/// vertex or the middle of one of its edges before [`restore_tips`] and [`fill_grooves`] put
/// the detail back. Smaller tolerances insert more vertices without bringing the remesh closer
/// to the input (the measurements are in `docs/remesh.md`).
pub(super) const DETAIL_TOLERANCE: f32 = 0.2;

/// Where along an edge [`fill_grooves`] measures the remesh's distance from the input: the
/// middle, the quarters and the eighths between (the farthest wins, the middle on a tie). An
/// edge may cross a groove off its middle: on the bunny, one whose middle lay 0.19 L from the
/// input had a point 0.25 L off a quarter of the way along.
const GROOVE_SAMPLES: [f32; 5] = [0.5, 0.25, 0.75, 0.375, 0.625];

/// The most rounds of moving the corners of thin triangles after the last iteration (see the
/// module doc); each round moves fewer corners than the one before, and more rounds left no
/// fewer thin triangles (`docs/remesh.md`).
const THIN_ROUNDS: usize = 3;

/// An input triangle whose longest side is more than this many target lengths is coarser
/// than the remesh: its corners alone do not say where the input lies, and its centre is put
/// back like a vertex ([`detail_points`]). On the bunny remeshed at 0.995 of its mean edge
/// length, one such triangle (sides 1.3, 2.1 and 2.9 L, folded 58° against its neighbours)
/// had all three corners on the remesh and its middle 0.199 % of the diagonal off it. At 1.5
/// the same, at 3 that triangle is missed; every centre, whatever its triangle's size, took
/// spot, the ogre and homer farther (`docs/performance.md`).
pub(super) const COARSE_TRIANGLE: f32 = 2.0;

/// The input's points [`restore_tips`] may put back, for a remesh to `length`: its vertices
/// off the boundary (the first `.1` of them), then the centres of its triangles whose
/// longest side exceeds [`COARSE_TRIANGLE`] · `length`.
pub(super) fn detail_points(t: &Connectivity, length: f32) -> (Vec<Vec3>, usize) {
    let mut points: Vec<Vec3> = t
        .vertices()
        .filter(|&v| !t.is_boundary_vertex(v))
        .map(|v| t.position(v))
        .collect();
    let vertices = points.len();
    points.extend(t.faces().filter_map(|f| {
        let [a, b, c] = t.triangle_corners(f);
        let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
        (longest > COARSE_TRIANGLE * length).then(|| (a + b + c) / 3.0)
    }));
    (points, vertices)
}

/// Puts back the input's vertices that the remesh left farther than `tolerance` from its
/// surface: the tips of spikes and folds narrower than `length`, which triangles of that size
/// cut off. For each, farthest first, a side of the nearest remesh triangle or of the
/// triangles beside it (not a feature or the boundary; the side nearest the tip that fits) is
/// split onto it ([`split_onto`]). One tip per `length` of surface (the surface has changed
/// around a tip put back). Returns the new vertices, which nothing moves after.
pub(super) fn restore_tips(
    world: &mut World,
    mesh: MeshId,
    tips: &[Vec3],
    input: &Reference,
    features: &EntityHashSet,
    length: f32,
    tolerance: f32,
) -> EntityHashSet {
    let MeshTables { tables: t, members } = extract(world, mesh);
    let far = farther_than(&t, tips, tolerance);
    let mut restored: Vec<Vec3> = Vec::new();
    let mut pinned = EntityHashSet::default();
    for (gap, tip, row) in far {
        if restored.iter().any(|r| r.distance(tip) < length) {
            continue;
        }
        let m = MeshRef::new(world);
        // The sides of the nearest triangle and of the triangles beside it, nearest first.
        let h = m.face_halfedge(members.faces[row]);
        let mut sides: Vec<(f32, HalfedgeId)> = [h, m.next(h), m.prev(h)]
            .into_iter()
            .flat_map(|x| {
                let y = m.twin(x);
                [x, m.next(y), m.prev(y)]
            })
            .filter(|&x| m.face(x).is_some() && splittable(&m, x, features))
            .map(|x| {
                let [a, b, ..] = quad_corners(&m, x);
                (distance_to_segment(tip, a, b), x)
            })
            .collect();
        sides.sort_by(|x, y| x.0.total_cmp(&y.0));
        if let Some(v) = sides
            .into_iter()
            .find_map(|(_, x)| split_onto(world, x, tip, input, gap))
        {
            pinned.insert(v.0);
            restored.push(tip);
        }
    }
    pinned
}

/// The `points` that the triangle mesh in `t` leaves farther than `distance` from it, farthest
/// first (in the points' order among equals), each with its distance and the row of the face
/// nearest it.
pub(super) fn farther_than(
    t: &Connectivity,
    points: &[Vec3],
    distance: f32,
) -> Vec<(f32, Vec3, usize)> {
    let surface = Reference::from_triangles(t.faces().map(|f| t.triangle_corners(f)).collect());
    // One search a point, each on its own: shared out over the cores.
    let mut found: Vec<Option<(f32, Vec3, usize)>> = vec![None; points.len()];
    in_parallel(&mut found, |i, slot| {
        let p = points[i];
        if !surface.is_near(p, distance) {
            let (q, row) = surface.closest_on(p);
            let d = q.distance(p);
            *slot = (d > distance).then_some((d, p, row));
        }
    });
    let mut far: Vec<(f32, Vec3, usize)> = found.into_iter().flatten().collect();
    far.sort_by(|a, b| b.0.total_cmp(&a.0));
    far
}

/// Splits the edges that the remesh left farther than `tolerance` from the input at one of
/// [`GROOVE_SAMPLES`] (where a groove, or the foot of a spike, narrower than the triangles is
/// bridged), farthest first, at the input's closest point to their farthest sample
/// ([`split_onto`]); features and the boundary are left alone. Returns the new vertices.
pub(super) fn fill_grooves(
    world: &mut World,
    mesh: MeshId,
    input: &Reference,
    features: &EntityHashSet,
    tolerance: f32,
) -> Vec<VertexId> {
    let MeshTables { tables: t, members } = extract(world, mesh);
    let at = |h: u32| t.positions[t.to_vertex[h as usize] as usize];
    // One search an edge, each on its own: shared out over the cores.
    let mut found: Vec<Option<(f32, EdgeId, Vec3)>> = vec![None; members.edges.len()];
    in_parallel(&mut found, |i, slot| {
        let h = t.edge_halfedge[i];
        let (a, b) = (at(h), at(t.twin[h as usize]));
        for along in GROOVE_SAMPLES {
            let p = a.lerp(b, along);
            if input.is_near(p, tolerance) {
                continue;
            }
            let q = input.closest(p);
            let d = q.distance(p);
            if d > tolerance && slot.is_none_or(|(farthest, ..)| farthest < d) {
                *slot = Some((d, members.edges[i], q));
            }
        }
    });
    let mut far: Vec<(f32, EdgeId, Vec3)> = found.into_iter().flatten().collect();
    far.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut added = Vec::new();
    for (gap, e, q) in far {
        let m = MeshRef::new(world);
        if m.try_edge(e).is_none() {
            continue;
        }
        let h = m.edge_halfedge(e);
        if splittable(&m, h, features) {
            added.extend(split_onto(world, h, q, input, gap));
        }
    }
    added
}

/// The thin-triangle clean-up, after the detail is put back: the sides of the triangles with an
/// angle under [`THIN_ANGLE_DEG`](crate::mesh::stats::THIN_ANGLE_DEG) are flipped
/// ([`flip_thin`]); then, for up to [`THIN_ROUNDS`] rounds, the corners of the triangles still
/// thin move ([`relax_thin_corners`], a feature line counting as straight to within
/// `tolerance`) and the edges around the corners that moved get the same flips, until a round
/// moves none. No flip takes an edge's middle farther than `detail` from the input unless the
/// old edge's already was ([`Fidelity`]). Nothing `pinned` moves or flips. Returns the flipped
/// edges, one entry a flip (an edge flipped in two rounds is listed twice).
pub(super) fn clean_up_thin(
    world: &mut World,
    mesh: MeshId,
    features: &EntityHashSet,
    pinned: &EntityHashSet,
    reference: &Reference,
    tolerance: f32,
    detail: f32,
) -> Vec<EdgeId> {
    let fidelity = Fidelity {
        input: reference,
        tolerance: detail,
    };
    let mut edges = thin_triangle_edges(world, mesh);
    let mut flipped = flip_thin(world, &edges, features, pinned, &fidelity);
    for _ in 0..THIN_ROUNDS {
        edges = relax_thin_corners(world, &edges, features, pinned, reference, tolerance);
        if edges.is_empty() {
            break;
        }
        flipped.extend(flip_thin(world, &edges, features, pinned, &fidelity));
    }
    flipped
}

/// Whether the edge of `h` may be split off its line: not a feature, not on the boundary.
fn splittable(m: &MeshRef<'_>, h: HalfedgeId, features: &EntityHashSet) -> bool {
    let e = m.edge(h);
    !features.contains(&e.0) && !m.is_boundary_edge(e)
}

/// Splits the edge of `h` (between triangles a b c and b a d) and moves the new vertex to
/// `to`, if none of the four triangles around it turns by more than 60° from the one it
/// replaces or gets an angle under 1°, and the middles of their sides and the triangles lie
/// within `bound` of the input (the gap being closed: a split must not open a wider one
/// beside it). Returns the new vertex.
fn split_onto(
    world: &mut World,
    h: HalfedgeId,
    to: Vec3,
    input: &Reference,
    bound: f32,
) -> Option<VertexId> {
    let m = MeshRef::new(world);
    let [a, b, c, d] = quad_corners(&m, h);
    let limit = 60f32.to_radians().cos();
    let before = [(b - a).cross(c - a), (a - b).cross(d - b)];
    let after = [
        ([a, to, c], 0),
        ([to, b, c], 0),
        ([b, to, d], 1),
        ([to, a, d], 1),
    ];
    let fits = after.iter().all(|&([p, q, r], side)| {
        let n = (q - p).cross(r - p);
        n.normalize_or_zero().dot(before[side].normalize_or_zero()) >= limit
            && min_corner_angle_deg(&[p, q, r]) >= 1.0
            && [
                (p + q + r) / 3.0,
                (p + q) / 2.0,
                (q + r) / 2.0,
                (r + p) / 2.0,
            ]
            .into_iter()
            .all(|x| input.distance(x) <= bound)
    });
    if !fits {
        return None;
    }
    let along = b - a;
    let t = ((to - a).dot(along) / along.length_squared().max(f32::MIN_POSITIVE)).clamp(0.1, 0.9);
    let e = m.edge(h);
    let t = if m.edge_halfedge(e) == h { t } else { 1.0 - t };
    let v = split_edge(world, e, t).ok()?;
    if let Some(mut position) = world.get_mut::<crate::mesh::Position>(v.0) {
        position.0 = to;
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::members::MeshMembers;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh};

    /// The square (±1, ±1, 0) as two triangles split along the diagonal from (−1, −1) to
    /// (1, 1) (the "remesh"), and `input`'s triangles as a second mesh of the same world, with
    /// a reference to them.
    fn square_over(input: PolygonSoup) -> (World, MeshId, Reference) {
        let corners = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let square = PolygonSoup::from_faces(corners, &[[0, 2, 1], [1, 3, 0]]);
        let mut world = World::new();
        let remesh = build_mesh(&mut world, &square, MeshInfo::default()).unwrap();
        let input = build_mesh(&mut world, &input, MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, input.mesh);
        let reference = Reference::new(&MeshRef::new(&world), &members);
        (world, remesh.mesh, reference)
    }

    /// The mesh's vertex count and whether one of its vertices is at `p`.
    fn has_vertex_at(world: &World, mesh: MeshId, p: Vec3) -> (usize, bool) {
        let members = MeshMembers::collect(world, mesh);
        let m = MeshRef::new(world);
        let found = members.vertices.iter().any(|&v| m.position(v) == p);
        (members.vertices.len(), found)
    }

    /// The four sides of a pyramid over the square [-1, 1]² at z = 0, with its apex at `apex`.
    fn pyramid(apex: Vec3) -> PolygonSoup {
        PolygonSoup::from_faces(
            vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
                apex,
            ],
            &[[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
        )
    }

    #[test]
    fn a_spike_the_remesh_cut_off_is_put_back_where_it_was() {
        // A pyramid 0.5 high over the square: its apex is 0.5 off the flat remesh.
        let apex = Vec3::new(0.0, 0.0, 0.5);
        let pyramid = pyramid(apex);
        let (mut world, mesh, input) = square_over(pyramid);
        let none = EntityHashSet::default();
        // Within the tolerance, nothing happens.
        let pinned = restore_tips(&mut world, mesh, &[apex], &input, &none, 2.0, 0.6);
        assert!(pinned.is_empty());
        let pinned = restore_tips(&mut world, mesh, &[apex], &input, &none, 2.0, 0.1);
        assert_eq!(pinned.len(), 1);
        // The diagonal was split onto the apex: the remesh is now the pyramid.
        assert_eq!(has_vertex_at(&world, mesh, apex), (5, true));
        let m = MeshRef::new(&world);
        let tip = VertexId(*pinned.iter().next().unwrap());
        assert_eq!(m.position(tip), apex);
        assert_eq!(m.vertex_neighbors(tip).count(), 4);
        assert_eq!(crate::mesh::validate(&world, mesh), Ok(()));
    }

    #[test]
    fn the_centres_of_triangles_coarser_than_the_remesh_are_detail_too() {
        // The pyramid's four sides: 2 along the base, 1.5 up to the apex.
        let pyramid = pyramid(Vec3::new(0.0, 0.0, 0.5));
        let mut world = World::new();
        let built = build_mesh(&mut world, &pyramid, MeshInfo::default()).unwrap();
        let t = extract(&world, built.mesh).tables;
        // The apex is the one vertex off the boundary; at L = 1 no side passes 2 L: no centre.
        let (points, vertices) = detail_points(&t, 1.0);
        assert_eq!((points.len(), vertices), (1, 1));
        assert_eq!(points[0], Vec3::new(0.0, 0.0, 0.5));
        // At L = 0.9 every side of the base is past 2 L: the four centres follow the apex.
        let (points, vertices) = detail_points(&t, 0.9);
        assert_eq!((points.len(), vertices), (5, 1));
        let centre =
            (Vec3::new(-1.0, -1.0, 0.0) + Vec3::new(1.0, -1.0, 0.0) + Vec3::new(0.0, 0.0, 0.5))
                / 3.0;
        assert!(points[1..].contains(&centre), "{points:?}");
    }

    #[test]
    fn a_bridged_groove_gets_a_vertex_on_its_wall() {
        // A groove 0.5 deep along x = 0 under the square, which bridges it.
        let floor = |y: f32| Vec3::new(0.0, y, -0.5);
        let groove = PolygonSoup::from_faces(
            vec![
                Vec3::new(-1.0, -1.0, 0.0),
                floor(-1.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
                floor(1.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            &[[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]],
        );
        let (mut world, mesh, input) = square_over(groove);
        let none = EntityHashSet::default();
        // Only the diagonal is inside (the sides are boundary), and its middle is 0.5 · 2/√5
        // from the groove's walls.
        assert_eq!(fill_grooves(&mut world, mesh, &input, &none, 0.5), vec![]);
        let added = fill_grooves(&mut world, mesh, &input, &none, 0.1);
        assert_eq!(added.len(), 1);
        let wall = input.closest(Vec3::ZERO);
        assert_eq!(MeshRef::new(&world).position(added[0]), wall);
        assert!(
            (wall.length() - 0.5 * 2.0 / 5f32.sqrt()).abs() < 1e-6,
            "{wall}"
        );
        assert_eq!(has_vertex_at(&world, mesh, wall), (5, true));
        assert_eq!(crate::mesh::validate(&world, mesh), Ok(()));
    }
}
