//! Discrete curvature after Meyer, Desbrun, Schröder & Barr, "Discrete Differential-Geometry
//! Operators for Triangulated 2-Manifolds" (2003).
//!
//! - **Mean curvature** from the cotangent Laplace–Beltrami operator over mixed Voronoi areas:
//!   `Δx_i = (1/A_i) Σ_j ½(cot α_ij + cot β_ij)(x_j − x_i) = −2 H_i n_i`, so
//!   `H_i = −½ Δx_i · n_i` with `n_i` the angle-weighted vertex normal (Thürmer & Wüthrich
//!   1998): positive where the surface bends away from its normal (a sphere with outward normals
//!   has `H = 1/r`).
//! - **Mixed areas** `A_i` (Meyer et al., fig. 4): each triangle gives its Voronoi region to a
//!   corner when it has no obtuse angle, else half its area to the obtuse corner and a quarter
//!   to each other one. They sum to the mesh's area.
//! - **Gaussian curvature** from the angle defect: `K_i = (2π − Σ θ_j) / A_i` inside; on the
//!   boundary the defect is taken from a straight boundary, `π − Σ θ_j` (so a flat disc has
//!   none), which is the turning of the boundary curve, not surface curvature.
//! - **Principal curvatures** `κ₁,₂ = H ± √max(H² − K, 0)`, and **principal directions** from a
//!   least-squares fit of the curvature tensor in the tangent plane to the normal curvatures
//!   along the edges, `κ_ij = −2 (x_j − x_i)·n_i / |x_j − x_i|²` (Meyer et al. §5; the sign
//!   makes a sphere's positive, as `H` is), weighted by
//!   the cotangent weights: the tensor's eigenvectors.
//!
//! Boundary vertices: the Laplacian sums their open fan, so `H` there measures the fan rather
//! than a surface around the vertex; it is reported, and flagged by [`Surface::boundary`].
//! Polygons are fanned into triangles first ([`Surface`]), so their curvature is that of the
//! fan. Degenerate triangles (zero area) contribute nothing.

use bevy::math::DVec3;
use std::f64::consts::PI;

use super::surface::Surface;

/// Per-vertex curvature, by table row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Curvature {
    /// Mixed Voronoi area of each vertex.
    pub area: Vec<f64>,
    /// Mean curvature `H`.
    pub mean: Vec<f64>,
    /// The angle defect `2π − Σθ` (`π − Σθ` on the boundary): Gaussian curvature integrated
    /// over the vertex's area. Its sum is `2πχ` on a closed mesh (Gauss–Bonnet), exactly.
    pub angle_defect: Vec<f64>,
    /// Gaussian curvature `K`: the angle defect over the mixed area.
    pub gaussian: Vec<f64>,
    /// The larger principal curvature `κ₁ = H + √max(H² − K, 0)`.
    pub max: Vec<f64>,
    /// The smaller principal curvature `κ₂ = H − √max(H² − K, 0)`.
    pub min: Vec<f64>,
    /// The direction of `κ₁` (unit, tangent); zero where the fit has no direction (an umbilic
    /// or a vertex with fewer than three neighbours).
    pub max_direction: Vec<DVec3>,
    /// The direction of `κ₂` (unit, tangent, normal × `max_direction`).
    pub min_direction: Vec<DVec3>,
    /// The angle-weighted vertex normals the signs and tangent planes come from.
    pub normal: Vec<DVec3>,
}

/// The cotangent weights `½ cot θ` of a triangle's sides, opposite corners 0, 1, 2 (the side
/// opposite corner 0 joins corners 1 and 2), its three angles, and twice its area. One cross
/// product serves all three corners (`|u × v|` is twice the area whichever corner it is taken
/// at); a flat triangle has zero weights, and angles 0 or π.
#[inline]
fn triangle_weights(p: [DVec3; 3]) -> ([f64; 3], [f64; 3], f64) {
    let mut twice_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    if !twice_area.is_finite() {
        twice_area = 0.0;
    }
    let mut weights = [0.0; 3];
    let mut angles = [0.0; 3];
    for k in 0..3 {
        let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        let dot = (b - a).dot(c - a);
        if twice_area > 0.0 {
            weights[k] = 0.5 * dot / twice_area;
        }
        // A flat triangle still has angles (0, 0 and π where its corners are in a row), which
        // the angle defects must count for Gauss–Bonnet to hold.
        angles[k] = twice_area.atan2(dot);
    }
    (weights, angles, twice_area)
}

/// The mixed Voronoi area a triangle gives corner `k` (Meyer et al., fig. 4).
#[inline]
fn mixed_share(p: [DVec3; 3], k: usize, w: [f64; 3], angles: [f64; 3], twice_area: f64) -> f64 {
    let whole = 0.5 * twice_area;
    match angles.iter().position(|&a| a > PI / 2.0) {
        Some(o) if o == k => whole / 2.0,
        Some(_) => whole / 4.0,
        // Voronoi: ¼ Σ over the two sides at k of |side|² · ½ cot(opposite angle).
        None => {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            0.25 * (w[(k + 2) % 3] * (b - a).length_squared()
                + w[(k + 1) % 3] * (c - a).length_squared())
        }
    }
}

/// The mixed Voronoi areas of Meyer et al. (fig. 4), by vertex. They sum to the mesh's area.
pub fn mixed_areas(s: &Surface) -> Vec<f64> {
    let mut area = vec![0.0; s.vertex_count()];
    for (t, tri) in s.triangles.iter().enumerate() {
        let p = s.corners(t);
        let (w, angles, twice_area) = triangle_weights(p);
        for k in 0..3 {
            area[tri[k] as usize] += mixed_share(p, k, w, angles, twice_area);
        }
    }
    area
}

/// What one pass over the triangles gives: mixed areas, the cotangent Laplacian of the
/// positions `Σ_j w_ij (x_j − x_i)` (not yet over the area), angle sums, and angle-weighted
/// normals (Thürmer & Wüthrich, each face's normal times its angle at the vertex).
struct Accumulated {
    area: Vec<f64>,
    laplacian: Vec<DVec3>,
    angle_sum: Vec<f64>,
    normal: Vec<DVec3>,
}

fn accumulate(s: &Surface) -> Accumulated {
    let n = s.vertex_count();
    let faces = s.triangle_face.iter().max().map_or(0, |&f| f as usize + 1);
    let mut face_area = vec![DVec3::ZERO; faces];
    let mut corner_angles = Vec::with_capacity(s.triangles.len());
    let mut acc = Accumulated {
        area: vec![0.0; n],
        laplacian: vec![DVec3::ZERO; n],
        angle_sum: vec![0.0; n],
        normal: vec![DVec3::ZERO; n],
    };
    for (t, (tri, &f)) in s.triangles.iter().zip(&s.triangle_face).enumerate() {
        let p = s.corners(t);
        face_area[f as usize] += (p[1] - p[0]).cross(p[2] - p[0]);
        let (w, angles, twice_area) = triangle_weights(p);
        for k in 0..3 {
            let (i, j) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let d = w[k] * (s.positions[j] - s.positions[i]);
            acc.laplacian[i] += d;
            acc.laplacian[j] -= d;
            acc.angle_sum[tri[k] as usize] += angles[k];
            acc.area[tri[k] as usize] += mixed_share(p, k, w, angles, twice_area);
        }
        corner_angles.push(angles);
    }
    let face_normal: Vec<DVec3> = face_area
        .into_iter()
        .map(DVec3::normalize_or_zero)
        .collect();
    for ((tri, &f), angles) in s.triangles.iter().zip(&s.triangle_face).zip(&corner_angles) {
        for k in 0..3 {
            acc.normal[tri[k] as usize] += angles[k] * face_normal[f as usize];
        }
    }
    for n in &mut acc.normal {
        *n = n.normalize_or_zero();
    }
    acc
}

/// Mean, Gaussian and principal curvature values (no directions: those are
/// [`curvature`]'s), by vertex: one pass over the triangles, one over the vertices.
pub fn scalar_curvature(s: &Surface) -> Curvature {
    let n = s.vertex_count();
    let Accumulated {
        area,
        laplacian,
        angle_sum,
        normal,
    } = accumulate(s);
    let mut c = Curvature {
        mean: vec![0.0; n],
        angle_defect: vec![0.0; n],
        gaussian: vec![0.0; n],
        max: vec![0.0; n],
        min: vec![0.0; n],
        max_direction: vec![DVec3::ZERO; n],
        min_direction: vec![DVec3::ZERO; n],
        ..Default::default()
    };
    for i in 0..n {
        let full = if s.boundary[i] { PI } else { 2.0 * PI };
        c.angle_defect[i] = full - angle_sum[i];
        if area[i] > 0.0 {
            c.mean[i] = -0.5 * laplacian[i].dot(normal[i]) / area[i];
            c.gaussian[i] = c.angle_defect[i] / area[i];
        }
        let root = (c.mean[i] * c.mean[i] - c.gaussian[i]).max(0.0).sqrt();
        c.max[i] = c.mean[i] + root;
        c.min[i] = c.mean[i] - root;
    }
    c.area = area;
    c.normal = normal;
    c
}

/// Every curvature of the module doc, principal directions included, by vertex.
pub fn curvature(s: &Surface) -> Curvature {
    let mut c = scalar_curvature(s);
    let normal = std::mem::take(&mut c.normal);
    principal_directions(s, &normal, &mut c);
    c.normal = normal;
    c
}

/// Fits the curvature tensor at each vertex to the normal curvatures along its edges (weighted
/// by `|cot weight|`, at least a small floor so a right-angled fan still counts), and stores its
/// eigenvectors.
fn principal_directions(s: &Surface, normal: &[DVec3], c: &mut Curvature) {
    let n = s.vertex_count();
    // Normal equations of the fit of (a, b, d) in κ(u) = a u₁² + 2b u₁u₂ + d u₂², accumulated
    // per vertex: Σ w φ φᵀ and Σ w κ φ with φ = (u₁², 2u₁u₂, u₂²).
    let mut ata = vec![[0.0f64; 6]; n];
    let mut atb = vec![[0.0f64; 3]; n];
    let mut frames = Vec::with_capacity(n);
    for &nrm in normal {
        let (e1, e2) = if nrm == DVec3::ZERO {
            (DVec3::ZERO, DVec3::ZERO)
        } else {
            nrm.any_orthonormal_pair()
        };
        frames.push((e1, e2));
    }
    let mut add = |i: usize, j: usize, w: f64| {
        let d = s.positions[j] - s.positions[i];
        let len2 = d.length_squared();
        let (e1, e2) = frames[i];
        let (u1, u2) = (d.dot(e1), d.dot(e2));
        let t2 = u1 * u1 + u2 * u2;
        if len2 <= 0.0 || t2 <= 0.0 {
            return;
        }
        let kappa = -2.0 * d.dot(normal[i]) / len2;
        let (u1, u2) = (u1 / t2.sqrt(), u2 / t2.sqrt());
        let phi = [u1 * u1, 2.0 * u1 * u2, u2 * u2];
        let m = &mut ata[i];
        m[0] += w * phi[0] * phi[0];
        m[1] += w * phi[0] * phi[1];
        m[2] += w * phi[0] * phi[2];
        m[3] += w * phi[1] * phi[1];
        m[4] += w * phi[1] * phi[2];
        m[5] += w * phi[2] * phi[2];
        for (k, value) in phi.iter().enumerate() {
            atb[i][k] += w * kappa * value;
        }
    };
    for (t, tri) in s.triangles.iter().enumerate() {
        let (w, _, _) = triangle_weights(s.corners(t));
        for k in 0..3 {
            let (i, j) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let weight = w[k].abs().max(1e-3);
            add(i, j, weight);
            add(j, i, weight);
        }
    }
    for i in 0..n {
        let m = ata[i];
        let sym = bevy::math::DMat3::from_cols(
            DVec3::new(m[0], m[1], m[2]),
            DVec3::new(m[1], m[3], m[4]),
            DVec3::new(m[2], m[4], m[5]),
        );
        if sym.determinant().abs() < 1e-12 {
            continue;
        }
        let x = sym.inverse() * DVec3::from(atb[i]);
        let (a, b, d) = (x.x, x.y, x.z);
        // The eigenvector of [[a, b], [b, d]] with the larger eigenvalue.
        let angle = 0.5 * (2.0 * b).atan2(a - d);
        let (e1, e2) = frames[i];
        let dir = (angle.cos() * e1 + angle.sin() * e2).normalize_or_zero();
        c.max_direction[i] = dir;
        c.min_direction[i] = normal[i].cross(dir).normalize_or_zero();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::ops::geometry::surface::of_soup as surface;

    #[test]
    fn the_unit_icosphere_has_mean_curvature_one_and_total_gaussian_four_pi() {
        let s = surface(&shapes::icosphere(3));
        let c = curvature(&s);
        for (i, h) in c.mean.iter().enumerate() {
            assert!((h - 1.0).abs() < 0.01, "H = {h} at {i}");
        }
        let total: f64 = c.angle_defect.iter().sum();
        assert!((total - 4.0 * PI).abs() < 1e-9, "{total}");
        // The mixed areas tile the surface.
        let area: f64 = c.area.iter().sum();
        let direct: f64 = (0..s.triangles.len())
            .map(|t| {
                let p = s.corners(t);
                0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
            })
            .sum();
        assert!((area - direct).abs() < 1e-9 * direct, "{area} vs {direct}");
    }

    #[test]
    fn a_planar_grid_has_no_curvature_inside() {
        let s = surface(&shapes::grid(6, 5));
        let c = curvature(&s);
        for i in (0..s.vertex_count()).filter(|&i| !s.boundary[i]) {
            assert!(c.mean[i].abs() < 1e-9, "{}", c.mean[i]);
            assert!(c.gaussian[i].abs() < 1e-9, "{}", c.gaussian[i]);
        }
        // A straight stretch of boundary has no defect either (the grid's corners turn by π/2).
        let corners = c
            .angle_defect
            .iter()
            .filter(|d| (*d - PI / 2.0).abs() < 1e-9)
            .count();
        assert_eq!(corners, 4);
    }

    #[test]
    fn a_cylinder_bends_one_way_along_its_circles() {
        // A cylinder of radius 2 (open): κ₁ = 1/2 around, κ₂ = 0 along the axis, H = 1/4.
        let (around, along) = (48u32, 6u32);
        let mut positions = Vec::new();
        for j in 0..=along {
            for i in 0..around {
                let a = 2.0 * std::f32::consts::PI * i as f32 / around as f32;
                positions.push(bevy::math::Vec3::new(
                    2.0 * a.cos(),
                    2.0 * a.sin(),
                    j as f32,
                ));
            }
        }
        let mut faces = Vec::new();
        for j in 0..along {
            for i in 0..around {
                let (a, b) = (j * around + i, j * around + (i + 1) % around);
                faces.push([a, b, b + around, a + around]);
            }
        }
        let soup = crate::mesh::PolygonSoup::from_faces(positions, &faces);
        let s = surface(&soup);
        let c = curvature(&s);
        for i in (0..s.vertex_count()).filter(|&i| !s.boundary[i]) {
            assert!((c.max[i] - 0.5).abs() < 0.02, "κ₁ = {}", c.max[i]);
            assert!(c.min[i].abs() < 0.02, "κ₂ = {}", c.min[i]);
            // The direction of κ₁ goes round the axis (no z), κ₂'s along it.
            assert!(c.max_direction[i].z.abs() < 0.05, "{}", c.max_direction[i]);
            assert!(c.min_direction[i].z.abs() > 0.95, "{}", c.min_direction[i]);
        }
    }
}
