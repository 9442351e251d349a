//! File formats (being written; placeholder so the crate builds).
use crate::mesh::soup::PolygonSoup;
use std::path::Path;

/// Reads a mesh file (placeholder).
pub fn read(path: &Path) -> Result<PolygonSoup, String> {
    Err(format!("{}: reading is not implemented yet", path.display()))
}

/// Writes a mesh file (placeholder).
pub fn write(path: &Path, _soup: &PolygonSoup) -> Result<(), String> {
    Err(format!("{}: writing is not implemented yet", path.display()))
}
