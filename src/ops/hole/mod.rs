//! Filling holes with a surface rather than one polygon (Liepa, "Filling Holes in Meshes",
//! SGP 2003; PMP's `fill_hole`, MeshLab's "close holes"):
//! 1. the boundary loop is triangulated by the dynamic programme that bends least
//!    ([`triangulation`]: smallest largest dihedral angle, then least area), never repeating an
//!    edge the mesh has;
//! 2. the triangles are refined toward the surrounding edge length `L` (the mean length of the
//!    edges at the loop's vertices), regularised and faired, so the patch continues the surface's
//!    curvature ([`patch`]).
//!
//! [`fill_holes`] does it for every boundary loop of a mesh, or makes each one polygon.
//!
//! Refusals (the mesh untouched): the edge is not on the boundary; the loop passes through a
//! vertex twice (a pinched hole, whose triangles would be degenerate); the loop is longer than
//! [`MAX_LOOP`] (the programme is cubic in its length); every triangulation would repeat an
//! existing edge.

mod patch;
mod triangulation;

use bevy::ecs::entity::EntityHashSet;
use bevy::math::DVec3;
use bevy::prelude::World;

use crate::mesh::MeshInfo;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;

use super::Refusal;
use super::local::{FillHolePlan, apply_fill_hole, fill_hole, plan_fill_hole, split_face};
use patch::Patch;
use triangulation::{HoleLoop, triangulate};

use crate::mesh::InMesh;
use crate::ops::declaration::{Declaration, Names, Parameter, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Redraw, Values, count};

/// Filling the hole beside one boundary edge with one polygon, or with a faired patch of
/// triangles (`fill-hole:A,B[:polygon|fair]`; F, Alt+F).
pub const FILL_HOLE: Declaration = Declaration::new("fill-hole")
    .titled("Fill hole")
    .described("fill the hole beside the selected boundary edge: one face, or faired triangles")
    .naming(Names::Edge)
    .with_parameters(&[Parameter::choice("FILL", &["polygon", "fair"], 0)])
    .in_section(Section::Modelling);

/// [`fill_hole`] or [`fill_hole_fair`] as an operation on a boundary edge.
pub struct FillHole;

impl FillHole {
    /// The value of its FILL parameter that fills with a faired patch.
    pub const FAIR: f64 = 1.0;
}

impl MeshOperation for FillHole {
    fn declaration(&self) -> &'static Declaration {
        &FILL_HOLE
    }

    /// One polygon: every halfedge of the loop takes the face, so its vertices are the seeds.
    /// A faired patch makes vertices away from the loop: the whole mesh.
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let m = MeshRef::new(world);
        let h = m.try_edge(values.edge().ok()?)?.halfedge;
        m.try_halfedge(h)?;
        let mesh = world.get::<InMesh>(h.0)?.0;
        if values.number(0) == Self::FAIR {
            return Some(Reach::Whole(mesh));
        }
        let h = if m.is_boundary(h) { h } else { m.twin(h) };
        Some(Reach::Local(
            mesh,
            m.loop_from(h).map(|x| m.from_vertex(x)).collect(),
        ))
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        if values.number(0) == Self::FAIR {
            let r = fill_hole_fair(world, e)?;
            return Ok(Applied {
                summary: format!(
                    "a hole of {} sides filled with {}, {} new",
                    r.sides,
                    count(r.triangles, "triangle"),
                    count(r.new_vertices, "vertex")
                ),
                redraw: Redraw::Whole,
                made: Some(ElementId::Face(r.face)),
            });
        }
        let f = fill_hole(world, e)?;
        let ring: Vec<VertexId> = MeshRef::new(world).face_vertices(f).collect();
        Ok(Applied {
            summary: format!("new face {f} of {} sides", ring.len()),
            redraw: Redraw::near(world, Vec::new(), ring),
            made: Some(ElementId::Face(f)),
        })
    }
}

/// Filling every hole, with one polygon each or a faired patch (`fill-holes[:polygon|fair]`,
/// Shift+F).
pub const FILL_HOLES: Declaration = Declaration::new("fill-holes")
    .titled("Fill all holes")
    .described("fill every hole: one face each, or triangles refined and faired into the surface")
    .on_key("Shift+F")
    .with_parameters(&[Parameter::choice("FILL", &["polygon", "fair"], 0)])
    .in_section(Section::Shape);

/// [`fill_holes`] as an operation: every hole, one polygon each or faired.
pub struct FillHoles;

impl MeshOperation for FillHoles {
    fn declaration(&self) -> &'static Declaration {
        &FILL_HOLES
    }

    /// Refused when no hole could be filled (or there is none); the holes a fair fill refuses
    /// are left open and named in the summary.
    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let r = fill_holes(world, mesh, values.choice(0) == 1)?;
        if r.filled == 0 {
            return Err(Refusal::BadParameter(match r.refused.first() {
                None => "the mesh has no holes".into(),
                Some(_) => format!("no hole could be filled: {}", r.refused.join("; ")),
            }));
        }
        let open = match r.refused.len() {
            0 => String::new(),
            n => format!("; {n} left open: {}", r.refused.join("; ")),
        };
        Ok(Applied::whole(format!(
            "{} filled: {} and {} added{open}",
            count(r.filled, "hole"),
            count(r.faces, "face"),
            count(r.vertices, "vertex")
        )))
    }
}

/// The longest loop a fair fill triangulates: 600 sides take about a second.
pub const MAX_LOOP: usize = 600;

/// What a fair fill made.
#[derive(Clone, Debug, PartialEq)]
pub struct FilledHole {
    /// The loop's length.
    pub sides: usize,
    /// Triangles in the patch.
    pub triangles: usize,
    /// Vertices the patch added.
    pub new_vertices: usize,
    /// A face of the patch (for the editor to select).
    pub face: FaceId,
}

/// The plan of a fair fill: the loop and its triangulation, checked.
struct FairFillPlan {
    /// The plain fill's plan: the loop, made one face first.
    fill: FillHolePlan,
    vertices: Vec<VertexId>,
    triangles: Vec<[usize; 3]>,
    length: f32,
}

/// Checks that the hole beside `e` can be filled fair and triangulates its loop.
///
/// # Refusals
/// See the module doc.
fn plan_fair_fill(world: &World, e: EdgeId) -> Result<FairFillPlan, Refusal> {
    // The plain fill's checks (a live boundary edge) and its loop.
    let fill = plan_fill_hole(world, e)?;
    let m = MeshRef::new(world);
    let ring = fill.ring();
    let vertices: Vec<VertexId> = ring.iter().map(|&h| m.from_vertex(h)).collect();
    let n = vertices.len();
    let distinct: EntityHashSet = vertices.iter().map(|v| v.0).collect();
    if distinct.len() != n {
        return Err(Refusal::BadParameter(format!(
            "the hole at {} passes through a vertex twice: fill it as one face instead",
            ElementId::Edge(e)
        )));
    }
    if n > MAX_LOOP {
        return Err(Refusal::BadParameter(format!(
            "the hole at {} has {n} sides, more than the {MAX_LOOP} a fair fill triangulates: \
             fill it as one face instead",
            ElementId::Edge(e)
        )));
    }
    let positions: Vec<DVec3> = vertices.iter().map(|&v| m.position(v).as_dvec3()).collect();
    let beyond: Vec<DVec3> = ring
        .iter()
        .map(|&h| {
            m.face(m.twin(h)).map_or(DVec3::ZERO, |f| {
                m.face_area_vector(f).as_dvec3().normalize_or_zero()
            })
        })
        .collect();
    let index: bevy::ecs::entity::EntityHashMap<usize> =
        vertices.iter().enumerate().map(|(i, v)| (v.0, i)).collect();
    let mut joined_pairs = std::collections::HashSet::new();
    for (i, &v) in vertices.iter().enumerate() {
        for u in m.vertex_neighbors(v) {
            if let Some(&k) = index.get(&u.0) {
                joined_pairs.insert((i.min(k), i.max(k)));
            }
        }
    }
    let joined = |i: usize, k: usize| joined_pairs.contains(&(i.min(k), i.max(k)));
    let triangles = triangulate(&HoleLoop {
        positions: &positions,
        beyond: &beyond,
        joined: &joined,
    })
    .ok_or_else(|| {
        Refusal::BadParameter(format!(
            "every triangulation of the hole at {} would repeat an edge the mesh has",
            ElementId::Edge(e)
        ))
    })?;
    // The surrounding length: the mean of the edges at the loop's vertices.
    let (mut sum, mut count) = (0.0f32, 0usize);
    for &v in &vertices {
        for u in m.vertex_neighbors(v) {
            sum += m.position(v).distance(m.position(u));
            count += 1;
        }
    }
    Ok(FairFillPlan {
        fill,
        vertices,
        triangles,
        length: sum / count.max(1) as f32,
    })
}

/// Fills the hole beside boundary edge `e` with a fair patch of triangles (see the module doc).
///
/// # Refusals
/// See the module doc; the mesh is then unchanged.
pub fn fill_hole_fair(world: &mut World, e: EdgeId) -> Result<FilledHole, Refusal> {
    let plan = plan_fair_fill(world, e)?;
    let (mesh, ring) = (plan.fill.mesh(), plan.fill.ring().to_vec());
    let face = apply_fill_hole(world, plan.fill);
    let mut patch_faces: EntityHashSet = [face.0].into_iter().collect();
    // Cut the polygon along the triangulation's diagonals, parents first: each diagonal's ends
    // then share exactly one patch face.
    for &[i, m, k] in &plan.triangles {
        for (a, b) in [(i, m), (m, k)] {
            if b == a + 1 {
                continue;
            }
            let (va, vb) = (plan.vertices[a], plan.vertices[b]);
            let shared = {
                let r = MeshRef::new(world);
                r.vertex_faces(va)
                    .find(|f| patch_faces.contains(&f.0) && r.face_vertices(*f).any(|x| x == vb))
            };
            if let Some(f) = shared
                && let Ok(edge) = split_face(world, f, va, vb)
            {
                let r = MeshRef::new(world);
                let h = r.edge_halfedge(edge);
                patch_faces.extend(
                    [r.face(h), r.face(r.twin(h))]
                        .into_iter()
                        .flatten()
                        .map(|f| f.0),
                );
            }
        }
    }
    let patch = Patch {
        mesh,
        ring,
        rim: plan.vertices.iter().map(|v| v.0).collect(),
        length: plan.length,
    };
    let new_vertices = patch.refine(world).len();
    let faces = patch.faces(world);
    Ok(FilledHole {
        sides: plan.vertices.len(),
        triangles: faces.len(),
        new_vertices,
        face: faces.first().copied().unwrap_or(face),
    })
}

/// What filling every hole did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FilledHoles {
    /// Holes filled.
    pub filled: usize,
    /// Faces added.
    pub faces: usize,
    /// Vertices added.
    pub vertices: usize,
    /// The holes left open, each with why.
    pub refused: Vec<String>,
}

/// Fills every hole of `mesh`: fair patches when `fair`, else one polygon each. A hole a fair
/// fill refuses is left open and listed (the others are filled).
///
/// # Refusals
/// A stale mesh.
pub fn fill_holes(world: &mut World, mesh: MeshId, fair: bool) -> Result<FilledHoles, Refusal> {
    if world.get::<MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    let loops = boundary_loops(world, mesh);
    let mut done = FilledHoles::default();
    let before = MeshMembers::collect(world, mesh);
    for e in loops {
        let filled = if fair {
            fill_hole_fair(world, e).map(|_| ())
        } else {
            fill_hole(world, e).map(|_| ())
        };
        match filled {
            Ok(()) => done.filled += 1,
            Err(why) => done.refused.push(why.to_string()),
        }
    }
    let after = MeshMembers::collect(world, mesh);
    done.faces = after.faces.len() - before.faces.len();
    done.vertices = after.vertices.len() - before.vertices.len();
    Ok(done)
}

/// One edge of each boundary loop of `mesh`.
fn boundary_loops(world: &World, mesh: MeshId) -> Vec<EdgeId> {
    let m = MeshRef::new(world);
    let mut seen = EntityHashSet::default();
    let mut loops = Vec::new();
    for e in MeshMembers::collect(world, mesh).edges {
        let h = m.edge_halfedge(e);
        let b = if m.is_boundary(h) {
            h
        } else if m.is_boundary(m.twin(h)) {
            m.twin(h)
        } else {
            continue;
        };
        if seen.insert(b.0) {
            seen.extend(m.loop_from(b).map(|x| x.0));
            loops.push(e);
        }
    }
    loops
}

#[cfg(test)]
mod tests;
