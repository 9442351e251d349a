//! One step of a stepped QEM run on the Stanford bunny (issue: watch an algorithm work): the
//! step itself (one collapse, recorded in the run's history, and the next collapse found), and
//! one editor frame of it (the `Step` request through the editor's logic: the step, the outcome
//! and the render copy's update of the touched chunks only).
//!
//! The target: the step itself ≤ 1 ms, so a step answers within one frame. When a run reaches
//! its end, a fresh one starts, untimed. Run: `cargo bench --bench step_frame` (needs
//! `../shared/models/stanford-bunny.obj`; skipped without it).

use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use pappus::editor::pipeline::stepping::Stepping;
use pappus::editor::session::requests::StepMove;
use pappus::editor::session::requests::{OutcomeLog, Request};
use pappus::mesh::{MeshId, MeshInfo, build_mesh};
use pappus::ops::progressive::{ProgressiveMesh, SlotIndex};
use pappus::ops::simplify::{QemRun, SimplifyParams};
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn bunny() -> Option<PathBuf> {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    path.exists().then_some(path).or_else(|| {
        println!("NOTICE: ../shared/models/stanford-bunny.obj is absent; skipping");
        None
    })
}

/// A QEM run on a fresh copy of the bunny, with its history, as the editor keeps them.
struct Run {
    world: World,
    run: QemRun,
    history: ProgressiveMesh,
    index: SlotIndex,
}

impl Run {
    fn start(soup: &pappus::mesh::soup::PolygonSoup) -> Self {
        let mut world = World::new();
        let mesh: MeshId = build_mesh(&mut world, soup, MeshInfo::default())
            .expect("the bunny builds")
            .mesh;
        let mut run = QemRun::start(&world, mesh, &SimplifyParams::ratio(0.25)).unwrap();
        let history = ProgressiveMesh::start(&world, mesh, run.faces());
        let index = SlotIndex::of(&history);
        run.peek(&world, |_| {});
        Self {
            world,
            run,
            history,
            index,
        }
    }

    /// One step: the collapse, its record, the next collapse found. `false` at the end.
    fn step(&mut self) -> bool {
        let Some(result) = self.run.collapse_next(&mut self.world, |_| {}) else {
            return false;
        };
        self.history.push(&self.world, &self.index, &result);
        self.run.peek(&self.world, |_| {});
        true
    }
}

fn editor(path: &std::path::Path) -> App {
    let mut app = pappus::editor::headless_app();
    app.world_mut()
        .write_message(Request::Open(path.to_path_buf()));
    app.update();
    app.update();
    start_run(&mut app);
    app
}

fn start_run(app: &mut App) {
    app.world_mut().write_message(Request::StartStepped(
        pappus::edit::Edit::invoked("simplify:0.25").unwrap(),
    ));
    app.update();
}

fn step_frame(c: &mut Criterion) {
    let Some(path) = bunny() else {
        return;
    };
    let (soup, _) = pappus::source::read_source(&path).expect("the bunny reads");
    let mut run = Run::start(&soup);
    c.bench_function("QEM step itself: collapse + record + next (bunny)", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let start = Instant::now();
                let stepped = run.step();
                total += start.elapsed();
                if !stepped {
                    run = Run::start(&soup);
                }
            }
            total
        });
    });
    let mut app = editor(&path);
    c.bench_function("QEM step, editor frame with render update (bunny)", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let finished = app
                    .world()
                    .resource::<Stepping>()
                    .run
                    .as_ref()
                    .is_none_or(|r| r.steps.finished());
                if finished {
                    app.world_mut()
                        .write_message(Request::Step(StepMove::Cancel));
                    app.update();
                    start_run(&mut app);
                }
                app.world_mut()
                    .write_message(Request::Step(StepMove::Forward(1)));
                let start = Instant::now();
                app.update();
                total += start.elapsed();
                let log = app.world().resource::<OutcomeLog>();
                if let Some(Err(why)) = log.entries.last().map(|o| &o.result) {
                    panic!("declined: {why}");
                }
            }
            total
        });
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30);
    targets = step_frame
}
criterion_main!(benches);
