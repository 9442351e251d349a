//! The layering rules of DESIGN §1, checked on the source: the crate's top-level modules form
//! the declared layers ([`LAYERS`]: mesh → io → ops → edit → the command line and the editor)
//! and none names a module of its own layer or one above it; in no folder of the crate do its
//! modules import each other round a circle, its own file (`mod.rs`) counted as one of them
//! (an item taken from it is an arrow to it; a `pub use` re-export is its face, not an
//! import); no room imports the editor's root back; no folder of the editor holds more
//! than 12 files, nor any of its files more than 600 lines; no function outside the tests runs
//! over 120 lines; the README is at most 400 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// The crate's top-level modules, bottom layer first. A module may name (`crate::NAME`) the
/// modules of the layers below its own and no other: the core (mesh, files, operations, the
/// edit layer) never reaches up to the command line or the editor, and those two never reach
/// each other. The Python package, a crate of its own, stands above them all.
const LAYERS: &[&[&str]] = &[
    &["checks", "process_memory", "colormap"],
    &["memory_budget"],
    &["mesh"],
    &["io"],
    &["ops"],
    &["edit"],
    &["source", "recovery", "fuzzing"],
    &["cli", "editor"],
];

/// `text` without its test modules (`#[cfg(test)]` before `mod NAME {`, to the brace that
/// closes it at the same indentation) and without comments; other lines keep their places.
fn without_tests(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut kept = Vec::with_capacity(lines.len());
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim() == "#[cfg(test)]"
            && let Some(next) = lines.get(i + 1)
        {
            let code = next.trim_start();
            let indent = &next[..next.len() - code.len()];
            let opens = code
                .trim_start_matches("pub ")
                .trim_start_matches("pub(crate) ")
                .starts_with("mod ")
                && code.ends_with('{');
            if opens {
                let close = (i + 2..lines.len())
                    .find(|&j| lines[j] == format!("{indent}}}"))
                    .unwrap_or(lines.len() - 1);
                kept.extend((i..=close).map(|_| String::new()));
                i = close + 1;
                continue;
            }
        }
        kept.push(lines[i].split("//").next().unwrap_or("").to_string());
        i += 1;
    }
    kept
}

/// The files declared test-only by their parent (`#[cfg(test)] mod NAME;`), as the paths of
/// their modules under `src` (`ops/local/testkit`).
fn test_only_modules(files: &[(String, String)]) -> BTreeSet<String> {
    let mut test_only = BTreeSet::new();
    for (module, text) in files {
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        for pair in lines.windows(2) {
            let declared = pair[1]
                .trim_start_matches("pub ")
                .trim_start_matches("pub(crate) ")
                .strip_prefix("mod ")
                .and_then(|rest| rest.strip_suffix(';'));
            if pair[0] == "#[cfg(test)]"
                && let Some(name) = declared
            {
                test_only.insert(match module.as_str() {
                    "" => name.to_string(),
                    parent => format!("{parent}/{name}"),
                });
            }
        }
    }
    test_only
}

/// Every `.rs` file under `src`, as (its module's path, `ops/local/flip`; `ops` for
/// `ops/mod.rs` and `ops.rs`; empty for `lib.rs` and `main.rs`), with its text.
fn source_files() -> Vec<(String, String)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(&root).unwrap().with_extension("");
                let mut module = rel.to_string_lossy().replace('\\', "/");
                for tail in ["/mod", "lib", "main"] {
                    if module.ends_with(tail) && (tail.starts_with('/') || module == tail) {
                        module.truncate(module.len() - tail.len());
                    }
                }
                files.push((module, std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}

/// Where a file of top-level module `from` names `crate::NAME` for a top-level module of its
/// own layer or one above: `"from → NAME: line"` each.
fn layer_violations(files: &[(String, String)]) -> Vec<String> {
    let layer_of = |name: &str| LAYERS.iter().position(|layer| layer.contains(&name));
    let test_only = test_only_modules(files);
    let mut violations = Vec::new();
    for (module, text) in files {
        let from = module.split('/').next().unwrap_or("");
        let tested_alone = test_only
            .iter()
            .any(|t| module == t || module.starts_with(&format!("{t}/")));
        if from.is_empty() || tested_alone {
            continue;
        }
        let Some(own) = layer_of(from) else {
            violations.push(format!("{from}: in no layer of LAYERS"));
            continue;
        };
        for line in without_tests(text) {
            for (i, _) in line.match_indices("crate::") {
                let name: String = line[i + "crate::".len()..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                let upward = layer_of(&name).is_some_and(|to| name != from && to >= own);
                if upward {
                    violations.push(format!("{from} → {name}: {}", line.trim()));
                }
            }
        }
    }
    violations
}

#[test]
fn no_module_names_its_own_layer_or_one_above() {
    let files = source_files();
    let tops: BTreeSet<&str> = files
        .iter()
        .filter_map(|(m, _)| m.split('/').next())
        .filter(|m| !m.is_empty())
        .collect();
    for top in tops {
        assert!(
            LAYERS.iter().any(|layer| layer.contains(&top)),
            "src/{top} is in no layer: put it in LAYERS"
        );
    }
    let violations = layer_violations(&files);
    assert!(
        violations.is_empty(),
        "imports against the layers:\n{}",
        violations.join("\n")
    );
}

#[test]
fn the_layer_check_finds_a_planted_upward_import() {
    let file = |module: &str, text: &str| (module.to_string(), text.to_string());
    let files = vec![
        // Down a layer: fine.
        file("ops/flip", "use crate::mesh::MeshRef;\n"),
        // Up: the core naming the editor, a peer naming a peer.
        file("mesh/topology", "use crate::editor::session::Selection;\n"),
        file("cli/process", "let x = crate::editor::run(None);\n"),
        // In a test module, or a test-only file: not the crate's layering.
        file(
            "io/off",
            "#[cfg(test)]\nmod tests {\n    use crate::edit::Edit;\n}\n",
        ),
        file("ops/local", "#[cfg(test)]\npub(crate) mod testkit;\n"),
        file("ops/local/testkit", "use crate::edit::Edit;\n"),
        // In a comment: not an import.
        file("io/obj", "// see crate::editor::input\n"),
    ];
    let found = layer_violations(&files);
    assert_eq!(
        found,
        vec![
            "mesh → editor: use crate::editor::session::Selection;".to_string(),
            "cli → editor: let x = crate::editor::run(None);".to_string(),
        ]
    );
}

/// `text`'s paths: each `use` statement's (its braces expanded, `pub use` re-exports left out:
/// a folder's face, not an import) and every other `a::b::c` in its code, test code and
/// comments left out.
fn named_paths(text: &str) -> Vec<Vec<String>> {
    let code = without_tests(text).join("\n");
    let mut paths = Vec::new();
    let mut rest = String::with_capacity(code.len());
    for statement in code.split_inclusive(';') {
        let trimmed = statement.trim_start();
        let (visibility, body) = match trimmed.split_once("use ") {
            Some((before, body)) if is_visibility(before.trim()) && is_use_tree(body) => {
                (before.trim(), body)
            }
            _ => {
                rest.push_str(statement);
                continue;
            }
        };
        if visibility.starts_with("pub") {
            continue;
        }
        for path in expand_use(body.trim_end_matches(';')) {
            let path = path.split(" as ").next().unwrap_or("").trim().to_string();
            paths.push(path.split("::").map(str::to_string).collect());
        }
    }
    // Every other path: an identifier followed by `::`, read to its end.
    let chars: Vec<char> = rest.chars().collect();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut i = 0;
    while i < chars.len() {
        let starts = ident(chars[i]) && (i == 0 || (!ident(chars[i - 1]) && chars[i - 1] != ':'));
        if !starts {
            i += 1;
            continue;
        }
        let mut segments = Vec::new();
        let mut j = i;
        loop {
            let start = j;
            while j < chars.len() && ident(chars[j]) {
                j += 1;
            }
            segments.push(chars[start..j].iter().collect::<String>());
            if chars.get(j) == Some(&':')
                && chars.get(j + 1) == Some(&':')
                && chars.get(j + 2).is_some_and(|&c| ident(c))
            {
                j += 2;
            } else {
                break;
            }
        }
        if segments.len() > 1 {
            paths.push(segments);
        }
        i = j.max(i + 1);
    }
    paths
}

/// Whether `text` is nothing or a visibility (`pub`, `pub(crate)`, `pub(in crate::x)`).
fn is_visibility(text: &str) -> bool {
    text.is_empty() || text == "pub" || (text.starts_with("pub(") && text.ends_with(')'))
}

/// Whether `body` reads as a `use` tree (`a::{b, c::d as e};`), not prose that happens to
/// hold the word.
fn is_use_tree(body: &str) -> bool {
    let tree = body.trim_end().trim_end_matches(';');
    let balanced = tree.matches('{').count() == tree.matches('}').count();
    balanced
        && tree
            .chars()
            .all(|c| c.is_alphanumeric() || "_:{},* \n\t".contains(c))
}

/// A `use` tree's paths: `a::{b, c::{d, e}}` → `a::b`, `a::c::d`, `a::c::e`.
fn expand_use(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.to_string()];
    };
    let (prefix, inner) = (
        &tree[..open],
        &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())],
    );
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (k, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.trim().is_empty())
        .flat_map(expand_use)
        .map(|p| format!("{prefix}{p}"))
        .collect()
}

/// The module `path` names, seen from module `at`: the deepest module of `modules` it reaches
/// (`crate::ops::Refusal` → `ops`, an item of `ops/mod.rs`), `None` for a path outside the
/// crate or not starting at a module.
fn resolve(modules: &BTreeSet<Vec<String>>, at: &[String], path: &[String]) -> Option<Vec<String>> {
    let (mut module, mut rest): (Vec<String>, &[String]) = match path.first()?.as_str() {
        "crate" => (Vec::new(), &path[1..]),
        "self" => (at.to_vec(), &path[1..]),
        "super" => {
            let ups = path.iter().take_while(|s| *s == "super").count();
            (at[..at.len().checked_sub(ups)?].to_vec(), &path[ups..])
        }
        first => {
            let child = [at, &[first.to_string()]].concat();
            if !modules.contains(&child) {
                return None;
            }
            (at.to_vec(), path)
        }
    };
    while let Some((next, tail)) = rest.split_first() {
        let deeper = [module.as_slice(), std::slice::from_ref(next)].concat();
        if !modules.contains(&deeper) {
            break;
        }
        module = deeper;
        rest = tail;
    }
    Some(module)
}

/// Each module (by path) and the modules its code names (itself left out).
fn module_arrows(files: &[(String, String)]) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let split = |m: &str| -> Vec<String> {
        m.split('/')
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect()
    };
    let test_only = test_only_modules(files);
    let modules: BTreeSet<Vec<String>> = files.iter().map(|(m, _)| split(m)).collect();
    let mut arrows = BTreeMap::new();
    for (module, text) in files {
        let tested_alone = test_only
            .iter()
            .any(|t| module == t || module.starts_with(&format!("{t}/")));
        if tested_alone {
            continue;
        }
        let at = split(module);
        let named: BTreeSet<Vec<String>> = named_paths(text)
            .iter()
            .filter_map(|p| resolve(&modules, &at, p))
            .filter(|m| *m != at)
            .collect();
        arrows.insert(at, named);
    }
    arrows
}

/// The graph of folder `folder`'s modules: each child (a sub-folder counts as one) and `mod`
/// (the folder's own file), with an arrow where one names the other.
fn folder_graph(
    arrows: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
    folder: &[String],
) -> BTreeMap<String, BTreeSet<String>> {
    let node = |m: &[String]| -> Option<String> {
        match m.strip_prefix(folder)? {
            [] => Some("mod".to_string()),
            [child, ..] => Some(child.clone()),
        }
    };
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, named) in arrows {
        let Some(a) = node(from) else { continue };
        let entry = graph.entry(a.clone()).or_default();
        for b in named.iter().filter_map(|m| node(m)) {
            if b != a {
                entry.insert(b);
            }
        }
    }
    graph
}

/// Every folder of the crate (a module with modules under it) and the circle among its modules,
/// if it has one.
fn folder_circles(files: &[(String, String)]) -> BTreeMap<String, Vec<String>> {
    let arrows = module_arrows(files);
    let folders: BTreeSet<Vec<String>> = arrows
        .keys()
        .filter(|m| !m.is_empty())
        .map(|m| m[..m.len() - 1].to_vec())
        .collect();
    folders
        .into_iter()
        .filter_map(|f| {
            let circle = find_cycle(&folder_graph(&arrows, &f))?;
            Some((f.join("/"), circle))
        })
        .collect()
}

#[test]
fn no_folder_imports_round_a_circle_counting_its_own_file() {
    let circles = folder_circles(&source_files());
    let found: Vec<String> = circles
        .iter()
        .map(|(folder, circle)| format!("src/{folder}: {}", circle.join(" -> ")))
        .collect();
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

#[test]
fn the_circle_check_counts_items_taken_from_a_folders_own_file() {
    let file = |module: &str, text: &str| (module.to_string(), text.to_string());
    // `x/mod.rs` calls its child and the child takes an item of `x/mod.rs`: a circle.
    let planted = vec![
        file(
            "x",
            "mod a;\npub fn helper() {}\npub fn run() { a::work() }\n",
        ),
        file("x/a", "use super::helper;\npub fn work() { helper() }\n"),
    ];
    assert_eq!(
        folder_circles(&planted).get("x"),
        Some(&vec!["a".to_string(), "mod".to_string()])
    );
    // A re-export (`pub use`) is the folder's face, not an import; a path in a comment or a
    // test module names nothing.
    let facade = vec![
        file(
            "x",
            "mod a;\npub use a::work;\npub fn helper() {}\n// a::work()\n",
        ),
        file(
            "x/a",
            "use super::helper;\npub fn work() { helper() }\n#[cfg(test)]\nmod tests {\n    use crate::x::run;\n}\n",
        ),
    ];
    assert_eq!(folder_circles(&facade).get("x"), None);
    // Siblings naming each other through the crate path.
    let siblings = vec![
        file("y", "mod b;\nmod c;\n"),
        file("y/b", "use crate::y::c::{Thing, other::{More}};\n"),
        file("y/c", "fn f() { let _ = crate::y::b::make(); }\n"),
    ];
    assert_eq!(folder_circles(&siblings).get("y").map(Vec::len), Some(2));
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

/// What follows a function's visibility and qualifiers (`pub(in crate::x) const unsafe
/// extern "C" fn f` → `fn f`).
fn past_qualifiers(code: &str) -> &str {
    let mut rest = code;
    if let Some(after) = rest.strip_prefix("pub") {
        rest = match after.strip_prefix('(') {
            Some(inner) => inner.split_once(')').map_or(after, |(_, r)| r),
            None => after,
        }
        .trim_start();
    }
    loop {
        let before = rest;
        for qualifier in ["const ", "async ", "unsafe ", "extern \"C\" ", "extern "] {
            rest = rest.strip_prefix(qualifier).unwrap_or(rest);
        }
        if rest == before {
            return rest;
        }
    }
}

/// The functions of a Rust source over `limit` lines (signature to closing brace), its test
/// modules left out: as `(name, first line, lines)`. Every other function is measured, in
/// `impl` and `trait` blocks too, wherever its file puts it.
fn long_functions(text: &str, limit: usize) -> Vec<(String, usize, usize)> {
    let kept = without_tests(text);
    let lines: Vec<&str> = kept.iter().map(String::as_str).collect();
    let mut long = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let code = line.trim_start();
        let indent = &line[..line.len() - code.len()];
        let Some(rest) = past_qualifiers(code).strip_prefix("fn ") else {
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
    // A test-only file declared first does not hide what follows it; a test module is left
    // out; qualifiers and a restricted visibility are read past; a method in an impl counts.
    let inner = body.replace("    let", "        let");
    let text = format!(
        "#[cfg(test)]\npub(crate) mod testkit;\n\npub(in crate::ops) const unsafe fn after() {{\n{body}{body}}}\n\nimpl A {{\n    pub async fn method(&self) {{\n{inner}{inner}    }}\n}}\n\n#[cfg(test)]\nmod tests {{\n    fn in_tests() {{\n{inner}{inner}    }}\n}}\n"
    );
    assert_eq!(
        long_functions(&text, 7),
        vec![("after".to_string(), 4, 12), ("method".to_string(), 18, 12)]
    );
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
