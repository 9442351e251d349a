//! Validating an edit by what it touched: the same rules and messages as
//! [`validate`](super::validate::validate), checked on the elements an edit of a valid mesh
//! can have broken, so that a commit costs what the edit touched, not what the mesh holds.
//!
//! Every rule of `validate` reads one element's links and those of the elements they name, and
//! three rules count the halfedges that name an element (two on an edge, a face's loop, the
//! halfedges leaving a vertex). If the mesh was valid before the edit, a rule can fail after it
//! only for an element that was changed, made or removed, or that reads or is counted by one:
//!
//! - halfedges: each changed or new halfedge, and the `twin`, `next` and `prev` of each
//!   changed or removed one, before the edit and after (a halfedge's rules read exactly its
//!   own links and those of these three; links are mutual in a valid mesh, so an unchanged
//!   halfedge naming a changed one was named by it before);
//! - halfedges that named a removed element before the edit (its edge's two halfedges, its
//!   face's loop, the halfedges into a removed vertex), whose links now dangle;
//! - edges, faces and vertices: each changed or new one, and, for every halfedge above, its
//!   edge, face, head and tail before the edit and after.
//!
//! The counts are kept by difference: the halfedges naming an element now are those that named
//! it before (its two halfedges, its loop, its fan, read as they were) and did not change, plus
//! the changed ones that name it now. Loops and fans are walked with a bound of the world's
//! entity count, so no walk runs forever whatever the links say.

use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::prelude::{Component, Entity, World};

use super::elements::{Edge, Face, Halfedge, InMesh, Vertex};
use super::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use super::topology::MeshRef;
use super::validate::{Checker, Invalid, Rule, fail};

/// The mesh before an edit, as far as the edit changed it: each changed element's links as
/// they were (the first value its journal overwrote), and the elements the edit made. Every
/// element not named here is as it was.
#[derive(Default)]
pub struct Before {
    /// Halfedges changed, as they were.
    pub halfedges: EntityHashMap<Halfedge>,
    /// Vertices whose halfedge changed, as they were.
    pub vertices: EntityHashMap<Vertex>,
    /// Vertices moved.
    pub moved: EntityHashSet,
    /// Edges changed, as they were.
    pub edges: EntityHashMap<Edge>,
    /// Faces changed, as they were.
    pub faces: EntityHashMap<Face>,
    /// Elements made by the edit (they did not exist before).
    pub made: EntityHashSet,
}

/// Checks `mesh`, valid before the edit `before` describes, as though `removed` were gone:
/// [`validate_without`](super::validate::validate_without)'s verdict, at the cost of what the
/// edit touched.
///
/// # Errors
/// A broken rule, with an element that breaks it (where several are broken, not always the
/// one the whole check names first).
pub fn validate_edit(
    world: &World,
    mesh: MeshId,
    removed: &EntityHashSet,
    before: &Before,
) -> Result<(), Invalid> {
    let limit = world.entities().len() as usize + 1;
    let checker = Checker::new(world, mesh, removed, limit);
    let was = Was { world, before };
    let region = Region::of(&was, removed, limit);
    for &h in &region.halfedges {
        checker.check_links(h)?;
    }
    for &h in &region.halfedges {
        checker.check_halfedge(h)?;
    }
    let m = MeshRef::new(world);
    let changed =
        |h: &HalfedgeId| before.halfedges.contains_key(&h.0) || before.made.contains(&h.0);
    // The halfedges whose edge, face or tail may differ from before: checked live above.
    let altered: Vec<HalfedgeId> = region.halfedges.iter().copied().filter(changed).collect();
    for &e in &region.edges {
        let kept = was
            .edge_halfedges(e)
            .into_iter()
            .filter(|h| !changed(h) && !removed.contains(&h.0))
            .count();
        let now = altered.iter().filter(|&&h| m.edge(h) == e).count();
        checker.check_edge(e, (kept + now) as u32)?;
    }
    let mut seen = Vec::new();
    for &f in &region.faces {
        let kept = was
            .face_loop(f, limit)
            .into_iter()
            .filter(|h| !changed(h) && !removed.contains(&h.0))
            .count();
        let now = altered.iter().filter(|&&h| m.face(h) == Some(f)).count();
        checker.check_face(f, (kept + now) as u32, &mut seen)?;
    }
    // A halfedge's tail is its twin's head: it moves with either.
    let tail_moved = |h: &HalfedgeId| changed(h) || changed(&m.twin(*h)) || removed.contains(&h.0);
    let retailed: Vec<HalfedgeId> = region
        .halfedges
        .iter()
        .copied()
        .filter(tail_moved)
        .collect();
    let retailed_set: EntityHashSet = retailed.iter().map(|h| h.0).collect();
    for &v in &region.vertices {
        let kept = was
            .leaving(v, limit)
            .into_iter()
            .filter(|h| !retailed_set.contains(&h.0) && !removed.contains(&h.0))
            .count();
        let now = retailed.iter().filter(|&&h| m.from_vertex(h) == v).count();
        checker.check_vertex(v, (kept + now) as u32, &mut seen)?;
    }
    let mut visited = EntityHashSet::default();
    for &h in &region.halfedges {
        if m.is_boundary(h) && !visited.contains(&h.0) {
            checker.check_boundary_loop(h, &mut visited)?;
        }
    }
    let faces_gone = removed.iter().any(|&e| world.get::<Face>(e).is_some());
    if faces_gone && !any_face_left(world, mesh, removed) {
        return fail(mesh, Rule::Empty);
    }
    Ok(())
}

/// Whether `mesh` has a face not in `removed` (looked for only when the edit removed faces).
fn any_face_left(world: &World, mesh: MeshId, removed: &EntityHashSet) -> bool {
    let Some(mut query) = world.try_query::<(Entity, &InMesh, &Face)>() else {
        return false;
    };
    query
        .iter(world)
        .any(|(e, m, _)| m.0 == mesh && !removed.contains(&e))
}

/// Reads the mesh as it was before the edit.
struct Was<'a> {
    world: &'a World,
    before: &'a Before,
}

impl Was<'_> {
    /// Element `e`'s `C` before the edit: its first journalled value where the edit changed
    /// it, else as it is now (`None`: made by the edit, or no such element).
    fn component<C: Component + Copy>(&self, e: Entity, changed: &EntityHashMap<C>) -> Option<C> {
        if self.before.made.contains(&e) {
            return None;
        }
        match changed.get(&e) {
            Some(&x) => Some(x),
            None => self.world.get::<C>(e).copied(),
        }
    }

    /// `h`'s links before the edit (`None`: made by it, or no halfedge).
    fn halfedge(&self, h: HalfedgeId) -> Option<Halfedge> {
        self.component(h.0, &self.before.halfedges)
    }

    /// The halfedges on `e` before the edit (none for an edge it made).
    fn edge_halfedges(&self, e: EdgeId) -> Vec<HalfedgeId> {
        let Some(h) = self.component(e.0, &self.before.edges).map(|x| x.halfedge) else {
            return Vec::new();
        };
        let mut on = vec![h];
        on.extend(self.halfedge(h).map(|x| x.twin));
        on
    }

    /// `f`'s loop before the edit (empty for a face it made).
    fn face_loop(&self, f: FaceId, limit: usize) -> Vec<HalfedgeId> {
        let Some(start) = self.component(f.0, &self.before.faces).map(|x| x.halfedge) else {
            return Vec::new();
        };
        self.walk(start, limit, |x| x.next)
    }

    /// The halfedges leaving `v` before the edit (none for a vertex it made).
    fn leaving(&self, v: VertexId, limit: usize) -> Vec<HalfedgeId> {
        let Some(start) = self
            .component(v.0, &self.before.vertices)
            .map(|x| x.halfedge)
        else {
            return Vec::new();
        };
        // Counter-clockwise: twin(prev(h)).
        self.walk(start, limit, |x| {
            self.halfedge(x.prev).map_or(x.prev, |p| p.twin)
        })
    }

    /// The halfedges from `start` along `step`, as they were, until `start` comes round again
    /// (at most `limit`).
    fn walk(
        &self,
        start: HalfedgeId,
        limit: usize,
        step: impl Fn(Halfedge) -> HalfedgeId,
    ) -> Vec<HalfedgeId> {
        let mut out = Vec::new();
        let mut h = start;
        while let Some(x) = self.halfedge(h) {
            out.push(h);
            h = step(x);
            if h == start || out.len() > limit {
                break;
            }
        }
        out
    }
}

/// The elements whose rules an edit may have broken (see the module doc), without the removed
/// ones; each list in a fixed order, free of repeats.
struct Region {
    halfedges: Vec<HalfedgeId>,
    edges: Vec<EdgeId>,
    faces: Vec<FaceId>,
    vertices: Vec<VertexId>,
}

impl Region {
    fn of(was: &Was<'_>, removed: &EntityHashSet, limit: usize) -> Region {
        let before = was.before;
        let world = was.world;
        let mut halfedges = Unique::default();
        let mut edges = Unique::default();
        let mut faces = Unique::default();
        let mut vertices = Unique::default();
        let is = |e: Entity, kind: fn(&World, Entity) -> bool| kind(world, e);
        let halfedge = |w: &World, e: Entity| w.get::<Halfedge>(e).is_some();
        let edge = |w: &World, e: Entity| w.get::<Edge>(e).is_some();
        let face = |w: &World, e: Entity| w.get::<Face>(e).is_some();
        let vertex = |w: &World, e: Entity| w.get::<Vertex>(e).is_some();
        // Changed and made halfedges, and removed ones, with what they name now and named.
        let mut seeds: Vec<HalfedgeId> = before.halfedges.keys().map(|&e| HalfedgeId(e)).collect();
        seeds.extend(
            before
                .made
                .iter()
                .chain(removed)
                .filter(|&&e| is(e, halfedge))
                .map(|&e| HalfedgeId(e)),
        );
        seeds.sort_unstable();
        seeds.dedup();
        for &g in &seeds {
            halfedges.add(g.0);
            let now = world.get::<Halfedge>(g.0).copied();
            for x in [was.halfedge(g), now].into_iter().flatten() {
                for h in [x.twin, x.next, x.prev] {
                    halfedges.add(h.0);
                }
            }
        }
        // Halfedges that named a removed edge, face or vertex.
        for &e in removed {
            let named: Vec<HalfedgeId> = if is(e, edge) {
                was.edge_halfedges(EdgeId(e))
            } else if is(e, face) {
                was.face_loop(FaceId(e), limit)
            } else if is(e, vertex) {
                was.leaving(VertexId(e), limit)
                    .into_iter()
                    .filter_map(|h| was.halfedge(h).map(|x| x.twin))
                    .collect()
            } else {
                Vec::new()
            };
            for h in named {
                halfedges.add(h.0);
            }
        }
        // Edges, faces and vertices changed or made, and those the halfedges name.
        for &e in before.edges.keys().chain(before.made.iter()) {
            if is(e, edge) {
                edges.add(e);
            }
        }
        for &e in before.faces.keys().chain(before.made.iter()) {
            if is(e, face) {
                faces.add(e);
            }
        }
        for &e in before
            .vertices
            .keys()
            .chain(&before.moved)
            .chain(before.made.iter())
        {
            if is(e, vertex) {
                vertices.add(e);
            }
        }
        for &h in &halfedges.list {
            let h = HalfedgeId(h);
            let now = world.get::<Halfedge>(h.0).copied();
            for x in [was.halfedge(h), now].into_iter().flatten() {
                edges.add(x.edge.0);
                if let Some(f) = x.face {
                    faces.add(f.0);
                }
                vertices.add(x.vertex.0);
                // The tail: the twin's head, before and now.
                let twins = [
                    was.halfedge(x.twin),
                    world.get::<Halfedge>(x.twin.0).copied(),
                ];
                for t in twins.into_iter().flatten() {
                    vertices.add(t.vertex.0);
                }
            }
        }
        let keep = |e: &Entity, kind: fn(&World, Entity) -> bool| {
            !removed.contains(e) && is(*e, kind) && world.get::<InMesh>(*e).is_some()
        };
        Region {
            halfedges: halfedges
                .take(|e| keep(e, halfedge))
                .map(HalfedgeId)
                .collect(),
            edges: edges.take(|e| keep(e, edge)).map(EdgeId).collect(),
            faces: faces.take(|e| keep(e, face)).map(FaceId).collect(),
            vertices: vertices.take(|e| keep(e, vertex)).map(VertexId).collect(),
        }
    }
}

/// Entities in the order first added, each once.
#[derive(Default)]
struct Unique {
    list: Vec<Entity>,
    set: EntityHashSet,
}

impl Unique {
    fn add(&mut self, e: Entity) {
        if e != Entity::PLACEHOLDER && self.set.insert(e) {
            self.list.push(e);
        }
    }

    fn take(self, keep: impl Fn(&Entity) -> bool) -> impl Iterator<Item = Entity> {
        self.list.into_iter().filter(move |e| keep(e))
    }
}
