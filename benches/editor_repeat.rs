//! An editor session that subdivides, undoes and subdivides again: is the second Loop ×1 as
//! fast as the first? (Issue 26: the process keeps the memory the first one touched, so the
//! second should not pay the kernel for fresh pages again.)
//!
//! Each run is a process of its own, set up as the `pappus` program sets itself up (freed
//! memory kept, `pappus::process_memory::keep_freed_memory`), holding the editor's logic
//! without a window (`pappus::editor::headless_app`) with the bunny open. It runs Loop ×1,
//! undo, Loop ×1, undo, Loop ×1, each as the editor runs it (a Loop on a mesh this size is a
//! job on a thread of its own, then committed), and times each step from its request to the end
//! of the frame that shows its outcome (the render copy rebuilt), frames paced at 60 Hz. The
//! bench runs itself `RUNS` times (default 10) and prints median / p90 / max.
//!
//! Run: `cargo bench --bench editor_repeat`. Uses `../shared/models/stanford-bunny.obj`.

use bevy::prelude::App;
use pappus::edit::Edit;
use pappus::editor::pipeline::jobs::Jobs;
use pappus::editor::session::requests::{OutcomeLog, Request};
use std::path::Path;
use std::time::{Duration, Instant};

/// The session's steps in order, by the name each row gives it: a Loop ×1, or the undo of one.
const STEPS: [(&str, bool); 5] = [
    ("Loop x1, the session's first", false),
    ("undo of it", true),
    ("Loop x1 again, after the undo", false),
    ("undo of it", true),
    ("Loop x1 a third time", false),
];

/// A frame at 60 Hz.
const FRAME: Duration = Duration::from_micros(16_667);

fn main() {
    if std::env::args().any(|a| a == "session") {
        session();
        return;
    }
    let runs: usize = std::env::var("RUNS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(10);
    let me = std::env::current_exe().expect("the bench's own path");
    let mut times = vec![Vec::with_capacity(runs); STEPS.len()];
    for _ in 0..runs {
        let out = std::process::Command::new(&me)
            .arg("session")
            .output()
            .expect("the bench runs itself");
        assert!(out.status.success(), "editor_repeat session failed");
        let line = String::from_utf8_lossy(&out.stdout);
        for (k, ms) in line.split_whitespace().enumerate().take(STEPS.len()) {
            times[k].push(ms.parse::<f64>().expect("a time"));
        }
    }
    println!(
        "The bunny in one editor session, each step from its request to the frame that shows \
         its outcome; {runs} sessions, median / p90 / max, ms"
    );
    println!();
    println!("| step | median | p90 | max |");
    println!("|---|---:|---:|---:|");
    for ((name, _), mut t) in STEPS.into_iter().zip(times) {
        t.sort_by(f64::total_cmp);
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} |",
            at(0.5),
            at(0.9),
            t[t.len() - 1]
        );
    }
}

/// One session: prints each step's milliseconds on one line.
fn session() {
    pappus::process_memory::keep_freed_memory();
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/stanford-bunny.obj");
    let mut app = pappus::editor::headless_app();
    run(&mut app, Request::Open(bunny));
    let subdivide = Edit::registered("loop").unwrap();
    let line: Vec<String> = STEPS
        .iter()
        .map(|&(_, undo)| {
            let start = Instant::now();
            run(
                &mut app,
                if undo {
                    Request::Undo
                } else {
                    subdivide.clone().into()
                },
            );
            format!("{:.1}", start.elapsed().as_secs_f64() * 1e3)
        })
        .collect();
    println!("{}", line.join(" "));
}

/// Sends `request` and runs frames until its outcome is logged and no job runs (a job logs
/// that it started, then its outcome); panics if it was declined. Frames are paced as a window's
/// at 60 Hz would be: one every [`FRAME`] at most, the thread sleeping in between, so that a job
/// has the cores a windowed editor leaves it.
fn run(app: &mut App, request: Request) {
    let logged = |app: &App| app.world().resource::<OutcomeLog>().entries.len();
    let running = |app: &App| app.world().resource::<Jobs>().running.is_some();
    let before = logged(app);
    app.world_mut().write_message(request);
    while logged(app) == before || running(app) {
        let frame = Instant::now();
        app.update();
        std::thread::sleep(FRAME.saturating_sub(frame.elapsed()));
    }
    let log = app.world().resource::<OutcomeLog>();
    if let Some(Err(why)) = log.entries.last().map(|o| &o.result) {
        panic!("declined: {why}");
    }
}
