//! Normalizing a mesh's placement and size (MeshLab's *Transform: Translate, Center* with
//! *Transform: Scale, Normalize*; Blender's *Origin to Geometry* with a scale to fit): the
//! centre of its bounding box moves to the origin and it is scaled uniformly so that the
//! longest side of its box is `SIZE` (1 by default) — what a model from another tool, in
//! millimetres or metres and far from the origin, needs before parameters given in absolute
//! units (a remeshing length, a deformation's offset) mean the same on every mesh.
//!
//! Each position becomes `(p − c) · SIZE / L`, with `c` the box's centre and `L` its longest
//! side, computed in double precision. Only positions change: every id, the connectivity, the
//! UVs, seams and groups stay, and vertex normals keep their directions (a uniform scale by a
//! positive factor turns none), so a save writes a file's normals as they were read. A mesh whose vertices all lie at one point has no size to
//! scale, and is refused.
//!
//! It is the operation that shows what a self-declaring operation costs: this file and its
//! registration line in [`crate::ops::registry`]; the step (`normalize[:SIZE]`), Alt+C,
//! the panel's button and its parameter, undo and Python's `Mesh.step` come from the
//! declaration.

use bevy::math::DVec3;
use bevy::prelude::World;

use crate::mesh::elements::{Position, Vertex};
use crate::mesh::ids::{MeshId, VertexId};
use crate::mesh::members::of_kind;
use crate::ops::Refusal;
use crate::ops::declaration::{Declaration, Parameter};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Redraw, Values};

/// Normalizing: positions only, every id and attribute kept.
pub const NORMALIZE: Declaration = Declaration::new("normalize")
    .titled("Normalize")
    .described("centre the mesh's box at the origin and scale it so its longest side is SIZE")
    .on_key("Alt+C")
    .with_parameters(&[Parameter::real("SIZE", 1.0, 1e-6, 1e6)])
    .keeping_normals();

/// [`normalize`] as an operation (the `normalize[:SIZE]` step, Alt+C).
pub struct Normalize;

impl MeshOperation for Normalize {
    fn declaration(&self) -> &'static Declaration {
        &NORMALIZE
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let done = normalize(world, mesh, values.number(0))?;
        Ok(Applied {
            summary: format!(
                "centred (moved by {:.4}, {:.4}, {:.4}) and scaled by {:.4}: longest side {}",
                tidy(-done.centre.x),
                tidy(-done.centre.y),
                tidy(-done.centre.z),
                done.scale,
                values.number(0)
            ),
            redraw: Redraw::Positions,
            made: None,
        })
    }
}

/// `x`, or 0 where it would print as `-0.0000`.
fn tidy(x: f64) -> f64 {
    if x.abs() < 5e-5 { 0.0 } else { x }
}

/// What normalizing did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalized {
    /// The centre of the bounding box before, now at the origin.
    pub centre: DVec3,
    /// The factor every offset from it was multiplied by.
    pub scale: f64,
}

/// Moves the centre of `mesh`'s bounding box to the origin and scales the mesh so that the
/// box's longest side is `size` (see the module doc).
///
/// # Refusals
/// [`Refusal::BadParameter`] when the mesh has no vertex, or all of them lie at one point;
/// the mesh is then untouched.
pub fn normalize(world: &mut World, mesh: MeshId, size: f64) -> Result<Normalized, Refusal> {
    let vertices = of_kind::<Vertex, _>(world, mesh, VertexId);
    let positions: Vec<DVec3> = vertices
        .iter()
        .map(|v| {
            world
                .get::<Position>(v.0)
                .map_or(DVec3::ZERO, |p| p.0.as_dvec3())
        })
        .collect();
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let longest = (hi - lo).max_element();
    if !(longest.is_finite() && longest > 0.0) {
        return Err(Refusal::BadParameter(
            "the mesh has no size to normalize: its vertices all lie at one point".into(),
        ));
    }
    let centre = (lo + hi) / 2.0;
    let scale = size / longest;
    for (v, p) in vertices.iter().zip(&positions) {
        world
            .entity_mut(v.0)
            .insert(Position(((*p - centre) * scale).as_vec3()));
    }
    Ok(Normalized { centre, scale })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, MeshMembers, MeshRef, build_mesh, shapes, validate};
    use bevy::math::Vec3;

    fn moved_sphere(world: &mut World) -> MeshId {
        let mut soup = shapes::icosphere(2);
        for p in &mut soup.positions {
            *p = *p * Vec3::new(3.0, 1.0, 0.5) + Vec3::new(100.0, -7.0, 2.0);
        }
        build_mesh(world, &soup, MeshInfo::default()).unwrap().mesh
    }

    fn bounds(world: &World, mesh: MeshId) -> (Vec3, Vec3) {
        let m = MeshRef::new(world);
        MeshMembers::collect(world, mesh)
            .vertices
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(m.position(v)), hi.max(m.position(v)))
            })
    }

    /// The box ends centred at the origin with its longest side `SIZE`; the other sides keep
    /// their proportions, and the connectivity is untouched.
    #[test]
    fn the_box_is_centred_and_its_longest_side_is_the_size() {
        let mut world = World::new();
        let mesh = moved_sphere(&mut world);
        let before = MeshMembers::collect(&world, mesh);
        let (lo0, hi0) = bounds(&world, mesh);
        let done = normalize(&mut world, mesh, 2.0).unwrap();
        let (lo, hi) = bounds(&world, mesh);
        assert!(((lo + hi) / 2.0).length() < 1e-5, "{lo} {hi}");
        let (side0, side) = (hi0 - lo0, hi - lo);
        assert!((side.x - 2.0).abs() < 1e-5, "{side}");
        assert!((side.y - 2.0 * side0.y / side0.x).abs() < 1e-5);
        assert!((side.z - 2.0 * side0.z / side0.x).abs() < 1e-5);
        assert!((done.scale - 2.0 / f64::from(side0.x)).abs() < 1e-9);
        validate(&world, mesh).unwrap();
        let after = MeshMembers::collect(&world, mesh);
        assert_eq!(after.vertices, before.vertices);
        assert_eq!(after.faces, before.faces);
        assert_eq!(after.halfedges, before.halfedges);
    }

    /// Normalizing twice changes nothing more (to rounding).
    #[test]
    fn normalizing_a_normalized_mesh_keeps_it() {
        let mut world = World::new();
        let mesh = moved_sphere(&mut world);
        normalize(&mut world, mesh, 1.0).unwrap();
        let again = normalize(&mut world, mesh, 1.0).unwrap();
        assert!(again.centre.length() < 1e-6 && (again.scale - 1.0).abs() < 1e-6);
    }

    /// A mesh squashed to one point has no size: refused, positions as they were.
    #[test]
    fn a_mesh_at_one_point_is_refused_untouched() {
        let mut world = World::new();
        let mesh = moved_sphere(&mut world);
        let vertices = MeshMembers::collect(&world, mesh).vertices;
        for v in &vertices {
            world.entity_mut(v.0).insert(Position(Vec3::ONE));
        }
        let refusal = normalize(&mut world, mesh, 1.0).unwrap_err();
        assert!(refusal.to_string().contains("one point"), "{refusal}");
        let m = MeshRef::new(&world);
        assert!(vertices.iter().all(|&v| m.position(v) == Vec3::ONE));
    }
}
