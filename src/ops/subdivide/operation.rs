//! Loop and Catmull–Clark subdivision as registered operations (`loop[:LEVELS]`, L;
//! `catmull-clark[:LEVELS]`, Q). Each is a function of the mesh's tables, so besides applying
//! to the entities it computes on the tables alone ([`MeshOperation::run_on_tables`]): the
//! editor's jobs take that way and skip spawning a copy of the mesh.

use bevy::prelude::World;

use super::{CATMULL_CLARK, LOOP, Scheme, SubdivideSteps, SubdivisionSummary};
use crate::mesh::ids::MeshId;
use crate::mesh::tables::{Connectivity, MeshTables};
use crate::ops::Refusal;
use crate::ops::declaration::Declaration;
use crate::ops::operation::stepping::Steps;
use crate::ops::operation::{Applied, EditContext, Invocation, MeshOperation, Values};

/// Subdivision by `Scheme`, `LEVELS` levels at a time.
pub struct Subdivide(pub Scheme);

impl Scheme {
    /// The registered operation that subdivides by this scheme.
    pub fn operation(self) -> &'static Subdivide {
        match self {
            Scheme::Loop => &Subdivide(Scheme::Loop),
            Scheme::CatmullClark => &Subdivide(Scheme::CatmullClark),
        }
    }
}

/// The scheme and levels an invocation of a [`Subdivide`] asks for (`None` for any other
/// operation): what step mode previews level by level.
pub fn subdivision(invocation: &Invocation) -> Option<(Scheme, u32)> {
    let levels = invocation.values();
    [Scheme::Loop, Scheme::CatmullClark]
        .into_iter()
        .find(|s| invocation.is(s.operation().declaration()))
        .map(|scheme| (scheme, levels.whole(0)))
}

impl MeshOperation for Subdivide {
    fn declaration(&self) -> &'static Declaration {
        match self.0 {
            Scheme::Loop => &LOOP,
            Scheme::CatmullClark => &CATMULL_CLARK,
        }
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let s =
            self.0
                .subdivide_with_progress(world, mesh, values.whole(0), &mut *context.progress)?;
        (context.progress)(1.0);
        Ok(Applied::whole(s.describe()))
    }

    /// Two steps a level: its points previewed, then committed ([`SubdivideSteps`]).
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let steps = SubdivideSteps::start(world, mesh, self.0, values.whole(0));
        Some(steps.map(|s| Box::new(s) as Box<dyn Steps>))
    }

    fn run_on_tables(
        &self,
        before: &MeshTables,
        values: Values<'_>,
    ) -> Option<Result<(Connectivity, Applied), Refusal>> {
        let levels = values.whole(0);
        let after = self
            .0
            .subdivide_tables(&before.tables, &before.members, levels);
        Some(after.map(|after| {
            let summary = SubdivisionSummary::of(levels, &after).describe();
            (after, Applied::whole(summary))
        }))
    }
}
