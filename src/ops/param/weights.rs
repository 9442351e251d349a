//! Edge weights of the barycentric (Tutte) mapping, assembled triangle by triangle.
//!
//! Each interior vertex `i` is placed at the weighted mean of its neighbours,
//! `Σ_j w_ij (u_i − u_j) = 0`. The weights, over the fanned triangles of the cut mesh (a polygon's
//! fan diagonals are edges too):
//!
//! - **uniform** (Tutte 1963): `w_ij = 1` for every neighbour, so `u_i` is the plain mean
//!   (`λ_ij = 1/n_i`). Symmetric and positive.
//! - **mean-value** (Floater 2003): `w_ij = (tan(α/2) + tan(β/2)) / |x_i − x_j|`, α and β the
//!   angles at `x_i` of the two triangles beside edge `ij`. Each triangle corner at `i`, of angle
//!   α, adds `tan(α/2)/|x_i − x_j|` and `tan(α/2)/|x_i − x_k|` to its two sides, so an edge on
//!   the boundary gets its one term. Positive for any non-degenerate triangle (α < π); not
//!   symmetric. Reproduces planar meshes (linear precision).
//! - **harmonic** (Eck et al. 1995; Pinkall & Polthier 1993): `w_ij = (cot γ_ij + cot γ_ji)/2`,
//!   the angles opposite edge `ij` — the cotangent Laplacian. Symmetric, linear precision,
//!   negative beside obtuse angles (then Tutte's theorem no longer holds: flips are possible and
//!   reported).
//!
//! `tan(α/2)` is computed as `|u × v| / (|u||v| + u·v)` and `cot γ` as `u·v / |u × v|`, both free
//! of trigonometric calls. A degenerate triangle (zero area, or a zero-length side) adds
//! nothing.

use bevy::math::DVec3;

use super::params::ParamMethod;

/// One directed weight: row `i`, column `j`, `w_ij`. Duplicates (the two triangles beside an
/// edge) are meant to be summed.
pub type Weight = (u32, u32, f64);

/// The weights `w_ij` of `method` over `triangles` (vertex indices into `positions`), as
/// directed entries to be summed (both `(i, j)` and `(j, i)` for every side). Uniform weights
/// are 1 per neighbour: each triangle side gives ½, a side with one triangle 1.
///
/// [`ParamMethod::Lscm`] has no Tutte weights: it gives the harmonic ones.
pub fn weights(method: ParamMethod, positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<Weight> {
    let mut out = Vec::with_capacity(6 * triangles.len());
    match method {
        ParamMethod::Uniform => uniform(triangles, &mut out),
        ParamMethod::MeanValue => {
            for tri in triangles {
                mean_value_triangle(positions, *tri, &mut out);
            }
        }
        ParamMethod::Harmonic | ParamMethod::Lscm => {
            for tri in triangles {
                for (i, j, cot) in cotangents(positions, *tri) {
                    out.push((i, j, 0.5 * cot));
                    out.push((j, i, 0.5 * cot));
                }
            }
        }
    }
    out
}

/// Uniform weights: 1 per neighbour. A side shared by two triangles appears twice (½ each), a
/// side with one triangle once (1): found by sorting the undirected sides.
fn uniform(triangles: &[[u32; 3]], out: &mut Vec<Weight>) {
    let mut sides: Vec<(u32, u32)> = Vec::with_capacity(3 * triangles.len());
    for &[a, b, c] in triangles {
        for (i, j) in [(a, b), (b, c), (c, a)] {
            sides.push((i.min(j), i.max(j)));
        }
    }
    sides.sort_unstable();
    sides.dedup();
    for (i, j) in sides {
        out.push((i, j, 1.0));
        out.push((j, i, 1.0));
    }
}

/// The mean-value terms of one triangle: at each corner `i` (angle α, sides to `j` and `k`),
/// `tan(α/2)/|x_j − x_i|` on `(i, j)` and `tan(α/2)/|x_k − x_i|` on `(i, k)`.
pub fn mean_value_triangle(positions: &[DVec3], tri: [u32; 3], out: &mut Vec<Weight>) {
    for k in 0..3 {
        let (i, j, l) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let p = positions[i as usize];
        let (u, v) = (positions[j as usize] - p, positions[l as usize] - p);
        let (lu, lv) = (u.length(), v.length());
        let denominator = lu * lv + u.dot(v);
        if lu <= 0.0 || lv <= 0.0 || denominator <= 0.0 {
            continue;
        }
        let half_tan = u.cross(v).length() / denominator;
        out.push((i, j, half_tan / lu));
        out.push((i, l, half_tan / lv));
    }
}

/// For each side `(i, j)` of `tri`, the cotangent of the angle opposite it (0 when the
/// triangle is degenerate).
pub fn cotangents(positions: &[DVec3], tri: [u32; 3]) -> [(u32, u32, f64); 3] {
    let mut out = [(0, 0, 0.0); 3];
    for k in 0..3 {
        let (o, i, j) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let p = positions[o as usize];
        let (u, v) = (positions[i as usize] - p, positions[j as usize] - p);
        let sin = u.cross(v).length();
        let cot = if sin > 0.0 { u.dot(v) / sin } else { 0.0 };
        out[k] = (i, j, cot);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sums the entries for `(i, j)`.
    fn w(all: &[Weight], i: u32, j: u32) -> f64 {
        all.iter()
            .filter(|e| (e.0, e.1) == (i, j))
            .map(|e| e.2)
            .sum()
    }

    /// A fan around vertex 0 at the origin: ring vertices 1 = (2,0), 2 = (0,1), 3 = (−1,0),
    /// 4 = (0,−1), triangles (0,1,2), (0,2,3), (0,3,4), (0,4,1).
    fn fan() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
        ];
        (p, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])
    }

    #[test]
    fn a_mean_value_weight_by_hand() {
        let (p, t) = fan();
        let all = weights(ParamMethod::MeanValue, &p, &t);
        // Edge 0–1 has length 2; the angles at vertex 0 beside it are both 90° (towards 2 and
        // towards 4): w_01 = (tan 45° + tan 45°) / 2 = 1.
        assert!((w(&all, 0, 1) - 1.0).abs() < 1e-12);
        // Edge 0–2 has length 1, both angles 90°: w_02 = 2.
        assert!((w(&all, 0, 2) - 2.0).abs() < 1e-12);
        // At vertex 1 = (2,0) the edge 1–0 (length 2) has the angles of triangles (0,1,2) and
        // (0,4,1) at vertex 1: both atan(1/2), tan(atan(1/2)/2) = (√5 − 2)/1 = 0.2360679…;
        // w_10 = 2 · 0.2360679… / 2 = 0.2360679…
        let half = 5f64.sqrt() - 2.0;
        assert!((w(&all, 1, 0) - half).abs() < 1e-12, "{}", w(&all, 1, 0));
        // Edge 1–2 is a boundary side at 1 (one triangle): angle atan(1/2) again, length √5.
        assert!((w(&all, 1, 2) - half / 5f64.sqrt()).abs() < 1e-12);
        // The mean-value weights of the centre reproduce it: Σ w_0j x_j = 0.
        let centre: DVec3 = (1..5).map(|j| w(&all, 0, j) * p[j as usize]).sum();
        assert!(centre.length() < 1e-12);
    }

    #[test]
    fn harmonic_weights_are_half_cotangent_sums_and_uniform_ones_are_one() {
        let (p, t) = fan();
        let all = weights(ParamMethod::Harmonic, &p, &t);
        // Edge 0–2: opposite angles at 1 (atan(1/2)… cot = 2) and at 3 (45°, cot = 1).
        assert!((w(&all, 0, 2) - 1.5).abs() < 1e-12);
        assert!((w(&all, 2, 0) - 1.5).abs() < 1e-12);
        let uniform = weights(ParamMethod::Uniform, &p, &t);
        assert_eq!(w(&uniform, 0, 1), 1.0);
        assert_eq!(w(&uniform, 1, 2), 1.0);
        assert_eq!(w(&uniform, 1, 3), 0.0);
    }
}
