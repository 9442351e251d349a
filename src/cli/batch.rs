//! `pappus process` on one input or many.
//!
//! One input (a file or `shape:NAME`, no pattern) runs as it always has: the steps' lines as
//! they are applied, then the result's report, or one JSON object. Several inputs — more than
//! one argument, or any glob pattern — run as a batch: `-o` is a pattern in which `{stem}`
//! stands for each input's file stem, `-j N` threads take the inputs in turn (each builds its
//! own `World`, so nothing is shared), a failure on one input is reported on stderr and the
//! others go on, and each input's report is printed whole when it is done (text, or one JSON
//! line with `input` and `output`, or `input` and `error`). The exit code is 1 when any input
//! failed.
//!
//! Patterns are expanded here, not by a shell, so they work quoted: `*` (any run of
//! characters but `/`), `?` (one character) and `[abc]` / `[a-z]` / `[!abc]` (one of a set) in
//! any path component. Matches are sorted; a pattern matching nothing is a failed input.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use serde_json::{Value, json};

use super::args::{ProcessArg, is_pattern};
use super::process::{ProcessJob, check_output, process_file};
use super::report::ms_since;
use super::report::round;
use crate::edit::Step;

/// Runs `process`: the first input, then `rest` (more inputs, then the steps).
///
/// # Errors
/// For a single input, its error. For a batch, a malformed pattern or an output collision
/// (before anything runs), or how many inputs failed (after all ran).
pub(super) fn process(
    input: String,
    output: PathBuf,
    rest: Vec<ProcessArg>,
    jobs: usize,
    mut job: ProcessJob,
) -> Result<(), String> {
    let mut inputs = vec![input];
    for arg in rest {
        match arg {
            ProcessArg::Input(text) if job.steps.is_empty() => inputs.push(text),
            ProcessArg::Input(text) => {
                return Err(format!(
                    "`{text}` follows the step `{}`: the inputs come first, then the steps",
                    job.steps.last().map(Step::to_string).unwrap_or_default()
                ));
            }
            ProcessArg::Step(step) => job.steps.push(step),
        }
    }
    if inputs.len() == 1 && !is_pattern(&inputs[0]) {
        return single(&job, &inputs[0], &output);
    }
    batch(&job, &inputs, &output, jobs)
}

/// One input, printed as it goes (the single-file form).
fn single(job: &ProcessJob, input: &str, output: &Path) -> Result<(), String> {
    check_output(job, output)?;
    let report = process_file(
        job,
        input,
        output,
        &mut |line| out!("{line}"),
        &mut |warning| eprintln!("pappus: {warning}"),
    )?;
    if job.json {
        outln!("{report}");
    }
    Ok(())
}

/// One input of a batch: where it comes from and where it goes, or why it cannot run.
struct Task {
    /// The input as given (a file, `shape:NAME`) or the pattern that matched nothing.
    input: String,
    /// The output path, or why there is none.
    output: Result<PathBuf, String>,
}

/// Several inputs on `jobs` threads.
fn batch(job: &ProcessJob, inputs: &[String], pattern: &Path, jobs: usize) -> Result<(), String> {
    let pattern_text = pattern.to_string_lossy();
    if !pattern_text.contains("{stem}") {
        return Err(format!(
            "with several inputs, -o is a pattern with {{stem}} (as in out/{{stem}}.ply), not {}",
            pattern.display()
        ));
    }
    check_output(job, pattern)?;
    let mut tasks = Vec::new();
    for input in inputs {
        if !is_pattern(input) || input.starts_with("shape:") {
            tasks.push(input.clone());
            continue;
        }
        let matches = expand(input)?;
        if matches.is_empty() {
            // Reported with the failures; the other inputs still run.
            tasks.push(input.clone());
        }
        tasks.extend(matches.iter().map(|p| p.to_string_lossy().into_owned()));
    }
    let tasks: Vec<Task> = tasks
        .into_iter()
        .map(|input| {
            let output = if is_pattern(&input) && !input.starts_with("shape:") {
                Err(format!("{input}: no file matches"))
            } else {
                Ok(PathBuf::from(pattern_text.replace("{stem}", &stem(&input))))
            };
            Task { input, output }
        })
        .collect();
    // Two inputs writing one file would lose one of the results: refuse before running any.
    let mut writers: HashMap<&Path, &str> = HashMap::new();
    for task in &tasks {
        if let Ok(out) = &task.output
            && let Some(first) = writers.insert(out, &task.input)
        {
            return Err(format!(
                "{first} and {} would both write {}: give -o a pattern that tells them apart",
                task.input,
                out.display()
            ));
        }
    }
    let next = AtomicUsize::new(0);
    let failed = AtomicUsize::new(0);
    let stdout = Mutex::new(());
    let workers = jobs.clamp(1, tasks.len().max(1));
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(task) = tasks.get(i) else { break };
                    let start = Instant::now();
                    let mut text = String::new();
                    let outcome = task.output.clone().and_then(|output| {
                        if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
                            std::fs::create_dir_all(dir)
                                .map_err(|e| format!("{}: {e}", dir.display()))?;
                        }
                        let report = process_file(
                            job,
                            &task.input,
                            &output,
                            &mut |line| text.push_str(line),
                            &mut |warning| eprintln!("pappus: {}: {warning}", task.input),
                        )?;
                        Ok((output, report))
                    });
                    let ms = round(ms_since(start), 3);
                    let _guard = stdout.lock().unwrap_or_else(|e| e.into_inner());
                    match outcome {
                        Ok((output, mut report)) => {
                            if job.json {
                                report["input"] = json!(task.input);
                                report["output"] = json!(output.to_string_lossy());
                                report["ms"] = json!(ms);
                                outln!("{report}");
                            } else {
                                out!("{}: {ms} ms\n{text}", task.input);
                            }
                        }
                        Err(message) => {
                            failed.fetch_add(1, Ordering::Relaxed);
                            let message = if message.contains(&task.input) {
                                message
                            } else {
                                format!("{}: {message}", task.input)
                            };
                            eprintln!("pappus: {message}");
                            if job.json {
                                let line: Value = json!({
                                    "input": task.input,
                                    "error": message,
                                    "ms": ms,
                                });
                                outln!("{line}");
                            }
                        }
                    }
                }
            });
        }
    });
    match failed.into_inner() {
        0 => Ok(()),
        n => Err(format!("{n} of {} inputs failed", tasks.len())),
    }
}

/// The `{stem}` of an input: its file name without the extension; for `shape:NAME:ARGS`, the
/// name and its arguments joined by `-`.
fn stem(input: &str) -> String {
    if let Some(shape) = input.strip_prefix("shape:") {
        return shape.replace(':', "-");
    }
    Path::new(input)
        .file_stem()
        .map_or_else(|| input.to_string(), |s| s.to_string_lossy().into_owned())
}

/// The paths matching `pattern`, sorted (wildcards in any component).
///
/// # Errors
/// An unclosed `[`.
fn expand(pattern: &str) -> Result<Vec<PathBuf>, String> {
    let absolute = pattern.starts_with('/');
    let mut found = vec![if absolute {
        PathBuf::from("/")
    } else {
        PathBuf::new()
    }];
    let parts: Vec<&str> = pattern.split('/').filter(|p| !p.is_empty()).collect();
    for (k, part) in parts.iter().enumerate() {
        let last = k + 1 == parts.len();
        let mut next = Vec::new();
        for base in &found {
            if !is_pattern(part) {
                let path = base.join(part);
                if path.exists() {
                    next.push(path);
                }
                continue;
            }
            let dir = if base.as_os_str().is_empty() {
                Path::new(".")
            } else {
                base.as_path()
            };
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            for entry in entries.flatten() {
                let name = entry.file_name();
                let name = name.to_string_lossy();
                // As shells do, `*` does not match a leading dot.
                if name.starts_with('.') && !part.starts_with('.') {
                    continue;
                }
                if matches(part, &name)? && (last || entry.path().is_dir()) {
                    next.push(base.join(&*name));
                }
            }
        }
        found = next;
    }
    found.retain(|p| p.is_file());
    found.sort();
    Ok(found)
}

/// Whether `name` matches the one-component pattern `pattern` (`*`, `?`, `[…]`).
///
/// # Errors
/// An unclosed `[`.
fn matches(pattern: &str, name: &str) -> Result<bool, String> {
    let p: Vec<char> = pattern.chars().collect();
    let n: Vec<char> = name.chars().collect();
    // Backtracking over the last `*`: linear in practice, correct always.
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < n.len() {
        let step = match p.get(i) {
            Some('*') => {
                star = Some((i, j));
                i += 1;
                continue;
            }
            Some('?') => Some(1),
            Some('[') => {
                let (hit, len) = class(&p[i..], n[j])
                    .ok_or_else(|| format!("pattern `{pattern}`: unclosed `[`"))?;
                hit.then_some(len)
            }
            Some(&c) => (c == n[j]).then_some(1),
            None => None,
        };
        match (step, star) {
            (Some(len), _) => {
                i += len;
                j += 1;
            }
            (None, Some((si, sj))) => {
                i = si + 1;
                j = sj + 1;
                star = Some((si, sj + 1));
            }
            (None, None) => return Ok(false),
        }
    }
    Ok(p[i..].iter().all(|&c| c == '*'))
}

/// Matches `c` against the class at the start of `p` (`[abc]`, `[a-z]`, `[!abc]`): whether
/// it matches and the class's length; `None` when the class is not closed.
fn class(p: &[char], c: char) -> Option<(bool, usize)> {
    let negated = matches!(p.get(1), Some('!' | '^'));
    let mut k = if negated { 2 } else { 1 };
    let mut hit = false;
    let mut first = true;
    loop {
        match *p.get(k)? {
            ']' if !first => return Some((hit != negated, k + 1)),
            a => {
                if p.get(k + 1) == Some(&'-') && p.get(k + 2).is_some_and(|&b| b != ']') {
                    hit |= (a..=p[k + 2]).contains(&c);
                    k += 3;
                } else {
                    hit |= a == c;
                    k += 1;
                }
            }
        }
        first = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_match_as_in_a_shell() {
        for (pattern, name, expected) in [
            ("*.obj", "bunny.obj", true),
            ("*.obj", "bunny.off", false),
            ("b?nny.*", "bunny.obj", true),
            ("*", "", true),
            ("a*b*c", "aXbYbZc", true),
            ("a*b*c", "aXbYbZ", false),
            ("[bc]ow.obj", "cow.obj", true),
            ("[!bc]ow.obj", "cow.obj", false),
            ("[a-d]*", "cow.obj", true),
            ("[]x]", "]", true),
        ] {
            assert_eq!(
                matches(pattern, name).unwrap(),
                expected,
                "{pattern} {name}"
            );
        }
        assert!(matches("[abc", "a").is_err());
    }

    #[test]
    fn stems_name_files_and_shapes() {
        assert_eq!(stem("models/bunny.obj"), "bunny");
        assert_eq!(stem("shape:icosphere:3"), "icosphere-3");
    }

    #[test]
    fn a_pattern_expands_to_the_sorted_files_it_matches() {
        let dir = std::env::temp_dir().join(format!("pappus-glob-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        for name in ["b.obj", "a.obj", "c.off", "sub/d.obj", ".hidden.obj"] {
            std::fs::write(dir.join(name), "").unwrap();
        }
        let pattern = format!("{}/*.obj", dir.display());
        let names: Vec<String> = expand(&pattern)
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.obj", "b.obj"]);
        assert_eq!(
            expand(&format!("{}/*/*.obj", dir.display())).unwrap().len(),
            1
        );
        assert!(
            expand(&format!("{}/*.stl", dir.display()))
                .unwrap()
                .is_empty()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
