//! The keymap: what a shortcut does ([`Action`]), the editor's own table ([`SHORTCUTS`]) and
//! the keys the registered operations declare, joined by [`shortcuts`]. The input system
//! ([`super::keyboard`]) reads it to act, the help overlay and the panel's buttons to show
//! the keys; a test holds the README's key table to it, and refuses two shortcuts on one key.

use bevy::prelude::*;

use crate::editor::session::requests::{Relation, StepMove};
use crate::editor::session::selection::SelectMode;
use crate::ops::operation::MeshOperation;

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Extrude the selected faces as one region, then drag the distance (with a halfedge
    /// active: go to its edge, as in Scotty3D).
    Extrude,
    /// Inset each selected face, then drag the amount.
    Inset,
    /// Fill the hole beside the selected boundary edge (with a halfedge active: go to its face).
    Fill,
    /// Fill the hole beside the selected boundary edge with a fair patch of triangles.
    FillFair,
    /// Proportional editing on / off.
    ToggleProportional,
    /// The selection's vertices become the anchors of handle deformation (nothing selected:
    /// no anchors).
    MarkAnchors,
    /// Run the registered operation of this step name ([`crate::ops::registry`]) with the
    /// panel's values of its parameters: on the active mesh, or on the selected element it
    /// names (of the operations sharing the name, the one that names what is selected).
    Operation(&'static str),
    /// Move the selection along a relation.
    Navigate(Relation),
    /// Change what a click selects.
    Mode(SelectMode),
    /// Select nothing.
    ClearSelection,
    /// Select nothing (never cancels a job, unlike Esc).
    SelectNone,
    /// Select every element of the click mode's kind.
    SelectAll,
    /// One ring more.
    Grow,
    /// One ring less.
    Shrink,
    /// Drag a box to select what is inside.
    BoxSelect,
    /// Move the selection with the pointer (G).
    Grab,
    /// Rotate the selection (R).
    Rotate,
    /// Scale the selection (S).
    Scale,
    /// Frame the selection (or the mesh).
    Frame,
    /// Flat / smooth shading.
    ToggleSmooth,
    /// Wireframe on / off.
    ToggleWireframe,
    /// Halfedge arrows on / off.
    ToggleHalfedges,
    /// The UV checkerboard on / off.
    ToggleChecker,
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
    /// Step mode on / off: global operations start a stepped run instead of running through.
    ToggleStepMode,
    /// Move the stepped run in progress.
    Step(StepMove),
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
    /// Alt must be held.
    pub alt: bool,
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
        alt: false,
        action,
        keys,
        description,
    }
}

const fn shift(
    key: KeyCode,
    keys: &'static str,
    action: Action,
    description: &'static str,
) -> Shortcut {
    Shortcut {
        key,
        ctrl: false,
        shift: true,
        alt: false,
        action,
        keys,
        description,
    }
}

const fn alt(
    key: KeyCode,
    keys: &'static str,
    action: Action,
    description: &'static str,
) -> Shortcut {
    Shortcut {
        key,
        ctrl: false,
        shift: false,
        alt: true,
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
        alt: false,
        action,
        keys,
        description,
    }
}

/// The keys of `action` as the help lists them (`"Ctrl+T"`), if it has a shortcut: a
/// registered operation's declared key before any other the editor gives it (erase: X, not
/// Delete).
pub fn keys_of(action: Action) -> Option<&'static str> {
    if let Action::Operation(name) = action
        && let Some(keys) =
            crate::ops::registry::operation(name).and_then(|op| op.declaration().key)
    {
        return Some(keys);
    }
    shortcuts().find(|s| s.action == action).map(|s| s.keys)
}

/// Every shortcut of the editor: the table below, then the keys the registered operations
/// declare ([`crate::ops::registry`]).
pub fn shortcuts() -> impl Iterator<Item = Shortcut> {
    // A key that does not read is left out here, and fails the keymap's test.
    // Operations that share a name and a key (collapse an edge or a face: C) are one shortcut,
    // with the first one's help.
    let all = crate::ops::registry::operations();
    let declared = all
        .clone()
        .into_iter()
        .enumerate()
        .filter_map(move |(i, op)| {
            let d = op.declaration();
            let keys = d.key?;
            let shared = all[..i]
                .iter()
                .any(|o| o.declaration().name == d.name && o.declaration().key == d.key);
            if shared {
                return None;
            }
            let chord = super::key_names::chord(keys)?;
            Some(Shortcut {
                key: chord.key,
                ctrl: chord.ctrl,
                shift: chord.shift,
                alt: chord.alt,
                action: Action::Operation(d.name),
                keys,
                description: d.help,
            })
        });
    SHORTCUTS.iter().copied().chain(declared)
}

/// The editor's own shortcuts (see [`shortcuts`] for all of them).
pub const SHORTCUTS: &[Shortcut] = &[
    key(
        KeyCode::KeyG,
        "G",
        Action::Grab,
        "move the selection (then X/Y/Z, a typed value, Enter or click; Esc cancels)",
    ),
    key(
        KeyCode::KeyR,
        "R",
        Action::Rotate,
        "rotate the selection about its centre (as G)",
    ),
    key(
        KeyCode::KeyS,
        "S",
        Action::Scale,
        "scale the selection about its centre (as G)",
    ),
    key(
        KeyCode::KeyA,
        "A",
        Action::SelectAll,
        "select all (vertices, or the click mode's kind)",
    ),
    alt(KeyCode::KeyA, "Alt+A", Action::SelectNone, "select nothing"),
    key(
        KeyCode::KeyB,
        "B",
        Action::BoxSelect,
        "box select: drag a rectangle (Shift at release adds)",
    ),
    ctrl(
        KeyCode::Equal,
        false,
        "Ctrl+=",
        Action::Grow,
        "select more: one ring around the selection",
    ),
    ctrl(
        KeyCode::Minus,
        false,
        "Ctrl+-",
        Action::Shrink,
        "select less: one ring off the selection",
    ),
    key(
        KeyCode::KeyE,
        "E",
        Action::Extrude,
        "extrude the selected faces as one region, then drag (halfedge active: go to edge)",
    ),
    key(
        KeyCode::KeyI,
        "I",
        Action::Inset,
        "inset each selected face, then drag the amount",
    ),
    key(
        KeyCode::Delete,
        "Delete",
        Action::Operation("erase"),
        "erase the selection: its faces become holes (as X)",
    ),
    key(
        KeyCode::KeyF,
        "F",
        Action::Fill,
        "fill the hole beside the selected boundary edge (halfedge active: go to face)",
    ),
    alt(
        KeyCode::KeyF,
        "Alt+F",
        Action::FillFair,
        "fill the hole beside the selected boundary edge with faired triangles",
    ),
    shift(
        KeyCode::KeyA,
        "Shift+A",
        Action::MarkAnchors,
        "anchors: the selection stays, G/R/S on a handle then deform the rest (again, empty: none)",
    ),
    alt(
        KeyCode::KeyO,
        "Alt+O",
        Action::ToggleProportional,
        "proportional editing on / off (G, R, S take the vertices within the radius along)",
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
        "cancel the running operation or stepped run, else select nothing",
    ),
    key(
        KeyCode::Period,
        ".",
        Action::Frame,
        "frame the selection (or the next collapse while stepping, or the mesh)",
    ),
    key(
        KeyCode::Home,
        "Home",
        Action::Frame,
        "frame the selection (or the next collapse while stepping, or the mesh)",
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
    shift(
        KeyCode::KeyW,
        "Shift+W",
        Action::ToggleHalfedges,
        "halfedge arrows on / off",
    ),
    shift(
        KeyCode::KeyC,
        "Shift+C",
        Action::ToggleChecker,
        "UV checkerboard on / off (meshes with UVs)",
    ),
    ctrl(
        KeyCode::Delete,
        false,
        "Ctrl+Delete",
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
    key(
        KeyCode::F9,
        "F9",
        Action::ToggleStepMode,
        "step mode on / off: Shift+S, M, L, Q and an ARAP handle drag then run a step at a time",
    ),
    key(
        KeyCode::ArrowRight,
        "Right",
        Action::Step(StepMove::Forward(1)),
        "step mode: one step forward",
    ),
    shift(
        KeyCode::ArrowRight,
        "Shift+Right",
        Action::Step(StepMove::Forward(10)),
        "step mode: 10 steps forward",
    ),
    ctrl(
        KeyCode::ArrowRight,
        false,
        "Ctrl+Right",
        Action::Step(StepMove::Forward(100)),
        "step mode: 100 steps forward",
    ),
    key(
        KeyCode::End,
        "End",
        Action::Step(StepMove::Forward(usize::MAX)),
        "step mode: to the end",
    ),
    key(
        KeyCode::ArrowLeft,
        "Left",
        Action::Step(StepMove::Back(1)),
        "step mode: one step back",
    ),
    shift(
        KeyCode::ArrowLeft,
        "Shift+Left",
        Action::Step(StepMove::Back(10)),
        "step mode: 10 steps back",
    ),
    ctrl(
        KeyCode::ArrowLeft,
        false,
        "Ctrl+Left",
        Action::Step(StepMove::Back(100)),
        "step mode: 100 steps back",
    ),
    key(
        KeyCode::Enter,
        "Enter",
        Action::Step(StepMove::Finish),
        "step mode: keep the mesh where the run is (one undo step)",
    ),
    key(KeyCode::F1, "F1", Action::Help, "show / hide this help"),
    shift(KeyCode::Slash, "?", Action::Help, "show / hide this help"),
];

/// The registered operation an action runs, if it runs one.
pub(super) fn registered(action: Action) -> Option<&'static dyn MeshOperation> {
    match action {
        Action::Operation(name) => crate::ops::registry::operation(name),
        _ => None,
    }
}

/// The shortcut matching a key press with exactly the given modifiers, if any.
pub fn shortcut_for(key: KeyCode, ctrl: bool, shift: bool, alt: bool) -> Option<Shortcut> {
    shortcuts().find(|s| s.key == key && s.ctrl == ctrl && s.shift == shift && s.alt == alt)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The README's key table (its first `| key | does |` table) and the keymap agree: every
    /// shortcut is written in it (in the key column, or in backticks in a row, as the pick
    /// modes are), and every key its key column names is a shortcut.
    #[test]
    fn the_readme_key_table_is_the_keymap() {
        let readme = include_str!("../../../README.md");
        let rows: Vec<&str> = readme
            .lines()
            .skip_while(|line| !line.starts_with("| key | does |"))
            .skip(2)
            .take_while(|line| line.starts_with('|'))
            .collect();
        assert!(
            rows.len() > 30,
            "the README's key table: {} rows",
            rows.len()
        );
        let text = rows.join("\n");
        let words: Vec<&str> = rows
            .iter()
            .flat_map(|row| row.split('|').nth(1).unwrap_or("").split([' ', ',']))
            .map(|word| word.trim_matches('`'))
            .filter(|word| !word.is_empty())
            .collect();
        let all: Vec<Shortcut> = shortcuts().collect();
        for shortcut in &all {
            let k = shortcut.keys;
            let written = words.contains(&k)
                || text.contains(&format!("`{k}`"))
                || text.contains(&format!("`` {k} ``"));
            assert!(
                written,
                "{k} ({:?}) is not in the README's key table",
                shortcut.action
            );
        }
        // A word of the key column that reads as a key (a lone lower-case letter is a word).
        let is_key = |word: &str| {
            let lower = word.chars().all(|c| c.is_ascii_lowercase());
            !lower && crate::editor::input::key_names::chord(word).is_some()
        };
        for word in words.iter().filter(|w| is_key(w)) {
            assert!(
                all.iter().any(|s| s.keys == *word),
                "the README's key table names {word}, which is no shortcut"
            );
        }
    }

    /// The keymap holds every key a registered operation declares, with its help line, and
    /// no two shortcuts (declared or the editor's own) share a key with the same modifiers.
    #[test]
    fn declared_keys_join_the_keymap_and_no_two_shortcuts_collide() {
        let all: Vec<Shortcut> = shortcuts().collect();
        for op in crate::ops::registry::operations() {
            let d = op.declaration();
            let Some(keys) = d.key else { continue };
            let chord = crate::editor::input::key_names::chord(keys)
                .unwrap_or_else(|| panic!("{}'s key `{keys}` does not read", d.name));
            let found = shortcut_for(chord.key, chord.ctrl, chord.shift, chord.alt).unwrap();
            assert_eq!(found.action, Action::Operation(d.name));
            // Operations that share a name and a key have the first one's help.
            let first = crate::ops::registry::operation(d.name)
                .unwrap()
                .declaration();
            assert_eq!((found.keys, found.description), (keys, first.help));
            assert_eq!(keys_of(Action::Operation(d.name)), Some(keys));
        }
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert!(
                    (a.key, a.ctrl, a.shift, a.alt) != (b.key, b.ctrl, b.shift, b.alt),
                    "{} is both {:?} and {:?}",
                    a.keys,
                    a.action,
                    b.action
                );
            }
        }
    }
}
