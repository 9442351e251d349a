//! Mesh statistics: counts, Euler characteristic, genus, boundary loops, components, quality.
//!
//! For a mesh with `C` connected components and `B` boundary loops, each component an
//! orientable surface of genus `g_i` with `b_i` boundary loops, `χ = V − E + F =
//! Σ (2 − 2 g_i − b_i)`, so the total genus is `g = (2C − B − χ) / 2`. Every mesh Pappus holds is
//! oriented (the builder orients it), so `g` is a whole number.

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;
use std::collections::BTreeMap;

use super::ids::MeshId;
use super::members::MeshMembers;
use super::topology::MeshRef;

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

/// Computes the statistics of `mesh`. Assumes a mesh that passes [`super::validate()`].
pub fn mesh_stats(world: &World, mesh: MeshId) -> MeshStats {
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);

    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &v in &members.vertices {
        let p = m.position(v);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let bbox_diag = if members.vertices.is_empty() {
        0.0
    } else {
        f64::from((hi - lo).length())
    };

    let mut face_sizes = BTreeMap::new();
    let mut min_angle = f64::INFINITY;
    let (mut triangles, mut sharp) = (0usize, 0usize);
    let mut corners = Vec::new();
    for &f in &members.faces {
        corners.clear();
        corners.extend(m.face_vertices(f).map(|v| m.position(v)));
        *face_sizes.entry(corners.len()).or_insert(0) += 1;
        let face_min = min_corner_angle_deg(&corners);
        min_angle = min_angle.min(face_min);
        if corners.len() == 3 {
            triangles += 1;
            sharp += usize::from(face_min < THIN_ANGLE_DEG);
        }
    }

    let boundary_loops = count_boundary_loops(&m, &members);
    let components = count_components(&m, &members);
    let total_length: f64 = members
        .edges
        .iter()
        .map(|&e| {
            let (a, b) = m.edge_vertices(e);
            f64::from(m.position(a).distance(m.position(b)))
        })
        .sum();
    let (v, e, f) = (
        members.vertices.len() as i64,
        members.edges.len() as i64,
        members.faces.len() as i64,
    );
    let euler_characteristic = v - e + f;
    MeshStats {
        vertices: members.vertices.len(),
        edges: members.edges.len(),
        faces: members.faces.len(),
        halfedges: members.halfedges.len(),
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

fn count_boundary_loops(m: &MeshRef<'_>, members: &MeshMembers) -> usize {
    let mut visited = EntityHashSet::default();
    let mut loops = 0;
    for &h in &members.halfedges {
        if !m.is_boundary(h) || visited.contains(&h.0) {
            continue;
        }
        loops += 1;
        for b in m.loop_from(h) {
            visited.insert(b.0);
        }
    }
    loops
}

fn count_components(m: &MeshRef<'_>, members: &MeshMembers) -> usize {
    let index = members.vertex_rows();
    let mut parent: Vec<u32> = (0..members.vertices.len() as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    let mut components = members.vertices.len();
    for &e in &members.edges {
        let (a, b) = m.edge_vertices(e);
        let (ra, rb) = (
            find(&mut parent, index[&a.0]),
            find(&mut parent, index[&b.0]),
        );
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
            components -= 1;
        }
    }
    components
}
