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
//! usage error).

use bevy::prelude::World;
use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::io;
use crate::mesh::ids::{EdgeId, ElementId};
use crate::mesh::topology::MeshRef;
use crate::mesh::{
    BuiltMesh, MeshId, RepairReport, VertexId, build_mesh, mesh_stats, to_soup, validate,
};
use crate::ops::local::{
    CollapseOptions, collapse_edge, dissolve_edge, flip_edge, split_edge, split_face,
};
use crate::ops::progressive::ProgressiveMesh;
use crate::ops::remesh::{RemeshParams, remesh};
use crate::ops::simplify::SimplifyParams;
use crate::ops::subdivide::{SubdivisionSummary, catmull_clark, loop_subdivide};
use crate::ops::{Refusal, triangulate};

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

/// What `main` should do with the arguments.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Open the editor, optionally on a file.
    Editor(Option<PathBuf>),
    /// `pappus info FILE [--json]`.
    Info {
        /// The mesh to describe.
        input: String,
        /// One JSON object instead of text.
        json: bool,
    },
    /// `pappus convert IN OUT`.
    Convert {
        /// Source file.
        input: String,
        /// Destination file (format by extension).
        output: PathBuf,
    },
    /// `pappus process IN -o OUT [--json] STEP...`.
    Process {
        /// Source file.
        input: String,
        /// Destination file.
        output: PathBuf,
        /// Steps, in order.
        steps: Vec<Step>,
        /// JSON report instead of text.
        json: bool,
    },
    /// Print the usage text.
    Help,
    /// Print the version.
    Version,
}

/// The usage text.
pub const USAGE: &str = "\
Pappus — an interactive halfedge mesh editor

usage:
  pappus [FILE]                               open the editor (on FILE, or the default model)
  pappus info FILE [--json]                   statistics, validation and repair report
  pappus convert IN OUT                       rewrite a mesh in another format (by extension)
  pappus process IN -o OUT [--json] STEP...   run steps in order, then write OUT

FILE: .obj .off .ply .stl, or shape:NAME (tetrahedron cube icosahedron icosphere torus grid
      quad-grid grid-with-holes double-torus)
STEP: validate | triangulate | flip:A,B | split:A,B | collapse:A,B | dissolve:A,B |
      split-face:A,B | loop[:N] | catmull-clark[:N] | simplify:RATIO | simplify-faces:N |
      refine[:FACES]   (split simplify's collapses back, up to FACES faces or all) |
      remesh[:ITERATIONS[:LENGTH]]   (isotropic; LENGTH defaults to the mean edge length)
      A, B: 0-based indices of the input file's vertices (the edge between them)
";

/// One step of `pappus process`.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Check every invariant; refused (with the broken rule) if one fails.
    Validate,
    /// Triangulate every polygon.
    Triangulate,
    /// Flip the edge between two input vertices.
    Flip(u32, u32),
    /// Split the edge between two input vertices at its midpoint.
    Split(u32, u32),
    /// Collapse the edge between two input vertices to its midpoint.
    Collapse(u32, u32),
    /// Merge the two faces of the edge between two input vertices.
    Dissolve(u32, u32),
    /// Join two input vertices across the face they share.
    SplitFace(u32, u32),
    /// QEM simplification to a ratio of the faces.
    Simplify(f64),
    /// QEM simplification to a face count.
    SimplifyFaces(usize),
    /// Split the last simplification's collapses back, up to a face count (all if `None`).
    Refine(Option<usize>),
    /// Isotropic remeshing: iterations, and the target length (mean edge length if `None`).
    Remesh(u32, Option<f32>),
    /// Loop subdivision, N levels.
    Loop(u32),
    /// Catmull–Clark subdivision, N levels.
    CatmullClark(u32),
}

impl Step {
    /// Parses a step as written on the command line.
    ///
    /// # Errors
    /// A message naming the step when it is unknown or its arguments are malformed.
    pub fn parse(text: &str) -> Result<Step, String> {
        let (name, args) = text.split_once(':').unwrap_or((text, ""));
        let pair = || -> Result<(u32, u32), String> {
            let bad = || format!("step `{text}`: expected two vertex numbers, as in `{name}:3,17`");
            let (a, b) = args.split_once(',').ok_or_else(bad)?;
            Ok((
                a.trim().parse().map_err(|_| bad())?,
                b.trim().parse().map_err(|_| bad())?,
            ))
        };
        let levels = || -> Result<u32, String> {
            if args.is_empty() {
                return Ok(1);
            }
            match args.parse::<u32>() {
                Ok(n) if (1..=8).contains(&n) => Ok(n),
                _ => Err(format!(
                    "step `{text}`: levels must be a number from 1 to 8"
                )),
            }
        };
        match name {
            "validate" => Ok(Step::Validate),
            "loop" => levels().map(Step::Loop),
            "simplify" => match args.parse::<f64>() {
                Ok(r) if r > 0.0 && r <= 1.0 => Ok(Step::Simplify(r)),
                _ => Err(format!(
                    "step `{text}`: the ratio must be in (0, 1], as in `simplify:0.25`"
                )),
            },
            "remesh" => {
                let bad = || format!("step `{text}`: expected remesh[:ITERATIONS[:LENGTH]]");
                let mut parts = args.split(':').filter(|p| !p.is_empty());
                let iterations = match parts.next() {
                    Some(n) => n
                        .parse::<u32>()
                        .ok()
                        .filter(|n| (1..=100).contains(n))
                        .ok_or_else(bad)?,
                    None => 5,
                };
                let length = match parts.next() {
                    Some(l) => Some(
                        l.parse::<f32>()
                            .ok()
                            .filter(|l| *l > 0.0 && l.is_finite())
                            .ok_or_else(bad)?,
                    ),
                    None => None,
                };
                Ok(Step::Remesh(iterations, length))
            }
            "refine" if args.is_empty() => Ok(Step::Refine(None)),
            "refine" => args
                .parse::<usize>()
                .map(|n| Step::Refine(Some(n)))
                .map_err(|_| format!("step `{text}`: expected a face count, as in `refine:5000`")),
            "simplify-faces" => args.parse::<usize>().map(Step::SimplifyFaces).map_err(|_| {
                format!("step `{text}`: expected a face count, as in `simplify-faces:1000`")
            }),
            "catmull-clark" => levels().map(Step::CatmullClark),
            "triangulate" => Ok(Step::Triangulate),
            "flip" => pair().map(|(a, b)| Step::Flip(a, b)),
            "split" => pair().map(|(a, b)| Step::Split(a, b)),
            "collapse" => pair().map(|(a, b)| Step::Collapse(a, b)),
            "dissolve" => pair().map(|(a, b)| Step::Dissolve(a, b)),
            "split-face" => pair().map(|(a, b)| Step::SplitFace(a, b)),
            _ => Err(format!("unknown step `{text}` (see `pappus --help`)")),
        }
    }
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Step::Validate => write!(f, "validate"),
            Step::Triangulate => write!(f, "triangulate"),
            Step::Flip(a, b) => write!(f, "flip:{a},{b}"),
            Step::Split(a, b) => write!(f, "split:{a},{b}"),
            Step::Collapse(a, b) => write!(f, "collapse:{a},{b}"),
            Step::Dissolve(a, b) => write!(f, "dissolve:{a},{b}"),
            Step::SplitFace(a, b) => write!(f, "split-face:{a},{b}"),
            Step::Simplify(r) => write!(f, "simplify:{r}"),
            Step::SimplifyFaces(n) => write!(f, "simplify-faces:{n}"),
            Step::Remesh(n, None) => write!(f, "remesh:{n}"),
            Step::Remesh(n, Some(l)) => write!(f, "remesh:{n}:{l}"),
            Step::Refine(None) => write!(f, "refine"),
            Step::Refine(Some(n)) => write!(f, "refine:{n}"),
            Step::Loop(n) => write!(f, "loop:{n}"),
            Step::CatmullClark(n) => write!(f, "catmull-clark:{n}"),
        }
    }
}

/// Parses the arguments (without the program name).
///
/// # Errors
/// A usage message.
pub fn parse_args<I: IntoIterator<Item = String>>(args: I) -> Result<Command, String> {
    let args: Vec<String> = args.into_iter().collect();
    let Some(first) = args.first() else {
        return Ok(Command::Editor(None));
    };
    let rest = &args[1..];
    let json = rest.iter().any(|a| a == "--json");
    let positional: Vec<&String> = rest.iter().filter(|a| *a != "--json").collect();
    match first.as_str() {
        "-h" | "--help" | "help" => Ok(Command::Help),
        "-V" | "--version" => Ok(Command::Version),
        "info" => match positional.as_slice() {
            [input] => Ok(Command::Info {
                input: input.to_string(),
                json,
            }),
            _ => Err("usage: pappus info FILE [--json]".into()),
        },
        "convert" => match positional.as_slice() {
            [input, output] => Ok(Command::Convert {
                input: input.to_string(),
                output: PathBuf::from(output),
            }),
            _ => Err("usage: pappus convert IN OUT".into()),
        },
        "process" => parse_process(&positional, json),
        other if other.starts_with('-') => Err(format!("unknown option `{other}`\n\n{USAGE}")),
        _ if rest.is_empty() => Ok(Command::Editor(Some(PathBuf::from(first)))),
        _ => Err(format!("unexpected arguments after `{first}`\n\n{USAGE}")),
    }
}

fn parse_process(args: &[&String], json: bool) -> Result<Command, String> {
    const USE: &str = "usage: pappus process IN -o OUT [--json] STEP...";
    let mut input = None;
    let mut output = None;
    let mut steps = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "-o" | "--output" => {
                output = Some(PathBuf::from(args.get(i + 1).ok_or(USE)?.as_str()));
                i += 1;
            }
            _ if input.is_none() => input = Some(args[i].to_string()),
            step => steps.push(Step::parse(step)?),
        }
        i += 1;
    }
    match (input, output) {
        (Some(input), Some(output)) => Ok(Command::Process {
            input,
            output,
            steps,
            json,
        }),
        _ => Err(USE.into()),
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

/// The outcome of one step.
#[derive(Clone, Debug, PartialEq)]
pub enum StepOutcome {
    /// Carried out; the text summarises what changed.
    Applied(String),
    /// Not carried out; the mesh is unchanged.
    Refused(Refusal),
}

/// Runs one step on a loaded mesh. `input_vertices` maps the input file's vertex numbers to
/// vertices (see [`BuiltMesh::input_vertices`]).
pub fn run_step(
    world: &mut World,
    mesh: MeshId,
    input_vertices: &[Option<VertexId>],
    history: &mut Option<ProgressiveMesh>,
    step: &Step,
) -> StepOutcome {
    let edge = |a: u32, b: u32| input_edge(world, input_vertices, a, b);
    match step {
        Step::Validate => match validate(world, mesh) {
            Ok(()) => StepOutcome::Applied("valid".into()),
            Err(e) => StepOutcome::Refused(Refusal::Unsuitable(format!("invalid: {e}"))),
        },
        Step::Triangulate => {
            let s = triangulate::triangulate(world, mesh);
            StepOutcome::Applied(format!(
                "{} polygon(s) cut, {} face(s) added",
                s.polygons, s.added_faces
            ))
        }
        Step::Flip(a, b) => match edge(*a, *b).and_then(|e| flip_edge(world, e)) {
            Ok(e) => StepOutcome::Applied(format!("new edge {e}")),
            Err(r) => StepOutcome::Refused(r),
        },
        Step::Split(a, b) => match edge(*a, *b).and_then(|e| split_edge(world, e, 0.5)) {
            Ok(v) => StepOutcome::Applied(format!("new vertex {v}")),
            Err(r) => StepOutcome::Refused(r),
        },
        Step::Dissolve(a, b) => match edge(*a, *b).and_then(|e| dissolve_edge(world, e)) {
            Ok(f) => StepOutcome::Applied(format!("merged into {f}")),
            Err(r) => StepOutcome::Refused(r),
        },
        Step::SplitFace(a, b) => match split_common_face(world, input_vertices, *a, *b) {
            Ok(e) => StepOutcome::Applied(format!("new edge {e}")),
            Err(r) => StepOutcome::Refused(r),
        },
        Step::Simplify(_) | Step::SimplifyFaces(_) => {
            let faces = crate::mesh::MeshMembers::collect(world, mesh).faces.len();
            let params = match step {
                Step::Simplify(r) => SimplifyParams::ratio(faces, *r),
                Step::SimplifyFaces(n) => SimplifyParams::faces(*n),
                _ => unreachable!("matched above"),
            };
            match ProgressiveMesh::simplify(world, mesh, &params) {
                Ok((pm, s)) => {
                    *history = Some(pm);
                    StepOutcome::Applied(format!(
                        "{} → {} faces in {} collapses{}",
                        s.faces_before,
                        s.faces_after,
                        s.collapses,
                        if s.reached_target {
                            ""
                        } else {
                            " (no legal collapse left before the target)"
                        }
                    ))
                }
                Err(r) => StepOutcome::Refused(r),
            }
        }
        Step::Remesh(iterations, length) => {
            let params = RemeshParams {
                target_length: *length,
                iterations: *iterations,
                ..RemeshParams::default()
            };
            match remesh(world, mesh, &params) {
                Ok(s) => StepOutcome::Applied(format!(
                    "L {:.5}: {} splits, {} collapses, {} flips",
                    s.target_length, s.splits, s.collapses, s.flips
                )),
                Err(r) => StepOutcome::Refused(r),
            }
        }
        Step::Refine(target) => {
            let Some(pm) = history.as_mut() else {
                return StepOutcome::Refused(Refusal::Unsuitable(
                    "nothing to refine: no simplify step before this one".into(),
                ));
            };
            match pm.go_to_faces(world, target.unwrap_or(usize::MAX)) {
                Ok(n) => StepOutcome::Applied(format!("{n} vertex splits, {} faces", pm.faces())),
                Err(r) => StepOutcome::Refused(r),
            }
        }
        Step::Loop(n) => subdivided(loop_subdivide(world, mesh, *n)),
        Step::CatmullClark(n) => subdivided(catmull_clark(world, mesh, *n)),
        Step::Collapse(a, b) => {
            match edge(*a, *b).and_then(|e| collapse_edge(world, e, CollapseOptions::default())) {
                Ok(r) => StepOutcome::Applied(format!("kept {}, removed {}", r.kept, r.removed)),
                Err(r) => StepOutcome::Refused(r),
            }
        }
    }
}

fn subdivided(result: Result<SubdivisionSummary, Refusal>) -> StepOutcome {
    match result {
        Ok(s) => StepOutcome::Applied(format!(
            "{} level(s): {} vertices, {} faces",
            s.levels, s.vertices, s.faces
        )),
        Err(r) => StepOutcome::Refused(r),
    }
}

/// Splits the face that the input file's vertices `a` and `b` share, between them.
fn split_common_face(
    world: &mut World,
    input_vertices: &[Option<VertexId>],
    a: u32,
    b: u32,
) -> Result<EdgeId, Refusal> {
    let (va, vb) = input_pair(world, input_vertices, a, b)?;
    let m = MeshRef::new(world);
    let face = m
        .vertex_faces(va)
        .find(|&f| m.face_vertices(f).any(|v| v == vb))
        .ok_or_else(|| Refusal::Unsuitable(format!("input vertices {a} and {b} share no face")))?;
    split_face(world, face, va, vb)
}

/// The live vertices the input file's vertices `a` and `b` became.
fn input_pair(
    world: &World,
    input_vertices: &[Option<VertexId>],
    a: u32,
    b: u32,
) -> Result<(VertexId, VertexId), Refusal> {
    Ok((
        input_vertex(world, input_vertices, a)?,
        input_vertex(world, input_vertices, b)?,
    ))
}

/// The live vertex the input file's vertex `i` became.
fn input_vertex(
    world: &World,
    input_vertices: &[Option<VertexId>],
    i: u32,
) -> Result<VertexId, Refusal> {
    let v = input_vertices
        .get(i as usize)
        .copied()
        .flatten()
        .ok_or_else(|| Refusal::Unsuitable(format!("the input has no vertex {i}")))?;
    MeshRef::new(world)
        .try_vertex(v)
        .map(|_| v)
        .ok_or(Refusal::Stale(ElementId::Vertex(v)))
}

/// The edge between the input file's vertices `a` and `b`.
fn input_edge(
    world: &World,
    input_vertices: &[Option<VertexId>],
    a: u32,
    b: u32,
) -> Result<EdgeId, Refusal> {
    let (va, vb) = input_pair(world, input_vertices, a, b)?;
    let m = MeshRef::new(world);
    m.find_halfedge(va, vb)
        .map(|h| m.edge(h))
        .ok_or_else(|| Refusal::Unsuitable(format!("input vertices {a} and {b} share no edge")))
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
        Command::Help => out!("{USAGE}"),
        Command::Version => outln!("pappus {}", env!("CARGO_PKG_VERSION")),
        Command::Editor(_) => return Err("the editor is started by main".into()),
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
                let outcome = run_step(
                    &mut loaded.world,
                    mesh,
                    &loaded.built.input_vertices,
                    &mut history,
                    step,
                );
                let ms = round(ms_since(start), 3);
                let mut record = Map::new();
                record.insert("step".into(), json!(step.to_string()));
                match &outcome {
                    StepOutcome::Applied(summary) => {
                        record.insert("outcome".into(), json!("applied"));
                        record.insert("summary".into(), json!(summary));
                        if !json {
                            outln!("{step}: applied ({summary}) in {ms} ms");
                        }
                    }
                    StepOutcome::Refused(reason) => {
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

    fn args(text: &str) -> Vec<String> {
        text.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn parses_every_command() {
        assert_eq!(parse_args(args("")), Ok(Command::Editor(None)));
        assert_eq!(
            parse_args(args("bunny.obj")),
            Ok(Command::Editor(Some("bunny.obj".into())))
        );
        assert_eq!(
            parse_args(args("info a.off --json")),
            Ok(Command::Info {
                input: "a.off".into(),
                json: true
            })
        );
        assert_eq!(
            parse_args(args("process a.obj -o b.ply triangulate validate --json")),
            Ok(Command::Process {
                input: "a.obj".into(),
                output: "b.ply".into(),
                steps: vec![Step::Triangulate, Step::Validate],
                json: true,
            })
        );
        assert!(parse_args(args("process a.obj triangulate")).is_err());
        assert!(parse_args(args("process a.obj -o b.obj frobnicate")).is_err());
        assert!(parse_args(args("info")).is_err());
        assert!(parse_args(args("--bogus")).is_err());
    }
}
