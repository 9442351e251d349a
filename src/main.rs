//! The `pappus` program: the editor, or batch mode when given a subcommand.

use clap::Parser;
use pappus::cli::{self, Cli};

fn main() {
    // A usage error prints the usage and exits with 2; --help and --version exit with 0.
    let Cli { file, command } = Cli::parse();
    let code = match command {
        None => pappus::editor::run(file),
        Some(command) => cli::run(command),
    };
    std::process::exit(code);
}
