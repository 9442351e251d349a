//! Changing the selected set: toggle, all, grow and shrink by one ring, edge loops and rings,
//! and the elements inside a box on screen.
//!
//! Grow and shrink keep each element's kind (Blender's Select More / Less): the set's vertices
//! `S` are the corners of its elements; growing selects every element of the same kind that
//! touches `S` (for vertices: their neighbours); shrinking drops each element with a corner
//! that touches an element of its kind outside the set. Halfedges count as their edges.

use bevy::ecs::entity::EntityHashSet;
use bevy::prelude::{Vec2, Vec3, World};

use crate::mesh::MeshMembers;
use crate::mesh::ids::{ElementId, FaceId, MeshId, VertexId};
use crate::mesh::loops::{edge_loop, edge_ring};
use crate::mesh::topology::MeshRef;

use super::requests::{Declined, SelectionEdit};
use super::selection::{ActiveMesh, SelectMode, Selection, exists};

/// Applies a selection change; the summary counts the set.
///
/// # Errors
/// [`Declined::NoSuchElement`] for an element that is gone (the selection is unchanged),
/// [`Declined::NoMesh`] for "all" without a mesh.
pub fn apply_selection_edit(world: &mut World, edit: &SelectionEdit) -> Result<String, Declined> {
    let m = MeshRef::new(world);
    let check = |xs: &[ElementId]| match xs.iter().find(|&&x| !exists(&m, x)) {
        Some(&x) => Err(Declined::NoSuchElement(x)),
        None => Ok(()),
    };
    let mut selection = world.resource::<Selection>().clone();
    match edit {
        SelectionEdit::Toggle(x) => {
            check(&[*x])?;
            selection.toggle(*x);
        }
        SelectionEdit::Add(xs) => {
            check(xs)?;
            selection.extend(xs.iter().copied());
        }
        SelectionEdit::Replace(xs) => {
            check(xs)?;
            selection.select_only(None);
            selection.extend(xs.iter().copied());
        }
        SelectionEdit::All => {
            let mesh = world.resource::<ActiveMesh>().0.ok_or(Declined::NoMesh)?;
            let mode = *world.resource::<SelectMode>();
            let active = selection.element;
            selection.select_only(None);
            selection.extend(all_of_kind(world, mesh, mode));
            if let Some(x) = active.filter(|&x| selection.contains(x)) {
                selection.add(x);
            }
        }
        SelectionEdit::Grow => {
            let grown = grow(&m, selection.elements());
            selection.extend(grown);
        }
        SelectionEdit::Shrink => {
            let keep: EntityHashSet = shrink(&m, selection.elements())
                .into_iter()
                .map(ElementId::entity)
                .collect();
            selection.retain(|x| keep.contains(&x.entity()));
        }
        SelectionEdit::Loop(e, add) | SelectionEdit::Ring(e, add) => {
            let path = match edit {
                SelectionEdit::Loop(..) => edge_loop(&m, *e),
                _ => edge_ring(&m, *e),
            }
            .ok_or(Declined::NoSuchElement(ElementId::Edge(*e)))?;
            if !add {
                selection.select_only(None);
            }
            selection.extend(path.into_iter().map(ElementId::Edge));
            selection.add(ElementId::Edge(*e));
        }
    }
    let summary = describe(&selection);
    *world.resource_mut::<Selection>() = selection;
    Ok(summary)
}

/// "3 vertices, 2 faces selected", or "nothing selected".
pub fn describe(selection: &Selection) -> String {
    let [v, e, f] = selection.counts();
    let parts: Vec<String> = [
        (v, "vertex", "vertices"),
        (e, "edge", "edges"),
        (f, "face", "faces"),
    ]
    .into_iter()
    .filter(|(n, ..)| *n > 0)
    .map(|(n, one, many)| format!("{n} {}", if n == 1 { one } else { many }))
    .collect();
    match parts.is_empty() {
        true => "nothing selected".into(),
        false => format!("{} selected", parts.join(", ")),
    }
}

/// Every element of `mesh` of the kind `mode` picks (vertices in auto mode, edges for
/// halfedges).
fn all_of_kind(world: &World, mesh: MeshId, mode: SelectMode) -> Vec<ElementId> {
    let members = MeshMembers::collect(world, mesh);
    match mode {
        SelectMode::Auto | SelectMode::Vertex => members
            .vertices
            .iter()
            .map(|&v| ElementId::Vertex(v))
            .collect(),
        SelectMode::Edge | SelectMode::Halfedge => {
            members.edges.iter().map(|&e| ElementId::Edge(e)).collect()
        }
        SelectMode::Face => members.faces.iter().map(|&f| ElementId::Face(f)).collect(),
    }
}

/// The corners of a live element (a halfedge's are its edge's; a mesh has none).
pub fn corners(m: &MeshRef<'_>, x: ElementId) -> Vec<VertexId> {
    match x {
        ElementId::Vertex(v) => vec![v],
        ElementId::Edge(e) => {
            let (a, b) = m.edge_vertices(e);
            vec![a, b]
        }
        ElementId::Halfedge(h) => vec![m.from_vertex(h), m.to_vertex(h)],
        ElementId::Face(f) => m.face_vertices(f).collect(),
        ElementId::Mesh(_) => Vec::new(),
    }
}

/// The elements of the same kind as `x` that touch vertex `v` (for a vertex: its neighbours).
fn touching(m: &MeshRef<'_>, v: VertexId, x: ElementId) -> Vec<ElementId> {
    match x {
        ElementId::Vertex(_) => m.vertex_neighbors(v).map(ElementId::Vertex).collect(),
        ElementId::Edge(_) | ElementId::Halfedge(_) => m
            .vertex_outgoing(v)
            .map(|h| ElementId::Edge(m.edge(h)))
            .collect(),
        ElementId::Face(_) => m.vertex_faces(v).map(ElementId::Face).collect(),
        ElementId::Mesh(_) => Vec::new(),
    }
}

/// The elements one ring beyond the set, each kind by itself (the set itself not repeated).
pub fn grow(m: &MeshRef<'_>, set: &[ElementId]) -> Vec<ElementId> {
    let live: Vec<ElementId> = set.iter().copied().filter(|&x| exists(m, x)).collect();
    let mut seen: EntityHashSet = live.iter().map(|x| x.entity()).collect();
    let mut out = Vec::new();
    for &x in &live {
        for v in corners(m, x) {
            for y in touching(m, v, x) {
                if seen.insert(y.entity()) {
                    out.push(y);
                }
            }
        }
    }
    out
}

/// The elements of the set that stay when it shrinks by one ring: those none of whose corners
/// touches an element of their kind outside the set.
pub fn shrink(m: &MeshRef<'_>, set: &[ElementId]) -> Vec<ElementId> {
    let inside: EntityHashSet = set
        .iter()
        .map(|&x| match (x, m) {
            // A halfedge stands for its edge.
            (ElementId::Halfedge(h), m) if m.try_halfedge(h).is_some() => m.edge(h).0,
            _ => x.entity(),
        })
        .collect();
    set.iter()
        .copied()
        .filter(|&x| exists(m, x))
        .filter(|&x| {
            corners(m, x).into_iter().all(|v| {
                let vertex_inside = !matches!(x, ElementId::Vertex(_)) || !m.is_boundary_vertex(v);
                vertex_inside
                    && touching(m, v, x)
                        .into_iter()
                        .all(|y| inside.contains(&y.entity()))
            })
        })
        .collect()
}

/// The elements of the kind `mode` picks whose screen position lies inside the rectangle
/// `min`–`max` and that face the camera: vertices and edges with a front-facing face around
/// them, faces that are front-facing. `to_screen` projects a point; `eye` is the camera's
/// position.
pub fn inside_box(
    m: &MeshRef<'_>,
    members: &MeshMembers,
    mode: SelectMode,
    (min, max): (Vec2, Vec2),
    eye: Vec3,
    to_screen: impl Fn(Vec3) -> Option<Vec2>,
) -> Vec<ElementId> {
    let inside = |p: Vec3| to_screen(p).is_some_and(|s| s.cmpge(min).all() && s.cmple(max).all());
    let facing = |f: FaceId| m.face_area_vector(f).dot(eye - m.face_centroid(f)) > 0.0;
    match mode {
        SelectMode::Auto | SelectMode::Vertex => members
            .vertices
            .iter()
            .copied()
            .filter(|&v| inside(m.position(v)) && m.vertex_faces(v).any(facing))
            .map(ElementId::Vertex)
            .collect(),
        SelectMode::Edge | SelectMode::Halfedge => members
            .edges
            .iter()
            .copied()
            .filter(|&e| {
                let h = m.edge_halfedge(e);
                let (a, b) = m.edge_vertices(e);
                inside(m.position(a))
                    && inside(m.position(b))
                    && [h, m.twin(h)]
                        .into_iter()
                        .filter_map(|x| m.face(x))
                        .any(facing)
            })
            .map(ElementId::Edge)
            .collect(),
        SelectMode::Face => members
            .faces
            .iter()
            .copied()
            .filter(|&f| facing(f) && inside(m.face_centroid(f)))
            .map(ElementId::Face)
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    fn grid() -> (World, Vec<VertexId>) {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::quad_grid(4, 4), MeshInfo::default()).unwrap();
        let vs = built.input_vertices.iter().map(|v| v.unwrap()).collect();
        (world, vs)
    }

    #[test]
    fn growing_a_vertex_adds_its_neighbours_and_shrinking_takes_them_back() {
        let (world, vs) = grid();
        let m = MeshRef::new(&world);
        // Vertex 12 is the centre of the 5×5 grid of vertices.
        let centre = ElementId::Vertex(vs[12]);
        let ring = grow(&m, &[centre]);
        assert_eq!(ring.len(), 4);
        let mut set = vec![centre];
        set.extend(ring);
        assert_eq!(shrink(&m, &set), vec![centre]);
    }

    #[test]
    fn growing_a_face_adds_the_faces_around_its_corners() {
        let (world, vs) = grid();
        let m = MeshRef::new(&world);
        let f = m.face(m.find_halfedge(vs[6], vs[7]).unwrap()).unwrap();
        assert_eq!(
            grow(&m, &[ElementId::Face(f)]).len(),
            8,
            "a 3×3 block of quads"
        );
        assert!(shrink(&m, &[ElementId::Face(f)]).is_empty());
    }

    #[test]
    fn toggling_follows_blender() {
        let (world, vs) = grid();
        let _ = world;
        let (a, b) = (ElementId::Vertex(vs[0]), ElementId::Vertex(vs[1]));
        let mut s = Selection::default();
        s.select_only(Some(a));
        s.toggle(b);
        assert_eq!((s.len(), s.element), (2, Some(b)));
        s.toggle(a);
        assert_eq!(
            (s.len(), s.element),
            (2, Some(a)),
            "a selected element becomes active"
        );
        s.toggle(a);
        assert_eq!(
            (s.len(), s.element),
            (1, Some(b)),
            "the active one leaves the set"
        );
        assert_eq!(describe(&s), "1 vertex selected");
    }
}
