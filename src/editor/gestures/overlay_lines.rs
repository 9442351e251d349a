//! The overlay's thin lines — halfedge arrows, vertex dots, axis lines — drawn as one mesh in
//! one draw (`overlay_lines.wgsl`), rebuilt only when the lines change.
//!
//! Bevy's gizmos draw every segment as an instance of a six-vertex quad, rebuilt every frame.
//! Under a software rasterizer (Mesa's lavapipe, the editor's renderer where there is no GPU)
//! the overlay's cost goes with the triangles set up, not the pixels they cover: the default
//! torus's 1 152 arrows (five segments each, a shaft and four tips) and 288 dots (six each)
//! took 4.2–5.8 ms of a 29–35 ms frame, where the torus's whole surface takes 2 ms. The same
//! segments in one mesh cost about as much, so what saves the time is fewer triangles: an arrow
//! is two segments here (its shaft and one barb) and a dot a filled hexagon of four triangles.
//! Every segment is a quad of one vertex buffer, widened to [`LINE_WIDTH_PX`] on screen by the
//! vertex shader (the construction of Bevy's line gizmos, after Rye Terrell's "Instanced Line
//! Rendering", 2019), drawn in the opaque pass.
//!
//! A dot is a filled hexagon whose corners are given as offsets in the camera's plane about its
//! centre, which the shader turns with the camera, so the mesh does not change while the camera
//! moves. [`update_overlay_lines`] compares this frame's thin shapes with the
//! ones drawn and rebuilds the buffer only when they differ: after an edit, a change of the
//! settings or of the selection's neighbourhood. The thick highlights (the selection, the hover)
//! are few and stay gizmos.

use bevy::asset::{RenderAssetUsages, embedded_asset};
use bevy::camera::visibility::NoFrustumCulling;
use bevy::color::LinearRgba;
use bevy::math::{Vec2, Vec3};
use bevy::mesh::{Indices, MeshVertexAttribute, MeshVertexBufferLayoutRef, PrimitiveTopology};
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey, MaterialPlugin};
use bevy::picking::Pickable;
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, RenderPipelineDescriptor, SpecializedMeshPipelineError, VertexFormat,
};
use bevy::shader::ShaderRef;

use super::overlay::{Overlay, Shape, barb};

/// Width of the thin lines on screen, in pixels.
pub const LINE_WIDTH_PX: f32 = 1.5;
/// How far the lines are pulled towards the eye, as a fraction of their distance from it:
/// enough that a line wins over the faces it lies on, too little to show through the surface.
pub const DEPTH_PULL: f32 = 0.003;
/// Corners of a vertex dot's hexagon.
pub const DOT_CORNERS: usize = 6;

/// The segment's other end (each vertex carries its own end as its position).
pub const ATTRIBUTE_OTHER_END: MeshVertexAttribute = MeshVertexAttribute::new(
    "Overlay_OtherEnd",
    0x7061_7070_7573_0001,
    VertexFormat::Float32x3,
);
/// Offsets in the camera's plane (right, up) of the vertex's own end (`xy`) and of the other
/// end (`zw`), in world units.
pub const ATTRIBUTE_FACING: MeshVertexAttribute = MeshVertexAttribute::new(
    "Overlay_Facing",
    0x7061_7070_7573_0002,
    VertexFormat::Float32x4,
);
/// Which side of the segment the vertex lies on, in line widths from its middle (±0.5), as
/// seen from its own end towards the other; 0 for a dot's corner.
pub const ATTRIBUTE_SIDE: MeshVertexAttribute =
    MeshVertexAttribute::new("Overlay_Side", 0x7061_7070_7573_0003, VertexFormat::Float32);

/// One straight line of the overlay, fixed in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Its ends.
    pub ends: [Vec3; 2],
    /// Its colour.
    pub color: LinearRgba,
}

/// A filled disc facing the camera (a vertex's dot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dot {
    /// Its centre.
    pub centre: Vec3,
    /// Its radius, in world units.
    pub radius: f32,
    /// Its colour.
    pub color: LinearRgba,
}

/// What the thin shapes of a frame are drawn as.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ThinLines {
    /// The straight lines.
    pub segments: Vec<Segment>,
    /// The dots.
    pub dots: Vec<Dot>,
}

/// Whether a shape is one of the thin shapes this module draws (the rest are gizmos).
pub fn is_thin(shape: &Shape) -> bool {
    matches!(shape, Shape::Line(..) | Shape::Arrow(..) | Shape::Dot(..))
}

/// The thin shapes among `shapes`: a line is one segment, an arrow two (its shaft and one
/// barb, on its face's side), a dot a dot.
pub fn thin_lines(shapes: &[Shape]) -> ThinLines {
    let mut out = ThinLines::default();
    for shape in shapes {
        match *shape {
            Shape::Line(a, b, c) => out.segments.push(fixed(a, b, c)),
            Shape::Arrow(a, b, inside, c) => arrow(a, b, inside, c.into(), &mut out.segments),
            Shape::Dot(centre, radius, c) => out.dots.push(Dot {
                centre,
                radius,
                color: c.into(),
            }),
            _ => {}
        }
    }
    out
}

fn fixed(a: Vec3, b: Vec3, color: impl Into<LinearRgba>) -> Segment {
    Segment {
        ends: [a, b],
        color: color.into(),
    }
}

/// The shaft from `a` to `b` and its [`barb`].
fn arrow(a: Vec3, b: Vec3, inside: Vec3, color: LinearRgba, out: &mut Vec<Segment>) {
    out.push(fixed(a, b, color));
    if let Some(tip) = barb(a, b, inside) {
        out.push(fixed(b, tip, color));
    }
}

/// The corners of a dot's hexagon about its centre, in the camera's plane (right, up), for a
/// radius of 1.
fn hexagon() -> [Vec2; DOT_CORNERS] {
    std::array::from_fn(|i| {
        let angle = i as f32 * std::f32::consts::TAU / DOT_CORNERS as f32;
        Vec2::new(angle.cos(), angle.sin())
    })
}

/// The vertex columns of the lines' mesh.
#[derive(Default)]
struct Columns {
    own: Vec<[f32; 3]>,
    other: Vec<[f32; 3]>,
    facing: Vec<[f32; 4]>,
    side: Vec<f32>,
    color: Vec<[f32; 4]>,
    triangles: Vec<u32>,
}

impl Columns {
    fn push(&mut self, own: Vec3, other: Vec3, facing: [Vec2; 2], side: f32, color: LinearRgba) {
        self.own.push(own.to_array());
        self.other.push(other.to_array());
        self.facing
            .push([facing[0].x, facing[0].y, facing[1].x, facing[1].y]);
        self.side.push(side);
        self.color.push(color.to_f32_array());
    }
}

/// The mesh of `lines`. A segment is a quad, four vertices and two triangles, each vertex with
/// its own end, the other end and its side, which the shader widens on screen. A dot is a
/// hexagon of [`DOT_CORNERS`] vertices and four triangles, each vertex at the centre with its
/// corner as an offset in the camera's plane and no side.
pub fn line_mesh(lines: &ThinLines) -> Mesh {
    let mut c = Columns::default();
    for s in &lines.segments {
        let first = c.own.len() as u32;
        // The quad's corners: (which end, side seen from that end). The left of a→b is +½
        // from a and −½ from b: corners 0 and 2 are on the left, 1 and 3 on the right.
        for (end, across) in [(0, 0.5), (0, -0.5), (1, -0.5), (1, 0.5)] {
            let (own, other) = (s.ends[end], s.ends[1 - end]);
            c.push(own, other, [Vec2::ZERO; 2], across, s.color);
        }
        c.triangles.extend([0, 1, 2, 1, 3, 2].map(|i| first + i));
    }
    let corners = hexagon();
    for d in &lines.dots {
        let first = c.own.len() as u32;
        for corner in corners {
            let at = corner * d.radius;
            c.push(d.centre, d.centre, [at, at], 0.0, d.color);
        }
        c.triangles
            .extend([0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5].map(|i| first + i));
    }
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, c.own)
    .with_inserted_attribute(ATTRIBUTE_OTHER_END, c.other)
    .with_inserted_attribute(ATTRIBUTE_FACING, c.facing)
    .with_inserted_attribute(ATTRIBUTE_SIDE, c.side)
    .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, c.color)
    .with_inserted_indices(Indices::U32(c.triangles))
}

/// The lines' width and depth pull (see [`LINE_WIDTH_PX`], [`DEPTH_PULL`]).
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
pub struct OverlayLinesMaterial {
    /// Width on screen, in pixels.
    #[uniform(0)]
    pub width: f32,
    /// Pulled towards the eye by this fraction of the distance.
    #[uniform(0)]
    pub depth_pull: f32,
}

impl Material for OverlayLinesMaterial {
    fn vertex_shader() -> ShaderRef {
        "embedded://pappus/editor/gestures/overlay_lines.wgsl".into()
    }

    fn fragment_shader() -> ShaderRef {
        "embedded://pappus/editor/gestures/overlay_lines.wgsl".into()
    }

    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        layout: &MeshVertexBufferLayoutRef,
        _key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        descriptor.vertex.buffers = vec![layout.0.get_layout(&[
            Mesh::ATTRIBUTE_POSITION.at_shader_location(0),
            ATTRIBUTE_OTHER_END.at_shader_location(1),
            ATTRIBUTE_FACING.at_shader_location(2),
            ATTRIBUTE_SIDE.at_shader_location(3),
            Mesh::ATTRIBUTE_COLOR.at_shader_location(4),
        ])?];
        // A quad's winding depends on which way its segment runs on screen.
        descriptor.primitive.cull_mode = None;
        Ok(())
    }
}

/// The entity that draws the thin lines.
#[derive(Component)]
pub struct OverlayLines;

/// Registers the material, embeds its shader and spawns the lines' entity (hidden until there
/// are lines).
pub struct OverlayLinesPlugin;

impl Plugin for OverlayLinesPlugin {
    fn build(&self, app: &mut App) {
        embedded_asset!(app, "overlay_lines.wgsl");
        app.add_plugins(MaterialPlugin::<OverlayLinesMaterial>::default())
            .add_systems(Startup, spawn_overlay_lines);
    }
}

fn spawn_overlay_lines(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<OverlayLinesMaterial>>,
) {
    commands.spawn((
        OverlayLines,
        Mesh3d(meshes.add(line_mesh(&ThinLines::default()))),
        MeshMaterial3d(materials.add(OverlayLinesMaterial {
            width: LINE_WIDTH_PX,
            depth_pull: DEPTH_PULL,
        })),
        Transform::IDENTITY,
        Visibility::Hidden,
        // The vertices' positions are segment ends; the shader widens them on screen.
        NoFrustumCulling,
        Pickable::IGNORE,
    ));
}

/// Puts this frame's thin shapes in the lines' mesh when they differ from the ones drawn.
pub fn update_overlay_lines(
    overlay: Res<Overlay>,
    mut lines: Query<(&Mesh3d, &mut Visibility), With<OverlayLines>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut drawn: Local<Vec<Shape>>,
) {
    let Ok((mesh, mut visibility)) = lines.single_mut() else {
        return;
    };
    let thin = overlay.shapes.iter().filter(|s| is_thin(s));
    if thin.clone().eq(drawn.iter()) {
        return;
    }
    *drawn = thin.copied().collect();
    *visibility = if drawn.is_empty() {
        Visibility::Hidden
    } else {
        Visibility::Inherited
    };
    // A mesh with no vertex is never drawn: the hidden entity keeps the last one.
    if !drawn.is_empty()
        && let Err(e) = meshes.insert(&mesh.0, line_mesh(&thin_lines(&drawn)))
    {
        bevy::log::warn!("overlay lines not redrawn: {e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::color::Color;
    use bevy::mesh::VertexAttributeValues;

    #[test]
    fn an_arrow_is_its_shaft_and_one_barb_a_fifth_its_length_at_45_degrees_on_its_faces_side() {
        let (a, b) = (Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0));
        let inside = Vec3::new(-3.0, 0.0, 1.0);
        let s = thin_lines(&[Shape::Arrow(a, b, inside, Color::WHITE)]).segments;
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].ends, [a, b]);
        let barb = s[1].ends[1] - b;
        assert_eq!(s[1].ends[0], b);
        assert!((barb.length() - 0.4).abs() < 1e-6);
        let half = 0.4 * std::f32::consts::FRAC_1_SQRT_2;
        assert!(barb.distance(Vec3::new(-half, 0.0, -half)) < 1e-6, "{barb}");
    }

    #[test]
    fn an_arrow_with_its_face_side_on_its_line_is_its_shaft_alone() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        let s = thin_lines(&[Shape::Arrow(a, b, Vec3::X * 3.0, Color::WHITE)]).segments;
        assert_eq!(s.len(), 1);
    }

    #[test]
    fn a_dot_is_a_hexagon_of_four_triangles_about_its_centre_in_the_cameras_plane() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let lines = thin_lines(&[Shape::Dot(p, 0.5, Color::BLACK)]);
        assert!(lines.segments.is_empty());
        let mesh = line_mesh(&lines);
        assert_eq!(mesh.count_vertices(), DOT_CORNERS);
        let Some(VertexAttributeValues::Float32x4(facing)) = mesh.attribute(ATTRIBUTE_FACING)
        else {
            panic!("offsets are four floats");
        };
        let corners: Vec<Vec2> = facing.iter().map(|f| Vec2::new(f[0], f[1])).collect();
        for c in &corners {
            assert!((c.length() - 0.5).abs() < 1e-6);
        }
        // Four triangles that tile the hexagon: their areas sum to its area.
        let triangles: Vec<usize> = mesh.indices().expect("indexed").iter().collect();
        assert_eq!(triangles.len(), 12);
        let area: f32 = triangles
            .chunks(3)
            .map(|t| {
                let (a, b, c) = (corners[t[0]], corners[t[1]], corners[t[2]]);
                (b - a).perp_dot(c - a).abs() / 2.0
            })
            .sum();
        let hexagon = 1.5 * 3f32.sqrt() * 0.25;
        assert!((area - hexagon).abs() < 1e-6, "{area} against {hexagon}");
    }

    #[test]
    fn highlights_are_left_to_the_gizmos() {
        let shapes = [
            Shape::Highlight(Vec3::ZERO, Vec3::X, Color::WHITE),
            Shape::HighlightDot(Vec3::ZERO, 1.0, Color::WHITE),
            Shape::Line(Vec3::ZERO, Vec3::Y, Color::WHITE),
        ];
        assert_eq!(shapes.iter().filter(|s| is_thin(s)).count(), 1);
        assert_eq!(thin_lines(&shapes).segments.len(), 1);
    }

    #[test]
    fn every_segment_is_two_triangles_with_both_sides_at_both_ends() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        let mesh = line_mesh(&thin_lines(&[Shape::Line(a, b, Color::WHITE)]));
        assert_eq!(mesh.count_vertices(), 4);
        let Some(VertexAttributeValues::Float32x3(own)) = mesh.attribute(Mesh::ATTRIBUTE_POSITION)
        else {
            panic!("positions are three floats");
        };
        let Some(VertexAttributeValues::Float32(side)) = mesh.attribute(ATTRIBUTE_SIDE) else {
            panic!("sides are one float");
        };
        // Each corner as (at b, on the left of a→b): the side is seen from the vertex's own
        // end, so it flips at b.
        let corner: Vec<(bool, bool)> = own
            .iter()
            .zip(side)
            .map(|(p, s)| {
                let at_b = *p == b.to_array();
                (at_b, (*s > 0.0) != at_b)
            })
            .collect();
        let mut sorted = corner.clone();
        sorted.sort();
        assert_eq!(
            sorted,
            [(false, false), (false, true), (true, false), (true, true)]
        );
        // Two triangles that share the quad's diagonal and together hold every corner.
        let triangles: Vec<usize> = mesh.indices().expect("indexed").iter().collect();
        assert_eq!(triangles.len(), 6);
        let (t0, t1) = (&triangles[..3], &triangles[3..]);
        assert_eq!(t0.iter().filter(|i| t1.contains(i)).count(), 2);
        let shared: Vec<(bool, bool)> = t0
            .iter()
            .filter(|i| t1.contains(i))
            .map(|&i| corner[i])
            .collect();
        // The diagonal joins opposite corners: another end and another side.
        assert!(shared[0].0 != shared[1].0 && shared[0].1 != shared[1].1);
    }
}
