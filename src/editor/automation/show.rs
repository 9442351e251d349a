//! A script's mesh in the editor (`pappus.show` in Python): the request a script writes, the
//! arrays it gives shown as quantities, and what goes back to it when the window closes.
//!
//! `pappus --show REQUEST` opens the editor on what `REQUEST`, a JSON file, names (a relative
//! path is the request's folder's):
//!
//! ```json
//! { "mesh": "mesh.ply", "name": "bunny.obj",
//!   "quantities": [ { "name": "geodesic", "values": "geodesic.f64" },
//!                   { "name": "area", "per": "face", "values": "area.f64" } ],
//!   "hand_back": "back" }
//! ```
//!
//! `name`, optional, is what the panel calls the mesh (the script's mesh's name rather than the
//! temporary file's).
//! Each quantity's values are little-endian `f64`, one per vertex of the mesh file in its order
//! (`"per": "face"`: one per face, each face drawn in one colour). Once the mesh is open they
//! become [`StoredQuantity`]s, listed in the Analysis
//! section beside Pappus's own (a name Pappus already has is shown as given and registered as
//! `NAME-script`); the mesh opens coloured by the first, with the Analysis section (its legend)
//! open.
//!
//! When the window closes, by its close button or a script's `exit`, nothing is asked about
//! unsaved changes ([`ReturnsToScript`]) and the editor writes into the `hand_back` folder:
//!
//! - `mesh.ply`: the mesh as the user left it (a stepped run in progress ended where it
//!   stands), its vertices and faces in the mesh's row order;
//! - `answer.json`: `{"mesh": "mesh.ply", "edited": bool, "selection": {...}, "notes": [...]}`.
//!   `edited` says whether anything was recorded in the undo history after the mesh opened
//!   (an edit, an undo of one, another file opened); the script keeps its own mesh, and its
//!   ids, when it is false. The selection is by kind, as rows of `mesh.ply`: `vertices` and
//!   `faces` as rows, `edges` as their two vertices' rows, `halfedges` as their (from, to)
//!   vertices' rows. `vertex_sources` and `face_sources` give, for each vertex and face of
//!   `mesh.ply`, its row in the request's mesh (-1 for one made in the window, and for every
//!   face after subdivision; [`Origins`], followed through undo), so that the script's
//!   per-element arrays and input numbers follow the edits; `null` when the mesh is another (a
//!   file opened in the window). `notes` says what did not go back (what PLY cannot hold, an
//!   operation still running). With no mesh open at the end, `"mesh"` is `null`.
//!
//! The recovery of the session's work is forgotten once the answer is written: the script has
//! it.

use std::path::{Path, PathBuf};

use bevy::ecs::message::{MessageCursor, Messages};
use bevy::prelude::*;
use serde_json::{Value, json};

use crate::edit::soup_to_save;
use crate::io;
use crate::mesh::ids::{ElementId, FaceId, MeshId};
use crate::mesh::tables::EntityRows;
use crate::mesh::topology::MeshRef;
use crate::mesh::{MeshMembers, VertexId};
use crate::ops::geometry::stored::StoredQuantity;

use crate::editor::panels::sections::folding::PanelSections;
use crate::editor::pipeline::jobs::Jobs;
use crate::editor::pipeline::{recovery, stepping};
use crate::editor::session::history::UndoHistory;
use crate::editor::session::origins::Origins;
use crate::editor::session::schedule::EditorSystems;
use crate::editor::session::selection::{ActiveMesh, Selection};
use crate::editor::session::state::ReturnsToScript;
use crate::editor::view::colouring::ColorBy;

/// What a script asked for ([`ShowRequest::read`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ShowRequest {
    /// The mesh file to open.
    pub mesh: PathBuf,
    /// What the panel calls the mesh, if not the file's name.
    pub name: Option<String>,
    /// The arrays to show, in the order given.
    pub quantities: Vec<GivenArray>,
    /// The folder the mesh and the answer go to when the window closes.
    pub hand_back: PathBuf,
}

/// One array a script gives: a value per vertex (or per face) of the mesh file, in its order.
#[derive(Debug, Clone, PartialEq)]
pub struct GivenArray {
    /// Its name, as the script gave it.
    pub name: String,
    /// Its values are the faces' rather than the vertices'.
    pub on_faces: bool,
    /// Its values.
    pub values: Vec<f64>,
}

impl ShowRequest {
    /// Reads a request and the arrays it names.
    ///
    /// # Errors
    /// A message naming the file that could not be read or what is wrong in it.
    pub fn read(path: &Path) -> Result<ShowRequest, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let json: Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let folder = path.parent().unwrap_or(Path::new("."));
        let file = |key: &str, at: &Value| -> Result<PathBuf, String> {
            at.get(key)
                .and_then(Value::as_str)
                .map(|p| folder.join(p))
                .ok_or_else(|| format!("{}: no \"{key}\" path", path.display()))
        };
        let mut quantities = Vec::new();
        for q in json
            .get("quantities")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            let name = q
                .get("name")
                .and_then(Value::as_str)
                .filter(|n| !n.trim().is_empty())
                .ok_or_else(|| format!("{}: a quantity without a name", path.display()))?;
            let values_path = file("values", q)?;
            let bytes = std::fs::read(&values_path)
                .map_err(|e| format!("{}: {e}", values_path.display()))?;
            if bytes.len() % 8 != 0 {
                return Err(format!(
                    "{}: {} bytes is not a whole number of f64 values",
                    values_path.display(),
                    bytes.len()
                ));
            }
            let values = bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("chunks of 8")))
                .collect();
            let on_faces = match q.get("per").and_then(Value::as_str) {
                None | Some("vertex") => false,
                Some("face") => true,
                Some(other) => {
                    return Err(format!(
                        "{}: quantity {name}: \"per\" is \"vertex\" or \"face\", not {other:?}",
                        path.display()
                    ));
                }
            };
            quantities.push(GivenArray {
                name: name.to_string(),
                on_faces,
                values,
            });
        }
        Ok(ShowRequest {
            mesh: file("mesh", &json)?,
            name: json.get("name").and_then(Value::as_str).map(str::to_string),
            quantities,
            hand_back: file("hand_back", &json)?,
        })
    }
}

/// The show session: the arrays waiting for the mesh to open, then the mesh they were given
/// for and the undo history's mark when it opened.
#[derive(Resource, Debug, Default)]
pub struct ShowSession {
    name: Option<String>,
    waiting: Vec<GivenArray>,
    opened: Option<(MeshId, u64)>,
}

/// The show session's systems: the arrays given once the mesh is open, the answer at exit.
pub struct ShowPlugin {
    /// The request read from the command line.
    pub request: ShowRequest,
}

impl Plugin for ShowPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(ReturnsToScript(self.request.hand_back.clone()))
            .insert_resource(ShowSession {
                name: self.request.name.clone(),
                waiting: self.request.quantities.clone(),
                opened: None,
            })
            .add_systems(
                Update,
                give_arrays_once_open
                    .after(EditorSystems::Apply)
                    .before(EditorSystems::Sync),
            )
            .add_systems(Last, hand_back_on_exit);
    }
}

/// Once the mesh is open: names it as the script does, registers each given array as a
/// quantity on its vertices or faces (an array whose length is not their count is left out
/// with a warning), colours by the first and opens the Analysis section, where its legend is.
pub fn give_arrays_once_open(world: &mut World) {
    if world.resource::<ShowSession>().opened.is_some() {
        return;
    }
    let Some(mesh) = world.resource::<ActiveMesh>().0 else {
        return;
    };
    let mark = world.resource::<UndoHistory>().mark();
    let (name, waiting) = {
        let mut session = world.resource_mut::<ShowSession>();
        session.opened = Some((mesh, mark));
        (session.name.take(), std::mem::take(&mut session.waiting))
    };
    if let Some(name) = name
        && let Some(mut info) = world.get_mut::<crate::mesh::MeshInfo>(mesh.0)
    {
        info.name = name;
    }
    // A freshly opened mesh lists its vertices and faces in file order.
    let vertices = crate::mesh::members::of_kind::<crate::mesh::Vertex, _>(world, mesh, VertexId);
    let faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(world, mesh, FaceId);
    world.insert_resource(Origins::of(&vertices, &faces));
    let mut first = None;
    for array in waiting {
        let (count, kind) = match array.on_faces {
            true => (faces.len(), "faces"),
            false => (vertices.len(), "vertices"),
        };
        if array.values.len() != count {
            warn!(
                "show: {} has {} values for {count} {kind}; not shown",
                array.name,
                array.values.len(),
            );
            continue;
        }
        let name = free_name(&array.name);
        let stored = match array.on_faces {
            true => StoredQuantity::on_faces(
                &name,
                &array.name,
                faces.iter().copied().zip(array.values),
            ),
            false => StoredQuantity::new(
                &name,
                &array.name,
                vertices.iter().copied().zip(array.values),
            ),
        };
        let stored = stored.of_world(world.id());
        match crate::ops::registry::register_quantity(stored) {
            Ok(q) => {
                first.get_or_insert(q);
            }
            Err(clash) => warn!("show: {clash}"),
        }
    }
    if let Some(q) = first {
        world.resource_mut::<ColorBy>().0 = Some(q);
        if let Some(mut sections) = world.get_resource_mut::<PanelSections>() {
            sections.set_open("Analysis", true);
        }
    }
}

/// `name`, or `name-script` (then `name-script2`, …) where a quantity of that name exists.
fn free_name(name: &str) -> String {
    let taken = |n: &str| crate::ops::registry::quantity(n).is_some();
    if !taken(name) {
        return name.to_string();
    }
    (1..)
        .map(|i| match i {
            1 => format!("{name}-script"),
            i => format!("{name}-script{i}"),
        })
        .find(|n| !taken(n))
        .expect("some name is free")
}

/// Writes the answer once the app is exiting (the `Last` schedule, after any system of the
/// frame has asked to exit), once.
pub fn hand_back_on_exit(world: &mut World, mut cursor: Local<MessageCursor<AppExit>>) {
    if cursor.read(world.resource::<Messages<AppExit>>()).count() == 0 {
        return;
    }
    let Some(ReturnsToScript(folder)) = world.remove_resource::<ReturnsToScript>() else {
        return;
    };
    match hand_back(world, &folder) {
        Ok(()) => recovery::forget(world),
        Err(e) => error!("show: the mesh could not be handed back: {e}"),
    }
}

/// Writes the mesh and the answer into `folder` (see the module doc).
///
/// # Errors
/// A message naming the file that could not be written.
pub fn hand_back(world: &mut World, folder: &Path) -> Result<(), String> {
    // A stepped run in progress ends where it stands, as one undo entry.
    let ended = stepping::end_run(world);
    let mut notes: Vec<String> = Vec::new();
    if let Err(declined) = ended {
        notes.push(format!("the stepped run could not end: {declined}"));
    }
    if let Some(job) = &world.resource::<Jobs>().running {
        notes.push(format!(
            "{} was still running when the window closed; the mesh is as before it",
            job.label
        ));
    }
    std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    let answer = match world.resource::<ActiveMesh>().0 {
        None => json!({ "mesh": null, "edited": true, "notes": notes }),
        Some(mesh) => {
            let path = folder.join("mesh.ply");
            let (soup, recomputed) = soup_to_save(world, mesh);
            notes.extend(
                io::dropped(&path, &soup)
                    .into_iter()
                    .map(|what| format!("{what} did not come back (PLY has no place for them)")),
            );
            notes.extend(recomputed.map(str::to_string));
            io::write(&path, &soup).map_err(|e| e.to_string())?;
            let opened = world.resource::<ShowSession>().opened;
            let mark = world.resource::<UndoHistory>().mark();
            let edited = opened.is_none_or(|(first, at)| first != mesh || mark > at);
            // Where each element came from, when the mesh is the one the script gave.
            let members = MeshMembers::collect(world, mesh);
            let origins = (world.get_resource::<Origins>())
                .filter(|_| opened.is_some_and(|(first, _)| first == mesh));
            let vertex_sources = origins.map(|o| o.vertex_rows(&members.vertices));
            let face_sources = origins.map(|o| o.face_rows(&members.faces));
            json!({
                "mesh": "mesh.ply",
                "edited": edited,
                "vertex_sources": vertex_sources,
                "face_sources": face_sources,
                "selection": selection_rows(world, mesh),
                "notes": notes,
            })
        }
    };
    let path = folder.join("answer.json");
    std::fs::write(&path, answer.to_string()).map_err(|e| format!("{}: {e}", path.display()))
}

/// The selected elements of `mesh` by kind, as rows of its tables (see the module doc).
pub fn selection_rows(world: &World, mesh: MeshId) -> Value {
    let members = MeshMembers::collect(world, mesh);
    let rows = EntityRows::new(&members);
    let m = MeshRef::new(world);
    let (mut vertices, mut halfedges, mut edges, mut faces) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let pair = |a: VertexId, b: VertexId| Some([rows.row(a.0)?, rows.row(b.0)?]);
    let selected = world
        .get_resource::<Selection>()
        .map(|s| s.elements().to_vec())
        .unwrap_or_default();
    for x in selected {
        if rows.row(x.entity()).is_none() {
            continue;
        }
        match x {
            ElementId::Vertex(v) => vertices.extend(rows.row(v.0)),
            ElementId::Face(f) => faces.extend(rows.row(f.0)),
            ElementId::Edge(e) => {
                let (a, b) = m.edge_vertices(e);
                edges.extend(pair(a, b));
            }
            ElementId::Halfedge(h) => halfedges.extend(pair(m.from_vertex(h), m.to_vertex(h))),
            ElementId::Mesh(_) => {}
        }
    }
    json!({ "vertices": vertices, "halfedges": halfedges, "edges": edges, "faces": faces })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_names_its_files_from_its_own_folder_and_refuses_what_is_wrong() {
        let folder = std::env::temp_dir().join(format!("pappus-show-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let values: Vec<u8> = [1.5f64, -2.0, 3.25]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        std::fs::write(folder.join("h.f64"), &values).unwrap();
        let request = folder.join("show.json");
        std::fs::write(
            &request,
            r#"{"mesh": "m.ply", "hand_back": "back",
                "quantities": [{"name": "height", "values": "h.f64"},
                               {"name": "area", "per": "face", "values": "h.f64"}]}"#,
        )
        .unwrap();
        let read = ShowRequest::read(&request).unwrap();
        assert_eq!(read.mesh, folder.join("m.ply"));
        assert_eq!(read.name, None);
        assert_eq!(read.hand_back, folder.join("back"));
        assert_eq!(
            read.quantities,
            vec![
                GivenArray {
                    name: "height".into(),
                    on_faces: false,
                    values: vec![1.5, -2.0, 3.25]
                },
                GivenArray {
                    name: "area".into(),
                    on_faces: true,
                    values: vec![1.5, -2.0, 3.25]
                }
            ]
        );
        // Values that are not whole f64s, a quantity without a name, no mesh: each named.
        std::fs::write(folder.join("h.f64"), [0u8; 7]).unwrap();
        assert!(ShowRequest::read(&request).unwrap_err().contains("7 bytes"));
        std::fs::write(
            &request,
            r#"{"mesh": "m.ply", "hand_back": "b", "quantities": [{"values": "h.f64"}]}"#,
        )
        .unwrap();
        assert!(
            ShowRequest::read(&request)
                .unwrap_err()
                .contains("without a name")
        );
        std::fs::write(&request, r#"{"hand_back": "b"}"#).unwrap();
        assert!(
            ShowRequest::read(&request)
                .unwrap_err()
                .contains("\"mesh\"")
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
