//! A handle deformation that runs while the handle is dragged: the system is factored once for
//! its anchors and handle ([`LiveDeform::new`]), then each frame places the handle and runs one
//! as-rigid-as-possible iteration from the last frame's result (or the one thin-plate solve),
//! the editor's `G` / `R` / `S` with anchors marked.

use std::time::Instant;

use bevy::math::{DVec3, Quat, Vec3};
use bevy::prelude::World;

use crate::mesh::MeshInfo;
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::tables::extract;
use crate::ops::Refusal;
use crate::ops::geometry::{Surface, cotan_edges};

use super::{Arap, DeformMethod, ThinPlate, hold_loose_parts};

enum Solver {
    Arap(Box<Arap>),
    /// The thin plate, the handle's placed rows, and the last solve's positions.
    Laplace {
        plate: ThinPlate,
        targets: Vec<(u32, DVec3)>,
        positions: Vec<DVec3>,
    },
}

/// A handle deformation in progress (see the module doc).
pub struct LiveDeform {
    solver: Solver,
    /// The vertex behind each row.
    vertices: Vec<VertexId>,
    /// The handle's rows, in the order [`LiveDeform::new`] was given them.
    handle: Vec<u32>,
    /// Where [`LiveDeform::place`] put the handle, in the same order.
    targets: Vec<Vec3>,
    /// Rows that are held (anchors, the handle, parts with nothing held).
    held: Vec<bool>,
    /// ARAP iterations run so far.
    iterations: u32,
    /// Parts with nothing held, left where they are.
    loose_parts: usize,
    /// Seconds spent building and factoring the system (after reading the mesh).
    factor_seconds: f64,
    /// Seconds spent in the iterations (or the thin-plate solves) so far.
    solving_seconds: f64,
}

impl std::fmt::Debug for LiveDeform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveDeform")
            .field("vertices", &self.vertices.len())
            .field("handle", &self.handle.len())
            .field("iterations", &self.iterations)
            .finish()
    }
}

impl LiveDeform {
    /// Prepares the deformation of `mesh` with these anchors and handle (a vertex in both is the
    /// handle's), and factors its system. The handle starts where it is.
    ///
    /// # Refusals
    /// A stale mesh or vertex, an empty handle, or a system that cannot be factored.
    pub fn new(
        world: &World,
        mesh: MeshId,
        method: DeformMethod,
        anchors: &[VertexId],
        handle: &[VertexId],
    ) -> Result<Self, Refusal> {
        if world.get::<MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        if handle.is_empty() {
            return Err(Refusal::BadParameter("no handle: select what moves".into()));
        }
        let read = extract(world, mesh);
        let surface = Surface::from_tables(&read.tables);
        let rows = read.members.vertex_rows();
        let row = |v: &VertexId| {
            rows.get(&v.0)
                .copied()
                .ok_or(Refusal::Stale(ElementId::Vertex(*v)))
        };
        let n = surface.vertex_count();
        let mut held = vec![false; n];
        for v in anchors {
            held[row(v)? as usize] = true;
        }
        let handle: Vec<u32> = handle.iter().map(row).collect::<Result<_, _>>()?;
        handle.iter().for_each(|&r| held[r as usize] = true);
        let started = Instant::now();
        let edges = cotan_edges(&surface);
        let loose_parts = hold_loose_parts(n, &edges, &mut held);
        let solver = match method {
            DeformMethod::Arap => Solver::Arap(Box::new(Arap::new(&surface, &held)?)),
            DeformMethod::Laplace => Solver::Laplace {
                plate: ThinPlate::new(&surface, &edges, &held)?,
                targets: Vec::new(),
                positions: surface.positions.clone(),
            },
        };
        let targets = handle
            .iter()
            .map(|&r| surface.positions[r as usize].as_vec3())
            .collect();
        Ok(Self {
            solver,
            vertices: read.members.vertices,
            handle,
            targets,
            held,
            iterations: 0,
            loose_parts,
            factor_seconds: started.elapsed().as_secs_f64(),
            solving_seconds: 0.0,
        })
    }

    /// Puts the handle's vertices at `targets` (in the handle's order).
    pub fn place(&mut self, targets: &[Vec3]) {
        self.targets = targets.to_vec();
        let placed = self
            .handle
            .iter()
            .zip(targets)
            .map(|(&r, p)| (r, p.as_dvec3()));
        match &mut self.solver {
            Solver::Arap(arap) => arap.place(placed),
            Solver::Laplace { targets, .. } => *targets = placed.collect(),
        }
    }

    /// Runs `iterations` ARAP iterations from the last result (the last one's accelerated guess
    /// checked: [`Arap::settle`]), or the thin-plate solve.
    pub fn iterate(&mut self, iterations: u32) {
        let started = Instant::now();
        match &mut self.solver {
            Solver::Arap(arap) => {
                for _ in 0..iterations {
                    arap.iterate();
                }
                self.solving_seconds += started.elapsed().as_secs_f64();
                // The check is the local step that the next iteration, or the final energy's
                // measure, runs anyway: it is not an iteration's cost.
                arap.settle();
                self.iterations += iterations;
            }
            Solver::Laplace {
                plate,
                targets,
                positions,
            } => {
                *positions = plate.displace(targets);
                self.solving_seconds += started.elapsed().as_secs_f64();
            }
        }
    }

    /// The ARAP energy of the current positions with their best rotations (0 for the thin
    /// plate).
    pub fn energy(&mut self) -> f64 {
        match &mut self.solver {
            Solver::Arap(arap) => {
                arap.fit_rotations();
                arap.energy()
            }
            Solver::Laplace { .. } => 0.0,
        }
    }

    /// Makes each ARAP iteration measure the energy it starts from, for
    /// [`LiveDeform::last_energy`] (the editor shows it; a tenth of an iteration's cost or more).
    pub fn measure_each_iteration(&mut self) {
        if let Solver::Arap(arap) = &mut self.solver {
            arap.measure_each_iteration(true);
        }
    }

    /// The ARAP energy the last local step measured: of the positions the last iteration started
    /// from (the handle where that iteration placed it), or of those it left when its
    /// accelerated guess was checked ([`Arap::settle`]); `None` for the thin plate, before
    /// the first iteration, or without [`LiveDeform::measure_each_iteration`]. Free to ask,
    /// unlike [`LiveDeform::energy`].
    pub fn last_energy(&self) -> Option<f64> {
        match &self.solver {
            Solver::Arap(arap) if self.iterations > 0 && arap.measures_each_iteration() => {
                Some(arap.energy())
            }
            _ => None,
        }
    }

    /// Where every vertex that is not held goes, and the handle (exactly at its targets).
    ///
    /// # Refusals
    /// [`Refusal::NotFinite`] when a position came out not finite.
    pub fn moves(&self) -> Result<Vec<(VertexId, Vec3)>, Refusal> {
        let x = match &self.solver {
            Solver::Arap(arap) => arap.positions(),
            Solver::Laplace { positions, .. } => positions,
        };
        let mut moves: Vec<(VertexId, Vec3)> = self
            .handle
            .iter()
            .zip(&self.targets)
            .map(|(&r, &p)| (self.vertices[r as usize], p))
            .collect();
        for r in (0..self.vertices.len()).filter(|&r| !self.held[r]) {
            let p = x[r].as_vec3();
            if !p.is_finite() {
                return Err(Refusal::NotFinite(p));
            }
            moves.push((self.vertices[r], p));
        }
        Ok(moves)
    }

    /// The rotation the last local step (an iteration's, or [`LiveDeform::energy`]'s) fitted at
    /// each vertex that is not held, in [`LiveDeform::moves`]' order after the handle (identity
    /// before any; empty for the thin plate, which has none).
    pub fn free_rotations(&self) -> Vec<Quat> {
        let Solver::Arap(arap) = &self.solver else {
            return Vec::new();
        };
        arap.rotations()
            .zip(&self.held)
            .filter(|(_, held)| !**held)
            .map(|(q, _)| q.as_quat())
            .collect()
    }

    /// [`LiveDeform::place`], [`LiveDeform::iterate`] and [`LiveDeform::moves`]: one frame.
    ///
    /// # Refusals
    /// As [`LiveDeform::moves`].
    pub fn solve(
        &mut self,
        targets: &[Vec3],
        iterations: u32,
    ) -> Result<Vec<(VertexId, Vec3)>, Refusal> {
        self.place(targets);
        self.iterate(iterations);
        self.moves()
    }

    /// ARAP iterations run so far.
    pub fn iterations(&self) -> u32 {
        self.iterations
    }

    /// Vertices that move freely.
    pub fn free(&self) -> usize {
        self.held.iter().filter(|h| !**h).count()
    }

    /// Parts with nothing held, left where they are.
    pub fn loose_parts(&self) -> usize {
        self.loose_parts
    }

    /// Seconds spent building and factoring the system.
    pub fn factor_seconds(&self) -> f64 {
        self.factor_seconds
    }

    /// Seconds spent in [`LiveDeform::iterate`]'s iterations (or thin-plate solves) so far:
    /// each ARAP iteration's local step (with its check of the last accelerated guess), global
    /// step and acceleration, but not the check of the last guess, which is the local step the
    /// next iteration or [`LiveDeform::energy`] runs anyway.
    pub fn solving_seconds(&self) -> f64 {
        self.solving_seconds
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshMembers, MeshRef, build_mesh, shapes};

    #[test]
    fn a_live_arap_drag_leaves_the_anchors_and_lands_the_handle_every_frame() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(2), MeshInfo::default()).unwrap();
        let vertices = MeshMembers::collect(&world, built.mesh).vertices;
        let m = MeshRef::new(&world);
        let anchors: Vec<VertexId> = vertices
            .iter()
            .copied()
            .filter(|&v| m.position(v).y < -0.6)
            .collect();
        let handle: Vec<VertexId> = vertices
            .iter()
            .copied()
            .filter(|&v| m.position(v).y > 0.7)
            .collect();
        let start: Vec<Vec3> = handle.iter().map(|&v| m.position(v)).collect();
        let mut live =
            LiveDeform::new(&world, built.mesh, DeformMethod::Arap, &anchors, &handle).unwrap();
        // Ten frames, each a tenth further, one iteration each; then more at the end.
        let mut moves = Vec::new();
        for frame in 1..=10 {
            let t = Vec3::X * 0.05 * frame as f32;
            let targets: Vec<Vec3> = start.iter().map(|p| *p + t).collect();
            moves = live.solve(&targets, 1).unwrap();
        }
        assert_eq!(live.iterations(), 10);
        // Anchors are not moved; the handle is where it was sent.
        assert!(moves.iter().all(|(v, _)| !anchors.contains(v)));
        for (v, p) in &moves[..handle.len()] {
            let i = handle.iter().position(|h| h == v).unwrap();
            assert_eq!(*p, start[i] + Vec3::X * 0.5);
        }
        assert_eq!(moves.len(), vertices.len() - anchors.len());
    }
}
