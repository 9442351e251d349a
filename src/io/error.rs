//! Why a file could not be read or written ([`IoError`], with the file's name), and a reader's
//! failure before the name is attached ([`ParseError`]): below every reader and writer, which
//! take these from here rather than from the folder's own file.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a file could not be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The extension names no supported format.
    #[error("{0}: unknown format (expected .obj, .off, .ply, .stl, .glb, .gltf or .dae)")]
    UnknownFormat(PathBuf),
    /// The format is one Pappus reads but does not write.
    #[error(
        "{0}: Pappus reads this format but does not write it (save as .obj, .ply, .off or .stl)"
    )]
    ReadOnly(PathBuf),
    /// A save failed; the file on disk is as it was before it.
    #[error("{path}: not saved ({source}); the file on disk is as it was")]
    Save {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
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
        /// `line N` (text) or `byte N` (binary, 0-based offset).
        location: String,
        /// What is wrong.
        message: String,
    },
    /// The contents are well-formed but use a variant of the format Pappus does not read
    /// (binary OFF, 4-D OFF, a PLY property type outside the standard eight, …).
    #[error("{path}: {location}: not supported: {message}")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// `line N` or `byte N`.
        location: String,
        /// What is not supported.
        message: String,
    },
}

/// A reader's failure before the file name is attached: where, and what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ParseError {
    /// `line N` or `byte N`.
    pub location: String,
    /// What is wrong.
    pub message: String,
    /// Well-formed but outside what Pappus reads (becomes [`IoError::Unsupported`]).
    pub unsupported: bool,
}

impl ParseError {
    /// An error at a 1-based line.
    pub fn line(line: usize, message: impl Into<String>) -> Self {
        Self {
            location: format!("line {line}"),
            message: message.into(),
            unsupported: false,
        }
    }

    /// An error at a 0-based byte offset.
    pub fn byte(offset: usize, message: impl Into<String>) -> Self {
        Self {
            location: format!("byte {offset}"),
            message: message.into(),
            unsupported: false,
        }
    }

    /// Marks the error as an unsupported variant rather than malformed contents.
    pub fn unsupported(self) -> Self {
        Self {
            unsupported: true,
            ..self
        }
    }

    /// The error with the file's name: [`IoError::Parse`], or [`IoError::Unsupported`].
    pub(super) fn in_file(self, path: &Path) -> IoError {
        let path = path.to_path_buf();
        let (location, message) = (self.location, self.message);
        if self.unsupported {
            IoError::Unsupported {
                path,
                location,
                message,
            }
        } else {
            IoError::Parse {
                path,
                location,
                message,
            }
        }
    }
}
