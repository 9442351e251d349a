//! Proportional editing (Blender's `O`): while the selection is moved, rotated or scaled, each
//! unselected vertex within a radius follows by a weight that falls off with its distance to the
//! selection.
//!
//! With `t = 1 − d / r` for a vertex at distance `d < r` (weight 0 beyond), the falloffs are
//! Blender's: smooth `3t² − 2t³`, sphere `√(2t − t²)`, root `√t`, linear `t`, sharp `t²`, constant
//! `1`. The distance is measured in space, or along the surface's edges ("connected only":
//! Dijkstra from every selected vertex, so the other side of a thin part, near in space, stays).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::InMesh;
use crate::mesh::ids::VertexId;
use crate::mesh::members::MeshMembers;
use crate::mesh::topology::MeshRef;
use crate::ops::named::Named;

/// How the weight falls from 1 at the selection to 0 at the radius.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Falloff {
    /// `3t² − 2t³`: flat at both ends.
    #[default]
    Smooth,
    /// `√(2t − t²)`: a quarter circle.
    Sphere,
    /// `√t`.
    Root,
    /// `t`.
    Linear,
    /// `t²`: a cusp at the selection.
    Sharp,
    /// 1 inside the radius.
    Constant,
}

impl Named for Falloff {
    const ALL: &'static [(Self, &'static str)] = &[
        (Falloff::Smooth, "smooth"),
        (Falloff::Sphere, "sphere"),
        (Falloff::Root, "root"),
        (Falloff::Linear, "linear"),
        (Falloff::Sharp, "sharp"),
        (Falloff::Constant, "constant"),
    ];
}

impl Falloff {
    /// The weight of a vertex at `distance` from the selection, for this `radius`: 1 at the
    /// selection, 0 at and beyond the radius (and for a radius that is not positive).
    pub fn weight(self, distance: f32, radius: f32) -> f32 {
        if radius.is_nan() || radius <= 0.0 || distance.is_nan() || distance >= radius {
            return 0.0;
        }
        let t = (1.0 - distance / radius).clamp(0.0, 1.0);
        match self {
            Falloff::Smooth => 3.0 * t * t - 2.0 * t * t * t,
            Falloff::Sphere => (2.0 * t - t * t).sqrt(),
            Falloff::Root => t.sqrt(),
            Falloff::Linear => t,
            Falloff::Sharp => t * t,
            Falloff::Constant => 1.0,
        }
    }
}

/// Proportional editing's settings (the editor's panel and `Alt+O`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proportional {
    /// On or off.
    pub enabled: bool,
    /// The falloff.
    pub falloff: Falloff,
    /// The radius, in world units.
    pub radius: f32,
    /// Distances along the surface's edges instead of in space.
    pub connected: bool,
}

impl Default for Proportional {
    fn default() -> Self {
        Self {
            enabled: false,
            falloff: Falloff::Smooth,
            radius: 0.1,
            connected: false,
        }
    }
}

/// Every vertex of the selection's meshes that is not selected and lies closer than `radius` to
/// it, with its distance: in space, or along edges when `connected`. Ordered by vertex.
pub fn distances(
    world: &World,
    selected: &[VertexId],
    radius: f32,
    connected: bool,
) -> Vec<(VertexId, f32)> {
    let m = MeshRef::new(world);
    let chosen: EntityHashSet = selected.iter().map(|v| v.0).collect();
    let mut found: Vec<(VertexId, f32)> = if connected {
        along_edges(&m, selected, radius, &chosen)
    } else {
        in_space(world, &m, selected, radius, &chosen)
    };
    found.sort_unstable_by_key(|(v, _)| *v);
    found
}

fn in_space(
    world: &World,
    m: &MeshRef<'_>,
    selected: &[VertexId],
    radius: f32,
    chosen: &EntityHashSet,
) -> Vec<(VertexId, f32)> {
    let points: Vec<Vec3> = selected.iter().map(|&v| m.position(v)).collect();
    let (low, high) = points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let (low, high) = (low - radius, high + radius);
    let meshes: EntityHashSet = selected
        .iter()
        .filter_map(|v| world.get::<InMesh>(v.0).map(|m| m.0.0))
        .collect();
    let mut out = Vec::new();
    for mesh in meshes {
        for v in MeshMembers::collect(world, crate::mesh::ids::MeshId(mesh)).vertices {
            if chosen.contains(&v.0) {
                continue;
            }
            let p = m.position(v);
            if p.cmplt(low).any() || p.cmpgt(high).any() {
                continue;
            }
            let d = points
                .iter()
                .map(|q| q.distance(p))
                .fold(f32::INFINITY, f32::min);
            if d < radius {
                out.push((v, d));
            }
        }
    }
    out
}

fn along_edges(
    m: &MeshRef<'_>,
    selected: &[VertexId],
    radius: f32,
    chosen: &EntityHashSet,
) -> Vec<(VertexId, f32)> {
    let mut best: EntityHashMap<f32> = selected.iter().map(|v| (v.0, 0.0)).collect();
    // Distances as ordered bits: non-negative floats order as their bit patterns.
    let mut heap: BinaryHeap<Reverse<(u32, VertexId)>> =
        selected.iter().map(|&v| Reverse((0, v))).collect();
    while let Some(Reverse((bits, v))) = heap.pop() {
        let d = f32::from_bits(bits);
        if best.get(&v.0).is_some_and(|&b| b < d) {
            continue;
        }
        let p = m.position(v);
        for u in m.vertex_neighbors(v) {
            let e = d + p.distance(m.position(u));
            if e < radius && best.get(&u.0).is_none_or(|&b| e < b) {
                best.insert(u.0, e);
                heap.push(Reverse((e.to_bits(), u)));
            }
        }
    }
    best.into_iter()
        .filter(|(v, _)| !chosen.contains(v))
        .map(|(v, d)| (VertexId(v), d))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    #[test]
    fn each_falloff_is_its_formula_and_zero_past_the_radius() {
        let r = 2.0;
        for d in [0.0f32, 0.3, 0.9, 1.5, 1.99] {
            let t = 1.0 - d / r;
            let want = [
                (Falloff::Smooth, 3.0 * t * t - 2.0 * t * t * t),
                (Falloff::Sphere, (2.0 * t - t * t).sqrt()),
                (Falloff::Root, t.sqrt()),
                (Falloff::Linear, t),
                (Falloff::Sharp, t * t),
                (Falloff::Constant, 1.0),
            ];
            for (f, w) in want {
                assert_eq!(f.weight(d, r), w, "{f:?} at {d}");
            }
        }
        for &(f, _) in Falloff::ALL {
            assert_eq!(f.weight(0.0, r), 1.0, "{f:?}");
            assert_eq!(f.weight(r, r), 0.0);
            assert_eq!(f.weight(5.0, r), 0.0);
            assert_eq!(f.weight(0.0, 0.0), 0.0);
        }
    }

    #[test]
    fn distances_along_edges_are_never_shorter_than_in_space() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(10, 10), MeshInfo::default()).unwrap();
        let members = MeshMembers::collect(&world, built.mesh);
        let m = MeshRef::new(&world);
        // The corner at the origin.
        let corner = *members
            .vertices
            .iter()
            .find(|&&v| m.position(v) == Vec3::ZERO)
            .unwrap();
        let space = distances(&world, &[corner], 0.35, false);
        let edges = distances(&world, &[corner], 0.35, true);
        assert!(!edges.is_empty() && edges.len() <= space.len());
        for (v, d) in &edges {
            let euclid = m.position(*v).length();
            assert!(*d >= euclid - 1e-6, "{d} < {euclid}");
            let (_, s) = space.iter().find(|(u, _)| u == v).unwrap();
            assert!((s - euclid).abs() < 1e-6);
        }
        // Along the grid's x axis the path is straight: exact.
        let on_axis = members
            .vertices
            .iter()
            .find(|&&v| m.position(v) == Vec3::new(0.3, 0.0, 0.0))
            .unwrap();
        let (_, d) = edges.iter().find(|(v, _)| v == on_axis).unwrap();
        assert!((d - 0.3).abs() < 1e-6);
    }
}
