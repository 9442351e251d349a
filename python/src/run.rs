//! `Mesh.run(name, *elements, progress=None, **parameters)`: every operation that declares
//! itself ([`pappus::ops::registry`]) by its name, from its declaration alone.
//!
//! The elements are handles or input vertex numbers (a number a vertex, a sequence of them an
//! edge or a face, as a step writes them); the keywords are the declared parameters' names in
//! lower case, a choice given as its word, `None` for automatic, anything left out taking its
//! default; ranges are the declaration's ([`Parameter::read`]), so a value out of range is a
//! `ValueError` with the command line's message. Of the operations sharing a name (`collapse`
//! an edge or a face), the one that names such elements runs. An operation added to the core
//! appears here with nothing written.
//!
//! What an edit made and removed is read from the world's change tracking: its trackers are
//! cleared before the edit, so the elements spawned are those whose kind component was added
//! since, and the elements despawned those the world reports removed. An edit that rewrote the
//! non-vertex elements in place (subdivision) has every one of them made anew and removed.

use bevy::ecs::change_detection::DetectChanges;
use bevy::ecs::entity::EntityHashSet;
use bevy::ecs::query::Added;
use bevy::prelude::{Entity, World};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PySequence};

use pappus::edit::{IdsKept, Invocation, Redraw, elements_at};
use pappus::mesh::{
    Edge, EdgeId, ElementId, Face, FaceId, Halfedge, HalfedgeId, MeshId, MeshMembers, MeshRef,
    Vertex, VertexId,
};
use pappus::ops::declaration::{Names, Parameter};
use pappus::ops::operation::MeshOperation;

use crate::elements::number;
use crate::handles::{EdgeHandle, FaceHandle, HalfedgeHandle, VertexHandle};
use crate::mesh::Mesh;

/// One element as the caller gave it.
pub(crate) enum Target {
    /// A handle's element (checked to be of this mesh and live).
    Element(ElementId),
    /// Input vertex numbers: a vertex, an edge's two ends, a face's consecutive corners.
    Numbers(Vec<u32>),
}

/// Reads the elements given to `run`: each a handle, an input vertex number, a sequence of
/// numbers (one edge or face), or a list of any of these (several elements).
pub(crate) fn targets(mesh: &Bound<'_, Mesh>, given: &Bound<'_, PyAny>) -> PyResult<Vec<Target>> {
    let mut out = Vec::new();
    for x in given.try_iter()? {
        read_target(mesh, &x?, &mut out)?;
    }
    Ok(out)
}

/// Appends what `x` names to `out`.
fn read_target(
    mesh: &Bound<'_, Mesh>,
    x: &Bound<'_, PyAny>,
    out: &mut Vec<Target>,
) -> PyResult<()> {
    if let Some(at) = handle_at(x) {
        let id = at.check_mesh(mesh)?;
        if !mesh.borrow().holds(id, at.revision()) {
            return Err(crate::handles::stale(id));
        }
        out.push(Target::Element(id));
        return Ok(());
    }
    if let Ok(v) = x.extract::<u32>() {
        out.push(Target::Numbers(vec![v]));
        return Ok(());
    }
    if let Ok(corners) = x.extract::<Vec<u32>>() {
        if corners.is_empty() {
            return Err(PyValueError::new_err(
                "an element names at least one vertex",
            ));
        }
        out.push(Target::Numbers(corners));
        return Ok(());
    }
    if !x.is_instance_of::<pyo3::types::PyString>()
        && let Ok(list) = x.cast::<PySequence>()
    {
        for item in list.try_iter()? {
            read_target(mesh, &item?, out)?;
        }
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "an element is a handle (pappus.Vertex, Halfedge, Edge, Face), an input vertex number or \
         a sequence of them, not {}",
        x.get_type().name()?
    )))
}

/// The place a handle of any kind points at.
fn handle_at<'a>(x: &'a Bound<'_, PyAny>) -> Option<&'a crate::handles::At> {
    if let Ok(v) = x.cast::<VertexHandle>() {
        return Some(v.get().at());
    }
    if let Ok(h) = x.cast::<HalfedgeHandle>() {
        return Some(h.get().at());
    }
    if let Ok(e) = x.cast::<EdgeHandle>() {
        return Some(e.get().at());
    }
    x.cast::<FaceHandle>().ok().map(|f| f.get().at())
}

/// The operation called `name` (`_` read as `-`) that names `targets`, with the `parameters`
/// given: `ValueError` for an unknown name, elements it does not name, or a parameter it does
/// not take; `Refused` (through [`Refused`](crate::errors::Refused)) for numbers that name no
/// element.
pub(crate) fn invocation(
    world: &World,
    input_vertices: &[Option<VertexId>],
    name: &str,
    targets: &[Target],
    parameters: Option<&Bound<'_, PyDict>>,
) -> PyResult<Invocation> {
    let name = name.replace('_', "-");
    let mut needs = Vec::new();
    for op in pappus::ops::registry::operations_named(&name) {
        let d = op.declaration();
        let elements = elements_for(world, input_vertices, d.names, targets)?;
        if !d.names.admits(&elements) {
            needs.push(d.names.what());
            continue;
        }
        let mut invocation = Invocation::with_defaults(op)
            .on(elements)
            .map_err(PyValueError::new_err)?;
        set_parameters(&mut invocation, op, parameters)?;
        return Ok(invocation);
    }
    Err(PyValueError::new_err(if needs.is_empty() {
        let known: Vec<&str> = pappus::ops::registry::operations()
            .iter()
            .map(|op| op.declaration().name)
            .collect();
        format!(
            "no operation is called `{name}`; known: {}",
            known.join(", ")
        )
    } else {
        format!("{name} needs {}", needs.join(" or "))
    }))
}

/// The elements `targets` name for an operation that names `names`.
fn elements_for(
    world: &World,
    input_vertices: &[Option<VertexId>],
    names: Names,
    targets: &[Target],
) -> PyResult<Vec<ElementId>> {
    let refused = |r: pappus::ops::Refusal| crate::errors::Refused::new_err(r.to_string());
    // Numbers alone read as a step reads them (a face split's two corners name their face).
    if let Some(numbers) = targets
        .iter()
        .map(|t| match t {
            Target::Numbers(n) => Some(n.clone()),
            Target::Element(_) => None,
        })
        .collect::<Option<Vec<_>>>()
    {
        return elements_at(world, input_vertices, names, &numbers).map_err(refused);
    }
    targets
        .iter()
        .map(|t| match t {
            Target::Element(id) => Ok(*id),
            Target::Numbers(n) => elements_at(
                world,
                input_vertices,
                Names::Elements,
                std::slice::from_ref(n),
            )
            .map(|e| e[0])
            .map_err(refused),
        })
        .collect()
}

/// Sets each keyword to its declared parameter, read as a step reads its text.
fn set_parameters(
    invocation: &mut Invocation,
    op: &'static dyn MeshOperation,
    parameters: Option<&Bound<'_, PyDict>>,
) -> PyResult<()> {
    let Some(parameters) = parameters else {
        return Ok(());
    };
    let d = op.declaration();
    for (key, value) in parameters.iter() {
        let key: String = key.extract()?;
        let Some(i) = d
            .parameters
            .iter()
            .position(|p| p.name.eq_ignore_ascii_case(&key))
        else {
            let takes: Vec<String> = d.parameters.iter().map(keyword).collect();
            return Err(PyValueError::new_err(format!(
                "{} has no parameter `{key}`; it takes {}",
                d.name,
                if takes.is_empty() {
                    "none".to_string()
                } else {
                    takes.join(", ")
                }
            )));
        };
        // A refused value is named with what the operation takes, as a step's refusal is.
        let refused = |why: String| {
            PyValueError::new_err(format!(
                "{}({key}={}): {why}; expected {}",
                d.name,
                value.repr().map_or_else(|_| "?".into(), |r| r.to_string()),
                d.syntax()
            ))
        };
        let text = value_text(&value).map_err(|e| refused(e.value(value.py()).to_string()))?;
        let x = d.parameters[i].read(&text).map_err(refused)?;
        invocation.set(i, x).map_err(refused)?;
    }
    Ok(())
}

/// A parameter's Python keyword: its declared name in lower case.
pub(crate) fn keyword(p: &Parameter) -> String {
    p.name.to_ascii_lowercase()
}

/// A keyword's value as a step writes it: a number, a word, or `auto` for None (`ValueError`
/// for anything else).
fn value_text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_none() {
        return Ok("auto".into());
    }
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyValueError::new_err(format!(
            "a parameter is a number or a word, not {value}"
        )));
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(number(x));
    }
    value.extract::<String>().map_err(|_| {
        PyValueError::new_err(format!(
            "a parameter is a number, a word or None, not {}",
            value
                .get_type()
                .name()
                .map_or_else(|_| "that".into(), |n| n.to_string())
        ))
    })
}

/// The elements an edit spawned and despawned, by kind.
#[derive(Default)]
pub(crate) struct Changes {
    /// Elements the edit made.
    pub(crate) created: Vec<ElementId>,
    /// Elements the edit removed.
    pub(crate) removed: Vec<ElementId>,
}

/// What a tracked edit needs from before it: the non-vertex elements, for an edit that
/// rewrites them in place.
pub(crate) struct Before {
    /// The elements, for an edit that keeps only vertex ids.
    members: Option<MeshMembers>,
}

impl Before {
    /// Starts tracking: clears the world's trackers (twice: removals are double-buffered), and
    /// for an edit keeping only vertex ids lists the elements it will rewrite.
    pub(crate) fn start(world: &mut World, mesh: MeshId, ids: IdsKept) -> Self {
        world.clear_trackers();
        world.clear_trackers();
        Self {
            members: (ids == IdsKept::VerticesOnly).then(|| MeshMembers::collect(world, mesh)),
        }
    }

    /// What the edit since [`Before::start`] made and removed. A local edit's `redraw` (the
    /// faces around some vertices, which the renderer redraws, so everything the edit made is
    /// among them, their sides and their corners) bounds the search for what it made; after a
    /// whole-mesh edit every element is read.
    pub(crate) fn changes(
        self,
        world: &mut World,
        mesh: MeshId,
        redraw: Option<&Redraw>,
    ) -> Changes {
        let mut changes = Changes {
            removed: world.removed::<Vertex>().map(vertex).collect(),
            created: Vec::new(),
        };
        if let Some(before) = self.members {
            let after = MeshMembers::collect(world, mesh);
            changes.created.extend(added::<Vertex>(world).map(vertex));
            changes.removed.extend(others(&before));
            changes.created.extend(others(&after));
            return changes;
        }
        if let Some(Redraw::Near { vertices, .. }) = redraw {
            changes.created = added_near(world, vertices);
        } else {
            changes.created.extend(added::<Vertex>(world).map(vertex));
            changes
                .created
                .extend(added::<Halfedge>(world).map(halfedge));
            changes.created.extend(added::<Edge>(world).map(edge));
            changes.created.extend(added::<Face>(world).map(face));
        }
        changes
            .removed
            .extend(world.removed::<Halfedge>().map(halfedge));
        changes.removed.extend(world.removed::<Edge>().map(edge));
        changes.removed.extend(world.removed::<Face>().map(face));
        changes
    }
}

/// A vertex entity's id.
fn vertex(e: Entity) -> ElementId {
    ElementId::Vertex(VertexId(e))
}

/// A halfedge entity's id.
fn halfedge(e: Entity) -> ElementId {
    ElementId::Halfedge(HalfedgeId(e))
}

/// An edge entity's id.
fn edge(e: Entity) -> ElementId {
    ElementId::Edge(EdgeId(e))
}

/// A face entity's id.
fn face(e: Entity) -> ElementId {
    ElementId::Face(FaceId(e))
}

/// Whether `id`'s kind component was added since the trackers were cleared.
fn is_added(world: &World, id: ElementId) -> bool {
    let Ok(entity) = world.get_entity(id.entity()) else {
        return false;
    };
    let added = match id {
        ElementId::Vertex(_) => entity.get_ref::<Vertex>().map(|c| c.is_added()),
        ElementId::Halfedge(_) => entity.get_ref::<Halfedge>().map(|c| c.is_added()),
        ElementId::Edge(_) => entity.get_ref::<Edge>().map(|c| c.is_added()),
        ElementId::Face(_) => entity.get_ref::<Face>().map(|c| c.is_added()),
        ElementId::Mesh(_) => None,
    };
    added.unwrap_or(false)
}

/// The elements added since the trackers were cleared among `vertices` (those alive), the
/// faces around them, the faces' halfedges, their twins, edges and tails: each once.
fn added_near(world: &World, vertices: &[VertexId]) -> Vec<ElementId> {
    let m = MeshRef::new(world);
    let mut seen = EntityHashSet::default();
    let mut found = Vec::new();
    let mut look = |id: ElementId| {
        if seen.insert(id.entity()) && is_added(world, id) {
            found.push(id);
        }
    };
    for &v in vertices {
        if m.try_vertex(v).is_none() {
            continue;
        }
        look(v.into());
        for f in m.vertex_faces(v) {
            look(f.into());
            for h in m.face_halfedges(f) {
                look(h.into());
                look(m.twin(h).into());
                look(m.edge(h).into());
                look(m.from_vertex(h).into());
            }
        }
    }
    found
}

/// The entities whose `C` was added since the world's trackers were last cleared.
fn added<C: bevy::prelude::Component>(world: &mut World) -> impl Iterator<Item = Entity> {
    let mut query = world.query_filtered::<Entity, Added<C>>();
    query.iter(world).collect::<Vec<_>>().into_iter()
}

/// The halfedges, edges and faces of `members`.
fn others(members: &MeshMembers) -> impl Iterator<Item = ElementId> + '_ {
    let h = members.halfedges.iter().map(|&h| ElementId::from(h));
    let e = members.edges.iter().map(|&e| ElementId::from(e));
    let f = members.faces.iter().map(|&f| ElementId::from(f));
    h.chain(e).chain(f)
}
