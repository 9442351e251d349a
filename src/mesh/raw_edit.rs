//! A checked low-level edit: rewire a mesh's links by hand, then commit one valid edit or roll
//! back to exactly the mesh before.
//!
//! The course labs have students write flip, split and collapse as pointer surgery on a
//! halfedge structure (Scotty3D's `Halfedge_Mesh`, CMU 15-462; OpenMesh's low-level setters).
//! Halfway through such an edit the mesh is invalid by necessity, so no check can run per
//! setter: [`RawEdit`] lets every link be set freely, journals the value each setter overwrote,
//! and checks the structure once, at [`RawEdit::commit`], with the rules and messages of
//! [`validate`](super::validate::validate), on what the edit touched ([`validate_edit`]: the
//! mesh was valid when the edit opened, as every mesh Pappus holds is). A failed check undoes
//! the journal in reverse, so the world holds exactly the components it held before (compared
//! element by element in the tests). A snapshot could not do this: the table extraction
//! assumes a valid mesh, and mid-edit the mesh is not one.
//!
//! Elements made here start unlinked (their links name no entity, which the check reports as a
//! dangling link until they are set). A removed element is no setter's argument from then on,
//! and the commit checks the mesh as though it were gone ([`validate_without`](super::validate::validate_without): a link still
//! naming it is dangling) before it despawns it; until then no component moves, so a rollback
//! leaves even the world's storage order as it was. An edit dropped without a commit rolls
//! back, so an early return or a panic never leaves a half-rewired mesh.
//!
//! Setters follow PMP's convention: [`RawEdit::set_next`] sets the next's `prev` too, and
//! [`RawEdit::set_twin`] both twins; every other setter sets one link. New elements carry no
//! attributes (UVs, colours, normals).

use bevy::ecs::component::Mutable;
use bevy::math::Vec3;
use bevy::prelude::{Component, Entity, World};
use thiserror::Error;

use super::elements::{Edge, Face, Halfedge, InMesh, Position, Vertex};
use super::ids::{EdgeId, ElementId, FaceId, HalfedgeId, MeshId, VertexId};
use super::validate::Invalid;
use super::validate_edit::{Before, validate_edit};
use bevy::ecs::entity::EntityHashSet;

/// Why a raw edit refused a setter or its commit.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum RawEditError {
    /// The element is not one of this mesh's now (removed, of another mesh, never one, or of
    /// another kind than the setter takes).
    #[error("{0} is not an element of this mesh")]
    NotInMesh(ElementId),
    /// A position that is not finite.
    #[error("{0} cannot be put at {1}: not a finite position")]
    NotFinite(ElementId, Vec3),
    /// A new vertex's position that is not finite.
    #[error("a new vertex cannot be put at {0}: not a finite position")]
    NewVertexNotFinite(Vec3),
    /// The commit's check found a broken rule; the edit was rolled back.
    #[error("{0}")]
    Invalid(#[from] Invalid),
}

/// One undo of the journal: the value a setter overwrote, or what making or removing did.
enum Undo {
    Halfedge(HalfedgeId, Halfedge),
    Vertex(VertexId, Vertex),
    Position(VertexId, Position),
    Edge(EdgeId, Edge),
    Face(FaceId, Face),
    /// An entity spawned here: despawned by a rollback.
    Spawned(Entity),
}

/// An open edit's journal, apart from the world: what [`RawEdit::suspend`] gives and
/// [`RawEdit::resume`] takes back, so that an edit can stay open between calls (Python's
/// `with mesh.edit()` block) without the world borrowed all along. Dropped on its own it
/// undoes nothing: resume it and roll back.
pub struct Journal {
    mesh: MeshId,
    undo: Vec<Undo>,
    /// The elements removed: the commit despawns them.
    removed: EntityHashSet,
}

impl Journal {
    /// The mesh the edit is of.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }

    /// What the edit changed, as it was before: each element's first journalled value, and
    /// the elements made.
    fn before(&self) -> Before {
        let mut before = Before::default();
        for undo in &self.undo {
            match *undo {
                Undo::Halfedge(h, x) => {
                    before.halfedges.entry(h.0).or_insert(x);
                }
                Undo::Vertex(v, x) => {
                    before.vertices.entry(v.0).or_insert(x);
                }
                Undo::Position(v, _) => {
                    before.moved.insert(v.0);
                }
                Undo::Edge(e, x) => {
                    before.edges.entry(e.0).or_insert(x);
                }
                Undo::Face(f, x) => {
                    before.faces.entry(f.0).or_insert(x);
                }
                Undo::Spawned(e) => {
                    before.made.insert(e);
                }
            }
        }
        before
    }
}

/// An open low-level edit of one mesh (see the module doc). Dropped without
/// [`RawEdit::commit`] or [`RawEdit::suspend`], it rolls back.
pub struct RawEdit<'w> {
    world: &'w mut World,
    journal: Journal,
    /// Whether the edit has been committed, rolled back or suspended.
    closed: bool,
}

impl<'w> RawEdit<'w> {
    /// Opens an edit of `mesh`, an existing mesh of `world`.
    pub fn new(world: &'w mut World, mesh: MeshId) -> Self {
        let journal = Journal {
            mesh,
            undo: Vec::new(),
            removed: EntityHashSet::default(),
        };
        Self::resume(world, journal)
    }

    /// Takes up an edit [`RawEdit::suspend`] set aside, on the world it was made in.
    pub fn resume(world: &'w mut World, journal: Journal) -> Self {
        Self {
            world,
            journal,
            closed: false,
        }
    }

    /// Sets the edit aside, open: its changes stay in the world and in the journal returned,
    /// for [`RawEdit::resume`] to take up.
    pub fn suspend(mut self) -> Journal {
        self.closed = true;
        let mesh = self.journal.mesh;
        std::mem::replace(
            &mut self.journal,
            Journal {
                mesh,
                undo: Vec::new(),
                removed: EntityHashSet::default(),
            },
        )
    }

    /// The world as it stands mid-edit (links may be broken: read with care).
    pub fn world(&self) -> &World {
        self.world
    }

    /// `x`'s entity when it is an element of this mesh now, of the kind `C` marks.
    fn member<C: Component>(&self, x: impl Into<ElementId>) -> Result<Entity, RawEditError> {
        let x = x.into();
        let e = self.world.get_entity(x.entity()).ok();
        match e {
            Some(e)
                if e.contains::<C>()
                    && e.get::<InMesh>() == Some(&InMesh(self.journal.mesh))
                    && !self.journal.removed.contains(&e.id()) =>
            {
                Ok(e.id())
            }
            _ => Err(RawEditError::NotInMesh(x)),
        }
    }

    /// Changes `x`'s `C` by `change`, journalling the value before.
    fn change<C: Component<Mutability = Mutable> + Copy>(
        &mut self,
        x: Entity,
        undo: fn(Entity, C) -> Undo,
        change: impl FnOnce(&mut C),
    ) {
        let mut component = self
            .world
            .get_mut::<C>(x)
            .expect("a member has its kind's component");
        self.journal.undo.push(undo(x, *component));
        change(&mut component);
    }

    /// Sets `h`'s next to `next`, and `next`'s prev to `h`.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for a halfedge not of this mesh; nothing changes.
    pub fn set_next(&mut self, h: HalfedgeId, next: HalfedgeId) -> Result<(), RawEditError> {
        let (a, b) = (self.member::<Halfedge>(h)?, self.member::<Halfedge>(next)?);
        self.change(a, halfedge_undo, |x: &mut Halfedge| x.next = next);
        self.change(b, halfedge_undo, |x: &mut Halfedge| x.prev = h);
        Ok(())
    }

    /// Makes `a` and `b` each other's twin.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for a halfedge not of this mesh; nothing changes.
    pub fn set_twin(&mut self, a: HalfedgeId, b: HalfedgeId) -> Result<(), RawEditError> {
        let (ea, eb) = (self.member::<Halfedge>(a)?, self.member::<Halfedge>(b)?);
        self.change(ea, halfedge_undo, |x: &mut Halfedge| x.twin = b);
        self.change(eb, halfedge_undo, |x: &mut Halfedge| x.twin = a);
        Ok(())
    }

    /// Sets the vertex `h` points to.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_to_vertex(&mut self, h: HalfedgeId, v: VertexId) -> Result<(), RawEditError> {
        let e = self.member::<Halfedge>(h)?;
        self.member::<Vertex>(v)?;
        self.change(e, halfedge_undo, |x: &mut Halfedge| x.vertex = v);
        Ok(())
    }

    /// Sets `h`'s edge.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_edge(&mut self, h: HalfedgeId, edge: EdgeId) -> Result<(), RawEditError> {
        let e = self.member::<Halfedge>(h)?;
        self.member::<Edge>(edge)?;
        self.change(e, halfedge_undo, |x: &mut Halfedge| x.edge = edge);
        Ok(())
    }

    /// Sets `h`'s face (`None`: a boundary halfedge).
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_face(&mut self, h: HalfedgeId, face: Option<FaceId>) -> Result<(), RawEditError> {
        let e = self.member::<Halfedge>(h)?;
        if let Some(f) = face {
            self.member::<Face>(f)?;
        }
        self.change(e, halfedge_undo, |x: &mut Halfedge| x.face = face);
        Ok(())
    }

    /// Sets a vertex's outgoing halfedge.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_vertex_halfedge(&mut self, v: VertexId, h: HalfedgeId) -> Result<(), RawEditError> {
        let e = self.member::<Vertex>(v)?;
        self.member::<Halfedge>(h)?;
        self.change(
            e,
            |e, x| Undo::Vertex(VertexId(e), x),
            |x: &mut Vertex| {
                x.halfedge = h;
            },
        );
        Ok(())
    }

    /// Sets an edge's halfedge.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_edge_halfedge(&mut self, edge: EdgeId, h: HalfedgeId) -> Result<(), RawEditError> {
        let e = self.member::<Edge>(edge)?;
        self.member::<Halfedge>(h)?;
        self.change(
            e,
            |e, x| Undo::Edge(EdgeId(e), x),
            |x: &mut Edge| x.halfedge = h,
        );
        Ok(())
    }

    /// Sets a face's halfedge.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh; nothing changes.
    pub fn set_face_halfedge(&mut self, face: FaceId, h: HalfedgeId) -> Result<(), RawEditError> {
        let e = self.member::<Face>(face)?;
        self.member::<Halfedge>(h)?;
        self.change(
            e,
            |e, x| Undo::Face(FaceId(e), x),
            |x: &mut Face| x.halfedge = h,
        );
        Ok(())
    }

    /// Moves a vertex.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for a vertex not of this mesh, [`RawEditError::NotFinite`]
    /// for a position that is not finite; nothing changes.
    pub fn set_position(&mut self, v: VertexId, p: Vec3) -> Result<(), RawEditError> {
        let e = self.member::<Vertex>(v)?;
        if !p.is_finite() {
            return Err(RawEditError::NotFinite(v.into(), p));
        }
        self.change(
            e,
            |e, x| Undo::Position(VertexId(e), x),
            |x: &mut Position| {
                x.0 = p;
            },
        );
        Ok(())
    }

    /// A new vertex at `p`, its halfedge not set yet.
    ///
    /// # Errors
    /// [`RawEditError::NotFinite`] for a position that is not finite.
    pub fn new_vertex(&mut self, p: Vec3) -> Result<VertexId, RawEditError> {
        let unset = HalfedgeId(Entity::PLACEHOLDER);
        if !p.is_finite() {
            return Err(RawEditError::NewVertexNotFinite(p));
        }
        let v = self.spawn((Vertex { halfedge: unset }, Position(p)));
        Ok(VertexId(v))
    }

    /// A new edge and its two halfedges, each the other's twin and its own next and prev,
    /// pointing at no vertex, on no face: `(edge, first, second)`, the edge's halfedge the
    /// first.
    pub fn new_edge(&mut self) -> (EdgeId, HalfedgeId, HalfedgeId) {
        let unset = Entity::PLACEHOLDER;
        let edge = EdgeId(self.spawn(Edge {
            halfedge: HalfedgeId(unset),
        }));
        let a = HalfedgeId(self.world.spawn_empty().id());
        let b = HalfedgeId(self.world.spawn_empty().id());
        for (h, twin) in [(a, b), (b, a)] {
            self.world.entity_mut(h.0).insert((
                Halfedge {
                    twin,
                    next: h,
                    prev: h,
                    vertex: VertexId(unset),
                    edge,
                    face: None,
                },
                InMesh(self.journal.mesh),
            ));
            self.journal.undo.push(Undo::Spawned(h.0));
        }
        self.world
            .get_mut::<Edge>(edge.0)
            .expect("just spawned")
            .halfedge = a;
        (edge, a, b)
    }

    /// A new face, its halfedge not set yet.
    pub fn new_face(&mut self) -> FaceId {
        FaceId(self.spawn(Face {
            halfedge: HalfedgeId(Entity::PLACEHOLDER),
        }))
    }

    /// Spawns an element of this mesh, journalled.
    fn spawn(&mut self, components: impl bevy::prelude::Bundle) -> Entity {
        let e = self
            .world
            .spawn((components, InMesh(self.journal.mesh)))
            .id();
        self.journal.undo.push(Undo::Spawned(e));
        e
    }

    /// Takes `x` out of the mesh: links still naming it are dangling from now on; the commit
    /// despawns it.
    ///
    /// # Errors
    /// [`RawEditError::NotInMesh`] for an element not of this mesh now; nothing changes.
    pub fn remove(&mut self, x: impl Into<ElementId>) -> Result<(), RawEditError> {
        let x = x.into();
        let e = match x {
            ElementId::Vertex(_) => self.member::<Vertex>(x)?,
            ElementId::Halfedge(_) => self.member::<Halfedge>(x)?,
            ElementId::Edge(_) => self.member::<Edge>(x)?,
            ElementId::Face(_) => self.member::<Face>(x)?,
            ElementId::Mesh(_) => return Err(RawEditError::NotInMesh(x)),
        };
        self.journal.removed.insert(e);
        Ok(())
    }

    /// Checks the mesh with `validate`'s rules, as though the removed elements were gone, on
    /// what the edit touched ([`validate_edit`]: the mesh was valid when the edit opened, so
    /// the check costs what the edit changed, not the mesh's size): valid, the removed
    /// elements are despawned and the edit stands; else it is rolled back and a broken rule
    /// returned, naming its element. Debug builds check the whole mesh too
    /// ([`validate_without`](super::validate::validate_without)) and assert that the two
    /// agree.
    ///
    /// # Errors
    /// [`RawEditError::Invalid`]: the mesh is exactly as before the edit.
    pub fn commit(mut self) -> Result<(), RawEditError> {
        self.closed = true;
        let (world, journal) = (&*self.world, &self.journal);
        let verdict = validate_edit(world, journal.mesh, &journal.removed, &journal.before());
        #[cfg(any(debug_assertions, feature = "checked"))]
        {
            let whole = super::validate::validate_without(world, journal.mesh, &journal.removed);
            assert_eq!(
                verdict.is_ok(),
                whole.is_ok(),
                "the edit's check ({verdict:?}) and the whole mesh's ({whole:?}) disagree"
            );
        }
        if let Err(invalid) = verdict {
            self.undo();
            return Err(invalid.into());
        }
        self.journal.undo.clear();
        for e in std::mem::take(&mut self.journal.removed) {
            self.world.despawn(e);
        }
        Ok(())
    }

    /// Undoes every change: the mesh is exactly as before the edit.
    pub fn rollback(mut self) {
        self.closed = true;
        self.undo();
    }

    /// Undoes the journal, newest first.
    fn undo(&mut self) {
        while let Some(undo) = self.journal.undo.pop() {
            match undo {
                Undo::Halfedge(h, x) => self.restore(h.0, x),
                Undo::Vertex(v, x) => self.restore(v.0, x),
                Undo::Position(v, x) => self.restore(v.0, x),
                Undo::Edge(e, x) => self.restore(e.0, x),
                Undo::Face(f, x) => self.restore(f.0, x),
                Undo::Spawned(e) => {
                    self.world.despawn(e);
                }
            }
        }
        self.journal.removed.clear();
    }

    /// Puts back a component's earlier value.
    fn restore<C: Component<Mutability = Mutable>>(&mut self, e: Entity, value: C) {
        *self
            .world
            .get_mut::<C>(e)
            .expect("a journalled element is live") = value;
    }
}

/// The journal entry for a halfedge's earlier value.
fn halfedge_undo(e: Entity, x: Halfedge) -> Undo {
    Undo::Halfedge(HalfedgeId(e), x)
}

impl Drop for RawEdit<'_> {
    fn drop(&mut self) {
        if !self.closed {
            self.undo();
        }
    }
}
