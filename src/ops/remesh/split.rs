//! Step 1 of an iteration (Botsch & Kobbelt 2004): split every edge longer than 4/3 L at its
//! midpoint.
//!
//! The long edges are listed once, before the first split (a split leaves every other edge as
//! long as it was), so the pass is bounded; an edge a split leaves longer than 4/3 L waits for
//! the next iteration. Both halves of a split feature edge stay features; the new edges across
//! the faces do not.

use bevy::ecs::entity::EntityHashSet;
use bevy::prelude::World;

use crate::mesh::ids::MeshId;
use crate::mesh::topology::MeshRef;
use crate::ops::local::split_edge;

use super::EdgeTable;
use super::pass::Touched;

/// Splits every edge of `mesh` longer than `high` (4/3 L) at its midpoint, the long edges
/// listed before the first split; the halves of a split feature edge join `features`.
/// Returns the new vertices and the edges around each as its split left them (a split adds
/// and removes no other element, so all stay alive through the pass); the count of splits is
/// the count of vertices.
pub(super) fn split_long(
    world: &mut World,
    mesh: MeshId,
    high: f32,
    features: &mut EntityHashSet,
) -> Touched {
    // A split leaves every other edge as long as it was: the long ones can be listed first.
    let edges = EdgeTable::read(world, mesh).edges_where(|length| length > high);
    let mut touched = Touched::default();
    for e in edges {
        let m = MeshRef::new(world);
        let feature = features.contains(&e.0);
        // The ends, read before the split: afterwards `e` is one of the halves.
        let (a, b) = m.edge_vertices(e);
        let Ok(v) = split_edge(world, e, 0.5) else {
            continue;
        };
        touched.vertices.push(v);
        let m = MeshRef::new(world);
        for h in m.vertex_outgoing(v) {
            let spoke = m.edge(h);
            touched.edges.push(spoke);
            // Both halves of a feature edge stay features; the cuts across faces do not.
            let w = m.to_vertex(h);
            if feature && (w == a || w == b) {
                features.insert(spoke.0);
            }
        }
    }
    touched
}
