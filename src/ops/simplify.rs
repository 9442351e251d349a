//! Quadric error simplification (Garland & Heckbert 1997).
//!
//! Every face contributes the quadric `K = p pᵀ` of its plane `p = (n, −n·x)` (area-weighted);
//! a vertex's quadric is the sum over its faces, plus, on the boundary, quadrics of planes
//! through each boundary edge perpendicular to its face (weighted by [`SimplifyParams::
//! boundary_weight`]) so that borders keep their shape and holes do not close. Sharp edges
//! (dihedral angle above [`SimplifyParams::feature_angle_deg`]) get the same planes, one per
//! side, weighted by [`SimplifyParams::feature_weight`]: a crease then holds its line as the
//! faces beside it are merged, where the face planes alone let it be rounded off. The cost of
//! collapsing an edge is `vᵀ (Q_a + Q_b) v` at the optimal `v` (the solution of the 3×3 system;
//! when it is near singular, the best of the two ends and the midpoint).
//!
//! Edges wait in an indexed heap ([`super::indexed_heap`]), one entry per edge: when a collapse
//! changes the cost of the edges around the merged vertex, their entries are re-keyed in place,
//! so no pop is spent on a stale entry. Equal costs are ordered by the edge's entity index, so a
//! run is deterministic. Every collapse goes through
//! [`crate::ops::local::plan_collapse`] — link condition, degenerate faces and a bound on how
//! far a face normal may turn — and a refused edge is simply dropped until a neighbouring
//! collapse gives it a new chance.

use bevy::math::{DVec3, Vec3};
use bevy::prelude::{Entity, World};

use crate::mesh::ids::{EdgeId, ElementId, MeshId, VertexId, slot, slots_for};
use crate::mesh::tables::{Connectivity, FaceRow, MeshTables, VertexRow, extract};
use crate::mesh::topology::{Lookups, MeshRef, newell_area_vector};

use super::Refusal;
use super::indexed_heap::IndexedHeap;

mod run;
pub use run::{NextCollapse, QemRun, QueuedEdge, Refused};

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

/// Simplifies `mesh` (triangles only) until it has at most the target's faces or no
/// legal collapse remains.
///
/// # Refusals
/// [`Refusal::NotTriangle`] if a face is not a triangle (the mesh is unchanged); a stale mesh.
pub fn simplify(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
) -> Result<SimplifySummary, Refusal> {
    simplify_with_progress(world, mesh, params, |_| true)
}

/// [`simplify`], calling `progress(fraction done)` every few hundred collapses; returning
/// `false` stops early (the mesh is then valid but less simplified).
///
/// # Refusals
/// As [`simplify`].
pub fn simplify_with_progress(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    progress: impl FnMut(f32) -> bool,
) -> Result<SimplifySummary, Refusal> {
    simplify_inner(world, mesh, params, progress, |_, _| {})
}

/// [`simplify_with_progress`], handing every collapse it makes to `record` in order, with the
/// world right after it (what [`crate::ops::progressive`] keeps to split them back).
///
/// # Refusals
/// As [`simplify`].
pub fn simplify_recorded(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    progress: impl FnMut(f32) -> bool,
    record: impl FnMut(&World, &super::local::CollapseResult),
) -> Result<SimplifySummary, Refusal> {
    simplify_inner(world, mesh, params, progress, record)
}

fn simplify_inner(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    mut progress: impl FnMut(f32) -> bool,
    mut record: impl FnMut(&World, &super::local::CollapseResult),
) -> Result<SimplifySummary, Refusal> {
    let mut run = QemRun::start(world, mesh, params)?;
    // What the collapses removed, despawned together at the end (see `despawn_removed`).
    let mut graveyard: Vec<Entity> = Vec::new();
    let lookups = Lookups::new(world);
    let to_remove = run.faces_before.saturating_sub(run.target_faces).max(1);
    while let Some(result) = run.collapse_next_deferred(world, &lookups, &mut graveyard) {
        record(world, &result);
        if run.collapses % 512 == 0 {
            let done = (run.faces_before - run.faces) as f32 / to_remove as f32;
            if !progress(done.min(1.0)) {
                break;
            }
        }
    }
    despawn_removed(world, graveyard);
    Ok(run.summary())
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

/// Despawns what the collapses removed, highest entity index first. The elements were
/// spawned in index order when the mesh was built, so this takes table rows from the end:
/// few live rows have to move into the holes, and memory is walked in order, where despawning
/// collapse by collapse moved a row and missed the cache for every element. The order comes
/// from placing each entity at its index in a table and reading the table backwards: one
/// linear pass, where sorting took a fifth of the despawning.
///
/// A stepped run despawns each collapse's elements as it goes, so its mesh is stored in
/// another order (Bevy fills a despawned row with the table's last), and a saved file lists
/// the same vertices and faces in another order. Despawning in collapse order here would make
/// the orders match; measured on the bunny's simplification to 25 %, median of 12, it took 198
/// ms against 134.
fn despawn_removed(world: &mut World, gone: Vec<Entity>) {
    let mut by_index = vec![None; slots_for(gone.iter().copied())];
    for e in gone {
        by_index[slot(e)] = Some(e);
    }
    for e in by_index.into_iter().rev().flatten() {
        world.despawn(e);
    }
}

/// What the main loop starts from: every vertex's quadric and every edge in the heap.
struct Setup {
    table: VertexTable,
    heap: IndexedHeap,
    faces_before: usize,
}

/// Reads the mesh once into tables ([`extract`]) and computes the quadrics and the first key
/// of every edge from them: plain array passes, where walking the entities edge by edge spent
/// most of the setup on lookups.
///
/// # Refusals
/// [`Refusal::NotTriangle`] naming the first face that is not a triangle.
fn setup(world: &World, mesh: MeshId, params: &SimplifyParams) -> Result<Setup, Refusal> {
    let MeshTables { tables: t, members } = extract(world, mesh);
    if let Some(f) = t.first_non_triangle() {
        return Err(Refusal::NotTriangle(ElementId::Face(
            members.faces[f.index()],
        )));
    }
    let edge_base = members
        .edges
        .iter()
        .map(|e| e.0.index_u32())
        .min()
        .unwrap_or(0);
    let edge_rows = slots_for(members.edges.iter().map(|e| e.0)).saturating_sub(edge_base as usize);
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
    // Each table vertex's slot in `table.quadric`.
    let slot_of_row: Vec<usize> = members.vertices.iter().map(|v| v.slot()).collect();
    let quadric = &mut table.quadric;
    let position = |v: VertexRow| t.position(v).as_dvec3();
    for f in t.faces() {
        let corners = t.triangle_halfedges(f).map(|h| t.to_vertex(h));
        let p = corners.map(position);
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let Some(n) = cross.try_normalize() else {
            continue;
        };
        let q = Quadric::plane(n, -n.dot(p[0]), cross.length() / 2.0);
        for v in corners {
            let at = slot_of_row[v.index()];
            quadric[at] = quadric[at] + q;
        }
    }
    // Boundary and sharp edges: a plane through the edge, perpendicular to the face on the
    // far side of `h` (for a sharp edge, `h` and its twin each give one).
    let sharp = params.feature_angle_deg.to_radians().cos();
    let area_vector: Vec<DVec3> = t
        .faces()
        .map(|f| face_area_vector(&t, f).as_dvec3())
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
            let at = slot_of_row[v.index()];
            quadric[at] = quadric[at] + q;
        }
    }
    let end = |v: VertexRow| (members.vertices[v.index()], t.position(v));
    let entries = members
        .edges
        .iter()
        .zip(t.edges())
        .map(|(&e, row)| {
            let h = t.edge_halfedge(row);
            let ends = [end(t.from_vertex(h)), end(t.to_vertex(h))];
            keyed_ends(&mut table, e, ends)
        })
        .collect();
    Ok(Setup {
        heap: IndexedHeap::from_entries(table.target.len(), entries),
        table,
        faces_before: t.face_count(),
    })
}

/// A triangle's area vector from the tables, as [`MeshRef::face_area_vector`] computes it.
fn face_area_vector(t: &Connectivity, f: FaceRow) -> Vec3 {
    newell_area_vector(&t.triangle_halfedges(f).map(|h| t.position(t.to_vertex(h))))
}

/// `e`'s heap key at its current cost, for its ends and their positions
/// the caller has read, remembering where it would collapse to.
fn keyed_ends(table: &mut VertexTable, e: EdgeId, mut ends: [(VertexId, Vec3); 2]) -> Key {
    // Either order gives the same sum of quadrics; a fixed one makes the fallback's tie
    // between the two ends independent of how the caller reached the edge.
    ends.sort_unstable_by_key(|(v, _)| v.0.to_bits());
    let c = placement(table, ends);
    let row = table.row(e);
    table.target[row as usize] = c.position;
    (u64::from((c.cost.max(0.0) as f32).to_bits()) << 32) | u64::from(row)
}

fn placement(table: &VertexTable, [(a, pa), (b, pb)]: [(VertexId, Vec3); 2]) -> Placement {
    let q = table.quadric[a.slot()] + table.quadric[b.slot()];
    let (pa, pb) = (pa.as_dvec3(), pb.as_dvec3());
    let position = q.optimum().unwrap_or_else(|| {
        [pa, pb, (pa + pb) / 2.0]
            .into_iter()
            .min_by(|x, y| q.error(*x).total_cmp(&q.error(*y)))
            .unwrap_or(pa)
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

    /// The quadric `setup` gives the corner at the origin of two unit right triangles folded at
    /// 90° along the x axis: `(0,0,0) (1,0,0) (0,1,0)` in the plane z = 0 and `(1,0,0)
    /// (0,0,0) (0,0,1)` in the plane y = 0.
    fn fold_corner_quadric(params: &SimplifyParams) -> Quadric {
        let soup = PolygonSoup::from_faces(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            &[[0, 1, 2], [1, 0, 3]],
        );
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let origin = built.input_vertices[0].unwrap();
        let Ok(s) = setup(&world, built.mesh, params) else {
            panic!("two triangles are refused");
        };
        s.table.quadric[origin.slot()]
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
