//! The test kit of the local operations: one set of helpers for the unit tests of extrude,
//! inset, bevel, erase, dissolve vertex, weld and collapse face.
//!
//! Every comparison here is bitwise (`f32::to_bits`), so `0.0` and `-0.0` differ and nothing
//! is "close enough".
//!
//! - Building: [`build`] builds a soup into a fresh world and checks that it validates;
//!   [`vertex`], [`edge`] and [`face_of`] find the elements built from input vertices (a face
//!   by its corners in any order); [`cell`] names the corners of a cell of
//!   [`crate::mesh::shapes::quad_grid`].
//! - Attributes: [`with_attributes`] gives a soup a UV at every corner ([`Uvs::Continuous`]:
//!   [`uv_at`] of the corner's position; [`Uvs::PerCorner`]: that plus the corner's place in
//!   its face, so the corners of one vertex differ), a normal and a colour at every vertex
//!   (different at every vertex of the shapes the tests use). [`assert_attributes_complete`]
//!   checks the attribute invariant (UVs exactly on face corners, a normal and a colour on
//!   every vertex); [`assert_uvs_follow_positions`] checks that every face corner still has
//!   [`uv_at`] of its position.
//! - Counting: [`counts`] is `(V, E, F, χ, boundary loops)`; [`boundary_loops`] the loops'
//!   lengths.
//! - Faces up to relabelling: [`position_cycle`] is one face's positions (bitwise) as a cycle
//!   rotated to start at the least, [`cycle_of`] the same for given points;
//!   [`position_cycles`] every face of a mesh that way, sorted, and [`cycles`] expected faces
//!   in that form; [`faces`] every face with every corner's position, UV, normal and colour.
//! - Untouched: [`snapshot`] is every element's components (links, position, normal,
//!   colour, UV, seam mark, bitwise) by entity, and the mesh's attribute record; snapshots
//!   compare equal only when all of it is; [`assert_untouched`] names the first element that
//!   changed. [`assert_refused`] runs an operation and checks that it is refused with exactly
//!   the given refusal and that the mesh is untouched; [`assert_refused_like`] does the same
//!   for a refusal that a predicate accepts (its kind, where the text is not the point).
//! - Undo: [`assert_undo_redo`] records an edit as the editor does and checks that undo gives
//!   back the original mesh and redo the edited one ([`shape`]: counts, vertices with their
//!   attributes, faces with their corners, edges with their seam marks and the attribute
//!   record, all up to relabelling), each valid.

use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Entity, World};

use crate::mesh::attributes::{CornerUv, MeshAttributes, Seam, VertexColor, VertexNormal};
use crate::mesh::change::{ElementState, LocalRecorder};
use crate::mesh::ids::{EdgeId, FaceId, HalfedgeId, MeshId, VertexId};
use crate::mesh::{BuiltMesh, MeshInfo, MeshMembers, MeshRef, PolygonSoup, build_mesh};
use crate::mesh::{mesh_stats, validate};
use crate::ops::Refusal;

/// A position's bits.
pub type Key = [u32; 3];

/// The bits of `p`.
pub fn bits(p: Vec3) -> Key {
    p.to_array().map(f32::to_bits)
}

/// The bits of `uv`.
fn uv_bits(uv: Vec2) -> [u32; 2] {
    uv.to_array().map(f32::to_bits)
}

/// A cycle rotated to start at its least entry.
pub fn canonical<T: Ord>(mut cycle: Vec<T>) -> Vec<T> {
    let start = (0..cycle.len()).min_by_key(|&i| &cycle[i]).unwrap_or(0);
    cycle.rotate_left(start);
    cycle
}

/// `x`, sorted.
pub fn sorted<T: Ord>(mut x: Vec<T>) -> Vec<T> {
    x.sort_unstable();
    x
}

// ---- building ---------------------------------------------------------------------------

/// Builds `soup` into a fresh world; the mesh must validate.
/// Every vertex position of `mesh`, in its members' order.
pub fn positions(world: &World, mesh: crate::mesh::ids::MeshId) -> Vec<Vec3> {
    let m = crate::mesh::MeshRef::new(world);
    crate::mesh::MeshMembers::collect(world, mesh)
        .vertices
        .iter()
        .map(|&v| m.position(v))
        .collect()
}

pub fn build(soup: &PolygonSoup) -> (World, BuiltMesh) {
    let mut world = World::new();
    let built = build_mesh(&mut world, soup, MeshInfo::default()).expect("builds");
    validate(&world, built.mesh).expect("a valid mesh");
    (world, built)
}

/// Builds `soup` as one more mesh in `world`; it must validate.
pub fn build_into(world: &mut World, soup: &PolygonSoup) -> BuiltMesh {
    let built = build_mesh(world, soup, MeshInfo::default()).expect("builds");
    validate(world, built.mesh).expect("a valid mesh");
    built
}

/// A face id that is not (no longer) a live entity.
pub fn gone_face(world: &mut World) -> FaceId {
    let gone = FaceId(world.spawn_empty().id());
    world.despawn(gone.0);
    gone
}

/// The unit square at height `z = 3e38`: moving it up by a finite distance such as
/// `f32::MAX` leaves the finite range.
pub fn far_square() -> PolygonSoup {
    let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    PolygonSoup::from_faces(
        corners.map(|(x, y)| Vec3::new(x, y, 3e38)).to_vec(),
        &[[0u32, 1, 2, 3]],
    )
}

/// The vertex built from input vertex `i`.
pub fn vertex(built: &BuiltMesh, i: usize) -> VertexId {
    built.input_vertices[i].expect("kept")
}

/// The edge between input vertices `i` and `j`.
pub fn edge(world: &World, built: &BuiltMesh, i: usize, j: usize) -> EdgeId {
    let m = MeshRef::new(world);
    m.edge(
        m.find_halfedge(vertex(built, i), vertex(built, j))
            .unwrap_or_else(|| panic!("no edge {i} {j}")),
    )
}

/// The face of `built`'s mesh whose corners are exactly the input vertices `corners` (in any
/// order).
pub fn face_of(world: &World, built: &BuiltMesh, corners: &[usize]) -> FaceId {
    let m = MeshRef::new(world);
    let want = sorted(corners.iter().map(|&i| vertex(built, i)).collect());
    MeshMembers::collect(world, built.mesh)
        .faces
        .into_iter()
        .find(|&f| sorted(m.face_vertices(f).collect()) == want)
        .unwrap_or_else(|| panic!("no face {corners:?}"))
}

/// The input corners of cell (i, j) of `shapes::quad_grid(nx, _)`, counter-clockwise.
pub fn cell(nx: usize, i: usize, j: usize) -> [usize; 4] {
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
}

// ---- attributes -------------------------------------------------------------------------

/// How [`with_attributes`] lays out the corner UVs.
#[derive(Clone, Copy, Debug)]
pub enum Uvs {
    /// [`uv_at`] of the corner's position: one chart, every corner of a vertex alike, and
    /// affine, so a corner made between two others must have the UV of its position exactly
    /// (for dyadic positions and amounts).
    Continuous,
    /// [`uv_at`] of the position plus `(k, 0)` for the corner's place `k` in its face, so the
    /// corners of a vertex (mostly) differ and a copied UV shows where it came from.
    PerCorner,
}

/// The UV of position `p` in the [`Uvs::Continuous`] layout: `(2x + 1 + z, 2y − z / 2)`.
pub fn uv_at(p: Vec3) -> Vec2 {
    Vec2::new(2.0 * p.x + 1.0 + p.z, 2.0 * p.y - 0.5 * p.z)
}

/// `soup` with a UV at every corner (laid out by `uvs`), and at every vertex the normal
/// `(x, y, 2 + z)` normalised and the colour `(60x, 60y, 7 + 60z)` (each as `u8`, so clamped
/// to 0–255). Normals and colours differ at every vertex of the cube and of grids in the unit
/// square (cells of at least 1/60).
pub fn with_attributes(mut soup: PolygonSoup, uvs: Uvs) -> PolygonSoup {
    let mut corner_uvs = Vec::with_capacity(soup.indices.len());
    for face in soup.faces() {
        for (k, &i) in face.iter().enumerate() {
            let uv = uv_at(soup.positions[i as usize]);
            corner_uvs.push(match uvs {
                Uvs::Continuous => uv,
                Uvs::PerCorner => uv + Vec2::new(k as f32, 0.0),
            });
        }
    }
    soup.corner_uvs = Some(corner_uvs);
    soup.vertex_normals = Some(
        soup.positions
            .iter()
            .map(|p| Vec3::new(p.x, p.y, 2.0 + p.z).normalize())
            .collect(),
    );
    soup.vertex_colors = Some(
        soup.positions
            .iter()
            .map(|p| {
                [
                    (p.x * 60.0) as u8,
                    (p.y * 60.0) as u8,
                    7u8.saturating_add((p.z * 60.0) as u8),
                ]
            })
            .collect(),
    );
    soup
}

/// The attribute invariant: the mesh has UVs, normals and colours; every face halfedge has a
/// UV and no boundary halfedge has one; every vertex has a normal and a colour.
pub fn assert_attributes_complete(world: &World, mesh: MeshId) {
    let has = MeshAttributes::of(world, mesh);
    assert!(has.uv && has.normals && has.colors, "{has:?}");
    let m = MeshRef::new(world);
    let members = MeshMembers::collect(world, mesh);
    for h in members.halfedges {
        assert_eq!(
            world.get::<CornerUv>(h.0).is_some(),
            m.face(h).is_some(),
            "{h}"
        );
    }
    for v in members.vertices {
        assert!(world.get::<VertexNormal>(v.0).is_some(), "{v}");
        assert!(world.get::<VertexColor>(v.0).is_some(), "{v}");
    }
}

/// Every face corner has exactly [`uv_at`] of its position; no boundary halfedge has a UV.
pub fn assert_uvs_follow_positions(world: &World, mesh: MeshId) {
    let m = MeshRef::new(world);
    for h in MeshMembers::collect(world, mesh).halfedges {
        let uv = world.get::<CornerUv>(h.0).map(|u| uv_bits(u.0));
        if m.face(h).is_none() {
            assert_eq!(uv, None, "{h} is a boundary halfedge");
            continue;
        }
        let p = m.position(m.to_vertex(h));
        assert_eq!(uv, Some(uv_bits(uv_at(p))), "{h} at {p}");
    }
}

/// Face `f`'s corners (its halfedges in order) and their UVs, read before an extrusion or an
/// inset of `f` for [`assert_sides_carry_rim`].
pub fn corner_uvs(world: &World, f: FaceId) -> (Vec<HalfedgeId>, Vec<Vec2>) {
    let m = MeshRef::new(world);
    m.face_halfedges(f)
        .map(|h| (h, world.get::<CornerUv>(h.0).expect("a corner UV").0))
        .unzip()
}

/// After an extrusion or an inset of a face whose corners were `rim` with UVs `uvs` (from
/// [`corner_uvs`]): the face's corners keep their UVs; outside each of its sides `b' → a'`
/// (the twin of a rim halfedge) is one of `sides`, a quad `a b b' a'` whose corners at `b`
/// and `b'` have the UV of the rim corner at `b` and those at `a` and `a'` the UV of the
/// corner at `a` (bitwise); and the copy `a'` is a new vertex with `a`'s normal and colour.
pub fn assert_sides_carry_rim(world: &World, rim: &[HalfedgeId], uvs: &[Vec2], sides: &[FaceId]) {
    let m = MeshRef::new(world);
    let uv = |h: HalfedgeId| world.get::<CornerUv>(h.0).map(|u| uv_bits(u.0));
    let n = rim.len();
    for (k, &h) in rim.iter().enumerate() {
        assert_eq!(
            uv(h),
            Some(uv_bits(uvs[k])),
            "the face keeps its corner UVs"
        );
        let top = m.twin(h); // b' → a'
        let side = m.face(top).expect("a side quad");
        assert!(sides.contains(&side), "{side} is not a side");
        let fall = m.next(top); // a' → a
        let bottom = m.next(fall); // a → b
        let rise = m.next(bottom); // b → b'
        let (at_a, at_b) = (uvs[(k + n - 1) % n], uvs[k]);
        assert_eq!(
            [bottom, rise, top, fall].map(uv),
            [at_b, at_b, at_a, at_a].map(|x| Some(uv_bits(x)))
        );
        let (copy, a) = (m.to_vertex(top), m.to_vertex(fall));
        assert_ne!(copy, a);
        assert_eq!(vertex_attributes(world, copy), vertex_attributes(world, a));
    }
}

// ---- counting ---------------------------------------------------------------------------

/// `(V, E, F, χ, boundary loops)`.
pub type Counts = (usize, usize, usize, i64, usize);

/// The mesh's [`Counts`]: `(V, E, F, χ, boundary loops)`.
pub fn counts(world: &World, mesh: MeshId) -> Counts {
    let s = mesh_stats(world, mesh);
    (
        s.vertices,
        s.edges,
        s.faces,
        s.euler_characteristic,
        s.boundary_loops,
    )
}

/// The lengths of the boundary loops, sorted.
pub fn boundary_loops(world: &World, mesh: MeshId) -> Vec<usize> {
    let m = MeshRef::new(world);
    let mut seen = Vec::new();
    let mut lengths = Vec::new();
    for h in MeshMembers::collect(world, mesh).halfedges {
        if m.is_boundary(h) && !seen.contains(&h) {
            let ring: Vec<_> = m.loop_from(h).collect();
            lengths.push(ring.len());
            seen.extend(ring);
        }
    }
    sorted(lengths)
}

// ---- faces up to relabelling ------------------------------------------------------------

/// The points as a cycle of bits, rotated to start at the least.
pub fn cycle_of(points: &[Vec3]) -> Vec<Key> {
    canonical(points.iter().map(|&p| bits(p)).collect())
}

/// Face `f`'s corner positions as a cycle of bits, rotated to start at the least.
pub fn position_cycle(world: &World, f: FaceId) -> Vec<Key> {
    let m = MeshRef::new(world);
    canonical(m.face_vertices(f).map(|v| bits(m.position(v))).collect())
}

/// Every face as a [`position_cycle`], sorted: the mesh up to relabelling, orientation kept.
pub fn position_cycles(world: &World, mesh: MeshId) -> Vec<Vec<Key>> {
    let faces = MeshMembers::collect(world, mesh).faces;
    sorted(faces.iter().map(|&f| position_cycle(world, f)).collect())
}

/// The expected faces (cycles of corner positions) in the form of [`position_cycles`].
pub fn cycles(faces: &[&[[f32; 3]]]) -> Vec<Vec<Key>> {
    sorted(
        faces
            .iter()
            .map(|c| canonical(c.iter().map(|&p| p.map(f32::to_bits)).collect()))
            .collect(),
    )
}

/// One face corner, bitwise: its vertex's position, its UV, its vertex's normal and colour.
pub type Corner = (Key, Option<[u32; 2]>, Option<Key>, Option<[u8; 3]>);

/// Every face as the cycle of its [`Corner`]s rotated to start at the least, sorted: the
/// faces up to relabelling with every attribute they show.
pub fn faces(world: &World, mesh: MeshId) -> Vec<Vec<Corner>> {
    let m = MeshRef::new(world);
    let corner = |h| {
        let v = m.to_vertex(h);
        let (normal, colour) = vertex_attributes(world, v);
        let uv = world.get::<CornerUv>(h.0).map(|u| uv_bits(u.0));
        (bits(m.position(v)), uv, normal, colour)
    };
    let faces = MeshMembers::collect(world, mesh).faces;
    sorted(
        faces
            .iter()
            .map(|&f| canonical(m.face_halfedges(f).map(corner).collect()))
            .collect(),
    )
}

fn vertex_attributes(world: &World, v: VertexId) -> (Option<Key>, Option<[u8; 3]>) {
    (
        world.get::<VertexNormal>(v.0).map(|n| bits(n.0)),
        world.get::<VertexColor>(v.0).map(|c| c.0),
    )
}

/// The whole mesh up to relabelling: [`counts`], every vertex (position, normal, colour),
/// every face ([`faces`]), every edge (its ends' positions, sorted, and whether it is a seam)
/// and the attribute record.
#[derive(Debug, PartialEq)]
pub struct Shape {
    counts: Counts,
    vertices: Vec<(Key, Option<Key>, Option<[u8; 3]>)>,
    faces: Vec<Vec<Corner>>,
    edges: Vec<([Key; 2], bool)>,
    record: MeshAttributes,
}

/// The mesh's [`Shape`].
pub fn shape(world: &World, mesh: MeshId) -> Shape {
    let m = MeshRef::new(world);
    let members = MeshMembers::collect(world, mesh);
    let vertices = members.vertices.iter().map(|&v| {
        let (normal, colour) = vertex_attributes(world, v);
        (bits(m.position(v)), normal, colour)
    });
    let edges = members.edges.iter().map(|&e| {
        let (a, b) = m.edge_vertices(e);
        let ends = sorted(vec![bits(m.position(a)), bits(m.position(b))]);
        ([ends[0], ends[1]], world.get::<Seam>(e.0).is_some())
    });
    Shape {
        counts: counts(world, mesh),
        vertices: sorted(vertices.collect()),
        faces: faces(world, mesh),
        edges: sorted(edges.collect()),
        record: MeshAttributes::of(world, mesh),
    }
}

// ---- untouched --------------------------------------------------------------------------

/// Every element of a mesh with all its components, by entity, and the mesh's attribute
/// record. Equal (bitwise, through [`ElementState::same`]) only when nothing changed.
#[derive(Debug)]
pub struct Snapshot {
    elements: Vec<(Entity, ElementState)>,
    record: MeshAttributes,
}

impl PartialEq for Snapshot {
    fn eq(&self, other: &Self) -> bool {
        self.record == other.record
            && self.elements.len() == other.elements.len()
            && self
                .elements
                .iter()
                .zip(&other.elements)
                .all(|((e, x), (f, y))| e == f && x.same(y))
    }
}

/// The mesh's [`Snapshot`].
pub fn snapshot(world: &World, mesh: MeshId) -> Snapshot {
    let all = sorted(MeshMembers::collect(world, mesh).entities().collect());
    Snapshot {
        elements: all
            .into_iter()
            .map(|e| (e, ElementState::of(world, e).expect("a live element")))
            .collect(),
        record: MeshAttributes::of(world, mesh),
    }
}

/// Checks that the mesh is as in `before`, naming the first element that changed.
pub fn assert_untouched(world: &World, mesh: MeshId, before: &Snapshot) {
    let now = snapshot(world, mesh);
    let entities = |s: &Snapshot| s.elements.iter().map(|x| x.0).collect::<Vec<_>>();
    assert_eq!(entities(&now), entities(before), "the elements changed");
    for ((e, x), (_, y)) in now.elements.iter().zip(&before.elements) {
        assert!(x.same(y), "{e} changed: {y:?} became {x:?}");
    }
    assert_eq!(now.record, before.record, "the attribute record changed");
}

/// Runs `op` and checks that it is refused with exactly `expected` and leaves the mesh
/// untouched.
pub fn assert_refused<T: std::fmt::Debug>(
    world: &mut World,
    mesh: MeshId,
    expected: Refusal,
    op: impl FnOnce(&mut World) -> Result<T, Refusal>,
) {
    let before = snapshot(world, mesh);
    let got = op(world);
    assert_eq!(got.map(|_| ()), Err(expected));
    assert_untouched(world, mesh, &before);
}

/// Runs `op` and checks that it is refused with a refusal that `kind` accepts and leaves the
/// mesh untouched.
pub fn assert_refused_like<T: std::fmt::Debug>(
    world: &mut World,
    mesh: MeshId,
    kind: impl FnOnce(&Refusal) -> bool,
    op: impl FnOnce(&mut World) -> Result<T, Refusal>,
) {
    let before = snapshot(world, mesh);
    match op(world) {
        Err(refusal) => assert!(kind(&refusal), "refused, but with {refusal:?}"),
        Ok(x) => panic!("not refused: {x:?}"),
    }
    assert_untouched(world, mesh, &before);
}

// ---- undo -------------------------------------------------------------------------------

/// Records `edit` as the editor does (a local recorder begun on `seeds`), checks that it
/// changed the mesh and left it valid, that undoing it gives the original [`shape`] back and
/// redoing it the edited one, both valid.
pub fn assert_undo_redo(
    world: &mut World,
    mesh: MeshId,
    seeds: &[VertexId],
    edit: impl FnOnce(&mut World),
) {
    let before = shape(world, mesh);
    let recorder = LocalRecorder::begin(world, mesh, seeds);
    edit(world);
    validate(world, mesh).expect("valid after the edit");
    let undo = recorder.finish(world);
    let after = shape(world, mesh);
    assert_ne!(after, before, "the edit changed nothing");
    let (redo, _, _) = undo.apply(world);
    validate(world, mesh).expect("valid after undo");
    assert_eq!(shape(world, mesh), before, "undo gives the original back");
    let _ = redo.apply(world);
    validate(world, mesh).expect("valid after redo");
    assert_eq!(shape(world, mesh), after, "redo gives the edit back");
}
