//! How good a layout is: flipped triangles, angle, conformal and area distortion.
//!
//! Measured on the fanned triangles of the cut mesh (a polygon counts once per fan triangle),
//! real triangles only (never the virtual hole fills), with the final UVs:
//!
//! - **flipped**: signed UV area < 0 for a triangle whose 3D area is > 0 (turned over).
//! - **degenerate**: UV area zero to rounding (under 1e-9 of its longest UV side squared) though
//!   the 3D area is not: three corners on one line. Tutte's theorem guarantees an embedding only
//!   for a 3-connected graph; a vertex with two neighbours (a polygon corner with no other
//!   face, or three boundary vertices on one side of the square) lands on the line between
//!   them. Not turned over, but no texture either.
//! - **angle distortion**: the mean over the corners of non-degenerate triangles of
//!   |angle in UV − angle in 3D|, in degrees (0 for a conformal map).
//! - **conformal energy** (the LSCM energy, Lévy et al. 2002): `Σ_T (E_D − A_uv)` over the total
//!   UV area (unsigned), scale-free, 0 exactly for a conformal map, ≥ 0.
//! - **area distortion**: the 3D-area-weighted mean of `|ln r_T|`, `r_T` the triangle's share of
//!   the UV area over its share of the 3D area, over unflipped triangles (0 when every triangle
//!   keeps its share of the area).

use bevy::math::{DVec2, DVec3};

use super::weights::cotangents;

/// The figures of [`measure`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Distortion {
    /// Triangles with signed UV area < 0 (and 3D area > 0).
    pub flipped: usize,
    /// Triangles with UV area zero to rounding (and 3D area > 0).
    pub degenerate: usize,
    /// Mean |angle in UV − angle in 3D| over corners, degrees.
    pub angle_deg: f64,
    /// Conformal energy over UV area (≥ 0; 0 for a conformal map).
    pub conformal: f64,
    /// 3D-area-weighted mean |ln(UV area share / 3D area share)|.
    pub area: f64,
}

/// The distortion of `uv` (by vertex) against `positions` over `triangles`.
pub fn measure(positions: &[DVec3], uv: &[DVec2], triangles: &[[u32; 3]]) -> Distortion {
    let mut d = Distortion::default();
    let (mut angle_sum, mut corners) = (0.0, 0usize);
    let (mut energy, mut uv_area, mut area_3d) = (0.0, 0.0, 0.0);
    let mut areas = Vec::with_capacity(triangles.len());
    for &tri in triangles {
        let p = tri.map(|i| positions[i as usize]);
        let q = tri.map(|i| uv[i as usize]);
        let a3 = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        let auv = 0.5 * (q[1] - q[0]).perp_dot(q[2] - q[0]);
        areas.push((a3, auv));
        if a3 <= 0.0 {
            continue;
        }
        let longest = (q[1] - q[0])
            .length_squared()
            .max((q[2] - q[1]).length_squared())
            .max((q[0] - q[2]).length_squared());
        if auv.abs() <= 1e-9 * longest {
            d.degenerate += 1;
        } else if auv < 0.0 {
            d.flipped += 1;
        }
        area_3d += a3;
        uv_area += auv.abs();
        let mut dirichlet = 0.0;
        for (k, (i, j, cot)) in cotangents(positions, tri).into_iter().enumerate() {
            dirichlet += 0.25 * cot * uv[i as usize].distance_squared(uv[j as usize]);
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            let (s, t) = (q[(k + 1) % 3] - q[k], q[(k + 2) % 3] - q[k]);
            let angle_3d = a.angle_between(b);
            let angle_uv = if s.length_squared() > 0.0 && t.length_squared() > 0.0 {
                s.angle_to(t).abs()
            } else {
                0.0
            };
            angle_sum += (angle_uv - angle_3d).abs();
            corners += 1;
        }
        energy += dirichlet - auv;
    }
    if corners > 0 {
        d.angle_deg = angle_sum.to_degrees() / corners as f64;
    }
    if uv_area > 0.0 {
        d.conformal = (energy / uv_area).max(0.0);
        let mut weighted = 0.0;
        for &(a3, auv) in &areas {
            if a3 > 0.0 && auv > 0.0 {
                weighted += a3 * ((auv / uv_area) / (a3 / area_3d)).ln().abs();
            }
        }
        d.area = weighted / area_3d;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_similarity_has_no_distortion_and_a_mirror_flips() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(0.3, 0.8, 0.0)];
        let tri = [[0, 1, 2]];
        // Rotated by 0.5 rad, scaled by 2, moved.
        let r = DVec2::from_angle(0.5) * 2.0;
        let uv: Vec<DVec2> = p
            .iter()
            .map(|x| r.rotate(x.truncate()) + DVec2::new(3.0, -1.0))
            .collect();
        let d = measure(&p, &uv, &tri);
        assert_eq!(d.flipped, 0);
        assert!(
            d.angle_deg < 1e-9 && d.conformal < 1e-12 && d.area < 1e-12,
            "{d:?}"
        );
        let mirrored: Vec<DVec2> = p.iter().map(|x| DVec2::new(x.x, -x.y)).collect();
        let m = measure(&p, &mirrored, &tri);
        assert_eq!((m.flipped, m.degenerate), (1, 0));
        // Three corners on one line (up to rounding): degenerate, not turned over.
        let flat = [DVec2::ZERO, DVec2::new(0.5, 1e-17), DVec2::X];
        let f = measure(&p, &flat, &tri);
        assert_eq!((f.flipped, f.degenerate), (0, 1));
        // A mirror keeps the angles but its conformal energy is the whole Dirichlet energy.
        assert!(
            m.angle_deg < 1e-9 && (m.conformal - 2.0).abs() < 1e-9,
            "{m:?}"
        );
    }
}
