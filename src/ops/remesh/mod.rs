//! Isotropic remeshing (Botsch & Kobbelt, "A Remeshing Approach to Multiresolution Modeling",
//! SGP 2004) with reprojection and feature preservation.
//!
//! Each iteration, for a target edge length `L`:
//! 1. split every edge longer than 4/3 L at its midpoint ([`split`]);
//! 2. collapse every edge shorter than 4/5 L, shortest first, to its midpoint or else to one of
//!    its ends, unless every choice would make an edge longer than 4/3 L (and through the
//!    collapse plan's refusals, with a 60° normal bound; features restrict the choice, see
//!    below) ([`collapse`]);
//! 3. flip an edge when that brings the valences of its four vertices closer to 6 (4 on the
//!    boundary), or leaves them as close and the edge was not locally Delaunay (the angles
//!    facing it summed to over 180°: flipping raises the pair's smallest angle) ([`flip`]);
//! 4. move every free vertex 1/5 of the way to the centre of mass of its triangles, within its
//!    tangent plane (all new positions computed first, then committed), repeated
//!    [`RemeshParams::smoothing_steps`] times (10, as in Scotty3D) ([`relax`]);
//! 5. project the free vertices back onto the input surface (closest point on the input
//!    triangles, found through a uniform grid: [`crate::ops::geometry::closest`]), once an
//!    iteration, after the last smoothing step ([`relax::project`]).
//!
//! Each of these five is a pass of a [`RemeshRun`], which makes one pass a call and reports
//! what it touched ([`PassReport`]), for the editor's step mode; [`remesh`] runs one to its
//! end.
//!
//! After the last iteration ([`finish`]), the detail that triangles of length L cannot follow
//! is put back where the remesh strays from the input by more than
//! [`DETAIL_TOLERANCE`](finish::DETAIL_TOLERANCE) · L: the input's vertices left that far off
//! its surface (the tips of spikes and folds narrower than L), and the centres of its
//! triangles longer than 2 L ([`detail_points`](finish::detail_points)), become vertices
//! again ([`restore_tips`](finish::restore_tips)), and the edges whose middle is that far off
//! (bridging a groove or the foot of a spike) are split onto the input
//! ([`fill_grooves`](finish::fill_grooves)); each split only where its triangles lie no farther
//! from the input than the gap it closes.
//!
//! Then the edges of triangles left with an angle under 30° are flipped where that makes the
//! pair less thin (a flip moves no vertex, so the surface stays where the projection put it).
//! Then the corners of the triangles still thin move to where their triangles are best shaped
//! ([`relax_thin_corners`](relax::relax_thin_corners): a free corner within its tangent plane
//! and back onto the input, a corner on a straight feature line or boundary along it), and the
//! edges around them get the same flips, for a bounded number of rounds
//! ([`clean_up_thin`](finish::clean_up_thin)). What stays thin has a corner that may not move:
//! a feature corner, or a feature line or boundary that bends there.
//!
//! Last, the vertices are fitted to the input
//! ([`surface_fit`](crate::ops::geometry::surface_fit)): each vertex that the projection left
//! on the input moves along its normal by the mean of the gaps around it, both ways (the
//! input's points from the remesh, the remesh's from the input), each weighted by its length,
//! so that the triangles straddle the input instead of lying on one side of it (one step of
//! Hoppe et al.'s least-squares fit, "Mesh Optimization", SIGGRAPH 1993). The boundary,
//! feature corners and the tips put back stay; no move makes a triangle thin. Then the input's
//! points still farthest off (past a tenth of L, and past half the farthest one's gap) pull a
//! corner of the remesh triangle nearest each part of the way towards them, where that brings
//! the largest gap around it down, both ways ([`far_spots`]): the least squares lowers the mean
//! gap, this step the largest one, which is the Hausdorff distance.
//!
//! Each pass starts from the mesh read into flat tables ([`extract`]): the edge lengths, the
//! valences and the feature degrees come from array passes. The collapses and the flips are
//! made on the tables and written back once a pass (the same edits, element for element, as
//! the local operations make on the entities); the splits go through the entities. Attributes
//! are dropped at the first pass (remeshing carries none), so no pass leaves a stale one.
//! Features are kept ([`features`]): boundary edges and edges whose dihedral angle exceeds
//! [`RemeshParams::feature_angle_deg`] (less the sides of triangles dented by scanner noise,
//! see [`without_noise`](features::without_noise)) are split (both halves stay features) but
//! never flipped, and a vertex on a feature does not move. A free vertex may collapse into a
//! feature vertex (which stays put), and a vertex on a feature line (two feature edges) into
//! its neighbour along the line where the line is straight to within L/20 there; feature
//! corners never go.
//! The work is bounded (a fixed number of passes over edge lists taken at the start of each
//! pass), so it ends on every input.
//!
//! What the passes measured on the test models (distance to the input, thin triangles) is in
//! `docs/remesh.md`.

mod collapse;
mod far_spots;
mod features;
mod finish;
pub(crate) mod flip;
mod operation;
mod pass;
mod relax;
mod run;
mod split;
mod stepping;

use crate::ops::declaration::{Declaration, Parameter};

/// Isotropic remeshing: a job on a large mesh; a mesh made anew, without attributes.
pub const REMESH: Declaration = Declaration::new("remesh")
    .titled("Remesh")
    .described(
        "isotropic remeshing (Botsch & Kobbelt): split, collapse, flip and relax towards edges \
         of LENGTH, keeping edges sharper than FEATURE degrees; triangles",
    )
    .on_key("M")
    .with_parameters(&[
        Parameter::whole("ITERATIONS", 5, 1, 100),
        Parameter::real("LENGTH", 0.01, 1e-6, 1e6).automatic_by_default("the mean edge length"),
        Parameter::real("FEATURE", 45.0, 0.0, 180.0),
    ])
    .as_job()
    .stepping()
    .dropping("remeshing does not carry attributes");

#[cfg(test)]
mod tests;

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, MeshId};
use crate::mesh::members::MeshMembers;
use crate::mesh::tables::Connectivity;
use crate::mesh::tables::{MeshTables, extract};

use super::Refusal;
pub use operation::Remesh;
pub use pass::{Pass, PassReport, Touched};
pub use run::RemeshRun;
pub use stepping::RemeshSteps;

/// How to remesh. The same struct serves the command line, the editor and the tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RemeshParams {
    /// Target edge length; `None`: the mean edge length of the input.
    pub target_length: Option<f32>,
    /// Iterations of split, collapse, flip, smooth. Default 5.
    pub iterations: u32,
    /// Edges with a dihedral angle above this (degrees) are features, unless all three sides
    /// of a triangle are (a dent, scanner noise). Default 45°.
    pub feature_angle_deg: f32,
    /// Smoothing steps (each 1/5 of the way to the centre of mass of the vertex's triangles,
    /// then reprojected) per iteration. Default 10, as Scotty3D's remesher.
    pub smoothing_steps: u32,
}

impl Default for RemeshParams {
    fn default() -> Self {
        Self {
            target_length: None,
            iterations: 5,
            feature_angle_deg: 45.0,
            smoothing_steps: 10,
        }
    }
}

/// What a remeshing did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RemeshSummary {
    /// The target length used.
    pub target_length: f32,
    /// Splits, collapses and flips made.
    pub splits: usize,
    /// Collapses made.
    pub collapses: usize,
    /// Flips made.
    pub flips: usize,
}

/// Remeshes a triangle mesh in place (see the module doc): a [`RemeshRun`] run to its end.
///
/// # Refusals
/// [`Refusal::NotTriangle`] on polygons; a stale mesh. The mesh is then unchanged.
pub fn remesh(
    world: &mut World,
    mesh: MeshId,
    params: &RemeshParams,
) -> Result<RemeshSummary, Refusal> {
    remesh_with_progress(world, mesh, params, |_| true)
}

/// [`remesh`], calling `progress(fraction done)` after each pass of a [`RemeshRun`] (split,
/// collapse, flip, relax, project, finish); returning `false` stops after that pass (the mesh
/// is then valid, less remeshed). The same as running a [`RemeshRun`] to its end.
///
/// # Refusals
/// As [`remesh`].
pub fn remesh_with_progress(
    world: &mut World,
    mesh: MeshId,
    params: &RemeshParams,
    mut progress: impl FnMut(f32) -> bool,
) -> Result<RemeshSummary, Refusal> {
    let mut run = RemeshRun::start(world, mesh, params)?;
    let total = run.passes_total() as f32;
    while run.next_pass(world).is_some() {
        if !progress(run.passes_done() as f32 / total) {
            break;
        }
    }
    Ok(run.summary())
}

/// The mesh's edges with their lengths, read in one pass over the world ([`extract`]) rather
/// than through several entity lookups an edge: each pass starts from it. Split and collapse
/// read it; its feature degrees are read in [`features`] ([`EdgeTable::feature_degree_rows`]).
struct EdgeTable {
    tables: Connectivity,
    members: MeshMembers,
    /// By edge row.
    length: Vec<f32>,
}

impl EdgeTable {
    /// Reads `mesh`'s tables and measures every edge.
    fn read(world: &World, mesh: MeshId) -> Self {
        let MeshTables { tables: t, members } = extract(world, mesh);
        let at = |h: u32| t.positions[t.to_vertex[h as usize] as usize];
        let length = t
            .edge_halfedge
            .iter()
            .map(|&h| at(t.twin[h as usize]).distance(at(h)))
            .collect();
        Self {
            tables: t,
            members,
            length,
        }
    }

    /// The edges whose length passes `keep`, in table order.
    fn edges_where(&self, keep: impl Fn(f32) -> bool) -> Vec<EdgeId> {
        self.members
            .edges
            .iter()
            .zip(&self.length)
            .filter(|&(_, &length)| keep(length))
            .map(|(&e, _)| e)
            .collect()
    }
}

/// How far `p` is from the segment `a b`.
fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let along = b - a;
    let t = ((p - a).dot(along) / along.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + along * t).distance(p)
}
