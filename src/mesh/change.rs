//! Recording what an edit changed, so that it can be undone and redone exactly.
//!
//! Three records, by the reach of the edit:
//! - [`Change`], for local edits (flip, split, collapse, a vertex move, …): the prior state of
//!   every element the edit touched. [`LocalRecorder`] captures a neighbourhood of the edit's
//!   seed vertices before it runs and compares it afterwards, keeping only what differs:
//!   elements removed (with their components), created (their ids) and modified (their old
//!   components). A few hundred bytes, whatever the size of the mesh.
//! - [`SavedContents`], for whole-mesh edits (subdivision, simplification, …): the mesh's
//!   [`MeshTables`] (flat index tables with the entity behind every row, about 32 bytes a
//!   halfedge, read by [`extract`]) and which mesh they are the contents of.
//! - [`SavedMesh`], for a mesh that is deleted or replaced: its contents and its [`MeshInfo`].
//!
//! Applying a record puts the world back in the recorded state and returns the inverse record
//! (apply that to redo) and a [`Remap`]. Bevy never hands out a despawned id again (the
//! generation is bumped), so elements brought back get new entities; the remap takes every id
//! the record held to the entity that now stands for it, and every other record that may name
//! those ids must be passed through it ([`Change::remap`], [`SavedContents::remap`]).
//!
//! States are compared bitwise (`-0.0` is not `0.0`), so an undo restores positions exactly.
//! Attributes travel with their elements: a local record holds each element's UV, normal and
//! colour beside its links (an edge its seam mark, a face its group), and the whole-mesh records hold the tables' attribute columns, whose
//! writer also restores the mesh's [`crate::mesh::attributes::MeshAttributes`] record.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Component, Entity, World};

use super::attributes::{CornerUv, Seam, VertexColor, VertexNormal};
use super::elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
use super::groups::FaceGroup;
use super::ids::{FaceId, MeshId, VertexId};
use super::members::MeshMembers;
use super::tables::write::write_tables;
use super::tables::{MeshTables, extract};
use super::topology::MeshRef;

/// From the ids a record held to the entities that stand for them after it was applied. Ids
/// not in the map are unchanged.
pub type Remap = EntityHashMap<Entity>;

/// Passes one id through a remap.
#[inline]
pub fn remapped(map: &Remap, e: Entity) -> Entity {
    map.get(&e).copied().unwrap_or(e)
}

/// Gives each entity `map` renames (from the entity an element had to the one that stands for
/// it now) the value its old entity has in `values`, keeping the old one's: what values kept by
/// entity beside the mesh do after an undo or redo brings elements back under new entities.
pub fn follow_renamed<T: Copy>(values: &mut EntityHashMap<T>, map: &Remap) {
    let moved: Vec<(Entity, T)> = (map.iter())
        .filter_map(|(old, &new)| Some((new, *values.get(old)?)))
        .collect();
    values.extend(moved);
}

/// A vertex's attributes (see [`crate::mesh::attributes`]), where it has them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexAttributes {
    /// Its normal.
    pub normal: Option<Vec3>,
    /// Its colour.
    pub color: Option<[u8; 3]>,
}

impl VertexAttributes {
    fn of(r: &bevy::ecs::world::EntityRef<'_>) -> Self {
        Self {
            normal: r.get::<VertexNormal>().map(|n| n.0),
            color: r.get::<VertexColor>().map(|c| c.0),
        }
    }

    fn bits(&self) -> (Option<[u32; 3]>, Option<[u8; 3]>) {
        (
            self.normal.map(|n| n.to_array().map(f32::to_bits)),
            self.color,
        )
    }
}

/// The components of one element, attributes included: what an undo writes back.
#[derive(Clone, Copy, Debug)]
pub enum ElementState {
    /// A vertex, its position and its attributes.
    Vertex(Vertex, Vec3, VertexAttributes),
    /// A halfedge and its corner's UV.
    Halfedge(Halfedge, Option<Vec2>),
    /// An edge and whether it is marked a seam.
    Edge(Edge, bool),
    /// A face and its group (a row of its mesh's group table).
    Face(Face, Option<u32>),
}

impl ElementState {
    /// The state of element `e`, or `None` if `e` is not a live element.
    pub fn of(world: &World, e: Entity) -> Option<Self> {
        let r = world.get_entity(e).ok()?;
        if let Some(h) = r.get::<Halfedge>() {
            Some(Self::Halfedge(*h, r.get::<CornerUv>().map(|c| c.0)))
        } else if let Some(v) = r.get::<Vertex>() {
            Some(Self::Vertex(
                *v,
                r.get::<Position>()?.0,
                VertexAttributes::of(&r),
            ))
        } else if let Some(x) = r.get::<Edge>() {
            Some(Self::Edge(*x, r.contains::<Seam>()))
        } else {
            r.get::<Face>()
                .map(|f| Self::Face(*f, r.get::<FaceGroup>().map(|g| g.0)))
        }
    }

    /// Equal links and bitwise-equal position and attributes.
    pub fn same(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Vertex(a, p, x), Self::Vertex(b, q, y)) => {
                a == b
                    && p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits)
                    && x.bits() == y.bits()
            }
            (Self::Halfedge(a, x), Self::Halfedge(b, y)) => {
                a == b
                    && x.map(|u| u.to_array().map(f32::to_bits))
                        == y.map(|u| u.to_array().map(f32::to_bits))
            }
            (Self::Edge(a, x), Self::Edge(b, y)) => a == b && x == y,
            (Self::Face(a, x), Self::Face(b, y)) => a == b && x == y,
            _ => false,
        }
    }

    /// Whether this is a vertex's state.
    pub fn is_vertex(&self) -> bool {
        matches!(self, Self::Vertex(..))
    }

    /// Passes every link through `map`.
    pub fn remap(&mut self, map: &mut Remap) {
        match self {
            Self::Vertex(v, ..) => Component::map_entities(v, map),
            Self::Halfedge(h, _) => Component::map_entities(h, map),
            Self::Edge(x, _) => Component::map_entities(x, map),
            Self::Face(f, _) => Component::map_entities(f, map),
        }
    }

    /// Overwrites live element `e` with this state (nothing if `e` is gone).
    fn write(self, world: &mut World, e: Entity) {
        let Ok(mut r) = world.get_entity_mut(e) else {
            return;
        };
        match self {
            Self::Vertex(v, p, a) => {
                if let Some(mut x) = r.get_mut::<Vertex>() {
                    *x = v;
                }
                if let Some(mut x) = r.get_mut::<Position>() {
                    x.0 = p;
                }
                match a.normal {
                    Some(n) => {
                        r.insert(VertexNormal(n));
                    }
                    None => {
                        r.remove::<VertexNormal>();
                    }
                }
                match a.color {
                    Some(c) => {
                        r.insert(VertexColor(c));
                    }
                    None => {
                        r.remove::<VertexColor>();
                    }
                }
            }
            Self::Halfedge(h, uv) => {
                if let Some(mut x) = r.get_mut::<Halfedge>() {
                    *x = h;
                }
                match uv {
                    Some(uv) => {
                        r.insert(CornerUv(uv));
                    }
                    None => {
                        r.remove::<CornerUv>();
                    }
                }
            }
            Self::Edge(edge, seam) => {
                if let Some(mut x) = r.get_mut::<Edge>() {
                    *x = edge;
                }
                if seam {
                    r.insert(Seam);
                } else {
                    r.remove::<Seam>();
                }
            }
            Self::Face(f, group) => {
                if let Some(mut x) = r.get_mut::<Face>() {
                    *x = f;
                }
                match group {
                    Some(g) => {
                        r.insert(FaceGroup(g));
                    }
                    None => {
                        r.remove::<FaceGroup>();
                    }
                }
            }
        }
    }

    /// Spawns this state as element `e` of `mesh` (`e` must be allocated and not spawned).
    fn spawn_at(self, world: &mut World, e: Entity, mesh: MeshId) {
        let member = InMesh(mesh);
        let spawned = match self {
            Self::Vertex(v, p, a) => world.spawn_at(e, (v, Position(p), member)).map(|mut x| {
                if let Some(n) = a.normal {
                    x.insert(VertexNormal(n));
                }
                if let Some(c) = a.color {
                    x.insert(VertexColor(c));
                }
            }),
            Self::Halfedge(h, uv) => world.spawn_at(e, (h, member)).map(|mut x| {
                if let Some(uv) = uv {
                    x.insert(CornerUv(uv));
                }
            }),
            Self::Edge(x, seam) => world.spawn_at(e, (x, member)).map(|mut x| {
                if seam {
                    x.insert(Seam);
                }
            }),
            Self::Face(f, group) => world.spawn_at(e, (f, member)).map(|mut x| {
                if let Some(g) = group {
                    x.insert(FaceGroup(g));
                }
            }),
        };
        // The entity was allocated just before: spawning it cannot fail.
        spawned.expect("a freshly allocated entity can be spawned");
    }
}

/// What a local edit changed, as the edit that undoes it: elements to bring back, to remove and
/// to overwrite. Applying it returns the change that redoes the edit.
#[derive(Clone, Debug)]
pub struct Change {
    /// The mesh the elements belong to.
    pub mesh: MeshId,
    spawn: Vec<(Entity, ElementState)>,
    despawn: Vec<Entity>,
    write: Vec<(Entity, ElementState)>,
}

/// Entities a change touched once applied, for redrawing.
#[derive(Clone, Debug, Default)]
pub struct Touched {
    /// Vertices spawned or overwritten (their current entities).
    pub vertices: Vec<VertexId>,
    /// Faces removed.
    pub removed_faces: Vec<FaceId>,
}

impl Change {
    /// Whether the change does nothing.
    pub fn is_empty(&self) -> bool {
        self.spawn.is_empty() && self.despawn.is_empty() && self.write.is_empty()
    }

    /// Elements it brings back, removes and overwrites.
    pub fn counts(&self) -> (usize, usize, usize) {
        (self.spawn.len(), self.despawn.len(), self.write.len())
    }

    /// Bytes held (what the history's memory cap counts).
    pub fn bytes(&self) -> usize {
        let state = std::mem::size_of::<(Entity, ElementState)>();
        std::mem::size_of::<Self>()
            + (self.spawn.capacity() + self.write.capacity()) * state
            + self.despawn.capacity() * std::mem::size_of::<Entity>()
    }

    /// Puts the recorded states back. Returns the inverse change, the remap from the ids of
    /// the elements brought back to their new entities, and what was touched.
    pub fn apply(self, world: &mut World) -> (Change, Remap, Touched) {
        let mut map = Remap::default();
        let fresh: Vec<Entity> = self
            .spawn
            .iter()
            .map(|&(old, _)| {
                let new = world.entity_allocator().alloc();
                map.insert(old, new);
                new
            })
            .collect();
        let state_of = |world: &World, &e: &Entity| Some((e, ElementState::of(world, e)?));
        let inverse = Change {
            mesh: self.mesh,
            spawn: self
                .despawn
                .iter()
                .filter_map(|e| state_of(world, e))
                .collect(),
            despawn: fresh.clone(),
            write: self
                .write
                .iter()
                .filter_map(|(e, _)| state_of(world, e))
                .collect(),
        };
        let mut touched = Touched::default();
        for &e in &self.despawn {
            if world.get::<Face>(e).is_some() {
                touched.removed_faces.push(FaceId(e));
            }
            world.despawn(e);
        }
        for ((_, mut state), e) in self.spawn.into_iter().zip(fresh) {
            state.remap(&mut map);
            state.spawn_at(world, e, self.mesh);
            if state.is_vertex() {
                touched.vertices.push(VertexId(e));
            }
        }
        for (e, mut state) in self.write {
            state.remap(&mut map);
            state.write(world, e);
            if state.is_vertex() {
                touched.vertices.push(VertexId(e));
            }
        }
        (inverse, map, touched)
    }

    /// Passes every id the change holds through `map`.
    pub fn remap(&mut self, map: &mut Remap) {
        self.mesh = MeshId(remapped(map, self.mesh.0));
        for (e, state) in self.spawn.iter_mut().chain(self.write.iter_mut()) {
            *e = remapped(map, *e);
            state.remap(map);
        }
        for e in &mut self.despawn {
            *e = remapped(map, *e);
        }
    }
}

/// Every element within reach of `seeds`: the seeds and their neighbours, and for each of those
/// its outgoing and incoming halfedges with their edges and tips, and every face around it with
/// all of the face's halfedges, their twins, edges and vertices. Dead seeds are skipped.
///
/// This is a superset of what any local operation on an edge or face at the seeds reads or
/// writes (the one-ring of both ends, the boundary loops through them, the wings' vertices).
pub fn neighbourhood(world: &World, seeds: &[VertexId]) -> EntityHashSet {
    let m = MeshRef::new(world);
    let mut ring: Vec<VertexId> = Vec::new();
    for &v in seeds {
        if m.try_vertex(v).is_some() {
            ring.push(v);
            ring.extend(m.vertex_neighbors(v));
        }
    }
    ring.sort_unstable();
    ring.dedup();
    let mut set = EntityHashSet::default();
    let mut faces = Vec::new();
    for &v in &ring {
        set.insert(v.0);
        for h in m.vertex_outgoing(v) {
            let t = m.twin(h);
            set.extend([h.0, t.0, m.edge(h).0, m.to_vertex(h).0]);
            faces.extend(m.face(h));
        }
    }
    faces.sort_unstable();
    faces.dedup();
    for f in faces {
        set.insert(f.0);
        for h in m.face_halfedges(f) {
            set.extend([h.0, m.twin(h).0, m.edge(h).0, m.to_vertex(h).0]);
        }
    }
    set
}

/// Records a local edit: [`LocalRecorder::begin`] before it, [`LocalRecorder::finish`] after.
pub struct LocalRecorder {
    mesh: MeshId,
    seeds: Vec<VertexId>,
    before: EntityHashMap<ElementState>,
    keep_seeds: bool,
    /// Only the seeds were captured (the edit changes nothing else).
    seeds_only: bool,
}

impl LocalRecorder {
    /// Captures the neighbourhood of `seeds` (the vertices the edit is about: an edge's ends, a
    /// face's corners, a moved vertex).
    pub fn begin(world: &World, mesh: MeshId, seeds: &[VertexId]) -> Self {
        Self::capture(world, mesh, seeds, neighbourhood(world, seeds), false)
    }

    /// Captures the seeds alone, for an edit that changes their states (positions,
    /// attributes) and nothing else: a move of a whole mesh records its vertices, not every
    /// element around them.
    pub fn begin_vertices(world: &World, mesh: MeshId, seeds: &[VertexId]) -> Self {
        Self::capture(world, mesh, seeds, seeds.iter().map(|v| v.0), true)
    }

    fn capture(
        world: &World,
        mesh: MeshId,
        seeds: &[VertexId],
        elements: impl IntoIterator<Item = Entity>,
        seeds_only: bool,
    ) -> Self {
        let before = elements
            .into_iter()
            .filter_map(|e| Some((e, ElementState::of(world, e)?)))
            .collect();
        Self {
            mesh,
            seeds: seeds.to_vec(),
            before,
            keep_seeds: false,
            seeds_only,
        }
    }

    /// With `keep`, the change records the seeds' prior state even where the edit left them
    /// as they were: for an edit that later edits merge into (the frames of a transform, some of
    /// which move a seed the first frame did not), so that undoing the merged step restores
    /// every seed.
    pub fn keeping_seeds(mut self, keep: bool) -> Self {
        self.keep_seeds = keep;
        self
    }

    /// Compares the neighbourhood (of the seeds still alive, and every element captured) with
    /// what was captured, and returns the change that undoes the edit.
    pub fn finish(self, world: &World) -> Change {
        let mut change = Change {
            mesh: self.mesh,
            spawn: Vec::new(),
            despawn: Vec::new(),
            write: Vec::new(),
        };
        let kept: EntityHashSet = match self.keep_seeds {
            true => self.seeds.iter().map(|v| v.0).collect(),
            false => EntityHashSet::default(),
        };
        for (&e, state) in &self.before {
            match ElementState::of(world, e) {
                None => change.spawn.push((e, *state)),
                Some(now) if !now.same(state) || kept.contains(&e) => {
                    change.write.push((e, *state));
                }
                Some(_) => {}
            }
        }
        let after = match self.seeds_only {
            true => EntityHashSet::default(),
            false => neighbourhood(world, &self.seeds),
        };
        change.despawn.extend(
            after
                .into_iter()
                .filter(|e| !self.before.contains_key(e) && ElementState::of(world, *e).is_some()),
        );
        // Hash order is arbitrary; a fixed order makes replays identical.
        change.spawn.sort_unstable_by_key(|(e, _)| *e);
        change.write.sort_unstable_by_key(|(e, _)| *e);
        change.despawn.sort_unstable();
        change
    }
}

/// A mesh's whole contents, to be put back into the same mesh entity: the record of a
/// whole-mesh edit.
#[derive(Clone)]
pub struct SavedContents {
    /// The mesh.
    pub mesh: MeshId,
    /// Its contents: the tables, with the entity behind every row.
    pub tables: MeshTables,
}

impl SavedContents {
    /// Reads `mesh` (which must be valid).
    pub fn capture(world: &World, mesh: MeshId) -> Self {
        Self {
            mesh,
            tables: extract(world, mesh),
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<MeshId>() + self.tables.bytes()
    }

    /// Makes the mesh's contents these tables again, reusing its current entities. Returns the
    /// contents it had (the inverse) and the remap from the recorded row ids to the entities
    /// that now hold those rows.
    pub fn apply(self, world: &mut World) -> (SavedContents, Remap) {
        let now = Self::capture(world, self.mesh);
        let rows = write_tables(
            world,
            &self.tables.tables,
            self.mesh,
            Some(&now.tables.members),
        );
        (now, row_map(&self.tables.members, &rows))
    }

    /// Passes every id held through `map`.
    pub fn remap(&mut self, map: &Remap) {
        self.mesh = MeshId(remapped(map, self.mesh.0));
        remap_members(&mut self.tables.members, map);
    }
}

/// A deleted or replaced mesh, to be brought back whole.
#[derive(Clone)]
pub struct SavedMesh {
    info: MeshInfo,
    contents: SavedContents,
}

impl SavedMesh {
    /// Reads `mesh` (which must be valid).
    pub fn capture(world: &World, mesh: MeshId) -> Self {
        Self {
            info: world.get::<MeshInfo>(mesh.0).cloned().unwrap_or_default(),
            contents: SavedContents::capture(world, mesh),
        }
    }

    /// The id the mesh had.
    pub fn mesh(&self) -> MeshId {
        self.contents.mesh
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.contents.bytes() + self.info.name.capacity()
    }

    /// Spawns the mesh again. Returns its new id and the remap from every id it had (the mesh
    /// and its elements) to the new ones.
    pub fn restore(self, world: &mut World) -> (MeshId, Remap) {
        let mesh = MeshId(world.spawn(self.info).id());
        let saved = &self.contents.tables;
        let rows = write_tables(world, &saved.tables, mesh, None);
        let mut map = row_map(&saved.members, &rows);
        map.insert(self.contents.mesh.0, mesh.0);
        (mesh, map)
    }

    /// Passes every id held through `map`.
    pub fn remap(&mut self, map: &Remap) {
        self.contents.remap(map);
    }
}

/// The bytes of a mesh's element components (links, positions, membership): a lower bound on
/// the mesh's size in the world, which adds entity bookkeeping and change ticks on top.
pub fn component_bytes(world: &World, mesh: MeshId) -> usize {
    use std::mem::size_of;
    let m = MeshMembers::collect(world, mesh);
    let member = size_of::<InMesh>();
    m.vertices.len() * (size_of::<Vertex>() + size_of::<Position>() + member)
        + m.halfedges.len() * (size_of::<Halfedge>() + member)
        + m.edges.len() * (size_of::<Edge>() + member)
        + m.faces.len() * (size_of::<Face>() + member)
}

/// The remap from the entities of `old`'s rows to those of `new`'s, row by row and kind by
/// kind (the two must have the same rows).
pub fn row_map(old: &MeshMembers, new: &MeshMembers) -> Remap {
    let mut map = Remap::default();
    map.reserve(old.vertices.len() + old.halfedges.len() + old.edges.len() + old.faces.len());
    map.extend(old.entities().zip(new.entities()));
    map
}

fn remap_members(m: &mut MeshMembers, map: &Remap) {
    for v in &mut m.vertices {
        v.0 = remapped(map, v.0);
    }
    for h in &mut m.halfedges {
        h.0 = remapped(map, h.0);
    }
    for e in &mut m.edges {
        e.0 = remapped(map, e.0);
    }
    for f in &mut m.faces {
        f.0 = remapped(map, f.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{build_mesh, shapes, to_soup, validate};

    fn grid() -> (World, MeshId) {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(3, 3), MeshInfo::default()).unwrap();
        (world, built.mesh)
    }

    #[test]
    fn a_local_change_undoes_and_redoes_exactly() {
        let (mut world, mesh) = grid();
        let original = to_soup(&world, mesh);
        let v = MeshMembers::collect(&world, mesh).vertices[5];
        let recorder = LocalRecorder::begin(&world, mesh, &[v]);
        world.get_mut::<Position>(v.0).unwrap().0 = Vec3::new(-0.0, 9.0, 1.0 / 3.0);
        let undo = recorder.finish(&world);
        assert_eq!(undo.counts(), (0, 0, 1), "only the moved vertex differs");
        let moved = to_soup(&world, mesh);
        let (redo, map, touched) = undo.apply(&mut world);
        assert!(map.is_empty());
        assert_eq!(touched.vertices, vec![v]);
        assert_eq!(to_soup(&world, mesh), original);
        let (_, _, _) = redo.apply(&mut world);
        let again = to_soup(&world, mesh);
        assert_eq!(again.positions[5].x.to_bits(), (-0.0f32).to_bits());
        assert_eq!(again, moved);
    }

    #[test]
    fn removed_elements_come_back_under_new_ids() {
        let (mut world, mesh) = grid();
        let before = to_soup(&world, mesh);
        let members = MeshMembers::collect(&world, mesh);
        // Replace the contents with another shape, then put the grid back.
        let other = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let cube_tables = SavedContents {
            mesh,
            tables: extract(&world, other.mesh),
        };
        let (grid_again, _) = cube_tables.apply(&mut world);
        assert_ne!(to_soup(&world, mesh), before);
        validate(&world, mesh).unwrap();
        let (_, map) = grid_again.apply(&mut world);
        assert_eq!(to_soup(&world, mesh), before);
        validate(&world, mesh).unwrap();
        // Every recorded row id maps to a live element of the mesh.
        let now = MeshMembers::collect(&world, mesh);
        assert_eq!(map.len(), now.entities().count());
        for e in members.entities() {
            let new = remapped(&map, e);
            assert_eq!(world.get::<InMesh>(new).map(|m| m.0), Some(mesh));
        }
    }

    #[test]
    fn a_saved_mesh_is_restored_whole() {
        let (mut world, mesh) = grid();
        world.get_mut::<MeshInfo>(mesh.0).unwrap().name = "grid".into();
        let before = to_soup(&world, mesh);
        let saved = SavedMesh::capture(&world, mesh);
        crate::mesh::despawn_mesh(&mut world, mesh);
        let (back, map) = saved.restore(&mut world);
        assert_eq!(map[&mesh.0], back.0);
        assert_eq!(world.get::<MeshInfo>(back.0).unwrap().name, "grid");
        assert_eq!(to_soup(&world, back), before);
        validate(&world, back).unwrap();
    }
}
