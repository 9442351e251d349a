//! Entities → tables: reading a mesh into [`MeshTables`].
//!
//! [`extract`] is the one way from a mesh's entities to its tables. It reads each kind of
//! element by one query, in storage order, and writes each element to its row through a dense
//! index (entity index → row), so no element costs an entity lookup. The rows of each kind
//! follow the world's storage order; [`MeshTables::members`] keeps the entity behind every row,
//! which is what takes the tables back into the same entities ([`super::write`]) and what an
//! undo record holds ([`crate::mesh::change`]).

use bevy::ecs::query::ReadOnlyQueryData;
use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Entity, World};

use super::connectivity::Connectivity;
use super::rows::NONE;
use crate::mesh::attributes::{
    AttributeColumns, CornerUv, MeshAttributes, Seam, VertexColor, VertexNormal,
};
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use crate::mesh::groups::{FaceGroup, FaceGroups, GroupTable};
use crate::mesh::ids::{HalfedgeId, MeshId, slot, slots_for};
use crate::mesh::members::MeshMembers;

/// A mesh read into tables, with the entity behind every table row: a snapshot of its whole
/// contents (about 32 bytes a halfedge), attributes included (the tables' attribute columns).
#[derive(Clone, Debug, Default)]
pub struct MeshTables {
    /// The tables.
    pub tables: Connectivity,
    /// The entities, by kind and row: `members.vertices[v]` is vertex row `v`, and so on.
    pub members: MeshMembers,
}

impl MeshTables {
    /// Bytes held (what the undo history's memory cap counts).
    pub fn bytes(&self) -> usize {
        let t = &self.tables;
        let u32s = t.vertex_halfedge.capacity()
            + t.twin.capacity()
            + t.next.capacity()
            + t.prev.capacity()
            + t.to_vertex.capacity()
            + t.edge.capacity()
            + t.face.capacity()
            + t.edge_halfedge.capacity()
            + t.face_halfedge.capacity();
        let m = &self.members;
        let ids = m.vertices.capacity()
            + m.halfedges.capacity()
            + m.edges.capacity()
            + m.faces.capacity();
        std::mem::size_of::<Self>()
            + u32s * 4
            + t.positions.capacity() * std::mem::size_of::<Vec3>()
            + ids * std::mem::size_of::<Entity>()
            + t.attributes.bytes()
    }
}

/// Maps each element entity to its row, its index *within its kind* in a [`MeshMembers`],
/// through a table indexed by entity index (faster than hashing: every lookup is one array
/// read). Entity indices are unique across kinds, so one table serves all four.
pub struct EntityRows {
    slots: Vec<u32>,
}

impl EntityRows {
    /// The rows of `members`' elements.
    pub fn new(members: &MeshMembers) -> Self {
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

    /// The row of `e`, an element of the members this was made from ([`NONE`] for an entity
    /// of no such element whose index is in range).
    ///
    /// # Panics
    /// For an entity whose index lies past every member's.
    #[inline]
    pub fn get(&self, e: Entity) -> u32 {
        self.slots[slot(e)]
    }

    /// The row of `e`, or `None` when `e` is no element of the members this was made from
    /// (and past every member's index: no panic).
    #[inline]
    pub fn row(&self, e: Entity) -> Option<u32> {
        self.slots.get(slot(e)).copied().filter(|&r| r != NONE)
    }
}

/// Reads `mesh` into tables. The mesh must be valid.
///
/// Each kind is read by a query, in storage order, and each element written to its row by
/// the dense index: no entity lookup an element, which after many edits (rows no longer in
/// entity order) missed the cache on nearly every one.
pub fn extract(world: &World, mesh: MeshId) -> MeshTables {
    let members = MeshMembers::collect(world, mesh);
    let index = EntityRows::new(&members);
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
        attributes: AttributeColumns::default(),
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
    // A mesh without attributes pays this one lookup.
    let has = MeshAttributes::of(world, mesh);
    if has.uv {
        let mut uv = vec![Vec2::ZERO; nh];
        for_each_element::<&CornerUv>(world, mesh, |e, x| uv[row(e)] = x.0);
        t.attributes.uv = Some(uv);
    }
    if has.normals {
        let mut normals = vec![Vec3::ZERO; nv];
        for_each_element::<&VertexNormal>(world, mesh, |e, x| normals[row(e)] = x.0);
        t.attributes.normals = Some(normals);
    }
    if has.colors {
        let mut colors = vec![[0u8; 3]; nv];
        for_each_element::<&VertexColor>(world, mesh, |e, x| colors[row(e)] = x.0);
        t.attributes.colors = Some(colors);
    }
    if has.seams {
        let mut seams = vec![false; t.edge_halfedge.len()];
        for_each_element::<&Seam>(world, mesh, |e, _| seams[row(e)] = true);
        t.attributes.seams = Some(seams);
    }
    if has.groups
        && let Some(table) = world.get::<GroupTable>(mesh.0)
    {
        let mut of_face = vec![0u32; t.face_halfedge.len()];
        for_each_element::<&FaceGroup>(world, mesh, |e, g| of_face[row(e)] = g.0);
        t.attributes.groups = Some(FaceGroups {
            table: table.clone(),
            of_face,
        });
    }
    MeshTables { tables: t, members }
}

/// Calls `each` with every element of `mesh` that has the components `D`, in storage order (the
/// order of [`MeshMembers::collect`], which is the order of [`extract`]'s rows).
pub(crate) fn for_each_element<D: ReadOnlyQueryData>(
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
