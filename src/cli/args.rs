//! The command line's arguments, as clap parses them: the commands, their options, the
//! `process` inputs and steps, and the help texts.

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

use crate::edit::{Step, step_syntax};
use crate::io;
use crate::memory_budget::Budget;
use crate::ops::geometry::NormalWeighting;

use super::process::{QuantityArg, parse_quantity, parse_weighting};

/// The command line.
#[derive(Parser, Clone, Debug, PartialEq)]
#[command(
    name = "pappus",
    version,
    about = "Pappus: an interactive halfedge mesh editor, and its batch mode",
    args_conflicts_with_subcommands = true,
    after_help = FILE_HELP
)]
pub struct Cli {
    /// Open the editor on this mesh (a file, or shape:NAME); the default model if none.
    pub file: Option<PathBuf>,
    /// A batch command; without one, the editor opens.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Open the editor on what a script hands over and hand the mesh back when the window
    /// closes: REQUEST is the JSON file Python's `pappus.show` writes (the mesh, its arrays,
    /// the folder the mesh goes back to).
    #[arg(long, value_name = "REQUEST", conflicts_with = "file")]
    pub show: Option<PathBuf>,
    /// The memory an operation may ask for: a size (2G, 512M) or a share of the available
    /// memory (50%); default 75%. An operation whose result would need more is refused with
    /// its estimate.
    #[arg(long, global = true, value_parser = Budget::parse, value_name = "SIZE")]
    pub max_memory: Option<Budget>,
}

/// What a FILE may be.
const FILE_HELP: &str = "FILE: .obj .off .ply .stl .glb .gltf .dae (read only), or shape:NAME (tetrahedron cube icosahedron \
icosphere torus grid quad-grid grid-with-holes double-torus)";

/// The batch commands.
#[derive(Subcommand, Clone, Debug, PartialEq)]
pub enum Command {
    /// Statistics, validation and repair report.
    #[command(after_help = FILE_HELP)]
    Info {
        /// The mesh to describe (a file, or shape:NAME).
        input: String,
        /// One JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Rewrite a mesh in another format (chosen by the extension).
    #[command(after_help = FILE_HELP)]
    Convert {
        /// Source file (or shape:NAME).
        input: String,
        /// Destination file.
        output: PathBuf,
    },
    /// Run steps in order, then write the result.
    #[command(after_help = format!("{PROCESS_HELP}\n\nSTEP: {}\n\n{FILE_HELP}", step_syntax()))]
    Process {
        /// Source file (or shape:NAME, or a glob pattern such as 'models/*.obj').
        input: String,
        /// Destination file (format by extension). With several inputs, a pattern: `{stem}`
        /// stands for each input's file name without its extension (`-o out/{stem}.ply`).
        #[arg(short, long)]
        output: PathBuf,
        /// One JSON object with a record per step instead of text (with several inputs: one
        /// line per input).
        #[arg(long)]
        json: bool,
        /// With several inputs: how many to process at once (threads, one World each).
        #[arg(short = 'j', long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
        jobs: u32,
        /// Write this per-vertex quantity of the result into OUT (a PLY file) as `quality`,
        /// and as vertex colours: mean, gaussian, angle-defect, max-curvature, min-curvature,
        /// valence, min-angle, edge-length, distance (to the input), or another registered
        /// one; one that starts from vertices takes their input numbers (`NAME:A/B`).
        #[arg(long, value_parser = parse_quantity, value_name = "NAME")]
        quantity: Option<QuantityArg>,
        /// Write vertex normals of the result into OUT (OBJ `vn`, PLY `nx ny nz`), weighted by
        /// the faces' angles at the vertex (Thürmer & Wüthrich) or by their areas.
        #[arg(long, value_parser = parse_weighting, value_name = "angle|area")]
        normals: Option<NormalWeighting>,
        /// More inputs (files with a mesh extension, shape:NAME, glob patterns), then the
        /// steps, in order.
        #[arg(value_parser = ProcessArg::parse, value_name = "STEP")]
        steps: Vec<ProcessArg>,
    },
    /// List or restore the editor's recovery files: unsaved work kept after a crash or a kill.
    #[command(after_help = RECOVER_HELP)]
    Recover {
        /// The recovery to restore, by name (as --list shows it).
        #[arg(conflicts_with_all = ["latest", "list"])]
        name: Option<String>,
        /// List the recoveries, newest first.
        #[arg(long, conflicts_with = "latest")]
        list: bool,
        /// Restore the newest recovery.
        #[arg(long)]
        latest: bool,
        /// Where to write the restored mesh (format by extension).
        #[arg(short, long, required_unless_present = "list")]
        output: Option<PathBuf>,
        /// JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// A positional argument of `process` after the first input: another input, or a step.
#[derive(Clone, Debug, PartialEq)]
pub enum ProcessArg {
    /// A mesh source: `shape:NAME`, a path with a mesh extension, or a glob pattern.
    Input(String),
    /// A step.
    Step(Step),
}

impl ProcessArg {
    /// An input when `text` names a mesh source (`shape:…`, a `.obj .off .ply .stl .glb .gltf .dae` path, or
    /// a pattern with `*`, `?` or `[`), else a step.
    ///
    /// # Errors
    /// The step's parse error (an unknown step, malformed arguments).
    pub fn parse(text: &str) -> Result<ProcessArg, String> {
        if text.starts_with("shape:")
            || is_pattern(text)
            || io::Format::from_path(Path::new(text)).is_ok()
        {
            return Ok(ProcessArg::Input(text.to_string()));
        }
        Step::parse(text).map(ProcessArg::Step)
    }
}

/// How `recover` is used.
const RECOVER_HELP: &str = "The editor keeps unsaved work in $XDG_STATE_HOME/pappus/recovery \
(default ~/.local/state/pappus/recovery) a few seconds after each edit, and removes it on save. \
`pappus recover --list` lists what is kept; `pappus recover --latest -o bunny.obj` writes the \
newest back as a mesh file.";

/// How `process` takes several inputs.
const PROCESS_HELP: &str = "Several inputs: `pappus process a.obj b.off 'scans/*.ply' -o out/{stem}.ply -j 2 STEP...`: \
each input runs the steps in its own World; a failed input is reported and the others go on \
(exit code 1 if any failed); --json prints one line per input, with `input` and `output` (or \
`error`) beside the single-file keys.";

/// Whether `text` is a glob pattern (holds `*`, `?` or `[`): an input that names several files.
pub(super) fn is_pattern(text: &str) -> bool {
    text.contains(['*', '?', '['])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Cli, clap::Error> {
        Cli::try_parse_from(std::iter::once("pappus").chain(text.split_whitespace()))
    }

    #[test]
    fn parses_every_command() {
        let editor = |file: Option<&str>| Cli {
            file: file.map(PathBuf::from),
            command: None,
            show: None,
            max_memory: None,
        };
        assert_eq!(parse("").unwrap(), editor(None));
        assert_eq!(parse("bunny.obj").unwrap(), editor(Some("bunny.obj")));
        assert_eq!(
            parse("--show /tmp/r.json").unwrap().show,
            Some(PathBuf::from("/tmp/r.json"))
        );
        assert!(parse("a.obj --show /tmp/r.json").is_err());
        assert_eq!(
            parse("info a.off --json").unwrap().command,
            Some(Command::Info {
                input: "a.off".into(),
                json: true
            })
        );
        assert_eq!(
            parse("process a.obj -o b.ply triangulate validate --json")
                .unwrap()
                .command,
            Some(Command::Process {
                input: "a.obj".into(),
                output: "b.ply".into(),
                steps: vec![
                    ProcessArg::Step(Step::Edit(
                        crate::edit::Edit::registered("triangulate").unwrap()
                    )),
                    ProcessArg::Step(Step::Validate)
                ],
                json: true,
                jobs: 1,
                quantity: None,
                normals: None,
            })
        );
        let Some(Command::Process { steps, jobs, .. }) =
            parse("process a.obj m/*.ply shape:cube -o out/{stem}.ply -j 2 loop")
                .unwrap()
                .command
        else {
            panic!("a process command");
        };
        assert_eq!(jobs, 2);
        assert_eq!(
            steps,
            [
                ProcessArg::Input("m/*.ply".into()),
                ProcessArg::Input("shape:cube".into()),
                ProcessArg::Step(Step::parse("loop").unwrap()),
            ]
        );
        assert!(parse("process a.obj -o b.obj -j 0").is_err());
        assert!(parse("process a.obj triangulate").is_err());
        let unknown = parse("process a.obj -o b.obj frobnicate").unwrap_err();
        assert!(unknown.to_string().contains("unknown step"), "{unknown}");
        assert!(parse("info").is_err());
        assert!(parse("--bogus").is_err());
        assert!(parse("a.obj b.obj").is_err());
    }

    #[test]
    fn a_quantity_takes_source_vertices_only_where_it_starts_from_them() {
        let q = parse_quantity("Mean").unwrap();
        assert_eq!(q.quantity.name(), "mean");
        assert!(q.sources.is_empty());
        let e = parse_quantity("valence:0/1").unwrap_err();
        assert_eq!(e, "valence takes no vertices");
        let e = parse_quantity("curl").unwrap_err();
        assert!(
            e.starts_with("unknown quantity `curl`; known: mean, gaussian"),
            "{e}"
        );
    }

    #[test]
    fn every_subcommand_has_help() {
        for sub in ["info", "convert", "process"] {
            let e = parse(&format!("{sub} --help")).unwrap_err();
            assert_eq!(e.kind(), clap::error::ErrorKind::DisplayHelp);
            let text = e.to_string();
            assert!(text.contains("Usage: pappus"), "{text}");
        }
        let process = parse("process --help").unwrap_err().to_string();
        assert!(process.contains("simplify[:RATIO]"), "{process}");
        assert!(
            process.contains("param[:uniform|mean-value|harmonic|lscm]"),
            "{process}"
        );
    }
}
