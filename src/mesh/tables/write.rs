//! Tables → entities: making a mesh's elements be a set of tables.
//!
//! [`spawn_connectivity`] spawns tables as a new mesh; [`replace_contents`] (and the undo
//! records, through `write_tables`) makes an existing mesh's elements be new tables, reusing
//! its entities row for row. Both are two passes: `reserve_rows` makes the right number of
//! entities of each kind exist (old ones kept, new ones batch-spawned with placeholder links,
//! a new mesh's with the attribute components the tables' columns give them, so that no row
//! moves table when the columns are written; the surplus despawned), then `write_links` writes
//! every link and position. Between the two
//! the world holds placeholders, so they run back to back; the bulk operations (subdivision,
//! progressive refinement) put their table computation in between, on another thread
//! (`reserve_rows_while`). Those passes are crate-internal for that reason.
//!
//! Guarantees: consistent tables (see [`super`]) become a mesh that passes
//! [`crate::mesh::validate()`]; every element is spawned once and never seen half-linked by
//! anything outside these calls; the first rows of each kind keep the entities of the old rows
//! (a selected vertex stays selected).

use bevy::ecs::bundle::NoBundleEffect;
use bevy::math::{Vec2, Vec3};
use bevy::prelude::Bundle;
use bevy::prelude::{Entity, World};
use std::sync::atomic::{AtomicBool, Ordering};

use bevy::ecs::entity::ContainsEntity;
use bevy::ecs::query::IterQueryData;
use bevy::prelude::Component;

use super::connectivity::Connectivity;
use super::rows::{EdgeRow, FaceRow, HalfedgeRow, NONE, RowCounts, VertexRow};
use crate::mesh::attributes::{
    CornerUv, MeshAttributes, Seam, VertexColor, VertexNormal, remove_attributes, set_record,
};
use crate::mesh::despawn::Despawner;
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
use crate::mesh::groups::{FaceGroup, GroupTable};
use crate::mesh::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;
use crate::process_memory;

/// Spawns halfedge tables as a new mesh: one entity per element, all links set. Returns the
/// mesh and the entities of every row, by kind, in table order.
///
/// The tables must be consistent (as [`Connectivity::from_corners`] makes them); the result is
/// then a mesh that passes [`crate::mesh::validate()`].
pub fn spawn_connectivity(
    world: &mut World,
    c: &Connectivity,
    info: MeshInfo,
) -> (MeshId, MeshMembers) {
    let mesh = MeshId(world.spawn(info).id());
    let rows = write_tables(world, c, mesh, None);
    (mesh, rows)
}

/// Replaces the contents of `mesh` with `tables`, reusing the old entities row for row (the
/// first `old.vertices.len()` table vertices keep their vertex entities, so a selected vertex
/// stays selected) and spawning or despawning the difference. Returns the entity of every row.
pub fn replace_contents(
    world: &mut World,
    mesh: MeshId,
    old: &MeshMembers,
    tables: &Connectivity,
) -> MeshMembers {
    write_tables(world, tables, mesh, Some(old))
}

/// Makes the elements of `mesh` be exactly the tables `c`, reusing the entities of `old` (the
/// mesh's current elements) row for row where it can, despawning the old ones left over and
/// batch-spawning the missing ones. Returns the entities of every row, by kind, in table order.
///
/// Two passes: [`reserve_rows`] (with pages faulted in ahead on a second thread when the
/// tables are large), then [`write_links`].
pub(crate) fn write_tables(
    world: &mut World,
    c: &Connectivity,
    mesh: MeshId,
    old: Option<&MeshMembers>,
) -> MeshMembers {
    let counts = c.row_counts();
    // Only a new mesh's rows: an old mesh's rows may still carry attributes the tables drop,
    // and new rows spawned into the final tables ahead of the old rows moving there would come
    // first in storage order.
    let with = match old {
        None => SpawnWith::of(c),
        Some(_) => SpawnWith::NONE,
    };
    let rows = faulting_in_ahead_of_rows(counts, || {
        reserve_rows(world, counts, mesh, old, with, &mut |_| {})
    });
    write_links(world, c, mesh, &rows);
    rows
}

/// Writes of at least this many rows fault the heap's pages in on a second thread while the
/// rows are made ([`reserve_rows_while`]), where the program keeps freed memory (elsewhere that
/// thread would do nothing): about 10 MB of them, where that saves milliseconds and starting
/// the thread costs microseconds.
const FAULT_AHEAD_ROWS: usize = 100_000;

/// Runs `make_rows` while a second thread faults the heap's pages in ahead of it
/// ([`process_memory::faulting_in_ahead`], as far around the top of the heap as the rows take),
/// for at least [`FAULT_AHEAD_ROWS`] rows: most of making a large mesh's rows exist in a fresh
/// process is the kernel handing out pages. Fewer rows are made on this thread alone.
pub(super) fn faulting_in_ahead_of_rows<T>(counts: RowCounts, make_rows: impl FnOnce() -> T) -> T {
    if counts.total() < FAULT_AHEAD_ROWS {
        return make_rows();
    }
    let bytes = counts.total().saturating_mul(process_memory::BYTES_PER_ROW);
    process_memory::faulting_in_ahead(bytes, make_rows)
}

/// The attribute components a new mesh's rows are spawned with, so that writing the attribute
/// columns afterwards ([`write_attributes`]) finds them in place instead of moving every row
/// into another archetype: Bevy keeps the capacity of a table or archetype it empties, and grows the
/// one the rows move into by doubling, one row at a time.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SpawnWith {
    /// Every halfedge row gets a `CornerUv` (a boundary halfedge's is then removed: few move).
    corner_uvs: bool,
    /// Every vertex row gets a `VertexNormal`.
    normals: bool,
    /// Every vertex row gets a `VertexColor`.
    colors: bool,
}

impl SpawnWith {
    /// None: rows whose attribute columns are not known yet (a bulk operation computing its
    /// tables while the rows are made).
    pub(crate) const NONE: Self = Self {
        corner_uvs: false,
        normals: false,
        colors: false,
    };

    /// What [`write_attributes`] will give the rows of `c`.
    fn of(c: &Connectivity) -> Self {
        let fit = fitting_columns(c);
        Self {
            corner_uvs: fit.uv,
            normals: fit.normals,
            colors: fit.colors,
        }
    }
}

/// Makes `counts` rows of each kind exist in `mesh`: the entities of `old` first (reused as
/// they are), then new ones spawned in one batch per kind with placeholder links; the rest of
/// `old` is despawned. The rows are not a mesh until [`write_links`] fills them, so the two
/// must run back to back (in between, other work that does not touch the world may run:
/// subdivision computes its tables on another thread meanwhile).
///
/// Batch spawning is the cheaper way in Bevy 0.19: 52–56 ns an entity against 71–85 ns for
/// spawning at allocated ids (31–35 ns in memory already faulted in, up to 280 ns in fresh
/// memory on the development VM).
///
/// `progress` is told the fraction of the rows made after each kind (vertices, halfedges,
/// edges, faces).
pub(crate) fn reserve_rows(
    world: &mut World,
    counts: RowCounts,
    mesh: MeshId,
    old: Option<&MeshMembers>,
    with: SpawnWith,
    progress: &mut dyn FnMut(f32),
) -> MeshMembers {
    let total = counts.total().max(1) as f32;
    let mut made = 0usize;
    let mut done = |rows: usize| {
        made += rows;
        progress(made as f32 / total);
    };
    let member = InMesh(mesh);
    let none = HalfedgeId(Entity::PLACEHOLDER);
    let old_of = |f: fn(&MeshMembers) -> Vec<Entity>| old.map(f).unwrap_or_default();
    let vertex = (Vertex { halfedge: none }, Position(Vec3::ZERO), member);
    let old_vertices = old_of(|o| o.vertices.iter().map(|v| v.0).collect());
    let n = counts.vertices;
    let (normal, color) = (VertexNormal(Vec3::ZERO), VertexColor([0; 3]));
    let vertices = match (with.normals, with.colors) {
        (false, false) => entities_for(world, n, old_vertices, vertex),
        (true, false) => entities_after(world, n, old_vertices, vertex, (vertex, normal)),
        (false, true) => entities_after(world, n, old_vertices, vertex, (vertex, color)),
        (true, true) => entities_after(world, n, old_vertices, vertex, (vertex, normal, color)),
    };
    done(counts.vertices);
    let placeholder = Halfedge {
        twin: none,
        next: none,
        prev: none,
        vertex: VertexId(Entity::PLACEHOLDER),
        edge: EdgeId(Entity::PLACEHOLDER),
        face: None,
    };
    let old_halfedges = old_of(|o| o.halfedges.iter().map(|h| h.0).collect());
    let (n, halfedge) = (counts.halfedges, (placeholder, member));
    let halfedges = match with.corner_uvs {
        false => entities_for(world, n, old_halfedges, halfedge),
        true => entities_after(
            world,
            n,
            old_halfedges,
            halfedge,
            (halfedge, CornerUv(Vec2::ZERO)),
        ),
    };
    done(counts.halfedges);
    let edges = entities_for(
        world,
        counts.edges,
        old_of(|o| o.edges.iter().map(|e| e.0).collect()),
        (Edge { halfedge: none }, member),
    );
    done(counts.edges);
    let faces = entities_for(
        world,
        counts.faces,
        old_of(|o| o.faces.iter().map(|f| f.0).collect()),
        (Face { halfedge: none }, member),
    );
    done(counts.faces);
    MeshMembers {
        vertices: vertices.into_iter().map(VertexId).collect(),
        halfedges: halfedges.into_iter().map(HalfedgeId).collect(),
        edges: edges.into_iter().map(EdgeId).collect(),
        faces: faces.into_iter().map(FaceId).collect(),
    }
}

/// [`reserve_rows`] on this thread while `compute` runs on another: the two largest costs of a
/// bulk rewrite (making the entities exist, computing the new tables) overlapped. Returns what
/// `compute` returned and the rows; a panic in `compute` is passed on. `progress` follows the
/// rows made, as [`reserve_rows`] tells it.
///
/// Making the rows exist is the longer of the two in a fresh process: most of it is the kernel
/// faulting in the new table columns. So once `compute` is done, its thread faults in the
/// heap's pages ahead of this one until the rows exist
/// ([`process_memory::fault_in_heap_while`], as far around the top of the heap as the rows
/// take).
pub(crate) fn reserve_rows_while<T: Send>(
    world: &mut World,
    counts: RowCounts,
    mesh: MeshId,
    old: Option<&MeshMembers>,
    with: SpawnWith,
    progress: &mut dyn FnMut(f32),
    compute: impl FnOnce() -> T + Send,
) -> (T, MeshMembers) {
    let reserved = AtomicBool::new(false);
    let rows_bytes = counts.total().saturating_mul(process_memory::BYTES_PER_ROW);
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let computed = compute();
            process_memory::fault_in_heap_while(rows_bytes, || !reserved.load(Ordering::Relaxed));
            computed
        });
        let rows = {
            // Set when the rows exist, or when making them panics (the worker then stops).
            let _reserved = process_memory::SetOnDrop(&reserved);
            reserve_rows(world, counts, mesh, old, with, progress)
        };
        let computed = worker
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (computed, rows)
    })
}

/// Despawns the rows of `rows` past `keep` (of each kind): what [`reserve_rows`] made beyond
/// what the tables turned out to need.
pub(crate) fn release_rows(world: &mut World, rows: &mut MeshMembers, keep: RowCounts) {
    let surplus = rows
        .vertices
        .drain(keep.vertices.min(rows.vertices.len())..);
    let mut gone: Vec<Entity> = surplus.map(|v| v.0).collect();
    gone.extend(
        rows.halfedges
            .drain(keep.halfedges.min(rows.halfedges.len())..)
            .map(|h| h.0),
    );
    gone.extend(
        rows.edges
            .drain(keep.edges.min(rows.edges.len())..)
            .map(|e| e.0),
    );
    gone.extend(
        rows.faces
            .drain(keep.faces.min(rows.faces.len())..)
            .map(|f| f.0),
    );
    let mut despawner = Despawner::new(world);
    for e in gone {
        despawner.despawn(e);
    }
}

/// Writes every link of the tables `c` into the rows `rows` (from [`reserve_rows`] with
/// `c.row_counts()`; in one walk through each table where the world holds only this mesh,
/// else a lookup per entity: see `for_each_row`), and the attribute columns the tables carry
/// ([`write_attributes`]) into `mesh`.
///
/// # Panics
/// If the row counts differ from the tables' (a bug in the caller).
pub(crate) fn write_links(world: &mut World, c: &Connectivity, mesh: MeshId, rows: &MeshMembers) {
    assert_eq!(
        c.row_counts(),
        RowCounts::of_rows(rows),
        "rows reserved for other tables"
    );
    let h = |x: HalfedgeRow| rows.halfedges[x.index()];
    for_each_row::<(&mut Vertex, &mut Position), _>(world, &rows.vertices, |i, (mut x, mut p)| {
        let v = VertexRow::new(i as u32);
        x.halfedge = h(c.vertex_halfedge(v));
        p.0 = c.position(v);
    });
    for_each_row::<&mut Halfedge, _>(world, &rows.halfedges, |i, mut x| {
        *x = halfedge_of_row(c, rows, HalfedgeRow::new(i as u32));
    });
    for_each_row::<&mut Edge, _>(world, &rows.edges, |i, mut x| {
        x.halfedge = h(c.edge_halfedge(EdgeRow::new(i as u32)));
    });
    for_each_row::<&mut Face, _>(world, &rows.faces, |i, mut x| {
        x.halfedge = h(c.face_halfedge(FaceRow::new(i as u32)));
    });
    write_attributes(world, c, mesh, rows);
}

/// Halfedge row `i` of `c` as its component, each link the entity of its row in `rows`.
fn halfedge_of_row(c: &Connectivity, rows: &MeshMembers, i: HalfedgeRow) -> Halfedge {
    let h = |x: HalfedgeRow| rows.halfedges[x.index()];
    Halfedge {
        twin: h(c.twin(i)),
        next: h(c.next(i)),
        prev: h(c.prev(i)),
        vertex: rows.vertices[c.to_vertex(i).index()],
        edge: rows.edges[c.edge(i).index()],
        face: c.face(i).map(|f| rows.faces[f.index()]),
    }
}

/// Writes the links of the listed rows of `c` into their entities (`rows`, row for row, as
/// [`write_links`] writes every row): each listed vertex's halfedge and position, each listed
/// halfedge's six links, each listed face's halfedge. For a pass that edited a few rows of
/// tables read by [`super::extract`] and spawned or despawned nothing. It writes no edge's
/// halfedge and no attribute column: a pass that changes those needs [`write_links`]. A row
/// listed twice is written twice, a row whose entity is gone is skipped.
pub(crate) fn write_listed_rows(
    world: &mut World,
    c: &Connectivity,
    rows: &MeshMembers,
    (vertices, halfedges, faces): (&[VertexRow], &[HalfedgeRow], &[FaceRow]),
) {
    let h = |x: HalfedgeRow| rows.halfedges[x.index()];
    let mut q = world.query::<(&mut Vertex, &mut Position)>();
    for &v in vertices {
        if let Ok((mut x, mut p)) = q.get_mut(world, rows.vertices[v.index()].0) {
            x.halfedge = h(c.vertex_halfedge(v));
            p.0 = c.position(v);
        }
    }
    let mut q = world.query::<&mut Halfedge>();
    for &i in halfedges {
        if let Ok(mut x) = q.get_mut(world, rows.halfedges[i.index()].0) {
            *x = halfedge_of_row(c, rows, i);
        }
    }
    let mut q = world.query::<&mut Face>();
    for &f in faces {
        if let Ok(mut x) = q.get_mut(world, rows.faces[f.index()].0) {
            x.halfedge = h(c.face_halfedge(f));
        }
    }
}

/// Calls `write(i, item)` with the `D` item of `rows[i]`, for every row. When the world's `D`
/// items are exactly `rows`, in order (a world holding one mesh whose rows were made in one
/// pass: the command line's, a script's), that is one walk through the table in storage
/// order; otherwise a lookup per row (12–18 ns each: the entity's location, then its row).
/// The walk checks every entity against `rows` and, at the first that differs, leaves the
/// rest to the lookups, which then write every row.
pub(super) fn for_each_row<D: IterQueryData, Id: ContainsEntity>(
    world: &mut World,
    rows: &[Id],
    mut write: impl FnMut(usize, D::Item<'_, '_>),
) {
    let mut q = world.query::<(Entity, D)>();
    if q.iter_mut(world).size_hint().1 == Some(rows.len()) {
        let mut walked = 0;
        for ((e, item), row) in q.iter_mut(world).zip(rows) {
            if e != row.entity() {
                break;
            }
            write(walked, item);
            walked += 1;
        }
        if walked == rows.len() {
            return;
        }
    }
    for (i, row) in rows.iter().enumerate() {
        if let Ok((_, item)) = q.get_mut(world, row.entity()) {
            write(i, item);
        }
    }
}

/// The attribute columns of `c` that fit its rows (one value a row of their kind, groups that
/// name rows of their table): those [`write_attributes`] writes; a column that does not fit is
/// left out.
fn fitting_columns(c: &Connectivity) -> MeshAttributes {
    let columns = &c.attributes;
    let counts = c.row_counts();
    MeshAttributes {
        uv: columns.uv.as_ref().map(Vec::len) == Some(counts.halfedges),
        normals: columns.normals.as_ref().map(Vec::len) == Some(counts.vertices),
        colors: columns.colors.as_ref().map(Vec::len) == Some(counts.vertices),
        seams: columns.seams.as_ref().map(Vec::len) == Some(counts.edges),
        groups: columns
            .groups
            .as_ref()
            .is_some_and(|g| g.fits(counts.faces)),
    }
}

/// Makes the attributes of `mesh` be the columns of `c` (see [`crate::mesh::attributes`]),
/// whose rows are the entities `rows` (as [`write_links`], its one caller, checks): a column
/// that fits ([`fitting_columns`]) is written into its components (UVs on face halfedges only) and
/// recorded on the mesh; an attribute the mesh had and the tables do not carry is removed from
/// every element and from the record. A mesh that had none, written from tables that carry
/// none, costs one lookup.
pub(crate) fn write_attributes(
    world: &mut World,
    c: &Connectivity,
    mesh: MeshId,
    rows: &MeshMembers,
) {
    let before = MeshAttributes::of(world, mesh);
    let columns = &c.attributes;
    if before.is_empty() && columns.is_empty() {
        return;
    }
    let now = fitting_columns(c);
    let uv = columns.uv.as_deref().filter(|_| now.uv);
    let normals = columns.normals.as_deref().filter(|_| now.normals);
    let colors = columns.colors.as_deref().filter(|_| now.colors);
    let seams = columns.seams.as_deref().filter(|_| now.seams);
    let groups = columns.groups.as_ref().filter(|_| now.groups);
    remove_attributes(world, mesh, before.lost_in(now));
    if let Some(uv) = uv {
        let corners = rows
            .halfedges
            .iter()
            .zip(&c.face)
            .zip(uv)
            .map(|((h, &f), &uv)| (h.0, (f != NONE).then_some(uv)));
        write_column(world, corners.collect(), CornerUv);
    }
    if let Some(normals) = normals {
        let values = rows
            .vertices
            .iter()
            .zip(normals)
            .map(|(v, &n)| (v.0, Some(n)));
        write_column(world, values.collect(), VertexNormal);
    }
    if let Some(colors) = colors {
        let values = rows
            .vertices
            .iter()
            .zip(colors)
            .map(|(v, &x)| (v.0, Some(x)));
        write_column(world, values.collect(), VertexColor);
    }
    if let Some(seams) = seams {
        let values = rows
            .edges
            .iter()
            .zip(seams)
            .map(|(e, &seam)| (e.0, seam.then_some(())));
        write_column(world, values.collect(), |()| Seam);
    }
    if let Some(groups) = groups {
        if world.get::<GroupTable>(mesh.0) != Some(&groups.table) {
            world.entity_mut(mesh.0).insert(groups.table.clone());
        }
        let values = rows
            .faces
            .iter()
            .zip(&groups.of_face)
            .map(|(f, &g)| (f.0, Some(g)));
        write_column(world, values.collect(), FaceGroup);
    }
    set_record(world, mesh, now);
}

/// Gives each entity its value as component `C` (overwritten where it has one, inserted in one
/// batch where it has none), or removes `C` where its value is `None`.
fn write_column<T: Copy, C: Component<Mutability = bevy::ecs::component::Mutable>>(
    world: &mut World,
    values: Vec<(Entity, Option<T>)>,
    wrap: fn(T) -> C,
) {
    let mut missing: Vec<(Entity, C)> = Vec::new();
    let mut extra: Vec<Entity> = Vec::new();
    let mut q = world.query::<Option<&mut C>>();
    for (e, value) in values {
        match (q.get_mut(world, e), value) {
            (Ok(Some(mut x)), Some(v)) => *x = wrap(v),
            (Ok(Some(_)), None) => extra.push(e),
            (Ok(None), Some(v)) => missing.push((e, wrap(v))),
            _ => {}
        }
    }
    world.insert_batch(missing);
    for e in extra {
        world.entity_mut(e).remove::<C>();
    }
}

/// `n` entities of one kind: the first of `old`, then new ones spawned in one batch with
/// `placeholder`; the rest of `old` is despawned.
fn entities_for<B>(world: &mut World, n: usize, old: Vec<Entity>, placeholder: B) -> Vec<Entity>
where
    B: bevy::prelude::Bundle<Effect: bevy::ecs::bundle::NoBundleEffect> + Clone,
{
    let mut ids = kept(world, n, old);
    let keep = ids.len();
    ids.extend(world.spawn_batch(std::iter::repeat_n(placeholder, n - keep)));
    ids
}

/// [`entities_for`] with the new rows spawned as `with` (the placeholder and attribute
/// components), the table of the `bare` placeholder made first (a batch of none of it): tables
/// are then made in the order they were when the attributes were inserted after the spawn,
/// and queries meet them in that order.
fn entities_after<B, W>(
    world: &mut World,
    n: usize,
    old: Vec<Entity>,
    bare: B,
    with: W,
) -> Vec<Entity>
where
    B: Bundle<Effect: NoBundleEffect> + Clone,
    W: Bundle<Effect: NoBundleEffect> + Clone,
{
    let mut ids = kept(world, n, old);
    let keep = ids.len();
    world.spawn_batch(std::iter::repeat_n(bare, 0));
    ids.extend(world.spawn_batch(std::iter::repeat_n(with, n - keep)));
    ids
}

/// The first `n` entities of `old` (the rows kept); the rest of `old` despawned, and the freed
/// ids about to be taken for the `n - kept` new rows sorted.
fn kept(world: &mut World, n: usize, old: Vec<Entity>) -> Vec<Entity> {
    let keep = old.len().min(n);
    // Last row first: rows a bulk edit spawned sit at the end of their table in row order, so
    // each despawn then takes the table's last row, moving no other row into its place (and
    // the rows kept stay in order).
    let mut despawner = Despawner::new(world);
    for &e in old[keep..].iter().rev() {
        despawner.despawn(e);
    }
    let mut ids = old;
    ids.truncate(keep);
    sort_free_ids(world, n - keep);
    ids
}

/// Puts the next `count` ids Bevy will hand out in ascending index order, where they come from
/// freed ones.
///
/// Bevy reuses freed ids first, in the order they were freed; after a simplification that is
/// a random order, and spawning and then linking rows whose ids are scattered misses the cache
/// on every entity (the bulk refine of the bunny spent 57 ms there, 29 ms with sorted ids).
/// So the freed ids about to be reused are taken, sorted and handed back: the batch spawn then
/// takes them again, front to back. Fresh ids are in order already, and a world that has freed
/// none (a mesh just loaded and subdivided) pays nothing.
pub(super) fn sort_free_ids(world: &mut World, count: usize) {
    let spawned: usize = world.archetypes().iter().map(|a| a.len() as usize).sum();
    let freed = (world.entities().len() as usize).saturating_sub(spawned);
    let Ok(count) = u32::try_from(count.min(freed)) else {
        return;
    };
    if count == 0 {
        return;
    }
    let mut ids: Vec<Entity> = world.entity_allocator().alloc_many(count).collect();
    ids.sort_unstable_by_key(|e| e.index_u32());
    world.entity_allocator_mut().free_many(&ids);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes each row's place in `rows` into its position's x, and reads every entity's back.
    fn written(world: &mut World, rows: &[VertexId]) -> Vec<f32> {
        for_each_row::<&mut Position, _>(world, rows, |i, mut p| p.0.x = i as f32);
        rows.iter()
            .map(|v| world.get::<Position>(v.0).unwrap().0.x)
            .collect()
    }

    #[test]
    fn every_row_gets_its_value_whether_walked_or_looked_up() {
        let mut world = World::new();
        let rows: Vec<VertexId> = world
            .spawn_batch(std::iter::repeat_n(Position(Vec3::NAN), 1000))
            .map(VertexId)
            .collect();
        let expected: Vec<f32> = (0..1000).map(|i| i as f32).collect();
        // In storage order: one walk.
        assert_eq!(written(&mut world, &rows), expected);
        // Reversed: the walk stops at the first entity and the lookups write every row.
        let reversed: Vec<VertexId> = rows.iter().rev().copied().collect();
        assert_eq!(written(&mut world, &reversed), expected);
        // The last two swapped: the walk writes most rows, the lookups all of them again.
        let mut swapped = rows.clone();
        swapped.swap(998, 999);
        assert_eq!(written(&mut world, &swapped), expected);
        // More entities with the component than rows: lookups only.
        world.spawn(Position(Vec3::ZERO));
        assert_eq!(written(&mut world, &rows[..500]), expected[..500]);
    }

    /// Rows spawned with the attribute components their columns give them: writing the
    /// columns then moves no row, so no table is left holding the capacity of rows that moved
    /// out (the halfedge tables' capacities sum to the halfedges, not twice them).
    #[test]
    fn rows_are_spawned_with_their_attributes_and_move_no_table() {
        use crate::mesh::{build_mesh, shapes, validate};
        let mut soup = shapes::grid_with_holes(3);
        let (corners, vertices) = (soup.indices.len(), soup.positions.len());
        soup.corner_uvs = Some((0..corners).map(|k| Vec2::new(k as f32, 1.0)).collect());
        soup.vertex_normals = Some(vec![Vec3::Z; vertices]);
        soup.vertex_colors = Some(vec![[1, 2, 3]; vertices]);
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        assert!(validate(&world, mesh).is_ok());
        let capacity_of = |world: &World, id| -> (usize, usize) {
            let mut held = (0, 0);
            // Archetypes that differ by a sparse-set component share a table.
            let mut tables: Vec<_> = world
                .archetypes()
                .iter()
                .filter(|a| a.contains(id))
                .map(|a| a.table_id())
                .collect();
            tables.sort_unstable_by_key(|t| t.as_usize());
            tables.dedup();
            for table in tables {
                let table = world.storages().tables.get(table).unwrap();
                held.0 += table.capacity();
                held.1 += table.entity_count() as usize;
            }
            held
        };
        let members = MeshMembers::collect(&world, mesh);
        for (id, rows) in [
            (world.component_id::<Halfedge>(), members.halfedges.len()),
            (world.component_id::<Vertex>(), members.vertices.len()),
        ] {
            let (capacity, held) = capacity_of(&world, id.unwrap());
            assert_eq!(held, rows);
            assert!(
                capacity <= rows + 8,
                "{capacity} rows' room for {rows} rows"
            );
        }
        // Every corner has its UV, every boundary halfedge none; every vertex its normal and
        // colour.
        let uvs = members
            .halfedges
            .iter()
            .filter(|h| world.get::<CornerUv>(h.0).is_some())
            .count();
        assert_eq!(uvs, corners);
        for v in &members.vertices {
            assert_eq!(world.get::<VertexColor>(v.0), Some(&VertexColor([1, 2, 3])));
            assert_eq!(world.get::<VertexNormal>(v.0), Some(&VertexNormal(Vec3::Z)));
        }
    }
}
