//! Erase faces (Scotty3D's make boundary, Blender's delete faces): the faces become holes.
//!
//! ```text
//!   i ---- j ---- k ---- l          i ---- j      k ---- l
//!   |      |      |      |          |      |      |      |
//!   |      |  x   |      |          |      |      |      |    erase x: its top side j k
//!   e ---- f ---- g ---- h    →     e ---- f ---- g ---- h    has no face left and goes;
//!   |      |      |      |          |      |      |      |    f g, g k and j f are boundary
//!   |      |      |      |          |      |      |      |    edges now, and the border
//!   a ---- b ---- c ---- d          a ---- b ---- c ---- d    runs … i j f g k l …
//! ```
//!
//! Each halfedge of an erased face whose twin still has a face becomes a boundary halfedge
//! (it loses its corner UV) and joins the boundary loop beside it: holes that meet merge into
//! one loop, a hole that reaches the border opens it. An edge left with no face on either side
//! is removed with its two halfedges, and a vertex left with no edge is removed. Everything else
//! keeps its entity. Any set of faces can be given (repeats are ignored); a set that covers a
//! whole connected component removes that component.
//!
//! Afterwards each surviving vertex of an erased face points at its outgoing boundary
//! halfedge, and each surviving edge names its interior halfedge. Counts: F − |faces|; χ goes
//! down by one for each face erased from the inside of the surface and changes less where the
//! hole merges with the boundary (a face sharing one edge with a hole: −1 face, −1 edge, χ
//! unchanged).
//!
//! [`faces_of_vertex`] and [`faces_of_edge`] give the faces that erasing a vertex (every face
//! around it) or an edge (its one or two faces) means.
//!
//! Refusals, in the order they are checked, each leaving the world untouched:
//! - `BadParameter`: no face given;
//! - `Stale`: a face that is not live;
//! - `BadParameter`: faces of two different meshes;
//! - `PinchedVertex`: a vertex that keeps some faces but would touch the boundary twice — its
//!   remaining faces would not be one fan with one gap (e.g. one triangle of a grid that touches
//!   the border only at a corner, or two quads that share only a vertex);
//! - `NoFacesLeft`: the faces are every face of the mesh.

use bevy::ecs::entity::EntityHashSet;
use bevy::prelude::World;

use crate::mesh::attributes::CornerUv;
use crate::mesh::elements::{Edge, Face, InMesh, Vertex};
use crate::mesh::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;
use crate::ops::declaration::{Declaration, Names, Section};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Reach, Values, count};

use super::{Refusal, he, link, live_edge};

/// What an erase removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Erased {
    /// Faces removed (the erased faces).
    pub faces: usize,
    /// Edges removed (left with no face on either side).
    pub edges: usize,
    /// Vertices removed (left with no edge).
    pub vertices: usize,
}

/// A surviving vertex of an erased face: its boundary halfedges after the erase, coming in and
/// going out (the incoming one's `next` is the outgoing one, which becomes the vertex's
/// halfedge).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rim {
    vertex: VertexId,
    into: HalfedgeId,
    out: HalfedgeId,
}

/// Everything an erase touches, collected by [`plan_erase`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ErasePlan {
    mesh: MeshId,
    /// The faces to erase, without repeats, in the order given.
    faces: Vec<FaceId>,
    /// Every vertex of those faces.
    corners: Vec<VertexId>,
    /// Halfedges of erased faces whose edge survives: they become boundary halfedges.
    opened: Vec<HalfedgeId>,
    /// Surviving edges whose halfedge is opened: they will name its twin.
    renamed_edges: Vec<(EdgeId, HalfedgeId)>,
    rims: Vec<Rim>,
    removed_halfedges: Vec<HalfedgeId>,
    removed_edges: Vec<EdgeId>,
    removed_vertices: Vec<VertexId>,
}

impl ErasePlan {
    /// The vertices whose neighbourhood covers everything the erase reads, changes or removes:
    /// every corner of every erased face (see [`crate::mesh::change::neighbourhood`]).
    pub fn seeds(&self) -> Vec<VertexId> {
        self.corners.clone()
    }

    /// The mesh the faces belong to.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }
}

/// Checks that `faces` can be erased and collects everything the erase touches.
///
/// # Refusals
/// See the module doc.
pub fn plan_erase(world: &World, faces: &[FaceId]) -> Result<ErasePlan, Refusal> {
    let m = MeshRef::new(world);
    if faces.is_empty() {
        return Err(Refusal::BadParameter("no face to erase".into()));
    }
    let mut list: Vec<FaceId> = Vec::with_capacity(faces.len());
    let mut erased = EntityHashSet::default();
    let mut mesh: Option<MeshId> = None;
    for &f in faces {
        let stale = || Refusal::Stale(ElementId::Face(f));
        m.try_face(f).ok_or_else(stale)?;
        let owner = world.get::<InMesh>(f.0).ok_or_else(stale)?.0;
        if *mesh.get_or_insert(owner) != owner {
            return Err(Refusal::BadParameter(format!(
                "{f} is not in the same mesh as {}",
                list[0]
            )));
        }
        if erased.insert(f.0) {
            list.push(f);
        }
    }
    let Some(mesh) = mesh else {
        unreachable!("at least one face was read");
    };
    // A halfedge whose face stays.
    let kept = |h: HalfedgeId| m.face(h).is_some_and(|f| !erased.contains(&f.0));

    let mut seen = EntityHashSet::default();
    let mut corners = Vec::new();
    for &f in &list {
        for v in m.face_vertices(f) {
            if seen.insert(v.0) {
                corners.push(v);
            }
        }
    }
    // Around each corner, the sector after outgoing halfedge `fan[i]` is its face. The kept
    // sectors must form one run (one gap, so one boundary halfedge in and one out), or none
    // (the vertex goes).
    let mut rims = Vec::new();
    let mut removed_vertices = Vec::new();
    for &v in &corners {
        let fan: Vec<HalfedgeId> = m.vertex_outgoing(v).collect();
        let k = fan.len();
        let full: Vec<bool> = fan.iter().map(|&h| kept(h)).collect();
        let gap_starts: Vec<usize> = (0..k)
            .filter(|&i| !full[i] && full[(i + k - 1) % k])
            .collect();
        match gap_starts[..] {
            [] => {
                crate::checks::checked_assert!(
                    full.iter().all(|x| !x),
                    "{v} is a corner of an erased face"
                );
                removed_vertices.push(v);
            }
            [i] => {
                let mut j = i;
                while !full[(j + 1) % k] {
                    j = (j + 1) % k;
                }
                rims.push(Rim {
                    vertex: v,
                    into: m.twin(fan[(j + 1) % k]),
                    out: fan[i],
                });
            }
            _ => return Err(Refusal::PinchedVertex(ElementId::Vertex(v))),
        }
    }
    if rims.is_empty() {
        // Every face around every corner is erased: the faces are whole components. Refuse
        // when they are the whole mesh.
        let all = crate::mesh::members::of_kind::<Face, _>(world, mesh, FaceId).len();
        if all == list.len() {
            return Err(Refusal::NoFacesLeft);
        }
    }
    let mut opened = Vec::new();
    let mut renamed_edges = Vec::new();
    let mut removed_halfedges = Vec::new();
    let mut removed_edges = Vec::new();
    let mut gone_edges = EntityHashSet::default();
    for &f in &list {
        for h in m.face_halfedges(f) {
            let (t, e) = (m.twin(h), m.edge(h));
            if kept(t) {
                opened.push(h);
                if m.edge_halfedge(e) == h {
                    renamed_edges.push((e, t));
                }
            } else if gone_edges.insert(e.0) {
                removed_edges.push(e);
                removed_halfedges.extend([h, t]);
            }
        }
    }
    Ok(ErasePlan {
        mesh,
        faces: list,
        corners,
        opened,
        renamed_edges,
        rims,
        removed_halfedges,
        removed_edges,
        removed_vertices,
    })
}

/// Carries out an erase planned by [`plan_erase`] on the unchanged world. Returns what was
/// removed.
pub fn apply_erase(world: &mut World, plan: ErasePlan) -> Erased {
    crate::checks::checked_assert_eq!(
        plan_erase(world, &plan.faces).as_ref(),
        Ok(&plan),
        "stale erase plan"
    );
    for &h in &plan.opened {
        he(world, h).face = None;
        world.entity_mut(h.0).remove::<CornerUv>();
    }
    for r in &plan.rims {
        link(world, r.into, r.out);
        world
            .get_mut::<Vertex>(r.vertex.0)
            .expect("planned")
            .halfedge = r.out;
    }
    for &(e, h) in &plan.renamed_edges {
        world.get_mut::<Edge>(e.0).expect("planned").halfedge = h;
    }
    let removed = Erased {
        faces: plan.faces.len(),
        edges: plan.removed_edges.len(),
        vertices: plan.removed_vertices.len(),
    };
    let entities = plan
        .faces
        .iter()
        .map(|f| f.0)
        .chain(plan.removed_halfedges.iter().map(|h| h.0))
        .chain(plan.removed_edges.iter().map(|e| e.0))
        .chain(plan.removed_vertices.iter().map(|v| v.0));
    for e in entities {
        world.despawn(e);
    }
    removed
}

/// Erases `faces` (see the module doc): plan, then apply. Returns what was removed.
///
/// # Refusals
/// See the module doc; the world is then unchanged.
pub fn erase_faces(world: &mut World, faces: &[FaceId]) -> Result<Erased, Refusal> {
    let plan = plan_erase(world, faces)?;
    Ok(apply_erase(world, plan))
}

/// The faces that erasing vertex `v` means: every face around it (none for no vertex of a
/// valid mesh). Pass them to [`plan_erase`] or [`erase_faces`].
///
/// # Refusals
/// `Stale` if `v` is not a live vertex.
pub fn faces_of_vertex(world: &World, v: VertexId) -> Result<Vec<FaceId>, Refusal> {
    let m = MeshRef::new(world);
    let h = m
        .try_vertex(v)
        .ok_or(Refusal::Stale(ElementId::Vertex(v)))?
        .halfedge;
    m.try_halfedge(h)
        .ok_or(Refusal::Stale(ElementId::Vertex(v)))?;
    Ok(m.vertex_faces(v).collect())
}

/// The faces that erasing edge `e` means: its one (boundary edge) or two faces. Pass them to
/// [`plan_erase`] or [`erase_faces`].
///
/// # Refusals
/// `Stale` if `e` is not a live edge.
pub fn faces_of_edge(world: &World, e: EdgeId) -> Result<Vec<FaceId>, Refusal> {
    let m = MeshRef::new(world);
    let h = live_edge(&m, e)?;
    Ok([m.face(h), m.face(m.twin(h))]
        .into_iter()
        .flatten()
        .collect())
}

/// The faces that erasing these elements means, each once in id order: a face itself, a
/// vertex's faces ([`faces_of_vertex`]), an edge's ([`faces_of_edge`]; a halfedge stands for its
/// edge). Pass them to [`plan_erase`] or [`erase_faces`].
///
/// # Refusals
/// `Stale` for an element that is not live.
pub fn faces_of(world: &World, elements: &[ElementId]) -> Result<Vec<FaceId>, Refusal> {
    let m = MeshRef::new(world);
    let mut faces = Vec::new();
    for &x in elements {
        match x {
            ElementId::Face(f) => {
                m.try_face(f).ok_or(Refusal::Stale(x))?;
                faces.push(f);
            }
            ElementId::Vertex(v) => faces.extend(faces_of_vertex(world, v)?),
            ElementId::Edge(e) => faces.extend(faces_of_edge(world, e)?),
            ElementId::Halfedge(h) => {
                let e = m.try_halfedge(h).ok_or(Refusal::Stale(x))?.edge;
                faces.extend(faces_of_edge(world, e)?);
            }
            ElementId::Mesh(_) => {}
        }
    }
    faces.sort_unstable();
    faces.dedup();
    Ok(faces)
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
        Ok(Applied::carried_out(world, plan.seeds(), |world| {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshMembers, mesh_stats, shapes, validate};
    use crate::ops::local::testkit::*;

    #[test]
    fn an_inner_quad_becomes_a_hole() {
        let (mut world, built) = build(&shapes::quad_grid(3, 3));
        let f = face_of(&world, &built, &[5, 6, 10, 9]);
        assert_eq!(counts(&world, built.mesh), (16, 24, 9, 1, 1));
        let erased = erase_faces(&mut world, &[f]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(
            erased,
            Erased {
                faces: 1,
                edges: 0,
                vertices: 0
            }
        );
        assert_eq!(counts(&world, built.mesh), (16, 24, 8, 0, 2));
        let m = MeshRef::new(&world);
        for i in [5, 6, 10, 9] {
            assert!(m.is_boundary_vertex(vertex(&built, i)));
        }
    }

    #[test]
    fn the_middle_of_three_quads_leaves_two_components() {
        // Scotty3D's make-boundary test: a strip of three quads.
        let (mut world, built) = build(&shapes::quad_grid(3, 1));
        let f = face_of(&world, &built, &[1, 2, 6, 5]);
        let erased = erase_faces(&mut world, &[f]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (1, 2, 0));
        let s = mesh_stats(&world, built.mesh);
        assert_eq!((s.vertices, s.edges, s.faces), (8, 8, 2));
        assert_eq!(
            (s.components, s.boundary_loops, s.euler_characteristic),
            (2, 2, 2)
        );
        let third = 1.0 / 3.0;
        let two = 2.0 / 3.0;
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[
                &[
                    [0.0, 0.0, 0.0],
                    [third, 0.0, 0.0],
                    [third, 1.0, 0.0],
                    [0.0, 1.0, 0.0]
                ],
                &[
                    [two, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [two, 1.0, 0.0]
                ],
            ])
        );
    }

    #[test]
    fn an_ear_triangle_takes_its_lone_vertex_with_it() {
        // The square 0 1 3 2 as triangles 0 1 3 and 0 3 2: erasing the second leaves vertex 2
        // with no edge.
        let (mut world, built) = build(&shapes::grid(1, 1));
        let f = face_of(&world, &built, &[0, 3, 2]);
        let gone = vertex(&built, 2);
        let erased = erase_faces(&mut world, &[f]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (1, 2, 1));
        assert_eq!(counts(&world, built.mesh), (3, 3, 1, 1, 1));
        assert!(world.get_entity(gone.0).is_err());
        assert_eq!(
            position_cycles(&world, built.mesh),
            cycles(&[&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]])
        );
    }

    #[test]
    fn a_block_of_faces_removes_the_edges_and_vertex_inside_it() {
        let (mut world, built) = build(&shapes::quad_grid(4, 4));
        // The 2 × 2 block around the centre vertex 12 (a row has 5 vertices).
        let block = [
            face_of(&world, &built, &[6, 7, 12, 11]),
            face_of(&world, &built, &[7, 8, 13, 12]),
            face_of(&world, &built, &[11, 12, 17, 16]),
            face_of(&world, &built, &[12, 13, 18, 17]),
        ];
        let mut given = block.to_vec();
        given.push(block[0]); // repeats are ignored
        let erased = erase_faces(&mut world, &given).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (4, 4, 1));
        assert_eq!(counts(&world, built.mesh), (24, 36, 12, 0, 2));
    }

    #[test]
    fn a_face_beside_a_hole_merges_with_it() {
        let (mut world, built) = build(&shapes::quad_grid(4, 4));
        let first = face_of(&world, &built, &[6, 7, 12, 11]);
        erase_faces(&mut world, &[first]).unwrap();
        let second = face_of(&world, &built, &[7, 8, 13, 12]);
        let erased = erase_faces(&mut world, &[second]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (1, 1, 0));
        assert_eq!(counts(&world, built.mesh), (25, 39, 14, 0, 2));
        // The hole is one loop of six sides around the two cells.
        let m = MeshRef::new(&world);
        let v7 = vertex(&built, 7);
        let hole: Vec<VertexId> = m
            .loop_from(m.vertex_halfedge(v7))
            .map(|h| m.to_vertex(h))
            .collect();
        assert_eq!(hole.len(), 6);
        for i in [6, 7, 8, 13, 12, 11] {
            assert!(hole.contains(&vertex(&built, i)));
        }
    }

    #[test]
    fn a_face_beside_both_a_hole_and_the_border_joins_them() {
        // A 3 × 3 grid of quads with the centre missing: erasing the right middle quad opens
        // the hole onto the border (one loop left, a disc again).
        let (mut world, built) = build(&shapes::grid_with_holes(1));
        assert_eq!(counts(&world, built.mesh), (16, 24, 8, 0, 2));
        let f = face_of(&world, &built, &[6, 7, 11, 10]);
        let erased = erase_faces(&mut world, &[f]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (1, 2, 0));
        assert_eq!(counts(&world, built.mesh), (16, 22, 7, 1, 1));
    }

    #[test]
    fn a_vertex_of_a_closed_triangle_mesh_becomes_a_hole() {
        let (mut world, built) = build(&shapes::icosahedron());
        let v = MeshMembers::collect(&world, built.mesh).vertices[0];
        let faces = faces_of_vertex(&world, v).unwrap();
        assert_eq!(faces.len(), 5);
        let erased = erase_faces(&mut world, &faces).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (5, 5, 1));
        assert_eq!(counts(&world, built.mesh), (11, 25, 15, 1, 1));
        // An edge on the new boundary has one face; an interior edge two.
        let m = MeshRef::new(&world);
        let members = MeshMembers::collect(&world, built.mesh);
        let border = members
            .edges
            .iter()
            .copied()
            .find(|&e| m.is_boundary_edge(e))
            .unwrap();
        let inner = members
            .edges
            .iter()
            .copied()
            .find(|&e| !m.is_boundary_edge(e))
            .unwrap();
        assert_eq!(faces_of_edge(&world, border).unwrap().len(), 1);
        assert_eq!(faces_of_edge(&world, inner).unwrap().len(), 2);
    }

    #[test]
    fn a_whole_component_goes_while_another_stays() {
        // Two separate squares in one mesh: erase both triangles of the first.
        let mut soup = shapes::grid(1, 1);
        soup.positions.extend(
            soup.positions
                .clone()
                .iter()
                .map(|p| *p + bevy::math::Vec3::X * 3.0),
        );
        soup.push_face(&[4, 5, 7]);
        soup.push_face(&[4, 7, 6]);
        let (mut world, built) = build(&soup);
        let first = [
            face_of(&world, &built, &[0, 1, 3]),
            face_of(&world, &built, &[0, 3, 2]),
        ];
        let erased = erase_faces(&mut world, &first).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!((erased.faces, erased.edges, erased.vertices), (2, 5, 4));
        assert_eq!(counts(&world, built.mesh), (4, 5, 2, 1, 1));
    }

    #[test]
    fn refusals_leave_the_mesh_untouched() {
        // A triangle of a grid that touches the border at one corner only: pinch.
        let (mut world, built) = build(&shapes::grid(3, 3));
        let corner_only = face_of(&world, &built, &[1, 6, 5]);
        let pinched = vertex(&built, 1);
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::PinchedVertex(ElementId::Vertex(pinched)),
            |w| erase_faces(w, &[corner_only]),
        );
        // Two quads that share only a vertex: pinch at that vertex.
        let (mut world, built) = build(&shapes::quad_grid(2, 2));
        let diagonal = [
            face_of(&world, &built, &[0, 1, 4, 3]),
            face_of(&world, &built, &[4, 5, 8, 7]),
        ];
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::PinchedVertex(ElementId::Vertex(vertex(&built, 4))),
            |w| erase_faces(w, &diagonal),
        );
        // Everything: no faces left.
        let all = MeshMembers::collect(&world, built.mesh).faces;
        assert_refused(&mut world, built.mesh, Refusal::NoFacesLeft, |w| {
            erase_faces(w, &all)
        });
        // Nothing.
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::BadParameter("no face to erase".into()),
            |w| erase_faces(w, &[]),
        );
        // A stale face.
        let f = face_of(&world, &built, &[0, 1, 4, 3]);
        erase_faces(&mut world, &[f]).unwrap();
        assert_refused(
            &mut world,
            built.mesh,
            Refusal::Stale(ElementId::Face(f)),
            |w| erase_faces(w, &[f]),
        );
        let v = vertex(&built, 0);
        assert_eq!(
            faces_of_vertex(&world, v),
            Err(Refusal::Stale(ElementId::Vertex(v)))
        );
        // Faces of two meshes.
        let other = build_into(&mut world, &shapes::tetrahedron());
        let there = MeshMembers::collect(&world, other.mesh).faces[0];
        let here = MeshMembers::collect(&world, built.mesh).faces[0];
        assert_refused_like(
            &mut world,
            other.mesh,
            |r| matches!(r, Refusal::BadParameter(_)),
            |w| erase_faces(w, &[here, there]),
        );
    }

    #[test]
    fn corner_uvs_leave_the_new_boundary_and_stay_elsewhere() {
        let (mut world, built) = build(&with_attributes(shapes::quad_grid(3, 3), Uvs::Continuous));
        assert_attributes_complete(&world, built.mesh);
        let f = face_of(&world, &built, &[5, 6, 10, 9]);
        let kept_before: Vec<Vec<Corner>> = faces(&world, built.mesh)
            .into_iter()
            .filter(|c| c.len() == 4)
            .collect();
        erase_faces(&mut world, &[f]).unwrap();
        validate(&world, built.mesh).unwrap();
        assert_attributes_complete(&world, built.mesh);
        // The eight faces left keep their corners exactly.
        let after = faces(&world, built.mesh);
        assert_eq!(after.len(), 8);
        assert!(after.iter().all(|c| kept_before.contains(c)));
    }

    #[test]
    fn undo_and_redo_restore_both_meshes() {
        let (mut world, built) = build(&with_attributes(shapes::grid(3, 3), Uvs::Continuous));
        let mesh = built.mesh;
        // A vertex on the border: its faces reach the boundary on both sides.
        let faces = faces_of_vertex(&world, vertex(&built, 1)).unwrap();
        let plan = plan_erase(&world, &faces).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, mesh, &seeds, |w| {
            apply_erase(w, plan);
        });
        // Then the inner cell beside the new hole, which merges with it.
        let inner = [
            face_of(&world, &built, &[5, 6, 10]),
            face_of(&world, &built, &[5, 10, 9]),
        ];
        let plan = plan_erase(&world, &inner).unwrap();
        let seeds = plan.seeds();
        assert_undo_redo(&mut world, mesh, &seeds, |w| {
            apply_erase(w, plan);
        });
    }
}
