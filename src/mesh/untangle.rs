//! A polygon that visits a vertex more than once, cut into triangles that a halfedge mesh can
//! hold.
//!
//! Such a polygon is usually a *keyhole*: a polygon with a hole, the hole joined to the outline
//! by a bridge walked once each way (`0 1 2 3 0 4 7 6 5 4`: the outline, the bridge to the hole,
//! the hole backwards, the bridge back), as concave-polygon test files and CAD exporters write
//! it. No cut at the repeated corners alone gives simple polygons (the hole would become a face
//! over itself), so the polygon is triangulated by ear clipping in its own plane: the plane of
//! its Newell normal, which fixes its winding, and in that plane an ear is a convex corner whose
//! triangle holds no reflex corner of the polygon but those standing at its own three vertices
//! (the bridge's ends stand twice). A weakly simple polygon of `n` corners always has an ear
//! (Meisters' two-ears theorem extends to it), so a keyhole gives `n − 2` triangles, the bridge
//! becoming an inner edge. The same cut mends a corner written twice in a row (`0 1 1 2`), and a
//! polygon whose two loops touch at one vertex (a bow tie), whose vertex the repair then splits
//! as any non-manifold one.
//!
//! What cannot be cut — a polygon with no area in any plane, or one that crosses itself so that
//! clipping finds no ear — is left to the caller to drop. So is one whose clipping would take more
//! than [`WORK`] corner tests (ear clipping is quadratic in the corners, cubic at worst; a keyhole
//! of 8 194 corners is cut in 0.25 s at the test profile's `opt-level = 1`, one of 65 538 is past
//! the budget), so that no file's polygon can hold a load up for minutes.

use bevy::math::{DVec2, DVec3, Vec3};

/// The corner tests one polygon's clipping may take before it gives up.
pub const WORK: usize = 1 << 28;

/// The triangles of `face` (corner offsets into it, in its winding), when it can be cut;
/// empty when it cannot (see the module doc). Every triangle names three distinct vertices.
pub fn untangle(face: &[u32], positions: &[Vec3]) -> Vec<[usize; 3]> {
    // A corner that repeats the one before it is an edge of no length: left out.
    let mut corners: Vec<usize> = Vec::with_capacity(face.len());
    for (k, &v) in face.iter().enumerate() {
        if corners.last().is_none_or(|&last| face[last] != v) {
            corners.push(k);
        }
    }
    while corners.len() > 1 && face[corners[0]] == face[corners[corners.len() - 1]] {
        corners.pop();
    }
    if corners.len() < 3 {
        return Vec::new();
    }
    let points: Vec<DVec3> = corners
        .iter()
        .map(|&k| positions[face[k] as usize].as_dvec3())
        .collect();
    let Some(plane) = Plane::of(&points) else {
        return Vec::new();
    };
    let flat: Vec<DVec2> = points.iter().map(|&p| plane.project(p)).collect();
    let ids: Vec<u32> = corners.iter().map(|&k| face[k]).collect();
    Clipper::new(flat, ids, plane.tolerance)
        .triangles()
        .into_iter()
        .map(|t| t.map(|i| corners[i]))
        .collect()
}

/// The plane a polygon is cut in: two axes whose cross product is its Newell normal, so that
/// its winding is counter-clockwise there.
struct Plane {
    u: DVec3,
    v: DVec3,
    /// Twice a triangle's area below which it counts as flat: relative to the polygon's size.
    tolerance: f64,
}

impl Plane {
    fn of(points: &[DVec3]) -> Option<Plane> {
        let mut normal = DVec3::ZERO;
        let (mut low, mut high) = (points[0], points[0]);
        for (i, &p) in points.iter().enumerate() {
            let q = points[(i + 1) % points.len()];
            normal += p.cross(q);
            low = low.min(p);
            high = high.max(p);
        }
        let size = (high - low).length_squared();
        let normal = normal.try_normalize().filter(|_| size > 0.0)?;
        let u = normal.any_orthonormal_vector();
        Some(Plane {
            u,
            v: normal.cross(u),
            tolerance: size * 1e-12,
        })
    }

    fn project(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.dot(self.u), p.dot(self.v))
    }
}

/// Ear clipping over a ring of corners.
struct Clipper {
    points: Vec<DVec2>,
    ids: Vec<u32>,
    prev: Vec<usize>,
    next: Vec<usize>,
    tolerance: f64,
    /// Corner tests left before the clipping gives up ([`WORK`] to start with).
    work_left: usize,
}

impl Clipper {
    fn new(points: Vec<DVec2>, ids: Vec<u32>, tolerance: f64) -> Clipper {
        let n = points.len();
        Clipper {
            prev: (0..n).map(|i| (i + n - 1) % n).collect(),
            next: (0..n).map(|i| (i + 1) % n).collect(),
            points,
            ids,
            tolerance,
            work_left: WORK,
        }
    }

    /// Twice the signed area of the triangle of corners `a b c`.
    fn area(&self, a: usize, b: usize, c: usize) -> f64 {
        let (a, b, c) = (self.points[a], self.points[b], self.points[c]);
        (b - a).perp_dot(c - a)
    }

    fn convex(&self, b: usize) -> bool {
        self.area(self.prev[b], b, self.next[b]) > self.tolerance
    }

    /// Whether corner `b` with its neighbours is a triangle to cut off.
    fn is_ear(&mut self, b: usize) -> bool {
        let (a, c) = (self.prev[b], self.next[b]);
        let own = [self.ids[a], self.ids[b], self.ids[c]];
        if own[0] == own[1] || own[1] == own[2] || own[0] == own[2] || !self.convex(b) {
            return false;
        }
        let mut p = self.next[c];
        while p != a {
            self.work_left = self.work_left.saturating_sub(1);
            let inside = !own.contains(&self.ids[p])
                && !self.convex(p)
                && self.area(a, b, p) >= -self.tolerance
                && self.area(b, c, p) >= -self.tolerance
                && self.area(c, a, p) >= -self.tolerance;
            if inside {
                return false;
            }
            p = self.next[p];
        }
        true
    }

    /// The triangles, as positions in the ring; empty when some ring is left that has no ear,
    /// or when finding the ears took more than [`WORK`] corner tests.
    ///
    /// The area still to cover is followed: once it is none, what is left of the ring is the
    /// spikes where two lobes touched (a bow tie's pinch), and is not cut; an ear larger than
    /// it would reach across such a pinch, outside the polygon, and is not taken.
    fn triangles(mut self) -> Vec<[usize; 3]> {
        let mut left = self.points.len();
        let mut out = Vec::with_capacity(left - 2);
        let mut uncovered: f64 = (1..left - 1).map(|i| self.area(0, i, i + 1)).sum();
        let mut at = 0;
        let mut tried = 0;
        while left > 3 {
            if uncovered <= self.tolerance {
                return out;
            }
            let ear = self.area(self.prev[at], at, self.next[at]);
            if ear <= uncovered + self.tolerance && self.is_ear(at) {
                let (a, c) = (self.prev[at], self.next[at]);
                out.push([a, at, c]);
                uncovered -= ear;
                self.next[a] = c;
                self.prev[c] = a;
                left -= 1;
                at = c;
                tried = 0;
            } else {
                tried += 1;
                if tried > left || self.work_left == 0 {
                    return Vec::new();
                }
                at = self.next[at];
            }
        }
        let (a, c) = (self.prev[at], self.next[at]);
        let last = [self.ids[a], self.ids[at], self.ids[c]];
        let distinct = last[0] != last[1] && last[1] != last[2] && last[0] != last[2];
        if distinct && self.area(a, at, c) > self.tolerance {
            out.push([a, at, c]);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corners' vertices of each triangle.
    fn vertices(face: &[u32], triangles: &[[usize; 3]]) -> Vec<[u32; 3]> {
        triangles.iter().map(|t| t.map(|k| face[k])).collect()
    }

    /// Twice the signed area of a triangle of points in the z = 0 plane.
    fn area(p: &[Vec3], t: [u32; 3]) -> f32 {
        let [a, b, c] = t.map(|i| p[i as usize]);
        (b - a).cross(c - a).z
    }

    /// A 4 × 4 square with a 2 × 2 hole, as a keyhole polygon.
    fn keyhole() -> (Vec<Vec3>, Vec<u32>) {
        let p = [
            (0., 0.),
            (4., 0.),
            (4., 4.),
            (0., 4.),
            (1., 1.),
            (3., 1.),
            (3., 3.),
            (1., 3.),
        ]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
        (p.to_vec(), vec![0, 1, 2, 3, 0, 4, 7, 6, 5, 4])
    }

    #[test]
    fn a_keyhole_becomes_the_ring_around_its_hole() {
        let (p, face) = keyhole();
        let t = vertices(&face, &untangle(&face, &p));
        // n − 2 triangles, each facing the polygon's way, covering the square less the hole.
        assert_eq!(t.len(), 8, "{t:?}");
        assert!(t.iter().all(|&t| area(&p, t) > 0.0), "{t:?}");
        let covered: f32 = t.iter().map(|&t| area(&p, t) / 2.0).sum();
        assert_eq!(covered, 16.0 - 4.0);
        // The bridge is an inner edge: its two directed halves are both used, once each.
        let directed = |a: u32, b: u32| {
            t.iter()
                .filter(|t| (0..3).any(|i| t[i] == a && t[(i + 1) % 3] == b))
                .count()
        };
        assert_eq!((directed(0, 4), directed(4, 0)), (1, 1));
        // Every outline and hole edge once, in the polygon's direction.
        for (a, b) in [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 7),
            (7, 6),
            (6, 5),
            (5, 4),
        ] {
            assert_eq!((directed(a, b), directed(b, a)), (1, 0), "{a}->{b}");
        }
    }

    #[test]
    fn a_keyhole_cuts_in_its_own_plane_whatever_it_faces() {
        let (p, face) = keyhole();
        // Tilted out of z = 0 and written backwards: the same cut, reversed.
        let turn = bevy::math::Quat::from_euler(bevy::math::EulerRot::XYZ, 0.7, -1.1, 0.3);
        let tilted: Vec<Vec3> = p.iter().map(|&q| turn * q + Vec3::ONE).collect();
        let back: Vec<u32> = face.iter().rev().copied().collect();
        let t = vertices(&back, &untangle(&back, &tilted));
        assert_eq!(t.len(), 8);
        let normal = |t: [u32; 3]| {
            let [a, b, c] = t.map(|i| tilted[i as usize]);
            (b - a).cross(c - a)
        };
        let facing = turn * Vec3::NEG_Z;
        assert!(t.iter().all(|&t| normal(t).dot(facing) > 0.0), "{t:?}");
    }

    #[test]
    fn a_corner_written_twice_and_a_bow_tie_are_cut_and_a_flat_polygon_is_not() {
        let p: Vec<Vec3> = [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (2., 1.), (2., 2.)]
            .map(|(x, y)| Vec3::new(x, y, 0.0))
            .to_vec();
        // `0 1 1 2 3 0`: a square with a repeated corner and its first written again last.
        let face = [0, 1, 1, 2, 3, 0];
        let t = vertices(&face, &untangle(&face, &p));
        assert_eq!(t.len(), 2);
        assert_eq!(t.iter().map(|&t| area(&p, t)).sum::<f32>(), 2.0);
        // A bow tie: two triangles touching at vertex 2.
        let bow = [0, 1, 2, 4, 5, 2];
        let t = vertices(&bow, &untangle(&bow, &p));
        assert_eq!(t.len(), 2, "{t:?}");
        assert!(t.iter().all(|&t| area(&p, t) > 0.0));
        // Two corners, and a polygon on a line, cannot be cut.
        assert!(untangle(&[0, 1, 1, 0], &p).is_empty());
        let line = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert!(untangle(&[0, 1, 2, 1], &line).is_empty());
    }

    #[test]
    fn a_polygon_whose_clipping_would_take_too_long_is_left_to_drop() {
        // A ring of n outline and n hole corners needs about n² corner tests: past the budget
        // for n = 32 768 (the test stops at the budget, in about a second).
        let n = 1 << 15;
        let circle = |r: f32| {
            (0..n).map(move |i| {
                let a = i as f32 / n as f32 * std::f32::consts::TAU;
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
        };
        let p: Vec<Vec3> = circle(2.0).chain(circle(1.0)).collect();
        let n = n as u32;
        let mut face: Vec<u32> = (0..n).collect();
        face.push(0);
        face.extend((n..2 * n).rev());
        face.push(2 * n - 1);
        assert!(untangle(&face, &p).is_empty());
        // The same shape at a sixteenth of the corners is cut whole.
        let m = n / 16;
        let p: Vec<Vec3> = p.iter().step_by(16).copied().collect();
        let mut face: Vec<u32> = (0..m).collect();
        face.push(0);
        face.extend((m..2 * m).rev());
        face.push(2 * m - 1);
        assert_eq!(untangle(&face, &p).len(), face.len() - 2);
    }
}
