//! What one pass of a stepped remesh ([`RemeshRun`](super::RemeshRun)) did: which pass it
//! was, in which iteration, how many operations it made and which elements it touched.
//!
//! The passes are those of an iteration of Botsch & Kobbelt 2004 (split long, collapse short,
//! flip towards valence 6, tangential relaxation, projection onto the input), and the one
//! finishing pass after the last iteration (see the [`remesh`](super) module doc). The touched
//! elements are for highlighting: every id is alive and in the mesh right after its pass, as
//! the pass left it (a later pass may remove it).

use crate::mesh::ids::{EdgeId, VertexId};

/// One pass of the remesh loop, in the order a run makes them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pass {
    /// Split every edge longer than 4/3 L at its midpoint.
    Split,
    /// Collapse the edges shorter than 4/5 L, shortest first.
    Collapse,
    /// Flip edges towards valence 6 (4 on the boundary).
    Flip,
    /// Tangential relaxation: the smoothing steps, each 1/5 of the way to the centre of mass
    /// of the vertex's triangles within the tangent plane.
    Relax,
    /// Project the relaxed vertices back onto the input surface.
    Project,
    /// After the last iteration: put back the tips and grooves the remesh cut off, clean up
    /// the thin triangles, then fit the vertices to the input and pull the corners nearest
    /// the input's farthest spots towards them.
    Finish,
}

impl Pass {
    /// The passes of one iteration, in order ([`Pass::Finish`] follows the last iteration).
    pub const ITERATION: [Pass; 5] = [
        Pass::Split,
        Pass::Collapse,
        Pass::Flip,
        Pass::Relax,
        Pass::Project,
    ];

    /// The pass's name for people: `"split"`, `"collapse"`, `"flip"`, `"relax"`, `"project"`,
    /// `"finish"`.
    pub fn name(self) -> &'static str {
        match self {
            Pass::Split => "split",
            Pass::Collapse => "collapse",
            Pass::Flip => "flip",
            Pass::Relax => "relax",
            Pass::Project => "project",
            Pass::Finish => "finish",
        }
    }
}

/// The elements a pass made or changed, as they are after it; each id was alive and in the
/// mesh when the pass ended.
///
/// - [`Pass::Split`]: the new vertices, and the edges around them (the halves of the split
///   edges and the cuts across their faces) as the split left them.
/// - [`Pass::Collapse`]: the surviving vertex of each collapse, once, less those a later
///   collapse of the pass removed.
/// - [`Pass::Flip`]: the flipped edges.
/// - [`Pass::Relax`], [`Pass::Project`]: the vertices that moved.
/// - [`Pass::Finish`]: the vertices it added (tips and grooves put back) and the edges it
///   flipped, each once (the corners of thin triangles it moved, the vertices the fit to
///   the input moved and the corners pulled towards the far spots are not listed).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Touched {
    /// Vertices made or changed.
    pub vertices: Vec<VertexId>,
    /// Edges made or changed.
    pub edges: Vec<EdgeId>,
}

/// What one pass of a run did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PassReport {
    /// Which pass.
    pub pass: Pass,
    /// The iteration it belongs to, from 0; [`Pass::Finish`] reports the number of iterations
    /// (it comes after the last one).
    pub iteration: u32,
    /// The operations it made: splits, collapses or flips; for [`Pass::Relax`] and
    /// [`Pass::Project`] the vertices that moved; for [`Pass::Finish`] its splits plus its flips
    /// (a flip counted each time it was made). The split, collapse, flip and finish counts of a
    /// run add up to its [`RemeshSummary`](super::RemeshSummary)'s.
    pub count: usize,
    /// The elements it made or changed.
    pub touched: Touched,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_iteration_names_its_five_passes_in_order() {
        let names = Pass::ITERATION.map(Pass::name);
        assert_eq!(names, ["split", "collapse", "flip", "relax", "project"]);
        assert_eq!(Pass::Finish.name(), "finish");
    }
}
