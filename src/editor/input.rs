//! Keyboard shortcuts: one table, read by the input system and listed by the help overlay.
//!
//! Shortcuts only write [`EditRequest`]s or flip view settings; they never touch a mesh. They
//! are ignored while egui wants the keyboard (typing in a text field), which the UI reports
//! through [`KeyboardCaptured`].

use bevy::prelude::*;

use crate::mesh::ids::ElementId;

use super::apply::selected_edge;
use super::render_sync::{ViewSettings, set_wireframes_visible};
use super::requests::{EditOutcome, EditRequest, OutcomeLog, Relation};
use super::selection::{ActiveMesh, MeshDirty, SelectMode, Selection};

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Flip the selected edge.
    Flip,
    /// Split the selected edge at its midpoint.
    Split,
    /// Collapse the selected edge to its midpoint.
    Collapse,
    /// Merge the two faces of the selected edge.
    Dissolve,
    /// Cut a corner off the selected halfedge's face: join its tip to the vertex two corners
    /// ahead.
    CutCorner,
    /// Triangulate the active mesh.
    Triangulate,
    /// Simplify the active mesh (QEM) to the panel's ratio.
    Simplify,
    /// Split the selected vertex back (undo its last collapse from the simplification).
    SplitVertex,
    /// Loop-subdivide the active mesh once.
    LoopSubdivide,
    /// Catmull–Clark-subdivide the active mesh once.
    CatmullClark,
    /// Remesh the active mesh (isotropic, default parameters).
    Remesh,
    /// Move the selection along a relation.
    Navigate(Relation),
    /// Change what a click selects.
    Mode(SelectMode),
    /// Select nothing.
    ClearSelection,
    /// Frame the selection (or the mesh).
    Frame,
    /// Flat / smooth shading.
    ToggleSmooth,
    /// Wireframe on / off.
    ToggleWireframe,
    /// Halfedge arrows on / off.
    ToggleHalfedges,
    /// Delete the active mesh.
    DeleteMesh,
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Open a file (focuses the path field).
    Open,
    /// Save to the mesh's file.
    Save,
    /// Save to another file (focuses the path field).
    SaveAs,
    /// Show or hide the help overlay.
    Help,
}

/// A key with modifiers, and what it does.
#[derive(Clone, Copy, Debug)]
pub struct Shortcut {
    /// The key.
    pub key: KeyCode,
    /// Ctrl must be held.
    pub ctrl: bool,
    /// Shift must be held.
    pub shift: bool,
    /// The action.
    pub action: Action,
    /// How the help overlay writes the key.
    pub keys: &'static str,
    /// What the help overlay says it does.
    pub description: &'static str,
}

const fn key(
    key: KeyCode,
    keys: &'static str,
    action: Action,
    description: &'static str,
) -> Shortcut {
    Shortcut {
        key,
        ctrl: false,
        shift: false,
        action,
        keys,
        description,
    }
}

const fn ctrl(
    key: KeyCode,
    shift: bool,
    keys: &'static str,
    action: Action,
    description: &'static str,
) -> Shortcut {
    Shortcut {
        key,
        ctrl: true,
        shift,
        action,
        keys,
        description,
    }
}

/// Every shortcut of the editor.
pub const SHORTCUTS: &[Shortcut] = &[
    key(
        KeyCode::KeyR,
        "R",
        Action::Flip,
        "flip (rotate) the selected edge",
    ),
    key(
        KeyCode::KeyS,
        "S",
        Action::Split,
        "split the selected edge at its midpoint",
    ),
    key(
        KeyCode::KeyC,
        "C",
        Action::Collapse,
        "collapse the selected edge to its midpoint",
    ),
    key(
        KeyCode::KeyD,
        "D",
        Action::Dissolve,
        "dissolve the selected edge (merge its two faces)",
    ),
    key(
        KeyCode::KeyJ,
        "J",
        Action::CutCorner,
        "split the selected halfedge's face: join its tip to the corner two ahead",
    ),
    ctrl(
        KeyCode::KeyT,
        false,
        "Ctrl+T",
        Action::Triangulate,
        "triangulate every polygon",
    ),
    key(
        KeyCode::KeyU,
        "U",
        Action::SplitVertex,
        "split the selected vertex back (after Shift+S: undoes its collapse)",
    ),
    Shortcut {
        key: KeyCode::KeyS,
        ctrl: false,
        shift: true,
        action: Action::Simplify,
        keys: "Shift+S",
        description: "simplify (QEM) to the ratio set in the panel",
    },
    key(
        KeyCode::KeyL,
        "L",
        Action::LoopSubdivide,
        "Loop subdivision (triangles)",
    ),
    key(
        KeyCode::KeyQ,
        "Q",
        Action::CatmullClark,
        "Catmull-Clark subdivision (to quads)",
    ),
    key(
        KeyCode::KeyM,
        "M",
        Action::Remesh,
        "isotropic remeshing (mean edge length, 5 iterations)",
    ),
    key(
        KeyCode::KeyH,
        "H",
        Action::Navigate(Relation::Halfedge),
        "go to the element's halfedge",
    ),
    key(
        KeyCode::KeyT,
        "T",
        Action::Navigate(Relation::Twin),
        "go to twin",
    ),
    key(
        KeyCode::KeyN,
        "N",
        Action::Navigate(Relation::Next),
        "go to next",
    ),
    key(
        KeyCode::KeyP,
        "P",
        Action::Navigate(Relation::Prev),
        "go to prev",
    ),
    key(
        KeyCode::KeyV,
        "V",
        Action::Navigate(Relation::Vertex),
        "go to vertex (tip)",
    ),
    key(
        KeyCode::KeyE,
        "E",
        Action::Navigate(Relation::Edge),
        "go to edge",
    ),
    key(
        KeyCode::KeyF,
        "F",
        Action::Navigate(Relation::Face),
        "go to face",
    ),
    key(
        KeyCode::Digit1,
        "1",
        Action::Mode(SelectMode::Vertex),
        "click selects vertices",
    ),
    key(
        KeyCode::Digit2,
        "2",
        Action::Mode(SelectMode::Edge),
        "click selects edges",
    ),
    key(
        KeyCode::Digit3,
        "3",
        Action::Mode(SelectMode::Face),
        "click selects faces",
    ),
    key(
        KeyCode::Digit4,
        "4",
        Action::Mode(SelectMode::Halfedge),
        "click selects halfedges",
    ),
    key(
        KeyCode::Backquote,
        "`",
        Action::Mode(SelectMode::Auto),
        "click selects the nearest element",
    ),
    key(
        KeyCode::Escape,
        "Esc",
        Action::ClearSelection,
        "cancel the running operation, else select nothing",
    ),
    key(
        KeyCode::Period,
        ".",
        Action::Frame,
        "frame the selection (or the mesh)",
    ),
    key(
        KeyCode::Home,
        "Home",
        Action::Frame,
        "frame the selection (or the mesh)",
    ),
    key(
        KeyCode::KeyZ,
        "Z",
        Action::ToggleSmooth,
        "flat / smooth shading",
    ),
    key(
        KeyCode::KeyW,
        "W",
        Action::ToggleWireframe,
        "wireframe on / off",
    ),
    key(
        KeyCode::KeyA,
        "A",
        Action::ToggleHalfedges,
        "halfedge arrows on / off",
    ),
    key(
        KeyCode::Delete,
        "Delete",
        Action::DeleteMesh,
        "delete the mesh",
    ),
    ctrl(
        KeyCode::KeyO,
        false,
        "Ctrl+O",
        Action::Open,
        "open a file: a dialog, the path field, or drop one on the window",
    ),
    ctrl(KeyCode::KeyS, false, "Ctrl+S", Action::Save, "save"),
    ctrl(KeyCode::KeyZ, false, "Ctrl+Z", Action::Undo, "undo"),
    ctrl(KeyCode::KeyZ, true, "Ctrl+Shift+Z", Action::Redo, "redo"),
    ctrl(KeyCode::KeyY, false, "Ctrl+Y", Action::Redo, "redo"),
    ctrl(
        KeyCode::KeyS,
        true,
        "Ctrl+Shift+S",
        Action::SaveAs,
        "save as",
    ),
    key(KeyCode::F1, "F1", Action::Help, "show / hide this help"),
    Shortcut {
        key: KeyCode::Slash,
        ctrl: false,
        shift: true,
        action: Action::Help,
        keys: "?",
        description: "show / hide this help",
    },
];

/// Whether egui is using the keyboard this frame (set by the UI; shortcuts then stay quiet).
#[derive(Resource, Default, Debug, Clone, Copy)]
pub struct KeyboardCaptured(pub bool);

/// UI state that shortcuts can change.
#[derive(Resource, Debug, Clone)]
pub struct UiState {
    /// The help overlay is open.
    pub show_help: bool,
    /// The path field should take the keyboard focus (for Open / Save as).
    pub focus_path: Option<PathPurpose>,
    /// The fraction of faces Simplify keeps (0.01–1, default one half).
    pub simplify_ratio: f32,
}

impl Default for UiState {
    fn default() -> Self {
        Self {
            show_help: false,
            focus_path: None,
            simplify_ratio: 0.5,
        }
    }
}

/// What the path field is being focused for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPurpose {
    /// Open the typed path.
    Open,
    /// Save to the typed path.
    SaveAs,
}

/// The shortcut matching a key press with the given modifiers, if any.
pub fn shortcut_for(key: KeyCode, ctrl: bool, shift: bool) -> Option<&'static Shortcut> {
    SHORTCUTS.iter().find(|s| {
        s.key == key && s.ctrl == ctrl && (s.shift == shift || (!s.ctrl && !s.shift && !shift))
    })
}

/// Reads key presses and performs their actions (the `Input` set).
pub fn keyboard_shortcuts(world: &mut World) {
    if world
        .get_resource::<KeyboardCaptured>()
        .is_some_and(|k| k.0)
    {
        return;
    }
    let keys = world.resource::<ButtonInput<KeyCode>>();
    let ctrl = keys.any_pressed([KeyCode::ControlLeft, KeyCode::ControlRight]);
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    let pressed: Vec<KeyCode> = keys.get_just_pressed().copied().collect();
    for key in pressed {
        if let Some(shortcut) = shortcut_for(key, ctrl, shift) {
            perform(world, shortcut.action);
        }
    }
}

/// Performs an action: writes the request it stands for, or changes a setting.
pub fn perform(world: &mut World, action: Action) {
    let request = match action {
        Action::SplitVertex => {
            let Some(ElementId::Vertex(v)) = world.resource::<Selection>().element else {
                refuse(world, action, "select a vertex first");
                return;
            };
            EditRequest::SplitVertex(v)
        }
        Action::CutCorner => {
            let m = crate::mesh::MeshRef::new(world);
            let target = match world.resource::<Selection>().element {
                Some(ElementId::Halfedge(h)) if m.try_halfedge(h).is_some() => m
                    .face(h)
                    .map(|f| (f, m.to_vertex(h), m.to_vertex(m.next(m.next(h))))),
                _ => None,
            };
            let Some((f, a, b)) = target else {
                refuse(world, action, "select a halfedge of a face first (mode 4)");
                return;
            };
            EditRequest::SplitFace(f, a, b)
        }
        Action::Flip | Action::Split | Action::Collapse | Action::Dissolve => {
            let Some(edge) = selected_edge(world) else {
                refuse(world, action, "select an edge (or halfedge) first");
                return;
            };
            match action {
                Action::Flip => EditRequest::Flip(edge),
                Action::Split => EditRequest::Split(edge),
                Action::Dissolve => EditRequest::Dissolve(edge),
                _ => EditRequest::Collapse(edge),
            }
        }
        Action::Triangulate
        | Action::LoopSubdivide
        | Action::CatmullClark
        | Action::Remesh
        | Action::Simplify => {
            let Some(mesh) = world.resource::<ActiveMesh>().0 else {
                refuse(world, action, "there is no mesh");
                return;
            };
            match action {
                Action::Triangulate => EditRequest::Triangulate(mesh),
                Action::LoopSubdivide => EditRequest::LoopSubdivide(mesh),
                Action::Remesh => EditRequest::Remesh(mesh),
                Action::Simplify => {
                    EditRequest::Simplify(mesh, world.resource::<UiState>().simplify_ratio)
                }
                _ => EditRequest::CatmullClark(mesh),
            }
        }
        Action::Navigate(relation) => EditRequest::Navigate(relation),
        // Esc first stops a running operation, as in Blender.
        Action::ClearSelection if world.resource::<super::jobs::Jobs>().running.is_some() => {
            EditRequest::CancelJob
        }
        Action::ClearSelection => EditRequest::Select(None),
        Action::DeleteMesh => EditRequest::DeleteMesh,
        Action::Undo => EditRequest::Undo,
        Action::Redo => EditRequest::Redo,
        Action::Save => EditRequest::Save(None),
        Action::Mode(mode) => {
            *world.resource_mut::<SelectMode>() = mode;
            return;
        }
        Action::Frame => {
            super::scene::frame_selection(world);
            return;
        }
        Action::ToggleSmooth => {
            let mut settings = world.resource_mut::<ViewSettings>();
            settings.smooth = !settings.smooth;
            mark_all_dirty(world);
            return;
        }
        Action::ToggleWireframe => {
            let mut settings = world.resource_mut::<ViewSettings>();
            settings.wireframe = !settings.wireframe;
            let visible = settings.wireframe;
            set_wireframes_visible(world, visible);
            if visible {
                mark_all_dirty(world);
            }
            return;
        }
        Action::ToggleHalfedges => {
            let mut settings = world.resource_mut::<ViewSettings>();
            settings.halfedges = !settings.halfedges;
            return;
        }
        Action::Open | Action::SaveAs | Action::Help => {
            let mut ui = world.resource_mut::<UiState>();
            match action {
                Action::Open => ui.focus_path = Some(PathPurpose::Open),
                Action::SaveAs => ui.focus_path = Some(PathPurpose::SaveAs),
                _ => ui.show_help = !ui.show_help,
            }
            let purpose = match action {
                Action::Open => Some(PathPurpose::Open),
                Action::SaveAs => Some(PathPurpose::SaveAs),
                _ => None,
            };
            if let Some(purpose) = purpose
                && world.contains_resource::<super::dialog::OpenDialog>()
            {
                super::dialog::show(world, purpose);
            }
            return;
        }
    };
    world.write_message(request);
}

fn refuse(world: &mut World, action: Action, reason: &str) {
    let outcome = EditOutcome {
        request: format!("{action:?}").to_lowercase(),
        result: Err(reason.to_string()),
    };
    world.write_message(outcome.clone());
    world.resource_mut::<OutcomeLog>().push(outcome);
}

fn mark_all_dirty(world: &mut World) {
    let meshes = crate::mesh::members::meshes(world);
    for m in meshes {
        world.entity_mut(m.0).insert(MeshDirty);
    }
}

/// The selected element, for the UI.
pub fn selected(world: &World) -> Option<ElementId> {
    world.resource::<Selection>().element
}
