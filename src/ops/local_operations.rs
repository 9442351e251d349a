//! The local operations as registered operations ([`MeshOperation`]): what each names (an
//! edge, a vertex, a face, faces, two edges, any elements), its title, key, panel section and
//! parameters, and how its outcome reads — the summary, what to redraw, what to select. The
//! algorithms, their plans and refusals are in [`crate::ops::local`], which knows nothing of
//! the edit layer; these adapters sit beside it rather than in it because the edit context
//! carries the simplification history ([`crate::ops::progressive`]), which is built from the
//! local operations (a module cycle otherwise).
//!
//! Each operation here is one `process` step, one key (or none, where the editor's own key
//! starts a drag first: E, I), one button, one `Mesh.step` from Python and one undoable edit;
//! operations that share a name and a key name different kinds of element (`collapse` an edge
//! or a face, C; `dissolve` an edge or a vertex, D), and what is selected, or what the step's
//! vertex numbers name, decides which runs.

use bevy::prelude::World;

use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::Refusal;
use crate::ops::declaration::{DROPPED_BY_SIMPLIFICATION, Declaration, Names, Parameter, Section};
use crate::ops::local::{
    CollapseOptions, apply_bevel_edge, apply_bevel_vertex, apply_collapse_face,
    apply_dissolve_vertex, apply_erase, apply_extrude, apply_inset, apply_weld, bisect_edge,
    check_growth, collapse_edge, dissolve_edge, faces_of, flip_edge, plan_bevel_edge,
    plan_bevel_vertex, plan_collapse_face, plan_dissolve_vertex, plan_erase, plan_extrude,
    plan_inset, plan_weld, split_edge, split_face, toggle_seam,
};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Redraw, Values, count};
use crate::ops::simplification_history::SimplificationHistory;

/// Changes the edge `e` with `change`, which says what it did and what it made (the selection
/// moves there); the faces that were around the edge's ends, and those around what was made,
/// are redrawn.
///
/// # Refusals
/// `change`'s.
fn on_edge(
    world: &mut World,
    e: EdgeId,
    change: impl FnOnce(&mut World) -> Result<(String, ElementId), Refusal>,
) -> Result<Applied, Refusal> {
    let m = MeshRef::new(world);
    let before = m.faces_around(&m.corners(e.into()));
    let (summary, made) = change(world)?;
    Ok(Applied::around(
        world,
        before,
        Vec::new(),
        summary,
        Some(made),
    ))
}

/// Carries out a checked plan whose undo seeds are `seeds`: `apply` makes the change and says
/// what it did and made; the faces around the seeds before and after, and around what was
/// made, are redrawn.
fn carry_out(
    world: &mut World,
    seeds: Vec<VertexId>,
    apply: impl FnOnce(&mut World) -> (String, Option<ElementId>),
) -> Applied {
    let before = MeshRef::new(world).faces_around(&seeds);
    let (summary, made) = apply(world);
    Applied::around(world, before, seeds, summary, made)
}

/// Flipping an edge: a local edit that keeps every id and attribute.
pub const FLIP: Declaration = Declaration::new("flip")
    .titled("Flip")
    .described("flip (rotate) the selected edge")
    .on_key("Alt+R")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`flip_edge`] as a registered operation: `flip:A,B`, Alt+R, the *Local operations* button.
pub struct Flip;

impl MeshOperation for Flip {
    fn declaration(&self) -> &'static Declaration {
        &FLIP
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        on_edge(world, e, |world| {
            let flipped = flip_edge(world, e)?;
            Ok((format!("flipped to {flipped}"), flipped.into()))
        })
    }
}

/// Splitting an edge: a local edit.
pub const SPLIT: Declaration = Declaration::new("split")
    .titled("Split")
    .described("split the selected edge at its midpoint")
    .on_key("Alt+S")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`split_edge`] at the midpoint as a registered operation: `split:A,B`, Alt+S.
pub struct Split;

impl MeshOperation for Split {
    fn declaration(&self) -> &'static Declaration {
        &SPLIT
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        on_edge(world, e, |world| {
            let v = split_edge(world, e, 0.5)?;
            Ok((format!("new vertex {v}"), v.into()))
        })
    }
}

/// Bisecting an edge: a local edit.
pub const BISECT: Declaration = Declaration::new("bisect")
    .titled("Bisect")
    .described("bisect the selected edge: a vertex at its midpoint, no face cut")
    .on_key("K")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`bisect_edge`] at the midpoint as a registered operation: `bisect:A,B`, K.
pub struct Bisect;

impl MeshOperation for Bisect {
    fn declaration(&self) -> &'static Declaration {
        &BISECT
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        on_edge(world, e, |world| {
            let v = bisect_edge(world, e, 0.5)?;
            Ok((format!("new vertex {v} on {e}"), v.into()))
        })
    }
}

/// Collapsing an edge: a local edit.
pub const COLLAPSE: Declaration = Declaration::new("collapse")
    .titled("Collapse")
    .described("collapse the active edge (to its midpoint) or face (to its centroid)")
    .on_key("C")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`collapse_edge`] to the midpoint as a registered operation: `collapse:A,B`, C on an edge.
pub struct Collapse;

impl MeshOperation for Collapse {
    fn declaration(&self) -> &'static Declaration {
        &COLLAPSE
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        on_edge(world, e, |world| {
            let r = collapse_edge(world, e, CollapseOptions::default())?;
            Ok((
                format!("kept {}, removed {}", r.kept, r.removed),
                r.kept.into(),
            ))
        })
    }
}

/// Collapsing a face (the `collapse:A,B,C` step): a local edit.
pub const COLLAPSE_FACE: Declaration = Declaration::new("collapse")
    .titled("Collapse")
    .described("collapse the active face to its centroid")
    .on_key("C")
    .naming(Names::Face)
    .in_section(Section::Local);

/// [`collapse_face`] as a registered operation: `collapse:A,B,C`, C on a face.
pub struct CollapseFace;

impl MeshOperation for CollapseFace {
    fn declaration(&self) -> &'static Declaration {
        &COLLAPSE_FACE
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_collapse_face(world, values.face().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = plan_collapse_face(world, values.face()?)?;
        Ok(carry_out(world, plan.seeds(), |world| {
            let made = apply_collapse_face(world, plan);
            let summary = format!("collapsed to {made}");
            (summary, Some(made.into()))
        }))
    }
}

/// Dissolving an edge: a local edit.
pub const DISSOLVE: Declaration = Declaration::new("dissolve")
    .titled("Dissolve")
    .described("dissolve the active edge (merge its two faces) or vertex (merge its faces)")
    .on_key("D")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// [`dissolve_edge`] as a registered operation: `dissolve:A,B`, D on an edge.
pub struct Dissolve;

impl MeshOperation for Dissolve {
    fn declaration(&self) -> &'static Declaration {
        &DISSOLVE
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        let m = MeshRef::new(world);
        let ends = m.corners(e.into());
        let before = m.faces_around(&ends);
        let f = dissolve_edge(world, e)?;
        Ok(Applied {
            summary: format!("merged into {f}"),
            redraw: Redraw::near(world, before, ends),
            made: Some(ElementId::Face(f)),
        })
    }
}

/// Dissolving a vertex (the `dissolve:A` step): a local edit.
pub const DISSOLVE_VERTEX: Declaration = Declaration::new("dissolve")
    .titled("Dissolve")
    .described("dissolve the active vertex: merge the faces around it")
    .on_key("D")
    .naming(Names::Vertex)
    .in_section(Section::Local);

/// [`dissolve_vertex`] as a registered operation: `dissolve:A`, D on a vertex.
pub struct DissolveVertex;

impl MeshOperation for DissolveVertex {
    fn declaration(&self) -> &'static Declaration {
        &DISSOLVE_VERTEX
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_dissolve_vertex(world, values.vertex().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = plan_dissolve_vertex(world, values.vertex()?)?;
        Ok(carry_out(world, plan.seeds(), |world| {
            let made = apply_dissolve_vertex(world, plan);
            let summary = format!("merged into {made}");
            (summary, Some(made.into()))
        }))
    }
}

/// Marking a seam (or unmarking it): a local edit of one edge's mark.
pub const SEAM: Declaration = Declaration::new("seam")
    .titled("Seam")
    .described("mark the selected edge as a seam for parameterizing (or unmark it)")
    .on_key("Ctrl+E")
    .naming(Names::Edge)
    .in_section(Section::Uv)
    .keeping_normals();

/// [`toggle_seam`] as a registered operation: `seam:A,B`, Ctrl+E.
pub struct ToggleSeam;

impl MeshOperation for ToggleSeam {
    fn declaration(&self) -> &'static Declaration {
        &SEAM
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        let marked = toggle_seam(world, e)?;
        Ok(Applied {
            summary: if marked {
                format!("{e} is a seam")
            } else {
                format!("{e} is no longer a seam")
            },
            redraw: Redraw::near(world, Vec::new(), MeshRef::new(world).corners(e.into())),
            made: None,
        })
    }
}

/// Extruding a region of faces: a local edit (the walls take the region's groups).
pub const EXTRUDE: Declaration = Declaration::new("extrude")
    .titled("Extrude")
    .described("extrude the faces as one region and push it DISTANCE along its normals")
    .naming(Names::Faces)
    .with_parameters(&[Parameter::real("DISTANCE", 0.0, -1e6, 1e6)])
    .in_section(Section::Modelling);

/// [`plan_extrude`] and [`apply_extrude`] as a registered operation: `extrude:FACES[:DISTANCE]`,
/// E (which then drags the distance).
pub struct Extrude;

impl MeshOperation for Extrude {
    fn declaration(&self) -> &'static Declaration {
        &EXTRUDE
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_extrude(world, &values.faces().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = {
            let faces = values.faces()?;
            let plan = plan_extrude(world, &faces)?;
            plan.check_distance(values.number(0) as f32)?;
            check_growth("extruding", faces.len(), plan.seeds().len())?;
            plan
        };
        Ok(carry_out(world, plan.seeds(), |world| {
            let done = apply_extrude(world, plan, values.number(0) as f32);
            let summary = format!(
                "{} lifted on {}",
                count(done.top.len(), "face"),
                count(done.sides.len(), "side face")
            );
            (summary, None)
        }))
    }
}

/// Insetting faces (with a depth, Scotty3D's bevel face): a local edit.
pub const INSET: Declaration = Declaration::new("inset")
    .titled("Inset")
    .described("inset each face: a ring of quads inside it, AMOUNT of the way to its centre, DEPTH along its normal")
    .naming(Names::Faces)
    .with_parameters(&[
        Parameter::real("AMOUNT", 0.0, 0.0, 0.999),
        Parameter::real("DEPTH", 0.0, -1e6, 1e6),
    ])
    .in_section(Section::Modelling);

/// [`plan_inset`] and [`apply_inset`] as a registered operation: `inset:FACES[:AMOUNT[:DEPTH]]`,
/// I (which then drags the amount); also the bevel of faces ([`Bevel`]).
pub struct Inset;

impl MeshOperation for Inset {
    fn declaration(&self) -> &'static Declaration {
        &INSET
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_inset(world, &values.faces().ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = {
            let faces = values.faces()?;
            let plan = plan_inset(world, &faces)?;
            plan.check(values.number(0) as f32, values.number(1) as f32)?;
            check_growth("insetting", faces.len(), plan.seeds().len())?;
            plan
        };
        Ok(carry_out(world, plan.seeds(), |world| {
            let (amount, depth) = (values.number(0) as f32, values.number(1) as f32);
            let done = apply_inset(world, plan, amount, depth);
            let summary = format!(
                "{} inset, {} around them",
                count(done.top.len(), "face"),
                count(done.sides.len(), "new face")
            );
            (summary, None)
        }))
    }
}

/// Bevelling a vertex, an edge or faces: a local edit.
pub const BEVEL: Declaration = Declaration::new("bevel")
    .titled("Bevel")
    .described("bevel the selected vertex or edge into a face whose corners lie AMOUNT (0–0.5) along its edges, or inset the selected faces by AMOUNT with DEPTH")
    .on_key("Ctrl+B")
    .naming(Names::Elements)
    .with_parameters(&[
        Parameter::real("AMOUNT", 0.25, 0.0, 0.999),
        Parameter::real("DEPTH", 0.0, -1e6, 1e6),
    ])
    .in_section(Section::Modelling);

/// Blender's bevel on what it names: one vertex or one edge ([`plan_bevel_vertex`],
/// [`plan_bevel_edge`]: Scotty3D's `bevel_vertex` and `bevel_edge`), or faces (an inset with
/// depth, as [`Inset`]): `bevel:ELEMENTS[:AMOUNT[:DEPTH]]`, Ctrl+B. A halfedge names its edge.
pub struct Bevel;

/// What a [`Bevel`] works on.
enum Bevelled {
    Vertex(VertexId),
    Edge(EdgeId),
    Faces,
}

impl Bevel {
    /// What `values` name, checked for kind (not for liveness: the plans check that).
    ///
    /// # Refusals
    /// [`Refusal::BadParameter`] for anything but one vertex, one edge (or halfedge) or faces.
    fn bevelled(world: &World, values: Values<'_>) -> Result<Bevelled, Refusal> {
        let m = MeshRef::new(world);
        match values.elements() {
            [ElementId::Vertex(v)] => Ok(Bevelled::Vertex(*v)),
            [ElementId::Edge(e)] => Ok(Bevelled::Edge(*e)),
            [ElementId::Halfedge(h)] if m.try_halfedge(*h).is_some() => {
                Ok(Bevelled::Edge(m.edge(*h)))
            }
            [ElementId::Halfedge(h)] => Err(Refusal::Stale(ElementId::Halfedge(*h))),
            faces if faces.iter().all(|x| matches!(x, ElementId::Face(_))) => Ok(Bevelled::Faces),
            _ => Err(Refusal::BadParameter(
                "bevel names one vertex, one edge or faces".into(),
            )),
        }
    }
}

impl MeshOperation for Bevel {
    fn declaration(&self) -> &'static Declaration {
        &BEVEL
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, mesh: MeshId, values: Values<'_>) -> Option<Reach> {
        let amount = values.number(0) as f32;
        match Self::bevelled(world, values).ok()? {
            Bevelled::Vertex(v) => {
                Reach::local(world, plan_bevel_vertex(world, v, amount).ok()?.seeds())
            }
            Bevelled::Edge(e) => {
                Reach::local(world, plan_bevel_edge(world, e, amount).ok()?.seeds())
            }
            Bevelled::Faces => Inset.reach(world, mesh, values),
        }
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let amount = values.number(0) as f32;
        let new_face = |f: FaceId| (format!("new face {f}"), Some(ElementId::Face(f)));
        match Self::bevelled(world, values)? {
            Bevelled::Vertex(v) => {
                let plan = plan_bevel_vertex(world, v, amount)?;
                Ok(carry_out(world, plan.seeds(), |world| {
                    new_face(apply_bevel_vertex(world, plan))
                }))
            }
            Bevelled::Edge(e) => {
                let plan = plan_bevel_edge(world, e, amount)?;
                Ok(carry_out(world, plan.seeds(), |world| {
                    new_face(apply_bevel_edge(world, plan))
                }))
            }
            Bevelled::Faces => Inset.apply(world, mesh, values, context),
        }
    }
}

/// Erasing faces: a local edit.
pub const ERASE: Declaration = Declaration::new("erase")
    .titled("Erase")
    .described("erase the selection: its faces become holes")
    .on_key("X")
    .naming(Names::Elements)
    .in_section(Section::Modelling);

/// [`plan_erase`] and [`apply_erase`] on the faces of the named elements (a vertex's, an
/// edge's, a face): `erase:ELEMENTS`, X.
pub struct Erase;

impl MeshOperation for Erase {
    fn declaration(&self) -> &'static Declaration {
        &ERASE
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = plan_erase(world, &faces_of(world, values.elements()).ok()?).ok()?;
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = plan_erase(world, &faces_of(world, values.elements())?)?;
        Ok(carry_out(world, plan.seeds(), |world| {
            let gone = apply_erase(world, plan);
            let summary = format!(
                "removed {}, {}, {}",
                count(gone.faces, "face"),
                count(gone.edges, "edge"),
                count(gone.vertices, "vertex")
            );
            (summary, None)
        }))
    }
}

/// Welding two boundary edges: a local edit.
pub const WELD: Declaration = Declaration::new("weld")
    .titled("Weld")
    .described("weld the first two selected boundary edges: the second onto the first")
    .on_key("Alt+M")
    .naming(Names::TwoEdges)
    .in_section(Section::Modelling);

/// [`plan_weld`] and [`apply_weld`] as a registered operation: `weld:A,B/C,D`, Alt+M.
pub struct Weld;

impl MeshOperation for Weld {
    fn declaration(&self) -> &'static Declaration {
        &WELD
    }

    /// What the plan touches (`None` when it is refused: it changes nothing).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let plan = {
            let [a, b] = values.two_edges().ok()?;
            plan_weld(world, a, b).ok()?
        };
        Reach::local(world, plan.seeds())
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let plan = {
            let [a, b] = values.two_edges()?;
            plan_weld(world, a, b)?
        };
        Ok(carry_out(world, plan.seeds(), |world| {
            let e = apply_weld(world, plan);
            (format!("welded into {e}"), Some(ElementId::Edge(e)))
        }))
    }
}

/// Splitting a face between two of its corners: a local edit.
pub const SPLIT_FACE: Declaration = Declaration::new("split-face")
    .titled("Split face")
    .described("join two corners of a face by a new edge (the selected halfedge's tip and the corner two ahead)")
    .on_key("J")
    .naming(Names::FaceCorners)
    .in_section(Section::Local);

/// [`split_face`] as a registered operation: `split-face:A,B` (the face the two vertices
/// share), J on a halfedge of a face.
pub struct SplitFace;

impl MeshOperation for SplitFace {
    fn declaration(&self) -> &'static Declaration {
        &SPLIT_FACE
    }

    /// The neighbourhood of the two corners (`None` when the face or a corner is gone).
    fn reach(&self, world: &World, _: MeshId, values: Values<'_>) -> Option<Reach> {
        let (f, a, b) = values.face_corners().ok()?;
        MeshRef::new(world).try_face(f)?;
        Reach::local(world, vec![a, b])
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let (f, a, b) = values.face_corners()?;
        let before = MeshRef::new(world).faces_around(&[a, b]);
        let e = split_face(world, f, a, b)?;
        Ok(Applied {
            summary: format!("new edge {e}"),
            redraw: Redraw::near(world, before, vec![a, b]),
            made: Some(ElementId::Edge(e)),
        })
    }
}

/// Splitting back the last collapse of a simplification: it moves along the history, so the
/// history survives it, and like the simplification it drops attributes.
pub const VERTEX_SPLIT: Declaration = Declaration::new("vertex-split")
    .titled("Split vertex back")
    .described("split the vertex back as it was before the simplification's last collapse into it")
    .on_key("U")
    .naming(Names::Vertex)
    .in_section(Section::Local)
    .keeping_history()
    .dropping(DROPPED_BY_SIMPLIFICATION);

/// [`crate::ops::progressive::ProgressiveMesh::refine_vertex`] as a registered operation:
/// `vertex-split:A` after a `simplify` step, U in the editor.
pub struct VertexSplit;

impl MeshOperation for VertexSplit {
    fn declaration(&self) -> &'static Declaration {
        &VERTEX_SPLIT
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let v = values.vertex()?;
        let b =
            SimplificationHistory::move_along(world, mesh, |pm, world| pm.refine_vertex(world, v))?;
        Ok(Applied {
            summary: format!("split back {b}"),
            redraw: Redraw::Whole,
            made: Some(ElementId::Vertex(v)),
        })
    }
}
