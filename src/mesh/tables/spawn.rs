//! Tables → a new mesh in one pass: every element spawned with its links already written.
//!
//! Loading a file spends most of its time and memory making the rows of a new mesh exist. The
//! general writer ([`super::write`]) spawns placeholder rows, then writes every link through the
//! list of each row's entity: two passes over six entities a face, and that list (8 bytes an
//! entity) held beside the tables and the World at the load's peak. A new mesh in a world with
//! no freed ids waiting needs neither. Bevy hands out fresh ids in order, so the rows get the
//! ids right after the mesh entity's, kind after kind, and each link can be written at spawn as
//! the id its row is foreseen to get ([`spawn_tables`]).
//!
//! - **Foreseen or not.** Each batch checks the ids it got against the foreseen ones. Where the
//!   allocator handed out others, the batch lists the ids it got, and once every kind exists
//!   the links are translated from the ids foreseen to the ids got. A mesh entity that is itself
//!   a reused id says that freed ids wait (the editor, after closing a mesh): the general writer
//!   then spawns the rows, taking the freed ids in order as it does for every bulk write. A mesh
//!   with attribute columns is spawned by the general writer too, which spawns rows with their
//!   attribute components.
//! - **Memory.** The tables are taken by value and each kind's columns are released once its
//!   rows exist, so at the end of the load the World stands nearly alone: no tables, no list of
//!   entities.
//!
//! The mesh is the general writer's, entity for entity and link for link: each batch sets ids
//! aside first as the general writer does (`sort_free_ids`), and the foresight models what that
//! takes ([`Numbering`]), so ties broken by entity order fall the same way.

use bevy::ecs::bundle::NoBundleEffect;
use bevy::ecs::entity::EntityGeneration;
use bevy::prelude::{Bundle, Entity, World};

use super::connectivity::Connectivity;
use super::rows::{NONE, RowCounts};
use super::write::{faulting_in_ahead_of_rows, for_each_row, sort_free_ids, write_tables};
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
use crate::mesh::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::members::MeshMembers;

/// The entities of one kind's rows, in row order: foreseen (consecutive fresh ids from
/// `first`, as Bevy hands them out where no freed id waits) or, where the allocator gave
/// others, listed.
#[derive(Clone, Debug)]
enum RowIds {
    Foreseen { first: u32, len: usize },
    Listed { first: u32, ids: Vec<Entity> },
}

impl RowIds {
    fn len(&self) -> usize {
        match self {
            Self::Foreseen { len, .. } => *len,
            Self::Listed { ids, .. } => ids.len(),
        }
    }

    fn get(&self, row: usize) -> Entity {
        match self {
            Self::Foreseen { first, .. } => foreseen(*first, row as u32),
            Self::Listed { ids, .. } => ids[row],
        }
    }

    /// The id got by the row whose foreseen id is `e` (`e` itself where the ids came as
    /// foreseen).
    fn got(&self, e: Entity) -> Entity {
        match self {
            Self::Foreseen { .. } => e,
            Self::Listed { first, ids } => ids[e.index_u32().wrapping_sub(*first) as usize],
        }
    }

    fn to_vec<T>(&self, wrap: fn(Entity) -> T) -> Vec<T> {
        (0..self.len()).map(|row| wrap(self.get(row))).collect()
    }
}

/// The id Bevy hands out `row` places after the fresh id `first` (generation one, as every fresh
/// id has). Past the largest index it is the placeholder, which no spawned entity is, so the
/// check of the batch fails and its ids are listed.
fn foreseen(first: u32, row: u32) -> Entity {
    first
        .checked_add(row)
        .and_then(Entity::from_raw_u32)
        .unwrap_or(Entity::PLACEHOLDER)
}

/// The rows of a mesh spawned by [`spawn_tables`]: the entity of every row, by kind, in table
/// order. Holds four numbers where the world's ids came as foreseen, the lists where not.
#[derive(Clone, Debug)]
pub struct SpawnedRows {
    vertices: RowIds,
    halfedges: RowIds,
    edges: RowIds,
    faces: RowIds,
}

impl SpawnedRows {
    /// How many rows of each kind.
    pub fn counts(&self) -> RowCounts {
        RowCounts {
            vertices: self.vertices.len(),
            halfedges: self.halfedges.len(),
            edges: self.edges.len(),
            faces: self.faces.len(),
        }
    }

    /// The vertex of row `row`.
    ///
    /// # Panics
    /// Past the last vertex row.
    pub fn vertex(&self, row: u32) -> VertexId {
        assert!((row as usize) < self.vertices.len(), "no vertex row {row}");
        VertexId(self.vertices.get(row as usize))
    }

    /// The face of row `row`.
    ///
    /// # Panics
    /// Past the last face row.
    pub fn face(&self, row: u32) -> FaceId {
        assert!((row as usize) < self.faces.len(), "no face row {row}");
        FaceId(self.faces.get(row as usize))
    }

    /// Every row's entity as lists (8 bytes an element).
    pub fn members(&self) -> MeshMembers {
        MeshMembers {
            vertices: self.vertices.to_vec(VertexId),
            halfedges: self.halfedges.to_vec(HalfedgeId),
            edges: self.edges.to_vec(EdgeId),
            faces: self.faces.to_vec(FaceId),
        }
    }

    /// Rows the general writer made: every kind listed.
    fn listed(rows: MeshMembers) -> Self {
        let list = |ids: Vec<Entity>| RowIds::Listed { first: 0, ids };
        Self {
            vertices: list(rows.vertices.into_iter().map(|v| v.0).collect()),
            halfedges: list(rows.halfedges.into_iter().map(|h| h.0).collect()),
            edges: list(rows.edges.into_iter().map(|e| e.0).collect()),
            faces: list(rows.faces.into_iter().map(|f| f.0).collect()),
        }
    }

    fn all_foreseen(&self) -> bool {
        [&self.vertices, &self.halfedges, &self.edges, &self.faces]
            .iter()
            .all(|ids| matches!(ids, RowIds::Foreseen { .. }))
    }
}

/// Spawns the tables `c` as a new mesh, each element with its links written as it is spawned,
/// and returns the mesh and the entity of every row. The mesh is the one
/// [`super::spawn_connectivity`] gives for the same tables, element for element in the same
/// storage order; what differs is the cost: one pass instead of two, no list of every row's
/// entity where the ids came as foreseen, and each kind's columns released once its rows exist.
/// Where freed ids wait, or the tables carry attribute columns, the general writer spawns it.
///
/// The tables must be consistent (as [`Connectivity::from_corners`] makes them); the result is
/// then a mesh that passes [`crate::mesh::validate()`].
pub fn spawn_tables(
    world: &mut World,
    mut c: Connectivity,
    info: MeshInfo,
) -> (MeshId, SpawnedRows) {
    let mesh = MeshId(world.spawn(info).id());
    if mesh.0.generation() != EntityGeneration::FIRST || !c.attributes.is_empty() {
        let rows = write_tables(world, &c, mesh, None);
        return (mesh, SpawnedRows::listed(rows));
    }
    let counts = c.row_counts();
    let rows = faulting_in_ahead_of_rows(counts, || spawn_rows(world, &mut c, mesh));
    if !rows.all_foreseen() {
        correct_links(world, &rows);
    }
    (mesh, rows)
}

/// Where each kind's rows are foreseen to start.
struct Firsts {
    vertex: u32,
    halfedge: u32,
    edge: u32,
    face: u32,
}

impl Firsts {
    /// The ids the general writer's batches get, kind after kind, in a world whose free list is
    /// empty and whose fresh ids continue after `mesh`'s ([`Numbering`]).
    fn after(world: &World, mesh: MeshId, counts: RowCounts) -> Self {
        let mut numbering = Numbering {
            cursor: mesh.0.index_u32() as usize + 1,
            records: world.entities().len() as usize,
            spawned: world.archetypes().iter().map(|a| a.len() as usize).sum(),
            set_aside: 0,
        };
        let at = |first: usize| u32::try_from(first).unwrap_or(u32::MAX);
        Self {
            vertex: at(numbering.batch(counts.vertices)),
            halfedge: at(numbering.batch(counts.halfedges)),
            edge: at(numbering.batch(counts.edges)),
            face: at(numbering.batch(counts.faces)),
        }
    }
}

/// How Bevy 0.19 numbers the general writer's batches: a model of the allocator, checked by
/// every batch against the ids it got (a wrong guess costs a translation pass, never a wrong
/// link).
///
/// Before each batch, `sort_free_ids` takes as many ids as it counts freed, up to the batch's
/// size, and frees them back sorted. It counts the entity records beyond the spawned entities,
/// and Bevy pads its records to their capacity, so in a world with no freed id it takes fresh
/// ids: more than the 128 Bevy keeps in its local buffer go back to the free list, and the batch
/// takes them first, in order; fewer stay in that buffer, out of the allocator's sight, and the
/// batch starts after them. Each batch then grows the records by doubling, one entity at a
/// time, to past its last index.
struct Numbering {
    /// The next fresh index.
    cursor: usize,
    /// The length of Bevy's entity records (always their capacity).
    records: usize,
    /// How many entities are spawned.
    spawned: usize,
    /// How many fresh ids sit in Bevy's local free buffer.
    set_aside: usize,
}

impl Numbering {
    /// The local free buffer's size in Bevy 0.19.
    const LOCAL_FREE: usize = 128;

    /// The first index of a batch of `n`, and the state after it.
    fn batch(&mut self, n: usize) -> usize {
        let taken = n.min(self.records.saturating_sub(self.spawned));
        let first = match taken {
            0 => self.cursor,
            _ if taken <= Self::LOCAL_FREE - self.set_aside => {
                self.set_aside += taken;
                self.cursor + taken
            }
            _ => self.cursor,
        };
        self.cursor = first + n;
        self.spawned += n;
        if n > 0 {
            let last = first + n - 1;
            while self.records <= last {
                let index = self.records.max(first);
                self.records = (self.records * 2).max(index + 1).max(4);
            }
        }
        first
    }
}

/// Spawns every row of `c` in `mesh`, kind after kind, links foreseen; releases each kind's
/// columns once its rows exist.
fn spawn_rows(world: &mut World, c: &mut Connectivity, mesh: MeshId) -> SpawnedRows {
    let at = Firsts::after(world, mesh, c.row_counts());
    let member = InMesh(mesh);
    let h = |row: u32| HalfedgeId(foreseen(at.halfedge, row));
    let vertices = spawn_kind(
        world,
        at.vertex,
        c.positions
            .iter()
            .zip(&c.vertex_halfedge)
            .map(|(&p, &x)| (Vertex { halfedge: h(x) }, Position(p), member)),
    );
    release(&mut [&mut c.vertex_halfedge]);
    c.positions = Vec::new();
    let halfedges = spawn_kind(
        world,
        at.halfedge,
        (0..c.twin.len()).map(|i| {
            let halfedge = Halfedge {
                twin: h(c.twin[i]),
                next: h(c.next[i]),
                prev: h(c.prev[i]),
                vertex: VertexId(foreseen(at.vertex, c.to_vertex[i])),
                edge: EdgeId(foreseen(at.edge, c.edge[i])),
                face: (c.face[i] != NONE).then(|| FaceId(foreseen(at.face, c.face[i]))),
            };
            (halfedge, member)
        }),
    );
    release(&mut [
        &mut c.twin,
        &mut c.next,
        &mut c.prev,
        &mut c.to_vertex,
        &mut c.edge,
        &mut c.face,
    ]);
    let edges = spawn_kind(
        world,
        at.edge,
        c.edge_halfedge
            .iter()
            .map(|&x| (Edge { halfedge: h(x) }, member)),
    );
    release(&mut [&mut c.edge_halfedge]);
    let faces = spawn_kind(
        world,
        at.face,
        c.face_halfedge
            .iter()
            .map(|&x| (Face { halfedge: h(x) }, member)),
    );
    release(&mut [&mut c.face_halfedge]);
    SpawnedRows {
        vertices,
        halfedges,
        edges,
        faces,
    }
}

/// Gives the memory of each column back.
fn release(columns: &mut [&mut Vec<u32>]) {
    for column in columns {
        **column = Vec::new();
    }
}

/// Spawns one kind's rows in one batch, from freed ids sorted first as the general writer does
/// (so with the ids it would give them), and checks each id against the one foreseen from
/// `first`; from the first that differs the ids are listed.
fn spawn_kind<B>(world: &mut World, first: u32, bundles: impl ExactSizeIterator<Item = B>) -> RowIds
where
    B: Bundle<Effect: NoBundleEffect>,
{
    let len = bundles.len();
    sort_free_ids(world, len);
    let mut listed: Option<Vec<Entity>> = None;
    for (row, id) in world.spawn_batch(bundles).enumerate() {
        match &mut listed {
            Some(ids) => ids.push(id),
            None if id == foreseen(first, row as u32) => {}
            None => {
                let mut ids = Vec::with_capacity(len);
                ids.extend((0..row as u32).map(|r| foreseen(first, r)));
                ids.push(id);
                listed = Some(ids);
            }
        }
    }
    match listed {
        None => RowIds::Foreseen { first, len },
        Some(ids) => RowIds::Listed { first, ids },
    }
}

/// Rewrites every link written as a foreseen id into the id its row got, for the kinds whose
/// ids were not as foreseen (a walk through each kind, as the general writer's links).
fn correct_links(world: &mut World, rows: &SpawnedRows) {
    let members = rows.members();
    let h = |x: HalfedgeId| HalfedgeId(rows.halfedges.got(x.0));
    for_each_row::<&mut Vertex, _>(world, &members.vertices, |_, mut x| {
        x.halfedge = h(x.halfedge);
    });
    for_each_row::<&mut Halfedge, _>(world, &members.halfedges, |_, mut x| {
        x.twin = h(x.twin);
        x.next = h(x.next);
        x.prev = h(x.prev);
        x.vertex = VertexId(rows.vertices.got(x.vertex.0));
        x.edge = EdgeId(rows.edges.got(x.edge.0));
        x.face = x.face.map(|f| FaceId(rows.faces.got(f.0)));
    });
    for_each_row::<&mut Edge, _>(world, &members.edges, |_, mut x| {
        x.halfedge = h(x.halfedge);
    });
    for_each_row::<&mut Face, _>(world, &members.faces, |_, mut x| {
        x.halfedge = h(x.halfedge);
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::attributes::CornerUv;
    use crate::mesh::tables::{extract, spawn_connectivity};
    use crate::mesh::{PolygonSoup, build_mesh, shapes, to_soup, validate};
    use bevy::math::{Vec2, Vec3};

    /// The tables of `soup`, laid out as a load lays them out.
    fn tables_of(soup: &PolygonSoup) -> Connectivity {
        let mut scratch = World::new();
        let built = build_mesh(&mut scratch, soup, MeshInfo::default()).unwrap();
        extract(&scratch, built.mesh).tables
    }

    /// Fresh ids set free, more than Bevy keeps aside before handing freed ids out: the mesh
    /// entity and its rows then get ids, fresh in generation, that are not in a row.
    fn world_with_fresh_ids_freed() -> World {
        let mut world = World::new();
        let ids: Vec<Entity> = world.entity_allocator().alloc_many(300).collect();
        let scattered: Vec<Entity> = ids
            .iter()
            .step_by(2)
            .chain(ids.iter().skip(1).step_by(2))
            .copied()
            .collect();
        world.entity_allocator_mut().free_many(&scattered);
        world
    }

    /// A world whose freed ids were despawned entities: a reused id names the mesh.
    fn world_with_despawned_ids() -> World {
        let mut world = World::new();
        let ids: Vec<Entity> = world
            .spawn_batch((0..300).map(|i| Position(Vec3::splat(i as f32))))
            .collect();
        for (k, &e) in ids.iter().enumerate() {
            if k % 3 != 1 {
                world.despawn(e);
            }
        }
        world
    }

    /// Spawned in one pass, a mesh is the general writer's: the same tables read back (so the
    /// same storage order and links), the same soup, valid; in a fresh world (ids foreseen), where
    /// fresh ids were freed (foreseen wrongly, links translated), and where despawned ids wait
    /// (the general writer's path); with boundaries and with corner UVs.
    #[test]
    fn one_pass_spawn_is_the_general_writers_mesh() {
        let mut with_uvs = shapes::grid_with_holes(2);
        let corners = with_uvs.indices.len();
        with_uvs.corner_uvs = Some((0..corners).map(|k| Vec2::new(k as f32, 0.5)).collect());
        for soup in [shapes::icosphere(2), shapes::grid_with_holes(3), with_uvs] {
            let tables = tables_of(&soup);
            let worlds = [
                World::new as fn() -> World,
                world_with_fresh_ids_freed,
                world_with_despawned_ids,
            ];
            for world_of in worlds {
                let (mut general, mut one_pass) = (world_of(), world_of());
                let (a, _) = spawn_connectivity(&mut general, &tables, MeshInfo::default());
                let (b, rows) = spawn_tables(&mut one_pass, tables.clone(), MeshInfo::default());
                assert!(validate(&one_pass, b).is_ok());
                assert_eq!(extract(&one_pass, b).tables, tables);
                assert_eq!(to_soup(&one_pass, b), to_soup(&general, a));
                assert_eq!(rows.members(), extract(&one_pass, b).members);
                let uvs = |world: &World, mesh| {
                    let members = MeshMembers::collect(world, mesh);
                    members
                        .halfedges
                        .iter()
                        .filter(|h| world.get::<CornerUv>(h.0).is_some())
                        .count()
                };
                assert_eq!(uvs(&one_pass, b), uvs(&general, a));
            }
        }
    }

    /// In a fresh world the rows hold four numbers, not a list; where fresh ids were freed they
    /// are listed; where despawned ids wait the general writer makes them; each row still names
    /// its entity.
    #[test]
    fn rows_are_foreseen_in_a_fresh_world_and_listed_otherwise() {
        // Large enough for Bevy's records to double many times, and with boundaries.
        for soup in [shapes::icosphere(5), shapes::grid_with_holes(40)] {
            let (_, fresh) = spawn_tables(&mut World::new(), tables_of(&soup), MeshInfo::default());
            assert!(fresh.all_foreseen());
        }
        let tables = tables_of(&shapes::icosphere(1));
        for world_of in [
            world_with_fresh_ids_freed as fn() -> World,
            world_with_despawned_ids,
        ] {
            let mut world = world_of();
            let (mesh, rows) = spawn_tables(&mut world, tables.clone(), MeshInfo::default());
            assert!(!rows.all_foreseen());
            assert_eq!(rows.counts(), tables.row_counts());
            assert_eq!(rows.members(), extract(&world, mesh).members);
            assert_eq!(rows.vertex(0), rows.members().vertices[0]);
            assert_eq!(rows.face(3), rows.members().faces[3]);
        }
    }
}
