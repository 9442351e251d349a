//! The triangulation of a hole's boundary loop that bends least, by dynamic programming
//! (Barequet & Sharir 1995; Liepa, "Filling Holes in Meshes", SGP 2003, §3).
//!
//! For the loop `v_0 … v_{n−1}`, `W(i, k)` is the best triangulation of the polygon
//! `v_i … v_k` closed by the side `v_k v_i`:
//!
//! `W(i, k) = min_{i<m<k} W(i, m) ⊕ W(m, k) ⊕ ω(i, m, k)`,
//!
//! where a weight is the pair (largest dihedral angle, total area), compared angle first, and
//! `⊕` takes the larger angle and adds the areas. The angle of the triangle `(i, m, k)` is
//! taken against its neighbours across the sides `v_i v_m` and `v_m v_k`: the triangle the
//! sub-problem chose there, or the mesh's face beyond a side of the loop. The side `v_{n−1} v_0`
//! of the whole polygon meets the mesh's face beyond it last. Diagonals that would repeat an edge
//! the mesh already has are forbidden. `O(n³)` time and `O(n²)` memory.

use bevy::math::DVec3;

/// A triangulation's cost: its largest dihedral angle (radians), then its area.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Weight {
    angle: f64,
    area: f64,
}

impl Weight {
    const NONE: Weight = Weight {
        angle: f64::INFINITY,
        area: f64::INFINITY,
    };

    fn better_than(self, other: Weight) -> bool {
        self.angle < other.angle || (self.angle == other.angle && self.area < other.area)
    }

    fn plus(self, other: Weight) -> Weight {
        Weight {
            angle: self.angle.max(other.angle),
            area: self.area + other.area,
        }
    }
}

/// The loop to triangulate.
pub struct HoleLoop<'a> {
    /// The loop's vertices, in the order the filling faces go round.
    pub positions: &'a [DVec3],
    /// The unit normal of the mesh's face beyond each side `v_i v_{i+1}` (zero if none).
    pub beyond: &'a [DVec3],
    /// Whether the mesh already joins `v_i` and `v_k` by an edge (for sides that are not the
    /// loop's own).
    pub joined: &'a dyn Fn(usize, usize) -> bool,
}

/// The angle between two unit normals; π when either is zero (a degenerate triangle is as bad as
/// a fold).
fn dihedral(a: DVec3, b: DVec3) -> f64 {
    if a == DVec3::ZERO || b == DVec3::ZERO {
        return std::f64::consts::PI;
    }
    a.dot(b).clamp(-1.0, 1.0).acos()
}

/// The triangles `[i, m, k]` (loop indices, in the filling faces' orientation) of the best
/// triangulation, parents before children; `None` when every triangulation would repeat an
/// existing edge.
pub fn triangulate(hole: &HoleLoop<'_>) -> Option<Vec<[usize; 3]>> {
    let n = hole.positions.len();
    if n < 3 {
        return None;
    }
    let p = hole.positions;
    let normal =
        |i: usize, m: usize, k: usize| (p[m] - p[i]).cross(p[k] - p[i]).normalize_or_zero();
    let area = |i: usize, m: usize, k: usize| 0.5 * (p[m] - p[i]).cross(p[k] - p[i]).length();
    let at = |i: usize, k: usize| i * n + k;
    let mut weight = vec![Weight::NONE; n * n];
    let mut apex = vec![u32::MAX; n * n];
    for i in 0..n - 1 {
        weight[at(i, i + 1)] = Weight {
            angle: 0.0,
            area: 0.0,
        };
    }
    // The normal of whatever lies beyond the side (i, k) of a sub-polygon.
    let neighbour = |apex: &[u32], i: usize, k: usize| -> DVec3 {
        if k == i + 1 {
            hole.beyond[i]
        } else {
            normal(i, apex[at(i, k)] as usize, k)
        }
    };
    for span in 2..n {
        for i in 0..n - span {
            let k = i + span;
            // The closing side of a sub-polygon becomes a diagonal (all but the whole loop's).
            if span < n - 1 && (hole.joined)(i, k) {
                continue;
            }
            let mut best = Weight::NONE;
            let mut best_m = u32::MAX;
            for m in i + 1..k {
                let (left, right) = (weight[at(i, m)], weight[at(m, k)]);
                if left.angle.is_infinite() || right.angle.is_infinite() {
                    continue;
                }
                let own = normal(i, m, k);
                let mut angle = dihedral(own, neighbour(&apex, i, m))
                    .max(dihedral(own, neighbour(&apex, m, k)));
                if span == n - 1 {
                    // The whole loop's closing side is the loop's last side.
                    angle = angle.max(dihedral(own, hole.beyond[n - 1]));
                }
                let w = left.plus(right).plus(Weight {
                    angle,
                    area: area(i, m, k),
                });
                if w.better_than(best) {
                    (best, best_m) = (w, m as u32);
                }
            }
            weight[at(i, k)] = best;
            apex[at(i, k)] = best_m;
        }
    }
    if apex[at(0, n - 1)] == u32::MAX {
        return None;
    }
    let mut triangles = Vec::with_capacity(n - 2);
    let mut stack = vec![(0usize, n - 1)];
    while let Some((i, k)) = stack.pop() {
        if k < i + 2 {
            continue;
        }
        let m = apex[at(i, k)] as usize;
        triangles.push([i, m, k]);
        stack.push((m, k));
        stack.push((i, m));
    }
    Some(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn never(_: usize, _: usize) -> bool {
        false
    }

    #[test]
    fn a_planar_convex_loop_gets_n_minus_2_triangles_covering_its_area() {
        let n = 9;
        let positions: Vec<DVec3> = (0..n)
            .map(|i| {
                let t = i as f64 / n as f64 * std::f64::consts::TAU;
                DVec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        // The mesh around lies in the plane too.
        let beyond = vec![DVec3::Z; n];
        let hole = HoleLoop {
            positions: &positions,
            beyond: &beyond,
            joined: &never,
        };
        let triangles = triangulate(&hole).unwrap();
        assert_eq!(triangles.len(), n - 2);
        let area: f64 = triangles
            .iter()
            .map(|&[i, m, k]| {
                let (a, b, c) = (positions[i], positions[m], positions[k]);
                (b - a).cross(c - a).z * 0.5
            })
            .sum();
        let polygon = 0.5 * n as f64 * (std::f64::consts::TAU / n as f64).sin();
        assert!((area - polygon).abs() < 1e-12, "{area} vs {polygon}");
    }

    #[test]
    fn a_diagonal_the_mesh_already_has_is_never_repeated() {
        // A square loop with 1 and 3 raised: either diagonal would do; the one the mesh already
        // has is never repeated.
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.5),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.5),
        ];
        let beyond = vec![DVec3::Z; 4];
        let forbid_02 = |i: usize, k: usize| (i, k) == (0, 2);
        let hole = HoleLoop {
            positions: &positions,
            beyond: &beyond,
            joined: &forbid_02,
        };
        let triangles = triangulate(&hole).unwrap();
        assert!(
            triangles.iter().all(|t| t.contains(&1) && t.contains(&3)),
            "{triangles:?}"
        );
        // Both diagonals forbidden: nothing.
        let forbid_both = |i: usize, k: usize| (i, k) == (0, 2) || (i, k) == (1, 3);
        let hole = HoleLoop {
            joined: &forbid_both,
            ..hole
        };
        assert_eq!(triangulate(&hole), None);
    }
}
