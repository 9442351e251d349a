//! The UV view: an egui window ("UV layout") that draws the active mesh's texture layout, and
//! the selection in it both ways.
//!
//! [`UvLayout`] is the layout copied out of the world: every face's corner UVs (for the click
//! test) and its sides as segments, the mesh boundary and seams (a side whose two faces give
//! its ends different UVs) apart from the rest. [`refresh_uv_layout`] (the `Sync` set, after
//! the render sync) copies it again only when the render generation
//! ([`RenderStats::rebuilds`]) or the active mesh changed, and only while the window is open;
//! it opens the window the first time the mesh has UVs. The selected element's UV shapes
//! ([`UvHighlight`]) are small and copied every frame.
//!
//! Painting ([`uv_window`]) does not walk the layout each frame: the sides become one
//! `egui::Mesh` of thin quads, built once per layout and window rect and painted from an
//! [`Arc`] (a 34k-face layout is ~100k segments, 400k vertices). A click inside the square
//! selects the face whose UV polygon (its fan triangles) holds the point ([`face_at`]), so it
//! is highlighted in 3D too; the 3D selection is drawn over the layout (a face filled, an
//! edge's segments on both sides, a vertex's corners as dots, a halfedge as an arrow).

use std::sync::Arc;

use bevy::math::Vec2;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

use crate::mesh::attributes::{CornerUv, MeshAttributes};
use crate::mesh::ids::{ElementId, FaceId, HalfedgeId, MeshId};
use crate::mesh::topology::MeshRef;

use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::Request;
use crate::editor::session::selection::{ActiveMesh, Selection, exists};
use crate::editor::view::render_sync::RenderStats;

/// Side of the square the layout is drawn in, in points.
pub const VIEW_SIZE: f32 = 320.0;

/// The selected element in UV space (empty when nothing is selected or the mesh has no UVs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UvHighlight {
    /// Filled polygons (a selected face).
    pub polygons: Vec<Vec<Vec2>>,
    /// Segments (an edge: one per side with a face).
    pub segments: Vec<[Vec2; 2]>,
    /// Arrows, tail to tip (a halfedge).
    pub arrows: Vec<[Vec2; 2]>,
    /// Dots (a vertex: one per corner, so a vertex on a seam shows several).
    pub points: Vec<Vec2>,
}

/// The active mesh's UV layout, as the UV view draws it.
#[derive(Resource, Debug, Default)]
pub struct UvLayout {
    /// The mesh the layout is of (`None`: no layout).
    pub mesh: Option<MeshId>,
    /// The render generation it was copied at.
    pub generation: usize,
    /// Bumped on every copy (the painted mesh is rebuilt when it changes).
    pub version: u64,
    /// The faces, in order.
    pub faces: Vec<FaceId>,
    /// Where each face's corners start in [`Self::corners`] (one more entry than faces).
    pub face_start: Vec<u32>,
    /// Every face's corner UVs, face after face, in the face's order.
    pub corners: Vec<Vec2>,
    /// Interior sides, each drawn once.
    pub edges: Vec<[Vec2; 2]>,
    /// Boundary and seam sides (a seam once from each face beside it).
    pub seams: Vec<[Vec2; 2]>,
    /// The smallest and largest UV, widened to hold `[0, 1]²`.
    pub bounds: [Vec2; 2],
    /// The selection in UV space, copied every frame.
    pub highlight: UvHighlight,
    /// Whether the active mesh had UVs at the last refresh (the window opens on the change).
    pub had_uvs: Option<(MeshId, bool)>,
    painted: Option<(u64, egui::Rect, Arc<egui::Mesh>)>,
}

fn uv(world: &World, h: HalfedgeId) -> Vec2 {
    world.get::<CornerUv>(h.0).map_or(Vec2::ZERO, |c| c.0)
}

impl UvLayout {
    /// Copies the layout of `mesh` (empty when it has no UVs). Face halfedge `h` is the side
    /// from the corner of `prev(h)` to the corner of `h`; it is a seam when its twin has no face
    /// or the twin's corners at the same two vertices have other UVs.
    pub fn copy(&mut self, world: &World, mesh: MeshId) {
        self.clear();
        self.mesh = Some(mesh);
        if !MeshAttributes::of(world, mesh).uv {
            return;
        }
        self.faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(world, mesh, FaceId);
        let m = MeshRef::new(world);
        self.face_start.push(0);
        for &f in &self.faces {
            for h in m.face_halfedges(f) {
                let (a, b) = (uv(world, m.prev(h)), uv(world, h));
                self.corners.push(b);
                self.bounds = [self.bounds[0].min(b), self.bounds[1].max(b)];
                let t = m.twin(h);
                let seam = m.face(t).is_none() || uv(world, t) != a || uv(world, m.prev(t)) != b;
                if seam {
                    self.seams.push([a, b]);
                } else if h.0 < t.0 {
                    self.edges.push([a, b]);
                }
            }
            self.face_start.push(self.corners.len() as u32);
        }
    }

    /// Forgets the layout (no mesh, nothing to draw).
    pub fn clear(&mut self) {
        self.mesh = None;
        self.version += 1;
        self.painted = None;
        for list in [&mut self.edges, &mut self.seams] {
            list.clear();
        }
        self.faces.clear();
        self.face_start.clear();
        self.corners.clear();
        self.bounds = [Vec2::ZERO, Vec2::ONE];
    }

    /// The corner UVs of the `i`th face.
    pub fn face_corners(&self, i: usize) -> &[Vec2] {
        &self.corners[self.face_start[i] as usize..self.face_start[i + 1] as usize]
    }

    /// Whether there is a layout to draw.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }
}

/// The face whose UV polygon holds `p`: the first whose fan triangles (from its first corner)
/// hold it, either orientation (a flipped triangle is still hit), edges included. `None` off
/// the layout.
pub fn face_at(layout: &UvLayout, p: Vec2) -> Option<FaceId> {
    let inside = |a: Vec2, b: Vec2, c: Vec2| {
        let d = [
            (b - a).perp_dot(p - a),
            (c - b).perp_dot(p - b),
            (a - c).perp_dot(p - c),
        ];
        let area = (b - a).perp_dot(c - a);
        area != 0.0 && (d.iter().all(|&x| x >= 0.0) || d.iter().all(|&x| x <= 0.0))
    };
    (0..layout.faces.len()).find_map(|i| {
        let c = layout.face_corners(i);
        (1..c.len().saturating_sub(1))
            .any(|k| inside(c[0], c[k], c[k + 1]))
            .then_some(layout.faces[i])
    })
}

/// The selected element's shapes in UV space (empty for a mesh without UVs or a mesh id).
pub fn highlight(world: &World, element: ElementId) -> UvHighlight {
    let m = MeshRef::new(world);
    let mut out = UvHighlight::default();
    let has = |h: HalfedgeId| world.get::<CornerUv>(h.0).is_some();
    let side = |h: HalfedgeId| [uv(world, m.prev(h)), uv(world, h)];
    match element {
        ElementId::Face(f) => {
            let polygon: Vec<Vec2> = m
                .face_halfedges(f)
                .filter(|&h| has(h))
                .map(|h| uv(world, h))
                .collect();
            if !polygon.is_empty() {
                out.polygons.push(polygon);
            }
        }
        ElementId::Edge(e) => {
            let h = m.edge_halfedge(e);
            for s in [h, m.twin(h)] {
                if m.face(s).is_some() && has(s) {
                    out.segments.push(side(s));
                }
            }
        }
        ElementId::Halfedge(h) => {
            if m.face(h).is_some() && has(h) {
                out.arrows.push(side(h));
            } else if has(m.twin(h)) {
                let [a, b] = side(m.twin(h));
                out.arrows.push([b, a]);
            }
        }
        ElementId::Vertex(v) => {
            for o in m.vertex_outgoing(v) {
                let incoming = m.twin(o);
                if m.face(incoming).is_some() && has(incoming) {
                    out.points.push(uv(world, incoming));
                }
            }
        }
        ElementId::Mesh(_) => {}
    }
    out
}

/// Keeps [`UvLayout`] in step with the active mesh (the `Sync` set, after the render sync):
/// opens the window when the mesh first has UVs, copies the layout when the window is open and
/// the render generation or the mesh changed, and copies the selection's shapes every frame.
pub fn refresh_uv_layout(world: &mut World) {
    let active = world
        .resource::<ActiveMesh>()
        .0
        .filter(|m| world.get::<crate::mesh::MeshInfo>(m.0).is_some());
    let generation = world.resource::<RenderStats>().rebuilds;
    let mut layout = std::mem::take(&mut *world.resource_mut::<UvLayout>());
    let has_uvs = active.is_some_and(|m| MeshAttributes::of(world, m).uv);
    let first_uvs = active.is_some_and(|m| has_uvs && layout.had_uvs != Some((m, true)));
    layout.had_uvs = active.map(|m| (m, has_uvs));
    if first_uvs {
        world.resource_mut::<UiState>().uv_view = true;
    }
    let open = world.resource::<UiState>().uv_view;
    match active {
        None => {
            if layout.mesh.is_some() {
                layout.clear();
            }
        }
        Some(mesh) if open && (layout.mesh != Some(mesh) || layout.generation != generation) => {
            layout.copy(world, mesh);
            layout.generation = generation;
        }
        Some(_) => {}
    }
    let m = MeshRef::new(world);
    layout.highlight = match world.resource::<Selection>().element {
        Some(x) if open && has_uvs && exists(&m, x) => highlight(world, x),
        _ => UvHighlight::default(),
    };
    *world.resource_mut::<UvLayout>() = layout;
}

/// Where UV space lands in the square `rect`: a uniform scale, `v` up.
#[derive(Clone, Copy, Debug)]
struct Frame {
    lo: Vec2,
    scale: f32,
    rect: egui::Rect,
}

const PAD: f32 = 8.0;

impl Frame {
    fn new(bounds: [Vec2; 2], rect: egui::Rect) -> Self {
        let size = (bounds[1] - bounds[0]).max_element().max(1e-12);
        Self {
            lo: bounds[0],
            scale: (rect.width().min(rect.height()) - 2.0 * PAD) / size,
            rect,
        }
    }

    fn to_screen(self, p: Vec2) -> egui::Pos2 {
        let q = (p - self.lo) * self.scale;
        egui::pos2(self.rect.left() + PAD + q.x, self.rect.bottom() - PAD - q.y)
    }

    fn to_uv(self, p: egui::Pos2) -> Vec2 {
        let x = (p.x - self.rect.left() - PAD) / self.scale;
        let y = (self.rect.bottom() - PAD - p.y) / self.scale;
        self.lo + Vec2::new(x, y)
    }
}

/// Interior sides: light and translucent, so density reads as brightness.
const EDGE_COLOUR: egui::Color32 = egui::Color32::from_rgba_premultiplied(95, 98, 105, 120);
/// Boundary and seam sides.
const SEAM_COLOUR: egui::Color32 = egui::Color32::from_rgb(235, 110, 60);
/// The selection.
const SELECTED_COLOUR: egui::Color32 = egui::Color32::from_rgb(255, 215, 40);

/// The layout's sides as thin quads in screen space (one `egui::Mesh`, built once per layout
/// and rect).
fn side_mesh(layout: &UvLayout, frame: Frame) -> egui::Mesh {
    let mut mesh = egui::Mesh::default();
    let n = layout.edges.len() + layout.seams.len();
    mesh.reserve_vertices(4 * n);
    mesh.reserve_triangles(2 * n);
    let mut quad = |[a, b]: [Vec2; 2], width: f32, colour: egui::Color32| {
        let (p, q) = (frame.to_screen(a), frame.to_screen(b));
        let d = q - p;
        let length = d.length();
        if length < 1e-6 {
            return;
        }
        let normal = egui::vec2(-d.y, d.x) / length * (width / 2.0);
        let i = mesh.vertices.len() as u32;
        for corner in [p + normal, p - normal, q - normal, q + normal] {
            mesh.colored_vertex(corner, colour);
        }
        mesh.add_triangle(i, i + 1, i + 2);
        mesh.add_triangle(i, i + 2, i + 3);
    };
    for &s in &layout.edges {
        quad(s, 1.0, EDGE_COLOUR);
    }
    for &s in &layout.seams {
        quad(s, 1.6, SEAM_COLOUR);
    }
    mesh
}

/// Draws the "UV layout" window while [`UiState::uv_view`] is on (egui pass, after the
/// panels); a click on the layout selects the face under it.
pub fn uv_window(
    mut contexts: EguiContexts,
    mut layout: ResMut<UvLayout>,
    mut ui_state: ResMut<UiState>,
    mut insets: ResMut<crate::editor::view::scene::PanelInsets>,
    mut requests: MessageWriter<Request>,
) -> Result {
    if !ui_state.uv_view {
        if insets.right != 0.0 {
            insets.right = 0.0;
        }
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?.clone();
    let mut open = true;
    let shown = egui::Window::new("UV layout")
        .open(&mut open)
        .anchor(egui::Align2::RIGHT_BOTTOM, [-8.0, -36.0])
        .resizable(false)
        .show(&ctx, |ui| {
            if layout.is_empty() {
                ui.label("The mesh has no UVs: parameterize it (Shift+U).");
                return;
            }
            let (rect, response) =
                ui.allocate_exact_size(egui::vec2(VIEW_SIZE, VIEW_SIZE), egui::Sense::click());
            let frame = Frame::new(layout.bounds, rect);
            let painter = ui.painter_at(rect);
            painter.rect_filled(rect, 2.0, egui::Color32::from_gray(238));
            let unit =
                egui::Rect::from_two_pos(frame.to_screen(Vec2::ZERO), frame.to_screen(Vec2::ONE));
            painter.rect_stroke(
                unit,
                0.0,
                egui::Stroke::new(1.0, egui::Color32::from_gray(180)),
                egui::StrokeKind::Middle,
            );
            let version = layout.version;
            let mesh = match &layout.painted {
                Some((v, r, mesh)) if *v == version && *r == rect => mesh.clone(),
                _ => {
                    let mesh = Arc::new(side_mesh(&layout, frame));
                    layout.painted = Some((version, rect, mesh.clone()));
                    mesh
                }
            };
            painter.add(egui::Shape::Mesh(mesh));
            paint_highlight(&painter, &layout.highlight, frame);
            if response.clicked()
                && let Some(pos) = response.interact_pointer_pos()
                && let Some(f) = face_at(&layout, frame.to_uv(pos))
            {
                requests.write(Request::Select(Some(ElementId::Face(f))));
            }
            ui.label(
                egui::RichText::new(format!(
                    "{} faces · boundary and seams orange · click selects a face",
                    layout.faces.len()
                ))
                .small(),
            );
        });
    // The 3D view keeps clear of the window, so the mesh is seen beside its layout.
    let right = match shown {
        Some(window) if open => ctx.content_rect().right() - window.response.rect.left(),
        _ => 0.0,
    };
    if insets.right != right {
        insets.right = right;
    }
    ui_state.uv_view = open;
    Ok(())
}

fn paint_highlight(painter: &egui::Painter, h: &UvHighlight, frame: Frame) {
    let stroke = egui::Stroke::new(2.5, SELECTED_COLOUR);
    // A small element of a big layout is a few pixels: ring it so the eye finds it.
    let all: Vec<egui::Pos2> = h
        .polygons
        .iter()
        .flatten()
        .chain(h.segments.iter().flatten())
        .chain(h.arrows.iter().flatten())
        .chain(&h.points)
        .map(|&p| frame.to_screen(p))
        .collect();
    if !all.is_empty() {
        let extent = egui::Rect::from_points(&all);
        if extent.width().max(extent.height()) < 16.0 {
            painter.circle_stroke(
                extent.center(),
                12.0,
                egui::Stroke::new(2.0, egui::Color32::from_rgb(200, 60, 20)),
            );
        }
    }
    for polygon in &h.polygons {
        let points = polygon.iter().map(|&p| frame.to_screen(p)).collect();
        painter.add(egui::Shape::convex_polygon(
            points,
            egui::Color32::from_rgba_unmultiplied(255, 215, 40, 150),
            egui::Stroke::new(1.5, egui::Color32::from_rgb(200, 150, 0)),
        ));
    }
    for &[a, b] in &h.segments {
        painter.line_segment([frame.to_screen(a), frame.to_screen(b)], stroke);
    }
    for &[a, b] in &h.arrows {
        let (p, q) = (frame.to_screen(a), frame.to_screen(b));
        painter.arrow(p, q - p, stroke);
    }
    for &p in &h.points {
        painter.circle(
            frame.to_screen(p),
            4.0,
            SELECTED_COLOUR,
            egui::Stroke::new(1.0, egui::Color32::from_gray(40)),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, PolygonSoup, build_mesh};
    use bevy::math::Vec3;

    /// The unit square as two triangles (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), each corner's
    /// UV its position's x and y.
    fn square() -> (World, MeshId) {
        let mut world = World::new();
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let soup = PolygonSoup::from_faces(positions, &[[0u32, 1, 2], [0, 2, 3]]);
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(&world, mesh, FaceId);
        let corners: Vec<(HalfedgeId, Vec2)> = {
            let m = MeshRef::new(&world);
            faces
                .iter()
                .flat_map(|&f| m.face_halfedges(f).collect::<Vec<_>>())
                .map(|h| (h, m.position(m.to_vertex(h)).truncate()))
                .collect()
        };
        for (h, p) in corners {
            world.entity_mut(h.0).insert(CornerUv(p));
        }
        world.entity_mut(mesh.0).insert(MeshAttributes {
            uv: true,
            ..MeshAttributes::NONE
        });
        (world, mesh)
    }

    fn face_with(world: &World, layout: &UvLayout, corner: Vec2) -> FaceId {
        (0..layout.faces.len())
            .find(|&i| layout.face_corners(i).contains(&corner))
            .map(|i| layout.faces[i])
            .unwrap_or_else(|| panic!("no face has a corner at {corner} in {world:?}"))
    }

    #[test]
    fn a_click_finds_the_face_whose_uv_triangle_holds_it() {
        let (world, mesh) = square();
        let mut layout = UvLayout::default();
        layout.copy(&world, mesh);
        assert_eq!(layout.faces.len(), 2);
        // Only the corner (1, 0) is in the lower triangle, (0, 1) in the upper one.
        let lower = face_with(&world, &layout, Vec2::new(1.0, 0.0));
        let upper = face_with(&world, &layout, Vec2::new(0.0, 1.0));
        assert_ne!(lower, upper);
        assert_eq!(face_at(&layout, Vec2::new(0.75, 0.25)), Some(lower));
        assert_eq!(face_at(&layout, Vec2::new(0.25, 0.75)), Some(upper));
        assert_eq!(face_at(&layout, Vec2::new(1.5, 0.5)), None);
        assert_eq!(face_at(&layout, Vec2::new(-0.01, 0.5)), None);
        // The square's four sides are boundary; the diagonal is one interior side.
        assert_eq!((layout.seams.len(), layout.edges.len()), (4, 1));
    }

    #[test]
    fn a_seam_is_drawn_from_both_sides_and_highlights_both() {
        let (mut world, mesh) = square();
        // Move the upper face's corners off to the right: the diagonal becomes a seam.
        let mut layout = UvLayout::default();
        layout.copy(&world, mesh);
        let upper = face_with(&world, &layout, Vec2::new(0.0, 1.0));
        let halfedges: Vec<HalfedgeId> = MeshRef::new(&world).face_halfedges(upper).collect();
        for h in halfedges {
            let p = world.get::<CornerUv>(h.0).unwrap().0;
            world
                .entity_mut(h.0)
                .insert(CornerUv(p + Vec2::new(2.0, 0.0)));
        }
        layout.copy(&world, mesh);
        assert_eq!((layout.seams.len(), layout.edges.len()), (6, 0));
        assert_eq!(face_at(&layout, Vec2::new(2.25, 0.75)), Some(upper));
        assert_eq!(face_at(&layout, Vec2::new(0.25, 0.75)), None);
        let m = MeshRef::new(&world);
        let diagonal = m
            .face_halfedges(upper)
            .find(|&h| m.face(m.twin(h)).is_some())
            .map(|h| m.edge(h))
            .unwrap();
        let shown = highlight(&world, ElementId::Edge(diagonal));
        assert_eq!(shown.segments.len(), 2);
        assert_ne!(
            shown.segments[0],
            [shown.segments[1][1], shown.segments[1][0]]
        );
        let v = m.from_vertex(m.face_halfedge(upper));
        assert!(!highlight(&world, ElementId::Vertex(v)).points.is_empty());
    }
}
