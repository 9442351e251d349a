//! Typed row indices, and row counts.
//!
//! A row is an element's index within its kind in the tables ([`super::Connectivity`]). The
//! tables store rows as plain `u32`; the four newtypes here name which kind a row is of, so that
//! code passing a face row where a vertex row is expected does not compile. Each is
//! `#[repr(transparent)]` over `u32`, and every conversion is `#[inline]`: indexing a table
//! through one compiles to the same code as through the bare integer.
//!
//! [`NONE`] is the one "no row" value, for the raw tables and (as each type's `NONE`) for the
//! typed rows. [`RowCounts`] is how many rows of each kind a set of tables has.

use crate::mesh::members::MeshMembers;

/// Marks "no row" in the index tables: a boundary halfedge's face, a corner without a twin, a
/// dropped vertex. No table has this many rows.
pub const NONE: u32 = u32::MAX;

macro_rules! row_type {
    ($(#[$doc:meta])* $name:ident, $what:literal) => {
        $(#[$doc])*
        #[repr(transparent)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(u32);

        impl $name {
            #[doc = concat!("No ", $what, " ([`NONE`]).")]
            pub const NONE: Self = Self(NONE);

            #[doc = concat!("The ", $what, " in row `row`.")]
            #[inline]
            pub const fn new(row: u32) -> Self {
                Self(row)
            }

            /// The row as stored in the tables.
            #[inline]
            pub const fn get(self) -> u32 {
                self.0
            }

            /// The row as an index into a table of this kind.
            #[inline]
            pub const fn index(self) -> usize {
                self.0 as usize
            }

            /// Whether this is [`Self::NONE`].
            #[inline]
            pub const fn is_none(self) -> bool {
                self.0 == NONE
            }
        }
    };
}

row_type!(
    /// A vertex's row: its index in the vertex tables.
    VertexRow,
    "vertex"
);
row_type!(
    /// A halfedge's row: its index in the halfedge tables.
    HalfedgeRow,
    "halfedge"
);
row_type!(
    /// An edge's row: its index in the edge tables.
    EdgeRow,
    "edge"
);
row_type!(
    /// A face's row: its index in the face tables.
    FaceRow,
    "face"
);

/// How many rows of each kind a set of tables has: what the writer's `reserve_rows` needs to
/// know before the tables themselves exist.
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

    /// Rows of every kind together.
    pub fn total(self) -> usize {
        self.vertices + self.halfedges + self.edges + self.faces
    }

    /// The counts of `rows` (the entities behind a set of tables).
    pub fn of_rows(rows: &MeshMembers) -> Self {
        Self {
            vertices: rows.vertices.len(),
            halfedges: rows.halfedges.len(),
            edges: rows.edges.len(),
            faces: rows.faces.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_is_its_u32() {
        assert_eq!(size_of::<FaceRow>(), size_of::<u32>());
        assert_eq!(size_of::<Option<VertexRow>>(), size_of::<Option<u32>>());
        let h = HalfedgeRow::new(7);
        assert_eq!((h.get(), h.index()), (7, 7));
        assert!(HalfedgeRow::NONE.is_none() && !h.is_none());
        assert!(EdgeRow::new(1) < EdgeRow::new(2));
    }
}
