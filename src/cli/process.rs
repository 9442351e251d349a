//! `process` on one input: the steps run in order, the result checked against what the
//! output format holds and written, with the per-vertex quantity and normals asked for.

use bevy::prelude::World;
use serde_json::{Map, Value, json};
use std::path::Path;
use std::time::Instant;

use crate::colormap::Range;
use crate::edit::Step;
use crate::io;
use crate::mesh::attributes::MeshAttributes;
use crate::mesh::ids::VertexId;
use crate::mesh::tables::{EntityRows, VertexRow, extract};
use crate::mesh::{MeshId, PolygonSoup, to_soup};
use crate::ops::geometry::closest::Reference;
use crate::ops::geometry::quantity::{Given, Needs};
use crate::ops::geometry::{NormalWeighting, Quantity, Surface, vertex_normals};

use super::loading::load_for;
use super::report::ms_since;
use super::report::{info_json, info_text, round};

/// What `process` does to each input: the steps and the output options.
#[derive(Clone, Debug)]
pub(super) struct ProcessJob {
    /// The steps, in order.
    pub(super) steps: Vec<Step>,
    /// JSON instead of text.
    pub(super) json: bool,
    /// A per-vertex quantity to write into the output.
    pub(super) quantity: Option<QuantityArg>,
    /// Vertex normals to write into the output.
    pub(super) normals: Option<NormalWeighting>,
}

/// Checks that `output`'s format can hold what `job` writes beside the mesh.
///
/// # Errors
/// A format Pappus does not write, `--normals` into a format without normals, `--quantity`
/// into anything but PLY.
pub(super) fn check_output(job: &ProcessJob, output: &Path) -> Result<(), String> {
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
pub(super) fn process_file(
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
    let (json, normals) = (*json, *normals);
    let mut loaded = load_for(input, steps)?;
    let mesh = loaded.built.mesh;
    // The distance quantity measures how far the steps moved the mesh from the input.
    let reference = quantity
        .as_ref()
        .filter(|q| q.quantity.needs() == Needs::Other)
        .map(|_| Reference::of_tables(&extract(&loaded.world, mesh).tables));
    let mut records = Vec::new();
    for step in steps {
        let start = Instant::now();
        let had = MeshAttributes::of(&loaded.world, mesh);
        let outcome = step.run(&mut loaded.world, mesh, &loaded.built.input_vertices);
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
    let quantity = match quantity {
        Some(q) => {
            let sources = q.source_vertices(&loaded.built.input_vertices)?;
            let given = (reference.as_ref(), sources.as_slice());
            Some(attach_quantity(
                &loaded.world,
                mesh,
                q.quantity,
                given,
                &mut soup,
            )?)
        }
        None => None,
    };
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
pub(super) fn write_mesh(
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
pub(super) fn parse_weighting(name: &str) -> Result<NormalWeighting, String> {
    match name {
        "angle" => Ok(NormalWeighting::Angle),
        "area" => Ok(NormalWeighting::Area),
        _ => Err(format!("unknown weighting `{name}`; known: angle, area")),
    }
}

/// A `--quantity` as given: the quantity, and the input's vertex numbers it starts from.
#[derive(Clone, Debug, PartialEq)]
pub struct QuantityArg {
    /// The registered quantity.
    pub quantity: Quantity,
    /// The input's vertex numbers a quantity from sources starts at (`geodesic:0/12`).
    pub sources: Vec<u32>,
}

impl QuantityArg {
    /// The source vertices as the mesh has them now, by entity.
    ///
    /// # Errors
    /// A number the input lacks, or a vertex the steps removed.
    fn source_vertices(&self, input: &[Option<VertexId>]) -> Result<Vec<VertexId>, String> {
        self.sources
            .iter()
            .map(|&i| {
                input.get(i as usize).copied().flatten().ok_or_else(|| {
                    format!(
                        "--quantity {}: the input has no vertex {i}",
                        self.quantity.name()
                    )
                })
            })
            .collect()
    }
}

/// Parses a `--quantity`: a registered quantity's name, then, for one that starts from
/// vertices, their numbers in the input (`geodesic:0/12`).
pub(super) fn parse_quantity(text: &str) -> Result<QuantityArg, String> {
    let (name, sources) = text.split_once(':').unwrap_or((text, ""));
    let quantity = crate::ops::registry::quantity(name).ok_or_else(|| {
        let names: Vec<&str> = crate::ops::registry::quantities()
            .iter()
            .map(|q| q.name())
            .collect();
        format!("unknown quantity `{name}`; known: {}", names.join(", "))
    })?;
    let sources: Vec<u32> = match sources {
        "" => Vec::new(),
        list => list
            .split('/')
            .map(|n| {
                n.parse()
                    .map_err(|_| format!("`{n}` is not a vertex number"))
            })
            .collect::<Result<_, _>>()?,
    };
    match (quantity.needs() == Needs::Sources, sources.is_empty()) {
        (true, true) => Err(format!(
            "{name} starts from vertices: give their numbers, {name}:A/B"
        )),
        (false, false) => Err(format!("{name} takes no vertices")),
        _ => Ok(QuantityArg { quantity, sources }),
    }
}

/// Computes `quantity` on `mesh` (a distance to `input`) and puts it into `soup` (whose vertices
/// are the mesh's table rows, as [`to_soup`] writes them) as quality and colours. Returns its
/// JSON summary.
fn attach_quantity(
    world: &World,
    mesh: MeshId,
    quantity: Quantity,
    (input, sources): (Option<&Reference>, &[VertexId]),
    soup: &mut crate::mesh::PolygonSoup,
) -> Result<Map<String, Value>, String> {
    let start = Instant::now();
    let read = extract(world, mesh);
    let rows = EntityRows::new(&read.members);
    let sources: Vec<VertexRow> = sources
        .iter()
        .map(|v| {
            rows.row(v.0).map(VertexRow::new).ok_or_else(|| {
                format!(
                    "--quantity {}: the steps removed source {v}",
                    quantity.name()
                )
            })
        })
        .collect::<Result<_, _>>()?;
    let given = Given {
        other: input,
        sources: &sources,
        vertices: &read.members.vertices,
        faces: &read.members.faces,
    };
    let values = quantity.per_vertex(&read.tables, &given);
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
    Ok(out)
}
