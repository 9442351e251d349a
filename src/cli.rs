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
//! usage error). Steps parse into the editor's own [`crate::edit::Edit`] ([`Step`]), so the two
//! apply the same operations with the same parameters and defaults.

use bevy::prelude::World;
use clap::{Parser, Subcommand};
use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::edit::{STEP_SYNTAX, Step};
use crate::io;
use crate::mesh::{BuiltMesh, MeshId, RepairReport, build_mesh, mesh_stats, to_soup, validate};

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
}

/// What a FILE may be.
const FILE_HELP: &str = "FILE: .obj .off .ply .stl, or shape:NAME (tetrahedron cube icosahedron \
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
    #[command(after_help = format!("STEP: {STEP_SYNTAX}\n\n{FILE_HELP}"))]
    Process {
        /// Source file (or shape:NAME).
        input: String,
        /// Destination file (format by extension).
        #[arg(short, long)]
        output: PathBuf,
        /// One JSON object with a record per step instead of text.
        #[arg(long)]
        json: bool,
        /// The steps, in order.
        #[arg(value_parser = Step::parse, value_name = "STEP")]
        steps: Vec<Step>,
    },
}

/// A mesh loaded for batch work, with what loading it cost.
pub struct Loaded {
    /// The world holding the mesh.
    pub world: World,
    /// The mesh and its repair report.
    pub built: BuiltMesh,
    /// Milliseconds spent reading and parsing the file.
    pub read_ms: f64,
    /// Milliseconds spent building entities (repairs included).
    pub build_ms: f64,
}

/// Reads `input` (a file, or `shape:NAME`) and builds it into a fresh world.
///
/// # Errors
/// A message naming the file and what is wrong with it.
pub fn load(input: &str) -> Result<Loaded, String> {
    let start = Instant::now();
    let (soup, info) = crate::source::read_source(Path::new(input))?;
    let read_ms = ms_since(start);
    let start = Instant::now();
    let mut world = World::new();
    let built = build_mesh(&mut world, &soup, info).map_err(|e| format!("{input}: {e}"))?;
    Ok(Loaded {
        world,
        built,
        read_ms,
        build_ms: ms_since(start),
    })
}

fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1000.0
}

/// The statistics, validation result and repairs of a mesh as the JSON object of
/// `pappus info --json` (see the README for the keys).
pub fn info_json(world: &World, mesh: MeshId, report: &RepairReport) -> Map<String, Value> {
    let s = mesh_stats(world, mesh);
    let validation = validate(world, mesh);
    let face_sizes: Map<String, Value> = s
        .face_sizes
        .iter()
        .map(|(k, v)| (k.to_string(), json!(v)))
        .collect();
    let repairs: Map<String, Value> = report
        .entries()
        .iter()
        .map(|&(k, v)| (k.to_string(), json!(v)))
        .collect();
    let manifold_input = report.non_manifold_vertices == 0
        && report.non_manifold_edge_faces == 0
        && report.non_orientable_faces == 0;
    let mut out = Map::new();
    for (k, v) in [
        ("vertices", json!(s.vertices)),
        ("edges", json!(s.edges)),
        ("faces", json!(s.faces)),
        ("halfedges", json!(s.halfedges)),
        ("boundary_loops", json!(s.boundary_loops)),
        ("components", json!(s.components)),
        ("euler_characteristic", json!(s.euler_characteristic)),
        ("genus", json!(s.genus)),
        ("manifold", json!(manifold_input && validation.is_ok())),
        ("closed", json!(s.closed)),
        ("face_sizes", Value::Object(face_sizes)),
        ("valid", json!(validation.is_ok())),
        ("repairs", Value::Object(repairs)),
        ("min_angle_deg", json!(round(s.min_angle_deg, 4))),
        (
            "pct_min_angle_below_30",
            json!(round(s.pct_min_angle_below_30, 4)),
        ),
        ("bbox_diag", json!(round(s.bbox_diag, 6))),
        ("mean_edge_length", json!(round(s.mean_edge_length, 6))),
    ] {
        out.insert(k.to_string(), v);
    }
    if let Err(e) = validation {
        out.insert("validation_error".into(), json!(e.to_string()));
    }
    out
}

fn round(x: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    (x * scale).round() / scale
}

fn info_text(name: &str, object: &Map<String, Value>, report: &RepairReport) -> String {
    let get = |k: &str| object.get(k).map(|v| v.to_string()).unwrap_or_default();
    let sizes: Vec<String> = object["face_sizes"]
        .as_object()
        .map(|m| m.iter().map(|(k, v)| format!("{k}-gons: {v}")).collect())
        .unwrap_or_default();
    let validity = match object.get("validation_error") {
        Some(e) => format!("INVALID: {}", e.as_str().unwrap_or_default()),
        None => "valid".to_string(),
    };
    format!(
        "{name}\n  V {}  E {}  F {}  H {}\n  χ {}  genus {}  components {}  boundary loops {}  closed {}  manifold {}\n  faces: {}\n  min angle {}°  triangles with min angle < 30°: {}%\n  bbox diagonal {}  mean edge length {}\n  {}\n  repairs: {}\n",
        get("vertices"),
        get("edges"),
        get("faces"),
        get("halfedges"),
        get("euler_characteristic"),
        get("genus"),
        get("components"),
        get("boundary_loops"),
        get("closed"),
        get("manifold"),
        sizes.join(", "),
        get("min_angle_deg"),
        get("pct_min_angle_below_30"),
        get("bbox_diag"),
        get("mean_edge_length"),
        validity,
        report,
    )
}

/// Runs a command and returns the process exit code. Output goes to stdout, errors to stderr.
pub fn run(command: Command) -> i32 {
    match execute(command) {
        Ok(()) => 0,
        Err(message) => {
            eprintln!("pappus: {message}");
            1
        }
    }
}

fn execute(command: Command) -> Result<(), String> {
    match command {
        Command::Info { input, json } => {
            let loaded = load(&input)?;
            let mut object = info_json(&loaded.world, loaded.built.mesh, &loaded.built.report);
            object.insert("read_ms".into(), json!(round(loaded.read_ms, 3)));
            object.insert("build_ms".into(), json!(round(loaded.build_ms, 3)));
            object.insert(
                "load_ms".into(),
                json!(round(loaded.read_ms + loaded.build_ms, 3)),
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
            io::write(&output, &soup).map_err(|e| e.to_string())?;
            if !loaded.built.report.is_clean() {
                eprintln!("pappus: {input}: repaired: {}", loaded.built.report);
            }
        }
        Command::Process {
            input,
            output,
            steps,
            json,
        } => {
            let mut loaded = load(&input)?;
            let mesh = loaded.built.mesh;
            let mut records = Vec::new();
            let mut history = None;
            for step in &steps {
                let start = Instant::now();
                let outcome = step.run(
                    &mut loaded.world,
                    mesh,
                    &loaded.built.input_vertices,
                    &mut history,
                );
                let ms = round(ms_since(start), 3);
                let mut record = Map::new();
                record.insert("step".into(), json!(step.to_string()));
                match &outcome {
                    Ok(summary) => {
                        record.insert("outcome".into(), json!("applied"));
                        record.insert("summary".into(), json!(summary));
                        if !json {
                            outln!("{step}: applied ({summary}) in {ms} ms");
                        }
                    }
                    Err(reason) => {
                        record.insert("outcome".into(), json!("refused"));
                        record.insert("reason".into(), json!(reason.to_string()));
                        if !json {
                            outln!("{step}: refused: {reason}");
                        }
                    }
                }
                record.insert("ms".into(), json!(ms));
                records.push(Value::Object(record));
            }
            let soup = to_soup(&loaded.world, mesh);
            io::write(&output, &soup).map_err(|e| e.to_string())?;
            let result = info_json(&loaded.world, mesh, &loaded.built.report);
            if json {
                outln!(
                    "{}",
                    json!({ "steps": records, "result": Value::Object(result) })
                );
            } else {
                out!(
                    "{}",
                    info_text(&output.display().to_string(), &result, &loaded.built.report)
                );
            }
        }
    }
    Ok(())
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
        };
        assert_eq!(parse("").unwrap(), editor(None));
        assert_eq!(parse("bunny.obj").unwrap(), editor(Some("bunny.obj")));
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
                steps: vec![Step::Edit(crate::edit::Edit::Triangulate), Step::Validate],
                json: true,
            })
        );
        assert!(parse("process a.obj triangulate").is_err());
        let unknown = parse("process a.obj -o b.obj frobnicate").unwrap_err();
        assert!(unknown.to_string().contains("unknown step"), "{unknown}");
        assert!(parse("info").is_err());
        assert!(parse("--bogus").is_err());
        assert!(parse("a.obj b.obj").is_err());
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
        assert!(process.contains("simplify:RATIO"), "{process}");
    }
}
