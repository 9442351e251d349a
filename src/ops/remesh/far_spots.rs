//! The finish's last step: the input's points that the fitted remesh still leaves farthest off
//! pull a corner of the remesh triangle nearest each towards them.
//!
//! The fit before it ([`surface_fit`](crate::ops::geometry::surface_fit)) moves each vertex by
//! a weighted mean of the gaps around it, a step towards the least squares, which one far point
//! among many near ones barely moves. The Hausdorff distance is the largest gap, not a mean
//! (Cignoni, Rocchini & Scopigno, "Metro: measuring error on simplified surfaces", 1998, measure
//! it both ways on samples of the two surfaces, as this step does around each far point). So,
//! farthest first, each of the input's points left more than [`FAR_SPOT`] · L off the remesh
//! tries each free corner of the remesh triangle nearest it at [`STEPS`] points along the way
//! towards it, and the corner moves to the one that brings the largest gap around it down the
//! most, both ways: the input's points over the corner's triangles (their corners and centres,
//! within the corner's longest side of it) to the remesh, and the corner itself, the middles of
//! its sides and the centres of its triangles to the input. A move is kept only where it takes
//! that largest gap down by [`GAIN`] of it at least, turns no triangle by more than 60° and
//! makes none thin that was not, nor a thin one thinner. The boundary, the feature corners and
//! the tips put back stay; a vertex on a feature line moves as any other, as in the fit. The
//! connectivity is left as it is.
//!
//! On the bunny remeshed at its mean edge length, one input vertex on a crumpled stretch of the
//! scan was left 0.197 L off after the fit (every other under 0.15 L); splitting a side onto it
//! turned a triangle by just over 60°, and moving the nearest corner (on a feature line of the
//! scan's noise) all the way onto it took its neighbours 0.27 L off. Three tenths of the way
//! there, the farthest gap around it is 0.15 L (`docs/performance.md`).

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::Position;
use crate::mesh::ids::{MeshId, VertexId};
use crate::mesh::stats::{THIN_ANGLE_DEG, min_corner_angle_deg};
use crate::mesh::tables::{Connectivity, MeshTables, NONE, extract};
use crate::ops::geometry::closest::{Reference, closest_on_triangle};
use crate::ops::geometry::surface_fit::held_vertices;

use super::finish::farther_than;

/// How far from the remesh (times the target length) an input point must be left for this step
/// to try to bring the remesh nearer to it.
const FAR_SPOT: f32 = 0.1;

/// How many points along the way from a corner to a far point are tried (at 1/`STEPS`,
/// 2/`STEPS`, ..., the far point itself).
const STEPS: usize = 10;

/// The spots farther than this share of the farthest one's gap are the ones tried: those
/// the Hausdorff distance may come down to (nearer ones only cost time: on the ogre, every
/// spot past [`FAR_SPOT`] took the remesh from 3.9 to 13.5 s, and the cow farther).
const BAND: f32 = 0.5;

/// The least share of the largest gap around a corner that its move must take off.
const GAIN: f32 = 0.01;

/// The most a move may turn a triangle (the limit the finish's splits keep too).
const MAX_TURN_DEG: f32 = 60.0;

/// Moves the free corners of `mesh` towards the `spots` (the input's points that may be put
/// back: its vertices off the boundary and the centres of its coarse triangles) that the remesh
/// leaves farther than [`FAR_SPOT`] · `length` from it, where that brings the largest gap
/// around them down (see the module doc). Vertices on the boundary, feature corners (where
/// other than two `features` edges meet) and the `pinned` ones stay. Returns the vertices
/// moved, each once.
pub(super) fn pull_to_far_spots(
    world: &mut World,
    mesh: MeshId,
    spots: &[Vec3],
    input: &Reference,
    features: &EntityHashSet,
    pinned: &EntityHashSet,
    length: f32,
) -> Vec<VertexId> {
    let MeshTables { tables: t, members } = extract(world, mesh);
    let mut far_spots = farther_than(&t, spots, FAR_SPOT * length);
    if let Some(&(farthest, ..)) = far_spots.first() {
        far_spots.retain(|spot| spot.0 >= BAND * farthest);
    }
    let held = held_vertices(&t, &members, features, pinned);
    let mut patch = Patch {
        t: &t,
        positions: t.positions.clone(),
        input,
    };
    let mut moved: Vec<u32> = Vec::new();
    for (_, p, row) in far_spots {
        let corners = t.triangle(row).map(|h| t.to_vertex[h as usize]);
        let best = (corners.into_iter())
            .filter(|&c| !held[c as usize])
            .filter_map(|c| patch.best_move(c, p).map(|(gain, x)| (gain, c, x)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, c, x)) = best {
            patch.positions[c as usize] = x;
            moved.push(c);
        }
    }
    moved.sort_unstable();
    moved.dedup();
    for &c in &moved {
        if let Some(mut position) = world.get_mut::<Position>(members.vertices[c as usize].0) {
            position.0 = patch.positions[c as usize];
        }
    }
    moved
        .into_iter()
        .map(|c| members.vertices[c as usize])
        .collect()
}

/// The remesh's triangles as the moves leave them, over the input.
struct Patch<'a> {
    /// The remesh's connectivity.
    t: &'a Connectivity,
    /// Each vertex's position, moved or not.
    positions: Vec<Vec3>,
    /// The input surface.
    input: &'a Reference,
}

impl Patch<'_> {
    /// The best point for corner `c` on the way towards the far point `p` (see the module
    /// doc), with how much it takes off the largest gap around `c`; none where no point fits
    /// and takes off [`GAIN`] of it.
    fn best_move(&self, c: u32, p: Vec3) -> Option<(f32, Vec3)> {
        let t = self.t;
        let at = |v: u32| self.positions[v as usize];
        let fan: Vec<usize> = t.outgoing(c).map(|h| t.face[h as usize] as usize).collect();
        let ring: Vec<u32> = t.outgoing(c).map(|h| t.to_vertex[h as usize]).collect();
        let centre = at(c);
        let reach = ring
            .iter()
            .map(|&u| at(u).distance(centre))
            .fold(0.0, f32::max);
        let corners = |f: usize, x: Vec3| {
            t.triangle(f)
                .map(|h| t.to_vertex[h as usize])
                .map(|v| if v == c { x } else { at(v) })
        };
        let before: Vec<[Vec3; 3]> = fan.iter().map(|&f| corners(f, centre)).collect();
        let mut inward = Inward::new(self.input, p, centre, reach, &before);
        // The triangles around the fan, which stay where they are.
        let mut around: Vec<usize> = (ring.iter())
            .flat_map(|&u| t.outgoing(u).map(|h| t.face[h as usize]))
            .filter(|&f| f != NONE && !fan.contains(&(f as usize)))
            .map(|f| f as usize)
            .collect();
        around.sort_unstable();
        around.dedup();
        let around: Vec<[Vec3; 3]> = around.iter().map(|&f| corners(f, centre)).collect();
        let outward = |x: Vec3, triangles: &[[Vec3; 3]]| {
            (ring.iter().map(|&u| (x + at(u)) / 2.0))
                .chain(triangles.iter().map(|&[a, b, d]| (a + b + d) / 3.0))
                .chain([x])
                .fold(0.0f32, |farthest, q| farthest.max(self.input.distance(q)))
        };
        let now = (inward.farthest(&before, 0.0, &around, f32::MAX))
            .unwrap_or(f32::MAX)
            .max(outward(centre, &before));
        let mut best: Option<(f32, Vec3)> = None;
        for k in 1..=STEPS {
            let x = centre.lerp(p, k as f32 / STEPS as f32);
            let after: Vec<[Vec3; 3]> = fan.iter().map(|&f| corners(f, x)).collect();
            if !keeps_shape(&before, &after) {
                continue;
            }
            let bound = best.map_or(now * (1.0 - GAIN), |(gap, _)| gap);
            let shift = x.distance(centre);
            if let Some(gap) = inward.farthest(&after, shift, &around, bound) {
                let gap = gap.max(outward(x, &after));
                if gap < bound {
                    best = Some((gap, x));
                }
            }
        }
        best.map(|(gap, x)| (now - gap, x))
    }
}

/// The input's points over a corner's fan of triangles, for the largest of their distances to
/// the remesh with the corner moved: the far point, and the corners and centres of the input's
/// triangles within the fan's reach of the corner, farthest from the fan first.
struct Inward {
    /// The points, farthest from the fan as it is first.
    points: Vec<Vec3>,
    /// Each point's distance to the fan as it is.
    to_fan: Vec<f32>,
    /// Each point's distance to the triangles around the fan, once measured (NaN before).
    to_rest: Vec<f32>,
}

impl Inward {
    /// The points over the fan `triangles` of the corner at `centre`, the farthest one of
    /// which reaches `reach` from it, with the far point `p`.
    fn new(input: &Reference, p: Vec3, centre: Vec3, reach: f32, triangles: &[[Vec3; 3]]) -> Self {
        let mut points = vec![p];
        for row in input.rows_near(centre, reach) {
            let [a, b, c] = input.triangles()[row];
            points.extend(
                [a, b, c, (a + b + c) / 3.0]
                    .into_iter()
                    .filter(|q| q.distance(centre) <= reach),
            );
        }
        let mut measured: Vec<(f32, Vec3)> = points
            .into_iter()
            .map(|q| (to_nearest(q, triangles), q))
            .collect();
        measured.sort_by(|a, b| b.0.total_cmp(&a.0));
        Self {
            to_rest: vec![f32::NAN; measured.len()],
            to_fan: measured.iter().map(|m| m.0).collect(),
            points: measured.into_iter().map(|m| m.1).collect(),
        }
    }

    /// The largest distance from the points to the remesh with the fan's triangles `after`
    /// (its corner moved by `shift`) and the triangles `around` it, or none where it reaches
    /// `bound`. Each point of the fan moves by `shift` at most, and so does each point's
    /// distance to it: once a point lies nearer the fan as it was than the farthest found
    /// less `shift`, no later one can be farther.
    fn farthest(
        &mut self,
        after: &[[Vec3; 3]],
        shift: f32,
        around: &[[Vec3; 3]],
        bound: f32,
    ) -> Option<f32> {
        let mut farthest = 0.0f32;
        for (i, &q) in self.points.iter().enumerate() {
            if self.to_fan[i] + shift <= farthest {
                break;
            }
            let to_fan = to_nearest(q, after);
            if to_fan <= farthest {
                continue;
            }
            if self.to_rest[i].is_nan() {
                self.to_rest[i] = to_nearest(q, around);
            }
            farthest = farthest.max(to_fan.min(self.to_rest[i]));
            if farthest >= bound {
                return None;
            }
        }
        Some(farthest)
    }
}

/// How far `q` lies from the nearest of `triangles` (`f32::MAX` from none).
fn to_nearest(q: Vec3, triangles: &[[Vec3; 3]]) -> f32 {
    triangles.iter().fold(f32::MAX, |d, tri| {
        d.min(closest_on_triangle(q, tri).distance(q))
    })
}

/// Whether the triangles `after` keep the shapes of `before` (the same triangles, one corner
/// moved): none turned by more than [`MAX_TURN_DEG`], none thin that was not, and none that
/// was thin thinner.
fn keeps_shape(before: &[[Vec3; 3]], after: &[[Vec3; 3]]) -> bool {
    let limit = MAX_TURN_DEG.to_radians().cos();
    let normal = |[a, b, c]: &[Vec3; 3]| (b - a).cross(c - a).normalize_or_zero();
    before.iter().zip(after).all(|(old, new)| {
        let (was, is) = (min_corner_angle_deg(old), min_corner_angle_deg(new));
        normal(old).dot(normal(new)) >= limit && (is >= THIN_ANGLE_DEG || is >= was)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::members::MeshMembers;
    use crate::mesh::topology::MeshRef;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh, validate};

    /// Six triangles round a centre at `apex`, their outer corners on the unit circle at z = 0.
    fn hexagon(apex: Vec3) -> PolygonSoup {
        let mut corners = vec![apex];
        corners.extend((0..6).map(|k| {
            let a = (k as f32 * 60.0).to_radians();
            Vec3::new(a.cos(), a.sin(), 0.0)
        }));
        let faces: Vec<[u32; 3]> = (1..=6).map(|k| [0, k, k % 6 + 1]).collect();
        PolygonSoup::from_faces(corners, &faces)
    }

    /// A flat hexagon (the "remesh") and `input` as a second mesh of the same world, with a
    /// reference to its triangles.
    fn flat_over(input: PolygonSoup) -> (World, MeshId, Reference) {
        let mut world = World::new();
        let remesh = build_mesh(&mut world, &hexagon(Vec3::ZERO), MeshInfo::default()).unwrap();
        let input = build_mesh(&mut world, &input, MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, input.mesh);
        let reference = Reference::new(&MeshRef::new(&world), &members);
        (world, remesh.mesh, reference)
    }

    /// The position of the centre of the hexagon `mesh` (its one vertex off the boundary).
    fn centre(world: &World, mesh: MeshId) -> Vec3 {
        let t = extract(world, mesh).tables;
        let v = t.vertices().find(|&v| !t.is_boundary_vertex(v)).unwrap();
        t.position(v)
    }

    #[test]
    fn a_corner_moves_onto_the_far_point_where_that_fits_the_input() {
        // The input is a low tent over the hexagon: its apex 0.3 above the flat centre, each
        // triangle turned by atan(0.3 / (√3/2)) ≈ 19°.
        let apex = Vec3::new(0.0, 0.0, 0.3);
        let (mut world, mesh, input) = flat_over(hexagon(apex));
        let none = EntityHashSet::default();
        let moved = pull_to_far_spots(&mut world, mesh, &[apex], &input, &none, &none, 1.0);
        assert_eq!(moved.len(), 1);
        // All the way: there, the remesh is the input.
        assert_eq!(centre(&world, mesh), apex);
        assert_eq!(validate(&world, mesh), Ok(()));
    }

    #[test]
    fn a_corner_goes_no_farther_than_turns_its_triangles_by_sixty_degrees() {
        // The apex 3.2 above: the steps are 0.32 apart. Five of them (1.6) would turn each
        // triangle by atan(1.6 / (√3/2)) = 61.6°, with its smallest angle still 30.7°; four
        // (1.28) turn it by 55.9°. The corner stops at four.
        let apex = Vec3::new(0.0, 0.0, 3.2);
        let (mut world, mesh, input) = flat_over(hexagon(apex));
        let none = EntityHashSet::default();
        pull_to_far_spots(&mut world, mesh, &[apex], &input, &none, &none, 1.0);
        assert_eq!(centre(&world, mesh), Vec3::ZERO.lerp(apex, 0.4));
    }

    #[test]
    fn pinned_corners_and_near_points_leave_the_remesh_as_it_is() {
        let apex = Vec3::new(0.0, 0.0, 0.3);
        let (mut world, mesh, input) = flat_over(hexagon(apex));
        let none = EntityHashSet::default();
        // Nearer than a tenth of the length: no spot to pull towards.
        let moved = pull_to_far_spots(&mut world, mesh, &[apex], &input, &none, &none, 4.0);
        assert!(moved.is_empty());
        // The centre pinned: nothing may move.
        let members = MeshMembers::collect(&world, mesh);
        let pinned: EntityHashSet = members.vertices.iter().map(|v| v.0).collect();
        let moved = pull_to_far_spots(&mut world, mesh, &[apex], &input, &none, &pinned, 1.0);
        assert!(moved.is_empty());
        assert_eq!(centre(&world, mesh), Vec3::ZERO);
    }

    /// A grid of `n` × `n` squares over [−1.5, 1.5]², each cut into two triangles, its
    /// corners at the heights `height(x, y)`.
    fn grid(n: u32, height: &mut dyn FnMut(f32, f32) -> f32) -> PolygonSoup {
        let mut corners = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (
                    i as f32 / n as f32 * 3.0 - 1.5,
                    j as f32 / n as f32 * 3.0 - 1.5,
                );
                corners.push(Vec3::new(x, y, height(x, y)));
            }
        }
        let row = |i: u32, j: u32| i * (n + 1) + j;
        let faces: Vec<[u32; 3]> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .flat_map(|(i, j)| {
                [
                    [row(i, j), row(i + 1, j), row(i + 1, j + 1)],
                    [row(i, j), row(i + 1, j + 1), row(i, j + 1)],
                ]
            })
            .collect();
        PolygonSoup::from_faces(corners, &faces)
    }

    /// The largest distance between `mesh` and `input` both ways, measured at their vertices,
    /// edge middles and triangle centres.
    fn largest_gap(world: &World, mesh: MeshId, input: &Reference) -> f32 {
        let t = extract(world, mesh).tables;
        let remesh = Reference::from_triangles(t.faces().map(|f| t.triangle_corners(f)).collect());
        let samples = |triangles: &[[Vec3; 3]]| -> Vec<Vec3> {
            (triangles.iter())
                .flat_map(|&[a, b, c]| {
                    [
                        a,
                        (a + b) / 2.0,
                        (b + c) / 2.0,
                        (c + a) / 2.0,
                        (a + b + c) / 3.0,
                    ]
                })
                .collect()
        };
        let outward = samples(remesh.triangles())
            .into_iter()
            .map(|p| input.distance(p));
        let inward = samples(input.triangles())
            .into_iter()
            .map(|p| remesh.distance(p));
        outward.chain(inward).fold(0.0, f32::max)
    }

    #[test]
    fn over_a_bump_narrower_than_the_triangles_the_largest_gap_comes_down() {
        // A flat grid of 6 × 6 squares (the "remesh", L = 0.5) over a grid of 24 × 24 with a
        // bump on it narrower than L, 0.25 high at (0.3, −0.2), off the remesh's vertices.
        let mut bump =
            |x: f32, y: f32| 0.25 * (-((x - 0.3).powi(2) + (y + 0.2).powi(2)) / 0.08).exp();
        let bumpy = grid(24, &mut bump);
        let (mut world, mesh, input) = {
            let mut world = World::new();
            let remesh = build_mesh(&mut world, &grid(6, &mut |_, _| 0.0), MeshInfo::default());
            let built = build_mesh(&mut world, &bumpy, MeshInfo::default()).unwrap();
            let members = MeshMembers::collect(&world, built.mesh);
            let reference = Reference::new(&MeshRef::new(&world), &members);
            (world, remesh.unwrap().mesh, reference)
        };
        let before = largest_gap(&world, mesh, &input);
        let t = extract(&world, mesh).tables;
        let normals: Vec<Vec3> = t.faces().map(|f| t.triangle_area_vector(f)).collect();
        let spots: Vec<Vec3> = bumpy.positions.clone();
        let none = EntityHashSet::default();
        let moved = pull_to_far_spots(&mut world, mesh, &spots, &input, &none, &none, 0.5);
        assert!(!moved.is_empty());
        let after = largest_gap(&world, mesh, &input);
        // The bump 0.235 off the flat remesh; after, under 0.1.
        assert!(after < before / 2.0, "{before} → {after}");
        let t = extract(&world, mesh).tables;
        for (f, was) in t.faces().zip(normals) {
            assert!(t.triangle_area_vector(f).dot(was) > 0.0);
        }
        assert_eq!(validate(&world, mesh), Ok(()));
    }

    #[test]
    fn the_early_exit_finds_the_farthest_gap_that_measuring_every_point_finds() {
        // A bumpy input over the hexagon, and the fan's corner moved to several places.
        let mut seed = 12345u32;
        let mut random = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32 - 0.5
        };
        let bumpy = grid(12, &mut |_, _| 0.2 * random());
        let input = Reference::from_triangles(
            (bumpy.faces())
                .map(|f| [f[0], f[1], f[2]].map(|v| bumpy.positions[v as usize]))
                .collect(),
        );
        let fan: Vec<[Vec3; 3]> = (0..6)
            .map(|k| {
                let corner = |k: usize| {
                    let a = (k as f32 * 60.0).to_radians();
                    Vec3::new(a.cos(), a.sin(), 0.0)
                };
                [Vec3::ZERO, corner(k), corner(k + 1)]
            })
            .collect();
        let around: Vec<[Vec3; 3]> = vec![[
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.5, 0.1),
            Vec3::new(0.5, 0.87, 0.0),
        ]];
        let far = Vec3::new(0.1, 0.2, 0.4);
        let mut inward = Inward::new(&input, far, Vec3::ZERO, 1.0, &fan);
        let all = inward.points.clone();
        for _ in 0..20 {
            let x = Vec3::new(random(), random(), random());
            let after: Vec<[Vec3; 3]> = fan.iter().map(|&[_, b, c]| [x, b, c]).collect();
            let every = all.iter().fold(0.0f32, |farthest, &q| {
                farthest.max(to_nearest(q, &after).min(to_nearest(q, &around)))
            });
            let found = inward.farthest(&after, x.length(), &around, f32::MAX);
            assert_eq!(found, Some(every), "{x}");
            // Bounded below what it is: refused.
            assert_eq!(inward.farthest(&after, x.length(), &around, every), None);
        }
    }
}
