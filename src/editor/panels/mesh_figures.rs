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

use bevy::prelude::{Resource, World};
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
use crate::editor::view::render_sync::RenderChunks;

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

/// Figures being counted apart from the frame: the mesh generation they are for, the mesh, and
/// where they stand.
#[derive(Resource, Default)]
pub struct Counting(Option<(usize, MeshId, Apart)>);

/// The two steps of counting a large mesh's figures.
enum Apart {
    /// Its tables being read, a slice a frame, with the quantity shown on it.
    Reading(Box<(GradualRead, Option<VertexValues>)>),
    /// The figures being counted from the tables on a thread.
    Counting(JoinHandle<Figures>),
}

/// Counts the figures of `mesh` (at mesh `generation`) into `view`: at once for a small mesh,
/// by starting to read a large one's tables (see the module doc; [`collect`] goes on).
pub fn count(
    world: &mut World,
    view: &mut Option<MeshView>,
    shown_histograms: &mut Vec<Histogram>,
    mesh: MeshId,
    generation: usize,
) {
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
/// they are for `generation` (figures of an older mesh are dropped). Asks for the next frame
/// while there is more to do. Returns whether the view changed.
pub fn collect(
    world: &mut World,
    view: &mut Option<MeshView>,
    shown_histograms: &mut Vec<Histogram>,
    generation: usize,
) -> bool {
    let Some((counted, mesh, apart)) = world.resource_mut::<Counting>().0.take() else {
        return false;
    };
    if counted != generation {
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
            record_closure(world, mesh, counted, closure);
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
    world.resource_mut::<Counting>().0 = next.map(|apart| (counted, mesh, apart));
    false
}

/// Checks the validity of `mesh` on the frame, for the panel's button.
pub fn check_validity(world: &World, view: &mut Option<MeshView>, mesh: MeshId) {
    if let Some(shown) = view.as_mut() {
        shown.validation = Some(validate(world, mesh).map_err(|e| e.to_string()));
    }
}
