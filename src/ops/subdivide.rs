//! Loop and Catmull–Clark subdivision, computed in bulk on index tables.
//!
//! Both read the mesh once ([`crate::mesh::arrays::extract`]), build the refined connectivity
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

use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::arrays::extract;
use crate::mesh::build::{RowCounts, reserve_rows_while, write_links};
use crate::mesh::connectivity::Connectivity;
use crate::mesh::ids::{ElementId, FaceId, MeshId};
use crate::mesh::repair::{NONE, RepairedFaces};

use super::Refusal;

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

/// The faces of a table mesh as rings of halfedges, each starting at the face's halfedge.
struct FaceRings {
    starts: Vec<u32>,
    ring: Vec<u32>,
    /// Each interior halfedge's position in its face's ring.
    slot: Vec<u32>,
}

impl FaceRings {
    fn new(t: &Connectivity) -> Self {
        let mut starts = Vec::with_capacity(t.face_count() + 1);
        let mut ring = Vec::with_capacity(t.halfedge_count());
        let mut slot = vec![NONE; t.halfedge_count()];
        starts.push(0);
        for &first in &t.face_halfedge {
            let mut h = first;
            let mut i = 0;
            loop {
                slot[h as usize] = i;
                ring.push(h);
                i += 1;
                h = t.next[h as usize];
                if h == first {
                    break;
                }
            }
            starts.push(ring.len() as u32);
        }
        Self { starts, ring, slot }
    }

    fn face(&self, f: usize) -> &[u32] {
        &self.ring[self.starts[f] as usize..self.starts[f + 1] as usize]
    }
}

fn from_vertex(t: &Connectivity, h: u32) -> u32 {
    t.to_vertex[t.twin[h as usize] as usize]
}

/// The positions at the start and the tip of halfedge `h`.
fn ends(t: &Connectivity, h: u32) -> (Vec3, Vec3) {
    (
        t.positions[from_vertex(t, h) as usize],
        t.positions[t.to_vertex[h as usize] as usize],
    )
}

fn is_boundary_edge(t: &Connectivity, h: u32) -> bool {
    t.face[h as usize] == NONE || t.face[t.twin[h as usize] as usize] == NONE
}

/// Boundary rule shared by both schemes: `3/4 P + 1/8 (a + b)` with the two boundary
/// neighbours (the vertex's halfedge is its outgoing boundary halfedge).
fn boundary_vertex(t: &Connectivity, v: u32) -> Vec3 {
    let h = t.vertex_halfedge[v as usize];
    let a = t.positions[t.to_vertex[h as usize] as usize];
    let b = t.positions[from_vertex(t, t.prev[h as usize]) as usize];
    0.75 * t.positions[v as usize] + 0.125 * (a + b)
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
    let scheme = Scheme {
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
    };
    subdivide(world, mesh, levels, scheme, |t, members| {
        match t.first_non_triangle() {
            Some(f) => Err(Refusal::NotTriangle(ElementId::Face(members.faces[f]))),
            None => Ok(()),
        }
    })
}

/// Catmull–Clark-subdivides any polygon mesh `levels` times. Never refuses.
pub fn catmull_clark(
    world: &mut World,
    mesh: MeshId,
    levels: u32,
) -> Result<SubdivisionSummary, Refusal> {
    let scheme = Scheme {
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
    };
    subdivide(world, mesh, levels, scheme, |_, _| Ok(()))
}

/// A subdivision scheme: one level on tables, and the row counts a level makes from the
/// counts before it and the number of face corners, known before the tables are computed.
struct Scheme {
    step: fn(&Connectivity) -> Connectivity,
    counts: fn(RowCounts, usize) -> RowCounts,
}

/// Runs `levels` levels of `scheme` after `check` passed. The tables are computed on a second
/// thread while this one makes the result's entities exist (the two largest costs, overlapped),
/// and the links are written once both are done.
fn subdivide(
    world: &mut World,
    mesh: MeshId,
    levels: u32,
    scheme: Scheme,
    check: impl Fn(&Connectivity, &crate::mesh::MeshMembers) -> Result<(), Refusal>,
) -> Result<SubdivisionSummary, Refusal> {
    if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
        return Err(Refusal::Stale(ElementId::Mesh(mesh)));
    }
    let extracted = extract(world, mesh);
    check(&extracted.tables, &extracted.members)?;
    if levels == 0 {
        return Ok(SubdivisionSummary {
            levels,
            vertices: extracted.tables.vertex_count(),
            faces: extracted.tables.face_count(),
        });
    }
    let mut counts = RowCounts::of(&extracted.tables);
    let mut corners = extracted.tables.face.iter().filter(|&&f| f != NONE).count();
    for _ in 0..levels {
        counts = (scheme.counts)(counts, corners);
        corners = 4 * counts.faces;
        if counts.halfedges >= NONE as usize {
            return Err(Refusal::TooLarge(counts.halfedges));
        }
    }
    let tables = &extracted.tables;
    let (result, rows) =
        reserve_rows_while(world, counts, mesh, Some(&extracted.members), move || {
            let mut t = (scheme.step)(tables);
            for _ in 1..levels {
                t = (scheme.step)(&t);
            }
            t
        });
    write_links(world, &result, &rows);
    Ok(SubdivisionSummary {
        levels,
        vertices: result.vertex_count(),
        faces: result.face_count(),
    })
}

/// One level of Loop subdivision on tables; `Err(face)` if a face is not a triangle.
pub fn loop_tables(t: &Connectivity) -> Result<Connectivity, usize> {
    if let Some(f) = t.first_non_triangle() {
        return Err(f);
    }
    let rings = FaceRings::new(t);
    let (nv, ne, nf) = (t.vertex_count(), t.edge_count(), t.face_count());
    let mut positions = Vec::with_capacity(nv + ne);
    for v in 0..nv as u32 {
        let p = t.positions[v as usize];
        let h0 = t.vertex_halfedge[v as usize];
        let n = t.outgoing(v).count();
        positions.push(if t.face[h0 as usize] == NONE {
            if n <= 2 { p } else { boundary_vertex(t, v) }
        } else {
            let u = if n == 3 {
                3.0 / 16.0
            } else {
                3.0 / (8.0 * n as f32)
            };
            let sum: Vec3 = t
                .outgoing(v)
                .map(|h| t.positions[t.to_vertex[h as usize] as usize])
                .sum();
            (1.0 - n as f32 * u) * p + u * sum
        });
    }
    for e in 0..ne {
        let h = t.edge_halfedge[e];
        let (a, b) = ends(t, h);
        positions.push(if is_boundary_edge(t, h) {
            (a + b) * 0.5
        } else {
            let c = t.positions[t.to_vertex[t.next[h as usize] as usize] as usize];
            let twin = t.twin[h as usize];
            let d = t.positions[t.to_vertex[t.next[twin as usize] as usize] as usize];
            0.375 * (a + b) + 0.125 * (c + d)
        });
    }

    let mut indices = Vec::with_capacity(12 * nf);
    let mut twin = Vec::with_capacity(12 * nf);
    let corner = |face: usize, k: usize| (3 * face + k) as u32;
    for f in 0..nf {
        let hs = rings.face(f);
        let v = |i: usize| from_vertex(t, hs[i % 3]);
        let m = |i: usize| nv as u32 + t.edge[hs[i % 3] as usize];
        // The neighbour across side i: (its face, the side's slot there), or none.
        let across = |i: usize| {
            let o = t.twin[hs[i % 3] as usize];
            let g = t.face[o as usize];
            (g != NONE).then(|| (g as usize, rings.slot[o as usize] as usize))
        };
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
    let face_starts = (0..=4 * nf as u32).map(|i| 3 * i).collect();
    Ok(Connectivity::from_repaired(&RepairedFaces {
        positions,
        indices,
        face_starts,
        twin,
        input_vertex: Vec::new(),
    }))
}

/// One level of Catmull–Clark subdivision on tables.
pub fn catmull_clark_tables(t: &Connectivity) -> Connectivity {
    let rings = FaceRings::new(t);
    let (nv, ne, nf) = (t.vertex_count(), t.edge_count(), t.face_count());
    let face_points: Vec<Vec3> = (0..nf)
        .map(|f| {
            let hs = rings.face(f);
            hs.iter()
                .map(|&h| t.positions[t.to_vertex[h as usize] as usize])
                .sum::<Vec3>()
                / hs.len() as f32
        })
        .collect();
    let mut positions = Vec::with_capacity(nv + ne + nf);
    for v in 0..nv as u32 {
        let p = t.positions[v as usize];
        let h0 = t.vertex_halfedge[v as usize];
        if t.face[h0 as usize] == NONE {
            let faces = t
                .outgoing(v)
                .filter(|&h| t.face[h as usize] != NONE)
                .count();
            positions.push(if faces <= 1 { p } else { boundary_vertex(t, v) });
            continue;
        }
        let (mut q, mut r, mut n) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
        for h in t.outgoing(v) {
            q += face_points[t.face[h as usize] as usize];
            r += (p + t.positions[t.to_vertex[h as usize] as usize]) * 0.5;
            n += 1.0;
        }
        positions.push((q / n + 2.0 * r / n + (n - 3.0) * p) / n);
    }
    for e in 0..ne {
        let h = t.edge_halfedge[e];
        let (a, b) = ends(t, h);
        positions.push(if is_boundary_edge(t, h) {
            (a + b) * 0.5
        } else {
            let f1 = face_points[t.face[h as usize] as usize];
            let f2 = face_points[t.face[t.twin[h as usize] as usize] as usize];
            (a + b + f1 + f2) * 0.25
        });
    }
    positions.extend_from_slice(&face_points);

    let corners = rings.ring.len();
    let mut indices = Vec::with_capacity(4 * corners);
    let mut twin = Vec::with_capacity(4 * corners);
    let quad = |r: usize, k: usize| (4 * r + k) as u32;
    for f in 0..nf {
        let hs = rings.face(f);
        let k = hs.len();
        let base = rings.starts[f] as usize;
        let fp = (nv + ne + f) as u32;
        let e = |i: usize| nv as u32 + t.edge[hs[i % k] as usize];
        let across = |i: usize| {
            let o = t.twin[hs[i % k] as usize];
            let g = t.face[o as usize];
            (g != NONE).then(|| {
                let g = g as usize;
                let kg = (rings.starts[g + 1] - rings.starts[g]) as usize;
                (
                    rings.starts[g] as usize,
                    rings.slot[o as usize] as usize,
                    kg,
                )
            })
        };
        for (i, &h) in hs.iter().enumerate() {
            let v = from_vertex(t, h);
            indices.extend([v, e(i), fp, e(i + k - 1)]);
            twin.push(across(i).map_or(NONE, |(gb, j, kg)| quad(gb + (j + 1) % kg, 3)));
            twin.push(quad(base + (i + 1) % k, 2));
            twin.push(quad(base + (i + k - 1) % k, 1));
            twin.push(across(i + k - 1).map_or(NONE, |(gb, j, _)| quad(gb + j, 0)));
        }
    }
    let face_starts = (0..=corners as u32).map(|i| 4 * i).collect();
    Connectivity::from_repaired(&RepairedFaces {
        positions,
        indices,
        face_starts,
        twin,
        input_vertex: Vec::new(),
    })
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
