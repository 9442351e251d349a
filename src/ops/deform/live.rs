//! A handle deformation that runs while the handle is dragged: the system is factored once for
//! its anchors and handle ([`LiveDeform::new`]), then each frame places the handle and runs one
//! as-rigid-as-possible iteration from the last frame's result (or the one thin-plate solve),
//! the editor's `G` / `R` / `S` with anchors marked.

use bevy::math::{DVec3, Vec3};
use bevy::prelude::World;

use crate::mesh::MeshInfo;
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::tables::extract;
use crate::ops::Refusal;
use crate::ops::geometry::{Surface, cotan_edges, mixed_areas};

use super::system::{HeldSystem, k_harmonic};
use super::{Arap, DeformMethod, hold_loose_parts};

enum Solver {
    Arap(Box<Arap>),
    Laplace {
        system: HeldSystem,
        rest: Vec<DVec3>,
    },
}

/// A handle deformation in progress (see the module doc).
pub struct LiveDeform {
    solver: Solver,
    /// The vertex behind each row.
    vertices: Vec<VertexId>,
    /// The handle's rows, in the order [`LiveDeform::new`] was given them.
    handle: Vec<u32>,
    /// Rows that are held (anchors, the handle, parts with nothing held).
    held: Vec<bool>,
    /// ARAP iterations run so far.
    iterations: u32,
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
    /// handle's), and factors its system.
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
        let edges = cotan_edges(&surface);
        hold_loose_parts(n, &edges, &mut held);
        let solver = match method {
            DeformMethod::Arap => Solver::Arap(Box::new(Arap::new(&surface, &held)?)),
            DeformMethod::Laplace => Solver::Laplace {
                system: HeldSystem::new(&k_harmonic(n, &edges, &mixed_areas(&surface), 2), &held)?,
                rest: surface.positions,
            },
        };
        Ok(Self {
            solver,
            vertices: read.members.vertices,
            handle,
            held,
            iterations: 0,
        })
    }

    /// Places the handle's vertices at `targets` (in the handle's order) and solves: `iterations`
    /// ARAP iterations from the last result, or the thin-plate solve. Returns where every vertex
    /// that is not an anchor goes (the handle exactly at its targets).
    pub fn solve(&mut self, targets: &[Vec3], iterations: u32) -> Vec<(VertexId, Vec3)> {
        let placed = self
            .handle
            .iter()
            .zip(targets)
            .map(|(&r, p)| (r, p.as_dvec3()));
        let x: Vec<DVec3> = match &mut self.solver {
            Solver::Arap(arap) => {
                arap.place(placed);
                for _ in 0..iterations {
                    arap.iterate();
                }
                self.iterations += iterations;
                arap.positions().to_vec()
            }
            Solver::Laplace { system, rest } => {
                let mut d = vec![DVec3::ZERO; rest.len()];
                for (r, p) in placed {
                    d[r as usize] = p - rest[r as usize];
                }
                system.solve(None, &mut d);
                rest.iter().zip(&d).map(|(p, d)| *p + *d).collect()
            }
        };
        let mut moves: Vec<(VertexId, Vec3)> = self
            .handle
            .iter()
            .zip(targets)
            .map(|(&r, &p)| (self.vertices[r as usize], p))
            .collect();
        moves.extend(
            (0..self.vertices.len())
                .filter(|&r| !self.held[r] && x[r].as_vec3().is_finite())
                .map(|r| (self.vertices[r], x[r].as_vec3())),
        );
        moves
    }

    /// ARAP iterations run so far.
    pub fn iterations(&self) -> u32 {
        self.iterations
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
            moves = live.solve(&targets, 1);
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
