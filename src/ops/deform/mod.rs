//! Shape editing that moves vertices and keeps the connectivity: handle deformation and fairing
//! (Botsch, Kobbelt, Pauly, Alliez & Lévy, *Polygon Mesh Processing*, ch. 9 "Deformation" and
//! §4.3 "Fairing").
//!
//! - **Laplacian (thin-plate) deformation** ([`DeformMethod::Laplace`]): the displacement `d`
//!   that minimises the thin-plate energy `∫ ‖Δd‖²`, discretised as `L M⁻¹ L d = 0` over the free
//!   vertices ([`system`]), with `d` zero on the anchors and the handle's motion on the handle.
//!   One sparse solve; linear precision (an affine motion of every held vertex of a flat patch
//!   moves it affinely), but rotations of the handle shear the detail rather than turn it.
//! - **As-rigid-as-possible** ([`DeformMethod::Arap`], [`arap`]): Sorkine & Alexa's local/global
//!   iterations, which turn the detail with the surface.
//! - **Fairing** ([`fair`]): the free vertices solve the k-harmonic equation
//!   `L (M⁻¹ L)^(k−1) x = 0` (PMP's `fair(mesh, k)`: k = 1 membrane, 2 thin plate, 3 minimum
//!   variation), every other vertex held where it is.
//!
//! - **Proportional editing** ([`falloff`]): the weights by which unselected vertices follow a
//!   transform of the selection.
//!
//! Weights are the cotangent weights of the fanned triangles ([`crate::ops::geometry::cotan`]),
//! areas the mixed Voronoi areas. A part of the mesh with no held vertex cannot be placed by
//! either solve (its position is free up to a translation), so such parts stay where they are and
//! the summary says how many. Held vertices are never written: they keep their positions to the
//! bit, and the handle lands exactly where its motion sends it.

mod anderson;
mod arap;
mod fairing;
mod falloff;
mod live;
mod region;
mod rotation;
mod stepping;
mod system;

use crate::ops::declaration::Declaration;

/// Handle deformation (ARAP or thin plate): only positions change.
pub const DEFORM: Declaration = Declaration::new("deform");

#[cfg(test)]
mod tests;

use bevy::ecs::entity::EntityHashSet;
use bevy::math::{Affine3A, DVec3, Vec3};
use bevy::prelude::World;

use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::{InMesh, MeshInfo, MeshRef, Position};

use super::Refusal;
use super::geometry::{Surface, cotan_edges, mixed_areas};
use super::named::Named;

pub use arap::Arap;
pub use fairing::{FAIR, Fair};
pub use falloff::{Falloff, Proportional, distances};
pub use live::LiveDeform;
pub use region::Region;
pub use rotation::closest_rotation;
pub use stepping::{DeformIteration, DeformSteps, FRAME_SIZE};
pub use system::{HeldSystem, k_harmonic};

/// How a handle's motion spreads over the free vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DeformMethod {
    /// The thin-plate displacement: one linear solve.
    Laplace,
    /// As-rigid-as-possible: local/global iterations.
    #[default]
    Arap,
}

impl Named for DeformMethod {
    const ALL: &'static [(Self, &'static str)] = &[
        (DeformMethod::Arap, "arap"),
        (DeformMethod::Laplace, "laplace"),
    ];
}

/// A handle deformation: which vertices stay, which move and how, and how far to iterate.
#[derive(Clone, Debug, PartialEq)]
pub struct DeformParams {
    /// The method. Default ARAP.
    pub method: DeformMethod,
    /// The anchors: they do not move.
    pub fixed: Vec<VertexId>,
    /// The handle: each of its vertices goes where `motion` sends it.
    pub handle: Vec<VertexId>,
    /// The handle's motion (a translation from the command line; any affine map from the
    /// editor's gestures).
    pub motion: Affine3A,
    /// ARAP iterations (1–10 000). Default [`DeformParams::DEFAULT_ITERATIONS`]. Ignored by the
    /// Laplacian method.
    pub iterations: u32,
}

impl DeformParams {
    /// ARAP iterations when none are given.
    pub const DEFAULT_ITERATIONS: u32 = 10;
    /// The most ARAP iterations one edit runs.
    pub const MAX_ITERATIONS: u32 = 10_000;
}

/// What a deformation did, measured as it ran.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeformSummary {
    /// Vertices that moved freely.
    pub free: usize,
    /// ARAP iterations run (0 for the Laplacian method).
    pub iterations: u32,
    /// The ARAP energy of the starting guess (the rest pose with the held vertices placed), and
    /// after the last iteration, each with its best rotations; 0 for the Laplacian method.
    pub energy_before: f64,
    /// See `energy_before`.
    pub energy: f64,
    /// Seconds spent building and factoring the system.
    pub factor_seconds: f64,
    /// Seconds per ARAP iteration (local and global step), or for the one Laplacian solve.
    pub iteration_seconds: f64,
    /// Parts of the mesh with no held vertex, left where they were.
    pub loose_parts: usize,
}

/// Fairing parameters: the vertices that move, and the order of the equation.
#[derive(Clone, Debug, PartialEq)]
pub struct FairParams {
    /// The vertices that move; all others are held.
    pub vertices: Vec<VertexId>,
    /// 1 (membrane), 2 (thin plate, the default) or 3 (minimum variation).
    pub k: u32,
}

/// What a fairing did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FairSummary {
    /// Vertices that moved.
    pub free: usize,
    /// The mean distance they moved.
    pub mean_move: f64,
    /// Parts of the mesh with no held vertex, left where they were.
    pub loose_parts: usize,
}

/// Holds every vertex of each part of the surface (connected through its triangles' edges)
/// that has no held vertex; returns how many parts that was.
fn hold_loose_parts(n: usize, edges: &[(u32, u32, f64)], held: &mut [bool]) -> usize {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for &(i, j, _) in edges {
        let (a, b) = (root(&mut parent, i), root(&mut parent, j));
        if a != b {
            parent[a as usize] = b;
        }
    }
    let mut anchored = vec![false; n];
    for (v, _) in held.iter().enumerate().filter(|(_, h)| **h) {
        let r = root(&mut parent, v as u32);
        anchored[r as usize] = true;
    }
    let mut loose = vec![false; n];
    for (v, h) in held.iter_mut().enumerate() {
        let r = root(&mut parent, v as u32) as usize;
        if !anchored[r] {
            loose[r] = true;
            *h = true;
        }
    }
    loose.iter().filter(|x| **x).count()
}

/// Checks a deformation's parameters and factors its system on `mesh` as it is (the rest pose):
/// the [`LiveDeform`] and where the motion sends each handle vertex, in the handle's order.
///
/// # Refusals
/// As [`deform`]'s.
pub fn prepare(
    world: &World,
    mesh: MeshId,
    params: &DeformParams,
) -> Result<(LiveDeform, Vec<Vec3>), Refusal> {
    let iterations_ok = (1..=DeformParams::MAX_ITERATIONS).contains(&params.iterations);
    if params.method == DeformMethod::Arap && !iterations_ok {
        return Err(Refusal::BadParameter(format!(
            "{} ARAP iterations: give 1 to {}",
            params.iterations,
            DeformParams::MAX_ITERATIONS
        )));
    }
    if !params.motion.is_finite() {
        return Err(Refusal::BadParameter(
            "the handle's motion is not finite".into(),
        ));
    }
    if params.handle.is_empty() {
        return Err(Refusal::BadParameter(
            "no handle: name the vertices that move".into(),
        ));
    }
    let handle_set: EntityHashSet = params.handle.iter().map(|v| v.0).collect();
    if let Some(both) = params.fixed.iter().find(|v| handle_set.contains(&v.0)) {
        return Err(Refusal::BadParameter(format!(
            "{} is both an anchor and part of the handle",
            ElementId::Vertex(*both)
        )));
    }
    let live = LiveDeform::new(world, mesh, params.method, &params.fixed, &params.handle)?;
    let m = MeshRef::new(world);
    let targets: Vec<Vec3> = params
        .handle
        .iter()
        .map(|&v| params.motion.transform_point3(m.position(v)))
        .collect();
    Ok((live, targets))
}

/// Deforms `mesh`: the anchors stay, the handle moves by its motion, the rest follows by the
/// method (see the module doc).
///
/// # Refusals
/// A stale mesh or vertex; an empty handle, a vertex both anchor and handle, a motion that is
/// not finite, iterations outside 1–10 000 ([`Refusal::BadParameter`]); a system that cannot be
/// solved. The mesh is then unchanged.
pub fn deform(
    world: &mut World,
    mesh: MeshId,
    params: &DeformParams,
) -> Result<DeformSummary, Refusal> {
    let (mut live, targets) = prepare(world, mesh, params)?;
    live.place(&targets);
    let energy_before = live.energy();
    live.iterate(params.iterations);
    let seconds = live.solving_seconds();
    let arap = params.method == DeformMethod::Arap;
    let summary = DeformSummary {
        free: live.free(),
        iterations: if arap { params.iterations } else { 0 },
        energy_before,
        energy: live.energy(),
        factor_seconds: live.factor_seconds(),
        iteration_seconds: if arap {
            seconds / params.iterations as f64
        } else {
            seconds
        },
        loose_parts: live.loose_parts(),
    };
    for (v, p) in live.moves()? {
        if let Some(mut at) = world.get_mut::<Position>(v.0) {
            at.0 = p;
        }
    }
    Ok(summary)
}

/// The thin-plate deformation of a surface (see the module doc), its system factored for one
/// set of held vertices.
pub struct ThinPlate {
    system: HeldSystem,
    rest: Vec<DVec3>,
}

impl ThinPlate {
    /// Factors `L M⁻¹ L` of `surface` (its positions the rest pose, `edges` its cotangent
    /// weights) with the vertices where `held` is set held.
    ///
    /// # Refusals
    /// As [`HeldSystem::new`].
    pub fn new(
        surface: &Surface,
        edges: &[(u32, u32, f64)],
        held: &[bool],
    ) -> Result<Self, Refusal> {
        let n = surface.vertex_count();
        let areas = mixed_areas(surface);
        Ok(Self {
            system: HeldSystem::new(&k_harmonic(n, edges, &areas, 2), held)?,
            rest: surface.positions.clone(),
        })
    }

    /// The positions with the vertices of `targets` there, the other held ones at rest, and the
    /// free ones displaced by `L M⁻¹ L d = 0`.
    pub fn displace(&self, targets: &[(u32, DVec3)]) -> Vec<DVec3> {
        let rest = &self.rest;
        let mut d = vec![DVec3::ZERO; rest.len()];
        for &(v, p) in targets {
            d[v as usize] = p - rest[v as usize];
        }
        self.system.solve(None, &mut d);
        let mut x: Vec<DVec3> = rest.iter().zip(&d).map(|(p, d)| *p + *d).collect();
        // Exactly where they were sent, not rest + (target − rest).
        targets.iter().for_each(|&(v, p)| x[v as usize] = p);
        x
    }
}

/// The summary's note on parts of the mesh a solve left alone, none of their vertices held
/// (empty when there were none).
pub fn loose_note(parts: usize) -> String {
    match parts {
        0 => String::new(),
        n => format!(
            " ({} with nothing held stayed)",
            crate::ops::operation::count(n, "part")
        ),
    }
}

/// Fairs `params.vertices`: they solve the k-harmonic equation, every other vertex held (see the
/// module doc).
///
/// # Refusals
/// A stale mesh or vertex; no vertices, or `k` outside 1–3 ([`Refusal::BadParameter`]); a
/// system that cannot be solved. The mesh is then unchanged.
pub fn fair(world: &mut World, mesh: MeshId, params: &FairParams) -> Result<FairSummary, Refusal> {
    if !(1..=3).contains(&params.k) {
        return Err(Refusal::BadParameter(format!(
            "fairing order k = {}: give 1, 2 or 3",
            params.k
        )));
    }
    if params.vertices.is_empty() {
        return Err(Refusal::BadParameter(
            "nothing to fair: select the vertices that move".into(),
        ));
    }
    if world.get::<MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    for &v in &params.vertices {
        if world.get::<InMesh>(v.0).map(|m| m.0) != Some(mesh)
            || world.get::<crate::mesh::Vertex>(v.0).is_none()
        {
            return Err(Refusal::Stale(ElementId::Vertex(v)));
        }
    }
    let mut region = Region::around(world, &params.vertices, params.k);
    let (x, loose_parts) = fair_rows(&region.surface, &mut region.held, params.k)?;
    if let Some(bad) = x.iter().find(|p| !p.as_vec3().is_finite()) {
        return Err(Refusal::NotFinite(bad.as_vec3()));
    }
    let (mut free, mut moved) = (0, 0.0);
    for (i, &v) in region.vertices.iter().enumerate() {
        if !region.held[i] {
            free += 1;
            moved += x[i].distance(region.surface.positions[i]);
            if let Some(mut p) = world.get_mut::<Position>(v.0) {
                p.0 = x[i].as_vec3();
            }
        }
    }
    Ok(FairSummary {
        free,
        mean_move: if free > 0 { moved / free as f64 } else { 0.0 },
        loose_parts,
    })
}

/// The surface's positions with the vertices not `held` solving the k-harmonic equation; parts
/// with nothing held are held whole (`held` is updated), and counted.
///
/// # Refusals
/// As [`HeldSystem::new`].
pub fn fair_rows(
    surface: &Surface,
    held: &mut [bool],
    k: u32,
) -> Result<(Vec<DVec3>, usize), Refusal> {
    let n = surface.vertex_count();
    let edges = cotan_edges(surface);
    let loose = hold_loose_parts(n, &edges, held);
    let areas = mixed_areas(surface);
    let system = HeldSystem::new(&k_harmonic(n, &edges, &areas, k), held)?;
    let mut x = surface.positions.clone();
    system.solve(None, &mut x);
    Ok((x, loose))
}
