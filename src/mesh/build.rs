//! Polygon soup → entities (with repairs), and entities → polygon soup.
//!
//! [`build_mesh`] is the one way a mesh enters a world: it repairs the soup
//! ([`super::repair`]), lays out the halfedge tables ([`Connectivity::from_corners`]) and
//! spawns them ([`spawn_tables`]). Every element is spawned once, already linked, so no
//! element is ever seen half-built. The flat tables, and the passes between them and the
//! entities, live in [`super::tables`]; this module only joins the soup to them.

use bevy::math::{Vec2, Vec3};
use bevy::prelude::World;
use thiserror::Error;

use super::attributes::{AttributeColumns, CornerUv, MeshAttributes, VertexColor, VertexNormal};
use super::elements::{Face, Halfedge, MeshInfo, Position, Vertex};
use super::groups::{FaceGroup, FaceGroups, GroupTable};
use super::ids::{FaceId, MeshId, VertexId, slot};
use super::members::MeshMembers;
use super::repair::{RepairReport, RepairedFaces, repair};
use super::soup::PolygonSoup;
use super::tables::read::for_each_element;
use super::tables::{Connectivity, NONE, spawn_tables};
use crate::process_memory;

/// Why a soup could not become a mesh at all (local defects are repaired, not errors).
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BuildError {
    /// Nothing was left to build after the repairs (or the input had no faces).
    #[error("no usable faces: {faces} face(s) in the input, {report}")]
    NoFaces {
        /// Faces in the input.
        faces: usize,
        /// What the repair dropped.
        report: RepairReport,
    },
    /// The mesh is larger than 32-bit indices can address.
    #[error("mesh too large: {0} face corners (the limit is 2^31)")]
    TooLarge(usize),
}

/// A freshly built mesh and what it took to build it.
#[derive(Clone, Debug)]
pub struct BuiltMesh {
    /// The new mesh entity.
    pub mesh: MeshId,
    /// Every repair made on the way.
    pub report: RepairReport,
    /// For each vertex of the input soup, the vertex it became (`None` if dropped). Lets scripts
    /// name elements by their index in the input file.
    pub input_vertices: Vec<Option<VertexId>>,
    /// Each face with the input face it came from (several faces share one where the repairs
    /// cut a face), when the soup carries [`face_scalars`](PolygonSoup::face_scalars): their
    /// only reader. Empty otherwise, so that a load without them pays nothing for it.
    pub face_sources: Vec<(FaceId, u32)>,
}

/// A soup repaired and laid out as tables, not yet in any world: what [`build_mesh`] computes
/// before it spawns, so that it can run away from the world (the editor opens a large file on
/// another thread and only spawns on its own).
#[derive(Clone, Debug)]
pub struct PreparedMesh {
    connectivity: Connectivity,
    report: RepairReport,
    /// For each input vertex, its vertex row ([`NONE`] if dropped).
    input_vertex: Vec<u32>,
    /// For each face row, its input face, when the soup has face scalars (else empty).
    input_face: Vec<u32>,
}

impl PreparedMesh {
    /// The repairs made.
    pub fn report(&self) -> &RepairReport {
        &self.report
    }

    /// Its tables, as they will be spawned (rows in the same order).
    pub fn tables(&self) -> &Connectivity {
        &self.connectivity
    }

    /// How many vertices and faces the mesh will have.
    pub fn counts(&self) -> (usize, usize) {
        (
            self.connectivity.vertex_count(),
            self.connectivity.face_count(),
        )
    }
}

/// Repairs `soup` and lays it out as tables (see [`super::repair`]); touches no world.
///
/// # Errors
/// [`BuildError::NoFaces`] if no face survives the repairs, [`BuildError::TooLarge`] past
/// 32-bit indices.
pub fn prepare_mesh(soup: &PolygonSoup) -> Result<PreparedMesh, BuildError> {
    if soup.indices.len() >= 1 << 31 {
        return Err(BuildError::TooLarge(soup.indices.len()));
    }
    let bytes = soup.indices.len().saturating_mul(PREPARED_BYTES_PER_CORNER);
    process_memory::faulting_in_ahead(bytes, || repair_and_lay_out(soup))
}

/// About how many bytes of fresh memory preparing a mesh writes per face corner, at most: the
/// repair's working arrays (the corners, their input corners and faces, each edge's entries
/// sorted, the twins, the fans' union-find: 28 bytes a corner), then the tables (six columns
/// a halfedge: 24), with the vertices' and faces' share (about 16 a corner on a triangle mesh).
/// It sets how far around the heap's top [`prepare_mesh`] faults pages in ahead; that walk
/// never runs more than [`process_memory::FAULT_AHEAD_BYTES`] past what is allocated, so an
/// estimate too large leaves nothing more resident.
const PREPARED_BYTES_PER_CORNER: usize = 68;

/// [`prepare_mesh`]'s work, on the calling thread.
fn repair_and_lay_out(soup: &PolygonSoup) -> Result<PreparedMesh, BuildError> {
    let (faces, report) = repair(soup);
    if faces.face_count() == 0 {
        return Err(BuildError::NoFaces {
            faces: soup.face_count(),
            report,
        });
    }
    let mut connectivity = Connectivity::from_corners(faces.corners());
    connectivity.attributes = attribute_columns(soup, &faces, &connectivity);
    let input_face = match soup.face_scalars.is_empty() {
        true => Vec::new(),
        false => input_faces(soup, &faces),
    };
    Ok(PreparedMesh {
        connectivity,
        report,
        input_vertex: faces.input_vertex,
        input_face,
    })
}

/// Spawns a prepared mesh into `world`: every element once, already linked
/// ([`spawn_tables`]).
pub fn spawn_prepared(world: &mut World, prepared: PreparedMesh, info: MeshInfo) -> BuiltMesh {
    let (mesh, rows) = spawn_tables(world, prepared.connectivity, info);
    let input_vertices = prepared
        .input_vertex
        .iter()
        .map(|&v| (v != NONE).then(|| rows.vertex(v)))
        .collect();
    let face_sources = (0..)
        .zip(prepared.input_face)
        .map(|(f, input)| (rows.face(f), input))
        .collect();
    BuiltMesh {
        mesh,
        report: prepared.report,
        input_vertices,
        face_sources,
    }
}

/// Builds a mesh from `soup` into `world`, repairing what it must (see [`super::repair`]):
/// [`prepare_mesh`] then [`spawn_prepared`].
///
/// # Errors
/// [`BuildError::NoFaces`] if no face survives the repairs; the world is then untouched.
pub fn build_mesh(
    world: &mut World,
    soup: &PolygonSoup,
    info: MeshInfo,
) -> Result<BuiltMesh, BuildError> {
    let prepared = prepare_mesh(soup)?;
    Ok(spawn_prepared(world, prepared, info))
}

/// The soup's corner UVs, normals and colours as table columns for the repaired faces laid out
/// as `c` (halfedge `k < corners` is corner `k`, whose corner in the UV sense is the next
/// corner's vertex). Only the attributes the soup holds completely ([`PolygonSoup::attributes`]).
fn attribute_columns(
    soup: &PolygonSoup,
    faces: &RepairedFaces,
    c: &Connectivity,
) -> AttributeColumns {
    let has = soup.attributes();
    let mut columns = AttributeColumns::default();
    if has.is_empty() {
        return columns;
    }
    let source = &faces.source_corner;
    if let Some(uvs) = soup.corner_uvs.as_deref().filter(|_| has.uv) {
        let mut uv = vec![Vec2::ZERO; c.twin.len()];
        for (k, slot) in uv.iter_mut().enumerate().take(source.len()) {
            *slot = uvs[source[c.next[k] as usize] as usize];
        }
        columns.uv = Some(uv);
    }
    // Each repaired vertex takes the values of the input vertex of any of its corners.
    let input_of = |vertex_count: usize| {
        let mut input = vec![0u32; vertex_count];
        for (k, &v) in faces.indices.iter().enumerate() {
            input[v as usize] = soup.indices[source[k] as usize];
        }
        input
    };
    let input = (has.normals || has.colors).then(|| input_of(c.positions.len()));
    if let (Some(normals), Some(input)) = (soup.vertex_normals.as_deref(), &input)
        && has.normals
    {
        columns.normals = Some(input.iter().map(|&i| normals[i as usize]).collect());
    }
    if let (Some(colors), Some(input)) = (soup.vertex_colors.as_deref(), &input)
        && has.colors
    {
        columns.colors = Some(input.iter().map(|&i| colors[i as usize]).collect());
    }
    if let Some(groups) = soup.face_groups.as_ref().filter(|_| has.groups) {
        let input = input_faces(soup, faces);
        let of_face = input.iter().map(|&f| groups.of_face[f as usize]).collect();
        columns.groups = Some(FaceGroups {
            table: groups.table.clone(),
            of_face,
        });
    }
    columns
}

/// For each repaired face, the input face its first corner came from. The repairs keep the
/// input's face order, so the search walks forward from the last face found; a face out of
/// that order is found by bisection.
fn input_faces(soup: &PolygonSoup, faces: &RepairedFaces) -> Vec<u32> {
    let (starts, n) = (&soup.face_starts, soup.face_count());
    let mut at = 0;
    let mut out = Vec::with_capacity(faces.face_count());
    for &first in faces.face_starts.iter().take(faces.face_count()) {
        let corner = faces.source_corner[first as usize];
        let inside = |f: usize| f < n && starts[f] <= corner && corner < starts[f + 1];
        if !inside(at) {
            at = match inside(at + 1) {
                true => at + 1,
                false => starts.partition_point(|&s| s <= corner) - 1,
            };
        }
        out.push(at as u32);
    }
    out
}

/// The mesh as a polygon soup: vertices in table order, faces as vertex cycles, with the
/// attributes the mesh has (corner UVs, vertex normals and colours, face groups). The inverse
/// of [`build_mesh`] up to the repairs, and exactly [`soup_of_tables`] of the mesh's
/// [`extract`](super::tables::extract)ed tables.
///
/// Read straight from the entities, without the tables: each kind in storage order (the
/// tables' row order), each face walked through its halfedges, a vertex's row found through
/// an array indexed by vertex entity. Saving a mesh of a million faces so holds the soup and
/// that array above the World (about 30 bytes a face), where the tables and the list of every
/// element's entity took 190.
pub fn to_soup(world: &World, mesh: MeshId) -> PolygonSoup {
    let (mut vertex_count, mut slots) = (0, 0);
    for_each_element::<&Vertex>(world, mesh, |e, _| {
        vertex_count += 1;
        slots = slots.max(slot(e) + 1);
    });
    let (mut face_count, mut corners) = (0, 0);
    for_each_element::<&Face>(world, mesh, |_, _| face_count += 1);
    for_each_element::<&Halfedge>(world, mesh, |_, h| corners += usize::from(h.face.is_some()));
    let mut soup = PolygonSoup::with_capacity(vertex_count, face_count, corners);
    let mut vertex_row = vec![NONE; slots];
    for_each_element::<(&Vertex, &Position)>(world, mesh, |e, (_, p)| {
        vertex_row[slot(e)] = soup.positions.len() as u32;
        soup.positions.push(p.0);
    });
    let has = MeshAttributes::of(world, mesh);
    let mut uvs = has.uv.then(|| Vec::with_capacity(corners));
    // Registered wherever a face is (a mesh without faces has none to walk); UVs where the
    // mesh has them.
    let mut halfedges = world.try_query::<&Halfedge>();
    let mut corner_uvs = world.try_query::<&CornerUv>().filter(|_| has.uv);
    let mut face = Vec::new();
    for_each_element::<&Face>(world, mesh, |_, f| {
        face.clear();
        let first = match halfedges.as_mut().map(|q| q.get(world, f.halfedge.0)) {
            Some(Ok(start)) => start.prev,
            _ => return,
        };
        let mut h = first;
        while let Some(Ok(x)) = halfedges.as_mut().map(|q| q.get(world, h.0)) {
            face.push(vertex_row[slot(x.vertex.0)]);
            if let Some(out) = &mut uvs {
                let uv = corner_uvs.as_mut().and_then(|q| q.get(world, h.0).ok());
                out.push(uv.map_or(Vec2::ZERO, |uv| uv.0));
            }
            h = x.next;
            if h == first {
                break;
            }
        }
        soup.push_face(&face);
    });
    soup.corner_uvs = uvs;
    if has.normals {
        let mut normals = Vec::with_capacity(vertex_count);
        for_each_element::<(&Vertex, Option<&VertexNormal>)>(world, mesh, |_, (_, n)| {
            normals.push(n.map_or(Vec3::ZERO, |n| n.0));
        });
        soup.vertex_normals = Some(normals);
    }
    if has.colors {
        let mut colors = Vec::with_capacity(vertex_count);
        for_each_element::<(&Vertex, Option<&VertexColor>)>(world, mesh, |_, (_, c)| {
            colors.push(c.map_or([0; 3], |c| c.0));
        });
        soup.vertex_colors = Some(colors);
    }
    if has.groups
        && let Some(table) = world.get::<GroupTable>(mesh.0)
    {
        let mut of_face = Vec::with_capacity(face_count);
        for_each_element::<(&Face, Option<&FaceGroup>)>(world, mesh, |_, (_, g)| {
            of_face.push(g.map_or(0, |g| g.0));
        });
        soup.face_groups = Some(FaceGroups {
            table: table.clone(),
            of_face,
        });
    }
    soup
}

/// The polygon soup of a mesh's tables ([`super::tables::extract`]): what [`to_soup`] gives,
/// computable away from the world (the editor's autosave reads the tables on its frame and
/// makes the soup on its writing thread). Each face starts one halfedge before its own, so it
/// lists its vertices in the order it was built from.
pub fn soup_of_tables(t: &Connectivity) -> PolygonSoup {
    let corners = t.halfedges().filter(|&h| !t.is_boundary(h)).count();
    let mut soup = PolygonSoup::with_capacity(t.vertex_count(), t.face_count(), corners);
    soup.positions.extend_from_slice(&t.positions);
    let mut face = Vec::new();
    let mut uvs = t
        .attributes
        .uv
        .as_ref()
        .map(|uv| (uv, Vec::with_capacity(corners)));
    for f in t.faces() {
        let first = t.prev(t.face_halfedge(f));
        face.clear();
        let mut h = first;
        loop {
            face.push(t.to_vertex(h).index() as u32);
            if let Some((uv, out)) = &mut uvs {
                out.push(uv[h.index()]);
            }
            h = t.next(h);
            if h == first {
                break;
            }
        }
        soup.push_face(&face);
    }
    soup.corner_uvs = uvs.map(|(_, out)| out);
    soup.vertex_normals.clone_from(&t.attributes.normals);
    soup.vertex_colors.clone_from(&t.attributes.colors);
    soup.face_groups.clone_from(&t.attributes.groups);
    soup
}

/// Despawns a mesh and every element in it. Returns how many entities went.
pub fn despawn_mesh(world: &mut World, mesh: MeshId) -> usize {
    let members = MeshMembers::collect(world, mesh);
    let mut count = 0;
    for e in members.entities() {
        count += usize::from(world.despawn(e));
    }
    count + usize::from(world.despawn(mesh.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::groups::Group;
    use crate::mesh::shapes;
    use crate::mesh::tables::extract;
    use crate::ops::local::{CollapseOptions, collapse_edge, flip_edge, split_edge};

    /// A soup with every attribute a soup carries: corner UVs, vertex normals and colours,
    /// face groups.
    fn with_every_attribute(mut soup: PolygonSoup) -> PolygonSoup {
        let (corners, vertices, faces) =
            (soup.indices.len(), soup.positions.len(), soup.face_count());
        soup.corner_uvs = Some((0..corners).map(|k| Vec2::new(k as f32, 0.25)).collect());
        soup.vertex_normals = Some(
            (0..vertices)
                .map(|v| Vec3::new(0.0, v as f32, 1.0))
                .collect(),
        );
        soup.vertex_colors = Some((0..vertices).map(|v| [v as u8, 7, 9]).collect());
        let group = |name: &str| Group {
            group: Some(name.into()),
            ..Group::default()
        };
        soup.face_groups = Some(FaceGroups {
            table: GroupTable {
                material_libraries: Vec::new(),
                groups: vec![group("a"), group("b")],
            },
            of_face: (0..faces as u32).map(|f| f % 2).collect(),
        });
        soup
    }

    /// Read straight from the entities, the soup is the one the tables give, bit for bit:
    /// closed and open meshes, with and without attributes, freshly built and after local
    /// edits have scattered the rows' entities and storage.
    #[test]
    fn the_soup_read_from_the_entities_is_the_tables_soup() {
        let soups = [
            shapes::icosphere(2),
            shapes::grid_with_holes(3),
            with_every_attribute(shapes::grid_with_holes(2)),
            with_every_attribute(shapes::torus(6, 5)),
        ];
        for soup in soups {
            let mut world = World::new();
            let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
                .unwrap()
                .mesh;
            let of_tables = |world: &World| soup_of_tables(&extract(world, mesh).tables);
            assert_eq!(to_soup(&world, mesh), of_tables(&world));
            let edges = MeshMembers::collect(&world, mesh).edges;
            // Some edits are refused (an edge gone with an earlier collapse, a flip that would
            // break the mesh); the mesh stays valid either way.
            for (k, &e) in edges.iter().enumerate().step_by(2) {
                let _ = match k % 3 {
                    0 => split_edge(&mut world, e, 0.3).map(drop),
                    1 => flip_edge(&mut world, e).map(drop),
                    _ => collapse_edge(&mut world, e, CollapseOptions::default()).map(drop),
                };
            }
            assert!(crate::mesh::validate(&world, mesh).is_ok());
            assert_eq!(to_soup(&world, mesh), of_tables(&world));
        }
    }

    /// Each face names the input face it came from, a dropped face leaving a gap; a soup
    /// without face scalars pays nothing for it.
    #[test]
    fn faces_name_their_input_face_when_the_soup_has_face_scalars() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
        // The middle face repeats a vertex and is dropped.
        let mut soup = PolygonSoup::from_faces(positions, &[[0, 1, 2], [0, 0, 1], [1, 3, 2]]);
        let mut world = World::new();
        let plain = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        assert!(plain.face_sources.is_empty());
        soup.face_scalars = vec![("w".to_string(), vec![10.0, 20.0, 30.0])];
        let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
        let faces = MeshMembers::collect(&world, built.mesh).faces;
        let sources: Vec<(FaceId, u32)> = faces.iter().copied().zip([0, 2]).collect();
        assert_eq!(built.face_sources, sources);
    }
}
