//! Where a mesh comes from: a file, or `shape:NAME` for a procedural shape. Shared by the
//! command line and the editor so both accept the same names.

use std::path::Path;

use crate::io;
use crate::mesh::{MeshInfo, PolygonSoup, shapes};

/// Reads `source` (a mesh file, or `shape:NAME`) into a soup and the mesh's name and path.
///
/// # Errors
/// A message naming the file (with line or offset) or the unknown shape.
pub fn read_source(source: &Path) -> Result<(PolygonSoup, MeshInfo), String> {
    let text = source.to_string_lossy();
    if let Some(name) = text.strip_prefix("shape:") {
        let soup = shapes::by_name(name).ok_or_else(|| {
            format!(
                "unknown shape `{name}`; known: {}",
                shapes::SHAPE_NAMES.join(", ")
            )
        })?;
        let info = MeshInfo {
            name: name.to_string(),
            path: None,
        };
        return Ok((soup, info));
    }
    let soup = io::read(source).map_err(|e| e.to_string())?;
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
