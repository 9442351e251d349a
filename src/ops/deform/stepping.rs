//! As-rigid-as-possible handle deformation stepped iteration by iteration ([`DeformSteps`]).
//!
//! In step mode a `G` / `R` / `S` of a handle with anchors marked moves the handle alone and,
//! confirmed, starts the run from the rest of the mesh as it was: iteration 0 places the handle
//! and moves nothing else. Each step is one local–global iteration (Sorkine & Alexa 2007), the
//! one [`super::deform`] makes; each free vertex's best rotation for the positions shown is
//! drawn as a small frame, and the energy of every iteration is listed. Back shows an earlier
//! iteration (each one's positions are kept), and a slider scrubs along them.

use bevy::math::{Quat, Vec3};
use bevy::prelude::World;

use super::{DeformParams, LiveDeform};
use crate::mesh::ids::{EdgeId, ElementId, MeshId, VertexId};
use crate::mesh::members::of_kind;
use crate::mesh::topology::MeshRef;
use crate::mesh::{Edge, Position};
use crate::ops::Refusal;
use crate::ops::operation::Redraw;
use crate::ops::operation::stepping::{
    Ended, GoesBack, Moved, StepLine, StepList, StepShape, StepShow, Steps, even_sample,
};

/// The length of a stepped deformation's rotation frames, in mean edge lengths.
pub const FRAME_SIZE: f32 = 0.7;

/// An as-rigid-as-possible deformation stepped iteration by iteration (see the module doc).
pub struct DeformSteps {
    live: Box<LiveDeform>,
    /// The vertices each iteration places: the handle, then every vertex that is not held.
    vertices: Vec<VertexId>,
    /// Each iteration's result, the handle placed before the first (iteration 0).
    pub iterations: Vec<DeformIteration>,
    /// The iteration the mesh shows.
    pub at: usize,
    /// The iterations the run makes in all.
    pub total: usize,
    /// The length of the rotation frames drawn ([`FRAME_SIZE`] of the mean edge length).
    pub frame_size: f32,
}

/// One iteration of a stepped deformation.
pub struct DeformIteration {
    /// Where the iteration put [`DeformSteps`]' vertices.
    pub positions: Vec<Vec3>,
    /// Each free vertex's best rotation for these positions (after the handle's in
    /// [`DeformSteps`]' order): what the next iteration's local step starts from.
    pub rotations: Vec<Quat>,
    /// The as-rigid-as-possible energy of these positions with those rotations.
    pub energy: f64,
}

impl DeformSteps {
    /// Checks the deformation and factors its system on the mesh as it is (the rest pose), then
    /// places the handle where the motion sends it: iteration 0, shown by [`Steps::open`].
    ///
    /// # Errors
    /// The deformation's refusal (the mesh is untouched).
    pub fn start(world: &World, mesh: MeshId, params: &DeformParams) -> Result<Self, Refusal> {
        let (mut live, targets) = super::prepare(world, mesh, params)?;
        let moves = live.solve(&targets, 0)?;
        let m = MeshRef::new(world);
        let energy = live.energy();
        let edges: Vec<_> = of_kind::<Edge, _>(world, mesh, EdgeId);
        let mean_edge = edges
            .iter()
            .map(|&e| {
                let (a, b) = m.edge_vertices(e);
                m.position(a).distance(m.position(b))
            })
            .sum::<f32>()
            / edges.len().max(1) as f32;
        Ok(Self {
            vertices: moves.iter().map(|(v, _)| *v).collect(),
            iterations: vec![DeformIteration {
                positions: moves.iter().map(|(_, p)| *p).collect(),
                rotations: live.free_rotations(),
                energy,
            }],
            live: Box::new(live),
            at: 0,
            total: params.iterations as usize,
            frame_size: FRAME_SIZE * mean_edge,
        })
    }

    /// Each free vertex of the iteration shown, where it is and its best rotation.
    pub fn frames(&self) -> impl Iterator<Item = (Vec3, Quat)> + '_ {
        let shown = &self.iterations[self.at];
        // The free vertices come last, one rotation each.
        let handle = shown.positions.len() - shown.rotations.len();
        shown.positions[handle..]
            .iter()
            .copied()
            .zip(shown.rotations.iter().copied())
    }

    /// The energy at the iteration shown.
    pub fn energy_line(&self) -> String {
        let energy = self.iterations[self.at].energy;
        match self.at {
            0 => format!("energy {energy:.6e}, the handle placed, the rest as it was"),
            _ => format!("energy {energy:.6e}"),
        }
    }

    /// Runs iterations up to `k` (at most the run's total) and shows iteration `k`.
    fn show_iteration(&mut self, world: &mut World, k: usize) -> Result<Redraw, Refusal> {
        let k = k.min(self.total);
        while self.iterations.len() <= k {
            self.live.iterate(1);
            let moves = self.live.moves()?;
            // This local step is the one the next iteration would run on the same positions,
            // and the next iteration reuses it, so measuring here leaves every later
            // iteration as an unstepped run makes it.
            let energy = self.live.energy();
            self.iterations.push(DeformIteration {
                positions: moves.into_iter().map(|(_, p)| p).collect(),
                rotations: self.live.free_rotations(),
                energy,
            });
        }
        self.at = k;
        for (v, &p) in self.vertices.iter().zip(&self.iterations[k].positions) {
            if let Some(mut at) = world.get_mut::<Position>(v.0) {
                at.0 = p;
            }
        }
        Ok(Redraw::Whole)
    }
}

impl Steps for DeformSteps {
    fn at(&self) -> usize {
        self.at
    }

    fn made(&self) -> usize {
        self.total
    }

    fn finished(&self) -> bool {
        self.at == self.total
    }

    fn goes_back(&self) -> GoesBack {
        GoesBack::Scrubs
    }

    fn open(&mut self, world: &mut World, _: MeshId) -> Result<Option<Redraw>, Refusal> {
        self.show_iteration(world, 0).map(Some)
    }

    fn go_to(
        &mut self,
        world: &mut World,
        _: MeshId,
        k: usize,
        _: Option<ElementId>,
    ) -> Result<Moved, Refusal> {
        self.show_iteration(world, k).map(Moved::redrawing)
    }

    fn describe(&self) -> String {
        format!(
            "iteration {} of {}: {}",
            self.at,
            self.total,
            self.energy_line()
        )
    }

    fn show(&self, _: &World, _: Option<ElementId>) -> StepShow {
        let frames: Vec<_> = self.frames().collect();
        StepShow {
            shapes: even_sample(frames.len())
                .map(|i| StepShape::Frame(frames[i].0, frames[i].1, self.frame_size))
                .collect(),
            lists: vec![StepList {
                title: "energy by iteration (each vertex's best rotation drawn as a frame)".into(),
                lines: (0..self.iterations.len())
                    .rev()
                    .map(|k| {
                        let shown = if k == self.at { "  ◀" } else { "" };
                        StepLine::text(format!("{k:>3}: {:.6e}{shown}", self.iterations[k].energy))
                    })
                    .collect(),
            }],
            ..StepShow::default()
        }
    }

    fn finish(self: Box<Self>, _: &mut World, _: MeshId) -> Ended {
        Ended::with(format!(
            "{} ARAP iterations (stepped; kept at iteration {} of {}), {}",
            self.iterations.len() - 1,
            self.at,
            self.total,
            self.energy_line()
        ))
    }
}
