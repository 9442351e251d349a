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

use crate::colormap::Range;
use crate::edit::{Edit, STEP_SYNTAX, Step};
use crate::io;
use crate::memory_budget::Budget;
use crate::mesh::attributes::MeshAttributes;
use crate::mesh::tables::extract;
use crate::mesh::{
    BuiltMesh, MeshId, PolygonSoup, RepairReport, build_mesh, mesh_stats, to_soup, validate,
};
use crate::ops::geometry::closest::Reference;
use crate::ops::geometry::{
    NormalWeighting, Quantity, Surface, face_normals, scalar_curvature, vertex_normals,
};
use crate::ops::named::Named;
use crate::process_memory;
use bevy::math::DVec3;

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

mod batch;
mod recover;

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
    #[command(after_help = format!("{PROCESS_HELP}\n\nSTEP: {STEP_SYNTAX}\n\n{FILE_HELP}"))]
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
        /// valence, min-angle, edge-length, distance (to the input).
        #[arg(long, value_parser = parse_quantity, value_name = "NAME")]
        quantity: Option<Quantity>,
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
            || batch::is_pattern(text)
            || io::Format::from_path(Path::new(text)).is_ok()
        {
            return Ok(ProcessArg::Input(text.to_string()));
        }
        Step::parse(text).map(ProcessArg::Step)
    }
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
    load_for(input, &[])
}

/// [`load`], for `steps`: when one of them subdivides, the memory its first level will touch is
/// warmed on the other core while the file is read and the mesh built
/// ([`process_memory::warm`]). The warming is over when this returns, so that the steps have
/// warm memory and both cores to themselves (warming that went on into a subdivision slowed
/// it, the two contending for the cores).
fn load_for(input: &str, steps: &[Step]) -> Result<Loaded, String> {
    let warming = process_memory::warm(subdivision_bytes(input, steps));
    let loaded = read_and_build(input);
    if let Some(warming) = warming {
        // A warming thread that panicked warmed nothing; the steps run all the same.
        let _ = warming.join();
    }
    loaded
}

/// Reads `input` and builds it into a fresh world.
fn read_and_build(input: &str) -> Result<Loaded, String> {
    let start = Instant::now();
    let (soup, info) = crate::source::read_source(Path::new(input)).map_err(|e| e.to_string())?;
    let read_ms = ms_since(start);
    let dropped = soup.vertex_attributes();
    if !dropped.is_empty() {
        eprintln!(
            "pappus: {input}: the file's vertex {} is not kept (outputs carry positions, faces, UVs, normals and colours, and what --quantity or --normals adds)",
            dropped.join(", ")
        );
    }
    for note in &soup.notes {
        eprintln!("pappus: {input}: {note}");
    }
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

/// About how many bytes of a mesh file hold one row of the mesh it builds (a vertex, halfedge,
/// edge or face): the bunny's OBJ holds 417 000 rows in 3.0 MB. Binary files hold more rows a
/// byte, so for them the estimate below falls short, never over.
const FILE_BYTES_PER_ROW: u64 = 7;

/// The fresh memory the first level of the first subdividing step among `steps` will touch,
/// estimated from the size of the file `input` before it is read (so that warming can start at
/// once) by [`FILE_BYTES_PER_ROW`] and [`process_memory::BYTES_PER_ROW`]: a level makes about
/// four times the rows it starts from. Only the first level: warming for the second (16 times
/// the rows) would still be under way while the first level runs, the two contending for the
/// two cores. 0 when no step subdivides or `input` is not a file.
fn subdivision_bytes(input: &str, steps: &[Step]) -> usize {
    let subdivides = steps
        .iter()
        .any(|step| matches!(step, Step::Edit(Edit::Subdivide(_))));
    let file_bytes = match std::fs::metadata(input) {
        Ok(meta) if subdivides => meta.len(),
        _ => return 0,
    };
    let rows = usize::try_from(file_bytes / FILE_BYTES_PER_ROW).unwrap_or(usize::MAX);
    rows.saturating_mul(4 * process_memory::BYTES_PER_ROW)
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
    let has = MeshAttributes::of(world, mesh);
    out.insert(
        "attributes".into(),
        json!({ "uv": has.uv, "normals": has.normals, "colors": has.colors, "seams": has.seams, "groups": has.groups }),
    );
    let (curvature, normals) = geometry_json(world, mesh, s.euler_characteristic);
    out.insert("curvature".into(), Value::Object(curvature));
    out.insert("normals".into(), Value::Object(normals));
    out
}

/// The whole object `pappus info --json` prints: [`info_json`] plus `read_ms`, `build_ms` and
/// `load_ms` (their sum), what reading and building the mesh took, rounded to 3 decimals.
pub fn info_with_load_times(
    world: &World,
    mesh: MeshId,
    report: &RepairReport,
    read_ms: f64,
    build_ms: f64,
) -> Map<String, Value> {
    let mut object = info_json(world, mesh, report);
    object.insert("read_ms".into(), json!(round(read_ms, 3)));
    object.insert("build_ms".into(), json!(round(build_ms, 3)));
    object.insert("load_ms".into(), json!(round(read_ms + build_ms, 3)));
    object
}

/// The curvature and normal summaries of `info --json`: each curvature's min, median and max
/// over the vertices; the total angle defect beside 2πχ (Gauss–Bonnet: equal); faces and
/// vertices whose normal is undefined (zero area).
fn geometry_json(
    world: &World,
    mesh: MeshId,
    chi: i64,
) -> (Map<String, Value>, Map<String, Value>) {
    let tables = extract(world, mesh).tables;
    let surface = Surface::from_tables(&tables);
    let c = scalar_curvature(&surface);
    let summary = |values: &[f64]| {
        let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_unstable_by(f64::total_cmp);
        let at = |p: f64| {
            sorted
                .get(((sorted.len().max(1) - 1) as f64 * p).round() as usize)
                .copied()
                .unwrap_or(0.0)
        };
        json!({ "min": at(0.0), "median": at(0.5), "max": at(1.0) })
    };
    let mut curvature_out = Map::new();
    for (k, v) in [
        ("mean", summary(&c.mean)),
        ("gaussian", summary(&c.gaussian)),
        ("max_principal", summary(&c.max)),
        ("min_principal", summary(&c.min)),
        (
            "total_angle_defect",
            json!(c.angle_defect.iter().sum::<f64>()),
        ),
        ("two_pi_chi", json!(2.0 * std::f64::consts::PI * chi as f64)),
    ] {
        curvature_out.insert(k.to_string(), v);
    }
    let faces = face_normals(&surface, tables.face_count());
    let mut normals = Map::new();
    normals.insert(
        "degenerate_faces".into(),
        json!(faces.iter().filter(|n| **n == DVec3::ZERO).count()),
    );
    normals.insert(
        "degenerate_vertices".into(),
        json!(c.normal.iter().filter(|n| **n == DVec3::ZERO).count()),
    );
    (curvature_out, normals)
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

/// What `process` does to each input: the steps and the output options.
#[derive(Clone, Debug)]
struct ProcessJob {
    /// The steps, in order.
    steps: Vec<Step>,
    /// JSON instead of text.
    json: bool,
    /// A per-vertex quantity to write into the output.
    quantity: Option<Quantity>,
    /// Vertex normals to write into the output.
    normals: Option<NormalWeighting>,
}

/// Checks that `output`'s format can hold what `job` writes beside the mesh.
///
/// # Errors
/// A format Pappus does not write, `--normals` into a format without normals, `--quantity`
/// into anything but PLY.
fn check_output(job: &ProcessJob, output: &Path) -> Result<(), String> {
    if let Ok(format) = io::Format::from_path(output)
        && !format.writes()
    {
        return Err(io::IoError::ReadOnly(output.to_path_buf()).to_string());
    }
    if job.normals.is_some()
        && !matches!(
            io::Format::from_path(output),
            Ok(io::Format::Ply | io::Format::Obj)
        )
    {
        return Err(format!(
            "--normals writes vertex normals, which OBJ and PLY hold: {} is neither",
            output.display()
        ));
    }
    if job.quantity.is_some() && !matches!(io::Format::from_path(output), Ok(io::Format::Ply)) {
        return Err(format!(
            "--quantity writes vertex quality and colours, which only PLY holds: {} is not a .ply file",
            output.display()
        ));
    }
    Ok(())
}

/// Runs `job` on one input and writes `output`. Text lines (when not `job.json`) go to
/// `text` as they come, warnings to `warn` (without the `pappus: ` prefix). Returns the JSON
/// report: `{"steps": […], "result": {info keys}, "dropped": [what the output's format could
/// not hold: "UVs", "normals", "colours", "quality"], "quantity"?: {…}}`.
///
/// # Errors
/// A message naming the file: it could not be read, built or written.
fn process_file(
    job: &ProcessJob,
    input: &str,
    output: &Path,
    text: &mut dyn FnMut(&str),
    warn: &mut dyn FnMut(&str),
) -> Result<Value, String> {
    let ProcessJob {
        steps,
        json,
        quantity,
        normals,
    } = job;
    let (json, quantity, normals) = (*json, *quantity, *normals);
    let mut loaded = load_for(input, steps)?;
    let mesh = loaded.built.mesh;
    // The distance quantity measures how far the steps moved the mesh from the input.
    let reference = (quantity == Some(Quantity::Distance))
        .then(|| Reference::of_tables(&extract(&loaded.world, mesh).tables));
    let mut records = Vec::new();
    let mut history = None;
    for step in steps {
        let start = Instant::now();
        let had = MeshAttributes::of(&loaded.world, mesh);
        let outcome = step.run(
            &mut loaded.world,
            mesh,
            &loaded.built.input_vertices,
            &mut history,
        );
        let ms = round(ms_since(start), 3);
        let lost = had.lost_in(MeshAttributes::of(&loaded.world, mesh));
        if !lost.is_empty() {
            warn(&format!(
                "{step}: {} dropped (the output will not have them)",
                lost.describe()
            ));
        }
        let mut record = Map::new();
        record.insert("step".into(), json!(step.to_string()));
        match &outcome {
            Ok(summary) => {
                record.insert("outcome".into(), json!("applied"));
                record.insert("summary".into(), json!(summary));
                if !json {
                    text(&format!("{step}: applied ({summary}) in {ms} ms\n"));
                }
            }
            Err(reason) => {
                record.insert("outcome".into(), json!("refused"));
                record.insert("reason".into(), json!(reason.to_string()));
                if !json {
                    text(&format!("{step}: refused: {reason}\n"));
                }
            }
        }
        record.insert("ms".into(), json!(ms));
        records.push(Value::Object(record));
    }
    // `--normals` writes normals of its own: stale ones need no recomputing first.
    let (mut soup, recomputed) = match normals {
        Some(_) => (to_soup(&loaded.world, mesh), None),
        None => crate::edit::soup_to_save(&loaded.world, mesh),
    };
    let quantity =
        quantity.map(|q| attach_quantity(&loaded.world, mesh, q, reference.as_ref(), &mut soup));
    if let Some(weighting) = normals {
        // The soup's vertices are the mesh's table rows (see `to_soup`).
        let surface = Surface::from_tables(&extract(&loaded.world, mesh).tables);
        let n = vertex_normals(&surface, weighting);
        soup.vertex_normals = Some(n.iter().map(|v| v.as_vec3()).collect());
    }
    let dropped = write_mesh(output, &soup, warn)?;
    if let Some(note) = recomputed {
        warn(&format!("{}: {note}", output.display()));
    }
    if MeshAttributes::of(&loaded.world, mesh).seams {
        warn(&format!(
            "{}: seam marks are not written (the format has no place for them; \
             a param step after them keeps the cut in the UVs)",
            output.display()
        ));
    }
    let result = info_json(&loaded.world, mesh, &loaded.built.report);
    if !json {
        text(&info_text(
            &output.display().to_string(),
            &result,
            &loaded.built.report,
        ));
    }
    let mut report =
        json!({ "steps": records, "result": Value::Object(result), "dropped": dropped });
    if let Some(q) = quantity {
        report["quantity"] = Value::Object(q);
    }
    Ok(report)
}

/// Writes `soup` to `output` and says on `warn` (without the `pappus: ` prefix) what the
/// output's format could not hold; returns that, for `--json`'s `"dropped"`.
///
/// # Errors
/// The write's error, naming the file.
fn write_mesh(
    output: &Path,
    soup: &PolygonSoup,
    warn: &mut dyn FnMut(&str),
) -> Result<Vec<&'static str>, String> {
    let dropped = io::dropped(output, soup);
    io::write(output, soup).map_err(|e| e.to_string())?;
    if !dropped.is_empty() {
        warn(&io::dropped_note(output, &dropped));
    }
    Ok(dropped)
}

/// Parses a `--normals` weighting.
fn parse_weighting(name: &str) -> Result<NormalWeighting, String> {
    match name {
        "angle" => Ok(NormalWeighting::Angle),
        "area" => Ok(NormalWeighting::Area),
        _ => Err(format!("unknown weighting `{name}`; known: angle, area")),
    }
}

/// Parses a `--quantity` name.
fn parse_quantity(name: &str) -> Result<Quantity, String> {
    Quantity::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Quantity::ALL.iter().map(|(_, n)| *n).collect();
        format!("unknown quantity `{name}`; known: {}", names.join(", "))
    })
}

/// Computes `quantity` on `mesh` (a distance to `input`) and puts it into `soup` (whose vertices
/// are the mesh's table rows, as [`to_soup`] writes them) as quality and colours. Returns its
/// JSON summary.
fn attach_quantity(
    world: &World,
    mesh: MeshId,
    quantity: Quantity,
    input: Option<&Reference>,
    soup: &mut crate::mesh::PolygonSoup,
) -> Map<String, Value> {
    let start = Instant::now();
    let values = quantity.per_vertex(&extract(world, mesh).tables, input);
    let ms = ms_since(start);
    let map = quantity.colormap();
    let range = Range::robust(&values, 1.0, map);
    soup.vertex_colors = Some(values.iter().map(|&v| map.at(range.fraction(v))).collect());
    soup.vertex_quality = Some(values.iter().map(|&v| v as f32).collect());
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let mean = finite.iter().sum::<f64>() / finite.len().max(1) as f64;
    let (min, max) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let mut out = Map::new();
    for (k, v) in [
        ("name", json!(quantity.name())),
        ("ms", json!(round(ms, 3))),
        ("min", json!(min)),
        ("max", json!(max)),
        ("mean", json!(mean)),
        ("colour_low", json!(range.low)),
        ("colour_high", json!(range.high)),
    ] {
        out.insert(k.to_string(), v);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warms_for_the_first_subdivision_level_by_the_file_size() {
        let dir = std::env::temp_dir().join(format!("pappus-warm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("mesh.obj");
        std::fs::write(&file, vec![b' '; 7_000]).unwrap();
        let input = file.to_str().unwrap();
        let steps = |text: &str| -> Vec<Step> {
            text.split_whitespace()
                .map(|s| Step::parse(s).unwrap())
                .collect()
        };
        // 7 000 bytes: 1 000 rows, four times as many after a level, whatever the levels.
        let level = 4 * 1_000 * process_memory::BYTES_PER_ROW;
        assert_eq!(subdivision_bytes(input, &steps("loop:1")), level);
        assert_eq!(
            subdivision_bytes(input, &steps("triangulate loop:3")),
            level
        );
        assert_eq!(subdivision_bytes(input, &steps("catmull-clark")), level);
        assert_eq!(subdivision_bytes(input, &steps("simplify:0.5 remesh")), 0);
        assert_eq!(subdivision_bytes("shape:torus", &steps("loop:1")), 0);
        assert_eq!(
            subdivision_bytes(&format!("{input}.gone"), &steps("loop:1")),
            0
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn parse(text: &str) -> Result<Cli, clap::Error> {
        Cli::try_parse_from(std::iter::once("pappus").chain(text.split_whitespace()))
    }

    #[test]
    fn parses_every_command() {
        let editor = |file: Option<&str>| Cli {
            file: file.map(PathBuf::from),
            command: None,
            max_memory: None,
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
                steps: vec![
                    ProcessArg::Step(Step::Edit(crate::edit::Edit::Triangulate)),
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
