//! Parameterization times on disks (issue 22's targets: harmonic ≤ 40 ms, LSCM ≤ 110 ms on a
//! 45k-face disk cut from the bunny), for `benches/param_vs_peers.py` to print beside libigl and
//! MeshLab.
//!
//! Times [`pappus::ops::param::parameterize`] (cut, weights, boundary, sparse solve, distortion
//! report, per-corner output) on tables already extracted, the median of 7 runs, for every
//! method, on each OBJ named in `PAPPUS_PARAM_MESHES` (paths separated by `:`; default the
//! shared `bunny-disk.obj`). Prints one line per mesh and method, `PARAM_JSON {...}`, with the
//! median total and solve times and the report's figures. Run:
//! `PAPPUS_PARAM_MESHES=a.obj:b.obj cargo bench --bench param`.

use bevy::prelude::World;
use pappus::mesh::tables::extract;
use pappus::mesh::{MeshInfo, build_mesh};
use pappus::ops::named::Named;
use pappus::ops::param::{ParamMethod, ParamParams, parameterize};
use std::path::{Path, PathBuf};
use std::time::Instant;

const RUNS: usize = 7;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let meshes: Vec<PathBuf> = match std::env::var("PAPPUS_PARAM_MESHES") {
        Ok(list) => list.split(':').map(PathBuf::from).collect(),
        Err(_) => {
            vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/bunny-disk.obj")]
        }
    };
    for path in meshes {
        let soup = match pappus::io::read(&path) {
            Ok(soup) => soup,
            Err(e) => {
                println!("NOTICE: {}: {e}; skipped", path.display());
                continue;
            }
        };
        let mut world = World::new();
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).expect("builds");
        let start = Instant::now();
        let tables = extract(&world, built.mesh).tables;
        let extract_ms = start.elapsed().as_secs_f64() * 1e3;
        for &(method, name) in ParamMethod::ALL {
            let params = ParamParams::new(method);
            let mut total = Vec::with_capacity(RUNS);
            let mut solve = Vec::with_capacity(RUNS);
            let mut last = None;
            for _ in 0..RUNS {
                let start = Instant::now();
                let p = parameterize(&tables, &params).expect("parameterizes");
                total.push(start.elapsed().as_secs_f64() * 1e3);
                solve.push(p.report.solve_ms);
                last = Some(p.report);
            }
            let r = last.expect("ran");
            println!(
                "PARAM_JSON {{\"mesh\": \"{}\", \"method\": \"{name}\", \"faces\": {}, \
                 \"median_ms\": {:.3}, \"solve_ms\": {:.3}, \"extract_ms\": {extract_ms:.3}, \
                 \"flipped\": {}, \"angle_deg\": {:.4}, \"conformal\": {:.6}, \"solver\": \"{}\"}}",
                path.display(),
                tables.face_count(),
                median(total),
                median(solve),
                r.flipped,
                r.angle_distortion_deg,
                r.conformal_energy,
                r.solver.name()
            );
        }
    }
}
