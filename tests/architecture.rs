//! The layering rules of DESIGN §1, checked on the source: no two modules of `src/editor`, of
//! each of its rooms, of `src/mesh` or of `src/ops` import each other, directly or round a
//! longer cycle; no room imports the editor's root back; no folder of the editor holds more
//! than 12 files, nor any of its files more than 600 lines; no function outside the tests runs
//! over 120 lines; the README is at most 400 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The sibling modules of a folder and, for each, the siblings its files name (through
/// `super::NAME` or `crate::FOLDER::NAME`). A sub-folder counts as one module.
fn import_graph(folder: &str) -> BTreeMap<String, BTreeSet<String>> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join(folder);
    let module_of = |path: &Path| -> Option<String> {
        let rel = path.strip_prefix(&root).ok()?;
        let first = rel
            .components()
            .next()?
            .as_os_str()
            .to_string_lossy()
            .into_owned();
        Some(first.trim_end_matches(".rs").to_string())
    };
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    let modules: BTreeSet<String> = files.iter().filter_map(|f| module_of(f)).collect();
    let crate_prefix = format!("crate::{}::", folder.replace('/', "::"));
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in &files {
        let Some(from) = module_of(file) else {
            continue;
        };
        // A file directly in the folder reaches its siblings as `super::`; one in a sub-folder
        // reaches them as `super::super::` or by the crate path, and its own folder's files as
        // `super::` (which are not siblings at this level).
        let depth = file.strip_prefix(&root).unwrap().components().count();
        let sibling_prefix = "super::".repeat(depth);
        let text = std::fs::read_to_string(file).unwrap();
        for line in text.lines().map(str::trim) {
            if line.starts_with("//") {
                continue;
            }
            for prefix in [sibling_prefix.as_str(), crate_prefix.as_str()] {
                for (i, _) in line.match_indices(prefix) {
                    let rest = &line[i + prefix.len()..];
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    // `use super::{a, b}` names several.
                    let names: Vec<String> = if let Some(list) = rest.strip_prefix('{') {
                        list.split(['}', ','])
                            .map(|n| n.trim().split("::").next().unwrap_or("").to_string())
                            .collect()
                    } else {
                        vec![name]
                    };
                    for name in names {
                        if name != from && modules.contains(&name) {
                            graph.entry(from.clone()).or_default().insert(name);
                        }
                    }
                }
            }
        }
        graph.entry(from).or_default();
    }
    graph
}

/// A cycle of the graph, if any (as the list of modules round it).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(start) = path.iter().position(|n| n == node) {
            return Some(path[start..].to_vec());
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, graph, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut Vec::new(), &mut done))
}

/// The editor's rooms: its sub-folders, as paths under `src` (`editor/session`, …).
fn editor_rooms() -> Vec<String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/editor");
    let mut rooms: Vec<String> = std::fs::read_dir(root)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.is_dir())
        .map(|path| format!("editor/{}", path.file_name().unwrap().to_string_lossy()))
        .collect();
    rooms.sort();
    rooms
}

#[test]
fn no_module_pair_imports_each_other() {
    let rooms = editor_rooms();
    assert!(rooms.len() >= 5, "the editor has rooms: {rooms:?}");
    let folders = ["editor", "mesh", "ops", "ops/local"]
        .into_iter()
        .map(String::from)
        .chain(rooms);
    for folder in folders {
        let graph = import_graph(&folder);
        assert!(graph.len() > 2, "{folder}: found no modules");
        if let Some(cycle) = find_cycle(&graph) {
            panic!("src/{folder}: import cycle {}", cycle.join(" -> "));
        }
    }
}

/// The editor's root (`editor/mod.rs`) adds every room's plugin; a room that named one of the
/// root's own items (`crate::editor::Item`, `super::super::`) would import it back.
#[test]
fn no_room_imports_the_editor_root() {
    let rooms: BTreeSet<String> = editor_rooms()
        .iter()
        .map(|r| r.trim_start_matches("editor/").to_string())
        .collect();
    for room in &rooms {
        let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("src/editor")
            .join(room);
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("");
                let back_up = code.contains("super::super::")
                    || code.match_indices("crate::editor::").any(|(i, m)| {
                        let name: String = code[i + m.len()..]
                            .chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect();
                        !rooms.contains(&name)
                    });
                assert!(
                    !back_up,
                    "{}:{}: a room imports the editor's root: {}",
                    path.display(),
                    n + 1,
                    line.trim()
                );
            }
        }
    }
}

/// A folder a newcomer can take in at a glance: no folder of the editor holds more than 12
/// files (its `mod.rs` and shaders included).
#[test]
fn no_editor_folder_holds_more_than_twelve_files() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/editor");
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        let mut files = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files += 1;
            }
        }
        assert!(files <= 12, "{} holds {files} files", dir.display());
    }
}

/// An editor file fits a reader's screen or two: none of `src/editor/` runs over 600 lines
/// (tests included), so a file that grows is split by concern.
#[test]
fn no_editor_file_runs_over_600_lines() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/editor");
    let mut stack = vec![root];
    let mut long = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let lines = std::fs::read_to_string(&path).unwrap().lines().count();
                if lines > 600 {
                    long.push(format!("{}: {lines} lines", path.display()));
                }
            }
        }
    }
    assert!(
        long.is_empty(),
        "editor files over 600 lines:\n{}",
        long.join("\n")
    );
}

/// The README stays a user's page, not a manual: at most 400 lines (its key table is checked
/// against the keymap by the editor's own tests).
#[test]
fn the_readme_is_at_most_400_lines() {
    let readme =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("README.md"))
            .unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 400, "the README has {lines} lines");
}

/// The functions of a Rust source over `limit` lines (signature to closing brace), before its
/// `#[cfg(test)]` module: as `(name, first line, lines)`.
fn long_functions(text: &str, limit: usize) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text
        .lines()
        .take_while(|l| l.trim() != "#[cfg(test)]")
        .collect();
    let mut long = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let code = line.trim_start();
        let indent = &line[..line.len() - code.len()];
        let signature = code
            .trim_start_matches("pub ")
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("const ")
            .trim_start_matches("unsafe ");
        let Some(rest) = signature.strip_prefix("fn ") else {
            i += 1;
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // The body opens at the first line ending in `{` (a declaration ends in `;`).
        let Some(open) = (i..lines.len()).find(|&j| {
            let l = lines[j].trim_end();
            l.ends_with('{') || l.ends_with(';')
        }) else {
            break;
        };
        if lines[open].trim_end().ends_with(';') {
            i = open + 1;
            continue;
        }
        let close = (open + 1..lines.len())
            .find(|&j| lines[j] == format!("{indent}}}"))
            .unwrap_or(lines.len() - 1);
        let count = close - i + 1;
        if count > limit {
            long.push((name, i + 1, count));
        }
        i = close + 1;
    }
    long
}

/// A function a reader can hold in their head: none outside the tests runs over 120 lines
/// (signature to closing brace, as rustfmt lays it out).
#[test]
fn no_function_runs_over_120_lines() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut stack = vec![root.join("src"), root.join("python/src")];
    let mut long = Vec::new();
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                for (name, line, count) in long_functions(&text, 120) {
                    long.push(format!("{}:{line} {name}: {count} lines", path.display()));
                }
            }
        }
    }
    assert!(
        long.is_empty(),
        "functions over 120 lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn the_length_check_measures_functions() {
    let body = "    let x = 1;\n".repeat(5);
    let text = format!(
        "fn short() {{\n{body}}}\n\npub fn long(\n    a: u32,\n) -> u32 {{\n{body}{body}    a\n}}\n"
    );
    assert_eq!(long_functions(&text, 7), vec![("long".to_string(), 9, 15)]);
}

#[test]
fn the_cycle_finder_finds_cycles() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(find_cycle(&graph).map(|c| c.len()), Some(3));
}
