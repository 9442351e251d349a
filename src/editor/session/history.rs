//! Undo and redo for every edit (Ctrl+Z; Ctrl+Shift+Z or Ctrl+Y).
//!
//! Before an edit runs, [`begin_edit`] captures what it may change, by its
//! [`crate::edit::Edit::reach`] (see [`crate::mesh::change`]): the neighbourhood of a local
//! edit, the tables of a mesh-wide one; [`begin_replace`] captures the whole mesh before an open
//! or a delete. Once the edit has succeeded,
//! [`commit`] turns that into an [`Entry`] on the undo stack; a refused edit leaves no entry.
//! Undoing applies the entry's record and keeps its inverse on the redo stack, and the other
//! way round; any new edit clears the redo stack.
//!
//! Elements brought back by an undo get new entities (Bevy never reuses an id), so every
//! application returns a remap, which is passed to the entries that name the restored state:
//! the rest of the stack the entry came from. The selection is remapped the same way and
//! returns to what it was on the restored side, and so are the values a script gave by entity
//! (`pappus.show`'s arrays: [`registry::quantities_follow`]).
//!
//! The entries hold only what changed, and their bytes are counted: past
//! [`UndoHistory::limit_bytes`] the oldest are dropped. Consecutive moves of one vertex within
//! one press of the mouse button (a drag, a drag of a panel field) are one entry, as are the
//! steps of one drag of the level-of-detail slider.

use bevy::input::ButtonInput;
use bevy::input::mouse::MouseButton;
use bevy::prelude::{Res, ResMut, Resource, World};

use crate::mesh::MeshInfo;
use crate::mesh::change::{Change, LocalRecorder, Remap, SavedContents, SavedMesh, remapped};
use crate::mesh::despawn_mesh;
use crate::mesh::ids::{ElementId, MeshId};
use crate::mesh::tables::MeshTables;
use crate::mesh::topology::MeshRef;
use crate::ops::registry;

use crate::edit::{Edit, MergeKey, Reach, Redraw};

use super::origins::Origins;
use super::selection::{ActiveMesh, Selection, exists, keep_live_selection};

/// What an entry puts back.
enum Record {
    /// A local edit's changed elements.
    Local(Change),
    /// A mesh's whole contents (the mesh entity stays).
    Whole(SavedContents),
    /// One mesh replaced by another: `remove` is despawned, `restore` spawned again.
    Replace {
        remove: Option<MeshId>,
        restore: Option<SavedMesh>,
    },
}

impl Record {
    fn bytes(&self) -> usize {
        match self {
            Record::Local(c) => c.bytes(),
            Record::Whole(t) => t.bytes(),
            Record::Replace { restore, .. } => restore.as_ref().map_or(0, SavedMesh::bytes),
        }
    }

    fn remap(&mut self, map: &mut Remap) {
        match self {
            Record::Local(c) => c.remap(map),
            Record::Whole(t) => t.remap(map),
            Record::Replace { remove, restore } => {
                if let Some(m) = remove {
                    *m = MeshId(remapped(map, m.0));
                }
                if let Some(s) = restore {
                    s.remap(map);
                }
            }
        }
    }

    /// Applies the record: returns its inverse, the remap, and the mesh it changed (none when
    /// it removed the only one) with what of it to redraw.
    fn apply(self, world: &mut World) -> (Record, Remap, Option<MeshId>, Redraw) {
        match self {
            Record::Local(change) => {
                let mesh = change.mesh;
                let (inverse, map, touched) = change.apply(world);
                let redraw = Redraw::near(world, touched.removed_faces, touched.vertices);
                (Record::Local(inverse), map, Some(mesh), redraw)
            }
            Record::Whole(saved) => {
                let mesh = saved.mesh;
                let (inverse, map) = saved.apply(world);
                (Record::Whole(inverse), map, Some(mesh), Redraw::Whole)
            }
            Record::Replace { remove, restore } => {
                let saved = remove
                    .filter(|m| world.get::<MeshInfo>(m.0).is_some())
                    .map(|m| {
                        let saved = SavedMesh::capture(world, m);
                        despawn_mesh(world, m);
                        saved
                    });
                let (mesh, map) = match restore {
                    Some(s) => {
                        let (mesh, map) = s.restore(world);
                        (Some(mesh), map)
                    }
                    None => (None, Remap::default()),
                };
                world.resource_mut::<ActiveMesh>().0 = mesh;
                let inverse = Record::Replace {
                    remove: mesh,
                    restore: saved,
                };
                (inverse, map, mesh, Redraw::Whole)
            }
        }
    }
}

/// One undoable step.
pub struct Entry {
    /// What the edit was (the request's label).
    pub label: String,
    record: Record,
    /// The selection on the side this entry restores.
    selection: Option<ElementId>,
    /// Set while later edits of the same kind may merge into this entry.
    merge: Option<(MergeKey, u64)>,
    bytes: usize,
    /// The entry's number, in the order edits were made (an undone entry keeps it on the redo
    /// stack and back): what a gesture's cancel counts back to ([`UndoHistory::mark`]).
    serial: u64,
}

impl Entry {
    fn new(
        label: String,
        record: Record,
        selection: Option<ElementId>,
        merge: Option<(MergeKey, u64)>,
    ) -> Self {
        let bytes = record.bytes() + label.capacity() + std::mem::size_of::<Entry>();
        Self {
            label,
            record,
            selection,
            merge,
            bytes,
            serial: 0,
        }
    }

    /// The entry's number (see [`UndoHistory::mark`]).
    pub fn serial(&self) -> u64 {
        self.serial
    }

    /// Bytes the entry holds.
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    fn remap(&mut self, map: &mut Remap) {
        self.record.remap(map);
        self.selection = self.selection.map(|x| remap_element(x, map));
    }
}

/// The undo and redo stacks.
#[derive(Resource)]
pub struct UndoHistory {
    undo: Vec<Entry>,
    redo: Vec<Entry>,
    /// The most bytes the entries may hold together; the oldest go first (the newest entry
    /// always stays, however large).
    pub limit_bytes: usize,
    /// Counts presses of the left mouse button; edits within one press may merge.
    press: u64,
    pressed: bool,
    /// A gesture (a keyboard-driven transform) is under way: its edits may merge as a drag's.
    gesture: bool,
    /// The serial number the next entry gets.
    next_serial: u64,
}

impl Default for UndoHistory {
    fn default() -> Self {
        Self {
            undo: Vec::new(),
            redo: Vec::new(),
            limit_bytes: Self::DEFAULT_LIMIT_BYTES,
            press: 0,
            pressed: false,
            gesture: false,
            next_serial: 0,
        }
    }
}

impl UndoHistory {
    /// The default memory cap: 512 MiB.
    pub const DEFAULT_LIMIT_BYTES: usize = 512 << 20;

    /// The undoable entries, oldest first.
    pub fn undo_entries(&self) -> &[Entry] {
        &self.undo
    }

    /// The redoable entries, the next one to redo last.
    pub fn redo_entries(&self) -> &[Entry] {
        &self.redo
    }

    /// Bytes held by both stacks.
    pub fn bytes(&self) -> usize {
        self.undo.iter().chain(&self.redo).map(|e| e.bytes).sum()
    }

    /// The undo stack, or the redo stack.
    fn stack(&mut self, redo: bool) -> &mut Vec<Entry> {
        if redo { &mut self.redo } else { &mut self.undo }
    }

    /// The mark of the history now: the entries made after this call have serial numbers at
    /// least this. A cancelled gesture takes back the entries from its mark on
    /// ([`crate::editor::session::requests::Request::Retract`]), however many the memory cap has
    /// dropped from the old end meanwhile.
    pub fn mark(&self) -> u64 {
        self.next_serial
    }

    fn push(&mut self, mut entry: Entry) {
        entry.serial = self.next_serial;
        self.next_serial += 1;
        self.redo.clear();
        self.undo.push(entry);
        self.trim();
    }

    /// Drops the oldest entries past the memory cap, keeping at least the newest one.
    fn trim(&mut self) {
        let mut total = self.bytes();
        let mut drop = 0;
        while total > self.limit_bytes && drop + 1 < self.undo.len() {
            total -= self.undo[drop].bytes;
            drop += 1;
        }
        self.undo.drain(..drop);
    }

    /// Starts a gesture: its edits merge into one entry as the frames of a drag do (and never
    /// into an entry from before it).
    pub fn begin_gesture(&mut self) {
        self.press += 1;
        self.gesture = true;
    }

    /// Ends the gesture.
    pub fn end_gesture(&mut self) {
        self.gesture = false;
    }

    /// Forgets the entry undone last (a cancelled gesture leaves nothing to redo).
    pub fn forget_undone(&mut self) {
        self.redo.pop();
    }

    fn can_merge(&self, key: MergeKey) -> bool {
        (self.pressed || self.gesture)
            && self.redo.is_empty()
            && self
                .undo
                .last()
                .is_some_and(|e| e.merge == Some((key, self.press)))
    }
}

/// Follows the left mouse button, so that a drag's edits merge into one entry (the `Input`
/// set; without a mouse nothing merges).
pub fn track_presses(
    buttons: Option<Res<ButtonInput<MouseButton>>>,
    mut history: ResMut<UndoHistory>,
) {
    let Some(buttons) = buttons else {
        return;
    };
    // The click that confirms a gesture stays part of it (its last frame merges).
    if buttons.just_pressed(MouseButton::Left) && !history.gesture {
        history.press += 1;
    }
    history.pressed = buttons.pressed(MouseButton::Left);
}

/// What [`begin_edit`] or [`begin_replace`] captured before an edit.
pub struct Pending {
    kind: PendingKind,
    selection: Option<ElementId>,
    merge: Option<MergeKey>,
}

impl Pending {
    /// The mesh's tables, when this is the record of a whole-mesh edit.
    pub fn tables(&self) -> Option<&MeshTables> {
        match &self.kind {
            PendingKind::Whole(saved) => Some(&saved.tables),
            _ => None,
        }
    }
}

enum PendingKind {
    Local(LocalRecorder),
    Whole(SavedContents),
    Replace(Option<SavedMesh>),
    /// The edit continues the last entry.
    Merge,
}

/// Captures what `edit` may change in `mesh`, before it runs. `None` when it names what is
/// gone (it will be refused and change nothing).
pub fn begin_edit(world: &World, edit: &Edit, mesh: MeshId) -> Option<Pending> {
    let merge = edit.merge_key();
    let kind = if merge.is_some_and(|key| world.resource::<UndoHistory>().can_merge(key)) {
        PendingKind::Merge
    } else {
        match edit.reach(world, mesh)? {
            // An edit that later frames may merge into records every seed even if this frame
            // leaves it in place: a later frame may move it.
            Reach::Local(mesh, seeds) => PendingKind::Local(
                LocalRecorder::begin(world, mesh, &seeds).keeping_seeds(merge.is_some()),
            ),
            Reach::Vertices(mesh, seeds) => PendingKind::Local(
                LocalRecorder::begin_vertices(world, mesh, &seeds).keeping_seeds(merge.is_some()),
            ),
            Reach::Whole(mesh) => PendingKind::Whole(SavedContents::capture(world, mesh)),
        }
    };
    Some(Pending {
        kind,
        selection: world.resource::<Selection>().element,
        merge,
    })
}

/// Captures the active mesh whole, before it is replaced (an open) or deleted. `None` when
/// there is no mesh: opening over no mesh loses nothing (the file is still there), so that the
/// first Ctrl+Z never empties the editor.
pub fn begin_replace(world: &World) -> Option<Pending> {
    let active = world.resource::<ActiveMesh>().0;
    let saved = active
        .filter(|a| world.get::<MeshInfo>(a.0).is_some())
        .map(|a| SavedMesh::capture(world, a))?;
    Some(Pending {
        kind: PendingKind::Replace(Some(saved)),
        selection: world.resource::<Selection>().element,
        merge: None,
    })
}

/// Records a successful edit as an entry (clearing the redo stack).
pub fn commit(world: &mut World, pending: Pending, label: String) {
    let record = match pending.kind {
        PendingKind::Local(recorder) => {
            let change = recorder.finish(world);
            if change.is_empty() {
                return;
            }
            Record::Local(change)
        }
        PendingKind::Whole(saved) => Record::Whole(saved),
        PendingKind::Replace(restore) => Record::Replace {
            remove: world.resource::<ActiveMesh>().0,
            restore,
        },
        PendingKind::Merge => {
            world.resource_mut::<UndoHistory>().redo.clear();
            return;
        }
    };
    let mut history = world.resource_mut::<UndoHistory>();
    let merge = pending.merge.map(|key| (key, history.press));
    history.push(Entry::new(label, record, pending.selection, merge));
}

/// Puts the mesh back as `pending` captured it, and the selection as it was then, and records
/// nothing: an edit taken back before it was committed (a stepped run cancelled). The undo
/// and redo entries follow the restored elements' new ids. Only a whole-mesh capture can be
/// put back: returns the remap of the ids it restored, `None` for any other capture.
pub fn restore(world: &mut World, pending: Pending) -> Option<Remap> {
    let PendingKind::Whole(saved) = pending.kind else {
        return None;
    };
    let (_, mut map) = saved.apply(world);
    let history = &mut *world.resource_mut::<UndoHistory>();
    for entry in history.undo.iter_mut().chain(history.redo.iter_mut()) {
        entry.remap(&mut map);
    }
    follow_renamed_elsewhere(world, &map);
    let selection = pending
        .selection
        .map(|x| remap_element(x, &mut map))
        .filter(|&x| exists(&MeshRef::new(world), x));
    world.resource_mut::<Selection>().select_only(selection);
    Some(map)
}

/// What an undo or redo did.
pub struct Stepped {
    /// The entry's label.
    pub label: String,
    /// The mesh the entry changed (now the active one), `None` when it removed the only one.
    pub mesh: Option<MeshId>,
    /// What of it to redraw: the faces around the vertices the entry brought back or changed
    /// and the faces it removed, or the whole mesh.
    pub redraw: Redraw,
}

/// Undoes the last entry (`redo == false`) or redoes the last undone one.
///
/// `None` when there is nothing to undo (or redo); nothing changes then.
pub fn step(world: &mut World, redo: bool) -> Option<Stepped> {
    let entry = world.resource_mut::<UndoHistory>().stack(redo).pop()?;
    let now_selected = world.resource::<Selection>().element;
    let (inverse, mut map, mesh, redraw) = entry.record.apply(world);
    for other in world.resource_mut::<UndoHistory>().stack(redo).iter_mut() {
        other.remap(&mut map);
    }
    follow_renamed_elsewhere(world, &map);
    let selection = entry
        .selection
        .map(|x| remap_element(x, &mut map))
        .filter(|&x| exists(&MeshRef::new(world), x));
    let mut back = Entry::new(entry.label.clone(), inverse, now_selected, None);
    back.serial = entry.serial;
    let mut history = world.resource_mut::<UndoHistory>();
    if redo {
        history.undo.push(back);
        history.trim();
    } else {
        history.redo.push(back);
    }
    keep_live_selection(world, |_| true);
    if let Some(x) = selection {
        world.resource_mut::<Selection>().add(x);
    }
    Some(Stepped {
        label: entry.label,
        mesh,
        redraw,
    })
}

/// What keeps values by entity beside the mesh follows the elements an undo, a redo or a
/// restore brought back under new entities: a script's arrays and the show session's origins.
fn follow_renamed_elsewhere(world: &mut World, map: &Remap) {
    registry::quantities_follow(world.id(), map);
    if let Some(mut origins) = world.get_resource_mut::<Origins>() {
        origins.follow(map);
    }
}

fn remap_element(x: ElementId, map: &mut Remap) -> ElementId {
    x.with_entity(remapped(map, x.entity()))
}
