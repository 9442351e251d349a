//! What every edit returns and runs with: what it changed and what to redraw ([`Applied`],
//! [`Redraw`]), what it may change, for the undo record ([`Reach`]), and the progress callback
//! it reports to ([`EditContext`]). Apart from the operations' trait, so that a step of a
//! stepped run ([`super::stepping`]) can say what it redraws without naming the trait.

use bevy::prelude::World;

use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::mesh::{InMesh, MeshRef};

/// What to redraw after an edit.
#[derive(Clone, Debug, PartialEq)]
pub enum Redraw {
    /// The faces around these vertices (as they are now), and these faces (from before the
    /// edit; they may be gone).
    Near {
        /// Faces from before the edit.
        faces: Vec<FaceId>,
        /// Vertices around which the faces changed.
        vertices: Vec<VertexId>,
    },
    /// The whole mesh.
    Whole,
    /// Only vertex positions changed (a move of most of the mesh): every face keeps its
    /// corners, so a render copy keeps its triangles and refreshes its positions.
    Positions,
}

/// What an edit may change, so that an undo record can capture it first.
#[derive(Clone, Debug, PartialEq)]
pub enum Reach {
    /// The neighbourhood of these vertices of this mesh.
    Local(MeshId, Vec<VertexId>),
    /// These vertices of this mesh, and nothing else: their positions (and attributes) change,
    /// the connectivity does not (a move, a fairing).
    Vertices(MeshId, Vec<VertexId>),
    /// Any element of this mesh.
    Whole(MeshId),
}

impl Reach {
    /// The neighbourhood of `seeds` in their mesh (`None` when there are none, or the first is
    /// gone).
    pub fn local(world: &World, seeds: Vec<VertexId>) -> Option<Reach> {
        let mesh = world.get::<InMesh>(seeds.first()?.0)?.0;
        Some(Reach::Local(mesh, seeds))
    }

    /// `vertices` alone, in their mesh (`None` when there are none or one is gone): a move, a
    /// fairing.
    pub fn vertices(world: &World, vertices: Vec<VertexId>) -> Option<Reach> {
        let m = MeshRef::new(world);
        vertices
            .iter()
            .try_for_each(|&v| m.try_vertex(v).map(|_| ()))?;
        let mesh = world.get::<InMesh>(vertices.first()?.0)?.0;
        Some(Reach::Vertices(mesh, vertices))
    }
}

impl Redraw {
    /// The faces around `vertices` as they are now, and `faces` from before the edit.
    pub fn near(world: &World, faces: Vec<FaceId>, vertices: Vec<VertexId>) -> Redraw {
        Redraw::Near {
            faces: [MeshRef::new(world).faces_around(&vertices), faces].concat(),
            vertices,
        }
    }
}

/// An edit carried out.
#[derive(Clone, Debug, PartialEq)]
pub struct Applied {
    /// One line for the status bar, the log and the command line's report.
    pub summary: String,
    /// What changed, for a renderer.
    pub redraw: Redraw,
    /// What the edit made, for the selection to move to (`None`: keep the selection, if its
    /// element survived).
    pub made: Option<ElementId>,
}

impl Applied {
    /// A local edit's outcome: redraw the faces that were around its `seeds` (`before`) and
    /// are around them now and around what it `made` (its corners), which the selection moves
    /// to.
    pub fn around(
        world: &World,
        before: Vec<FaceId>,
        mut seeds: Vec<VertexId>,
        summary: String,
        made: Option<ElementId>,
    ) -> Self {
        if let Some(x) = made {
            seeds.extend(MeshRef::new(world).corners(x));
        }
        Self {
            summary,
            redraw: Redraw::near(world, before, seeds),
            made,
        }
    }

    /// A whole-mesh edit's outcome: redraw everything, keep the selection.
    pub fn whole(summary: String) -> Self {
        Self {
            summary,
            redraw: Redraw::Whole,
            made: None,
        }
    }
}

/// What an edit runs with beside the world: the progress callback that long edits report to.
/// (The simplification history is on the mesh entity:
/// [`crate::ops::simplification_history`].)
pub struct EditContext<'a> {
    /// Called with the fraction done (0–1) now and then by long edits; returning `false` asks
    /// the edit to stop early where it can (the mesh is then valid, the edit partly done).
    pub progress: &'a mut dyn FnMut(f32) -> bool,
}
