//! A mesh closed over its holes, and which way it faces: whether its back faces can be seen
//! from a point.
//!
//! Every mesh Pappus holds is oriented, so each connected component faces one way throughout.
//! Close each of its boundary loops with a cone from the loop's centroid — a triangle
//! `(centroid, from, to)` on every boundary halfedge, oriented as a face filling the hole would
//! be — and the component bounds a volume. Its signed volume (the divergence theorem:
//! `Σ p₀ · (p₁ × p₂) / 6` over the triangles of its faces and cones) is positive when the faces
//! point out of it and negative when they point into it (an inside-out component).
//!
//! From an eye outside every component, a sight line crosses the closed surfaces alternately
//! inwards and outwards, and where a component faces outward its first inward crossing is a
//! front face, unless it is a hole's: only through a hole can a sight line reach back faces.
//! A hole whose loop, seen along its normal (the loop's area vector), is a simple polygon can
//! be closed by a surface that is a height field over that view, lying within the slab its
//! loop spans along the normal. A sight line from an eye on the inner side of that slab crosses
//! such a cap only outwards. So when every component faces outward, the eye lies outside the
//! bounding box and on the inner side of every hole's slab, no back face can be seen
//! ([`Closure::back_faces_hidden_from`]). A component enclosing no volume (a flat sheet) is not
//! counted as facing either way, and a hole that doubles back on itself in that view (or has no
//! area) lets no eye pass. What the argument leaves out is a surface that passes through itself
//! (a fold dragged by hand, a cap through the mesh), where a back face can be nearest the eye.

use bevy::math::{DVec3, Vec2, Vec3};

use super::build::prepare_mesh;
use super::soup::PolygonSoup;
use super::stats::component_of_vertices;
use super::tables::Connectivity;

/// The volume a mesh bounds once its holes are closed, and its holes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Closure {
    /// The signed volume each connected component bounds, its holes closed by cones: positive
    /// where its faces point outward.
    pub volumes: Vec<f64>,
    /// Every hole, or `None` for one that lets no eye pass (see the module doc).
    pub holes: Vec<Option<Hole>>,
    /// The smallest box holding every vertex, `None` for a mesh without vertices.
    pub bounds: Option<(Vec3, Vec3)>,
}

/// A hole: where it is, which way a face filling it would face, and how far its loop strays
/// from its plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hole {
    /// The centroid of its loop's vertices.
    pub centre: Vec3,
    /// The unit normal of its loop's area vector, pointing out of the mesh.
    pub normal: Vec3,
    /// The farthest a loop vertex lies from the plane through `centre` along `normal`.
    pub reach: f32,
}

/// Below this share of the bounding box's volume, a component's volume counts as none.
const FLAT: f64 = 1e-9;

/// Loops longer than this are not checked for doubling back (a quadratic check) and let no eye
/// pass.
const LONGEST_CHECKED_LOOP: usize = 4096;

impl Closure {
    /// Closes the mesh of `t` (see the module doc). Assumes consistent tables, as
    /// [`super::tables::extract`] reads them.
    pub fn of(t: &Connectivity) -> Self {
        let component = component_of_vertices(t);
        let components = component.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
        let mut volumes = vec![0.0; components];
        let tet =
            |a: Vec3, b: Vec3, c: Vec3| a.as_dvec3().dot(b.as_dvec3().cross(c.as_dvec3())) / 6.0;
        for f in t.faces() {
            let mut corners = t.face_halfedges(f).map(|h| t.to_vertex(h));
            let Some(first) = corners.next() else {
                continue;
            };
            let p0 = t.position(first);
            let mut volume = 0.0;
            let mut previous = corners.next().map(|v| t.position(v));
            for v in corners {
                let p = t.position(v);
                if let Some(q) = previous {
                    volume += tet(p0, q, p);
                }
                previous = Some(p);
            }
            volumes[component[first.index()] as usize] += volume;
        }
        let mut holes = Vec::new();
        let mut seen = vec![false; t.halfedge_count()];
        for start in t.halfedges() {
            if !t.is_boundary(start) || seen[start.index()] {
                continue;
            }
            let mut hole = Vec::new();
            let mut h = start;
            // A consistent loop comes back to its start; the count bounds a broken one.
            for _ in 0..t.halfedge_count() {
                seen[h.index()] = true;
                hole.push(h);
                h = t.next(h);
                if h == start {
                    break;
                }
            }
            let sum: DVec3 = hole
                .iter()
                .map(|&h| t.position(t.from_vertex(h)).as_dvec3())
                .sum();
            let apex = (sum / hole.len() as f64).as_vec3();
            let c = component[t.from_vertex(start).index()] as usize;
            let mut area = Vec3::ZERO;
            let corners: Vec<Vec3> = hole.iter().map(|&h| t.position(t.from_vertex(h))).collect();
            for (i, &a) in corners.iter().enumerate() {
                let b = corners[(i + 1) % corners.len()];
                volumes[c] += tet(apex, a, b);
                area += (a - apex).cross(b - apex);
            }
            holes.push(hole_of(apex, area, &corners));
        }
        Self {
            volumes,
            holes,
            bounds: bounding_box(t.positions.iter().copied()),
        }
    }

    /// The closure of the mesh drawn by `triangles` (corners indexing `positions`, each mesh
    /// vertex once): a polygon mesh's fans, as the renderer draws it, close as the polygons do.
    /// `None` when the triangles are not a clean oriented manifold as they stand (the builder
    /// would have to repair them: turn a face, split a vertex), since the closure of a repaired
    /// mesh says nothing of the drawn one.
    pub fn of_triangles(positions: Vec<Vec3>, triangles: Vec<u32>) -> Option<Self> {
        let faces = triangles.len() / 3;
        let soup = PolygonSoup {
            positions,
            indices: triangles,
            face_starts: (0..=faces).map(|f| 3 * f as u32).collect(),
            ..PolygonSoup::default()
        };
        let prepared = prepare_mesh(&soup).ok()?;
        prepared
            .report()
            .is_clean()
            .then(|| Self::of(prepared.tables()))
    }

    /// This closure after an edit that left its holes as they were: its one component's volume
    /// changed by `volume_change` (what the signed volume under the faces changed by) and the
    /// vertices' box now `bounds`. `None` for a closure of several components, among which a
    /// change summed over the mesh cannot be shared out.
    pub fn changed(&self, volume_change: f64, bounds: Option<(Vec3, Vec3)>) -> Option<Self> {
        let [volume] = self.volumes[..] else {
            return None;
        };
        Some(Self {
            volumes: vec![volume + volume_change],
            holes: self.holes.clone(),
            bounds,
        })
    }

    /// Whether every component bounds a volume and its faces point out of it. A mesh without
    /// faces does not.
    pub fn faces_outward(&self) -> bool {
        let Some((lo, hi)) = self.bounds else {
            return false;
        };
        let size = (hi - lo).as_dvec3();
        let flat = FLAT * size.x * size.y * size.z;
        !self.volumes.is_empty() && self.volumes.iter().all(|&v| v > flat && flat > 0.0)
    }

    /// Whether no back face of the mesh can be seen from `eye`: every component faces outward,
    /// `eye` lies outside the bounding box and on the inner side of every hole's slab (see the
    /// module doc, and the exception it names).
    pub fn back_faces_hidden_from(&self, eye: Vec3) -> bool {
        let Some((lo, hi)) = self.bounds else {
            return false;
        };
        let outside = eye.cmplt(lo).any() || eye.cmpgt(hi).any();
        outside
            && self.faces_outward()
            && self
                .holes
                .iter()
                .all(|hole| hole.is_some_and(|h| (eye - h.centre).dot(h.normal) < -h.reach))
    }
}

/// The smallest box holding `points`, as its lowest and highest corners; `None` for no point.
pub fn bounding_box(points: impl IntoIterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    points.into_iter().fold(None, |b, p| {
        Some(b.map_or((p, p), |(lo, hi): (Vec3, Vec3)| (lo.min(p), hi.max(p))))
    })
}

/// The hole whose loop has these `corners`, centroid `centre` and area vector `area`, or `None`
/// where the loop has no area or doubles back on itself seen along its normal.
fn hole_of(centre: Vec3, area: Vec3, corners: &[Vec3]) -> Option<Hole> {
    let normal = area.try_normalize()?;
    if corners.len() > LONGEST_CHECKED_LOOP {
        return None;
    }
    let (u, v) = normal.any_orthonormal_pair();
    let seen: Vec<Vec2> = corners
        .iter()
        .map(|&p| Vec2::new((p - centre).dot(u), (p - centre).dot(v)))
        .collect();
    if !is_simple_polygon(&seen) {
        return None;
    }
    let reach = corners
        .iter()
        .map(|&p| (p - centre).dot(normal).abs())
        .fold(0.0, f32::max);
    Some(Hole {
        centre,
        normal,
        reach,
    })
}

/// Whether no two sides of the closed polygon `p` meet other than neighbours at their shared
/// corner (a quadratic check).
fn is_simple_polygon(p: &[Vec2]) -> bool {
    let n = p.len();
    if n < 3 {
        return false;
    }
    let side = |i: usize| (p[i], p[(i + 1) % n]);
    let orient = |a: Vec2, b: Vec2, c: Vec2| (b - a).perp_dot(c - a);
    let cross = |(a, b): (Vec2, Vec2), (c, d): (Vec2, Vec2)| {
        let (d1, d2) = (orient(a, b, c), orient(a, b, d));
        let (d3, d4) = (orient(c, d, a), orient(c, d, b));
        // Touching or overlapping counts as meeting: a loop that grazes itself is refused.
        d1 * d2 <= 0.0 && d3 * d4 <= 0.0
    };
    (0..n).all(|i| {
        // Sides i and i+1 share a corner; so do the last and the first.
        (i + 2..n).all(|j| (i == 0 && j == n - 1) || !cross(side(i), side(j)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use bevy::prelude::World;

    fn closure(soup: &PolygonSoup) -> Closure {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, soup, MeshInfo::default())
            .expect("a valid soup")
            .mesh;
        Closure::of(&extract(&world, mesh).tables)
    }

    /// `soup` with every face turned the other way.
    fn inside_out(soup: &PolygonSoup) -> PolygonSoup {
        let faces: Vec<Vec<u32>> = soup
            .faces()
            .map(|f| f.iter().rev().copied().collect())
            .collect();
        PolygonSoup::from_faces(soup.positions.clone(), &faces)
    }

    /// The cube `[-1, 1]³` without its +z face (the second).
    fn open_at_the_top() -> PolygonSoup {
        let cube = shapes::cube();
        let faces: Vec<&[u32]> = cube
            .faces()
            .enumerate()
            .filter_map(|(f, face)| (f != 1).then_some(face))
            .collect();
        PolygonSoup::from_faces(cube.positions.clone(), &faces)
    }

    /// `a`, and `b` moved 5 along x beside it: two components.
    fn side_by_side(a: &PolygonSoup, b: &PolygonSoup) -> PolygonSoup {
        let mut both = a.clone();
        let offset = a.positions.len() as u32;
        both.positions
            .extend(b.positions.iter().map(|p| *p + Vec3::X * 5.0));
        for face in b.faces() {
            both.push_face(&face.iter().map(|i| i + offset).collect::<Vec<u32>>());
        }
        both
    }

    #[test]
    fn a_closed_cube_bounds_its_volume_and_faces_outward() {
        let c = closure(&shapes::cube());
        assert_eq!(c.volumes.len(), 1);
        assert!((c.volumes[0] - 8.0).abs() < 1e-9, "{:?}", c.volumes);
        assert!(c.holes.is_empty());
        assert!(c.faces_outward());
        assert!(c.back_faces_hidden_from(Vec3::new(0.0, 0.0, 5.0)));
        // Inside the box: the back faces are all there is to see.
        assert!(!c.back_faces_hidden_from(Vec3::ZERO));
    }

    #[test]
    fn the_drawn_triangles_close_as_the_polygons_do() {
        // Open at the top, beside a whole cube turned inside out: two components and a hole.
        let soup = side_by_side(&open_at_the_top(), &inside_out(&shapes::cube()));
        let mut fans: Vec<[u32; 3]> = soup
            .faces()
            .flat_map(|f| (1..f.len() - 1).map(move |i| [f[0], f[i], f[i + 1]]))
            .collect();
        let drawn =
            Closure::of_triangles(soup.positions.clone(), fans.concat()).expect("clean fans");
        let polygons = closure(&soup);
        assert_eq!((drawn.holes.len(), drawn.bounds), (1, polygons.bounds));
        assert_eq!(drawn.holes, polygons.holes);
        let sorted = |c: &Closure| {
            let mut v = c.volumes.clone();
            v.sort_by(f64::total_cmp);
            v
        };
        for (d, p) in sorted(&drawn).into_iter().zip(sorted(&polygons)) {
            assert!((d - p).abs() < 1e-12, "{drawn:?} against {polygons:?}");
        }
        assert!((sorted(&drawn)[0] + 8.0).abs() < 1e-12, "{drawn:?}");
        // A triangle turned against its neighbours is a repair, not the drawn mesh.
        fans[0].swap(1, 2);
        assert_eq!(Closure::of_triangles(soup.positions, fans.concat()), None);
    }

    #[test]
    fn a_changed_closure_keeps_its_holes_and_takes_the_new_volume_and_box() {
        let c = closure(&shapes::cube());
        let grown = (Vec3::splat(-1.0), Vec3::splat(2.0));
        let changed = c.changed(-10.0, Some(grown)).expect("one component");
        assert_eq!(changed.volumes.len(), 1);
        assert!(
            (changed.volumes[0] + 2.0).abs() < 1e-9,
            "{:?}",
            changed.volumes
        );
        assert_eq!((changed.holes, changed.bounds), (c.holes, Some(grown)));
        // Two components: a change summed over both cannot be shared out.
        let two = Closure {
            volumes: vec![8.0, 8.0],
            ..Closure::default()
        };
        assert_eq!(two.changed(1.0, None), None);
    }

    #[test]
    fn an_inside_out_cube_bounds_a_negative_volume() {
        let c = closure(&inside_out(&shapes::cube()));
        assert!((c.volumes[0] + 8.0).abs() < 1e-9, "{:?}", c.volumes);
        assert!(!c.faces_outward());
        assert!(!c.back_faces_hidden_from(Vec3::new(0.0, 0.0, 5.0)));
    }

    #[test]
    fn a_cube_open_at_the_top_hides_its_inside_only_from_below_the_rim() {
        let c = closure(&open_at_the_top());
        // The cone's apex is the top's centre, so the cone is the missing face itself.
        assert!((c.volumes[0] - 8.0).abs() < 1e-6, "{:?}", c.volumes);
        let hole = c.holes[0].expect("a flat square loop");
        assert_eq!(
            (hole.centre, hole.normal, hole.reach),
            (Vec3::Z, Vec3::Z, 0.0)
        );
        // From above the rim, sight lines pass through the hole onto the inner walls.
        assert!(!c.back_faces_hidden_from(Vec3::new(0.0, 0.0, 5.0)));
        assert!(!c.back_faces_hidden_from(Vec3::new(3.0, 0.0, 2.0)));
        // Level with the rim, only grazing; still not counted as hidden.
        assert!(!c.back_faces_hidden_from(Vec3::new(5.0, 0.0, 1.0)));
        // Below it, they cannot.
        assert!(c.back_faces_hidden_from(Vec3::new(0.0, 0.0, -5.0)));
        assert!(c.back_faces_hidden_from(Vec3::new(4.0, 3.0, 0.5)));
    }

    #[test]
    fn a_loop_that_doubles_back_on_itself_lets_no_eye_pass() {
        let square = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        assert!(is_simple_polygon(&square));
        let bow_tie = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];
        assert!(!is_simple_polygon(&bow_tie));
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        assert_eq!(hole_of(Vec3::splat(0.5), Vec3::Z, &corners), None);
        // A loop with no area has no normal.
        assert_eq!(hole_of(Vec3::ZERO, Vec3::ZERO, &corners[..3]), None);
    }

    #[test]
    fn a_flat_sheet_faces_neither_way() {
        let c = closure(&shapes::grid(4, 4));
        assert_eq!(c.volumes.len(), 1);
        assert!(c.volumes[0].abs() < 1e-9, "{:?}", c.volumes);
        assert!(!c.faces_outward());
        let (lo, hi) = c.bounds.expect("vertices");
        let above = (lo + hi) / 2.0 + Vec3::new(0.0, 0.0, 10.0);
        assert!(!c.back_faces_hidden_from(above));
    }

    #[test]
    fn every_component_must_face_outward() {
        let cube = shapes::cube();
        let c = closure(&side_by_side(&cube, &inside_out(&cube)));
        assert_eq!(c.volumes.len(), 2);
        assert!((c.volumes[0] - 8.0).abs() < 1e-9 && (c.volumes[1] + 8.0).abs() < 1e-9);
        assert!(!c.faces_outward());
        assert!(closure(&side_by_side(&cube, &cube)).faces_outward());
    }
}
