//! Where a mesh comes from: a file, or `shape:NAME` for a procedural shape. Shared by the
//! command line and the editor so both accept the same names.

use std::path::Path;

use crate::io::{self, IoError};
use crate::mesh::{MeshInfo, PolygonSoup, shapes};

/// Why a source could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SourceError {
    /// `shape:NAME` names no shape [`shapes::by_name`] knows, or sizes too large to make.
    #[error(transparent)]
    Shape(#[from] shapes::ShapeError),
    /// The file could not be read (the error names it, with the line or offset).
    #[error(transparent)]
    Io(#[from] IoError),
}

/// Reads `source` (a mesh file, or `shape:NAME`) into a soup and the mesh's name and path.
///
/// # Errors
/// [`SourceError`]: the unknown shape, or the file's error (naming it, with the line or offset).
pub fn read_source(source: &Path) -> Result<(PolygonSoup, MeshInfo), SourceError> {
    let text = source.to_string_lossy();
    if let Some(name) = text.strip_prefix("shape:") {
        let soup = shapes::by_name(name)?;
        let info = MeshInfo {
            name: name.to_string(),
            path: None,
        };
        return Ok((soup, info));
    }
    let soup = io::read(source)?;
    let name = source
        .file_name()
        .map_or_else(|| text.to_string(), |n| n.to_string_lossy().into_owned());
    Ok((
        soup,
        MeshInfo {
            name,
            path: Some(source.to_path_buf()),
        },
    ))
}
