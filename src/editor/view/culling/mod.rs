//! Back faces left undrawn where none can be seen, on a software rasterizer.
//!
//! The surface is drawn two-sided so that a back face seen through a hole, or on a part turned
//! inside out, shows in its own colour. On Mesa's software Vulkan (lavapipe: the editor's
//! renderer where there is no GPU) the surface's cost is the triangles it sets up, half of them
//! facing away: culling them took the bunny's opaque pass from 24–26 to 14–15 ms. So where no
//! back face can be seen, the chunks of a mesh take the material that culls them
//! ([`SceneMaterials::surface_culled`]): when the mesh's [`Closure`] says every component
//! faces outward, the eye is outside the mesh's box, and the eye lies on the inner side of every
//! hole's slab (see [`crate::mesh::closure`]).
//!
//! The closure is counted with the panel's figures, off the frame for a large mesh, at a render
//! generation. A large opened mesh brings its closure with it ([`ClosureAtOpen`], counted from
//! the tables it is spawned from), so it is culled from the frame that first draws it: the panel's
//! count of the 1.3 M-face icosphere comes 12 s later on lavapipe (its tables read back a
//! slice a frame). Between counts the closure is followed through the edits
//! ([`closure_followed`]): each chunk keeps the signed volume under its triangles and the box
//! of its corners ([`ChunkShape`]), so a one-component mesh's volume now is the counted one
//! changed by what the chunks' sum changed by, at no cost per edit beyond the chunks it redraws.
//! That holds while its holes and its one component are as counted, which the chunks'
//! [`ChunkChanges`](super::render_sync::ChunkChanges) tell: no face redrawn beside the
//! boundary, no faces added apart from the rest (a part restored by an undo would be a second
//! component, which one volume cannot speak for), and for a mesh with holes no face added or
//! removed and no positions refreshed wholesale. Otherwise, and for a mesh counted with several
//! components once it is redrawn, it is drawn two-sided until it is counted anew; so is it after
//! an edit that redraws it whole (a change of shading or colouring, which redraws the same
//! surface, does not count as one). Then it is counted anew from the triangles its chunks draw,
//! on a thread of its own ([`drawn`]): the panel's count, which reads the mesh a slice a frame,
//! comes 7–12 s after an edit of the 1.3 M-face icosphere.
//!
//! Only on a CPU adapter. On a GPU back faces cost little, and drawing them keeps the one case
//! the closure cannot see in the back colour: a surface that passes through itself, where a
//! back face can be nearest the eye (a fold dragged by hand).

pub mod drawn;

use bevy::pbr::MeshMaterial3d;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use crate::mesh::MeshId;
use crate::mesh::closure::{Closure, bounding_box};

use super::render_data::ChunkShape;
use super::render_sync::{RenderChunks, RenderStats};
use super::scene::{OrbitCamera, SceneMaterials, SoftwareRenderer};
use super::surface::SurfaceMaterial;
use crate::editor::session::selection::MeshDirty;
use crate::editor::session::state::Modified;

/// Each mesh's closure, as last counted.
#[derive(Resource, Default, Debug)]
pub struct Closures(pub HashMap<MeshId, Counted>);

/// A mesh's closure and when it was counted.
#[derive(Clone, Debug, PartialEq)]
pub struct Counted {
    /// The render generation ([`RenderStats::rebuilds`]) it was counted at.
    pub generation: usize,
    /// The closure.
    pub closure: Closure,
    /// The sum of the chunks' signed volumes ([`ChunkShape`]) when it was counted, if every
    /// chunk then drew that mesh: what a later sum is compared with.
    pub drawn_volume: Option<f64>,
}

/// Records `mesh`'s closure as counted at render `generation`, with the volume its chunks drew
/// then if they still draw that mesh; a count already recorded from later (from the drawn
/// triangles, [`drawn::DrawnCounts`]), or from then with the volume drawn, stays.
pub fn record_closure(world: &mut World, mesh: MeshId, generation: usize, closure: Closure) {
    let drawn_volume = (world.resource::<RenderStats>().rebuilds == generation)
        .then(|| drawn_shape(world, mesh).map(|(volume, _)| volume))
        .flatten();
    let counted = Counted {
        generation,
        closure,
        drawn_volume,
    };
    keep_count(world, mesh, counted);
}

/// Records `counted` as `mesh`'s closure unless one counted later is recorded, or one counted
/// then with the volume drawn where `counted` has none.
fn keep_count(world: &mut World, mesh: MeshId, counted: Counted) {
    let Some(mut closures) = world.get_resource_mut::<Closures>() else {
        return;
    };
    let (at, drawn) = (counted.generation, counted.drawn_volume.is_some());
    if !closures
        .0
        .get(&mesh)
        .is_some_and(|c| c.generation > at || (c.generation == at && !drawn))
    {
        closures.0.insert(mesh, counted);
    }
}

/// The summed signed volume of `mesh`'s chunks and the box of their corners; `None` while a
/// chunk has no shape.
fn drawn_shape(world: &World, mesh: MeshId) -> Option<(f64, Option<(Vec3, Vec3)>)> {
    let chunks = world.get::<RenderChunks>(mesh.0)?;
    let shapes: Vec<&ChunkShape> = chunks
        .chunks
        .iter()
        .map(|&c| world.get::<ChunkShape>(c))
        .collect::<Option<_>>()?;
    let volume = shapes.iter().map(|s| s.volume).sum();
    let corners = shapes
        .iter()
        .filter_map(|s| s.bounds)
        .flat_map(|(lo, hi)| [lo, hi]);
    Some((volume, bounding_box(corners)))
}

/// Whether none of `mesh`'s back faces can be seen from `eye` at render `generation`, by its
/// closure as `counted`: at this generation, or before and followed through the edits since
/// ([`closure_followed`]).
fn back_faces_hidden(
    world: &World,
    mesh: MeshId,
    counted: &Counted,
    generation: usize,
    eye: Vec3,
) -> bool {
    if counted.generation == generation {
        return counted.closure.back_faces_hidden_from(eye);
    }
    closure_followed(world, mesh, counted).is_some_and(|c| c.back_faces_hidden_from(eye))
}

/// `mesh`'s closure as `counted` before, followed through the edits since where they left its
/// holes and its one component as they were: no chunk drawn anew, no face redrawn beside the
/// boundary, no faces added apart from the rest, and for a mesh with holes no face added or
/// removed and no positions refreshed wholesale. Its one component's volume changes by what its
/// chunks' volumes changed by, and its box is theirs. A mesh not redrawn since keeps its
/// closure whatever its parts. `None` where the edits may have changed its holes, or it has
/// several components and was redrawn.
fn closure_followed(world: &World, mesh: MeshId, counted: &Counted) -> Option<Closure> {
    let changes = world.get::<RenderChunks>(mesh.0)?.changes;
    let since = |at: usize| at > counted.generation;
    let with_holes = !counted.closure.holes.is_empty();
    let holes_kept = !since(changes.boundary)
        && !(with_holes && (since(changes.faces) || since(changes.positions)));
    if since(changes.whole) || since(changes.parts) || !holes_kept {
        return None;
    }
    let (volume, bounds) = drawn_shape(world, mesh)?;
    if !since(changes.drawn) {
        // Not redrawn since (another mesh was, or its looks changed): as counted, every part.
        return Some(Closure {
            bounds,
            ..counted.closure.clone()
        });
    }
    counted
        .closure
        .changed(volume - counted.drawn_volume?, bounds)
}

/// The closure of a mesh as it was opened, counted from the tables it was spawned from (a
/// component of the mesh entity until the frame that first draws it). [`choose_culling`] takes it
/// once the render copy is drawn and records it at that render's generation, unless the mesh
/// was edited before ([`Modified`]): then it is dropped and the panel's count stands.
#[derive(Component, Debug)]
pub struct ClosureAtOpen(pub Closure);

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
                closures.0.get(&MeshId(mesh)).is_some_and(|counted| {
                    back_faces_hidden(world, MeshId(mesh), counted, generation, eye)
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
            record_closure(world, MeshId(mesh), generation, closure);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::view::render_data::{ChunkVertices, render_data};
    use crate::editor::view::render_sync::ChunkChanges;
    use crate::mesh::closure::Hole;
    use crate::mesh::ids::FaceId;
    use crate::mesh::shapes;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh};

    /// A world with the cube `[-1, 1]³` drawn by one chunk (two-sided), its closure counted at
    /// render generation 3, and the camera at `eye`.
    fn cube_seen_from(eye: Vec3, software: bool) -> (World, Entity, SceneMaterials) {
        let (mut world, mesh, chunk, materials) = cube_unclosed(eye, software);
        let closure = Closure::of(&extract(&world, mesh).tables);
        record_closure(&mut world, mesh, 3, closure);
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

    /// The world of [`cube_unclosed`] with its chunk drawing the cube's triangles (its mesh
    /// asset, vertex list and shape), as the render sync leaves it.
    pub(in crate::editor::view::culling) fn cube_drawn(
        eye: Vec3,
    ) -> (World, MeshId, Entity, SceneMaterials) {
        let (mut world, mesh, chunk, materials) = cube_unclosed(eye, true);
        let faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(&world, mesh, FaceId);
        let data = render_data(&world, &faces, false, false);
        let shape = ChunkShape::of(&data.positions, data.indices.iter().map(|&i| i as usize));
        let vertices = ChunkVertices(data.vertices.clone());
        let mut meshes = Assets::<Mesh>::default();
        let handle = meshes.add(data.into_mesh(None));
        world.insert_resource(meshes);
        world.insert_resource(drawn::DrawnCounts::default());
        world
            .entity_mut(chunk)
            .insert((Mesh3d(handle), vertices, shape));
        (world, mesh, chunk, materials)
    }

    pub(in crate::editor::view::culling) fn drawn_with(
        world: &World,
        chunk: Entity,
    ) -> Handle<SurfaceMaterial> {
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
        // An edit redraws the mesh, whose chunk has no shape to follow the closure by.
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
        let counted = &world.resource::<Closures>().0[&mesh];
        assert_eq!((counted.generation, &counted.closure), (3, &closure));
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

    /// The cube's closure as counted. With a hole under it, facing away from the eye:
    fn closed(_: &mut Closure) {}
    fn holed(c: &mut Closure) {
        let (centre, normal, reach) = (Vec3::new(0.0, 0.0, -1.0), Vec3::NEG_Z, 0.0);
        c.holes.push(Some(Hole {
            centre,
            normal,
            reach,
        }));
    }
    /// As two parts of half its volume each.
    fn two_parts(c: &mut Closure) {
        c.volumes = vec![4.0, 4.0];
    }

    /// The cube of [`cube_unclosed`] seen from `(0, 0, 5)`, its chunk drawing it with its volume
    /// (8) and box, its closure counted at render generation 3 (as `counted` makes it); then an
    /// edit drawn at generation 4 that leaves the chunk's volume `volume` and stamps `changes`
    /// (and `drawn`, unless `changes` has it).
    /// Whether its back faces are culled after the edit.
    fn culled_after_edit(volume: f64, changes: ChunkChanges, counted: fn(&mut Closure)) -> bool {
        let (mut world, mesh, chunk, materials) = cube_unclosed(Vec3::new(0.0, 0.0, 5.0), true);
        let bounds = Some((Vec3::splat(-1.0), Vec3::splat(1.0)));
        world.entity_mut(chunk).insert(ChunkShape {
            volume: 8.0,
            bounds,
        });
        let mut closure = Closure::of(&extract(&world, mesh).tables);
        counted(&mut closure);
        record_closure(&mut world, mesh, 3, closure);
        assert_eq!(
            world.resource::<Closures>().0[&mesh].drawn_volume,
            Some(8.0)
        );
        choose_culling(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface_culled);
        world
            .entity_mut(chunk)
            .insert(ChunkShape { volume, bounds });
        let drawn = if changes.drawn == 0 { 4 } else { changes.drawn };
        world.get_mut::<RenderChunks>(mesh.0).unwrap().changes = ChunkChanges { drawn, ..changes };
        world.resource_mut::<RenderStats>().rebuilds = 4;
        choose_culling(&mut world);
        drawn_with(&world, chunk) == materials.surface_culled
    }

    #[test]
    fn a_closed_mesh_stays_culled_through_edits_that_keep_it_closed_and_outward() {
        // A flip or a move: no stamp, the volume a little changed.
        assert!(culled_after_edit(8.5, ChunkChanges::default(), closed));
        // Faces added or positions refreshed wholesale: a closed mesh has no hole to change.
        let (faces, positions) = (4, 4);
        let grown = ChunkChanges {
            faces,
            positions,
            ..default()
        };
        assert!(culled_after_edit(8.5, grown, closed));
        // Turned inside out, or flattened: both sides drawn.
        assert!(!culled_after_edit(-8.0, ChunkChanges::default(), closed));
        assert!(!culled_after_edit(0.0, ChunkChanges::default(), closed));
        // Several parts: culled while not redrawn since (another mesh was), not once redrawn.
        let untouched = ChunkChanges {
            drawn: 3,
            ..default()
        };
        assert!(culled_after_edit(8.0, untouched, two_parts));
        assert!(!culled_after_edit(8.0, ChunkChanges::default(), two_parts));
    }

    #[test]
    fn edits_that_may_change_a_hole_or_redraw_the_whole_wait_for_the_next_count() {
        // Changes stamped at generation 4, after the count at 3.
        let stamped = |stamp: fn(&mut ChunkChanges)| {
            let mut changes = ChunkChanges::default();
            stamp(&mut changes);
            changes
        };
        for (changes, counted) in [
            (stamped(|c| c.boundary = 4), closed as fn(&mut Closure)),
            (stamped(|c| c.whole = 4), closed),
            (stamped(|c| (c.faces, c.parts) = (4, 4)), closed),
            (stamped(|c| c.faces = 4), holed),
            (stamped(|c| c.positions = 4), holed),
        ] {
            assert!(!culled_after_edit(8.0, changes, counted), "{changes:?}");
        }
        // A mesh with a hole keeps its closure through an edit away from it; stamps from
        // before the count are no change since.
        assert!(culled_after_edit(8.2, ChunkChanges::default(), holed));
        let before = ChunkChanges {
            whole: 3,
            boundary: 2,
            faces: 3,
            positions: 1,
            parts: 2,
            drawn: 3,
        };
        assert!(culled_after_edit(8.0, before, holed));
    }
}
