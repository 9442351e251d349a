//! What is selected, what is under the pointer, walking the halfedge relations, and the marks
//! an edit leaves on a mesh for the render sync ([`MeshDirty`], [`DirtyFaces`]).

use bevy::ecs::entity::EntityHashSet;
use bevy::prelude::{Component, Resource, World};

use crate::mesh::ids::{EdgeId, ElementId, FaceId, MeshId};
use crate::mesh::topology::MeshRef;

use super::requests::Relation;

/// What is selected: the active element (the one the inspector shows and relations walk
/// from) and the selected set that operations act on.
///
/// The active element, when there is one, is always in the set. The set keeps the order
/// elements were added in (welding takes the first two edges). Ids of elements an edit removed
/// drop out of the set after the edit ([`Selection::retain`]).
#[derive(Resource, Default, Debug, Clone)]
pub struct Selection {
    /// The active element.
    pub element: Option<ElementId>,
    set: Vec<ElementId>,
    members: EntityHashSet,
}

impl Selection {
    /// Selects `element` alone (or nothing).
    pub fn select_only(&mut self, element: Option<ElementId>) {
        self.set.clear();
        self.members.clear();
        self.element = None;
        if let Some(x) = element {
            self.add(x);
        }
    }

    /// Adds `x` to the set and makes it active.
    pub fn add(&mut self, x: ElementId) {
        if self.members.insert(x.entity()) {
            self.set.push(x);
        }
        self.element = Some(x);
    }

    /// Adds elements to the set; the last one added becomes active if none is.
    pub fn extend(&mut self, elements: impl IntoIterator<Item = ElementId>) {
        for x in elements {
            if self.members.insert(x.entity()) {
                self.set.push(x);
            }
        }
        if self.element.is_none() {
            self.element = self.set.last().copied();
        }
    }

    /// Shift-click, as in Blender: an element outside the set joins it and becomes active; a
    /// selected element that is not active becomes active; the active element leaves the set
    /// (the most recently added one left becomes active).
    pub fn toggle(&mut self, x: ElementId) {
        if !self.contains(x) || self.element != Some(x) {
            self.add(x);
            return;
        }
        self.members.remove(&x.entity());
        self.set.retain(|&y| y != x);
        self.element = self.set.last().copied();
    }

    /// Whether `x` is in the set.
    pub fn contains(&self, x: ElementId) -> bool {
        self.members.contains(&x.entity())
    }

    /// The selected elements, in the order they were added.
    pub fn elements(&self) -> &[ElementId] {
        &self.set
    }

    /// How many elements are selected.
    pub fn len(&self) -> usize {
        self.set.len()
    }

    /// Whether nothing is selected.
    pub fn is_empty(&self) -> bool {
        self.set.is_empty()
    }

    /// Keeps the elements for which `keep` holds (the active one too, or it is cleared and the
    /// most recently added survivor takes its place).
    pub fn retain(&mut self, mut keep: impl FnMut(ElementId) -> bool) {
        let members = &mut self.members;
        self.set.retain(|&x| {
            let kept = keep(x);
            if !kept {
                members.remove(&x.entity());
            }
            kept
        });
        if self
            .element
            .is_some_and(|x| !self.members.contains(&x.entity()))
        {
            self.element = self.set.last().copied();
        }
    }

    /// Counts of the set by kind: vertices, edges (halfedges count as their edges), faces.
    pub fn counts(&self) -> [usize; 3] {
        let mut counts = [0; 3];
        for x in &self.set {
            match x {
                ElementId::Vertex(_) => counts[0] += 1,
                ElementId::Edge(_) | ElementId::Halfedge(_) => counts[1] += 1,
                ElementId::Face(_) => counts[2] += 1,
                ElementId::Mesh(_) => {}
            }
        }
        counts
    }
}

/// The element under the pointer, if any.
#[derive(Resource, Default, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Hover {
    /// The element.
    pub element: Option<ElementId>,
}

/// Which kind of element a click picks (keys 1–4 and the backquote, as in Blender).
#[derive(Resource, Default, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SelectMode {
    /// Whatever is nearest: a vertex if the click is near one, else an edge if near one, else
    /// the face.
    #[default]
    Auto,
    /// Vertices only.
    Vertex,
    /// Edges only.
    Edge,
    /// Faces only.
    Face,
    /// Halfedges only (the side of the edge the click is on).
    Halfedge,
}

impl SelectMode {
    /// Its name as shown to the user.
    pub fn name(self) -> &'static str {
        match self {
            SelectMode::Auto => "auto",
            SelectMode::Vertex => "vertex",
            SelectMode::Edge => "edge",
            SelectMode::Face => "face",
            SelectMode::Halfedge => "halfedge",
        }
    }
}

/// The mesh being edited.
#[derive(Resource, Default, Debug, Clone, Copy, PartialEq, Eq)]
pub struct ActiveMesh(pub Option<MeshId>);

/// Marks a mesh whose vertices moved and nothing else changed: its render copy keeps its
/// triangles and refreshes its positions (set by a move of most of the mesh, cleared by
/// render sync).
#[derive(Component, Default, Debug, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct PositionsDirty;

/// Marks a mesh whose render copy must be rebuilt (set by every edit, cleared by render sync).
#[derive(Component, Default, Debug, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct MeshDirty;

/// Marks a mesh whose render copy must be drawn anew though its geometry is as drawn: the
/// shading, the checkerboard, the wireframe shown or the colouring changed (cleared by render
/// sync). It is redrawn whole, but its chunks keep the record of what changed them, so the
/// closure counted before still holds (see the editor's culling). With an edit pending too
/// ([`MeshDirty`], [`DirtyFaces`], [`PositionsDirty`]) it is one more edit's redraw.
#[derive(Component, Default, Debug, Clone, Copy)]
#[component(storage = "SparseSet")]
pub struct LooksDirty;

/// Faces whose drawing must be redone (set by local edits; the render sync rebuilds only the
/// chunks holding them). Dead faces are dropped from their chunks.
#[derive(Component, Debug, Clone, Default)]
#[component(storage = "SparseSet")]
pub struct DirtyFaces(pub Vec<FaceId>);

/// Marks `faces` of `mesh` for redrawing (adding to those already marked).
pub fn mark_faces_dirty(world: &mut World, mesh: MeshId, faces: Vec<FaceId>) {
    let mut entity = world.entity_mut(mesh.0);
    match entity.get_mut::<DirtyFaces>() {
        Some(mut dirty) => dirty.0.extend(faces),
        None => {
            entity.insert(DirtyFaces(faces));
        }
    }
}

/// The live faces of the selected set, in selection order.
pub fn selected_faces(world: &World) -> Vec<FaceId> {
    let m = MeshRef::new(world);
    world
        .resource::<Selection>()
        .elements()
        .iter()
        .filter_map(|&x| match x {
            ElementId::Face(f) if m.try_face(f).is_some() => Some(f),
            _ => None,
        })
        .collect()
}

/// Drops from the selection every element that is gone or that `keep` rejects (after an edit).
pub fn keep_live_selection(world: &mut World, keep: impl Fn(ElementId) -> bool) {
    let mut selection = std::mem::take(&mut *world.resource_mut::<Selection>());
    let m = MeshRef::new(world);
    selection.retain(|x| keep(x) && exists(&m, x));
    *world.resource_mut::<Selection>() = selection;
}

/// Whether `element` is alive in the world behind `m`.
pub fn exists(m: &MeshRef<'_>, element: ElementId) -> bool {
    m.exists(element)
}

/// The element reached from `from` along `relation`, or `None` where the relation leads nowhere
/// (the face of a boundary halfedge) or `from` no longer exists.
///
/// Halfedges have every relation. Other elements first step to their halfedge (a vertex's
/// outgoing one, an edge's, a face's) and follow the relation from there, so `vertex` of a face
/// is the tip of its halfedge and `next` of a vertex is the halfedge after its outgoing one.
pub fn navigate(m: &MeshRef<'_>, from: ElementId, relation: Relation) -> Option<ElementId> {
    if !exists(m, from) {
        return None;
    }
    let h = match from {
        ElementId::Halfedge(h) => h,
        ElementId::Vertex(v) => m.vertex_halfedge(v),
        ElementId::Edge(e) => m.edge_halfedge(e),
        ElementId::Face(f) => m.face_halfedge(f),
        ElementId::Mesh(_) => return None,
    };
    let is_halfedge = matches!(from, ElementId::Halfedge(_));
    Some(match relation {
        Relation::Halfedge => ElementId::Halfedge(h),
        Relation::Twin => ElementId::Halfedge(m.twin(h)),
        Relation::Next => ElementId::Halfedge(m.next(h)),
        Relation::Prev => ElementId::Halfedge(m.prev(h)),
        // A vertex's "vertex" is the neighbour its outgoing halfedge points to.
        Relation::Vertex => ElementId::Vertex(m.to_vertex(h)),
        Relation::Edge => ElementId::Edge(m.edge(h)),
        Relation::Face => {
            let face = m
                .face(h)
                .or_else(|| (!is_halfedge).then(|| m.face(m.twin(h))).flatten());
            ElementId::Face(face?)
        }
    })
}

/// The edge under a selection, for operations on edges: the edge itself, or a halfedge's edge.
pub fn selected_edge(m: &MeshRef<'_>, selection: Option<ElementId>) -> Option<EdgeId> {
    match selection? {
        ElementId::Edge(e) => m.try_edge(e).map(|_| e),
        ElementId::Halfedge(h) => m.try_halfedge(h).map(|x| x.edge),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    #[test]
    fn relations_follow_the_halfedge_links() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(2, 2), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        let corner = built.input_vertices[0].unwrap();
        let h = m.vertex_halfedge(corner);
        assert!(m.is_boundary(h));
        let go = |x, r| navigate(&m, x, r);
        let hx = ElementId::Halfedge(h);
        assert_eq!(go(ElementId::Vertex(corner), Relation::Halfedge), Some(hx));
        assert_eq!(go(hx, Relation::Twin), Some(ElementId::Halfedge(m.twin(h))));
        assert_eq!(go(hx, Relation::Next), Some(ElementId::Halfedge(m.next(h))));
        assert_eq!(go(hx, Relation::Prev), Some(ElementId::Halfedge(m.prev(h))));
        assert_eq!(go(hx, Relation::Edge), Some(ElementId::Edge(m.edge(h))));
        assert_eq!(
            go(hx, Relation::Face),
            None,
            "a boundary halfedge has no face"
        );
        let inner = m.twin(h);
        assert_eq!(
            go(ElementId::Halfedge(inner), Relation::Face),
            m.face(inner).map(ElementId::Face)
        );
        // An edge on the boundary still reaches its one face.
        assert!(go(ElementId::Edge(m.edge(h)), Relation::Face).is_some());
    }
}
