//! Step 2 of an iteration (Botsch & Kobbelt 2004): collapse the edges shorter than 4/5 L,
//! shortest first, where no edge around the merged vertex would become longer than 4/3 L.
//!
//! The pass runs on flat triangle tables ([`FlatTriangles`], the simplifier's): the mesh is
//! read once, every collapse is made on `u32` rows, and the survivors are written back into
//! their entities in one go. Each collapse is checked as the local collapse plan checks one
//! (link condition, degenerate faces, and a 60° bound on how far a face normal may turn), so a
//! refused edge is skipped and the mesh stays valid; the tables make the same collapses the
//! entities would, element for element (see [`crate::ops::simplify::flat`]). Features
//! restrict where the survivor may go ([`CollapseRules::collapse_choice`]): a feature vertex
//! stays put, a feature-line vertex goes only along a line straight to within L/20 there, and
//! a feature corner never goes; no collapse merges two feature edges into one.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::ids::{MeshId, VertexId};
use crate::ops::simplify::flat::FlatTriangles;

use super::{EdgeTable, distance_to_segment};

/// How far a face's normal may turn in a collapse of the pass.
const MAX_NORMAL_TURN_DEG: f32 = 60.0;

/// Collapses the edges of `mesh` shorter than `low` (4/5 L), shortest first (ties by edge
/// entity), where [`CollapseRules::collapse_choice`] allows and the collapse checks (with a
/// 60° normal bound) accept. Returns how many, and the surviving vertices, each once, less
/// those a later collapse of the pass removed.
pub(super) fn collapse_short(
    world: &mut World,
    mesh: MeshId,
    low: f32,
    high: f32,
    features: &EntityHashSet,
) -> (usize, Vec<VertexId>) {
    let table = EdgeTable::read(world, mesh);
    let edges = &table.members.edges;
    let feature: Vec<bool> = edges.iter().map(|e| features.contains(&e.0)).collect();
    let degree = table.feature_degree_rows(&feature);
    // Shortest first: collapsing them early removes the most short edges.
    let mut keyed: Vec<(f32, u32)> = (0..edges.len() as u32)
        .filter(|&e| table.length[e as usize] < low)
        .map(|e| (table.length[e as usize], e))
        .collect();
    keyed.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(edges[a.1 as usize].cmp(&edges[b.1 as usize]))
    });
    if keyed.is_empty() {
        return (0, Vec::new());
    }
    let numbers: Vec<u32> = (0..edges.len() as u32).collect();
    let mut flat = FlatTriangles::new(&table.tables, &numbers, edges.len());
    let mut edge_alive = vec![true; edges.len()];
    let limit = MAX_NORMAL_TURN_DEG.to_radians().cos();
    let rules = CollapseRules {
        feature: &feature,
        degree: &degree,
        high,
        low,
    };
    let mut kept = Vec::new();
    for (_, e) in keyed {
        if !edge_alive[e as usize] {
            continue;
        }
        let Some((h, target)) = rules.collapse_choice(&flat, e) else {
            continue;
        };
        if let Some(plan) = flat.plan(h, target, limit) {
            let collapsed = flat.apply(plan, |_, _, _| {});
            for gone in collapsed.removed_edges.into_iter().flatten() {
                edge_alive[gone as usize] = false;
            }
            kept.push(collapsed.kept);
        }
    }
    let collapses = kept.len();
    let rows = flat.write_back(world, &table.members, &numbers);
    let mut survivors: Vec<VertexId> = kept.iter().filter_map(|&v| rows[v as usize]).collect();
    survivors.sort_unstable();
    survivors.dedup();
    (collapses, survivors)
}

/// What a collapse pass decides by: the feature edges and degrees by row, 4/3 L and 4/5 L.
struct CollapseRules<'a> {
    /// By edge row: whether the edge is a feature.
    feature: &'a [bool],
    /// By vertex row: how many feature edges meet there
    /// ([`EdgeTable::feature_degree_rows`]); they stay right through a pass.
    degree: &'a [u8],
    high: f32,
    low: f32,
}

impl CollapseRules<'_> {
    /// How the short edge `e` may collapse without harming a feature: the halfedge whose start
    /// survives (its tip is removed) and where the survivor goes; `None` if it may not, or if
    /// it is no longer shorter than `low` (an earlier collapse of the pass moved an end).
    ///
    /// - Two free vertices merge at the midpoint, else at either end (as PMP tries both
    ///   directions), whichever makes no edge longer than `high` (4/3 L).
    /// - A free vertex merges into a feature vertex, which stays where it is.
    /// - Along a feature line (the edge is a feature and one end has exactly two feature
    ///   edges), that end merges into the other, which stays; only where the line is nearly
    ///   straight there (the removed vertex within `low / 16`, L/20, of the line's new
    ///   segment), so a crease keeps its shape and the boundary stays where it was.
    /// - Feature corners never go, and no collapse removes a feature edge other than its own:
    ///   the removed vertex's other edges in the vanishing triangles merge into the survivor's.
    fn collapse_choice(&self, m: &FlatTriangles, e: u32) -> Option<(u32, Vec3)> {
        let h = m.edge_halfedge(e);
        let (a, b) = (m.tip(m.twin(h)), m.tip(h));
        let (pa, pb) = (m.position(a), m.position(b));
        if pa.distance(pb) >= self.low {
            return None;
        }
        let high = self.high;
        let around = |v: u32| m.outgoing(v).map(|o| m.tip(o));
        let fits = |target: Vec3| {
            !around(a)
                .chain(around(b))
                .any(|n| n != a && n != b && m.position(n).distance(target) > high)
        };
        let (da, db) = (self.degree[a as usize], self.degree[b as usize]);
        crate::checks::checked_assert_eq!(
            (da, db),
            (self.degree_now(m, a), self.degree_now(m, b)),
            "stale feature degrees"
        );
        match (da, db) {
            (0, 0) => {
                // One walk over the neighbours for all three targets, stopping once none fits.
                let targets = [(pa + pb) / 2.0, pa, pb];
                let mut fit = [true; 3];
                for n in around(a).chain(around(b)) {
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
            _ if self.feature[e as usize] => [(h, db), (m.twin(h), da)]
                .into_iter()
                .filter(|&(_, degree)| degree == 2)
                .find(|&(keep, _)| {
                    let target = m.position(m.tip(m.twin(keep)));
                    fits(target) && self.slides_along_line(m, keep)
                })
                .map(|(keep, _)| (keep, m.position(m.tip(m.twin(keep))))),
            _ => None,
        }
    }

    /// How many feature edges meet at `v` as the tables are now (for the checks).
    fn degree_now(&self, m: &FlatTriangles, v: u32) -> u8 {
        m.outgoing(v)
            .filter(|&o| self.feature[m.edge(o) as usize])
            .count() as u8
    }

    /// Whether removing the tip `r` of the feature halfedge `keep` (from `k`) keeps its
    /// feature line: `r`'s other feature neighbour `x` is not a wing of the collapse (that
    /// would merge two feature edges into one), and `r` lies within L/20 of the new segment
    /// `k x`.
    fn slides_along_line(&self, m: &FlatTriangles, keep: u32) -> bool {
        let (k, r) = (m.tip(m.twin(keep)), m.tip(keep));
        let wings = [keep, m.twin(keep)].map(|x| m.has_face(x).then(|| m.tip(m.next(x))));
        let Some(x) = m
            .outgoing(r)
            .find(|&o| m.tip(o) != k && self.feature[m.edge(o) as usize])
            .map(|o| m.tip(o))
        else {
            return false;
        };
        if wings.contains(&Some(x)) {
            return false;
        }
        let (pr, pk, px) = (m.position(r), m.position(k), m.position(x));
        distance_to_segment(pr, pk, px) <= self.low / 16.0
    }
}
