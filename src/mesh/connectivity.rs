//! Halfedge connectivity as flat index tables: the step between repaired faces and entities.
//!
//! [`Connectivity`] holds exactly what the entity mesh will hold, with `u32` indices in place of
//! entities. Building it is pure index work (no ECS), so bulk operations that make a whole new
//! mesh (subdivision, the loader) fill these tables and spawn them in one pass
//! ([`super::build::spawn_connectivity`]) instead of editing entities one by one.
//!
//! Layout: halfedges `0..interior` are the face corners in face order (corner `c` runs from
//! `indices[c]` to the next corner's vertex); boundary halfedges follow. Every boundary vertex's
//! outgoing halfedge is its boundary halfedge. Each edge's halfedge is an interior one.

use bevy::math::Vec3;

use super::repair::{NONE, RepairedFaces};
use super::topology::MAX_LOOP;

/// Halfedge tables. `NONE` ([`super::repair::NONE`]) marks a boundary halfedge's face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Connectivity {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Each vertex's outgoing halfedge (the boundary one on the boundary).
    pub vertex_halfedge: Vec<u32>,
    /// Each halfedge's twin.
    pub twin: Vec<u32>,
    /// Each halfedge's next.
    pub next: Vec<u32>,
    /// Each halfedge's prev.
    pub prev: Vec<u32>,
    /// Each halfedge's tip vertex.
    pub to_vertex: Vec<u32>,
    /// Each halfedge's edge.
    pub edge: Vec<u32>,
    /// Each halfedge's face, or `NONE` on the boundary.
    pub face: Vec<u32>,
    /// Each edge's halfedge.
    pub edge_halfedge: Vec<u32>,
    /// Each face's first halfedge.
    pub face_halfedge: Vec<u32>,
}

impl Connectivity {
    /// Builds the tables from repaired faces: boundary halfedges are added and linked into
    /// loops, edges numbered.
    pub fn from_repaired(faces: &RepairedFaces) -> Self {
        let nv = faces.positions.len();
        let nf = faces.face_count();
        let interior = faces.indices.len();
        let boundary = faces.twin.iter().filter(|&&t| t == NONE).count();
        let nh = interior + boundary;

        let mut c = Connectivity {
            positions: faces.positions.clone(),
            vertex_halfedge: vec![NONE; nv],
            twin: Vec::with_capacity(nh),
            next: Vec::with_capacity(nh),
            prev: Vec::with_capacity(nh),
            to_vertex: Vec::with_capacity(nh),
            edge: vec![NONE; nh],
            face: Vec::with_capacity(nh),
            edge_halfedge: Vec::with_capacity(nh / 2),
            face_halfedge: Vec::with_capacity(nf),
        };

        for f in 0..nf {
            let (s, e) = (
                faces.face_starts[f] as usize,
                faces.face_starts[f + 1] as usize,
            );
            c.face_halfedge.push(s as u32);
            for h in s..e {
                let n = if h + 1 == e { s } else { h + 1 };
                let p = if h == s { e - 1 } else { h - 1 };
                c.next.push(n as u32);
                c.prev.push(p as u32);
                c.to_vertex.push(faces.indices[n]);
                c.face.push(f as u32);
                c.vertex_halfedge[faces.indices[h] as usize] = h as u32;
            }
        }
        c.twin.extend_from_slice(&faces.twin);

        // Boundary halfedges: the twin of interior corner h runs from to(h) back to from(h).
        let mut boundary_out = vec![NONE; nv];
        for h in 0..interior {
            if faces.twin[h] != NONE {
                continue;
            }
            let b = c.twin.len() as u32;
            c.twin[h] = b;
            c.twin.push(h as u32);
            c.to_vertex.push(faces.indices[h]);
            c.face.push(NONE);
            c.next.push(NONE);
            c.prev.push(NONE);
            let from = c.to_vertex[h];
            boundary_out[from as usize] = b;
            c.vertex_halfedge[from as usize] = b;
        }
        for b in interior..nh {
            let n = boundary_out[c.to_vertex[b] as usize];
            c.next[b] = n;
            c.prev[n as usize] = b as u32;
        }

        for h in 0..nh {
            if c.edge[h] == NONE {
                let e = c.edge_halfedge.len() as u32;
                c.edge[h] = e;
                c.edge[c.twin[h] as usize] = e;
                c.edge_halfedge.push(h as u32);
            }
        }
        c
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of halfedges (interior and boundary).
    pub fn halfedge_count(&self) -> usize {
        self.twin.len()
    }

    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.edge_halfedge.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_halfedge.len()
    }

    /// The first face that is not a triangle, if any (three `next` steps from its halfedge do
    /// not come back to it).
    pub fn first_non_triangle(&self) -> Option<usize> {
        let next = |h: u32| self.next[h as usize];
        self.face_halfedge
            .iter()
            .position(|&h| next(h) == h || next(next(next(h))) != h)
    }

    /// The halfedges of face `f` in order from its first: its three sides when it is a
    /// triangle (see [`Connectivity::first_non_triangle`]), the first three otherwise.
    #[inline]
    pub fn triangle(&self, f: usize) -> [u32; 3] {
        let first = self.face_halfedge[f];
        let second = self.next[first as usize];
        [first, second, self.next[second as usize]]
    }

    /// The next outgoing halfedge of `h`'s start vertex, counter-clockwise: `twin(prev(h))`.
    #[inline]
    pub fn ccw_rotated(&self, h: u32) -> u32 {
        self.twin[self.prev[h as usize] as usize]
    }

    /// The outgoing halfedges of `v`, counter-clockwise from its halfedge (the boundary one
    /// first on the boundary). Stops after [`MAX_LOOP`] steps even if the links do not close,
    /// like every circulator.
    pub fn outgoing(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.vertex_halfedge[v as usize];
        let mut h = Some(first);
        std::iter::from_fn(move || {
            let current = h?;
            let next = self.ccw_rotated(current);
            h = (next != first).then_some(next);
            Some(current)
        })
        .take(MAX_LOOP)
    }

    /// Makes room for `more` rows of each kind beyond the current ones (tables that grow
    /// row by row, as the bulk refine's, then never reallocate).
    pub fn reserve(&mut self, more: super::build::RowCounts) {
        self.positions.reserve(more.vertices);
        self.vertex_halfedge.reserve(more.vertices);
        for table in [
            &mut self.twin,
            &mut self.next,
            &mut self.prev,
            &mut self.to_vertex,
            &mut self.edge,
            &mut self.face,
        ] {
            table.reserve(more.halfedges);
        }
        self.edge_halfedge.reserve(more.edges);
        self.face_halfedge.reserve(more.faces);
    }
}
