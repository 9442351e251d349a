//! Saving that cannot lose the old file.
//!
//! [`replace`] writes the new contents to a temporary file beside the target, flushes it to
//! the disk, renames it over the target and then flushes the folder, so that after a crash or
//! a power cut the name holds either the old contents or the new, whole. The classic recipe
//! (as in the notes of `rename(2)` and in the lock files of `SQLite` and Git), with the
//! details that make it hold in practice:
//!
//! - **A temporary name per save, not per process**: `.NAME.PID-N.tmp` with `N` counted per
//!   save and the file created with `O_EXCL`, so two threads saving at once (Python releases
//!   the GIL while saving) never write into one temporary file; the last rename wins and the
//!   target is always one whole file.
//! - **Links are followed**: saving through a symbolic link replaces the file it points to
//!   and keeps the link (renaming over the link itself would turn it into a plain file).
//! - **Permissions are kept**: the temporary file takes the old file's mode before the
//!   rename.
//! - **A folder is refused** before anything is written.
//! - **A failed write leaves no trace**: no space, the file-size limit (`EFBIG`; the program
//!   ignores `SIGXFSZ` so that the limit is an error, not a kill: [`ignore_file_size_signal`]),
//!   no permission: the temporary file is removed, the old file is untouched, and the error
//!   says what the system said.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::io::error::IoError;

/// How many links [`resolve_links`] follows before giving up (Linux's own limit is 40).
const MAX_LINKS: usize = 40;

/// Saves counted in this process, for unique temporary names.
static SAVES: AtomicU64 = AtomicU64::new(0);

/// Replaces the file at `path` (through any symbolic links) with `bytes`, atomically: see the
/// module documentation. Creates the file if it does not exist.
///
/// # Errors
/// [`IoError::Save`] naming `path` and the system's reason: the target is a folder, the folder
/// does not exist or may not be written, the disk is full, the file-size limit was reached.
/// The file at `path` is then exactly as it was, and no temporary file is left.
pub fn replace(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let failed = |source: std::io::Error| IoError::Save {
        path: path.to_path_buf(),
        source,
    };
    let target = resolve_links(path).map_err(failed)?;
    let old = match std::fs::metadata(&target) {
        Ok(meta) if meta.is_dir() => {
            return Err(failed(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "it is a folder",
            )));
        }
        Ok(meta) => Some(meta.permissions()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(failed(e)),
    };
    let (tmp, mut file) = create_temporary(&target).map_err(failed)?;
    let written = file
        .write_all(bytes)
        .and_then(|()| match &old {
            Some(permissions) => file.set_permissions(permissions.clone()),
            None => Ok(()),
        })
        .and_then(|()| file.sync_all())
        .and_then(|()| {
            drop(file);
            std::fs::rename(&tmp, &target)
        });
    if let Err(e) = written {
        // Best effort: the temporary file exists (it was created above) unless the rename
        // went through, and then this fails harmlessly.
        let _ = std::fs::remove_file(&tmp);
        return Err(failed(e));
    }
    sync_folder(&target);
    Ok(())
}

/// The file `path` names once its symbolic links are followed (the link's target, which may
/// not exist yet); `path` itself when it is not a link.
fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut at = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&at) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let next = std::fs::read_link(&at)?;
                at = match at.parent() {
                    Some(folder) if next.is_relative() => folder.join(next),
                    _ => next,
                };
            }
            _ => return Ok(at),
        }
    }
    Err(std::io::Error::new(
        std::io::ErrorKind::InvalidInput,
        "too many levels of symbolic links",
    ))
}

/// Creates a new temporary file beside `target`, with a name no other save uses.
fn create_temporary(target: &Path) -> std::io::Result<(PathBuf, File)> {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    loop {
        let n = SAVES.fetch_add(1, Ordering::Relaxed);
        let tmp = target.with_file_name(format!(".{name}.{}-{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            // A leftover of an earlier process with the same id: take the next number.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            opened => return opened.map(|file| (tmp, file)),
        }
    }
}

/// Flushes the folder holding `target`, so that the rename itself survives a power cut. Where
/// a folder cannot be opened or synced (some file systems, other systems) the save stands as
/// it is: the data were synced before the rename.
fn sync_folder(target: &Path) {
    let folder = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if let Ok(dir) = File::open(folder) {
        let _ = dir.sync_all();
    }
}

/// Makes the file-size limit (`ulimit -f`) an error that a save reports, rather than the
/// signal (`SIGXFSZ`) that ends the process by default. The program and the Python module call
/// it once at start; nothing else in Pappus uses that signal.
pub fn ignore_file_size_signal() {
    imp::ignore_file_size_signal();
}

#[cfg(unix)]
mod imp {
    #[allow(unsafe_code)]
    pub fn ignore_file_size_signal() {
        // SAFETY: setting a signal's disposition to SIG_IGN installs no handler code; it is
        // async-signal-safe and affects only how the kernel treats SIGXFSZ (the write then
        // fails with EFBIG).
        unsafe {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        }
    }
}

#[cfg(not(unix))]
mod imp {
    pub fn ignore_file_size_signal() {}
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// A fresh folder for one test.
    fn folder(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("pappus-save-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn temporaries(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".tmp"))
            .collect()
    }

    #[test]
    fn a_save_through_a_link_replaces_its_target_and_keeps_the_link() {
        let dir = folder("link");
        std::fs::create_dir(dir.join("real")).unwrap();
        std::fs::write(dir.join("real/m.obj"), b"old").unwrap();
        std::os::unix::fs::symlink("real/m.obj", dir.join("link.obj")).unwrap();
        replace(&dir.join("link.obj"), b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(dir.join("link.obj"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(dir.join("real/m.obj")).unwrap(), b"new");
        assert!(temporaries(&dir.join("real")).is_empty());
        // A dangling link: the file it names is created.
        std::os::unix::fs::symlink("real/new.obj", dir.join("dangling.obj")).unwrap();
        replace(&dir.join("dangling.obj"), b"made").unwrap();
        assert_eq!(std::fs::read(dir.join("real/new.obj")).unwrap(), b"made");
        // A loop of links is an error that says so, and writes nothing.
        std::os::unix::fs::symlink("b.obj", dir.join("a.obj")).unwrap();
        std::os::unix::fs::symlink("a.obj", dir.join("b.obj")).unwrap();
        let err = replace(&dir.join("a.obj"), b"x").unwrap_err();
        assert!(err.to_string().contains("symbolic links"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_save_keeps_the_old_files_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let dir = folder("mode");
        let path = dir.join("m.off");
        std::fs::write(&path, b"old").unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).unwrap();
        replace(&path, b"new").unwrap();
        let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_is_refused_and_left_alone() {
        let dir = folder("dir");
        std::fs::create_dir_all(dir.join("m.ply/inside")).unwrap();
        let err = replace(&dir.join("m.ply"), b"x").unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "{}: not saved (it is a folder); the file on disk is as it was",
                dir.join("m.ply").display()
            )
        );
        assert!(dir.join("m.ply/inside").is_dir());
        assert!(temporaries(&dir).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn threads_saving_one_path_leave_one_whole_file() {
        let dir = folder("threads");
        let path = dir.join("m.obj");
        let contents: Vec<Vec<u8>> = (0..8u8).map(|i| vec![b'a' + i; 200_000]).collect();
        std::thread::scope(|scope| {
            for bytes in &contents {
                let path = &path;
                scope.spawn(move || {
                    for _ in 0..5 {
                        replace(path, bytes).unwrap();
                    }
                });
            }
        });
        let saved = std::fs::read(&path).unwrap();
        assert!(contents.contains(&saved), "a mixed file was left");
        assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
