//! Loop and Catmull–Clark subdivision stepped two steps a level ([`SubdivideSteps`]).
//!
//! The run opens on the level's new edge (and face) points drawn over the mesh; a step adds
//! the old vertices at their moved positions; the next commits the level, the very level
//! [`Scheme::subdivide`] makes. Meanwhile the selected element's stencil — its old vertices
//! and their weights ([`super::stencil`]) — is drawn and tabled. Back takes back the preview
//! step of the level not yet committed; a committed level does not step back.

use bevy::prelude::World;

use super::Scheme;
use super::stencil::{NextLevelPoints, Stencil, next_level_points, stencil_of_element};
use super::stencil_shapes::{
    PointsShown, point_shapes, point_shapes_near, stencil_shapes, stencil_table,
};
use crate::mesh::Face;
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::members::of_kind;
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::IdsKept;
use crate::ops::operation::Redraw;
use crate::ops::operation::stepping::{Ended, GoesBack, MAX_DRAWN, Moved, StepShow, Steps};

/// Subdivision previewed and committed a level at a time (see the module doc).
pub struct SubdivideSteps {
    /// The scheme.
    pub scheme: Scheme,
    /// Levels asked for.
    pub levels: u32,
    /// Levels committed.
    pub done: u32,
    /// Whether the moved old vertices are shown (the level's second step) beside the new
    /// points (its first).
    pub moved_shown: bool,
    /// The next level's points, while it is previewed.
    pub points: Option<NextLevelPoints>,
    /// The mesh's vertex and face counts now (read at the start, then given by each level).
    counts: (usize, usize),
}

impl SubdivideSteps {
    /// A stepped subdivision of `mesh` by `scheme`, `levels` levels, previewing the first.
    ///
    /// # Errors
    /// The scheme's refusal (Loop on a face that is not a triangle); the mesh is untouched.
    pub fn start(
        world: &World,
        mesh: MeshId,
        scheme: Scheme,
        levels: u32,
    ) -> Result<Self, Refusal> {
        let points = next_level_points(world, mesh, scheme)?;
        let faces = of_kind::<Face, _>(world, mesh, |f| f).len();
        Ok(Self {
            scheme,
            levels,
            done: 0,
            moved_shown: false,
            counts: (points.vertex.len(), faces),
            points: Some(points),
        })
    }

    /// The stencil of `selected`'s point in the level being previewed (none once the last
    /// level is committed).
    pub fn stencil(&self, world: &World, selected: Option<ElementId>) -> Option<Stencil> {
        self.points.as_ref()?;
        stencil_of_element(&MeshRef::new(world), self.scheme, selected?)
    }
}

impl Steps for SubdivideSteps {
    fn at(&self) -> usize {
        2 * self.done as usize + usize::from(self.moved_shown)
    }

    fn made(&self) -> usize {
        2 * self.levels as usize
    }

    fn finished(&self) -> bool {
        self.done == self.levels
    }

    fn goes_back(&self) -> GoesBack {
        GoesBack::Steps
    }

    fn go_to(
        &mut self,
        world: &mut World,
        mesh: MeshId,
        k: usize,
        _: Option<ElementId>,
    ) -> Result<Moved, Refusal> {
        if k < 2 * self.done as usize {
            return Err(Refusal::BadParameter(
                "a committed level does not step back: Esc puts the mesh back as it was before \
                 the run"
                    .into(),
            ));
        }
        let mut moved = Moved::nothing();
        while self.at() < k && self.done < self.levels {
            if !self.moved_shown {
                self.moved_shown = true;
                continue;
            }
            let level = self.scheme.subdivide(world, mesh, 1)?;
            self.counts = (level.vertices, level.faces);
            self.done += 1;
            self.moved_shown = false;
            // Subdivision keeps vertex ids only.
            moved = Moved {
                redraw: Some(Redraw::Whole),
                ids: IdsKept::VerticesOnly,
                became: None,
            };
            self.points = match self.done < self.levels {
                true => Some(next_level_points(world, mesh, self.scheme)?),
                false => None,
            };
        }
        if k < self.at() {
            self.moved_shown = false;
        }
        Ok(moved)
    }

    fn describe(&self) -> String {
        let faces = self.counts.1;
        match (self.done == self.levels, self.moved_shown) {
            (true, _) => format!("{} level(s) committed, {faces} faces", self.done),
            (false, false) => format!(
                "level {}: the new points shown ({faces} faces now)",
                self.done + 1
            ),
            (false, true) => format!(
                "level {}: the old vertices moved as well; the next step commits it",
                self.done + 1
            ),
        }
    }

    fn show(&self, world: &World, selected: Option<ElementId>) -> StepShow {
        let mut show = StepShow::default();
        let stencil = self.stencil(world, selected);
        if let Some(points) = &self.points {
            let which = PointsShown {
                new_points: true,
                moved_vertices: self.moved_shown,
            };
            match stencil.as_ref().map(|s| s.position) {
                Some(near) => point_shapes_near(points, which, near, &mut show.shapes, MAX_DRAWN),
                None => point_shapes(points, which, &mut show.shapes, MAX_DRAWN),
            }
        }
        match &stencil {
            Some(stencil) => {
                stencil_shapes(&MeshRef::new(world), stencil, &mut show.shapes);
                show.table = Some(stencil_table(stencil));
            }
            None => {
                show.hint = Some("select a vertex, an edge or a face to see its stencil".into());
            }
        }
        show
    }

    fn finish(self: Box<Self>, _: &mut World, _: MeshId) -> Ended {
        if self.done == 0 {
            return Ended {
                summary: None,
                recorded: None,
            };
        }
        let (vertices, faces) = self.counts;
        let mut ended = Ended::with(format!(
            "{} level(s): {vertices} vertices, {faces} faces (stepped)",
            self.done
        ));
        // A later level refused still leaves the levels made: the entry names those.
        if self.done < self.levels {
            ended.recorded = Some(vec![Some(f64::from(self.done))]);
        }
        ended
    }
}
