//! Handle deformation: with [`Anchors`] marked (Shift+A), a move, rotation or scale of the
//! selection (the handle) deforms the rest of the mesh, the anchors held
//! ([`crate::ops::deform::LiveDeform`], Sorkine & Alexa 2007 for as-rigid-as-possible). The
//! system is factored when the gesture starts ([`handle_deformation`]); each frame runs one
//! iteration from the last frame's result, confirming runs [`FINAL_ITERATIONS`] more. In step
//! mode the gesture moves the handle alone and confirming hands the same deformation to a
//! stepped run of [`STEPPED_ITERATIONS`] iterations ([`stepped_deformation`]).

use bevy::math::Affine3A;
use bevy::prelude::*;

use crate::edit::Edit;
use crate::mesh::ids::VertexId;
use crate::mesh::topology::MeshRef;
use crate::ops::deform::{DeformMethod, DeformParams, LiveDeform};

/// ARAP iterations run when a handle deformation is confirmed (one runs each frame before).
pub const FINAL_ITERATIONS: u32 = 10;

/// ARAP iterations a handle deformation confirmed in step mode may be stepped through.
pub const STEPPED_ITERATIONS: u32 = 100;

/// The fixed region of handle deformation (Shift+A marks the selection's vertices), and how the
/// rest follows the handle.
#[derive(Resource, Default, Debug, Clone)]
pub struct Anchors {
    /// The anchors; none: gestures move the selection alone.
    pub vertices: Vec<VertexId>,
    /// As-rigid-as-possible or thin plate.
    pub method: DeformMethod,
    /// The last handle deformation's ARAP iterations and energy, for the panel.
    pub progress: Option<DeformProgress>,
}

/// How far an as-rigid-as-possible handle deformation has come.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeformProgress {
    /// Iterations run since the gesture started (one a frame, more on confirm).
    pub iterations: u32,
    /// The energy the last iteration's local step measured ([`LiveDeform::last_energy`]).
    pub energy: f64,
}

impl std::fmt::Display for DeformProgress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ARAP iterations, energy {:.4e}",
            self.iterations, self.energy
        )
    }
}

impl DeformProgress {
    /// The progress of `live`, once it has run an ARAP iteration.
    pub fn of(live: &LiveDeform) -> Option<Self> {
        Some(Self {
            iterations: live.iterations(),
            energy: live.last_energy()?,
        })
    }
}

/// The handle deformation a move, rotation or scale of the vertices `start` starts when anchors
/// are marked (none otherwise), its system factored.
///
/// # Errors
/// When the system cannot be factored (a part with nothing held is held whole, so this is a
/// degenerate mesh).
pub fn handle_deformation(
    world: &World,
    start: &[(VertexId, Vec3)],
) -> Result<Option<Box<LiveDeform>>, crate::ops::Refusal> {
    let Some(anchors) = world.get_resource::<Anchors>() else {
        return Ok(None);
    };
    let mesh = start
        .first()
        .and_then(|(v, _)| world.get::<crate::mesh::InMesh>(v.0))
        .map(|m| m.0);
    let (Some(mesh), false) = (mesh, anchors.vertices.is_empty()) else {
        return Ok(None);
    };
    let handle: Vec<VertexId> = start.iter().map(|(v, _)| *v).collect();
    let fixed = anchors_apart_from(world, &handle);
    let mut live = LiveDeform::new(world, mesh, anchors.method, &fixed, &handle)?;
    live.measure_each_iteration();
    Ok(Some(Box::new(live)))
}

/// The live anchors that are not part of `handle`.
fn anchors_apart_from(world: &World, handle: &[VertexId]) -> Vec<VertexId> {
    let handle_set: bevy::ecs::entity::EntityHashSet = handle.iter().map(|v| v.0).collect();
    let m = MeshRef::new(world);
    world
        .get_resource::<Anchors>()
        .map(|anchors| {
            anchors
                .vertices
                .iter()
                .copied()
                .filter(|v| m.try_vertex(*v).is_some() && !handle_set.contains(&v.0))
                .collect()
        })
        .unwrap_or_default()
}

/// The stepped run a handle deformation confirmed in step mode asks for: the same
/// as-rigid-as-possible deformation of `handle` by `motion`, from the mesh as it was before the
/// gesture, for [`STEPPED_ITERATIONS`] iterations.
pub fn stepped_deformation(world: &World, handle: Vec<VertexId>, motion: Affine3A) -> Edit {
    Edit::Deform(DeformParams {
        method: DeformMethod::Arap,
        fixed: anchors_apart_from(world, &handle),
        handle,
        motion,
        iterations: STEPPED_ITERATIONS,
    })
}
