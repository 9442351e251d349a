//! Operations on the entity mesh.
//!
//! The contract, in Scotty3D's words and PMP's shape: **check, then mutate; a refusal is a
//! value.** Each operation has a read-only `plan_*` that validates its input and collects every
//! id it will touch, returning a [`Refusal`] when the result would not be a valid mesh, and an
//! `apply_*` that cannot fail on a plan just made. A refused operation leaves the world exactly
//! as it was.
//!
//! Operations are plain functions over `&World` / `&mut World`, callable from a unit test, the
//! command line and the editor alike; the editor's systems are thin adapters around them.

pub mod decimate;
pub mod declaration;
pub mod deform;
pub mod geometry;
pub mod hole;
pub mod indexed_heap;
pub mod local;
pub mod named;
pub mod normalize;
pub mod operation;
pub mod param;
pub mod progressive;
pub mod refusal;
pub mod remesh;
pub mod reverse;
pub mod simplification_history;
pub mod simplify;
pub mod smooth;
pub mod subdivide;
pub mod table_split;
pub mod triangulate;

use operation::MeshOperation;
/// Why an operation was not carried out (defined in [`refusal`], which imports nothing else
/// of `ops` but the parameterization's error it wraps).
pub use refusal::Refusal;

/// Every operation that declares itself whole ([`MeshOperation`]), in the order the panel,
/// the help overlay and the usage text list them: the whole-mesh operations, then the local
/// ones on the elements they name. Adding one is its module above and one line
/// here; the step parser, the keymap, the panel, undo and jobs then know it.
pub const OPERATIONS: &[&dyn MeshOperation] = &[
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

/// The registered operation whose step is called `name` (the first, where several share the
/// name and differ in what they name: `collapse` an edge or a face).
pub fn operation(name: &str) -> Option<&'static dyn MeshOperation> {
    operations_named(name).next()
}

/// The registered operations whose step is called `name`, in registry order: one, or several
/// that name different elements (`dissolve` an edge or a vertex), between which the elements
/// given decide.
pub fn operations_named(name: &str) -> impl Iterator<Item = &'static dyn MeshOperation> {
    OPERATIONS
        .iter()
        .copied()
        .filter(move |op| op.declaration().name == name)
}

/// The registered operation called `name` that names `elements` (of those sharing the name,
/// the first whose declaration admits them), with its defaults.
///
/// # Errors
/// No registered operation of that name, or none that names such elements: the message says
/// what it names ("collapse needs an edge or a face").
pub fn invocation_on(
    name: &str,
    elements: Vec<crate::mesh::ids::ElementId>,
) -> Result<operation::Invocation, String> {
    let mut needs = Vec::new();
    for op in operations_named(name) {
        let d = op.declaration();
        if d.names.admits(&elements) {
            return operation::Invocation::with_defaults(op).on(elements);
        }
        needs.push(d.names.what());
    }
    match needs.is_empty() {
        true => Err(format!("no registered operation is called `{name}`")),
        false => Err(format!("{name} needs {}", needs.join(" or "))),
    }
}
