//! Seam marks: an edge marked as a seam is one the parameterization cuts the surface along
//! ([`crate::ops::param`]). Marking changes no connectivity and no position; the mesh's
//! attribute record says it may have seams from the first mark on, so a save writes them.

use bevy::prelude::World;

use crate::mesh::InMesh;
use crate::mesh::attributes::{MeshAttributes, Seam, set_record};
use crate::mesh::ids::{EdgeId, ElementId, MeshId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Redraw, Values};

/// Marks `e` as a seam, or unmarks it; returns whether it is one now.
///
/// # Refusals
/// [`Refusal::Stale`] when `e` is not a live edge.
pub fn toggle_seam(world: &mut World, e: EdgeId) -> Result<bool, Refusal> {
    let Some(mesh) = world
        .get::<crate::mesh::Edge>(e.0)
        .and_then(|_| world.get::<InMesh>(e.0))
        .map(|m| m.0)
    else {
        return Err(Refusal::Stale(ElementId::Edge(e)));
    };
    let mut edge = world.entity_mut(e.0);
    let marked = !edge.contains::<Seam>();
    if marked {
        edge.insert(Seam);
        let mut has = MeshAttributes::of(world, mesh);
        has.seams = true;
        set_record(world, mesh, has);
    } else {
        edge.remove::<Seam>();
    }
    Ok(marked)
}

/// Marking a seam (or unmarking it): a local edit of one edge's mark.
pub const SEAM: Declaration = Declaration::new("seam")
    .titled("Seam")
    .described("mark the selected edge as a seam for parameterizing (or unmark it)")
    .on_key("Ctrl+E")
    .naming(Names::Edge)
    .in_section(Section::Uv)
    .keeping_normals();

/// [`toggle_seam`] as a registered operation: `seam:A,B`, Ctrl+E.
pub struct ToggleSeam;

impl MeshOperation for ToggleSeam {
    fn declaration(&self) -> &'static Declaration {
        &SEAM
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        let marked = toggle_seam(world, e)?;
        Ok(Applied {
            summary: if marked {
                format!("{e} is a seam")
            } else {
                format!("{e} is no longer a seam")
            },
            redraw: Redraw::near(world, Vec::new(), MeshRef::new(world).corners(e.into())),
            made: None,
        })
    }
}
