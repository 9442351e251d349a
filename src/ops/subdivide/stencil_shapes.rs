//! How subdivision stencils and the next level's points are shown in step mode: shapes over
//! the mesh and a table for the step window (issue 28: "the new edge and face points and the
//! moved old vertices shown with their stencils … before the level is committed").
//!
//! The stencils themselves ([`Stencil`], [`NextLevelPoints`]) come from [`super::stencil`],
//! which states the rules (Loop 1987, Catmull & Clark 1978). This module only turns them into
//! [`StepShape`]s and a [`StepTable`]: plain data in, shapes out, so the tests check it without
//! a window.
//!
//! ```text
//!        · 1/8                      ● the new point (large, over everything)
//!       ╱                           ━ a heavy weight (≥ 1/4): a thick line, warm colour
//!  3/8 ●━━━━◉━━━━● 3/8              ─ a light weight: a thin line, pale colour
//!       ╲                           · an old vertex: a dot, larger for a larger weight
//!        · 1/8
//! ```
//!
//! Colours: edge and face points [`NEW_POINT`], moved old vertices [`MOVED_VERTEX`], both in
//! the preview of the whole level and for the new point of a stencil.

use bevy::math::Vec3;

use super::stencil::{NewPoint, NextLevelPoints, Stencil};
use crate::mesh::ids::VertexId;
use crate::mesh::topology::MeshRef;
use crate::ops::operation::stepping::{Rgb, StepShape, StepTable};

/// Colour of the points a level inserts (edge points and face points).
pub const NEW_POINT: Rgb = [0.1, 0.8, 0.45];
/// Colour of the old vertices at their moved positions.
pub const MOVED_VERTEX: Rgb = [0.85, 0.3, 0.9];
/// A term of at least this weight is drawn as a thick line ([`StepShape::Highlight`]); lighter
/// ones as thin lines ([`StepShape::Line`]).
pub const HEAVY_WEIGHT: f32 = 0.25;
/// Up to this many preview points are drawn as large dots over everything (a coarse mesh,
/// where the new points often lie inside the old surface); more as plain dots, which the
/// surface hides where it is in front of them.
pub const FEW_POINTS: usize = 1_000;

/// Which points of the next level [`point_shapes`] draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PointsShown {
    /// Edge points and face points. Default on.
    pub new_points: bool,
    /// The old vertices at their moved positions. Default on.
    pub moved_vertices: bool,
}

impl Default for PointsShown {
    fn default() -> Self {
        Self {
            new_points: true,
            moved_vertices: true,
        }
    }
}

/// The colour of a term of weight `w`: pale blue-grey for a small weight through to a deep
/// orange for a weight near 1 (square-root scale, so 1/64 and 1/16 still differ). Weights
/// outside `[0, 1]` take the end colours.
pub fn weight_color(w: f32) -> Rgb {
    let t = w.clamp(0.0, 1.0).sqrt();
    let (light, heavy) = ([0.55, 0.65, 0.8], [1.0, 0.42, 0.05]);
    let c = |i: usize| light[i] + (heavy[i] - light[i]) * t;
    [c(0), c(1), c(2)]
}

/// The colour of the new point `p` in the preview and in a stencil.
pub fn point_color(p: NewPoint) -> Rgb {
    match p {
        NewPoint::Vertex(_) => MOVED_VERTEX,
        NewPoint::Edge(_) | NewPoint::Face(_) => NEW_POINT,
    }
}

/// The mean length of the edges at `v`, `None` for a stale vertex or one without edges.
fn edge_length_near(m: &MeshRef<'_>, v: VertexId) -> Option<f32> {
    let p = m.try_position(v)?;
    m.try_vertex(v)?;
    let (sum, n) = m
        .vertex_neighbors(v)
        .fold((0.0, 0), |(s, n), w| (s + m.position(w).distance(p), n + 1));
    (n > 0).then(|| sum / n as f32)
}

/// Appends the shapes of stencil `s`: the new point as a large dot ([`StepShape::HighlightDot`]
/// in [`point_color`]); a line from it to each old vertex, thick ([`StepShape::Highlight`]) for a
/// weight of at least [`HEAVY_WEIGHT`] and thin ([`StepShape::Line`]) below, coloured by
/// [`weight_color`] (none where the old vertex sits on the new point); each old vertex as a
/// [`StepShape::Dot`] of that colour whose radius grows with the weight. Sizes follow the mean
/// edge length around the old vertices. Terms whose vertex no longer exists are skipped.
pub fn stencil_shapes(m: &MeshRef<'_>, s: &Stencil, out: &mut Vec<StepShape>) {
    let lengths: Vec<f32> = s
        .terms
        .iter()
        .filter_map(|&(v, _)| edge_length_near(m, v))
        .collect();
    let scale = if lengths.is_empty() {
        0.01
    } else {
        lengths.iter().sum::<f32>() / lengths.len() as f32
    };
    out.push(StepShape::HighlightDot(
        s.position,
        0.16 * scale,
        point_color(s.point),
    ));
    for &(v, w) in &s.terms {
        let Some(p) = m.try_position(v) else {
            continue;
        };
        let color = weight_color(w);
        if p.distance(s.position) > 1e-4 * scale {
            out.push(if w >= HEAVY_WEIGHT {
                StepShape::Highlight(s.position, p, color)
            } else {
                StepShape::Line(s.position, p, color)
            });
        }
        out.push(StepShape::Dot(
            p,
            scale * (0.04 + 0.1 * w.clamp(0.0, 1.0).sqrt()),
            color,
        ));
    }
}

/// The points `which` selects, numbered in the order vertices, edges, faces, read one by one
/// (the whole list is never copied for [`point_shapes`]).
struct Shown<'a> {
    points: &'a NextLevelPoints,
    vertices: usize,
    edges: usize,
    faces: usize,
}

impl<'a> Shown<'a> {
    fn new(points: &'a NextLevelPoints, which: PointsShown) -> Self {
        let (vertices, edges, faces) = (
            if which.moved_vertices {
                points.vertex.len()
            } else {
                0
            },
            if which.new_points {
                points.edge.len()
            } else {
                0
            },
            if which.new_points {
                points.face.len()
            } else {
                0
            },
        );
        Self {
            points,
            vertices,
            edges,
            faces,
        }
    }

    fn len(&self) -> usize {
        self.vertices + self.edges + self.faces
    }

    /// Point `i` (below [`Shown::len`]) and its colour.
    fn at(&self, i: usize) -> (Vec3, Rgb) {
        if i < self.vertices {
            (self.points.vertex[i].1, MOVED_VERTEX)
        } else if i < self.vertices + self.edges {
            (self.points.edge[i - self.vertices].1, NEW_POINT)
        } else {
            (
                self.points.face[i - self.vertices - self.edges].1,
                NEW_POINT,
            )
        }
    }
}

/// A dot radius for the preview: a tenth of the typical spacing of all the next level's points
/// (the diagonal of their bounding box over the square root of their count), so the dots keep
/// their size whichever kinds are shown.
fn dot_radius(points: &NextLevelPoints) -> f32 {
    let all = points
        .vertex
        .iter()
        .map(|x| x.1)
        .chain(points.edge.iter().map(|x| x.1))
        .chain(points.face.iter().map(|x| x.1));
    let (mut lo, mut hi, mut n) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN), 0usize);
    for p in all {
        lo = lo.min(p);
        hi = hi.max(p);
        n += 1;
    }
    if n < 2 {
        return 0.01;
    }
    0.1 * lo.distance(hi) / (n as f32).sqrt()
}

/// Pushes `chosen` as dots: large ones over everything when there are few, plain ones else.
fn push_dots(chosen: impl ExactSizeIterator<Item = (Vec3, Rgb)>, r: f32, out: &mut Vec<StepShape>) {
    let few = chosen.len() <= FEW_POINTS;
    out.extend(chosen.map(|(p, c)| {
        if few {
            StepShape::HighlightDot(p, r, c)
        } else {
            StepShape::Dot(p, r, c)
        }
    }));
}

/// Appends a dot for each point of the next level that `which` selects: edge and face points
/// in [`NEW_POINT`], moved old vertices in [`MOVED_VERTEX`]; [`StepShape::HighlightDot`]s when at
/// most [`FEW_POINTS`] are drawn, [`StepShape::Dot`]s above.
///
/// At most `limit` dots: above that, an even sample (every k-th point in storage order, so the
/// whole mesh stays covered, thinner), exactly `limit` of them. [`point_shapes_near`] keeps
/// the ones nearest a point instead (the selection, for a large mesh).
pub fn point_shapes(
    points: &NextLevelPoints,
    which: PointsShown,
    out: &mut Vec<StepShape>,
    limit: usize,
) {
    let shown = Shown::new(points, which);
    let r = dot_radius(points);
    let total = shown.len();
    if total <= limit {
        push_dots((0..total).map(|i| shown.at(i)), r, out);
    } else {
        push_dots((0..limit).map(|i| shown.at(i * total / limit)), r, out);
    }
}

/// Like [`point_shapes`], but above `limit` it keeps the `limit` points nearest `near` (the
/// selected element's position, say), so the neighbourhood a student looks at is complete.
pub fn point_shapes_near(
    points: &NextLevelPoints,
    which: PointsShown,
    near: Vec3,
    out: &mut Vec<StepShape>,
    limit: usize,
) {
    let shown = Shown::new(points, which);
    let r = dot_radius(points);
    if shown.len() <= limit {
        push_dots((0..shown.len()).map(|i| shown.at(i)), r, out);
        return;
    }
    // Each point's squared distance, computed once, with its number.
    let mut order: Vec<(f32, u32)> = (0..shown.len())
        .map(|i| (shown.at(i).0.distance_squared(near), i as u32))
        .collect();
    if limit > 0 {
        order.select_nth_unstable_by(limit - 1, |a, b| a.0.total_cmp(&b.0));
    }
    push_dots(
        order[..limit].iter().map(|&(_, i)| shown.at(i as usize)),
        r,
        out,
    );
}

/// A weight as the panel prints it: a fraction in lowest terms where it is one with a
/// denominator up to 1024 (to `f32` precision: "3/8", "1/16", "5/12"), `1` and `0` as such,
/// else a decimal with up to 6 places.
pub fn weight_text(w: f32) -> String {
    let w64 = f64::from(w);
    for d in 1..=1024u32 {
        let k = (w64 * f64::from(d)).round();
        if (w64 - k / f64::from(d)).abs() <= 8e-8 {
            return if d == 1 {
                format!("{k}")
            } else {
                format!("{k}/{d}")
            };
        }
    }
    let text = format!("{w:.6}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The new point in words: "v12v0 moved", "edge point of e3v0", "face point of f5v0".
pub fn point_title(p: NewPoint) -> String {
    match p {
        NewPoint::Vertex(v) => format!("{v} moved"),
        NewPoint::Edge(e) => format!("edge point of {e}"),
        NewPoint::Face(f) => format!("face point of {f}"),
    }
}

/// The window's table for stencil `s`: the point ([`point_title`]) over its rule line, the old
/// vertices (by their ids, `v123v0`) with their weights ([`weight_text`]), heaviest first, and
/// the new position under it.
pub fn stencil_table(s: &Stencil) -> StepTable {
    let p = s.position;
    StepTable {
        title: point_title(s.point),
        note: s.rule.clone(),
        header: ["old vertex".into(), "weight".into()],
        rows: s
            .terms
            .iter()
            .map(|&(v, w)| [v.to_string(), weight_text(w)])
            .collect(),
        footer: format!("new position ({:.4}, {:.4}, {:.4})", p.x, p.y, p.z),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::Scheme;
    use crate::mesh::ids::EdgeId;
    use crate::mesh::{MeshId, MeshInfo, PolygonSoup, build_mesh, shapes};
    use crate::ops::subdivide::stencil::tests::vertex_at;
    use crate::ops::subdivide::stencil::{next_level_points, stencil};
    use bevy::prelude::World;

    fn world_with(soup: &PolygonSoup) -> (World, MeshId) {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, soup, MeshInfo::default())
            .unwrap()
            .mesh;
        (world, mesh)
    }

    /// (large dots, thick lines, thin lines, plain dots).
    fn census(shapes: &[StepShape]) -> (usize, usize, usize, usize) {
        let mut c = (0, 0, 0, 0);
        for s in shapes {
            match s {
                StepShape::HighlightDot(..) => c.0 += 1,
                StepShape::Highlight(..) => c.1 += 1,
                StepShape::Line(..) => c.2 += 1,
                StepShape::Dot(..) => c.3 += 1,
                _ => panic!("unexpected {s:?}"),
            }
        }
        c
    }

    fn radius(s: &StepShape) -> f32 {
        match *s {
            StepShape::Dot(_, r, _) | StepShape::HighlightDot(_, r, _) => r,
            _ => panic!("not a dot: {s:?}"),
        }
    }

    /// A grid and one of its interior edges, with the edge's Loop stencil.
    struct InteriorLoopEdge {
        world: World,
        edge: EdgeId,
        ends: (VertexId, VertexId),
        stencil: Stencil,
    }

    fn interior_loop_edge() -> InteriorLoopEdge {
        let (world, mesh) = world_with(&shapes::grid(4, 4));
        let m = MeshRef::new(&world);
        let a = vertex_at(&world, mesh, Vec3::new(0.5, 0.5, 0.0));
        let b = vertex_at(&world, mesh, Vec3::new(0.75, 0.5, 0.0));
        let edge = m.edge(m.find_halfedge(a, b).unwrap());
        let stencil = stencil(&m, Scheme::Loop, NewPoint::Edge(edge)).unwrap();
        InteriorLoopEdge {
            world,
            edge,
            ends: (a, b),
            stencil,
        }
    }

    #[test]
    fn a_loop_edge_draws_its_heavy_ends_thick_and_its_light_wings_thin() {
        let InteriorLoopEdge {
            world,
            ends: (a, b),
            stencil: s,
            ..
        } = interior_loop_edge();
        let m = MeshRef::new(&world);
        let mut out = Vec::new();
        stencil_shapes(&m, &s, &mut out);
        assert_eq!(census(&out), (1, 2, 2, 4));
        assert!(matches!(out[0], StepShape::HighlightDot(p, _, NEW_POINT) if p == s.position));
        let mut dots = Vec::new();
        for shape in &out {
            match *shape {
                // The thick lines run from the new point to the ends, in the 3/8 colour.
                StepShape::Highlight(from, to, c) => {
                    assert_eq!(from, s.position);
                    assert!(to == m.position(a) || to == m.position(b));
                    assert_eq!(c, weight_color(0.375));
                }
                StepShape::Line(from, _, c) => {
                    assert_eq!(from, s.position);
                    assert_eq!(c, weight_color(0.125));
                }
                StepShape::Dot(p, r, _) => dots.push((p, r)),
                _ => {}
            }
        }
        // Dots in the order of the terms: the ends larger than the wings.
        let term_positions: Vec<Vec3> = s.terms.iter().map(|t| m.position(t.0)).collect();
        assert_eq!(dots.iter().map(|d| d.0).collect::<Vec<_>>(), term_positions);
        assert!(dots[0].1 == dots[1].1 && dots[1].1 > dots[2].1 && dots[2].1 == dots[3].1);
        assert!(radius(&out[0]) > dots[0].1);
    }

    #[test]
    fn a_vertex_that_stays_in_place_has_no_line_to_itself() {
        // Catmull–Clark on a flat regular grid: the vertex keeps its place (9/16 on itself).
        let (world, mesh) = world_with(&shapes::quad_grid(4, 4));
        let m = MeshRef::new(&world);
        let v = vertex_at(&world, mesh, Vec3::new(0.5, 0.5, 0.0));
        let s = stencil(&m, Scheme::CatmullClark, NewPoint::Vertex(v)).unwrap();
        let mut out = Vec::new();
        stencil_shapes(&m, &s, &mut out);
        // 8 neighbours, all lighter than 1/4: thin lines; 9 old vertices.
        assert_eq!(census(&out), (1, 0, 8, 9));
        assert!(matches!(
            out[0],
            StepShape::HighlightDot(_, _, MOVED_VERTEX)
        ));
        // The grid's edges are 1/4 long: the new point's radius is 0.16 of that.
        assert!((radius(&out[0]) - 0.04).abs() < 1e-6);
    }

    #[test]
    fn weight_colours_run_from_pale_to_warm() {
        let ws = [0.0, 1.0 / 64.0, 1.0 / 16.0, 0.125, 0.375, 0.5625, 1.0];
        let rgb: Vec<[f32; 3]> = ws.iter().map(|&w| weight_color(w)).collect();
        for pair in rgb.windows(2) {
            assert!(
                pair[0][0] < pair[1][0] && pair[0][2] > pair[1][2],
                "{pair:?}"
            );
        }
        assert_eq!(weight_color(-0.5), weight_color(0.0));
        assert_eq!(weight_color(2.0), weight_color(1.0));
    }

    #[test]
    fn point_shapes_draw_what_is_asked_up_to_the_limit() {
        let (world, mesh) = world_with(&shapes::icosahedron());
        let points = next_level_points(&world, mesh, Scheme::CatmullClark).unwrap();
        let (nv, ne, nf) = (12, 30, 20);
        let run = |which: PointsShown, limit: usize| {
            let mut out = Vec::new();
            point_shapes(&points, which, &mut out, limit);
            out
        };
        let all = PointsShown::default();
        let out = run(all, 5_000);
        assert_eq!(census(&out), (nv + ne + nf, 0, 0, 0));
        let colour = |s: &StepShape| match *s {
            StepShape::HighlightDot(_, _, c) => c,
            _ => unreachable!(),
        };
        assert_eq!(out.iter().filter(|s| colour(s) == MOVED_VERTEX).count(), nv);
        assert_eq!(
            out.iter().filter(|s| colour(s) == NEW_POINT).count(),
            ne + nf
        );
        let moved = PointsShown {
            new_points: false,
            moved_vertices: true,
        };
        let out = run(moved, 5_000);
        assert_eq!(out.len(), nv);
        for (shape, &(_, p)) in out.iter().zip(&points.vertex) {
            assert!(matches!(*shape, StepShape::HighlightDot(q, _, MOVED_VERTEX) if q == p));
        }
        let new = PointsShown {
            new_points: true,
            moved_vertices: false,
        };
        assert_eq!(run(new, 5_000).len(), ne + nf);
        let none = PointsShown {
            new_points: false,
            moved_vertices: false,
        };
        assert!(run(none, 5_000).is_empty());
        // Above the limit: exactly the limit, sampled across the kinds.
        let out = run(all, 10);
        assert_eq!(out.len(), 10);
        assert!(out.iter().any(|s| colour(s) == MOVED_VERTEX));
        assert!(out.iter().any(|s| colour(s) == NEW_POINT));
        assert!(run(all, 0).is_empty());
        // Every dot the same size whichever kinds are shown.
        let r = radius(&run(all, 5_000)[0]);
        assert!(run(new, 5_000).iter().all(|s| radius(s) == r));
    }

    #[test]
    fn many_points_become_plain_dots_and_near_keeps_the_nearest() {
        let (world, mesh) = world_with(&shapes::icosphere(3));
        let points = next_level_points(&world, mesh, Scheme::Loop).unwrap();
        let total = 642 + 1920;
        let mut out = Vec::new();
        point_shapes(&points, PointsShown::default(), &mut out, 5_000);
        assert_eq!(census(&out), (0, 0, 0, total));
        out.clear();
        point_shapes(&points, PointsShown::default(), &mut out, FEW_POINTS);
        assert_eq!(census(&out), (FEW_POINTS, 0, 0, 0));

        let near = Vec3::X;
        out.clear();
        point_shapes_near(&points, PointsShown::default(), near, &mut out, 40);
        assert_eq!(out.len(), 40);
        let kept: Vec<Vec3> = out
            .iter()
            .map(|s| match *s {
                StepShape::HighlightDot(p, ..) => p,
                _ => unreachable!(),
            })
            .collect();
        let farthest_kept = kept.iter().map(|p| p.distance(near)).fold(0.0, f32::max);
        let all = points
            .vertex
            .iter()
            .map(|x| x.1)
            .chain(points.edge.iter().map(|x| x.1));
        let closer_left_out = all
            .filter(|p| !kept.contains(p))
            .filter(|p| p.distance(near) < farthest_kept)
            .count();
        assert_eq!(closer_left_out, 0);
        out.clear();
        point_shapes_near(&points, PointsShown::default(), near, &mut out, 0);
        assert!(out.is_empty());
    }

    #[test]
    fn weights_print_as_fractions_where_they_are_one() {
        assert_eq!(weight_text(0.375), "3/8");
        assert_eq!(weight_text(1.0 / 16.0), "1/16");
        assert_eq!(weight_text(10.0 / 16.0), "5/8");
        assert_eq!(weight_text(9.0 / 16.0), "9/16");
        assert_eq!(weight_text(1.0 / 64.0), "1/64");
        assert_eq!(weight_text((5.0f64 / 12.0) as f32), "5/12");
        assert_eq!(weight_text((3.0f64 / 56.0) as f32), "3/56");
        assert_eq!(weight_text(1.0), "1");
        assert_eq!(weight_text(0.0), "0");
        assert_eq!(weight_text(2f32.sqrt() - 1.0), "0.414214");
    }

    #[test]
    fn the_table_lists_the_rule_the_vertices_and_their_weights() {
        let InteriorLoopEdge {
            edge: e,
            stencil: s,
            ..
        } = interior_loop_edge();
        let table = stencil_table(&s);
        assert_eq!(table.title, format!("edge point of {e}"));
        assert_eq!(table.note, s.rule);
        assert_eq!(table.header, ["old vertex".to_string(), "weight".into()]);
        let rows: Vec<[String; 2]> = s
            .terms
            .iter()
            .map(|&(v, w)| [v.to_string(), weight_text(w)])
            .collect();
        assert_eq!(table.rows, rows);
        assert_eq!(table.rows.iter().filter(|r| r[1] == "3/8").count(), 2);
        assert_eq!(table.rows.iter().filter(|r| r[1] == "1/8").count(), 2);
        assert_eq!(table.footer, "new position (0.6250, 0.5000, 0.0000)");
    }
}
