//! OBJ's grouping statements — `mtllib`, `o`, `g`, `usemtl`, `s` — read into face groups
//! ([`crate::mesh::groups`]) and written back.
//!
//! Reading: each statement sets its part of the current state (`o` the object, `g` the group,
//! `usemtl` the material, `s` the smoothing group; each keeps the rest of its line as written)
//! and every face takes the state it is read in. Each distinct state becomes one row of the
//! table, in order of first use; `mtllib` lines are listed as they are. A file without any of
//! these statements has no groups.
//!
//! Writing: the `mtllib` lines first, then before each face the statements whose part of the
//! state differs from the face before it (so a file Pappus read writes back the same
//! statements in the same places). A name from another format that a line cannot hold (a line
//! break, a `#`, a final `\`) is written with `_` in their place. A statement cannot unset a part (there is no "no object"),
//! so when a face's group lacks a part the face before it had (only faces an edit made can do
//! that), the faces are written grouped by row instead, rows in table order: rows in order of
//! first use only ever gain parts.

use crate::mesh::groups::{FaceGroups, Group, GroupRows, GroupTable};

/// The grouping state while a file is read, and the group of each face so far.
#[derive(Default)]
pub(super) struct GroupReader {
    current: Group,
    /// The row of `current` in the table, once a face has used it.
    current_row: Option<u32>,
    rows: GroupRows,
    material_libraries: Vec<String>,
    of_face: Vec<u32>,
    /// Whether any grouping statement was read.
    any: bool,
}

impl GroupReader {
    /// Reads a grouping statement: `keyword` with the `rest` of its line. Returns `false` for
    /// any other statement.
    pub fn statement(&mut self, keyword: &str, rest: &str) -> bool {
        let name = Some(rest.trim().to_string());
        let part = match keyword {
            "mtllib" => {
                self.material_libraries.push(rest.trim().to_string());
                self.any = true;
                return true;
            }
            "o" => &mut self.current.object,
            "g" => &mut self.current.group,
            "usemtl" => &mut self.current.material,
            "s" => &mut self.current.smoothing,
            _ => return false,
        };
        if *part != name {
            *part = name;
            self.current_row = None;
        }
        self.any = true;
        true
    }

    /// Records that a face was read in the current state.
    pub fn face(&mut self) {
        let row = match self.current_row {
            Some(row) => row,
            None => {
                let row = self.rows.row(&self.current);
                self.current_row = Some(row);
                row
            }
        };
        self.of_face.push(row);
    }

    /// The groups of the faces read, if the file had any grouping statement. A file whose
    /// faces all came before its statements gets the one empty group.
    pub fn finish(self) -> Option<FaceGroups> {
        if !self.any {
            return None;
        }
        let mut groups = self.rows.into_groups();
        if groups.is_empty() {
            groups.push(Group::default());
        }
        Some(FaceGroups {
            table: GroupTable {
                material_libraries: self.material_libraries,
                groups,
            },
            of_face: self.of_face,
        })
    }
}

/// The statements that make `to` the current state after `from`, in the order `o`, `g`,
/// `usemtl`, `s`; `None` when a part `from` has is missing in `to`.
fn changes(from: &Group, to: &Group, out: &mut String) -> Option<()> {
    let parts = [
        ("o", &from.object, &to.object),
        ("g", &from.group, &to.group),
        ("usemtl", &from.material, &to.material),
        ("s", &from.smoothing, &to.smoothing),
    ];
    if parts.iter().any(|(_, a, b)| a.is_some() && b.is_none()) {
        return None;
    }
    for (keyword, a, b) in parts {
        if a != b
            && let Some(name) = b
        {
            out.push_str(keyword);
            if !name.is_empty() {
                out.push(' ');
                push_name(name, out);
            }
            out.push('\n');
        }
    }
    Some(())
}

/// Writes a name (from a scene's node or material, which may hold anything) as one OBJ line can
/// hold it: a line break or other control character, and a `#` (a comment), become `_`, and so
/// does a final `\` (a continuation, which would join the next line, a face, to the name).
fn push_name(name: &str, out: &mut String) {
    let name = name.trim();
    let last = name.char_indices().last().map_or(0, |(i, _)| i);
    for (i, c) in name.char_indices() {
        let unwritable = c == '#' || c.is_control() || (i == last && c == '\\');
        out.push(if unwritable { '_' } else { c });
    }
}

/// Whether faces in order `of_face` can be written as they are (no face lacks a part of its
/// group that the face before it had).
pub(super) fn writable_in_order(groups: &FaceGroups) -> bool {
    let mut scratch = String::new();
    let mut before = &Group::default();
    groups.of_face.iter().all(|&g| {
        let group = &groups.table.groups[g as usize];
        let ok = changes(before, group, &mut scratch).is_some();
        before = group;
        ok
    })
}

/// Writes OBJ's grouping statements for a list of faces.
pub(super) struct GroupWriter<'a> {
    groups: &'a FaceGroups,
    before: Group,
}

impl<'a> GroupWriter<'a> {
    /// Starts: writes the `mtllib` lines.
    pub fn new(groups: &'a FaceGroups, out: &mut String) -> Self {
        for library in &groups.table.material_libraries {
            out.push_str("mtllib ");
            push_name(library, out);
            out.push('\n');
        }
        Self {
            groups,
            before: Group::default(),
        }
    }

    /// Writes the statements face `face` (of the soup) needs before its `f` line.
    pub fn before_face(&mut self, face: usize, out: &mut String) {
        let group = &self.groups.table.groups[self.groups.of_face[face] as usize];
        if changes(&self.before, group, out).is_some() {
            self.before.clone_from(group);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn group(object: Option<&str>, material: Option<&str>) -> Group {
        Group {
            object: object.map(Into::into),
            material: material.map(Into::into),
            ..Group::default()
        }
    }

    #[test]
    fn each_state_is_one_row_in_order_of_first_use() {
        let mut r = GroupReader::default();
        r.face();
        assert!(r.statement("mtllib", " a.mtl b.mtl "));
        assert!(r.statement("o", "cube"));
        assert!(r.statement("usemtl", "red"));
        r.face();
        r.face();
        assert!(r.statement("usemtl", "blue"));
        r.face();
        assert!(r.statement("usemtl", "red"));
        r.face();
        assert!(!r.statement("l", "1 2"));
        let groups = r.finish().unwrap();
        assert_eq!(groups.of_face, [0, 1, 1, 2, 1]);
        assert_eq!(groups.table.material_libraries, ["a.mtl b.mtl"]);
        assert_eq!(
            groups.table.groups,
            [
                Group::default(),
                group(Some("cube"), Some("red")),
                group(Some("cube"), Some("blue")),
            ]
        );
    }

    #[test]
    fn a_file_without_statements_has_no_groups() {
        let mut r = GroupReader::default();
        r.face();
        assert!(r.finish().is_none());
    }

    #[test]
    fn statements_are_written_where_a_part_changes() {
        let groups = FaceGroups {
            table: GroupTable {
                material_libraries: vec!["m.mtl".into()],
                groups: vec![
                    group(Some("a"), Some("red")),
                    group(Some("a"), Some("blue")),
                ],
            },
            of_face: vec![0, 0, 1, 0],
        };
        assert!(writable_in_order(&groups));
        let mut out = String::new();
        let mut w = GroupWriter::new(&groups, &mut out);
        for face in 0..4 {
            w.before_face(face, &mut out);
            out.push_str("f\n");
        }
        assert_eq!(
            out,
            "mtllib m.mtl\no a\nusemtl red\nf\nf\nusemtl blue\nf\nusemtl red\nf\n"
        );
    }

    #[test]
    fn a_part_that_would_have_to_be_unset_is_found() {
        let groups = FaceGroups {
            table: GroupTable {
                material_libraries: vec![],
                groups: vec![group(None, None), group(Some("a"), None)],
            },
            of_face: vec![1, 0],
        };
        assert!(!writable_in_order(&groups));
    }

    #[test]
    fn a_name_no_obj_line_can_hold_is_written_so_the_next_line_stays_a_face() {
        let mut out = String::new();
        for name in ["\\", "Material #25", "two\nlines", " a\\b\\ "] {
            push_name(name, &mut out);
            out.push('|');
        }
        assert_eq!(out, "_|Material _25|two_lines|a\\b_|");
    }
}
