//! The cotangent weights of a triangle mesh's edges: the stiffness of linear finite elements
//! (Pinkall & Polthier 1993; Botsch et al., *Polygon Mesh Processing*, §3.3), shared by the
//! smoothing, the deformations and the fairing.

use super::Surface;

/// The cotangent weights `½(cot α + cot β)` of every edge of the fanned triangles, as
/// (i, j, w) with i < j, merged.
pub fn cotan_edges(s: &Surface) -> Vec<(u32, u32, f64)> {
    let mut edges: Vec<(u32, u32, f64)> = Vec::with_capacity(3 * s.triangles.len());
    for (t, tri) in s.triangles.iter().enumerate() {
        let p = s.corners(t);
        for k in 0..3 {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (u, v) = (b - a, c - a);
            let sin = u.cross(v).length();
            let w = if sin > 0.0 { 0.5 * u.dot(v) / sin } else { 0.0 };
            let (i, j) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            edges.push((i.min(j), i.max(j), w));
        }
    }
    merged(edges)
}

/// Weights `(i, j, w)` with `i < j`, sorted and those of one pair of vertices added up.
pub fn merged(mut edges: Vec<(u32, u32, f64)>) -> Vec<(u32, u32, f64)> {
    edges.sort_unstable_by_key(|&(i, j, _)| (i, j));
    let mut merged: Vec<(u32, u32, f64)> = Vec::with_capacity(edges.len() / 2 + 1);
    for (i, j, w) in edges {
        match merged.last_mut() {
            Some(last) if (last.0, last.1) == (i, j) => last.2 += w,
            _ => merged.push((i, j, w)),
        }
    }
    merged
}
