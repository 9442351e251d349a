//! Isotropic remeshing (Botsch & Kobbelt 2004) one pass at a time, for a student to watch the
//! loop work on the live mesh: [`RemeshRun`] holds what the loop reads before its first pass
//! (the target length, the input surface to project onto, the input's tips and the feature
//! edges) and makes one pass a call.
//!
//! A run makes, for each iteration, the passes [`Pass::ITERATION`] (split, collapse, flip,
//! relax, project; see the [`remesh`](super) module doc for what each does), then after the
//! last iteration one [`Pass::Finish`] (tips and grooves put back, thin triangles cleaned
//! up). Each pass is ordinary edits of the world (splits, collapses, flips, moves), and the
//! mesh is valid between any two. [`remesh_with_progress`](super::remesh_with_progress) is this
//! loop run to the end, so a run stepped by hand ends in the very same mesh, to the bit.
//!
//! The relaxation and the projection are two passes, where the loop once projected inside the
//! last smoothing step: the steps are Jacobi (every new position from the old ones), so
//! projecting the relaxed positions afterwards gives the same bits.
//!
//! ```text
//!   start ─▶ [split ▶ collapse ▶ flip ▶ relax ▶ project] × iterations ▶ finish ─▶ None
//! ```

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::geometry::closest::Reference;

use super::collapse::collapse_short;
use super::features::{is_feature, without_noise};
use super::finish::{DETAIL_TOLERANCE, clean_up_thin, fill_grooves, restore_tips};
use super::flip::flip_to_valence;
use super::pass::{Pass, PassReport, Touched};
use super::relax::{Smoother, project};
use super::split::split_long;
use super::{RemeshParams, RemeshSummary, edge_length};

/// A remesh under way, one pass a call to [`RemeshRun::next_pass`].
///
/// It holds the input surface (for the projections and the finish) and the feature edges,
/// which the splits extend; it assumes the mesh changes only through it between passes. It
/// holds no borrow of the world, so it can wait between frames (it is `Send + Sync`).
pub struct RemeshRun {
    mesh: MeshId,
    iterations: u32,
    smoothing_steps: u32,
    /// The target length L, and 4/3 L and 4/5 L.
    length: f32,
    high: f32,
    low: f32,
    /// The input surface, for the projections and the finish.
    reference: Reference,
    /// The input's interior vertices, for [`restore_tips`].
    tips: Vec<Vec3>,
    features: EntityHashSet,
    summary: RemeshSummary,
    done: usize,
    /// The vertices the last relax pass could move, which the project pass puts back onto
    /// the input.
    relaxed: Vec<VertexId>,
}

impl RemeshRun {
    /// Reads `mesh` for a remesh with `params`: the target length (the mean edge length when
    /// `params` gives none), the input surface, the input's interior vertices and the feature
    /// edges. Changes nothing.
    ///
    /// # Refusals
    /// [`Refusal::Stale`] for a mesh that is not there, [`Refusal::NotTriangle`] on a polygon.
    pub fn start(world: &World, mesh: MeshId, params: &RemeshParams) -> Result<Self, Refusal> {
        if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        let members = MeshMembers::collect(world, mesh);
        let m = MeshRef::new(world);
        if let Some(&f) = members.faces.iter().find(|&&f| m.face_degree(f) != 3) {
            return Err(Refusal::NotTriangle(ElementId::Face(f)));
        }
        let length = params.target_length.unwrap_or_else(|| {
            let sum: f32 = members.edges.iter().map(|&e| edge_length(&m, e)).sum();
            sum / members.edges.len().max(1) as f32
        });
        let reference = Reference::new(&m, &members);
        let tips: Vec<Vec3> = members
            .vertices
            .iter()
            .filter(|&&v| !m.is_boundary_vertex(v))
            .map(|&v| m.position(v))
            .collect();
        let cos_limit = params.feature_angle_deg.to_radians().cos();
        let sharp: EntityHashSet = members
            .edges
            .iter()
            .filter(|&&e| is_feature(&m, e, cos_limit))
            .map(|e| e.0)
            .collect();
        let features = without_noise(&m, &members, sharp);
        Ok(Self {
            mesh,
            iterations: params.iterations,
            smoothing_steps: params.smoothing_steps,
            length,
            high: 4.0 / 3.0 * length,
            low: 4.0 / 5.0 * length,
            reference,
            tips,
            features,
            summary: RemeshSummary {
                target_length: length,
                splits: 0,
                collapses: 0,
                flips: 0,
            },
            done: 0,
            relaxed: Vec::new(),
        })
    }

    /// The mesh being remeshed.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }

    /// How many passes the whole run makes: five an iteration and the finish, or none for no
    /// iterations.
    pub fn passes_total(&self) -> usize {
        match self.iterations {
            0 => 0,
            n => n as usize * Pass::ITERATION.len() + 1,
        }
    }

    /// How many passes have been made.
    pub fn passes_done(&self) -> usize {
        self.done
    }

    /// The pass [`RemeshRun::next_pass`] makes next and its iteration, or `None` when the run
    /// is over.
    pub fn upcoming(&self) -> Option<(Pass, u32)> {
        let per = Pass::ITERATION.len();
        if self.done >= self.passes_total() {
            None
        } else if self.done + 1 == self.passes_total() {
            Some((Pass::Finish, self.iterations))
        } else {
            Some((Pass::ITERATION[self.done % per], (self.done / per) as u32))
        }
    }

    /// The target length and the splits, collapses and flips made so far.
    pub fn summary(&self) -> RemeshSummary {
        self.summary
    }

    /// Makes the next pass (see [`RemeshRun::upcoming`]) and says what it did; `None`, with the
    /// world untouched, when the run is over or the mesh is gone (which ends the run).
    pub fn next_pass(&mut self, world: &mut World) -> Option<PassReport> {
        let (pass, iteration) = self.upcoming()?;
        if world.get::<crate::mesh::MeshInfo>(self.mesh.0).is_none() {
            self.done = self.passes_total();
            return None;
        }
        let mesh = self.mesh;
        let mut touched = Touched::default();
        let count = match pass {
            Pass::Split => {
                touched = split_long(world, mesh, self.high, &mut self.features);
                self.summary.splits += touched.vertices.len();
                touched.vertices.len()
            }
            Pass::Collapse => {
                let (collapses, survivors) =
                    collapse_short(world, mesh, self.low, self.high, &self.features);
                touched.vertices = survivors;
                self.summary.collapses += collapses;
                collapses
            }
            Pass::Flip => {
                touched.edges = flip_to_valence(world, mesh, &self.features);
                self.summary.flips += touched.edges.len();
                touched.edges.len()
            }
            Pass::Relax => {
                // Small steps over one connectivity, read once and written once.
                let mut smoother = Smoother::new(world, mesh, &self.features);
                for _ in 0..self.smoothing_steps.max(1) {
                    smoother.step();
                }
                let relaxed = smoother.write(world);
                self.relaxed = relaxed.free;
                touched.vertices = relaxed.moved;
                touched.vertices.len()
            }
            Pass::Project => {
                let relaxed = std::mem::take(&mut self.relaxed);
                touched.vertices = project(world, &relaxed, &self.reference);
                touched.vertices.len()
            }
            Pass::Finish => self.finish(world, &mut touched),
        };
        self.done += 1;
        Some(PassReport {
            pass,
            iteration,
            count,
            touched,
        })
    }

    /// The finishing pass: tips and grooves put back, then the thin triangles cleaned up.
    /// Fills `touched` with the vertices added and the edges flipped; returns the splits plus
    /// the flips.
    fn finish(&mut self, world: &mut World, touched: &mut Touched) -> usize {
        let (mesh, length) = (self.mesh, self.length);
        let tolerance = DETAIL_TOLERANCE * length;
        let (reference, features) = (&self.reference, &self.features);
        let pinned = restore_tips(world, mesh, &self.tips, reference, features, length, tolerance);
        let grooves = fill_grooves(world, mesh, reference, features, tolerance);
        let flipped = clean_up_thin(world, mesh, features, &pinned, reference, self.low / 16.0);
        let splits = pinned.len() + grooves.len();
        self.summary.splits += splits;
        self.summary.flips += flipped.len();
        touched.vertices = pinned.iter().map(|&v| VertexId(v)).collect();
        touched.vertices.sort_unstable();
        touched.vertices.extend(grooves);
        touched.edges = flipped.clone();
        touched.edges.sort_unstable();
        touched.edges.dedup();
        splits + flipped.len()
    }
}
