//! A mesh's closure counted anew from the triangles its chunks draw, on a thread of its own,
//! where the edits since its last count could not be followed (see the parent module).
//!
//! The panel counts the closure with its figures, reading a large mesh's tables a slice a frame:
//! 7–12 s after an edit of the 1.3 M-face icosphere on lavapipe, every frame of it two-sided.
//! What the closure needs is all in the render chunks: their triangles, and the mesh vertex
//! behind each render vertex ([`DrawnTriangles`]). So once a frame has passed with nothing
//! redrawn and no mouse button held (not at every step of a drag), [`count_drawn`] copies them
//! and closes them apart ([`DrawnTriangles::close`], 0.4 s for the icosphere on one core). The
//! count is recorded at the render generation it was taken at, with the chunks' summed volume
//! then, so the edits after it are followed from there. A mesh is counted at most once a redraw
//! of its own: one whose triangles the builder would have to repair, whose closure they cannot
//! tell, waits for the panel's count.

use bevy::input::ButtonInput;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use std::thread::JoinHandle;

use crate::editor::session::selection::MeshDirty;
use crate::editor::view::render_data::DrawnTriangles;
use crate::editor::view::render_sync::{RenderChunks, RenderStats};
use crate::editor::view::scene::SoftwareRenderer;
use crate::mesh::MeshId;
use crate::mesh::closure::Closure;

use super::{ClosureAtOpen, Closures, Counted, closure_followed, drawn_shape, keep_count};

/// Closures being counted from the triangles the chunks draw (see the module doc).
#[derive(Resource, Default)]
pub struct DrawnCounts {
    /// The render generation the last frame ended at: a mesh is counted once a frame has
    /// passed without a redraw.
    last_generation: usize,
    /// The generation each mesh's last count was tried at (started or not): none is tried
    /// again before the mesh's chunks are redrawn ([`ChunkChanges::drawn`](crate::editor::view::render_sync::ChunkChanges::drawn)).
    started: HashMap<MeshId, usize>,
    counting: HashMap<MeshId, DrawnCount>,
}

/// A count under way: the render generation and the chunks' summed volume it is of.
struct DrawnCount {
    generation: usize,
    drawn_volume: f64,
    thread: JoinHandle<Option<Closure>>,
}

impl DrawnCounts {
    /// Whether every count started has finished.
    #[cfg(test)]
    fn finished(&self) -> bool {
        self.counting.values().all(|c| c.thread.is_finished())
    }
}

/// Records the counts that have finished (unless a later count of the same mesh was recorded
/// meanwhile), and starts one for each mesh whose closure the edits could not follow, once a
/// frame has passed with nothing redrawn and no mouse button held. Only on a software renderer,
/// the only one that culls.
pub fn count_drawn(world: &mut World) {
    let software = world
        .get_resource::<SoftwareRenderer>()
        .is_some_and(|s| s.0);
    if !software {
        return;
    }
    let Some(mut counts) = world.remove_resource::<DrawnCounts>() else {
        return;
    };
    let generation = world.resource::<RenderStats>().rebuilds;
    let done: Vec<MeshId> = counts
        .counting
        .iter()
        .filter(|(_, c)| c.thread.is_finished())
        .map(|(&m, _)| m)
        .collect();
    for mesh in done {
        let count = counts.counting.remove(&mesh).expect("listed");
        if let Ok(Some(closure)) = count.thread.join() {
            let counted = Counted {
                generation: count.generation,
                closure,
                drawn_volume: Some(count.drawn_volume),
            };
            keep_count(world, mesh, counted);
            debug!("mesh {}: closure counted from the drawn triangles", mesh.0);
        }
    }
    let held = world
        .get_resource::<ButtonInput<MouseButton>>()
        .is_some_and(|b| b.get_pressed().next().is_some());
    if counts.last_generation == generation && !held {
        for mesh in stale(world, &counts, generation) {
            // Tried once this redraw, whether or not it could start.
            counts.started.insert(mesh, generation);
            if let Some(count) = start_count(world, mesh, generation) {
                counts.counting.insert(mesh, count);
                debug!("mesh {}: closure counted apart", mesh.0);
            }
        }
    }
    counts.last_generation = generation;
    // Meshes deleted: their counts are dropped (a thread runs on to its end unheard).
    counts
        .counting
        .retain(|m, _| world.get::<RenderChunks>(m.0).is_some());
    counts
        .started
        .retain(|m, _| world.get::<RenderChunks>(m.0).is_some());
    world.insert_resource(counts);
}

/// The drawn meshes whose closure is not known at `generation`, not being counted and not
/// counted since their chunks were last redrawn.
fn stale(world: &mut World, counts: &DrawnCounts, generation: usize) -> Vec<MeshId> {
    world
        .query_filtered::<(Entity, &RenderChunks), (Without<ClosureAtOpen>, Without<MeshDirty>)>()
        .iter(world)
        .filter(|(m, chunks)| {
            let mesh = MeshId(*m);
            let started = counts.started.get(&mesh);
            !counts.counting.contains_key(&mesh)
                && started.is_none_or(|&at| at < chunks.changes.drawn)
        })
        .map(|(m, _)| MeshId(m))
        .filter(|&m| match world.resource::<Closures>().0.get(&m) {
            Some(counted) => {
                counted.generation != generation && closure_followed(world, m, counted).is_none()
            }
            None => true,
        })
        .collect()
}

/// Copies what `mesh`'s chunks draw and starts closing it on a thread; `None` when they draw
/// nothing to close or the system refused a thread.
fn start_count(world: &World, mesh: MeshId, generation: usize) -> Option<DrawnCount> {
    let (drawn_volume, _) = drawn_shape(world, mesh)?;
    let chunks = &world.get::<RenderChunks>(mesh.0)?.chunks;
    let triangles = DrawnTriangles::read(world, chunks)?;
    let thread = std::thread::Builder::new()
        .name("closure".into())
        .spawn(move || triangles.close())
        .ok()?;
    Some(DrawnCount {
        generation,
        drawn_volume,
        thread,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::view::culling::choose_culling;
    use crate::editor::view::culling::tests::{cube_drawn, drawn_with};
    use crate::mesh::tables::extract;
    use bevy::mesh::Indices;

    /// A frame of the two systems: counts, then the materials.
    fn frame(world: &mut World) {
        count_drawn(world);
        choose_culling(world);
    }

    fn wait_for_counts(world: &World) {
        while !world.resource::<DrawnCounts>().finished() {
            std::thread::yield_now();
        }
    }

    /// The cube of `cube_drawn`, its closure counted at render generation 2 and its chunks
    /// redrawn whole at 3, where the world stands.
    fn cube_redrawn() -> (
        World,
        MeshId,
        Entity,
        crate::editor::view::scene::SceneMaterials,
    ) {
        let (mut world, mesh, chunk, materials) = cube_drawn(Vec3::new(0.0, 0.0, 5.0));
        let closure = Closure::of(&extract(&world, mesh).tables);
        super::super::record_closure(&mut world, mesh, 2, closure);
        let changes = &mut world.get_mut::<RenderChunks>(mesh.0).unwrap().changes;
        (changes.whole, changes.drawn) = (3, 3);
        (world, mesh, chunk, materials)
    }

    #[test]
    fn a_closure_the_edits_could_not_follow_is_counted_anew_from_the_drawn_triangles() {
        let (mut world, mesh, chunk, materials) = cube_redrawn();
        // The frame of the redraw: both sides drawn, nothing counted yet.
        frame(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface);
        assert!(world.resource::<DrawnCounts>().counting.is_empty());
        // A frame on with nothing redrawn: counted apart, and culled once the count is in.
        frame(&mut world);
        assert_eq!(world.resource::<DrawnCounts>().counting.len(), 1);
        wait_for_counts(&world);
        frame(&mut world);
        assert_eq!(drawn_with(&world, chunk), materials.surface_culled);
        let counted = &world.resource::<Closures>().0[&mesh];
        assert_eq!((counted.generation, counted.closure.holes.len()), (3, 0));
        let volumes = (counted.closure.volumes[0], counted.drawn_volume.unwrap());
        assert!((volumes.0 - 8.0).abs() < 1e-9 && (volumes.1 - 8.0).abs() < 1e-9);
        frame(&mut world);
        assert!(world.resource::<DrawnCounts>().counting.is_empty());
    }

    #[test]
    fn triangles_the_builder_would_repair_are_counted_once_a_redraw() {
        let (mut world, mesh, chunk, materials) = cube_redrawn();
        // One triangle turned against its neighbours: no closure to tell.
        let handle = world.get::<Mesh3d>(chunk).unwrap().0.clone();
        let mut meshes = world.resource_mut::<Assets<Mesh>>();
        if let Some(Indices::U32(corners)) = meshes.get_mut(&handle).unwrap().indices_mut() {
            corners.swap(1, 2);
        }
        for _ in 0..2 {
            frame(&mut world);
        }
        wait_for_counts(&world);
        for _ in 0..3 {
            frame(&mut world);
            assert!(world.resource::<DrawnCounts>().counting.is_empty());
        }
        assert_eq!(drawn_with(&world, chunk), materials.surface);
        assert_eq!(world.resource::<Closures>().0[&mesh].generation, 2);
        // Redrawn: tried again, a frame later.
        world.get_mut::<RenderChunks>(mesh.0).unwrap().changes.drawn = 4;
        world.resource_mut::<RenderStats>().rebuilds = 4;
        frame(&mut world);
        frame(&mut world);
        assert_eq!(world.resource::<DrawnCounts>().counting.len(), 1);
    }

    #[test]
    fn nothing_is_counted_while_a_mouse_button_is_held_or_on_a_gpu() {
        let (mut world, _, _, _) = cube_redrawn();
        let mut buttons = ButtonInput::<MouseButton>::default();
        buttons.press(MouseButton::Left);
        world.insert_resource(buttons);
        for _ in 0..3 {
            frame(&mut world);
        }
        assert!(world.resource::<DrawnCounts>().counting.is_empty());
        world
            .resource_mut::<ButtonInput<MouseButton>>()
            .release(MouseButton::Left);
        world.insert_resource(SoftwareRenderer(false));
        for _ in 0..3 {
            frame(&mut world);
        }
        assert!(world.resource::<DrawnCounts>().counting.is_empty());
    }
}
