//! The barycentric (Tutte) mapping: the outer boundary fixed on a convex polygon, every other
//! vertex at the weighted mean of its neighbours (Tutte 1963; Floater 1997, 2003).
//!
//! For the free vertices `i`, `Σ_j w_ij (u_i − u_j) = 0` with the fixed vertices' terms moved to
//! the right-hand side: one sparse solve with two right-hand sides (u and v). With symmetric
//! weights (uniform, harmonic) the matrix is symmetric, and positive definite when the weights
//! are positive: faer's sparse Cholesky (falling back to LU when harmonic weights make it
//! indefinite); mean-value weights are not symmetric: sparse LU.
//!
//! **Several boundary loops.** The longest loop is the outer boundary. Every other loop (a hole)
//! is filled *virtually* for the solve: a virtual vertex at the loop's centroid, fanned to the
//! loop's vertices. The graph is then a triangulated disk, so with positive weights (uniform,
//! mean-value: the virtual triangles get their weights from their own geometry like every
//! triangle) Tutte's theorem still guarantees an embedding without flips. The virtual vertices
//! and triangles are dropped from the output: the hole becomes a star-shaped gap in the layout.
//!
//! [`solve_fixed`] is the entry point with the boundary fixed to any given positions: a planar
//! mesh with a convex boundary fixed at its own positions is reproduced exactly by weights with
//! linear precision (mean-value, harmonic) — what the tests check.

use bevy::math::{DVec2, DVec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::Solve;
use faer::sparse::SparseColMat;
use faer::sparse::linalg::cholesky::{SymmetricOrdering, factorize_symbolic_cholesky};
use faer::{Conj, Mat, Par, Side};

use super::params::{ParamError, ParamMethod};
use super::sparse::from_entries;
use super::weights::{Weight, weights};

/// Which factorization solved a system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Sparse Cholesky (symmetric positive definite).
    #[default]
    Cholesky,
    /// Sparse LU with partial pivoting.
    Lu,
}

impl Solver {
    /// Its name in a report.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Cholesky => "cholesky",
            Solver::Lu => "lu",
        }
    }
}

/// The triangles of the virtual fills of `holes` (each loop fanned to a new vertex at its
/// centroid), appended to `positions` and `triangles`. Returns how many vertices were added.
pub fn fill_holes(
    positions: &mut Vec<DVec3>,
    triangles: &mut Vec<[u32; 3]>,
    holes: &[Vec<u32>],
) -> usize {
    for hole in holes {
        let centre = positions.len() as u32;
        let centroid =
            hole.iter().map(|&c| positions[c as usize]).sum::<DVec3>() / hole.len() as f64;
        positions.push(centroid);
        // The loop runs with the surface on its left, so the fill goes the other way round.
        for k in 0..hole.len() {
            let (a, b) = (hole[k], hole[(k + 1) % hole.len()]);
            triangles.push([b, a, centre]);
        }
    }
    holes.len()
}

/// The barycentric mapping of `triangles` with `method`'s weights and the `fixed` positions
/// (`Some` on the boundary): every vertex's position, and the factorization used.
///
/// Which entries the matrix has depends only on which vertices are neighbours, not on the
/// weights: for the symmetric weights (uniform, harmonic) the fill-reducing ordering and the
/// symbolic Cholesky factorization — half the solve — run on a second thread while this one
/// computes the weights and assembles the values. Mean-value weights go to [`solve_fixed`]'s
/// LU; so do harmonic weights whose matrix is not positive definite.
///
/// # Errors
/// As [`solve_fixed`].
pub fn solve_triangles(
    method: ParamMethod,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    fixed: &[Option<DVec2>],
) -> Result<(Vec<DVec2>, Solver), ParamError> {
    if method == ParamMethod::MeanValue {
        let w = weights(method, positions, triangles);
        return solve_fixed(&w, fixed, false);
    }
    let (column, free) = columns(fixed);
    let mut uv: Vec<DVec2> = fixed.iter().map(|f| f.unwrap_or(DVec2::ZERO)).collect();
    if free == 0 {
        return Ok((uv, Solver::Cholesky));
    }
    let (symbolic, w, (matrix, rhs)) = std::thread::scope(|scope| {
        let symbolic = scope.spawn(|| {
            let mut pattern = Vec::with_capacity(3 * triangles.len() + free);
            for tri in triangles {
                for k in 0..3 {
                    let (i, j) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
                    let (ci, cj) = (column[i], column[j]);
                    if ci != u32::MAX && cj != u32::MAX {
                        pattern.push((ci.max(cj), ci.min(cj), 0.0));
                    }
                }
            }
            pattern.extend((0..free as u32).map(|c| (c, c, 0.0)));
            let pattern = from_entries(free, &pattern);
            factorize_symbolic_cholesky(
                pattern.symbolic(),
                Side::Lower,
                SymmetricOrdering::Amd,
                Default::default(),
            )
        });
        let w = weights(method, positions, triangles);
        let system = assemble(&w, &column, free, &uv, true);
        let symbolic = symbolic
            .join()
            .expect("the symbolic factorization does not panic");
        (symbolic, w, system)
    });
    // Not positive definite (harmonic weights beside obtuse angles), or not finite: LU.
    let by_lu = |mut uv: Vec<DVec2>| -> Result<(Vec<DVec2>, Solver), ParamError> {
        let x = solve_lu(&w, &column, free, &uv)?;
        place(&mut uv, &column, &x)?;
        Ok((uv, Solver::Lu))
    };
    let Ok(symbolic) = symbolic else {
        return by_lu(uv);
    };
    let mut values = vec![0.0f64; symbolic.len_val()];
    let par = Par::Seq;
    let llt = symbolic.factorize_numeric_llt(
        &mut values,
        matrix.as_ref(),
        Side::Lower,
        Default::default(),
        par,
        MemStack::new(&mut MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )),
        Default::default(),
    );
    let Ok(llt) = llt else {
        return by_lu(uv);
    };
    let mut x = rhs;
    llt.solve_in_place_with_conj(
        Conj::No,
        x.as_mut(),
        par,
        MemStack::new(&mut MemBuffer::new(
            llt.solve_in_place_scratch::<f64>(2, par),
        )),
    );
    if !finite(&x) {
        return by_lu(uv);
    }
    place(&mut uv, &column, &x)?;
    Ok((uv, Solver::Cholesky))
}

/// Whether every entry of `x` is finite.
fn finite(x: &Mat<f64>) -> bool {
    x.col_iter().all(|c| c.iter().all(|v| v.is_finite()))
}

/// The unknowns of the full system (both triangles), by sparse LU.
fn solve_lu(
    weights: &[Weight],
    column: &[u32],
    free: usize,
    uv: &[DVec2],
) -> Result<Mat<f64>, ParamError> {
    let (full, mut x) = assemble(weights, column, free, uv, false);
    let lu = full
        .sp_lu()
        .map_err(|e| ParamError::Solve(format!("the sparse LU failed: {e:?}")))?;
    lu.solve_in_place(x.as_mut());
    Ok(x)
}

/// Writes the solved unknowns `x` into the free vertices' positions.
///
/// # Errors
/// [`ParamError::Solve`] when one is not finite (a singular system).
fn place(uv: &mut [DVec2], column: &[u32], x: &Mat<f64>) -> Result<(), ParamError> {
    for (p, &c) in uv.iter_mut().zip(column) {
        if c != u32::MAX {
            let q = DVec2::new(x[(c as usize, 0)], x[(c as usize, 1)]);
            if !q.is_finite() {
                return Err(ParamError::Solve(
                    "the system is singular (a degenerate mesh?)".into(),
                ));
            }
            *p = q;
        }
    }
    Ok(())
}

/// Each free vertex's unknown (`u32::MAX` for a fixed one), and how many are free.
fn columns(fixed: &[Option<DVec2>]) -> (Vec<u32>, usize) {
    let mut column = vec![u32::MAX; fixed.len()];
    let mut free = 0usize;
    for (i, f) in fixed.iter().enumerate() {
        if f.is_none() {
            column[i] = free as u32;
            free += 1;
        }
    }
    (column, free)
}

/// The free vertices' system: `column[i]` is vertex `i`'s unknown (`u32::MAX` when fixed, then
/// `uv[i]` is its position), only the lower triangle when `lower`. Returns the matrix and the
/// right-hand sides (the fixed neighbours' pull), one column per coordinate.
fn assemble(
    weights: &[Weight],
    column: &[u32],
    free: usize,
    uv: &[DVec2],
    lower: bool,
) -> (SparseColMat<usize, f64>, Mat<f64>) {
    let mut rhs = Mat::<f64>::zeros(free, 2);
    let mut entries = Vec::with_capacity(weights.len() + free);
    let mut diagonal = vec![0.0f64; free];
    for &(i, j, w) in weights {
        let ci = column[i as usize];
        if ci == u32::MAX {
            continue;
        }
        diagonal[ci as usize] += w;
        let cj = column[j as usize];
        if cj == u32::MAX {
            let p = uv[j as usize];
            rhs[(ci as usize, 0)] += w * p.x;
            rhs[(ci as usize, 1)] += w * p.y;
        } else if !lower || ci > cj {
            // Row ci is free vertex i's equation; Cholesky reads the lower triangle only.
            entries.push((ci, cj, -w));
        }
    }
    entries.extend(
        diagonal
            .iter()
            .enumerate()
            .map(|(c, &d)| (c as u32, c as u32, d)),
    );
    (from_entries(free, &entries), rhs)
}

/// Solves the barycentric mapping with `weights` (directed entries, summed) over the vertices of
/// `fixed`: `fixed[i]` is `Some(position)` for a fixed vertex, `None` for a free one. `symmetric` says the
/// weights are (then Cholesky is tried first). Returns every vertex's position.
///
/// # Errors
/// [`ParamError::Solve`] when the system is singular (a free vertex connected to no fixed
/// one, or zero weights everywhere around a vertex).
pub fn solve_fixed(
    weights: &[Weight],
    fixed: &[Option<DVec2>],
    symmetric: bool,
) -> Result<(Vec<DVec2>, Solver), ParamError> {
    let (column, free) = columns(fixed);
    let mut uv: Vec<DVec2> = fixed.iter().map(|f| f.unwrap_or(DVec2::ZERO)).collect();
    if free == 0 {
        return Ok((uv, Solver::Cholesky));
    }
    let cholesky = symmetric
        .then(|| {
            let (lower, mut x) = assemble(weights, &column, free, &uv, true);
            let llt = lower.sp_cholesky(Side::Lower).ok()?;
            llt.solve_in_place(x.as_mut());
            finite(&x).then_some(x)
        })
        .flatten();
    let (x, solver) = match cholesky {
        Some(x) => (x, Solver::Cholesky),
        None => (solve_lu(weights, &column, free, &uv)?, Solver::Lu),
    };
    place(&mut uv, &column, &x)?;
    Ok((uv, solver))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::ops::param::test_tables;
    use crate::ops::param::{ParamMethod, cut::cut, weights::weights};

    /// A planar grid with its interior vertices jittered (deterministically), its boundary
    /// fixed at its own positions, is reproduced by the weights with linear precision.
    #[test]
    fn a_planar_mesh_with_its_own_boundary_is_reproduced() {
        let mut soup = shapes::grid(7, 6);
        for (k, p) in soup.positions.iter_mut().enumerate() {
            let inside = p.x > 1e-6 && p.x < 1.0 - 1e-6 && p.y > 1e-6 && p.y < 1.0 - 1e-6;
            if inside {
                let a = k as f32 * 2.399;
                p.x += 0.04 * a.cos();
                p.y += 0.04 * a.sin();
            }
        }
        let t = test_tables(&soup);
        let c = cut(&t, &[], false).unwrap();
        let mut fixed = vec![None; c.vertex_count()];
        for &b in &c.loops[0] {
            fixed[b as usize] = Some(c.positions[b as usize].truncate());
        }
        for (method, symmetric) in [
            (ParamMethod::MeanValue, false),
            (ParamMethod::Harmonic, true),
        ] {
            let w = weights(method, &c.positions, &c.triangles);
            let (uv, _) = solve_fixed(&w, &fixed, symmetric).unwrap();
            for (q, p) in uv.iter().zip(&c.positions) {
                assert!(q.distance(p.truncate()) < 1e-9, "{method:?}: {q} vs {p}");
            }
        }
    }

    #[test]
    fn uniform_weights_on_a_regular_grid_give_the_grid() {
        // The fan-split grid: each interior vertex has 6 neighbours, symmetric in pairs, so
        // the regular grid is their mean.
        let t = test_tables(&shapes::grid(5, 5));
        let c = cut(&t, &[], false).unwrap();
        let mut fixed = vec![None; c.vertex_count()];
        for &b in &c.loops[0] {
            fixed[b as usize] = Some(c.positions[b as usize].truncate());
        }
        let w = weights(ParamMethod::Uniform, &c.positions, &c.triangles);
        let (uv, solver) = solve_fixed(&w, &fixed, true).unwrap();
        assert_eq!(solver, Solver::Cholesky);
        for (q, p) in uv.iter().zip(&c.positions) {
            // The grid's f32 positions are regular to f32 rounding.
            assert!(q.distance(p.truncate()) < 1e-7, "{q} vs {p}");
        }
    }
}
