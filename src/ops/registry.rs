//! The registry of operations and quantities: one list of each for the whole process, which the
//! command line's step parser and `--quantity`, Python's `pappus.operations()`, `Mesh.run` and
//! `Mesh.quantity`, the editor's keymap, panel, colouring and step mode all read, and which
//! take operations and quantities at run time.
//!
//! Pappus's own operations ([`BUILT_IN`]) register through the same door as one written in
//! another crate, a test or a student's lab ([`register`]); in the editor, through
//! `App::add_operation` (`crate::editor::AddOperation`). The registry lives outside any Bevy
//! `World` because the command line parses its steps and Python lists its operations with no
//! World at hand. Registering leaks the operation (it is needed for the life of the process,
//! and the list hands out `&'static` references), and a read costs one reference count: the
//! list is swapped whole on a registration, never changed in place.
//!
//! Two operations may share a step name only when they name different kinds of element
//! (`collapse` an edge or a face); they may share a key only when they share the name (C
//! collapses what is selected). Anything else is a [`Clash`], refused with both operations
//! named, and the registry is left as it was.
//!
//! ```
//! use bevy::prelude::World;
//! use pappus::mesh::MeshId;
//! use pappus::ops::Refusal;
//! use pappus::ops::declaration::{Declaration, Names};
//! use pappus::ops::operation::{Applied, EditContext, MeshOperation, Values};
//!
//! /// Counts the faces, changing nothing.
//! struct CountFaces;
//!
//! const COUNT_FACES: Declaration = Declaration::new("count-faces")
//!     .titled("Count faces")
//!     .described("say how many faces the mesh has")
//!     .naming(Names::Mesh);
//!
//! impl MeshOperation for CountFaces {
//!     fn declaration(&self) -> &'static Declaration {
//!         &COUNT_FACES
//!     }
//!
//!     fn apply(
//!         &self,
//!         world: &mut World,
//!         mesh: MeshId,
//!         _: Values<'_>,
//!         _: &mut EditContext<'_>,
//!     ) -> Result<Applied, Refusal> {
//!         let faces = pappus::mesh::mesh_stats(world, mesh).faces;
//!         Ok(Applied::whole(format!("{faces} faces")))
//!     }
//! }
//!
//! pappus::ops::registry::register(CountFaces).unwrap();
//! assert!(pappus::ops::registry::operation("count-faces").is_some());
//! // Once is enough: a second registration of the same name and kind is refused.
//! let clash = pappus::ops::registry::register(CountFaces).err().unwrap();
//! assert!(clash.to_string().contains("Count faces"));
//! ```

use std::sync::{Arc, LazyLock, RwLock};

use bevy::ecs::world::WorldId;

use crate::mesh::ids::{EdgeId, ElementId, FaceId, VertexId};
use crate::ops::declaration::{Declaration, Names};
use crate::ops::geometry::quantity::{Quantity, VertexQuantity};
use crate::ops::operation::{Invocation, MeshOperation};
use crate::ops::{
    decimate, deform, geodesic, hole, local, normalize, param, remesh, reverse, smooth, subdivide,
    triangulate,
};

/// Pappus's own operations, registered first, in the order the panel, the help overlay and
/// the usage text list them: the whole-mesh operations, then the local ones on the elements
/// they name. Adding one is its module and one line here.
pub const BUILT_IN: &[&dyn MeshOperation] = &[
    &triangulate::Triangulate,
    &reverse::Reverse,
    &reverse::OrientOutside,
    &normalize::Normalize,
    &decimate::Simplify,
    &decimate::SimplifyFaces,
    &decimate::Refine,
    &subdivide::Subdivide(subdivide::Scheme::Loop),
    &subdivide::Subdivide(subdivide::Scheme::CatmullClark),
    &remesh::Remesh,
    &smooth::Smooth,
    &hole::FillHoles,
    &deform::Fair,
    &param::Parameterize,
    &local::Flip,
    &local::Split,
    &local::Bisect,
    &local::Collapse,
    &local::CollapseFace,
    &local::Dissolve,
    &local::DissolveVertex,
    &hole::FillHole,
    &local::ToggleSeam,
    &local::SplitFace,
    &decimate::VertexSplit,
    &local::Extrude,
    &local::Inset,
    &local::Bevel,
    &local::Erase,
    &local::Weld,
];

/// The registered operations, in the order they were registered: a slice to read, or to
/// iterate by value (a cheap copy: the list is shared, and a registration made meanwhile
/// shows in the next copy).
#[derive(Clone)]
pub struct Operations(Arc<[&'static dyn MeshOperation]>);

impl std::ops::Deref for Operations {
    type Target = [&'static dyn MeshOperation];

    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl IntoIterator for Operations {
    type Item = &'static dyn MeshOperation;
    type IntoIter = OperationsIter;

    fn into_iter(self) -> OperationsIter {
        OperationsIter { list: self, at: 0 }
    }
}

/// The registered operations one by one, holding the list it was made from.
pub struct OperationsIter {
    list: Operations,
    at: usize,
}

impl Iterator for OperationsIter {
    type Item = &'static dyn MeshOperation;

    fn next(&mut self) -> Option<Self::Item> {
        let op = self.list.get(self.at).copied()?;
        self.at += 1;
        Some(op)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.list.len() - self.at;
        (left, Some(left))
    }
}

/// The process's registry: the built-in operations, then the others in the order they came.
static REGISTRY: LazyLock<RwLock<Operations>> = LazyLock::new(|| {
    let mut list: Vec<&'static dyn MeshOperation> = Vec::with_capacity(BUILT_IN.len());
    for &op in BUILT_IN {
        if let Err(clash) = admit(&list, op) {
            panic!("Pappus's own operations clash: {clash}");
        }
        list.push(op);
    }
    RwLock::new(Operations(list.into()))
});

/// Pappus's quantities beyond the geometry's own ([`Quantity::BUILT_IN`]), registered after
/// them: adding one is its module and one line here.
const MORE_QUANTITIES: &[Quantity] = &[Quantity(&geodesic::Geodesic)];

/// The registered quantities, built-in first, then the others in the order they came.
static QUANTITIES: LazyLock<RwLock<Arc<[Quantity]>>> = LazyLock::new(|| {
    let built_in = Quantity::BUILT_IN.iter().chain(MORE_QUANTITIES);
    RwLock::new(built_in.copied().collect())
});

/// Every registered quantity, built-in first.
pub fn quantities() -> Arc<[Quantity]> {
    match QUANTITIES.read() {
        Ok(list) => list.clone(),
        Err(poisoned) => poisoned.into_inner().clone(),
    }
}

/// The registered quantity called `name` (any case).
pub fn quantity(name: &str) -> Option<Quantity> {
    quantities()
        .iter()
        .copied()
        .find(|q| q.name().eq_ignore_ascii_case(name))
}

/// Registers `q` for the rest of the process: the editor colours by it, `process --quantity`
/// writes it, Python's `Mesh.quantity` returns it. Returns it as the registry holds it.
///
/// # Errors
/// A [`Clash`] naming both when a registered quantity has its name (any case); nothing is
/// registered then.
pub fn register_quantity(q: impl VertexQuantity) -> Result<Quantity, Clash> {
    let mut list = match QUANTITIES.write() {
        Ok(list) => list,
        Err(poisoned) => poisoned.into_inner(),
    };
    let new = q.declaration();
    if let Some(old) = list
        .iter()
        .find(|o| o.name().eq_ignore_ascii_case(new.name))
    {
        return Err(Clash {
            new: format!("`{}` (\"{}\")", new.name, new.label),
            old: format!("`{}` (\"{}\")", old.name(), old.label()),
            why: "both are quantities of that name".into(),
        });
    }
    let q = Quantity(Box::leak(Box::new(q)));
    *list = list.iter().copied().chain([q]).collect();
    Ok(q)
}

/// Every registered quantity follows an undo's or redo's new entities in `world`
/// ([`VertexQuantity::follow`]: `map` from the entity each element had to the one that stands
/// for it now).
pub fn quantities_follow(world: WorldId, map: &crate::mesh::change::Remap) {
    for q in quantities().iter() {
        q.0.follow(world, map);
    }
}

/// Every registered quantity hears that an edit in `world` rewrote the faces in place
/// ([`VertexQuantity::faces_renumbered`]); the names of those that forgot their values.
pub fn quantities_faces_renumbered(world: WorldId) -> Vec<&'static str> {
    (quantities().iter())
        .filter(|q| q.0.faces_renumbered(world))
        .map(|q| q.name())
        .collect()
}

/// Why an operation was not registered: it would share a step name, or a key, with one
/// already registered. Both are named.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{new} clashes with the registered {old}: {why}")]
pub struct Clash {
    /// The operation refused, as `` `name` ("Title") ``.
    pub new: String,
    /// The registered operation it clashes with, the same way.
    pub old: String,
    /// What they share ("both name an edge", "both take the key Alt+R").
    pub why: String,
}

/// Every registered operation, built-in first.
pub fn operations() -> Operations {
    match REGISTRY.read() {
        Ok(list) => list.clone(),
        // A panic while the list was swapped leaves the old one whole: read it.
        Err(poisoned) => poisoned.into_inner().clone(),
    }
}

/// Registers `op` for the rest of the process: it becomes a step, a key (if it declares one),
/// a button in its panel section, a Python operation and an undoable edit. Returns it as the
/// registry holds it.
///
/// # Errors
/// A [`Clash`]: another operation already has its step name and names the same kind of
/// element, or already has its key under another name. Nothing is registered then.
pub fn register(op: impl MeshOperation) -> Result<&'static dyn MeshOperation, Clash> {
    let mut list = match REGISTRY.write() {
        Ok(list) => list,
        Err(poisoned) => poisoned.into_inner(),
    };
    admit(&list, &op)?;
    let op: &'static dyn MeshOperation = Box::leak(Box::new(op));
    *list = Operations(list.iter().copied().chain([op]).collect());
    Ok(op)
}

/// Whether `op` may join `list`.
fn admit(list: &[&'static dyn MeshOperation], op: &dyn MeshOperation) -> Result<(), Clash> {
    let new = op.declaration();
    for old in list.iter().map(|o| o.declaration()) {
        let why = if new.name == old.name && overlap(new.names, old.names) {
            Some(format!("both are `{}` on {}", new.name, new.names.what()))
        } else if new.name != old.name
            && let (Some(a), Some(b)) = (new.key, old.key)
            && a.eq_ignore_ascii_case(b)
        {
            Some(format!("both take the key {a}"))
        } else {
            None
        };
        if let Some(why) = why {
            return Err(Clash {
                new: called(new),
                old: called(old),
                why,
            });
        }
    }
    Ok(())
}

/// An operation as a clash names it: `` `flip` ("Flip") ``.
fn called(d: &Declaration) -> String {
    format!("`{}` (\"{}\")", d.name, d.title)
}

/// Whether some list of elements is named by both `a` and `b` (then one step could mean
/// either).
fn overlap(a: Names, b: Names) -> bool {
    let e = ElementId::Edge(EdgeId(bevy::prelude::Entity::PLACEHOLDER));
    let v = ElementId::Vertex(VertexId(bevy::prelude::Entity::PLACEHOLDER));
    let f = ElementId::Face(FaceId(bevy::prelude::Entity::PLACEHOLDER));
    let samples: [&[ElementId]; 8] = [&[], &[e], &[v], &[f], &[f, f], &[e, e], &[v, v], &[f, v, v]];
    samples.iter().any(|s| a.admits(s) && b.admits(s))
}

/// The registered operation whose step is called `name` (the first, where several share the
/// name and differ in what they name: `collapse` an edge or a face).
pub fn operation(name: &str) -> Option<&'static dyn MeshOperation> {
    operations()
        .into_iter()
        .find(|op| op.declaration().name == name)
}

/// The registered operations whose step is called `name`, in registry order: one, or several
/// that name different elements (`dissolve` an edge or a vertex), between which the elements
/// given decide.
pub fn operations_named(name: &str) -> Vec<&'static dyn MeshOperation> {
    operations()
        .into_iter()
        .filter(|op| op.declaration().name == name)
        .collect()
}

/// The registered operation called `name` that names `elements` (of those sharing the name,
/// the first whose declaration admits them), with its defaults.
///
/// # Errors
/// No registered operation of that name, or none that names such elements: the message says
/// what it names ("collapse needs an edge or a face").
pub fn invocation_on(name: &str, elements: Vec<ElementId>) -> Result<Invocation, String> {
    let mut needs = Vec::new();
    for op in operations_named(name) {
        let d = op.declaration();
        if d.names.admits(&elements) {
            return Invocation::with_defaults(op).on(elements);
        }
        needs.push(d.names.what());
    }
    match needs.is_empty() {
        true => Err(format!("no registered operation is called `{name}`")),
        false => Err(format!("{name} needs {}", needs.join(" or "))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_operations_are_registered_in_order_and_shared_names_name_other_kinds() {
        let all = operations();
        assert!(all.len() >= BUILT_IN.len());
        for (a, b) in BUILT_IN.iter().zip(all.iter()) {
            assert_eq!(a.declaration().name, b.declaration().name);
        }
        // collapse an edge or a face, dissolve an edge or a vertex: one name, other kinds.
        assert_eq!(operations_named("collapse").len(), 2);
        assert_eq!(operations_named("dissolve").len(), 2);
        assert!(operation("no-such-operation").is_none());
    }

    #[test]
    fn a_clash_names_both_operations_and_what_they_share() {
        let list: Vec<&'static dyn MeshOperation> = BUILT_IN.to_vec();
        let again = admit(&list, &local::Flip).unwrap_err();
        assert_eq!(again.new, "`flip` (\"Flip\")");
        assert_eq!(again.old, "`flip` (\"Flip\")");
        assert_eq!(again.why, "both are `flip` on an edge");
        // Collapse a face beside collapse an edge is no clash; beside itself it is.
        let edges_only: Vec<&'static dyn MeshOperation> = vec![&local::Collapse];
        assert!(admit(&edges_only, &local::CollapseFace).is_ok());
        assert!(admit(&[&local::CollapseFace], &local::CollapseFace).is_err());
        // Bevel names any elements: it overlaps every kind but the whole mesh.
        assert!(overlap(Names::Elements, Names::Edge));
        assert!(overlap(Names::Vertex, Names::Vertices));
        assert!(overlap(Names::Mesh, Names::MeshHolding));
        assert!(!overlap(Names::Mesh, Names::Edge));
        assert!(!overlap(Names::Edge, Names::Face));
    }
}
