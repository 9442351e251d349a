//! Entities → tables a slice at a time: reading a large mesh across many frames.
//!
//! [`extract`](super::extract) reads a mesh in one go. For the editor's panel figures of a
//! 1.3 M-face mesh that held one frame for 650–800 ms after every edit, most of it fresh pages
//! and cache misses that no reordering removes. [`GradualRead`] does the same work in slices of
//! a given duration, so a frame pays only its slice; the caller decides how much a frame may
//! spend and checks, between slices, that the mesh did not change (the editor compares its
//! render generation) — an edit between two slices makes a read worthless, and the caller
//! starts a new one.
//!
//! Two stages, each resumable at any element:
//! 1. **Listing.** The world's archetypes are walked in id order, and the entities of every
//!    archetype holding an element kind are kept when their [`InMesh`] names the mesh. Each
//!    gets its row (its place in its kind's list) in a table indexed by entity index, as
//!    [`EntityRows`](super::EntityRows) holds them.
//! 2. **Reading.** Each kind's elements are read by entity, their links written as rows.
//!
//! Rows follow the archetypes' order, which is not always the storage order `extract` gives (a
//! halfedge with a corner UV sits in another archetype of the same table), so the tables are
//! the same mesh numbered possibly otherwise, with the same attribute columns (corner UVs,
//! normals, colours, seams, face groups; what an element lacks reads as `extract` reads it).
//! What a read finds inconsistent — an element listed twice, a link to an
//! entity outside the mesh, an element gone — ends it with [`ReadBroken`]; it never panics.

use std::time::{Duration, Instant};

use bevy::ecs::archetype::ArchetypeId;
use bevy::ecs::component::ComponentId;
use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Entity, World};

use super::connectivity::Connectivity;
use super::read::MeshTables;
use super::rows::NONE;
use crate::mesh::attributes::{CornerUv, MeshAttributes, Seam, VertexColor, VertexNormal};
use crate::mesh::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use crate::mesh::groups::{FaceGroup, FaceGroups, GroupTable};
use crate::mesh::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId, slot};
use crate::mesh::members::MeshMembers;

/// Elements handled between two looks at the clock.
const BETWEEN_CLOCK_READS: usize = 1024;

/// A read of one mesh into tables, advanced a slice at a time by [`GradualRead::advance`].
pub struct GradualRead {
    mesh: MeshId,
    stage: Stage,
    members: MeshMembers,
    /// Each listed element's row within its kind, by entity index ([`NONE`]: not listed).
    rows: Vec<u32>,
    tables: Connectivity,
    /// Elements handled between two looks at the clock.
    between_clock_reads: usize,
}

/// Where a read stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    /// Listing the elements: the archetype by id, and the next entity in it.
    Listing { archetype: usize, at: usize },
    /// Reading the elements of one kind (0 vertices, 1 halfedges, 2 edges, 3 faces) from `at`.
    Reading { kind: usize, at: usize },
}

/// A read found the mesh other than a valid mesh left alone between slices: it changed
/// without the caller noticing, or is broken. The read is over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadBroken;

impl std::fmt::Display for ReadBroken {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the mesh changed while it was being read")
    }
}

impl std::error::Error for ReadBroken {}

/// The component ids of the four element kinds and of [`InMesh`] (`None` before any mesh).
fn kind_components(world: &World) -> Option<([ComponentId; 4], ComponentId)> {
    Some((
        [
            world.component_id::<Vertex>()?,
            world.component_id::<Halfedge>()?,
            world.component_id::<Edge>()?,
            world.component_id::<Face>()?,
        ],
        world.component_id::<InMesh>()?,
    ))
}

impl GradualRead {
    /// A read of `mesh` that has read nothing yet.
    pub fn new(mesh: MeshId) -> Self {
        Self {
            mesh,
            stage: Stage::Listing {
                archetype: 0,
                at: 0,
            },
            members: MeshMembers::default(),
            rows: Vec::new(),
            tables: Connectivity::default(),
            between_clock_reads: BETWEEN_CLOCK_READS,
        }
    }

    /// Reads on for about `slice` (the clock is read every thousand elements or so), and
    /// returns the tables once every element is read (the read is then spent).
    ///
    /// Every slice must see the world as the first did, at least as far as this mesh goes.
    ///
    /// # Errors
    /// [`ReadBroken`] when this slice finds it did not: an element listed twice or gone, or a
    /// link to an entity that is not one of the mesh's elements.
    pub fn advance(
        &mut self,
        world: &World,
        slice: Duration,
    ) -> Result<Option<MeshTables>, ReadBroken> {
        let start = Instant::now();
        let (mut done, every) = (0usize, self.between_clock_reads);
        let mut time_left = || {
            done += 1;
            done % every != 0 || start.elapsed() < slice
        };
        while let Stage::Listing { .. } = self.stage {
            if !self.list(world, &mut time_left)? {
                return Ok(None);
            }
        }
        while let Stage::Reading { kind, .. } = self.stage {
            if kind == 4 {
                let members = std::mem::take(&mut self.members);
                let tables = std::mem::take(&mut self.tables);
                return Ok(Some(MeshTables { tables, members }));
            }
            if !self.read(world, &mut time_left)? {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// Lists elements until the time is up (`false`) or the listing is done (`true`, the
    /// tables then reserved).
    fn list(
        &mut self,
        world: &World,
        time_left: &mut impl FnMut() -> bool,
    ) -> Result<bool, ReadBroken> {
        let Stage::Listing { archetype, at } = self.stage else {
            return Ok(true);
        };
        let Some((kinds, in_mesh)) = kind_components(world) else {
            // No element was ever spawned: an empty mesh.
            self.finish_listing(world);
            return Ok(true);
        };
        let archetypes = world.archetypes();
        let Some(current) = archetypes.get(ArchetypeId::new(archetype)) else {
            self.finish_listing(world);
            return Ok(true);
        };
        let kind = kinds.iter().position(|&k| current.contains(k));
        let Some(kind) = kind.filter(|_| current.contains(in_mesh)) else {
            self.stage = Stage::Listing {
                archetype: archetype + 1,
                at: 0,
            };
            return Ok(true);
        };
        let entities = current.entities();
        if at == 0 {
            // At most this many more: reserved now, so no list is copied as it grows (untouched
            // capacity costs no memory).
            let more = entities.len();
            match kind {
                0 => self.members.vertices.reserve(more),
                1 => self.members.halfedges.reserve(more),
                2 => self.members.edges.reserve(more),
                _ => self.members.faces.reserve(more),
            }
            let slots = world.entities().len() as usize;
            self.rows.reserve(slots.saturating_sub(self.rows.len()));
        }
        for (i, entity) in entities.iter().enumerate().skip(at) {
            if !time_left() {
                self.stage = Stage::Listing { archetype, at: i };
                return Ok(false);
            }
            let e = entity.id();
            if world.get::<InMesh>(e).map(|m| m.0) != Some(self.mesh) {
                continue;
            }
            let row = match kind {
                0 => push(&mut self.members.vertices, VertexId(e)),
                1 => push(&mut self.members.halfedges, HalfedgeId(e)),
                2 => push(&mut self.members.edges, EdgeId(e)),
                _ => push(&mut self.members.faces, FaceId(e)),
            };
            let s = slot(e);
            if s >= self.rows.len() {
                self.rows.resize(s + 1, NONE);
            }
            if self.rows[s] != NONE {
                return Err(ReadBroken);
            }
            self.rows[s] = row;
        }
        self.stage = Stage::Listing {
            archetype: archetype + 1,
            at: 0,
        };
        Ok(true)
    }

    /// Reserves the tables for the listed elements and moves on to reading them. Nothing is
    /// written yet: the rows are pushed as they are read, so the pages are touched a slice at a
    /// time rather than all in this one.
    fn finish_listing(&mut self, world: &World) {
        let m = &self.members;
        let (nv, nh) = (m.vertices.len(), m.halfedges.len());
        let t = &mut self.tables;
        t.positions.reserve_exact(nv);
        t.vertex_halfedge.reserve_exact(nv);
        for column in [
            &mut t.twin,
            &mut t.next,
            &mut t.prev,
            &mut t.to_vertex,
            &mut t.edge,
            &mut t.face,
        ] {
            column.reserve_exact(nh);
        }
        t.edge_halfedge.reserve_exact(m.edges.len());
        t.face_halfedge.reserve_exact(m.faces.len());
        let has = MeshAttributes::of(world, self.mesh);
        let a = &mut t.attributes;
        a.uv = has.uv.then(|| Vec::with_capacity(nh));
        a.normals = has.normals.then(|| Vec::with_capacity(nv));
        a.colors = has.colors.then(|| Vec::with_capacity(nv));
        a.seams = has.seams.then(|| Vec::with_capacity(m.edges.len()));
        a.groups = has
            .groups
            .then(|| world.get::<GroupTable>(self.mesh.0))
            .flatten()
            .map(|table| FaceGroups {
                table: table.clone(),
                of_face: Vec::with_capacity(m.faces.len()),
            });
        self.stage = Stage::Reading { kind: 0, at: 0 };
    }

    /// Reads elements until the time is up (`false`) or the kind is done (`true`).
    fn read(
        &mut self,
        world: &World,
        time_left: &mut impl FnMut() -> bool,
    ) -> Result<bool, ReadBroken> {
        let Stage::Reading { kind, at } = self.stage else {
            return Ok(true);
        };
        let count = match kind {
            0 => self.members.vertices.len(),
            1 => self.members.halfedges.len(),
            2 => self.members.edges.len(),
            _ => self.members.faces.len(),
        };
        for i in at..count {
            if !time_left() {
                self.stage = Stage::Reading { kind, at: i };
                return Ok(false);
            }
            self.read_element(world, kind, i).ok_or(ReadBroken)?;
        }
        self.stage = Stage::Reading {
            kind: kind + 1,
            at: 0,
        };
        Ok(true)
    }

    /// Reads row `i` of `kind` (the next row of its tables) into the tables; `None` when it is
    /// gone or links outside the mesh.
    fn read_element(&mut self, world: &World, kind: usize, i: usize) -> Option<()> {
        let rows = &self.rows;
        let row = |e: Entity| rows.get(slot(e)).copied().filter(|&r| r != NONE);
        let t = &mut self.tables;
        match kind {
            0 => {
                let e = world.get_entity(self.members.vertices[i].0).ok()?;
                let halfedge = row(e.get::<Vertex>()?.halfedge.0)?;
                t.positions.push(e.get::<Position>()?.0);
                t.vertex_halfedge.push(halfedge);
                let a = &mut t.attributes;
                if let Some(normals) = a.normals.as_mut() {
                    normals.push(e.get::<VertexNormal>().map_or(Vec3::ZERO, |n| n.0));
                }
                if let Some(colors) = a.colors.as_mut() {
                    colors.push(e.get::<VertexColor>().map_or([0; 3], |c| c.0));
                }
            }
            1 => {
                let e = world.get_entity(self.members.halfedges[i].0).ok()?;
                let x = e.get::<Halfedge>()?;
                let face = match x.face {
                    Some(f) => row(f.0)?,
                    None => NONE,
                };
                let links = [
                    row(x.twin.0)?,
                    row(x.next.0)?,
                    row(x.prev.0)?,
                    row(x.vertex.0)?,
                    row(x.edge.0)?,
                    face,
                ];
                let columns = [
                    &mut t.twin,
                    &mut t.next,
                    &mut t.prev,
                    &mut t.to_vertex,
                    &mut t.edge,
                    &mut t.face,
                ];
                for (column, link) in columns.into_iter().zip(links) {
                    column.push(link);
                }
                if let Some(uv) = t.attributes.uv.as_mut() {
                    uv.push(e.get::<CornerUv>().map_or(Vec2::ZERO, |c| c.0));
                }
            }
            2 => {
                let e = world.get_entity(self.members.edges[i].0).ok()?;
                t.edge_halfedge.push(row(e.get::<Edge>()?.halfedge.0)?);
                if let Some(seams) = t.attributes.seams.as_mut() {
                    seams.push(e.contains::<Seam>());
                }
            }
            _ => {
                let e = world.get_entity(self.members.faces[i].0).ok()?;
                t.face_halfedge.push(row(e.get::<Face>()?.halfedge.0)?);
                if let Some(groups) = t.attributes.groups.as_mut() {
                    groups.of_face.push(e.get::<FaceGroup>().map_or(0, |g| g.0));
                }
            }
        }
        Some(())
    }
}

/// Appends `x` and returns its index.
fn push<T>(list: &mut Vec<T>, x: T) -> u32 {
    list.push(x);
    (list.len() - 1) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes, stats_of_tables};
    use bevy::math::Vec2;

    /// Reads `mesh` gradually with a zero slice: 50 elements a call.
    fn read_all(world: &World, mesh: MeshId) -> (MeshTables, usize) {
        let mut read = GradualRead::new(mesh);
        read.between_clock_reads = 50;
        let mut calls = 0;
        loop {
            calls += 1;
            if let Some(tables) = read.advance(world, Duration::ZERO).unwrap() {
                return (tables, calls);
            }
        }
    }

    /// Every element of `m` with its links named by entity, sorted: the mesh the tables hold,
    /// whatever order their rows are in.
    fn named(m: &MeshTables) -> Vec<(Entity, [Option<Entity>; 6], [u32; 3])> {
        let (t, k) = (&m.tables, &m.members);
        let name = |list: &[Entity], r: u32| (r != NONE).then(|| list[r as usize]);
        let vertices: Vec<Entity> = k.vertices.iter().map(|v| v.0).collect();
        let halfedges: Vec<Entity> = k.halfedges.iter().map(|h| h.0).collect();
        let edges: Vec<Entity> = k.edges.iter().map(|e| e.0).collect();
        let faces: Vec<Entity> = k.faces.iter().map(|f| f.0).collect();
        let mut all = Vec::new();
        for (i, &v) in vertices.iter().enumerate() {
            let p = t.positions[i].to_array().map(f32::to_bits);
            let h = name(&halfedges, t.vertex_halfedge[i]);
            all.push((v, [h, None, None, None, None, None], p));
        }
        for (i, &h) in halfedges.iter().enumerate() {
            let links = [
                name(&halfedges, t.twin[i]),
                name(&halfedges, t.next[i]),
                name(&halfedges, t.prev[i]),
                name(&vertices, t.to_vertex[i]),
                name(&edges, t.edge[i]),
                name(&faces, t.face[i]),
            ];
            all.push((h, links, [0; 3]));
        }
        for (list, ends) in [(&edges, &t.edge_halfedge), (&faces, &t.face_halfedge)] {
            for (i, &x) in list.iter().enumerate() {
                let h = name(&halfedges, ends[i]);
                all.push((x, [h, None, None, None, None, None], [0; 3]));
            }
        }
        all.sort_unstable_by_key(|x| x.0);
        all
    }

    #[test]
    fn a_gradual_read_gives_the_mesh_extract_gives_in_many_slices() {
        let mut world = World::new();
        // Two meshes in the same archetypes: only the one asked for is read.
        let torus = build_mesh(&mut world, &shapes::torus(12, 8), MeshInfo::default())
            .unwrap()
            .mesh;
        let grid = build_mesh(&mut world, &shapes::grid_with_holes(6), MeshInfo::default())
            .unwrap()
            .mesh;
        let (gradual, calls) = read_all(&world, grid);
        let whole = extract(&world, grid);
        assert!(calls > 20, "{calls} slices");
        assert_eq!(named(&gradual), named(&whole));
        assert_eq!(
            stats_of_tables(&gradual.tables),
            stats_of_tables(&whole.tables)
        );
        assert_eq!(
            named(&read_all(&world, torus).0),
            named(&extract(&world, torus))
        );
    }

    /// Each element's attributes, by entity: (entity, the values' bits), sorted.
    fn attributes(m: &MeshTables) -> Vec<(Entity, Vec<u32>)> {
        let (a, k) = (&m.tables.attributes, &m.members);
        let mut all = Vec::new();
        for (i, v) in k.vertices.iter().enumerate() {
            let mut bits: Vec<u32> = a.normals.as_ref().unwrap()[i]
                .to_array()
                .map(f32::to_bits)
                .into();
            bits.extend(a.colors.as_ref().unwrap()[i].map(u32::from));
            all.push((v.0, bits));
        }
        for (i, h) in k.halfedges.iter().enumerate() {
            let uv = a.uv.as_ref().unwrap()[i].to_array().map(f32::to_bits);
            all.push((h.0, uv.into()));
        }
        all.sort_unstable();
        all
    }

    #[test]
    fn a_gradual_read_gives_the_attributes_extract_gives() {
        let mut soup = shapes::grid_with_holes(3);
        let n = soup.positions.len();
        soup.vertex_normals = Some(
            soup.positions
                .iter()
                .map(|p| p.normalize_or_zero())
                .collect(),
        );
        soup.vertex_colors = Some((0..n).map(|i| [i as u8, 7, (i / 3) as u8]).collect());
        let corners = soup.indices.len();
        soup.corner_uvs = Some((0..corners).map(|c| Vec2::new(c as f32, 0.5)).collect());
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let (gradual, _) = read_all(&world, mesh);
        let whole = extract(&world, mesh);
        assert_eq!(
            gradual.tables.attributes.present(),
            whole.tables.attributes.present()
        );
        assert_eq!(attributes(&gradual), attributes(&whole));
        assert_eq!(named(&gradual), named(&whole));
    }

    #[test]
    fn a_read_the_mesh_changed_under_ends_broken_not_in_a_panic() {
        let mut world = World::new();
        let soup = shapes::grid_with_holes(6);
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let mut read = GradualRead::new(mesh);
        read.between_clock_reads = 50;
        // List everything, then take a face away before the faces are read.
        while !matches!(read.stage, Stage::Reading { .. }) {
            assert!(read.advance(&world, Duration::ZERO).unwrap().is_none());
        }
        world.despawn(read.members.faces[0].0);
        let result = std::iter::repeat_with(|| read.advance(&world, Duration::ZERO))
            .find(|r| !matches!(r, Ok(None)))
            .unwrap();
        assert_eq!(result.err(), Some(ReadBroken));
    }
}
