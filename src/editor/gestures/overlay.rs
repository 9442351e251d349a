//! What is drawn over the surface each frame: the selection, the hover highlight, vertex dots
//! and halfedge arrows (offset into their face, with one barb on the face's side, as Dandelion
//! and Scotty3D draw them), and the edges marked as seams.
//!
//! An exclusive system gathers the shapes from the mesh ([`gather_overlay`]). The thin lines
//! (arrows, dots, plain lines) are drawn as one mesh ([`super::overlay_lines`]); the thick
//! highlights with gizmos ([`draw_overlay`]). Arrows and dots cover the whole mesh only while it
//! is small (see [`SMALL_MESH_FACES`]); on a large mesh they are drawn around the selection.

use bevy::color::Color;
use bevy::gizmos::config::GizmoConfigGroup;
use bevy::math::{Isometry3d, Vec3};
use bevy::prelude::*;

use crate::mesh::attributes::Seam;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::members::{MeshMembers, of_kind};
use crate::mesh::topology::MeshRef;
use crate::mesh::{Face, InMesh, MeshInfo};

use crate::editor::session::selection::{ActiveMesh, Hover, Selection};
use crate::editor::view::readability::WireframeDensity;
use crate::editor::view::render_data::EDGE_COLOR;
use crate::editor::view::render_sync::ViewSettings;

/// Meshes with at most this many faces get arrows and dots everywhere.
pub const SMALL_MESH_FACES: usize = 3000;

/// Colour of the selection.
pub const SELECTED: Color = Color::srgb(1.0, 0.62, 0.0);
/// Colour of the other elements of the selected set.
pub const IN_SET: Color = Color::srgb(1.0, 0.85, 0.3);
/// The most elements of the selected set drawn one by one (the panel counts them all).
pub const MAX_SET_DRAWN: usize = 5_000;
/// Colours of the X, Y and Z axes (a transform's constraint), as Blender draws them.
pub const AXIS_COLORS: [Color; 3] = [
    Color::srgb(0.9, 0.25, 0.3),
    Color::srgb(0.45, 0.75, 0.2),
    Color::srgb(0.25, 0.5, 0.95),
];
/// Colour of the hover highlight.
pub const HOVERED: Color = Color::srgb(0.35, 0.8, 1.0);
/// Colour of halfedge arrows.
pub const ARROW: Color = Color::srgb(0.2, 0.25, 0.55);
/// Colour of seam marks.
pub const SEAM: Color = Color::srgb(0.95, 0.2, 0.75);
/// Colour of the anchors of handle deformation.
pub const ANCHOR: Color = Color::srgb(0.85, 0.15, 0.15);
/// Colour of proportional editing's radius.
pub const PROPORTIONAL: Color = Color::srgb(0.95, 0.95, 0.95);
/// Colour of vertex dots.
pub const DOT: Color = Color::srgb(0.05, 0.05, 0.05);

/// Thick lines drawn on top of everything (selection and hover).
#[derive(Default, Reflect, GizmoConfigGroup)]
pub struct HighlightGizmos;

/// One shape to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A thin line.
    Line(Vec3, Vec3, Color),
    /// A thick line over everything.
    Highlight(Vec3, Vec3, Color),
    /// A thick circle facing the camera: centre, radius.
    Ring(Vec3, f32, Color),
    /// A thick halfedge arrow over everything, its barb as [`Shape::Arrow`]'s.
    HighlightArrow(Vec3, Vec3, Vec3, Color),
    /// A thin halfedge arrow: from, to, and a point on its face's side, towards which its one
    /// barb leans.
    Arrow(Vec3, Vec3, Vec3, Color),
    /// A dot of the given world radius.
    Dot(Vec3, f32, Color),
    /// A large dot over everything.
    HighlightDot(Vec3, f32, Color),
}

/// The shapes of this frame.
#[derive(Resource, Default, Debug, Clone)]
pub struct Overlay {
    /// Everything to draw.
    pub shapes: Vec<Shape>,
    /// Face count of the active mesh, and the render rebuild it was counted at (counting is
    /// O(mesh), so it is redone only after a rebuild).
    face_count: Option<(MeshId, usize, usize)>,
}

/// The arrow of halfedge `h`: its segment pulled towards the centre of its face (away from the
/// other face on the boundary) and shortened, so the two halfedges of an edge sit side by side;
/// then the point it was pulled towards, on its face's side.
pub fn halfedge_arrow(m: &MeshRef<'_>, h: HalfedgeId) -> (Vec3, Vec3, Vec3) {
    let (a, b) = (m.position(m.from_vertex(h)), m.position(m.to_vertex(h)));
    let inside = match m.face(h) {
        Some(f) => m.face_centroid(f),
        None => {
            let other = m
                .face(m.twin(h))
                .map_or((a + b) / 2.0, |f| m.face_centroid(f));
            (a + b) - other
        }
    };
    let pull = |p: Vec3| p + (inside - p) * 0.12;
    let (pa, pb) = (pull(a), pull(b));
    (pa.lerp(pb, 0.12), pa.lerp(pb, 0.88), inside)
}

/// An arrow's barb, as long as this fraction of its shaft.
pub const TIP_FRACTION: f32 = 0.2;

/// The free end of an arrow's one barb: back from its head `b` at 45°, [`TIP_FRACTION`] of the
/// shaft long, leaning towards `inside` (its face's side). `None` where `inside` lies on the
/// shaft's line or the shaft has no length.
pub fn barb(a: Vec3, b: Vec3, inside: Vec3) -> Option<Vec3> {
    let along = (b - a).try_normalize()?;
    let towards = inside - b;
    let across = (towards - along * towards.dot(along)).try_normalize()?;
    let tip = a.distance(b) * TIP_FRACTION;
    Some(b + (across - along) * (tip * std::f32::consts::FRAC_1_SQRT_2))
}

fn mean_edge_near(m: &MeshRef<'_>, v: VertexId) -> f32 {
    let p = m.position(v);
    let (sum, n) = m
        .vertex_neighbors(v)
        .fold((0.0, 0), |(s, n), w| (s + m.position(w).distance(p), n + 1));
    if n == 0 { 0.01 } else { sum / n as f32 }
}

fn element_shapes(m: &MeshRef<'_>, x: ElementId, color: Color, out: &mut Vec<Shape>) {
    if !crate::editor::session::selection::exists(m, x) {
        return;
    }
    match x {
        ElementId::Vertex(v) => {
            let r = mean_edge_near(m, v) * 0.12;
            out.push(Shape::HighlightDot(m.position(v), r, color));
        }
        ElementId::Edge(e) => {
            let (a, b) = m.edge_vertices(e);
            out.push(Shape::Highlight(m.position(a), m.position(b), color));
        }
        ElementId::Halfedge(h) => {
            let (a, b, inside) = halfedge_arrow(m, h);
            out.push(Shape::HighlightArrow(a, b, inside, color));
        }
        ElementId::Face(f) => face_outline(m, f, color, out),
        ElementId::Mesh(_) => {}
    }
}

/// The faces around an element: a vertex's fan, an edge's or a halfedge's sides, a face and its
/// neighbours. Stale ids give none.
fn faces_around(m: &MeshRef<'_>, x: ElementId) -> Vec<FaceId> {
    if !crate::editor::session::selection::exists(m, x) {
        return Vec::new();
    }
    let sides = |h: HalfedgeId| [m.face(h), m.face(m.twin(h))].into_iter().flatten();
    match x {
        ElementId::Vertex(v) => m.vertex_faces(v).collect(),
        ElementId::Edge(e) => sides(m.edge_halfedge(e)).collect(),
        ElementId::Halfedge(h) => sides(h).collect(),
        ElementId::Face(f) => m.face_halfedges(f).flat_map(sides).collect(),
        ElementId::Mesh(_) => Vec::new(),
    }
}

fn face_outline(m: &MeshRef<'_>, f: FaceId, color: Color, out: &mut Vec<Shape>) {
    let c = m.face_centroid(f);
    for h in m.face_halfedges(f) {
        let (a, b) = (m.position(m.from_vertex(h)), m.position(m.to_vertex(h)));
        out.push(Shape::Highlight(a, b, color));
        // Hatch the face towards its centre so a selected face reads as filled.
        out.push(Shape::Highlight(a.lerp(c, 0.15), b.lerp(c, 0.15), color));
    }
}

/// Gathers this frame's overlay shapes (the `Sync` set).
pub fn gather_overlay(world: &mut World) {
    let mut shapes = Vec::new();
    let settings = world
        .get_resource::<ViewSettings>()
        .copied()
        .unwrap_or_default();
    if let Some(mesh) = world.resource::<ActiveMesh>().0
        && world.get::<MeshInfo>(mesh.0).is_some()
    {
        let generation = world
            .resource::<crate::editor::view::render_sync::RenderStats>()
            .rebuilds;
        let cached = world.resource::<Overlay>().face_count;
        let faces = match cached {
            Some((m, g, n)) if m == mesh && g == generation => n,
            _ => {
                let n = of_kind::<Face, _>(world, mesh, FaceId).len();
                world.resource_mut::<Overlay>().face_count = Some((mesh, generation, n));
                n
            }
        };
        let m = MeshRef::new(world);
        dots_and_arrows(
            world,
            &m,
            mesh,
            faces <= SMALL_MESH_FACES,
            settings,
            &mut shapes,
        );
        // Seam marks, over everything: the cut a parameterization will make.
        if crate::mesh::attributes::MeshAttributes::of(world, mesh).seams
            && let Some(mut seams) = world.try_query_filtered::<(Entity, &InMesh), With<Seam>>()
        {
            for (e, in_mesh) in seams.iter(world) {
                if in_mesh.0 == mesh {
                    let (a, b) = m.edge_vertices(EdgeId(e));
                    shapes.push(Shape::Highlight(m.position(a), m.position(b), SEAM));
                }
            }
        }
        // With the full wireframe hidden as too dense, the faces around the selection keep theirs.
        let dense = world
            .get_resource::<WireframeDensity>()
            .is_some_and(|d| d.hidden);
        if dense && let Some(x) = world.resource::<Selection>().element {
            for f in faces_around(&m, x) {
                for h in m.face_halfedges(f) {
                    let (a, b) = (m.position(m.from_vertex(h)), m.position(m.to_vertex(h)));
                    shapes.push(Shape::Line(a, b, EDGE_COLOR));
                }
            }
        }
        if let Some(x) = world.resource::<Hover>().element
            && Some(x) != world.resource::<Selection>().element
        {
            element_shapes(&m, x, HOVERED, &mut shapes);
        }
        let selection = world.resource::<Selection>();
        for &x in selection.elements().iter().take(MAX_SET_DRAWN) {
            match x {
                _ if Some(x) == selection.element => {}
                // A plain dot: thousands of selected vertices stay cheap to draw.
                ElementId::Vertex(v) if m.try_vertex(v).is_some() => {
                    let r = mean_edge_near(&m, v) * 0.08;
                    shapes.push(Shape::Dot(m.position(v), r, IN_SET));
                }
                _ => element_shapes(&m, x, IN_SET, &mut shapes),
            }
        }
        if let Some(x) = selection.element {
            element_shapes(&m, x, SELECTED, &mut shapes);
        }
        gesture_shapes(world, &m, &mut shapes);
    }
    world.resource_mut::<Overlay>().shapes = shapes;
}

/// Vertex dots and halfedge arrows: everywhere on a small mesh, else the arrows around the
/// selection (when arrows are on).
fn dots_and_arrows(
    world: &World,
    m: &MeshRef<'_>,
    mesh: MeshId,
    small: bool,
    settings: ViewSettings,
    shapes: &mut Vec<Shape>,
) {
    if small {
        let members = MeshMembers::collect(world, mesh);
        for &v in &members.vertices {
            shapes.push(Shape::Dot(m.position(v), mean_edge_near(m, v) * 0.04, DOT));
        }
        if settings.halfedges {
            for &h in &members.halfedges {
                let (a, b, inside) = halfedge_arrow(m, h);
                shapes.push(Shape::Arrow(a, b, inside, ARROW));
            }
        }
    } else if settings.halfedges {
        // Around the selection only.
        let near: Vec<HalfedgeId> = match world.resource::<Selection>().element {
            Some(ElementId::Face(f)) if m.try_face(f).is_some() => m.face_halfedges(f).collect(),
            Some(ElementId::Vertex(v)) if m.try_vertex(v).is_some() => {
                m.vertex_outgoing(v).flat_map(|h| [h, m.twin(h)]).collect()
            }
            Some(ElementId::Halfedge(h)) if m.try_halfedge(h).is_some() => {
                m.loop_from(h).chain(m.loop_from(m.twin(h))).collect()
            }
            Some(ElementId::Edge(e)) if m.try_edge(e).is_some() => {
                let h = m.edge_halfedge(e);
                m.loop_from(h).chain(m.loop_from(m.twin(h))).collect()
            }
            _ => Vec::new(),
        };
        for h in near {
            let (a, b, inside) = halfedge_arrow(m, h);
            shapes.push(Shape::Arrow(a, b, inside, ARROW));
        }
    }
}

/// What a gesture shows: the axis it is held to, the anchors of handle deformation, and
/// proportional editing's reach.
fn gesture_shapes(world: &World, m: &MeshRef<'_>, shapes: &mut Vec<Shape>) {
    // The axis a transform is held to, through its pivot, in Blender's colours.
    if let Some(gesture) = world
        .get_resource::<super::transform::Gestures>()
        .and_then(|g| g.active.as_ref())
        && let Some(axis) = gesture.axis
    {
        let reach = Vec3::AXES[axis] * 1e3;
        let p = gesture.pivot;
        shapes.push(Shape::Line(p - reach, p + reach, AXIS_COLORS[axis]));
    }
    // The anchors of handle deformation.
    if let Some(anchors) = world.get_resource::<super::handle_deform::Anchors>() {
        for &v in anchors.vertices.iter().take(MAX_SET_DRAWN) {
            if m.try_vertex(v).is_some() {
                let r = mean_edge_near(m, v) * 0.1;
                shapes.push(Shape::Dot(m.position(v), r, ANCHOR));
            }
        }
    }
    // Proportional editing's reach about the pivot.
    if let Some(follow) = world
        .get_resource::<super::transform::Gestures>()
        .and_then(|g| g.active.as_ref())
        .and_then(|g| Some((g.pivot, g.follow.as_ref()?)))
    {
        let (pivot, follow) = follow;
        shapes.push(Shape::Ring(pivot, follow.settings.radius, PROPORTIONAL));
    }
}

/// Draws the gathered highlights (the thin shapes are [`super::overlay_lines`]'s).
pub fn draw_overlay(
    overlay: Res<Overlay>,
    mut thick: Gizmos<HighlightGizmos>,
    cameras: Query<&GlobalTransform, With<Camera3d>>,
) {
    let facing = cameras
        .iter()
        .next()
        .map_or(Quat::IDENTITY, |t| t.compute_transform().rotation);
    for shape in &overlay.shapes {
        match *shape {
            Shape::Line(..) | Shape::Arrow(..) | Shape::Dot(..) => {}
            Shape::Highlight(a, b, c) => {
                thick.line(a, b, c);
            }
            Shape::HighlightArrow(a, b, inside, c) => {
                thick.line(a, b, c);
                if let Some(tip) = barb(a, b, inside) {
                    thick.line(b, tip, c);
                }
            }
            Shape::Ring(p, r, c) => {
                thick
                    .circle(Isometry3d::new(p, facing), r, c)
                    .resolution(64);
            }
            Shape::HighlightDot(p, r, c) => {
                thick
                    .circle(Isometry3d::new(p, facing), r, c)
                    .resolution(12);
                thick
                    .circle(Isometry3d::new(p, facing), r * 0.5, c)
                    .resolution(8);
            }
        }
    }
}

/// Makes highlight lines thick and drawn over the surface.
pub fn configure_gizmos(mut store: ResMut<GizmoConfigStore>) {
    let (config, _) = store.config_mut::<HighlightGizmos>();
    config.line.width = 4.0;
    config.depth_bias = -0.9;
}
