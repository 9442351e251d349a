//! Despawning many elements without Bevy's removal log growing with them.
//!
//! Bevy logs every component of every despawned entity (the log `RemovedComponents` reads),
//! and only [`World::clear_trackers`] empties it: an app calls it once a frame, a bare world
//! (the command line's, a job's scratch copy) never, and within one frame a bulk edit despawns
//! millions of elements. Simplifying a 1.1 M-face scan to 10 % kept 263 MB of log entries, a
//! sixth of its peak memory. Nothing in Pappus reads that log or compares changes against the
//! world's last change tick, so a [`Despawner`] clears the trackers every [`CLEAR_EVERY`]
//! despawns: the log then never holds more than that many entries a component.

use bevy::prelude::{Entity, World};

/// Despawns between two clearings of the trackers.
pub const CLEAR_EVERY: usize = 1 << 16;

/// Despawns entities one by one, clearing the world's trackers every [`CLEAR_EVERY`] of them.
pub struct Despawner<'w> {
    world: &'w mut World,
    since_clear: usize,
}

impl<'w> Despawner<'w> {
    /// A despawner for `world`.
    pub fn new(world: &'w mut World) -> Self {
        Self {
            world,
            since_clear: 0,
        }
    }

    /// Despawns `e` (nothing if it is not spawned), as [`World::despawn`] does.
    pub fn despawn(&mut self, e: Entity) {
        self.world.despawn(e);
        self.since_clear += 1;
        if self.since_clear == CLEAR_EVERY {
            // The log is double-buffered: the second update drops what the first kept.
            self.world.clear_trackers();
            self.world.clear_trackers();
            self.since_clear = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Position;

    #[test]
    fn a_bulk_despawn_keeps_no_more_than_a_batch_of_removals_logged() {
        let mut world = World::new();
        let n = 3 * CLEAR_EVERY + 5;
        let ids: Vec<Entity> = world
            .spawn_batch(std::iter::repeat_n(Position(bevy::math::Vec3::ZERO), n))
            .collect();
        let mut despawner = Despawner::new(&mut world);
        for &e in &ids {
            despawner.despawn(e);
        }
        assert!(ids.iter().all(|&e| world.get_entity(e).is_err()));
        let logged = world.removed::<Position>().count();
        assert!(logged <= CLEAR_EVERY, "{logged} removals still logged");
    }
}
