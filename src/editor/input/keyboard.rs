//! The input system of the keyboard: a key press found in the keymap ([`super::shortcuts`])
//! becomes its action — a request, a gesture begun or a view setting flipped.
//!
//! Shortcuts only write [`Request`]s or flip view settings; they never touch a mesh. An edit's
//! parameters are the panel's ([`UiState`]), the same structs and defaults as the command
//! line's. Shortcuts are ignored while egui wants the keyboard (typing in a text field), which
//! the UI reports through [`KeyboardCaptured`](crate::editor::session::schedule::KeyboardCaptured).

use crate::editor::pipeline::stepping::Stepping;
use crate::editor::session::requests::StepMove;
use bevy::prelude::*;

use crate::edit::{Edit, Invocation};
use crate::mesh::MeshRef;
use crate::mesh::ids::ElementId;
use crate::ops::Refusal;
use crate::ops::declaration::Names;
use crate::ops::operation::MeshOperation;

use crate::editor::gestures::box_select::BoxSelect;
use crate::editor::gestures::handle_deform::Anchors;
use crate::editor::gestures::transform::{GestureKind, Gestures};
use crate::editor::pipeline::jobs::Jobs;
use crate::editor::session::dialog::{OpenDialog, PathPurpose};
use crate::editor::session::finish::report;
use crate::editor::session::panel_state::UiState;
use crate::editor::session::requests::SelectionEdit;
use crate::editor::session::requests::{Declined, Relation, Request};
use crate::editor::session::selection::{
    ActiveMesh, LooksDirty, SelectMode, Selection, selected_edge, selected_faces,
};
use crate::editor::view::render_sync::ViewSettings;
use crate::editor::view::wireframe::set_wireframes_visible;

use super::shortcuts::{Action, registered, shortcut_for};

/// Reads key presses and performs their actions (the `Input` set).
pub fn keyboard_shortcuts(world: &mut World) {
    let gesture = world
        .get_resource::<Gestures>()
        .is_some_and(|g| g.active.is_some() || g.keys_taken);
    if gesture
        || world
            .get_resource::<crate::editor::session::schedule::KeyboardCaptured>()
            .is_some_and(|k| k.0)
    {
        return;
    }
    let keys = world.resource::<ButtonInput<KeyCode>>();
    let ctrl = keys.any_pressed([KeyCode::ControlLeft, KeyCode::ControlRight]);
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    let alt = keys.any_pressed([KeyCode::AltLeft, KeyCode::AltRight]);
    let pressed: Vec<KeyCode> = keys.get_just_pressed().copied().collect();
    for key in pressed {
        // Once a key starts a transform (or an extrusion whose height one follows), the other
        // keys of the frame are the gesture's (`X` constrains rather than erases).
        let gesture = world
            .get_resource::<Gestures>()
            .is_some_and(|g| g.active.is_some() || g.after_edit.is_some());
        if gesture {
            break;
        }
        if let Some(shortcut) = shortcut_for(key, ctrl, shift, alt) {
            perform(world, shortcut.action);
        }
    }
}

/// Performs an action: writes the request it stands for, or changes a setting.
pub fn perform(world: &mut World, action: Action) {
    // A box armed before a transform (or an extrusion's height) would take its confirming click.
    if matches!(
        action,
        Action::Grab | Action::Rotate | Action::Scale | Action::Extrude | Action::Inset
    ) && let Some(mut armed) = world.get_resource_mut::<BoxSelect>()
    {
        *armed = BoxSelect::default();
    }
    // A gesture counts the undo entries when it starts, to take back to them on Esc: a
    // stepped run ends first, so its entry is counted and stays.
    if matches!(
        action,
        Action::Grab | Action::Rotate | Action::Scale | Action::Extrude | Action::Inset
    ) && world.resource::<Stepping>().run.is_some()
    {
        let ended = crate::editor::pipeline::stepping::end_run(world)
            .map(|()| "the stepped run is kept".into());
        report(world, "end the stepped run".into(), ended, 0.0);
    }
    match request_for(world, action) {
        Ok(Some(request)) => {
            world.write_message(request);
        }
        Ok(None) => {}
        Err(why) => report(world, action_words(action), Err(why), 0.0),
    }
}

/// An action in a person's words, for the status line ("flip", "split vertex back", "fill
/// hole"): a local edge operation by its step name, the others by their name split into words.
fn action_words(action: Action) -> String {
    if let Some(op) = registered(action) {
        return op.declaration().title.to_lowercase();
    }
    let name = format!("{action:?}");
    let mut words = String::with_capacity(name.len() + 4);
    for (i, c) in name.chars().take_while(|c| c.is_alphanumeric()).enumerate() {
        if c.is_uppercase() && i > 0 {
            words.push(' ');
        }
        words.extend(c.to_lowercase());
    }
    words
}

/// The request an action stands for (`None` for actions that only change a setting, done
/// here), or why it cannot be asked now.
fn request_for(world: &mut World, action: Action) -> Result<Option<Request>, Declined> {
    let edit = match selection_edit(world, action)? {
        Some(edit) => edit,
        None => match whole_mesh_edit(world, action)? {
            Some(edit) => edit,
            None => return act(world, action),
        },
    };
    if world.resource::<Stepping>().enabled && edit.can_step() {
        return Ok(Some(Request::StartStepped(edit)));
    }
    Ok(Some(Request::Edit(edit)))
}

/// E and F on a single halfedge walk to its edge and face, as the inspector's keys do.
fn walks_instead(world: &World, action: Action) -> bool {
    let selection = world.resource::<Selection>();
    matches!(action, Action::Extrude | Action::Fill)
        && matches!(selection.element, Some(ElementId::Halfedge(_)))
        && selection.len() == 1
}

/// The edit an action asks of the selection (`None` for an action that is not one), or what
/// must be selected first.
fn selection_edit(world: &mut World, action: Action) -> Result<Option<Edit>, Declined> {
    if walks_instead(world, action) {
        return Ok(None);
    }
    let selection = world.resource::<Selection>().element;
    let m = MeshRef::new(world);
    let edit = match action {
        Action::Fill | Action::FillFair => {
            let edge = selected_edge(&m, selection)
                .ok_or(Declined::SelectFirst("a boundary edge".into()))?;
            let fill = match action {
                Action::FillFair => Some(crate::ops::hole::FillHole::FAIR),
                _ => None,
            };
            let given: Vec<Option<f64>> = fill.into_iter().map(Some).collect();
            Edit::Operation(
                Invocation::new(&crate::ops::hole::FillHole, &given)
                    .and_then(|i| i.on(vec![ElementId::Edge(edge)]))
                    .map_err(Refusal::BadParameter)?,
            )
        }
        Action::Extrude | Action::Inset => {
            let faces = selected_faces(world);
            if faces.is_empty() {
                return Err(Declined::SelectFirst("faces (mode 3)".into()));
            }
            let op: &'static dyn MeshOperation = match action {
                Action::Extrude => &crate::ops::local::Extrude,
                _ => &crate::ops::local::Inset,
            };
            let faces = faces.into_iter().map(ElementId::Face).collect();
            let edit = Edit::Operation(
                Invocation::with_defaults(op)
                    .on(faces)
                    .map_err(Refusal::BadParameter)?,
            );
            let undo_mark = world
                .resource::<crate::editor::session::history::UndoHistory>()
                .mark();
            world.resource_mut::<Gestures>().after_edit =
                Some(crate::editor::gestures::transform::FollowUp {
                    label: edit.label(),
                    inset: action == Action::Inset,
                    undo_mark,
                });
            edit
        }
        _ => return Ok(None),
    };
    Ok(Some(edit))
}

/// The whole-mesh edit an action asks for, with the panel's parameters (`None` for an action
/// that is not one), or that there is no mesh.
fn whole_mesh_edit(world: &mut World, action: Action) -> Result<Option<Edit>, Declined> {
    let edit = match action {
        Action::Operation(name) => {
            world.resource::<ActiveMesh>().0.ok_or(Declined::NoMesh)?;
            Edit::Operation(registered_invocation(world, name)?)
        }
        _ => return Ok(None),
    };
    Ok(Some(edit))
}

/// The registered operation called `name` with the panel's values: on the active mesh, or on
/// the selected element of the kind it names (of the operations sharing the name, the first
/// whose kind is selected: `C` collapses an edge or a face).
///
/// # Declines
/// No registered operation of that name; none that names what is selected (the message says
/// what to select).
fn registered_invocation(world: &World, name: &str) -> Result<Invocation, Declined> {
    let mut needs = Vec::new();
    for op in crate::ops::registry::operations_named(name) {
        let names = op.declaration().names;
        let invocation = world.resource::<UiState>().invocation(op);
        if names == Names::Mesh {
            return Ok(invocation);
        }
        let elements = selected_for(world, names);
        if names.admits(&elements) {
            return invocation
                .on(elements)
                .map_err(|why| Refusal::BadParameter(why).into());
        }
        needs.push(names.select_first());
    }
    match needs.is_empty() {
        true => Err(Refusal::BadParameter(format!("no operation is called `{name}`")).into()),
        false => Err(Declined::SelectFirst(needs.join(" or "))),
    }
}

/// What the selection offers an operation that names `names`: the active edge (or the active
/// halfedge's), vertex or face, the selected faces, the first two selected edges, or every
/// selected element (the selection's set holds live elements only).
fn selected_for(world: &World, names: Names) -> Vec<ElementId> {
    let selection = world.resource::<Selection>();
    let m = MeshRef::new(world);
    let active = selection.element.filter(|&x| match x {
        ElementId::Vertex(v) => m.try_vertex(v).is_some(),
        ElementId::Face(f) => m.try_face(f).is_some(),
        _ => true,
    });
    match (names, active) {
        (Names::Edge, _) => selected_edge(&m, active)
            .map(ElementId::Edge)
            .into_iter()
            .collect(),
        (Names::Vertex, Some(x @ ElementId::Vertex(_)))
        | (Names::Face, Some(x @ ElementId::Face(_))) => {
            vec![x]
        }
        (Names::Faces, _) => selected_faces(world)
            .into_iter()
            .map(ElementId::Face)
            .collect(),
        (Names::TwoEdges, _) => {
            let edges = selection
                .elements()
                .iter()
                .filter_map(|&x| selected_edge(&m, Some(x)));
            edges.take(2).map(ElementId::Edge).collect()
        }
        (Names::Elements, _) => selection.elements().to_vec(),
        // Smoothing holds the selected vertices.
        (Names::MeshHolding, _) => selection
            .elements()
            .iter()
            .filter(|x| matches!(x, ElementId::Vertex(_)))
            .copied()
            .collect(),
        // Fairing moves the selection's vertices (the corners of selected faces and edges too).
        (Names::Vertices, _) => crate::editor::gestures::transform::selected_vertices(world)
            .into_iter()
            .map(ElementId::Vertex)
            .collect(),
        // The selected halfedge's face, split from its tip to the corner two ahead.
        (Names::FaceCorners, Some(ElementId::Halfedge(h))) if m.try_halfedge(h).is_some() => m
            .face(h)
            .map(|f| {
                let (a, b) = (m.to_vertex(h), m.to_vertex(m.next(m.next(h))));
                vec![
                    ElementId::Face(f),
                    ElementId::Vertex(a),
                    ElementId::Vertex(b),
                ]
            })
            .unwrap_or_default(),
        _ => Vec::new(),
    }
}

/// What an action that is not an edit does: a request (walk, select, undo, save, step) or a
/// setting changed here (view toggles, modes, a gesture started, a dialog shown).
fn act(world: &mut World, action: Action) -> Result<Option<Request>, Declined> {
    match action {
        Action::Extrude | Action::Fill if walks_instead(world, action) => {
            let to = match action {
                Action::Extrude => Relation::Edge,
                _ => Relation::Face,
            };
            Ok(Some(Request::Navigate(to)))
        }
        Action::MarkAnchors => {
            let vertices = crate::editor::gestures::transform::selected_vertices(world);
            let count = vertices.len();
            world.resource_mut::<Anchors>().vertices = vertices;
            let summary = match count {
                0 => "no anchors: G, R and S move the selection alone".to_string(),
                n => format!("{n} anchor vertices: G, R and S on a handle now deform the mesh"),
            };
            report(world, "anchors".into(), Ok(summary), 0.0);
            Ok(None)
        }
        Action::ToggleProportional => {
            let mut ui = world.resource_mut::<UiState>();
            ui.proportional.enabled = !ui.proportional.enabled;
            Ok(None)
        }
        Action::Navigate(relation) => Ok(Some(Request::Navigate(relation))),
        // Esc first stops a running operation, as in Blender.
        Action::ClearSelection if world.resource::<Jobs>().running.is_some() => {
            Ok(Some(Request::CancelJob))
        }
        Action::ClearSelection if world.resource::<Stepping>().run.is_some() => {
            Ok(Some(Request::Step(StepMove::Cancel)))
        }
        // The arrows, End and Enter do nothing without a run (Enter may end a text field).
        Action::Step(_) if world.resource::<Stepping>().run.is_none() => Ok(None),
        Action::Step(movement) => Ok(Some(Request::Step(movement))),
        Action::ToggleStepMode => {
            let mut stepping = world.resource_mut::<Stepping>();
            stepping.enabled = !stepping.enabled;
            Ok(None)
        }
        Action::ClearSelection | Action::SelectNone => Ok(Some(Request::Select(None))),
        Action::SelectAll => Ok(Some(SelectionEdit::All.into())),
        Action::Grow => Ok(Some(SelectionEdit::Grow.into())),
        Action::Shrink => Ok(Some(SelectionEdit::Shrink.into())),
        Action::BoxSelect => {
            world.resource_mut::<BoxSelect>().armed = true;
            Ok(None)
        }
        Action::Grab | Action::Rotate | Action::Scale => {
            let kind = match action {
                Action::Grab => GestureKind::Grab,
                Action::Rotate => GestureKind::Rotate,
                _ => GestureKind::Scale,
            };
            if world.resource::<Selection>().is_empty() {
                return Err(Declined::SelectFirst("something to transform".into()));
            }
            let proportional = world.resource::<UiState>().proportional;
            crate::editor::gestures::transform::start(world, kind, None, Some(proportional));
            Ok(None)
        }
        Action::DeleteMesh => Ok(Some(Request::DeleteMesh)),
        Action::Undo => Ok(Some(Request::Undo)),
        Action::Redo => Ok(Some(Request::Redo)),
        Action::Save => Ok(Some(Request::Save(None))),
        Action::Mode(mode) => {
            *world.resource_mut::<SelectMode>() = mode;
            Ok(None)
        }
        Action::Frame => {
            crate::editor::gestures::camera::frame_selection(world);
            Ok(None)
        }
        Action::ToggleSmooth
        | Action::ToggleWireframe
        | Action::ToggleChecker
        | Action::ToggleHalfedges => {
            toggle_view(world, action);
            Ok(None)
        }
        Action::Open | Action::SaveAs | Action::Help => {
            let purpose = match action {
                Action::Open => Some(PathPurpose::Open),
                Action::SaveAs => Some(PathPurpose::SaveAs),
                _ => None,
            };
            let mut ui = world.resource_mut::<UiState>();
            match purpose {
                Some(purpose) => ui.focus_path = Some(purpose),
                None => ui.show_help = !ui.show_help,
            }
            if let Some(purpose) = purpose
                && world.contains_resource::<OpenDialog>()
            {
                crate::editor::session::dialog::show(world, purpose);
            }
            Ok(None)
        }
        _ => Ok(None),
    }
}

/// Turns a view setting on or off (smooth shading, wireframe, checker, halfedge arrows) and
/// marks what must be drawn again.
fn toggle_view(world: &mut World, action: Action) {
    let mut settings = world.resource_mut::<ViewSettings>();
    match action {
        Action::ToggleSmooth => settings.smooth = !settings.smooth,
        Action::ToggleChecker => settings.checker = !settings.checker,
        Action::ToggleHalfedges => {
            // The overlay draws the arrows each frame; nothing to redraw.
            settings.halfedges = !settings.halfedges;
            return;
        }
        Action::ToggleWireframe => {
            settings.wireframe = !settings.wireframe;
            let visible = settings.wireframe;
            set_wireframes_visible(world, visible);
            if !visible {
                return;
            }
        }
        _ => return,
    }
    // Every mesh drawn anew, its geometry as it was.
    for m in crate::mesh::members::meshes(world) {
        world.entity_mut(m.0).insert(LooksDirty);
    }
}

/// The selected element, for the UI.
pub fn selected(world: &World) -> Option<ElementId> {
    world.resource::<Selection>().element
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn actions_are_named_in_words_on_the_status_line() {
        assert_eq!(action_words(Action::Operation("flip")), "flip");
        assert_eq!(action_words(Action::ToggleStepMode), "toggle step mode");
        assert_eq!(action_words(Action::FillFair), "fill fair");
        assert_eq!(action_words(Action::Navigate(Relation::Twin)), "navigate");
        assert_eq!(
            action_words(Action::Operation("orient-outside")),
            "orient outside"
        );
    }
}
