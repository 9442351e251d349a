//! Step 2 of an iteration (Botsch & Kobbelt 2004): collapse the edges shorter than 4/5 L,
//! shortest first, where no edge around the merged vertex would become longer than 4/3 L.
//!
//! Every collapse goes through the local collapse plan (link condition, degenerate faces, and a
//! 60° bound on how far a face normal may turn), so a refused edge is skipped and the mesh stays
//! valid. Features restrict where the survivor may go ([`collapse_choice`]): a feature vertex
//! stays put, a feature-line vertex goes only along a line straight to within L/20 there, and a
//! feature corner never goes; no collapse merges two feature edges into one.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::local::{CollapseOptions, apply_collapse, plan_collapse_halfedge};

use super::features::{FeatureDegrees, feature_degree};
use super::{EdgeTable, distance_to_segment};

/// Collapses the edges of `mesh` shorter than `low` (4/5 L), shortest first, where
/// [`collapse_choice`] allows and the collapse plan (with a 60° normal bound) accepts.
/// Returns how many, and the surviving vertices, each once, less those a later collapse of
/// the pass removed.
pub(super) fn collapse_short(
    world: &mut World,
    mesh: MeshId,
    low: f32,
    high: f32,
    features: &EntityHashSet,
) -> (usize, Vec<VertexId>) {
    let table = EdgeTable::read(world, mesh);
    let degree = table.feature_degrees(features);
    // Shortest first: collapsing them early removes the most short edges.
    let mut keyed: Vec<(f32, EdgeId)> = table
        .members
        .edges
        .iter()
        .zip(&table.length)
        .filter(|&(_, &length)| length < low)
        .map(|(&e, &length)| (length, e))
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut collapses = 0;
    let mut survivors = Vec::new();
    for (_, e) in keyed {
        let m = MeshRef::new(world);
        if m.try_edge(e).is_none() {
            continue;
        }
        let Some((h, target)) = collapse_choice(&m, e, features, &degree, high, low) else {
            continue;
        };
        let options = CollapseOptions {
            position: Some(target),
            max_normal_change_deg: Some(60.0),
        };
        if let Ok(plan) = plan_collapse_halfedge(world, h, options) {
            survivors.push(apply_collapse(world, plan).kept);
            collapses += 1;
        }
    }
    // A collapse despawns the vertex it removes (and spawns nothing, so no id comes back).
    let m = MeshRef::new(world);
    survivors.retain(|&v| m.try_vertex(v).is_some());
    survivors.sort_unstable();
    survivors.dedup();
    (collapses, survivors)
}

/// How the short edge `e` may collapse without harming a feature: the halfedge whose start
/// survives (its tip is removed) and where the survivor goes; `None` if it may not, or if it
/// is no longer shorter than `low` (an earlier collapse of the pass moved an end).
///
/// - Two free vertices merge at the midpoint, else at either end (as PMP tries both
///   directions), whichever makes no edge longer than `high` (4/3 L).
/// - A free vertex merges into a feature vertex, which stays where it is.
/// - Along a feature line (the edge is a feature and one end has exactly two feature edges),
///   that end merges into the other, which stays; only where the line is nearly straight
///   there (the removed vertex within `low / 16`, L/20, of the line's new segment), so a crease keeps
///   its shape and the boundary stays where it was.
/// - Feature corners never go, and no collapse removes a feature edge other than its own:
///   the removed vertex's other edges in the vanishing triangles merge into the survivor's.
fn collapse_choice(
    m: &MeshRef<'_>,
    e: EdgeId,
    features: &EntityHashSet,
    degree: &FeatureDegrees,
    high: f32,
    low: f32,
) -> Option<(HalfedgeId, Vec3)> {
    let h = m.edge_halfedge(e);
    let (a, b) = (m.from_vertex(h), m.to_vertex(h));
    let (pa, pb) = (m.position(a), m.position(b));
    if pa.distance(pb) >= low {
        return None;
    }
    let fits = |target: Vec3| {
        !m.vertex_neighbors(a)
            .chain(m.vertex_neighbors(b))
            .any(|n| n != a && n != b && m.position(n).distance(target) > high)
    };
    let (da, db) = (degree.of(a), degree.of(b));
    crate::checks::checked_assert_eq!(
        (da, db),
        (
            feature_degree(m, a, features),
            feature_degree(m, b, features)
        ),
        "stale feature degrees"
    );
    match (da, db) {
        (0, 0) => {
            // One walk over the neighbours for all three targets, stopping once none fits.
            let targets = [(pa + pb) / 2.0, pa, pb];
            let mut fit = [true; 3];
            for n in m.vertex_neighbors(a).chain(m.vertex_neighbors(b)) {
                if n == a || n == b {
                    continue;
                }
                let p = m.position(n);
                for (ok, t) in fit.iter_mut().zip(targets) {
                    *ok &= p.distance(t) <= high;
                }
                if fit == [false; 3] {
                    return None;
                }
            }
            let first = fit.iter().position(|&ok| ok)?;
            Some((h, targets[first]))
        }
        (_, 0) => fits(pa).then_some((h, pa)),
        (0, _) => fits(pb).then_some((m.twin(h), pb)),
        _ if features.contains(&e.0) => [(h, db), (m.twin(h), da)]
            .into_iter()
            .filter(|&(_, degree)| degree == 2)
            .find(|&(keep, _)| {
                let target = m.position(m.from_vertex(keep));
                fits(target) && slides_along_line(m, keep, features, low / 16.0)
            })
            .map(|(keep, _)| (keep, m.position(m.from_vertex(keep)))),
        _ => None,
    }
}

/// Whether removing the tip `r` of the feature halfedge `keep` (from `k`) keeps its feature
/// line: `r`'s other feature neighbour `x` is not a wing of the collapse (that would merge two
/// feature edges into one), and `r` lies within `tolerance` of the new segment `k x`.
fn slides_along_line(
    m: &MeshRef<'_>,
    keep: HalfedgeId,
    features: &EntityHashSet,
    tolerance: f32,
) -> bool {
    let (k, r) = (m.from_vertex(keep), m.to_vertex(keep));
    let wings = [keep, m.twin(keep)].map(|x| m.face(x).map(|_| m.to_vertex(m.next(x))));
    let Some(x) = m
        .vertex_outgoing(r)
        .find(|&o| m.to_vertex(o) != k && features.contains(&m.edge(o).0))
        .map(|o| m.to_vertex(o))
    else {
        return false;
    };
    if wings.contains(&Some(x)) {
        return false;
    }
    distance_to_segment(m.position(r), m.position(k), m.position(x)) <= tolerance
}
