//! A simplification's last move, when asked for
//! ([`SimplifyParams::fit_to_input`](super::SimplifyParams::fit_to_input)): its
//! vertices fitted to the input by one least-squares step ([`surface_fit`]).
//!
//! The quadrics put a merged vertex where the summed squared distances to the planes it
//! gathered are least, which is not where the farthest point of the input from the result is
//! least: a bump one vertex wide, a crease drawn with small triangles, a stretch of the scan
//! that bends within a triangle of the result all end up on one side of it. One step of the fit
//! moves each vertex along its normal by the mean of the gaps around it, each weighted by its
//! length, measured both ways against the input as it was at the start, so that the result
//! straddles the input where it lay on one side:
//! - from the result, the centres of every other input triangle: half the input's points, which
//!   pulled the result less hard towards the input than all of them did, against the other way
//!   round, and came out closer (the bunny at a quarter of its faces 0.079 → 0.075 % of its
//!   diagonal, the spot 0.312 → 0.286 %, the bunny disk 0.096 → 0.088 %; homer, the teapot,
//!   the beast, the cow and suzanne within 0.003 %) in half the searches;
//! - from the input, the result's vertices and edge middles: its vertices stand where the
//!   quadrics put them, off the input, where the remesh's lie on it; its triangle centres
//!   besides added nothing (the bunny 0.078 against 0.079 %, homer 0.184 against 0.183 %).
//!
//! Boundary vertices stay, and so does every vertex that no collapse kept: the simplification
//! history ([`crate::ops::progressive`]) keeps a vertex's place at the coarsest level as the
//! merged position of the last collapse that kept it, so only such a vertex can move and still
//! be found there again (`ProgressiveMesh::settle_coarsest`). The corners of sharp edges move:
//! held, as the remesh holds its feature corners, they kept the bunny's farthest spot (a bump
//! the result's edges meet at over 45°) where it was, 0.092 %. No move turns a triangle over;
//! the remesh's guard against thin triangles is left off, since the quadrics leave many thin
//! already, and with it half the moves were cancelled.
//!
//! The stepped run ([`super::QemRun`]) reads the mesh's elements ([`InputSurface::fit`]); the
//! one-go run ([`super::simplify`]) reads the same elements from its own rows, so that the
//! searches run while it writes the rows back into the entities ([`InputSurface::moves`]).
//! The fit takes the elements by entity, whatever order they were read in, so stepping to the
//! end gives the same bits.
//!
//! [`surface_fit`]: crate::ops::geometry::surface_fit

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use crate::mesh::ids::MeshId;
use crate::mesh::tables::{Connectivity, MeshTables, extract};
use crate::ops::geometry::closest::Reference;
use crate::ops::geometry::surface_fit::{FitElements, FitOptions, apply_moves};

/// What the simplification's fit measures of the result besides its edge middles: its
/// vertices, not its triangle centres; it leaves thin triangles as the quadrics made them, and
/// takes the elements in entity order, which the one-go and the stepped run share.
const SIMPLIFICATION_FIT: FitOptions = FitOptions {
    centres_sampled: false,
    vertices_sampled: true,
    keep_fat: false,
    entity_order: true,
};

/// The input as the fit measures against it: its triangles' grid, and the points of it
/// measured to the result (the centres of every other triangle).
pub(crate) struct InputSurface {
    reference: Reference,
    points: Vec<Vec3>,
}

impl InputSurface {
    /// The triangles of the mesh in `t`, before any collapse.
    pub fn of_tables(t: &Connectivity) -> Self {
        let reference = Reference::of_tables(t);
        let points = reference
            .triangles()
            .iter()
            .step_by(2)
            .map(|&[a, b, c]| (a + b + c) / 3.0)
            .collect();
        Self { reference, points }
    }

    /// Fits the simplified `mesh` to this input (see the module doc): boundary vertices and
    /// the vertices in `unmoved` stay. Leaves the connectivity as it was, and no triangle
    /// turned over.
    pub fn fit(&self, world: &mut World, mesh: MeshId, unmoved: &EntityHashSet) {
        let MeshTables { tables: t, members } = extract(world, mesh);
        let held: Vec<bool> = t
            .vertices()
            .map(|v| t.is_boundary_vertex(v) || unmoved.contains(&members.vertices[v.index()].0))
            .collect();
        let moves = self.moves(&FitElements::of_tables(&t, &members, &held));
        apply_moves(world, &moves);
    }

    /// The moves that fit the simplified mesh's `elements` to this input, as [`Self::fit`]
    /// makes them, the held vertices staying; the same moves whether the elements were read
    /// from the mesh or from the simplification's rows, since the fit takes them by entity.
    pub fn moves(&self, elements: &FitElements) -> Vec<(Entity, Vec3)> {
        elements.fitted_moves(&self.reference, &self.points, SIMPLIFICATION_FIT)
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::{MeshInfo, build_mesh, shapes, validate};
    use crate::ops::simplify::{SimplifyParams, simplify};
    use bevy::prelude::World;

    #[test]
    fn a_vertex_far_out_leaves_a_fitted_simplification_valid_and_ended() {
        // One vertex of a grid 1e30 out along x: the triangles round it are so long that the
        // searches' distances to them overflow, and one search walked some 1e10 cells.
        let mut soup = shapes::grid(16, 16);
        soup.positions[40].x = 1e30;
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let params = SimplifyParams {
            fit_to_input: true,
            ..SimplifyParams::ratio(0.5)
        };
        let summary = simplify(&mut world, mesh, &params).unwrap();
        assert!(summary.faces_after < summary.faces_before, "{summary:?}");
        assert_eq!(validate(&world, mesh), Ok(()));
    }
}
