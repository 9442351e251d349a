//! glTF 2.0 (`.gltf` with `.bin` files or embedded data, `.glb`), read and written with the
//! `gltf` crate, the one Bevy's loader uses.
//!
//! **Reading** walks the default scene (else the first; a file without scenes places each mesh
//! once) with every node's transform applied, and reads every primitive drawn as `TRIANGLES`,
//! `TRIANGLE_STRIP` or `TRIANGLE_FAN` ([`super::strips`] for strips); points and lines are counted
//! in the notes, as are skins, animations, morph targets, cameras, materials' properties and
//! textures. Each face keeps its primitive's material name and its node's name as its face group
//! ([`super::parts`]). What the document must be to be read (its version, its required extensions,
//! the `gltf` crate's validation, with what is tolerated) is [`document`]'s. Attributes:
//! `POSITION`, `NORMAL`, `TEXCOORD_0` (any component type `KHR_mesh_quantization` allows,
//! normalised integers scaled as glTF says, [`values`]; glTF's `v` runs down the image, so it is
//! flipped, `v = 1 − v′`, as OBJ and Blender count it), `COLOR_0` (RGB or RGBA, alpha dropped);
//! indices of any width; sparse accessors. glTF splits a vertex wherever an attribute differs (a UV
//! seam, a hard edge): reading welds the vertices of one mesh that sit at the same position (bit
//! for bit, `−0` as `+0`), so a closed surface comes back closed — or, in a file Pappus wrote, the
//! vertices that copy one mesh vertex ([`VERTEX_ATTRIBUTE`]), so that two distinct vertices that
//! coincide stay two — and keeps the split values per corner: UVs as they are; normals and colours,
//! which Pappus keeps per vertex, as their mean where the corners differ (said in the notes).
//!
//! **Writing** ([`mod@write`]) is a scene of one node and one mesh of one triangle primitive:
//! polygons fan-triangulated (said by the caller: a polygon's face is not kept as one), a vertex written once per distinct (position, UV) pair, normals and
//! colours per vertex. `.glb` by default, `.gltf` with the buffer embedded as a data URI.

mod buffers;
mod document;
mod draco;
mod values;
mod write;

use bevy::math::{Mat4, Vec2, Vec3};
use bevy::platform::collections::HashMap as FastMap;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use std::path::Path;

use super::parts::{NO_POSITION, Part, assemble};
use super::skipped::Skipped;
use super::strips::strip_triangles;
use crate::io::error::ParseError;
use crate::mesh::groups::Group;
use crate::mesh::soup::PolygonSoup;
use buffers::Buffers;
pub(super) use write::write;

/// An application-specific attribute (glTF §3.7.2.1: a name starting with `_`) that Pappus
/// writes: for each vertex, the mesh vertex it is a copy of (`VEC2` of `u16`, low and high
/// halves). Reading joins the copies by it, exactly, where a file has it; other files' vertices
/// are joined by position. Other readers ignore it (Blender keeps it as a generic attribute).
pub(super) const VERTEX_ATTRIBUTE: &str = "_PAPPUS_VERTEX";

/// Node trees nested deeper than this are refused (a cycle, which validation does not catch).
const MAX_DEPTH: usize = 64;

/// Scenes that walk more nodes than this are refused.
const MAX_NODES: usize = 1 << 20;

/// Reads a glTF or GLB document; external buffers are looked for in `folder`.
///
/// # Errors
/// A document the `gltf` crate does not parse or validate, a buffer that cannot be resolved,
/// an accessor that cannot be read safely, or a scene too large for the memory budget.
pub fn read(bytes: &[u8], folder: Option<&Path>) -> Result<PolygonSoup, ParseError> {
    let error = |message: String| ParseError::byte(0, message);
    let document::Parsed {
        document,
        blob,
        notes,
    } = document::parse(bytes)?;
    let buffers = Buffers::resolve(&document, blob, folder).map_err(error)?;
    let placements = placements(&document).map_err(error)?;
    let keyed: Vec<_> = placements
        .iter()
        .map(|(mesh, transform, name)| (mesh.index(), *transform, name.as_str()))
        .collect();
    let (mut soup, parts) = assemble(&keyed, |index| {
        let mesh = document.meshes().nth(index);
        mesh.map(|mesh| read_mesh(&mesh, &document, &buffers))
            .transpose()
            .map_err(|e| ParseError::byte(0, e).unsupported())
    })?;
    let mut skipped = Skipped::default();
    for part in parts.values().flatten() {
        skipped.add(&part.skipped);
    }
    skipped.count(
        "skin(s) (meshes read in their bind pose)",
        document.skins().count(),
    );
    skipped.count("animation(s)", document.animations().count());
    skipped.count("camera(s)", document.cameras().count());
    // A file Pappus wrote has materials of a name only, which its groups keep.
    let written_by_pappus = parts.values().flatten().any(|p| p.exact_groups);
    if !written_by_pappus {
        skipped.count(
            "material(s) (their names kept as face groups, not their properties)",
            document.materials().count(),
        );
    }
    skipped.count("texture(s)", document.textures().count());
    soup.notes.extend(notes);
    soup.notes.extend(skipped.note());
    Ok(soup)
}

/// Every mesh the scene draws, with its transform and a name (the node's, else the mesh's).
fn placements(document: &gltf::Document) -> Result<Vec<(gltf::Mesh<'_>, Mat4, String)>, String> {
    let mut out = Vec::new();
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next());
    let Some(scene) = scene else {
        for mesh in document.meshes() {
            let name = mesh
                .name()
                .map_or_else(|| format!("mesh {}", mesh.index()), str::to_owned);
            out.push((mesh, Mat4::IDENTITY, name));
        }
        return Ok(out);
    };
    let mut walked = 0usize;
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    stack.reverse();
    while let Some((node, parent, depth)) = stack.pop() {
        walked += 1;
        if depth > MAX_DEPTH || walked > MAX_NODES {
            return Err(format!(
                "the scene's nodes nest deeper than {MAX_DEPTH} or number more than {MAX_NODES} (a cycle?)"
            ));
        }
        let transform = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let name = node
                .name()
                .or_else(|| mesh.name())
                .map_or_else(|| format!("node {}", node.index()), str::to_owned);
            out.push((mesh, transform, name));
        }
        let children: Vec<_> = node.children().collect();
        stack.extend(
            children
                .into_iter()
                .rev()
                .map(|c| (c, transform, depth + 1)),
        );
    }
    Ok(out)
}

/// The accessor types glTF allows for each attribute Pappus reads, with those
/// `KHR_mesh_quantization` adds ([`values`]).
const POSITIONS: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec3),
    (DataType::I8, Dimensions::Vec3),
    (DataType::U8, Dimensions::Vec3),
    (DataType::I16, Dimensions::Vec3),
    (DataType::U16, Dimensions::Vec3),
];
const NORMALS: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec3),
    (DataType::I8, Dimensions::Vec3),
    (DataType::I16, Dimensions::Vec3),
];
const TEXCOORDS: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec2),
    (DataType::I8, Dimensions::Vec2),
    (DataType::U8, Dimensions::Vec2),
    (DataType::I16, Dimensions::Vec2),
    (DataType::U16, Dimensions::Vec2),
];
const COLORS: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec3),
    (DataType::U8, Dimensions::Vec3),
    (DataType::U16, Dimensions::Vec3),
    (DataType::F32, Dimensions::Vec4),
    (DataType::U8, Dimensions::Vec4),
    (DataType::U16, Dimensions::Vec4),
];
const VERTEX_IDS: &[(DataType, Dimensions)] = &[(DataType::U16, Dimensions::Vec2)];
const INDICES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Scalar),
    (DataType::U16, Dimensions::Scalar),
    (DataType::U32, Dimensions::Scalar),
];

/// What joins a primitive's vertices into one mesh vertex.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Weld {
    /// The position's bits (`−0` as `+0`).
    Position([u32; 3]),
    /// The mesh vertex [`VERTEX_ATTRIBUTE`] names.
    Vertex(u32),
}

/// One primitive's vertex data, as read.
struct Vertices {
    positions: Vec<Vec3>,
    /// [`VERTEX_ATTRIBUTE`], where the file has it.
    ids: Option<Vec<u32>>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec3>>,
}

/// Reads a mesh's triangle primitives into one part, welding vertices at the same position.
fn read_mesh(
    mesh: &gltf::Mesh,
    document: &gltf::Document,
    buffers: &Buffers,
) -> Result<Part, String> {
    let mut part = Part::new();
    part.material_libraries = extras_field(mesh.extras(), LIBRARIES_EXTRA)
        .and_then(|v| serde_json::from_value(v).ok())
        .unwrap_or_default();
    let mut welded: FastMap<Weld, u32> = FastMap::default();
    for primitive in mesh.primitives() {
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            let what = if mode == Mode::Points {
                "point primitive(s)"
            } else {
                "line primitive(s)"
            };
            part.skipped.count(what, 1);
            continue;
        }
        part.skipped
            .count("morph target(s)", primitive.morph_targets().count());
        let draco = draco::decode(&primitive, document, buffers)?;
        let Some(vertices) = read_vertices(&primitive, buffers, draco.as_ref())? else {
            part.skipped.count("primitive(s) without positions", 1);
            continue;
        };
        // This primitive's vertex `i` is the part's position `slot[i]`.
        let slot: Vec<u32> = vertices
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let key = match &vertices.ids {
                    Some(ids) => Weld::Vertex(ids[i]),
                    None => Weld::Position((p + Vec3::ZERO).to_array().map(f32::to_bits)),
                };
                *welded.entry(key).or_insert_with(|| {
                    part.positions.push(p);
                    (part.positions.len() - 1) as u32
                })
            })
            .collect();
        part.use_group(primitive_group(&primitive));
        part.exact_groups |= vertices.ids.is_some();
        let order = match &draco {
            Some(stream) => stream.triangles(),
            None => read_indices(&primitive, buffers, vertices.positions.len())?,
        };
        let mut triangle = |corners: [u32; 3]| {
            for i in corners {
                let i = i as usize;
                let index = slot.get(i).copied().unwrap_or(NO_POSITION);
                part.push_corner(
                    index,
                    value_at(&vertices.normals, i),
                    value_at(&vertices.uvs, i),
                    value_at(&vertices.colors, i),
                );
            }
            part.end_face();
        };
        match mode {
            Mode::Triangles => order
                .chunks_exact(3)
                .for_each(|t| triangle([t[0], t[1], t[2]])),
            Mode::TriangleFan => {
                for i in 1..order.len().saturating_sub(1) {
                    triangle([order[0], order[i], order[i + 1]]);
                }
            }
            _ => {
                strip_triangles(&order, |v| v).for_each(&mut triangle);
            }
        }
    }
    Ok(part)
}

/// The key of a primitive's `extras` under which Pappus records its faces' whole group (object,
/// group, material, smoothing group: each a string or absent), so that a file Pappus wrote
/// gives the groups back exactly. Other readers ignore it.
const GROUP_EXTRA: &str = "pappus_group";

/// The key of a mesh's `extras` under which Pappus records the material libraries (OBJ's
/// `mtllib`) of the mesh it wrote.
const LIBRARIES_EXTRA: &str = "pappus_material_libraries";

/// The value under `key` in an `extras` object, if it has one.
fn extras_field(extras: &gltf::json::Extras, key: &str) -> Option<serde_json::Value> {
    let raw = extras.as_ref()?;
    let mut value: serde_json::Value = serde_json::from_str(raw.get()).ok()?;
    Some(value.get_mut(key)?.take())
}

/// A primitive's faces' group: the one Pappus recorded, else the name of its material
/// (`material N` for one without a name; no material, no name).
fn primitive_group(primitive: &gltf::Primitive) -> Group {
    if let Some(recorded) = extras_field(primitive.extras(), GROUP_EXTRA) {
        let name = |key: &str| recorded.get(key)?.as_str().map(str::to_owned);
        return Group {
            object: name("object"),
            group: name("group"),
            material: name("material"),
            smoothing: name("smoothing"),
        };
    }
    let material = primitive.material();
    Group {
        material: material.index().map(|i| {
            material
                .name()
                .map_or_else(|| format!("material {i}"), str::to_owned)
        }),
        ..Group::default()
    }
}

/// Vertex `i`'s value of an attribute the primitive may not have.
fn value_at<T: Copy>(list: &Option<Vec<T>>, i: usize) -> Option<T> {
    list.as_ref().and_then(|l| l.get(i).copied())
}

/// A primitive's positions and the attributes Pappus reads; `None` without positions. An
/// attribute the primitive's Draco stream compresses is read from the stream, any other from
/// its accessor.
fn read_vertices(
    primitive: &gltf::Primitive,
    buffers: &Buffers,
    draco: Option<&draco::Decoded>,
) -> Result<Option<Vertices>, String> {
    use gltf::Semantic;
    let compressed = |semantic: &Semantic| draco.filter(|stream| stream.has(semantic));
    let positions: Vec<Vec3> = match compressed(&Semantic::Positions) {
        Some(stream) => stream
            .floats::<3>(&Semantic::Positions)?
            .unwrap_or_default(),
        None => {
            let Some(accessor) = primitive.get(&Semantic::Positions) else {
                return Ok(None);
            };
            buffers.check_accessor(&accessor, POSITIONS, "positions")?;
            values::floats::<3>(&accessor, buffers).ok_or("positions cannot be read")?
        }
    }
    .into_iter()
    .map(Vec3::from_array)
    .collect();
    let n = positions.len();
    // An uncompressed attribute's accessor, checked; `None` when the primitive lacks it.
    let accessor = |semantic: Semantic, allowed, what: &str| -> Result<_, String> {
        let Some(accessor) = primitive.get(&semantic) else {
            return Ok(None);
        };
        buffers.check_accessor(&accessor, allowed, what)?;
        if accessor.count() < n {
            return Err(format!("{what}: {} for {n} positions", accessor.count()));
        }
        Ok(Some(accessor))
    };
    // The attribute's values as `N` floats, from the stream or from its accessor.
    macro_rules! floats {
        ($n:literal, $semantic:expr, $allowed:expr, $what:expr) => {
            match compressed(&$semantic) {
                Some(stream) => stream.floats::<$n>(&$semantic)?,
                None => accessor($semantic, $allowed, $what)?
                    .and_then(|a| values::floats::<$n>(&a, buffers)),
            }
        };
    }
    let normals = floats!(3, Semantic::Normals, NORMALS, "normals")
        .map(|n| n.into_iter().map(Vec3::from_array).collect());
    // glTF's v runs down the image; Pappus's (OBJ's, Blender's) runs up.
    let uvs = floats!(2, Semantic::TexCoords(0), TEXCOORDS, "texture coordinates").map(|uvs| {
        uvs.into_iter()
            .map(|[u, v]| Vec2::new(u, 1.0 - v))
            .collect()
    });
    let bytes = |c: [f32; 3]| Vec3::from_array(c.map(|v| (v * 255.0).round().clamp(0.0, 255.0)));
    let colors = match compressed(&Semantic::Colors(0)) {
        Some(stream) => stream.floats::<3>(&Semantic::Colors(0))?,
        None => accessor(Semantic::Colors(0), COLORS, "colours")?.and_then(|_| {
            let reader = primitive.reader(|b| buffers.get(b));
            Some(reader.read_colors(0)?.into_rgb_f32().collect())
        }),
    }
    .map(|colors: Vec<[f32; 3]>| colors.into_iter().map(bytes).collect());
    let id_semantic = || Semantic::Extras(VERTEX_ATTRIBUTE[1..].into());
    let ids = match compressed(&id_semantic()) {
        Some(stream) => stream.floats::<2>(&id_semantic())?.map(|ids| {
            ids.into_iter()
                .map(|[low, high]| [low as u16, high as u16])
                .collect()
        }),
        None => accessor(id_semantic(), VERTEX_IDS, "vertex ids")?.and_then(|accessor| {
            Some(gltf::accessor::Iter::<[u16; 2]>::new(accessor, |b| buffers.get(b))?.collect())
        }),
    }
    .map(|ids: Vec<[u16; 2]>| {
        ids.into_iter()
            .map(|[low, high]| u32::from(low) | (u32::from(high) << 16))
            .collect()
    });
    Ok(Some(Vertices {
        positions,
        ids,
        normals,
        uvs,
        colors,
    }))
}

/// A primitive's vertex order: its indices, or every vertex in turn without them. An index
/// past the vertices stays, for the part to turn into [`NO_POSITION`].
fn read_indices(
    primitive: &gltf::Primitive,
    buffers: &Buffers,
    vertices: usize,
) -> Result<Vec<u32>, String> {
    let Some(accessor) = primitive.indices() else {
        return Ok((0..vertices as u32).collect());
    };
    buffers.check_accessor(&accessor, INDICES, "indices")?;
    let reader = primitive.reader(|b| buffers.get(b));
    Ok(reader
        .read_indices()
        .ok_or("indices cannot be read")?
        .into_u32()
        .collect())
}

#[cfg(test)]
mod tests;
