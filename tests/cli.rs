//! The command line as scripts use it: exit codes, JSON keys, steps, errors on stderr.

mod common;

use serde_json::{Value, json};
use std::path::PathBuf;
use std::process::{Command, Output};

fn pappus(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pappus"))
        .args(args)
        .output()
        .expect("runs pappus")
}

fn json(output: &Output) -> Value {
    assert!(
        output.status.success(),
        "failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("stdout is one JSON object")
}

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs `pappus process INPUT -o <tmp OUT> --json ARGS…` and returns its JSON and the output
/// path.
fn process_json(input: &str, out: &str, args: &[&str]) -> (Value, PathBuf) {
    let out_path = tmp(out);
    let mut all = vec!["process", input, "-o", out_path.to_str().unwrap(), "--json"];
    all.extend_from_slice(args);
    (json(&pappus(&all)), out_path)
}

const INFO_KEYS: [&str; 18] = [
    "vertices",
    "edges",
    "faces",
    "halfedges",
    "boundary_loops",
    "components",
    "euler_characteristic",
    "genus",
    "manifold",
    "closed",
    "face_sizes",
    "valid",
    "repairs",
    "min_angle_deg",
    "pct_min_angle_below_30",
    "bbox_diag",
    "load_ms",
    "mean_edge_length",
];

#[test]
fn info_json_has_every_key_and_exact_figures() {
    let v = json(&pappus(&["info", "shape:double-torus", "--json"]));
    for key in INFO_KEYS {
        assert!(v.get(key).is_some(), "missing key {key}: {v}");
    }
    assert_eq!(v["euler_characteristic"], -2);
    assert_eq!(v["genus"], 2);
    assert_eq!(v["closed"], true);
    assert_eq!(v["valid"], true);
    assert_eq!(v["manifold"], true);
    assert_eq!(v["face_sizes"]["4"], 50);
    assert_eq!(v["repairs"]["unreferenced_vertices"], 0);
    // Gauss–Bonnet: the angle defects add up to 2πχ = −4π.
    let total = v["curvature"]["total_angle_defect"].as_f64().unwrap();
    assert!((total + 4.0 * std::f64::consts::PI).abs() < 1e-9, "{total}");
    assert_eq!(v["curvature"]["two_pi_chi"], -4.0 * std::f64::consts::PI);
    assert_eq!(v["normals"]["degenerate_faces"], 0);
    let v = json(&pappus(&["info", "shape:grid", "--json"]));
    assert_eq!(
        (v["vertices"].as_u64(), v["faces"].as_u64()),
        (Some(121), Some(200))
    );
    assert_eq!(v["boundary_loops"], 1);
    assert_eq!(v["euler_characteristic"], 1);
}

#[test]
fn info_text_is_readable() {
    let out = pappus(&["info", "shape:cube"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("V 8  E 12  F 6"), "{text}");
    assert!(text.contains("valid"), "{text}");
}

#[test]
fn errors_go_to_stderr_with_a_nonzero_exit() {
    let out = pappus(&["info", "/no/such/file.obj"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/no/such/file.obj"));
    assert!(out.stdout.is_empty());
    // An unknown shape is a usage error, found before anything is read.
    let out = pappus(&["info", "shape:klein-bottle"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown shape"));
    let out = pappus(&["process", "shape:cube", "-o", "x.obj", "frobnicate"]);
    assert_eq!(out.status.code(), Some(2));
    let out = pappus(&["info", "notes.txt"]);
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn broken_files_are_reported_not_panicked_on() {
    for (name, bytes) in [
        ("garbage.obj", &b"v 1 2\nf 1 2 3 4 5\n\x00\xff"[..]),
        (
            "truncated.ply",
            &b"ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"[..],
        ),
        ("empty.off", &b""[..]),
        ("short.stl", &b"\x00\x01"[..]),
    ] {
        let path = tmp(name);
        std::fs::write(&path, bytes).unwrap();
        let out = pappus(&["info", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert!(
            stderr.contains(name),
            "{name}: the message names the file: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    }
}

#[test]
fn a_keyhole_opens_as_its_ring_and_a_gltf_1_file_is_refused_by_name() {
    // A 4 × 4 square with a 2 × 2 hole, one polygon through a bridge, as CAD exporters write.
    let keyhole = tmp("keyhole.obj");
    std::fs::write(
        &keyhole,
        "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 1 0\nv 3 1 0\nv 3 3 0\nv 1 3 0\n\
         f 1 2 3 4 1 5 8 7 6 5\n",
    )
    .unwrap();
    let v = json(&pappus(&["info", "--json", keyhole.to_str().unwrap()]));
    assert_eq!(v["repairs"]["untangled_faces"], 1);
    assert_eq!(
        (
            &v["faces"],
            &v["vertices"],
            &v["boundary_loops"],
            &v["valid"]
        ),
        (&json!(8), &json!(8), &json!(2), &json!(true))
    );
    let old = tmp("old.gltf");
    std::fs::write(
        &old,
        r#"{"asset": {"version": "1.0"}, "meshes": {"m": {"primitives": []}}}"#,
    )
    .unwrap();
    let out = pappus(&["info", old.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("old.gltf")
            && stderr.contains("glTF 1.0 is not supported: re-export as glTF 2.0"),
        "{stderr}"
    );
}

#[test]
fn process_runs_steps_in_order_and_reports_json() {
    let (v, out_path) = process_json(
        "shape:cube",
        "cube-tri.off",
        &["validate", "triangulate", "validate"],
    );
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    assert_eq!(steps[1]["step"], "triangulate");
    assert!(
        steps
            .iter()
            .all(|s| s["outcome"] == "applied" && s["ms"].is_number())
    );
    assert_eq!(v["result"]["faces"], 12);
    assert_eq!(v["result"]["face_sizes"]["3"], 12);
    // The written file reads back as the same mesh.
    let back = json(&pappus(&["info", out_path.to_str().unwrap(), "--json"]));
    assert_eq!(back["faces"], 12);
    assert_eq!(back["euler_characteristic"], 2);
}

#[test]
fn a_refused_step_is_reported_and_the_run_goes_on() {
    let out_path = tmp("tet.obj");
    // Every edge of a tetrahedron refuses a flip (the new edge exists already).
    let v = json(&pappus(&[
        "process",
        "shape:tetrahedron",
        "-o",
        out_path.to_str().unwrap(),
        "--json",
        "flip:0,1",
        "flip:0,9",
        "validate",
    ]));
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps[0]["outcome"], "refused");
    assert!(steps[0]["reason"].as_str().unwrap().len() > 5);
    assert_eq!(steps[1]["outcome"], "refused");
    assert!(steps[1]["reason"].as_str().unwrap().contains("no vertex 9"));
    assert_eq!(steps[2]["outcome"], "applied");
    assert_eq!(v["result"]["faces"], 4);
}

#[test]
fn local_steps_name_edges_by_input_vertices() {
    let (v, _) = process_json(
        "shape:icosahedron",
        "ico.ply",
        &[
            "split:0,11",
            "flip:0,5",
            "collapse:1,5",
            "bisect:2,3",
            "validate",
        ],
    );
    let steps = v["steps"].as_array().unwrap();
    for s in steps {
        assert_eq!(s["outcome"], "applied", "{s}");
    }
    // split: V+1 F+2; flip: same; collapse: V-1 F-2; bisect: V+1, two triangles become quads.
    assert_eq!(v["result"]["vertices"], 13);
    assert_eq!(v["result"]["faces"], 20);
    assert_eq!(v["result"]["face_sizes"]["4"], 2);
    assert_eq!(v["result"]["euler_characteristic"], 2);
}

#[test]
fn modelling_steps_name_vertices_edges_and_faces_by_input_vertices() {
    // The cube's input: faces 0 3 2 1 (−z), 4 5 6 7 (+z), 0 1 5 4 (−y), 2 3 7 6 (+y), … .
    let (v, out) = process_json(
        "shape:cube",
        "modelled.obj",
        &[
            "extrude:4,5,6:0.5", // the +z face rises 0.5: V 12, E 20, F 10
            "inset:0,3,2:0.25",  // the −z face gets a ring: V 16, E 28, F 14
            "bevel:1",           // the corner (1,−1,−1): V 18, E 31, F 15
            "bevel:2,3",         // the −z/+y edge 2–3: its ends have 4 edges each
            "erase:0,4,7",       // the −x face (three consecutive corners) becomes a hole
            "collapse:4,5,6",    // refused: the top is made of new vertices now
            "validate",
        ],
    );
    let steps = v["steps"].as_array().unwrap();
    let outcomes: Vec<&str> = steps
        .iter()
        .map(|s| s["outcome"].as_str().unwrap())
        .collect();
    assert_eq!(
        outcomes,
        [
            "applied", "applied", "applied", "applied", "applied", "refused", "applied"
        ],
        "{steps:?}"
    );
    assert_eq!(steps[0]["summary"], "1 face lifted on 4 side faces");
    assert!(
        steps[5]["reason"]
            .as_str()
            .unwrap()
            .contains("share no face"),
        "{steps:?}"
    );
    assert_eq!(v["result"]["boundary_loops"], 1);
    assert_eq!(v["result"]["valid"], true);
    // The extruded top sits at z = 1.5.
    let text = std::fs::read_to_string(out).unwrap();
    assert_eq!(
        text.lines()
            .filter(|l| l.starts_with("v ") && l.ends_with(" 1.5"))
            .count(),
        4
    );
    // Arity mistakes are usage errors, named.
    let bad = pappus(&["process", "shape:cube", "-o", "/dev/null", "weld:0,1"]);
    assert_eq!(bad.status.code(), Some(2));
    let said = String::from_utf8_lossy(&bad.stderr);
    assert!(
        said.contains("weld names two edges; expected weld:A,B/C,D"),
        "{said}"
    );
}

#[test]
fn weld_and_dissolve_steps_on_open_strips() {
    // A 3 × 1 strip of quads (vertices 0–3 along the bottom, 4–7 along the top): welding its
    // two end edges closes it into a tube of three quads with two boundary loops.
    let (v, _) = process_json(
        "shape:quad-grid:3:1",
        "tube.obj",
        &["weld:0,4/3,7", "validate"],
    );
    assert_eq!(v["steps"][0]["outcome"], "applied", "{v}");
    let r = &v["result"];
    assert_eq!(
        (
            &r["vertices"],
            &r["edges"],
            &r["faces"],
            &r["boundary_loops"]
        ),
        (&6.into(), &9.into(), &3.into(), &2.into())
    );
    assert_eq!(r["euler_characteristic"], 0);
    // On a 2 × 1 strip the same weld would join the two quads along two edges: refused.
    let (v, _) = process_json("shape:quad-grid:2:1", "short.obj", &["weld:0,3/2,5"]);
    assert_eq!(v["steps"][0]["outcome"], "refused");
    assert!(
        v["steps"][0]["reason"]
            .as_str()
            .unwrap()
            .contains("duplicate"),
        "{v}"
    );
    // Dissolving the border vertex between the two quads leaves one pentagon.
    let (v, _) = process_json(
        "shape:quad-grid:2:1",
        "merged.obj",
        &["dissolve:1", "validate"],
    );
    assert_eq!(v["steps"][0]["outcome"], "applied", "{v}");
    assert_eq!(v["result"]["face_sizes"]["5"], 1);
    assert_eq!(v["result"]["vertices"], 5);
}

#[test]
fn convert_round_trips_between_formats() {
    let mut previous = None;
    for ext in ["obj", "off", "ply", "stl"] {
        let path = tmp(&format!("torus.{ext}"));
        let out = pappus(&["convert", "shape:icosphere", path.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v = json(&pappus(&["info", path.to_str().unwrap(), "--json"]));
        let figures = (
            v["vertices"].clone(),
            v["faces"].clone(),
            v["euler_characteristic"].clone(),
        );
        if let Some(p) = &previous {
            assert_eq!(&figures, p, "{ext}");
        }
        previous = Some(figures);
    }
}

#[test]
fn simplify_then_refine_gives_back_the_input() {
    let (v, _) = process_json(
        "shape:icosphere:3",
        "refined.ply",
        &["refine", "simplify:0.1", "refine:640", "refine", "validate"],
    );
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(
        steps[0]["outcome"], "refused",
        "no history yet: {}",
        steps[0]
    );
    assert!(steps[1..].iter().all(|s| s["outcome"] == "applied"), "{v}");
    assert!(
        steps[2]["summary"].as_str().unwrap().ends_with("640 faces"),
        "{}",
        steps[2]
    );
    assert_eq!(v["result"]["faces"], 1280);
    assert_eq!(v["result"]["euler_characteristic"], 2);
}

#[test]
fn a_quantity_is_exported_to_ply_and_summarised() {
    let (v, out_path) = process_json("shape:icosphere", "curvature.ply", &["--quantity", "mean"]);
    // The unit sphere's mean curvature is 1, within the discretisation's error.
    let q = &v["quantity"];
    assert_eq!(q["name"], "mean");
    for key in ["min", "max", "mean"] {
        assert!((q[key].as_f64().unwrap() - 1.0).abs() < 0.01, "{q}");
    }
    assert!(q["ms"].as_f64().unwrap() >= 0.0);
    // The PLY carries the value and its colour at every vertex.
    let soup = pappus::io::read(&out_path).unwrap();
    let quality = soup.vertex_quality.expect("quality written");
    assert_eq!(quality.len(), 642);
    assert!(quality.iter().all(|h| (h - 1.0).abs() < 0.01));
    assert_eq!(soup.vertex_colors.map(|c| c.len()), Some(642));
    // Opening that file says what the mesh does not keep, never silently.
    let out = pappus(&["info", out_path.to_str().unwrap()]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("vertex quality is not kept"), "{stderr}");
    assert!(!stderr.contains("colours is not kept"), "{stderr}");
    // Only PLY holds per-vertex quality: anything else is refused before any work.
    let out = pappus(&["process", "shape:cube", "-o", "x.obj", "--quantity", "mean"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("PLY"));
    let out = pappus(&[
        "process",
        "shape:cube",
        "-o",
        "x.ply",
        "--quantity",
        "wobble",
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn smooth_steps_run_every_method() {
    for method in ["uniform", "cotan", "implicit", "taubin"] {
        let step = format!("smooth:{method}:2");
        let (v, _) = process_json("shape:icosphere", "smooth.obj", &[&step, "validate"]);
        for s in v["steps"].as_array().unwrap() {
            assert_eq!(s["outcome"], "applied", "{s}");
        }
        assert_eq!(v["result"]["vertices"], 642);
    }
}

#[test]
fn vertex_normals_are_exported_on_request() {
    for (file, weighting) in [("normals.obj", "angle"), ("normals.ply", "area")] {
        let out_path = tmp(file);
        let out = pappus(&[
            "process",
            "shape:cube",
            "-o",
            out_path.to_str().unwrap(),
            "--normals",
            weighting,
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read(&out_path).unwrap();
        if file.ends_with(".obj") {
            let text = String::from_utf8(text).unwrap();
            assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 8);
        } else {
            // A cube's corner normal points along its diagonal, either way.
            let soup = pappus::io::read(&out_path).unwrap();
            for (p, n) in soup.positions.iter().zip(soup.vertex_normals.unwrap()) {
                assert!((n - p.normalize()).length() < 1e-6, "{n} at {p}");
            }
        }
    }
    let out = pappus(&["process", "shape:cube", "-o", "x.stl", "--normals", "angle"]);
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn the_distance_quantity_measures_how_far_the_steps_moved_the_mesh() {
    let (v, _) = process_json(
        "shape:icosphere",
        "distance.ply",
        &["--quantity", "distance", "simplify:0.25"],
    );
    let q = &v["quantity"];
    let (min, max) = (q["min"].as_f64().unwrap(), q["max"].as_f64().unwrap());
    assert!(min >= 0.0 && max > 1e-4 && max < 0.05, "{q}");
}

#[test]
fn the_geodesic_quantity_starts_from_the_input_vertices_named() {
    // On the unit sphere the farthest point is half a great circle, π, from any vertex; the
    // source survives a subdivision (Loop keeps the vertices' ids).
    let (v, out_path) = process_json(
        "shape:icosphere",
        "geodesic.ply",
        &["--quantity", "geodesic:0", "loop"],
    );
    let q = &v["quantity"];
    assert_eq!(q["name"], "geodesic");
    let (min, max) = (q["min"].as_f64().unwrap(), q["max"].as_f64().unwrap());
    assert!(min.abs() < 1e-9, "{q}");
    assert!((max - std::f64::consts::PI).abs() < 0.05, "{q}");
    let quality = pappus::io::read(&out_path).unwrap().vertex_quality.unwrap();
    assert_eq!(quality.len(), 2562);
    // Two sources: half way between them at most.
    let (v, _) = process_json(
        "shape:icosphere",
        "geodesic.ply",
        &["--quantity", "geodesic:0/1"],
    );
    assert!(v["quantity"]["max"].as_f64().unwrap() < std::f64::consts::PI);
    // Without its vertices, or with a number the input lacks, it is refused.
    for (quantity, code) in [("geodesic", 2), ("geodesic:x", 2), ("geodesic:9999", 1)] {
        let out = pappus(&[
            "process",
            "shape:icosphere",
            "-o",
            tmp("x.ply").to_str().unwrap(),
            "--quantity",
            quantity,
        ]);
        assert_eq!(out.status.code(), Some(code), "{quantity}");
    }
}

#[test]
fn fill_hole_closes_a_grid_through_its_step() {
    // The grid's corner 0 and its neighbour 1 are on its border.
    let (v, _) = process_json("shape:grid:3", "filled.obj", &["fill-hole:0,1", "validate"]);
    for s in v["steps"].as_array().unwrap() {
        assert_eq!(s["outcome"], "applied", "{s}");
    }
    assert_eq!(v["result"]["closed"], true);
    assert_eq!(v["result"]["faces"], 19);
    assert_eq!(v["result"]["face_sizes"]["12"], 1);
    // An interior edge has no hole beside it.
    let (v, _) = process_json("shape:icosahedron", "x.obj", &["fill-hole:0,11"]);
    assert_eq!(v["steps"][0]["outcome"], "refused");
    assert!(
        v["steps"][0]["reason"]
            .as_str()
            .unwrap()
            .contains("not on the boundary")
    );
}

/// A quad and a triangle with UVs (a seam at vertex 4), normals and colours.
const ATTRIBUTED: &str = "v 0 0 0 0.2 0.4 1\nv 1 0 0 0 0 0\nv 1 1 0 1 1 1\nv 0 1 0 0.5 0.1 0.9\nv 0.5 2 0 0.3 0.3 0.3\n\
vt -0 0.33333334\nvt 1 1e-7\nvt 1 1\nvt 0 1\nvt 2.5 -3\nvt 0.25 0.75\n\
vn 0 0 1\nvn -0 0.6 0.8\nvn 1e-20 0 -1\nvn 0.5773503 0.5773503 0.5773503\nvn 0 0 2\n\
f 1/1/1 2/2/2 3/3/3 4/4/4\nf 4/6/4 3/3/3 5/5/5\n";

#[test]
fn info_reports_attributes_and_files_keep_them() {
    let input = tmp("attributed.obj");
    std::fs::write(&input, ATTRIBUTED).unwrap();
    let out = pappus(&["info", input.to_str().unwrap(), "--json"]);
    assert!(
        !String::from_utf8_lossy(&out.stderr).contains("not kept"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json(&out);
    assert_eq!(
        v["attributes"],
        serde_json::json!({ "uv": true, "normals": true, "colors": true, "seams": false, "groups": false })
    );
    let v = json(&pappus(&["info", "shape:cube", "--json"]));
    assert_eq!(
        v["attributes"],
        serde_json::json!({ "uv": false, "normals": false, "colors": false, "seams": false, "groups": false })
    );
    // OBJ → PLY → OBJ keeps every value; saving over the file writes the same bytes again.
    let ply = tmp("attributed.ply");
    let back = tmp("attributed-back.obj");
    for (from, to) in [(&input, &ply), (&ply, &back)] {
        let out = pappus(&["convert", from.to_str().unwrap(), to.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let (a, b) = (
        pappus::io::read(&input).unwrap(),
        pappus::io::read(&back).unwrap(),
    );
    let bits = |s: &pappus::mesh::PolygonSoup| {
        let uv: Vec<[u32; 2]> = s
            .corner_uvs
            .as_ref()
            .unwrap()
            .iter()
            .map(|u| u.to_array().map(f32::to_bits))
            .collect();
        let n: Vec<[u32; 3]> = s
            .vertex_normals
            .as_ref()
            .unwrap()
            .iter()
            .map(|u| u.to_array().map(f32::to_bits))
            .collect();
        (uv, n, s.vertex_colors.clone())
    };
    assert_eq!(bits(&a), bits(&b));
    let first = std::fs::read(&back).unwrap();
    let out = pappus(&["convert", back.to_str().unwrap(), back.to_str().unwrap()]);
    assert!(out.status.success());
    assert_eq!(std::fs::read(&back).unwrap(), first);
}

#[test]
fn a_param_step_writes_uvs_and_reports_its_distortion() {
    // A closed genus-0 sphere is cut open automatically; a disk with holes gets them filled for
    // the solve; both come out with a UV at every corner.
    for (input, step) in [
        ("shape:icosphere", "param:lscm"),
        ("shape:grid-with-holes", "param:mean-value:square"),
        ("shape:quad-grid", "param:harmonic"),
    ] {
        let (v, out) = process_json(input, "param.obj", &[step, "validate"]);
        let steps = v["steps"].as_array().unwrap();
        assert_eq!(steps[0]["outcome"], "applied", "{step}: {}", steps[0]);
        let summary = steps[0]["summary"].as_str().unwrap();
        assert!(summary.contains("0 flipped of"), "{step}: {summary}");
        assert!(summary.contains("angle distortion"), "{step}: {summary}");
        assert_eq!(v["result"]["attributes"]["uv"], true, "{step}");
        let text = std::fs::read_to_string(&out).unwrap();
        let faces: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
        assert!(!faces.is_empty());
        assert!(
            faces
                .iter()
                .all(|f| f.split_whitespace().skip(1).all(|c| c.contains('/'))),
            "{step}: every corner names its vt"
        );
        for vt in text.lines().filter(|l| l.starts_with("vt ")) {
            let uv: Vec<f32> = vt[3..]
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            assert!(
                uv.iter().all(|x| (-1e-6..=1.0 + 1e-6).contains(x)),
                "{step}: {vt}"
            );
        }
    }
}

#[test]
fn a_torus_is_refused_a_layout_with_its_genus_named() {
    let (v, _) = process_json("shape:torus", "torus-param.obj", &["param:harmonic"]);
    let step = &v["steps"][0];
    assert_eq!(step["outcome"], "refused");
    let reason = step["reason"].as_str().unwrap();
    assert!(reason.contains("genus 1"), "{reason}");
    assert_eq!(v["result"]["attributes"]["uv"], false);
}

#[test]
fn seams_marked_by_steps_cut_the_layout() {
    // A closed sphere cut along marked seams instead of the automatic cut: the icosphere's
    // vertices 0-11 are the icosahedron's, and a path of marked edges from one to another
    // opens it into a disk. Marking an edge twice unmarks it.
    let path = ["seam:0,11", "seam:11,5", "seam:11,5", "seam:11,5"];
    let mut args: Vec<&str> = path.to_vec();
    args.push("param:mean-value");
    let (v, out) = process_json("shape:icosahedron", "seams.obj", &args);
    let steps = v["steps"].as_array().unwrap();
    for s in steps {
        assert_eq!(s["outcome"], "applied", "{s}");
    }
    assert!(
        steps[2]["summary"]
            .as_str()
            .unwrap()
            .contains("no longer a seam")
    );
    let summary = steps[4]["summary"].as_str().unwrap();
    assert!(summary.contains("cut along 2 edges"), "{summary}");
    assert!(summary.contains("0 flipped"), "{summary}");
    assert_eq!(v["result"]["attributes"]["seams"], true);
    // The three vertices on the cut have two UVs each except its two ends: 12 + 1 vt.
    let text = std::fs::read_to_string(out).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("vt ")).count(), 13);
}

/// A fresh empty folder under the test target dir.
fn fresh_dir(name: &str) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// stdout as one JSON object per line, sorted by `input`.
fn json_lines(output: &Output) -> Vec<Value> {
    let mut lines: Vec<Value> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line is one JSON object"))
        .collect();
    lines.sort_by_key(|v| v["input"].as_str().unwrap_or_default().to_string());
    lines
}

#[test]
fn several_inputs_write_one_output_each_by_the_stem_pattern() {
    let dir = fresh_dir("batch-shapes");
    let pattern = dir.join("out/{stem}.obj");
    let output = pappus(&[
        "process",
        "shape:cube",
        "shape:icosphere:2",
        "-o",
        pattern.to_str().unwrap(),
        "-j",
        "2",
        "--json",
        "triangulate",
        "loop",
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 2);
    for (line, (stem, faces)) in lines.iter().zip([("cube", 48), ("icosphere-2", 1280)]) {
        assert_eq!(line["input"], format!("shape:{}", stem.replace('-', ":")));
        let out = dir.join(format!("out/{stem}.obj"));
        assert_eq!(line["output"], out.to_str().unwrap());
        assert!(out.is_file());
        assert_eq!(line["result"]["faces"], faces, "{line}");
        assert_eq!(line["steps"].as_array().unwrap().len(), 2);
        assert!(line["ms"].as_f64().unwrap() > 0.0);
    }
}

#[test]
fn a_failed_input_is_reported_and_the_others_go_on() {
    let dir = fresh_dir("batch-failure");
    let good = dir.join("good.obj");
    let bad = dir.join("bad.obj");
    assert!(
        pappus(&["convert", "shape:icosahedron", good.to_str().unwrap()])
            .status
            .success()
    );
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n").unwrap();
    let nothing = dir.join("none/*.obj");
    let pattern = dir.join("out/{stem}.ply");
    let output = pappus(&[
        "process",
        bad.to_str().unwrap(),
        good.to_str().unwrap(),
        nothing.to_str().unwrap(),
        "-o",
        pattern.to_str().unwrap(),
        "--json",
        "simplify:0.5",
    ]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("bad.obj: line 4"), "{stderr}");
    assert!(stderr.contains("no file matches"), "{stderr}");
    assert!(stderr.contains("2 of 3 inputs failed"), "{stderr}");
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 3);
    let by_input = |path: &PathBuf| {
        lines
            .iter()
            .find(|l| l["input"] == path.to_str().unwrap())
            .unwrap()
    };
    assert!(by_input(&bad)["error"].as_str().unwrap().contains("line 4"));
    assert!(by_input(&nothing)["error"].is_string());
    assert_eq!(by_input(&good)["result"]["faces"], 10);
    assert!(dir.join("out/good.ply").is_file());
}

#[test]
fn a_glob_pattern_is_expanded_and_runs_on_worker_threads() {
    let dir = fresh_dir("batch-glob");
    for shape in ["cube", "torus", "icosphere"] {
        let path = dir.join(format!("in/{shape}.off"));
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        assert!(
            pappus(&["convert", &format!("shape:{shape}"), path.to_str().unwrap()])
                .status
                .success()
        );
    }
    std::fs::write(dir.join("in/notes.txt"), "not a mesh").unwrap();
    let inputs = dir.join("in/*.off");
    let pattern = dir.join("out/{stem}.stl");
    let output = pappus(&[
        "process",
        inputs.to_str().unwrap(),
        "-o",
        pattern.to_str().unwrap(),
        "-j",
        "3",
        "triangulate",
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8_lossy(&output.stdout);
    for shape in ["cube", "torus", "icosphere"] {
        assert!(dir.join(format!("out/{shape}.stl")).is_file());
        // Each input's report is printed whole, headed by the input and its time.
        let head = format!("{}: ", dir.join(format!("in/{shape}.off")).display());
        assert!(
            text.lines()
                .any(|l| l.starts_with(&head) && l.ends_with(" ms")),
            "{text}"
        );
    }
    assert_eq!(text.matches("triangulate: applied").count(), 3, "{text}");
}

#[test]
fn several_inputs_need_a_pattern_that_tells_their_outputs_apart() {
    let out = tmp("same.obj");
    let output = pappus(&[
        "process",
        "shape:cube",
        "shape:torus",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("{stem}"));
    let pattern = tmp("{stem}.obj");
    let twice = pappus(&[
        "process",
        "shape:cube",
        "shape:cube",
        "-o",
        pattern.to_str().unwrap(),
    ]);
    assert_eq!(twice.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&twice.stderr).contains("would both write"));
    let late = pappus(&[
        "process",
        "shape:cube",
        "-o",
        pattern.to_str().unwrap(),
        "triangulate",
        "shape:torus",
    ]);
    assert_eq!(late.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&late.stderr).contains("the inputs come first"));
}

/// Runs `pappus ARGS…` under `sh -c` with `limits` (ulimit commands) applied first.
fn pappus_limited(limits: &str, args: &[&str]) -> Output {
    let mut script = format!("{limits} && exec \"$0\"");
    for i in 1..=args.len() {
        script.push_str(&format!(" \"${i}\""));
    }
    Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_pappus"))
        .args(args)
        .output()
        .expect("runs pappus under sh")
}

/// Operations whose result's size follows from their parameters are refused before they start,
/// with the estimate and the budget, under an address-space limit that an attempt would exhaust
/// (4 GiB, as a user's `ulimit -v` might be): no abort; the step is reported refused with its
/// reason and the run goes on, as for any refused step.
#[test]
fn sizes_beyond_the_memory_are_refused_before_they_start() {
    let Some(bunny) = common::model("stanford-bunny.obj") else {
        return;
    };
    let bunny = bunny.to_str().unwrap();
    let out = tmp("never.off");
    let out = out.to_str().unwrap();
    for (step, what) in [
        (
            "loop:5",
            "Loop ×5 would make 71 M faces, about 49 GB; the budget is ",
        ),
        (
            "catmull-clark:7",
            "Catmull–Clark ×7 would make 853 M faces, about 778 GB; the budget is ",
        ),
        (
            "remesh:8:0.00001",
            "remeshing to edges of 0.00001 (8 iterations) would make 1319 M faces, about ",
        ),
    ] {
        let start = std::time::Instant::now();
        let output = pappus_limited("ulimit -v 4194304", &["process", bunny, "-o", out, step]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{step}: {stderr}");
        assert!(
            stdout.contains(&format!("{step}: refused: {what}")),
            "{stdout}"
        );
        assert!(stdout.contains("under the address-space limit"), "{stdout}");
        assert!(
            start.elapsed().as_secs() < 10,
            "{step} took {:?}",
            start.elapsed()
        );
    }
    // --max-memory sets the budget: a Loop ×1 of the bunny fits 2 GB, not 10 MB.
    let output = pappus(&["process", bunny, "-o", out, "--max-memory", "10M", "loop:1"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("the budget is 10 MB (the limit set): use fewer levels"),
        "{stdout}"
    );
    let output = pappus(&["process", bunny, "-o", out, "--max-memory", "2G", "loop:1"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success() && !stdout.contains("refused"),
        "{stdout}"
    );
    let output = pappus(&["info", "shape:cube", "--max-memory", "lots"]);
    assert_eq!(output.status.code(), Some(2));
}

/// Shape sizes are multiplied out in 64 bits and held to the budget before anything is made: a
/// usage error (exit 2) in well under a second, never a wrap or an abort.
#[test]
fn huge_shape_sizes_are_usage_errors() {
    for name in [
        "shape:grid:100000",
        "shape:torus:100000:100000",
        "shape:grid:10000",
    ] {
        let start = std::time::Instant::now();
        let output = pappus(&["info", name]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.starts_with("pappus: shape `"), "{stderr}");
        assert!(start.elapsed().as_secs() < 5);
    }
    let out = tmp("huge.off");
    let output = pappus(&["convert", "shape:grid:100000", out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(!out.exists());
}

/// A save past the file-size limit fails with the system's reason and leaves the old file
/// byte for byte and no temporary file; a save through a symbolic link replaces its target.
#[test]
fn a_failed_save_leaves_the_old_file_whole() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli-save");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("m.obj");
    let old = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(&path, old).unwrap();
    // 64 blocks of 512 bytes: far less than an icosphere of 5 levels takes as OBJ.
    let output = pappus_limited(
        "ulimit -f 64",
        &["convert", "shape:icosphere:5", path.to_str().unwrap()],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("not saved (File too large")
            && stderr.contains("the file on disk is as it was"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), old);
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["m.obj"], "no temporary file is left");
    // Through a link: the target changes, the link stays a link.
    std::os::unix::fs::symlink("m.obj", dir.join("link.obj")).unwrap();
    let output = pappus(&[
        "convert",
        "shape:cube",
        dir.join("link.obj").to_str().unwrap(),
    ]);
    assert!(output.status.success());
    assert!(
        std::fs::symlink_metadata(dir.join("link.obj"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(pappus::io::read(&path).unwrap().face_count(), 6, "the cube");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `pappus recover` lists the recoveries and writes one back; with none it says so.
#[test]
fn recover_lists_and_restores_recovery_files() {
    let state = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli-recover");
    let _ = std::fs::remove_dir_all(&state);
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_pappus"))
            .args(args)
            .env("XDG_STATE_HOME", &state)
            .output()
            .unwrap()
    };
    let output = run(&["recover", "--list"]);
    assert!(output.status.success());
    assert!(String::from_utf8_lossy(&output.stdout).starts_with("no recovery in "));
    let output = run(&["recover", "--latest", "-o", "x.obj"]);
    assert_eq!(output.status.code(), Some(1));
    let soup = pappus::mesh::shapes::torus(5, 3);
    let info = pappus::recovery::RecoveryInfo {
        source: None,
        name: "torus".into(),
        saved_at: pappus::recovery::now(),
        pid: u32::MAX,
        vertices: soup.positions.len(),
        faces: soup.face_count(),
    };
    let folder = state.join("pappus/recovery");
    pappus::recovery::write(&folder, "torus-1-2", &soup, &info).unwrap();
    let listed = json(&run(&["recover", "--list", "--json"]));
    assert_eq!(listed[0]["name"], "torus-1-2");
    assert_eq!(listed[0]["faces"], 15);
    assert_eq!(listed[0]["newer_than_source"], true);
    let out = state.join("back.off");
    let output = run(&["recover", "torus-1-2", "-o", out.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let back = pappus::io::read(&out).unwrap();
    assert_eq!(back.positions, soup.positions);
    assert_eq!(back.indices, soup.indices);
    let output = run(&["recover", "nothing-of-the-kind", "-o", "x.obj"]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("no recovery named"));
    std::fs::remove_dir_all(&state).unwrap();
}

/// A save into a format that cannot hold the mesh's UVs says so, on stderr and in `--json`;
/// COLLADA reads but is refused as an output before any work is done.
#[test]
fn saves_name_what_their_format_drops_and_dae_is_read_only() {
    let Some(beast) = common::model("beast.obj") else {
        return;
    };
    let beast = beast.to_str().unwrap();
    let off = tmp("beast-dropped.off");
    let out = pappus(&["convert", beast, off.to_str().unwrap()]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("beast-dropped.off: UVs dropped (OFF cannot hold it)"),
        "{stderr}"
    );
    let (report, _) = process_json(beast, "beast-dropped.stl", &["triangulate"]);
    assert_eq!(report["dropped"], serde_json::json!(["UVs"]));
    let (report, _) = process_json(beast, "beast-kept.ply", &["triangulate"]);
    assert_eq!(report["dropped"], serde_json::json!([]));
    let dae = tmp("out.dae");
    let out = pappus(&["process", beast, "-o", dae.to_str().unwrap(), "loop"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("reads this format but does not write it"),
        "{stderr}"
    );
    if let Some(cube) = common::model("course/cube.dae") {
        let info = json(&pappus(&["info", cube.to_str().unwrap(), "--json"]));
        assert_eq!(
            (info["vertices"].as_u64(), info["faces"].as_u64()),
            (Some(8), Some(12))
        );
    }
}
