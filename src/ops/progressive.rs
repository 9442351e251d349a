//! Progressive meshes (Hoppe 1996): a simplification recorded collapse by collapse, so that
//! the mesh can move between its coarsest and its full level, both ways, exactly.
//!
//! Entity ids cannot name vertices across levels: a vertex split makes a *new* entity for the
//! vertex it brings back, and later records would go stale. So the history names vertices by
//! *slot*, a number that stays with a vertex for the life of the history; a table maps each
//! slot to the entity that currently holds it. Splitting record `i` back needs every vertex that
//! existed when collapse `i` was made; refining in reverse order guarantees it, and records
//! nest naturally (a vertex made by a split can be the kept vertex or a wing of an earlier one).
//!
//! Moving down again replays the recorded collapse of the same pair of vertices to the same
//! position, so coarsen and refine can be interleaved freely.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::prelude::World;

use crate::mesh::change::remapped;
use crate::mesh::elements::Vertex;
use crate::mesh::ids::{ElementId, MeshId, VertexId, slots_for};
use crate::mesh::members::of_kind;
use crate::mesh::tables::write::{SpawnWith, release_rows, reserve_rows_while, write_links};
use crate::mesh::tables::{Connectivity, RowCounts, VertexRow, extract};
use crate::mesh::topology::MeshRef;

use super::Refusal;
use super::local::{
    CollapseOptions, CollapseRecord, CollapseResult, apply_collapse, plan_collapse_halfedge,
    vertex_split,
};
pub use super::simplify::SlotRecord;
use super::simplify::{SimplifyParams, SimplifySummary, simplify_recorded};
use super::table_split::{SplitMismatch, TableSplit, split_in_tables};

use crate::ops::declaration::{DROPPED_BY_SIMPLIFICATION, Declaration, Parameter};

/// Moving along the simplification history (the `refine` step, the level-of-detail slider):
/// the history survives, and like the simplification it drops attributes.
pub const LEVEL_OF_DETAIL: Declaration = Declaration::new("refine")
    .titled("Refine")
    .described(
        "go along the simplification history to FACES faces: split its collapses back (or \
         redo them), exactly the input at the full mesh",
    )
    .with_parameters(&[
        Parameter::whole("FACES", 1000, 0, u32::MAX).automatic_by_default("the full mesh")
    ])
    .merging_while_held()
    .keeping_history()
    .dropping(DROPPED_BY_SIMPLIFICATION);

/// Refining takes the bulk path (tables, then one write of the whole mesh) when it makes at
/// least one split for every this many faces the mesh has now. Measured on the bunny: one
/// split on entities costs about 4.5 µs (a dozen single spawns and lookups), a whole-mesh
/// rewrite about 0.34 µs a face; a 1 % slider step averaged 2.0 ms over the whole range with
/// 16 here, 2.1 ms with 10 or 25, 2.8 ms with 100 and 12 ms always in bulk. Refining from
/// the coarsest level goes in bulk.
const FACES_PER_BULK_SPLIT: usize = 16;

/// What a move along the levels did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LevelMove {
    /// Splits and collapses made.
    pub steps: usize,
    /// Whether the mesh was rewritten as a whole (the bulk refine path): every element may
    /// have changed, so a renderer must redraw all of it. Otherwise only what the watched
    /// vertices touch changed.
    pub rewritten: bool,
}

/// A mesh's simplification history and where along it the mesh is now.
#[derive(Clone, Debug)]
pub struct ProgressiveMesh {
    /// The mesh the history belongs to.
    pub mesh: MeshId,
    /// Collapses in the order they were made.
    pub records: Vec<SlotRecord>,
    /// How many of them are applied now (`records.len()`: the coarsest level).
    pub applied: usize,
    /// Faces at the full level.
    pub full_faces: usize,
    slots: Vec<Option<VertexId>>,
}

/// Each vertex's history slot, by entity index: one array read a lookup, where hashing cost
/// more than the rest of recording.
pub struct SlotIndex(Vec<u32>);

impl SlotIndex {
    /// The slots of the vertices `pm` holds now.
    pub fn of(pm: &ProgressiveMesh) -> Self {
        let live = || pm.slots.iter().flatten().map(|v| v.0);
        let mut slot_of = vec![u32::MAX; slots_for(live())];
        for (slot, v) in pm.slots.iter().enumerate() {
            if let Some(v) = v {
                slot_of[v.slot()] = slot as u32;
            }
        }
        Self(slot_of)
    }

    /// `v`'s slot.
    ///
    /// # Panics
    /// When `v` held no slot when the index was taken.
    pub fn slot(&self, v: VertexId) -> u32 {
        let slot = self.0.get(v.slot()).copied().unwrap_or(u32::MAX);
        assert_ne!(slot, u32::MAX, "{v} has no history slot");
        slot
    }
}

impl ProgressiveMesh {
    /// Simplifies `mesh` as [`crate::ops::simplify::simplify`] does and records every collapse.
    ///
    /// # Refusals
    /// As [`crate::ops::simplify::simplify`].
    pub fn simplify(
        world: &mut World,
        mesh: MeshId,
        params: &SimplifyParams,
    ) -> Result<(ProgressiveMesh, SimplifySummary), Refusal> {
        Self::simplify_with_progress(world, mesh, params, |_| true)
    }

    /// [`ProgressiveMesh::simplify`] with a progress callback, as
    /// [`crate::ops::simplify::simplify_with_progress`] (stopping early records the collapses
    /// made so far).
    ///
    /// # Refusals
    /// As [`crate::ops::simplify::simplify`].
    pub fn simplify_with_progress(
        world: &mut World,
        mesh: MeshId,
        params: &SimplifyParams,
        progress: impl FnMut(f32) -> bool,
    ) -> Result<(ProgressiveMesh, SimplifySummary), Refusal> {
        let mut records = Vec::new();
        let (summary, slots) = simplify_recorded(world, mesh, params, progress, |r| {
            records.push(r);
        })?;
        let mut pm = ProgressiveMesh {
            mesh,
            applied: records.len(),
            records,
            full_faces: summary.faces_before,
            slots,
        };
        if params.fit_to_input {
            pm.settle_coarsest(world);
        }
        Ok((pm, summary))
    }

    /// An empty history of `mesh` at its full level (`faces` faces, every vertex given the
    /// next slot), for [`Self::push`] to record collapses into as they are made.
    pub fn start(world: &World, mesh: MeshId, faces: usize) -> Self {
        ProgressiveMesh {
            mesh,
            records: Vec::new(),
            applied: 0,
            full_faces: faces,
            slots: of_kind::<Vertex, _>(world, mesh, |v| Some(VertexId(v))),
        }
    }

    /// Records the collapse `r` just made on `world`, which leaves the mesh at the new
    /// coarsest level; `index` must be this history's [`SlotIndex`] (collapses only remove
    /// vertices, so one index serves every collapse after it was taken). The merged position
    /// is where the collapse put the kept vertex.
    ///
    /// # Panics
    /// When the history is not at its coarsest level (a collapse pushed there would not be
    /// the next one), or `r` names a vertex the history does not hold.
    pub fn push(&mut self, world: &World, index: &SlotIndex, r: &CollapseResult) {
        assert_eq!(
            self.applied,
            self.records.len(),
            "a collapse is recorded at the coarsest level"
        );
        let slot = |v: VertexId| index.slot(v);
        let rec = &r.record;
        let record = SlotRecord {
            kept: slot(r.kept),
            removed: slot(r.removed),
            merged_position: MeshRef::new(world).position(r.kept),
            kept_position: rec.kept_position,
            removed_position: rec.removed_position,
            left: rec.left.map(slot),
            right: rec.right.map(slot),
            faces: rec.triangles_removed(),
        };
        self.slots[record.removed as usize] = None;
        self.records.push(record);
        self.applied += 1;
    }

    /// Makes the mesh as it stands the history's coarsest level: each vertex's place there is
    /// the merged position of the last collapse that kept it, which this sets to where the
    /// vertex is now in `world`, so that a move made after the collapses (the simplification's
    /// fit to its input) is found again when the history comes back to that level. Vertices no
    /// collapse kept have no such place ([`Self::never_kept`]) and are left out.
    ///
    /// # Panics
    /// When the history is not at its coarsest level.
    pub fn settle_coarsest(&mut self, world: &World) {
        assert_eq!(
            self.applied,
            self.records.len(),
            "the history is settled at its coarsest level"
        );
        let m = MeshRef::new(world);
        let mut settled = vec![false; self.slots.len()];
        for r in self.records.iter_mut().rev() {
            let slot = r.kept as usize;
            if !std::mem::replace(&mut settled[slot], true)
                && let Some(p) = self.slots[slot].and_then(|v| m.try_position(v))
            {
                r.merged_position = p;
            }
        }
    }

    /// The vertices at this level that no applied collapse kept: each is where the full mesh
    /// has it, and the history has no place of its own for it.
    pub fn never_kept(&self) -> EntityHashSet {
        let mut kept = vec![false; self.slots.len()];
        for r in &self.records[..self.applied] {
            kept[r.kept as usize] = true;
        }
        self.slots
            .iter()
            .zip(&kept)
            .filter_map(|(v, &k)| v.filter(|_| !k).map(|v| v.0))
            .collect()
    }

    /// The vertex holding each slot now (`None`: collapsed away at this level).
    pub fn slots(&self) -> &[Option<VertexId>] {
        &self.slots
    }

    /// Moves the history to another world: `mesh` is the mesh there, and `map` takes each
    /// vertex entity the history names to the entity that holds that vertex there (vertices not
    /// in the map keep their ids).
    pub fn remap(&mut self, mesh: MeshId, map: &EntityHashMap<bevy::prelude::Entity>) {
        self.mesh = mesh;
        for v in self.slots.iter_mut().flatten() {
            v.0 = remapped(map, v.0);
        }
    }

    /// Faces at the current level.
    pub fn faces(&self) -> usize {
        self.full_faces
            - self.records[..self.applied]
                .iter()
                .map(|r| r.faces)
                .sum::<usize>()
    }

    fn vertex(&self, slot: u32) -> Result<VertexId, Refusal> {
        self.slots[slot as usize].ok_or_else(|| {
            Refusal::HistoryMismatch(format!("history slot {slot} has no vertex now"))
        })
    }

    /// Splits the last applied collapse back. Returns `false` at the full level.
    ///
    /// # Refusals
    /// When the mesh was edited outside the history so that the split no longer fits.
    pub fn refine_one(&mut self, world: &mut World) -> Result<bool, Refusal> {
        let Some(i) = self.applied.checked_sub(1) else {
            return Ok(false);
        };
        let r = self.records[i];
        let record = CollapseRecord {
            kept: self.vertex(r.kept)?,
            kept_position: r.kept_position,
            removed_position: r.removed_position,
            left: r.left.map(|s| self.vertex(s)).transpose()?,
            right: r.right.map(|s| self.vertex(s)).transpose()?,
            invertible: true,
        };
        let b = vertex_split(world, &record)?;
        self.slots[r.removed as usize] = Some(b);
        self.applied = i;
        Ok(true)
    }

    /// Collapses the next recorded edge again. Returns `false` at the coarsest level.
    ///
    /// # Refusals
    /// When the mesh was edited outside the history so that the collapse no longer fits.
    pub fn coarsen_one(&mut self, world: &mut World) -> Result<bool, Refusal> {
        let Some(&r) = self.records.get(self.applied) else {
            return Ok(false);
        };
        let (a, b) = (self.vertex(r.kept)?, self.vertex(r.removed)?);
        let h = MeshRef::new(world).find_halfedge(a, b).ok_or_else(|| {
            Refusal::HistoryMismatch(format!("{a} and {b} are no longer joined by an edge"))
        })?;
        let plan = plan_collapse_halfedge(
            world,
            h,
            CollapseOptions {
                position: Some(r.merged_position),
                max_normal_change_deg: None,
            },
        )?;
        apply_collapse(world, plan);
        self.slots[r.removed as usize] = None;
        self.applied += 1;
        Ok(true)
    }

    /// The vertex whose split comes next (the one the last applied collapse kept), if any.
    pub fn next_split_vertex(&self) -> Option<VertexId> {
        let r = self.records.get(self.applied.checked_sub(1)?)?;
        self.slots[r.kept as usize]
    }

    /// Splits back the last collapse if `v` is the vertex it kept — the one split a vertex can
    /// take without undoing other collapses first. Returns the vertex made again.
    ///
    /// # Refusals
    /// When `v` is not the vertex kept by the last applied collapse (the message says which
    /// vertex is), or as [`Self::refine_one`].
    pub fn refine_vertex(&mut self, world: &mut World, v: VertexId) -> Result<VertexId, Refusal> {
        let Some(i) = self.applied.checked_sub(1) else {
            return Err(Refusal::AtFullLevel);
        };
        let r = self.records[i];
        let kept = self.vertex(r.kept)?;
        if kept != v {
            return Err(Refusal::NotNextSplit(
                ElementId::Vertex(v),
                ElementId::Vertex(kept),
            ));
        }
        self.refine_one(world)?;
        self.vertex(r.removed)
    }

    /// Moves to the level closest to `faces` faces (refining or coarsening as needed). Returns
    /// how many splits or collapses it made.
    ///
    /// # Refusals
    /// As [`Self::refine_one`] and [`Self::coarsen_one`]; the mesh is then valid, at the level
    /// reached so far.
    pub fn go_to_faces(&mut self, world: &mut World, faces: usize) -> Result<usize, Refusal> {
        self.go_to_faces_watching(world, faces, |_, _| {})
            .map(|moved| moved.steps)
    }

    /// [`Self::go_to_faces`], calling `touched(world, v)` for every vertex a step involves (the
    /// kept and removed vertex and the wings), before and after the step — what a renderer
    /// needs to redraw only what changed. A long refine goes in bulk instead
    /// ([`LevelMove::rewritten`]), and calls `touched` for no vertex.
    ///
    /// # Refusals
    /// As [`Self::go_to_faces`].
    pub fn go_to_faces_watching(
        &mut self,
        world: &mut World,
        faces: usize,
        mut touched: impl FnMut(&World, VertexId),
    ) -> Result<LevelMove, Refusal> {
        if world.get::<crate::mesh::MeshInfo>(self.mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(self.mesh)));
        }
        let mut moved = LevelMove::default();
        let mut now = self.faces();
        let splits = self.records[..self.applied]
            .iter()
            .rev()
            .scan(now, |at, r| {
                (*at < faces).then(|| {
                    *at += r.faces;
                })
            })
            .count();
        if splits > 0 && splits * FACES_PER_BULK_SPLIT >= now {
            moved.rewritten = true;
            moved.steps = self.refine_in_bulk(world, splits)?;
            now = self.faces();
        }
        let mut watch = |pm: &ProgressiveMesh, world: &World, r: SlotRecord| {
            for slot in [Some(r.kept), Some(r.removed), r.left, r.right]
                .into_iter()
                .flatten()
            {
                if let Some(v) = pm.slots[slot as usize] {
                    touched(world, v);
                }
            }
        };
        while now < faces && self.applied > 0 {
            let r = self.records[self.applied - 1];
            watch(self, world, r);
            self.refine_one(world)?;
            watch(self, world, r);
            now += r.faces;
            moved.steps += 1;
        }
        while now > faces && self.applied < self.records.len() {
            let r = self.records[self.applied];
            watch(self, world, r);
            self.coarsen_one(world)?;
            watch(self, world, r);
            now -= r.faces;
            moved.steps += 1;
        }
        Ok(moved)
    }

    /// Splits back the last `count` applied collapses on flat tables and writes the mesh back
    /// once ([`split_in_tables`]; surviving elements keep their entities). The row counts
    /// after the splits follow from the records, so the new entities are spawned while
    /// another thread replays the splits. Returns how many it made: `count`, unless a record
    /// no longer fits, in which case the splits before it are kept, written back, and the
    /// refusal returned.
    fn refine_in_bulk(&mut self, world: &mut World, count: usize) -> Result<usize, Refusal> {
        let extracted = extract(world, self.mesh);
        let old = &extracted.members;
        let row_of = old.vertex_rows();
        // Each slot's table row, as the splits go (rows for the vertices they make are new);
        // `NONE` for a slot with no vertex at this level.
        let mut rows: Vec<VertexRow> = self
            .slots
            .iter()
            .map(|v| {
                v.and_then(|v| row_of.get(&v.0).copied())
                    .map_or(VertexRow::NONE, VertexRow::new)
            })
            .collect();
        let records = &self.records[self.applied - count..self.applied];
        let faces: usize = records.iter().map(|r| r.faces).sum();
        let before = extracted.tables.row_counts();
        let added = RowCounts {
            vertices: count,
            halfedges: 2 * (count + faces),
            edges: count + faces,
            faces,
        };
        let mut tables = extracted.tables;
        tables.reserve(added);
        let ((made, refusal), mut written) = reserve_rows_while(
            world,
            before.plus(added),
            self.mesh,
            Some(old),
            SpawnWith::NONE,
            &mut |_| {},
            || replay(&mut tables, records, &mut rows, &old.vertices),
        );
        // A refusal left fewer rows than were reserved: the surplus goes.
        release_rows(world, &mut written, tables.row_counts());
        write_links(world, &tables, self.mesh, &written);
        for (slot, &row) in self.slots.iter_mut().zip(&rows) {
            *slot = (!row.is_none()).then(|| written.vertices[row.index()]);
        }
        self.applied -= made;
        refusal.map_or(Ok(made), Err)
    }

    /// The refusal for a split that does not fit, naming vertices by the entities they had
    /// before the bulk refine began (`old`, by row).
    fn mismatch(why: SplitMismatch, split: &TableSplit, old: &[VertexId]) -> Refusal {
        let name = |row: VertexRow| {
            old.get(row.index())
                .map_or("a vertex this refine made".to_string(), |v| v.to_string())
        };
        Refusal::HistoryMismatch(match why {
            SplitMismatch::NotNeighbour(w) => format!(
                "{} is no longer a neighbour of {}",
                name(w),
                name(split.kept)
            ),
            SplitMismatch::NotOnBoundary => format!(
                "{} is not on the boundary, but the collapse it undoes was",
                name(split.kept)
            ),
            SplitMismatch::NoWing => "a record names no face to make again".to_string(),
        })
    }
}

/// Replays the splits of `records`, the last first, on `tables`; `rows` maps each history
/// slot to its table row ([`VertexRow::NONE`] while its vertex is collapsed away) and follows
/// the splits. Stops at the first record that no longer
/// fits. Returns how many splits it made, and the refusal if it stopped (vertices named by
/// `old`, the entities of the rows that existed before).
fn replay(
    tables: &mut Connectivity,
    records: &[SlotRecord],
    rows: &mut [VertexRow],
    old: &[VertexId],
) -> (usize, Option<Refusal>) {
    for (made, r) in records.iter().rev().enumerate() {
        let row = |slot: u32| match rows[slot as usize] {
            VertexRow::NONE => Err(Refusal::HistoryMismatch(format!(
                "history slot {slot} has no vertex now"
            ))),
            row => Ok(row),
        };
        let split = (|| {
            Ok(TableSplit {
                kept: row(r.kept)?,
                left: r.left.map(row).transpose()?,
                right: r.right.map(row).transpose()?,
                kept_position: r.kept_position,
                removed_position: r.removed_position,
            })
        })();
        let result = split.and_then(|split| {
            split_in_tables(tables, &split)
                .map_err(|why| ProgressiveMesh::mismatch(why, &split, old))
        });
        match result {
            Ok(b) => rows[r.removed as usize] = b,
            Err(why) => return (made, Some(why)),
        }
    }
    (records.len(), None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, mesh_stats, shapes, validate};
    use crate::ops::local::flip_edge;

    /// A bulk refine that meets a record the mesh no longer fits (it was edited outside the
    /// history) stops there: the splits before it are written back, the mesh is valid, and the
    /// history stands at the level reached.
    #[test]
    fn a_bulk_refine_that_meets_an_edited_mesh_stops_valid() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(3), MeshInfo::default()).unwrap();
        let mesh = built.mesh;
        let faces = mesh_stats(&world, mesh).faces;
        let params = SimplifyParams::ratio(0.05);
        let (mut pm, _) = ProgressiveMesh::simplify(&mut world, mesh, &params).unwrap();
        // Edges between a kept vertex and its wing, from records a quarter of the way back
        // into the history, among the vertices alive now: flipping one breaks that record.
        let candidates: Vec<_> = {
            let m = MeshRef::new(&world);
            (0..pm.applied - pm.applied / 4)
                .rev()
                .filter_map(|i| {
                    let r = pm.records[i];
                    let (a, c) = (pm.slots[r.kept as usize]?, pm.slots[r.left? as usize]?);
                    Some(m.edge(m.find_halfedge(a, c)?))
                })
                .collect()
        };
        assert!(
            candidates
                .into_iter()
                .any(|e| flip_edge(&mut world, e).is_ok()),
            "no record edge could be flipped"
        );
        let coarsest = pm.faces();
        let refused = pm.go_to_faces(&mut world, usize::MAX).unwrap_err();
        assert!(refused.to_string().contains("no longer"), "{refused}");
        validate(&world, mesh).unwrap();
        assert_eq!(mesh_stats(&world, mesh).faces, pm.faces());
        assert!(pm.faces() > coarsest && pm.faces() < faces);
    }
}
