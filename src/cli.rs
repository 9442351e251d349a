//! The batch command line: `info`, `convert` and `process`, with no window and no GPU.
//!
//! ```text
//! pappus [FILE]                               open the editor (on FILE, or the default model)
//! pappus info FILE [--json]                   statistics, validation and repair report
//! pappus convert IN OUT                       rewrite a mesh in another format (by extension)
//! pappus process IN -o OUT [--json] STEP...   run steps in order, then write OUT
//! ```
//!
//! `FILE` may also be `shape:NAME` for a procedural shape (`shape:torus`, see
//! [`crate::mesh::shapes::SHAPE_NAMES`]). This is a contract that scripts and benchmarks rely
//! on: the keys of the JSON output are stable. Errors go to stderr with exit code 1 (2 for a
//! usage error). Steps parse into the editor's own [`crate::edit::Edit`]
//! ([`crate::edit::Step`]), so the two apply the same operations with the same parameters and
//! defaults. The files: `args` (what clap parses), `loading` (an input read and built),
//! `report` (what `info` prints), `process` (one input's steps and output), `batch` (many
//! inputs on threads), `recover` (the editor's recoveries).

use serde_json::Value;

use crate::mesh::to_soup;

/// Writes to stdout; a reader that has gone away (`pappus info … | head`) ends the output
/// quietly instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($arg)*);
    }};
}

/// [`out!`] with a newline.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod args;
mod batch;
mod loading;
mod process;
mod recover;
mod report;

pub use args::{Cli, Command, ProcessArg};
pub use loading::{Loaded, load};
pub use report::{info_json, info_with_load_times};

use process::{ProcessJob, write_mesh};
use report::info_text;

/// Runs a command and returns the process exit code. Output goes to stdout, errors to stderr:
/// 1 for a failure, 2 for a usage error (a `shape:` name that is unknown, or whose sizes pass
/// the limits, found before anything is read).
pub fn run(command: Command) -> i32 {
    if let Err(message) = check_shapes(&command) {
        eprintln!("pappus: {message}");
        return 2;
    }
    match execute(command) {
        Ok(()) => 0,
        Err(message) => {
            eprintln!("pappus: {message}");
            1
        }
    }
}

/// Checks every `shape:` input of `command` ([`crate::mesh::shapes::check_name`]): its sizes
/// are multiplied out in 64 bits and held to the memory budget before anything is made.
fn check_shapes(command: &Command) -> Result<(), String> {
    let inputs: Vec<&str> = match command {
        Command::Info { input, .. } | Command::Convert { input, .. } => vec![input],
        Command::Process { input, steps, .. } => std::iter::once(input.as_str())
            .chain(steps.iter().filter_map(|arg| match arg {
                ProcessArg::Input(input) => Some(input.as_str()),
                ProcessArg::Step(_) => None,
            }))
            .collect(),
        Command::Recover { .. } => Vec::new(),
    };
    for name in inputs.iter().filter_map(|i| i.strip_prefix("shape:")) {
        crate::mesh::shapes::check_name(name).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn execute(command: Command) -> Result<(), String> {
    match command {
        Command::Info { input, json } => {
            let loaded = load(&input)?;
            let object = info_with_load_times(
                &loaded.world,
                loaded.built.mesh,
                &loaded.built.report,
                loaded.read_ms,
                loaded.build_ms,
            );
            if json {
                outln!("{}", Value::Object(object));
            } else {
                out!("{}", info_text(&input, &object, &loaded.built.report));
                outln!(
                    "  loaded in {:.1} ms (read {:.1} ms, build {:.1} ms)",
                    loaded.read_ms + loaded.build_ms,
                    loaded.read_ms,
                    loaded.build_ms
                );
            }
        }
        Command::Convert { input, output } => {
            let loaded = load(&input)?;
            let soup = to_soup(&loaded.world, loaded.built.mesh);
            write_mesh(&output, &soup, &mut |message| {
                eprintln!("pappus: {message}");
            })?;
            if !loaded.built.report.is_clean() {
                eprintln!("pappus: {input}: repaired: {}", loaded.built.report);
            }
        }
        Command::Process {
            input,
            output,
            steps,
            json,
            jobs,
            quantity,
            normals,
        } => {
            let job = ProcessJob {
                json,
                quantity,
                normals,
                steps: Vec::new(),
            };
            return batch::process(input, output, steps, jobs as usize, job);
        }
        Command::Recover {
            name,
            list,
            latest,
            output,
            json,
        } => {
            return recover::recover(recover::RecoverArgs {
                name,
                list,
                latest,
                output,
                json,
            });
        }
    }
    Ok(())
}
