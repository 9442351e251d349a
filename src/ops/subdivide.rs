//! Loop and Catmull–Clark subdivision, computed in bulk on index tables.
//!
//! Both read the mesh once ([`crate::mesh::tables::extract`]), build the refined connectivity
//! by index arithmetic — every child halfedge's twin is known from its parent's, so no search
//! or sort is needed — and write it back in one pass. Old vertices keep their entities.
//!
//! **Loop** (Loop 1987), triangles only. Each triangle `(v0, v1, v2)` with edge points `m_i` on
//! side `v_i v_{i+1}` becomes `(v_i, m_i, m_{i−1})` for each corner plus `(m0, m1, m2)`:
//!
//! ```text
//!         v2                    v2
//!        /  \                  /  \
//!       /    \       →       m2 —— m1
//!      /      \              / \  / \
//!    v0 ——————  v1         v0 —— m0 —— v1
//! ```
//!
//! - edge point, interior: `3/8 (a + b) + 1/8 (c + d)`; boundary: the midpoint;
//! - vertex, interior of valence n: `(1 − n u) v + u Σ neighbours`, `u = 3/16` for n = 3, else
//!   `3 / (8 n)` (the weights of the course and of Scotty3D's tests);
//! - vertex on the boundary: `3/4 v + 1/8 (a + b)` with its two boundary neighbours; a corner
//!   (two edges) stays put.
//!
//! **Catmull–Clark** (Catmull & Clark 1978), any polygons; the result is all quads. Face point:
//! the centroid. Edge point: `(a + b + f1 + f2) / 4`, the midpoint on the boundary. Vertex of
//! valence n: `(Q + 2 R + (n − 3) P) / n` with Q the mean of its face points and R of its edge
//! midpoints; on the boundary the cubic B-spline rule `3/4 P + 1/8 (a + b)`, and a vertex with a
//! single face stays put.
//!
//! **Attributes**: UVs are interpolated linearly per corner, the standard choice: an old vertex's
//! corners keep their UVs, an edge point's corners take the midpoint of the edge's UVs inside
//! each face (so a seam stays a seam), a face point the centroid of its face's UVs. Colours are
//! kept at old vertices and averaged at new ones (edge ends, face corners). Normals are
//! dropped (the surface moved; the edit's outcome says so).

use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;

use crate::mesh::MeshMembers;
use crate::mesh::attributes::{AttributeColumns, mean_color};
use crate::mesh::groups::FaceGroups;
use crate::mesh::ids::{ElementId, FaceId, MeshId};
use crate::mesh::tables::write::{SpawnWith, reserve_rows_while, write_links};
use crate::mesh::tables::{
    Connectivity, FaceCorners, FaceRow, HalfedgeRow, MeshTables, NONE, RowCounts, VertexRow,
    extract,
};

use super::Refusal;
use crate::memory_budget::Estimate;

use crate::ops::declaration::{Declaration, FaceChildren, Parameter};

mod operation;
pub mod stencil;
pub mod stencil_shapes;
mod stepping;
pub use operation::{Subdivide, subdivision};
pub use stepping::SubdivideSteps;

/// The levels one step may ask for (each quadruples the faces).
const LEVELS: Parameter = Parameter::whole("LEVELS", 1, 1, 8);

/// What subdivision carries and what it drops (see the module doc).
const CARRIES_SOME: &str = "subdivision carries UVs, colours and groups, not normals or seam marks";

/// Loop subdivision: a job on a large mesh that rewrites the tables (only vertex ids survive).
pub const LOOP: Declaration = Declaration::new("loop")
    .titled("Loop subdivision")
    .described("Loop subdivision (1987), LEVELS times: each triangle into four, smoothed")
    .on_key("L")
    .with_parameters(&[LEVELS])
    .computed_on_tables()
    .as_job()
    .stepping()
    .renumbering(FaceChildren::Each(4))
    .carrying_some(CARRIES_SOME);

/// Catmull–Clark subdivision: as [`LOOP`].
pub const CATMULL_CLARK: Declaration = Declaration::new("catmull-clark")
    .titled("Catmull-Clark subdivision")
    .described("Catmull-Clark subdivision (1978), LEVELS times: any polygons into quads, smoothed")
    .on_key("Q")
    .with_parameters(&[LEVELS])
    .computed_on_tables()
    .as_job()
    .stepping()
    .renumbering(FaceChildren::PerCorner(4))
    .carrying_some(CARRIES_SOME);

/// A subdivision scheme (the edit layer names it as `crate::edit::Scheme`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Loop (1987): triangles to triangles, approximating.
    Loop,
    /// Catmull–Clark (1978): any polygons to quads, approximating.
    CatmullClark,
}

impl Scheme {
    /// Subdivides `mesh` `levels` times with this scheme: [`loop_subdivide`] or
    /// [`catmull_clark`], with their refusals.
    pub fn subdivide(
        self,
        world: &mut World,
        mesh: MeshId,
        levels: u32,
    ) -> Result<SubdivisionSummary, Refusal> {
        subdivide(world, mesh, levels, self, &mut |_| true)
    }

    /// [`Scheme::subdivide`], calling `progress` as its phases end: the plan checked (0.05),
    /// then as each kind of row of the result is made (up to 0.8) while the levels are computed
    /// on another thread. `false` at the first call stops it
    /// before anything changed ([`Refusal::Stopped`]); from then on it runs to the end (its
    /// levels are computed in one pass on another thread while this one makes the rows, and
    /// half-written rows would be no mesh).
    ///
    /// # Refusals
    /// As [`Scheme::subdivide`]'s, and [`Refusal::Stopped`].
    pub fn subdivide_with_progress(
        self,
        world: &mut World,
        mesh: MeshId,
        levels: u32,
        progress: &mut dyn FnMut(f32) -> bool,
    ) -> Result<SubdivisionSummary, Refusal> {
        subdivide(world, mesh, levels, self, progress)
    }

    /// The tables `levels` levels of this scheme make from `tables` (whose rows are the
    /// entities `members`): what [`Scheme::subdivide`] writes back, for a caller that holds the
    /// tables already and writes them itself (the editor's jobs).
    ///
    /// # Refusals
    /// As [`Scheme::subdivide`]'s, naming the element by its entity in `members`.
    pub fn subdivide_tables(
        self,
        tables: &Connectivity,
        members: &MeshMembers,
        levels: u32,
    ) -> Result<Connectivity, Refusal> {
        Ok(match self.plan(tables, members, levels)? {
            Some(_) => self.run_levels(tables, levels),
            None => tables.clone(),
        })
    }

    /// Checks `tables` (rows: `members`) and returns the row counts `levels` levels make, or
    /// `None` for no level.
    ///
    /// # Refusals
    /// Loop: [`Refusal::NotTriangle`] naming a face that is not a triangle. Both:
    /// [`Refusal::OverBudget`] when the result would take more memory than the budget allows
    /// ([`crate::memory_budget`]), [`Refusal::TooLarge`] when its halfedges would not fit
    /// 32-bit rows.
    fn plan(
        self,
        tables: &Connectivity,
        members: &MeshMembers,
        levels: u32,
    ) -> Result<Option<RowCounts>, Refusal> {
        if let (Scheme::Loop, Some(f)) = (self, tables.first_non_triangle()) {
            return Err(Refusal::NotTriangle(ElementId::Face(
                members.faces[f.index()],
            )));
        }
        if levels == 0 {
            return Ok(None);
        }
        let counts = final_counts(self.steps(), tables, levels);
        crate::memory_budget::check(&Estimate {
            what: format!("{} ×{levels}", self.name()),
            faces: counts.faces as u64,
            rows: (counts.vertices + counts.halfedges + counts.edges + counts.faces) as u64,
            instead: "use fewer levels",
        })?;
        if counts.halfedges >= NONE as usize {
            return Err(Refusal::TooLarge(counts.halfedges));
        }
        Ok(Some(counts))
    }

    /// The scheme's name as a person says it: "Loop", "Catmull–Clark".
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Loop => "Loop",
            Scheme::CatmullClark => "Catmull–Clark",
        }
    }

    /// How one level runs.
    fn steps(self) -> Steps {
        match self {
            Scheme::Loop => Steps {
                step: |t| loop_tables(t).expect("checked: every face is a triangle"),
                counts: |t, _| {
                    let edges = 2 * t.edges + 3 * t.faces;
                    RowCounts {
                        vertices: t.vertices + t.edges,
                        halfedges: 2 * edges,
                        edges,
                        faces: 4 * t.faces,
                    }
                },
            },
            Scheme::CatmullClark => Steps {
                step: catmull_clark_tables,
                // Every corner becomes a quad, and each adds an edge from its face point.
                counts: |t, corners| {
                    let edges = 2 * t.edges + corners;
                    RowCounts {
                        vertices: t.vertices + t.edges + t.faces,
                        halfedges: 2 * edges,
                        edges,
                        faces: corners,
                    }
                },
            },
        }
    }

    /// `levels` levels of the scheme on tables [`Scheme::plan`] passed (at least one level).
    fn run_levels(self, tables: &Connectivity, levels: u32) -> Connectivity {
        let step = self.steps().step;
        let mut t = step(tables);
        for _ in 1..levels {
            t = step(&t);
        }
        t
    }
}

/// What a subdivision produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubdivisionSummary {
    /// Levels applied.
    pub levels: u32,
    /// Vertices after.
    pub vertices: usize,
    /// Faces after.
    pub faces: usize,
}

impl SubdivisionSummary {
    /// The summary of `levels` levels that made the tables `t`.
    pub fn of(levels: u32, t: &Connectivity) -> Self {
        Self {
            levels,
            vertices: t.vertex_count(),
            faces: t.face_count(),
        }
    }

    /// What the subdivision made, for its outcome: levels, vertices and faces.
    pub fn describe(&self) -> String {
        format!(
            "{} level(s): {} vertices, {} faces",
            self.levels, self.vertices, self.faces
        )
    }
}

/// The faces of a table mesh as rings of halfedges, each starting at the face's halfedge.
struct FaceRings {
    starts: Vec<u32>,
    ring: Vec<HalfedgeRow>,
    /// Each interior halfedge's position in its face's ring, by halfedge row.
    slot: Vec<u32>,
}

impl FaceRings {
    fn new(t: &Connectivity) -> Self {
        let mut starts = Vec::with_capacity(t.face_count() + 1);
        let mut ring = Vec::with_capacity(t.halfedge_count());
        let mut slot = vec![NONE; t.halfedge_count()];
        starts.push(0);
        for f in t.faces() {
            for (i, h) in t.face_halfedges(f).enumerate() {
                slot[h.index()] = i as u32;
                ring.push(h);
            }
            starts.push(ring.len() as u32);
        }
        Self { starts, ring, slot }
    }

    /// Face `f`'s halfedges.
    fn face(&self, f: FaceRow) -> &[HalfedgeRow] {
        &self.ring[self.start(f)..self.starts[f.index() + 1] as usize]
    }

    /// Where face `f`'s ring starts in [`FaceRings::ring`].
    fn start(&self, f: FaceRow) -> usize {
        self.starts[f.index()] as usize
    }

    /// Interior halfedge `h`'s position in its face's ring.
    fn slot(&self, h: HalfedgeRow) -> usize {
        self.slot[h.index()] as usize
    }
}

/// The positions at the start and the tip of halfedge `h`.
fn ends(t: &Connectivity, h: HalfedgeRow) -> (Vec3, Vec3) {
    (t.position(t.from_vertex(h)), t.position(t.to_vertex(h)))
}

/// Boundary rule shared by both schemes: `3/4 P + 1/8 (a + b)` with the two boundary
/// neighbours (the vertex's halfedge is its outgoing boundary halfedge).
fn boundary_vertex(t: &Connectivity, v: VertexRow) -> Vec3 {
    let h = t.vertex_halfedge(v);
    let a = t.position(t.to_vertex(h));
    let b = t.position(t.from_vertex(t.prev(h)));
    0.75 * t.position(v) + 0.125 * (a + b)
}

/// Loop-subdivides a triangle mesh `levels` times.
///
/// # Refusals
/// [`Refusal::NotTriangle`] naming a face with other than three sides; the mesh is unchanged.
pub fn loop_subdivide(
    world: &mut World,
    mesh: MeshId,
    levels: u32,
) -> Result<SubdivisionSummary, Refusal> {
    subdivide(world, mesh, levels, Scheme::Loop, &mut |_| true)
}

/// Catmull–Clark-subdivides any polygon mesh `levels` times. Never refuses.
pub fn catmull_clark(
    world: &mut World,
    mesh: MeshId,
    levels: u32,
) -> Result<SubdivisionSummary, Refusal> {
    subdivide(world, mesh, levels, Scheme::CatmullClark, &mut |_| true)
}

/// How a scheme runs: one level on tables, and the row counts a level makes from the
/// counts before it and the number of face corners, known before the tables are computed.
#[derive(Clone, Copy)]
struct Steps {
    step: fn(&Connectivity) -> Connectivity,
    counts: fn(RowCounts, usize) -> RowCounts,
}

/// The row counts `levels` levels of `steps` make from `tables` (saturating: a count too
/// large for `usize` is refused by the budget long before).
fn final_counts(steps: Steps, tables: &Connectivity, levels: u32) -> RowCounts {
    let mut counts = tables.row_counts();
    let mut corners = tables
        .halfedges()
        .filter(|&h| !tables.is_boundary(h))
        .count();
    for _ in 0..levels {
        counts = (steps.counts)(counts, corners);
        corners = counts.faces.saturating_mul(4);
    }
    counts
}

/// Runs `levels` levels of `scheme` on `mesh`, if [`Scheme::plan`] passes its tables. The new
/// tables are computed on a second thread while this one makes the result's entities exist
/// (the two largest costs, overlapped), and the links are written once both are done.
fn subdivide(
    world: &mut World,
    mesh: MeshId,
    levels: u32,
    scheme: Scheme,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<SubdivisionSummary, Refusal> {
    if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    let MeshTables { tables, members } = extract(world, mesh);
    let Some(counts) = scheme.plan(&tables, &members, levels)? else {
        return Ok(SubdivisionSummary::of(levels, &tables));
    };
    if !progress(0.05) {
        return Err(Refusal::Stopped);
    }
    let tables = &tables;
    // The rows are made on this thread while the levels are computed on the other: progress
    // follows the rows, kind by kind.
    let mut rows_made = |fraction: f32| {
        progress(0.05 + 0.75 * fraction);
    };
    let (result, rows) = reserve_rows_while(
        world,
        counts,
        mesh,
        Some(&members),
        SpawnWith::NONE,
        &mut rows_made,
        move || scheme.run_levels(tables, levels),
    );
    write_links(world, &result, mesh, &rows);
    Ok(SubdivisionSummary::of(levels, &result))
}

/// The positions of the vertices one level of Loop subdivision makes, by their rows in
/// [`loop_tables`]' result: the old vertices moved (by vertex row), then one point per old edge
/// (by edge row). `Err(face)` if a face is not a triangle.
pub fn loop_points(t: &Connectivity) -> Result<Vec<Vec3>, FaceRow> {
    if let Some(f) = t.first_non_triangle() {
        return Err(f);
    }
    let mut positions = Vec::with_capacity(t.vertex_count() + t.edge_count());
    for v in t.vertices() {
        let p = t.position(v);
        let n = t.vertex_outgoing(v).count();
        positions.push(if t.is_boundary_vertex(v) {
            if n <= 2 { p } else { boundary_vertex(t, v) }
        } else {
            let u = if n == 3 {
                3.0 / 16.0
            } else {
                3.0 / (8.0 * n as f32)
            };
            let sum: Vec3 = t
                .vertex_outgoing(v)
                .map(|h| t.position(t.to_vertex(h)))
                .sum();
            (1.0 - n as f32 * u) * p + u * sum
        });
    }
    for e in t.edges() {
        let h = t.edge_halfedge(e);
        let (a, b) = ends(t, h);
        positions.push(if t.is_boundary_edge(e) {
            (a + b) * 0.5
        } else {
            let c = t.position(t.to_vertex(t.next(h)));
            let d = t.position(t.to_vertex(t.next(t.twin(h))));
            0.375 * (a + b) + 0.125 * (c + d)
        });
    }
    Ok(positions)
}

/// One level of Loop subdivision on tables; `Err(face)` if a face is not a triangle.
pub fn loop_tables(t: &Connectivity) -> Result<Connectivity, FaceRow> {
    let positions = loop_points(t)?;
    let rings = FaceRings::new(t);
    let (nv, nf) = (t.vertex_count(), t.face_count());

    // The new faces as corners: vertex rows (the old vertices, then one per old edge) and
    // each corner's twin corner.
    let mut indices = Vec::with_capacity(12 * nf);
    let mut twin = Vec::with_capacity(12 * nf);
    let corner = |face: usize, k: usize| (3 * face + k) as u32;
    for f in t.faces() {
        let hs = rings.face(f);
        let v = |i: usize| t.from_vertex(hs[i % 3]).get();
        let m = |i: usize| nv as u32 + t.edge(hs[i % 3]).get();
        // The neighbour across side i: (its face, the side's slot there), or none.
        let across = |i: usize| {
            let o = t.twin(hs[i % 3]);
            t.face(o).map(|g| (g.index(), rings.slot(o)))
        };
        let f = f.index();
        for i in 0..3 {
            indices.extend([v(i), m(i), m(i + 2)]);
            twin.push(across(i).map_or(NONE, |(g, j)| corner(4 * g + (j + 1) % 3, 2)));
            twin.push(corner(4 * f + 3, (i + 2) % 3));
            twin.push(across(i + 2).map_or(NONE, |(g, j)| corner(4 * g + j, 0)));
        }
        indices.extend([m(0), m(1), m(2)]);
        for j in 0..3 {
            twin.push(corner(4 * f + (j + 1) % 3, 1));
        }
    }
    let face_starts: Vec<u32> = (0..=4 * nf as u32).map(|i| 3 * i).collect();
    let mut c = Connectivity::from_corners(FaceCorners {
        positions: &positions,
        indices: &indices,
        face_starts: &face_starts,
        twin: &twin,
    });
    // The attributes, by the same layout: per old face, per corner i `(v_i, m_i, m_{i−1})`,
    // then `(m0, m1, m2)`.
    c.attributes = subdivided_attributes(
        t,
        &c,
        3,
        |_| 4,
        |uv, out| {
            for f in t.faces() {
                let hs = rings.face(f);
                // The UV at v_i inside f: the corner of the halfedge into it.
                let at = |i: usize| uv[hs[(i + 2) % 3].index()];
                let mid = |i: usize| (at(i) + at(i + 1)) * 0.5;
                for i in 0..3 {
                    out.extend([at(i), mid(i), mid(i + 2)]);
                }
                out.extend([mid(0), mid(1), mid(2)]);
            }
        },
    );
    Ok(c)
}

/// The attribute columns of a subdivided mesh `c` (faces of `sides` corners each, the
/// `children(f)` faces of old face `f` one after another, in old face order) from those of `t`:
/// UVs from `corner_uvs`, which pushes the UV at every new corner's vertex in `c`'s corner
/// order; colours kept at old vertices, the mean of the edge's ends at edge points and of the
/// face's corners at face points; each new face in its old face's group; normals dropped (the
/// surface moved).
fn subdivided_attributes(
    t: &Connectivity,
    c: &Connectivity,
    sides: usize,
    children: impl Fn(FaceRow) -> usize,
    corner_uvs: impl FnOnce(&[Vec2], &mut Vec<Vec2>),
) -> AttributeColumns {
    let mut out = AttributeColumns::default();
    if let Some(groups) = &t.attributes.groups {
        let of_face = t
            .faces()
            .flat_map(|f| std::iter::repeat_n(groups.of_face[f.index()], children(f)))
            .collect();
        out.groups = Some(FaceGroups {
            table: groups.table.clone(),
            of_face,
        });
    }
    if let Some(uv) = t
        .attributes
        .uv
        .as_deref()
        .filter(|u| u.len() == t.twin.len())
    {
        let mut corners = Vec::with_capacity(c.face_halfedge.len() * sides);
        corner_uvs(uv, &mut corners);
        // Halfedge k (corner k) holds the UV at its tip, the next corner's vertex.
        let mut table = vec![Vec2::ZERO; c.twin.len()];
        for (k, slot) in table.iter_mut().enumerate().take(corners.len()) {
            let base = k - k % sides;
            *slot = corners[base + (k % sides + 1) % sides];
        }
        out.uv = Some(table);
    }
    if let Some(colors) = t
        .attributes
        .colors
        .as_deref()
        .filter(|x| x.len() == t.positions.len())
    {
        let mut new = colors.to_vec();
        new.extend(t.edges().map(|e| {
            let h = t.edge_halfedge(e);
            mean_color([
                colors[t.from_vertex(h).index()],
                colors[t.to_vertex(h).index()],
            ])
        }));
        // Catmull–Clark adds one vertex per face after the edge points.
        if c.positions.len() > new.len() {
            new.extend(
                t.faces().map(|f| {
                    mean_color(t.face_halfedges(f).map(|h| colors[t.to_vertex(h).index()]))
                }),
            );
        }
        out.colors = Some(new);
    }
    out
}

/// The positions of the vertices one level of Catmull–Clark subdivision makes, by their rows
/// in [`catmull_clark_tables`]' result: the old vertices moved (by vertex row), then one point
/// per old edge (by edge row), then one per old face (by face row).
pub fn catmull_clark_points(t: &Connectivity) -> Vec<Vec3> {
    let (nv, ne, nf) = (t.vertex_count(), t.edge_count(), t.face_count());
    let face_points: Vec<Vec3> = t
        .faces()
        .map(|f| {
            let (sum, k) = t.face_halfedges(f).fold((Vec3::ZERO, 0usize), |(s, k), h| {
                (s + t.position(t.to_vertex(h)), k + 1)
            });
            sum / k as f32
        })
        .collect();
    // The face point of the face of `h`, which must have one.
    let face_point = |h: HalfedgeRow| {
        let f = t.face(h).expect("an interior halfedge has a face");
        face_points[f.index()]
    };
    let mut positions = Vec::with_capacity(nv + ne + nf);
    for v in t.vertices() {
        let p = t.position(v);
        if t.is_boundary_vertex(v) {
            let faces = t.vertex_outgoing(v).filter(|&h| !t.is_boundary(h)).count();
            positions.push(if faces <= 1 { p } else { boundary_vertex(t, v) });
            continue;
        }
        let (mut q, mut r, mut n) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
        for h in t.vertex_outgoing(v) {
            q += face_point(h);
            r += (p + t.position(t.to_vertex(h))) * 0.5;
            n += 1.0;
        }
        positions.push((q / n + 2.0 * r / n + (n - 3.0) * p) / n);
    }
    for e in t.edges() {
        let h = t.edge_halfedge(e);
        let (a, b) = ends(t, h);
        positions.push(if t.is_boundary_edge(e) {
            (a + b) * 0.5
        } else {
            let f1 = face_point(h);
            let f2 = face_point(t.twin(h));
            (a + b + f1 + f2) * 0.25
        });
    }
    positions.extend_from_slice(&face_points);
    positions
}

/// One level of Catmull–Clark subdivision on tables.
pub fn catmull_clark_tables(t: &Connectivity) -> Connectivity {
    let positions = catmull_clark_points(t);
    let rings = FaceRings::new(t);
    let (nv, ne) = (t.vertex_count(), t.edge_count());

    // The new quads as corners: vertex rows (the old vertices, one per old edge, one per old
    // face) and each corner's twin corner.
    let corners = rings.ring.len();
    let mut indices = Vec::with_capacity(4 * corners);
    let mut twin = Vec::with_capacity(4 * corners);
    let quad = |r: usize, k: usize| (4 * r + k) as u32;
    for f in t.faces() {
        let hs = rings.face(f);
        let k = hs.len();
        let base = rings.start(f);
        let fp = (nv + ne + f.index()) as u32;
        let e = |i: usize| nv as u32 + t.edge(hs[i % k]).get();
        // The neighbour across side i: (where its ring starts, the side's slot there, its
        // side count), or none.
        let across = |i: usize| {
            let o = t.twin(hs[i % k]);
            t.face(o)
                .map(|g| (rings.start(g), rings.slot(o), rings.face(g).len()))
        };
        for (i, &h) in hs.iter().enumerate() {
            let v = t.from_vertex(h).get();
            indices.extend([v, e(i), fp, e(i + k - 1)]);
            twin.push(across(i).map_or(NONE, |(gb, j, kg)| quad(gb + (j + 1) % kg, 3)));
            twin.push(quad(base + (i + 1) % k, 2));
            twin.push(quad(base + (i + k - 1) % k, 1));
            twin.push(across(i + k - 1).map_or(NONE, |(gb, j, _)| quad(gb + j, 0)));
        }
    }
    let face_starts: Vec<u32> = (0..=corners as u32).map(|i| 4 * i).collect();
    let mut c = Connectivity::from_corners(FaceCorners {
        positions: &positions,
        indices: &indices,
        face_starts: &face_starts,
        twin: &twin,
    });
    // The attributes, by the same layout: per old face, per corner i
    // `(v_i, e_i, face point, e_{i−1})`.
    c.attributes = subdivided_attributes(
        t,
        &c,
        4,
        |f| rings.face(f).len(),
        |uv, out| {
            for f in t.faces() {
                let hs = rings.face(f);
                let k = hs.len();
                let at = |i: usize| uv[hs[(i + k - 1) % k].index()];
                let mid = |i: usize| (at(i) + at(i + 1)) * 0.5;
                let centre = (0..k).map(at).sum::<Vec2>() / k as f32;
                for i in 0..k {
                    out.extend([at(i), mid(i), centre, mid(i + k - 1)]);
                }
            }
        },
    );
    c
}

/// Faces of `mesh` that are not triangles (the first few), for refusals that offer to
/// triangulate.
pub fn first_non_triangle(world: &World, mesh: MeshId) -> Option<FaceId> {
    let m = crate::mesh::MeshRef::new(world);
    crate::mesh::MeshMembers::collect(world, mesh)
        .faces
        .into_iter()
        .find(|&f| m.face_degree(f) != 3)
}
