//! Where a frame goes: the breakdown behind the frame-time figures.
//!
//! [`FrameStatsPlugin`] records, per frame, the main world's CPU time from `First` to `Last`
//! (every editor system, egui's layout, picking), the time of the editor's own `Sync` stage
//! (render copies and overlay), and — through Bevy's [`RenderDiagnosticsPlugin`] — the CPU and
//! GPU time of every render pass (main opaque pass, tonemapping, egui, gizmos, upscaling). The
//! script's `measure:N` step clears the history, lets N frames pass and logs the mean of each
//! (see [`log_breakdown`]); `benches/frame_time.sh` reads those lines.
//!
//! The plugin is added only when asked for (`PAPPUS_FRAME_STATS=1`, which the bench script
//! sets): timestamp queries cost a little on every pass.

use bevy::diagnostic::{
    Diagnostic, DiagnosticPath, Diagnostics, DiagnosticsStore, FrameTimeDiagnosticsPlugin,
    RegisterDiagnostic,
};
use bevy::prelude::*;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use std::time::Instant;

use crate::editor::session::schedule::EditorSystems;

/// Main-world CPU time of a frame, `First` to `Last`, in ms.
pub const MAIN_WORLD: DiagnosticPath = DiagnosticPath::const_new("pappus/main_world_cpu");
/// Time of the editor's `Sync` stage (render copies, colouring, overlay gathering), in ms.
pub const SYNC_STAGE: DiagnosticPath = DiagnosticPath::const_new("pappus/sync_stage_cpu");

/// Adds frame-time, main-world and per-render-pass diagnostics (see the module doc).
pub struct FrameStatsPlugin;

/// When the current span started.
#[derive(Resource, Default)]
struct SpanStarts {
    frame: Option<Instant>,
    sync: Option<Instant>,
}

impl Plugin for FrameStatsPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((
            FrameTimeDiagnosticsPlugin::new(1000),
            RenderDiagnosticsPlugin,
        ))
        .register_diagnostic(Diagnostic::new(MAIN_WORLD).with_max_history_length(1000))
        .register_diagnostic(Diagnostic::new(SYNC_STAGE).with_max_history_length(1000))
        .init_resource::<SpanStarts>()
        .add_systems(First, |mut s: ResMut<SpanStarts>| {
            s.frame = Some(Instant::now());
        })
        .add_systems(Last, end_frame_span)
        .add_systems(
            Update,
            (
                (|mut s: ResMut<SpanStarts>| {
                    s.sync = Some(Instant::now());
                })
                .before(EditorSystems::Sync)
                .after(EditorSystems::Apply),
                end_sync_span
                    .after(EditorSystems::Sync)
                    .before(EditorSystems::Ui),
            ),
        );
    }
}

fn elapsed_ms(start: Option<Instant>) -> Option<f64> {
    start.map(|s| s.elapsed().as_secs_f64() * 1000.0)
}

fn end_frame_span(starts: Res<SpanStarts>, mut diagnostics: Diagnostics) {
    if let Some(ms) = elapsed_ms(starts.frame) {
        diagnostics.add_measurement(&MAIN_WORLD, || ms);
    }
}

fn end_sync_span(starts: Res<SpanStarts>, mut diagnostics: Diagnostics) {
    if let Some(ms) = elapsed_ms(starts.sync) {
        diagnostics.add_measurement(&SYNC_STAGE, || ms);
    }
}

/// Forgets every diagnostic's history, so the next [`log_breakdown`] covers only what follows.
pub fn clear_history(world: &mut World) {
    if let Some(mut store) = world.get_resource_mut::<DiagnosticsStore>() {
        for diagnostic in store.iter_mut() {
            diagnostic.clear_history();
        }
    }
}

/// Logs the mean and the longest of every timing diagnostic since [`clear_history`] (one
/// `frame-stats:` line each, slowest first), if the plugin is present.
pub fn log_breakdown(world: &World) {
    let Some(store) = world.get_resource::<DiagnosticsStore>() else {
        return;
    };
    let mut rows: Vec<(String, f64, f64, usize)> = store
        .iter()
        .filter(|d| d.is_enabled)
        .filter(|d| {
            let p = d.path().as_str();
            p == FrameTimeDiagnosticsPlugin::FRAME_TIME.as_str()
                || p.starts_with("pappus/")
                || p.ends_with("elapsed_cpu")
                || p.ends_with("elapsed_gpu")
        })
        .filter_map(|d| {
            let n = d.history_len();
            (n > 0).then(|| {
                (
                    d.path().as_str().to_string(),
                    d.values().sum::<f64>() / n as f64,
                    d.values().copied().fold(f64::NEG_INFINITY, f64::max),
                    n,
                )
            })
        })
        .collect();
    rows.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (path, mean, max, n) in rows {
        bevy::log::info!("frame-stats: {path} {mean:.2} ms (mean of {n}, the longest {max:.2})");
    }
}

/// CPU time this process has used so far, all threads, user and system, in ms (from
/// `/proc/self/stat`; `None` where that is not readable). Resolution: one clock tick (10 ms).
pub fn process_cpu_ms() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces) start after the last ')'.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the whole line: 12 and 13 after the name.
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks * 10.0)
}
