//! Mesh statistics: counts, Euler characteristic, genus, boundary loops, components, quality.
//!
//! For a mesh with `C` connected components and `B` boundary loops, each component an
//! orientable surface of genus `g_i` with `b_i` boundary loops, `χ = V − E + F =
//! Σ (2 − 2 g_i − b_i)`, so the total genus is `g = (2C − B − χ) / 2`. Every mesh Pappus holds is
//! oriented (the builder orients it), so `g` is a whole number.

use bevy::math::Vec3;
use bevy::prelude::World;
use std::collections::BTreeMap;

use super::ids::MeshId;
use super::tables::{Connectivity, extract};

/// Figures describing one mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshStats {
    /// Vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// Halfedges (twice the edges).
    pub halfedges: usize,
    /// Boundary loops (holes and outer borders).
    pub boundary_loops: usize,
    /// Connected components.
    pub components: usize,
    /// Euler characteristic `V − E + F`.
    pub euler_characteristic: i64,
    /// Total genus `(2C − B − χ) / 2` (see the module doc).
    pub genus: i64,
    /// Whether the mesh has no boundary.
    pub closed: bool,
    /// Number of faces by number of sides.
    pub face_sizes: BTreeMap<usize, usize>,
    /// The smallest corner angle of any face, in degrees.
    pub min_angle_deg: f64,
    /// Percentage of triangles whose smallest angle is below 30°.
    pub pct_min_angle_below_30: f64,
    /// Length of the bounding-box diagonal.
    pub bbox_diag: f64,
    /// Mean edge length.
    pub mean_edge_length: f64,
}

/// Computes the statistics of `mesh`: [`stats_of_tables`] of its tables (read in bulk, then
/// walked as arrays: faster than entity by entity). Assumes a mesh that passes
/// [`super::validate()`].
pub fn mesh_stats(world: &World, mesh: MeshId) -> MeshStats {
    stats_of_tables(&extract(world, mesh).tables)
}

/// The statistics of a mesh in table form (see [`super::tables`]); computable away from the
/// world, as the editor does for a large mesh. Assumes consistent tables.
pub fn stats_of_tables(t: &Connectivity) -> MeshStats {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &p in &t.positions {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let bbox_diag = if t.positions.is_empty() {
        0.0
    } else {
        f64::from((hi - lo).length())
    };

    let mut face_sizes = BTreeMap::new();
    let mut min_angle = f64::INFINITY;
    let (mut triangles, mut sharp) = (0usize, 0usize);
    let mut corners = Vec::new();
    for f in t.faces() {
        corners.clear();
        corners.extend(t.face_halfedges(f).map(|h| t.position(t.to_vertex(h))));
        *face_sizes.entry(corners.len()).or_insert(0) += 1;
        let face_min = min_corner_angle_deg(&corners);
        min_angle = min_angle.min(face_min);
        if corners.len() == 3 {
            triangles += 1;
            sharp += usize::from(face_min < THIN_ANGLE_DEG);
        }
    }

    let boundary_loops = count_boundary_loops(t);
    let components = count_components(t);
    let total_length: f64 = t.edges().map(|e| f64::from(t.edge_length(e))).sum();
    let (v, e, f) = (
        t.vertex_count() as i64,
        t.edge_count() as i64,
        t.face_count() as i64,
    );
    let euler_characteristic = v - e + f;
    MeshStats {
        vertices: t.vertex_count(),
        edges: t.edge_count(),
        faces: t.face_count(),
        halfedges: t.halfedge_count(),
        boundary_loops,
        components,
        euler_characteristic,
        genus: (2 * components as i64 - boundary_loops as i64 - euler_characteristic) / 2,
        closed: boundary_loops == 0,
        face_sizes,
        min_angle_deg: if min_angle.is_finite() {
            min_angle
        } else {
            0.0
        },
        pct_min_angle_below_30: if triangles == 0 {
            0.0
        } else {
            100.0 * sharp as f64 / triangles as f64
        },
        bbox_diag,
        mean_edge_length: if e == 0 { 0.0 } else { total_length / e as f64 },
    }
}

/// Below this corner angle (degrees) a triangle counts as thin: the share that
/// [`MeshStats::pct_min_angle_below_30`] reports, and the quality measure of the remeshing
/// benchmarks.
pub const THIN_ANGLE_DEG: f64 = 30.0;

/// The smallest interior angle at any corner of a polygon, in degrees (0 for a degenerate
/// corner with a zero-length side).
pub fn min_corner_angle_deg(corners: &[Vec3]) -> f64 {
    let k = corners.len();
    let mut min = f64::INFINITY;
    for i in 0..k {
        let p = corners[i];
        let a = corners[(i + k - 1) % k] - p;
        let b = corners[(i + 1) % k] - p;
        let angle = if a.length_squared() == 0.0 || b.length_squared() == 0.0 {
            0.0
        } else {
            f64::from(a.angle_between(b)).to_degrees()
        };
        min = min.min(angle);
    }
    min
}

fn count_boundary_loops(t: &Connectivity) -> usize {
    let mut visited = vec![false; t.halfedge_count()];
    let mut loops = 0;
    for h in t.halfedges() {
        if !t.is_boundary(h) || visited[h.index()] {
            continue;
        }
        loops += 1;
        let mut b = h;
        // A consistent loop returns to its start; the count bounds a broken one.
        for _ in 0..t.halfedge_count() {
            visited[b.index()] = true;
            b = t.next(b);
            if b == h {
                break;
            }
        }
    }
    loops
}

fn count_components(t: &Connectivity) -> usize {
    component_of_vertices(t)
        .iter()
        .max()
        .map_or(0, |&c| c as usize + 1)
}

/// Each vertex's connected component, numbered from 0 in the order of their lowest vertex.
pub(crate) fn component_of_vertices(t: &Connectivity) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..t.vertex_count() as u32).collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    for e in t.edges() {
        let h = t.edge_halfedge(e);
        let (a, b) = (
            root(&mut parent, t.from_vertex(h).get()),
            root(&mut parent, t.to_vertex(h).get()),
        );
        if a != b {
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    let mut number = vec![u32::MAX; parent.len()];
    let mut next = 0;
    (0..parent.len() as u32)
        .map(|v| {
            let r = root(&mut parent, v) as usize;
            if number[r] == u32::MAX {
                number[r] = next;
                next += 1;
            }
            number[r]
        })
        .collect()
}
