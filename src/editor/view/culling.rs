//! Back faces left undrawn where none can be seen, on a software rasterizer.
//!
//! The surface is drawn two-sided so that a back face seen through a hole, or on a part turned
//! inside out, shows in its own colour. On Mesa's software Vulkan (lavapipe: the editor's
//! renderer where there is no GPU) the surface's cost is the triangles it sets up, half of them
//! facing away: culling them took the bunny's opaque pass from 24–26 to 14–15 ms. So where no
//! back face can be seen, the chunks of a mesh take the material that culls them
//! ([`SceneMaterials::surface_culled`]): when the mesh's [`Closure`] says every component
//! faces outward, the eye is outside the mesh's box, and the eye lies on the inner side of every
//! hole's slab (see [`crate::mesh::closure`]). The closure is counted with the panel's figures, off the frame
//! for a large mesh, and holds for the render generation it was counted at: after any edit the
//! mesh is drawn two-sided again until it is counted anew. An opened mesh brings its closure
//! with it ([`ClosureAtOpen`], counted from the tables it is spawned from), so it is culled from
//! the frame that first draws it: the panel's count of the 1.3 M-face icosphere comes 12 s
//! later on lavapipe (its tables read back a slice a frame).
//!
//! Only on a CPU adapter. On a GPU back faces cost little, and drawing them keeps the one case
//! the closure cannot see in the back colour: a surface that passes through itself, where a
//! back face can be nearest the eye (a fold dragged by hand).

use bevy::pbr::MeshMaterial3d;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::renderer::RenderAdapterInfo;

use crate::mesh::MeshId;
use crate::mesh::closure::Closure;

use super::render_sync::{RenderChunks, RenderStats};
use super::scene::{OrbitCamera, SceneMaterials};
use super::surface::SurfaceMaterial;
use crate::editor::session::selection::MeshDirty;
use crate::editor::session::state::Modified;

/// Each mesh's closure, with the render generation ([`RenderStats::rebuilds`]) it was counted at.
#[derive(Resource, Default, Debug)]
pub struct Closures(pub HashMap<MeshId, (usize, Closure)>);

impl Closures {
    /// Records `mesh`'s closure as counted at render `generation`.
    pub fn record(&mut self, mesh: MeshId, generation: usize, closure: Closure) {
        self.0.insert(mesh, (generation, closure));
    }
}

/// The closure of a mesh as it was opened, counted from the tables it was spawned from (a
/// component of the mesh entity until the frame that first draws it). [`choose_culling`] takes it
/// once the render copy is drawn and records it at that render's generation, unless the mesh
/// was edited before ([`Modified`]): then it is dropped and the panel's count stands.
#[derive(Component, Debug)]
pub struct ClosureAtOpen(pub Closure);

/// Whether the frames are drawn by a software rasterizer (a CPU adapter): the only renderer
/// that culls back faces (see the module doc). Absent, none is.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SoftwareRenderer(pub bool);

/// Reads the adapter's kind into [`SoftwareRenderer`] (at startup).
pub fn detect_software_renderer(mut commands: Commands, adapter: Option<Res<RenderAdapterInfo>>) {
    let software = adapter.is_some_and(|info| info.device_type == wgpu_types::DeviceType::Cpu);
    commands.insert_resource(SoftwareRenderer(software));
}

/// Gives each mesh's chunks the culling material where none of its back faces can be seen from
/// the camera, the two-sided one elsewhere (see the module doc). Writes only what changes.
pub fn choose_culling(world: &mut World) {
    let software = world
        .get_resource::<SoftwareRenderer>()
        .is_some_and(|s| s.0);
    let Some(materials) = world.get_resource::<SceneMaterials>().cloned() else {
        return;
    };
    // The orbit camera has no parent: its transform is where it is this frame.
    let eye = world
        .query_filtered::<&Transform, With<OrbitCamera>>()
        .iter(world)
        .next()
        .map(|t| t.translation);
    let generation = world.resource::<RenderStats>().rebuilds;
    adopt_closures_at_open(world, generation);
    let mut meshes = world.query::<(Entity, &RenderChunks)>();
    let mut chosen: Vec<(Entity, Handle<SurfaceMaterial>)> = Vec::new();
    let closures = world.resource::<Closures>();
    for (mesh, chunks) in meshes.iter(world) {
        let hidden = software
            && eye.is_some_and(|eye| {
                closures
                    .0
                    .get(&MeshId(mesh))
                    .is_some_and(|(counted, closure)| {
                        *counted == generation && closure.back_faces_hidden_from(eye)
                    })
            });
        let material = if hidden {
            &materials.surface_culled
        } else {
            &materials.surface
        };
        let before = chosen.len();
        for &chunk in &chunks.chunks {
            let drawn = world.get::<MeshMaterial3d<SurfaceMaterial>>(chunk);
            if drawn.is_some_and(|m| m.0 != *material) {
                chosen.push((chunk, material.clone()));
            }
        }
        if chosen.len() > before {
            let now = if hidden { "culled" } else { "drawn" };
            bevy::log::debug!("mesh {mesh}: back faces {now}");
        }
    }
    for (chunk, material) in chosen {
        world.entity_mut(chunk).insert(MeshMaterial3d(material));
    }
    // Forget the closures of meshes deleted since.
    let gone: Vec<MeshId> = world
        .resource::<Closures>()
        .0
        .keys()
        .filter(|m| world.get::<RenderChunks>(m.0).is_none())
        .copied()
        .collect();
    let mut closures = world.resource_mut::<Closures>();
    for mesh in gone {
        closures.0.remove(&mesh);
    }
}

/// Records the closure each opened mesh brought ([`ClosureAtOpen`]) at render `generation`,
/// once its render copy is drawn (it is no longer [`MeshDirty`]); a mesh edited since its open
/// drops its closure instead.
fn adopt_closures_at_open(world: &mut World, generation: usize) {
    let drawn: Vec<(Entity, bool)> = world
        .query_filtered::<(Entity, Has<Modified>), (With<ClosureAtOpen>, With<RenderChunks>, Without<MeshDirty>)>()
        .iter(world)
        .collect();
    for (mesh, edited) in drawn {
        let Some(ClosureAtOpen(closure)) = world.entity_mut(mesh).take::<ClosureAtOpen>() else {
            continue;
        };
        if !edited {
            world
                .resource_mut::<Closures>()
                .record(MeshId(mesh), generation, closure);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh};

    /// A world with the cube `[-1, 1]³` drawn by one chunk (two-sided), its closure counted at
    /// render generation 3, and the camera at `eye`.
    fn cube_seen_from(eye: Vec3, software: bool) -> (World, Entity, SceneMaterials) {
        let (mut world, mesh, chunk, materials) = cube_unclosed(eye, software);
        let closure = Closure::of(&extract(&world, mesh).tables);
        world.resource_mut::<Closures>().record(mesh, 3, closure);
        (world, chunk, materials)
    }

    /// The world of [`cube_seen_from`] with no closure recorded: the cube, its chunk, the
    /// materials.
    fn cube_unclosed(eye: Vec3, software: bool) -> (World, MeshId, Entity, SceneMaterials) {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &shapes::cube(), MeshInfo::default())
            .expect("a cube")
            .mesh;
        let mut assets = Assets::<SurfaceMaterial>::default();
        let surface = SurfaceMaterial {
            color: LinearRgba::WHITE,
            back_color: LinearRgba::BLACK,
            cull_back_faces: false,
        };
        let materials = SceneMaterials {
            surface_culled: assets.add(SurfaceMaterial {
                cull_back_faces: true,
                ..surface.clone()
            }),
            surface: assets.add(surface),
            wireframe: Handle::default(),
        };
        let chunk = world.spawn(MeshMaterial3d(materials.surface.clone())).id();
        world.entity_mut(mesh.0).insert(RenderChunks {
            chunks: vec![chunk],
            ..default()
        });
        world.spawn((OrbitCamera::default(), Transform::from_translation(eye)));
        world.insert_resource(materials.clone());
        world.insert_resource(SoftwareRenderer(software));
        world.insert_resource(RenderStats {
            rebuilds: 3,
            ..default()
        });
        world.insert_resource(Closures::default());
        (world, mesh, chunk, materials)
    }

    fn drawn_with(world: &World, chunk: Entity) -> Handle<SurfaceMaterial> {
        world
            .get::<MeshMaterial3d<SurfaceMaterial>>(chunk)
            .expect("a material")
            .0
            .clone()
    }

    #[test]
    fn a_closed_outward_mesh_seen_from_outside_culls_on_a_software_renderer_only() {
        let (mut world, chunk, materials) = cube_seen_from(Vec3::new(0.0, 0.0, 5.0), true);
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface_culled);
        let (mut world, chunk, materials) = cube_seen_from(Vec3::new(0.0, 0.0, 5.0), false);
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
    }

    #[test]
    fn inside_the_mesh_or_after_an_edit_both_sides_are_drawn() {
        let (mut world, chunk, materials) = cube_seen_from(Vec3::new(0.0, 0.0, 5.0), true);
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface_culled);
        // An edit redraws the mesh: the closure is of the mesh before it.
        world.resource_mut::<RenderStats>().rebuilds += 1;
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
        let (mut world, chunk, materials) = cube_seen_from(Vec3::new(0.0, 0.0, 0.5), true);
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
    }

    #[test]
    fn an_opened_mesh_is_culled_once_drawn_with_the_closure_it_brought_unless_edited() {
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let (mut world, mesh, chunk, materials) = cube_unclosed(eye, true);
        let closure = Closure::of(&extract(&world, mesh).tables);
        // Not drawn yet: the closure waits for the render copy.
        world
            .entity_mut(mesh.0)
            .insert((ClosureAtOpen(closure.clone()), MeshDirty));
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
        assert!(world.get::<ClosureAtOpen>(mesh.0).is_some());
        // Drawn: recorded at this render's generation, and culled at once.
        world.entity_mut(mesh.0).remove::<MeshDirty>();
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface_culled);
        assert!(world.get::<ClosureAtOpen>(mesh.0).is_none());
        assert_eq!(
            world.resource::<Closures>().0.get(&mesh),
            Some(&(3, closure.clone()))
        );
        // Edited before its first draw: the closure is of the mesh before the edit, and dropped.
        let (mut world, mesh, chunk, materials) = cube_unclosed(eye, true);
        world
            .entity_mut(mesh.0)
            .insert((ClosureAtOpen(closure), Modified));
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
        assert!(world.get::<ClosureAtOpen>(mesh.0).is_none());
        assert!(world.resource::<Closures>().0.is_empty());
    }
}
