//! The intrinsic Delaunay triangulation of a surface: its triangles' edges flipped, by their
//! lengths alone, until every edge is Delaunay (Bobenko & Springborn, *A discrete
//! Laplace–Beltrami operator for simplicial surfaces*, 2007; Fisher, Springborn, Schröder &
//! Bobenko, *An algorithm for the construction of intrinsic Delaunay triangulations*, 2007).
//!
//! The surface is not moved: an intrinsic triangulation has the same vertices and the same
//! metric (each triangle flat, the angle around each vertex unchanged), only other edges — a
//! flipped edge runs across the two triangles it separated, its length that of the straight
//! line between the two far corners once the triangles are unfolded into the plane. Its
//! cotangent Laplacian has no negative weights, so heat flows the right way on meshes whose
//! obtuse triangles make the mesh's own cotangent weights negative (Sharp & Crane, *A
//! Laplacian for nonmanifold triangle meshes*, 2020, which potpourri3d's heat method uses by
//! default).
//!
//! The triangulation may stop being a simplicial complex — two edges between one pair of
//! vertices, two sides of a triangle glued together — and is held as a triangle list with the
//! side lengths and each side's twin, which says so without trouble. Side `k` of a triangle
//! runs from its corner `k` to corner `k + 1`; half-edge `3t + k` names it.

use bevy::math::DVec2;

use super::Surface;

/// No twin: a side on the boundary.
const NONE: u32 = u32::MAX;

/// An intrinsic triangulation of a surface's vertices (see the module doc).
#[derive(Clone, Debug)]
pub struct Intrinsic {
    /// Triangles as vertex rows, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// The length of each side, by triangle: side `k` from corner `k` to corner `k + 1`.
    pub lengths: Vec<[f64; 3]>,
    /// Each side's twin (`3t + k`), or [`NONE`] on the boundary.
    twin: Vec<u32>,
    vertex_count: usize,
}

impl Intrinsic {
    /// The surface's own triangles, with the lengths of their sides in space.
    pub fn of(s: &Surface) -> Self {
        let lengths = (0..s.triangles.len())
            .map(|t| {
                let p = s.corners(t);
                [0, 1, 2].map(|k| p[k].distance(p[(k + 1) % 3]))
            })
            .collect();
        let mut sides = std::collections::HashMap::with_capacity(3 * s.triangles.len());
        for (t, tri) in s.triangles.iter().enumerate() {
            for k in 0..3 {
                sides.insert((tri[k], tri[(k + 1) % 3]), (3 * t + k) as u32);
            }
        }
        let twin = (0..3 * s.triangles.len())
            .map(|h| {
                let tri = s.triangles[h / 3];
                let (a, b) = (tri[h % 3], tri[(h % 3 + 1) % 3]);
                sides.get(&(b, a)).copied().unwrap_or(NONE)
            })
            .collect();
        Self {
            triangles: s.triangles.clone(),
            lengths,
            twin,
            vertex_count: s.vertex_count(),
        }
    }

    /// The surface's intrinsic Delaunay triangulation.
    pub fn delaunay(s: &Surface) -> Self {
        let mut x = Self::of(s);
        x.flip_to_delaunay();
        x
    }

    /// How many vertices the surface has.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Flips non-Delaunay edges until there is none (or, on a surface so degenerate that
    /// flipping cycles, until 50 flips a triangle have been made). Returns the flips made.
    pub fn flip_to_delaunay(&mut self) -> usize {
        let mut pending: Vec<u32> = (0..self.twin.len() as u32)
            .filter(|&h| self.twin[h as usize] != NONE && h < self.twin[h as usize])
            .collect();
        let limit = 50 * self.triangles.len();
        let mut flips = 0;
        while let Some(h) = pending.pop() {
            if flips == limit {
                break;
            }
            if self.is_delaunay(h as usize) {
                continue;
            }
            let (t, s) = (h as usize / 3, self.twin[h as usize] as usize / 3);
            self.flip(h as usize);
            flips += 1;
            pending.extend([3 * t + 1, 3 * t + 2, 3 * s + 1, 3 * s + 2].map(|x| x as u32));
        }
        flips
    }

    /// Whether side `h` is Delaunay: the angles facing it across its two triangles sum to no
    /// more than π (their cotangents to no less than zero). A boundary side always is, and so
    /// is a side glued to its own triangle.
    fn is_delaunay(&self, h: usize) -> bool {
        let g = self.twin[h];
        if g == NONE || g as usize / 3 == h / 3 {
            return true;
        }
        let g = g as usize;
        let facing = |x: usize| self.cot(x / 3, (x % 3 + 2) % 3);
        facing(h) + facing(g) >= -1e-12
    }

    /// Flips side `h` (interior, its two triangles distinct): triangle `t` (a, b, c) and its
    /// twin's `s` (b, a, d) become (d, c, a) and (c, d, b), the new side c → d as long as the
    /// two triangles unfolded into the plane put c and d apart.
    fn flip(&mut self, h: usize) {
        let g = self.twin[h] as usize;
        let (t, i, s, j) = (h / 3, h % 3, g / 3, g % 3);
        let next = |k: usize| (k + 1) % 3;
        let (vt, vs) = (self.triangles[t], self.triangles[s]);
        let (a, b, c, d) = (vt[i], vt[next(i)], vt[next(next(i))], vs[next(next(j))]);
        let (lt, ls) = (self.lengths[t], self.lengths[s]);
        let (ab, bc, ca) = (lt[i], lt[next(i)], lt[next(next(i))]);
        let (ad, db) = (ls[next(j)], ls[next(next(j))]);
        // Unfolded: a at the origin, b on the x axis, c above it and d below.
        let c2 = apex(ab, ca, bc);
        let d2 = apex(ab, ad, db);
        let cd = c2.distance(DVec2::new(d2.x, -d2.y));
        // The old sides' places in the new triangles (their twins follow them).
        let old = [
            3 * t + next(i),
            3 * t + next(next(i)),
            3 * s + next(j),
            3 * s + next(next(j)),
        ];
        let new = [3 * s + 2, 3 * t + 1, 3 * t + 2, 3 * s + 1];
        let moved = |x: u32| match old.iter().position(|&o| o as u32 == x) {
            Some(k) => new[k] as u32,
            None if x as usize == h => (3 * t) as u32,
            None if x as usize == g => (3 * s) as u32,
            None => x,
        };
        let outer: Vec<u32> = old.iter().map(|&o| moved(self.twin[o])).collect();
        self.triangles[t] = [d, c, a];
        self.triangles[s] = [c, d, b];
        self.lengths[t] = [cd, ca, ad];
        self.lengths[s] = [cd, db, bc];
        self.twin[3 * t] = (3 * s) as u32;
        self.twin[3 * s] = (3 * t) as u32;
        for (&place, &twin) in new.iter().zip(&outer) {
            self.twin[place] = twin;
            if twin != NONE {
                self.twin[twin as usize] = place as u32;
            }
        }
    }

    /// Triangle `t`'s area, from its side lengths (Heron's formula, in its stable form).
    pub fn area(&self, t: usize) -> f64 {
        let mut l = self.lengths[t];
        l.sort_unstable_by(|x, y| y.total_cmp(x));
        let [a, b, c] = l;
        let product = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
        0.25 * product.max(0.0).sqrt()
    }

    /// The cotangent of triangle `t`'s angle at corner `k` (zero for a degenerate triangle).
    pub fn cot(&self, t: usize, k: usize) -> f64 {
        let l = self.lengths[t];
        let (near, far, facing) = (l[k], l[(k + 2) % 3], l[(k + 1) % 3]);
        let area = self.area(t);
        match area > 0.0 {
            true => (near * near + far * far - facing * facing) / (4.0 * area),
            false => 0.0,
        }
    }

    /// Triangle `t` laid out in the plane: corner 0 at the origin, corner 1 on the x axis,
    /// corner 2 above it.
    pub fn layout(&self, t: usize) -> [DVec2; 3] {
        let [l0, l1, l2] = self.lengths[t];
        [DVec2::ZERO, DVec2::new(l0, 0.0), apex(l0, l2, l1)]
    }

    /// The cotangent weights `½(cot α + cot β)` of every edge, as (i, j, w) with i < j, merged
    /// (two edges between one pair of vertices add up; an edge from a vertex to itself weighs
    /// nothing in a Laplacian and is left out).
    pub fn cotan_edges(&self) -> Vec<(u32, u32, f64)> {
        let mut edges = Vec::with_capacity(3 * self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (i, j) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                if i != j {
                    edges.push((i.min(j), i.max(j), 0.5 * self.cot(t, k)));
                }
            }
        }
        super::cotan::merged(edges)
    }

    /// The mean length of the edges (each counted once).
    pub fn mean_edge_length(&self) -> f64 {
        let (mut sum, mut count) = (0.0, 0usize);
        for (h, &g) in self.twin.iter().enumerate() {
            if g == NONE || h < g as usize {
                sum += self.lengths[h / 3][h % 3];
                count += 1;
            }
        }
        sum / count.max(1) as f64
    }
}

/// The point at distance `to_a` from the origin and `to_b` from (`base`, 0), above the x axis.
fn apex(base: f64, to_a: f64, to_b: f64) -> DVec2 {
    if base <= 0.0 {
        return DVec2::new(0.0, to_a);
    }
    let x = (base * base + to_a * to_a - to_b * to_b) / (2.0 * base);
    DVec2::new(x, (to_a * to_a - x * x).max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::ops::geometry::surface::of_soup;
    use bevy::math::DVec3;

    fn surface(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Surface {
        let positions = positions.iter().map(|p| DVec3::from_array(*p).as_vec3());
        of_soup(&crate::mesh::PolygonSoup::from_faces(
            positions.collect(),
            triangles,
        ))
    }

    /// The sum of the angles around each vertex (the cone angle, which flips keep).
    fn angle_sums(x: &Intrinsic) -> Vec<f64> {
        let mut sums = vec![0.0; x.vertex_count()];
        for (t, tri) in x.triangles.iter().enumerate() {
            for k in 0..3 {
                sums[tri[k] as usize] +=
                    x.cot(t, k).recip().atan().rem_euclid(std::f64::consts::PI);
            }
        }
        sums
    }

    #[test]
    fn a_flat_quad_with_the_long_diagonal_flips_to_the_short_one() {
        // A rhombus 4 wide and 1 tall, cut along its long diagonal: two very obtuse triangles.
        let s = surface(
            &[
                [-2.0, 0.0, 0.0],
                [0.0, -0.5, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 0.5, 0.0],
            ],
            &[[0, 1, 2], [0, 2, 3]],
        );
        let mut x = Intrinsic::of(&s);
        let area = x.area(0) + x.area(1);
        assert!(
            x.cot(0, 1) < 0.0,
            "the angle facing the long diagonal is obtuse"
        );
        assert_eq!(x.flip_to_delaunay(), 1);
        // The new edge joins 1 and 3, exactly 1 long; every side is one the plane has.
        let joins = |t: usize, k: usize| {
            let tri = x.triangles[t];
            (tri[k].min(tri[(k + 1) % 3]), tri[k].max(tri[(k + 1) % 3]))
        };
        assert_eq!(joins(0, 0), (1, 3));
        assert!((x.lengths[0][0] - 1.0).abs() < 1e-12);
        for t in 0..2 {
            for k in 0..3 {
                let (i, j) = joins(t, k);
                let (p, q) = (s.positions[i as usize], s.positions[j as usize]);
                assert!((x.lengths[t][k] - p.distance(q)).abs() < 1e-12);
            }
        }
        assert!((x.area(0) + x.area(1) - area).abs() < 1e-12);
        assert_eq!(x.flip_to_delaunay(), 0);
        assert!(x.cotan_edges().iter().all(|&(_, _, w)| w >= -1e-12));
    }

    /// On a bumpy surface every edge ends Delaunay, the triangles keep the area and each
    /// vertex its angle sum, and no weight is negative; a regular grid needs no flip.
    #[test]
    fn flips_keep_the_metric_and_leave_every_edge_delaunay() {
        let mut soup = shapes::icosphere(2);
        for (i, p) in soup.positions.iter_mut().enumerate() {
            *p *= 0.4 + 1.6 * ((i * 7919) % 13) as f32 / 13.0;
        }
        let s = of_soup(&soup);
        let before = Intrinsic::of(&s);
        assert!(before.cotan_edges().iter().any(|&(_, _, w)| w < 0.0));
        let mut x = before.clone();
        assert!(x.flip_to_delaunay() > 10);
        let total = |x: &Intrinsic| (0..x.triangles.len()).map(|t| x.area(t)).sum::<f64>();
        assert!((total(&x) - total(&before)).abs() < 1e-9 * total(&before));
        for (a, b) in angle_sums(&x).iter().zip(angle_sums(&before)) {
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
        assert!(x.cotan_edges().iter().all(|&(_, _, w)| w >= -1e-12));
        for h in 0..3 * x.triangles.len() {
            assert!(x.is_delaunay(h));
            assert_eq!(x.twin[x.twin[h] as usize] as usize, h);
        }
        let grid = of_soup(&shapes::grid(4, 4));
        assert_eq!(Intrinsic::of(&grid).flip_to_delaunay(), 0);
    }
}
