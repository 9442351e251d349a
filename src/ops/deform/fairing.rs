//! Fairing as a registered operation ([`FAIR`]): the `fair:VERTICES[:K]` step, Shift+O on the
//! selected vertices and its row in the panel's *Shape* section. The solve is
//! [`super::fair`]'s: the named vertices take the k-harmonic positions, every other vertex held.

use bevy::prelude::World;

use crate::mesh::ids::MeshId;
use crate::ops::Refusal;
use crate::ops::declaration::{Declaration, Names, Parameter, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Redraw, Values, count};

use super::{FairParams, fair, loose_note};

/// Fairing the named vertices: only their positions change.
pub const FAIR: Declaration = Declaration::new("fair")
    .titled("Fair")
    .described(
        "move the vertices to solve the k-harmonic equation, the rest held \
         (K 1 membrane, 2 thin plate, 3 minimum variation)",
    )
    .on_key("Shift+O")
    .naming(Names::Vertices)
    .with_parameters(&[Parameter::whole("K", 2, 1, 3)])
    .in_section(Section::Shape);

/// Fairing, declared by [`FAIR`].
pub struct Fair;

impl MeshOperation for Fair {
    fn declaration(&self) -> &'static Declaration {
        &FAIR
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let params = FairParams {
            vertices: values.vertices(),
            k: values.whole(0),
        };
        let s = fair(world, mesh, &params)?;
        Ok(Applied {
            summary: format!(
                "{} faired (k = {}), moved {:.3e} on average{}",
                count(s.free, "vertex"),
                params.k,
                s.mean_move,
                loose_note(s.loose_parts)
            ),
            redraw: Redraw::near(world, Vec::new(), params.vertices),
            made: None,
        })
    }

    /// The named vertices, and nothing else (`None` when one is gone).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        Reach::vertices(world, values.vertices())
    }
}
