//! One step of a least-squares fit of a triangle mesh to the surface it stands for.
//!
//! Hoppe et al. ("Mesh Optimization", SIGGRAPH 1993) fit a mesh to points of a surface by
//! minimising the squared distances from the points to the mesh, alternating closest points with a
//! linear least-squares solve for the vertices. Here the points are both surfaces' samples: the
//! input's points the caller names, such as its triangle centres (how far the input lies from the
//! mesh), and the mesh's edge middles with its triangle centres or its vertices (how far the mesh
//! lies from the input). Each residual is shared out to the corners of the mesh triangle it falls
//! on by its barycentric weights, and weighted by its own length, so that the far spots, which make
//! the Hausdorff distance, count the most (a step of iteratively reweighted least squares, towards
//! the largest distance rather than the mean). Each vertex then moves along its normal by the
//! weighted mean of its residuals: one Jacobi step of the normal equations. A mesh whose triangles
//! lie on one side of the input (a remesh, whose vertices are projected onto it) or whose vertices
//! stand where the quadrics put them (a simplification) comes to straddle the input instead.
//!
//! No move may turn a triangle over, nor, where the caller asks ([`FitOptions::keep_fat`]),
//! make it thin: where the moves would take a triangle's normal against what it was, or its
//! smallest angle under [`THIN_ANGLE_DEG`] and below what it was, its corner that would move
//! the most stays, until no triangle would be. Boundary vertices stay, so a boundary keeps its
//! place on the input's, and so do feature corners (where other than two feature edges meet)
//! and the vertices the caller pins; a vertex on a feature line moves as any other, across the
//! line.
//!
//! The remesh ends with it (its finish, `ops/remesh/run.rs`, the input's vertices sampled
//! besides its triangle centres). One step, not Hoppe's alternation to convergence: three
//! rounds, the closest points found anew each, moved the bunny no closer (0.121 → 0.122 % of
//! its diagonal) and the fandisk a little (0.143 → 0.135 %) at three times the cost, and with
//! the feature corners moving too the fandisk went back and forth from round to round (0.143,
//! 0.175, 0.133, 0.164 %) (`docs/performance.md`, "The remesh fitted to the input").

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use super::closest::{Reference, barycentric};
use crate::mesh::ids::MeshId;
use crate::mesh::members::MeshMembers;
use crate::mesh::stats::THIN_ANGLE_DEG;
use crate::mesh::tables::{Connectivity, MeshTables, NONE, extract};
use crate::ops::parallel::in_parallel;

/// The most times the moves are checked for thin triangles (each check keeps at least one
/// more vertex in place). Past it, nothing moves.
const THIN_CHECKS: usize = 20;

/// How much the cosine of a thin triangle's smallest angle may grow before a move counts as
/// thinning it (about a thousandth of a degree at 30°: rounding, not a change of shape).
const THINNER: f32 = 1e-5;

/// A residual shared out to the corners of a triangle of the mesh: from the mesh's point to
/// the input's, with each corner's share.
#[derive(Clone, Copy, Default)]
struct Residual {
    corners: [u32; 3],
    shares: [f32; 3],
    offset: Vec3,
}

/// Moves the vertices of `mesh` along their normals to fit `input` (see the module doc);
/// `samples` are the input's points to fit besides its triangles' centres (the run passes the
/// input's vertices off its boundary).
/// Vertices on the boundary, the corners of `features` (where other than two feature edges
/// meet) and the `pinned` tips stay. Leaves the connectivity as it was, no triangle thin that
/// was not, and none turned over.
pub(crate) fn fit_to_input(
    world: &mut World,
    mesh: MeshId,
    input: &Reference,
    samples: &[Vec3],
    features: &EntityHashSet,
    pinned: &EntityHashSet,
) {
    let MeshTables { tables: t, members } = extract(world, mesh);
    let held = held_vertices(&t, &members, features, pinned);
    let input_points: Vec<Vec3> = samples
        .iter()
        .copied()
        .chain(input.triangles().iter().map(|&[a, b, c]| (a + b + c) / 3.0))
        .collect();
    move_to_fit(world, &t, &members, input, &input_points, &held, REMESH_FIT);
}

/// Which vertex rows of the remesh in `t` (its entities `members`) stay where they are when
/// it is fitted to its input: those on the boundary, the corners of `features` (where other
/// than two feature edges meet) and the `pinned` tips. A vertex on a feature line may move.
pub(crate) fn held_vertices(
    t: &Connectivity,
    members: &MeshMembers,
    features: &EntityHashSet,
    pinned: &EntityHashSet,
) -> Vec<bool> {
    let mut feature_degree = vec![0u32; t.vertex_count()];
    for (&h, e) in t.edge_halfedge.iter().zip(&members.edges) {
        if features.contains(&e.0) {
            for end in [h, t.twin[h as usize]] {
                feature_degree[t.to_vertex[end as usize] as usize] += 1;
            }
        }
    }
    (0..t.vertex_count())
        .map(|v| {
            t.face[t.vertex_halfedge[v] as usize] == NONE
                || !matches!(feature_degree[v], 0 | 2)
                || pinned.contains(&members.vertices[v].0)
        })
        .collect()
}

/// Moves the vertices of the triangle mesh read into `t` (its entities `members`) along their
/// normals to fit `input`, measuring `input_points` (the input's points, such as its triangle
/// centres) to the mesh, as `options` say; the `held` rows stay. Leaves the connectivity as it
/// was, no triangle turned over, and with [`FitOptions::keep_fat`] no triangle thin that was
/// not.
pub(crate) fn move_to_fit(
    world: &mut World,
    t: &Connectivity,
    members: &MeshMembers,
    input: &Reference,
    input_points: &[Vec3],
    held: &[bool],
    options: FitOptions,
) {
    let elements = FitElements::of_tables(t, members, held);
    apply_moves(world, &elements.fitted_moves(input, input_points, options));
}

/// Moves each vertex by its move, as [`FitElements::fitted_moves`] lists them; a vertex no
/// longer in `world` is passed over.
pub(crate) fn apply_moves(world: &mut World, moves: &[(Entity, Vec3)]) {
    let mut q = world.query::<&mut crate::mesh::Position>();
    for &(v, m) in moves {
        if let Ok(mut position) = q.get_mut(world, v) {
            position.0 += m;
        }
    }
}

/// A triangle mesh's elements as the fit takes them, each with its entity (which orders them
/// where [`FitOptions::entity_order`] asks): its vertices, its triangles' corners (from the
/// face's halfedge on, counter-clockwise) and its edges' ends (the tips of the edge's halfedge
/// and of its twin), as indices into the vertices. Read from a mesh's tables
/// ([`FitElements::of_tables`]), or from a simplification's rows before they are written back,
/// so that the fit's searches run beside the writing.
pub(crate) struct FitElements {
    /// Each vertex: its entity, its position, and whether it stays where it is.
    pub vertices: Vec<(Entity, Vec3, bool)>,
    /// Each triangle: its face's entity and its corners.
    pub triangles: Vec<(Entity, [u32; 3])>,
    /// Each edge: its entity and its two ends.
    pub edges: Vec<(Entity, [u32; 2])>,
}

impl FitElements {
    /// The elements of the triangle mesh read into `t` (its entities `members`), in row order;
    /// the `held` vertex rows stay.
    pub fn of_tables(t: &Connectivity, members: &MeshMembers, held: &[bool]) -> Self {
        let tip = |h: u32| t.to_vertex[h as usize];
        Self {
            vertices: (0..t.vertex_count())
                .map(|v| (members.vertices[v].0, t.positions[v], held[v]))
                .collect(),
            triangles: (t.face_halfedge.iter().zip(&members.faces))
                .map(|(&h, f)| (f.0, [h, t.next[h as usize], t.prev[h as usize]].map(tip)))
                .collect(),
            edges: (t.edge_halfedge.iter().zip(&members.edges))
                .map(|(&h, e)| (e.0, [h, t.twin[h as usize]].map(tip)))
                .collect(),
        }
    }

    /// Each vertex's move to fit `input`, measuring `input_points` to the mesh, as `options`
    /// say (see [`move_to_fit`]); the vertices that do not move are left out.
    pub fn fitted_moves(
        &self,
        input: &Reference,
        input_points: &[Vec3],
        options: FitOptions,
    ) -> Vec<(Entity, Vec3)> {
        // Each kind's rows as the fit takes them: as listed, or by entity.
        let order = |count: usize, entity: &dyn Fn(usize) -> Entity| {
            let mut rows: Vec<u32> = (0..count as u32).collect();
            if options.entity_order {
                rows.sort_unstable_by_key(|&row| entity(row as usize).to_bits());
            }
            rows
        };
        let vertex_rows = order(self.vertices.len(), &|v| self.vertices[v].0);
        let face_rows = order(self.triangles.len(), &|f| self.triangles[f].0);
        let edge_rows = order(self.edges.len(), &|e| self.edges[e].0);
        let mut rank = vec![0u32; vertex_rows.len()];
        for (k, &v) in vertex_rows.iter().enumerate() {
            rank[v as usize] = k as u32;
        }
        let ranked = |v: u32| rank[v as usize];
        let triangles: Vec<[u32; 3]> = (face_rows.iter())
            .map(|&f| self.triangles[f as usize].1.map(ranked))
            .collect();
        let edges: Vec<[u32; 2]> = (edge_rows.iter())
            .map(|&e| self.edges[e as usize].1.map(ranked))
            .collect();
        let vertex = |v: u32| self.vertices[v as usize];
        let positions: Vec<Vec3> = vertex_rows.iter().map(|&v| vertex(v).1).collect();
        let held: Vec<bool> = vertex_rows.iter().map(|&v| vertex(v).2).collect();
        let fit = FitMesh {
            positions: &positions,
            triangles: &triangles,
            edges: &edges,
            options,
        };
        let moves = fit.fitted_moves(&held, input, input_points);
        (vertex_rows.iter().zip(moves))
            .filter(|&(_, m)| m != Vec3::ZERO)
            .map(|(&v, m)| (vertex(v).0, m))
            .collect()
    }
}

/// A triangle mesh as the fit reads it: its positions, and its triangles' and edges'
/// vertices, by row.
struct FitMesh<'a> {
    /// Each vertex's position.
    positions: &'a [Vec3],
    /// Each triangle's corners, counter-clockwise.
    triangles: &'a [[u32; 3]],
    /// Each edge's two ends.
    edges: &'a [[u32; 2]],
    /// What it measures and what it keeps.
    options: FitOptions,
}

/// What a fit measures of the mesh besides its edge middles, and what its moves must keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FitOptions {
    /// Whether the mesh's triangle centres are measured to the input.
    pub centres_sampled: bool,
    /// Whether the mesh's vertices are measured to the input: not where they lie on it
    /// already (a remesh's, which the projection put there), but where they may stand off it
    /// (a simplification's, where the quadrics put them).
    pub vertices_sampled: bool,
    /// Whether no move may make a triangle thin (a remesh's, whose angles it worked for; a
    /// simplification's are as the quadrics left them, many thin already). No move turns a
    /// triangle over either way.
    pub keep_fat: bool,
    /// Whether the mesh's elements are taken in the order of their entities rather than as
    /// the tables list them (their storage order): the moves are sums, whose last bits
    /// depend on the order, and two runs that make the same mesh by other means (the stepped
    /// simplification and the one-go one) store it in different orders.
    pub entity_order: bool,
}

/// The remesh's fit: its edge middles and triangle centres measured (its vertices lie on the
/// input), and its triangles kept fat.
pub(crate) const REMESH_FIT: FitOptions = FitOptions {
    centres_sampled: true,
    vertices_sampled: false,
    keep_fat: true,
    entity_order: false,
};

impl FitMesh<'_> {
    /// The fit's move of each vertex (see the module doc), none for the `held`: along its
    /// normal, so that the mesh comes closer to `input` and to `input_points` (the input's
    /// points measured to the mesh, its triangle centres among them), none turning a triangle
    /// over nor, with [`FitOptions::keep_fat`], taking its smallest angle under
    /// [`THIN_ANGLE_DEG`] and below what it was. Leaves the mesh itself alone.
    fn fitted_moves(&self, held: &[bool], input: &Reference, input_points: &[Vec3]) -> Vec<Vec3> {
        let mut moves = self.moves(held, input, input_points);
        cancel_harmful_moves(
            self.positions,
            self.triangles,
            self.options.keep_fat,
            &mut moves,
        );
        moves
    }

    /// Each vertex's move: along its normal, by the mean of the residuals shared out to it,
    /// each weighted by its share and its length. Held vertices, those no residual reaches and
    /// those whose move is not a finite vector do not move.
    fn moves(&self, held: &[bool], input: &Reference, input_points: &[Vec3]) -> Vec<Vec3> {
        let mut pull = vec![(Vec3::ZERO, 0.0f32); self.positions.len()];
        for r in self.inward(input_points).iter().chain(&self.outward(input)) {
            let weight = r.offset.length();
            for k in 0..3 {
                let w = weight * r.shares[k];
                let slot = &mut pull[r.corners[k] as usize];
                slot.0 += r.offset * w;
                slot.1 += w;
            }
        }
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for tri in self.triangles {
            let [a, b, c] = self.corners(tri);
            let n = (b - a).cross(c - a).normalize_or_zero();
            for &v in tri {
                normals[v as usize] += n;
            }
        }
        pull.iter()
            .zip(&normals)
            .zip(held)
            .map(|((&(sum, weight), normal), &held)| {
                let n = normal.normalize_or_zero();
                let step = n * n.dot(sum / weight);
                // No residual, or none that a number can say (a degenerate triangle): no move.
                if held || weight <= 0.0 || !step.is_finite() {
                    Vec3::ZERO
                } else {
                    step
                }
            })
            .collect()
    }

    /// The corners of a triangle.
    fn corners(&self, tri: &[u32; 3]) -> [Vec3; 3] {
        tri.map(|v| self.positions[v as usize])
    }

    /// The input's points, each from its closest point on the mesh.
    fn inward(&self, input_points: &[Vec3]) -> Vec<Residual> {
        let surface =
            Reference::from_triangles(self.triangles.iter().map(|t| self.corners(t)).collect());
        let mut residuals = vec![Residual::default(); input_points.len()];
        in_parallel(&mut residuals, |i, slot| {
            let p = input_points[i];
            let (q, row) = surface.closest_on(p);
            let tri = self.triangles[row];
            // The weights as shares: summing to 1 (equal ones on a degenerate triangle).
            let weights = barycentric(q, self.corners(&tri));
            let total: f32 = weights.iter().sum();
            *slot = Residual {
                corners: tri,
                shares: weights.map(|w| w / total),
                offset: p - q,
            };
        });
        residuals
    }

    /// The mesh's edge middles, and its triangle centres and vertices as
    /// [`FitOptions`] say, each to its closest point on the input.
    fn outward(&self, input: &Reference) -> Vec<Residual> {
        let edges = self.edges.len();
        let count = |sampled: bool, n: usize| if sampled { n } else { 0 };
        let centres = count(self.options.centres_sampled, self.triangles.len());
        let vertices = count(self.options.vertices_sampled, self.positions.len());
        let mut residuals = vec![Residual::default(); edges + centres + vertices];
        in_parallel(&mut residuals, |i, slot| {
            let (corners, shares) = if i < edges {
                let [a, b] = self.edges[i];
                ([a, b, b], [0.5, 0.5, 0.0])
            } else if i < edges + centres {
                (self.triangles[i - edges], [1.0 / 3.0; 3])
            } else {
                ([(i - edges - centres) as u32; 3], [1.0, 0.0, 0.0])
            };
            let p = (0..3)
                .map(|k| self.positions[corners[k] as usize] * shares[k])
                .sum::<Vec3>();
            *slot = Residual {
                corners,
                shares,
                offset: input.closest(p) - p,
            };
        });
        residuals
    }
}

/// Cancels moves until none turns a triangle over (its normal against what it was) or, if
/// `keep_fat`, takes a triangle's smallest angle under [`THIN_ANGLE_DEG`] and below what it
/// was: in each such triangle, the move of the corner that would go farthest. Past
/// [`THIN_CHECKS`] checks, cancels every move. (Compared as cosines: the smallest angle's is
/// the largest of the three.)
fn cancel_harmful_moves(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    keep_fat: bool,
    moves: &mut [Vec3],
) {
    let thin = (THIN_ANGLE_DEG as f32).to_radians().cos();
    // The smallest angle is read only to keep triangles fat (three square roots a triangle).
    let shape = |[a, b, c]: [Vec3; 3]| {
        let cosine = if keep_fat {
            smallest_angle_cosine([a, b, c])
        } else {
            0.0
        };
        (cosine, (b - a).cross(c - a))
    };
    let before: Vec<(f32, Vec3)> = triangles
        .iter()
        .map(|tri| shape(tri.map(|v| positions[v as usize])))
        .collect();
    for _ in 0..THIN_CHECKS {
        let harmed: Vec<u32> = triangles
            .iter()
            .zip(&before)
            .filter_map(|(tri, &(was, normal))| {
                let (now, turned) = shape(tri.map(|v| positions[v as usize] + moves[v as usize]));
                let thinned = keep_fat && now > thin && now > was + THINNER;
                (thinned || turned.dot(normal) < 0.0).then(|| {
                    *tri.iter()
                        .max_by(|&&a, &&b| {
                            moves[a as usize]
                                .length_squared()
                                .total_cmp(&moves[b as usize].length_squared())
                        })
                        .expect("a triangle has three corners")
                })
            })
            .collect();
        if harmed.is_empty() {
            return;
        }
        for v in harmed {
            moves[v as usize] = Vec3::ZERO;
        }
    }
    moves.fill(Vec3::ZERO);
}

/// The cosine of a triangle's smallest angle (the largest of its corners' cosines); 1 for a
/// triangle with a side of no length.
fn smallest_angle_cosine([a, b, c]: [Vec3; 3]) -> f32 {
    let sides = [b - a, c - b, a - c].map(Vec3::normalize_or_zero);
    if sides.contains(&Vec3::ZERO) {
        return 1.0;
    }
    // The corner at a lies between the sides a → b and a → c, and so on round.
    let [ab, bc, ca] = sides;
    (-ca).dot(ab).max((-ab).dot(bc)).max((-bc).dot(ca))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::members::MeshMembers;
    use crate::mesh::topology::MeshRef;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh, shapes};

    /// `remesh` and `input` built into one world, with the input as a reference and its
    /// vertices as the samples.
    fn over(remesh: &PolygonSoup, input: &PolygonSoup) -> (World, MeshId, Reference, Vec<Vec3>) {
        let mut world = World::new();
        let remesh = build_mesh(&mut world, remesh, MeshInfo::default()).unwrap();
        let input_mesh = build_mesh(&mut world, input, MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, input_mesh.mesh);
        let reference = Reference::new(&MeshRef::new(&world), &members);
        (world, remesh.mesh, reference, input.positions.clone())
    }

    /// The positions of `mesh`'s vertices, in member order.
    fn positions(world: &World, mesh: MeshId) -> Vec<Vec3> {
        let m = MeshRef::new(world);
        let members = MeshMembers::collect(world, mesh);
        members.vertices.iter().map(|&v| m.position(v)).collect()
    }

    /// The largest distance from any of `points` to `surface`.
    fn farthest(points: &[Vec3], surface: &Reference) -> f32 {
        points
            .iter()
            .map(|&p| surface.distance(p))
            .fold(0.0, f32::max)
    }

    #[test]
    fn an_inscribed_sphere_comes_to_straddle_the_sphere() {
        // An icosphere of 80 triangles, its vertices on a sphere of 1280: every triangle lies
        // inside the finer sphere, up to the gap at its centre.
        let (coarse, fine) = (shapes::icosphere(1), shapes::icosphere(3));
        let (mut world, mesh, input, samples) = over(&coarse, &fine);
        let surface_of = |world: &World| {
            let p = positions(world, mesh);
            let triangles = coarse.faces().map(|f| [0, 1, 2].map(|k| p[f[k] as usize]));
            Reference::from_triangles(triangles.collect())
        };
        let before = farthest(&samples, &surface_of(&world));
        let none = EntityHashSet::default();
        fit_to_input(&mut world, mesh, &input, &samples, &none, &none);
        let after = farthest(&samples, &surface_of(&world));
        // Every vertex moved outward, none as far as the gap.
        for p in positions(&world, mesh) {
            assert!(p.length() > 1.0 && p.length() < 1.0 + before, "{p}");
        }
        assert!(after < 0.75 * before, "{after} against {before}");
        // The other way, the remesh's corners now lie off the sphere, by less than the gap.
        let corners = positions(&world, mesh);
        assert!(farthest(&corners, &input) < before);
        assert_eq!(crate::mesh::validate(&world, mesh), Ok(()));
    }

    #[test]
    fn boundary_and_feature_corners_stay() {
        // A flat 4 × 4 grid under a dome that meets it at its border.
        let mut dome = shapes::grid(16, 16);
        for p in &mut dome.positions {
            p.z = 0.05 * (std::f32::consts::PI * p.x).sin() * (std::f32::consts::PI * p.y).sin();
        }
        let (mut world, mesh, input, samples) = over(&shapes::grid(4, 4), &dome);
        let m = MeshRef::new(&world);
        let members = MeshMembers::collect(&world, mesh);
        // A feature line along the middle row, from x = 1/4 to 3/4: its ends are corners
        // (one feature edge), its middle is not (two).
        let on_line = |p: Vec3| p.y == 0.5 && (0.25..=0.75).contains(&p.x);
        let features: EntityHashSet = members
            .edges
            .iter()
            .filter(|&&e| {
                let (a, b) = m.edge_vertices(e);
                on_line(m.position(a)) && on_line(m.position(b))
            })
            .map(|e| e.0)
            .collect();
        assert_eq!(features.len(), 2);
        let boundary: Vec<bool> = members
            .vertices
            .iter()
            .map(|&v| m.is_boundary_vertex(v))
            .collect();
        let before = positions(&world, mesh);
        fit_to_input(
            &mut world,
            mesh,
            &input,
            &samples,
            &features,
            &EntityHashSet::default(),
        );
        let after = positions(&world, mesh);
        let mut moved = 0;
        for (k, (p, q)) in before.iter().zip(&after).enumerate() {
            let corner = on_line(*p) && p.x != 0.5;
            if boundary[k] || corner {
                assert_eq!(p, q, "a boundary vertex or a feature corner moved");
            } else {
                // Straight up, towards the dome (the grid's normal is z).
                assert!(q.z > 0.0 && q.x == p.x && q.y == p.y, "{p} → {q}");
                moved += 1;
            }
        }
        // The nine inner vertices less the line's two ends.
        assert_eq!(moved, 7);
    }

    /// The move left to the apex of the triangle on the base (0, 0, 0)–(1, 0, 0) after the
    /// guard, asked to move by `step`.
    fn apex_move(apex: Vec3, step: Vec3, keep_fat: bool) -> Vec3 {
        let mut moves = vec![Vec3::ZERO, Vec3::ZERO, step];
        cancel_harmful_moves(
            &[Vec3::ZERO, Vec3::X, apex],
            &[[0, 1, 2]],
            keep_fat,
            &mut moves,
        );
        moves[2]
    }

    #[test]
    fn a_move_that_would_thin_a_triangle_is_cancelled() {
        let apex = Vec3::new(0.5, 0.8, 0.0);
        // The apex lowered to 0.1 over the base: its base angles under 30°.
        let down = Vec3::new(0.0, -0.7, 0.0);
        assert_eq!(apex_move(apex, down, true), Vec3::ZERO);
        assert_eq!(apex_move(apex, down, false), down);
        // Lifted off the plane a little: still no angle under 30°, so it moves.
        let lift = Vec3::new(0.0, 0.0, 0.1);
        assert_eq!(apex_move(apex, lift, true), lift);
    }

    #[test]
    fn a_move_that_would_turn_a_sliver_over_is_cancelled() {
        // A sliver, thin already: its apex taken across the base to the mirror image keeps its
        // angles, so only the turned normal tells, with or without the guard against thin ones.
        let apex = Vec3::new(0.5, 0.05, 0.0);
        let across = Vec3::new(0.0, -0.1, 0.0);
        assert_eq!(apex_move(apex, across, true), Vec3::ZERO);
        assert_eq!(apex_move(apex, across, false), Vec3::ZERO);
        // Half-way up instead: fatter, and the same way round, so it moves.
        let up = Vec3::new(0.0, 0.2, 0.0);
        assert_eq!(apex_move(apex, up, true), up);
    }

    #[test]
    fn the_smallest_angle_is_the_largest_cosine() {
        let h = 3f32.sqrt() / 2.0;
        let equilateral = [Vec3::ZERO, Vec3::X, Vec3::new(0.5, h, 0.0)];
        assert!((smallest_angle_cosine(equilateral) - 0.5).abs() < 1e-6);
        // 30°, 60° and 90°, in either order round.
        let half = [Vec3::ZERO, Vec3::new(h, 0.0, 0.0), Vec3::new(h, 0.5, 0.0)];
        assert!((smallest_angle_cosine(half) - h).abs() < 1e-6);
        let [a, b, c] = half;
        assert!((smallest_angle_cosine([a, c, b]) - h).abs() < 1e-6);
        assert_eq!(smallest_angle_cosine([a, a, b]), 1.0);
    }
}
