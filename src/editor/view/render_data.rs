//! What a list of faces becomes on the GPU, built on the CPU: [`render_data`] (positions,
//! normals for smooth shading, fan-triangulated indices, the face of each triangle for picking,
//! texture coordinates split at UV seams) and [`edge_lines`] (the real edges, each once, boundary
//! edges red). [`super::render_sync`] uploads them chunk by chunk, each with its
//! [`ChunkShape`] (the signed volume under its triangles and its box), and asks here whether a
//! redraw's faces lie beside the boundary ([`on_boundary`]) or were added apart from the rest
//! ([`added_apart`]): what [`super::culling`] needs to follow a mesh's closure through edits.

use bevy::asset::RenderAssetUsages;
use bevy::color::Color;
use bevy::ecs::entity::EntityHashMap;
use bevy::math::{Vec2, Vec3};
use bevy::mesh::{Indices, Mesh, Mesh3d, PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::{Assets, Component, Entity, World};

use crate::mesh::attributes::{CornerUv, MeshAttributes};
use crate::mesh::closure::{Closure, bounding_box};
use crate::mesh::ids::{FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;

use super::colouring::VertexValues;

/// Colour of interior edges in the wireframe.
pub const EDGE_COLOR: Color = Color::srgb(0.08, 0.08, 0.1);
/// Colour of boundary edges in the wireframe.
pub const BOUNDARY_COLOR: Color = Color::srgb(0.9, 0.15, 0.1);

/// The signed volume under a chunk's triangles and the box of its corners (a component of the
/// chunk): what [`super::culling`] sums to follow a mesh's closure through local edits.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct ChunkShape {
    /// The sum over its triangles `a b c` of the signed volume of the tetrahedron on the origin,
    /// `a · (b × c) / 6`.
    pub volume: f64,
    /// The smallest box holding its corners, `None` for a chunk without any.
    pub bounds: Option<(Vec3, Vec3)>,
}

impl ChunkShape {
    /// The shape of the triangles whose corners are `triangles` (three indices into `positions`
    /// a triangle).
    pub fn of(positions: &[[f32; 3]], triangles: impl IntoIterator<Item = usize>) -> Self {
        let corner = |i: usize| Vec3::from_array(positions[i]).as_dvec3();
        let mut corners = triangles.into_iter();
        let mut volume = 0.0;
        while let (Some(a), Some(b), Some(c)) = (corners.next(), corners.next(), corners.next()) {
            volume += corner(a).dot(corner(b).cross(corner(c))) / 6.0;
        }
        let bounds = bounding_box(positions.iter().map(|&p| Vec3::from_array(p)));
        Self { volume, bounds }
    }
}

/// The mesh vertex behind each render vertex of a chunk ([`RenderData::vertices`]): what a
/// refresh of positions reads.
#[derive(Component, Debug, Clone, Default)]
pub struct ChunkVertices(pub Vec<VertexId>);

/// The triangles a mesh's chunks draw, read back from their mesh assets: what its closure is
/// counted from apart from the frame (see [`super::culling`]).
pub struct DrawnTriangles(Vec<DrawnChunk>);

/// One chunk's triangles as drawn: the positions of its render vertices, its corners, and the
/// mesh vertex behind each render vertex.
struct DrawnChunk {
    positions: Vec<[f32; 3]>,
    corners: Vec<u32>,
    vertices: Vec<Entity>,
}

impl DrawnTriangles {
    /// Copies what `chunks` draw; `None` while a chunk is not drawn as its vertex list says
    /// (its mesh asset missing or of another size).
    pub fn read(world: &World, chunks: &[Entity]) -> Option<Self> {
        let meshes = world.get_resource::<Assets<Mesh>>()?;
        let mut drawn = Vec::new();
        for &chunk in chunks {
            let vertices = &world.get::<ChunkVertices>(chunk)?.0;
            let Some(handle) = world.get::<Mesh3d>(chunk) else {
                // A chunk left without faces draws nothing.
                if vertices.is_empty() {
                    continue;
                }
                return None;
            };
            let render = meshes.get(&handle.0)?;
            let (Some(VertexAttributeValues::Float32x3(positions)), Some(Indices::U32(corners))) =
                (render.attribute(Mesh::ATTRIBUTE_POSITION), render.indices())
            else {
                return None;
            };
            if positions.len() != vertices.len() {
                return None;
            }
            drawn.push(DrawnChunk {
                positions: positions.clone(),
                corners: corners.clone(),
                vertices: vertices.iter().map(|v| v.0).collect(),
            });
        }
        Some(Self(drawn))
    }

    /// Their closure ([`Closure::of_triangles`]), each mesh vertex once however many chunks
    /// (or UV seams) repeat it.
    pub fn close(self) -> Option<Closure> {
        let mut row: EntityHashMap<u32> = EntityHashMap::default();
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for chunk in self.0 {
            let rows: Vec<u32> = chunk
                .vertices
                .iter()
                .zip(&chunk.positions)
                .map(|(&v, &p)| {
                    *row.entry(v).or_insert_with(|| {
                        positions.push(Vec3::from_array(p));
                        positions.len() as u32 - 1
                    })
                })
                .collect();
            let corners = chunk.corners.iter().map(|&c| rows.get(c as usize).copied());
            triangles.extend(corners.collect::<Option<Vec<u32>>>()?);
        }
        Closure::of_triangles(positions, triangles)
    }
}

/// Triangles, normals and the triangle → face table for a list of faces.
#[derive(Debug, Clone, Default)]
pub struct RenderData {
    /// Vertex positions of the render mesh.
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals of the render mesh (smooth shading only; empty when flat).
    pub normals: Vec<[f32; 3]>,
    /// Triangle corners.
    pub indices: Vec<u32>,
    /// The face of each triangle.
    pub triangle_faces: Vec<FaceId>,
    /// The mesh vertex behind each render vertex (for colouring by a quantity).
    pub vertices: Vec<VertexId>,
    /// The face each render vertex belongs to, when drawn a face at a time
    /// ([`render_data_by_face`]; empty otherwise).
    pub vertex_faces: Vec<FaceId>,
    /// The texture coordinate of each render vertex (only when drawn with UVs; empty
    /// otherwise).
    pub uvs: Vec<[f32; 2]>,
    /// The summed length of the faces' sides (each interior edge counted from both faces).
    pub side_length: f64,
    /// The number of the faces' sides.
    pub sides: usize,
}

impl RenderData {
    /// The render mesh of these triangles: their positions and corners, the normals (smooth
    /// shading) and UVs (the checkerboard) when there are any, and `colours` (a quantity's) when
    /// given.
    pub fn into_mesh(self, colours: Option<Vec<[f32; 4]>>) -> Mesh {
        let mut render = Mesh::new(
            PrimitiveTopology::TriangleList,
            // Picking casts rays against the main-world copy: keep it.
            RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
        );
        render.insert_attribute(Mesh::ATTRIBUTE_POSITION, self.positions);
        if !self.normals.is_empty() {
            render.insert_attribute(Mesh::ATTRIBUTE_NORMAL, self.normals);
        }
        if !self.uvs.is_empty() {
            render.insert_attribute(Mesh::ATTRIBUTE_UV_0, self.uvs);
        }
        if let Some(colours) = colours {
            render.insert_attribute(Mesh::ATTRIBUTE_COLOR, colours);
        }
        render.insert_indices(Indices::U32(self.indices));
        render
    }
}

/// One chunk's surface, read from the world without changing it (so that several chunks are
/// read at once): its triangles, its vertex colours when its mesh is coloured by a quantity,
/// and its shape (taken here, on the compute threads, rather than as it is uploaded).
pub struct ChunkSurface {
    /// Its triangles.
    pub data: RenderData,
    /// A colour for each render vertex, when the mesh is coloured by a quantity.
    pub colours: Option<Vec<[f32; 4]>>,
    /// The volume under its triangles and their box.
    pub shape: ChunkShape,
}

impl ChunkSurface {
    fn new(data: RenderData, colours: Option<Vec<[f32; 4]>>) -> Self {
        let shape = ChunkShape::of(&data.positions, data.indices.iter().map(|&i| i as usize));
        Self {
            data,
            colours,
            shape,
        }
    }

    /// What `faces` of `mesh` draw: shaded `smooth` or flat, with texture coordinates where
    /// the `checker` is on and the mesh has UVs, coloured by the quantity the mesh carries
    /// ([`VertexValues`]; a quantity on faces gives each face corners of its own).
    pub fn read(
        world: &World,
        mesh: Option<MeshId>,
        faces: &[FaceId],
        smooth: bool,
        checker: bool,
    ) -> Self {
        let values = mesh.and_then(|m| world.get::<VertexValues>(m.0));
        if let Some(values) = values.filter(|v| v.on_faces) {
            let data = render_data_by_face(world, faces, smooth);
            let colours = data
                .vertex_faces
                .iter()
                .map(|f| values.colour(f.0))
                .collect();
            return Self::new(data, Some(colours));
        }
        let uvs = checker && mesh.is_some_and(|m| MeshAttributes::of(world, m).uv);
        let data = render_data(world, faces, smooth, uvs);
        let colours =
            values.map(|values| data.vertices.iter().map(|&v| values.colour(v.0)).collect());
        Self::new(data, colours)
    }
}

/// Builds the render data of `faces`: each face fanned from its first corner, every mesh
/// vertex once per chunk (indexed). Smooth shading gives each vertex the area-weighted normal of
/// *all* its faces (so chunk borders show no seam); flat shading gives no normals at all: the
/// surface shader takes each pixel's face normal from the derivatives of its position, so a
/// vertex need not be repeated for every face around it (six times fewer vertices to transform
/// on a triangle mesh, which is what a software rasteriser spends its time on).
///
/// With `uvs` (the mesh has [`CornerUv`]s and the checkerboard is on) a render vertex is one
/// distinct (vertex, UV) pair instead: the corners of a vertex on a seam, whose UVs differ,
/// become separate render vertices, and [`RenderData::uvs`] is filled. Without it nothing is
/// hashed by UV, so a mesh without UVs costs what it did.
pub fn render_data(world: &World, faces: &[FaceId], smooth: bool, uvs: bool) -> RenderData {
    if uvs {
        return render_data_with_uvs(world, faces, smooth);
    }
    let m = MeshRef::new(world);
    let mut out = RenderData::default();
    let mut corners = Vec::new();
    let mut index: EntityHashMap<u32> = EntityHashMap::default();
    for &f in faces {
        corners.clear();
        for v in m.face_vertices(f) {
            let next = index.len() as u32;
            let i = *index.entry(v.0).or_insert_with(|| {
                push_vertex(&m, &mut out, v, smooth);
                next
            });
            corners.push(i);
        }
        fan(&mut out, &corners, f);
    }
    out
}

/// [`render_data`] with every face's corners render vertices of their own (no UVs), so that a
/// face can be drawn in one colour: what colouring by a quantity on the faces draws. Each
/// render vertex records its face in [`RenderData::vertex_faces`].
pub fn render_data_by_face(world: &World, faces: &[FaceId], smooth: bool) -> RenderData {
    let m = MeshRef::new(world);
    let mut out = RenderData::default();
    let mut corners = Vec::new();
    for &f in faces {
        corners.clear();
        for v in m.face_vertices(f) {
            corners.push(out.positions.len() as u32);
            push_vertex(&m, &mut out, v, smooth);
            out.vertex_faces.push(f);
        }
        fan(&mut out, &corners, f);
    }
    out
}

/// [`render_data`] with one render vertex per distinct (vertex, corner UV) pair.
fn render_data_with_uvs(world: &World, faces: &[FaceId], smooth: bool) -> RenderData {
    let m = MeshRef::new(world);
    let mut out = RenderData::default();
    let mut corners = Vec::new();
    let mut index: bevy::platform::collections::HashMap<(Entity, [u32; 2]), u32> =
        bevy::platform::collections::HashMap::default();
    for &f in faces {
        corners.clear();
        for h in m.face_halfedges(f) {
            let v = m.to_vertex(h);
            let uv = world.get::<CornerUv>(h.0).map_or(Vec2::ZERO, |c| c.0);
            let key = (v.0, [uv.x.to_bits(), uv.y.to_bits()]);
            let next = index.len() as u32;
            let i = *index.entry(key).or_insert_with(|| {
                push_vertex(&m, &mut out, v, smooth);
                out.uvs.push(uv.to_array());
                next
            });
            corners.push(i);
        }
        fan(&mut out, &corners, f);
    }
    out
}

/// Appends render vertex `v`: its position, its vertex id, and (smooth) its normal.
fn push_vertex(m: &MeshRef<'_>, out: &mut RenderData, v: VertexId, smooth: bool) {
    out.positions.push(m.position(v).to_array());
    out.vertices.push(v);
    if smooth {
        out.normals.push(smooth_normal(m, v));
    }
}

/// The smooth-shading normal of `v`: the area-weighted normal of all its faces.
pub(super) fn smooth_normal(m: &MeshRef<'_>, v: VertexId) -> [f32; 3] {
    let n = m.vertex_area_vector(v);
    n.try_normalize().unwrap_or(Vec3::Z).to_array()
}

/// Fans face `f` (its render vertices `corners`) into triangles, and counts its sides.
fn fan(out: &mut RenderData, corners: &[u32], f: FaceId) {
    let at = |i: u32| Vec3::from(out.positions[i as usize]);
    if let Some(&last) = corners.last() {
        let mut from = at(last);
        for &i in corners {
            let to = at(i);
            out.side_length += f64::from(from.distance(to));
            from = to;
        }
        out.sides += corners.len();
    }
    for i in 1..corners.len().saturating_sub(1) {
        out.indices
            .extend_from_slice(&[corners[0], corners[i], corners[i + 1]]);
        out.triangle_faces.push(f);
    }
}

/// The edges drawn by a chunk: an interior edge by the face of its lower-numbered halfedge, a
/// boundary edge by its one face, so every edge is drawn once whichever chunks hold its faces.
/// Boundary edges are red. Each side costs three lookups (its halfedge, its twin's face, its
/// tip's position): a 16k-face chunk of the bunny in 3 ms, where walking edge → halfedge → face
/// took 27.
pub fn edge_lines(world: &World, faces: &[FaceId]) -> Vec<(Vec3, Vec3, Color)> {
    let m = MeshRef::new(world);
    edge_line_ends(world, faces)
        .into_iter()
        .map(|(a, b, color)| (m.position(a), m.position(b), color))
        .collect()
}

/// [`edge_lines`] by their end vertices, which a refresh of positions reads again.
pub(super) fn edge_line_ends(world: &World, faces: &[FaceId]) -> Vec<(VertexId, VertexId, Color)> {
    let m = MeshRef::new(world);
    let mut out = Vec::with_capacity(faces.len() * 2);
    let mut ring: Vec<(HalfedgeId, HalfedgeId, VertexId)> = Vec::new();
    for &f in faces {
        ring.clear();
        ring.extend(m.face_halfedges(f).map(|h| {
            let x = m.halfedge(h);
            (h, x.twin, x.vertex)
        }));
        let Some(&(_, _, mut from)) = ring.last() else {
            continue;
        };
        for &(h, twin, to) in &ring {
            let boundary = m.face(twin).is_none();
            if boundary || h.0 < twin.0 {
                out.push((from, to, if boundary { BOUNDARY_COLOR } else { EDGE_COLOR }));
            }
            from = to;
        }
    }
    out
}

/// Whether any of `faces` still in the mesh has a side on the boundary.
pub(super) fn on_boundary(world: &World, faces: &[FaceId]) -> bool {
    let m = MeshRef::new(world);
    faces
        .iter()
        .any(|&f| m.try_face(f).is_some() && m.face_halfedges(f).any(|h| m.is_boundary(m.twin(h))))
}

/// Whether some of the `added` faces (all in the mesh) make a part of their own: faces joined
/// by their edges to one another and to no other face (a component restored by an undo, or
/// made on its own).
pub(super) fn added_apart(world: &World, added: &[FaceId]) -> bool {
    let m = MeshRef::new(world);
    let new: bevy::ecs::entity::EntityHashSet = added.iter().map(|f| f.0).collect();
    let mut seen = bevy::ecs::entity::EntityHashSet::default();
    added.iter().any(|&start| {
        if !seen.insert(start.0) {
            return false;
        }
        let (mut stack, mut joined) = (vec![start], false);
        while let Some(f) = stack.pop() {
            for g in m.face_halfedges(f).filter_map(|h| m.face(m.twin(h))) {
                if !new.contains(&g.0) {
                    joined = true;
                } else if seen.insert(g.0) {
                    stack.push(g);
                }
            }
        }
        !joined
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Edge, Face, MeshInfo, build_mesh, members::of_kind, shapes};

    #[test]
    fn a_chunks_shape_is_its_triangles_signed_volume_and_its_corners_box() {
        // The unit tetrahedron's three faces away from the origin, wound outward, and one
        // more corner off every triangle: it widens the box, not the volume.
        let positions = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -2.0],
        ];
        let shape = ChunkShape::of(&positions, [0, 1, 2]);
        assert!((shape.volume - 1.0 / 6.0).abs() < 1e-12, "{}", shape.volume);
        assert_eq!(
            shape.bounds,
            Some((Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 1.0)))
        );
        // Turned around, the same triangle bounds the volume with the other sign.
        assert!((ChunkShape::of(&positions, [0, 2, 1]).volume + 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(ChunkShape::of(&[], []), ChunkShape::default());
    }

    #[test]
    fn every_edge_is_drawn_once_whichever_chunks_hold_its_faces() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid_with_holes(2), MeshInfo::default())
            .expect("builds");
        let faces = of_kind::<Face, _>(&world, built.mesh, FaceId);
        let edges = of_kind::<Edge, _>(&world, built.mesh, crate::mesh::EdgeId);
        let m = MeshRef::new(&world);
        let boundary = edges.iter().filter(|&&e| m.is_boundary_edge(e)).count();
        assert!(boundary > 0);
        // Two chunks, interleaved, so most edges have their faces in different chunks.
        let (even, odd): (Vec<_>, Vec<_>) = faces.iter().enumerate().partition(|(i, _)| i % 2 == 0);
        let chunk =
            |part: Vec<(usize, &FaceId)>| part.into_iter().map(|(_, &f)| f).collect::<Vec<_>>();
        let mut lines = edge_lines(&world, &chunk(even));
        lines.extend(edge_lines(&world, &chunk(odd)));
        assert_eq!(lines.len(), edges.len());
        let red = lines.iter().filter(|l| l.2 == BOUNDARY_COLOR).count();
        assert_eq!(red, boundary);
        // Each line is a real edge, once.
        let key = |a: Vec3, b: Vec3| {
            let (a, b) = (
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
            );
            if a < b { (a, b) } else { (b, a) }
        };
        let mut seen: Vec<_> = lines.iter().map(|&(a, b, _)| key(a, b)).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), edges.len());
        for e in edges {
            let (a, b) = m.edge_vertices(e);
            assert!(
                seen.binary_search(&key(m.position(a), m.position(b)))
                    .is_ok()
            );
        }
    }

    #[test]
    fn faces_added_apart_are_those_joined_to_no_face_drawn_before() {
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &shapes::cube(), MeshInfo::default())
            .expect("a cube")
            .mesh;
        let faces = of_kind::<Face, _>(&world, mesh, FaceId);
        // The whole cube added at once (an erase of it undone): a part of its own.
        assert!(added_apart(&world, &faces));
        // Some of its faces: joined to the others.
        assert!(!added_apart(&world, &faces[..5]));
        assert!(!added_apart(&world, &[]));
    }
}
