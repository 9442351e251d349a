//! Where a mesh's simplification history lives: a component on the mesh entity.
//!
//! The history ([`ProgressiveMesh`], Hoppe 1996) describes one mesh, so it sits on that mesh's
//! entity, beside [`crate::mesh::MeshInfo`], rather than in a field every operation is handed or
//! a resource of the editor's. A simplification puts it there; `refine` and a vertex split move
//! along it; any other edit ends it, by one rule, [`crate::edit::Edit::settle_history`], since
//! the history would no longer describe the mesh. A mesh despawned takes its history with it;
//! an undo or a cancelled run that puts a mesh back says what becomes of it (see the editor's
//! pipeline). The command line, Python and the editor all keep it here, so a world holding
//! several meshes holds a history for each.

use bevy::prelude::{Component, World};

use crate::mesh::ids::MeshId;
use crate::ops::Refusal;
use crate::ops::progressive::ProgressiveMesh;

/// The simplification history of the mesh entity it is on, while it still describes that
/// mesh.
#[derive(Component, Clone, Debug)]
pub struct SimplificationHistory(pub ProgressiveMesh);

impl SimplificationHistory {
    /// `mesh`'s history, if it has one.
    pub fn of(world: &World, mesh: MeshId) -> Option<&ProgressiveMesh> {
        world.get::<SimplificationHistory>(mesh.0).map(|h| &h.0)
    }

    /// The levels as the level-of-detail slider shows them: (coarsest, current, full) face
    /// counts of `mesh`'s history, if it has one.
    pub fn levels(world: &World, mesh: MeshId) -> Option<(usize, usize, usize)> {
        Self::of(world, mesh).map(|pm| {
            let coarsest = pm.full_faces - pm.records.iter().map(|r| r.faces).sum::<usize>();
            (coarsest, pm.faces(), pm.full_faces)
        })
    }

    /// Gives `mesh` the history `pm` (replacing the one it had). Does nothing when `mesh` is
    /// gone.
    pub fn keep(world: &mut World, mesh: MeshId, pm: ProgressiveMesh) {
        if let Ok(mut entity) = world.get_entity_mut(mesh.0) {
            entity.insert(SimplificationHistory(pm));
        }
    }

    /// Takes `mesh`'s history off it (to move along it with the world at hand, or to set it
    /// aside while a run may change the mesh).
    pub fn take(world: &mut World, mesh: MeshId) -> Option<ProgressiveMesh> {
        let mut entity = world.get_entity_mut(mesh.0).ok()?;
        entity.take::<SimplificationHistory>().map(|h| h.0)
    }

    /// Ends `mesh`'s history (the mesh was changed in a way it does not describe).
    pub fn end(world: &mut World, mesh: MeshId) {
        Self::take(world, mesh);
    }

    /// Runs `f` with `mesh`'s history and the world, then puts the history back whatever `f`
    /// returns (a move along it that stops half-way still leaves it describing the mesh).
    ///
    /// # Refusals
    /// [`Refusal::NoHistory`] when `mesh` has none; `f`'s own.
    pub fn move_along<T>(
        world: &mut World,
        mesh: MeshId,
        f: impl FnOnce(&mut ProgressiveMesh, &mut World) -> Result<T, Refusal>,
    ) -> Result<T, Refusal> {
        let mut pm = Self::take(world, mesh).ok_or(Refusal::NoHistory)?;
        let result = f(&mut pm, world);
        Self::keep(world, mesh, pm);
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::{Edit, EditContext};
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    fn run(world: &mut World, mesh: MeshId, edit: &Edit) -> Result<String, Refusal> {
        let mut context = EditContext {
            progress: &mut |_| true,
        };
        edit.run(world, mesh, &mut context).map(|a| a.summary)
    }

    #[test]
    fn each_mesh_keeps_its_own_history_and_only_its_own_edits_end_it() {
        let mut world = World::new();
        let a = build_mesh(&mut world, &shapes::icosphere(2), MeshInfo::default())
            .unwrap()
            .mesh;
        let b = build_mesh(&mut world, &shapes::icosphere(3), MeshInfo::default())
            .unwrap()
            .mesh;
        let half = Edit::invoked("simplify:0.5").unwrap();
        run(&mut world, a, &half).unwrap();
        run(&mut world, b, &half).unwrap();
        assert_eq!(
            SimplificationHistory::levels(&world, a),
            Some((160, 160, 320))
        );
        assert_eq!(
            SimplificationHistory::levels(&world, b),
            Some((640, 640, 1280))
        );
        // Moving along a's history moves a alone.
        run(&mut world, a, &Edit::invoked("refine:200").unwrap()).unwrap();
        assert_eq!(
            SimplificationHistory::levels(&world, a),
            Some((160, 200, 320))
        );
        // An edit that does not keep the history ends the history of its mesh only.
        run(&mut world, a, &Edit::invoked("smooth").unwrap()).unwrap();
        assert!(SimplificationHistory::of(&world, a).is_none());
        assert!(SimplificationHistory::of(&world, b).is_some());
        // Refining without a history is refused and changes nothing.
        let refine = Edit::invoked("refine").unwrap();
        assert!(matches!(
            run(&mut world, a, &refine),
            Err(Refusal::NoHistory)
        ));
        run(&mut world, b, &refine).unwrap();
        assert_eq!(
            SimplificationHistory::levels(&world, b),
            Some((640, 1280, 1280))
        );
    }
}
