//! Least-squares conformal maps (Lévy, Petitjean, Ray & Maillot 2002): a free boundary.
//!
//! LSCM minimises, over all triangles, how far the map is from satisfying the Cauchy–Riemann
//! equations, `Σ_T A_T |∇v − rot₉₀ ∇u|² / 2`. The same energy is the *conformal energy*
//! (Desbrun, Meyer & Alliez 2002; Mullen, Tong, Alliez & Desbrun 2008): the Dirichlet energy of
//! `u` and `v` minus the signed area of the image,
//!
//! ```text
//! E_C(u, v) = ½ uᵀ L u + ½ vᵀ L v − A(u, v),   A = ½ Σ_{boundary sides i→j} (u_i v_j − u_j v_i)
//! ```
//!
//! with `L` the cotangent stiffness matrix (`L_ij = −½(cot α_ij + cot β_ij)`, the rows summing
//! to 0). Per triangle `E_D − A ≥ 0` (the Dirichlet energy bounds the area, with equality for an
//! orientation-preserving similarity), so the quadratic form `Q = [L 0; 0 L] − B` is positive
//! semi-definite; its kernel on a connected surface is the similarities. Two pinned vertices (the
//! two far-apart boundary vertices of the longest loop, [`super::boundary::far_pair`], at (0, 0)
//! and (1, 0)) remove it: `Q_FF x_F = −Q_FP x_P` is symmetric positive definite and solved by
//! faer's sparse Cholesky (`2n` unknowns, `u_i` and `v_i` interleaved). The interior sides'
//! area terms cancel, so `B` has entries on the boundary only. Holes need no filling: LSCM works
//! on any connected surface of genus 0 with a boundary (the cut mesh).

use super::sparse::from_entries;
use bevy::math::{DVec2, DVec3};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use super::params::ParamError;
use super::weights::cotangents;

/// The LSCM of the triangles over `positions` with the boundary `loops` (surface on the left)
/// and `pins` at (0, 0) and (1, 0). Returns every vertex's position.
///
/// # Errors
/// [`ParamError::Solve`] when the system is not positive definite (degenerate triangles, or a
/// piece not connected to the pins).
pub fn lscm(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    loops: &[Vec<u32>],
    pins: (u32, u32),
) -> Result<Vec<DVec2>, ParamError> {
    let n = positions.len();
    let mut pinned = vec![None; n];
    pinned[pins.0 as usize] = Some(DVec2::ZERO);
    pinned[pins.1 as usize] = Some(DVec2::X);
    // Unknowns: u_i = 2i, v_i = 2i + 1, renumbered without the pins' four.
    let mut column = vec![u32::MAX; 2 * n];
    let mut free = 0usize;
    for i in 0..n {
        if pinned[i].is_none() {
            column[2 * i] = free as u32;
            column[2 * i + 1] = free as u32 + 1;
            free += 2;
        }
    }
    let value = |r: usize| -> f64 {
        let p = pinned[r / 2].unwrap_or(DVec2::ZERO);
        if r.is_multiple_of(2) { p.x } else { p.y }
    };
    let mut rhs = Mat::<f64>::zeros(free, 1);
    let mut entries: Vec<(u32, u32, f64)> = Vec::with_capacity(12 * triangles.len());
    // Adds Q[r][c] += q, for every entry and its symmetric one alike: a free row keeps the
    // lower triangle, a pinned column goes to the right-hand side.
    let mut add = |r: usize, c: usize, q: f64| {
        let cr = column[r];
        if cr == u32::MAX {
            return;
        }
        let cc = column[c];
        if cc == u32::MAX {
            rhs[(cr as usize, 0)] -= q * value(c);
        } else if cr >= cc {
            entries.push((cr, cc, q));
        }
    };
    for tri in triangles {
        for (i, j, cot) in cotangents(positions, *tri) {
            let w = 0.5 * cot;
            let (i, j) = (i as usize, j as usize);
            for k in 0..2 {
                let (a, b) = (2 * i + k, 2 * j + k);
                add(a, a, w);
                add(b, b, w);
                add(a, b, -w);
                add(b, a, -w);
            }
        }
    }
    for l in loops {
        for k in 0..l.len() {
            let (i, j) = (l[k] as usize, l[(k + 1) % l.len()] as usize);
            // −B for the side i → j: −½ (u_i v_j − u_j v_i), spread symmetrically.
            add(2 * i, 2 * j + 1, -0.5);
            add(2 * j + 1, 2 * i, -0.5);
            add(2 * j, 2 * i + 1, 0.5);
            add(2 * i + 1, 2 * j, 0.5);
        }
    }
    let matrix = from_entries(free, &entries);
    let llt = matrix.sp_cholesky(Side::Lower).map_err(|e| {
        ParamError::Solve(format!(
            "the LSCM system is not positive definite ({e:?}): degenerate triangles?"
        ))
    })?;
    llt.solve_in_place(rhs.as_mut());
    let mut uv = vec![DVec2::ZERO; n];
    for i in 0..n {
        uv[i] = match pinned[i] {
            Some(p) => p,
            None => {
                let c = column[2 * i] as usize;
                DVec2::new(rhs[(c, 0)], rhs[(c + 1, 0)])
            }
        };
        if !uv[i].is_finite() {
            return Err(ParamError::Solve("the LSCM solve is not finite".into()));
        }
    }
    Ok(uv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::ops::param::cut::cut;
    use crate::ops::param::test_tables;

    #[test]
    fn a_planar_mesh_is_reproduced_up_to_similarity() {
        let mut soup = shapes::grid(6, 5);
        for (k, p) in soup.positions.iter_mut().enumerate() {
            let a = k as f32 * 2.399;
            p.x += 0.03 * a.cos();
            p.y += 0.03 * a.sin();
        }
        let t = test_tables(&soup);
        let c = cut(&t, &[], false).unwrap();
        let (a, b) = (c.loops[0][0], c.loops[0][5]);
        let uv = lscm(&c.positions, &c.triangles, &c.loops, (a, b)).unwrap();
        // The similarity taking a → (0,0), b → (1,0), as a complex map z ↦ (z − z_a) / (z_b − z_a).
        let (za, zb) = (
            c.positions[a as usize].truncate(),
            c.positions[b as usize].truncate(),
        );
        let d = zb - za;
        for (q, p) in uv.iter().zip(&c.positions) {
            let z = p.truncate() - za;
            let expected =
                DVec2::new(z.x * d.x + z.y * d.y, z.y * d.x - z.x * d.y) / d.length_squared();
            assert!(q.distance(expected) < 1e-9, "{q} vs {expected}");
        }
    }
}
