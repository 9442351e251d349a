//! The panel's figures of the active mesh — statistics, validity, histograms, and the mesh
//! closed over its holes that tells the renderer whether its back faces can be seen
//! ([`crate::editor::view::culling`]) — counted where they do not stall the window.
//!
//! They are O(mesh). [`super::ui::snapshot`] decides *when* (once the mesh stands still, never
//! during a drag); this module decides *where*. A mesh under [`JobSettings::min_faces_figures_apart`] faces is counted on
//! the frame (about 150 ms on the bunny, 100 of it the validity check). A larger one would stall
//! the window for seconds (the 1.1 M-face scan: about 2 s of validation and 1.2 s of
//! statistics), so its tables are read a slice of [`READ_SLICE`] a frame ([`GradualRead`]: read
//! in one go they held a frame of the 1.3 M-face icosphere for 650 ms after every edit) and the
//! statistics and histograms counted from them on a thread of their own, the last figures shown
//! meanwhile; an edit during the read starts it again. Its validity is checked when asked (the
//! panel's button), since every mesh an operation leaves is valid by construction and the full
//! check stays a frame-long wait.

use bevy::ecs::change_detection::Tick;
use bevy::prelude::{DetectChanges, Resource, World};
use bevy::window::RequestRedraw;
use std::path::PathBuf;
use std::thread::JoinHandle;

use crate::mesh::closure::Closure;
use crate::mesh::tables::{GradualRead, MeshTables, extract};
use crate::mesh::{MeshId, MeshInfo, MeshStats, stats_of_tables, validate};

use super::plots::{Histogram, histograms_of_tables};
use crate::editor::pipeline::jobs::{JobSettings, READ_SLICE};
use crate::editor::view::colouring::VertexValues;
use crate::editor::view::culling::record_closure;
use crate::editor::view::render_sync::{RenderChunks, RenderStats};

/// The active mesh as the panel shows it.
#[derive(Debug, Clone)]
pub struct MeshView {
    /// Its name.
    pub name: String,
    /// Its file.
    pub path: Option<PathBuf>,
    /// Its statistics (`None` until first counted).
    pub stats: Option<MeshStats>,
    /// `Ok` or the first broken invariant; `None` when not checked (a large mesh is checked
    /// when asked, see the module doc).
    pub validation: Option<Result<(), String>>,
    /// Its figures are being counted on a thread (those shown are from before).
    pub counting: bool,
}

/// What a counting thread hands back: the statistics, the histograms and the mesh closed over
/// its holes (for [`crate::editor::view::culling`]).
type Figures = (MeshStats, Vec<Histogram>, Closure);

/// What a mesh's figures are counted at: the mesh, the redraws of edits so far
/// ([`RenderStats::edits_drawn`]) and when the quantity shown on it last changed (its histogram
/// is among the figures). A redraw for the looks alone (shading, wireframe, checkerboard)
/// changes none of them, so the figures shown stand: on the bunny a count is 150 ms of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FiguresKey {
    mesh: Option<MeshId>,
    edits: usize,
    shown: Option<Tick>,
}

impl FiguresKey {
    /// The key of `mesh`'s figures as the world stands.
    pub fn of(world: &World, mesh: MeshId) -> Self {
        Self {
            mesh: Some(mesh),
            edits: world.resource::<RenderStats>().edits_drawn,
            shown: world
                .get_entity(mesh.0)
                .ok()
                .and_then(|e| e.get_ref::<VertexValues>())
                .map(|values| values.last_changed()),
        }
    }
}

/// Figures being counted apart from the frame: what they are counted at, the render generation
/// the count began at (the closure holds for it, see [`record_closure`]), the mesh, and where
/// they stand.
#[derive(Resource, Default)]
pub struct Counting(Option<(FiguresKey, usize, MeshId, Apart)>);

/// The two steps of counting a large mesh's figures.
enum Apart {
    /// Its tables being read, a slice a frame, with the quantity shown on it.
    Reading(Box<(GradualRead, Option<VertexValues>)>),
    /// The figures being counted from the tables on a thread.
    Counting(JoinHandle<Figures>),
}

/// Counts the figures of `mesh` (at `key`) into `view`: at once for a small mesh, by starting
/// to read a large one's tables (see the module doc; [`collect`] goes on).
pub fn count(
    world: &mut World,
    view: &mut Option<MeshView>,
    shown_histograms: &mut Vec<Histogram>,
    mesh: MeshId,
    key: FiguresKey,
) {
    let generation = world.resource::<RenderStats>().rebuilds;
    let info = world.get::<MeshInfo>(mesh.0).cloned().unwrap_or_default();
    // The faces drawn: known without a walk over the mesh.
    let faces = world
        .get::<RenderChunks>(mesh.0)
        .map_or(0, |c| c.face_chunk.len());
    let large = world
        .get_resource::<JobSettings>()
        .is_some_and(|s| faces >= s.min_faces_figures_apart);
    if !large {
        let read = extract(world, mesh);
        record_closure(world, mesh, generation, Closure::of(&read.tables));
        *view = Some(MeshView {
            name: info.name,
            path: info.path,
            stats: Some(stats_of_tables(&read.tables)),
            validation: Some(validate(world, mesh).map_err(|e| e.to_string())),
            counting: false,
        });
        *shown_histograms = histograms_of_tables(&read.tables, world.get::<VertexValues>(mesh.0));
        return;
    }
    let shown = world.get::<VertexValues>(mesh.0).cloned();
    let previous = view.take();
    *view = Some(MeshView {
        name: info.name,
        path: info.path,
        stats: previous.and_then(|m| m.stats),
        validation: None,
        counting: true,
    });
    world.resource_mut::<Counting>().0 = Some((
        key,
        generation,
        mesh,
        Apart::Reading(Box::new((GradualRead::new(mesh), shown))),
    ));
    world.write_message(RequestRedraw);
}

/// Starts the thread that counts the figures of `tables`; `None` when the system refused one
/// (the figures then stay unknown until the next change).
fn count_apart(tables: MeshTables, shown: Option<VertexValues>) -> Option<JoinHandle<Figures>> {
    std::thread::Builder::new()
        .name("panel figures".into())
        .spawn(move || {
            let stats = stats_of_tables(&tables.tables);
            let histograms = histograms_of_tables(&tables.tables, shown.as_ref());
            (stats, histograms, Closure::of(&tables.tables))
        })
        .ok()
}

/// Goes on counting a large mesh's figures: reads the next slice of its tables, starts the
/// counting thread once they are read, and takes the figures it has finished into `view`, if
/// they are for `key` (figures of an older mesh are dropped). Asks for the next frame while
/// there is more to do. Returns whether the view changed.
pub fn collect(
    world: &mut World,
    view: &mut Option<MeshView>,
    shown_histograms: &mut Vec<Histogram>,
    key: FiguresKey,
) -> bool {
    let Some((counted, generation, mesh, apart)) = world.resource_mut::<Counting>().0.take() else {
        return false;
    };
    if counted != key {
        return false;
    }
    let next = match apart {
        Apart::Reading(mut reading) => match reading.0.advance(world, READ_SLICE) {
            Ok(None) => Some(Apart::Reading(reading)),
            Ok(Some(tables)) => count_apart(tables, reading.1).map(Apart::Counting),
            Err(broken) => {
                bevy::log::warn!("panel figures: {broken}; they are counted after the next edit");
                if let Some(mesh) = view.as_mut() {
                    mesh.counting = false;
                }
                None
            }
        },
        Apart::Counting(thread) if !thread.is_finished() => Some(Apart::Counting(thread)),
        Apart::Counting(thread) => {
            let Ok((stats, histograms, closure)) = thread.join() else {
                return false;
            };
            record_closure(world, mesh, generation, closure);
            if let Some(mesh) = view.as_mut() {
                mesh.stats = Some(stats);
                mesh.counting = false;
            }
            *shown_histograms = histograms;
            return true;
        }
    };
    if next.is_some() {
        world.write_message(RequestRedraw);
    }
    world.resource_mut::<Counting>().0 = next.map(|apart| (counted, generation, mesh, apart));
    false
}

/// Checks the validity of `mesh` on the frame, for the panel's button.
pub fn check_validity(world: &World, view: &mut Option<MeshView>, mesh: MeshId) {
    if let Some(shown) = view.as_mut() {
        shown.validation = Some(validate(world, mesh).map_err(|e| e.to_string()));
    }
}
