//! The `pappus` program: the editor, or batch mode when given a subcommand.

use pappus::cli::{self, Command};

fn main() {
    let code = match cli::parse_args(std::env::args().skip(1)) {
        Ok(Command::Editor(path)) => pappus::editor::run(path),
        Ok(command) => cli::run(command),
        Err(message) => {
            eprintln!("pappus: {message}");
            2
        }
    };
    std::process::exit(code);
}
