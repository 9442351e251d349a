//! Step 4 of an iteration (Botsch & Kobbelt 2004's tangential relaxation), and the moves of
//! the corners of thin triangles after the last iteration.
//!
//! [`Smoother`] moves every free vertex (off the boundary and off the features) 1/5 of the way
//! to the centroid of its triangles' centres weighted by their areas, within its tangent plane,
//! all new positions from the old ones (Jacobi), and [`project`] puts it back onto the input
//! after the last step; vertices on features and the boundary never move. That centroid is the
//! centre of mass of the vertex's fan, so each step is a damped step of Lloyd's iteration with
//! the fan standing for the vertex's Voronoi cell (Du, Faber & Gunzburger, "Centroidal Voronoi
//! Tessellations", SIAM Review 1999): it spreads the vertices by the surface they stand for
//! rather than by their neighbours. On the bunny 84.0 % of the interior vertices have valence 6
//! against 83.4 % with the neighbours' mean (`docs/performance.md`).
//!
//! [`relax_thin_corners`] then moves, one by one, the corners of the triangles still thin to
//! the candidate point that most raises the smallest angle around them: a free corner within
//! its tangent plane and back onto the input, a corner on a straight feature line or boundary
//! along that line, so the line keeps its shape; feature corners and pinned vertices stay.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, MeshId, VertexId};
use crate::mesh::stats::{THIN_ANGLE_DEG, min_corner_angle_deg};
use crate::mesh::tables::NONE;
use crate::mesh::tables::{MeshTables, extract};
use crate::mesh::topology::MeshRef;

use super::distance_to_segment;
use crate::ops::geometry::closest::Reference;
use crate::ops::parallel::in_parallel;

/// The free vertices' one-rings and fans as flat arrays. Smoothing takes many steps over one
/// connectivity, so the world is read once before them and written once after, and each step
/// is plain array arithmetic (Jacobi: every new position from the old ones).
pub(super) struct Smoother {
    vertices: Vec<VertexId>,
    positions: Vec<Vec3>,
    next: Vec<Vec3>,
    /// Indices (into `vertices`) of the vertices that move: not on the boundary or a feature.
    free: Vec<u32>,
    /// For free vertex `k`, its neighbours are `ring[ring_start[k]..ring_start[k + 1]]`.
    ring_start: Vec<u32>,
    ring: Vec<u32>,
    /// For free vertex `k`, its triangles are `fan[fan_start[k]..fan_start[k + 1]]`.
    fan_start: Vec<u32>,
    fan: Vec<[u32; 3]>,
    /// By free vertex, its next position (a step's scratch).
    targets: Vec<Vec3>,
}

impl Smoother {
    /// The free vertices of `mesh` (off the boundary and off `features`), read once.
    pub(super) fn new(world: &World, mesh: MeshId, features: &EntityHashSet) -> Self {
        // The flat tables (one pass over the world) are much cheaper to walk than the
        // entities, and each iteration walks every one-ring.
        let MeshTables { tables: t, members } = extract(world, mesh);
        let feature: Vec<bool> = members
            .edges
            .iter()
            .map(|e| features.contains(&e.0))
            .collect();
        let mut s = Smoother {
            next: t.positions.clone(),
            positions: t.positions.clone(),
            free: Vec::new(),
            ring_start: vec![0],
            ring: Vec::new(),
            fan_start: vec![0],
            fan: Vec::new(),
            targets: Vec::new(),
            vertices: members.vertices,
        };
        let mut outgoing = Vec::new();
        for (v, &first) in t.vertex_halfedge.iter().enumerate() {
            // A boundary vertex's halfedge is its boundary one.
            if t.face[first as usize] == NONE {
                continue;
            }
            outgoing.clear();
            outgoing.extend(t.outgoing(v as u32));
            if outgoing
                .iter()
                .any(|&h| feature[t.edge[h as usize] as usize])
            {
                continue;
            }
            s.free.push(v as u32);
            for &h in &outgoing {
                let h = h as usize;
                s.ring.push(t.to_vertex[h]);
                s.fan
                    .push([v as u32, t.to_vertex[h], t.to_vertex[t.next[h] as usize]]);
            }
            s.ring_start.push(s.ring.len() as u32);
            s.fan_start.push(s.fan.len() as u32);
        }
        s
    }

    /// Moves every free vertex 1/5 of the way to the centroid of its triangles' centres
    /// weighted by their areas, within its tangent plane (the normal: the sum of its
    /// triangles' area vectors); to its neighbours' mean where its triangles have no area.
    pub(super) fn step(&mut self) {
        let p = &self.positions;
        let mut targets = std::mem::take(&mut self.targets);
        targets.resize(self.free.len(), Vec3::ZERO);
        // Each target is computed from the old positions alone (Jacobi), so the cores may
        // share the vertices out in any way.
        in_parallel(&mut targets, |k, target| {
            let i = self.free[k];
            let ring = &self.ring[self.ring_start[k] as usize..self.ring_start[k + 1] as usize];
            let fan = &self.fan[self.fan_start[k] as usize..self.fan_start[k + 1] as usize];
            let here = p[i as usize];
            // The fan's area vectors: their sum is the normal, their lengths weigh the
            // triangles' centres.
            let (mut normal, mut weighted, mut area) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
            for t in fan {
                let [a, b, c] = t.map(|j| p[j as usize]);
                let n = (b - a).cross(c - a);
                normal += n;
                weighted += (a + b + c) / 3.0 * n.length();
                area += n.length();
            }
            let centroid = if area > 0.0 {
                weighted / area
            } else {
                ring.iter().map(|&j| p[j as usize]).sum::<Vec3>() / ring.len() as f32
            };
            let normal = normal.normalize_or_zero();
            let step = centroid - here;
            *target = here + 0.2 * (step - normal * normal.dot(step));
        });
        for (&i, &target) in self.free.iter().zip(&targets) {
            self.next[i as usize] = target;
        }
        self.targets = targets;
        // Every free vertex is rewritten each step and the others never move, so swapping
        // leaves both buffers right.
        std::mem::swap(&mut self.positions, &mut self.next);
    }

    /// Writes the free vertices' positions into the world. Returns the free vertices, and
    /// those of them whose position changed.
    pub(super) fn write(self, world: &mut World) -> Relaxed {
        let mut relaxed = Relaxed {
            free: Vec::with_capacity(self.free.len()),
            moved: Vec::new(),
        };
        for &i in &self.free {
            let v = self.vertices[i as usize];
            if let Some(mut position) = world.get_mut::<crate::mesh::Position>(v.0) {
                let to = self.positions[i as usize];
                if bits(position.0) != bits(to) {
                    relaxed.moved.push(v);
                }
                position.0 = to;
            }
            relaxed.free.push(v);
        }
        relaxed
    }
}

/// What [`Smoother::write`] wrote.
pub(super) struct Relaxed {
    /// The vertices the smoothing may move (off the boundary and the features), for
    /// [`project`].
    pub free: Vec<VertexId>,
    /// Those whose position changed.
    pub moved: Vec<VertexId>,
}

/// Moves each of `vertices` to its closest point on `reference` (the projection after the
/// relaxation: one search of the input's triangles a vertex, the expensive part, so it is done
/// once an iteration, after the last smoothing step). Stale ids are skipped. Returns the
/// vertices that moved.
///
/// Projecting after [`Smoother::write`] gives the same bits as projecting inside the last step:
/// the steps are Jacobi, so no vertex's projection feeds another's step.
pub(super) fn project(
    world: &mut World,
    vertices: &[VertexId],
    reference: &Reference,
) -> Vec<VertexId> {
    let mut q = world.query::<&crate::mesh::Position>();
    let mut at: Vec<Option<(Vec3, Vec3)>> = vertices
        .iter()
        .map(|&v| q.get(world, v.0).ok().map(|p| (p.0, p.0)))
        .collect();
    // One search a vertex, each on its own: shared out over the cores.
    in_parallel(&mut at, |_, slot| {
        if let Some((from, to)) = slot {
            *to = reference.closest(*from);
        }
    });
    let mut moved = Vec::new();
    let mut q = world.query::<&mut crate::mesh::Position>();
    for (&v, slot) in vertices.iter().zip(at) {
        if let Some((from, to)) = slot
            && let Ok(mut position) = q.get_mut(world, v.0)
        {
            if bits(from) != bits(to) {
                moved.push(v);
            }
            position.0 = to;
        }
    }
    moved
}

/// `p` as bits: a vertex moved when any bit of its position changed.
fn bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// How far along the way to its one-ring centroid a thin triangle's free corner is tried, in
/// fractions of the way (beyond 1: past the centroid).
const RELAX_STEPS: [f32; 6] = [0.25, 0.5, 0.75, 1.0, 1.25, 1.5];

/// The circles, in fractions of its mean spoke length, on which a thin triangle's free corner
/// also tries twelve points around where it is.
const RELAX_AROUND: [f32; 3] = [0.1, 0.2, 0.3];

/// How far along each of its two feature edges a thin triangle's corner on a straight feature
/// line is tried, in fractions of the edge.
const RELAX_SLIDE: [f32; 4] = [0.1, 0.2, 0.3, 0.4];

/// Moves the ends of `edges` that have a thin triangle around them to where their triangles
/// are best shaped: of the candidate points, the one that most raises the smallest angle of
/// the vertex's triangles, none of which may turn by more than 60° (a fold has angles too).
///
/// - A free vertex (on no feature and off the boundary) tries the points on the way to its
///   one-ring centroid ([`RELAX_STEPS`]) and around it ([`RELAX_AROUND`]), within its tangent
///   plane, each projected onto `reference`.
/// - A vertex on a feature line or the boundary (two feature edges) slides along one of them
///   ([`RELAX_SLIDE`]), only where the line is straight to within `tolerance` there: the line
///   keeps its shape, as in the collapse pass ([`super::collapse`]).
/// - A feature corner stays, and so does a vertex in `pinned` (a tip [`super::finish::restore_tips`] put
///   back).
///
/// Vertex by vertex, each seeing the moves before it. Returns the edges of the triangles
/// around the vertices that moved.
pub(super) fn relax_thin_corners(
    world: &mut World,
    edges: &[EdgeId],
    features: &EntityHashSet,
    pinned: &EntityHashSet,
    reference: &Reference,
    tolerance: f32,
) -> Vec<EdgeId> {
    let limit = 60f32.to_radians().cos();
    let m = MeshRef::new(world);
    let mut corners: Vec<VertexId> = edges
        .iter()
        .filter(|&&e| m.try_edge(e).is_some())
        .flat_map(|&e| <[VertexId; 2]>::from(m.edge_vertices(e)))
        .collect();
    corners.retain(|v| !pinned.contains(&v.0));
    corners.sort_unstable();
    corners.dedup();
    let mut touched = Vec::new();
    for v in corners {
        let m = MeshRef::new(world);
        let here = m.position(v);
        // The triangles around `v`: the far side of each, from the spoke's tip on.
        let fan: Vec<[Vec3; 2]> = m
            .vertex_outgoing(v)
            .filter(|&h| m.face(h).is_some())
            .map(|h| [m.to_vertex(h), m.to_vertex(m.next(h))].map(|x| m.position(x)))
            .collect();
        let area = |at: Vec3, [b, c]: [Vec3; 2]| (b - at).cross(c - at);
        // The smallest angle of the fan with `v` at `at`, or `None` if a triangle would turn
        // too far.
        let smallest = |at: Vec3| {
            fan.iter().try_fold(f64::INFINITY, |min, &[b, c]| {
                let (before, after) = (area(here, [b, c]), area(at, [b, c]));
                let turned = before.normalize_or_zero().dot(after.normalize_or_zero());
                (turned >= limit).then(|| min.min(min_corner_angle_deg(&[at, b, c])))
            })
        };
        let Some(before) = smallest(here).filter(|&a| a < THIN_ANGLE_DEG) else {
            continue;
        };
        let along: Vec<Vec3> = m
            .vertex_outgoing(v)
            .filter(|&h| features.contains(&m.edge(h).0))
            .map(|h| m.position(m.to_vertex(h)))
            .collect();
        let candidates: Vec<Vec3> = match along[..] {
            [] if !fan.is_empty() && !m.is_boundary_vertex(v) => {
                let spokes = fan.iter().map(|&[b, _]| b);
                let centroid = spokes.clone().sum::<Vec3>() / fan.len() as f32;
                let reach = spokes.map(|b| b.distance(here)).sum::<f32>() / fan.len() as f32;
                let normal = fan
                    .iter()
                    .map(|&t| area(here, t))
                    .sum::<Vec3>()
                    .normalize_or_zero();
                let (u, w) = normal.any_orthonormal_pair();
                let step = centroid - here;
                let on_the_way = RELAX_STEPS.map(|t| t * (step - normal * normal.dot(step)));
                let around = RELAX_AROUND.iter().flat_map(|&r| {
                    (0..12).map(move |k| {
                        let turn = k as f32 * std::f32::consts::TAU / 12.0;
                        r * reach * (turn.cos() * u + turn.sin() * w)
                    })
                });
                on_the_way
                    .into_iter()
                    .chain(around)
                    .map(|d| reference.closest(here + d))
                    .collect()
            }
            [p, q] if distance_to_segment(here, p, q) <= tolerance => [p, q]
                .iter()
                .flat_map(|&end| RELAX_SLIDE.map(|t| here + t * (end - here)))
                .collect(),
            _ => continue,
        };
        let best = candidates
            .into_iter()
            .filter_map(|at| smallest(at).map(|angle| (angle, at)))
            .filter(|&(angle, _)| angle > before)
            .max_by(|x, y| x.0.total_cmp(&y.0));
        let Some((_, at)) = best else { continue };
        touched.extend(
            m.vertex_outgoing(v)
                .flat_map(|h| [m.edge(h), m.edge(m.next(h))]),
        );
        if let Some(mut position) = world.get_mut::<crate::mesh::Position>(v.0) {
            position.0 = at;
        }
    }
    touched.sort_unstable();
    touched.dedup();
    touched
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::members::MeshMembers;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh};
    use crate::ops::remesh::flip::thin_triangle_edges;

    /// A regular hexagon fanned around a centre at `centre`, in the plane z = 0: the world,
    /// the mesh and the centre vertex.
    fn hexagon_fan(centre: Vec3) -> (World, MeshId, VertexId) {
        let mut points: Vec<Vec3> = (0..6)
            .map(|k| {
                let angle = k as f32 * std::f32::consts::TAU / 6.0;
                Vec3::new(angle.cos(), angle.sin(), 0.0)
            })
            .collect();
        points.push(centre);
        let faces: Vec<[u32; 3]> = (0..6).map(|k| [6, k, (k + 1) % 6]).collect();
        let soup = PolygonSoup::from_faces(points, &faces);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let centre = built.input_vertices[6].unwrap();
        (world, built.mesh, centre)
    }

    /// One round of [`relax_thin_corners`] over `mesh`'s thin triangles, with `features`,
    /// nothing pinned, the mesh itself as the input and lines straight to within 0.05: the
    /// edges it touched.
    fn relax_once(world: &mut World, mesh: MeshId, features: &EntityHashSet) -> Vec<EdgeId> {
        let reference = Reference::new(&MeshRef::new(world), &MeshMembers::collect(world, mesh));
        let edges = thin_triangle_edges(world, mesh);
        let pinned = EntityHashSet::default();
        relax_thin_corners(world, &edges, features, &pinned, &reference, 0.05)
    }

    #[test]
    fn a_thin_triangles_free_corner_moves_to_where_its_triangles_are_best_shaped() {
        // Pushed 4/5 of the way to a rim vertex, the centre leaves two triangles thin; the
        // best point on the way back to the ring's centroid is the centroid itself, where
        // every angle is 60°, and it stays on the input surface (the plane).
        let (mut world, mesh, centre) = hexagon_fan(Vec3::new(0.8, 0.0, 0.0));
        let touched = relax_once(&mut world, mesh, &EntityHashSet::default());
        // The six spokes and the six rim edges around the centre.
        assert_eq!(touched.len(), 12);
        let m = MeshRef::new(&world);
        let at = m.position(centre);
        assert!(at.length() < 1e-5, "{at}");
        assert!(thin_triangle_edges(&world, mesh).is_empty());
        crate::mesh::validate(&world, mesh).unwrap();

        // On a feature, the same centre stays where it is.
        let (mut world, mesh, centre) = hexagon_fan(Vec3::new(0.8, 0.0, 0.0));
        let m = MeshRef::new(&world);
        let spoke: EntityHashSet = [m.edge(m.vertex_halfedge(centre)).0].into_iter().collect();
        assert!(relax_once(&mut world, mesh, &spoke).is_empty());
        assert_eq!(
            MeshRef::new(&world).position(centre),
            Vec3::new(0.8, 0.0, 0.0)
        );
    }

    /// The triangles (0, 0) `corner` (1, 1) and `corner` (2, 0) (1, 1), with the boundary edges
    /// as the features: the world, the mesh, the corner vertex and the features.
    fn boundary_corner(corner: Vec3) -> (World, MeshId, VertexId, EntityHashSet) {
        let points = vec![
            Vec3::ZERO,
            corner,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let soup = PolygonSoup::from_faces(points, &[[0, 1, 3], [1, 2, 3]]);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, built.mesh);
        let m = MeshRef::new(&world);
        let boundary: EntityHashSet = members
            .edges
            .iter()
            .filter(|&&e| m.is_boundary_edge(e))
            .map(|e| e.0)
            .collect();
        let corner = built.input_vertices[1].unwrap();
        (world, built.mesh, corner, boundary)
    }

    #[test]
    fn a_thin_triangles_corner_on_a_straight_boundary_slides_along_it() {
        // The boundary runs straight from (0, 0) through (0.2, 0) to (2, 0); the apex (1, 1)
        // sees the first side at under 10°.
        let (mut world, mesh, corner, boundary) = boundary_corner(Vec3::new(0.2, 0.0, 0.0));
        let touched = relax_once(&mut world, mesh, &boundary);
        assert!(!touched.is_empty());
        let at = MeshRef::new(&world).position(corner);
        // Along the line towards (2, 0), and the line stays straight.
        assert_eq!(at.y, 0.0);
        assert!(at.x > 0.2, "{at}");
        assert!(thin_triangle_edges(&world, mesh).is_empty());

        // Bent by more than the tolerance there, the line holds the vertex where it is.
        let (mut world, mesh, corner, boundary) = boundary_corner(Vec3::new(0.2, -0.1, 0.0));
        assert!(relax_once(&mut world, mesh, &boundary).is_empty());
        assert_eq!(
            MeshRef::new(&world).position(corner),
            Vec3::new(0.2, -0.1, 0.0)
        );
    }
}
