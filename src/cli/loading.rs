//! Reading an input for a command: a file or `shape:NAME` read and built into a World, with
//! memory warmed on the other core for a subdivision to come.

use bevy::prelude::World;
use std::path::Path;
use std::time::Instant;

use crate::edit::{Edit, Step};
use crate::mesh::{BuiltMesh, build_mesh};
use crate::ops::subdivide::subdivision;
use crate::process_memory;

use super::report::ms_since;

/// About how many bytes of a mesh file hold one row of the mesh it builds (a vertex, halfedge,
/// edge or face): the bunny's OBJ holds 417 000 rows in 3.0 MB. Binary files hold more rows a
/// byte, so for them the estimate below falls short, never over.
const FILE_BYTES_PER_ROW: u64 = 7;

/// A mesh loaded for batch work, with what loading it cost.
pub struct Loaded {
    /// The world holding the mesh.
    pub world: World,
    /// The mesh and its repair report.
    pub built: BuiltMesh,
    /// Milliseconds spent reading and parsing the file.
    pub read_ms: f64,
    /// Milliseconds spent building entities (repairs included).
    pub build_ms: f64,
}

/// Reads `input` (a file, or `shape:NAME`) and builds it into a fresh world.
///
/// # Errors
/// A message naming the file and what is wrong with it.
pub fn load(input: &str) -> Result<Loaded, String> {
    load_for(input, &[])
}

/// [`load`], for `steps`: when one of them subdivides, the memory its first level will touch is
/// warmed on the other core while the file is read and the mesh built
/// ([`process_memory::warm`]). The warming is over when this returns, so that the steps have
/// warm memory and both cores to themselves (warming that went on into a subdivision slowed
/// it, the two contending for the cores).
pub(super) fn load_for(input: &str, steps: &[Step]) -> Result<Loaded, String> {
    let warming = process_memory::warm(subdivision_bytes(input, steps));
    let loaded = read_and_build(input);
    if let Some(warming) = warming {
        // A warming thread that panicked warmed nothing; the steps run all the same.
        let _ = warming.join();
    }
    loaded
}

/// Reads `input` and builds it into a fresh world.
fn read_and_build(input: &str) -> Result<Loaded, String> {
    let start = Instant::now();
    let (soup, info) = crate::source::read_source(Path::new(input)).map_err(|e| e.to_string())?;
    let read_ms = ms_since(start);
    if let Some(names) = soup.scalars_not_kept() {
        eprintln!(
            "pappus: {input}: the file's {names} is not kept (outputs carry positions, faces, UVs, normals and colours, and what --quantity or --normals adds)"
        );
    }
    for note in &soup.notes {
        eprintln!("pappus: {input}: {note}");
    }
    let start = Instant::now();
    let mut world = World::new();
    let built = build_mesh(&mut world, &soup, info).map_err(|e| format!("{input}: {e}"))?;
    Ok(Loaded {
        world,
        built,
        read_ms,
        build_ms: ms_since(start),
    })
}

/// The fresh memory the first level of the first subdividing step among `steps` will touch,
/// estimated from the size of the file `input` before it is read (so that warming can start at
/// once) by [`FILE_BYTES_PER_ROW`] and [`process_memory::BYTES_PER_ROW`]: a level makes about
/// four times the rows it starts from. Only the first level: warming for the second (16 times
/// the rows) would still be under way while the first level runs, the two contending for the
/// two cores. 0 when no step subdivides or `input` is not a file.
fn subdivision_bytes(input: &str, steps: &[Step]) -> usize {
    let subdivides = steps
        .iter()
        .any(|step| matches!(step, Step::Edit(Edit::Operation(op)) if subdivision(op).is_some()));
    let file_bytes = match std::fs::metadata(input) {
        Ok(meta) if subdivides => meta.len(),
        _ => return 0,
    };
    let rows = usize::try_from(file_bytes / FILE_BYTES_PER_ROW).unwrap_or(usize::MAX);
    rows.saturating_mul(4 * process_memory::BYTES_PER_ROW)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warms_for_the_first_subdivision_level_by_the_file_size() {
        let dir = std::env::temp_dir().join(format!("pappus-warm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("mesh.obj");
        std::fs::write(&file, vec![b' '; 7_000]).unwrap();
        let input = file.to_str().unwrap();
        let steps = |text: &str| -> Vec<Step> {
            text.split_whitespace()
                .map(|s| Step::parse(s).unwrap())
                .collect()
        };
        // 7 000 bytes: 1 000 rows, four times as many after a level, whatever the levels.
        let level = 4 * 1_000 * process_memory::BYTES_PER_ROW;
        assert_eq!(subdivision_bytes(input, &steps("loop:1")), level);
        assert_eq!(
            subdivision_bytes(input, &steps("triangulate loop:3")),
            level
        );
        assert_eq!(subdivision_bytes(input, &steps("catmull-clark")), level);
        assert_eq!(subdivision_bytes(input, &steps("simplify:0.5 remesh")), 0);
        assert_eq!(subdivision_bytes("shape:torus", &steps("loop:1")), 0);
        assert_eq!(
            subdivision_bytes(&format!("{input}.gone"), &steps("loop:1")),
            0
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
