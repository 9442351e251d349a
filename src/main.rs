//! The `pappus` program: the editor, or batch mode when given a subcommand.
//!
//! Built without the `editor` feature (`--no-default-features`) it is batch mode only: with no
//! subcommand it says so and exits with 2, as for a usage error.

use clap::Parser;
use pappus::cli::{self, Cli};

fn main() {
    // Before any bulk allocation: freed memory is kept for the next operation.
    pappus::process_memory::keep_freed_memory();
    // A save past the file-size limit (`ulimit -f`) fails with a message, the old file intact.
    pappus::io::ignore_file_size_signal();
    // A usage error prints the usage and exits with 2; --help and --version exit with 0.
    let Cli {
        file,
        command,
        show,
        max_memory,
    } = Cli::parse();
    if let Some(budget) = max_memory {
        pappus::memory_budget::set(budget);
    }
    let code = match command {
        None => open_editor(file, show),
        Some(command) => cli::run(command),
    };
    std::process::exit(code);
}

/// Opens the editor on `file` (or the default model), or on what a script hands over
/// (`--show`), and returns its exit code.
#[cfg(feature = "editor")]
fn open_editor(file: Option<std::path::PathBuf>, show: Option<std::path::PathBuf>) -> i32 {
    match show {
        Some(request) => pappus::editor::run_show(&request),
        None => pappus::editor::run(file),
    }
}

/// This build has no editor: says so, and returns 2.
#[cfg(not(feature = "editor"))]
fn open_editor(_file: Option<std::path::PathBuf>, _show: Option<std::path::PathBuf>) -> i32 {
    eprintln!(
        "pappus: this build has no editor (built without the `editor` feature); \
         use a subcommand: info, convert, process (see `pappus --help`)"
    );
    2
}
