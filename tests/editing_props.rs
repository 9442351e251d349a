//! Random sequences of every local edit — the modelling operations (extrude, inset, bevel of
//! vertices, edges and faces, erase, dissolve vertex, collapse face, weld, fill) among flips,
//! splits, collapses, dissolves, bisections and moves — through the one edit layer, on random
//! shapes: the mesh validates after every step, a refused edit changes nothing, and every
//! applied edit is undone exactly (faces by position, bitwise) and redone exactly by the record
//! the editor's history takes ([`LocalRecorder`] over the edit's reach; checked on every fourth
//! applied edit). 256 cases × 400 operations = 102 400 operations per run.

mod common;

use bevy::math::Vec3;
use bevy::prelude::World;
use pappus::edit::{Edit, EditContext, Reach};
use pappus::mesh::change::LocalRecorder;
use pappus::mesh::{
    EdgeId, FaceId, MeshId, MeshMembers, MeshRef, PolygonSoup, VertexId, shapes, to_soup, validate,
};
use proptest::prelude::*;

fn shape(i: u8) -> PolygonSoup {
    match i % SHAPES {
        0 => shapes::icosphere(1),
        1 => shapes::torus(6, 5),
        2 => shapes::grid(4, 3),
        3 => shapes::quad_grid(4, 4),
        4 => shapes::cube(),
        5 => shapes::grid_with_holes(2),
        _ => shapes::tetrahedron(),
    }
}

const SHAPES: u8 = 7;

/// Past this many faces, edits that add faces are skipped.
const MAX_FACES: usize = 300;

/// The kinds of edit a step draws from.
const KINDS: u8 = 16;

/// One random edit of kind `kind` on the elements `pick` chooses, with parameter `t` in
/// (0.05, 0.95). `None` when the mesh has nothing of the kind.
fn random_edit(world: &World, mesh: MeshId, kind: u8, pick: u32, t: f32) -> Option<Edit> {
    let members = MeshMembers::collect(world, mesh);
    // Extrusions, insets and bevels add faces; past a few hundred the mesh only loses them, so
    // that every case stays small and quick.
    if members.faces.len() > MAX_FACES && (5..=9).contains(&kind) {
        return None;
    }
    let m = MeshRef::new(world);
    let nth = |n: usize| pick as usize % n.max(1);
    let vertex =
        || -> Option<VertexId> { members.vertices.get(nth(members.vertices.len())).copied() };
    let edge = || -> Option<EdgeId> { members.edges.get(nth(members.edges.len())).copied() };
    let face = || -> Option<FaceId> { members.faces.get(nth(members.faces.len())).copied() };
    // A face and the faces around one of its corners: a small region.
    let region = || -> Option<Vec<FaceId>> {
        let f = face()?;
        let v = m.face_vertices(f).nth(pick as usize % 3)?;
        let mut faces: Vec<FaceId> = m
            .vertex_faces(v)
            .take(1 + (pick as usize >> 8) % 4)
            .collect();
        faces.push(f);
        faces.sort_unstable();
        faces.dedup();
        Some(faces)
    };
    let boundary: Vec<EdgeId> = members
        .edges
        .iter()
        .copied()
        .filter(|&e| m.is_boundary_edge(e))
        .collect();
    Some(match kind {
        0 => Edit::local("flip", edge()?),
        1 => Edit::local("split", edge()?),
        2 => Edit::local("collapse", edge()?),
        3 => Edit::local("dissolve", edge()?),
        4 => Edit::local("bisect", edge()?),
        5 => Edit::local_on("extrude", region()?, &[f64::from(t - 0.5)]),
        6 => Edit::local_on("inset", region()?, &[f64::from(t)]),
        7 => Edit::local_on(
            "inset",
            [face()?],
            &[f64::from(t * 0.9), f64::from(t - 0.5)],
        ),
        8 => Edit::local_on("bevel", [vertex()?], &[f64::from(t) * 0.5]),
        9 => Edit::local_on("bevel", [edge()?], &[f64::from(t) * 0.5]),
        10 => Edit::local_on(
            "erase",
            region()?.into_iter().take(1 + pick as usize % 2),
            &[],
        ),
        11 => Edit::local("dissolve", vertex()?),
        12 => Edit::local("collapse", face()?),
        13 => {
            // A boundary edge and the one two steps further round its loop: zipping those
            // closes a notch when it can.
            let e = *boundary.get(nth(boundary.len()))?;
            let h = m.edge_halfedge(e);
            let h = if m.is_boundary(h) { h } else { m.twin(h) };
            let far = match pick % 3 {
                0 => m.next(m.next(h)),
                1 => m.next(h),
                _ => boundary
                    .get((pick as usize / 3) % boundary.len())
                    .map(|&x| m.edge_halfedge(x))?,
            };
            Edit::local_on("weld", [e, m.edge(far)], &[])
        }
        14 => Edit::local("fill-hole", *boundary.get(nth(boundary.len()))?),
        _ => {
            let v = vertex()?;
            Edit::Move(vec![(v, m.position(v) + Vec3::new(t, -t, 0.5 * t) * 0.1)])
        }
    })
}

fn run(world: &mut World, mesh: MeshId, edit: &Edit) -> bool {
    let mut context = EditContext {
        progress: &mut |_| true,
    };
    edit.run(world, mesh, &mut context).is_ok()
}

fn shape_of(world: &World, mesh: MeshId) -> Vec<Vec<common::Key>> {
    common::canonical(&to_soup(world, mesh))
}

/// Every element's id and links and every position, hashed: equal exactly when nothing was
/// touched (cheaper than [`shape_of`], for refusals).
fn fingerprint(world: &World, mesh: MeshId) -> u64 {
    use std::hash::{Hash, Hasher};
    let members = MeshMembers::collect(world, mesh);
    let m = MeshRef::new(world);
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for &v in &members.vertices {
        (
            v,
            m.vertex_halfedge(v),
            m.position(v).to_array().map(f32::to_bits),
        )
            .hash(&mut h);
    }
    for &x in &members.halfedges {
        (
            x,
            m.next(x),
            m.twin(x),
            m.to_vertex(x),
            m.edge(x),
            m.face(x),
        )
            .hash(&mut h);
    }
    for &f in &members.faces {
        (f, m.face_halfedge(f)).hash(&mut h);
    }
    for &e in &members.edges {
        (e, m.edge_halfedge(e)).hash(&mut h);
    }
    h.finish()
}

proptest! {
    #![proptest_config(common::proptest_config())]

    #[test]
    fn random_editing_keeps_the_mesh_valid_and_undoes_exactly(
        which in 0u8..SHAPES,
        ops in proptest::collection::vec((0u8..KINDS, any::<u32>(), common::edge_fraction()), 400),
    ) {
        let (mut world, built) = common::build(&shape(which));
        let mesh = built.mesh;
        let mut applied_count = 0usize;
        for (kind, pick, t) in ops {
            let Some(edit) = random_edit(&world, mesh, kind, pick, t) else {
                continue;
            };
            // Undo and redo are checked on every fourth applied edit (the canonical forms cost
            // O(mesh log mesh)); over a run every kind is checked hundreds of times.
            let check_undo = applied_count.is_multiple_of(4);
            let before_print = fingerprint(&world, mesh);
            let before = if check_undo { shape_of(&world, mesh) } else { Vec::new() };
            let recorder = match edit.reach(&world, mesh) {
                Some(Reach::Local(m, seeds)) => Some(LocalRecorder::begin(&world, m, &seeds)),
                Some(Reach::Vertices(m, seeds)) => Some(LocalRecorder::begin_vertices(&world, m, &seeds)),
                _ => None,
            };
            // `Edit::run` validates the mesh after every applied edit in test builds (and panics,
            // which fails the case, if it is broken); a refused one is checked untouched below.
            let applied = run(&mut world, mesh, &edit);
            if !applied {
                prop_assert_eq!(fingerprint(&world, mesh), before_print, "a refused {} changed the mesh", edit.label());
                continue;
            }
            applied_count += 1;
            if !check_undo {
                continue;
            }
            let Some(recorder) = recorder else {
                prop_assert!(false, "{} applied without a reach", edit.label());
                unreachable!();
            };
            let after = shape_of(&world, mesh);
            let (redo, _, _) = recorder.finish(&world).apply(&mut world);
            prop_assert!(validate(&world, mesh).is_ok(), "undo of {}", edit.label());
            prop_assert_eq!(shape_of(&world, mesh), before.clone(), "undo of {}", edit.label());
            redo.apply(&mut world);
            prop_assert!(validate(&world, mesh).is_ok(), "redo of {}", edit.label());
            prop_assert_eq!(shape_of(&world, mesh), after, "redo of {}", edit.label());
        }
    }
}

/// The random runs above exercise every kind: over a fixed sample of cases (a small linear
/// congruential generator in place of proptest's), each kind of edit is applied at least a few
/// times, so no operation passes by always being refused.
#[test]
fn every_kind_of_edit_is_applied_in_random_runs() {
    let mut applied = [0usize; KINDS as usize];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 33) as u32
    };
    for case in 0..2 * SHAPES {
        let (mut world, built) = common::build(&shape(case));
        for _ in 0..300 {
            let kind = (next() % KINDS as u32) as u8;
            let pick = next();
            let t = 0.05 + 0.9 * (next() % 1000) as f32 / 1000.0;
            if let Some(edit) = random_edit(&world, built.mesh, kind, pick, t)
                && run(&mut world, built.mesh, &edit)
            {
                applied[kind as usize] += 1;
            }
        }
    }
    println!("applied, by kind: {applied:?}");
    for (kind, n) in applied.iter().enumerate() {
        assert!(
            *n >= 3,
            "edit kind {kind} applied only {n} times: {applied:?}"
        );
    }
}
