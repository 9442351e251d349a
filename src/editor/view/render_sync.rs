//! Keeps each mesh's render copy in step with its entities, redrawing only what changed.
//!
//! A mesh is drawn by chunks of [`CHUNK_FACES`] faces, each a render entity with a Bevy
//! [`Mesh`] (built by [`super::render_data`]: every polygon fan-triangulated, every vertex once; flat shading: no normals, the
//! shader derives each face's; smooth: area-weighted vertex normals over *all* the vertex's faces,
//! so chunk borders show no seam), a
//! [`TriangleFaces`] table mapping each GPU triangle back to its face for picking, and a
//! wireframe of the *real* edges ([`super::wireframe`]).
//!
//! In the `Sync` set, a mesh marked [`MeshDirty`] (opened, globally edited) is redrawn whole, and
//! so is one marked [`LooksDirty`] (its shading or colouring changed), whose chunks keep the
//! record of what changed them ([`ChunkChanges`]: the geometry is as drawn); a
//! mesh carrying [`DirtyFaces`] (a local edit) has only the
//! chunks holding those faces redrawn, new faces joining the last chunk; a mesh marked
//! [`PositionsDirty`] (most of its vertices moved, as in an ARAP drag) keeps its chunks and
//! their triangles and has only their positions (smooth normals, wireframe lines) refreshed. A mesh coloured by a
//! quantity ([`VertexValues`]) gets vertex colours; a mesh with UVs, while
//! [`ViewSettings::checker`] is on, gets texture coordinates (one render vertex per distinct
//! vertex and UV, so a seam splits them) and the shader draws a checkerboard. A 1M-face mesh thus re-renders an edit in milliseconds,
//! and meshes that did not change cost nothing per frame.

use bevy::color::Color;
use bevy::ecs::entity::EntityHashMap;
use bevy::mesh::{Mesh, Mesh3d};
use bevy::pbr::MeshMaterial3d;
use bevy::prelude::{
    Assets, Component, Entity, Has, Or, Resource, Transform, Visibility, With, World,
};
use bevy::tasks::{ComputeTaskPool, ParallelSlice, TaskPool};
use std::time::Instant;

use crate::mesh::MeshInfo;
use crate::mesh::ids::{FaceId, MeshId, VertexId};
use crate::mesh::topology::MeshRef;

use super::colouring::VertexValues;
use super::render_data::{
    ChunkShape, ChunkSurface, ChunkVertices, added_apart, edge_line_ends, on_boundary,
    smooth_normal,
};
use super::surface::SurfaceMaterial;
use super::wireframe::{WireEnds, WireLines, draw_wire, wire_mesh};
use crate::editor::session::selection::{DirtyFaces, LooksDirty, MeshDirty, PositionsDirty};

/// The render entity of a mesh: carries its [`Mesh3d`] and [`TriangleFaces`].
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOf(pub MeshId);

/// The wireframe entity of a mesh's chunk (a mesh of its edges' lines, [`super::lines`]).
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct WireframeOf(pub MeshId);

/// For each triangle of the render mesh, the face it was cut from.
#[derive(Component, Debug, Clone, Default)]
pub struct TriangleFaces(pub Vec<FaceId>);

/// How meshes are drawn.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    /// Smooth (vertex normals) rather than flat (face normals) shading.
    pub smooth: bool,
    /// Draw the wireframe of the real edges.
    pub wireframe: bool,
    /// Draw halfedge arrows (always near the selection; everywhere on small meshes).
    pub halfedges: bool,
    /// Draw the wireframe even where its edges are too dense on screen to be told apart
    /// (see [`super::readability`]).
    pub dense_wireframe: bool,
    /// Draw a checkerboard from the mesh's UVs (when it has them), to show the layout's
    /// distortion: squares that stay square are conformal, equal ones area-preserving.
    pub checker: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        Self {
            smooth: false,
            wireframe: true,
            halfedges: true,
            dense_wireframe: false,
            checker: true,
        }
    }
}

/// Counters for tests and the frame-time figures.
#[derive(Resource, Debug, Clone, Default)]
pub struct RenderStats {
    /// Render meshes rebuilt so far.
    pub rebuilds: usize,
    /// Those of [`Self::rebuilds`] that drew a mesh opened or changed by an edit: every one
    /// but a redraw for its looks alone ([`LooksDirty`]: shading, wireframe, checkerboard,
    /// colouring). The panel's figures of the mesh are counted again after these.
    pub edits_drawn: usize,
    /// Milliseconds the last rebuild took.
    pub last_rebuild_ms: f64,
    /// Triangles in the last rebuilt mesh.
    pub last_triangles: usize,
}

/// Meshes with more edges than this get no full wireframe (at that density it is a black
/// blob and costs seconds per frame under software rendering); the selection is still drawn.
pub const WIREFRAME_MAX_EDGES: usize = 400_000;

/// Faces per render chunk. Each chunk is one render entity with its own GPU mesh, so an edit
/// re-uploads only the chunks it touched.
pub const CHUNK_FACES: usize = 16_384;

/// The render chunks of a mesh (a component of the mesh entity).
#[derive(Component, Debug, Default)]
pub struct RenderChunks {
    /// Chunk entities, in order.
    pub chunks: Vec<Entity>,
    /// The wireframe entity of each chunk.
    pub wires: Vec<Entity>,
    /// Which chunk each face is drawn by.
    pub face_chunk: EntityHashMap<u32>,
    /// Whether the mesh is small enough for a full wireframe.
    pub wireframe: bool,
    /// Mean edge length when the mesh was last drawn whole (how dense its wireframe is).
    pub mean_edge_length: f32,
    /// When the chunks last changed in the ways that bear on the mesh's closure.
    pub changes: ChunkChanges,
}

/// The render generations ([`RenderStats::rebuilds`], as counted once the redraw is recorded)
/// at which a mesh's chunks last changed in each way that can change its closure (see
/// [`super::culling`]): a closure counted at a later generation still holds after the other
/// changes, its volume followed by the chunks' [`ChunkShape`]s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChunkChanges {
    /// Every chunk drawn anew after an edit (not for a change of looks alone, [`LooksDirty`]).
    pub whole: usize,
    /// A face with a side on the boundary redrawn: a hole made or moved (one closed leaves no
    /// such face, but adds faces).
    pub boundary: usize,
    /// Faces added or removed (a hole's loop can change with no face left beside it).
    pub faces: usize,
    /// Faces added apart from the rest, joined by no edge to a face drawn before: a component
    /// restored (an undone erase) or made on its own.
    pub parts: usize,
    /// Positions refreshed in place: any vertex may have moved, the holes' too.
    pub positions: usize,
    /// Any chunk redrawn for an edit, however small.
    pub drawn: usize,
}

/// The render generation the redraw under way will be recorded at.
fn this_generation(world: &World) -> usize {
    world.resource::<RenderStats>().rebuilds + 1
}

/// The faces a chunk draws.
#[derive(Component, Debug, Clone, Default)]
pub struct ChunkFaces(pub Vec<FaceId>);

/// Rebuilds render copies (the `Sync` set): every chunk of a mesh marked [`MeshDirty`], and
/// only the chunks holding [`DirtyFaces`] otherwise. Render copies of meshes that are gone are
/// removed.
pub fn sync_render_meshes(world: &mut World) {
    remove_orphans(world);
    let settings = world
        .get_resource::<ViewSettings>()
        .copied()
        .unwrap_or_default();
    // Redrawn whole: edited meshes, and those whose looks alone changed (the same geometry).
    let dirty: Vec<(Entity, bool)> = world
        .query_filtered::<(Entity, Has<MeshDirty>, Has<DirtyFaces>, Has<PositionsDirty>), (With<MeshInfo>, Or<(With<MeshDirty>, With<LooksDirty>)>)>()
        .iter(world)
        .map(|(e, whole, faces, moved)| (e, !(whole || faces || moved)))
        .collect();
    for (entity, same_geometry) in dirty {
        let start = Instant::now();
        let triangles = rebuild_all(world, MeshId(entity), settings, same_geometry);
        world
            .entity_mut(entity)
            .remove::<(MeshDirty, LooksDirty, DirtyFaces, PositionsDirty)>();
        record(world, MeshId(entity), triangles, start, !same_geometry);
    }
    let partial: Vec<Entity> = world
        .query_filtered::<Entity, (With<MeshInfo>, With<DirtyFaces>)>()
        .iter(world)
        .collect();
    for entity in partial {
        let start = Instant::now();
        let faces = world
            .entity_mut(entity)
            .take::<DirtyFaces>()
            .unwrap_or_default();
        let triangles = rebuild_some(world, MeshId(entity), &faces.0, settings);
        record(world, MeshId(entity), triangles, start, true);
    }
    // After the partial redraws: a chunk whose faces changed has its vertex list anew.
    let moved: Vec<Entity> = world
        .query_filtered::<Entity, (With<MeshInfo>, With<PositionsDirty>)>()
        .iter(world)
        .collect();
    for entity in moved {
        let start = Instant::now();
        world.entity_mut(entity).remove::<PositionsDirty>();
        let triangles = match refresh_positions(world, MeshId(entity), settings) {
            Some(triangles) => triangles,
            None => rebuild_all(world, MeshId(entity), settings, false),
        };
        record(world, MeshId(entity), triangles, start, true);
    }
}

/// Counts a redraw of `mesh` in [`RenderStats`]: one of an edit's where `edited`, else one for
/// its looks alone.
fn record(world: &mut World, mesh: MeshId, triangles: usize, start: Instant, edited: bool) {
    let mut stats = world.resource_mut::<RenderStats>();
    stats.rebuilds += 1;
    stats.edits_drawn += usize::from(edited);
    stats.last_triangles = triangles;
    stats.last_rebuild_ms = start.elapsed().as_secs_f64() * 1000.0;
    bevy::log::info!(
        "render sync {mesh}: {triangles} triangles in {:.1} ms",
        stats.last_rebuild_ms
    );
}

/// Drops every chunk of `mesh` and draws it anew. Returns the triangles drawn. With
/// `same_geometry` (its looks alone changed) the new chunks keep the old ones'
/// [`ChunkChanges`]: they draw the same surface.
///
/// What each chunk draws is read from the world on the compute threads, the chunks shared
/// among them; the uploads follow on this thread. The wireframe's lines are read in a second
/// such pass, once the chunks' sides have said whether the mesh is sparse enough to draw them.
fn rebuild_all(
    world: &mut World,
    mesh: MeshId,
    settings: ViewSettings,
    same_geometry: bool,
) -> usize {
    let now = this_generation(world);
    let mut changes = ChunkChanges {
        whole: now,
        drawn: now,
        ..Default::default()
    };
    if let Some(old) = world.entity_mut(mesh.0).take::<RenderChunks>() {
        if same_geometry {
            changes = old.changes;
        }
        for e in old.chunks.into_iter().chain(old.wires) {
            world.despawn(e);
        }
    }
    let faces = crate::mesh::members::of_kind::<crate::mesh::Face, _>(world, mesh, FaceId);
    let pool = ComputeTaskPool::get_or_init(TaskPool::default);
    let surfaces = faces.par_chunk_map(pool, CHUNK_FACES, |_, group| {
        ChunkSurface::read(world, Some(mesh), group, settings.smooth, settings.checker)
    });
    // Σ face degrees = 2 × interior edges + boundary edges: half of it bounds the edge count
    // from below without walking the edges.
    let (length, sides) = surfaces.iter().fold((0.0, 0), |(l, n), s| {
        (l + s.data.side_length, n + s.data.sides)
    });
    let wireframe = sides / 2 <= WIREFRAME_MAX_EDGES;
    let lines = faces.par_chunk_map(pool, CHUNK_FACES, |_, group| {
        chunk_lines(world, group, wireframe, settings)
    });
    let mut chunks = RenderChunks {
        wireframe,
        // Each interior edge counted twice, which leaves the mean as it is.
        mean_edge_length: if sides == 0 {
            0.0
        } else {
            (length / sides as f64) as f32
        },
        changes,
        ..Default::default()
    };
    let mut triangles = 0;
    let drawn = surfaces.into_iter().zip(lines);
    for (i, (group, (surface, lines))) in faces.chunks(CHUNK_FACES).zip(drawn).enumerate() {
        for &f in group {
            chunks.face_chunk.insert(f.0, i as u32);
        }
        let chunk = world
            .spawn((RenderOf(mesh), ChunkFaces(group.to_vec())))
            .id();
        let wire = world.spawn(WireframeOf(mesh)).id();
        chunks.chunks.push(chunk);
        chunks.wires.push(wire);
        triangles += upload_chunk(world, chunk, wire, surface, lines);
    }
    world.entity_mut(mesh.0).insert(chunks);
    triangles
}

/// Redraws the chunks holding `faces` (new faces join the last chunk). Returns the triangles
/// drawn.
fn rebuild_some(
    world: &mut World,
    mesh: MeshId,
    faces: &[FaceId],
    settings: ViewSettings,
) -> usize {
    let Some(mut chunks) = world.entity_mut(mesh.0).take::<RenderChunks>() else {
        return rebuild_all(world, mesh, settings, false);
    };
    // An edit that reaches a quarter of the mesh (a big level-of-detail jump) is cheaper drawn
    // whole, which also packs the chunks again.
    if faces.len() > chunks.face_chunk.len() / 4 {
        world.entity_mut(mesh.0).insert(chunks);
        return rebuild_all(world, mesh, settings, false);
    }
    let now = this_generation(world);
    let mut touched: Vec<u32> = Vec::new();
    let mut added = Vec::new();
    for &f in faces {
        let alive = world.get::<crate::mesh::Face>(f.0).is_some();
        match (chunks.face_chunk.get(&f.0).copied(), alive) {
            (Some(c), true) => touched.push(c),
            (Some(c), false) => {
                chunks.face_chunk.remove(&f.0);
                chunks.changes.faces = now;
                touched.push(c);
            }
            (None, true) => {
                let last = chunks.chunks.len() - 1;
                let full = world
                    .get::<ChunkFaces>(chunks.chunks[last])
                    .is_some_and(|c| c.0.len() >= 2 * CHUNK_FACES);
                let c = if full {
                    chunks
                        .chunks
                        .push(world.spawn((RenderOf(mesh), ChunkFaces::default())).id());
                    chunks.wires.push(world.spawn(WireframeOf(mesh)).id());
                    chunks.chunks.len() - 1
                } else {
                    last
                };
                if let Some(mut list) = world.get_mut::<ChunkFaces>(chunks.chunks[c]) {
                    list.0.push(f);
                }
                chunks.face_chunk.insert(f.0, c as u32);
                chunks.changes.faces = now;
                added.push(f);
                touched.push(c as u32);
            }
            (None, false) => {}
        }
    }
    chunks.changes.drawn = now;
    if on_boundary(world, faces) {
        chunks.changes.boundary = now;
    }
    if added_apart(world, &added) {
        chunks.changes.parts = now;
    }
    touched.sort_unstable();
    touched.dedup();
    let mut triangles = 0;
    for c in touched {
        let (chunk, wire) = (chunks.chunks[c as usize], chunks.wires[c as usize]);
        let alive: Vec<FaceId> = world
            .get::<ChunkFaces>(chunk)
            .map(|l| {
                l.0.iter()
                    .copied()
                    .filter(|f| world.get::<crate::mesh::Face>(f.0).is_some())
                    .collect()
            })
            .unwrap_or_default();
        world.entity_mut(chunk).insert(ChunkFaces(alive));
        triangles += draw_chunk(world, chunk, wire, chunks.wireframe, settings);
    }
    world.entity_mut(mesh.0).insert(chunks);
    triangles
}

/// Builds and uploads one chunk's surface and wireframe. Returns its triangle count.
fn draw_chunk(
    world: &mut World,
    chunk: Entity,
    wire: Entity,
    wireframe: bool,
    settings: ViewSettings,
) -> usize {
    let faces = world
        .get::<ChunkFaces>(chunk)
        .map(|c| c.0.clone())
        .unwrap_or_default();
    let mesh = world.get::<RenderOf>(chunk).map(|r| r.0);
    let surface = ChunkSurface::read(world, mesh, &faces, settings.smooth, settings.checker);
    let lines = chunk_lines(world, &faces, wireframe, settings);
    upload_chunk(world, chunk, wire, surface, lines)
}

/// One chunk's wireframe lines when wireframes are drawn (`None` otherwise): its edges when
/// the mesh's `wireframe` is sparse enough, none beyond [`WIREFRAME_MAX_EDGES`].
fn chunk_lines(
    world: &World,
    faces: &[FaceId],
    wireframe: bool,
    settings: ViewSettings,
) -> Option<Vec<(VertexId, VertexId, Color)>> {
    (settings.wireframe && world.contains_resource::<super::scene::SceneMaterials>()).then(|| {
        if wireframe {
            edge_line_ends(world, faces)
        } else {
            Vec::new()
        }
    })
}

/// Gives `chunk` its surface (a new [`Mesh`] asset) and `wire` its lines (another), when there
/// are any to draw: a chunk left without faces has no [`Mesh3d`] (Bevy's mesh allocator logs
/// a use-after-free for a mesh without vertices). Returns the chunk's triangle count.
fn upload_chunk(
    world: &mut World,
    chunk: Entity,
    wire: Entity,
    surface: ChunkSurface,
    lines: Option<Vec<(VertexId, VertexId, Color)>>,
) -> usize {
    let ChunkSurface {
        mut data,
        colours,
        shape,
    } = surface;
    let triangles = data.triangle_faces.len();
    let faces = TriangleFaces(std::mem::take(&mut data.triangle_faces));
    let vertices = ChunkVertices(std::mem::take(&mut data.vertices));
    let handle = (triangles > 0).then(|| {
        world
            .resource_mut::<Assets<Mesh>>()
            .add(data.into_mesh(colours))
    });
    let materials = world
        .get_resource::<super::scene::SceneMaterials>()
        .cloned();
    let mut e = world.entity_mut(chunk);
    e.insert((
        faces,
        vertices,
        shape,
        Transform::default(),
        Visibility::default(),
    ));
    match (handle, &materials) {
        (Some(handle), Some(materials)) => {
            e.insert((Mesh3d(handle), MeshMaterial3d(materials.surface.clone())));
        }
        (Some(handle), None) => {
            e.insert(Mesh3d(handle));
        }
        (None, _) => {
            e.remove::<(Mesh3d, MeshMaterial3d<SurfaceMaterial>)>();
        }
    }
    draw_wire(
        world,
        wire,
        lines.unwrap_or_default(),
        materials.map(|m| m.wireframe),
    );
    triangles
}

/// Refreshes the positions of every chunk of `mesh` whose vertices moved and whose faces did
/// not: each chunk's render positions (and smooth normals) are read again on the compute
/// threads, written into its existing mesh asset, and its wireframe lines redrawn from their
/// ends; triangles, the triangle → face tables and the chunks themselves stay. `None` (and
/// nothing done) where that cannot serve and the caller draws the mesh whole: no chunks yet,
/// colours by a quantity (they follow the positions), or a chunk without its vertex list.
fn refresh_positions(world: &mut World, mesh: MeshId, settings: ViewSettings) -> Option<usize> {
    let chunks = world.get::<RenderChunks>(mesh.0)?;
    if world.get::<VertexValues>(mesh.0).is_some() {
        return None;
    }
    let pairs: Vec<(Entity, Entity)> = chunks
        .chunks
        .iter()
        .copied()
        .zip(chunks.wires.iter().copied())
        .collect();
    if pairs
        .iter()
        .any(|&(c, _)| world.get::<ChunkVertices>(c).is_none())
    {
        return None;
    }
    let pool = ComputeTaskPool::get_or_init(TaskPool::default);
    let world_ref: &World = world;
    let refreshed = pairs.par_chunk_map(pool, 1, |_, pair| {
        let (chunk, wire) = pair[0];
        let m = MeshRef::new(world_ref);
        let vertices = &world_ref.get::<ChunkVertices>(chunk).expect("checked").0;
        // A vertex gone (an edit beside the move) leaves the positions unknown: drawn whole.
        let positions: Vec<[f32; 3]> = vertices
            .iter()
            .map(|&v| m.try_position(v).map(|p| p.to_array()))
            .collect::<Option<_>>()?;
        let normals: Vec<[f32; 3]> = if settings.smooth {
            vertices.iter().map(|&v| smooth_normal(&m, v)).collect()
        } else {
            Vec::new()
        };
        let ends = world_ref.get::<WireEnds>(wire);
        if ends.is_some_and(|e| {
            e.0.iter()
                .any(|&(a, b, _)| m.try_vertex(a).is_none() || m.try_vertex(b).is_none())
        }) {
            return None;
        }
        let lines = ends.map(|ends| wire_mesh(world_ref, &ends.0));
        let shape = match world_ref.get::<Mesh3d>(chunk) {
            // A chunk without faces has no mesh and draws no volume.
            None => Some(ChunkShape::default()),
            Some(m) => world_ref
                .resource::<Assets<Mesh>>()
                .get(&m.0)
                .and_then(|render| {
                    render
                        .indices()
                        .map(|c| ChunkShape::of(&positions, c.iter()))
                }),
        };
        Some((positions, normals, lines, shape))
    });
    let refreshed: Vec<_> = refreshed.into_iter().collect::<Option<_>>()?;
    let mut triangles = 0;
    for ((chunk, wire), (positions, normals, lines, shape)) in pairs.into_iter().zip(refreshed) {
        let handle = world.get::<Mesh3d>(chunk).map(|m| m.0.clone());
        triangles += world.get::<TriangleFaces>(chunk).map_or(0, |t| t.0.len());
        if let Some(handle) = handle {
            let mut meshes = world.resource_mut::<Assets<Mesh>>();
            if let Some(mut render) = meshes.get_mut(&handle) {
                render.insert_attribute(Mesh::ATTRIBUTE_POSITION, positions);
                if !normals.is_empty() {
                    render.insert_attribute(Mesh::ATTRIBUTE_NORMAL, normals);
                }
            }
        }
        match shape {
            Some(shape) => world.entity_mut(chunk).insert(shape),
            None => world.entity_mut(chunk).remove::<ChunkShape>(),
        };
        let wire_handle = world.get::<WireLines>(wire).map(|l| l.0.clone());
        if let (Some(handle), Some(lines)) = (wire_handle, lines)
            && let Err(e) = world.resource_mut::<Assets<Mesh>>().insert(&handle, lines)
        {
            bevy::log::warn!("wireframe not moved: {e}");
        }
    }
    let generation = this_generation(world);
    if let Some(mut chunks) = world.get_mut::<RenderChunks>(mesh.0) {
        (chunks.changes.positions, chunks.changes.drawn) = (generation, generation);
    }
    Some(triangles)
}

fn remove_orphans(world: &mut World) {
    // Filtered to render entities: an unfiltered query would visit every element of every
    // mesh each frame (8 M entities, 30 ms, on a 1.3M-face mesh).
    let orphans: Vec<Entity> = world
        .query_filtered::<(Entity, Option<&RenderOf>, Option<&WireframeOf>), Or<(With<RenderOf>, With<WireframeOf>)>>()
        .iter(world)
        .filter_map(|(e, r, w)| {
            let mesh = r.map(|r| r.0).or(w.map(|w| w.0))?;
            world.get::<MeshInfo>(mesh.0).is_none().then_some(e)
        })
        .collect();
    for e in orphans {
        world.despawn(e);
    }
}
