//! File formats: OBJ, OFF, PLY (ASCII and binary), STL (ASCII and binary), chosen by extension.
//!
//! Every reader produces a [`PolygonSoup`] and every writer takes one: this module knows
//! nothing of entities. Readers keep the file's vertex order (so scripts can name vertices by
//! their index in the file) and keep unreferenced vertices and bad faces in the soup, so that
//! the builder can count them as repairs. A file that cannot be read at all is an [`IoError`]
//! naming the file and the line (text) or byte offset (binary); readers never panic.
//!
//! Writing goes to a temporary file beside the target, which is then renamed over it: a failed
//! save never destroys the old file.

mod obj;
mod off;
mod ply;
mod stl;
mod text;

use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

use crate::mesh::soup::PolygonSoup;

pub use ply::PlyEncoding;

/// The file formats Pappus reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (read with `tobj`).
    Obj,
    /// Object File Format (ASCII).
    Off,
    /// Stanford PLY (ASCII, binary little- and big-endian; written binary little-endian).
    Ply,
    /// STL (ASCII and binary; written binary, polygons fan-triangulated).
    Stl,
}

impl Format {
    /// The format of a path, by its extension (case-insensitive).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("off") => Ok(Format::Off),
            Some("ply") => Ok(Format::Ply),
            Some("stl") => Ok(Format::Stl),
            _ => Err(IoError::UnknownFormat(path.to_path_buf())),
        }
    }
}

/// Why a file could not be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The extension names no supported format.
    #[error("{0}: unknown format (expected .obj, .off, .ply or .stl)")]
    UnknownFormat(PathBuf),
    /// The file system refused.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The contents are malformed.
    #[error("{path}: {location}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// `line N` or `byte N`.
        location: String,
        /// What is wrong.
        message: String,
    },
}

/// A parse failure before the file name is known: where, and what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    /// `line N` or `byte N`.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl ParseError {
    /// An error at a 1-based line.
    pub fn line(line: usize, message: impl Into<String>) -> Self {
        Self {
            location: format!("line {line}"),
            message: message.into(),
        }
    }

    /// An error at a byte offset.
    pub fn byte(offset: usize, message: impl Into<String>) -> Self {
        Self {
            location: format!("byte {offset}"),
            message: message.into(),
        }
    }

    fn in_file(self, path: &Path) -> IoError {
        IoError::Parse {
            path: path.to_path_buf(),
            location: self.location,
            message: self.message,
        }
    }
}

/// Parses a file's bytes in the given format.
///
/// # Errors
/// Where and why the bytes are malformed.
pub fn read_bytes(format: Format, bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    match format {
        Format::Obj => obj::read(bytes),
        Format::Off => off::read(bytes),
        Format::Ply => ply::read(bytes),
        Format::Stl => stl::read(bytes),
    }
}

/// Encodes a soup in the given format.
pub fn write_bytes(format: Format, soup: &PolygonSoup) -> Vec<u8> {
    match format {
        Format::Obj => obj::write(soup),
        Format::Off => off::write(soup),
        Format::Ply => ply::write(soup, PlyEncoding::BinaryLittleEndian),
        Format::Stl => stl::write(soup),
    }
}

/// Reads a mesh file, its format chosen by extension.
///
/// # Errors
/// An unknown extension, a file that cannot be opened, or malformed contents (with the line
/// or byte offset).
pub fn read(path: &Path) -> Result<PolygonSoup, IoError> {
    let format = Format::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|source| IoError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_bytes(format, &bytes).map_err(|e| e.in_file(path))
}

/// Writes a mesh file, its format chosen by extension, atomically: the data goes to a
/// temporary file in the same folder, which is renamed over `path` once complete.
///
/// # Errors
/// An unknown extension or a file-system failure; `path` is then untouched.
pub fn write(path: &Path, soup: &PolygonSoup) -> Result<(), IoError> {
    let format = Format::from_path(path)?;
    let bytes = write_bytes(format, soup);
    let io_err = |source| IoError::Io {
        path: path.to_path_buf(),
        source,
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(&bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_err(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::math::Vec3;

    /// A quad and a triangle sharing an edge, with awkward coordinates.
    pub(crate) fn mixed() -> PolygonSoup {
        PolygonSoup::from_faces(
            vec![
                Vec3::new(0.1, -2.5e-7, 3.0),
                Vec3::new(1.0, 0.0, 1e6),
                Vec3::new(1.0, 1.0 / 3.0, 0.0),
                Vec3::new(-0.0, 1.0, f32::MIN_POSITIVE),
                Vec3::new(0.5, 2.0, 0.25),
            ],
            &[vec![0, 1, 2, 3], vec![3, 2, 4]],
        )
    }

    #[test]
    fn every_format_round_trips_exactly() {
        for format in [Format::Obj, Format::Off, Format::Ply] {
            let soup = mixed();
            let back = read_bytes(format, &write_bytes(format, &soup)).unwrap();
            assert_eq!(back, soup, "{format:?}");
        }
        let ascii = ply::write(&mixed(), PlyEncoding::Ascii);
        assert_eq!(read_bytes(Format::Ply, &ascii).unwrap(), mixed());
    }

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(
            Format::from_path(Path::new("a/B.OBJ")).unwrap(),
            Format::Obj
        );
        assert_eq!(Format::from_path(Path::new("x.ply")).unwrap(), Format::Ply);
        let err = Format::from_path(Path::new("notes.txt")).unwrap_err();
        assert!(err.to_string().contains("notes.txt"));
    }

    #[test]
    fn saving_is_atomic() {
        let dir = std::env::temp_dir().join(format!("pappus-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.off");
        write(&path, &mixed()).unwrap();
        assert_eq!(read(&path).unwrap(), mixed());
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
            .collect();
        assert!(leftovers.is_empty());
        // A folder that does not exist: an error, and nothing written.
        let missing = dir.join("no/such/dir/m.obj");
        assert!(write(&missing, &mixed()).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
