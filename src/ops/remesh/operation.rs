//! Isotropic remeshing as a registered operation (`remesh[:ITERATIONS][:LENGTH][:FEATURE]`,
//! M, the *Whole mesh* row): its values read into a [`RemeshParams`], then
//! [`remesh_with_progress`]. Step mode runs the same parameters pass by pass
//! ([`super::RemeshRun`]), reading them with [`Remesh::params`].

use bevy::prelude::World;

use super::{REMESH, RemeshParams, remesh_with_progress};
use crate::mesh::ids::MeshId;
use crate::ops::Refusal;
use crate::ops::declaration::Declaration;
use crate::ops::operation::stepping::Steps;
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

use super::RemeshSteps;

/// [`remesh_with_progress`] as an operation.
pub struct Remesh;

impl Remesh {
    /// The parameters its values name (iterations, target length or the mean edge length,
    /// feature angle), with the default smoothing steps.
    pub fn params(values: Values<'_>) -> RemeshParams {
        RemeshParams {
            iterations: values.whole(0),
            target_length: values.given(1).map(|l| l as f32),
            feature_angle_deg: values.number(2) as f32,
            ..RemeshParams::default()
        }
    }
}

impl MeshOperation for Remesh {
    fn declaration(&self) -> &'static Declaration {
        &REMESH
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let params = Self::params(values);
        let s = remesh_with_progress(world, mesh, &params, &mut *context.progress)?;
        Ok(Applied::whole(format!(
            "L {:.5}: {} splits, {} collapses, {} flips",
            s.target_length, s.splits, s.collapses, s.flips
        )))
    }

    /// A pass a step ([`RemeshSteps`]).
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let steps = RemeshSteps::start(world, mesh, &Self::params(values));
        Some(steps.map(|s| Box::new(s) as Box<dyn Steps>))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::operation::Invocation;

    #[test]
    fn its_defaults_are_the_parameters_defaults() {
        let defaults = Invocation::with_defaults(&Remesh);
        assert_eq!(Remesh::params(defaults.values()), RemeshParams::default());
        let given = Invocation::parse(&Remesh, "3:0.5:30").unwrap();
        let params = Remesh::params(given.values());
        assert_eq!(
            (
                params.iterations,
                params.target_length,
                params.feature_angle_deg
            ),
            (3, Some(0.5), 30.0)
        );
    }
}
