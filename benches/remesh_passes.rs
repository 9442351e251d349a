//! Where isotropic remeshing's time goes: a [`RemeshRun`] made pass by pass on a model, each
//! pass timed, the times summed by pass kind (split, collapse, flip, relax, project, finish)
//! over the iterations, the median of several fresh runs. The start (reading the input
//! surface and the features) is timed as its own line.
//!
//! Run: `cargo bench --bench remesh_passes [MODEL] [RUNS]` (MODEL a path, by default the shared
//! bunny; RUNS 5). Each run remeshes a freshly built world with the command line's defaults:
//! 5 iterations, the mean edge length, features at 45°.

use bevy::prelude::World;
use pappus::mesh::{MeshInfo, build_mesh};
use pappus::ops::remesh::{Pass, RemeshParams, RemeshRun};
use std::path::PathBuf;
use std::time::Instant;

/// The kinds of time reported, in the order printed.
const LINES: [&str; 7] = [
    "start", "split", "collapse", "flip", "relax", "project", "finish",
];

/// The index of `pass` in [`LINES`].
fn line_of(pass: Pass) -> usize {
    match pass {
        Pass::Split => 1,
        Pass::Collapse => 2,
        Pass::Flip => 3,
        Pass::Relax => 4,
        Pass::Project => 5,
        Pass::Finish => 6,
    }
}

fn main() {
    // `cargo bench` passes `--bench`; the other arguments are ours.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let path = args.first().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj")
    });
    let runs: usize = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(5);
    let soup = pappus::io::read(&path).expect("the model reads");
    let params = RemeshParams::default();
    let mut times = vec![Vec::new(); LINES.len()];
    let mut totals = Vec::new();
    let mut faces = 0;
    for _ in 0..runs {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let mut this_run = [0.0f64; LINES.len()];
        let whole = Instant::now();
        let start = Instant::now();
        let mut run = RemeshRun::start(&world, mesh, &params).unwrap();
        this_run[0] = start.elapsed().as_secs_f64() * 1e3;
        while let Some((pass, _)) = run.upcoming() {
            let at = Instant::now();
            run.next_pass(&mut world).unwrap();
            this_run[line_of(pass)] += at.elapsed().as_secs_f64() * 1e3;
        }
        totals.push(whole.elapsed().as_secs_f64() * 1e3);
        for (line, ms) in times.iter_mut().zip(this_run) {
            line.push(ms);
        }
        faces = pappus::mesh::members::MeshMembers::collect(&world, mesh)
            .faces
            .len();
    }
    let median = |values: &mut Vec<f64>| {
        values.sort_by(f64::total_cmp);
        values[values.len() / 2]
    };
    println!(
        "{}: remesh, 5 iterations, {faces} faces after; median of {runs} runs (ms)",
        path.display()
    );
    for (name, values) in LINES.iter().zip(&mut times) {
        println!("{name:>9} {:8.1}", median(values));
    }
    println!("{:>9} {:8.1}", "total", median(&mut totals));
}
