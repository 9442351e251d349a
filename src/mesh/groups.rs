//! Face groups: which object, group, material and smoothing group each face belongs to, as
//! OBJ's `o`, `g`, `usemtl` and `s` statements (and glTF's primitives and materials) say.
//!
//! A mesh with groups has a [`GroupTable`] on its entity, listing each distinct combination
//! of names once (a [`Group`]) and the material libraries the file referenced (`mtllib`), and
//! a [`FaceGroup`] on every face: its row in the table. The record
//! [`crate::mesh::attributes::MeshAttributes::groups`] says whether the mesh has them, with the
//! same invariant as the other attributes: when it does, every face has a [`FaceGroup`] naming
//! a row of the table; when it does not, no face has one.
//!
//! # Who carries them
//! The table never changes after a file is read: operations only ever give a face a row that
//! already exists.
//! - A face made from a face keeps its group: the two halves of a cut face, the triangles of a
//!   triangulated polygon, the faces around an extruded, inset or bevelled face, subdivision's
//!   children.
//! - A face made where there was none (a filled hole, the faces a vertex split opens) takes a
//!   neighbour's ([`settle`], which every edit that carries attributes runs: it gives each face
//!   still without a group the group of a face across one of its edges).
//! - Remeshing and simplification drop them, with a note, as they drop UVs.
//! - Undo restores them with their faces ([`crate::mesh::change`]); the tables carry them as a
//!   column by face row ([`crate::mesh::attributes::AttributeColumns::groups`]).
//!
//! Files: OBJ reads and writes every statement back ([`crate::io`]); PLY, OFF and STL cannot
//! hold them, and a save into one says "groups dropped".

use bevy::prelude::{Component, Entity, With, Without, World};

use super::elements::{Face, Halfedge, InMesh};
use super::ids::{FaceId, MeshId};

/// One combination of names a face can carry; `None` where the file set none.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Group {
    /// The object (`o name`), as written after the keyword.
    pub object: Option<String>,
    /// The group or groups (`g a b`), as written after the keyword.
    pub group: Option<String>,
    /// The material (`usemtl name`).
    pub material: Option<String>,
    /// The smoothing group (`s 1`, `s off`).
    pub smoothing: Option<String>,
}

impl Group {
    /// The names in a person's words, for the inspector: `object cube · group side · material
    /// red`; `no group` when none is set.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = [
            ("object", &self.object),
            ("group", &self.group),
            ("material", &self.material),
            ("smoothing", &self.smoothing),
        ]
        .into_iter()
        .filter_map(|(what, name)| name.as_ref().map(|n| format!("{what} {n}")))
        .collect();
        if parts.is_empty() {
            "no group".into()
        } else {
            parts.join(" · ")
        }
    }
}

/// The groups of a mesh and the material libraries its file named, on the mesh entity.
#[derive(Component, Clone, Debug, Default, PartialEq, Eq)]
pub struct GroupTable {
    /// Each `mtllib` statement's file names, as written (referenced on save, never rewritten).
    pub material_libraries: Vec<String>,
    /// The distinct combinations, in order of first use; a [`FaceGroup`] is a row of it.
    pub groups: Vec<Group>,
}

/// The rows of a table being filled: each distinct group gets the next row the first time it
/// is asked for, the same row after (how readers build a [`GroupTable`]).
#[derive(Default)]
pub struct GroupRows {
    rows: std::collections::HashMap<Group, u32>,
    groups: Vec<Group>,
}

impl GroupRows {
    /// The row of `group`, added at the end if it is new.
    pub fn row(&mut self, group: &Group) -> u32 {
        if let Some(&row) = self.rows.get(group) {
            return row;
        }
        let row = self.groups.len() as u32;
        self.rows.insert(group.clone(), row);
        self.groups.push(group.clone());
        row
    }

    /// The groups, by row.
    pub fn into_groups(self) -> Vec<Group> {
        self.groups
    }
}

/// A face's row in its mesh's [`GroupTable`].
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceGroup(pub u32);

/// A group per face, with the table the numbers refer to: how a soup carries groups (one per
/// face, in face order) and how the tables do (one per face row).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceGroups {
    /// The names.
    pub table: GroupTable,
    /// Each face's row in `table`.
    pub of_face: Vec<u32>,
}

impl FaceGroups {
    /// Whether there is one group per face of `faces` and each names a row of the table.
    pub fn fits(&self, faces: usize) -> bool {
        self.of_face.len() == faces && self.of_face.iter().all(|&g| self.in_table(g))
    }

    /// Whether `g` is a row of the table.
    pub fn in_table(&self, g: u32) -> bool {
        (g as usize) < self.table.groups.len()
    }
}

/// The group of face `f`, if it has one.
pub fn face_group(world: &World, f: FaceId) -> Option<u32> {
    world.get::<FaceGroup>(f.0).map(|g| g.0)
}

/// Gives face `f` the group `group` (nothing when `group` is `None`, or `f` is gone).
pub fn set_face_group(world: &mut World, f: FaceId, group: Option<u32>) {
    if let (Some(g), Ok(mut e)) = (group, world.get_entity_mut(f.0)) {
        e.insert(FaceGroup(g));
    }
}

/// The group of `mesh`'s face `f`, described (`None` when the mesh has no groups).
pub fn describe_face_group(world: &World, mesh: MeshId, f: FaceId) -> Option<String> {
    let table = world.get::<GroupTable>(mesh.0)?;
    let g = face_group(world, f)?;
    table.groups.get(g as usize).map(Group::describe)
}

/// Gives every face of `mesh` that has no group the group of a face across one of its edges,
/// repeating until no face without one touches a face with one, then row 0 to any left (a
/// face whose whole component had none). Keeps the invariant of the module doc after an edit
/// that made faces without saying which group they take. Costs a look at the faces without a
/// group only (none, after most edits).
pub fn settle(world: &mut World, mesh: MeshId) {
    let Some(mut q) =
        world.try_query_filtered::<(Entity, &InMesh), (With<Face>, Without<FaceGroup>)>()
    else {
        return;
    };
    let mut pending: Vec<FaceId> = q
        .iter(world)
        .filter(|(_, m)| m.0 == mesh)
        .map(|(e, _)| FaceId(e))
        .collect();
    while !pending.is_empty() {
        let found: Vec<(FaceId, u32)> = pending
            .iter()
            .filter_map(|&f| neighbours_group(world, f).map(|g| (f, g)))
            .collect();
        if found.is_empty() {
            for f in pending.drain(..) {
                set_face_group(world, f, Some(0));
            }
            break;
        }
        for &(f, g) in &found {
            set_face_group(world, f, Some(g));
        }
        pending.retain(|f| face_group(world, *f).is_none());
    }
}

/// The group of the first face across one of `f`'s sides that has one (read from the links
/// directly: this module sits below [`super::topology`]).
fn neighbours_group(world: &World, f: FaceId) -> Option<u32> {
    let halfedge = |h: super::ids::HalfedgeId| world.get::<Halfedge>(h.0);
    let first = world.get::<Face>(f.0)?.halfedge;
    let mut h = first;
    loop {
        let link = halfedge(h)?;
        if let Some(g) = halfedge(link.twin)
            .and_then(|t| t.face)
            .and_then(|across| face_group(world, across))
        {
            return Some(g);
        }
        h = link.next;
        if h == first {
            return None;
        }
    }
}

/// Removes every face's group from `mesh` (the table stays on the mesh entity, unused, so an
/// undo that brings the groups back finds their names).
pub fn remove_face_groups(world: &mut World, mesh: MeshId) {
    let Some(mut q) = world.try_query_filtered::<(Entity, &InMesh), With<FaceGroup>>() else {
        return;
    };
    let gone: Vec<Entity> = q
        .iter(world)
        .filter(|(_, m)| m.0 == mesh)
        .map(|(e, _)| e)
        .collect();
    for e in gone {
        world.entity_mut(e).remove::<FaceGroup>();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_group_reads_as_its_names() {
        let g = Group {
            object: Some("cube".into()),
            group: None,
            material: Some("red".into()),
            smoothing: Some("1".into()),
        };
        assert_eq!(g.describe(), "object cube · material red · smoothing 1");
        assert_eq!(Group::default().describe(), "no group");
    }

    #[test]
    fn groups_fit_one_per_face_within_the_table() {
        let groups = FaceGroups {
            table: GroupTable {
                material_libraries: vec![],
                groups: vec![Group::default(); 2],
            },
            of_face: vec![0, 1, 1],
        };
        assert!(groups.fits(3));
        assert!(!groups.fits(2));
        let beyond = FaceGroups {
            of_face: vec![0, 2, 1],
            ..groups
        };
        assert!(!beyond.fits(3));
    }
}
