//! `pappus recover`: the editor's recovery files ([`crate::recovery`]) from the command line.
//!
//! ```text
//! pappus recover --list [--json]          the recoveries, newest first
//! pappus recover --latest -o PATH         writes the newest one's mesh to PATH
//! pappus recover NAME -o PATH             writes that one's mesh to PATH
//! ```
//!
//! Restoring writes the mesh as it was kept (the recovery's positions bit for bit, its faces,
//! UVs, normals and colours, in the format PATH's extension names) and leaves the recovery in
//! place: it goes when the editor that wrote it saves, or by hand.

use std::path::{Path, PathBuf};

use serde_json::json;

use crate::recovery::{self, Recovery};

/// What `pappus recover` was asked.
pub(super) struct RecoverArgs {
    /// The recovery to restore, by name.
    pub name: Option<String>,
    /// List them.
    pub list: bool,
    /// Restore the newest.
    pub latest: bool,
    /// Where to write the restored mesh.
    pub output: Option<PathBuf>,
    /// JSON instead of text.
    pub json: bool,
}

/// Runs `pappus recover`.
///
/// # Errors
/// No recovery folder (neither `XDG_STATE_HOME` nor `HOME` set), no recovery (of that name),
/// a recovery that cannot be read, an output that cannot be written; the message says which.
pub(super) fn recover(args: RecoverArgs) -> Result<(), String> {
    let folder = recovery::folder()
        .ok_or("no recovery folder: neither XDG_STATE_HOME nor HOME is set to an absolute path")?;
    let found = recovery::list(&folder);
    if args.list {
        print_list(&folder, &found, args.json);
        return Ok(());
    }
    let chosen = match (&args.name, args.latest) {
        (Some(name), _) => found.iter().find(|r| &r.name == name).ok_or_else(|| {
            format!(
                "no recovery named `{name}` in {} (`pappus recover --list` lists them)",
                folder.display()
            )
        })?,
        (None, true) => found
            .first()
            .ok_or_else(|| format!("no recovery in {}", folder.display()))?,
        (None, false) => {
            return Err("say which recovery: NAME, --latest, or --list to see them".into());
        }
    };
    let output = args
        .output
        .ok_or("-o PATH is needed to restore a recovery (where to write the mesh)")?;
    restore(chosen, &output)?;
    if args.json {
        outln!(
            "{}",
            json!({ "restored": chosen.name, "output": output.to_string_lossy(),
                    "vertices": chosen.info.vertices, "faces": chosen.info.faces })
        );
    } else {
        outln!(
            "restored {} ({} vertices, {} faces) to {}",
            chosen.name,
            chosen.info.vertices,
            chosen.info.faces,
            output.display()
        );
    }
    Ok(())
}

/// Writes `chosen`'s mesh to `output`.
fn restore(chosen: &Recovery, output: &Path) -> Result<(), String> {
    let soup = chosen
        .read()
        .map_err(|e| format!("the recovery is damaged: {e}"))?;
    super::process::write_mesh(output, &soup, &mut |message| eprintln!("pappus: {message}"))?;
    Ok(())
}

/// Prints the recoveries, newest first.
fn print_list(folder: &Path, found: &[Recovery], as_json: bool) {
    let now = recovery::now();
    if as_json {
        let rows: Vec<_> = found
            .iter()
            .map(|r| {
                json!({
                    "name": r.name,
                    "mesh": r.mesh.to_string_lossy(),
                    "source": r.info.source.as_ref().map(|p| p.to_string_lossy()),
                    "saved_at": r.info.saved_at,
                    "vertices": r.info.vertices,
                    "faces": r.info.faces,
                    "newer_than_source": r.newer_than_source(),
                    "writer_running": r.writer_is_running(),
                })
            })
            .collect();
        outln!("{}", json!(rows));
        return;
    }
    if found.is_empty() {
        outln!("no recovery in {}", folder.display());
        return;
    }
    for r in found {
        let source = r
            .info
            .source
            .as_ref()
            .map_or_else(|| "never saved".to_string(), |p| p.display().to_string());
        let state = match (r.writer_is_running(), r.newer_than_source()) {
            (true, _) => "; its editor is still running",
            (false, true) => "; newer than its source",
            (false, false) => "; its source is newer",
        };
        outln!(
            "{}  {} ago  {} ({} vertices, {} faces), from {source}{state}",
            r.name,
            recovery::age(now - r.info.saved_at),
            r.info.name,
            r.info.vertices,
            r.info.faces
        );
    }
}
