//! The rotation closest to a 3×3 matrix `A`: the `R` that maximises `f(R) = tr(Rᵀ A)` (the
//! rotational factor of `A`'s polar decomposition, or the best proper rotation when
//! `det A < 0`), found by Newton's method on the rotations, warm-started from a guess.
//!
//! Turning `R` by a small rotation vector `ω` (`R ← exp([ω]×) R`) and writing `B = A Rᵀ`,
//! `f = f₀ + g·ω + ½ ωᵀ (sym B − tr B · I) ω + O(|ω|³)`, where `g` is the axial vector of
//! `B − Bᵀ` (the "torque" `Σ_k r_k × a_k` of Müller, Bender, Chentanez & Macklin, "A Robust
//! Method to Extract the Rotational Part of Deformations", MIG 2016). The Newton step is
//! `ω = (tr B · I − sym B)⁻¹ g`; near the optimum that matrix has the eigenvalues `σ_i + σ_j`
//! of `A`'s singular values, positive even for the flat (rank-2) matrices of a surface's
//! one-rings, and the method converges quadratically: one or two steps from the last
//! iteration's rotation in as-rigid-as-possible deformation. Where the step is not an ascent
//! (far from the optimum) it falls back to Müller's step `ω = g / |tr B|`, which converges from
//! anywhere. The rotation stays a unit quaternion.

use bevy::math::{DMat3, DMat4, DQuat, DVec3, DVec4};

/// Jacobi sweeps at most for Horn's quaternion (a 4×4 converges in about five).
const JACOBI_SWEEPS: u32 = 12;

/// Steps at most.
const MAX_STEPS: u32 = 100;

/// The step (radians) under which the rotation is taken as converged. The energy is quadratic in
/// the rotation's error about its optimum, and after a Newton step of length `h` the error is
/// about `h²`: a Newton step under 1e-5 leaves it near 1e-10, a Müller step (linear
/// convergence) has to be under 1e-9 itself.
const NEWTON_CONVERGED: f64 = 1e-5;
/// See [`NEWTON_CONVERGED`].
const CONVERGED: f64 = 1e-9;

/// The rotation closest to `a` (see the module doc), starting from `guess`.
pub fn closest_rotation(a: &DMat3, guess: DQuat) -> DQuat {
    let mut q = guess.normalize();
    let mut next = step(a, q);
    if !next.1 {
        let start = better_start(a, q);
        if start != q {
            q = start;
            next = step(a, q);
        }
    }
    for _ in 0..MAX_STEPS {
        let (omega, newton) = next;
        let angle = omega.length();
        if angle.is_nan() {
            break;
        }
        // The last, small step is taken too: after a Newton step the error is about its square.
        q = (DQuat::from_scaled_axis(omega) * q).normalize();
        if angle <= if newton { NEWTON_CONVERGED } else { CONVERGED } {
            break;
        }
        next = step(a, q);
    }
    q
}

/// The step from `q`, and whether it is Newton's (`f` concave about `q`: near the maximum).
fn step(a: &DMat3, q: DQuat) -> (DVec3, bool) {
    let b = *a * DMat3::from_quat(q).transpose();
    let g = DVec3::new(
        b.y_axis.z - b.z_axis.y,
        b.z_axis.x - b.x_axis.z,
        b.x_axis.y - b.y_axis.x,
    );
    let trace = b.x_axis.x + b.y_axis.y + b.z_axis.z;
    let m = DMat3::from_diagonal(DVec3::splat(trace)) - (b + b.transpose()) * 0.5;
    // Positive definite by Sylvester's criterion: the leading minors.
    let minor = m.x_axis.x * m.y_axis.y - m.y_axis.x * m.x_axis.y;
    if m.x_axis.x > 0.0 && minor > 0.0 && m.determinant() > 0.0 {
        let newton = m.inverse() * g;
        if newton.is_finite() && newton.length() < 1.0 {
            return (newton, true);
        }
    }
    (g / (trace.abs() + 1e-300), false)
}

/// Horn's matrix: `vᵀ N v = tr(R(q)ᵀ A)` for the unit quaternion `q` with components
/// `v = (x, y, z, w)` (glam's order).
fn horn(a: &DMat3) -> DMat4 {
    // S_xy = Σ_k (e_k)_x (a_k)_y: the basis vectors rotated onto `a`'s columns.
    let s = |i: usize, j: usize| a.col(i)[j];
    let (xx, xy, xz) = (s(0, 0), s(0, 1), s(0, 2));
    let (yx, yy, yz) = (s(1, 0), s(1, 1), s(1, 2));
    let (zx, zy, zz) = (s(2, 0), s(2, 1), s(2, 2));
    // Horn's matrix in the order (w, x, y, z).
    let h = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    // Reordered to (x, y, z, w).
    let at = |k: usize| (k + 1) % 4;
    DMat4::from_cols_array(&std::array::from_fn(|n| h[at(n % 4)][at(n / 4)]))
}

/// A start in the concave region about the maximum, for a guess far from it (near a saddle of
/// `f`, where the torque vanishes too): the best rotation itself, as the unit quaternion of the
/// largest eigenvalue of Horn's symmetric 4×4 matrix `N(A)` (Horn, "Closed-form solution of
/// absolute orientation using unit quaternions", 1987: `f(q) = qᵀ N q`), found by Jacobi's
/// method. (Power iterations are not enough: a one-ring whose deformed spokes are nearly
/// collinear gives eigenvalues so close that forty of them stop short, and Müller's steps
/// from there crawl.) The guess stays where it scores at least as well.
fn better_start(a: &DMat3, guess: DQuat) -> DQuat {
    let found = DQuat::from_vec4(largest_eigenvector(horn(a))).normalize();
    let score = |q: DQuat| {
        let r = DMat3::from_quat(q);
        r.x_axis.dot(a.x_axis) + r.y_axis.dot(a.y_axis) + r.z_axis.dot(a.z_axis)
    };
    if found.is_finite() && score(found) > score(guess) {
        found
    } else {
        guess
    }
}

/// The unit eigenvector of the largest eigenvalue of the symmetric `n`, by cyclic Jacobi
/// rotations (Golub & Van Loan, *Matrix Computations*, §8.5): each zeroes one off-diagonal
/// entry; sweeps stop when the off-diagonal part is negligible against the diagonal.
fn largest_eigenvector(mut n: DMat4) -> DVec4 {
    let mut vectors = DMat4::IDENTITY;
    for _ in 0..JACOBI_SWEEPS {
        let off: f64 = (0..4)
            .flat_map(|i| (0..i).map(move |j| (i, j)))
            .map(|(i, j)| n.col(i)[j] * n.col(i)[j])
            .sum();
        let diagonal: f64 = (0..4).map(|i| n.col(i)[i] * n.col(i)[i]).sum();
        if off <= f64::EPSILON * f64::EPSILON * diagonal || off == 0.0 {
            break;
        }
        for p in 0..3 {
            for q in p + 1..4 {
                let apq = n.col(q)[p];
                if apq == 0.0 {
                    continue;
                }
                // The rotation (c, s) that zeroes n[p][q].
                let theta = (n.col(q)[q] - n.col(p)[p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                let mut g = DMat4::IDENTITY;
                g.col_mut(p)[p] = c;
                g.col_mut(q)[q] = c;
                g.col_mut(q)[p] = s;
                g.col_mut(p)[q] = -s;
                n = g.transpose() * n * g;
                vectors *= g;
            }
        }
    }
    let largest = (0..4)
        .max_by(|&i, &j| n.col(i)[i].total_cmp(&n.col(j)[j]))
        .unwrap_or(0);
    vectors.col(largest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotation_times_a_stretch_gives_the_rotation_back() {
        let rotation = DQuat::from_euler(bevy::math::EulerRot::XYZ, 0.7, -1.2, 2.1);
        // A symmetric positive definite stretch: R S has polar factor R.
        let stretch = DMat3::from_cols(
            DVec3::new(2.0, 0.3, 0.1),
            DVec3::new(0.3, 1.5, -0.2),
            DVec3::new(0.1, -0.2, 0.8),
        );
        let a = DMat3::from_quat(rotation) * stretch;
        for guess in [DQuat::IDENTITY, rotation, DQuat::from_rotation_z(3.0)] {
            let found = closest_rotation(&a, guess);
            assert!(
                found.angle_between(rotation) < 1e-7,
                "from {guess:?}: {found:?}"
            );
        }
    }

    #[test]
    fn a_rotation_is_its_own_closest() {
        let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.4);
        let found = closest_rotation(&DMat3::from_quat(rotation), DQuat::IDENTITY);
        assert!(found.angle_between(rotation) < 1e-12);
        // The zero matrix has no torque: the guess stays.
        assert_eq!(
            closest_rotation(&DMat3::ZERO, rotation),
            rotation.normalize()
        );
    }
}

#[cfg(test)]
mod against_svd {
    use super::*;

    /// The best proper rotation by SVD (faer): `R = U diag(1, 1, det(U Vᵀ)) Vᵀ`.
    fn by_svd(a: &DMat3) -> DMat3 {
        let m = faer::Mat::<f64>::from_fn(3, 3, |i, j| a.col(j)[i]);
        let svd = m.svd().unwrap();
        let (u, v) = (svd.U(), svd.V());
        let to = |x: faer::MatRef<'_, f64>| {
            DMat3::from_cols_array(&std::array::from_fn(|k| x[(k % 3, k / 3)]))
        };
        let (u, v) = (to(u), to(v));
        let d = (u * v.transpose()).determinant().signum();
        u * DMat3::from_diagonal(DVec3::new(1.0, 1.0, d)) * v.transpose()
    }

    /// Numbers uniform in [−1, 1), from a linear congruential generator seeded with `seed`.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn score(r: &DMat3, a: &DMat3) -> f64 {
        (0..3).map(|k| r.col(k).dot(a.col(k))).sum()
    }

    #[test]
    fn horns_matrix_gives_the_score_of_every_rotation() {
        let a = DMat3::from_cols_array(&[0.3, -1.2, 0.5, 2.0, 0.1, -0.7, 0.4, 0.9, 1.1]);
        for q in [
            DQuat::IDENTITY,
            DQuat::from_rotation_x(1.0),
            DQuat::from_rotation_y(-2.0),
            DQuat::from_scaled_axis(DVec3::new(0.3, -0.8, 1.9)),
        ] {
            let v = DVec4::from(q.to_array());
            let quadratic = v.dot(horn(&a) * v);
            assert!(
                (quadratic - score(&DMat3::from_quat(q), &a)).abs() < 1e-12,
                "{q:?}"
            );
        }
    }

    #[test]
    fn newton_reaches_the_svd_optimum_from_the_identity() {
        let mut next = uniform(12345);
        let mut worst: f64 = 0.0;
        for trial in 0..2000 {
            let mut a = DMat3::from_cols_array(&std::array::from_fn(|_| next()));
            if trial % 3 == 0 {
                // Flat, as a surface's one-ring: rank 2.
                a.z_axis = DVec3::ZERO;
                a = DMat3::from_quat(DQuat::from_scaled_axis(
                    DVec3::new(next(), next(), next()) * 3.0,
                )) * a;
            }
            let best = score(&by_svd(&a), &a);
            let ours = score(&DMat3::from_quat(closest_rotation(&a, DQuat::IDENTITY)), &a);
            worst = worst.max((best - ours) / best.abs().max(1e-12));
        }
        assert!(worst < 1e-9, "worst relative shortfall {worst}");
    }

    /// Flat one-rings whose deformed spokes are nearly collinear (singular values 1, ε, 0) and
    /// whose best rotation folds the ring over (a half turn about an axis in its plane), from
    /// the identity and from random guesses: the cases where power iterations toward Horn's
    /// quaternion stopped short and the steps from there crawled.
    #[test]
    fn nearly_collinear_flat_rings_reach_the_svd_optimum() {
        let mut next = uniform(777);
        let mut worst: f64 = 0.0;
        for trial in 0..3000 {
            let mut turn = || {
                DMat3::from_quat(DQuat::from_scaled_axis(
                    DVec3::new(next(), next(), next()) * 3.0,
                ))
            };
            let (u, v) = (turn(), turn());
            let epsilon = 10f64.powf(-1.0 - 3.0 * (trial % 7) as f64 / 6.0);
            let mirror = if trial % 2 == 0 { 1.0 } else { -1.0 };
            let a =
                u * DMat3::from_diagonal(DVec3::new(1.0, epsilon * mirror, 0.0)) * v.transpose();
            let guess = if trial % 3 == 0 {
                DQuat::IDENTITY
            } else {
                DQuat::from_mat3(&turn())
            };
            let best = score(&by_svd(&a), &a);
            let ours = score(&DMat3::from_quat(closest_rotation(&a, guess)), &a);
            worst = worst.max((best - ours) / best.abs().max(1e-12));
        }
        assert!(worst < 1e-9, "worst relative shortfall {worst}");
    }

    #[test]
    fn jacobi_finds_the_largest_eigenvector() {
        let n = DMat4::from_cols_array(&[
            4.0, 1.0, -2.0, 0.5, 1.0, 3.0, 0.0, 1.5, -2.0, 0.0, -1.0, 2.0, 0.5, 1.5, 2.0, 2.0,
        ]);
        let v = largest_eigenvector(n);
        let lambda = v.dot(n * v);
        assert!((n * v - v * lambda).length() < 1e-12);
        // No other unit vector scores higher: the Rayleigh quotient's maximum.
        for w in [
            DVec4::X,
            DVec4::Y,
            DVec4::Z,
            DVec4::W,
            DVec4::ONE.normalize(),
        ] {
            assert!(w.dot(n * w) <= lambda + 1e-12);
        }
    }
}
