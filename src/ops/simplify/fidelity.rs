//! How far a collapse takes the surface from the input: samples of the input kept in bins by
//! the simplified mesh's nearest face, measured against the faces a collapse reshapes.
//!
//! The quadric error sums squared distances to planes, weighted by area: a one-vertex bump or a
//! crease drawn with small triangles costs little to flatten, and the largest distance from the
//! input, the Hausdorff distance a user measures, ends up wherever those collapses went. After
//! Klein, Liebich & Straßer ("Mesh reduction with error control", 1996) and OpenMesh's
//! `ModHausdorffT`, each face of the simplified mesh keeps the input's points that lie nearest it
//! (at the start every face's centroid and every vertex, in the bin of a face that has it); a
//! collapse reshapes the faces around the two ends, so the points of those faces are measured
//! against the faces that will stand there afterwards, and move into the bin of the nearest.
//! Their farthest distance `d` makes the collapse cost at least `w · 2Ā · d²` (`2Ā` the mean of
//! the faces' doubled areas `|(b − a) × (c − a)|` at the start, `w`
//! [`super::SimplifyParams::distance_weight`]), a quantity of the same kind as the quadric's
//! area-weighted squares: the collapses that would take any of the input farthest away wait
//! until the others are done.
//!
//! Measuring every edge each time its neighbourhood changes would cost more than the
//! simplification; the check is lazy instead. An edge is queued at its quadric error, and
//! measured when it is popped: if its cost with the distance is above the key it was popped at,
//! it is queued again at that cost, remembered as measured, and collapses when it comes back
//! without its neighbourhood having changed in between (a collapse stamps the merged vertex and
//! its neighbours; an edge measured before either of its ends was stamped is measured again,
//! and collapses at once if it now costs no more than its key). A distance under a millionth of
//! the input's diagonal counts as none ([`NOISE_FRACTION`]).
//!
//! The samples are the input's vertices and face centroids: with the vertices alone the bunny's
//! distance at a quarter of the faces did not move (0.092 %), since the farthest points lie
//! inside the input's triangles; measured figures in `docs/performance.md`.
//!
//! Both runs ([`super::simplify`] on rows, [`super::QemRun`] on entities) name faces by their
//! row in the tables read at the start and list a collapse's faces alike, and every choice here
//! is independent of the order they are listed in (a point goes to the nearest face, the lowest
//! row among equals), so the two make the same collapses.

use bevy::math::Vec3;
use smallvec::SmallVec;

use crate::mesh::closure::bounding_box;
use crate::mesh::tables::{Connectivity, NONE};
use crate::ops::geometry::closest::closest_on_triangle;
use crate::ops::indexed_heap::slot_of;

/// A heap entry as the run keys its edges: the cost's bits above the edge's slot.
type Key = u64;

/// The distance, as a fraction of the input's bounding box diagonal, under which a point counts
/// as on the surface. Positions carry about seven digits, so below it a distance is the
/// rounding of the corners: on a flat region every collapse would measure such a distance above
/// its quadric's (nearly zero) and go back in the queue for it, a third of the check's time on
/// the fandisk, with no distance measured any different.
const NOISE_FRACTION: f32 = 1e-6;

/// A face of the simplified mesh as it will stand after a collapse, ready for many point
/// queries: its row, its corners, its plane and the planes through its sides perpendicular to
/// it. A point whose foot falls inside is measured by one dot product, and a triangle that
/// cannot be the nearest is passed over on a bound: the triangle lies in its plane and on the
/// inner side of each side's plane, so no point of it is nearer than `h² + e²` (`h` the
/// height over the plane, `e` the farthest a side's plane is crossed, the two at right angles).
#[derive(Clone, Copy, Debug)]
struct FanTriangle {
    face: u32,
    corners: [Vec3; 3],
    /// The unit normal and its offset (`normal · x = offset` on the plane); `None` for a
    /// triangle too thin to have one, always measured in full.
    plane: Option<(Vec3, f32)>,
    /// Each side's outward unit normal in the plane and its offset.
    sides: [(Vec3, f32); 3],
}

impl FanTriangle {
    fn new(face: u32, corners: [Vec3; 3]) -> Self {
        let [a, b, c] = corners;
        let normal = (b - a).cross(c - a).try_normalize();
        let side = |p: Vec3, q: Vec3, n: Vec3| {
            let out = (q - p).cross(n).normalize_or_zero();
            (out, out.dot(p))
        };
        let (plane, sides) = match normal {
            Some(n) => (
                Some((n, n.dot(a))),
                [side(a, b, n), side(b, c, n), side(c, a, n)],
            ),
            None => (None, [(Vec3::ZERO, 0.0); 3]),
        };
        Self {
            face,
            corners,
            plane,
            sides,
        }
    }

    /// The squared distance from `p`, or a lower bound of it that is greater than `bound`
    /// (so a value equal to `bound` or under it is exact).
    #[inline]
    fn squared_distance_below(&self, p: Vec3, bound: f32) -> f32 {
        let Some((n, offset)) = self.plane else {
            return (closest_on_triangle(p, &self.corners) - p).length_squared();
        };
        let h = n.dot(p) - offset;
        let outside = self
            .sides
            .iter()
            .map(|&(m, o)| m.dot(p) - o)
            .fold(0.0f32, f32::max);
        let low = h * h + outside * outside;
        if outside <= 0.0 || low > bound {
            low
        } else {
            (closest_on_triangle(p, &self.corners) - p).length_squared()
        }
    }
}

/// The points in one face's bin, stored beside it while they are few (a review reads the bins
/// of about ten faces scattered over the rows, each once).
type Bin = SmallVec<[Vec3; 4]>;

/// The input's points, in bins by face row (see the module doc).
struct InputSamples {
    bins: Vec<Bin>,
    /// Scratch for [`InputSamples::rebin`]: the points moving, each with its face's place in
    /// the fan.
    moving: Vec<(Vec3, usize)>,
}

impl InputSamples {
    /// Every face's centroid in its own bin, and every vertex in the bin of the first face (by
    /// row) that has it.
    fn new(t: &Connectivity) -> Self {
        let mut placed = vec![false; t.vertex_count()];
        let bins = t
            .faces()
            .map(|f| {
                let corners = t.triangle_halfedges(f).map(|h| t.to_vertex(h));
                let at = corners.map(|v| t.position(v));
                let mut bin = Bin::new();
                bin.push((at[0] + at[1] + at[2]) / 3.0);
                for (v, at) in corners.into_iter().zip(at) {
                    if !std::mem::replace(&mut placed[v.index()], true) {
                        bin.push(at);
                    }
                }
                bin
            })
            .collect();
        Self {
            bins,
            moving: Vec::new(),
        }
    }

    /// Asks for the bin of `face` to be brought into the cache, where the processor can: a
    /// review reads about ten bins scattered over the rows, and each waits on memory otherwise.
    #[inline]
    #[allow(unsafe_code)]
    fn prefetch(&self, face: u32) {
        #[cfg(target_arch = "x86_64")]
        if let Some(bin) = self.bins.get(face as usize) {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            // SAFETY: a prefetch is a hint that reads nothing into the program and cannot
            // fault; SSE, which it needs, is part of every x86-64 processor.
            let at: *const i8 = (bin as *const Bin).cast();
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(at);
                _mm_prefetch::<_MM_HINT_T0>(at.wrapping_add(size_of::<Bin>() - 1));
            }
        }
    }

    /// The largest squared distance from a point in the bins of the faces `before` to the
    /// nearest of the triangles `fan`, or `floor` if none is farther (`f32::MAX` for a point
    /// when `fan` is empty). Each point is tried first against its own face's new shape, where
    /// it mostly lies nearest, and the others only while it could still be the farthest.
    fn farthest(&self, before: &[u32], fan: &[FanTriangle], floor: f32) -> f32 {
        let mut worst = floor;
        for &f in before {
            let own = fan.iter().find(|t| t.face == f);
            for &p in &self.bins[f as usize] {
                let mut nearest = own.map_or(f32::MAX, |t| t.squared_distance_below(p, f32::MAX));
                if nearest <= worst {
                    continue;
                }
                for t in fan {
                    nearest = nearest.min(t.squared_distance_below(p, nearest));
                    if nearest <= worst {
                        break;
                    }
                }
                worst = worst.max(nearest);
            }
        }
        worst
    }

    /// Moves the points of the faces `before` each into the bin of the nearest of `fan` (the
    /// lowest face row among equals); with `fan` empty, they stay where they are.
    fn rebin(&mut self, before: &[u32], fan: &[FanTriangle]) {
        if fan.is_empty() {
            return;
        }
        let mut moving = std::mem::take(&mut self.moving);
        moving.clear();
        for &f in before {
            let own = fan.iter().position(|t| t.face == f).unwrap_or(0);
            moving.extend(self.bins[f as usize].drain(..).map(|p| (p, own)));
        }
        for &(p, own) in &moving {
            // Its own face's new shape first (where it mostly stays), then the others on a bound.
            let t = &fan[own];
            let mut best = (t.squared_distance_below(p, f32::MAX), t.face);
            for t in fan {
                let d = t.squared_distance_below(p, best.0);
                if d < best.0 || (d == best.0 && t.face < best.1) {
                    best = (d, t.face);
                }
            }
            self.bins[best.1 as usize].push(p);
        }
        self.moving = moving;
    }
}

/// The lazy distance check of a run (see the module doc): the samples, each edge's key by its
/// quadric alone, and when each edge was measured and each vertex's faces last changed.
pub(crate) struct DistanceCheck {
    samples: InputSamples,
    /// `w · 2Ā` (the weight times the mean doubled face area): what a squared distance costs.
    scale: f64,
    /// The squared distance under which a point counts as on the surface (see
    /// [`NOISE_FRACTION`]).
    noise: f32,
    /// Each edge's key by its quadric error alone, by heap slot.
    quadric_key: Vec<Key>,
    /// The clock when each edge was last measured (0: not since it was last queued).
    measured_at: Vec<u32>,
    /// The clock when each vertex's faces last changed, by the run's vertex index.
    changed_at: Vec<u32>,
    /// Collapses made, plus one.
    clock: u32,
    /// The faces around the edge under review, by row, and the shapes of those that stay.
    before: Vec<u32>,
    fan: Vec<FanTriangle>,
}

impl DistanceCheck {
    /// The check for a run over the triangles `t` at `weight` (see the module doc), with `edges`
    /// heap slots, `vertices` vertex indices and the edges first queued at `keys`; `None` for a
    /// weight of 0 (or not a positive number), which leaves the quadrics alone.
    pub fn for_run(
        t: &Connectivity,
        weight: f64,
        [edges, vertices]: [usize; 2],
        keys: &[Key],
    ) -> Option<Self> {
        if weight.is_nan() || weight <= 0.0 {
            return None;
        }
        let area: f64 = t
            .faces()
            .map(|f| f64::from(t.triangle_area_vector(f).length()))
            .sum();
        let noise = bounding_box(t.vertices().map(|v| t.position(v)))
            .map_or(0.0, |(low, high)| (high - low).length() * NOISE_FRACTION);
        let mut check = Self {
            samples: InputSamples::new(t),
            scale: weight * area / t.face_count().max(1) as f64,
            noise: noise * noise,
            quadric_key: vec![0; edges],
            measured_at: vec![0; edges],
            changed_at: vec![0; vertices],
            clock: 1,
            before: Vec::with_capacity(16),
            fan: Vec::with_capacity(16),
        };
        for &key in keys {
            check.queued(key);
        }
        Some(check)
    }

    /// Notes that an edge is queued at `key`, its quadric error alone.
    pub fn queued(&mut self, key: Key) {
        let slot = slot_of(key) as usize;
        self.quadric_key[slot] = key;
        self.measured_at[slot] = 0;
    }

    /// Reads the faces a planned collapse reshapes, by row, each with its corners afterwards
    /// (`None`: it goes), as the plans list them; rows of [`NONE`] are left out.
    pub fn read_faces(&mut self, faces: impl IntoIterator<Item = (u32, Option<[Vec3; 3]>)>) {
        self.before.clear();
        self.fan.clear();
        for (face, corners) in faces {
            if face == NONE {
                continue;
            }
            self.before.push(face);
            self.samples.prefetch(face);
            if let Some(corners) = corners {
                self.fan.push(FanTriangle::new(face, corners));
            }
        }
    }

    /// Reviews the popped `entry` of an edge whose collapse, merging the vertices `ends`, is
    /// allowed, its faces read ([`DistanceCheck::read_faces`]): the key to queue it at again
    /// when its cost is above the key it was popped at, or `None` to collapse it.
    /// `heap_key(cost, slot)` is the run's own key of a cost.
    pub fn review(
        &mut self,
        entry: Key,
        ends: [usize; 2],
        heap_key: impl Fn(f64, u32) -> Key,
    ) -> Option<Key> {
        let slot = slot_of(entry) as usize;
        let measured = self.measured_at[slot];
        if measured != 0 && ends.iter().all(|&v| self.changed_at[v] <= measured) {
            return None;
        }
        let quadric = f64::from(f32::from_bits((self.quadric_key[slot] >> 32) as u32));
        // Points nearer than this cannot raise the cost above the quadric's, nor those within
        // the rounding of the surface.
        let floor = ((quadric / self.scale) as f32).max(self.noise);
        let farthest = self.samples.farthest(&self.before, &self.fan, floor);
        let cost = if farthest > self.noise {
            quadric.max(self.scale * f64::from(farthest))
        } else {
            quadric
        };
        let key = heap_key(cost, slot as u32);
        self.measured_at[slot] = self.clock;
        // A cost at or under the key it was popped at is still the cheapest: collapse now.
        (key > entry).then_some(key)
    }

    /// After the reviewed collapse: its faces' points rebinned, the merged vertex `kept` and
    /// its neighbours `ring` stamped.
    pub fn collapsed(&mut self, kept: usize, ring: impl IntoIterator<Item = usize>) {
        self.samples.rebin(&self.before, &self.fan);
        self.clock += 1;
        self.changed_at[kept] = self.clock;
        for v in ring {
            self.changed_at[v] = self.clock;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::soup::PolygonSoup;
    use crate::mesh::tables::{MeshTables, extract};
    use crate::mesh::{MeshInfo, build_mesh};
    use bevy::prelude::World;

    /// The tables of the unit square in the plane z = 0, cut along its diagonal into the
    /// triangles (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1).
    fn square() -> Connectivity {
        let soup = PolygonSoup::from_faces(square_corners().to_vec(), &[[0, 1, 2], [0, 2, 3]]);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let MeshTables { tables, .. } = extract(&world, built.mesh);
        tables
    }

    fn square_corners() -> [Vec3; 4] {
        [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]
    }

    #[test]
    fn each_face_holds_its_centroid_and_each_vertex_once() {
        let samples = InputSamples::new(&square());
        let mut all: Vec<Vec3> = samples.bins.iter().flatten().copied().collect();
        assert_eq!(all.len(), 2 + 4);
        all.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        all.dedup();
        assert_eq!(all.len(), 6, "no point twice");
        let corners = square_corners();
        for bin in &samples.bins {
            assert!(!corners.contains(&bin[0]), "a centroid first: {}", bin[0]);
        }
    }

    #[test]
    fn the_farthest_point_is_measured_against_the_reshaped_faces() {
        let t = square();
        let samples = InputSamples::new(&t);
        // Both faces lifted by 0.5: every point lies 0.5 below them.
        let lifted: Vec<FanTriangle> = (0..2)
            .map(|f| {
                let corners = t
                    .triangle_halfedges(crate::mesh::tables::FaceRow::new(f))
                    .map(|h| t.position(t.to_vertex(h)) + Vec3::Z * 0.5);
                FanTriangle::new(f, corners)
            })
            .collect();
        assert_eq!(samples.farthest(&[0, 1], &lifted, 0.0), 0.25);
        // A floor above it is returned as it is; the points of no face measure nothing.
        assert_eq!(samples.farthest(&[0, 1], &lifted, 1.0), 1.0);
        assert_eq!(samples.farthest(&[], &lifted, 0.0), 0.0);
        // One face gone: its points measured against the other, whose plane they lie in.
        let one = &lifted[1..];
        let far = samples.farthest(&[0], one, 0.0);
        // Face 0's farthest point from face 1 lifted: (1, 0, 0), 1/√2 across and 0.5 below.
        assert!((far - (0.5 + 0.25)).abs() < 1e-6, "{far}");
    }

    #[test]
    fn rebinning_moves_each_point_to_the_nearest_face_and_loses_none() {
        let t = square();
        let mut samples = InputSamples::new(&t);
        // Face 1 moved far away: every point goes to face 0, which stayed.
        let fan = [
            FanTriangle::new(0, [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)]),
            FanTriangle::new(
                1,
                [Vec3::Z * 10.0, Vec3::Z * 11.0, Vec3::new(0.0, 1.0, 10.0)],
            ),
        ];
        samples.rebin(&[0, 1], &fan);
        assert_eq!(samples.bins[0].len(), 6);
        assert!(samples.bins[1].is_empty());
        // With no face left to go to, the points stay.
        samples.rebin(&[0], &[]);
        assert_eq!(samples.bins[0].len(), 6);
    }

    #[test]
    fn a_distance_within_the_rounding_of_the_surface_costs_nothing() {
        let t = square();
        let heap_key = super::super::heap_key;
        // Edge 0 queued at no cost: the square is flat, its quadrics zero.
        let entry = heap_key(0.0, 0);
        // Face 0 lifted by `height`, face 1 as it is.
        let lifted_by = |height: f32| {
            [(0, height), (1, 0.0)].map(|(f, height)| {
                let corners = t
                    .triangle_halfedges(crate::mesh::tables::FaceRow::new(f))
                    .map(|h| t.position(t.to_vertex(h)) + Vec3::Z * height);
                (f, Some(corners))
            })
        };
        let mut check = DistanceCheck::for_run(&t, 8.0, [5, 4], &[entry]).unwrap();
        // Lifted by far less than a millionth of the diagonal: no distance, the quadric's cost.
        check.read_faces(lifted_by(1e-9));
        assert_eq!(check.review(entry, [0, 1], heap_key), None);
        // A thousandth of the diagonal is a distance: queued again at its cost.
        let mut check = DistanceCheck::for_run(&t, 8.0, [5, 4], &[entry]).unwrap();
        check.read_faces(lifted_by(1.5e-3));
        let requeued = check.review(entry, [0, 1], heap_key).expect("queued again");
        assert!(requeued > entry);
    }

    #[test]
    fn a_point_is_measured_exactly_or_passed_over_on_a_bound_that_holds() {
        let t = FanTriangle::new(7, [Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0]);
        // Over the inside: its height.
        assert_eq!(
            t.squared_distance_below(Vec3::new(0.5, 0.5, 3.0), f32::MAX),
            9.0
        );
        // Beyond the corner (2, 0, 0): 1 across and 2 up, exactly, under a loose bound.
        let p = Vec3::new(3.0, 0.0, 2.0);
        assert_eq!(t.squared_distance_below(p, f32::MAX), 5.0);
        // Under a tight bound, a value above the bound and no more than the distance.
        let low = t.squared_distance_below(p, 1.0);
        assert!(low > 1.0 && low <= 5.0, "{low}");
        // A triangle too thin for a plane is measured in full.
        let thin = FanTriangle::new(8, [Vec3::ZERO, Vec3::X, Vec3::X * 2.0]);
        assert_eq!(
            thin.squared_distance_below(Vec3::new(1.0, 0.0, 2.0), 0.0),
            4.0
        );
    }
}
