//! File formats: OBJ, OFF, PLY (ASCII and binary), STL (ASCII and binary), glTF 2.0 (`.gltf`,
//! `.glb`), read and written; COLLADA, read; chosen by extension.
//!
//! Every reader produces a [`PolygonSoup`] and every writer takes one: this module knows
//! nothing of entities. Readers keep the file's vertex order (so scripts can name vertices by
//! their index in the file) and keep unreferenced vertices and bad faces (too few corners, an
//! index out of range) in the soup, so that the builder can drop and count them as repairs.
//! What cannot be read at all is an [`IoError`] naming the file and the line (text) or byte
//! offset (binary); readers never panic, and never reserve memory from a header's counts
//! beyond what the input could hold.
//!
//! Writing goes to a temporary file beside the target, which is then renamed over it: a failed
//! save never destroys the old file ([`save`] says how).

mod collada;
mod corners;
mod error;
mod gltf;
mod obj;
mod off;
mod parts;
mod ply;
mod save;
mod skipped;
mod stl;
mod strips;
mod text;

use std::path::Path;

use crate::mesh::soup::PolygonSoup;

pub use error::IoError;
pub use ply::{PlyEncoding, keeps_face_scalar, keeps_vertex_scalar};
pub use save::ignore_file_size_signal;
pub use stl::StlEncoding;

/// The file formats Pappus reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (parsed with `tobj`; positions and faces only).
    Obj,
    /// Object File Format, ASCII (`OFF`, and `COFF`/`NOFF`/`STOFF`-style variants whose extra
    /// per-vertex values are ignored).
    Off,
    /// Stanford PLY (ASCII, binary little- and big-endian; written binary little-endian). The
    /// one format that carries a per-vertex quality and colour, both ways.
    Ply,
    /// STL (ASCII and binary; written binary, polygons fan-triangulated).
    Stl,
    /// COLLADA (`.dae`, 1.4.1 and 1.5), read only: its scene's meshes, placed by their node
    /// transforms, Y-up, with normals, texture coordinates and colours.
    Collada,
    /// glTF 2.0 as JSON (`.gltf`: buffers beside it or embedded; written embedded).
    Gltf,
    /// glTF 2.0 binary (`.glb`).
    Glb,
}

/// Every extension Pappus knows, and its format: what [`Format::from_path`] reads and what
/// [`extensions`] lists.
const EXTENSIONS: [(&str, Format); 7] = [
    ("obj", Format::Obj),
    ("off", Format::Off),
    ("ply", Format::Ply),
    ("stl", Format::Stl),
    ("glb", Format::Glb),
    ("gltf", Format::Gltf),
    ("dae", Format::Collada),
];

/// The extensions of the formats Pappus reads (every one), or of those it writes when
/// `writing` (all but COLLADA): the open and save dialogs' filters.
pub fn extensions(writing: bool) -> Vec<&'static str> {
    EXTENSIONS
        .iter()
        .filter(|(_, format)| !writing || format.writes())
        .map(|&(extension, _)| extension)
        .collect()
}

impl Format {
    /// Whether Pappus writes this format (COLLADA is read only).
    pub fn writes(self) -> bool {
        self != Format::Collada
    }

    /// The format of a path, by its extension (case-insensitive).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        EXTENSIONS
            .iter()
            .find(|(extension, _)| Some(*extension) == ext.as_deref())
            .map(|&(_, format)| format)
            .ok_or_else(|| IoError::UnknownFormat(path.to_path_buf()))
    }
}

/// What the soup carries that a file at `path` (its format by extension) cannot hold, in a
/// person's words (`"UVs"`, `"normals"`, `"colours"`, `"quality"`, `"other vertex
/// properties"`, `"face properties"`, `"groups"`, then `"polygon faces (written as
/// triangles)"`), in that order: empty when a save keeps everything, or when the extension
/// names no format Pappus writes (the save itself then fails). OBJ and glTF hold all but the
/// quality and the vertex and face properties, PLY all but the groups, OFF and STL none of
/// them; STL and glTF hold triangles only.
pub fn dropped(path: &Path, soup: &PolygonSoup) -> Vec<&'static str> {
    let Ok(format) = Format::from_path(path) else {
        return Vec::new();
    };
    let has = soup.attributes();
    let carried = [
        ("UVs", has.uv),
        ("normals", has.normals),
        ("colours", has.colors),
        ("quality", soup.vertex_quality.is_some()),
        ("other vertex properties", !soup.vertex_scalars.is_empty()),
        ("face properties", !soup.face_scalars.is_empty()),
        ("groups", has.groups),
    ];
    let holds = |what: &str| match format {
        Format::Ply => what != "groups",
        Format::Obj | Format::Gltf | Format::Glb => !matches!(
            what,
            "quality" | "other vertex properties" | "face properties"
        ),
        Format::Off | Format::Stl | Format::Collada => false,
    };
    let triangles_only = matches!(format, Format::Stl | Format::Gltf | Format::Glb);
    let polygons = triangles_only && soup.faces().any(|f| f.len() > 3);
    carried
        .into_iter()
        .filter(|&(what, carries)| carries && !holds(what))
        .map(|(what, _)| what)
        .chain(polygons.then_some("polygon faces (written as triangles)"))
        .collect()
}

/// The sentence for what a save into `path` drops: `"m.off: UVs and normals dropped (OFF
/// cannot hold them)"`.
pub fn dropped_note(path: &Path, dropped: &[&str]) -> String {
    let list = crate::mesh::attributes::listed(dropped);
    let format = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_uppercase())
        .unwrap_or_default();
    format!(
        "{}: {list} dropped ({format} cannot hold {})",
        path.display(),
        if dropped.len() == 1 { "it" } else { "them" }
    )
}

/// Parses a file's contents, already in memory, in the given format. `name` is only used in
/// error messages (pass the file's path, or any label).
///
/// # Errors
/// [`IoError::Parse`] or [`IoError::Unsupported`], naming `name` and the line or byte offset.
pub fn read_bytes(format: Format, bytes: &[u8], name: &Path) -> Result<PolygonSoup, IoError> {
    let soup = match format {
        Format::Obj => obj::read(bytes),
        Format::Off => off::read(bytes),
        Format::Ply => ply::read(bytes),
        Format::Stl => stl::read(bytes),
        Format::Collada => collada::read(bytes),
        Format::Gltf | Format::Glb => gltf::read(bytes, None),
    };
    soup.map_err(|e| e.in_file(name))
}

/// Encodes a soup in the given format, as [`write()`] would save it (PLY binary little-endian,
/// STL binary, glTF with its buffer embedded); `None` for a format Pappus only reads (COLLADA).
pub fn write_bytes(format: Format, soup: &PolygonSoup) -> Option<Vec<u8>> {
    Some(match format {
        Format::Obj => obj::write(soup),
        Format::Off => off::write(soup),
        Format::Ply => ply::write(soup, PlyEncoding::BinaryLittleEndian),
        Format::Stl => stl::write(soup, StlEncoding::Binary),
        Format::Gltf => gltf::write(soup, false),
        Format::Glb => gltf::write(soup, true),
        Format::Collada => return None,
    })
}

/// Encodes a soup as PLY with the chosen encoding: `float x y z`, then `uchar red green blue`
/// and `float quality` when the soup carries [`vertex_colors`](PolygonSoup::vertex_colors)
/// and [`vertex_quality`](PolygonSoup::vertex_quality) (one per position; MeshLab reads them
/// as the vertex colour and scalar), then `list uchar int vertex_indices` (`list int int`
/// when a face has more than 255 corners, `uint` indices when one exceeds `i32::MAX`).
pub fn write_ply(soup: &PolygonSoup, encoding: PlyEncoding) -> Vec<u8> {
    ply::write(soup, encoding)
}

/// Encodes a soup as STL with the chosen encoding. STL holds only triangles: polygons are
/// fan-triangulated from their first corner, and every triangle stores its own corners, so
/// reading the file back welds them by position.
pub fn write_stl(soup: &PolygonSoup, encoding: StlEncoding) -> Vec<u8> {
    stl::write(soup, encoding)
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
    match format {
        // A `.gltf`'s buffers may be files beside it.
        Format::Gltf | Format::Glb => {
            gltf::read(&bytes, path.parent()).map_err(|e| e.in_file(path))
        }
        _ => read_bytes(format, &bytes, path),
    }
}

/// Replaces the file at `path` with `bytes` as mesh saves do ([`save::replace`]): atomically,
/// through symbolic links, keeping permissions.
///
/// # Errors
/// [`IoError::Save`] with the system's reason; the file on disk is then as it was.
pub fn replace_file(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    save::replace(path, bytes)
}

/// Writes a mesh file, its format chosen by extension, atomically ([`save::replace`]): a
/// temporary file beside the target, synced, renamed over it (through symbolic links, keeping
/// its permissions), then the folder synced.
///
/// # Errors
/// An unknown extension, a format Pappus only reads ([`IoError::ReadOnly`]), or
/// [`IoError::Save`] with the system's reason; the file on disk is then exactly as it was and
/// no temporary file is left.
pub fn write(path: &Path, soup: &PolygonSoup) -> Result<(), IoError> {
    let format = Format::from_path(path)?;
    let bytes = write_bytes(format, soup).ok_or_else(|| IoError::ReadOnly(path.to_path_buf()))?;
    save::replace(path, &bytes)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use bevy::math::{Vec2, Vec3};

    /// A quad and a triangle sharing an edge, with awkward coordinates (a negative zero, a
    /// third, a subnormal-adjacent value, a large one).
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

    /// Bitwise equality of positions (`==` on floats would let `-0.0` pass for `0.0`).
    pub(crate) fn same_bits(a: &PolygonSoup, b: &PolygonSoup) -> bool {
        let bits = |s: &PolygonSoup| -> Vec<[u32; 3]> {
            s.positions
                .iter()
                .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
                .collect()
        };
        bits(a) == bits(b) && a.indices == b.indices && a.face_starts == b.face_starts
    }

    fn name() -> &'static Path {
        Path::new("t")
    }

    #[test]
    fn every_format_round_trips_exactly() {
        for format in [Format::Obj, Format::Off, Format::Ply] {
            let soup = mixed();
            let back = read_bytes(format, &write_bytes(format, &soup).unwrap(), name()).unwrap();
            assert!(same_bits(&back, &soup), "{format:?}: {back:?}");
        }
        for encoding in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let back = read_bytes(Format::Ply, &write_ply(&mixed(), encoding), name()).unwrap();
            assert!(same_bits(&back, &mixed()), "{encoding:?}");
        }
    }

    #[test]
    fn errors_name_the_file_and_the_place() {
        let err = read_bytes(Format::Obj, b"v 0 0 0\nv 1 2\n", Path::new("m.obj")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.obj: line 2: expected 3 coordinates, found 2"
        );
        let err = read_bytes(Format::Stl, &[1u8; 90], Path::new("m.stl")).unwrap_err();
        assert!(matches!(err, IoError::Parse { .. }));
        assert!(err.to_string().starts_with("m.stl: byte "), "{err}");
        let err = read_bytes(Format::Off, b"4OFF\n", Path::new("m.off")).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        assert!(err.to_string().starts_with("m.off: line 1: not supported"));
    }

    #[test]
    fn a_save_names_what_its_format_cannot_hold() {
        let soup = read_bytes(Format::Obj, ATTRIBUTED_OBJ, name()).unwrap();
        let dropped = |extension: &str, soup: &PolygonSoup| {
            dropped(&Path::new("m").with_extension(extension), soup)
        };
        assert_eq!(dropped("off", &soup), ["UVs", "normals", "colours"]);
        assert_eq!(
            dropped("stl", &soup),
            [
                "UVs",
                "normals",
                "colours",
                "polygon faces (written as triangles)"
            ]
        );
        assert_eq!(
            dropped("glb", &soup),
            ["polygon faces (written as triangles)"]
        );
        assert!(dropped("obj", &soup).is_empty());
        assert!(dropped("ply", &soup).is_empty());
        assert!(dropped("off", &mixed()).is_empty());
        let with_quality = PolygonSoup {
            vertex_quality: Some(vec![0.5; 5]),
            ..mixed()
        };
        assert_eq!(dropped("obj", &with_quality), ["quality"]);
        assert_eq!(
            dropped_note(Path::new("beast.off"), &["UVs"]),
            "beast.off: UVs dropped (OFF cannot hold it)"
        );
        assert_eq!(
            dropped_note(Path::new("m.stl"), &["UVs", "normals", "colours"]),
            "m.stl: UVs, normals and colours dropped (STL cannot hold them)"
        );
    }

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(
            Format::from_path(Path::new("a/B.OBJ")).unwrap(),
            Format::Obj
        );
        assert_eq!(Format::from_path(Path::new("x.Ply")).unwrap(), Format::Ply);
        assert_eq!(Format::from_path(Path::new("x.off")).unwrap(), Format::Off);
        assert_eq!(Format::from_path(Path::new("x.STL")).unwrap(), Format::Stl);
        assert_eq!(
            extensions(false),
            ["obj", "off", "ply", "stl", "glb", "gltf", "dae"]
        );
        assert_eq!(
            extensions(true),
            ["obj", "off", "ply", "stl", "glb", "gltf"]
        );
        for bad in ["notes.txt", "noext", "obj"] {
            let err = Format::from_path(Path::new(bad)).unwrap_err();
            assert!(err.to_string().starts_with(bad), "{err}");
        }
    }

    /// Every prefix of every encoding, and copies with bytes overwritten, read without a panic.
    #[test]
    fn damaged_files_never_panic() {
        let soup = mixed();
        let files = [
            (Format::Obj, write_bytes(Format::Obj, &soup).unwrap()),
            (Format::Off, write_bytes(Format::Off, &soup).unwrap()),
            (Format::Ply, write_ply(&soup, PlyEncoding::Ascii)),
            (
                Format::Ply,
                write_ply(&soup, PlyEncoding::BinaryLittleEndian),
            ),
            (Format::Ply, write_ply(&soup, PlyEncoding::BinaryBigEndian)),
            (Format::Stl, write_stl(&soup, StlEncoding::Binary)),
            (Format::Stl, write_stl(&soup, StlEncoding::Ascii)),
        ];
        let mut seed = 0x2545_f491_u32;
        let mut random = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        for (format, bytes) in &files {
            for cut in 0..bytes.len() {
                let _ = read_bytes(*format, &bytes[..cut], name());
            }
            for _ in 0..300 {
                let mut damaged = bytes.clone();
                for _ in 0..1 + random() % 4 {
                    let at = random() as usize % damaged.len();
                    damaged[at] = [b'-', b'9', b' ', b'\n', 0xff, 0, b'#'][random() as usize % 7];
                }
                let _ = read_bytes(*format, &damaged, name());
            }
        }
        for format in [Format::Obj, Format::Off, Format::Ply, Format::Stl] {
            for garbage in [
                &b""[..],
                b"\0",
                b"\xff\xfe",
                b"solid",
                b"ply",
                b"OFF",
                b"f 1 2 3",
            ] {
                let _ = read_bytes(format, garbage, name());
            }
        }
    }

    #[test]
    fn saving_is_atomic() {
        let dir = std::env::temp_dir().join(format!("pappus-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let leftovers = || -> Vec<_> {
            std::fs::read_dir(&dir)
                .unwrap()
                .filter_map(|e| e.ok())
                .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
                .map(|e| e.file_name())
                .collect()
        };
        let path = dir.join("m.off");
        write(&path, &mixed()).unwrap();
        assert!(same_bits(&read(&path).unwrap(), &mixed()));
        // Overwriting replaces the contents.
        let tri = PolygonSoup::from_faces(vec![Vec3::X, Vec3::Y, Vec3::Z], &[[0, 1, 2]]);
        write(&path, &tri).unwrap();
        assert_eq!(read(&path).unwrap(), tri);
        assert!(leftovers().is_empty(), "{:?}", leftovers());
        // A folder that does not exist: an error, and nothing written.
        let missing = dir.join("no/such/dir/m.obj");
        let err = write(&missing, &mixed()).unwrap_err();
        assert!(matches!(err, IoError::Save { .. }));
        assert!(err.to_string().contains("m.obj"), "{err}");
        // The target is a folder: the rename fails, the temporary file is removed and the
        // folder survives.
        let blocked = dir.join("blocked.ply");
        std::fs::create_dir_all(blocked.join("inside")).unwrap();
        assert!(write(&blocked, &mixed()).is_err());
        assert!(blocked.join("inside").is_dir());
        assert!(leftovers().is_empty(), "{:?}", leftovers());
        assert!(matches!(
            read(&dir.join("absent.obj")),
            Err(IoError::Io { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Reads `bytes`, builds the mesh, and turns it back into a soup (what saving writes).
    fn through_mesh(format: Format, bytes: &[u8]) -> PolygonSoup {
        let soup = read_bytes(format, bytes, name()).unwrap();
        let mut world = bevy::prelude::World::new();
        let built = crate::mesh::build_mesh(&mut world, &soup, Default::default()).unwrap();
        crate::mesh::to_soup(&world, built.mesh)
    }

    fn uv_bits(s: &PolygonSoup) -> Option<Vec<[u32; 2]>> {
        let u = s.corner_uvs.as_ref()?;
        Some(u.iter().map(|v| v.to_array().map(f32::to_bits)).collect())
    }

    fn normal_bits(s: &PolygonSoup) -> Option<Vec<[u32; 3]>> {
        let n = s.vertex_normals.as_ref()?;
        Some(n.iter().map(|v| v.to_array().map(f32::to_bits)).collect())
    }

    /// A quad and a triangle with a UV seam at vertex 3 (two corners, two UVs), awkward UVs
    /// (a negative zero, a third, a tiny value, one outside 0–1), unnormalised and signed-zero
    /// normals, and colours off the 1/255 grid.
    const ATTRIBUTED_OBJ: &[u8] = b"# hand-written\n\
v 0 0 0 0.2 0.4 1\nv 1 0 0 0 0 0\nv 1 1 0 1 1 1\nv 0 1 0 0.5 0.123 0.999\nv 0.5 2 0 0.3 0.3 0.3\n\
vt -0 0.33333334\nvt 1 1e-7\nvt 1 1\nvt 0 1\nvt 2.5 -3\nvt 0.25 0.75\n\
vn 0 0 1\nvn -0 0.6 0.8\nvn 1e-20 0 -1\nvn 0.5773503 0.5773503 0.5773503\nvn 0 0 2\n\
f 1/1/1 2/2/2 3/3/3 4/4/4\nf 4/6/4 3/3/3 5/5/5\n";

    /// The soup of a mesh walked element by element through the world (face by face from one
    /// halfedge before its own, each corner's UV, each vertex's normal and colour): what
    /// `to_soup` read before it read the tables, kept here as the reference.
    fn soup_by_elements(world: &bevy::prelude::World, mesh: crate::mesh::MeshId) -> PolygonSoup {
        use crate::mesh::attributes::{CornerUv, MeshAttributes, VertexColor, VertexNormal};
        let has = MeshAttributes::of(world, mesh);
        let members = crate::mesh::MeshMembers::collect(world, mesh);
        let m = crate::mesh::MeshRef::new(world);
        let index = members.vertex_rows();
        let mut soup = PolygonSoup::with_capacity(0, 0, 0);
        soup.positions = members.vertices.iter().map(|&v| m.position(v)).collect();
        let mut uvs = has.uv.then(Vec::new);
        for &f in &members.faces {
            let first = m.prev(m.face_halfedge(f));
            let face: Vec<u32> = m
                .loop_from(first)
                .map(|h| index[&m.to_vertex(h).0])
                .collect();
            if let Some(uvs) = &mut uvs {
                uvs.extend(
                    m.loop_from(first)
                        .map(|h| world.get::<CornerUv>(h.0).map_or(Vec2::ZERO, |c| c.0)),
                );
            }
            soup.push_face(&face);
        }
        soup.corner_uvs = uvs;
        if has.normals {
            let n = |v: &crate::mesh::ids::VertexId| {
                world.get::<VertexNormal>(v.0).map_or(Vec3::ZERO, |x| x.0)
            };
            soup.vertex_normals = Some(members.vertices.iter().map(n).collect());
        }
        if has.colors {
            let c = |v: &crate::mesh::ids::VertexId| {
                world.get::<VertexColor>(v.0).map_or([0; 3], |x| x.0)
            };
            soup.vertex_colors = Some(members.vertices.iter().map(c).collect());
        }
        soup
    }

    /// The soup read through the tables is the soup walked element by element, attributes and
    /// face starts included, before and after edits that reorder rows.
    #[test]
    fn the_soup_read_through_the_tables_is_the_mesh_element_by_element() {
        let soup = read_bytes(Format::Obj, ATTRIBUTED_OBJ, name()).unwrap();
        let mut world = bevy::prelude::World::new();
        let mesh = crate::mesh::build_mesh(&mut world, &soup, Default::default())
            .unwrap()
            .mesh;
        let same = |world: &bevy::prelude::World| {
            assert_eq!(
                crate::mesh::to_soup(world, mesh),
                soup_by_elements(world, mesh)
            );
        };
        same(&world);
        crate::ops::triangulate::triangulate(&mut world, mesh);
        same(&world);
        crate::edit::Scheme::Loop
            .subdivide(&mut world, mesh, 1)
            .unwrap();
        same(&world);
        // Holes, and every shared model (repaired, polygons, UVs) where they are.
        let mut soups = vec![crate::mesh::shapes::grid_with_holes(2)];
        let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
        for entry in std::fs::read_dir(models).into_iter().flatten().flatten() {
            if entry.path().extension().is_some_and(|e| e == "obj") {
                soups.push(read(&entry.path()).unwrap());
            }
        }
        for soup in soups {
            let mut world = bevy::prelude::World::new();
            let built = crate::mesh::build_mesh(&mut world, &soup, Default::default()).unwrap();
            assert_eq!(
                crate::mesh::to_soup(&world, built.mesh),
                soup_by_elements(&world, built.mesh)
            );
        }
    }

    #[test]
    fn obj_attributes_survive_the_mesh_bit_for_bit() {
        let input = read_bytes(Format::Obj, ATTRIBUTED_OBJ, name()).unwrap();
        assert!(input.notes.is_empty(), "{:?}", input.notes);
        let back = through_mesh(Format::Obj, ATTRIBUTED_OBJ);
        assert!(same_bits(&back, &input));
        assert_eq!(uv_bits(&back), uv_bits(&input));
        assert_eq!(normal_bits(&back), normal_bits(&input));
        assert_eq!(
            back.vertex_colors,
            Some(vec![
                [51, 102, 255],
                [0, 0, 0],
                [255, 255, 255],
                [128, 31, 255],
                [77, 77, 77]
            ])
        );
        // The seam: vertex 3 (index 3) has UV (0, 1) in the quad and (0.25, 0.75) in the triangle.
        let uvs = back.corner_uvs.as_ref().unwrap();
        assert_eq!(
            (uvs[3], uvs[4]),
            (Vec2::new(0.0, 1.0), Vec2::new(0.25, 0.75))
        );
        // Written and read again: the same file, byte for byte, and the same values.
        let once = write_bytes(Format::Obj, &back).unwrap();
        let twice = write_bytes(Format::Obj, &through_mesh(Format::Obj, &once)).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&once),
            String::from_utf8_lossy(&twice)
        );
        let text = String::from_utf8(once).unwrap();
        assert!(text.contains("vt -0 0.33333334\n"), "{text}");
        assert!(text.contains("f 4/5/4 3/3/3 5/6/5\n"), "{text}");
        assert_eq!(
            text.matches("vt ").count(),
            6,
            "identical UVs are written once"
        );
    }

    #[test]
    fn ply_attributes_survive_the_mesh_bit_for_bit() {
        let obj = read_bytes(Format::Obj, ATTRIBUTED_OBJ, name()).unwrap();
        // With the seam: per-face `texcoord`; without it, per-vertex `u v`.
        let mut seamless = obj.clone();
        seamless.corner_uvs.as_mut().unwrap()[4] = Vec2::new(0.0, 1.0);
        for (soup, layout) in [(&obj, "texcoord"), (&seamless, "property float u\n")] {
            for encoding in [
                PlyEncoding::Ascii,
                PlyEncoding::BinaryLittleEndian,
                PlyEncoding::BinaryBigEndian,
            ] {
                let bytes = write_ply(soup, encoding);
                assert!(
                    String::from_utf8_lossy(&bytes).contains(layout),
                    "{encoding:?}"
                );
                let back = through_mesh(Format::Ply, &bytes);
                assert!(same_bits(&back, soup), "{encoding:?}");
                assert_eq!(uv_bits(&back), uv_bits(soup), "{encoding:?} {layout}");
                assert_eq!(normal_bits(&back), normal_bits(soup), "{encoding:?}");
                assert_eq!(back.vertex_colors, soup.vertex_colors, "{encoding:?}");
                assert_eq!(write_ply(&back, encoding), bytes, "{encoding:?}");
            }
        }
    }

    #[test]
    fn obj_colours_round_trip_every_byte() {
        let soup = PolygonSoup {
            vertex_colors: Some((0..=255u8).map(|c| [c, 255 - c, c / 3]).collect()),
            ..PolygonSoup::from_faces(vec![Vec3::ZERO; 256], &[[0u32, 1, 2]])
        };
        let back = read_bytes(
            Format::Obj,
            &write_bytes(Format::Obj, &soup).unwrap(),
            name(),
        )
        .unwrap();
        assert_eq!(back.vertex_colors, soup.vertex_colors);
    }

    #[test]
    fn broken_attribute_references_name_the_line() {
        let cases: [(&[u8], &str, &str); 4] = [
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n\nf 1/1 2/9 3/1\n",
                "line 6",
                "texture coordinate 9 does not exist (the file defines 1)",
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//-2 3//1\n",
                "line 5",
                "normal -2 does not exist (the file defines 1)",
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/0 2/1 3/1\nvt 0 0\n",
                "line 4",
                "`1/0` names texture coordinate 0 (they are numbered from 1)",
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/a 2/1 3/1\n",
                "line 5",
                "`1/a`: `a` is not a texture coordinate reference",
            ),
        ];
        for (text, location, message) in cases {
            let err = read_bytes(Format::Obj, text, Path::new("m.obj")).unwrap_err();
            assert_eq!(err.to_string(), format!("m.obj: {location}: {message}"));
        }
        // A `vt` defined after the face that names it is fine.
        let soup = read_bytes(
            Format::Obj,
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/2\nvt 0 0\nvt 1 1\n",
            name(),
        )
        .unwrap();
        assert_eq!(soup.corner_uvs.unwrap()[2], Vec2::ONE);
    }

    #[test]
    fn differing_corner_normals_are_averaged_and_said() {
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 1 0 0\nf 1//1 2//1 3//1\nf 2//2 4//2 3//1\n";
        let soup = read_bytes(Format::Obj, text, name()).unwrap();
        let n = soup.vertex_normals.unwrap();
        assert_eq!(n[0], Vec3::Z);
        assert_eq!(n[1], Vec3::new(1.0, 0.0, 1.0).normalize());
        assert_eq!(n[3], Vec3::X);
        assert_eq!(soup.notes.len(), 1, "{:?}", soup.notes);
        assert!(soup.notes[0].starts_with("1 vertex(es) had different normals"));
    }
}
