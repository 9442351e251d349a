//! Recovery files: the editor's unsaved mesh, kept on disk so that a crash, a kill or a power
//! cut loses at most the last seconds of work (Blender's `quit.blend` and autosave play the same
//! part).
//!
//! A recovery is two files in [`folder`] (`$XDG_STATE_HOME/pappus/recovery/`, by default
//! `~/.local/state/pappus/recovery/`), named by the editor session that wrote it:
//!
//! - `NAME.ply`: the mesh as binary PLY, the one format Pappus writes that holds everything a
//!   mesh carries (positions bit for bit, polygons, vertex order, per-corner UVs, normals,
//!   colours);
//! - `NAME.json`: what it is ([`RecoveryInfo`]): the file the mesh came from, the mesh's name,
//!   when it was written, by which process, its counts. It is written after the PLY, so a
//!   recovery whose JSON exists is whole.
//!
//! Both are written atomically ([`crate::io`]'s saves). The editor writes them on a thread once
//! it is idle after an edit and removes them after a save; on start it offers a recovery newer
//! than its source; `pappus recover` lists and restores them from the command line.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde_json::{Value, json};

use crate::io::{self, IoError};
use crate::mesh::PolygonSoup;

/// What a recovery holds, beside the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct RecoveryInfo {
    /// The file the mesh was read from (and is saved to), if it has one.
    pub source: Option<PathBuf>,
    /// The mesh's name as the editor shows it.
    pub name: String,
    /// When the recovery was written, in seconds since the Unix epoch.
    pub saved_at: f64,
    /// The process that wrote it.
    pub pid: u32,
    /// The mesh's vertices.
    pub vertices: usize,
    /// The mesh's faces.
    pub faces: usize,
}

/// A recovery found on disk.
#[derive(Clone, Debug, PartialEq)]
pub struct Recovery {
    /// The name of its files, without the extension (what `pappus recover NAME` takes).
    pub name: String,
    /// The mesh file.
    pub mesh: PathBuf,
    /// What it holds.
    pub info: RecoveryInfo,
}

impl Recovery {
    /// Whether it holds work its source does not: the source file is older than the recovery,
    /// is gone, or there is none (a shape, a mesh never saved).
    pub fn newer_than_source(&self) -> bool {
        let Some(source) = &self.info.source else {
            return true;
        };
        match std::fs::metadata(source).and_then(|m| m.modified()) {
            Ok(modified) => seconds(modified) < self.info.saved_at,
            Err(_) => true,
        }
    }

    /// Whether the process that wrote it is still running (its recovery is that process's own
    /// to keep, not one to offer elsewhere). Where this cannot be told (not Linux), `false`.
    pub fn writer_is_running(&self) -> bool {
        self.info.pid != std::process::id()
            && std::fs::read_to_string(format!("/proc/{}/comm", self.info.pid))
                .is_ok_and(|comm| comm.trim_end() == "pappus")
    }

    /// Reads the mesh.
    ///
    /// # Errors
    /// The mesh file's error (gone, damaged).
    pub fn read(&self) -> Result<PolygonSoup, IoError> {
        io::read(&self.mesh)
    }

    /// Removes both files (either may be gone already).
    pub fn remove(&self) {
        remove(&self.mesh);
    }
}

/// The folder recoveries live in: `$XDG_STATE_HOME/pappus/recovery`, or
/// `$HOME/.local/state/pappus/recovery` (the XDG base directory default); `None` when neither
/// variable is set to an absolute path.
pub fn folder() -> Option<PathBuf> {
    let absolute = |name: &str| {
        std::env::var_os(name)
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
    };
    let state = absolute("XDG_STATE_HOME")
        .or_else(|| absolute("HOME").map(|home| home.join(".local/state")))?;
    Some(state.join("pappus/recovery"))
}

/// The name of the recovery a session writes for a mesh named `mesh_name`: the mesh's name (its
/// characters that are not safe in a file name replaced), the process id and when the session
/// started, so that two editors never write one recovery.
pub fn session_name(mesh_name: &str, started_at: f64) -> String {
    let safe: String = mesh_name
        .chars()
        .map(|c| match c {
            'a'..='z' | 'A'..='Z' | '0'..='9' | '.' | '-' | '_' => c,
            _ => '_',
        })
        .take(64)
        .collect();
    format!("{safe}-{}-{}", std::process::id(), started_at as u64)
}

/// Writes a recovery named `name` into `folder` (created if needed): the mesh, then its
/// [`RecoveryInfo`]. Returns the mesh file's path.
///
/// # Errors
/// The folder cannot be made or a file cannot be written (the message names it). A failed
/// write leaves the previous recovery of that name as it was.
pub fn write(
    folder: &Path,
    name: &str,
    soup: &PolygonSoup,
    info: &RecoveryInfo,
) -> Result<PathBuf, IoError> {
    std::fs::create_dir_all(folder).map_err(|source| IoError::Save {
        path: folder.to_path_buf(),
        source,
    })?;
    let mesh = folder.join(format!("{name}.ply"));
    io::write(&mesh, soup)?;
    let record = json!({
        "source": info.source.as_ref().map(|p| p.to_string_lossy().into_owned()),
        "name": info.name,
        "saved_at": info.saved_at,
        "pid": info.pid,
        "vertices": info.vertices,
        "faces": info.faces,
    });
    let json_path = mesh.with_extension("json");
    crate::io::replace_file(&json_path, record.to_string().as_bytes())?;
    Ok(mesh)
}

/// Removes the recovery whose mesh file is `mesh` (both files; either may be gone already).
pub fn remove(mesh: &Path) {
    // The description first: without it the mesh file is not listed as a recovery.
    let _ = std::fs::remove_file(mesh.with_extension("json"));
    let _ = std::fs::remove_file(mesh);
}

/// The recoveries in `folder`, newest first. Files that are not whole recoveries (a mesh
/// without its description, a description that does not parse) are passed over.
pub fn list(folder: &Path) -> Vec<Recovery> {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return Vec::new();
    };
    let mut found: Vec<Recovery> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .filter_map(|json_path| {
            let mesh = json_path.with_extension("ply");
            let info = parse_info(&std::fs::read_to_string(&json_path).ok()?)?;
            let name = json_path.file_stem()?.to_string_lossy().into_owned();
            mesh.is_file().then_some(Recovery { name, mesh, info })
        })
        .collect();
    found.sort_by(|a, b| b.info.saved_at.total_cmp(&a.info.saved_at));
    found
}

/// A recovery's description, from its JSON.
fn parse_info(text: &str) -> Option<RecoveryInfo> {
    let v: Value = serde_json::from_str(text).ok()?;
    let count = |k: &str| v.get(k).and_then(Value::as_u64).map(|n| n as usize);
    Some(RecoveryInfo {
        source: v.get("source").and_then(Value::as_str).map(PathBuf::from),
        name: v.get("name")?.as_str()?.to_string(),
        saved_at: v.get("saved_at")?.as_f64()?,
        pid: u32::try_from(v.get("pid")?.as_u64()?).ok()?,
        vertices: count("vertices")?,
        faces: count("faces")?,
    })
}

/// A duration in seconds as a person reads it: `40 s`, `12 min`, `3 h`, `2 days`.
pub fn age(seconds: f64) -> String {
    let s = seconds.max(0.0) as u64;
    match s {
        0..120 => format!("{s} s"),
        120..7200 => format!("{} min", s / 60),
        7200..172_800 => format!("{} h", s / 3600),
        _ => format!("{} days", s / 86_400),
    }
}

/// Now, in seconds since the Unix epoch.
pub fn now() -> f64 {
    seconds(SystemTime::now())
}

fn seconds(t: SystemTime) -> f64 {
    t.duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    fn scratch(test: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("pappus-recovery-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    fn info(source: Option<PathBuf>, saved_at: f64, soup: &PolygonSoup) -> RecoveryInfo {
        RecoveryInfo {
            source,
            name: "grid".into(),
            saved_at,
            pid: std::process::id(),
            vertices: soup.positions.len(),
            faces: soup.face_count(),
        }
    }

    #[test]
    fn a_recovery_gives_back_the_mesh_bit_for_bit() {
        let dir = scratch("round-trip");
        let mut soup = shapes::quad_grid(3, 2);
        soup.positions[4].z = -0.0;
        soup.positions[5].x = 1.0 / 3.0;
        soup.vertex_colors = Some(vec![[1, 2, 3]; soup.positions.len()]);
        let name = session_name("my mesh/ü.obj", 1_700_000_000.5);
        assert!(name.starts_with("my_mesh__.obj-"), "{name}");
        let path = write(&dir, &name, &soup, &info(None, now(), &soup)).unwrap();
        let found = list(&dir);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].mesh, path);
        assert_eq!(found[0].name, name);
        assert_eq!(found[0].info, info(None, found[0].info.saved_at, &soup));
        let back = found[0].read().unwrap();
        assert!(crate::io::tests::same_bits(&back, &soup));
        assert_eq!(back.vertex_colors, soup.vertex_colors);
        found[0].remove();
        assert!(list(&dir).is_empty());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "no file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn recoveries_list_newest_first_and_skip_what_is_not_whole() {
        let dir = scratch("list");
        let soup = shapes::tetrahedron();
        write(&dir, "old", &soup, &info(None, 100.0, &soup)).unwrap();
        write(&dir, "new", &soup, &info(None, 200.0, &soup)).unwrap();
        write(&dir, "torn", &soup, &info(None, 300.0, &soup)).unwrap();
        std::fs::remove_file(dir.join("torn.ply")).unwrap();
        std::fs::write(dir.join("bad.json"), b"{not json").unwrap();
        std::fs::write(dir.join("bad.ply"), b"ply").unwrap();
        let names: Vec<String> = list(&dir).into_iter().map(|r| r.name).collect();
        assert_eq!(names, ["new", "old"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_recovery_is_newer_than_its_source_only_when_it_is() {
        let dir = scratch("newer");
        std::fs::create_dir_all(&dir).unwrap();
        let source = dir.join("m.obj");
        std::fs::write(&source, b"v 0 0 0\n").unwrap();
        let soup = shapes::tetrahedron();
        let recovery = |saved_at| Recovery {
            name: "m".into(),
            mesh: dir.join("m.ply"),
            info: info(Some(source.clone()), saved_at, &soup),
        };
        assert!(recovery(now() + 60.0).newer_than_source());
        assert!(!recovery(now() - 3600.0).newer_than_source());
        std::fs::remove_file(&source).unwrap();
        assert!(recovery(now() - 3600.0).newer_than_source(), "source gone");
        assert!(
            !recovery(now()).writer_is_running(),
            "this process is not another"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
