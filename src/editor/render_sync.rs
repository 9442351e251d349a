//! Keeps each mesh's render copy in step with its entities, rebuilding only meshes that changed.
//!
//! A mesh marked [`MeshDirty`] gets, in the `Sync` set: a Bevy [`Mesh`] with every polygon
//! fan-triangulated (flat shading: one normal per face, Newell's; smooth: area-weighted vertex
//! normals), a [`TriangleFaces`] table mapping each GPU triangle back to its face for picking,
//! and a retained wireframe of the *real* edges (a quad shows 4 edges, not 5), boundary edges in
//! red. Meshes that did not change cost nothing per frame.

use bevy::asset::RenderAssetUsages;
use bevy::color::Color;
use bevy::ecs::entity::EntityHashMap;
use bevy::math::Vec3;
use bevy::mesh::{Indices, Mesh, Mesh3d, PrimitiveTopology};
use bevy::prelude::{Assets, Component, Entity, Resource, Transform, Visibility, With, World};
use std::time::Instant;

use crate::mesh::ids::{FaceId, MeshId};
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;
use crate::mesh::{Edge, MeshInfo};

use super::selection::MeshDirty;

/// The render entity of a mesh: carries its [`Mesh3d`] and [`TriangleFaces`].
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOf(pub MeshId);

/// The wireframe entity of a mesh (a retained gizmo of its edges).
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct WireframeOf(pub MeshId);

/// For each triangle of the render mesh, the face it was cut from.
#[derive(Component, Debug, Clone, Default)]
pub struct TriangleFaces(pub Vec<FaceId>);

/// How meshes are drawn.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    /// Smooth (vertex normals) rather than flat (face normals) shading.
    pub smooth: bool,
    /// Draw the wireframe of the real edges.
    pub wireframe: bool,
    /// Draw halfedge arrows (always near the selection; everywhere on small meshes).
    pub halfedges: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        Self {
            smooth: false,
            wireframe: true,
            halfedges: true,
        }
    }
}

/// Counters for tests and the frame-time figures.
#[derive(Resource, Debug, Clone, Default)]
pub struct RenderStats {
    /// Render meshes rebuilt so far.
    pub rebuilds: usize,
    /// Milliseconds the last rebuild took.
    pub last_rebuild_ms: f64,
    /// Triangles in the last rebuilt mesh.
    pub last_triangles: usize,
}

/// Meshes with more edges than this get no full wireframe (at that density it is a black
/// blob and costs seconds per frame under software rendering); the selection is still drawn.
pub const WIREFRAME_MAX_EDGES: usize = 400_000;

/// Colour of interior edges in the wireframe.
pub const EDGE_COLOR: Color = Color::srgb(0.08, 0.08, 0.1);
/// Colour of boundary edges in the wireframe.
pub const BOUNDARY_COLOR: Color = Color::srgb(0.9, 0.15, 0.1);

/// Triangles, normals and the triangle → face table for one mesh.
#[derive(Debug, Clone, Default)]
pub struct RenderData {
    /// Vertex positions of the render mesh.
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals of the render mesh.
    pub normals: Vec<[f32; 3]>,
    /// Triangle corners.
    pub indices: Vec<u32>,
    /// The face of each triangle.
    pub triangle_faces: Vec<FaceId>,
}

/// Builds the render data of `mesh`: each face fanned from its first corner.
pub fn render_data(world: &World, mesh: MeshId, smooth: bool) -> RenderData {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let mut out = RenderData::default();
    let mut corners = Vec::new();
    if smooth {
        let mut index: EntityHashMap<u32> = EntityHashMap::default();
        index.reserve(members.vertices.len());
        for (i, &v) in members.vertices.iter().enumerate() {
            index.insert(v.0, i as u32);
            out.positions.push(m.position(v).to_array());
        }
        let mut normals = vec![Vec3::ZERO; members.vertices.len()];
        for &f in &members.faces {
            corners.clear();
            corners.extend(m.face_vertices(f).map(|v| index[&v.0]));
            let points: Vec<Vec3> = corners
                .iter()
                .map(|&i| Vec3::from_array(out.positions[i as usize]))
                .collect();
            let area = crate::mesh::topology::newell_area_vector(&points);
            for &i in &corners {
                normals[i as usize] += area;
            }
            fan(&mut out, &corners, f);
        }
        out.normals = normals
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Z).to_array())
            .collect();
    } else {
        for &f in &members.faces {
            let base = out.positions.len() as u32;
            let start = out.positions.len();
            out.positions
                .extend(m.face_vertices(f).map(|v| m.position(v).to_array()));
            let points: Vec<Vec3> = out.positions[start..]
                .iter()
                .map(|&p| Vec3::from_array(p))
                .collect();
            let n = crate::mesh::topology::newell_area_vector(&points)
                .try_normalize()
                .unwrap_or(Vec3::Z)
                .to_array();
            out.normals.extend(std::iter::repeat_n(n, points.len()));
            corners.clear();
            corners.extend(base..out.positions.len() as u32);
            fan(&mut out, &corners, f);
        }
    }
    out
}

fn fan(out: &mut RenderData, corners: &[u32], f: FaceId) {
    for i in 1..corners.len().saturating_sub(1) {
        out.indices
            .extend_from_slice(&[corners[0], corners[i], corners[i + 1]]);
        out.triangle_faces.push(f);
    }
}

/// The edges of a mesh as line segments with colours (boundary edges red).
pub fn edge_lines(world: &World, mesh: MeshId) -> Vec<(Vec3, Vec3, Color)> {
    let m = MeshRef::new(world);
    let Some(mut edges) = world.try_query::<(&Edge, &crate::mesh::InMesh)>() else {
        return Vec::new();
    };
    edges
        .iter(world)
        .filter(|(_, of)| of.0 == mesh)
        .map(|(e, _)| {
            let h = e.halfedge;
            let (a, b) = (m.position(m.from_vertex(h)), m.position(m.to_vertex(h)));
            let boundary = m.is_boundary(h) || m.is_boundary(m.twin(h));
            (a, b, if boundary { BOUNDARY_COLOR } else { EDGE_COLOR })
        })
        .collect()
}

/// Rebuilds the render copy of every dirty mesh and removes render copies of meshes that are
/// gone (the `Sync` set).
pub fn sync_render_meshes(world: &mut World) {
    remove_orphans(world);
    let dirty: Vec<Entity> = world
        .query_filtered::<Entity, (With<MeshInfo>, With<MeshDirty>)>()
        .iter(world)
        .collect();
    let settings = world
        .get_resource::<ViewSettings>()
        .copied()
        .unwrap_or_default();
    for entity in dirty {
        let mesh = MeshId(entity);
        let start = Instant::now();
        let data = render_data(world, mesh, settings.smooth);
        let triangles = data.triangle_faces.len();
        // Σ face degrees = triangles + 2 × faces (a k-gon is fanned into k − 2 triangles), and
        // each edge is at most two of those sides: half of it bounds the edge count from below
        // without walking the edges.
        let faces = data
            .triangle_faces
            .iter()
            .enumerate()
            .filter(|&(i, f)| i == 0 || data.triangle_faces[i - 1] != *f)
            .count();
        let corners = data.triangle_faces.len() + 2 * faces;
        upload(world, mesh, data);
        if settings.wireframe {
            upload_wireframe(world, mesh, corners / 2 <= WIREFRAME_MAX_EDGES);
        }
        world.entity_mut(entity).remove::<MeshDirty>();
        let mut stats = world.resource_mut::<RenderStats>();
        stats.rebuilds += 1;
        stats.last_triangles = triangles;
        stats.last_rebuild_ms = start.elapsed().as_secs_f64() * 1000.0;
        bevy::log::info!(
            "render sync {mesh}: {triangles} triangles in {:.1} ms",
            stats.last_rebuild_ms
        );
    }
}

fn upload(world: &mut World, mesh: MeshId, data: RenderData) {
    let mut render = Mesh::new(
        PrimitiveTopology::TriangleList,
        // Picking casts rays against the main-world copy: keep it.
        RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
    );
    render.insert_attribute(Mesh::ATTRIBUTE_POSITION, data.positions);
    render.insert_attribute(Mesh::ATTRIBUTE_NORMAL, data.normals);
    render.insert_indices(Indices::U32(data.indices));
    let existing = world
        .query::<(Entity, &RenderOf)>()
        .iter(world)
        .find(|(_, r)| r.0 == mesh)
        .map(|(e, _)| e);
    let handle = world.resource_mut::<Assets<Mesh>>().add(render);
    let faces = TriangleFaces(data.triangle_faces);
    match existing {
        Some(e) => {
            world.entity_mut(e).insert((Mesh3d(handle), faces));
        }
        None => {
            let material = world
                .get_resource::<super::scene::SceneMaterials>()
                .map(|m| m.surface.clone());
            let mut e = world.spawn((
                RenderOf(mesh),
                Mesh3d(handle),
                faces,
                Transform::default(),
                Visibility::default(),
            ));
            if let Some(material) = material {
                e.insert(bevy::pbr::MeshMaterial3d(material));
            }
        }
    }
}

fn upload_wireframe(world: &mut World, mesh: MeshId, small_enough: bool) {
    if !world.contains_resource::<Assets<bevy::gizmos::GizmoAsset>>() {
        return;
    }
    let mut lines = if small_enough {
        edge_lines(world, mesh)
    } else {
        Vec::new()
    };
    if lines.len() > WIREFRAME_MAX_EDGES {
        lines.clear();
    }
    let mut asset = bevy::gizmos::GizmoAsset::default();
    for (a, b, color) in lines {
        asset.line(a, b, color);
    }
    let handle = world
        .resource_mut::<Assets<bevy::gizmos::GizmoAsset>>()
        .add(asset);
    let existing = world
        .query::<(Entity, &WireframeOf)>()
        .iter(world)
        .find(|(_, w)| w.0 == mesh)
        .map(|(e, _)| e);
    let gizmo = bevy::gizmos::retained::Gizmo {
        handle,
        line_config: bevy::gizmos::config::GizmoLineConfig {
            width: 1.0,
            ..Default::default()
        },
        depth_bias: -0.0005,
    };
    match existing {
        Some(e) => {
            world.entity_mut(e).insert(gizmo);
        }
        None => {
            world.spawn((WireframeOf(mesh), gizmo));
        }
    }
}

/// Hides or shows every wireframe (the wireframe toggle), rebuilding them when shown.
pub fn set_wireframes_visible(world: &mut World, visible: bool) {
    let wires: Vec<Entity> = world
        .query_filtered::<Entity, With<WireframeOf>>()
        .iter(world)
        .collect();
    for e in wires {
        world.entity_mut(e).insert(if visible {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        });
    }
}

fn remove_orphans(world: &mut World) {
    let orphans: Vec<Entity> = world
        .query::<(Entity, Option<&RenderOf>, Option<&WireframeOf>)>()
        .iter(world)
        .filter_map(|(e, r, w)| {
            let mesh = r.map(|r| r.0).or(w.map(|w| w.0))?;
            world.get::<MeshInfo>(mesh.0).is_none().then_some(e)
        })
        .collect();
    for e in orphans {
        world.despawn(e);
    }
}
