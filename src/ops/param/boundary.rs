//! Where the outer boundary goes for the barycentric mapping: a convex polygon, by arc length.
//!
//! The outer loop's vertices `c_0 … c_{m−1}` (counter-clockwise, the surface on the left) sit at
//! cumulative 3D arc lengths `s_0 = 0 < s_1 < … < L`:
//!
//! - **circle**: at angle `2π s_k / L` on the unit circle. Every vertex is a corner of the
//!   (strictly convex) polygon, so Tutte's theorem applies as it is.
//! - **square**: four loop vertices become the corners of the unit square, those nearest to the
//!   arc lengths `0, L/4, L/2, 3L/4` (kept distinct and in order); the vertices between two
//!   corners are spaced along that side by their arc length. Three boundary vertices on one side
//!   are collinear, so a triangle with all its corners on one side is flat (counted as degenerate):
//!   that is the square's price, and why the circle is the default.
//!
//! Also here: the two far-apart boundary vertices LSCM pins ([`far_pair`]).

use bevy::math::{DVec2, DVec3};

use super::params::{BoundaryShape, ParamError};

/// The positions of the loop `vertices` (cut-vertex indices into `positions`), in order, on
/// `shape` by arc length.
///
/// # Errors
/// [`ParamError::BoundaryTooShort`] when the loop has fewer than 3 vertices (4 for the square)
/// or no length.
pub fn map_loop(
    positions: &[DVec3],
    vertices: &[u32],
    shape: BoundaryShape,
) -> Result<Vec<DVec2>, ParamError> {
    let m = vertices.len();
    let needed = match shape {
        BoundaryShape::Circle => 3,
        BoundaryShape::Square => 4,
    };
    let mut s = Vec::with_capacity(m + 1);
    s.push(0.0);
    for k in 0..m {
        let (a, b) = (vertices[k], vertices[(k + 1) % m]);
        let step = positions[a as usize].distance(positions[b as usize]);
        s.push(s[k] + step);
    }
    let total = s[m];
    if m < needed || total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(ParamError::BoundaryTooShort {
            vertices: m,
            needed,
        });
    }
    Ok(match shape {
        BoundaryShape::Circle => s[..m]
            .iter()
            .map(|&sk| DVec2::from_angle(std::f64::consts::TAU * sk / total))
            .collect(),
        BoundaryShape::Square => square(&s, total),
    })
}

/// The square's corners at the vertices nearest to the quarter arc lengths, the rest spread by
/// arc length along the sides (see the module doc).
fn square(s: &[f64], total: f64) -> Vec<DVec2> {
    let m = s.len() - 1;
    const CORNERS: [DVec2; 5] = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(0.0, 0.0),
    ];
    // Corner q at the vertex nearest to q L / 4, each strictly after the previous one and
    // leaving room for the ones after it.
    let mut corner = [0usize, 0, 0, 0, m];
    for q in 1..4 {
        let target = q as f64 * total / 4.0;
        let nearest = (0..m)
            .min_by(|&a, &b| (s[a] - target).abs().total_cmp(&(s[b] - target).abs()))
            .unwrap_or(0);
        corner[q] = nearest.clamp(corner[q - 1] + 1, m - (4 - q));
    }
    let mut out = vec![DVec2::ZERO; m];
    for q in 0..4 {
        let (from, to) = (corner[q], corner[q + 1]);
        let (s0, s1) = (s[from], s[to]);
        for (k, slot) in out.iter_mut().enumerate().take(to).skip(from) {
            let t = if s1 > s0 {
                (s[k] - s0) / (s1 - s0)
            } else {
                0.0
            };
            *slot = CORNERS[q].lerp(CORNERS[q + 1], t);
        }
    }
    out
}

/// Two far-apart vertices of `vertices`: the one farthest (in 3D) from the first, and the one
/// farthest from that one (a double sweep: the exact farthest pair costs `O(m²)`, this `O(m)`
/// and is within a factor √3 of it, in practice nearly exact).
pub fn far_pair(positions: &[DVec3], vertices: &[u32]) -> (u32, u32) {
    let farthest_from = |from: u32| {
        let p = positions[from as usize];
        vertices
            .iter()
            .copied()
            .max_by(|&a, &b| {
                p.distance_squared(positions[a as usize])
                    .total_cmp(&p.distance_squared(positions[b as usize]))
            })
            .unwrap_or(from)
    };
    let a = farthest_from(vertices[0]);
    let b = farthest_from(a);
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_circle_and_the_square_follow_arc_length() {
        // An 8-vertex loop, unit sides around a 2 × 2 square, counter-clockwise.
        let p: Vec<DVec3> = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (2., 1.),
            (2., 2.),
            (1., 2.),
            (0., 2.),
            (0., 1.),
        ]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 0.0))
        .collect();
        let l: Vec<u32> = (0..8).collect();
        let circle = map_loop(&p, &l, BoundaryShape::Circle).unwrap();
        for (k, uv) in circle.iter().enumerate() {
            let expected = DVec2::from_angle(std::f64::consts::TAU * k as f64 / 8.0);
            assert!(uv.distance(expected) < 1e-12);
        }
        let square = map_loop(&p, &l, BoundaryShape::Square).unwrap();
        for (uv, q) in square.iter().zip(&p) {
            assert!(uv.distance(q.truncate() / 2.0) < 1e-12, "{uv} {q}");
        }
        assert_eq!(
            map_loop(&p, &l[..3], BoundaryShape::Square).unwrap_err(),
            ParamError::BoundaryTooShort {
                vertices: 3,
                needed: 4
            }
        );
        assert_eq!(far_pair(&p, &l), (4, 0));
    }
}
