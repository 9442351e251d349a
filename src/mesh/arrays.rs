//! A mesh's entities as flat index tables, and back: the bulk path for whole-mesh operations.
//!
//! Global operations (subdivision, …) read the whole mesh once into a [`Connectivity`]
//! ([`extract`]), compute the new tables with plain index arithmetic, and write the result back
//! in one pass ([`replace_contents`]) instead of editing entities one by one. Vertex entities
//! survive a replacement (so a selected vertex stays selected); halfedges, edges and faces are
//! despawned and spawned anew.

use bevy::prelude::{Entity, World};

use super::build::write_tables;
use super::connectivity::Connectivity;
use super::ids::{HalfedgeId, MeshId};
use super::members::MeshMembers;
use super::repair::NONE;
use super::topology::MeshRef;

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
        let size = members
            .entities()
            .map(|e| e.index_u32() as usize + 1)
            .max()
            .unwrap_or(0);
        let mut slots = vec![NONE; size];
        let mut fill = |list: &mut dyn Iterator<Item = Entity>| {
            for (i, e) in list.enumerate() {
                slots[e.index_u32() as usize] = i as u32;
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
        self.slots[e.index_u32() as usize]
    }
}

/// Reads `mesh` into tables. The mesh must be valid.
pub fn extract(world: &World, mesh: MeshId) -> Extracted {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let index = DenseIndex::new(&members);
    let h = |x: HalfedgeId| index.get(x.0);
    let mut t = Connectivity {
        positions: Vec::with_capacity(members.vertices.len()),
        vertex_halfedge: Vec::with_capacity(members.vertices.len()),
        twin: Vec::with_capacity(members.halfedges.len()),
        next: Vec::with_capacity(members.halfedges.len()),
        prev: Vec::with_capacity(members.halfedges.len()),
        to_vertex: Vec::with_capacity(members.halfedges.len()),
        edge: Vec::with_capacity(members.halfedges.len()),
        face: Vec::with_capacity(members.halfedges.len()),
        edge_halfedge: Vec::with_capacity(members.edges.len()),
        face_halfedge: Vec::with_capacity(members.faces.len()),
    };
    for &v in &members.vertices {
        t.positions.push(m.position(v));
        t.vertex_halfedge.push(h(m.vertex_halfedge(v)));
    }
    for &x in &members.halfedges {
        let he = m.halfedge(x);
        t.twin.push(h(he.twin));
        t.next.push(h(he.next));
        t.prev.push(h(he.prev));
        t.to_vertex.push(index.get(he.vertex.0));
        t.edge.push(index.get(he.edge.0));
        t.face.push(he.face.map_or(NONE, |f| index.get(f.0)));
    }
    for &e in &members.edges {
        t.edge_halfedge.push(h(m.edge_halfedge(e)));
    }
    for &f in &members.faces {
        t.face_halfedge.push(h(m.face_halfedge(f)));
    }
    Extracted { tables: t, members }
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
