//! A mesh's entities as flat index tables, and back: the bulk path for whole-mesh operations.
//!
//! Global operations (subdivision, …) read the whole mesh once into a [`Connectivity`]
//! ([`extract`]), compute the new tables with plain index arithmetic, and write the result back
//! in one pass ([`replace_contents`]) instead of editing entities one by one. Vertex entities
//! survive a replacement (so a selected vertex stays selected); halfedges, edges and faces are
//! despawned and spawned anew.

use bevy::ecs::query::ReadOnlyQueryData;
use bevy::math::Vec3;
use bevy::prelude::{Entity, World};

use super::build::write_tables;
use super::connectivity::Connectivity;
use super::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use super::ids::{HalfedgeId, MeshId, slot, slots_for};
use super::members::MeshMembers;
use super::repair::NONE;

/// A mesh read into tables, with the entity behind every table row.
pub struct Extracted {
    /// The tables.
    pub tables: Connectivity,
    /// The entities, by table index.
    pub members: MeshMembers,
}

/// Maps each element entity to its index *within its kind* through a table indexed by entity
/// index (faster than hashing: every lookup is one array read). Entity indices are unique
/// across kinds, so one table serves all four.
struct DenseIndex {
    slots: Vec<u32>,
}

impl DenseIndex {
    fn new(members: &MeshMembers) -> Self {
        let mut slots = vec![NONE; slots_for(members.entities())];
        let mut fill = |list: &mut dyn Iterator<Item = Entity>| {
            for (i, e) in list.enumerate() {
                slots[slot(e)] = i as u32;
            }
        };
        fill(&mut members.vertices.iter().map(|v| v.0));
        fill(&mut members.halfedges.iter().map(|h| h.0));
        fill(&mut members.edges.iter().map(|e| e.0));
        fill(&mut members.faces.iter().map(|f| f.0));
        Self { slots }
    }

    #[inline]
    fn get(&self, e: Entity) -> u32 {
        self.slots[slot(e)]
    }
}

/// Reads `mesh` into tables. The mesh must be valid.
///
/// Each kind is read by a query, in storage order, and each element written to its row by
/// the dense index: no entity lookup an element, which after many edits (rows no longer in
/// entity order) missed the cache on nearly every one.
pub fn extract(world: &World, mesh: MeshId) -> Extracted {
    let members = MeshMembers::collect(world, mesh);
    let index = DenseIndex::new(&members);
    let h = |x: HalfedgeId| index.get(x.0);
    let row = |e: Entity| index.get(e) as usize;
    let (nv, nh) = (members.vertices.len(), members.halfedges.len());
    let mut t = Connectivity {
        positions: vec![Vec3::ZERO; nv],
        vertex_halfedge: vec![NONE; nv],
        twin: vec![NONE; nh],
        next: vec![NONE; nh],
        prev: vec![NONE; nh],
        to_vertex: vec![NONE; nh],
        edge: vec![NONE; nh],
        face: vec![NONE; nh],
        edge_halfedge: vec![NONE; members.edges.len()],
        face_halfedge: vec![NONE; members.faces.len()],
    };
    for_each_element::<(&Vertex, &Position)>(world, mesh, |e, (v, p)| {
        let i = row(e);
        t.positions[i] = p.0;
        t.vertex_halfedge[i] = h(v.halfedge);
    });
    for_each_element::<&Halfedge>(world, mesh, |e, x| {
        let i = row(e);
        t.twin[i] = h(x.twin);
        t.next[i] = h(x.next);
        t.prev[i] = h(x.prev);
        t.to_vertex[i] = index.get(x.vertex.0);
        t.edge[i] = index.get(x.edge.0);
        t.face[i] = x.face.map_or(NONE, |f| index.get(f.0));
    });
    for_each_element::<&Edge>(world, mesh, |e, x| t.edge_halfedge[row(e)] = h(x.halfedge));
    for_each_element::<&Face>(world, mesh, |e, x| t.face_halfedge[row(e)] = h(x.halfedge));
    Extracted { tables: t, members }
}

/// Calls `each` with every element of `mesh` that has the components `D`, in storage order.
fn for_each_element<D: ReadOnlyQueryData>(
    world: &World,
    mesh: MeshId,
    mut each: impl FnMut(Entity, D::Item<'_, '_>),
) {
    let Some(mut query) = world.try_query::<(Entity, &InMesh, D)>() else {
        return;
    };
    for (e, in_mesh, item) in query.iter(world) {
        if in_mesh.0 == mesh {
            each(e, item);
        }
    }
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
