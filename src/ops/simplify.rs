//! Quadric error simplification (Garland & Heckbert 1997).
//!
//! Every face contributes the quadric `K = p pᵀ` of its plane `p = (n, −n·x)`, weighted by its
//! area but never by less than [`SimplifyParams::min_area_share`] of the mean face area: with
//! the area alone, a crease or a bump drawn with small or sliver triangles weighs little and is
//! among the first things flattened (the share measured on the shared models:
//! `docs/performance.md`);
//! a vertex's quadric is the sum over its faces, plus, on the boundary, quadrics of planes
//! through each boundary edge perpendicular to its face (weighted by [`SimplifyParams::
//! boundary_weight`]) so that borders keep their shape and holes do not close. Sharp edges
//! (dihedral angle above [`SimplifyParams::feature_angle_deg`]) get the same planes, one per
//! side, weighted by [`SimplifyParams::feature_weight`]: a crease then holds its line as the
//! faces beside it are merged, where the face planes alone let it be rounded off. The cost of
//! collapsing an edge is `vᵀ (Q_a + Q_b) v` at the optimal `v` (the solution of the 3×3 system;
//! when it is near singular, the best of the two ends and the midpoint). With
//! [`SimplifyParams::distance_weight`] above 0, a collapse also costs at least what the input's
//! farthest point from the faces it reshapes weighs ([`fidelity`]): the Hausdorff distance to
//! the input comes out smaller, in about three times the time. With
//! [`SimplifyParams::fit_to_input`], the result's vertices are fitted to the input by one
//! least-squares step at the end ([`fit`]).
//!
//! Edges wait in an indexed heap ([`super::indexed_heap`]), one entry per edge: when a collapse
//! changes the cost of the edges around the merged vertex, their entries are re-keyed in place,
//! so no pop is spent on a stale entry. Equal costs are ordered by the edge's entity index, so a
//! run is deterministic. Every collapse is checked as [`crate::ops::local::plan_collapse`]
//! checks it — link condition, degenerate faces and a bound on how far a face normal may turn
//! — and a refused edge is simply dropped until a neighbouring collapse gives it a new chance.
//!
//! Two runs make the same collapses in the same order:
//! - [`simplify`] (and [`simplify_recorded`], which the `simplify` operation uses) reads the
//!   mesh into tables once, makes every collapse on rows (module `flat`) and writes the survivors
//!   back at the end: nothing is looked up by entity in the loop.
//! - [`QemRun`] keeps the loop's state between collapses for the editor's step mode and makes
//!   each collapse on the entities ([`crate::ops::local::collapse_edge`]), so the mesh can be shown
//!   and moved along its history between any two.
//!
//! Both compute the quadrics and the first keys the same way (`vertex_quadrics`,
//! `placement`) and break ties by entity; `tests/qem_run.rs` holds them to the same mesh,
//! element for element, and the same history records, bit for bit.

use bevy::math::{DVec3, Vec3};
use bevy::prelude::{Entity, World};

use crate::mesh::MeshMembers;
use crate::mesh::despawn::Despawner;
use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId, slots_for};
use crate::mesh::tables::{Connectivity, EntityRows, FaceRow, MeshTables, VertexRow, extract};
use crate::mesh::topology::MeshRef;

use super::Refusal;
use super::indexed_heap::{IndexedHeap, slot_of};
use fidelity::DistanceCheck;
use fit::InputSurface;

mod fidelity;
mod fit;
pub(crate) mod flat;
mod run;
mod to_target;
pub use run::{NextCollapse, QemRun, QueuedEdge, Refused};
pub use to_target::{simplify, simplify_recorded, simplify_with_progress};

/// How many faces a simplification keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SimplifyTarget {
    /// This fraction (0–1] of the faces the mesh has when the simplification starts.
    Ratio(f64),
    /// This many faces.
    Faces(usize),
}

impl SimplifyTarget {
    /// The face count to reach from a mesh of `faces` faces (a ratio rounds to the nearest
    /// count; one outside [0, 1] is clamped).
    pub fn faces(self, faces: usize) -> usize {
        match self {
            SimplifyTarget::Ratio(ratio) => (faces as f64 * ratio.clamp(0.0, 1.0)).round() as usize,
            SimplifyTarget::Faces(target) => target,
        }
    }
}

/// How to simplify. The same struct serves the command line, the editor and the tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimplifyParams {
    /// How many faces to keep. Default: half of them.
    pub target: SimplifyTarget,
    /// The most a face normal may turn in one collapse (degrees); the collapse is refused past it.
    /// Default 60°.
    pub max_normal_change_deg: f32,
    /// Weight of the boundary-preserving planes relative to the face planes. Default 100.
    pub boundary_weight: f64,
    /// Interior edges whose faces meet at more than this angle (degrees between their
    /// normals) keep their line like the boundary does. Default 45°, the remesher's; 180
    /// turns it off.
    pub feature_angle_deg: f32,
    /// Weight of those feature planes relative to the face planes. Default 1.
    pub feature_weight: f64,
    /// The least weight of a face's plane, as a share of the mean face area at the start (a
    /// face's weight is its area, or this if more). Default 0.25; 0 weighs by area alone,
    /// as Garland & Heckbert do.
    pub min_area_share: f64,
    /// What the farthest point of the input from the faces a collapse reshapes adds to its
    /// cost: its squared distance times this times twice the mean face area at the start (see
    /// [`fidelity`]). Default 0, which leaves the quadric error alone, as Garland & Heckbert
    /// do; 8 takes the bunny's Hausdorff distance at a quarter of its faces from 0.092 to
    /// 0.074 % of its diagonal, in about three times the time (`docs/performance.md`).
    pub distance_weight: f64,
    /// Whether the result's vertices are fitted to the input at the end, by one least-squares
    /// step along their normals ([`fit`]). Default `false`.
    pub fit_to_input: bool,
}

impl Default for SimplifyParams {
    fn default() -> Self {
        Self::ratio(0.5)
    }
}

impl SimplifyParams {
    /// Simplify to `ratio` (0–1] of the face count at the start, with the default limits.
    pub fn ratio(ratio: f64) -> Self {
        Self::to(SimplifyTarget::Ratio(ratio))
    }

    /// Simplify to `target` faces, with the default limits.
    pub fn faces(target: usize) -> Self {
        Self::to(SimplifyTarget::Faces(target))
    }

    /// Simplify to `target`, with the default limits.
    pub fn to(target: SimplifyTarget) -> Self {
        Self {
            target,
            max_normal_change_deg: 60.0,
            boundary_weight: 100.0,
            feature_angle_deg: 45.0,
            feature_weight: 1.0,
            min_area_share: 0.25,
            distance_weight: 0.0,
            fit_to_input: false,
        }
    }
}

/// What a simplification did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SimplifySummary {
    /// Faces before.
    pub faces_before: usize,
    /// Faces after.
    pub faces_after: usize,
    /// Collapses carried out.
    pub collapses: usize,
    /// Whether the target was reached (otherwise no legal collapse was left).
    pub reached_target: bool,
}

/// One recorded collapse, by slot: a vertex's place in a history
/// ([`crate::ops::progressive::ProgressiveMesh`]), which keeps these to split the collapses back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlotRecord {
    /// The surviving vertex.
    pub kept: u32,
    /// The removed vertex.
    pub removed: u32,
    /// Where the surviving vertex went.
    pub merged_position: Vec3,
    /// Positions before the collapse.
    pub kept_position: Vec3,
    /// The removed vertex's position before the collapse.
    pub removed_position: Vec3,
    /// Wing on the kept → removed side.
    pub left: Option<u32>,
    /// Wing on the other side.
    pub right: Option<u32>,
    /// Faces removed by the collapse (2 inside, 1 on the boundary).
    pub faces: usize,
}

/// A symmetric 4×4 quadric, stored as its upper triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric([f64; 10]);

impl Quadric {
    /// The quadric of the plane `n·x + d = 0`, times `weight`.
    pub fn plane(n: DVec3, d: f64, weight: f64) -> Self {
        let p = [n.x, n.y, n.z, d];
        let mut q = [0.0; 10];
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                q[k] = weight * p[i] * p[j];
                k += 1;
            }
        }
        Self(q)
    }

    /// `vᵀ Q v` for the point `v`.
    #[inline]
    pub fn error(&self, v: DVec3) -> f64 {
        let q = &self.0;
        let (x, y, z) = (v.x, v.y, v.z);
        q[0] * x * x
            + 2.0 * q[1] * x * y
            + 2.0 * q[2] * x * z
            + 2.0 * q[3] * x
            + q[4] * y * y
            + 2.0 * q[5] * y * z
            + 2.0 * q[6] * y
            + q[7] * z * z
            + 2.0 * q[8] * z
            + q[9]
    }

    /// The point minimising the error, if the 3×3 system is well conditioned.
    #[inline]
    pub fn optimum(&self) -> Option<DVec3> {
        let q = &self.0;
        // The system is symmetric, so its inverse's rows are the cofactor rows over the
        // determinant: one set of cross products serves both.
        let (c0, c1, c2) = (
            DVec3::new(q[0], q[1], q[2]),
            DVec3::new(q[1], q[4], q[5]),
            DVec3::new(q[2], q[5], q[7]),
        );
        let cofactors = [c1.cross(c2), c2.cross(c0), c0.cross(c1)];
        let det = c2.dot(cofactors[2]);
        let scale = q[0].abs() + q[4].abs() + q[7].abs();
        if det.abs() <= 1e-12 * scale.powi(3).max(f64::MIN_POSITIVE) {
            return None;
        }
        let rows = cofactors.map(|c| c * det.recip());
        let rhs = -DVec3::new(q[3], q[6], q[8]);
        let v = DVec3::new(rows[0].dot(rhs), rows[1].dot(rhs), rows[2].dot(rhs));
        v.is_finite().then_some(v)
    }
}

impl std::ops::Add for Quadric {
    type Output = Quadric;
    #[inline]
    fn add(mut self, other: Quadric) -> Quadric {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += b;
        }
        self
    }
}

/// A heap entry: the cost as order-preserving bits (non-negative f32s order like their bits)
/// above the edge's row, in one word ([`super::indexed_heap`]). Rows follow entity indices, so
/// equal costs go by entity index. Lowest first.
type Key = u64;

/// The heap key of an edge in `slot` whose collapse costs `cost`.
fn heap_key(cost: f64, slot: u32) -> Key {
    (u64::from((cost.max(0.0) as f32).to_bits()) << 32) | u64::from(slot)
}

/// Where an edge should collapse to and what it costs.
struct Placement {
    cost: f64,
    position: Vec3,
}

/// Per-vertex and per-edge data: vertices by entity index, edges by entity index less the
/// lowest edge's (the edges of a mesh are mostly spawned in one batch, so their indices are
/// one dense run above the vertices'; indexing from zero would leave the tables mostly empty
/// and the live part spread over more pages).
struct VertexTable {
    quadric: Vec<Quadric>,
    /// The entity index of the edge in row 0.
    edge_base: u32,
    /// Where each edge would collapse to, as of its latest key (by edge row).
    target: Vec<Vec3>,
    /// The edge behind each row, which is also its slot in the heap.
    edge: Vec<EdgeId>,
}

impl VertexTable {
    /// `e`'s row in the edge tables and its slot in the heap.
    #[inline]
    fn row(&self, e: EdgeId) -> u32 {
        e.0.index_u32() - self.edge_base
    }
}

/// The heap slots of `edges`: the lowest edge's entity index, which is slot 0, and how many
/// slots reach the highest. An edge's slot is its entity index less the lowest, so that equal
/// costs pop in entity order in both runs.
fn edge_slot_range(edges: &[EdgeId]) -> (u32, usize) {
    let base = edges.iter().map(|e| e.0.index_u32()).min().unwrap_or(0);
    let slots = slots_for(edges.iter().map(|e| e.0)).saturating_sub(base as usize);
    (base, slots)
}

/// Whether `ring` lists exactly the edges around `v`, with their other ends where they are.
fn ring_matches(m: &MeshRef<'_>, v: VertexId, ring: &[(EdgeId, VertexId, Vec3)]) -> bool {
    let mut live: Vec<(u64, u64, [u32; 3])> = m
        .vertex_outgoing(v)
        .map(|h| {
            let tip = m.to_vertex(h);
            let at = m.position(tip).to_array().map(f32::to_bits);
            (m.edge(h).0.to_bits(), tip.0.to_bits(), at)
        })
        .collect();
    let mut planned: Vec<(u64, u64, [u32; 3])> = ring
        .iter()
        .map(|(e, tip, at)| {
            (
                e.0.to_bits(),
                tip.0.to_bits(),
                at.to_array().map(f32::to_bits),
            )
        })
        .collect();
    live.sort_unstable();
    planned.sort_unstable();
    live == planned
}

/// Despawns the entities of `rows` that are not `alive`, where `rows` lists the mesh's
/// elements of one kind in storage order ([`extract`]'s rows).
///
/// Bevy keeps a table dense by moving its last row into the hole a despawn leaves, and a
/// moved row costs as much again as the despawn (the row's columns copied, two location
/// records rewritten). So the removed rows go from both ends: a removed row that is last in
/// the table goes alone, and only where the last row survives is the first removed row from
/// the front despawned, that survivor moving into its place. Rows then move only as often as
/// survivors lie beyond the part of the table the survivors will fill: at a quarter kept,
/// about one removal in four, where going by entity index moved one on nearly every removal.
/// Rows out of storage order (another mesh's rows in the same table) only cost more moves.
fn despawn_dead<T: Copy>(
    despawner: &mut Despawner<'_>,
    rows: &[T],
    entity: impl Fn(T) -> Entity,
    alive: &[bool],
) {
    let (mut front, mut back) = (0, rows.len());
    while front < back {
        if !alive[back - 1] {
            despawner.despawn(entity(rows[back - 1]));
            back -= 1;
        } else if !alive[front] {
            // The survivor last in the table takes this row's place.
            despawner.despawn(entity(rows[front]));
            front += 1;
            back -= 1;
        } else {
            front += 1;
        }
    }
}

/// What the main loop starts from: every vertex's quadric and every edge in the heap.
struct Setup {
    table: VertexTable,
    heap: IndexedHeap,
    faces_before: usize,
    /// With a distance weight: the check, and each face's row by entity index.
    check: Option<(DistanceCheck, FaceRows)>,
    /// With [`SimplifyParams::fit_to_input`]: the input, to fit the result to at the end.
    input: Option<InputSurface>,
}

/// The rows of a mesh's faces as [`extract`] listed them at a run's start, by entity: the
/// names the distance check ([`fidelity`]) knows them by.
struct FaceRows {
    /// Every element's row by entity.
    rows: EntityRows,
    /// By row: the face, to tell a face the run started with from a later one at its index.
    face: Vec<FaceId>,
}

impl FaceRows {
    fn new(members: &MeshMembers) -> Self {
        Self {
            rows: EntityRows::new(members),
            face: members.faces.clone(),
        }
    }

    /// The row of `f` ([`crate::mesh::tables::NONE`] for a face the run did not start with).
    fn of(&self, f: FaceId) -> u32 {
        self.rows
            .row(f.0)
            .filter(|&row| self.face.get(row as usize) == Some(&f))
            .unwrap_or(crate::mesh::tables::NONE)
    }
}

/// `mesh` read into tables ([`extract`]) for a run.
///
/// # Refusals
/// [`Refusal::Stale`] for a mesh that is gone; [`Refusal::NotTriangle`] naming the first face
/// that is not a triangle.
fn read_triangles(world: &World, mesh: MeshId) -> Result<MeshTables, Refusal> {
    if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    let tables = extract(world, mesh);
    match tables.tables.first_non_triangle() {
        Some(f) => Err(Refusal::NotTriangle(ElementId::Face(
            tables.members.faces[f.index()],
        ))),
        None => Ok(tables),
    }
}

/// Reads the mesh once into tables ([`extract`]) and computes the quadrics and the first key
/// of every edge from them: plain array passes, where walking the entities edge by edge spent
/// most of the setup on lookups.
///
/// # Refusals
/// [`Refusal::NotTriangle`] naming the first face that is not a triangle.
fn setup(world: &World, mesh: MeshId, params: &SimplifyParams) -> Result<Setup, Refusal> {
    let MeshTables { tables: t, members } = read_triangles(world, mesh)?;
    let (edge_base, edge_rows) = edge_slot_range(&members.edges);
    let mut table = VertexTable {
        quadric: vec![Quadric::default(); slots_for(members.vertices.iter().map(|v| v.0))],
        edge_base,
        target: vec![Vec3::ZERO; edge_rows],
        edge: vec![EdgeId(Entity::PLACEHOLDER); edge_rows],
    };
    for &e in &members.edges {
        let row = table.row(e) as usize;
        table.edge[row] = e;
    }
    for (q, v) in vertex_quadrics(&t, params)
        .into_iter()
        .zip(&members.vertices)
    {
        table.quadric[v.slot()] = q;
    }
    let end = |v: VertexRow| (members.vertices[v.index()], t.position(v));
    let entries: Vec<Key> = members
        .edges
        .iter()
        .zip(t.edges())
        .map(|(&e, row)| {
            let h = t.edge_halfedge(row);
            let ends = [end(t.from_vertex(h)), end(t.to_vertex(h))];
            keyed_ends(&mut table, e, ends)
        })
        .collect();
    let sizes = [table.target.len(), table.quadric.len()];
    let check = DistanceCheck::for_run(&t, params.distance_weight, sizes, &entries)
        .map(|check| (check, FaceRows::new(&members)));
    Ok(Setup {
        heap: IndexedHeap::from_entries(table.target.len(), entries),
        table,
        faces_before: t.face_count(),
        check,
        input: params.fit_to_input.then(|| InputSurface::of_tables(&t)),
    })
}

/// Every vertex's quadric, by vertex row: the planes of its faces (weighted by area, at least
/// [`SimplifyParams::min_area_share`] of the mean), and of its boundary and sharp edges (see
/// the module doc). Plain array passes over the tables.
fn vertex_quadrics(t: &Connectivity, params: &SimplifyParams) -> Vec<Quadric> {
    let mut quadric = vec![Quadric::default(); t.vertex_count()];
    let position = |v: VertexRow| t.position(v).as_dvec3();
    let corners_of = |f: FaceRow| t.triangle_halfedges(f).map(|h| t.to_vertex(h));
    // Twice each face's area vector, by face row: the plane's normal and weight.
    let cross: Vec<DVec3> = t
        .faces()
        .map(|f| {
            let p = corners_of(f).map(position);
            (p[1] - p[0]).cross(p[2] - p[0])
        })
        .collect();
    let total_area: f64 = cross.iter().map(|c| c.length() / 2.0).sum();
    let least_weight = params.min_area_share * total_area / t.face_count().max(1) as f64;
    for f in t.faces() {
        let corners = corners_of(f);
        let cross = cross[f.index()];
        let Some(n) = cross.try_normalize() else {
            continue;
        };
        let weight = (cross.length() / 2.0).max(least_weight);
        let q = Quadric::plane(n, -n.dot(position(corners[0])), weight);
        for v in corners {
            quadric[v.index()] = quadric[v.index()] + q;
        }
    }
    // Boundary and sharp edges: a plane through the edge, perpendicular to the face on the
    // far side of `h` (for a sharp edge, `h` and its twin each give one).
    let sharp = params.feature_angle_deg.to_radians().cos();
    let area_vector: Vec<DVec3> = t
        .faces()
        .map(|f| t.triangle_area_vector(f).as_dvec3())
        .collect();
    let unit_normal: Vec<Option<DVec3>> = area_vector.iter().map(|a| a.try_normalize()).collect();
    for h in t.halfedges() {
        let inner = t.twin(h);
        let Some(inner_face) = t.face(inner) else {
            continue;
        };
        let normal = area_vector[inner_face.index()];
        let weight = match t.face(h) {
            None => params.boundary_weight,
            Some(face) => match (unit_normal[inner_face.index()], unit_normal[face.index()]) {
                (Some(n0), Some(n1)) if n0.dot(n1) < f64::from(sharp) => params.feature_weight,
                _ => continue,
            },
        };
        let (from, to) = (t.to_vertex(inner), t.to_vertex(h));
        let (a, b) = (position(from), position(to));
        let Some(n) = (b - a).cross(normal).try_normalize() else {
            continue;
        };
        let q = Quadric::plane(n, -n.dot(a), weight * (b - a).length_squared());
        for v in [from, to] {
            quadric[v.index()] = quadric[v.index()] + q;
        }
    }
    quadric
}

/// `e`'s heap key at its current cost, for its ends and their positions
/// the caller has read, remembering where it would collapse to.
fn keyed_ends(
    table: &mut VertexTable,
    e: EdgeId,
    [(a, pa), (b, pb)]: [(VertexId, Vec3); 2],
) -> Key {
    let c = placement(
        table.quadric[a.slot()] + table.quadric[b.slot()],
        pa,
        pb,
        || a.0.to_bits() < b.0.to_bits(),
    );
    let row = table.row(e);
    table.target[row as usize] = c.position;
    heap_key(c.cost, row)
}

/// Where two vertices at `pa` and `pb` whose quadrics sum to `q` should merge, and at what
/// cost: the quadric's optimum, or where it is ill-conditioned the best of the two ends and
/// the midpoint. Between two ends of equal error the one first in the vertices' fixed order
/// wins (`a_first`: whether the vertex at `pa` comes first), so that the result does not
/// depend on which end the caller names first; it is asked only then.
fn placement(q: Quadric, pa: Vec3, pb: Vec3, a_first: impl FnOnce() -> bool) -> Placement {
    let (pa, pb) = (pa.as_dvec3(), pb.as_dvec3());
    let position = q.optimum().unwrap_or_else(|| {
        let (ea, eb) = (q.error(pa), q.error(pb));
        let (first, second) = match ea.total_cmp(&eb) {
            std::cmp::Ordering::Equal if !a_first() => (pb, pa),
            _ => (pa, pb),
        };
        // The first of equals, in the order: first end, second end, midpoint.
        [first, second, (pa + pb) / 2.0]
            .into_iter()
            .min_by(|x, y| q.error(*x).total_cmp(&q.error(*y)))
            .unwrap_or(first)
    });
    Placement {
        cost: q.error(position).max(0.0),
        position: position.as_vec3(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::soup::PolygonSoup;
    use crate::mesh::{MeshInfo, build_mesh};

    /// The quadric `setup` gives input vertex 0 of the triangles `faces` over `positions`.
    fn first_vertex_quadric(
        positions: Vec<Vec3>,
        faces: &[[u32; 3]],
        params: &SimplifyParams,
    ) -> Quadric {
        let soup = PolygonSoup::from_faces(positions, faces);
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let origin = built.input_vertices[0].unwrap();
        let Ok(s) = setup(&world, built.mesh, params) else {
            panic!("two triangles are refused");
        };
        s.table.quadric[origin.slot()]
    }

    /// The quadric `setup` gives the corner at the origin of two unit right triangles folded at
    /// 90° along the x axis: `(0,0,0) (1,0,0) (0,1,0)` in the plane z = 0 and `(1,0,0)
    /// (0,0,0) (0,0,1)` in the plane y = 0.
    fn fold_corner_quadric(params: &SimplifyParams) -> Quadric {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        first_vertex_quadric(positions, &[[0, 1, 2], [1, 0, 3]], params)
    }

    /// The quadric `setup` gives the origin, corner of a triangle of area 1/2 and one of area
    /// 1/20 beside it in the plane z = 0.
    fn small_beside_large_quadric(params: &SimplifyParams) -> Quadric {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, -0.1, 0.0)];
        first_vertex_quadric(positions, &[[0, 1, 2], [1, 0, 3]], params)
    }

    #[test]
    fn a_face_plane_weighs_its_area_or_a_share_of_the_mean_area_if_more() {
        let share = |min_area_share| SimplifyParams {
            min_area_share,
            ..SimplifyParams::faces(0)
        };
        let p = DVec3::new(0.3, 0.2, -0.5);
        let by_area = small_beside_large_quadric(&share(0.0)).error(p);
        // The mean area is 0.275: the small face weighs that instead of 0.05, the large one
        // keeps its 0.5; both planes are z = 0, at distance 0.5 from `p`.
        let added = small_beside_large_quadric(&share(1.0)).error(p) - by_area;
        assert!((added - (0.275 - 0.05) * 0.25).abs() < 1e-9, "{added}");
        // A share under the small face's area changes nothing.
        let under = small_beside_large_quadric(&share(0.1)).error(p) - by_area;
        assert!(under.abs() < 1e-12, "{under}");
    }

    #[test]
    fn a_sharp_edge_adds_the_planes_through_it_perpendicular_to_its_faces() {
        let with = SimplifyParams::faces(0);
        // The fold's faces meet at 90°: sharp at the default 45°, not at 100°.
        let without = SimplifyParams {
            feature_angle_deg: 100.0,
            ..with
        };
        let p = DVec3::new(0.3, 0.2, -0.5);
        // Perpendicular to the face in z = 0 through the x axis is the plane y = 0, and the
        // other way round; each weighs |edge|² = 1, so they add y² + z².
        let added = fold_corner_quadric(&with).error(p) - fold_corner_quadric(&without).error(p);
        assert!(
            (added - (0.2f64.powi(2) + 0.5f64.powi(2))).abs() < 1e-9,
            "{added}"
        );
    }
}
