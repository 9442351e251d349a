//! The bodies of the fuzz targets (`fuzz/`, run by `cargo fuzz` and `benches/fuzz.sh`), here in
//! the library so that the test suite replays the fuzzers' corpus and every crash they found
//! through the very same code (`fuzz/corpus/TARGET/` and `fuzz/regressions/TARGET/`).
//!
//! Each checks more than "no panic": what a reader accepts must build into a valid mesh whose
//! soup round-trips through the writers of every format that holds it; a step that parses must
//! print as text that parses back to the same step.

use std::path::Path;

use bevy::prelude::World;

use crate::edit::Step;
use crate::io::{self, Format};
use crate::mesh::{MeshInfo, build_mesh, to_soup, validate};

/// The fuzz targets, by the name of their folder in `fuzz/corpus/` and `fuzz/fuzz_targets/`.
pub const TARGETS: [&str; 7] = [
    "read_obj",
    "read_off",
    "read_ply",
    "read_stl",
    "read_dae",
    "read_glb",
    "parse_step",
];

/// Runs the fuzz target `target` on `data`.
///
/// # Panics
/// When the code under test misbehaves (that is the point): a reader or the builder panics,
/// a built mesh is invalid, a written mesh does not read back the same, a step does not print
/// back. Also for an unknown target name.
pub fn run(target: &str, data: &[u8]) {
    match target {
        "read_obj" => read_and_build(Format::Obj, data),
        "read_off" => read_and_build(Format::Off, data),
        "read_ply" => read_and_build(Format::Ply, data),
        "read_stl" => read_and_build(Format::Stl, data),
        "read_dae" => read_and_build(Format::Collada, data),
        "read_glb" => read_and_build(Format::Glb, data),
        "parse_step" => parse_step(data),
        _ => panic!("no fuzz target `{target}`"),
    }
}

/// Reads `data` as `format`; what reads must build into a valid mesh (repairs allowed), and the
/// mesh's soup must read back from `format`'s writer (OBJ's for a format Pappus only reads)
/// with the same faces and positions.
///
/// # Panics
/// As [`run`].
pub fn read_and_build(format: Format, data: &[u8]) {
    let name = Path::new("fuzz");
    let Ok(soup) = io::read_bytes(format, data, name) else {
        return;
    };
    let mut world = World::new();
    let Ok(built) = build_mesh(&mut world, &soup, MeshInfo::default()) else {
        return;
    };
    if let Err(e) = validate(&world, built.mesh) {
        panic!("a {format:?} file built into an invalid mesh: {e}");
    }
    let saved = to_soup(&world, built.mesh);
    let (format, bytes) = match io::write_bytes(format, &saved) {
        Some(bytes) => (format, bytes),
        None => (
            Format::Obj,
            io::write_bytes(Format::Obj, &saved).expect("Pappus writes OBJ"),
        ),
    };
    let again = io::read_bytes(format, &bytes, name)
        .unwrap_or_else(|e| panic!("Pappus's own {format:?} does not read back: {e}"));
    let triangles =
        |s: &crate::mesh::PolygonSoup| s.faces().map(|f| f.len().saturating_sub(2)).sum::<usize>();
    if format == Format::Stl {
        // STL stores triangles and welds by position: the counts of triangles are what survive.
        assert_eq!(triangles(&again), triangles(&saved), "STL round trip");
        return;
    }
    if format == Format::Glb && saved.face_groups.is_some() {
        // glTF writes a primitive per face group, so a group's faces come back together: the
        // same faces, in group order (a mesh whose group repeats after another's, as two nodes
        // of one name or one mesh's primitives red, blue, red give).
        let sorted = |s: &crate::mesh::PolygonSoup| {
            let mut faces: Vec<Vec<u32>> = s.faces().map(<[u32]>::to_vec).collect();
            faces.sort_unstable();
            faces
        };
        assert_eq!(
            sorted(&again),
            sorted(&saved),
            "{format:?} round trip: faces"
        );
    } else {
        assert_eq!(again.indices, saved.indices, "{format:?} round trip: faces");
        assert_eq!(
            again.face_starts, saved.face_starts,
            "{format:?} round trip"
        );
    }
    let bits = |s: &crate::mesh::PolygonSoup| -> Vec<[u32; 3]> {
        s.positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(
        bits(&again),
        bits(&saved),
        "{format:?} round trip: positions"
    );
}

/// Parses `data` (as UTF-8, lossily) as a `process` step; a step that parses prints as text
/// that parses back to the same step.
///
/// # Panics
/// As [`run`].
pub fn parse_step(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(step) = Step::parse(&text) else {
        return;
    };
    let printed = step.to_string();
    match Step::parse(&printed) {
        Ok(again) => assert_eq!(again, step, "`{text}` printed as `{printed}`"),
        Err(e) => panic!("`{text}` printed as `{printed}`, which does not parse: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file of the fuzzers' corpus and every crash they found, through its target once:
    /// what CI runs instead of fuzzing.
    #[test]
    fn the_fuzz_corpus_and_regressions_replay_cleanly() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
        let mut replayed = 0;
        for target in TARGETS {
            for folder in ["corpus", "regressions"] {
                let Ok(entries) = std::fs::read_dir(root.join(folder).join(target)) else {
                    continue;
                };
                for entry in entries.filter_map(Result::ok) {
                    let data = std::fs::read(entry.path()).unwrap();
                    let result = std::panic::catch_unwind(|| run(target, &data));
                    assert!(result.is_ok(), "{target}: {}", entry.path().display());
                    replayed += 1;
                }
            }
        }
        assert!(
            replayed >= TARGETS.len(),
            "the corpus is missing: {replayed} files"
        );
    }
}
