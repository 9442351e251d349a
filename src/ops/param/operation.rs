//! Parameterization as a registered operation (`param[:METHOD][:BOUNDARY]`, Shift+U, the UV
//! section's row): the method and the boundary shape as choices, read into a
//! [`ParamParams`], then [`parameterize_in_place`] with the seams the mesh marks.

use bevy::prelude::World;

use super::parameterize_in_place;
use super::params::{BoundaryShape, ParamMethod, ParamParams};
use crate::mesh::ids::MeshId;
use crate::ops::Refusal;
use crate::ops::declaration::{Declaration, Parameter, Section};
use crate::ops::named::Named;
use crate::ops::operation::{Applied, EditContext, MeshOperation, Values};

/// The methods' words, in [`ParamMethod::ALL`]'s order (a test checks it).
const METHODS: &[&str] = &["uniform", "mean-value", "harmonic", "lscm"];

/// The boundary shapes' words, in [`BoundaryShape::ALL`]'s order (a test checks it).
const SHAPES: &[&str] = &["circle", "square"];

/// Parameterization: a job on a large mesh; only UVs change.
pub const PARAMETERIZE: Declaration = Declaration::new("param")
    .titled("Parameterize")
    .described(
        "unwrap the mesh onto the plane, a UV per corner: Tutte (uniform), mean-value, harmonic \
         or LSCM; a fixed boundary on a circle or a square; cut along the marked seams",
    )
    .on_key("Shift+U")
    .with_parameters(&[
        Parameter::choice("METHOD", METHODS, 1),
        Parameter::choice("BOUNDARY", SHAPES, 0),
    ])
    .in_section(Section::Uv)
    .as_job();

/// [`parameterize_in_place`] as an operation.
pub struct Parameterize;

impl Parameterize {
    /// The parameters its values name: the method and the boundary shape, no seams given (the
    /// mesh's marks are used), the automatic cut on.
    pub fn params(values: Values<'_>) -> ParamParams {
        let mut params = ParamParams::new(ParamMethod::ALL[values.choice(0)].0);
        params.boundary = BoundaryShape::ALL[values.choice(1)].0;
        params
    }
}

impl MeshOperation for Parameterize {
    fn declaration(&self) -> &'static Declaration {
        &PARAMETERIZE
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let r = parameterize_in_place(world, mesh, &Self::params(values), &mut *context.progress)?;
        (context.progress)(1.0);
        let cut = match (r.seam_edges, r.filled_holes) {
            (0, 0) => String::new(),
            (0, h) => format!(", {h} inner holes filled for the solve"),
            (s, _) => format!(", cut along {s} edges"),
        };
        let degenerate = match r.degenerate {
            0 => String::new(),
            n => format!(" ({n} laid flat)"),
        };
        Ok(Applied::whole(format!(
            "{} flipped of {} triangles{degenerate}, angle distortion {:.2}°, area distortion \
             {:.3}, conformal energy {:.4}{cut}",
            r.flipped, r.triangles, r.angle_distortion_deg, r.area_distortion, r.conformal_energy
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_declared_words_are_the_methods_and_shapes_in_order() {
        fn names<T>(all: &[(T, &'static str)]) -> Vec<&'static str> {
            all.iter().map(|x| x.1).collect()
        }
        assert_eq!(names(ParamMethod::ALL), METHODS);
        assert_eq!(names(BoundaryShape::ALL), SHAPES);
        let d = &PARAMETERIZE;
        assert_eq!(
            d.parameters[0].write(d.parameters[0].default),
            ParamMethod::default().name()
        );
        assert_eq!(
            d.parameters[1].write(d.parameters[1].default),
            BoundaryShape::default().name()
        );
    }
}
