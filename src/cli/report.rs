//! What `info` and `process` print: the statistics, validity and repair report of a mesh as
//! JSON or text, with its curvature summaries.

use bevy::prelude::World;
use serde_json::{Map, Value, json};

use crate::mesh::attributes::MeshAttributes;
use crate::mesh::tables::extract;
use crate::mesh::{MeshId, RepairReport, mesh_stats, validate};
use crate::ops::geometry::{Surface, face_normals, scalar_curvature};
use bevy::math::DVec3;

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

/// Milliseconds since `start`.
pub(super) fn ms_since(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1000.0
}

pub(super) fn round(x: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    (x * scale).round() / scale
}

pub(super) fn info_text(name: &str, object: &Map<String, Value>, report: &RepairReport) -> String {
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
