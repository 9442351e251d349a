//! The panel's figures of the active mesh — statistics, validity, histograms — counted where
//! they do not stall the window.
//!
//! They are O(mesh). [`super::ui::snapshot`] decides *when* (once the mesh stands still, never
//! during a drag); this module decides *where*. A mesh under [`JobSettings::min_faces_figures_apart`] faces is counted on
//! the frame (about 150 ms on the bunny, 100 of it the validity check). A larger one would stall
//! the window for seconds (the 1.1 M-face scan: about 2 s of validation and 1.2 s of
//! statistics), so its tables are read on the frame and the statistics and histograms counted
//! from them on a thread of their own, the last figures shown meanwhile; its validity is checked
//! when asked (the panel's button), since every mesh an operation leaves is valid by
//! construction and the full check stays a frame-long wait.

use bevy::prelude::{Resource, World};
use std::path::PathBuf;
use std::thread::JoinHandle;

use crate::mesh::tables::extract;
use crate::mesh::{MeshId, MeshInfo, MeshStats, mesh_stats, stats_of_tables, validate};

use super::plots::{Histogram, histograms, histograms_of_tables};
use crate::editor::pipeline::jobs::JobSettings;
use crate::editor::view::colouring::VertexValues;
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

/// What a counting thread hands back.
type Figures = (MeshStats, Vec<Histogram>);

/// Figures being counted on a thread: the mesh generation they are for, and the thread.
#[derive(Resource, Default)]
pub struct Counting(Option<(usize, JoinHandle<Figures>)>);

/// Counts the figures of `mesh` (at mesh `generation`) into `view`: at once for a small mesh,
/// by starting a thread for a large one (see the module doc).
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
        *view = Some(MeshView {
            name: info.name,
            path: info.path,
            stats: Some(mesh_stats(world, mesh)),
            validation: Some(validate(world, mesh).map_err(|e| e.to_string())),
            counting: false,
        });
        *shown_histograms = histograms(world, mesh, world.get::<VertexValues>(mesh.0));
        return;
    }
    let tables = extract(world, mesh).tables;
    let shown = world.get::<VertexValues>(mesh.0).cloned();
    let thread = std::thread::Builder::new()
        .name("panel figures".into())
        .spawn(move || {
            let stats = stats_of_tables(&tables);
            let histograms = histograms_of_tables(&tables, shown.as_ref());
            (stats, histograms)
        });
    let previous = view.take();
    *view = Some(MeshView {
        name: info.name,
        path: info.path,
        stats: previous.and_then(|m| m.stats),
        validation: None,
        counting: true,
    });
    // Without a thread (the system refused one) the figures stay unknown until the next change.
    world.resource_mut::<Counting>().0 = thread.ok().map(|t| (generation, t));
}

/// Takes the figures a thread has finished counting into `view`, if they are for `generation`
/// (figures of an older mesh are dropped). Returns whether the view changed.
pub fn collect(
    world: &mut World,
    view: &mut Option<MeshView>,
    shown_histograms: &mut Vec<Histogram>,
    generation: usize,
) -> bool {
    let finished = world
        .resource::<Counting>()
        .0
        .as_ref()
        .is_some_and(|(_, t)| t.is_finished());
    if !finished {
        return false;
    }
    let Some((counted, thread)) = world.resource_mut::<Counting>().0.take() else {
        return false;
    };
    let Ok((stats, histograms)) = thread.join() else {
        return false;
    };
    if counted != generation {
        return false;
    }
    if let Some(mesh) = view.as_mut() {
        mesh.stats = Some(stats);
        mesh.counting = false;
    }
    *shown_histograms = histograms;
    true
}

/// Checks the validity of `mesh` on the frame, for the panel's button.
pub fn check_validity(world: &World, view: &mut Option<MeshView>, mesh: MeshId) {
    if let Some(shown) = view.as_mut() {
        shown.validation = Some(validate(world, mesh).map_err(|e| e.to_string()));
    }
}
