//! The squared distances from one point to [`LANES`] triangles at once, each coordinate of the
//! four triangles in one of glam's `Vec4`s (a vector register), without a branch: what lets
//! the grid's search ([`super::Reference::closest_on`]) pass over the triangles of a cell that
//! cannot be nearer than the nearest found before the exact test (Ericson's, whose branches on
//! the point's region of the triangle, mispredicted from one triangle to the next, were what
//! the search spent its time on).
//!
//! A lane's distance is the least of the point's distances to the triangle's three sides and,
//! where its projection falls inside the triangle, to its plane. It never exceeds the exact
//! test's by more than rounding, a few units in the last place of the point's and the corners'
//! coordinates, so that a triangle it puts farther than the nearest found by more than that
//! cannot be nearer: the inside test takes in a rim round the triangle wider than its own
//! rounding (a point just outside taken as inside measures to the plane, nearer than to the
//! side: only an exact test more), and a triangle whose plane cannot be trusted, its angle at
//! the first corner under about 2° (the sine's square under [`THIN_SINE`]), measures 0,
//! leaving it to the exact test.

use bevy::math::{BVec4A, Vec3, Vec4};

/// How many triangles a call measures.
pub(super) const LANES: usize = 4;

/// Below this squared sine of a triangle's angle at its first corner, its normal (the cross
/// product of the sides from there) is too short for the distance to its plane to be within
/// rounding of the exact one: such a triangle's lane is 0.
const THIN_SINE: f32 = 1e-3;

/// How wide a rim round the triangle the inside test takes in, in units of the rounding of its
/// terms.
const INSIDE_SLACK: f32 = 16.0 * f32::EPSILON;

/// A point or a vector in each of the four lanes.
#[derive(Clone, Copy)]
struct Lanes3 {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl Lanes3 {
    /// `p` in every lane.
    fn splat(p: Vec3) -> Self {
        Self {
            x: Vec4::splat(p.x),
            y: Vec4::splat(p.y),
            z: Vec4::splat(p.z),
        }
    }

    /// Lane by lane, `self - o`.
    fn minus(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    /// Lane by lane, `self - o * t`.
    fn minus_scaled(self, o: Self, t: Vec4) -> Self {
        Self {
            x: self.x - o.x * t,
            y: self.y - o.y * t,
            z: self.z - o.z * t,
        }
    }

    /// Lane by lane, the dot product.
    fn dot(self, o: Self) -> Vec4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Lane by lane, the cross product.
    fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }
}

/// [`LANES`] triangles' corners, lane by lane.
#[derive(Clone, Copy)]
pub(super) struct TriangleLanes {
    corners: [Lanes3; 3],
}

impl TriangleLanes {
    /// Lanes of the triangles `rows` of `triangles` (one to [`LANES`] of them); the lanes past
    /// them repeat the last.
    pub fn gather(triangles: &[[Vec3; 3]], rows: &[u32]) -> Self {
        let last = rows.len() - 1;
        let t = [0, 1, 2, 3].map(|lane| &triangles[rows[lane.min(last)] as usize]);
        let corner = |k: usize| Lanes3 {
            x: Vec4::new(t[0][k].x, t[1][k].x, t[2][k].x, t[3][k].x),
            y: Vec4::new(t[0][k].y, t[1][k].y, t[2][k].y, t[3][k].y),
            z: Vec4::new(t[0][k].z, t[1][k].z, t[2][k].z, t[3][k].z),
        };
        Self {
            corners: [corner(0), corner(1), corner(2)],
        }
    }

    /// The squared distance from `p` to each lane's triangle (see the module doc).
    pub fn squared_distances(&self, p: Vec3) -> [f32; LANES] {
        let [a, b, c] = self.corners;
        let p = Lanes3::splat(p);
        let (ab, ac, bc) = (b.minus(a), c.minus(a), c.minus(b));
        let (ap, bp) = (p.minus(a), p.minus(b));
        let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
        let (d20, d21) = (ab.dot(ap), ac.dot(ap));
        let sides = side_distance(ap, ab, d20, d00)
            .min(side_distance(ap, ac, d21, d11))
            .min(side_distance(bp, bc, bc.dot(bp), bc.dot(bc)));
        // Barycentric weights times the Gram determinant: inside where all are positive, up
        // to the rounding of terms no larger than s³ |ap| and s⁴ (s the longer side).
        let det = d00 * d11 - d01 * d01;
        let (v, w) = (d11 * d20 - d01 * d21, d00 * d21 - d01 * d20);
        let s2 = d00.max(d11);
        let lean = INSIDE_SLACK * s2 * (s2 + (s2 * ap.dot(ap)).sqrt());
        let inside = v.cmpge(-lean) & w.cmpge(-lean) & (v + w).cmple(det + lean);
        let n = ab.cross(ac);
        let height = n.dot(ap);
        let plane = height * height / n.dot(n).max(Vec4::splat(f32::MIN_POSITIVE));
        let thin: BVec4A = det.cmplt(THIN_SINE * d00 * d11);
        let measured = Vec4::select(inside, plane, sides);
        Vec4::select(thin, Vec4::ZERO, measured).to_array()
    }
}

/// Lane by lane, the squared distance from a point to the segment from `s` to `s + d`, given
/// the point's offset `sp` from `s`, `sp · d` and `d · d` (a segment of no length: its end).
fn side_distance(sp: Lanes3, d: Lanes3, dot: Vec4, length_squared: Vec4) -> Vec4 {
    let t = (dot / length_squared.max(Vec4::splat(f32::MIN_POSITIVE))).clamp(Vec4::ZERO, Vec4::ONE);
    let off = sp.minus_scaled(d, t);
    off.dot(off)
}

#[cfg(test)]
mod tests {
    use super::super::closest_on_triangle;
    use super::super::tests::coordinates;
    use super::*;

    #[test]
    fn each_lane_is_the_exact_distance_to_within_rounding() {
        // Triangles of all shapes, the thin included, and points all round them (a fixed
        // pseudo-random sequence).
        let mut coordinate = coordinates(11, 1.0);
        let mut triangles: Vec<[Vec3; 3]> = (0..64)
            .map(|_| [(); 3].map(|_| Vec3::new(coordinate(), coordinate(), coordinate())))
            .collect();
        // A sliver, a triangle with two corners the same and one with all three.
        triangles.push([Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1e-4, 0.0)]);
        triangles.push([Vec3::ZERO, Vec3::ZERO, Vec3::Y]);
        triangles.push([Vec3::ONE; 3]);
        let rows: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut thin_lanes = 0;
        for _ in 0..200 {
            let p = Vec3::new(coordinate(), coordinate(), coordinate()) * 1.5;
            for chunk in rows.chunks(LANES) {
                let lanes = TriangleLanes::gather(&triangles, chunk);
                let got = lanes.squared_distances(p);
                for (lane, &row) in chunk.iter().enumerate() {
                    let t = &triangles[row as usize];
                    let exact = closest_on_triangle(p, t).distance_squared(p);
                    // Ericson's test divides by a side of no length: NaN, which no search
                    // takes as nearer, whatever the lane says.
                    if exact.is_nan() {
                        assert_eq!(t[0], t[1], "{p} to {t:?}");
                        continue;
                    }
                    // Never farther; as near, but for the thin ones' 0.
                    let (got, exact) = (got[lane].sqrt(), exact.sqrt());
                    assert!(got <= exact + 1e-6, "{p} to {t:?}: {got} against {exact}");
                    if got == 0.0 && exact > 0.0 {
                        thin_lanes += 1;
                    } else {
                        assert!(exact - got < 1e-6, "{p} to {t:?}: {got} against {exact}");
                    }
                }
            }
        }
        // The sliver and the point at least, from every point.
        assert!(thin_lanes >= 400, "{thin_lanes}");
    }
}
