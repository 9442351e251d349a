//! Which edits step mode runs a step at a time, and the run each starts: an operation that
//! declares it ([`crate::ops::declaration::Declaration::stepping`]) through its own
//! [`crate::ops::operation::MeshOperation::step_through`], and an as-rigid-as-possible handle
//! deformation ([`DeformSteps`]), which is a gesture's edit rather than an operation.

use bevy::prelude::World;

use super::Edit;
use crate::mesh::ids::MeshId;
use crate::ops::Refusal;
use crate::ops::deform::{DeformMethod, DeformSteps};
use crate::ops::operation::stepping::Steps;

impl Edit {
    /// Whether step mode can run it a step at a time.
    pub fn can_step(&self) -> bool {
        match self {
            Edit::Operation(op) => op.declaration().steps,
            Edit::Deform(params) => params.method == DeformMethod::Arap,
            Edit::Move(_) => false,
        }
    }

    /// A run of it a step at a time on `mesh`, before its first step.
    ///
    /// # Refusals
    /// An edit that cannot be stepped ([`Edit::can_step`]); the operation's own refusal. The
    /// world is then as it was.
    pub fn step_through(&self, world: &mut World, mesh: MeshId) -> Result<Box<dyn Steps>, Refusal> {
        let cannot =
            || Refusal::BadParameter(format!("{} cannot be stepped through", self.label()));
        match self {
            Edit::Operation(op) => op
                .operation()
                .step_through(world, mesh, op.values())
                .ok_or_else(cannot)?,
            Edit::Deform(params) if self.can_step() => {
                Ok(Box::new(DeformSteps::start(world, mesh, params)?))
            }
            _ => Err(cannot()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use crate::ops::operation::Invocation;
    use crate::ops::registry::operations;

    #[test]
    fn an_operation_steps_exactly_when_it_declares_it() {
        for op in operations().iter() {
            let mut world = World::new();
            let mesh = build_mesh(&mut world, &shapes::icosahedron(), MeshInfo::default())
                .unwrap()
                .mesh;
            let invocation = Invocation::with_defaults(*op);
            if !invocation.declaration().names.is_whole_mesh() {
                // A local operation names elements: none declares stepping.
                assert!(!invocation.declaration().steps, "{}", invocation.label());
                continue;
            }
            let run = op.step_through(&mut world, mesh, invocation.values());
            assert_eq!(
                run.is_some(),
                invocation.declaration().steps,
                "{}",
                invocation.label()
            );
        }
    }
}
