//! The surface material: a camera-borne light in a few lines of WGSL (`surface.wgsl`).
//!
//! A mesh editor needs shape, not photorealism. Bevy's `StandardMaterial` runs the full PBR
//! shader (clustered lights, image-based terms, tonemapping in the shader) for every pixel; under
//! Mesa's software Vulkan that was most of a frame. This material reads one uniform and shades
//! with a key light and a headlight that move with the camera (as MeshLab and Blender's
//! workbench do), so every side of the mesh is lit wherever the user orbits, and there are no
//! lights to cluster. Both sides are drawn; back faces get their own colour. A second material
//! leaves back faces undrawn, for a mesh none of whose back faces can be seen (see
//! [`super::culling`]).
//!
//! A mesh drawn with texture coordinates (its UVs, while the checkerboard is on) has its base
//! colour modulated by a 16 × 16 checkerboard in UV space, two soft tones, to show the layout's
//! distortion.
//!
//! While a quantity is shown the mesh's vertex colours replace the base colour, unshaded by any
//! tonemapping, so the colour map on screen is the one in the legend. A mesh drawn without
//! normals is shaded flat: the shader takes each face's normal from the screen-space derivatives
//! of the position (see `render_data::render_data`).

use bevy::asset::embedded_asset;
use bevy::color::LinearRgba;
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey, MaterialPlugin};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, Face, RenderPipelineDescriptor, SpecializedMeshPipelineError,
};
use bevy::shader::ShaderRef;

/// The colours of a surface: front and back.
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
#[bind_group_data(SurfaceKey)]
pub struct SurfaceMaterial {
    /// Colour of front faces (when the mesh has no vertex colours).
    #[uniform(0)]
    pub color: LinearRgba,
    /// Colour of back faces.
    #[uniform(0)]
    pub back_color: LinearRgba,
    /// Whether back faces are left undrawn: only where none can be seen (see
    /// [`super::culling`]).
    pub cull_back_faces: bool,
}

/// What makes one surface pipeline differ from another: whether it culls back faces.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub struct SurfaceKey {
    cull_back_faces: bool,
}

impl From<&SurfaceMaterial> for SurfaceKey {
    fn from(material: &SurfaceMaterial) -> Self {
        Self {
            cull_back_faces: material.cull_back_faces,
        }
    }
}

impl Material for SurfaceMaterial {
    fn fragment_shader() -> ShaderRef {
        "embedded://pappus/editor/view/surface.wgsl".into()
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        descriptor.primitive.cull_mode = key.bind_group_data.cull_back_faces.then_some(Face::Back);
        Ok(())
    }
}

/// Registers the material and embeds its shader in the binary (no asset folder needed).
pub struct SurfacePlugin;

impl Plugin for SurfacePlugin {
    fn build(&self, app: &mut App) {
        embedded_asset!(app, "surface.wgsl");
        app.add_plugins(MaterialPlugin::<SurfaceMaterial>::default());
    }
}
