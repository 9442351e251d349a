//! Closest points on a surface: what the remesher projects its vertices back onto (Botsch &
//! Kobbelt 2004 project each relaxed vertex onto the original surface), and what measures how
//! far a mesh moved from the one before (the editor's distance colouring).
//!
//! [`Reference`] holds a surface's triangles in a uniform grid and answers the exact closest
//! point of all its triangles ([`Reference::closest`]: rings of cells are searched outwards
//! until nothing unscanned can be nearer, skipping the cells of a ring that lie wholly farther
//! than the nearest point found so far) and whether some triangle lies within a distance
//! ([`Reference::is_near`]). A cell's triangles are measured four at a time without a branch
//! first ([`lanes`]), and only those that could be nearer than the nearest found are tested
//! exactly, in order: the same point and row as testing every one, in about two thirds of
//! the time (`docs/performance.md`, "The grid's triangles measured four at a time"). A ring
//! is walked over its cells in the grid only, so a search that finds nothing near (triangles
//! so long their distances overflow, as a vertex at 1e30 makes) ends after as many steps as
//! the grid has cells, where the blocks it walked whole once hung a simplification.

mod lanes;

use bevy::math::{IVec3, Vec3};

use crate::mesh::members::MeshMembers;
use crate::mesh::tables::Connectivity;

use super::surface::Surface;
use crate::mesh::topology::MeshRef;

/// A surface, for closest-point queries: its triangles in a uniform grid of cells
/// about half a triangle across, stored flat (the triangles of cell `c` are
/// `cell_triangles[cell_start[c]..cell_start[c + 1]]`).
pub struct Reference {
    triangles: Vec<[Vec3; 3]>,
    origin: Vec3,
    cell: f32,
    dims: [i32; 3],
    cell_start: Vec<u32>,
    cell_triangles: Vec<u32>,
    /// How far apart two computations of a distance to a triangle may come out by rounding
    /// alone, for a point at the origin (see [`Reference::nearest_in`]).
    rounding: f32,
}

impl Reference {
    /// The grid of `members`' faces (triangles all; the first three corners of any other).
    pub fn new(m: &MeshRef<'_>, members: &MeshMembers) -> Self {
        let triangles: Vec<[Vec3; 3]> = members
            .faces
            .iter()
            .map(|&f| {
                let v: Vec<Vec3> = m.face_vertices(f).map(|x| m.position(x)).collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        Self::from_triangles(triangles)
    }

    /// The grid of the fanned triangles of the mesh in `t` (polygons too).
    pub fn of_tables(t: &Connectivity) -> Self {
        let s = Surface::from_tables(t);
        Self::from_triangles(
            (0..s.triangles.len())
                .map(|i| s.corners(i).map(|p| p.as_vec3()))
                .collect(),
        )
    }

    /// The grid of these triangles (the row of each is its index here).
    pub fn from_triangles(triangles: Vec<[Vec3; 3]>) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for t in &triangles {
            for p in t {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        // Smaller cells hold fewer triangles to test, but a query may have to look further;
        // half the size of a triangle's cube root of volume measured fastest (at most 512
        // cells along an axis).
        let cell = (extent.x * extent.y * extent.z / triangles.len().max(1) as f32)
            .cbrt()
            .max(extent.max_element() / 512.0)
            * 0.5;
        let dims = ((extent / cell).ceil().as_ivec3() + 1).to_array();
        let cells_of = |t: &[Vec3; 3]| {
            let (a, b) = (
                t.iter().fold(Vec3::splat(f32::MAX), |x, p| x.min(*p)),
                t.iter().fold(Vec3::splat(f32::MIN), |x, p| x.max(*p)),
            );
            let (ca, cb) = (
                ((a - lo) / cell).floor().as_ivec3(),
                ((b - lo) / cell).floor().as_ivec3(),
            );
            (ca.z..=cb.z).flat_map(move |z| {
                (ca.y..=cb.y).flat_map(move |y| (ca.x..=cb.x).map(move |x| [x, y, z]))
            })
        };
        let index = |c: [i32; 3]| cell_row(dims, c);
        let count = dims.iter().map(|&d| d as usize).product::<usize>();
        // Count, then place: a counting sort of (cell, triangle) pairs.
        let mut cell_start = vec![0u32; count + 1];
        for t in &triangles {
            for c in cells_of(t) {
                cell_start[index(c) + 1] += 1;
            }
        }
        for i in 0..count {
            cell_start[i + 1] += cell_start[i];
        }
        let mut fill = cell_start.clone();
        let mut cell_triangles = vec![0u32; cell_start[count] as usize];
        for (i, t) in triangles.iter().enumerate() {
            for c in cells_of(t) {
                let slot = &mut fill[index(c)];
                cell_triangles[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
        let magnitude = lo.abs().max(hi.abs()).max_element();
        Self {
            triangles,
            origin: lo,
            cell,
            dims,
            cell_start,
            cell_triangles,
            rounding: ROUNDING_ULPS * f32::EPSILON * magnitude,
        }
    }

    /// The triangles listed in cell `c`, none outside the grid.
    fn cell(&self, [x, y, z]: [i32; 3]) -> &[u32] {
        let [dx, dy, dz] = self.dims;
        if x < 0 || y < 0 || z < 0 || x >= dx || y >= dy || z >= dz {
            return &[];
        }
        let i = cell_row(self.dims, [x, y, z]);
        &self.cell_triangles[self.cell_start[i] as usize..self.cell_start[i + 1] as usize]
    }

    /// The surface's triangles, in the order they were given (each one's row).
    pub fn triangles(&self) -> &[[Vec3; 3]] {
        &self.triangles
    }

    /// The closest point of the surface to `p` (searching rings of cells outwards).
    pub fn closest(&self, p: Vec3) -> Vec3 {
        self.closest_on(p).0
    }

    /// How far `p` lies from the surface: its distance to [`Reference::closest`].
    pub fn distance(&self, p: Vec3) -> f32 {
        self.closest(p).distance(p)
    }

    /// Whether some triangle lies within `r` of `p`: the cells the ball around `p` touches,
    /// stopping at the first triangle found within reach (far cheaper than
    /// [`Reference::closest`] where most points are near, as the remesh's are).
    pub fn is_near(&self, p: Vec3, r: f32) -> bool {
        let cell_of = |q: Vec3| ((q - self.origin) / self.cell).floor().as_ivec3();
        let (lo, hi) = (cell_of(p - Vec3::splat(r)), cell_of(p + Vec3::splat(r)));
        (lo.z..=hi.z).any(|z| {
            (lo.y..=hi.y).any(|y| {
                (lo.x..=hi.x).any(|x| {
                    self.cell([x, y, z]).iter().any(|&i| {
                        closest_on_triangle(p, &self.triangles[i as usize]).distance_squared(p)
                            <= r * r
                    })
                })
            })
        })
    }

    /// The rows of the triangles listed in the cells the ball of radius `r` around `p`
    /// touches, each once, in order: every triangle within `r` of `p` among them (and some
    /// farther, in the same cells).
    pub fn rows_near(&self, p: Vec3, r: f32) -> Vec<usize> {
        let cell_of = |q: Vec3| ((q - self.origin) / self.cell).floor().as_ivec3();
        let (lo, hi) = (cell_of(p - Vec3::splat(r)), cell_of(p + Vec3::splat(r)));
        let mut rows: Vec<usize> = (lo.z..=hi.z)
            .flat_map(|z| (lo.y..=hi.y).flat_map(move |y| (lo.x..=hi.x).map(move |x| [x, y, z])))
            .flat_map(|c| self.cell(c).iter().map(|&i| i as usize))
            .collect();
        rows.sort_unstable();
        rows.dedup();
        rows
    }

    /// [`Reference::closest`], with the row of the triangle it lies on (the row of its face
    /// in the members the reference was made from). A point with a coordinate that is not a
    /// finite number has no nearest point: it is its own answer, with row 0 (as is any point
    /// of a surface with no triangle that measures to a number).
    pub fn closest_on(&self, p: Vec3) -> (Vec3, usize) {
        if !p.is_finite() {
            return (p, 0);
        }
        let local = (p - self.origin) / self.cell;
        let mut best = (f32::MAX, p, 0);
        if local.abs().max_element() > FAR_CELLS {
            // Farther out, its cell's index and the rings' reach could overflow an `i32`.
            self.nearest_in(p, &self.all_rows(), &mut best);
            return (best.1, best.2);
        }
        let c = local.floor().as_ivec3();
        // How far `p` is from the nearest wall of its own cell, in cells: after scanning the
        // block of cells within `ring` of it, everything unscanned is at least
        // `(ring + wall) * cell` away.
        let f = local - local.floor();
        let wall = f.min(Vec3::ONE - f).min_element();
        // Far enough to take in the whole grid, from a point outside it too.
        let outside = (0..3)
            .map(|k| (-c[k]).max(c[k] - self.dims[k] + 1).max(0))
            .max()
            .unwrap_or(0);
        let max_ring = self.dims.iter().copied().max().unwrap_or(1) + outside;
        // Rings nearer than `outside` hold no cell of the grid: start where the grid begins.
        for ring in outside..=max_ring {
            self.for_each_in_ring(c, ring, |offset| {
                // A cell wholly farther than the nearest point found holds no nearer one
                // (which leaves the point found the same).
                let corner = self.origin + (c + offset).as_vec3() * self.cell;
                let outside = (corner - p).max(p - corner - self.cell).max(Vec3::ZERO);
                if outside.length_squared() <= best.0 {
                    self.nearest_in(p, self.cell((c + offset).to_array()), &mut best);
                }
            });
            if best.0 < f32::MAX && best.0.sqrt() <= (ring as f32 + wall) * self.cell {
                break;
            }
        }
        (best.1, best.2)
    }

    /// Calls `visit` with the offset from cell `c` of each cell at Chebyshev distance `ring`
    /// from it (the shell of the block within `ring`) that lies in the grid, in the order of
    /// x, then y, then z, each ascending: a ring costs as many steps as it has cells in the
    /// grid, so that a search that finds nothing near (its triangles' distances all not
    /// numbers) still ends soon.
    fn for_each_in_ring(&self, c: IVec3, ring: i32, mut visit: impl FnMut(IVec3)) {
        let span = |k: usize| (-ring).max(-c[k])..=ring.min(self.dims[k] - 1 - c[k]);
        let zs = span(2);
        for x in span(0) {
            for y in span(1) {
                if x.abs() == ring || y.abs() == ring {
                    zs.clone().for_each(|z| visit(IVec3::new(x, y, z)));
                } else {
                    // Inside the shell in x and y: only its two faces in z.
                    for z in [-ring, ring] {
                        if zs.contains(&z) {
                            visit(IVec3::new(x, y, z));
                        }
                    }
                }
            }
        }
    }

    /// Every triangle's row, in order.
    fn all_rows(&self) -> Vec<u32> {
        (0..self.triangles.len() as u32).collect()
    }

    /// Tests `p` against the triangles `rows`, in order, keeping in `best` the squared
    /// distance, the point and the row of the nearest (the first of equals). The same as
    /// testing each exactly ([`closest_on_triangle`]), but that the triangles the lanes
    /// ([`lanes`]) put farther than the nearest found by more than their rounding are passed
    /// over: none of them could have been nearer.
    fn nearest_in(&self, p: Vec3, rows: &[u32], best: &mut (f32, Vec3, usize)) {
        let slack = self.rounding + ROUNDING_ULPS * f32::EPSILON * p.abs().max_element();
        let reach = |d: f32| sq(d.sqrt() + slack);
        let mut bound = reach(best.0);
        for chunk in rows.chunks(lanes::LANES) {
            let distances =
                lanes::TriangleLanes::gather(&self.triangles, chunk).squared_distances(p);
            for (&i, &d) in chunk.iter().zip(&distances) {
                if d > bound {
                    continue;
                }
                let q = closest_on_triangle(p, &self.triangles[i as usize]);
                let d = q.distance_squared(p);
                if d < best.0 {
                    *best = (d, q, i as usize);
                    bound = reach(d);
                }
            }
        }
    }
}

/// How many units in the last place of the largest coordinate two computations of a
/// distance to a triangle may differ by (each is within a few): the tests below find a nearer
/// triangle passed over with none, and none with 4.
const ROUNDING_ULPS: f32 = 64.0;

/// How far from the grid's origin, in cells, a point is searched for by rings: past it, where
/// cell indices near `i32`'s range could overflow, every triangle is tested in turn.
const FAR_CELLS: f32 = 1e6;

/// `x` squared.
fn sq(x: f32) -> f32 {
    x * x
}

/// The row of cell `[x, y, z]` (inside the grid) in a grid of `dims` cells, x fastest.
fn cell_row([dx, dy, _]: [i32; 3], [x, y, z]: [i32; 3]) -> usize {
    (x + dx * (y + dy * z)) as usize
}

/// The closest point of triangle `t` to `p` (Ericson, Real-Time Collision Detection, 5.1.5).
pub(crate) fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The barycentric weights of `q`, a point of triangle `[a, b, c]`. Equal weights for a
/// degenerate triangle; a weight slightly outside [0, 1] from rounding is clamped.
pub(crate) fn barycentric(q: Vec3, [a, b, c]: [Vec3; 3]) -> [f32; 3] {
    let (ab, ac, aq) = (b - a, c - a, q - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (aq.dot(ab), aq.dot(ac));
    let denominator = d00 * d11 - d01 * d01;
    if denominator.abs() <= f32::EPSILON * d00 * d11 {
        return [1.0; 3];
    }
    let v = ((d11 * d20 - d01 * d21) / denominator).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / denominator).clamp(0.0, 1.0);
    [(1.0 - v - w).max(0.0), v, w]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh};
    use bevy::prelude::World;

    /// A fixed pseudo-random sequence of coordinates in [-half, half) from `seed`.
    pub(super) fn coordinates(seed: u32, half: f32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 * (2.0 * half) - half
        }
    }

    #[test]
    fn barycentric_weights_rebuild_the_point() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(
            barycentric(Vec3::new(0.25, 0.5, 0.0), tri),
            [0.25, 0.25, 0.5]
        );
        // Off the triangle: clamped onto it.
        assert_eq!(barycentric(Vec3::new(2.0, 0.0, 0.0), tri), [0.0, 1.0, 0.0]);
        // A degenerate triangle: equal weights.
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert_eq!(barycentric(Vec3::X, flat), [1.0; 3]);
    }

    #[test]
    fn far_from_the_origin_the_grid_finds_the_point_that_testing_every_triangle_finds() {
        // A fine sphere a thousand units out, where a unit in the last place of a coordinate
        // is about 6e-5: the lanes' rounding must not pass over a triangle that testing
        // every one exactly finds nearer. (Of two triangles as near, at a corner they share,
        // the grid keeps the first it meets, which need not be the first by row.)
        let offset = Vec3::new(1000.0, -700.0, 300.0);
        let soup = crate::mesh::shapes::icosphere(4);
        let triangles: Vec<[Vec3; 3]> = soup
            .faces()
            .map(|f| [0, 1, 2].map(|k| soup.positions[f[k] as usize] + offset))
            .collect();
        let reference = Reference::from_triangles(triangles.clone());
        let mut coordinate = coordinates(3, 1.2);
        for _ in 0..500 {
            let p = offset + Vec3::new(coordinate(), coordinate(), coordinate());
            let mut brute = (f32::MAX, p, 0);
            for (row, t) in triangles.iter().enumerate() {
                let q = closest_on_triangle(p, t);
                if q.distance_squared(p) < brute.0 {
                    brute = (q.distance_squared(p), q, row);
                }
            }
            let (q, row) = reference.closest_on(p);
            assert_eq!(q, brute.1, "at {p}");
            assert_eq!(
                closest_on_triangle(p, &triangles[row]),
                q,
                "at {p}: row {row}"
            );
        }
    }

    #[test]
    fn points_not_finite_or_far_out_and_triangles_that_measure_to_no_number() {
        let small = [Vec3::ZERO, Vec3::X, Vec3::Y];
        // Slivers reaching 1e15 out along x: every distance to them overflows to no number in
        // Ericson's test, so a search near their far end finds nothing until it reaches the
        // small triangle, three hundred cells away along a grid two cells thick (its rings'
        // blocks, scanned whole, came to about 1e10 cells).
        let far = Vec3::new(1e15, 0.0, 0.0);
        let slivers = (1..6).map(|k| [Vec3::new(0.0, 0.1 * k as f32, 0.5), far, far + Vec3::Z]);
        let triangles: Vec<[Vec3; 3]> = std::iter::once(small).chain(slivers).collect();
        let reference = Reference::from_triangles(triangles);
        let p = Vec3::new(3e14, 0.2, 0.2);
        assert_eq!(reference.closest_on(p), (closest_on_triangle(p, &small), 0));
        // Not a number, or infinite: its own answer.
        for p in [Vec3::NAN, Vec3::new(0.0, f32::INFINITY, 0.0)] {
            let (q, row) = reference.closest_on(p);
            assert!(q.is_nan() == p.is_nan() && row == 0, "{p}: {q}");
        }
        // Millions of cells out: every triangle tested in turn.
        let grid = Reference::from_triangles(vec![small.map(|q| q + 1000.0 * Vec3::X), small]);
        let p = Vec3::new(-1e7, 0.5, 3.0);
        assert_eq!(grid.closest_on(p), (Vec3::new(0.0, 0.5, 0.0), 1));
    }

    #[test]
    fn the_reference_grid_finds_the_closest_point_of_all_triangles_and_those_near() {
        let soup = crate::mesh::shapes::icosphere(2);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, built.mesh);
        let reference = Reference::new(&MeshRef::new(&world), &members);
        // Points inside, near and far outside the sphere (a fixed pseudo-random sequence).
        let mut coordinate = coordinates(7, 4.0);
        for _ in 0..200 {
            let p = Vec3::new(coordinate(), coordinate(), coordinate());
            let nearest = reference
                .triangles
                .iter()
                .map(|t| closest_on_triangle(p, t).distance(p))
                .fold(f32::MAX, f32::min);
            assert_eq!(reference.distance(p), nearest, "at {p}");
            for r in [0.05, 0.3, 1.0, 3.0] {
                assert_eq!(reference.is_near(p, r), nearest <= r, "at {p}, within {r}");
                let rows = reference.rows_near(p, r);
                assert!(rows.windows(2).all(|w| w[0] < w[1]), "each once, in order");
                for (row, t) in reference.triangles.iter().enumerate() {
                    if closest_on_triangle(p, t).distance(p) <= r {
                        assert!(rows.contains(&row), "at {p}, within {r}: {row}");
                    }
                }
            }
        }
    }
}
