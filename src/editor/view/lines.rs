//! Lines a constant number of pixels wide, drawn as triangles in one mesh (`lines.wgsl`): the
//! mesh's wireframe and the overlay's thin lines and dots.
//!
//! Every segment is a quad of one vertex buffer, widened to its width on screen by the vertex
//! shader (the construction of Bevy's line gizmos, after Rye Terrell's "Instanced Line
//! Rendering", 2019), drawn in the opaque pass and pulled towards the eye by a small fraction of
//! its distance, so that it wins over the faces it lies on. Bevy's gizmos build the same quads
//! as instances, every frame unless retained; the wireframe was a retained gizmo, and is drawn
//! here so that the editor has one way of drawing lines. Under a software rasterizer (Mesa's lavapipe) the lines cost what their triangles
//! do, however they are batched: the torus's wireframe as a retained gizmo or as this mesh
//! measured the same frame (median of 6 alternating runs, 22.5 and 22.2 ms), and native 1-pixel
//! line primitives saved a few tenths of a millisecond of its 0.7, not worth a second way of
//! drawing.
//!
//! A dot is a filled hexagon whose corners are given as offsets in the camera's plane about its
//! centre, which the shader turns with the camera, so the mesh does not change while the camera
//! moves.

use bevy::asset::{RenderAssetUsages, embedded_asset};
use bevy::color::LinearRgba;
use bevy::math::{Vec2, Vec3};
use bevy::mesh::{Indices, MeshVertexAttribute, MeshVertexBufferLayoutRef, PrimitiveTopology};
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey, MaterialPlugin};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, RenderPipelineDescriptor, SpecializedMeshPipelineError, VertexFormat,
};
use bevy::shader::ShaderRef;

/// How far the lines are pulled towards the eye, as a fraction of their distance from it:
/// enough that a line wins over the faces it lies on, too little to show through the surface.
pub const DEPTH_PULL: f32 = 0.003;
/// Corners of a dot's hexagon.
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

/// One straight line, fixed in the world.
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

/// Lines and dots to draw as one mesh ([`line_mesh`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ThinLines {
    /// The straight lines.
    pub segments: Vec<Segment>,
    /// The dots.
    pub dots: Vec<Dot>,
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

/// The lines' width on screen and their pull towards the eye (see [`DEPTH_PULL`]).
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
pub struct LinesMaterial {
    /// Width on screen, in pixels.
    #[uniform(0)]
    pub width: f32,
    /// Pulled towards the eye by this fraction of the distance.
    #[uniform(0)]
    pub depth_pull: f32,
}

impl Material for LinesMaterial {
    fn vertex_shader() -> ShaderRef {
        "embedded://pappus/editor/view/lines.wgsl".into()
    }

    fn fragment_shader() -> ShaderRef {
        "embedded://pappus/editor/view/lines.wgsl".into()
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

/// Registers the lines' material and embeds its shader in the binary.
pub struct LinesPlugin;

impl Plugin for LinesPlugin {
    fn build(&self, app: &mut App) {
        embedded_asset!(app, "lines.wgsl");
        app.add_plugins(MaterialPlugin::<LinesMaterial>::default());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::mesh::VertexAttributeValues;

    #[test]
    fn a_dot_is_a_hexagon_of_four_triangles_about_its_centre_in_the_cameras_plane() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let mesh = line_mesh(&ThinLines {
            segments: Vec::new(),
            dots: vec![Dot {
                centre: p,
                radius: 0.5,
                color: LinearRgba::BLACK,
            }],
        });
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
    fn every_segment_is_two_triangles_with_both_sides_at_both_ends() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        let mesh = line_mesh(&ThinLines {
            segments: vec![Segment {
                ends: [a, b],
                color: LinearRgba::WHITE,
            }],
            dots: Vec::new(),
        });
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
