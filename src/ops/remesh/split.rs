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

/// Splits every edge of `mesh` longer than `high` (4/3 L) at its midpoint, the long edges
/// listed before the first split; the halves of a split feature edge join `features`.
/// Returns how many.
pub(super) fn split_long(
    world: &mut World,
    mesh: MeshId,
    high: f32,
    features: &mut EntityHashSet,
) -> usize {
    // A split leaves every other edge as long as it was: the long ones can be listed first.
    let edges = EdgeTable::read(world, mesh).edges_where(|length| length > high);
    let mut splits = 0;
    for e in edges {
        let m = MeshRef::new(world);
        let feature = features.contains(&e.0);
        // The ends, read before the split: afterwards `e` is one of the halves.
        let (a, b) = m.edge_vertices(e);
        let Ok(v) = split_edge(world, e, 0.5) else {
            continue;
        };
        splits += 1;
        if feature {
            // Both halves of a feature edge stay features; the cuts across faces do not.
            let m = MeshRef::new(world);
            for h in m.vertex_outgoing(v) {
                let w = m.to_vertex(h);
                if w == a || w == b {
                    features.insert(m.edge(h).0);
                }
            }
        }
    }
    splits
}
