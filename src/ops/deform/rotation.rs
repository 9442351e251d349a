//! The rotation closest to a 3×3 matrix, by Müller, Bender, Chentanez & Macklin, "A Robust
//! Method to Extract the Rotational Part of Deformations" (MIG 2016).
//!
//! The rotation `R` that maximises `tr(Rᵀ A)` (the rotational factor of `A`'s polar
//! decomposition, or the best proper rotation when `det A < 0`) is where the "torque"
//! `Σ_k r_k × a_k` of `R`'s columns against `A`'s vanishes. Starting from a guess (last
//! iteration's rotation, in as-rigid-as-possible deformation), each step turns `R` about that
//! torque by its length over `|Σ_k r_k · a_k|`: a damped Newton step that converges in a few
//! iterations from a near guess, needs no SVD, and never leaves the rotations (a unit
//! quaternion, renormalised each step).

use bevy::math::{DMat3, DQuat, DVec3};

/// Iterations at most; a warm start usually stops after two or three.
const MAX_ITERATIONS: u32 = 30;

/// The torque, relative to the alignment, under which the rotation is taken as converged.
const CONVERGED: f64 = 1e-12;

/// The rotation closest to `a` (see the module doc), starting from `guess`.
pub fn closest_rotation(a: &DMat3, guess: DQuat) -> DQuat {
    let mut q = guess.normalize();
    for _ in 0..MAX_ITERATIONS {
        let r = DMat3::from_quat(q);
        let torque = r.x_axis.cross(a.x_axis) + r.y_axis.cross(a.y_axis) + r.z_axis.cross(a.z_axis);
        let alignment = r.x_axis.dot(a.x_axis) + r.y_axis.dot(a.y_axis) + r.z_axis.dot(a.z_axis);
        let omega: DVec3 = torque / (alignment.abs() + 1e-300);
        let angle = omega.length();
        if angle.is_nan() || angle <= CONVERGED {
            break;
        }
        q = (DQuat::from_axis_angle(omega / angle, angle) * q).normalize();
    }
    q
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
                found.angle_between(rotation) < 1e-9,
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
