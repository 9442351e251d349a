//! Polygon soup → entities (with repairs), and entities → polygon soup.
//!
//! [`build_mesh`] is the one way a mesh enters a world: it repairs the soup
//! ([`super::repair`]), lays out the halfedge tables ([`super::connectivity`]) and spawns them
//! ([`spawn_connectivity`]). Ids are allocated first and every element is spawned once, already
//! linked, so no element is ever seen half-built.

use bevy::prelude::{Entity, World};
use thiserror::Error;

use super::connectivity::Connectivity;
use super::elements::{Edge, Face, Halfedge, InMesh, MeshInfo, Position, Vertex};
use super::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use super::members::MeshMembers;
use super::repair::{NONE, RepairReport, repair};
use super::soup::PolygonSoup;
use super::topology::MeshRef;

/// Why a soup could not become a mesh at all (local defects are repaired, not errors).
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BuildError {
    /// Nothing was left to build after the repairs (or the input had no faces).
    #[error("no usable faces: {faces} face(s) in the input, {report}")]
    NoFaces {
        /// Faces in the input.
        faces: usize,
        /// What the repair dropped.
        report: RepairReport,
    },
    /// The mesh is larger than 32-bit indices can address.
    #[error("mesh too large: {0} face corners (the limit is 2^31)")]
    TooLarge(usize),
}

/// A freshly built mesh and what it took to build it.
#[derive(Clone, Debug)]
pub struct BuiltMesh {
    /// The new mesh entity.
    pub mesh: MeshId,
    /// Every repair made on the way.
    pub report: RepairReport,
    /// For each vertex of the input soup, the vertex it became (`None` if dropped). Lets scripts
    /// name elements by their index in the input file.
    pub input_vertices: Vec<Option<VertexId>>,
}

/// Builds a mesh from `soup` into `world`, repairing what it must (see [`super::repair`]).
///
/// # Errors
/// [`BuildError::NoFaces`] if no face survives the repairs; the world is then untouched.
pub fn build_mesh(
    world: &mut World,
    soup: &PolygonSoup,
    info: MeshInfo,
) -> Result<BuiltMesh, BuildError> {
    if soup.indices.len() >= 1 << 31 {
        return Err(BuildError::TooLarge(soup.indices.len()));
    }
    let (faces, report) = repair(soup);
    if faces.face_count() == 0 {
        return Err(BuildError::NoFaces {
            faces: soup.face_count(),
            report,
        });
    }
    let connectivity = Connectivity::from_repaired(&faces);
    let (mesh, rows) = spawn_connectivity(world, &connectivity, info);
    let vertices = rows.vertices;
    let input_vertices = faces
        .input_vertex
        .iter()
        .map(|&v| (v != NONE).then(|| vertices[v as usize]))
        .collect();
    Ok(BuiltMesh {
        mesh,
        report,
        input_vertices,
    })
}

/// Spawns halfedge tables as a new mesh: one entity per element, all links set. Returns the
/// mesh and the entities of every row, by kind, in table order.
///
/// The tables must be consistent (as [`Connectivity::from_repaired`] makes them); the result is
/// then a mesh that passes [`super::validate()`].
pub fn spawn_connectivity(
    world: &mut World,
    c: &Connectivity,
    info: MeshInfo,
) -> (MeshId, MeshMembers) {
    let mesh = MeshId(world.spawn(info).id());
    let rows = write_tables(world, c, mesh, None);
    (mesh, rows)
}

/// How many rows of each kind a set of tables has: what `reserve_rows` needs to know before
/// the tables themselves exist.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowCounts {
    /// Vertices.
    pub vertices: usize,
    /// Halfedges (interior and boundary).
    pub halfedges: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
}

impl RowCounts {
    /// The counts of both, added kind by kind.
    pub fn plus(self, other: Self) -> Self {
        Self {
            vertices: self.vertices + other.vertices,
            halfedges: self.halfedges + other.halfedges,
            edges: self.edges + other.edges,
            faces: self.faces + other.faces,
        }
    }

    /// The counts of `rows`.
    pub fn of_rows(rows: &MeshMembers) -> Self {
        Self {
            vertices: rows.vertices.len(),
            halfedges: rows.halfedges.len(),
            edges: rows.edges.len(),
            faces: rows.faces.len(),
        }
    }

    /// The counts of `c`.
    pub fn of(c: &Connectivity) -> Self {
        Self {
            vertices: c.vertex_count(),
            halfedges: c.halfedge_count(),
            edges: c.edge_count(),
            faces: c.face_count(),
        }
    }
}

/// Makes the elements of `mesh` be exactly the tables `c`, reusing the entities of `old` (the
/// mesh's current elements) row for row where it can, despawning the old ones left over and
/// batch-spawning the missing ones. Returns the entities of every row, by kind, in table order.
///
/// Two passes: [`reserve_rows`], then [`write_links`].
pub(crate) fn write_tables(
    world: &mut World,
    c: &Connectivity,
    mesh: MeshId,
    old: Option<&MeshMembers>,
) -> MeshMembers {
    let rows = reserve_rows(world, RowCounts::of(c), mesh, old);
    write_links(world, c, &rows);
    rows
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
pub(crate) fn reserve_rows(
    world: &mut World,
    counts: RowCounts,
    mesh: MeshId,
    old: Option<&MeshMembers>,
) -> MeshMembers {
    let member = InMesh(mesh);
    let none = HalfedgeId(Entity::PLACEHOLDER);
    let old_of = |f: fn(&MeshMembers) -> Vec<Entity>| old.map(f).unwrap_or_default();
    let vertices = entities_for(
        world,
        counts.vertices,
        old_of(|o| o.vertices.iter().map(|v| v.0).collect()),
        (
            Vertex { halfedge: none },
            Position(bevy::math::Vec3::ZERO),
            member,
        ),
    );
    let placeholder = Halfedge {
        twin: none,
        next: none,
        prev: none,
        vertex: VertexId(Entity::PLACEHOLDER),
        edge: EdgeId(Entity::PLACEHOLDER),
        face: None,
    };
    let halfedges = entities_for(
        world,
        counts.halfedges,
        old_of(|o| o.halfedges.iter().map(|h| h.0).collect()),
        (placeholder, member),
    );
    let edges = entities_for(
        world,
        counts.edges,
        old_of(|o| o.edges.iter().map(|e| e.0).collect()),
        (Edge { halfedge: none }, member),
    );
    let faces = entities_for(
        world,
        counts.faces,
        old_of(|o| o.faces.iter().map(|f| f.0).collect()),
        (Face { halfedge: none }, member),
    );
    MeshMembers {
        vertices: vertices.into_iter().map(VertexId).collect(),
        halfedges: halfedges.into_iter().map(HalfedgeId).collect(),
        edges: edges.into_iter().map(EdgeId).collect(),
        faces: faces.into_iter().map(FaceId).collect(),
    }
}

/// [`reserve_rows`] on this thread while `compute` runs on another: the two largest costs of a
/// bulk rewrite (making the entities exist, computing the new tables) overlapped. Returns what
/// `compute` returned and the rows; a panic in `compute` is passed on.
pub(crate) fn reserve_rows_while<T: Send>(
    world: &mut World,
    counts: RowCounts,
    mesh: MeshId,
    old: Option<&MeshMembers>,
    compute: impl FnOnce() -> T + Send,
) -> (T, MeshMembers) {
    std::thread::scope(|scope| {
        let worker = scope.spawn(compute);
        let rows = reserve_rows(world, counts, mesh, old);
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
    for e in gone {
        world.despawn(e);
    }
}

/// Writes every link of the tables `c` into the rows `rows` (from [`reserve_rows`] with
/// `RowCounts::of(c)`; 12–18 ns an entity, a lookup and a change tick each).
///
/// # Panics
/// If the row counts differ from the tables' (a bug in the caller).
pub(crate) fn write_links(world: &mut World, c: &Connectivity, rows: &MeshMembers) {
    assert_eq!(
        RowCounts::of(c),
        RowCounts::of_rows(rows),
        "rows reserved for other tables"
    );
    let h = |i: u32| rows.halfedges[i as usize];
    let mut q = world.query::<(&mut Vertex, &mut Position)>();
    for (i, &e) in rows.vertices.iter().enumerate() {
        if let Ok((mut v, mut p)) = q.get_mut(world, e.0) {
            v.halfedge = h(c.vertex_halfedge[i]);
            p.0 = c.positions[i];
        }
    }
    let mut q = world.query::<&mut Halfedge>();
    for (i, &e) in rows.halfedges.iter().enumerate() {
        if let Ok(mut x) = q.get_mut(world, e.0) {
            let face = c.face[i];
            *x = Halfedge {
                twin: h(c.twin[i]),
                next: h(c.next[i]),
                prev: h(c.prev[i]),
                vertex: rows.vertices[c.to_vertex[i] as usize],
                edge: rows.edges[c.edge[i] as usize],
                face: (face != NONE).then(|| rows.faces[face as usize]),
            };
        }
    }
    let mut q = world.query::<&mut Edge>();
    for (i, &e) in rows.edges.iter().enumerate() {
        if let Ok(mut x) = q.get_mut(world, e.0) {
            x.halfedge = h(c.edge_halfedge[i]);
        }
    }
    let mut q = world.query::<&mut Face>();
    for (i, &e) in rows.faces.iter().enumerate() {
        if let Ok(mut x) = q.get_mut(world, e.0) {
            x.halfedge = h(c.face_halfedge[i]);
        }
    }
}

/// `n` entities of one kind: the first of `old`, then new ones spawned in one batch with
/// `placeholder`; the rest of `old` is despawned.
fn entities_for<B>(world: &mut World, n: usize, old: Vec<Entity>, placeholder: B) -> Vec<Entity>
where
    B: bevy::prelude::Bundle<Effect: bevy::ecs::bundle::NoBundleEffect> + Clone,
{
    let keep = old.len().min(n);
    for &e in &old[keep..] {
        world.despawn(e);
    }
    let mut ids = old;
    ids.truncate(keep);
    sort_free_ids(world, n - keep);
    ids.extend(world.spawn_batch(std::iter::repeat_n(placeholder, n - keep)));
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
fn sort_free_ids(world: &mut World, count: usize) {
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

/// The mesh as a polygon soup: vertices in table order, faces as vertex cycles. The inverse of
/// [`build_mesh`] up to the repairs.
pub fn to_soup(world: &World, mesh: MeshId) -> PolygonSoup {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let index = members.vertex_rows();
    let mut soup = PolygonSoup::with_capacity(
        members.vertices.len(),
        members.faces.len(),
        members.halfedges.len(),
    );
    soup.positions
        .extend(members.vertices.iter().map(|&v| m.position(v)));
    let mut face = Vec::new();
    for &f in &members.faces {
        face.clear();
        // Start one halfedge back so the face lists its vertices in the order it was built from.
        let first = m.prev(m.face_halfedge(f));
        face.extend(m.loop_from(first).map(|h| index[&m.to_vertex(h).0]));
        soup.push_face(&face);
    }
    soup
}

/// Despawns a mesh and every element in it. Returns how many entities went.
pub fn despawn_mesh(world: &mut World, mesh: MeshId) -> usize {
    let members = MeshMembers::collect(world, mesh);
    let mut count = 0;
    for e in members.entities() {
        count += usize::from(world.despawn(e));
    }
    count + usize::from(world.despawn(mesh.0))
}
