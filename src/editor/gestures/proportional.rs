//! Proportional editing (Alt+O): a move, rotation or scale also takes the unselected
//! vertices within a radius of the selection along, each by its falloff weight
//! ([`crate::ops::deform::Falloff`]). [`gather`] takes in the vertices a radius reaches (as it
//! grows while the gesture runs, [`Follow::resize`]); [`Follow::weight`] is what each one follows by.

use bevy::prelude::*;

use crate::mesh::ids::VertexId;
use crate::mesh::topology::MeshRef;
use crate::ops::deform::{Proportional, distances};

/// The unselected vertices a proportional gesture takes along.
#[derive(Clone, Debug)]
pub struct Follow {
    /// The settings, the radius as the gesture changed it.
    pub settings: Proportional,
    /// How many of the gesture's vertices ([`Gesture::start`](super::transform::Gesture::start))
    /// are the selection (the rest follow).
    pub selected: usize,
    /// The distance of each following vertex to the selection (`start[selected + i]`).
    pub distances: Vec<f32>,
    /// The radius the following vertices were gathered for.
    pub gathered: f32,
}

impl Follow {
    /// The weight of start vertex `i`.
    pub fn weight(&self, i: usize) -> f32 {
        match i.checked_sub(self.selected) {
            None => 1.0,
            Some(k) => self
                .settings
                .falloff
                .weight(self.distances[k], self.settings.radius),
        }
    }

    /// Scales the radius by `factor` (Page Up / Page Down, the wheel), never to nothing.
    pub fn resize(&mut self, factor: f32) {
        self.settings.radius = (self.settings.radius * factor).max(1e-6);
    }
}

/// Takes along the vertices within the proportional radius that the gesture does not hold yet
/// (where they are: out of reach until now, they have not moved), appending them to `start`,
/// the gesture's vertices and where they started.
pub fn gather(world: &World, follow: &mut Follow, start: &mut Vec<(VertexId, Vec3)>) {
    let radius = follow.settings.radius;
    if radius <= follow.gathered {
        return;
    }
    let selected: Vec<VertexId> = start[..follow.selected].iter().map(|(v, _)| *v).collect();
    let held: bevy::ecs::entity::EntityHashMap<usize> = start[follow.selected..]
        .iter()
        .enumerate()
        .map(|(k, (v, _))| (v.0, k))
        .collect();
    let m = MeshRef::new(world);
    for (v, d) in distances(world, &selected, radius, follow.settings.connected) {
        match held.get(&v.0) {
            Some(&k) => follow.distances[k] = d,
            None => {
                start.push((v, m.position(v)));
                follow.distances.push(d);
            }
        }
    }
    follow.gathered = radius;
}
