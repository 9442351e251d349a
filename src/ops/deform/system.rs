//! The linear algebra the deformations share: the cotangent Laplacian and its powers as sparse
//! matrices, and a symmetric system solved with some unknowns held at given values.
//!
//! With `L` the cotangent stiffness matrix (`L_ii = Σ_j w_ij`, `L_ij = −w_ij`, positive
//! semi-definite) and `M` the diagonal of mixed areas, the k-harmonic operator is
//! `L (M⁻¹ L)^(k−1)`: `L` for k = 1 (membrane), `L M⁻¹ L` for k = 2 (thin plate), and so on. Its
//! only null space on a connected surface is the constants, so one held vertex per component
//! makes the free block positive definite; [`HeldSystem`] factors that block once (faer's sparse
//! Cholesky, fill-reducing ordering included) and then solves for any values of the held
//! unknowns by moving their columns to the right-hand side.

use bevy::math::DVec3;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::ops::Refusal;

/// Free unknowns from which a solve splits its columns over two threads.
const PARALLEL_SOLVE: usize = 10_000;

/// The cotangent stiffness matrix of `n` vertices from the merged edge weights `(i, j, w)`,
/// each scaled by `1 / scale[i]` on row `i` when `scale` is given (`M⁻¹ L`).
fn stiffness(
    n: usize,
    edges: &[(u32, u32, f64)],
    scale: Option<&[f64]>,
) -> SparseColMat<usize, f64> {
    let mut diagonal = vec![0.0; n];
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(2 * edges.len() + n);
    let row_scale = |i: usize| scale.map_or(1.0, |s| 1.0 / s[i]);
    for &(i, j, w) in edges {
        let (i, j) = (i as usize, j as usize);
        diagonal[i] += w;
        diagonal[j] += w;
        triplets.push(Triplet::new(i, j, -w * row_scale(i)));
        triplets.push(Triplet::new(j, i, -w * row_scale(j)));
    }
    for (i, d) in diagonal.into_iter().enumerate() {
        triplets.push(Triplet::new(i, i, d * row_scale(i)));
    }
    SparseColMat::try_new_from_triplets(n, n, &triplets)
        .expect("indices below n, duplicates summed")
}

/// The k-harmonic operator `L (M⁻¹ L)^(k−1)` (see the module doc) of `n` vertices with these
/// edge weights and vertex areas. Areas are clamped below at a millionth of their mean, so a
/// vertex on flat, degenerate triangles does not divide by zero.
pub fn k_harmonic(
    n: usize,
    edges: &[(u32, u32, f64)],
    areas: &[f64],
    k: u32,
) -> SparseColMat<usize, f64> {
    let l = stiffness(n, edges, None);
    if k <= 1 {
        return l;
    }
    let mean = areas.iter().sum::<f64>() / areas.len().max(1) as f64;
    let floor = (mean * 1e-6).max(f64::MIN_POSITIVE);
    let clamped: Vec<f64> = areas.iter().map(|a| a.max(floor)).collect();
    let scaled = stiffness(n, edges, Some(&clamped));
    let mut operator = l.clone();
    for _ in 1..k {
        operator = operator.as_ref() * scaled.as_ref();
    }
    operator
}

/// A symmetric positive semi-definite system `A x = b` over the vertices with some of them held
/// at given values: the free block of `A` factored once, solved for any held values and any
/// right-hand side. Three columns (x, y, z) at a time.
pub struct HeldSystem {
    /// Each vertex's column among the free unknowns, or `u32::MAX` when held.
    column: Vec<u32>,
    /// The free vertices, by column.
    free: Vec<u32>,
    /// `A`'s entries in a free row and a held column: (free column, held vertex, value).
    coupling: Vec<(u32, u32, f64)>,
    llt: Llt<usize, f64>,
}

impl HeldSystem {
    /// Factors the free block of `a` (square, symmetric), the vertices with `held[v]` set held.
    ///
    /// # Refusals
    /// [`Refusal::BadParameter`] when nothing is free, or when the free block is not positive
    /// definite (a component with no held vertex, or degenerate triangles).
    pub fn new(a: &SparseColMat<usize, f64>, held: &[bool]) -> Result<Self, Refusal> {
        let n = held.len();
        let mut column = vec![u32::MAX; n];
        let mut free = Vec::new();
        for (v, &h) in held.iter().enumerate() {
            if !h {
                column[v] = free.len() as u32;
                free.push(v as u32);
            }
        }
        if free.is_empty() {
            return Err(Refusal::BadParameter(
                "every vertex is held: nothing is free to move".into(),
            ));
        }
        let mut triplets = Vec::with_capacity(a.compute_nnz());
        let mut coupling = Vec::new();
        let (col_ptr, row_idx, values) = (a.col_ptr(), a.row_idx(), a.val());
        for j in 0..n {
            for k in col_ptr[j]..col_ptr[j + 1] {
                let (i, value) = (row_idx[k], values[k]);
                match (column[i], column[j]) {
                    (u32::MAX, _) => {}
                    (ci, u32::MAX) => coupling.push((ci, j as u32, value)),
                    (ci, cj) if cj <= ci => {
                        triplets.push(Triplet::new(ci as usize, cj as usize, value));
                    }
                    _ => {}
                }
            }
        }
        let size = free.len();
        let block = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &triplets)
            .map_err(|e| Refusal::BadParameter(format!("the deformation system: {e:?}")))?;
        let llt = block.sp_cholesky(Side::Lower).map_err(|e| {
            Refusal::BadParameter(format!(
                "the deformation system is singular ({e:?}): a part of the mesh with nothing \
                 held, or degenerate triangles"
            ))
        })?;
        Ok(Self {
            column,
            free,
            coupling,
            llt,
        })
    }

    /// The free vertices, in column order.
    pub fn free(&self) -> &[u32] {
        &self.free
    }

    /// Whether vertex `v` is held.
    pub fn is_held(&self, v: u32) -> bool {
        self.column[v as usize] == u32::MAX
    }

    /// Solves `A x = b` for the free vertices of `x`, its held ones read as given; `b` is zero
    /// where `rhs` is `None`. Writes the free values into `x`; a value that came out not finite
    /// (a nearly singular block) leaves that vertex as it was.
    pub fn solve(&self, rhs: Option<&[DVec3]>, x: &mut [DVec3]) {
        let size = self.free.len();
        let mut b = Mat::<f64>::zeros(size, 3);
        if let Some(rhs) = rhs {
            for (c, &v) in self.free.iter().enumerate() {
                let r = rhs[v as usize];
                (b[(c, 0)], b[(c, 1)], b[(c, 2)]) = (r.x, r.y, r.z);
            }
        }
        for &(c, v, value) in &self.coupling {
            let held = x[v as usize] * value;
            let c = c as usize;
            b[(c, 0)] -= held.x;
            b[(c, 1)] -= held.y;
            b[(c, 2)] -= held.z;
        }
        if size < PARALLEL_SOLVE {
            self.llt.solve_in_place(b.as_mut());
        } else {
            // x and y on one core, z on another (both read the same factor).
            let (xy, z) = b.as_mut().split_at_col_mut(2);
            std::thread::scope(|scope| {
                scope.spawn(|| self.llt.solve_in_place(z));
                self.llt.solve_in_place(xy);
            });
        }
        for (c, &v) in self.free.iter().enumerate() {
            let p = DVec3::new(b[(c, 0)], b[(c, 1)], b[(c, 2)]);
            if p.is_finite() {
                x[v as usize] = p;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path of four vertices with unit weights: the 1-D Laplacian.
    fn path() -> Vec<(u32, u32, f64)> {
        vec![(0, 1, 1.0), (1, 2, 1.0), (2, 3, 1.0)]
    }

    #[test]
    fn the_membrane_interpolates_linearly_between_held_ends() {
        let a = k_harmonic(4, &path(), &[1.0; 4], 1);
        let system = HeldSystem::new(&a, &[true, false, false, true]).unwrap();
        let mut x = vec![
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::new(3.0, 6.0, -3.0),
        ];
        system.solve(None, &mut x);
        assert!(
            (x[1] - DVec3::new(1.0, 2.0, -1.0)).length() < 1e-12,
            "{:?}",
            x[1]
        );
        assert!(
            (x[2] - DVec3::new(2.0, 4.0, -2.0)).length() < 1e-12,
            "{:?}",
            x[2]
        );
    }

    #[test]
    fn the_thin_plate_operator_is_the_squared_stencil() {
        // On a path with unit areas, L M⁻¹ L = L²: row 1 is −row 0 + 2 row 1 − row 2 of L,
        // (−3, 6, −4, 1), the interior stencil 1 −4 6 −4 1 cut off by the free end.
        let a = k_harmonic(4, &path(), &[1.0; 4], 2);
        let dense = a.to_dense();
        let row: Vec<f64> = (0..4).map(|j| dense[(1, j)]).collect();
        assert_eq!(row, vec![-3.0, 6.0, -4.0, 1.0]);
        for i in 0..4 {
            for j in 0..4 {
                assert_eq!(dense[(i, j)], dense[(j, i)]);
            }
        }
    }

    #[test]
    fn nothing_free_or_nothing_held_is_refused() {
        let a = k_harmonic(4, &path(), &[1.0; 4], 1);
        assert!(HeldSystem::new(&a, &[true; 4]).is_err());
        // Nothing held: L is singular (the constants).
        assert!(HeldSystem::new(&a, &[false; 4]).is_err());
    }
}
